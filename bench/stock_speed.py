#!/usr/bin/python3
"""Does our build cost anything when our styles are not used? Runs one stock
deck, in the style of LIGGGHTS' packing tutorial (Hertz, tangential history,
no cohesion, no rolling resistance; a few thousand spheres inserted with
insert/pack fall and settle in a box with six walls), with our
build/bin/liggghts and with Debian's /usr/bin/liggghts, alternating the two
binaries over several repetitions, and reports the ratio of their loop times
within each repetition.

Both binaries read the very same deck file (its sha256 is recorded). The deck
uses only stock styles and a contact-model combination compiled in both
(hertz + tangential history + rolling off is on our whitelist).

Writes its section of doc/accuracy_cost_rolling.md and
bench/results/stock_speed.txt.

    /usr/bin/python3 bench/stock_speed.py            # full size, ~4 min
    /usr/bin/python3 bench/stock_speed.py --quick    # smoke run, < 1 min
"""

import argparse
import hashlib
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

BINARIES = {"ours": benchlib.OUR_BINARY, "debian": benchlib.STOCK_BINARY}


def deck(volume_fraction, steps):
    """The packing tutorial's box, materials and walls, with gravity instead
    of particle growth and two small sphere sizes (2.5 and 3 mm radius)."""
    return f"""# stock deck for bench/stock_speed.py: spheres settling in a box
atom_style granular
atom_modify map array
boundary m m m
newton off
communicate single vel yes
units si

region reg block -0.05 0.05 -0.05 0.05 0. 0.15 units box
create_box 1 reg
neighbor 0.002 bin
neigh_modify delay 0

fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.45
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.3
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5

pair_style gran model hertz tangential history
pair_coeff * *
timestep 0.00001

fix xwalls1 all wall/gran model hertz tangential history primitive type 1 xplane -0.05
fix xwalls2 all wall/gran model hertz tangential history primitive type 1 xplane +0.05
fix ywalls1 all wall/gran model hertz tangential history primitive type 1 yplane -0.05
fix ywalls2 all wall/gran model hertz tangential history primitive type 1 yplane +0.05
fix zwalls1 all wall/gran model hertz tangential history primitive type 1 zplane  0.00
fix zwalls2 all wall/gran model hertz tangential history primitive type 1 zplane  0.15

fix gravi all gravity 9.81 vector 0.0 0.0 -1.0

fix pts1 all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.0025
fix pts2 all particletemplate/sphere 15485867 atom_type 1 density constant 2500 radius constant 0.003
fix pdd1 all particledistribution/discrete 32452843 2 pts1 0.5 pts2 0.5

group nve_group region reg
fix ins nve_group insert/pack seed 32452867 distributiontemplate pdd1 &
    maxattempt 200 insert_every once overlapcheck yes all_in yes vel constant 0. 0. 0. &
    region reg volumefraction_region {volume_fraction}
fix integr nve_group nve/sphere

compute rke all erotate/sphere
thermo_style custom step atoms ke c_rke
thermo {max(steps // 5, 1)}
thermo_modify lost ignore norm no

# insert, then the timed run
run 1
unfix ins
run {steps}
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: about 900 spheres, 2 repetitions, 3000 steps")
    parser.add_argument("--volume-fraction", type=float, default=0.2,
                        help="insert/pack volume fraction of the box (0.2: about 3600 spheres)")
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--steps", type=int, default=30000,
                        help="timed steps per run (dt = 1e-5 s; 30000: fall, impact and settling)")
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.volume_fraction, args.repetitions, args.steps = 0.05, 2, 3000

    for name, binary in BINARIES.items():
        if not binary.exists():
            sys.exit(f"{binary} ({name}) is missing")
    text = deck(args.volume_fraction, args.steps)
    digest = hashlib.sha256(text.encode()).hexdigest()
    workdir = benchlib.WORK / "stock_speed"
    start_load = benchlib.load_average()

    names = list(BINARIES)
    loop_times = {name: [] for name in names}
    finals = {name: [] for name in names}
    raw = ["# stock_speed raw results",
           f"# deck sha256 {digest} (bench/work/stock_speed/<binary>/in.deck)",
           "# repetition binary loop_time_s steps atoms process_cpu_s process_wall_s "
           "final_ke_J final_rotational_ke_J"]
    atoms = None
    for rep in range(args.repetitions):
        order = names if rep % 2 == 0 else names[::-1]
        for name in order:
            result = benchlib.run_deck(text, workdir / name, binary=BINARIES[name])
            seconds, steps, atoms = result["loops"][-1]
            ke, rke = final_energies(result["output"])
            loop_times[name].append(seconds)
            finals[name].append((ke, rke))
            raw.append(f"{rep} {name} {seconds:.6g} {steps} {atoms} {result['cpu']:.4g} "
                       f"{result['wall']:.4g} {ke:.10g} {rke:.10g}")
            benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {name:7s} "
                              f"loop time {seconds:8.4g} s for {steps} steps, {atoms} atoms, "
                              f"final KE {ke:.6g} J")

    table = report(loop_times, finals, atoms, args, digest, start_load)
    benchlib.write_section("stock_speed", table)
    path = benchlib.write_raw("stock_speed", "\n".join(raw) + "\n")
    benchlib.progress(f"wrote {benchlib.REPORT.relative_to(benchlib.ROOT)} and "
                      f"{path.relative_to(benchlib.ROOT)}")
    print(table)


def final_energies(output):
    """KinEng and c_rke of the last thermo line before the last Loop time."""
    lines = output[:output.rindex("Loop time")].splitlines()
    values = [line.split() for line in lines if line.split()[:1] and line.split()[0].isdigit()]
    return float(values[-1][2]), float(values[-1][3])


def report(loop_times, finals, atoms, args, digest, start_load):
    ours, debian = loop_times["ours"], loop_times["debian"]
    ratios = [a / b for a, b in zip(ours, debian)]
    ratio, low, high = benchlib.spread(ratios)
    same_trajectory = all(f == finals["ours"][0] for f in finals["ours"] + finals["debian"])
    lines = [
        "## Stock deck, our build against Debian's (`bench/stock_speed.py`)",
        "",
        f"The packing tutorial's box, materials and six walls (Hertz, tangential history, "
        f"no cohesion, no rolling resistance), {atoms} spheres of radius 2.5 and 3 mm "
        f"inserted by insert/pack (volume fraction {args.volume_fraction}) and falling "
        f"under gravity; {args.steps} timed steps of 1e-5 s after the insertion step. "
        f"The same deck file (sha256 `{digest[:16]}…`) runs with both binaries, "
        f"alternating, {args.repetitions} repetitions; the ratio is taken within each "
        f"repetition.",
        "",
        "| binary | loop time (s), median [min–max] | time per step per atom (µs) |",
        "|---|---|---|",
    ]
    for name, label in (("ours", "`build/bin/liggghts` (silokit)"),
                        ("debian", "`/usr/bin/liggghts` (Debian 3.8.0)")):
        median, a, b = benchlib.spread(loop_times[name])
        lines.append(f"| {label} | {median:.4g} [{a:.4g}–{b:.4g}] | "
                     f"{1e6 * median / (args.steps * atoms):.3f} |")
    lines += [
        "",
        f"**Ratio ours / Debian: {ratio:.3f} [{low:.3f}–{high:.3f}]** (median [min–max] "
        f"over repetitions; below 1 means our build is faster).",
        "",
        ("Both binaries end every run with the same kinetic energies to all printed "
         "digits (the same trajectory)." if same_trajectory else
         "The final kinetic energies differ between runs or binaries (see the raw "
         "results): the trajectories are not bitwise identical, so the two binaries "
         "did not do exactly the same work."),
        "",
        benchlib.provenance(extra_load=start_load),
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
