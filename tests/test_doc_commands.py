"""The commands in the README and the pages run as written from a fresh
clone after `bash tools/setup.sh`: each shell block and each inline command
names files, decks, modules and options that exist, calls our binary by its
path (Debian's `liggghts` on the PATH lacks our styles) and the Python that
has numpy. The quick scene commands themselves run in the scene tests; the
demo runs in tools/setup.sh."""

import os
import re
import shlex
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / "README.md"] + sorted((ROOT / "doc").glob("*.md")) + sorted((ROOT / "doc").glob("*/*.md"))
PAGES = [page for page in PAGES if "doc/data" not in page.as_posix()]
# top-level folders whose paths a command may name: they must exist
REPO_DIRS = ("inputs/", "examples/", "tools/", "bench/", "doc/", "analysis/", "tests/", "src_plugin/", "cmake/")
# what `bash tools/setup.sh` builds; the fast tier runs without it, so paths
# into it are checked only where the build exists (the full tier)
BUILD = ROOT / "build"
PYTHON = "/usr/bin/python3"


def built():
    return (BUILD / "bin" / "liggghts").exists()


def shell_blocks(text):
    """The ```sh / ```bash blocks of a Markdown text, as lists of commands
    (continuation lines joined, comments dropped)."""
    blocks = []
    for block in re.findall(r"```(?:sh|bash|shell)\n(.*?)```", text, re.S):
        joined = re.sub(r"\\\n\s*", " ", block)
        commands = []
        for line in joined.splitlines():
            line = re.sub(r"(^|\s)#.*$", "", line).strip()
            if line:
                commands.append(line)
        blocks.append(commands)
    return blocks


def inline_commands(text):
    """Inline code spans outside code blocks that read as a command of ours."""
    prose = re.sub(r"```.*?```", "", text, flags=re.S)
    spans = re.findall(r"`([^`\n]+)`", prose)
    return [span for span in spans if re.match(r"(\S*python3|\S*liggghts|bash|mpirun)\s", span)]


def words(command):
    try:
        return shlex.split(command)
    except ValueError:
        return command.split()


def problems_of(command, cwd):
    """What is wrong with one command line run in `cwd` (a folder of the
    clone), as (problems, the folder it ends in)."""
    found = []
    for part in re.split(r"\s*(?:&&|\|\||;|\|)\s*", command):
        argv = words(part)
        # environment assignments before the program
        while argv and re.match(r"^[A-Z_][A-Z0-9_]*=", argv[0]):
            argv = argv[1:]
        if not argv:
            continue
        if argv[0] == "cd" and len(argv) == 2:
            cwd = Path(os.path.normpath(cwd / argv[1]))
            continue
        if argv[0] == "mpirun":
            argv = [w for w in argv[1:] if not w.startswith("-") and not w.isdigit()]
        program = argv[0] if argv else ""
        if program == "liggghts":
            found.append(f"bare `liggghts` is Debian's binary, without our styles: `{part}`")
        if program.endswith("python3") and program != PYTHON:
            found.append(f"`{program}` may lack numpy; use {PYTHON}: `{part}`")
        if program.endswith("python3") and "-m" in argv[:-1]:
            module = argv[argv.index("-m") + 1]
            found += module_problems(module, argv[argv.index("-m") + 2:], part)
        for word in argv:
            found += [f"`{path}` does not exist: `{part}`" for path in missing_paths(word, cwd)]
    return found, cwd


def missing_paths(word, cwd):
    """The paths into the clone that `word` names and that do not exist
    (a glob must match something)."""
    missing = []
    for path in re.findall(r"[\w./*-]+", word):
        path = path.rstrip(".,")
        if not path.startswith(REPO_DIRS + ("build/", "../")) or "<" in word:
            continue
        # (normpath: the folder a block cds into may not exist before it runs)
        here = Path(os.path.normpath(cwd / path))
        if here.is_relative_to(BUILD) and not built():
            continue
        if "*" in path:
            if not list(Path(here.anchor).glob(str(here.relative_to(here.anchor)))) and not list(ROOT.glob(path)):
                missing.append(path)
        elif not here.exists() and not (ROOT / path).exists():
            missing.append(path)
    return missing


def module_problems(module, args, command):
    if not module.startswith("analysis."):
        return []
    if not (ROOT / (module.replace(".", "/") + ".py")).exists() and \
            not (ROOT / module.replace(".", "/") / "__main__.py").exists():
        return [f"no module {module}: `{command}`"]
    usage = module_help(module)
    if usage is None:
        return [f"`{PYTHON} -m {module} --help` fails: `{command}`"]
    return [f"{module} has no option {option}: `{command}`"
            for option in args if option.startswith("--") and option.split("=")[0] not in usage]


@lru_cache(maxsize=None)
def module_help(module):
    result = subprocess.run([PYTHON, "-m", module, "--help"], cwd=ROOT, capture_output=True, text=True,
                            timeout=120)
    return result.stdout if result.returncode == 0 else None


def page_problems(page):
    text = page.read_text()
    found = []
    for commands in shell_blocks(text):
        cwd = ROOT
        for command in commands:
            problems, cwd = problems_of(command, cwd)
            found += problems
    for command in inline_commands(text):
        found += problems_of(command, ROOT)[0]
    return found


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_commands_in_page_run_as_written(page):
    problems = page_problems(page)
    assert not problems, f"{page.relative_to(ROOT)}:\n" + "\n".join(problems)


def test_the_checker_finds_what_it_should(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("```sh\nliggghts -in inputs/silo2d/in.silo2d\n"
                    "python3 -m analysis.silo2d doc/data/silo2d_scan --mu 0.4\n"
                    "build/bin/liggghts -in inputs/nowhere/in.deck\n"
                    f"{PYTHON} -m analysis.silo2d RUNS --no-such-option\n```\n"
                    "and inline `python3 -m analysis.pile2d x`.\n")
    problems = "\n".join(page_problems(page))
    assert "bare `liggghts`" in problems
    assert problems.count("may lack numpy") == 2
    assert "inputs/nowhere/in.deck` does not exist" in problems
    assert "analysis.silo2d has no option --no-such-option" in problems
    good = tmp_path / "good.md"
    good.write_text("```sh\nbuild/bin/liggghts -in inputs/silo2d/in.silo2d -var quick 1\n"
                    f"{PYTHON} -m analysis.silo2d RUNS --mu 0.4\n```\n")
    assert page_problems(good) == []


def test_build_paths_are_checked_where_the_build_exists(tmp_path, monkeypatch):
    page = tmp_path / "page.md"
    page.write_text("```sh\nbuild/bin/no-such-binary -in inputs/silo2d/in.silo2d\n"
                    "cd examples/silo2d && ../../build/bin/no-such-binary -in in.x\n```\n")
    monkeypatch.setattr(sys.modules[__name__], "built", lambda: False)
    assert page_problems(page) == []  # no build: the fast tier
    monkeypatch.setattr(sys.modules[__name__], "built", lambda: True)
    problems = "\n".join(page_problems(page))
    assert problems.count("no-such-binary` does not exist") == 2
