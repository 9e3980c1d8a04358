#!/usr/bin/python3
"""What do rods cost? Instructions per particle-step, counted by valgrind's
callgrind (repeatable on a busy machine, unlike wall-clock time), of:

(a) spheres before and after the rods: the stock deck of
    bench/stock_speed.py (its `deck()`, imported; Hertz, tangential
    history, spheres of 2.5 and 3 mm in a box) run by a binary built
    without the rods and the build flag NONSPHERICAL_ACTIVE_FLAG (--before
    PATH, read only: build commit 9ac283f^ in a tree of its own; without
    it, (a) is left out) and by ours, in two windows: the spheres falling
    just after their insertion, and the settled heap;
(b) rods against spheres: a settled bed of N rods (L = 20 mm, L/d = 3.3,
    rho = 620 kg/m^3, the linear spring-dashpot of
    inputs/silo3d_rotating/in.silo3d_rotating -var shape rod) in a box of
    five planes (fix wall/gran/spherocylinder, fix nve/spherocylinder),
    against N spheres of the volume-equivalent diameter d* = 9.9 mm (that
    deck's spheres and contact law) in the same box, stock fix wall/gran
    and fix nve/sphere;
(c) the stock alternative: the same N rods as rigid clumps of glued
    spheres (fix particletemplate/multisphere with the solid rod's mass and
    inertia given, fix insert/pack, fix multisphere, which is LIGGGHTS 3.8's
    integrator for clumps), the rods' contact law per sphere contact, the
    same box.

Each bed settles once, natively (cached in bench/work/spherocylinder_cost/
beds/ under a hash of its deck), and is written to a restart file. Every
measured deck is run under callgrind twice, to N and to 2N steps of its
last `run`; the difference of the two instruction totals over N is the cost
of one step in the window N..2N, set-up and start-up cancelled. For (b) and
(c) the same is done once more with a neighbour-list build at every step
(`neigh_modify every 1 check no`): the difference to the plain window is the
cost of one build (a settled bed builds none; a discharging silo builds one
every few tens of steps). The profiles are kept and split into the pair
loop, integration, post_force (walls, gravity), neighbour lists and the
rest. A native `run 0` from each restart dumps the grains; contacts are
counted from their geometry (rod cores closer than d, by the styles' own
core header; spheres closer than the sum of radii; clump spheres of
different clumps).

Also printed: the contact times t_c of the rods' contact law (head on, an
end on the floor, two rods crossing at their ends; doc/spherocylinder.md,
"Time step"), of the spheres and of the clumps.

The pieces: the grains, decks and contact counts in
spherocylinder_beds.py (the rods' geometry from the core header, through
core_geometry.py), callgrind in callgrind.py, the page's sections in
spherocylinder_report.py.

Writes bench/results/spherocylinder_cost.txt and its section of
doc/accuracy_cost_spherocylinder.md. With --wall, times the same decks in
wall-clock seconds instead (LIGGGHTS' Loop time of the last run, the same
two step counts, the binaries and variants alternating over repetitions,
ratios within a repetition, as bench/stock_speed.py does): for a quiet
machine; it writes spherocylinder_cost_wall.txt and its own section.

    /usr/bin/python3 bench/spherocylinder_cost.py            # ~9 min CPU (2 of them settling, cached)
    /usr/bin/python3 bench/spherocylinder_cost.py --quick    # smoke run, < 1 min CPU
    /usr/bin/python3 bench/spherocylinder_cost.py --wall     # wall-clock, quiet machine
"""

import argparse
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
import callgrind  # noqa: E402
import spherocylinder_beds  # noqa: E402
import spherocylinder_report as report  # noqa: E402
import stock_speed  # noqa: E402
from spherocylinder_beds import DT_FRACTION, G, ROD_VARIANTS, Bed, Grains  # noqa: E402

PAGE_NAME = "accuracy_cost_spherocylinder.md"
SECTION = "spherocylinder_cost"


def wall_seconds(deck, binary, steps, workdir):
    """Loop time of the last run: (t(2N) - t(N)) / N per step."""
    times = []
    for n in (steps, 2 * steps):
        result = benchlib.run_deck(deck(n), workdir / f"steps{n}", binary=binary)
        benchlib.check_complete(result["output"], n, workdir / f"steps{n}")
        times.append(result["loops"][-1][0])
    return (times[1] - times[0]) / steps, result["loops"][-1][2]


