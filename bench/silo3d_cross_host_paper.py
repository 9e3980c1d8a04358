#!/usr/bin/python3
"""The paper's rotating silo (spheres: N = 10 000, Dc = 0.19 m, D = 0.06 m,
dt = t_c/40) in both hosts, side by side: the LIGGGHTS deck
(inputs/silo3d_rotating/in.silo3d_rotating, build/bin/liggghts) and the
LAMMPS deck (in.silo3d_rotating.lammps, build/bin/lmp with our plugin).

Per seed (a prime, the gas's), each host settles its own packing once (1 s
in the closed silo, written with write_packing) and discharges it at each
frequency (default f = 0 and 0.32 Hz, read_packing) for 2 s with
reinjection (reinject 1: the grains re-enter at the top, the flow stays
stationary), as examples/silo3d_rotating/run.sh runs the scene's spheres.
Q is taken over 0.5-2 s after the opening (analysis.silo3d_rotating, block
standard errors), the window of the page's sphere row. A clog at rest ends
a run (the decks' clog_stop): it counts as finished, without a Q.

Resumable. Each run has its own directory in the campaign directory given
on the command line, <host>_packing_s<seed> and <host>_D<D>_f<f>_s<seed>;
a run whose run.txt ends with the decks' `finished` line is kept, any
other is started again from its beginning (a discharge is some 10 CPU-min).
As each run finishes, its records (run.txt, discharge.txt, and cost.txt:
process CPU and wall seconds, the binaries' sha256) are copied into the
records directory (default doc/data/silo3d_cross_host/); a run whose
records are there is done, even if the campaign directory is gone. A
packing is settled again only when a run still needs it (settling a seed
again gives the same packing). The engines die with the driver (parent
death signal), and a second driver on the same campaign directory is
refused. A run that fails within its first minute (a binary being
relinked) is tried once more 30 s later; any other failure is reported
(exit status 1) and left for the next invocation. A finished run of
another protocol (D, f, N, discharge time) stops the driver.

The report, written from the records alone (--report-only rebuilds it
without running anything): Q per run with its block error; per host and
f the mean over packings with its 95 % Student-t interval; LAMMPS -
LIGGGHTS per f with its Welch 95 % interval; each host's Q(f)/Q(0) - 1
paired by packing; CPU per run and per host. It goes to
bench/results/silo3d_cross_host_paper.txt and to the section
`silo3d_cross_host_paper` of doc/silo3d_rotating.md.

    /usr/bin/python3 bench/silo3d_cross_host_paper.py runs/cross_host_paper            # run or resume
    /usr/bin/python3 bench/silo3d_cross_host_paper.py runs/cross_host_paper --jobs 2   # two engines at once
    /usr/bin/python3 bench/silo3d_cross_host_paper.py runs/cross_host_paper --frequencies 0 0.32 1.28 --hosts liggghts
    /usr/bin/python3 bench/silo3d_cross_host_paper.py --report-only                    # the report from doc/data
    /usr/bin/python3 bench/silo3d_cross_host_paper.py --quick                          # smoke: the quick silo, 0.2 s, 1 seed, f = 0

--quick runs the quick silo (900 spheres, Dc = 0.1188 m, D = 0.05 m,
0.4 s of settling) into bench/work/quick/silo3d_cross_host_paper/ (records
in its records/), and writes its report under bench/work/quick/.
"""

import argparse
import ctypes
import datetime
import hashlib
import os
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402
from silo3d_cross_host import CONFIDENCE, LMP, PLUGIN, SEEDS, deck, welch  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.stats import mean_t_ci  # noqa: E402
from analysis.silo3d_rotating.flow import analyse_flow  # noqa: E402
from analysis.silo3d_rotating.records import load_run, read_run_info  # noqa: E402

HOSTS = ("liggghts", "lammps")
BINARIES = {"liggghts": benchlib.OUR_BINARY, "lammps": LMP}
RECORDS = benchlib.ROOT / "doc" / "data" / "silo3d_cross_host"
PAGE = benchlib.ROOT / "doc" / "silo3d_rotating.md"
SECTION = "silo3d_cross_host_paper"
RECORD_FILES = ("run.txt", "discharge.txt", "cost.txt")
LOCK = "driver.pid"
PR_SET_PDEATHSIG = 1                    # <linux/prctl.h>
EARLY_FAILURE = 60                      # s: a run failing this soon gets one retry ...
RETRY_AFTER = 30                        # s: ... this much later (a binary being relinked)
POLL = 1.0                              # s between looks at the running engines


