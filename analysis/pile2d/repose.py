"""The shape of open piles before any discharge (doc/pile2d.md, "Is the
pile a pile?"): the free surface of each equilibrated pile, its slope and
angle, and their means with 95 % intervals per (model, L) of one or more
ensembles.

Reads driver output directories (analysis.pile2d.driver run with
`--var final_dump=1`, which makes in.build write `<pile>.dump` next to each
restart file) and pairs each dump with its line of piles.txt.

The surface: on a grid of vertical lines 0.1 d apart over the substrate,
the height of the highest point of a free grain (y_i + sqrt(r_i^2 -
(x - x_i)^2) for |x - x_i| < r_i), 0 where no grain is. The slope s is the
least-squares fit of top(x) = c - s |x - x_peak| over the lines 1 d or
more from the substrate's ends and from the peak (x_peak the centre of the
pile's mass): a pile that spread flat has s = 0, a triangle of repose
angle theta filling the substrate has s = tan(theta). With the grain-scale
roughness of the surface, the fit's residual is about 0.3 d. The piles
have a summit some 10 d wide whose slope is not the flank's (steeper at
L <= 100 d, rounded at 200 d), so over the whole flank s drifts with L;
--peak-margin 10 fits the flank beyond it, the angle of repose proper.

Run-on check (--run-on FACTOR): each pile is read back and run on, with
nothing changed, for FACTOR times the time its relaxation took (t_end -
t_rain) with inputs/pile2d/in.runon, which appends to RUN_DIR/runon.txt
the grains and h0 before and after, the largest displacement of a grain
and whether the equilibrium criteria still hold. Piles already in
runon.txt are not run again (resumable); --run-on-L limits it to some L.

Base motion (--base-motion DUMP DT): for the frames of in.build's
dump.build (-var dump_every N), how the grains of the bottom layer (centre
below 0.75 d) move: mean |v_x| and mean |v_x + omega_z r|, the slip at the
substrate (0 for a disc rolling without sliding, |v_x| for one sliding
without turning).

CLI:  python3 -m analysis.pile2d.repose RUN_DIR [RUN_DIR ...] [--peak-margin 10] [--run-on 10 [--run-on-L 20 50] [-j 2]]
      python3 -m analysis.pile2d.repose --base-motion dump.build 0.0028065
"""

import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_rows
from analysis.pile2d.discharges import mean_std_ci
from analysis.common.cli import command_line
from analysis.common.hosts import LIGGGHTS_BINARY

ROOT = Path(__file__).resolve().parents[2]
# a frozen copy of the decks for a long campaign (LIGGGHTS reads a deck as it
# runs, and every run of the ensemble must use the same one)
INPUTS = Path(os.environ.get("SILOKIT_INPUTS", ROOT / "inputs"))
# deck variables a pile was built with, from its piles.txt line (default
# when an older record lacks the column)
BUILD_VARIABLES = {"model": None, "L": None, "seed": None, "damping": 0.3, "rolling_damping": 0.3,
                   "dt_fraction": 25}
# substrate_lc of piles whose record predates its column (2026-11-24):
# the decks then had no rolling resistance on the substrate but each
# model's own (fixed: its 0.05 d; 0 for the others means their own l_c)
SUBSTRATE_LC_BEFORE_RECORDED = {"none": 0, "depth": 0, "overlap": 0, "fixed": 0.05}

GRID_STEP = 0.1      # d, spacing of the vertical lines of the surface
EDGE_MARGIN = 1.0    # d, lines this close to a substrate end are left out of the fit
PEAK_MARGIN = 1.0    # d, lines this close to the peak are left out of the fit


def surface(x, y, r, length, step=GRID_STEP):
    """(lines, top): the highest point of any disc on each vertical line
    over the substrate [-L/2, L/2], 0 where no disc crosses the line."""
    lines = np.arange(-length / 2 + step / 2, length / 2, step)
    top = np.zeros_like(lines)
    for xi, yi, ri in zip(x, y, r):
        near = np.abs(lines - xi) < ri
        if np.any(near):
            top[near] = np.maximum(top[near], yi + np.sqrt(ri * ri - (lines[near] - xi) ** 2))
    return lines, top


