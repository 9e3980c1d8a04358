#!/usr/bin/python3
"""How fast are our builds against Debian's /usr/bin/liggghts? Runs decks
with several LIGGGHTS binaries, alternating them within each repetition,
and reports the ratios of their loop times taken within each repetition.

Binaries: `--binary NAME=PATH` (repeatable; default: ours =
build/bin/liggghts), plus Debian's /usr/bin/liggghts as "debian". The first
--binary is the reference ("plain": our -O2 build when comparing build
options, see README's build section).

Decks:
- stock: one deck in the style of LIGGGHTS' packing tutorial (Hertz,
  tangential history, no cohesion, no rolling resistance; a few thousand
  spheres inserted with insert/pack fall and settle in a box with six
  walls). Only stock styles: every binary runs it.
- with --scenes, small variants of our scene decks (inputs/):
  silo3d_mesh    the rotating-bottom silo with the stock peer of our bottom
                 (a meshed annulus turning by surface_ang_vel): stock only
  silo3d         the same silo with our fix wall/gran/rotating
  silo2d         the clogging silo (fix clog, fix reinject) to its 3rd arch
  pile2d_none    the open 2D pile (L = 50 d, bench/pile2d_cost.py's
                 configuration) discharging, no rolling resistance: stock only
  pile2d_fixed   the same with rolling_friction jiang (fixed l_c)
  Debian's binary lacks our styles: it runs the stock-only decks; the
  others compare our binaries with each other.

Each deck file is the same for every binary (its sha256 is recorded). The
same trajectory is checked by comparing every thermo line (and the deck's
record files) across binaries and repetitions.

Writes its section of doc/accuracy_cost_rolling.md and
bench/results/stock_speed.txt. The section `stock_speed` there is the
comparison of build variants behind the default flags; a measurement of
other binaries (a candidate build against the default one) goes to a
section of its own with `--section NAME` (and bench/results/NAME.txt), so
that it does not overwrite that comparison.

    /usr/bin/python3 bench/stock_speed.py            # stock deck, ~4 min
    /usr/bin/python3 bench/stock_speed.py --scenes \
        --binary plain=build-o2/bin/liggghts --binary pgo=build/bin/liggghts   # ~20 min
    /usr/bin/python3 bench/stock_speed.py --scenes --section stock_speed_candidate \
        --binary default=build/bin/liggghts --binary candidate=build-new/bin/liggghts
    /usr/bin/python3 bench/stock_speed.py --quick [--scenes]   # smoke run, < 2 min
"""

import argparse
import hashlib
import re
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.stl import annulus_triangles, write_stl  # noqa: E402

INPUTS = benchlib.INPUTS
DEBIAN = "debian"
# the section of doc/accuracy_cost_rolling.md with the build variants behind the default flags
SECTION = "stock_speed"


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


def silo3d_deck(variables):
    """inputs/silo3d_rotating in its quick variant (Dc = 12 d, 900 spheres,
    orifice 5 d) with index variables set ahead of it."""
    return benchlib.scene_deck("silo3d_rotating", {**variables, "quick": 1})


def silo2d_deck():
    """inputs/silo2d in its quick variant (12 d wide, 230 grains) until its
    third arch (the deck's quick default)."""
    return benchlib.scene_deck("silo2d", {"quick": 1})


class Deck:
    """A deck to time: its text, whether Debian's binary can run it (only
    stock styles), which of its loop times count ("last" run or "all"
    runs), the record files whose content must agree between binaries."""

    def __init__(self, name, title, text, stock, timed="last", records=()):
        self.name, self.title, self.text, self.stock = name, title, text, stock
        self.timed, self.records = timed, records
        self.digest = hashlib.sha256(text.encode()).hexdigest()

    def seconds_steps(self, result):
        loops = result["loops"] if self.timed == "all" else result["loops"][-1:]
        return sum(t for t, _, _ in loops), sum(s for _, s, _ in loops), loops[-1][2]