@dataclass(frozen=True)
class Protocol:
    """What every run of a campaign shares."""
    quick: bool
    D: float                            # orifice (m)
    discharge: float                    # s of discharge after the opening
    transient: float                    # s after the opening left out of Q
    dt_fraction: int = 40               # dt = t_c/dt_fraction, the scene's sphere runs


PAPER = Protocol(quick=False, D=0.06, discharge=2.0, transient=0.5)
QUICK = Protocol(quick=True, D=0.05, discharge=0.2, transient=0.05)


@dataclass(frozen=True)
class Run:
    """One run: a host's packing of a seed (f is None), or its discharge at f."""
    host: str
    seed: int
    f: float = None

    @property
    def is_packing(self):
        return self.f is None

    def name(self, protocol):
        if self.is_packing:
            return f"{self.host}_packing_s{self.seed}"
        return f"{self.host}_D{protocol.D:g}_f{self.f:g}_s{self.seed}"

    def packing(self):
        return Run(self.host, self.seed)


def is_finished(directory):
    """The decks append `finished t` to run.txt as their last act (LIGGGHTS
    ends a run it got SIGTERM for with exit status 0: only this line says
    the run reached its end)."""
    path = Path(directory) / "run.txt"
    return path.exists() and any(line.split()[:1] == ["finished"] for line in path.read_text().splitlines())


def deck_variables(run, protocol, campaign):
    """The deck's -var settings of one run (both hosts take the same names)."""
    variables = {"seed": run.seed, "dt_fraction": protocol.dt_fraction}
    if protocol.quick:
        variables["quick"] = 1
    packing = campaign / run.packing().name(protocol) / "packing.restart"
    if run.is_packing:
        # the bottom opens after the settling: no discharge (LIGGGHTS runs
        # one 0.05 s chunk of it, as run.sh's settlings do)
        return {**variables, "write_packing": 1, "packing": packing, "discharge_time": 0}
    return {**variables, "read_packing": 1, "packing": packing, "reinject": 1, "D": protocol.D,
            "f": f"{run.f:g}", "discharge_time": protocol.discharge}


def plan(runs, protocol, campaign, records):
    """What to do now: (to_run, to_copy, done). A run is done when its
    records are in `records`, to_copy when only its campaign directory has
    it finished. A packing is run only if a discharge to run needs it and
    its campaign directory holds no finished one with its packing file;
    to_run lists each packing ahead of its discharges."""
    to_run, to_copy, done = [], [], []
    for run in runs:
        name = run.name(protocol)
        if is_finished(records / name):
            done.append(run)
        elif is_finished(campaign / name):
            to_copy.append(run)
        elif not run.is_packing:
            to_run.append(run)
    for run in list(to_run):
        packing = run.packing()
        directory = campaign / packing.name(protocol)
        ready = is_finished(directory) and (directory / "packing.restart").exists()
        if not ready and packing not in to_run:
            to_run.append(packing)
    order = {run: k for k, run in enumerate(runs)}
    return sorted(to_run, key=lambda run: order[run]), to_copy, done


def campaign_runs(seeds, frequencies):
    """Every run, seed by seed, each host's packing before its discharges."""
    return [Run(host, seed, f) for seed in seeds for host in HOSTS for f in (None, *frequencies)]


def check_protocol(run, protocol, directory):
    """A finished run kept from before must be of this protocol (a campaign
    directory or records folder holds one protocol)."""
    info = read_run_info(directory, required=())
    expected = {"seed": run.seed, "N": 900 if protocol.quick else 10000}
    if not run.is_packing:
        expected.update(D=protocol.D, f=run.f, discharge_time=protocol.discharge, reinject=1)
    wrong = {key: info.get(key) for key, value in expected.items()
             if info.get(key) is None or abs(info[key] - value) > 1e-9 * max(1.0, abs(value))}
    if wrong:
        sys.exit(f"{directory} holds a finished run with {wrong}, not {expected}: "
                 "another protocol; give another campaign directory (and --records)")


# ---- running the engines ------------------------------------------------------

def sha256_prefix(path):
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:12]


