#!/usr/bin/python3
"""Accuracy against cost for the clogging silo (inputs/silo2d/in.silo2d):
arches per CPU-hour and the science metrics at several time steps.

Two measurements per time step dt:

1. Metrics (small silo, `-var quick 1`: 12 d wide, 230 grains, the paper's
   grains, contacts and outlet R = 3): run until NARCHES arches; mean eta,
   the peak of the phi PDF, the fraction of defects (phi > 180 deg), the
   ratio <f_n,arch>/<f_n,bulk> (bulk: regions C and I, 8 < h/d < 14, the
   small silo's counterpart of the paper's 27-48 window), and the arch rate
   per simulated second; each with a 95 % confidence interval.
2. Cost (the paper's silo, 32 d wide, 2870 grains, serial): time per step
   while the silo flows, from the Loop time lines after the deck says it
   has filled (`silo2d: filled at`).

Arches per CPU-hour of the paper's silo = (arch rate per simulated second
of the small silo) x (simulated seconds per CPU-hour of the paper's silo).
The arch rate is taken from the small silo because the flow through the
outlet, and so the time between clogs, depends on the outlet and not on the
silo's width and height (Beverloo); that is the assumption of this estimate,
and the small silo's own arches per CPU-hour are given beside it.

A third measurement gives the cost of fix clog's check: the paper's silo at
dt = 1e-5 with the check every step against the deck's default (every
0.01 s); the difference per step is the cost of one check.

Writes doc/accuracy_cost_silo2d.md and bench/results/silo2d_cost.txt.

    /usr/bin/python3 bench/silo2d_cost.py               # ~70 CPU-min serial (estimate)
    /usr/bin/python3 bench/silo2d_cost.py --quick       # smoke run, ~8 CPU-min

--quick took 490 CPU-s on 2026-11-30: most of it the paper's silo, which
fills for about 2 s of simulated time at each dt before it is timed. The
full run's estimate from the costs per step: the paper's silo 2.7 M steps
at dt = 1e-6 (about 20 min) and fewer at the larger ones, the small
silo's 30 arches at each dt about 35 min.
"""

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.tables import read_table  # noqa: E402
from analysis.common.stats import mean_t_ci  # noqa: E402
from analysis.silo2d import clogs as silo2d  # noqa: E402
from analysis.silo2d.clogs import bulk_mask  # noqa: E402
from analysis.silo2d.scan import PHI_BIN, phi_peak  # noqa: E402

D = 1.0 / 32
T_CONTACT = 2.4458e-4           # contact time of the deck's normal contact (s)
BULK_WINDOW = (8.0, 14.0)       # h/d, the small silo's bulk


def deck(variables):
    """The production deck, with index variables set ahead of it."""
    return benchlib.scene_deck("silo2d", variables)


def metrics(run_dir, simulated_time, rng):
    clogs = read_table(run_dir / "clogs.txt")
    arches = read_table(run_dir / "arches.txt")
    contacts = read_table(run_dir / "contacts.txt")
    found = clogs["clog"][clogs["status"] == 1]
    eta = clogs["eta"][clogs["status"] == 1]
    phi = arches["phi"]
    bulk = bulk_mask(contacts["x"], contacts["z"], D, *BULK_WINDOW)
    groups = []
    for c in found:
        group = silo2d.force_sums(arches["fn"][arches["clog"] == c], contacts["fn"][bulk & (contacts["clog"] == c)])
        group["phi"] = phi[arches["clog"] == c]
        groups.append(group)
    # a proportion of grains: a lower bound on the width
    defects = silo2d.wilson_interval(int(np.sum(phi > 180.0)), phi.size)
    # arches per simulated second: Poisson count, exact (Garwood) interval
    count = found.size
    rate_lo = stats.chi2.ppf(0.025, 2 * count) / 2 / simulated_time if count else 0.0
    rate_hi = stats.chi2.ppf(0.975, 2 * count + 2) / 2 / simulated_time
    return {
        "arches": count, "clogs": clogs["clog"].size,
        "eta": mean_t_ci(eta),
        "phi_peak": phi_peak(phi),
        "phi_peak_ci": silo2d.bootstrap_over_clogs(
            groups, lambda g: phi_peak(np.concatenate([x["phi"] for x in g])), rng),
        "defects": defects,
        "force_ratio": silo2d.force_ratio(groups),
        "force_ratio_ci": silo2d.bootstrap_over_clogs(groups, silo2d.force_ratio, rng),
        "rate": (count / simulated_time, rate_lo, rate_hi),
    }


