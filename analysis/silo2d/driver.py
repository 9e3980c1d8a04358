"""Clogging-silo campaigns (Hidalgo et al. 2013) that go on across sessions:
runs inputs/silo2d/in.silo2d at each friction coefficient until a number
of arches, in segments of simulated time, each ending with a restart file
from which the next one starts (doc/silo2d.md, "Running a campaign").

A run is a chain of segments: segment 1 fills the silo and runs
`--segment-time` seconds of the clog loop, segment k > 1 reads the restart
file of segment k - 1 and runs as long again. A segment is complete when
the engine has ended normally and written its restart file; the driver then
appends a line to segments.txt. A cut segment (the session ended, ^C, a
crash) has no line: the next call runs it again from the restart file of
the segment before, and fix clog first removes the records the cut segment
had written past that file (doc/fix_clog.md, Restart). On one rank and with
the same binary a segment is a deterministic function of its restart
file, so the records of a cut and resumed run are those of an uncut one
(tests/test_silo2d_driver.py), and a cut costs at most one segment.

Files in OUT/mu<MU>/: the deck's records (clogs.txt, arches.txt, feet.txt,
contacts.txt, reinject.txt, silo.txt), parameters.txt (the deck variables
of the run: a resumed run must be given the same), segments.txt (one line
per complete segment: segment, time of the last clog attempt, clog attempts,
arches, CPU seconds and wall seconds of the segment), state<k>.restart
(the last two are kept), logs/segment<k>.txt (the engine's screen output);
in OUT/: host.txt (the campaign's engine).

--host lammps runs the same segments in LAMMPS ($SILOKIT_LMP, default
build/bin/lmp) with the deck's twin in.silo2d.lammps and `-var plugin
$SILOKIT_LAMMPS_PLUGIN` when that is set (doc/silo2d.md, "LAMMPS"): the
same -var names, the same records, its own restart files
(`read_restart state<k-1>.restart`), and fix clog removes a cut segment's
rows there too (doc/fix_clog_lammps.md, Restart). A campaign holds one
host's runs: the host goes to OUT/host.txt and a call with the other is
refused (analysis.common.hosts.claim_host); a campaign with segments and
no host.txt was run before the switch existed, by LIGGGHTS.

CLI:
    python3 -m analysis.silo2d.driver --campaign runs/silo2d --mu 0.2 0.4 0.8 \\
        --arches 200 --dt 2e-5 --segment-time 20 -j 2
Environment: SILOKIT_LIGGGHTS (the binary, default build/bin/liggghts),
SILOKIT_LMP and SILOKIT_LAMMPS_PLUGIN (--host lammps) and SILOKIT_INPUTS
(the inputs/ directory, default the repository's): LIGGGHTS reads its deck
as it runs, so a campaign that must survive edits of the repository runs
on copies of the binary and the decks.
Calling it again with the same arguments continues; a larger --arches
extends a finished run.
"""

import os
import subprocess
import sys
import time
import threading
from pathlib import Path

import numpy as np

from analysis.common import hosts
from analysis.common.tables import read_table
from analysis.common.cli import command_line

ROOT = Path(__file__).resolve().parents[2]
# LIGGGHTS reads its input file line by line as it runs (and `jump SELF`
# reads it again): a deck edited while a campaign runs would be read half
# old, half new. A long campaign should run on a copy (--inputs).
INPUTS = Path(os.environ.get("SILOKIT_INPUTS", ROOT / "inputs"))
SEGMENTS_HEADER = "# segment last_clog_time clogs arches cpu_s wall_s"
# fix clog raises its flag only after this many arches: the driver, not the
# deck, decides when a run has enough, so a finished run can be extended
ARCHES_NEVER_REACHED = 1000000000
KEPT_RESTART_FILES = 2


def run_directory(out, mu):
    return Path(out) / f"mu{mu:g}"


def deck_variables(mu, dt, seed, quick, extra):
    """The deck variables that define a run (the same for all its segments)."""
    variables = {"mu": f"{mu:g}", "dt": f"{dt:g}", "seed": str(seed), "quick": str(int(quick)),
                 "narches": str(ARCHES_NEVER_REACHED)}
    variables.update(extra)
    return variables


def check_parameters(directory, variables):
    """Writes parameters.txt at the first segment; later, the same variables
    must be given, or the records would mix two set-ups."""
    path = directory / "parameters.txt"
    text = "".join(f"{name} {value}\n" for name, value in sorted(variables.items()))
    if not path.exists():
        path.write_text(text)
        return
    if path.read_text() != text:
        raise SystemExit(f"silo2d_driver: {directory} was started with other parameters:\n"
                         f"{path.read_text()}now:\n{text}(use another --campaign, or the same options)")


def completed_segments(directory):
    """Rows of segments.txt as dicts, in order; [] when there is none."""
    path = directory / "segments.txt"
    if not path.exists():
        return []
    table = read_table(path)
    names = SEGMENTS_HEADER[2:].split()
    return [dict(zip(names, row)) for row in zip(*(np.atleast_1d(table[n]) for n in names))]