def flank_slope(lines, top, peak, length, edge_margin=EDGE_MARGIN, peak_margin=PEAK_MARGIN):
    """(slope, residual): least-squares fit of top = c - slope |x - peak| on
    the lines away from the ends and the peak; NaN with fewer than 3 lines
    on the distance axis."""
    distance = np.abs(lines - peak)
    use = (np.abs(lines) <= length / 2 - edge_margin) & (distance >= peak_margin)
    if np.unique(np.round(distance[use], 6)).size < 3:
        return math.nan, math.nan
    design = np.column_stack([np.ones(use.sum()), -distance[use]])
    coefficients, *_ = np.linalg.lstsq(design, top[use], rcond=None)
    residual = top[use] - design @ coefficients
    return float(coefficients[1]), float(np.sqrt(np.mean(residual ** 2)))


def pile_shape(dump_path, length, peak_margin=PEAK_MARGIN):
    """Shape of one equilibrated pile: grains, peak height, slope, angle
    (of the flank peak_margin d or more from the peak)."""
    atoms = read_dump(dump_path)[-1][1]
    free = atoms["type"] == 1
    x, y, r = atoms["x"][free], atoms["y"][free], atoms["radius"][free]
    on_substrate = np.abs(x) <= length / 2
    x, y, r = x[on_substrate], y[on_substrate], r[on_substrate]
    lines, top = surface(x, y, r, length)
    peak = float(np.sum(x * r * r) / np.sum(r * r)) if x.size else 0.0
    slope, residual = flank_slope(lines, top, peak, length, peak_margin=peak_margin)
    return {"grains": int(x.size), "top": float(top.max()) if top.size else 0.0,
            "slope": slope, "angle": math.degrees(math.atan(slope)) if slope == slope else math.nan,
            "residual": residual, "peak": peak}


def pile_path(run_dir, row):
    """The restart file of a piles.txt row (relative paths from run_dir)."""
    path = Path(str(row["pile"]))
    return path if path.is_absolute() else Path(run_dir) / path


def ensemble_shapes(run_dir, peak_margin=PEAK_MARGIN):
    """One dict per pile of a driver directory with a dump: the piles.txt
    columns plus the shape; piles without a dump are counted, not read."""
    run_dir = Path(run_dir)
    shapes, missing = [], 0
    for row in read_rows(run_dir / "piles.txt"):
        dump = Path(str(pile_path(run_dir, row)) + ".dump")
        if not dump.exists():
            missing += 1
            continue
        shapes.append({**row, **pile_shape(dump, row["L"], peak_margin), "run": str(run_dir)})
    return shapes, missing


def number_text(value):
    """A record's number as the deck wants it (a seed as an integer)."""
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def run_on(run_dir, factor, lengths=None, jobs=1):
    """Run every pile of run_dir not yet in runon.txt on for factor x its
    relaxation time (in.runon); returns the failures."""
    run_dir = Path(run_dir).resolve()
    record = run_dir / "runon.txt"
    done = set()
    if record.exists():
        done = {(r["model"], r["L"], int(r["seed"])) for r in read_rows(record)}
    todo = [r for r in read_rows(run_dir / "piles.txt")
            if (r["model"], r["L"], int(r["seed"])) not in done
            and (lengths is None or r["L"] in lengths) and pile_path(run_dir, r).exists()]
    (run_dir / "logs").mkdir(exist_ok=True)
    print(f"{run_dir}: running {len(todo)} pile(s) on for {factor:g} x their relaxation", flush=True)

    def one(row):
        variables = {name: number_text(row.get(name, default)) for name, default in BUILD_VARIABLES.items()}
        variables["substrate_lc"] = number_text(row.get("substrate_lc",
                                                        SUBSTRATE_LC_BEFORE_RECORDED[row["model"]]))
        variables.update({"pile": pile_path(run_dir, row), "runon": record, "inputs": INPUTS,
                          "time": f"{factor * (row['t_end'] - row['t_rain']):.6g}"})
        name = f"{row['model']}_L{row['L']:g}_s{int(row['seed'])}"
        command = ["stdbuf", "-oL", str(LIGGGHTS_BINARY), "-in", str(INPUTS / "pile2d" / "in.runon"), "-log", "none"]
        for key, value in variables.items():
            command += ["-var", key, str(value)]
        with open(run_dir / "logs" / f"runon_{name}.txt", "w") as handle:
            result = subprocess.run(command, cwd=run_dir, stdout=handle, stderr=subprocess.STDOUT)
        print(f"run-on {name}: {'done' if result.returncode == 0 else 'FAILED'}", flush=True)
        return None if result.returncode == 0 else name

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        return [name for name in pool.map(one, todo) if name]