def binaries_of(host):
    """The files whose code a host's run executes: LAMMPS' lmp is a small
    front end to bin/../lib/liblammps.so.0, and the plugin."""
    if host == "liggghts":
        return [benchlib.OUR_BINARY]
    return [LMP, LMP.resolve().parent.parent / "lib" / "liblammps.so.0", PLUGIN]


def die_with_parent():
    """In the engine's process before exec: SIGTERM when the driver dies,
    so that no engine goes on writing into a run directory that the next
    driver starts again."""
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGTERM)


def launch(run, protocol, campaign):
    """Starts one run in a fresh directory: (Popen, start time, identity)."""
    directory = campaign / run.name(protocol)
    if directory.exists():
        shutil.rmtree(directory)
    directory.mkdir(parents=True)
    (directory / "in.deck").write_text(deck(run.host, deck_variables(run, protocol, campaign)))
    identity = [f"{benchlib.shown_path(path)} {sha256_prefix(path)}" for path in binaries_of(run.host)]
    with open(directory / "screen.txt", "w") as screen:
        process = subprocess.Popen([str(BINARIES[run.host]), "-in", "in.deck", "-log", "none"],
                                   cwd=directory, stdout=screen, stderr=subprocess.STDOUT,
                                   preexec_fn=die_with_parent)
    return process, time.perf_counter(), identity


def write_cost(directory, cpu, wall, identity):
    lines = ["# process CPU (user + system) and wall-clock seconds of the run; the code it ran (sha256)",
             f"cpu_seconds {cpu:.1f}", f"wall_seconds {wall:.1f}",
             f"date {datetime.datetime.now().astimezone().strftime('%Y-%m-%dT%H:%M%z')}"]
    lines += [f"binary {line}" for line in identity]
    (directory / "cost.txt").write_text("\n".join(lines) + "\n")


def failure_of(directory, status):
    """Why a run that ended is not a finished run, or None."""
    output = (directory / "screen.txt").read_text(errors="replace")
    errors = [line for line in output.splitlines() if "ERROR" in line]
    if status != 0 or errors:
        return errors[0] if errors else f"exit status {status}"
    if not is_finished(directory):
        return "ended before its `finished` line (SIGTERM?)"
    return None


def copy_records(run, protocol, campaign, records):
    """The run's records into records/<name>, whole or not at all (through
    a temporary folder: an interrupted copy leaves no run that looks done)."""
    name = run.name(protocol)
    target, part = records / name, records / f"{name}.part"
    shutil.rmtree(part, ignore_errors=True)
    part.mkdir(parents=True)
    for file in RECORD_FILES:
        source = campaign / name / file
        if source.exists() and not (run.is_packing and file == "discharge.txt"):
            shutil.copy2(source, part / file)
    shutil.rmtree(target, ignore_errors=True)
    part.rename(target)


def cost_of(directory):
    """cost.txt's CPU and wall seconds (NaN where missing) and its binary lines."""
    cost = {"cpu_seconds": np.nan, "wall_seconds": np.nan, "binaries": []}
    path = Path(directory) / "cost.txt"
    for line in (path.read_text().splitlines() if path.exists() else []):
        key, _, value = line.partition(" ")
        if key in ("cpu_seconds", "wall_seconds"):
            cost[key] = float(value)
        elif key == "binary":
            cost["binaries"].append(value)
    return cost


def describe(run, protocol, directory):
    """The progress line's account of a finished run."""
    cpu = cost_of(directory)["cpu_seconds"]
    if run.is_packing:
        return f"settled, {cpu:.0f} s CPU"
    info = read_run_info(directory, required=())
    if "clogged" in info:
        return f"clogged at rest at t = {info['clogged']:g} s (no Q), {cpu:.0f} s CPU"
    flow = analyse_flow(load_run(directory), transient=protocol.transient)
    return f"Q = {flow.q_mass:.4f} +- {flow.q_mass_se:.4f} kg/s, {cpu:.0f} s CPU"


@dataclass
class Running:
    run: Run
    process: subprocess.Popen
    start: float
    identity: list


