#!/usr/bin/python3
"""Cost and accuracy against cost for the open 2D pile (inputs/pile2d,
doc/pile2d.md). Writes doc/accuracy_cost_pile2d.md and
bench/results/pile2d_cost.txt.

1. Time per step of the contact models (none, overlap, depth, fixed) on one configuration: a pile
   of L = 50 d built with the fixed-l_c model (in.build, seed 15485863) is
   recreated atom by atom from its dump (no contact history) and run with
   each model's contacts (inputs/pile2d/contacts.in), at rest and while it
   discharges through a 6 d orifice; the models are interleaved over
   --repetitions rounds; median loop time per step and its ratio to no
   rolling resistance, with the min-max of the per-round ratios.
2. Accuracy against cost: the whole protocol (build, then discharge at
   three widths) with the fixed-l_c model at L = 30 d for --seeds piles, at
   each time step t_c/N (N = --fractions); mean h and P(h > 0) at each
   width with 95 % intervals, and the CPU time per pile (build and its
   three discharges). The piles differ with the time step (the rain is
   chaotic), so this measures what a user gets from the protocol, not the
   error of one trajectory.

    /usr/bin/python3 bench/pile2d_cost.py            # ~1 h serial on 2 cores
    /usr/bin/python3 bench/pile2d_cost.py --quick    # smoke run, ~3 min
"""

import argparse
import resource
import statistics
import subprocess
import sys
from pathlib import Path

from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.lammps_io import read_dump  # noqa: E402
from analysis.common.stats import mean_t_ci  # noqa: E402
from analysis.common.tables import read_rows  # noqa: E402

INPUTS = benchlib.INPUTS
MODELS = ("none", "overlap", "depth", "fixed")
SEED = 15485863


def children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_driver(out, length, seeds, widths, fractions_value, model="fixed"):
    """The ensemble driver (resumable) for one time step; returns the CPU
    seconds its LIGGGHTS runs took (0 when everything was already done)."""
    before = children_cpu()
    command = [sys.executable, "-m", "analysis.pile2d.driver", "--campaign", str(out), "--models", model,
               "--L", str(length), "--seeds", str(seeds), "--widths"] + [str(w) for w in widths] + \
              ["--dt-fraction", str(fractions_value), "-j", "1"]
    subprocess.run(command, cwd=benchlib.ROOT, check=True)
    return children_cpu() - before


# ---------------------------------------------------------------- 1. cost

def configuration_deck(columns, model, orifice, steps):
    """The dumped pile, atom by atom, with `model`'s contacts."""
    free = columns["type"] == 1
    lines = [f"variable model index {model}", f"variable inputs index {INPUTS}",
             "variable damping index 0.3", "variable rolling_damping index 0.3",
             "variable dt_fraction index 25",
             # the reference: no rolling resistance anywhere, not even the
             # default one on the substrate contacts (doc/pile2d.md)
             *(["variable substrate_lc index 0"] if model == "none" else []),
             "units si", "dimension 2", "atom_style sphere", "atom_modify map array",
             "boundary f f p", "newton off", "communicate single vel yes", "processors * 1 1",
             "region box block -27 27 -1 52 -0.5 0.5 units box", "create_box 2 box"]
    substrate = ~free
    for x, y in zip(columns["x"][substrate], columns["y"][substrate]):
        lines.append(f"create_atoms 2 single {x!r} {y!r} 0 units box")
    for x, y in zip(columns["x"][free], columns["y"][free]):
        lines.append(f"create_atoms 1 single {x!r} {y!r} 0 units box")
    lines += ["group substrate type 2", "group grains type 1",
              f"include {INPUTS / 'pile2d' / 'contacts.in'}",
              "set group substrate diameter 0.1 density ${rho}"]
    start = int(substrate.sum())
    for k, radius in enumerate(columns["radius"][free]):
        lines.append(f"set atom {start + k + 1} diameter {2 * radius!r} density ${{rho}}")
    lines += ["fix substrate_fixed substrate freeze", "fix gravity grains gravity ${g} vector 0 -1 0",
              "fix integrate grains nve/sphere", "fix plane all enforce2d",
              "thermo_modify lost ignore norm no", "thermo 1000",
              "run 200"]   # settle the fresh contacts a little before timing
    if orifice:
        lines += [f"region orifice block -{orifice / 2 + 0.05 - 1e-9} {orifice / 2 + 0.05 - 1e-9} "
                  "-1 0 -0.5 0.5 units box",
                  "group hole region orifice", "group hole_substrate intersect hole substrate",
                  "delete_atoms group hole_substrate"]
    lines.append(f"run {steps}")
    return "\n".join(lines) + "\n"