def pile_columns(quick, binary):
    """The L = 50 d pile of bench/pile2d_cost.py (fixed l_c, seed 15485863),
    built once with `binary` and cached under bench/work/."""
    import pile2d_cost  # scipy, analysis.pile2d.discharges: only when the scenes run
    from analysis.common.lammps_io import read_dump
    pile = benchlib.WORK / "stock_speed" / ("pile_L30" if quick else "pile_L50")
    dump = pile / "pile.restart.dump"
    if not dump.exists():
        benchlib.progress(f"building the pile for pile2d_none/pile2d_fixed with {binary}, once")
        pile.mkdir(parents=True, exist_ok=True)
        variables = {"L": 30 if quick else 50, "model": "fixed", "seed": pile2d_cost.SEED,
                     "inputs": INPUTS, "final_dump": 1, "pile": "pile.restart", "piles": "piles.txt"}
        text = "".join(f"variable {k} index {v}\n" for k, v in variables.items())
        text += f"include {INPUTS / 'pile2d' / 'in.build'}\n"
        benchlib.run_deck(text, pile, binary=binary)
    return pile2d_cost.configuration_deck, read_dump(dump)[-1][1]


def decks(args, reference):
    found = [Deck("stock", "stock deck: spheres settling in a box (Hertz)",
                  deck(args.volume_fraction, args.steps), stock=True)]
    if not args.scenes:
        return found
    stl = benchlib.WORK / "stock_speed" / "annulus.stl"
    stl.parent.mkdir(parents=True, exist_ok=True)
    # the quick silo's orifice D = 0.05 m and diameter Dc = 0.1188 m
    write_stl(stl, annulus_triangles(0.05 / 2, 0.1188 / 2))
    silo3d = {"f": 0.32, "discharge_time": 0.3}
    if args.quick:
        silo3d.update({"settle_time": 0.02, "discharge_time": 0.02})
    configuration, columns = pile_columns(args.quick, reference)
    pile_steps = 2000 if args.quick else 100000

    def pile(model):
        # the deck's default thermo prints the CPU time: print the state only
        return configuration(columns, model, 6.0, pile_steps).replace(
            "thermo_modify lost", "thermo_style custom step atoms ke\nthermo_modify lost")

    found += [
        Deck("silo3d_mesh", "rotating-bottom silo, stock meshed bottom (surface_ang_vel)",
             silo3d_deck({**silo3d, "mesh_bottom": 1, "bottom_mesh": stl}), stock=True,
             timed="all", records=("discharge.txt",)),
        Deck("silo3d", "rotating-bottom silo, our fix wall/gran/rotating",
             silo3d_deck(silo3d), stock=False, timed="all", records=("discharge.txt",)),
        Deck("silo2d", "clogging silo to its 3rd arch (fix clog, fix reinject)",
             silo2d_deck() if not args.quick else silo2d_deck().replace(
                 "variable quick", "variable narches index 1\nvariable quick"),
             stock=False, timed="all", records=("clogs.txt",)),
        Deck("pile2d_none", "open 2D pile discharging, no rolling resistance",
             pile("none"), stock=True),
        Deck("pile2d_fixed", "open 2D pile discharging, rolling_friction jiang (fixed l_c)",
             pile("fixed"), stock=False),
    ]
    return found


def printed_state(output, workdir, records):
    """What must agree between two runs of one deck: every thermo line
    (lines that start with a step number) and the record files."""
    thermo = [line for line in output.splitlines()
              if line.split()[:1] and line.split()[0].isdigit()]
    files = [(Path(workdir) / name).read_text() for name in records]
    return "\n".join(thermo), tuple(files)


def parse_binaries(specs):
    binaries = {}
    for spec in specs or [f"ours={benchlib.OUR_BINARY}"]:
        name, sep, path = spec.partition("=")
        if not sep or not name or name == DEBIAN:
            sys.exit(f"--binary {spec}: expected NAME=PATH (NAME not '{DEBIAN}')")
        binaries[name] = Path(path).resolve()
    binaries[DEBIAN] = benchlib.STOCK_BINARY
    return binaries



def existing_binaries(specs):
    """parse_binaries, stopping with a message when one of them is missing."""
    binaries = parse_binaries(specs)
    for name, binary in binaries.items():
        if not binary.exists():
            sys.exit(f"{binary} ({name}) is missing")
    return binaries

