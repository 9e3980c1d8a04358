#!/usr/bin/python3
"""Cost of our LAMMPS pair style: time per step of one settled 3D bed of
spheres with `pair_style granular/jiang` (our plugin) against LAMMPS' own
`pair_style granular` with the same contact law as near as it goes
(`hooke` + `damping mass_velocity` + `tangential linear_history`), without
rolling resistance and with it (ours: `rolling jiang`, LAMMPS': `rolling
sds` set to the same stiffness and limit at the nominal size).

The bed (spheres of d = 10 mm +-5 %, uniform, poured from a lattice and
settled under gravity on a flat `fix wall/gran` in a box periodic in x and
y) is built once with LAMMPS' own pair style, written with write_data and
cached in bench/work/; every timed run reads the same file (so contact
histories start unloaded). The four variants alternate: each repetition
runs all four in an order rotated from one repetition to the next, and
t_ours/t_lammps is taken within the repetition, for the loop time, the
pair time ("Pair" row of LAMMPS' MPI task timing breakdown) and the CPU
time of the process (steadier than the wall-clock times when other jobs
share the cores).

Writes the table into bench/results/lammps_pair_cost.txt (with the raw
runs) and the section "Cost" of doc/pair_granular_jiang.md.

    /usr/bin/python3 bench/lammps_pair_cost.py            # full size, ~6 min
    /usr/bin/python3 bench/lammps_pair_cost.py --quick    # smoke run, < 1 min
"""

import argparse
import hashlib
import math
import os
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

LMP = Path(os.environ.get("SILOKIT_LMP", benchlib.ROOT / "build" / "bin" / "lmp"))
PLUGIN = Path(os.environ.get("SILOKIT_LAMMPS_PLUGIN",
                             benchlib.ROOT / "build" / "lib" / "silokit_lammps.so"))
PAGE = benchlib.ROOT / "doc" / "pair_granular_jiang.md"
SECTION = "lammps_pair_cost"

DIAMETER = 0.01            # nominal sphere diameter (m)
POLYDISPERSITY = 0.05      # diameters uniform in d (1 +- 0.05)
DENSITY = 2500.0
KN = 1.0e5                 # N/m
KT = 2.0 / 7.0 * KN
MU = 0.5
GRAVITY = 9.81
SIDE = 15                  # spheres per lattice row, in x and in y (periodic)
SPACING = 1.1 * DIAMETER   # lattice spacing: a gap so that the spheres start apart
DAMPING_RATIO = 0.35       # normal damping, fraction of critical (restitution ~0.3)
DT_FRACTION = 1.0 / 50.0   # time step as a fraction of t_c
CONTACT_LENGTH = 0.05 * DIAMETER
SETTLE_TIME = 0.4          # s of settling under gravity
SEEDS = (15485863, 32452843, 49979687, 67867967)

# LAMMPS' rolling sds set to Jiang's fixed-length law at the nominal size:
# its torque is R_eff n x F_r with F_r = -k_R (R_eff x rolled angle), so the
# rolling stiffness is k_R R_eff^2 = kn l_c^2 and the cap R_eff mu_R F_n =
# mu l_c F_n, with R_eff = d/4 for two nominal spheres. No rolling damping
# on either side.
REDUCED_RADIUS = DIAMETER / 4.0
SDS_STIFFNESS = KN * (CONTACT_LENGTH / REDUCED_RADIUS) ** 2
SDS_FRICTION = MU * CONTACT_LENGTH / REDUCED_RADIUS

VARIANTS = ["ours_off", "lammps_off", "ours_rolling", "lammps_rolling"]
LABELS = {
    "ours_off": "`granular/jiang`, no rolling resistance",
    "lammps_off": "`granular`, no rolling resistance",
    "ours_rolling": "`granular/jiang` + `rolling jiang`, fixed l_c = 0.05 d",
    "lammps_rolling": "`granular` + `rolling sds`, the same k_r and cap at the nominal size",
}
# which stock variant each of ours is compared with
PEERS = {"ours_off": "lammps_off", "ours_rolling": "lammps_rolling"}