def flowing_ms_per_step(result):
    """Mean time per step of the runs after the filling: the Loop time
    lines after the deck's `silo2d: filled at` line (the filling is a run
    and then chunks of 0.05 s until the gas is down or at rest; the chunks
    once counted as flow)."""
    loops = benchlib.loop_lines(after_filling(result["output"]))
    seconds = sum(t for t, _, _ in loops)
    steps = sum(s for _, s, _ in loops)
    return 1e3 * seconds / steps, steps


FILLED = "silo2d: filled at t = "       # the deck's line when its filling ends


def after_filling(output):
    """The screen output from the deck's FILLED line on."""
    if FILLED not in output:
        raise RuntimeError(f"the deck did not print '{FILLED}...'")
    return output.split(FILLED, 1)[1]


def filled_at(output):
    """The simulated time at which the deck's filling ended (s)."""
    return float(after_filling(output).split()[0])


def simulated_time_of(output):
    for line in output.splitlines():
        if line.startswith("silo2d: done after"):
            return float(line.split("t = ")[1].split()[0])
    raise RuntimeError("the deck did not print its final line")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smoke run: few arches, two dt")
    parser.add_argument("--narches", type=int, default=30)
    parser.add_argument("--dts", type=float, nargs="+", default=[1e-6, 2.5e-6, 5e-6, 1e-5, 2e-5])
    parser.add_argument("--seed", type=int, default=32452843)
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.narches, args.dts = 3, [5e-6, 1e-5]
    report_path = (benchlib.WORK / "quick" if args.quick else benchlib.ROOT / "doc") / "accuracy_cost_silo2d.md"
    rng = np.random.default_rng(1)
    rows = []
    for dt in args.dts:
        work = benchlib.WORK / "silo2d" / f"dt{dt:g}"
        benchlib.progress(f"dt = {dt:g} s (t_c/{T_CONTACT / dt:.0f}): small silo until {args.narches} arches")
        small = benchlib.run_deck(deck({"quick": 1, "dt": dt, "narches": args.narches, "seed": args.seed,
                                        "total_time": 400}), work / "small")
        simulated = simulated_time_of(small["output"]) - filled_at(small["output"])
        found = metrics(work / "small", simulated, rng)
        benchlib.progress(f"  {found['arches']} arches in {simulated:.1f} s simulated, "
                          f"{small['cpu']:.0f} s CPU; paper's silo: cost per step")
        full = benchlib.run_deck(deck({"dt": dt, "narches": 100000, "seed": args.seed,
                                       "total_time": 0.3 if not args.quick else 0.1}), work / "full")
        ms_per_step, steps = flowing_ms_per_step(full)
        benchlib.progress(f"  {ms_per_step:.3f} ms per step over {steps} steps")
        simulated_per_cpu_hour = 3600.0 / (ms_per_step * 1e-3 / dt)
        rows.append({"dt": dt, "small_cpu": small["cpu"], "simulated": simulated,
                     "ms_per_step": ms_per_step, "arches_per_hour": found["rate"][0] * simulated_per_cpu_hour,
                     "arches_per_hour_ci": (found["rate"][1] * simulated_per_cpu_hour,
                                            found["rate"][2] * simulated_per_cpu_hour),
                     "small_arches_per_hour": found["arches"] / (small["cpu"] / 3600.0), **found})

    benchlib.progress("cost of the check: paper's silo, dt 1e-5, check every step vs every 0.01 s")
    check_dt = 1e-5
    check_time = 0.1 if args.quick else 0.3
    costs = {}
    for label, every in (("default", 0.01), ("every step", check_dt)):
        result = benchlib.run_deck(deck({"dt": check_dt, "narches": 100000, "seed": args.seed,
                                         "total_time": check_time, "check_every_time": every}),
                                   benchlib.WORK / "silo2d" / f"check_{label.replace(' ', '_')}")
        costs[label] = flowing_ms_per_step(result)[0]
    check_fraction = costs["every step"] / costs["default"] - 1.0

    table = ["| dt (s) | t_c/dt | ms/step (paper's silo) | arches per CPU-hour (paper's silo, est.) "
             "| arches per CPU-hour (small silo) | arches | mean eta | phi peak (deg) | defects (phi > 180) "
             "| <f_n,arch>/<f_n,bulk> |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        eta, eta_half = r["eta"]
        d, d_lo, d_hi = r["defects"]
        table.append(
            f"| {r['dt']:g} | {T_CONTACT / r['dt']:.0f} | {r['ms_per_step']:.3f} "
            f"| {r['arches_per_hour']:.1f} [{r['arches_per_hour_ci'][0]:.1f}, {r['arches_per_hour_ci'][1]:.1f}] "
            f"| {r['small_arches_per_hour']:.0f} | {r['arches']} | {eta:.2f} ± {eta_half:.2f} "
            f"| {r['phi_peak']:.0f} [{r['phi_peak_ci'][0]:.0f}, {r['phi_peak_ci'][1]:.0f}] "
            f"| {d:.2f} [{d_lo:.2f}, {d_hi:.2f}] "
            f"| {r['force_ratio']:.2f} [{r['force_ratio_ci'][0]:.2f}, {r['force_ratio_ci'][1]:.2f}] |")
    text = f"""# Accuracy and cost: the clogging silo (Hidalgo et al. 2013)

Written by `bench/silo2d_cost.py` (its docstring says exactly what is run).
Metrics from the small silo (`-var quick 1`, 12 d wide, 230 grains) run until
{args.narches} arches at each time step, same seed; cost per step from the
paper's silo (32 d wide, 2650 grains, serial) while it flows. Arches per
CPU-hour of the paper's silo = arch rate per simulated second (small silo)
x simulated seconds per CPU-hour (paper's silo): an estimate that assumes the
time between clogs does not depend on the silo's size.

Confidence intervals (95 %): mean eta, Student t; phi peak (centre of the
fullest {PHI_BIN:g}-degree bin) and the force ratio, bootstrap over clogs;
defects, Wilson interval over arch grains; arch rate, exact Poisson interval.
The contact time t_c = {T_CONTACT:.4g} s; the paper uses dt = 1e-6 s = t_c/245.
Paper (R = 3, mu = 0.4): the eta PDF peaks near R + 2 = 5 (Fig. 2), the phi
PDF peaks below 180 degrees with a tail of defects above (Fig. 3),
<f_n,arch>/<f_n,b> = 35/20 = 1.75 (Table 1).

{chr(10).join(table)}

Cost of fix clog's check (paper's silo, dt = 1e-5, serial, {check_time:g} s of
flow after filling): {costs['default']:.4f} ms per step with the deck's check
every 0.01 s, {costs['every step']:.4f} ms with a check every step: one check
costs {100 * check_fraction:.2f} % of a step (a negative value is timing noise:
the check is below what this measurement resolves). At the deck's default
(every 1000 steps at dt = 1e-5, every 10000 at 1e-6) that is
{100 * check_fraction / 1000:.4f} % of a step or less.

{benchlib.provenance()}
"""
    report_path.parent.mkdir(parents=True, exist_ok=True)
    report_path.write_text(text)
    benchlib.write_raw("silo2d_cost", repr(rows) + "\n" + repr(costs) + "\n")
    benchlib.progress(f"wrote {report_path}")
    print(text)


if __name__ == "__main__":
    main()
