#!/usr/bin/python3
"""The cost of each scene in both hosts, measured in one run (issue 46,
part 3): a short fixed-length run of each scene's production deck in
LIGGGHTS (`inputs/<scene>/in.*`, $SILOKIT_LIGGGHTS, default
build/bin/liggghts) and in LAMMPS (the `.lammps` twins, $SILOKIT_LMP,
default build/bin/lmp, with the plugin $SILOKIT_LAMMPS_PLUGIN, default
build/lib/silokit_lammps.so), with the same -var values.

Scenes (the production physics, cut short: 9-25 CPU-s per run here):
  silo2d   the paper's clogging silo (2870 grains, 32 d wide, mu = 0.4) at
           the campaigns' dt = 2e-5 s and seed 32452843: 1 s of flow with
           fix clog and fix reinject, as segment 2 of a campaign (the
           deck's -var segment 2 -var segment_time 1) from the state a
           segment 1 of 0.1 s wrote; that segment 1 (filling) runs once
           per host, untimed, its CPU and simulated time reported apart
           and the state cached in bench/work/ (the hosts fill for
           different times, doc/lammps_host.md 10.1, and a campaign
           fills once)
  pile2d   the open pile, L = 50 d, model fixed, seed 15485863: the build
           (rain and relaxation, in.build) and one discharge at w = 3 d
           (in.discharge)
  silo3d   the rotating silo, `-var quick 1` (900 spheres, Dc = 12 d,
           D = 5 d), f = 0.32 Hz: 0.4 s of settling and 0.6 s of discharge

Each repetition runs every scene in both hosts, the host order alternating
from one repetition to the next (LIGGGHTS first in even repetitions), one
engine at a time at nice 10. Per run: the CPU time (user + system) of the
engine processes, from os.wait4; the steps and atoms of the `Loop time`
lines; the simulated time from the scene's own records. Per scene: each
host's CPU per run, per simulated second and per step, median [min-max],
and t_lammps/t_liggghts of the process CPU per repetition, median [min-max].

Same physics: on one rank the two hosts build the same pile to the bit
(doc/pile2d.md), so the pile's records (piles.txt, discharges.txt) must be
the same text in both hosts and every repetition, and the same as
LIGGGHTS' recorded ensemble in doc/data; the silos' contact conventions
differ between the hosts (doc/lammps_host.md), so their flows part by
design: for them the records must agree between the repetitions of one
host, and the table gives each host's grains out and clogs.

Writes bench/results/scene_cost_hosts.txt and the section
`scene_cost_hosts` of doc/lammps_host.md (section 10.1).

    /usr/bin/python3 bench/scene_cost_hosts.py            # 3 repetitions, ~5 CPU-min
                                                          # (+ ~2.5 once: the filled silo)
    /usr/bin/python3 bench/scene_cost_hosts.py --quick    # 1 repetition, small runs, < 1 CPU-min
"""

import argparse
import hashlib
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common import hosts  # noqa: E402

# the engines analysis.common.hosts runs ($SILOKIT_LIGGGHTS, $SILOKIT_LMP)
LIGGGHTS, LMP = hosts.LIGGGHTS_BINARY, hosts.LAMMPS_BINARY
PLUGIN = Path(os.environ.get("SILOKIT_LAMMPS_PLUGIN",
                             benchlib.ROOT / "build" / "lib" / "silokit_lammps.so"))
PAGE = benchlib.ROOT / "doc" / "lammps_host.md"
SECTION = "scene_cost_hosts"
HOSTS = ("liggghts", "lammps")
NICE = 10
INPUTS = benchlib.INPUTS
LOOP_TIME = re.compile(r"^Loop time of \S+ on \d+ procs for (\d+) steps with (\d+) atoms",
                       re.MULTILINE)
SILO2D_DONE = re.compile(r"^silo2d: done after (\d+) clogs, (\d+) arches, t = (\S+) s", re.MULTILINE)
# LIGGGHTS' recorded pile ensemble (doc/pile2d.md, results), model fixed
PILE_ENSEMBLE = benchlib.ROOT / "doc" / "data" / "pile2d_discharges.txt"


