"""Ensembles of open-pile discharges (Magalhaes et al. 2014): builds a pile
per (model, L, seed) with inputs/pile2d/in.build and discharges it at every
width with inputs/pile2d/in.discharge (doc/pile2d.md).

Resumable: a pile whose restart file and build record exist is not built
again, a discharge whose (model, L, w, seed) is already in the results file
is not run again; so an interrupted ensemble is continued by the same
command. A pile whose discharges are all recorded is not rebuilt when its
restart is gone (records copied to a new directory resume there); one with
discharges still to run is rebuilt, and must come out as the recorded pile
(grain count and h0 to the printed digit; its line goes to
logs/rebuild_*.txt, not twice into piles.txt): otherwise the pile fails
with an error, since its recorded discharges were of another pile (a new
binary or deck can build another pile from the same seed).
Several tasks (one task = one pile and its discharges) run at once with
-j; --mpi N runs each LIGGGHTS under mpirun -np N.

--host lammps runs the same tasks in LAMMPS instead ($SILOKIT_LMP, default
build/bin/lmp, with the decks' twins in.build.lammps and in.discharge.lammps
and `-var plugin $SILOKIT_LAMMPS_PLUGIN` when that is set; doc/pile2d.md,
"LAMMPS"): the same records, so the analysis reads either. A campaign holds
one host's piles (each host reads only its own restart files): its host is
written to OUT/host.txt on the first run and a later run with the other one
is refused; a campaign with piles and no host.txt was run, before the
switch existed, by LIGGGHTS.

Files in OUT: piles.txt (one line per pile), discharges.txt (one line per
discharge; the deck appends it, flushed), piles/*.restart, logs/*.txt.

CLI:
    python3 -m analysis.pile2d.driver --campaign runs/pile2d --models none overlap fixed \
        --L 20 30 --seeds 10 --widths 1 2 3 4 5 6 -j 2
"""

import math
import os
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from analysis.common import hosts
from analysis.common.tables import read_rows
from analysis.common.cli import command_line

ROOT = Path(__file__).resolve().parents[2]
# a frozen copy of the decks for a long campaign (LIGGGHTS reads a deck as it
# runs, and every run of the ensemble must use the same one)
INPUTS = Path(os.environ.get("SILOKIT_INPUTS", ROOT / "inputs"))
MODELS = ("none", "overlap", "depth", "fixed")
FIRST_SEED = 15485863
PILES_HEADER = ("# model L seed n_pile h0 rows inserted t_rain t_end status dt_fraction "
                "damping rolling_damping pile substrate_d substrate_lc")
DISCHARGES_HEADER = ("# model L w seed h n_out h0 n_pile w_gap t_end status dt_fraction "
                     "damping rolling_damping")


# ---------------------------------------------------------------- seeds

def is_prime(n):
    if n < 2:
        return False
    if n % 2 == 0:
        return n == 2
    for k in range(3, int(math.isqrt(n)) + 1, 2):
        if n % k == 0:
            return False
    return True


def prime_seeds(count, first=FIRST_SEED):
    """`count` primes from `first` on (LIGGGHTS wants prime seeds > 10000)."""
    seeds, n = [], max(first, 10001)
    while len(seeds) < count:
        if is_prime(n):
            seeds.append(n)
        n += 1
    return seeds


# ---------------------------------------------------------------- records

def width_key(w):
    """Widths as they appear in records ("4", "4.2"): compare rounded."""
    return round(float(w), 6)


def row_key(row, key_columns):
    """The key tuple of a row: model as text, the rest rounded numbers."""
    return tuple(row[c] if c == "model" else width_key(row[c]) for c in key_columns)


def read_records(path, key_columns):
    """Set of key tuples of the lines of a record file."""
    return {row_key(row, key_columns) for row in read_rows(path, text=True, missing_ok=True)}