def count_records(directory):
    """(clog attempts, arches) in clogs.txt."""
    path = directory / "clogs.txt"
    if not path.exists():
        return 0, 0
    clogs = read_table(path)
    status = np.atleast_1d(clogs["status"])
    return int(status.size), int(np.sum(status == 1))


def simulated_time(directory):
    """Time of the last clog attempt recorded (0 without any)."""
    path = directory / "clogs.txt"
    if not path.exists():
        return 0.0
    times = np.atleast_1d(read_table(path)["time"])
    return float(times[-1]) if times.size else 0.0


def segment_command(host, segment, variables, segment_time, nprocs=1, nice=0):
    """The command line of segment `segment` (1, 2, ...) of a run in
    `host`: the scene's deck for that host, the run's variables, then the
    segment's (segment k reads state<k-1>.restart, writes state<k>.restart)."""
    variables = {"inputs": INPUTS, **variables, "segment": segment,
                 "segment_time": f"{segment_time:g}", "state": "state"}
    deck = INPUTS / "silo2d" / hosts.deck_name(host, "in.silo2d")
    return hosts.engine_command(host, deck, variables, nprocs, nice, options=("-echo", "none"))


def run_segment(directory, segment, variables, segment_time, nprocs, host="liggghts", nice=0):
    """Runs segment `segment` (1, 2, ...); returns (cpu_s, wall_s); raises
    RuntimeError if the engine fails or writes no restart file."""
    logs = directory / "logs"
    logs.mkdir(exist_ok=True)
    save_to = f"state{segment}.restart"
    command = segment_command(host, segment, variables, segment_time, nprocs, nice)
    (directory / save_to).unlink(missing_ok=True)
    start = time.time()
    with open(logs / f"segment{segment}.txt", "w") as log:
        process = subprocess.Popen(command, cwd=directory, stdout=log, stderr=subprocess.STDOUT)
        # wait4 instead of wait: the child's CPU time comes with it
        _, status, usage = os.wait4(process.pid, 0)
        process.returncode = os.waitstatus_to_exitcode(status)
    wall = time.time() - start
    if process.returncode != 0 or not (directory / save_to).exists():
        raise RuntimeError(f"segment {segment} in {directory} failed (exit {process.returncode}); "
                           f"see {logs / f'segment{segment}.txt'}")
    return usage.ru_utime + usage.ru_stime, wall


def claim_campaign_host(out, host):
    """The campaign's host in OUT/host.txt (hosts.claim_host: ValueError
    for the other host). A campaign that has segments but no host.txt was
    run before --host existed, by LIGGGHTS: its host is written first."""
    out = Path(out)
    hosts.claim_host(out, host, has_runs=any(
        completed_segments(run) for run in out.glob("mu*") if run.is_dir()))


def remove_old_restart_files(directory, segment):
    for old in range(1, segment - KEPT_RESTART_FILES + 1):
        (directory / f"state{old}.restart").unlink(missing_ok=True)


