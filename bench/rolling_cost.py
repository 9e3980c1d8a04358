#!/usr/bin/python3
"""Cost of rolling resistance: time per step of one dense 2D packing of
polydisperse discs with no rolling resistance, stock `rolling_friction epsd3`
(configured like jiang), `rolling_friction jiang` with a fixed contact length
and with the contact length from the overlap.

The packing (discs of diameter d = 1 mm +-5 %, uniform, settled under
gravity in a box with walls) is built once, written with write_data and
cached in bench/work/; every timed run reads the same file. The models are
interleaved: each repetition runs all four, in an order rotated from one
repetition to the next, and the ratio to "no rolling" is taken within each
repetition (so a machine that slows down for a while hurts both sides).

Writes its section of doc/accuracy_cost_rolling.md and
bench/results/rolling_cost.txt.

    /usr/bin/python3 bench/rolling_cost.py            # full size, ~5-10 min
    /usr/bin/python3 bench/rolling_cost.py --quick    # smoke run, ~1 min
"""

import argparse
import hashlib
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.deck_blocks import granular_setup  # noqa: E402

DIAMETER = 1.0e-3          # nominal disc diameter (m)
POLYDISPERSITY = 0.05      # diameters uniform in d (1 +- 0.05)
DENSITY = 2500.0
KN = 1.0e5                 # N/m
KT = 2.0 / 7.0 * KN
MU = 0.5
GRAVITY = 9.81
COLUMNS = 45               # discs per lattice row of the initial square lattice
SPACING = 1.1 * DIAMETER   # lattice spacing: a gap so that the discs start apart
DAMPING_RATIO = 0.35       # normal damping, fraction of critical (restitution ~0.3)
DT_FRACTION = 1.0 / 50.0   # time step as a fraction of t_c
CONTACT_LENGTH = 0.05 * DIAMETER
SETTLE_TIME = 0.4          # s of settling under gravity
SEEDS = (15485863, 32452843, 49979687)   # LIGGGHTS wants primes > 10000

# The four models, all with the same normal and tangential law. The walls
# carry no rolling resistance in every variant, so that only the pair
# contacts differ. epsd3 is configured to give jiang's fixed-length law at the
# nominal size: k_r = rollingStiffness kn (rmu r_eff)^2 = kn l_c^2 and
# cap = rmu r_eff |F_n| = mu l_c |F_n| with rmu = mu l_c / r_eff and
# rollingStiffness = 1/mu^2; r_eff = d/4 for two nominal discs.
REDUCED_RADIUS = DIAMETER / 4.0
MODELS = {
    "off": ("", ""),
    "epsd3": ("rolling_friction epsd3",
              f"fix m_rmu all property/global coefficientRollingFriction peratomtypepair 1 "
              f"{MU * CONTACT_LENGTH / REDUCED_RADIUS!r}\n"
              "fix m_rvd all property/global coefficientRollingViscousDamping peratomtypepair 1 0.0\n"
              f"fix m_rks all property/global rollingStiffness scalar {1.0 / MU**2!r}\n"),
    "jiang_fixed": ("rolling_friction jiang",
                    f"fix m_lc all property/global rollingContactLength peratomtypepair 1 "
                    f"{CONTACT_LENGTH!r}\n"),
    "jiang_overlap": ("rolling_friction jiang contactLengthFromOverlap on", ""),
}
LABELS = {
    "off": "no rolling resistance",
    "epsd3": "epsd3, rmu = μ l_c / r_eff, rollingStiffness = 1/μ²",
    "jiang_fixed": "jiang, fixed l_c = 0.05 d",
    "jiang_overlap": "jiang, l_c from the overlap",
}


def contact_time():
    """t_c = pi sqrt(m_eff/kn) of two nominal discs (2D mass pi r^2 rho)."""
    mass = math.pi * (DIAMETER / 2) ** 2 * DENSITY
    return math.pi * math.sqrt(0.5 * mass / KN)


def normal_damping():
    """gamman of hooke/stiffness (it multiplies m_eff) for DAMPING_RATIO."""
    mass = math.pi * (DIAMETER / 2) ** 2 * DENSITY
    return 2.0 * DAMPING_RATIO * math.sqrt(KN / (0.5 * mass))


def materials():
    gamman = normal_damping()
    return (f"fix m_kn all property/global kn peratomtypepair 1 {KN!r}\n"
            f"fix m_kt all property/global kt peratomtypepair 1 {KT!r}\n"
            f"fix m_gn all property/global gamman peratomtypepair 1 {gamman!r}\n"
            f"fix m_gt all property/global gammat peratomtypepair 1 {0.5 * gamman!r}\n"
            f"fix m_mu all property/global coefficientFriction peratomtypepair 1 {MU!r}\n")


def box(rows):
    width = COLUMNS * SPACING
    height = 1.3 * rows * SPACING
    return width, height


def walls(width):
    model = "model hooke/stiffness tangential history"
    return (f"fix wall_left all wall/gran {model} primitive type 1 xplane 0.0\n"
            f"fix wall_right all wall/gran {model} primitive type 1 xplane {width!r}\n"
            f"fix wall_bottom all wall/gran {model} primitive type 1 yplane 0.0\n")


