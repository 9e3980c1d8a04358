#!/usr/bin/python3
"""Cost and accuracy of the rotating-bottom silo (inputs/silo3d_rotating/
in.silo3d_rotating), written to doc/accuracy_cost_silo3d_rotating.md and
bench/results/silo3d_rotating_cost.txt.

1. Cost per step, the paper's silo (10000 spheres) discharging from one
   settled packing (made once, cached in bench/work/silo3d/), serial,
   variants interleaved over repetitions so that they share the machine's
   load:
   - ours: fix wall/gran/rotating, D = 6 cm, f = 0.32 Hz;
   - mesh: the stock peer, the same bottom as a meshed annulus (64 sectors)
     in fix mesh/surface with surface_ang_vel, same D and f;
   - plate: fix wall/gran/rotating without hole or rotation, against
   - plane: the stock primitive zplane, the same physics (bit for bit,
     tests/test_wall_gran_rotating.py): the overhead of our force loop.
   Time per step = Loop time / steps of the discharge run (the settling
   is read from the packing).
2. Flow-rate agreement, ours against the mesh peer: the same packing, D and
   f, run --flow-time seconds each; stationary Q after --transient, with
   block standard errors (analysis/silo3d_rotating/flow.py).
3. Accuracy against cost: the quick silo (Dc = 12 d, 900 spheres, D = 5 d,
   f = 0.32 Hz, reinjection) at dt = t_c/158 (the paper's 1e-6 s), t_c/80,
   t_c/40, t_c/20, --seeds gas seeds each: stationary Q with its 95 % CI
   over seeds, against the CPU time per simulated second.

    /usr/bin/python3 bench/silo3d_rotating_cost.py            # ~1.5 h serial
    /usr/bin/python3 bench/silo3d_rotating_cost.py --quick    # smoke run, a few minutes
"""

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.silo3d_rotating.flow import analyse_flow  # noqa: E402
from analysis.silo3d_rotating.records import load_run  # noqa: E402
from analysis.common.stl import annulus_triangles, write_stl  # noqa: E402
from analysis.common.stats import mean_t_ci  # noqa: E402

T_CONTACT = 1.5797e-4        # s, the deck's grain-grain contact time
D = 0.06
F = 0.32
SILO_DIAMETER = 0.19


def deck(variables):
    """The production deck, with index variables set ahead of it."""
    return benchlib.scene_deck("silo3d_rotating", variables)


def packing(work, dt_fraction, quick):
    """The settled paper's silo, made once per dt (--quick: 2000 grains);
    returns the deck variables of a run that starts from it."""
    path = work / f"packing_dt{dt_fraction}" / "packing.restart"
    grains = {"N": 2000} if quick else {}      # the deck checks that the packing holds N
    if not path.exists():
        benchlib.progress(f"settling the paper's silo ({grains.get('N', 10000)} grains, "
                          f"dt t_c/{dt_fraction}), once")
        variables = {"dt_fraction": dt_fraction, "write_packing": 1, "discharge_time": 0}
        if quick:
            variables.update({**grains, "settle_time": 0.3})
        benchlib.run_deck(deck(variables), path.parent)
    return {"read_packing": 1, "packing": path, **grains}


def cost_variants(stl):
    """name -> extra deck variables of the discharge run."""
    return {
        "ours": {"D": D, "f": F},
        "mesh": {"D": D, "f": F, "mesh_bottom": 1, "bottom_mesh": stl},
        "plate": {"D": 0, "f": 0},
        "plane": {"D": 0, "f": 0, "plane_bottom": 1},
    }


def discharge_cost(result):
    """ms per step of the runs after the set-up (the deck's chunks)."""
    loops = result["loops"]
    seconds = sum(t for t, _, _ in loops)
    steps = sum(s for _, s, _ in loops)
    return 1e3 * seconds / steps, steps


def measure_costs(work, packed, stl, repetitions, flow_time, dt_fraction):
    times = {name: [] for name in cost_variants(stl)}
    for rep in range(repetitions):
        for name, extra in cost_variants(stl).items():
            variables = {"dt_fraction": dt_fraction, **packed,
                         "reinject": 1, "discharge_time": flow_time, **extra}
            result = benchlib.run_deck(deck(variables), work / "cost" / f"{name}_{rep}")
            ms, steps = discharge_cost(result)
            times[name].append(ms)
            benchlib.progress(f"cost, repetition {rep + 1}/{repetitions}, {name}: {ms:.3f} ms/step over {steps} steps")
    return times