def run_campaign(runs, protocol, campaign, records, jobs):
    """Runs what plan() asks for, `jobs` engines at a time, each discharge
    after its packing; returns the names of the runs that failed."""
    to_run, to_copy, done = plan(runs, protocol, campaign, records)
    for run in done:
        check_protocol(run, protocol, records / run.name(protocol))
        if run not in to_run:      # (a packing whose file is gone is settled again)
            benchlib.progress(f"{run.name(protocol)}: done before, records in {benchlib.shown_path(records)}")
    for run in to_copy:
        check_protocol(run, protocol, campaign / run.name(protocol))
        copy_records(run, protocol, campaign, records)
        benchlib.progress(f"{run.name(protocol)}: finished before, records copied")
    pending, running, failed, retry_at, launched = list(to_run), {}, set(), {}, 0
    total = len(pending)
    before = sum(not run.is_packing for run in done + to_copy)
    benchlib.progress(f"{before} discharges done before, {total} runs to do "
                      f"({sum(run.is_packing for run in pending)} packings), {jobs} at a time")

    def failure(run, problem, wall):
        """A run that fails at its start (a binary being relinked) gets one
        more try after RETRY_AFTER s; any other failure is left for the
        next driver."""
        name = run.name(protocol)
        if wall < EARLY_FAILURE and run not in retry_at:
            retry_at[run] = time.monotonic() + RETRY_AFTER
            pending.insert(0, run)
            benchlib.progress(f"{name}: FAILED after {wall:.0f} s ({problem}): once more in {RETRY_AFTER} s")
            return
        failed.add(name)
        benchlib.progress(f"{name}: FAILED ({problem}); see {campaign / name / 'screen.txt'}; "
                          "the same command runs it again")

    while pending or running:
        busy = {job.run for job in running.values()}
        waiting = set(pending) | busy
        ready = [run for run in pending if (run.is_packing or run.packing() not in waiting)
                 and retry_at.get(run, 0) <= time.monotonic()]
        for run in ready[:max(0, jobs - len(running))]:
            pending.remove(run)
            if not run.is_packing and run.packing().name(protocol) in failed:
                failed.add(run.name(protocol))
                benchlib.progress(f"{run.name(protocol)}: not run, its packing failed")
                continue
            try:
                process, start, identity = launch(run, protocol, campaign)
            except OSError as problem:     # (a binary being relinked: permission denied, text file busy)
                failure(run, f"{BINARIES[run.host]} did not start: {problem}", 0.0)
                continue
            running[process.pid] = Running(run, process, start, identity)
            if run in retry_at:
                benchlib.progress(f"{run.name(protocol)}: started again")
            else:
                launched += 1
                benchlib.progress(f"{run.name(protocol)}: started ({launched} of {total})")
        # (polled: a run waiting for its retry starts while others run)
        pid, status, usage = os.wait4(-1, os.WNOHANG) if running else (0, 0, None)
        job = running.pop(pid, None)
        if job is None:
            time.sleep(POLL)
            continue
        job.process.returncode = os.waitstatus_to_exitcode(status)
        name, directory = job.run.name(protocol), campaign / job.run.name(protocol)
        wall = time.perf_counter() - job.start
        write_cost(directory, usage.ru_utime + usage.ru_stime, wall, job.identity)
        problem = failure_of(directory, job.process.returncode)
        if problem:
            failure(job.run, problem, wall)
            continue
        copy_records(job.run, protocol, campaign, records)
        benchlib.progress(f"{name}: {describe(job.run, protocol, directory)}")
    return sorted(failed)


def lock(campaign):
    """One driver per campaign directory: a second one would start again
    the runs the first is running."""
    path = campaign / LOCK
    if path.exists():
        try:
            pid = int(path.read_text().split()[0])
            command = Path(f"/proc/{pid}/cmdline").read_bytes().decode(errors="replace")
        except (ValueError, IndexError, OSError):
            command = ""
        if Path(__file__).name in command:
            sys.exit(f"{campaign} is being run by the driver with PID {pid} ({path}); "
                     "wait for it, or end it by its PID")
    path.write_text(f"{os.getpid()}\n")
    return path


# ---- the report, from the records alone ------------------------------------------

@dataclass
class Record:
    """One finished run as its records give it."""
    name: str
    host: str
    seed: int
    f: float                            # None for a packing
    info: dict
    cost: dict
    q: float = np.nan
    q_se: float = np.nan
    n_out: float = np.nan

    @property
    def clogged(self):
        return "clogged" in self.info