class Campaign:
    """The runs of one call: a segment at a time per friction coefficient,
    the next segment always going to the run with the fewest arches that is
    not running already, so that with -j 2 every run advances at a similar
    pace and a campaign cut by the end of a session has comparable
    statistics at every mu."""

    def __init__(self, out, mus, arches_wanted, dt, seed, quick, segment_time, max_segments,
                 nprocs, extra, log=print, host="liggghts", nice=0):
        self.arches_wanted = arches_wanted
        self.segment_time = segment_time
        self.nprocs = nprocs
        self.host = host
        self.nice = nice
        self.log = log
        self.lock = threading.Lock()
        self.runs = {}
        Path(out).mkdir(parents=True, exist_ok=True)
        claim_campaign_host(out, host)
        for mu in mus:
            directory = run_directory(out, mu)
            directory.mkdir(parents=True, exist_ok=True)
            variables = deck_variables(mu, dt, seed, quick, extra)
            check_parameters(directory, variables)
            path = directory / "segments.txt"
            if not path.exists():
                path.write_text(SEGMENTS_HEADER + "\n")
            done = completed_segments(directory)
            self.runs[mu] = {"directory": directory, "variables": variables, "done": done,
                             "arches": int(done[-1]["arches"]) if done else 0,
                             "left": max_segments, "busy": False, "failed": None}

    def next_run(self):
        """The mu whose run gets the next segment (None: nothing left)."""
        with self.lock:
            waiting = [mu for mu, run in self.runs.items()
                       if not run["busy"] and run["failed"] is None and run["left"] > 0
                       and run["arches"] < self.arches_wanted]
            if not waiting:
                return None
            mu = min(waiting, key=lambda m: (self.runs[m]["arches"], m))
            self.runs[mu]["busy"] = True
            self.runs[mu]["left"] -= 1
            return mu

    def worker(self):
        while True:
            mu = self.next_run()
            if mu is None:
                return
            run = self.runs[mu]
            try:
                self.run_one_segment(mu, run)
            except RuntimeError as error:
                run["failed"] = str(error)
                self.log(f"silo2d_driver: mu {mu:g}: {error}", flush=True)
            finally:
                with self.lock:
                    run["busy"] = False

    def run_one_segment(self, mu, run):
        directory, done = run["directory"], run["done"]
        segment = len(done) + 1
        if segment > 1 and not (directory / f"state{segment - 1}.restart").exists():
            raise RuntimeError(f"state{segment - 1}.restart is missing in {directory}, "
                               f"though segments.txt says segment {segment - 1} is complete")
        cpu, wall = run_segment(directory, segment, run["variables"], self.segment_time, self.nprocs,
                                self.host, self.nice)
        clogs, arches = count_records(directory)
        row = {"segment": segment, "last_clog_time": simulated_time(directory), "clogs": clogs,
               "arches": arches, "cpu_s": cpu, "wall_s": wall}
        with open(directory / "segments.txt", "a") as records:
            records.write(f"{segment} {row['last_clog_time']:.6g} {clogs} {arches} {cpu:.1f} {wall:.1f}\n")
        done.append(row)
        run["arches"] = arches
        remove_old_restart_files(directory, segment)
        total_cpu = sum(float(r["cpu_s"]) for r in done)
        self.log(f"silo2d_driver: mu {mu:g}: segment {segment} done, {clogs} clogs, {arches} "
                 f"arches of {self.arches_wanted}, {total_cpu / 3600:.2f} CPU-hours so far "
                 f"({arches / max(total_cpu, 1e-9) * 3600:.0f} arches per CPU-hour)", flush=True)

    def run_all(self, jobs):
        """Runs segments on `jobs` workers until every run has its arches;
        returns {mu: (arches, error or None)}."""
        threads = [threading.Thread(target=self.worker) for _ in range(jobs)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        return {mu: (run["arches"], run["failed"]) for mu, run in self.runs.items()}


def parse(argv):
    parser = command_line("analysis.silo2d.driver", __doc__.split("\n\n")[0],
                          "/usr/bin/python3 -m analysis.silo2d.driver --campaign runs/silo2d_quick --mu 0.4 "
                          "--arches 3 --quick")
    parser.add_argument("--campaign", required=True, type=Path, metavar="DIR",
                        help="the campaign's directory: records, restarts and logs; a later call goes on from it")
    parser.add_argument("--mu", type=float, nargs="+", required=True, help="friction coefficients")
    parser.add_argument("--arches", type=int, required=True, help="arches wanted per mu")
    parser.add_argument("--dt", type=float, default=2e-5, help="time step (s); default t_c/12")
    parser.add_argument("--seed", type=int, default=32452843, help="deck seed (prime > 10000)")
    parser.add_argument("--quick", action="store_true", help="the deck's small CI silo")
    parser.add_argument("--segment-time", type=float, default=20.0,
                        help="simulated seconds per segment (default 20)")
    parser.add_argument("--max-segments", type=int, default=1000000,
                        help="at most this many segments per mu in this call")
    parser.add_argument("--mpi", type=int, default=1, help="ranks per run (mpirun -np)")
    parser.add_argument("--host", choices=hosts.HOSTS, default="liggghts",
                        help="the engine: liggghts (default; $SILOKIT_LIGGGHTS) or lammps ($SILOKIT_LMP, "
                             "in.silo2d.lammps, the plugin from $SILOKIT_LAMMPS_PLUGIN if set)")
    parser.add_argument("--nice", type=int, default=0, help="run the engine under nice -n N")
    parser.add_argument("-j", "--jobs", type=int, default=1, help="segments at once (of different mu)")
    parser.add_argument("--var", action="append", default=[], metavar="NAME=VALUE",
                        help="another deck variable, the same for every segment (repeatable)")
    args = parser.parse_args(argv)
    if args.arches < 1:
        parser.error("--arches must be >= 1")
    if not args.segment_time > 0:
        parser.error("--segment-time must be > 0")
    if not args.dt > 0:
        parser.error("--dt must be > 0")
    reserved = {"mu", "dt", "seed", "quick", "narches", "segment", "segment_time", "state",
                "inputs"}
    for item in args.var:
        if "=" not in item:
            parser.error(f"--var {item}: expected NAME=VALUE")
    args.var = [tuple(item.split("=", 1)) for item in args.var]
    for name, _ in args.var:
        if name in reserved:
            parser.error(f"--var {name}: set by the driver itself")
    return args


def main(argv=None):
    args = parse(argv)
    binary = hosts.engine_binary(args.host)
    if not binary.exists():
        raise SystemExit(f"silo2d_driver: no {args.host} binary at {binary} (bash tools/build.sh)")
    try:
        campaign = Campaign(args.campaign, args.mu, args.arches, args.dt, args.seed, args.quick,
                            args.segment_time, args.max_segments, args.mpi, dict(args.var),
                            host=args.host, nice=args.nice)
    except ValueError as problem:
        print(f"silo2d_driver: {problem}", file=sys.stderr)
        return 2
    results = campaign.run_all(args.jobs)
    for mu, (arches, failed) in results.items():
        print(f"silo2d_driver: mu {mu:g}: {arches} arches" + (f" (stopped: {failed})" if failed else ""),
              flush=True)
    return 1 if any(failed for _, failed in results.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