def flow_rate_of(run_dir, transient):
    run = load_run(run_dir)
    return analyse_flow(run, transient=transient)


def measure_agreement(work, packed, stl, flow_time, transient, dt_fraction):
    flows = {}
    for name in ("ours", "mesh"):
        extra = cost_variants(stl)[name]
        variables = {"dt_fraction": dt_fraction, **packed,
                     "reinject": 1, "discharge_time": flow_time, **extra}
        benchlib.progress(f"flow rate, {name}: {flow_time:g} s of discharge")
        result = benchlib.run_deck(deck(variables), work / "agreement" / name)
        flows[name] = (flow_rate_of(work / "agreement" / name, transient), discharge_cost(result)[0])
        benchlib.progress(f"  Q = {flows[name][0].q_mass:.4f} +- {flows[name][0].q_mass_se:.4f} kg/s")
    return flows


def measure_accuracy(work, fractions, seeds, flow_time, transient):
    rows = []
    for fraction in fractions:
        qs, cpu, simulated = [], 0.0, 0.0
        for seed in seeds:
            run_dir = work / "accuracy" / f"dt{fraction}_s{seed}"
            variables = {"quick": 1, "dt_fraction": fraction, "seed": seed, "reinject": 1,
                         "f": F, "discharge_time": flow_time}
            result = benchlib.run_deck(deck(variables), run_dir)
            flow = flow_rate_of(run_dir, transient)
            qs.append(flow.q_mass)
            cpu += result["cpu"]
            simulated += 0.4 + flow_time
            benchlib.progress(f"accuracy, dt = t_c/{fraction}, seed {seed}: Q = {flow.q_mass:.4f} "
                              f"+- {flow.q_mass_se:.4f} kg/s, {result['cpu']:.0f} s CPU")
        mean, half = mean_t_ci(qs)
        rows.append({"fraction": fraction, "dt": T_CONTACT / fraction, "Q": mean, "Q_ci": half,
                     "Q_all": qs, "cpu_per_s": cpu / simulated})
    return rows