def measure_cost(repetitions, steps, quick):
    work = benchlib.WORK / ("quick" if quick else "") / "pile2d_cost"
    pile = work / "pile"
    pile.mkdir(parents=True, exist_ok=True)
    dump = pile / "pile.restart.dump"
    if not dump.exists():
        benchlib.progress("building the L = 50 d pile (fixed l_c) for the cost runs")
        subprocess.run([str(benchlib.OUR_BINARY), "-in", str(INPUTS / "pile2d" / "in.build"),
                        "-log", "none", "-var", "L", "30" if quick else "50", "-var", "model", "fixed",
                        "-var", "seed", str(SEED), "-var", "inputs", str(INPUTS), "-var", "final_dump", "1",
                        "-var", "pile", "pile.restart", "-var", "piles", "piles.txt"],
                       cwd=pile, check=True, stdout=subprocess.DEVNULL)
    columns = read_dump(dump)[-1][1]
    grains = int((columns["type"] == 1).sum())
    times = {(phase, m): [] for phase in ("rest", "discharge") for m in MODELS}
    for round_ in range(repetitions):
        for phase, orifice in (("rest", 0.0), ("discharge", 6.0)):
            for model in MODELS:
                result = benchlib.run_deck(configuration_deck(columns, model, orifice, steps),
                                           work / f"{phase}_{model}")
                seconds, count, _ = result["loops"][-1]
                times[(phase, model)].append(seconds / count)
        benchlib.progress(f"round {round_ + 1}/{repetitions}: " + ", ".join(
            f"{p} {m} {1e6 * times[(p, m)][-1]:.1f} us" for p, m in times))
    return grains, times


# ---------------------------------------------------------------- 2. accuracy

def proportion_ci(successes, n, level=0.95):
    """Clopper-Pearson interval of a proportion."""
    alpha = 1 - level
    lo = stats.beta.ppf(alpha / 2, successes, n - successes + 1) if successes > 0 else 0.0
    hi = stats.beta.ppf(1 - alpha / 2, successes + 1, n - successes) if successes < n else 1.0
    return lo, hi