LOOP_TIME = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms",
                       re.MULTILINE)
# "Pair    |  min time  |  avg time  |  max time  |%varavg| %total" of each run
PAIR_ROW = re.compile(r"^Pair\s+\|\s*(\S+)\s*\|\s*(\S+)\s*\|", re.MULTILINE)
CONTACTS = re.compile(r"^contacts (\S+)$", re.MULTILINE)
# LAMMPS' share of a core during each run: low when the machine is loaded
CPU_USE = re.compile(r"^([\d.]+)% CPU use with", re.MULTILINE)


def sphere_mass():
    return DENSITY * 4.0 / 3.0 * math.pi * (DIAMETER / 2) ** 3


def contact_time():
    """t_c = pi sqrt(m_eff/kn) of two nominal spheres."""
    return math.pi * math.sqrt(0.5 * sphere_mass() / KN)


def normal_damping():
    """gamman (1/s, it multiplies m_eff) for DAMPING_RATIO of critical."""
    return 2.0 * DAMPING_RATIO * math.sqrt(KN / (0.5 * sphere_mass()))


def pair_lines(variant):
    """pair_style and pair_coeff of a variant: the same kn, kt, damping
    (gamman m_eff normal, gammat m_eff tangential) and friction."""
    gamman = normal_damping()
    gammat = 0.5 * gamman
    if variant.startswith("ours"):
        coeff = (f"normal hooke/stiffness {KN!r} {KT!r} {gamman!r} {gammat!r} friction {MU!r}")
        if variant == "ours_rolling":
            coeff += f" rolling jiang 1 1 lc {CONTACT_LENGTH!r}"
        return f"pair_style granular/jiang\npair_coeff * * {coeff}\n"
    # LAMMPS: damping mass_velocity gives gamman m_eff; the tangential
    # damping is its second coefficient times the normal one
    coeff = (f"hooke {KN!r} {gamman!r} damping mass_velocity "
             f"tangential linear_history {KT!r} {gammat / gamman!r} {MU!r}")
    if variant == "lammps_rolling":
        coeff += f" rolling sds {SDS_STIFFNESS!r} 0.0 {SDS_FRICTION!r}"
    return f"pair_style granular\npair_coeff * * {coeff}\n"


def header(plugin=True):
    """The deck's head; the timed decks all load the plugin, so that they
    differ in their pair lines only."""
    load = f"variable plugin index {PLUGIN}\nplugin load ${{plugin}}\n" if plugin else ""
    return f"""{load}units si
atom_style sphere
boundary p p f
newton off
comm_modify vel yes
"""


def box(layers):
    width = SIDE * SPACING
    return width, 1.5 * layers * SPACING


def wall():
    """The floor: LAMMPS' own fix wall/gran (its hooke/history law), the
    same in every variant."""
    gamman = normal_damping()
    return (f"fix floor all wall/gran hooke/history {KN!r} {KT!r} {gamman!r} {0.5 * gamman!r} "
            f"{MU!r} 1 zplane 0.0 NULL\n")


def settle_deck(layers, dt, steps):
    width, height = box(layers)
    return f"""{header(plugin=False)}
region box block 0 {width!r} 0 {width!r} 0 {height!r} units box
create_box 1 box
neighbor {0.2 * DIAMETER!r} bin
neigh_modify delay 0
{pair_lines("lammps_off")}
{wall()}
timestep {dt!r}
lattice sc {SPACING!r} origin 0.5 0.5 0.5
region fill block 0 {width!r} 0 {width!r} 0 {layers * SPACING!r} units box
create_atoms 1 region fill
variable diameter atom {DIAMETER!r}*(1-{POLYDISPERSITY!r}+2*{POLYDISPERSITY!r}*random(0,1,{SEEDS[0]}))
set group all diameter v_diameter density {DENSITY!r}
# random initial velocities, else the lattice columns fall as straight stacks
variable vx atom 0.2*(random(0,1,{SEEDS[1]})-0.5)
variable vy atom 0.2*(random(0,1,{SEEDS[2]})-0.5)
variable vz atom 0.2*(random(0,1,{SEEDS[3]})-0.5)
set group all vx v_vx vy v_vy vz v_vz
fix gravity all gravity {GRAVITY!r} vector 0 0 -1
fix integrate all nve/sphere
thermo_style custom step atoms ke
thermo_modify norm no
thermo {max(steps // 10, 1)}
run {steps}
write_data packing.data
"""


