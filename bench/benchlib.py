"""Shared pieces of the benchmark scripts: run a LIGGGHTS deck and read its
loop time, describe the machine, and write a script's own section of the
report in doc/ and its raw numbers in bench/results/.

Benchmarks are not tests: they measure and write tables, they do not pass or
fail on the numbers (they do stop when LIGGGHTS stops with an error)."""

import datetime
import hashlib
import os
import platform
import re
import shlex
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUR_BINARY = Path(os.environ.get("SILOKIT_LIGGGHTS", ROOT / "build" / "bin" / "liggghts"))
STOCK_BINARY = Path("/usr/bin/liggghts")
REPORT = ROOT / "doc" / "accuracy_cost_rolling.md"
RESULTS = ROOT / "bench" / "results"
WORK = ROOT / "bench" / "work"
INPUTS = ROOT / "inputs"
SECTION_ORDER = ["rolling_cost", "stock_speed", "rolling_accuracy"]

LOOP_TIME = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms",
                       re.MULTILINE)
PAIR_TIME = re.compile(r"^Pair  time \(%\) = (\S+)", re.MULTILINE)


class LiggghtsFailed(RuntimeError):
    pass


def progress(message):
    """A progress line on stdout, with the wall-clock time."""
    print(f"[{time.strftime('%H:%M:%S')}] {message}", flush=True)


def pin_to_cpu(cpu):
    """Runs this process, and every engine it starts, on core `cpu` only
    (children inherit the affinity); stops with a message if that core is
    not one this process may use."""
    if cpu not in os.sched_getaffinity(0):
        sys.exit(f"--cpu {cpu}: not one of this process' cores {sorted(os.sched_getaffinity(0))}")
    os.sched_setaffinity(0, {cpu})