def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: about 900 spheres, 2 repetitions, 3000 steps; small scenes")
    parser.add_argument("--binary", action="append", metavar="NAME=PATH",
                        help="a LIGGGHTS binary to time (repeatable; the first is the reference); "
                             "default: ours=build/bin/liggghts")
    parser.add_argument("--scenes", action="store_true",
                        help="time the scene decks too (see above)")
    parser.add_argument("--volume-fraction", type=float, default=0.2,
                        help="insert/pack volume fraction of the box (0.2: about 3600 spheres)")
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--section", default=SECTION,
                        help="the section of doc/accuracy_cost_rolling.md to write "
                             f"(default {SECTION}: the build variants' comparison)")
    parser.add_argument("--steps", type=int, default=30000,
                        help="timed steps per run (dt = 1e-5 s; 30000: fall, impact and settling)")
    args = parser.parse_args()
    if not re.fullmatch(r"[a-z0-9_]+", args.section):
        parser.error(f"--section {args.section!r}: lower-case letters, digits and _ only")
    if args.quick:
        benchlib.use_smoke_outputs()
        args.volume_fraction, args.repetitions, args.steps = 0.05, 2, 3000

    binaries = existing_binaries(args.binary)
    names = list(binaries)
    reference = names[0]
    # the first binary is "ours" of the provenance lines (binary identity)
    benchlib.OUR_BINARY = binaries[reference]
    start_load = benchlib.load_average()
    work = benchlib.WORK / "stock_speed"
    all_decks = decks(args, binaries[reference])

    times = {(d.name, b): [] for d in all_decks for b in names}
    cpu = {(d.name, b): [] for d in all_decks for b in names}
    states = {d.name: {} for d in all_decks}
    atoms = {}
    raw = ["# stock_speed raw results", "# binaries: " + ", ".join(
               f"{n} {benchlib.binary_identity(binaries[n])}" for n in names)]
    raw += [f"# deck {d.name} sha256 {d.digest} (bench/work/stock_speed/{d.name}/<binary>/in.deck)"
            for d in all_decks]
    raw.append("# repetition deck binary loop_time_s steps atoms process_cpu_s process_wall_s")
    for rep in range(args.repetitions):
        # rotate the order of the binaries from one repetition to the next
        order = names[rep % len(names):] + names[:rep % len(names)]
        for d in all_decks:
            for name in order:
                if name == DEBIAN and not d.stock:
                    continue
                workdir = work / d.name / name
                for record in d.records:   # the decks append to their records
                    (workdir / record).unlink(missing_ok=True)
                result = benchlib.run_deck(d.text, workdir, binary=binaries[name])
                seconds, steps, atoms[d.name] = d.seconds_steps(result)
                times[(d.name, name)].append(seconds)
                cpu[(d.name, name)].append(result["cpu"])
                states[d.name].setdefault(printed_state(result["output"], workdir, d.records),
                                          []).append(f"{name}#{rep}")
                raw.append(f"{rep} {d.name} {name} {seconds:.6g} {steps} {atoms[d.name]} "
                           f"{result['cpu']:.4g} {result['wall']:.4g}")
                benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {d.name:12s} {name:8s} "
                                  f"loop time {seconds:8.4g} s, {steps} steps, {atoms[d.name]} atoms")

    table = report(all_decks, names, times, cpu, states, atoms, args, start_load, binaries)
    benchlib.write_section(args.section, table)
    path = benchlib.write_raw(args.section, "\n".join(raw) + "\n")
    benchlib.progress(f"wrote {benchlib.REPORT.relative_to(benchlib.ROOT)} and "
                      f"{path.relative_to(benchlib.ROOT)}")
    print(table)


def speedups(times, deck_name, name, against):
    """t_against / t_name per repetition: above 1, `name` is faster."""
    return [b / a for a, b in zip(times[(deck_name, name)], times[(deck_name, against)])]


def cell(values):
    if not values:
        return "—"
    median, low, high = benchlib.spread(values)
    return f"{median:.3f} [{low:.3f}–{high:.3f}]"