def read_records(records, transient):
    """Every finished run in `records`, packings and discharges."""
    found = []
    for directory in sorted(records.glob("*_s*")) if records.exists() else []:
        if directory.name.endswith(".part") or not is_finished(directory):
            continue
        host = directory.name.split("_")[0]
        info = read_run_info(directory, required=())
        record = Record(directory.name, host, int(info["seed"]),
                        None if "_packing_" in directory.name else info["f"], info, cost_of(directory))
        if record.f is not None:
            run = load_run(directory)
            record.n_out = float(run.discharge["n_out"][-1])
            # a clog at rest ends the run before the window does: no Q over
            # the window (as analysis.silo3d_rotating.results.window_rate)
            if not record.clogged:
                flow = analyse_flow(run, transient=transient)
                record.q, record.q_se = flow.q_mass, flow.q_mass_se
        found.append(record)
    return found


def host_label(host):
    return {"liggghts": "LIGGGHTS", "lammps": "LAMMPS"}[host]


def q_table(discharges, frequencies):
    """Per host and f: mean over packings, its t interval, sd, each packing."""
    lines = ["| host | f (Hz) | packings | Q (kg/s), mean ± 95 % CI | sd between packings | "
             "per packing: Q ± block SE (seed) |", "|---|---|---|---|---|---|"]
    for host in HOSTS:
        for f in frequencies:
            runs = [r for r in discharges if r.host == host and r.f == f]
            flowing = [r.q for r in runs if np.isfinite(r.q)]
            mean, half = mean_t_ci(flowing, CONFIDENCE)
            sd = f"{np.std(flowing, ddof=1):.4f}" if len(flowing) > 1 else "—"
            each = ", ".join(f"{r.q:.4f} ± {r.q_se:.4f} ({r.seed})" if np.isfinite(r.q)
                             else f"clogged ({r.seed})" for r in runs)
            lines.append(f"| {host_label(host)} | {f:g} | {len(flowing)} | {number(mean, half)} | "
                         f"{sd} | {each or '—'} |")
    return lines


def number(value, half, digits=4):
    if not np.isfinite(value):
        return "—"
    return f"{value:.{digits}f}" + (f" ± {half:.{digits}f}" if np.isfinite(half) else " (one packing)")


def comparisons(discharges, frequencies):
    """LAMMPS - LIGGGHTS per f (Welch) and each host's Q(f)/Q(f0) - 1 paired by packing."""
    lines = []
    for f in frequencies:
        q = {host: [r.q for r in discharges if r.host == host and r.f == f and np.isfinite(r.q)]
             for host in HOSTS}
        if min(len(values) for values in q.values()) < 2:
            lines.append(f"- f = {f:g} Hz: LAMMPS − LIGGGHTS needs two flowing packings per host "
                         f"(LIGGGHTS {len(q['liggghts'])}, LAMMPS {len(q['lammps'])})")
            continue
        difference, half = welch(q["lammps"], q["liggghts"], CONFIDENCE)
        base = np.mean(q["liggghts"])
        verdict = ("the hosts agree within the interval" if abs(difference) <= half
                   else "the hosts differ by more than the interval")
        lines.append(f"- f = {f:g} Hz: LAMMPS − LIGGGHTS = {difference:+.4f} ± {half:.4f} kg/s "
                     f"(Welch, 95 %), {100 * difference / base:+.1f} ± {100 * half / base:.1f} % "
                     f"of LIGGGHTS' Q: {verdict}")
    reference = frequencies[0]
    for f in frequencies[1:]:
        parts = []
        for host in HOSTS:
            by_seed = {r.seed: r.q for r in discharges if r.host == host and r.f == reference}
            changes = [r.q / by_seed[r.seed] - 1 for r in discharges
                       if r.host == host and r.f == f and np.isfinite(r.q) and np.isfinite(by_seed.get(r.seed, np.nan))]
            mean, half = mean_t_ci(changes, CONFIDENCE)
            parts.append(f"{host_label(host)} " + (f"{100 * mean:+.1f}" if np.isfinite(mean) else "—")
                         + (f" ± {100 * half:.1f} %" if np.isfinite(half) else " %")
                         + f" ({len(changes)} packings)")
        lines.append(f"- Q({f:g} Hz)/Q({reference:g}) − 1, paired by packing (95 %): " + "; ".join(parts))
    return lines