HEADER_2D = granular_setup(dimension=2, boundary="f f p") + "\n"


def settle_deck(rows, dt, steps):
    width, height = box(rows)
    half_depth = DIAMETER / 2
    fill_height = rows * SPACING
    return f"""{HEADER_2D}
region box block 0 {width!r} 0 {height!r} {-half_depth!r} {half_depth!r} units box
create_box 1 box
neighbor {0.2 * DIAMETER!r} bin
neigh_modify delay 0
{materials()}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
{walls(width)}
timestep {dt!r}
lattice sq {SPACING!r} origin 0.5 0.5 0
region fill block 0 {width!r} 0 {fill_height!r} {-half_depth!r} {half_depth!r} units box
create_atoms 1 region fill
variable diameter atom {DIAMETER!r}*(1-{POLYDISPERSITY!r}+2*{POLYDISPERSITY!r}*random(0,1,{SEEDS[0]}))
set group all diameter v_diameter
set group all density {DENSITY!r}
# random initial velocities, else the lattice columns fall as straight stacks
variable vx atom 0.2*(random(0,1,{SEEDS[1]})-0.5)
variable vy atom 0.2*(random(0,1,{SEEDS[2]})-0.5)
set group all vx v_vx vy v_vy
fix gravity all gravity {GRAVITY!r} vector 0 -1 0
fix integrate all nve/sphere
fix twod all enforce2d
thermo_style custom step atoms ke
thermo_modify norm no
thermo {max(steps // 10, 1)}
run {steps}
write_data packing.data
"""


def timed_deck(model, width, dt, warmup_steps, steps):
    rolling, properties = MODELS[model]
    return f"""{HEADER_2D}
read_data packing.data
# write_data of LIGGGHTS 3.8 stores a 2D disc's density as mass/(4/3 pi r^3)
# and read_data turns it back with pi r^2: set the density again
set group all density {DENSITY!r}
neighbor {0.2 * DIAMETER!r} bin
neigh_modify delay 0
{materials()}{properties}
pair_style gran model hooke/stiffness tangential history {rolling}
pair_coeff * *
{walls(width)}
timestep {dt!r}
fix gravity all gravity {GRAVITY!r} vector 0 -1 0
fix integrate all nve/sphere
fix twod all enforce2d
thermo_style custom step atoms ke
thermo {steps}
run {warmup_steps}
run {steps}
# contacts (overlapping pairs), counted after the timed run
compute touching all contact/atom
compute contacts_times_two all reduce sum c_touching
thermo_style custom step atoms ke c_contacts_times_two
run 0
"""


def last_thermo_row(output):
    """Column names and the last row of the last thermo table in `output`."""
    lines = output.splitlines()
    header = max(i for i, line in enumerate(lines) if line.split()[:1] == ["Step"])
    row = header
    while row + 1 < len(lines) and lines[row + 1].split()[:1] and \
            lines[row + 1].split()[0].isdigit():
        row += 1
    return lines[header].split(), [float(value) for value in lines[row].split()]


def build_packing(workdir, rows, dt):
    steps = int(round(SETTLE_TIME / dt))
    path = workdir / "packing.data"
    if path.exists():
        benchlib.progress(f"reusing the packing {path.relative_to(benchlib.ROOT)}")
        return path
    benchlib.progress(f"settling {rows * COLUMNS} discs for {SETTLE_TIME} s "
                      f"({steps} steps), once; cached in {workdir.relative_to(benchlib.ROOT)}")
    result = benchlib.run_deck(settle_deck(rows, dt, steps), workdir)
    names, values = last_thermo_row(result["output"].split("System init for write_data")[0])
    kinetic = values[names.index("KinEng")]
    benchlib.progress(f"settled in {result['wall']:.0f} s; kinetic energy at the end "
                      f"{kinetic:.3g} J")
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 450 discs, 2 repetitions, 500 steps")
    parser.add_argument("--atoms", type=int, default=3150,
                        help="number of discs (rounded up to full rows of 45); default 3150")
    parser.add_argument("--repetitions", type=int, default=6)
    parser.add_argument("--steps", type=int, default=10000, help="timed steps per run")
    parser.add_argument("--warmup", type=int, default=200,
                        help="untimed steps before each timed run")
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.atoms, args.repetitions, args.steps, args.warmup = 450, 2, 500, 50

    rows = -(-args.atoms // COLUMNS)
    t_c = contact_time()
    dt = DT_FRACTION * t_c
    width, _ = box(rows)
    # the cached packing is named after its deck: other parameters, other file
    settle = settle_deck(rows, dt, int(round(SETTLE_TIME / dt)))
    key = hashlib.sha256(settle.encode()).hexdigest()[:10]
    workdir = benchlib.WORK / "rolling_cost" / f"rows{rows}_{key}"
    start_load = benchlib.load_average()
    build_packing(workdir, rows, dt)

    names = list(MODELS)
    loop_times = {name: [] for name in names}
    pair_times = {name: [] for name in names}
    contacts = {}
    atoms = None
    raw = ["# rolling_cost raw results",
           f"# {rows * COLUMNS} discs, dt = {dt:.6g} s = t_c/{1 / DT_FRACTION:.0f}, "
           f"{args.steps} timed steps after {args.warmup} warm-up steps",
           "# repetition model loop_time_s pair_time_s steps atoms process_cpu_s "
           "process_wall_s contacts"]
    for rep in range(args.repetitions):
        order = names[rep % len(names):] + names[:rep % len(names)]
        for name in order:
            result = _run_model(name, workdir, width, dt, args)
            seconds, steps, atoms = result["loops"][1]
            count = last_thermo_row(result["output"])[1][-1] / 2
            contacts.setdefault(name, count)
            loop_times[name].append(seconds)
            pair_times[name].append(result["pair_times"][1])
            raw.append(f"{rep} {name} {seconds:.6g} {result['pair_times'][1]:.6g} {steps} "
                       f"{atoms} {result['cpu']:.4g} "
                       f"{result['wall']:.4g} {count:.0f}")
            benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {name:14s} "
                              f"{1e6 * seconds / steps:8.2f} us/step  ({count:.0f} contacts)")

    table = report(names, loop_times, pair_times, contacts, args, atoms, dt, t_c, start_load)
    benchlib.write_section("rolling_cost", table)
    path = benchlib.write_raw("rolling_cost", "\n".join(raw) + "\n")
    benchlib.progress(f"wrote {benchlib.REPORT.relative_to(benchlib.ROOT)} and "
                      f"{path.relative_to(benchlib.ROOT)}")
    print(table)