def report(all_decks, names, times, cpu, states, atoms, args, start_load, binaries):
    reference = names[0]
    ours = [n for n in names if n != DEBIAN]
    lines = [
        "## Speed of our builds against Debian's (`bench/stock_speed.py`)",
        "",
        "Binaries: " + "; ".join(f"**{n}** {benchlib.binary_identity(binaries[n])}" for n in names)
        + f". Reference: **{reference}**. Every deck runs with every binary that can run it, "
        f"alternating (the order rotates from one repetition to the next), {args.repetitions} "
        f"repetitions; ratios are taken within each repetition.",
        "",
        "Decks: **stock** the packing tutorial's box, materials and six walls (Hertz, "
        f"tangential history, no rolling resistance), {atoms.get('stock')} spheres of radius "
        f"2.5 and 3 mm inserted by insert/pack (volume fraction {args.volume_fraction}) falling "
        f"under gravity, {args.steps} timed steps of 1e-5 s after the insertion step."
    ]
    if args.scenes:
        lines[-1] += (
            " **silo3d_mesh / silo3d** `inputs/silo3d_rotating` `-var quick 1` (900 spheres, "
            "f = 0.32 Hz), settling and discharge, all runs timed; the bottom is the stock meshed "
            "annulus (`-var mesh_bottom 1`, stock styles only) or our `fix wall/gran/rotating`. "
            "**silo2d** `inputs/silo2d` `-var quick 1` to its third arch, all runs timed. "
            "**pile2d_none / pile2d_fixed** the L = 50 d pile of `bench/pile2d_cost.py` "
            "recreated from its dump and discharging through a 6 d orifice, the last run timed, "
            "without rolling resistance (stock styles only) or with `rolling_friction jiang`, "
            "fixed l_c. Debian's binary runs only the decks made of stock styles.")
    lines += ["", "Loop times (s), median [min–max]:", "",
              "| deck | atoms | " + " | ".join(names) + " |",
              "|---|---|" + "---|" * len(names)]
    for d in all_decks:
        row = [d.name, str(atoms.get(d.name, ""))]
        for n in names:
            values = times[(d.name, n)]
            row.append(f"{benchlib.spread(values)[0]:.4g} [{min(values):.4g}–{max(values):.4g}]"
                       if values else "cannot run" if n == DEBIAN else "—")
        lines.append("| " + " | ".join(row) + " |")
    def speed_table(samples):
        """Each build against Debian's binary and against the reference."""
        table = ["| deck | " + " | ".join(f"{n} / debian" for n in ours)
                 + " | " + " | ".join(f"{n} / {reference}" for n in ours if n != reference) + " |",
                 "|---|" + "---|" * (len(ours) + len(ours) - 1)]
        for d in all_decks:
            row = [d.name]
            row += [cell(speedups(samples, d.name, n, DEBIAN)) if d.stock else "—" for n in ours]
            row += [cell(speedups(samples, d.name, n, reference)) for n in ours if n != reference]
            table.append("| " + " | ".join(row) + " |")
        return table

    lines += ["", "Speed against Debian's binary (t_debian / t_build per repetition, median "
              "[min–max]; above 1 our build is faster), and against the reference "
              f"**{reference}** (t_{reference} / t_build):", ""] + speed_table(times)
    # CPU time of the process (start-up and set-up included): less
    # sensitive than the loop's wall time to sharing the core with others
    lines += ["", "The same from the CPU time of the LIGGGHTS process (user + system, "
              "start-up included), which counts only the time the process ran:", ""] + speed_table(cpu)
    stock_decks = [d.name for d in all_decks if d.stock]
    if args.scenes and len(ours) > 1:
        # the chain for the decks Debian cannot run
        base = [statistics.median(speedups(times, s, reference, DEBIAN)) for s in stock_decks]
        lines += ["", f"For the decks Debian's binary cannot run, speed against Debian = "
                  f"(t_{reference} / t_build on the deck) × (t_debian / t_{reference}), the "
                  f"second factor measured on the stock-only decks of this run: "
                  + ", ".join(f"{s} {b:.3f}" for s, b in zip(stock_decks, base))
                  + f" (their median {statistics.median(base):.3f}, used below):", "",
                  "| deck | " + " | ".join(f"{n} / debian (chained)" for n in ours) + " |",
                  "|---|" + "---|" * len(ours)]
        for d in all_decks:
            if d.stock:
                continue
            row = [d.name]
            for n in ours:
                own = statistics.median(speedups(times, d.name, n, reference))
                row.append(f"{own * statistics.median(base):.3f}")
            lines.append("| " + " | ".join(row) + " |")
    lines.append("")
    for d in all_decks:
        runs = states[d.name]
        if len(runs) == 1:
            lines.append(f"- {d.name}: every run of every binary prints the same thermo lines"
                         + (" and writes the same " + ", ".join(f"`{r}`" for r in d.records)
                            if d.records else "") + " (the same trajectory).")
        else:
            groups = "; ".join(", ".join(sorted(set(r.split("#")[0] for r in v)))
                               for v in runs.values())
            lines.append(f"- {d.name}: the runs differ in their printed state; groups of "
                         f"binaries with identical output: {groups}.")
    lines += ["", benchlib.provenance(extra_load=start_load)]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