def claim_campaign_host(out, host):
    """The campaign's host in OUT/host.txt (hosts.claim_host: ValueError
    for the other host). A campaign with piles but no host.txt was run
    before --host existed, by LIGGGHTS (its restart files are LIGGGHTS'):
    its host is written first."""
    hosts.claim_host(out, host, has_runs=bool(read_records(Path(out) / "piles.txt", ("model", "L", "seed"))))


def pile_name(model, length, seed):
    """A pile's name in file names: model_L<L>_s<seed>."""
    return f"{model}_L{length:g}_s{seed}"


def pile_key(model, length, seed):
    """A pile's key among the (model, L, seed) keys of piles.txt."""
    return (model, width_key(length), width_key(seed))


def missing_widths(done, model, length, seed, widths):
    """The widths of this pile whose discharge is not among the `done` keys."""
    return [w for w in widths
            if (model, width_key(length), width_key(w), width_key(seed)) not in done]


def needs_build(recorded, restart_exists, missing_widths):
    """Whether a pile must be (re)built: it has no line in piles.txt, or
    discharges are still to run and its restart file is gone. A pile whose
    discharges are all recorded is not rebuilt for want of its restart (a
    record copied to a new directory keeps its finished piles as they are)."""
    return not recorded or (bool(missing_widths) and not restart_exists)


def rebuilt_pile_problem(recorded_row, rebuilt_row):
    """None when a rebuilt pile is the recorded one (its grain count and
    h0 to the printed digit), else what differs: the discharges already
    recorded were then made from another pile."""
    if rebuilt_row is None:
        return "the rebuild wrote no line"
    changed = [f"{c} {recorded_row[c]} -> {rebuilt_row[c]}" for c in ("n_pile", "h0")
               if recorded_row[c] != rebuilt_row[c]]
    return ", ".join(changed) or None


def ensure_header(path, header):
    path = Path(path)
    if not path.exists() or path.stat().st_size == 0:
        path.write_text(header + "\n")


# ---------------------------------------------------------------- running