def _run_model(name, workdir, width, dt, args):
    run_dir = workdir / name
    run_dir.mkdir(parents=True, exist_ok=True)
    packing = run_dir / "packing.data"
    if not packing.exists():
        packing.symlink_to(workdir / "packing.data")
    return benchlib.run_deck(timed_deck(name, width, dt, args.warmup, args.steps), run_dir)


def report(names, loop_times, pair_times, contacts, args, atoms, dt, t_c, start_load):
    steps = args.steps
    reference = loop_times["off"]
    lines = [
        "## Cost of rolling resistance (`bench/rolling_cost.py`)",
        "",
        f"A settled 2D packing of {atoms} discs (d = 1 mm ± 5 %, uniform; "
        f"k_n = {KN:g} N/m, μ = {MU}, normal damping {DAMPING_RATIO:g} of critical) "
        f"in a box with three walls, under gravity; Δt = t_c/{1 / DT_FRACTION:.0f} = "
        f"{dt:.3g} s with t_c = π sqrt(m_eff/k_n) = {t_c:.3g} s for two nominal discs. "
        f"Each run reads the same packing (write_data, so contact histories start "
        f"unloaded), runs {args.warmup} untimed steps, then {steps} timed steps "
        f"(`Loop time`). {args.repetitions} repetitions; in each, the four models run "
        f"one after the other in a rotated order, and the ratio to \"no rolling\" is "
        f"taken within the repetition. Walls have no rolling resistance in any variant. "
        f"l_c = 0.05 d; epsd3 is set to the same law at the nominal size "
        f"(coefficientRollingFriction = μ l_c / r_eff = "
        f"{MU * CONTACT_LENGTH / REDUCED_RADIUS:g}, rollingStiffness = 1/μ² = "
        f"{1 / MU**2:g}, no rolling damping).",
        "",
        "| model | time per step (µs), median [min–max] | ratio to no rolling, median [min–max] "
        "| contacts | time per step per contact (ns) | pair time per step per contact (ns), "
        "median [min–max] |",
        "|---|---|---|---|---|---|",
    ]
    for name in names:
        per_step = [1e6 * t / steps for t in loop_times[name]]
        ratios = [t / r for t, r in zip(loop_times[name], reference)]
        median, low, high = benchlib.spread(per_step)
        ratio, ratio_low, ratio_high = benchlib.spread(ratios)
        per_contact = 1e3 * median / contacts[name]
        pair = [1e9 * t / steps / contacts[name] for t in pair_times[name]]
        pair_median, pair_low, pair_high = benchlib.spread(pair)
        lines.append(f"| {LABELS[name]} | {median:.1f} [{low:.1f}–{high:.1f}] | "
                     f"{ratio:.3f} [{ratio_low:.3f}–{ratio_high:.3f}] | "
                     f"{contacts[name]:.0f} | {per_contact:.1f} | "
                     f"{pair_median:.1f} [{pair_low:.1f}–{pair_high:.1f}] |")
    lines += [
        "",
        "Contacts: overlapping disc pairs after the timed run (`compute contact/atom`, "
        "wall contacts not counted); time per contact divides the whole step "
        "(integration, neighbour lists, walls included) by them; pair time is "
        "LIGGGHTS' `Pair time` of the timed run (the pair force loop only).",
        "",
        benchlib.provenance(extra_load=start_load),
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