def stock_measurements(args):
    """(a): name -> (label, deck(steps), binary)."""
    settle = args.stock_settle

    def falling(steps):
        return stock_speed.deck(args.volume_fraction, steps)

    def settled(steps):
        return stock_speed.deck(args.volume_fraction, settle) + f"run {steps}\n"
    items = {}
    for state, deck in (("falling", falling), ("settled", settled)):
        for name, binary in (("before", args.before), ("after", benchlib.OUR_BINARY)):
            items[f"{state}_{name}"] = (f"(a) {state} spheres, {name}", deck, binary)
    return items


def bed_measurements(beds, rebuild_steps, before=None):
    """(b), (c): name -> (label, deck(steps), binary); the `_rebuild`
    variants build the neighbour list at every step; `sphere_before` is the
    sphere bed run by the binary from before the rods (part (a) with the
    silo deck's hooke/stiffness)."""
    items = {}
    for shape, bed in beds.items():
        items[shape] = (f"({'c' if shape == 'clump' else 'b'}) {shape} bed", bed.measure_deck, benchlib.OUR_BINARY)
        if shape == "sphere" and before:
            items["sphere_before"] = ("(a) sphere bed of (b), before", bed.measure_deck, before)
        if shape == "rod":
            for name, (label, integrator) in ROD_VARIANTS.items():
                items[name] = (f"(b) rod bed, {label}",
                               lambda n, bed=bed, integrator=integrator: bed.measure_deck(n, integrator=integrator),
                               benchlib.OUR_BINARY)
        if rebuild_steps:
            items[f"{shape}_rebuild"] = (f"({'c' if shape == 'clump' else 'b'}) {shape} bed, a build every step",
                                         lambda n, bed=bed: bed.measure_deck(n, rebuild_every_step=True),
                                         benchlib.OUR_BINARY)
    return items


def run_instruction_counts(args, grains, beds, work):
    results, failures = {}, {}
    if args.before:
        try:
            for name, (label, deck, binary) in stock_measurements(args).items():
                results[name] = callgrind.measure(label, deck, binary, args.stock_steps,
                                                  work / "stock" / name, exclusive=True)
        except benchlib.LiggghtsFailed as problem:
            failures["stock"] = str(problem)
            benchlib.progress(f"(a): FAILED: {str(problem).splitlines()[0]}")
    else:
        failures["stock"] = "no binary from before the rods given (--before PATH)"
        benchlib.progress(f"(a) skipped: {failures['stock']}")
    for shape, bed in beds.items():
        try:
            bed.settle()
            counts_dir = bed.dir / "count"
            benchlib.run_deck(bed.count_deck(), counts_dir)
            bed.counts = spherocylinder_beds.count_contacts(bed, counts_dir / "grains.dump")
        except (benchlib.LiggghtsFailed, RuntimeError) as problem:
            failures[shape] = str(problem)
            benchlib.progress(f"{shape}: FAILED: {str(problem).splitlines()[0]}")
            continue
        for name, (label, deck, binary) in bed_measurements({shape: bed}, args.rebuild_steps, args.before).items():
            steps = args.rebuild_steps if name.endswith("_rebuild") else args.steps
            try:
                results[name] = callgrind.measure(label, deck, binary, steps, work / "beds_measured" / name,
                                                  exclusive=name.startswith("sphere"))
            except benchlib.LiggghtsFailed as problem:
                failures[name] = str(problem)
                benchlib.progress(f"{name}: FAILED: {str(problem).splitlines()[0]}")
    return results, failures


