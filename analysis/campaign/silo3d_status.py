"""Where a campaign of the rotating-bottom silo stands, run by run: how far
each discharge has got, what it has cost and what is left, from the
records a run directory holds (run.txt, discharge.txt, screen.txt).

- t / T: the time since the opening of discharge.txt's last row, and the
  discharge the run is set to (run.txt's last `discharge_time`);
- status: finished (run.sh's `finished` file), or running/stopped at t;
  clogged when the deck stopped it at a clog (run.txt's `clogged`);
- loop h: LIGGGHTS' loop times in screen.txt (which run.sh appends to
  across resumptions, so the chunks run again after an interruption
  count), times the processes. These are wall-clock hours: with a core
  to itself a run's CPU-hours, but a run that shared its core or was
  stopped (SIGSTOP) counts that time too, so they bound the CPU-hours
  from above;
- loop h per simulated s, and the hours left at that pace.

CLI:  python3 -m analysis.campaign.silo3d_status DIR [DIR ...]

A DIR is a run directory (D<D>_f<f>_s<seed>) or a campaign directory
holding them (run.sh's RUN_DIR); the settling of packings is not counted.
"""

import re
import sys
from pathlib import Path

from analysis.silo3d_rotating.records import read_run_info
from analysis.common.cli import command_line

LOOP = re.compile(r"^Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps")


def loop_cost(screen):
    """(CPU seconds, steps) summed over the `Loop time` lines of a screen file."""
    cpu, steps = 0.0, 0
    for line in screen.read_text(errors="replace").splitlines():
        match = LOOP.match(line)
        if match:
            cpu += float(match.group(1)) * int(match.group(2))
            steps += int(match.group(3))
    return cpu, steps


def last_time(discharge):
    """The time since the opening of the last complete row of discharge.txt (0 without rows)."""
    t = 0.0
    for line in discharge.read_text().splitlines():
        words = line.split()
        if len(words) >= 4 and not line.startswith("#"):
            t = float(words[1])
    return t


def run_status(run_dir):
    run_dir = Path(run_dir)
    info = read_run_info(run_dir, required=("f", "D", "seed", "dt"))
    length = info.get("discharge_time", float("nan"))
    t = last_time(run_dir / "discharge.txt") if (run_dir / "discharge.txt").exists() else 0.0
    cpu, steps = loop_cost(run_dir / "screen.txt") if (run_dir / "screen.txt").exists() else (0.0, 0)
    simulated = steps * info["dt"]
    per_second = cpu / 3600 / simulated if simulated > 0 else float("nan")
    finished = (run_dir / "finished").exists()
    return {"run": run_dir.name, "f": info["f"], "D": info["D"], "seed": int(info["seed"]), "t": t,
            "length": length, "finished": finished, "clogged": info.get("clogged"),
            "cpu_hours": cpu / 3600, "per_second": per_second,
            "left": 0.0 if finished else max(length - t, 0.0) * per_second}


def run_dirs(paths):
    found = []
    for path in map(Path, paths):
        if (path / "run.txt").exists() and path.name.startswith("D"):
            found.append(path)
        else:
            found += sorted(p for p in path.glob("D*_f*_s*") if (p / "run.txt").exists())
    return found


def main(argv=None):
    parser = command_line("analysis.campaign.silo3d_status", __doc__,
                          "/usr/bin/python3 -m analysis.campaign.silo3d_status runs/rods_fig2c")
    parser.add_argument("dirs", nargs="+", help="run or campaign directories")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    runs = run_dirs(args.dirs)
    if not runs:
        print("silo3d_status: ERROR: no run directory (D<D>_f<f>_s<seed> with run.txt) in "
              + " ".join(args.dirs), file=sys.stderr)
        return 2
    rows = [run_status(path) for path in runs]
    print("| run | f (Hz) | D (m) | seed | t / T (s) | status | loop h | loop h per simulated s | loop h left |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        status = "finished" if r["finished"] else f"at {r['t']:.2f} s"
        if r["clogged"] is not None:
            status += f", clogged (stopped at {r['t']:.2f} s)"
        print(f"| {r['run']} | {r['f']:g} | {r['D']:g} | {r['seed']} | {r['t']:.2f} / {r['length']:g} | {status} "
              f"| {r['cpu_hours']:.2f} | {r['per_second']:.2f} | {r['left']:.2f} |")
    done = sum(r["finished"] for r in rows)
    print(f"\n{done} of {len(rows)} runs finished; {sum(r['cpu_hours'] for r in rows):.1f} loop hours spent, "
          f"{sum(r['left'] for r in rows if r['left'] == r['left']):.1f} left in the runs started (wall clock "
          "of LIGGGHTS' loops times processes: CPU-hours with a core each, more when shared or stopped)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