def timed_deck(variant, dt, warmup_steps, steps):
    return f"""{header()}
read_data packing.data
neighbor {0.2 * DIAMETER!r} bin
neigh_modify delay 0
{pair_lines(variant)}
{wall()}
timestep {dt!r}
fix gravity all gravity {GRAVITY!r} vector 0 0 -1
fix integrate all nve/sphere
thermo_style custom step atoms ke
thermo_modify norm no
thermo {steps}
run {warmup_steps}
run {steps}
# contacts (touching pairs), counted after the timed run
compute touching all contact/atom
compute contacts_times_two all reduce sum c_touching
thermo_style custom step atoms ke c_contacts_times_two
variable contacts equal c_contacts_times_two/2
run 0 post no
print "contacts ${{contacts}}"
"""


def run(deck, workdir):
    """Runs a deck with our lmp; loop and pair time of each `run`."""
    result = benchlib.run_deck(deck, workdir, binary=LMP)
    output = result["output"]
    result["loops"] = [(float(t), int(steps), int(atoms))
                       for t, _, steps, atoms in LOOP_TIME.findall(output)]
    result["pair_times"] = [float(avg) for _, avg in PAIR_ROW.findall(output)]
    result["cpu_use"] = [float(share) for share in CPU_USE.findall(output)]
    return result


def last_kinetic_energy(output):
    lines = output[:output.rindex("Loop time")].splitlines()
    header = max(k for k, line in enumerate(lines) if line.split()[:1] == ["Step"])
    rows = [line.split() for line in lines[header + 1:]
            if line.split()[:1] and line.split()[0].isdigit()]
    return float(rows[-1][lines[header].split().index("KinEng")])


def build_packing(workdir, layers, dt):
    path = workdir / "packing.data"
    if path.exists():
        benchlib.progress(f"reusing the bed {path.relative_to(benchlib.ROOT)}")
        return path
    steps = int(round(SETTLE_TIME / dt))
    benchlib.progress(f"settling {layers * SIDE * SIDE} spheres for {SETTLE_TIME} s "
                      f"({steps} steps), once; cached in {workdir.relative_to(benchlib.ROOT)}")
    result = run(settle_deck(layers, dt, steps), workdir)
    benchlib.progress(f"settled in {result['wall']:.0f} s; kinetic energy at the end "
                      f"{last_kinetic_energy(result['output']):.3g} J "
                      f"(potential energy of the bed ~{layers * SIDE**2 * sphere_mass() * GRAVITY * layers * DIAMETER / 2:.3g} J)")
    return path