def run_wall(args, grains, beds, work):
    """name -> list of seconds per step over repetitions."""
    items = {}
    if args.before:
        items.update(stock_measurements(args))
    for shape, bed in beds.items():
        bed.settle()
    items.update(bed_measurements(beds, 0, args.before))
    seconds = {name: [] for name in items}
    atoms = {}
    names = list(items)
    for rep in range(args.repetitions):
        order = names if rep % 2 == 0 else names[::-1]
        for name in order:
            label, deck, binary = items[name]
            steps = args.stock_steps if name.startswith(("falling", "settled")) else args.steps
            per_step, atoms[name] = wall_seconds(deck, binary, steps, work / "wall" / name)
            seconds[name].append(per_step)
            benchlib.progress(f"repetition {rep + 1}/{args.repetitions} {label}: "
                              f"{1e6 * per_step:.4g} µs per step")
    return seconds, atoms


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 32 grains, windows of 40 steps, no build-every-step window; "
                             "writes to bench/work/quick/")
    parser.add_argument("--wall", action="store_true", help="wall-clock seconds instead of instructions")
    parser.add_argument("--grains", type=int, default=480, help="rods, spheres and clumps per bed")
    parser.add_argument("--clump-spheres", type=int, default=10, help="spheres per clump in (c), 8-12")
    parser.add_argument("--steps", type=int, default=None,
                        help="window of (b), (c) in steps (default 1000; 10000 with --wall)")
    parser.add_argument("--rebuild-steps", type=int, default=250,
                        help="window with a neighbour-list build at every step (0: skip)")
    parser.add_argument("--settle-extra", type=float, default=0.3,
                        help="s of settling after the fall from the top of the gas")
    parser.add_argument("--volume-fraction", type=float, default=0.05,
                        help="(a): stock_speed.py's insertion volume fraction (0.05: 905 spheres)")
    parser.add_argument("--stock-settle", type=int, default=30000,
                        help="(a): steps before the settled window (stock_speed.py's full run)")
    parser.add_argument("--stock-steps", type=int, default=None,
                        help="(a): window in steps (default 1000; 10000 with --wall)")
    parser.add_argument("--repetitions", type=int, default=5, help="--wall: repetitions")
    before = os.environ.get("SILOKIT_LIGGGHTS_BEFORE")
    parser.add_argument("--before", type=Path, default=Path(before) if before else None,
                        help="(a): a binary built before the rods, at commit 9ac283f^ (read only; "
                             "env SILOKIT_LIGGGHTS_BEFORE); without it, (a) is left out")
    args = parser.parse_args()
    default_steps = 10000 if args.wall else 1000
    args.steps = args.steps or default_steps
    args.stock_steps = args.stock_steps or default_steps
    if args.quick:
        benchlib.use_smoke_outputs()
        # no window with a build at every step: it is the same code path
        args.grains, args.steps, args.rebuild_steps = 32, 40, 0
        args.volume_fraction, args.stock_settle, args.stock_steps = 0.01, 2000, 40
        args.settle_extra, args.repetitions = 0.05, 2
    if not 2 <= args.clump_spheres:
        sys.exit("--clump-spheres must be at least 2")
    if args.before and not args.before.is_file():
        sys.exit(f"--before {args.before}: no such binary")
    work = benchlib.WORK / ("quick" if args.quick else "") / "spherocylinder_cost"
    page = (benchlib.WORK / "quick" if args.quick else benchlib.ROOT / "doc") / PAGE_NAME
    start_wall, start_cpu = time.perf_counter(), os.times()
    ours_at_start = benchlib.binary_identity(benchlib.OUR_BINARY)

    grains = Grains(args.clump_spheres)
    shapes = ("rod", "sphere", "clump")
    probe = {s: Bed(s, grains, args.grains, 0.0, work) for s in shapes}
    fall_height = max(probe[s].column_top() for s in shapes)
    settle_time = math.sqrt(2 * fall_height / G) + args.settle_extra
    beds = {s: Bed(s, grains, args.grains, settle_time, work) for s in shapes}
    benchlib.progress(f"grains: {args.grains} per bed, dt {grains.dt:.4g} s (rods' shortest t_c "
                      f"{grains.rod_tc_min:.4g} s / {DT_FRACTION}), settling {settle_time:.2f} s")

    if args.wall:
        seconds, atoms = run_wall(args, grains, beds, work)
        text = report.wall_section(seconds, atoms, args)
        raw = "# name atoms seconds_per_step...\n" + "".join(
            f"{name} {atoms[name]} " + " ".join(f"{v:.6g}" for v in values) + "\n"
            for name, values in seconds.items())
    else:
        results, failures = run_instruction_counts(args, grains, beds, work)
        end_cpu = os.times()
        elapsed = {"wall": time.perf_counter() - start_wall,
                   "cpu": sum(getattr(end_cpu, k) - getattr(start_cpu, k)
                              for k in ("user", "system", "children_user", "children_system"))}
        text = report.section(results, failures, beds, grains, args, elapsed)
        raw = report.raw_text(results, failures, beds, grains, args)
    # the binary can be rebuilt while this runs: then the numbers mix two builds
    if benchlib.binary_identity(benchlib.OUR_BINARY) != ours_at_start:
        warning = (f"WARNING: {benchlib.shown_path(benchlib.OUR_BINARY)} changed during the measurement "
                   f"(at the start: {ours_at_start})")
        benchlib.progress(warning)
        text += f"\n- {warning}"
        raw += f"# {warning}\n"
    name = SECTION + ("_wall" if args.wall else "")
    benchlib.write_page_section(page, name, text, report.PAGE_HEADER)
    path = benchlib.write_raw(name, raw)
    benchlib.progress(f"wrote {page} and {path}")
    print(text)


if __name__ == "__main__":
    main()
