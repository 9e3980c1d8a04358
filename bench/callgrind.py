"""Instruction counts of LIGGGHTS runs under valgrind's callgrind: run a
deck counted, split a profile into the parts of a step (callgrind_annotate),
and the cost per step of a window of steps, start-up cancelled (a run to N
steps and one to 2N). Used by bench/spherocylinder_cost.py."""

import os
import re
import subprocess
from pathlib import Path

import benchlib

COLLECTED = re.compile(r"Collected : (\d+)")
NEIGHBOURS = re.compile(r"^Total # of neighbors = (\d+)", re.MULTILINE)
BUILDS = re.compile(r"^Neighbor list builds = (\d+)", re.MULTILINE)


def run_counted(deck, workdir, binary):
    """Runs `deck` under callgrind; returns the instruction total, the
    screen output and the profile's path."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    profile = workdir / "callgrind.out"
    command = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={profile}",
               str(binary), "-in", "in.deck", "-log", "none"]
    with open(workdir / "screen.txt", "w") as screen, open(workdir / "valgrind.txt", "w") as log:
        process = subprocess.Popen(command, cwd=workdir, stdout=screen, stderr=log)
        _, status, usage = os.wait4(process.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    output = (workdir / "screen.txt").read_text(errors="replace")
    report = (workdir / "valgrind.txt").read_text(errors="replace")
    errors = [line for line in (output + report).splitlines() if "ERROR" in line]
    collected = COLLECTED.search(report)
    if code != 0 or errors or not collected:
        tail = "\n".join(output.splitlines()[-10:])
        raise benchlib.LiggghtsFailed(f"{binary} under callgrind failed in {workdir}: "
                                      f"{errors[0] if errors else 'exit code %d' % code}\n{tail}")
    return {"instructions": int(collected.group(1)), "output": output, "profile": profile,
            "cpu": usage.ru_utime + usage.ru_stime}


# The profile split: inclusive instructions of these functions (the rest is
# "other": communication, exchange, output, pre/post neighbour hooks).
CATEGORIES = [
    ("pair", ["LAMMPS_NS::PairGran::compute(int, int)"]),
    ("integration", ["LAMMPS_NS::Modify::initial_integrate(int)", "LAMMPS_NS::Modify::final_integrate()"]),
    ("post_force", ["LAMMPS_NS::Modify::post_force(int)"]),
    ("neighbour", ["LAMMPS_NS::Neighbor::decide()", "LAMMPS_NS::Neighbor::build(int)"]),
]
ANNOTATE_LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$")


def profile_functions(profile, inclusive):
    """function name -> instructions, from callgrind_annotate."""
    command = ["callgrind_annotate", f"--inclusive={'yes' if inclusive else 'no'}", "--threshold=100", str(profile)]
    text = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    functions = {}
    for line in text.splitlines():
        match = ANNOTATE_LINE.match(line)
        if not match or "PROGRAM TOTALS" in line:
            continue
        name = match.group(2)
        name = re.sub(r" \[[^\]]*\]$", "", name)          # the object file
        name = re.sub(r"^(\?\?\?|[^\s:()]+):", "", name)    # the source file
        functions[name] = functions.get(name, 0) + int(match.group(1).replace(",", ""))
    return functions


def window(short, long, steps):
    """Per-step costs of the window from the runs to N and to 2N steps."""
    per_step = (long["instructions"] - short["instructions"]) / steps
    inclusive = [profile_functions(r["profile"], True) for r in (short, long)]
    parts = {}
    for name, functions in CATEGORIES:
        parts[name] = sum(inclusive[1].get(f, 0) - inclusive[0].get(f, 0) for f in functions) / steps
    parts["other"] = per_step - sum(parts.values())
    builds = [benchlib.last_int(BUILDS, r["output"]) or 0 for r in (short, long)]
    return {"per_step": per_step, "parts": parts,
            "neighbours": benchlib.last_int(NEIGHBOURS, long["output"]),
            "builds": builds[1] - builds[0], "ke": benchlib.final_ke(long["output"]),
            "cpu": short["cpu"] + long["cpu"], "runs": (short["instructions"], long["instructions"])}


def measure(label, deck, binary, steps, workdir, exclusive=False):
    """Instructions per step of the window N..2N of `deck(steps)`'s last run;
    with `exclusive`, also each function's own instructions in both runs."""
    runs = []
    for n in (steps, 2 * steps):
        runs.append(run_counted(deck(n), workdir / f"steps{n}", binary))
        benchlib.check_complete(runs[-1]["output"], n, workdir / f"steps{n}")
    result = window(runs[0], runs[1], steps)
    result["atoms"] = int(benchlib.LOOP_TIME.findall(runs[1]["output"])[-1][3])
    if exclusive:
        result["exclusive"] = [profile_functions(r["profile"], False) for r in runs]
    benchlib.progress(f"{label}: {result['per_step']:,.0f} instructions per step "
                      f"({result['per_step'] / result['atoms']:,.0f} per atom), "
                      f"{result['neighbours']} list pairs, {result['builds']} builds in the window, "
                      f"{result['cpu']:.0f} s CPU")
    return result


def function_changes(before, after, steps, atoms, top=6):
    """The functions whose own (exclusive) instructions per step changed
    most between the two binaries, per atom-step."""
    def per_step(result, name):
        short, long = result["exclusive"]
        return (long.get(name, 0) - short.get(name, 0)) / steps
    # LIGGGHTS' own functions (C++ names): libc's string and thread
    # functions differ between the runs' set-ups by a few instructions
    names = {n for n in set(before["exclusive"][1]) | set(after["exclusive"][1]) if "::" in n}
    changes = [(per_step(after, n) - per_step(before, n), per_step(before, n), per_step(after, n), n)
               for n in names]
    changes.sort(key=lambda c: -abs(c[0]))
    return [(name, b / atoms, a / atoms, d / atoms) for d, b, a, name in changes[:top] if abs(d) >= 0.1 * atoms]