def run_variant(variant, workdir, dt, args):
    run_dir = workdir / variant
    run_dir.mkdir(parents=True, exist_ok=True)
    packing = run_dir / "packing.data"
    if not packing.exists():
        packing.symlink_to(workdir / "packing.data")
    result = run(timed_deck(variant, dt, args.warmup, args.steps), run_dir)
    seconds, steps, atoms = result["loops"][1]
    if steps != args.steps or len(result["pair_times"]) < 2:
        raise benchlib.LiggghtsFailed(f"{run_dir}: the timed run is not in the output")
    contacts = float(CONTACTS.findall(result["output"])[-1])
    return seconds, result["pair_times"][1], atoms, contacts, result["cpu"], result["cpu_use"][1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 450 spheres, 2 repetitions, 300 steps, short settling")
    parser.add_argument("--layers", type=int, default=14,
                        help=f"lattice layers of {SIDE}x{SIDE} spheres; default 14 (3150 spheres)")
    parser.add_argument("--repetitions", type=int, default=6)
    parser.add_argument("--steps", type=int, default=10000, help="timed steps per run")
    parser.add_argument("--warmup", type=int, default=200,
                        help="untimed steps before each timed run")
    parser.add_argument("--scratch", action="store_true",
                        help="write the table under bench/work/scratch/, not into doc/ and "
                             "results/ (to try another plugin build: SILOKIT_LAMMPS_PLUGIN)")
    args = parser.parse_args()
    global SETTLE_TIME, PAGE
    if args.quick or args.scratch:
        outputs = benchlib.WORK / ("quick" if args.quick else "scratch")
        benchlib.RESULTS = outputs / "results"
        PAGE = outputs / "pair_granular_jiang.md"
    if args.quick:
        args.layers, args.repetitions, args.steps, args.warmup = 2, 2, 300, 50
        SETTLE_TIME = 0.05
    for path in (LMP, PLUGIN):
        if not path.exists():
            sys.exit(f"{path} is missing: build LAMMPS and our plugin (tools/build.sh), "
                     "or point SILOKIT_LMP / SILOKIT_LAMMPS_PLUGIN at them")

    t_c = contact_time()
    dt = DT_FRACTION * t_c
    # the cached bed is named after its deck: other parameters, other file
    settle = settle_deck(args.layers, dt, int(round(SETTLE_TIME / dt)))
    key = hashlib.sha256(settle.encode()).hexdigest()[:10]
    workdir = benchlib.WORK / "lammps_pair_cost" / f"layers{args.layers}_{key}"
    start_load = benchlib.load_average()
    build_packing(workdir, args.layers, dt)

    loop_times = {name: [] for name in VARIANTS}
    pair_times = {name: [] for name in VARIANTS}
    cpu_times = {name: [] for name in VARIANTS}
    cpu_use = []
    contacts = {}
    atoms = None
    raw = ["# repetition variant loop_time_s pair_time_s steps atoms contacts process_cpu_s "
           "cpu_use_percent"]
    for rep in range(args.repetitions):
        order = VARIANTS[rep % len(VARIANTS):] + VARIANTS[:rep % len(VARIANTS)]
        for name in order:
            seconds, pair, atoms, count, cpu, share = run_variant(name, workdir, dt, args)
            cpu_use.append(share)
            contacts.setdefault(name, count)
            loop_times[name].append(seconds)
            pair_times[name].append(pair)
            cpu_times[name].append(cpu)
            raw.append(f"{rep} {name} {seconds:.6g} {pair:.6g} {args.steps} {atoms} {count:.0f} "
                       f"{cpu:.4g} {share:g}")
            benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {name:15s} "
                              f"{1e6 * seconds / args.steps:8.1f} us/step, pair "
                              f"{1e6 * pair / args.steps:8.1f} us/step ({count:.0f} contacts)")

    end_load = benchlib.load_average()
    table = report(loop_times, pair_times, cpu_times, contacts, args, atoms, dt, t_c,
                   start_load, end_load, cpu_use)
    benchlib.write_page_section(PAGE, SECTION, table, header="# pair_style granular/jiang\n")
    path = benchlib.write_raw("lammps_pair_cost", table + "\n\n## Raw runs\n\n" +
                              "\n".join(raw) + "\n")
    benchlib.progress(f"wrote {benchlib.shown_path(PAGE)} and {benchlib.shown_path(path)}")
    print(table)


def lammps_identity():
    """`lmp` is a small launcher: LAMMPS itself is the liblammps.so.0 it
    loads (our build: ../lib beside it)."""
    library = LMP.resolve().parent.parent / "lib" / "liblammps.so.0"
    if library.exists():
        return f"{benchlib.binary_identity(LMP)} with {benchlib.binary_identity(library)}"
    return benchlib.binary_identity(LMP)


def ratio_cell(ours, theirs):
    ratios = [a / b for a, b in zip(ours, theirs)]
    median, low, high = benchlib.spread(ratios)
    return f"{median:.3f} [{low:.3f}–{high:.3f}]"


def time_cell(seconds, steps):
    median, low, high = benchlib.spread([1e6 * t / steps for t in seconds])
    return f"{median:.0f} [{low:.0f}–{high:.0f}]"


