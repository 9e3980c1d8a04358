"""The report of bench/spherocylinder_cost.py: its sections of
doc/accuracy_cost_spherocylinder.md (instruction counts, or wall-clock
seconds with --wall) and its raw numbers, from the measured results."""

import benchlib
import callgrind
from spherocylinder_beds import BOX, DT_FRACTION, LENGTH, MU, RHO, ROD_VARIANTS, SPHERE_D

def fmt(value, digits=3):
    return "—" if value is None else f"{value:.{digits}g}"


def thousands(value):
    return "—" if value is None else f"{value:,.0f}"


def time_step_table(grains):
    lines = ["| grains | contact | t_c (ms) | Δt used / t_c |", "|---|---|---|---|"]
    for shape, configuration, tc in grains.times:
        lines.append(f"| {shape} | {configuration} | {1e3 * tc:.4f} | 1/{tc / grains.dt:.1f} |")
    return "\n".join(lines)


def stock_section(results, args):
    lines = [
        "### (a) Spheres, before and after the rods (`bench/stock_speed.py`'s deck)",
        "",
        f"The stock deck of `bench/stock_speed.py` (Hertz, tangential history, spheres of "
        f"radius 2.5 and 3 mm, a box of six walls) at volume fraction {args.volume_fraction}; "
        f"windows of {args.stock_steps} steps: **falling**, steps {args.stock_steps}–{2 * args.stock_steps} "
        f"after the insertion (the deck as it is, `run N` and `run 2N`), and **settled**, the "
        f"deck run to {args.stock_settle} steps and then `run N` / `run 2N` appended. "
        f"*before*: `{args.before}` (the commit before the rods, without "
        f"NONSPHERICAL_ACTIVE_FLAG); *after*: `{benchlib.shown_path(benchlib.OUR_BINARY)}`.",
        "",
        f"The third row is the sphere bed of (b) below (d* = {SPHERE_D * 1e3:g} mm, the silo "
        f"deck's hooke/stiffness with absolute damping, five planes), its window of {args.steps} "
        "steps run by both binaries from the same restart file.",
        "",
        "| window | spheres | before: instructions per sphere-step | after | after / before "
        "| list pairs per sphere | builds in the window | final KE before / after (J) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    windows = [(state, f"{state}_before", f"{state}_after", args.stock_steps) for state in ("falling", "settled")]
    windows.append(("settled bed of (b), hooke/stiffness", "sphere_before", "sphere", args.steps))
    windows = [w for w in windows if w[1] in results and w[2] in results]
    for state, before_key, after_key, _ in windows:
        before, after = results[before_key], results[after_key]
        atoms = after["atoms"]
        lines.append(
            f"| {state} | {atoms} | {thousands(before['per_step'] / atoms)} | "
            f"{thousands(after['per_step'] / atoms)} | **{after['per_step'] / before['per_step']:.4f}** | "
            f"{after['neighbours'] / atoms:.2f} | {after['builds']} | {before['ke']} / {after['ke']} |")
    for state, before_key, after_key, steps in windows:
        before, after = results[before_key], results[after_key]
        changes = callgrind.function_changes(before, after, steps, after["atoms"])
        lines += ["", f"Largest changes, {state} (the function's own instructions per sphere-step, "
                  "before → after):", ""]
        lines += [f"- `{name[:110]}`: {b:,.1f} → {a:,.1f} ({d:+,.1f})" for name, b, a, d in changes[:3]]
        if not changes:
            lines.append("- none of 0.1 or more")
    return "\n".join(lines)


def bed_section(results, failures, beds, grains, args):
    n = args.grains
    rod = results.get("rod")
    sphere = results.get("sphere")
    lines = [
        f"### (b) Rods against spheres, (c) against glued spheres: a settled bed of {n} grains",
        "",
        f"Box {BOX * 100:g} × {BOX * 100:g} cm, five planes; rods d = {grains.rod_d * 1e3:.3f} mm, "
        f"L = {LENGTH * 1e3:g} mm, ρ = {RHO:g} kg/m³, m = {grains.rod_mass:.4g} kg, k_n = "
        f"{grains.rod_law['kn']:.4g} N/m, γ_n = γ_t = {grains.rod_law['gamman']:.4g} N s/m (absolute), "
        f"k_t = 2/7 k_n, μ = {MU}; spheres d* = {SPHERE_D * 1e3:g} mm, m = {grains.sphere_mass:.4g} kg, "
        f"k_n = {grains.sphere_law['kn']:.4g} N/m, γ_n = {grains.sphere_law['gamman']:.4g} N s/m; "
        f"clumps: {grains.clump_spheres} spheres of diameter d on the core, the rod's mass and "
        f"inertia, the rods' law per sphere contact. Δt = {grains.dt:.4g} s for all (the rods' "
        f"shortest t_c / {DT_FRACTION}); windows of {args.steps} steps (builds every step: "
        f"{args.rebuild_steps}); skin 0.1 of the grain diameter. Per particle: per rod, per "
        f"sphere, per clump (a clump is {grains.clump_spheres} atoms).",
        "",
        "| grains | instructions per particle-step | ÷ spheres | ÷ rods | list pairs per particle "
        "| bounding spheres overlapping per particle | contacts per particle | per build, per particle "
        "| per simulated second ÷ spheres |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    labels = {"rod": "rods (ours)", "sphere": "spheres d*",
              "clump": f"clumps of {grains.clump_spheres} spheres (fix multisphere)"}
    min_tc = {shape: min(t for s, _, t in grains.times if s == shape) for shape in labels}
    labels.update({name: label for name, (label, _) in ROD_VARIANTS.items()})
    rows = ["rod", *ROD_VARIANTS, "sphere", "clump"]

    def kind(row):
        return "rod" if row in ROD_VARIANTS else row

    for row in rows:
        shape = kind(row)
        if row not in results:
            if row in failures or shape in failures:
                problem = failures.get(row, failures.get(shape))
                lines.append(f"| {labels[row]} | failed: {problem.splitlines()[0][:200]} |||||||")
            continue
        result, bed = results[row], beds[shape]
        per = result["per_step"] / n
        counts = bed.counts
        contacts = f"{counts['contacts']:.2f}"
        if shape == "clump":
            contacts += f" sphere contacts ({counts['clump_contacts']:.2f} clumps touched)"
        rebuild = results.get(f"{row}_rebuild")
        per_build = (rebuild["per_step"] - result["per_step"]) / n if rebuild else None
        # cost of a simulated second at dt = (own shortest t_c) / DT_FRACTION
        per_second = (result["per_step"] / (min_tc[shape] / DT_FRACTION))
        per_second_sphere = (sphere["per_step"] / (min_tc["sphere"] / DT_FRACTION)) if sphere else None
        lines.append(
            f"| {labels[row]} | {thousands(per)} | "
            f"{fmt(result['per_step'] / sphere['per_step']) if sphere else '—'} | "
            f"{fmt(result['per_step'] / rod['per_step']) if rod else '—'} | "
            f"{result['neighbours'] / n:.2f} | {fmt(counts['broad'])} | {contacts} | {thousands(per_build)} | "
            f"{fmt(per_second / per_second_sphere) if per_second_sphere else '—'} |")
    lines += ["", "Where the instructions of a step go (per particle-step; inclusive counts of the "
              "pair loop `PairGran::compute`, `Modify::initial_integrate` + `final_integrate`, "
              "`Modify::post_force` (walls, gravity), `Neighbor::decide` + `build`):", "",
              "| grains | pair loop | integration | walls, gravity | neighbour lists | other "
              "| pair loop per list pair | pair loop per contact |", "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        if row not in results:
            continue
        result, bed = results[row], beds[kind(row)]
        parts = {k: v / n for k, v in result["parts"].items()}
        contacts = bed.counts["contacts"] * n
        lines.append(f"| {labels[row]} | {thousands(parts['pair'])} | {thousands(parts['integration'])} | "
                     f"{thousands(parts['post_force'])} | {thousands(parts['neighbour'])} | "
                     f"{thousands(parts['other'])} | "
                     f"{thousands(result['parts']['pair'] / result['neighbours'])} | "
                     f"{thousands(result['parts']['pair'] / contacts) if contacts else '—'} |")
    for name, problem in failures.items():
        if name != "stock":
            lines += ["", f"`{name}` failed:", "", "```", problem, "```"]
    lines += ["", "Contact times of the contact laws (damped; the time step above is the same for "
              "all three beds):", "", time_step_table(grains)]
    return "\n".join(lines)


def section(results, failures, beds, grains, args, elapsed):
    parts = ["## Instructions per step (`bench/spherocylinder_cost.py`)", "",
             "Counted by callgrind (`valgrind --tool=callgrind`): the difference of the "
             "instruction totals of two runs of a deck, to N and to 2N steps, over N. "
             "Repeatable to a few 10⁻⁴ whatever else runs on the machine; instructions are "
             "not time (cache misses, divisions and square roots cost more than an add), so "
             "check ratios with `--wall` on a quiet machine before quoting seconds.", ""]
    if "stock" in failures:
        parts += ["(a) not measured:", "", "```", failures["stock"], "```", ""]
    else:
        parts += [stock_section(results, args), ""]
    parts += [bed_section(results, failures, beds, grains, args), "",
              f"- CPU time of the measurement: {elapsed['cpu'] / 60:.1f} min "
              f"(wall clock {elapsed['wall'] / 60:.1f} min)",
              f"- before binary: {benchlib.binary_identity(args.before) if args.before else 'none given'}",
              benchlib.provenance()]
    return "\n".join(parts)


def raw_text(results, failures, beds, grains, args):
    lines = ["# spherocylinder_cost raw results (instruction counts, callgrind)",
             f"# grains {args.grains}, clump spheres {grains.clump_spheres}, dt {grains.dt!r} s, "
             f"window {args.steps} steps, rebuild window {args.rebuild_steps}, stock window "
             f"{args.stock_steps} after {args.stock_settle}, volume fraction {args.volume_fraction}",
             "# name atoms instructions_N instructions_2N per_step per_atom_step pair integration "
             "post_force neighbour other list_pairs builds_in_window final_ke"]
    for name, r in results.items():
        p = r["parts"]
        lines.append(f"{name} {r['atoms']} {r['runs'][0]} {r['runs'][1]} {r['per_step']:.1f} "
                     f"{r['per_step'] / r['atoms']:.2f} {p['pair']:.1f} {p['integration']:.1f} "
                     f"{p['post_force']:.1f} {p['neighbour']:.1f} {p['other']:.1f} {r['neighbours']} "
                     f"{r['builds']} {r['ke']}")
    lines.append("# contacts per particle at the start of the window (geometry of the dumped grains)")
    for shape, bed in beds.items():
        if hasattr(bed, "counts"):
            lines.append(f"counts {shape} " + " ".join(f"{k} {v}" for k, v in bed.counts.items()))
    lines.append("# contact times (s)")
    lines += [f"t_c {shape} '{configuration}' {tc!r}" for shape, configuration, tc in grains.times]
    for key, problem in failures.items():
        lines.append(f"# FAILED {key}: {problem}")
    return "\n".join(lines) + "\n"


def wall_section(seconds, atoms, args):
    def spread(values):
        median, low, high = benchlib.spread(values)
        return f"{median:.4g} [{low:.4g}–{high:.4g}]"

    def ratios(a, b):
        return spread([x / y for x, y in zip(seconds[a], seconds[b])])

    lines = ["## Wall-clock time per step (`bench/spherocylinder_cost.py --wall`)", "",
             f"The decks of the instruction counts, timed by LIGGGHTS' Loop time of the last run "
             f"((t(2N) − t(N)) / N) with windows of N = {args.stock_steps} steps for (a) and "
             f"{args.steps} for the beds, {args.repetitions} repetitions, variants alternating "
             "(the order reversed every other repetition); median [min–max] over repetitions, "
             "ratios within each repetition.", "",
             "| deck | atoms | µs per step | µs per atom-step |", "|---|---|---|---|"]
    for name, values in seconds.items():
        median = benchlib.spread(values)[0]
        lines.append(f"| {name} | {atoms[name]} | {spread([1e6 * v for v in values])} | "
                     f"{1e6 * median / atoms[name]:.4g} |")
    lines.append("")
    for a, b in (("falling_after", "falling_before"), ("settled_after", "settled_before"),
                 ("sphere", "sphere_before"), ("rod", "sphere"), ("rod_before", "sphere"),
                 ("rod", "rod_before"), ("clump", "rod")):
        if a in seconds and b in seconds:
            lines.append(f"- {a} / {b}: **{ratios(a, b)}**")
    lines += ["", benchlib.provenance()]
    return "\n".join(lines)


PAGE_HEADER = """# Accuracy and cost: rods (spherocylinders)

Written in part by `bench/spherocylinder_cost.py`, which rewrites only its
own sections (between the `BEGIN`/`END` markers).
"""