class Runner:
    def __init__(self, args, argv=()):
        self.args = args
        self.argv = list(argv)
        self.out = Path(args.campaign).resolve()
        self.piles_file = self.out / "piles.txt"
        self.results_file = self.out / "discharges.txt"
        self.lock = threading.Lock()
        self.done = 0
        self.total = 0
        self.start = time.time()

    def common_variables(self, model, length, seed):
        a = self.args
        variables = {"model": model, "L": length, "seed": seed, "inputs": INPUTS,
                     "dt_fraction": a.dt_fraction, "damping": a.damping,
                     "rolling_damping": a.rolling_damping}
        for item in a.var:
            name, value = item.split("=", 1)
            variables[name] = value
        return variables

    def engine(self, deck, variables, log):
        """Runs step `deck` ("in.build", "in.discharge") in the campaign's
        host (LIGGGHTS, or LAMMPS with --host lammps); seconds of wall time."""
        deck = hosts.deck_name(self.args.host, deck)
        command = hosts.engine_command(self.args.host, INPUTS / "pile2d" / deck, variables,
                                 self.args.mpi, self.args.nice)
        started = time.time()
        with open(log, "w") as handle:
            result = subprocess.run(command, cwd=self.out, stdout=handle, stderr=subprocess.STDOUT)
        if result.returncode != 0:
            lines = Path(log).read_text(errors="replace").splitlines()
            errors = [line for line in lines if line.startswith("ERROR")]
            raise RuntimeError(f"{deck} failed ({log}): {errors[0] if errors else lines[-3:]}")
        return time.time() - started

    def progress(self, text):
        with self.lock:
            self.done += 1
            elapsed = time.time() - self.start
            print(f"[{time.strftime('%H:%M:%S')}] {self.done}/{self.total} ({elapsed / 60:.1f} min) "
                  f"{text}", flush=True)

    def restart_path(self, model, length, seed):
        return self.out / "piles" / f"{pile_name(model, length, seed)}.restart"

    def rebuild(self, name, variables, restart, recorded_row):
        """Rebuild a recorded pile whose restart is gone, for the discharges
        it still owes. Its line is written aside and compared with the
        recorded one: another pile (a new binary or deck) fails the task,
        and its restart is kept out of later runs."""
        piles = self.out / "logs" / f"rebuild_{name}.txt"
        piles.unlink(missing_ok=True)
        seconds = self.engine("in.build", {**variables, "pile": restart, "piles": piles},
                                self.out / "logs" / f"build_{name}.txt")
        rebuilt = read_rows(piles, text=True, missing_ok=True)
        problem = rebuilt_pile_problem(recorded_row, rebuilt[-1] if rebuilt else None)
        if problem:
            if restart.exists():
                restart.rename(restart.with_name(restart.name + ".differs"))
            raise RuntimeError(
                f"{name} rebuilt is not the recorded pile ({problem}); its recorded "
                f"discharges are of the recorded one: rerun the pile in a new --campaign "
                f"(the rebuilt one is {restart.name}.differs)")
        self.progress(f"rebuilt {name} in {seconds:.1f} s, the recorded pile "
                      f"(n_pile {rebuilt[-1]['n_pile']}, h0 {rebuilt[-1]['h0']})")

    def task(self, model, length, seed, widths):
        """Build the pile if needed, then the discharges still missing."""
        name = pile_name(model, length, seed)
        restart = self.restart_path(model, length, seed)
        variables = self.common_variables(model, length, seed)
        recorded = [row for row in read_rows(self.piles_file, text=True, missing_ok=True)
                    if row_key(row, ("model", "L", "seed")) == pile_key(model, length, seed)]
        done = read_records(self.results_file, ("model", "L", "w", "seed"))
        missing = missing_widths(done, model, length, seed, widths)
        if needs_build(bool(recorded), restart.exists(), missing):
            if recorded:
                self.rebuild(name, variables, restart, recorded[-1])
            else:
                seconds = self.engine("in.build", {**variables, "pile": restart,
                                                     "piles": self.piles_file},
                                        self.out / "logs" / f"build_{name}.txt")
                self.progress(f"built {name} in {seconds:.1f} s")
        for w in missing:
            seconds = self.engine("in.discharge", {**variables, "pile": restart, "w": w,
                                                     "results": self.results_file},
                                    self.out / "logs" / f"discharge_{name}_w{w:g}.txt")
            self.progress(f"{name} w={w:g}: {last_result(self.results_file, model, length, w, seed)}"
                          f" ({seconds:.1f} s)")

    def run(self):
        a = self.args
        (self.out / "piles").mkdir(parents=True, exist_ok=True)
        (self.out / "logs").mkdir(parents=True, exist_ok=True)
        claim_campaign_host(self.out, a.host)
        ensure_header(self.piles_file, PILES_HEADER)
        ensure_header(self.results_file, DISCHARGES_HEADER)
        # the records do not carry every deck variable (--var): each
        # invocation's command line is kept beside them
        with open(self.out / "driver_commands.txt", "a") as handle:
            handle.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')} python3 -m analysis.pile2d.driver "
                         f"{' '.join(self.argv)}\n")
        seeds = a.seed_list or prime_seeds(a.seeds, a.first_seed)
        tasks = [(model, length, seed) for length in a.L for seed in seeds for model in a.models]
        built = read_records(self.piles_file, ("model", "L", "seed"))
        done = read_records(self.results_file, ("model", "L", "w", "seed"))
        self.total = 0
        for m, length, s in tasks:
            missing = missing_widths(done, m, length, s, a.widths)
            self.total += len(missing) + needs_build(pile_key(m, length, s) in built,
                                                     self.restart_path(m, length, s).exists(), missing)
        print(f"pile2d driver ({a.host}): {len(tasks)} piles x {len(a.widths)} widths, "
              f"{self.total} runs to do, -j {a.jobs}, results in {self.results_file}", flush=True)
        failures = []
        with ThreadPoolExecutor(max_workers=a.jobs) as pool:
            futures = {pool.submit(self.task, m, length, s, a.widths): (m, length, s)
                       for m, length, s in tasks}
            for future, what in futures.items():
                try:
                    future.result()
                except RuntimeError as problem:
                    failures.append(f"{what}: {problem}")
                    print(f"FAILED {what}: {problem}", flush=True)
        return failures