class Scene:
    """One scene: the engine runs it makes in one directory (deck, -var
    values), the record files that describe its physics, whether the two
    hosts promise the same records, and how to read its simulated time
    and outcome from the directory."""

    def __init__(self, name, title, runs, records, same_in_both, prepare=None, dt=None):
        self.name, self.title, self.runs = name, title, runs
        self.records, self.same_in_both = records, same_in_both
        # (run, files): an untimed run made once per host whose output
        # files the timed runs start from (linked into their directory)
        self.prepare, self.dt = prepare, dt


def scenes(quick):
    common = {"inputs": INPUTS}
    silo2d = {**common, "mu": 0.4, "seed": 32452843, "dt": 2e-5}
    if quick:
        silo2d = {**common, "quick": 1, "dt": 1e-5}
    flow_time = 0.2 if quick else 1.0
    # a campaign's segments: segment 1 fills and flows 0.1 s, writes state1.restart
    fill = ("silo2d", "in.silo2d", {**silo2d, "segment": 1, "segment_time": 0.1, "state": "state"})
    flow = ("silo2d", "in.silo2d", {**silo2d, "segment": 2, "segment_time": flow_time,
                                    "state": "state"})
    pile = {**common, "model": "fixed", "L": 20 if quick else 50, "seed": 15485863,
            "pile": "pile.restart"}
    silo3d = {**common, "quick": 1, "f": 0.32}
    if quick:
        silo3d.update({"settle_time": 0.05, "discharge_time": 0.05})
    return [
        Scene("silo2d", ("clogging silo, the quick one (230 grains)" if quick else
                         "clogging silo, the paper's (2870 grains, dt 2e-5 s)")
              + f": {flow_time} s of flow from the filled state (segment 2)",
              [flow], ("clogs.txt", "reinject.txt"), same_in_both=False,
              prepare=(fill, ("state1.restart",)), dt=silo2d["dt"]),
        Scene("pile2d", f"open pile, L = {pile['L']} d, model fixed: build + one discharge (w = 3 d)",
              [("pile2d", "in.build", {**pile, "piles": "piles.txt"}),
               ("pile2d", "in.discharge", {**pile, "w": 3, "results": "discharges.txt"})],
              ("piles.txt", "discharges.txt"), same_in_both=True),
        Scene("silo3d", "rotating silo, quick (900 spheres), f = 0.32 Hz: settling + discharge",
              [("silo3d_rotating", "in.silo3d_rotating", silo3d)],
              ("discharge.txt",), same_in_both=False),
    ]


# ---------------------------------------------------------------- running