def cost_table(records):
    lines = ["| host | settlings: CPU s each, mean (runs) | discharges: CPU s each, mean (runs) | "
             "wall s per discharge, mean | CPU, all its runs |", "|---|---|---|---|---|"]
    for host in HOSTS:
        packings = [r.cost["cpu_seconds"] for r in records if r.host == host and r.f is None]
        runs = [r for r in records if r.host == host and r.f is not None]
        cpu = [r.cost["cpu_seconds"] for r in runs]
        wall = [r.cost["wall_seconds"] for r in runs]
        lines.append(f"| {host_label(host)} | {mean_or_dash(packings)} ({len(packings)}) | "
                     f"{mean_or_dash(cpu)} ({len(cpu)}) | {mean_or_dash(wall)} | "
                     f"{np.nansum(packings + cpu):.0f} s = {np.nansum(packings + cpu) / 3600:.2f} h |")
    return lines


def mean_or_dash(values):
    return f"{np.nanmean(values):.0f}" if len(values) and np.isfinite(values).any() else "—"


def run_table(discharges):
    lines = ["| run | Q (kg/s) ± block SE | grains out | CPU (s) | wall (s) |", "|---|---|---|---|---|"]
    for r in discharges:
        q = f"{r.q:.4f} ± {r.q_se:.4f}" if np.isfinite(r.q) else \
            (f"clogged at rest at t = {r.info['clogged']:g} s" if r.clogged else "no stationary flow")
        lines.append(f"| {r.name} | {q} | {r.n_out:.0f} | {mean_or_dash([r.cost['cpu_seconds']])} | "
                     f"{mean_or_dash([r.cost['wall_seconds']])} |")
    return lines


QUICK_SILO, PAPER_SILO = "The quick silo", "The paper's silo"


def report(records, asked, protocol, records_dir):
    """The section's Markdown, from the records found and the runs asked for."""
    # each packing's runs side by side
    discharges = sorted((r for r in records if r.f is not None), key=lambda r: (r.f, r.seed, HOSTS.index(r.host)))
    frequencies = sorted({run.f for run in asked if not run.is_packing} | {r.f for r in discharges})
    names = {r.name for r in records}
    missing = [run.name(protocol) for run in asked if not run.is_packing and run.name(protocol) not in names]
    asked_discharges = sum(not run.is_packing for run in asked)
    if not discharges:
        settled = sum(r.f is None for r in records)
        return (f"Not run yet: 0 of the {asked_discharges} discharges and {settled} of the "
                f"{len(asked) - asked_discharges} settlings asked for are in "
                f"`{benchlib.shown_path(records_dir)}/` ({benchlib.machine()['date']}). "
                f"`bench/silo3d_cross_host_paper.py` writes the tables here from them when it ends, "
                f"and with `--report-only` at any time.\n")
    info = discharges[0].info
    silo = f"N = {info['N']:.0f} spheres, Dc = {info['Dc']:g} m, D = {info['D']:g} m, dt = {info['dt']:.4g} s"
    binaries = sorted({line for r in records for line in r.cost["binaries"]})
    status = (f"{asked_discharges - len(missing)} of the {asked_discharges} discharges asked for are finished"
              + (f"; missing: {', '.join(missing)}" if missing else ""))
    return "\n".join([
        f"Written by `bench/silo3d_cross_host_paper.py` from the records in "
        f"`{benchlib.shown_path(records_dir)}/` (its docstring says what it runs). "
        f"{QUICK_SILO if protocol.quick else PAPER_SILO}: {silo}; each host "
        f"settles its own packing per seed and discharges it at f = "
        f"{', '.join(f'{f:g}' for f in frequencies)} Hz for {protocol.discharge:g} s with "
        f"reinjection; Q over {protocol.transient:g}–{protocol.discharge:g} s after the opening "
        f"(block standard errors). {status}.",
        "", *q_table(discharges, frequencies), "", *comparisons(discharges, frequencies), "",
        "Cost (process CPU seconds, user + system):", "", *cost_table(records), "",
        "Every run:", "", *run_table(discharges), "",
        f"- binaries (sha256, from the runs' cost.txt): {'; '.join(f'`{b}`' for b in binaries) or '—'}",
        f"- report: {benchlib.machine()['date']}, `{benchlib.command_line()}`, "
        f"silokit commit {benchlib.git_commit()}", ""])


# ---- the command line ---------------------------------------------------------------