def runon_summary(run_dir):
    """Per (model, L) of a run's runon.txt: piles, how many still in
    equilibrium, grains lost, largest h0 change and displacement."""
    record = Path(run_dir) / "runon.txt"
    if not record.exists():
        return []
    groups = {}
    for r in read_rows(record):
        groups.setdefault((r["model"], r["L"]), []).append(r)
    summary = []
    for (model, length), rows in sorted(groups.items()):
        summary.append({"run": str(run_dir), "model": model, "L": length, "piles": len(rows),
                        "factor_time": min(r["time"] for r in rows),
                        "still": sum(1 for r in rows if r["status"] == 1),
                        "lost": max(r["n_before"] - r["n_after"] for r in rows),
                        "dh0": max(abs(r["h0_after"] - r["h0_before"]) for r in rows),
                        "moved": max(r["max_displacement"] for r in rows)})
    return summary


def format_runon(summary):
    lines = ["| run | model | L (d) | piles | shortest run-on (sqrt(d/g)) | still in equilibrium | "
             "most grains lost | largest change of h0 (d) | largest displacement (d) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for e in summary:
        lines.append(f"| {Path(e['run']).name} | {e['model']} | {e['L']:g} | {e['piles']} | "
                     f"{e['factor_time']:.0f} | {e['still']} | {e['lost']:g} | {e['dh0']:.2g} | "
                     f"{e['moved']:.2g} |")
    return "\n".join(lines)


def base_motion(dump_path, dt, base_height=0.75):
    """Rows (time, grains over the substrate, base grains, base grains moving faster than
    1e-3 sqrt(g d), mean |v_x| and mean slip |v_x + omega_z r| of the base
    grains) for every frame of a dump with x y vx omegaz radius type."""
    from analysis.common.lammps_io import read_dump as read_frames
    rows = []
    for step, c in read_frames(dump_path):
        substrate = c["type"] == 2
        over = ((c["x"] >= c["x"][substrate].min()) & (c["x"] <= c["x"][substrate].max())
                if substrate.any() else np.ones_like(c["x"], dtype=bool))
        free = (c["type"] == 1) & (c["y"] > -0.5 * c["radius"]) & over
        base = free & (c["y"] < base_height)
        vx, slip = c["vx"][base], c["vx"][base] + c["omegaz"][base] * c["radius"][base]
        rows.append((step * dt, int(free.sum()), int(base.sum()), int(np.sum(np.abs(vx) > 1e-3)),
                     float(np.abs(vx).mean()) if vx.size else 0.0,
                     float(np.abs(slip).mean()) if slip.size else 0.0))
    return rows


def summarize(shapes):
    """Per (run, model, L): count, and mean with 95 % interval of the
    grains, h0, slope and angle."""
    groups = {}
    for s in shapes:
        groups.setdefault((s["run"], s["model"], s["L"]), []).append(s)
    summary = []
    for (run, model, length), members in sorted(groups.items()):
        entry = {"run": run, "model": model, "L": length, "piles": len(members)}
        for name in ("grains", "h0", "slope", "angle", "t_end"):
            mean, _, interval, _ = mean_std_ci([m[name] for m in members])
            entry[name] = (mean, interval)
        entry["unsettled"] = sum(1 for m in members if m.get("status", 1) != 1)
        summary.append(entry)
    return summary


def format_value(value):
    mean, (lo, hi) = value
    if math.isnan(lo):
        return f"{mean:.3g}"
    return f"{mean:.3g} [{lo:.3g}, {hi:.3g}]"


def format_table(summary):
    lines = ["| run | model | L (d) | piles | grains | h0 (d) | slope | angle (deg) | t_end (sqrt(d/g)) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for e in summary:
        lines.append(f"| {Path(e['run']).name} | {e['model']} | {e['L']:g} | {e['piles']}"
                     + (f" ({e['unsettled']} unsettled)" if e["unsettled"] else "")
                     + "".join(f" | {format_value(e[n])}" for n in ("grains", "h0", "slope", "angle",
                                                                     "t_end")) + " |")
    return "\n".join(lines)


def main(argv=None):
    parser = command_line("analysis.pile2d.repose", __doc__,
                          "/usr/bin/python3 -m analysis.pile2d.repose runs/piles --run-on 10 --write "
                          "runs/piles/shapes.txt")
    parser.add_argument("runs", nargs="*", type=Path, help="analysis.pile2d.driver output directories")
    parser.add_argument("--base-motion", dest="base_motion", nargs=2, metavar=("DUMP", "DT"),
                        help="the bottom layer's motion in the frames of in.build's dump.build")
    parser.add_argument("--run-on", dest="run_on", type=float, default=None, metavar="FACTOR",
                        help="run each pile on for FACTOR x its relaxation time first (in.runon)")
    parser.add_argument("--run-on-L", dest="run_on_L", nargs="+", type=float, default=None,
                        help="only the piles of these L")
    parser.add_argument("-j", "--jobs", type=int, default=1, help="run-on runs at once")
    parser.add_argument("--peak-margin", dest="peak_margin", type=float, default=PEAK_MARGIN,
                        metavar="D", help="fit the flank this far (in d) or more from the peak "
                        f"(default {PEAK_MARGIN:g}; 10 leaves out the summit, doc/pile2d.md)")
    parser.add_argument("--write", type=Path, default=None, metavar="FILE",
                        help="also write one line per pile (its run, record columns and shape)")
    args = parser.parse_args(argv)
    if args.base_motion:
        print("| time (sqrt(d/g)) | grains | base grains | moving | mean abs(v_x) | mean abs(v_x + omega r) |")
        print("|---|---|---|---|---|---|")
        for row in base_motion(args.base_motion[0], float(args.base_motion[1])):
            print("| {:.1f} | {} | {} | {} | {:.2e} | {:.2e} |".format(*row))
        return 0
    if not args.runs:
        parser.error("give RUN_DIR(s) or --base-motion")
    if not args.peak_margin >= 0:
        parser.error("--peak-margin: D must be >= 0")
    if args.run_on is not None:
        if not args.run_on > 0:
            parser.error("--run-on: FACTOR must be > 0")
        failures = []
        for run in args.runs:
            failures += run_on(run, args.run_on, args.run_on_L, args.jobs)
        if failures:
            print(f"run-on failed for {failures} (logs/runon_*.txt)", file=sys.stderr)
    shapes = []
    for run in args.runs:
        found, missing = ensemble_shapes(run, args.peak_margin)
        if missing:
            print(f"{run}: {missing} pile(s) without a dump (run the driver with --var final_dump=1)",
                  file=sys.stderr)
        shapes += found
    if not shapes:
        print("no pile dumps found", file=sys.stderr)
        return 1
    if args.write:
        columns = ("run", "model", "L", "seed", "damping", "substrate_d", "substrate_lc", "n_pile", "h0", "t_rain",
                   "t_end", "status", "grains", "top", "slope", "angle", "residual")
        with open(args.write, "w") as handle:
            handle.write("# " + " ".join(columns) + "\n")
            for shape in shapes:
                values = {**shape, "run": Path(shape["run"]).name}
                handle.write(" ".join(number_text(values.get(c, "nan")) for c in columns) + "\n")
    print(format_table(summarize(shapes)))
    runs_on = [e for run in args.runs for e in runon_summary(run)]
    if runs_on:
        print()
        print(format_runon(runs_on))
    return 0


if __name__ == "__main__":
    sys.exit(main())