def engine_run(host, folder, deck, variables, workdir, log):
    """One engine run of a deck at nice 10; (cpu seconds, screen text).
    The command is `nice stdbuf engine ...`: both wrappers exec, so the
    process waited for is the engine and wait4 gives its own usage."""
    variables = dict(variables)
    if host == "lammps":
        variables["plugin"] = PLUGIN
    command = hosts.engine_command(host, INPUTS / folder / hosts.deck_name(host, deck),
                                   variables, nice=NICE)
    with open(log, "w") as screen:
        process = subprocess.Popen(command, cwd=workdir, stdout=screen, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(process.pid, 0)
    output = Path(log).read_text(errors="replace")
    errors = [line for line in output.splitlines() if line.startswith("ERROR")]
    if os.waitstatus_to_exitcode(status) != 0 or errors:
        raise benchlib.LiggghtsFailed(f"{host} {deck} failed in {workdir}: "
                                      f"{errors[0] if errors else output.splitlines()[-3:]}")
    return usage.ru_utime + usage.ru_stime, output


def prepare_scene(scene, host, workdir):
    """The scene's untimed run in `workdir`, once (kept while its files
    are there): dict of cpu, steps, simulated time, screen output."""
    (folder, deck, variables), files = scene.prepare
    screen = workdir / "prepare.txt"
    if not all((workdir / name).exists() for name in files) or not screen.exists():
        shutil.rmtree(workdir, ignore_errors=True)
        workdir.mkdir(parents=True)
        benchlib.progress(f"{scene.name} {host}: the untimed run ({deck} "
                          + " ".join(f"{k} {v}" for k, v in variables.items() if k != "inputs")
                          + f"), once, in {benchlib.shown_path(workdir)}")
        cpu, output = engine_run(host, folder, deck, variables, workdir, workdir / "run.txt")
        (workdir / "cpu.txt").write_text(f"{cpu:.2f}\n")
        (workdir / "run.txt").rename(screen)
    output = screen.read_text(errors="replace")
    steps = sum(int(s) for s, _ in LOOP_TIME.findall(output))
    return {"cpu": float((workdir / "cpu.txt").read_text()), "steps": steps,
            "simulated": steps * scene.dt, "output": output}


def engine_files(host):
    """The files whose change changes what a host computes."""
    if host == "liggghts":
        return [LIGGGHTS]
    return [LMP, LMP.resolve().parent.parent / "lib" / "liblammps.so.0", PLUGIN]


def prepared_key(scene, host):
    """The name of a scene's untimed run in `host`: a digest of its
    variables, the deck's text and the engine's files, so that another
    deck or build runs it again rather than reuse a state it would not
    write (the key once hashed the variables alone)."""
    (folder, deck, _), _ = scene.prepare
    digest = hashlib.sha256(repr(scene.prepare).encode())
    digest.update((INPUTS / folder / hosts.deck_name(host, deck)).read_bytes())
    for path in engine_files(host):
        digest.update(path.read_bytes() if path.exists() else b"missing")
    return digest.hexdigest()[:10]


def run_scene(scene, host, workdir, prepared=None):
    """All runs of a scene in a fresh directory (the prepared files linked
    into it): dict of cpu, steps, atoms, simulated time, outcome, the
    records' text."""
    shutil.rmtree(workdir, ignore_errors=True)
    workdir.mkdir(parents=True)
    for name in (scene.prepare[1] if scene.prepare else ()):
        (workdir / name).symlink_to(prepared / name)
    cpu, outputs = 0.0, []
    for k, (folder, deck, variables) in enumerate(scene.runs):
        seconds, output = engine_run(host, folder, deck, variables, workdir,
                                     workdir / f"screen{k}.txt")
        cpu += seconds
        outputs.append(output)
    loops = [(int(s), int(a)) for output in outputs for s, a in LOOP_TIME.findall(output)]
    records = {name: (workdir / name).read_text() for name in scene.records}
    steps = sum(s for s, _ in loops)
    simulated, outcome = SCENE_READERS[scene.name](workdir, outputs, records, steps * (scene.dt or 0))
    return {"cpu": cpu, "steps": steps, "atoms": max(a for _, a in loops),
            "simulated": simulated, "outcome": outcome, "records": records}


def data_rows(text):
    return [line.split() for line in text.splitlines() if line.strip() and not line.startswith("#")]


def read_silo2d(workdir, outputs, records, steps_time):
    """Simulated time: the segment's steps times dt (LAMMPS' `time` starts
    again at a restart); outcome: clogs, lines of the re-entry record."""
    clogs, arches, t_end = SILO2D_DONE.findall(outputs[-1])[-1]
    reentered = len(data_rows(records["reinject.txt"]))
    return steps_time, f"{clogs} clogs, {reentered} re-entry lines, t_end {float(t_end):.4g} s"


def read_pile(workdir, outputs, records, steps_time):
    """Simulated time: the build's and the discharge's t_end (s; each counts
    from its own start); outcome: grains of the pile, grains out."""
    pile = data_rows(records["piles.txt"])[-1]
    discharge = data_rows(records["discharges.txt"])[-1]
    return (float(pile[8]) + float(discharge[9]),
            f"n_pile {pile[3]}, h0 {float(pile[4]):.4f}; w = 3: {discharge[5]} out, h {float(discharge[4]):.4f}")


def read_silo3d(workdir, outputs, records, steps_time):
    """Simulated time from run.txt (`finished`); outcome: grains out at the end."""
    finished = [line.split()[1] for line in (workdir / "run.txt").read_text().splitlines()
                if line.startswith("finished ")]
    last = data_rows(records["discharge.txt"])[-1]
    return float(finished[-1]), f"{last[2]} grains out"


SCENE_READERS = {"silo2d": read_silo2d, "pile2d": read_pile, "silo3d": read_silo3d}


def ensemble_check(results):
    """The pile's discharge line in LIGGGHTS' recorded ensemble (doc/data),
    compared word for word (numbers as numbers: the record writes 50.0)."""
    ours = data_rows(results[0]["records"]["discharges.txt"])[-1]
    key = [float(x) for x in ours[1:4]]
    for row in data_rows(PILE_ENSEMBLE.read_text()):
        if row[0] == ours[0] and [float(x) for x in row[1:4]] == key:
            same = all(a == b or float(a) == float(b) for a, b in zip(ours, row))
            return ("the same line as LIGGGHTS' recorded ensemble "
                    f"(`doc/data/{PILE_ENSEMBLE.name}`)" if same else
                    f"differs from LIGGGHTS' recorded ensemble: {' '.join(row)}")
    return "not in LIGGGHTS' recorded ensemble (another L or seed)"


# ---------------------------------------------------------------- report

def spread_cell(values, digits=3):
    median, low, high = benchlib.spread(values)
    return f"{median:.{digits}g} [{low:.{digits}g}–{high:.{digits}g}]"


def ratio_cell(values):
    """A ratio near 1 with three decimals (`:.3g` would print 1.005 as 1)."""
    median, low, high = benchlib.spread(values)
    return f"{median:.3f} [{low:.3f}–{high:.3f}]"


def lammps_identity():
    """`lmp` is a launcher: LAMMPS is the liblammps.so.0 beside it in ../lib."""
    library = engine_files("lammps")[1]
    found = benchlib.binary_identity(LMP)
    return f"{found} with {benchlib.binary_identity(library)}" if library.exists() else found


def consistency(scene, results):
    """What the records say about the physics of the runs."""
    texts = {host: {tuple(sorted(r["records"].items())) for r in results[host]} for host in HOSTS}
    names = ", ".join(f"`{n}`" for n in scene.records)
    repeatable = all(len(t) == 1 for t in texts.values())
    if scene.same_in_both:
        if repeatable and texts["liggghts"] == texts["lammps"]:
            return (f"{names}: the same text in both hosts and every repetition; "
                    + ensemble_check(results["lammps"]) + ".")
        return f"{names}: NOT the same in both hosts and every repetition (the decks promise it)."
    outcome = "; ".join(f"{host} {results[host][0]['outcome']}" for host in HOSTS)
    return (f"{names}: " + ("the same text in every repetition of a host"
                            if repeatable else "DIFFER between repetitions of a host")
            + f"; the hosts differ by design ({outcome}).")


def report(all_scenes, results, prepared, args, start_load):
    end_load = benchlib.load_average()
    lines = [
        "Measured with `bench/scene_cost_hosts.py`: each scene's production deck in "
        "LIGGGHTS and its `.lammps` twin in LAMMPS, the same `-var` values, "
        f"{args.repetitions} repetition{'s' if args.repetitions > 1 else ''}; in each, every "
        "scene runs in both hosts one after the other, the host order alternating from one "
        "repetition to the next (LIGGGHTS first in the first), one engine at a time at nice "
        f"{NICE}, serially. CPU: user + system time of the engine processes (start-up and "
        "set-up included), which the time spent waiting for a core does not inflate. "
        "t_lammps/t_liggghts is taken within each repetition.",
        "",
        "| scene | steps | atoms | simulated (s) | host | CPU per run (s) | CPU per simulated s "
        "| CPU per step (µs) | t_lammps/t_liggghts (CPU) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for scene in all_scenes:
        per = results[scene.name]
        ratios = [b["cpu"] / a["cpu"] for a, b in zip(per["liggghts"], per["lammps"])]
        for k, host in enumerate(HOSTS):
            runs = per[host]
            first = runs[0]
            lines.append(
                f"| {scene.name if k == 0 else ''} | {first['steps']} | {first['atoms']} "
                f"| {first['simulated']:.4g} | {host} "
                f"| {spread_cell([r['cpu'] for r in runs])} "
                f"| {spread_cell([r['cpu'] / r['simulated'] for r in runs])} "
                f"| {spread_cell([1e6 * r['cpu'] / r['steps'] for r in runs])} "
                f"| {ratio_cell(ratios) if k == 0 else ''} |")
    lines += ["", "Scenes:"]
    for scene in all_scenes:
        commands = "; ".join(
            f"`{hosts.deck_name('liggghts', deck)}`(`.lammps`) "
            + " ".join(f"-var {k} {v}" for k, v in variables.items() if k != "inputs")
            for _, deck, variables in scene.runs)
        lines.append(f"- **{scene.name}** {scene.title}: {commands}.")
    for scene in [s for s in all_scenes if s.prepare]:
        runs = {host: prepared[(scene.name, host)][1] for host in HOSTS}
        (_, deck, variables), _ = scene.prepare
        lines += ["", f"The untimed run the **{scene.name}** runs start from (`{deck}` "
                  + " ".join(f"-var {k} {v}" for k, v in variables.items() if k != "inputs")
                  + ", once per host, cached): "
                  + "; ".join(f"{host} {runs[host]['steps']} steps, {runs[host]['simulated']:.4g} s "
                              f"simulated, {runs[host]['cpu']:.1f} CPU-s" for host in HOSTS) + "."]
    lines += ["", "Steps: the sum of the `Loop time` lines of the first run (the hosts' run "
              "chunks differ, so the counts may differ by a few steps); atoms: the most in any "
              "`run`; simulated: the scene's own clock (silo2d its steps times Δt, pile2d "
              "the build's plus the discharge's `t_end`, silo3d `run.txt`'s `finished`). "
              "The same physics:"]
    lines += [f"- {scene.name}: {consistency(scene, results[scene.name])}" for scene in all_scenes]
    info = benchlib.machine()
    lines += [
        "",
        f"- machine: {info['nproc']} cores, {info['cpu']}, {info['system']}; date: {info['date']}; "
        f"load average (1/5/15 min) {start_load} at the start, {end_load} at the end",
        f"- command (from the repository root): `{benchlib.command_line()}`",
        f"- silokit commit: {benchlib.git_commit()}",
        f"- LIGGGHTS: {benchlib.binary_identity(LIGGGHTS)}",
        f"- LAMMPS: {lammps_identity()}; plugin: {benchlib.binary_identity(PLUGIN)}",
    ]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 1 repetition, the quick silo, L = 20 d, a short "
                             "rotating silo; writes under bench/work/quick/")
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--scenes", nargs="+", choices=list(SCENE_READERS),
                        default=list(SCENE_READERS), help="the scenes to run (default: all)")
    args = parser.parse_args()
    global PAGE
    work = benchlib.WORK / SECTION
    if args.quick:
        benchlib.use_smoke_outputs()
        PAGE = benchlib.WORK / "quick" / "lammps_host.md"
        work = benchlib.WORK / "quick" / SECTION
        args.repetitions = 1
    if args.repetitions < 1:
        parser.error(f"--repetitions {args.repetitions}: at least 1")
    for path in (LIGGGHTS, LMP, PLUGIN):
        if not path.exists():
            sys.exit(f"{path} is missing: set SILOKIT_LIGGGHTS, SILOKIT_LMP, SILOKIT_LAMMPS_PLUGIN")

    start_load = benchlib.load_average()
    all_scenes = [s for s in scenes(args.quick) if s.name in args.scenes]
    results = {s.name: {h: [] for h in HOSTS} for s in all_scenes}
    prepared = {}
    for scene in [s for s in all_scenes if s.prepare]:
        for host in HOSTS:
            folder = work / f"{scene.name}_prepared" / f"{host}_{prepared_key(scene, host)}"
            prepared[(scene.name, host)] = (folder, prepare_scene(scene, host, folder))
    raw = ["# scene_cost_hosts raw runs", f"# {benchlib.command_line()}",
           "# repetition scene host cpu_s steps atoms simulated_s outcome"]
    for rep in range(args.repetitions):
        order = HOSTS if rep % 2 == 0 else HOSTS[::-1]
        for scene in all_scenes:
            for host in order:
                started = time.time()
                result = run_scene(scene, host, work / scene.name / host,
                                   prepared.get((scene.name, host), (None,))[0])
                results[scene.name][host].append(result)
                raw.append(f"{rep} {scene.name} {host} {result['cpu']:.2f} {result['steps']} "
                           f"{result['atoms']} {result['simulated']:.6g} {result['outcome']}")
                benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {scene.name} {host:8s} "
                                  f"{result['cpu']:6.1f} CPU-s ({time.time() - started:.0f} s wall), "
                                  f"{result['steps']} steps, {result['simulated']:.4g} s simulated; "
                                  f"{result['outcome']}")

    table = report(all_scenes, results, prepared, args, start_load)
    benchlib.write_page_section(PAGE, SECTION, table, header="# LAMMPS host\n")
    path = benchlib.write_raw(SECTION, table + "\n\n## Raw runs\n\n" + "\n".join(raw) + "\n")
    benchlib.progress(f"wrote {benchlib.shown_path(PAGE)} and {benchlib.shown_path(path)}")
    print(table)


if __name__ == "__main__":
    main()