def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("campaign", nargs="?", type=Path,
                        help="the campaign directory: one run directory per (host, seed, f); "
                             "the same directory resumes (--quick: bench/work/quick/silo3d_cross_host_paper)")
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: the quick silo, 0.2 s, Q over 0.05-0.2 s, 1 seed, f = 0; "
                             "records and report under bench/work/quick/")
    parser.add_argument("--seeds", type=int, nargs="+", help="gas seeds, primes > 10000 (default: 3; --quick: 1)")
    parser.add_argument("--frequencies", type=float, nargs="+",
                        help="bottom frequencies in Hz, the first the reference of Q(f)/Q(f0) "
                             "(default: 0 0.32; --quick: 0)")
    parser.add_argument("--discharge", type=float, help="s of discharge per run (default 2; --quick 0.2)")
    parser.add_argument("--transient", type=float, help="s after the opening left out of Q (default 0.5; --quick 0.05)")
    parser.add_argument("--jobs", type=int, default=1, help="engines at once, serial each (default 1)")
    parser.add_argument("--hosts", nargs="+", choices=HOSTS, default=list(HOSTS),
                        help="run only these hosts' runs (default both); the report still lists "
                             "every host's, those not run as missing")
    parser.add_argument("--records", type=Path,
                        help="where each finished run's records go (default doc/data/silo3d_cross_host; "
                             "--quick: CAMPAIGN/records)")
    parser.add_argument("--report-only", action="store_true",
                        help="run nothing: the report from the records")
    args = parser.parse_args()
    protocol = QUICK if args.quick else PAPER
    protocol = Protocol(protocol.quick, protocol.D,
                        args.discharge if args.discharge is not None else protocol.discharge,
                        args.transient if args.transient is not None else protocol.transient)
    if not 0 <= protocol.transient < protocol.discharge:
        parser.error(f"--transient ({protocol.transient:g} s) must be in [0, --discharge = {protocol.discharge:g} s)")
    if args.jobs < 1:
        parser.error(f"--jobs is at least 1, not {args.jobs}")
    seeds = args.seeds or list(SEEDS[:1] if args.quick else SEEDS[:3])
    # (LIGGGHTS' insert/pack refuses others; the decks share the seed)
    not_prime = [seed for seed in seeds if seed <= 10000 or any(seed % k == 0 for k in range(2, int(seed ** 0.5) + 1))]
    if not_prime:
        parser.error(f"--seeds are primes > 10000, not {' '.join(map(str, not_prime))}")
    frequencies = args.frequencies or ([0.0] if args.quick else [0.0, 0.32])
    if len(set(seeds)) < len(seeds) or len(set(frequencies)) < len(frequencies):
        parser.error("--seeds and --frequencies take each value once")
    if args.quick:
        benchlib.use_smoke_outputs()
    campaign = args.campaign or (benchlib.WORK / "quick" / SECTION if args.quick else None)
    records = args.records or (campaign / "records" if args.quick else RECORDS)
    asked = campaign_runs(seeds, frequencies)
    if not args.report_only:
        if campaign is None:
            parser.error("give the campaign directory (or --report-only)")
        for path in (*binaries_of("liggghts"), *binaries_of("lammps")):
            if not path.exists():
                sys.exit(f"{path} is missing: build it (tools/build.sh)")
        campaign = campaign.resolve()
        campaign.mkdir(parents=True, exist_ok=True)
        lock_file = lock(campaign)
        try:
            failed = run_campaign([run for run in asked if run.host in args.hosts], protocol, campaign,
                                  records, args.jobs)
        finally:
            lock_file.unlink(missing_ok=True)
    else:
        failed = []
        for run in asked:
            if is_finished(records / run.name(protocol)):
                check_protocol(run, protocol, records / run.name(protocol))
    text = report(read_records(records, protocol.transient), asked, protocol, records)
    raw_path = benchlib.write_raw(SECTION, text)
    page = benchlib.WORK / "quick" / f"{SECTION}.md" if args.quick else PAGE
    benchlib.write_page_section(page, SECTION, text, "# silo3d cross-host, the paper's silo (smoke run)\n")
    benchlib.progress(f"wrote {benchlib.shown_path(raw_path)} and the section {SECTION} of {benchlib.shown_path(page)}")
    if failed:
        sys.exit(f"{len(failed)} runs failed: {', '.join(failed)}; the same command runs them again")


if __name__ == "__main__":
    main()
