"""The command lines of the analysis package follow one convention
(analysis/common/cli.py): the usage line is a command that runs as written,
`--help` ends with an example of it, `--out` is a directory, lengths carry
their unit; and the modules that look for the repository find it."""

import importlib
import importlib.util
import pkgutil
import re
from pathlib import Path

import pytest

import analysis

ROOT = Path(__file__).resolve().parent.parent


def modules():
    """Every module of the analysis package, by name."""
    names = []
    for info in pkgutil.walk_packages(analysis.__path__, "analysis."):
        if not info.name.endswith("__main__"):
            names.append(info.name)
    return sorted(names)


def command_modules():
    return [name for name in modules() if name != "analysis.common.cli"
            and "command_line(" in Path(importlib.util.find_spec(name).origin).read_text()]


def runs_as(name):
    """Whether `python3 -m <name>` runs: a module with a __main__ guard, or a
    package with its __main__.py."""
    spec = importlib.util.find_spec(name)
    if spec.submodule_search_locations:
        return (Path(spec.origin).parent / "__main__.py").exists()
    return 'if __name__ == "__main__":' in Path(spec.origin).read_text()


def test_every_command_line_module_is_found():
    names = command_modules()
    assert "analysis.silo3d_rotating.analyse" in names and "analysis.campaign.silo3d_carry" in names
    assert "analysis.silo3d_rotating.elongation" in names
    assert len(names) == 21


@pytest.mark.parametrize("name", command_modules())
def test_help_names_a_runnable_command_and_ends_with_an_example(name, capsys):
    module = importlib.import_module(name)
    with pytest.raises(SystemExit) as stop:
        module.main(["--help"])
    assert stop.value.code == 0
    text = capsys.readouterr().out
    command = re.match(r"usage: /usr/bin/python3 -m (\S+)", text)
    assert command, text[:200]
    assert runs_as(command.group(1)), f"{name}: `python3 -m {command.group(1)}` does not run"
    example = text.rstrip().split("\n")[-2:]
    assert example[0] == "example:" and example[1].startswith(f"  /usr/bin/python3 -m {command.group(1)}"), text
    options = re.findall(r"(?<![\w-])--[a-z][\w-]*", text)
    assert not {"--zmax", "--z-max", "--z-min"} & set(options), f"{name}: a length option without its unit"
    out = re.search(r"\n  --out (\S+)\s+(.*)", text)
    if out:
        assert out.group(1) == "DIR" and "directory" in out.group(2), f"{name}: --out is not a directory"


@pytest.mark.parametrize("name", modules())
def test_the_repository_a_module_takes_is_the_repository(name):
    module = importlib.import_module(name)
    for attribute in ("ROOT", "REPOSITORY"):
        if isinstance(getattr(module, attribute, None), Path):
            assert getattr(module, attribute) == ROOT, f"{name}.{attribute}"