def report(costs, flows, accuracy, args):
    def spread(values):
        return f"{np.median(values):.3f} [{min(values):.3f}, {max(values):.3f}]"

    ratios = {name: [t / r for t, r in zip(costs[name], costs[ref])]
              for name, ref in (("mesh", "ours"), ("plate", "plane"))}
    cost_table = ["| variant | bottom | ms per step, median [min, max] |", "|---|---|---|",
                  f"| ours | fix wall/gran/rotating, D = {D * 100:g} cm, f = {F:g} Hz | {spread(costs['ours'])} |",
                  f"| mesh | stock mesh annulus (64 sectors), surface_ang_vel, same D, f | {spread(costs['mesh'])} |",
                  f"| plate | fix wall/gran/rotating, no hole, no rotation | {spread(costs['plate'])} |",
                  f"| plane | stock wall/gran primitive zplane | {spread(costs['plane'])} |"]
    ours, mesh = flows["ours"][0], flows["mesh"][0]
    difference = ours.q_mass - mesh.q_mass
    sigma = math.hypot(ours.q_mass_se, mesh.q_mass_se)
    accuracy_table = ["| dt | t_c/dt | Q (kg/s), mean over seeds ± 95 % CI | per seed | CPU s per simulated s |",
                      "|---|---|---|---|---|"]
    for row in accuracy:
        accuracy_table.append(
            f"| {row['dt']:.3g} | {row['fraction']} | {row['Q']:.4f} ± {row['Q_ci']:.4f} "
            f"| {', '.join(f'{q:.4f}' for q in row['Q_all'])} | {row['cpu_per_s']:.0f} |")
    return f"""# Accuracy and cost: the rotating-bottom silo (Pongó et al. 2022)

Written by `bench/silo3d_rotating_cost.py` (its docstring says exactly what
is run). Timings are serial `Loop time`s on a machine that may be shared:
compare the ratios, taken between variants run one after the other in each
repetition.

## Cost per step (the paper's silo, 10000 spheres, dt = t_c/{args.dt_fraction}, {args.cost_time:g} s of discharge per run, {args.repetitions} repetitions)

{chr(10).join(cost_table)}

- stock mesh bottom / ours: {spread(ratios['mesh'])} (median [min, max] over repetitions)
- our plate / stock plane (same physics): {spread(ratios['plate'])}

## Flow rate, ours against the stock mesh peer

Same packing, D = {D * 100:g} cm, f = {F:g} Hz, reinjection, {args.flow_time:g} s of discharge,
stationary Q after {args.transient:g} s (block standard errors):

| bottom | Q (kg/s) | ms per step |
|---|---|---|
| ours | {ours.q_mass:.4f} ± {ours.q_mass_se:.4f} | {flows['ours'][1]:.3f} |
| stock mesh | {mesh.q_mass:.4f} ± {mesh.q_mass_se:.4f} | {flows['mesh'][1]:.3f} |

Difference {difference:+.4f} kg/s = {difference / sigma:+.1f} standard errors
({100 * difference / mesh.q_mass:+.1f} %). The two bottoms differ where the
mesh's hole is a 64-gon inscribed in the circle (its area 0.16 % smaller) and
in how a contact moves from triangle to triangle; the flow itself is chaotic,
so agreement is statistical.

## Accuracy against cost (quick silo: Dc = 12 d, 900 spheres, D = 5 d, f = {F:g} Hz, reinjection)

Seeds: {', '.join(str(s) for s in args.seeds)}; {args.accuracy_time:g} s of discharge, Q after
{args.transient:g} s; t_c = {T_CONTACT:.4g} s (the paper's dt = 1e-6 s is t_c/158).

{chr(10).join(accuracy_table)}

{benchlib.provenance()}
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smoke run (small packing, short runs)")
    parser.add_argument("--repetitions", type=int, default=3)
    parser.add_argument("--cost-time", type=float, default=0.05, help="discharge per cost run (s)")
    parser.add_argument("--flow-time", type=float, default=2.0, help="discharge per agreement run (s)")
    parser.add_argument("--accuracy-time", type=float, default=3.0, help="discharge per accuracy run (s)")
    parser.add_argument("--transient", type=float, default=0.5)
    parser.add_argument("--dt-fraction", type=int, default=40, help="dt = t_c/this for parts 1 and 2")
    parser.add_argument("--fractions", type=int, nargs="+", default=[158, 80, 40, 20])
    parser.add_argument("--seeds", type=int, nargs="+", default=[32452843, 49979687, 67867967])
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.repetitions, args.flow_time, args.accuracy_time = 1, 0.6, 0.6
        args.fractions, args.seeds, args.transient = [40, 20], [32452843, 49979687], 0.2
    work = benchlib.WORK / ("quick" if args.quick else "") / "silo3d"
    report_path = (benchlib.WORK / "quick" if args.quick else benchlib.ROOT / "doc") / \
        "accuracy_cost_silo3d_rotating.md"
    stl = work / "annulus.stl"
    stl.parent.mkdir(parents=True, exist_ok=True)
    write_stl(stl, annulus_triangles(D / 2, SILO_DIAMETER / 2))

    packed = packing(work, args.dt_fraction, args.quick)
    costs = measure_costs(work, packed, stl, args.repetitions, args.cost_time, args.dt_fraction)
    flows = measure_agreement(work, packed, stl, args.flow_time, args.transient, args.dt_fraction)
    accuracy = measure_accuracy(work, args.fractions, args.seeds, args.accuracy_time, args.transient)
    text = report(costs, flows, accuracy, args)
    report_path.parent.mkdir(parents=True, exist_ok=True)
    report_path.write_text(text)
    benchlib.write_raw("silo3d_rotating_cost", repr({"costs": costs, "accuracy": accuracy,
                                                     "flows": {k: (v[0].q_mass, v[0].q_mass_se, v[1])
                                                               for k, v in flows.items()}}) + "\n")
    benchlib.progress(f"wrote {report_path}")
    print(text)


if __name__ == "__main__":
    main()