def measure_accuracy(fractions, seeds, length, widths, quick):
    rows = []
    for fraction in fractions:
        out = benchlib.WORK / ("quick" if quick else "") / "pile2d_accuracy" / f"dt{fraction:g}"
        benchlib.progress(f"dt = t_c/{fraction:g}: {seeds} piles at L = {length:g} d, widths {widths}")
        cpu = run_driver(out, length, seeds, widths, fraction)
        records = read_rows(out / "discharges.txt")
        piles = read_rows(out / "piles.txt")
        row = {"fraction": fraction, "cpu": cpu, "piles": len(piles),
               "settled": sum(1 for p in piles if p["status"] == 1),
               "h0": mean_t_ci([p["h0"] for p in piles])}
        for w in widths:
            h = [r["h"] for r in records if abs(r["w"] - w) < 1e-6]
            jammed = sum(1 for value in h if value > 0)
            row[w] = {"n": len(h), "mean": mean_t_ci(h), "jam": jammed / len(h),
                      "jam_ci": proportion_ci(jammed, len(h))}
        rows.append(row)
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smoke run")
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--steps", type=int, default=5000)
    parser.add_argument("--fractions", type=float, nargs="+", default=[12.5, 25, 50, 100])
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--L", type=float, default=30.0)
    parser.add_argument("--widths", type=float, nargs=3, default=[3.0, 3.8, 4.6])
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.repetitions, args.steps, args.fractions, args.seeds, args.L = 1, 500, [12.5, 25], 3, 20.0
    report_path = (benchlib.WORK / "quick" if args.quick else benchlib.ROOT / "doc") / "accuracy_cost_pile2d.md"
    load_start = benchlib.load_average()

    grains, times = measure_cost(args.repetitions, args.steps, args.quick)
    accuracy = measure_accuracy(args.fractions, args.seeds, args.L, args.widths, args.quick)

    cost_table = ["| phase | model | time per step (us) | ratio to no rolling resistance [min, max over rounds] |",
                  "|---|---|---|---|"]
    for phase in ("rest", "discharge"):
        base = times[(phase, "none")]
        for model in MODELS:
            own = times[(phase, model)]
            ratios = [a / b for a, b in zip(own, base)]
            cost_table.append(f"| {phase} | {model} | {1e6 * statistics.median(own):.1f} | "
                              f"{statistics.median(own) / statistics.median(base):.3f} "
                              f"[{min(ratios):.3f}, {max(ratios):.3f}] |")
    accuracy_table = ["| dt | piles (settled) | CPU s per pile (build + 3 discharges) | h0 (d) | "
                      + " | ".join(f"w = {w:g} d: mean h (d) ± 95 % | P(jam) [95 %]" for w in args.widths) + " |",
                      "|---|---|---|---|" + "---|---|" * len(args.widths)]
    for row in accuracy:
        cells = [f"t_c/{row['fraction']:g}", f"{row['piles']} ({row['settled']})",
                 f"{row['cpu'] / max(row['piles'], 1):.1f}" if row["cpu"] > 0 else "(cached)",
                 f"{row['h0'][0]:.2f} ± {row['h0'][1]:.2f}"]
        for w in args.widths:
            entry = row[w]
            cells.append(f"{entry['mean'][0]:.2f} ± {entry['mean'][1]:.2f}")
            cells.append(f"{entry['jam']:.2f} [{entry['jam_ci'][0]:.2f}, {entry['jam_ci'][1]:.2f}]")
        accuracy_table.append("| " + " | ".join(cells) + " |")

    report = f"""# Accuracy and cost: the open 2D pile

Written by `bench/pile2d_cost.py` (see `bench/README.md`); the scene is
described in [pile2d.md](pile2d.md). Raw numbers: `bench/results/pile2d_cost.txt`.

## Time per step of the contact models

One pile of {grains} grains (L = {50 if not args.quick else 30} d, built with the fixed-l_c model)
recreated atom by atom (no contact history) and run with each model's
contacts, serially: at rest ({args.steps} steps after 200 of settling) and
discharging through a 6 d orifice ({args.steps} steps from the opening). Models
interleaved over {args.repetitions} rounds; median of the rounds.

{chr(10).join(cost_table)}

## Accuracy against cost: the time step

The whole protocol with the fixed-l_c model at L = {args.L:g} d: {args.seeds} piles
built (in.build) at each time step, each discharged at w = {', '.join(f'{w:g}' for w in args.widths)} d
(in.discharge). Mean h with a Student t 95 % interval, P(jam) = P(h > 0)
with a Clopper-Pearson 95 % interval. CPU time: all LIGGGHTS runs of the
step's ensemble (user + system) divided by the number of piles.

{chr(10).join(accuracy_table)}

Conditions:
{benchlib.provenance(load_start)}
"""
    report_path.parent.mkdir(parents=True, exist_ok=True)
    report_path.write_text(report)
    benchlib.write_raw("pile2d_cost", repr({str(k): v for k, v in times.items()}) + "\n" +
                       repr([{str(k): v for k, v in row.items()} for row in accuracy]) + "\n")
    benchlib.progress(f"written {report_path}")


if __name__ == "__main__":
    main()