def last_result(path, model, length, w, seed):
    """'h=... n_out=...' of the record line of this sample, for the progress line."""
    for line in reversed(Path(path).read_text().splitlines()):
        words = line.split()
        if (len(words) >= 6 and words[0] == model and width_key(words[1]) == width_key(length)
                and width_key(words[2]) == width_key(w) and width_key(words[3]) == width_key(seed)):
            return f"h={float(words[4]):.2f} n_out={words[5]}"
    return "(no record)"


def parse(argv):
    parser = command_line("analysis.pile2d.driver", __doc__,
                          "/usr/bin/python3 -m analysis.pile2d.driver --campaign runs/piles --models none --L 20 "
                          "50 --seeds 10")
    parser.add_argument("--campaign", required=True, metavar="DIR",
                        help="the campaign's directory: records, piles and logs; a later call goes on from it")
    parser.add_argument("--models", nargs="+", default=list(MODELS), choices=MODELS)
    parser.add_argument("--L", nargs="+", type=float, required=True, help="substrate lengths (d)")
    parser.add_argument("--widths", nargs="*", type=float, default=[],
                        help="orifice widths (d); none: build the piles only")
    parser.add_argument("--seeds", type=int, default=10, help="number of piles per (model, L)")
    parser.add_argument("--first-seed", dest="first_seed", type=int, default=FIRST_SEED,
                        help="seeds are the primes from this one on")
    parser.add_argument("--seed-list", dest="seed_list", nargs="+", type=int,
                        help="explicit seeds (primes > 10000) instead of --seeds")
    parser.add_argument("--dt-fraction", dest="dt_fraction", type=float, default=25,
                        help="time step = t_c / DT_FRACTION (default 25)")
    parser.add_argument("--damping", type=float, default=0.3,
                        help="normal and tangential damping, fraction of critical (default 0.3)")
    parser.add_argument("--rolling-damping", dest="rolling_damping", type=float, default=0.3,
                        help="rolling damping, fraction of critical; 0: none (default 0.3)")
    parser.add_argument("--var", action="append", default=[], metavar="NAME=VALUE",
                        help="any other deck variable, for both decks (repeatable)")
    parser.add_argument("-j", "--jobs", type=int, default=1, help="tasks run at once")
    parser.add_argument("--host", choices=hosts.HOSTS, default="liggghts",
                        help="the engine: liggghts (default; $SILOKIT_LIGGGHTS) or lammps ($SILOKIT_LMP, "
                             "the .lammps decks, the plugin from $SILOKIT_LAMMPS_PLUGIN if set)")
    parser.add_argument("--mpi", type=int, default=1, help="MPI ranks per engine run")
    parser.add_argument("--nice", type=int, default=0, help="run the engine under nice -n N")
    args = parser.parse_args(argv)
    for item in args.var:
        if "=" not in item:
            parser.error(f"--var {item}: expected NAME=VALUE")
    if args.seed_list:
        bad = [s for s in args.seed_list if s <= 10000 or not is_prime(s)]
        if bad:
            parser.error(f"--seed-list: not primes > 10000: {bad}")
    return args


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    try:
        failures = Runner(parse(argv), argv).run()
    except ValueError as problem:
        print(f"analysis.pile2d.driver: {problem}", file=sys.stderr)
        return 2
    if failures:
        print(f"{len(failures)} task(s) failed", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