def run_deck(deck, workdir, binary=OUR_BINARY, env=None):
    """Writes `deck` to workdir/in.deck, runs it serially with `binary` (with
    the variables of `env`, name -> value, added to this environment) and
    returns a dict: output (screen text), loops (list of (seconds, steps,
    atoms), one per `run`), pair_times (the `Pair time` of each run, seconds),
    cpu (user+system seconds of the LIGGGHTS process, start-up included),
    wall (seconds, start-up included)."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    command = [str(binary), "-in", "in.deck", "-log", "none"]
    env = {**os.environ, **env} if env else None
    start = time.perf_counter()
    with open(workdir / "screen.txt", "w") as screen:
        process = subprocess.Popen(command, cwd=workdir, stdout=screen,
                                   stderr=subprocess.STDOUT, env=env)
        # wait4 hands back the resource usage of exactly this process
        _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - start
    cpu = usage.ru_utime + usage.ru_stime
    output = (workdir / "screen.txt").read_text(errors="replace")
    errors = [line for line in output.splitlines() if "ERROR" in line]
    if process.returncode != 0 or errors:
        raise LiggghtsFailed(f"{binary} failed in {workdir}: "
                             f"{errors[0] if errors else 'exit code %d' % process.returncode}\n"
                             f"{_error_context(command, workdir, env)}")
    loops = loop_lines(output)
    # the pair part of each run's loop time (LIGGGHTS' timing breakdown)
    pair_times = [float(t) for t in PAIR_TIME.findall(output)]
    return {"output": output, "loops": loops, "pair_times": pair_times, "cpu": cpu,
            "wall": wall}


def loop_lines(output):
    """(seconds, steps, atoms) of each `Loop time` line of a LIGGGHTS screen output."""
    return [(float(t), int(steps), int(atoms)) for t, procs, steps, atoms in LOOP_TIME.findall(output)]


def _error_context(command, workdir, env=None):
    """LIGGGHTS buffers its screen output, and an MPI abort loses what was
    not flushed (often the ERROR line itself): rerun with line buffering to
    show the end of the output."""
    try:
        rerun = subprocess.run(["stdbuf", "-oL", "-eL"] + command, cwd=workdir, env=env,
                               capture_output=True, text=True, errors="replace", timeout=600)
        lines = (rerun.stdout + rerun.stderr).splitlines()
        return "\n".join(lines[-15:])
    except (OSError, subprocess.TimeoutExpired) as problem:
        return f"(could not rerun for the error message: {problem})"


def scene_deck(scene, variables):
    """A deck that runs the production deck inputs/<scene>/in.<scene> with
    `variables` (name -> value) set ahead of it as index variables (as
    `-var name value` would)."""
    lines = [f"variable {name} index {value}" for name, value in variables.items()]
    lines += [f"variable inputs index {INPUTS}", f"include {INPUTS / scene / f'in.{scene}'}"]
    return "\n".join(lines) + "\n"


# ---- reading LIGGGHTS' screen output ----------------------------------------

def last_int(pattern, output):
    """The last match of `pattern` (one integer group) in `output`, or None."""
    found = pattern.findall(output)
    return int(found[-1]) if found else None


def last_run_steps(output):
    """Steps between the first and the last thermo line of the last run (a
    run stopped early, by a signal say, still reports the steps it was
    asked for in its Loop time line)."""
    lines = output[:output.rindex("Loop time")].splitlines()
    header = max(k for k, line in enumerate(lines) if line.split()[:1] == ["Step"])
    steps = [int(line.split()[0]) for line in lines[header + 1:]
             if line.split()[:1] and line.split()[0].isdigit()]
    return steps[-1] - steps[0]


def check_complete(output, steps, where):
    """Raises LiggghtsFailed unless the last run made its `steps` steps."""
    done = last_run_steps(output)
    if done != steps:
        raise LiggghtsFailed(f"{where}: the last run made {done} of its {steps} steps (interrupted?)")


def final_ke(output):
    """KinEng of the last thermo line before the last Loop time."""
    lines = output[:output.rindex("Loop time")].splitlines()
    rows = [line.split() for line in lines if line.split()[:1] and line.split()[0].isdigit()]
    return rows[-1][2] if rows else "?"


def machine():
    """nproc, CPU model, load, date: what a reader needs to weigh timings."""
    model = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = " ".join(f"{x:.2f}" for x in os.getloadavg())
    return {
        "nproc": os.cpu_count(),
        "cpu": model,
        "load": load,
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "system": f"{platform.system()} {platform.release()}",
    }


def _head():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                              capture_output=True, text=True).stdout.strip() or "unknown"
    except OSError:
        return "unknown"


# read when the bench starts: a long bench may end after later commits, and
# its record names the commit whose code ran
_COMMIT_AT_START = _head()


def git_commit():
    """The commit checked out when this bench started (its code ran), and
    the one checked out now if that differs."""
    now = _head()
    return _COMMIT_AT_START if now == _COMMIT_AT_START else f"{_COMMIT_AT_START} (HEAD at the end: {now})"


def command_line():
    """The exact command that ran this script, as one could type it again
    from the repository root."""
    script = Path(sys.argv[0]).resolve()
    try:
        script = script.relative_to(ROOT)
    except ValueError:
        pass
    return " ".join(shlex.quote(part) for part in ["/usr/bin/python3", str(script)] + sys.argv[1:])


def provenance(extra_load=None, load_when="at the end"):
    """Markdown lines: machine, date, command, commit (load_when: when this
    is called, for the load average's label)."""
    info = machine()
    lines = [
        f"- machine: {info['nproc']} cores, {info['cpu']}, {info['system']}",
        f"- date: {info['date']}; load average {load_when} (1/5/15 min): {info['load']}"
        + (f"; at the start: {extra_load}" if extra_load else ""),
        f"- command (from the repository root): `{command_line()}`",
        f"- silokit commit: {git_commit()}; binary: {binary_identity(OUR_BINARY)}",
    ]
    return "\n".join(lines)


def shown_path(path):
    """`path` relative to the repository when it lies inside it."""
    try:
        return Path(path).relative_to(ROOT)
    except ValueError:
        return Path(path)


def binary_identity(binary):
    """Path, modification time and sha256 prefix: the binary can be rebuilt
    between two benchmark runs."""
    shown = shown_path(binary)
    if not Path(binary).exists():
        return f"`{shown}` (not built)"    # e.g. provenance() of a bench that ran only other binaries
    stamp = datetime.datetime.fromtimestamp(binary.stat().st_mtime).astimezone()
    digest = hashlib.sha256(binary.read_bytes()).hexdigest()[:12]
    return (f"`{shown}` built {stamp.strftime('%Y-%m-%d %H:%M %Z')}, sha256 {digest}…"
            + build_options(binary))


def build_options(binary):
    """The optimisation options of the build tree a binary comes from
    (bin/../CMakeCache.txt; README, "Build options"), as ", with ..."."""
    binary = Path(binary).resolve()
    cache = binary.parent.parent / "CMakeCache.txt"
    if binary.parent.name != "bin" or binary.name != "liggghts":
        return ""   # a copy elsewhere: the tree's options may not be its own
    try:
        text = cache.read_text()
    except OSError:
        return ""
    found = re.findall(r"^(SILOKIT_LTO|SILOKIT_PGO|SILOKIT_OPTIMIZATION_FLAGS):\w+=(.*)$",
                       text, re.MULTILINE)
    return ", with " + " ".join(f"{name}={value}" for name, value in found) if found else ""


def load_average():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def use_smoke_outputs():
    """--quick runs write their report and raw numbers under work/quick/,
    so that a smoke run never replaces a measurement in doc/ or results/."""
    global REPORT, RESULTS
    REPORT = WORK / "quick" / "accuracy_cost_rolling.md"
    RESULTS = WORK / "quick" / "results"


def write_section(name, markdown):
    """Replaces the section `name` of doc/accuracy_cost_rolling.md (between
    its BEGIN/END markers) with `markdown`, leaving the other sections as
    they are; creates the file and missing sections in SECTION_ORDER, and
    appends a section of another name (stock_speed.py --section)."""
    text = REPORT.read_text() if REPORT.exists() else _REPORT_HEADER
    for section in SECTION_ORDER + ([] if name in SECTION_ORDER else [name]):
        if f"<!-- BEGIN {section} -->" not in text:
            text = text.rstrip("\n") + (f"\n\n<!-- BEGIN {section} -->\n"
                                        f"(not measured yet: run `bench/{section}.py`)\n"
                                        f"<!-- END {section} -->\n")
    REPORT.parent.mkdir(parents=True, exist_ok=True)
    REPORT.write_text(replace_section(text, name, markdown))


def write_page_section(path, name, markdown, header):
    """Replaces the section `name` of the page `path` (between its
    BEGIN/END markers; appended if missing) with `markdown`, leaving the
    rest of the page as it is; a new page starts with `header`."""
    text = path.read_text() if path.exists() else header
    if f"<!-- BEGIN {name} -->" not in text:
        text = text.rstrip("\n") + f"\n\n<!-- BEGIN {name} -->\n<!-- END {name} -->\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(replace_section(text, name, markdown))


def replace_section(text, name, markdown):
    begin, end = f"<!-- BEGIN {name} -->", f"<!-- END {name} -->"
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{begin}\n{markdown.strip()}\n{end}{tail}"


_REPORT_HEADER = """# Accuracy and cost of rolling resistance

Written by the scripts in `bench/` (see `bench/README.md`); each script
rewrites only its own section, between its `BEGIN`/`END` markers. Timings
are wall-clock `Loop time` of LIGGGHTS (serial runs), so they depend on the
machine and on what else runs on it: compare ratios measured in the same run,
not absolute times across sections or machines. Raw numbers are in
`bench/results/`.
"""


def write_raw(name, text):
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"{name}.txt"
    path.write_text(text)
    return path


def spread(values):
    """median, min, max of a list."""
    return statistics.median(values), min(values), max(values)