def report(loop_times, pair_times, cpu_times, contacts, args, atoms, dt, t_c, start_load,
           end_load, cpu_use):
    steps = args.steps
    lines = [
        f"Measured with `bench/lammps_pair_cost.py`; load average (1/5/15 min, `uptime`) "
        f"{start_load} at the start, {end_load} at the end, on {os.cpu_count()} cores "
        f"(one of them held by another long run throughout); LAMMPS' own \"% CPU use\" "
        f"of the timed runs {benchlib.spread(cpu_use)[0]:.0f} % "
        f"[{min(cpu_use):.0f}–{max(cpu_use):.0f}].",
        "",
        f"A settled 3D bed of {atoms} spheres (d = 10 mm ± 5 %, uniform; "
        f"k_n = {KN:g} N/m, k_t = 2/7 k_n, μ = {MU}, normal damping {DAMPING_RATIO:g} "
        f"of critical, tangential damping half of it) on a flat `fix wall/gran` "
        f"(the same in every run), periodic in x and y, under gravity; "
        f"Δt = t_c/{1 / DT_FRACTION:.0f} = {dt:.3g} s. Each run reads the same bed, runs "
        f"{args.warmup} untimed steps, then {steps} timed steps, serially. "
        f"{args.repetitions} repetitions; in each, the four variants run one after the "
        f"other in a rotated order, and t_ours/t_lammps is taken within the repetition. "
        f"LAMMPS' `granular`: `hooke k_n γ_n damping mass_velocity tangential "
        f"linear_history k_t 0.5 μ` (the damping times m_eff, as `hooke/stiffness`), "
        f"with rolling `rolling sds {SDS_STIFFNESS:g} 0 {SDS_FRICTION:g}` "
        f"(k_R R_eff² = k_n l_c², R_eff μ_R = μ l_c at R_eff = d/4, l_c = 0.05 d, "
        f"no rolling damping on either side).",
        "",
        "| pair style | loop time per step (µs), median [min–max] "
        "| pair time per step (µs), median [min–max] | contacts "
        "| t_ours/t_lammps, loop | t_ours/t_lammps, pair | t_ours/t_lammps, process CPU |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in VARIANTS:
        peer = PEERS.get(name)
        loop_ratio = ratio_cell(loop_times[name], loop_times[peer]) if peer else ""
        pair_ratio = ratio_cell(pair_times[name], pair_times[peer]) if peer else ""
        cpu_ratio = ratio_cell(cpu_times[name], cpu_times[peer]) if peer else ""
        lines.append(f"| {LABELS[name]} | {time_cell(loop_times[name], steps)} | "
                     f"{time_cell(pair_times[name], steps)} | {contacts[name]:.0f} | "
                     f"{loop_ratio} | {pair_ratio} | {cpu_ratio} |")
    lines += [
        "",
        "Loop time: LAMMPS' `Loop time` of the timed run (the whole step: pair, "
        "neighbour lists, wall, integration). Pair time: the average of the "
        "\"Pair\" row of its MPI task timing breakdown (the pair force loop). "
        "Loop and pair time are wall-clock: on a loaded machine they include the time "
        "the run waited for a core. Process CPU: user + system time of the whole `lmp` "
        "process (start-up, reading the bed and the warm-up included, the same in every "
        "variant), which waiting does not inflate. "
        "Contacts: touching pairs after the timed run (`compute contact/atom`). "
        "The two laws are not the same law: LAMMPS' caps the tangential spring plus "
        "damping at μ F_n and keeps the spring's length when it turns the spring "
        "into the contact plane, ours caps the spring alone and does not rescale "
        "(doc/lammps_host.md, section 6), so the beds move apart in the last "
        "digits and the contact counts may differ slightly.",
        "",
        f"- machine: {benchlib.machine()['nproc']} cores, {benchlib.machine()['cpu']}, "
        f"{benchlib.machine()['system']}; date: {benchlib.machine()['date']}",
        f"- command (from the repository root): `{benchlib.command_line()}`",
        f"- silokit commit: {benchlib.git_commit()}; LAMMPS: {lammps_identity()}; "
        f"plugin: {benchlib.binary_identity(PLUGIN)}",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
