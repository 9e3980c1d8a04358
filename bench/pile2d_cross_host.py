#!/usr/bin/python3
"""The open 2D pile in LAMMPS against LIGGGHTS' ensemble (issue 46, part 3):
models none and fixed at L = 50 d, the seeds and widths of LIGGGHTS'
records in doc/data, built and discharged in LAMMPS through
analysis.pile2d.driver --host lammps (build/bin/lmp or $SILOKIT_LMP, the
plugin from $SILOKIT_LAMMPS_PLUGIN; doc/pile2d.md, "LAMMPS").

LIGGGHTS' lines: model none from doc/data/pile2d_standing/discharges.txt
(the piles with l_c = 0.1 d on the substrate contacts, today's default),
model fixed from doc/data/pile2d_discharges.txt (the first ensemble).
Seeds: the first --seeds of that ensemble's 20 (the driver's primes from
15485863 on); widths: every width the ensemble ran for that model and L.

On one rank the two hosts build the same pile from the same seed to the
bit (doc/pile2d.md, "The same piles"), so every LAMMPS record line is
compared with LIGGGHTS' line of the same (model, L, w, seed): the same text,
or the first differing column and the size of the difference. Then, per
host and model, over the same seeds, analysis.pile2d.discharges.summarize
(2000 bootstrap replicates over the piles, seed 1): w_t (largest
fluctuation of h) and w_50 (half the piles jam) with their bootstrap
standard deviations; beside them LIGGGHTS' whole 20-pile ensemble.

CPU: user + system time of the engine processes of each pile (its build
and all its discharges), from the driver's children's resource usage,
run at nice 15 one at a time. LIGGGHTS' CPU per pile: --liggghts-seeds
piles per model run by LIGGGHTS too (default 1; their lines are compared
with doc/data as well, a check that today's LIGGGHTS binary still makes the
recorded ensemble).

Resumable: the driver keeps finished piles and discharges in
bench/work/pile2d_cross_host/ (or work/quick/), so the same command, or one
with more --seeds, goes on from there. Writes bench/results/pile2d_cross_host.txt,
the LAMMPS records into doc/data/pile2d_cross_host/ and the section
`pile2d_cross_host` of doc/pile2d.md.

    /usr/bin/python3 bench/pile2d_cross_host.py --seeds 20   # 22-60 CPU-s per pile, ~30 CPU-min
    /usr/bin/python3 bench/pile2d_cross_host.py --quick      # 2 seeds, L = 20 d, 3 widths, ~1 CPU-min
    /usr/bin/python3 bench/pile2d_cross_host.py --report-only  # no engine: the records there
"""

import argparse
import math
import os
import re
import resource
import shutil
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.tables import read_rows  # noqa: E402
from analysis.common import hosts  # noqa: E402
from analysis.pile2d import driver  # noqa: E402
from analysis.pile2d.discharges import summarize  # noqa: E402

SECTION = "pile2d_cross_host"
PAGE = benchlib.ROOT / "doc" / "pile2d.md"
DATA = benchlib.ROOT / "doc" / "data"
RECORDS = DATA / "pile2d_cross_host"
# the driver writes the campaign's absolute paths (restart files, --campaign);
# the records keep them relative to the clone that ran them
ABSOLUTE_WORK_PATH = re.compile(r"/\S*?/(?=bench/work/)")
# LIGGGHTS' records of each model (doc/pile2d.md, results)
LIGGGHTS_RECORDS = {"none": DATA / "pile2d_standing" / "discharges.txt",
                    "fixed": DATA / "pile2d_discharges.txt"}
MODELS = ("none", "fixed")
NICE = 15
REPLICATES, BOOTSTRAP_SEED = 2000, 1
CPU_HEADER = "# host model L seed runs cpu_s wall_s"


# ---------------------------------------------------------------- LIGGGHTS' ensemble

def record_lines(path):
    """{(model, L, w, seed) key: the line's text, stripped} of a discharge record."""
    lines = {}
    for line in Path(path).read_text().splitlines():
        words = line.split()
        if not words or words[0].startswith("#") or len(words) < 4:
            continue
        key = (words[0],) + tuple(driver.width_key(x) for x in words[1:4])
        lines[key] = " ".join(words)
    return lines


def ensemble_plan(model, length, lines):
    """(seeds, widths) of LIGGGHTS' lines of one model and L, sorted."""
    keys = [k for k in lines if k[0] == model and k[1] == driver.width_key(length)]
    return sorted({int(k[3]) for k in keys}), sorted({k[2] for k in keys})


def compare_line(ours, theirs, columns):
    """'identical', 'missing in LIGGGHTS', or the first differing column:
    '<column>: <ours> vs <theirs> (difference x)'."""
    if theirs is None:
        return "missing in LIGGGHTS"
    a, b = ours.split(), theirs.split()
    if a == b:
        return "identical"
    for k, (x, y) in enumerate(zip(a, b)):
        if x != y:
            name = columns[k] if k < len(columns) else f"column {k + 1}"
            try:
                size = f"difference {float(x) - float(y):+.3g}"
            except ValueError:
                size = "text"
            return f"{name}: {x} vs {y} ({size})"
    return f"{len(a)} columns vs {len(b)}"


# ---------------------------------------------------------------- running

def run_pile(host, campaign, model, length, seed, widths, cpu_file):
    """One pile and its discharges through the driver, serially at nice 15;
    appends the engines' CPU to cpu_file when something ran."""
    argv = ["--host", host, "--nice", str(NICE), "--campaign", str(campaign), "--models", model,
            "--L", f"{length:g}", "--seed-list", str(seed), "--widths"] + [f"{w:g}" for w in widths]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.time()
    runner = driver.Runner(driver.parse(argv), argv)
    failures = runner.run()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if runner.done:
        driver.ensure_header(cpu_file, CPU_HEADER)
        with open(cpu_file, "a") as handle:
            handle.write(f"{host} {model} {length:g} {seed} {runner.done} {cpu:.2f} "
                         f"{time.time() - started:.1f}\n")
    if failures:
        raise SystemExit(f"{host} {model} L={length:g} seed {seed}: {failures}")
    return runner.done


def cpu_per_pile(cpu_file, host, model, runs_per_pile, seeds=None):
    """CPU seconds of the piles run whole in one go (build + every width),
    of these seeds only if given."""
    rows = read_rows(cpu_file, text=True, missing_ok=True)
    return [float(r["cpu_s"]) for r in rows
            if r["host"] == host and r["model"] == model and int(r["runs"]) == runs_per_pile
            and (seeds is None or int(r["seed"]) in seeds)]


# ---------------------------------------------------------------- statistics

def host_summary(rows, model, length):
    """w_t, its bootstrap std, w_50, its bootstrap std, piles."""
    chosen = [r for r in rows if r["model"] == model and r["L"] == length]
    if len({r["seed"] for r in chosen}) < 2:
        return None
    entry = summarize(chosen, replicates=REPLICATES, seed=BOOTSTRAP_SEED)[model]
    data, critical = entry["lengths"][length], entry["critical"]
    k = critical["L"].index(length)
    return {"w_t": critical["w_t"][k], "w_t_sigma": critical["w_t_sigma"][k],
            "w_50": data["w_50"], "w_50_sigma": data["w_50_sigma"], "piles": len(data["seeds"])}


def rows_of(lines, keys):
    """Numeric rows (as read_rows gives) of the lines of these keys."""
    columns = driver.DISCHARGES_HEADER.lstrip("# ").split()
    rows = []
    for key in keys:
        words = lines[key].split()
        row = {c: (words[0] if c == "model" else float(words[i])) for i, c in enumerate(columns)}
        rows.append(row)
    return rows


def fmt(entry, name):
    if entry is None or entry[name] is None or math.isnan(entry[name]):
        return "n/a"
    return f"{entry[name]:.2f} ± {entry[name + '_sigma']:.2f}"


# ---------------------------------------------------------------- report

def report(length, plans, liggghts_lines, lammps_lines, check_lines, cpu_file):
    columns = driver.DISCHARGES_HEADER.lstrip("# ").split()
    raw = [f"# {SECTION}: LAMMPS record lines against LIGGGHTS' (doc/data), L = {length:g} d",
           f"# {benchlib.command_line()}", "# status host line"]
    table = ["| model | seeds | lines | identical | first difference | w_t LAMMPS | w_t LIGGGHTS (same seeds) "
             "| w_t LIGGGHTS (all) | w_50 LAMMPS | w_50 LIGGGHTS (same seeds) | w_50 LIGGGHTS (all) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    cost = ["| model | runs per pile | LAMMPS CPU per pile (s) | LIGGGHTS CPU per pile (s) "
            "| the same piles: LAMMPS / LIGGGHTS (s) |",
            "|---|---|---|---|---|"]
    summary_lines, counts = [], [0, 0]
    for model in MODELS:
        seeds, widths = plans[model]
        keys = [(model, driver.width_key(length), w, driver.width_key(s)) for s in seeds for w in widths]
        ours = [k for k in keys if k in lammps_lines]
        statuses = [(compare_line(lammps_lines[k], liggghts_lines.get(k), columns), k) for k in ours]
        for status, k in statuses:
            raw.append(f"{'identical' if status == 'identical' else 'differs'} lammps {lammps_lines[k]}")
            if status != "identical":
                raw.append(f"#   {status}; LIGGGHTS: {liggghts_lines.get(k)}")
        identical = sum(s == "identical" for s, _ in statuses)
        counts[0] += identical
        counts[1] += len(statuses)
        first = next((f"seed {int(k[3])} w {k[2]:g}: {s}" for s, k in statuses if s != "identical"), "none")
        done_seeds = sorted({int(k[3]) for k in ours})
        same = [k for k in keys if k in liggghts_lines and int(k[3]) in done_seeds]
        all_seeds, _ = ensemble_plan(model, length, liggghts_lines)
        every = [k for k in liggghts_lines if k[0] == model and k[1] == driver.width_key(length)
                 and k[2] in widths]
        s_lammps = host_summary(rows_of(lammps_lines, ours), model, length)
        s_same = host_summary(rows_of(liggghts_lines, same), model, length)
        s_all = host_summary(rows_of(liggghts_lines, every), model, length)
        table.append(f"| {model} | {len(done_seeds)} | {len(ours)} | {identical} | {first} "
                     f"| {fmt(s_lammps, 'w_t')} | {fmt(s_same, 'w_t')} | {fmt(s_all, 'w_t')} "
                     f"| {fmt(s_lammps, 'w_50')} | {fmt(s_same, 'w_50')} | {fmt(s_all, 'w_50')} |")
        summary_lines.append(f"# {model}: {len(done_seeds)} seeds, {len(ours)} LAMMPS lines, "
                             f"{identical} identical; w_t/w_50 LAMMPS {fmt(s_lammps, 'w_t')} / "
                             f"{fmt(s_lammps, 'w_50')}, LIGGGHTS same seeds {fmt(s_same, 'w_t')} / "
                             f"{fmt(s_same, 'w_50')}, LIGGGHTS all {len(all_seeds)} {fmt(s_all, 'w_t')} / "
                             f"{fmt(s_all, 'w_50')}")
        runs = 1 + len(widths)
        cells = []
        for host in ("lammps", "liggghts"):
            values = cpu_per_pile(cpu_file, host, model, runs)
            cells.append(f"{np.median(values):.1f} [{min(values):.1f}–{max(values):.1f}], "
                         f"{len(values)} pile{'s' if len(values) > 1 else ''}" if values else "not measured")
            summary_lines.append(f"# {model} {host}: CPU per pile (s) {values}")
        # LIGGGHTS ran few piles: the same piles in LAMMPS, paired (the
        # spread between piles is larger than the difference of the hosts)
        ligg_rows = [r for r in read_rows(cpu_file, text=True, missing_ok=True)
                     if r["host"] == "liggghts" and r["model"] == model and int(r["runs"]) == runs]
        pairs = []
        for r in ligg_rows:
            lammps_cpu = cpu_per_pile(cpu_file, "lammps", model, runs, {int(r["seed"])})
            if lammps_cpu:
                pairs.append(f"seed {r['seed']}: {lammps_cpu[0]:.1f} / {float(r['cpu_s']):.1f}")
        cost.append(f"| {model} | {runs} | {cells[0]} | {cells[1]} | {'; '.join(pairs) or 'n/a'} |")
        for k in sorted(check_lines):
            if k[0] == model:
                status = compare_line(check_lines[k], liggghts_lines.get(k), columns)
                raw.append(f"{'identical' if status == 'identical' else 'differs'} liggghts-today "
                           f"{check_lines[k]}")
                if status != "identical":
                    raw.append(f"#   {status}")
    if counts[1] and counts[0] == counts[1]:
        verdict = (f"All {counts[1]} LAMMPS lines are LIGGGHTS' lines to every printed digit (the same piles, "
                   f"the same h after every discharge), so the two hosts give the same w_t and w_50 over the "
                   f"same piles, not merely within the intervals. LIGGGHTS' ensemble on these piles, and with "
                   f"it the fixed model's gap to the paper's w_c ([above](#w_c-of-the-fixed-l_c-model)), are not an "
                   f"artefact of LIGGGHTS' host code (integrator, neighbour lists, contact bookkeeping, 2D "
                   f"handling, the frozen substrate). They still share the contact law, which both hosts take "
                   f"from `src_plugin/core/` and which is checked on its own against hand calculations.")
    else:
        verdict = (f"{counts[1] - counts[0]} of {counts[1]} LAMMPS lines differ from LIGGGHTS' (first "
                   f"difference per model in the table; every line in `bench/results/{SECTION}.txt`).")
    checked = [compare_line(v, liggghts_lines.get(k), columns) for k, v in check_lines.items()]
    text = f"""### LAMMPS against LIGGGHTS' ensemble (bench/pile2d_cross_host.py)

Models none and fixed at L = {length:g} d in LAMMPS (`analysis.pile2d.driver --host lammps`,
one rank), the seeds and widths of LIGGGHTS' records (none:
`pile2d_standing/discharges.txt`, fixed: `pile2d_discharges.txt`); the LAMMPS
records are in [`data/pile2d_cross_host/`](data/pile2d_cross_host/). Every
LAMMPS line against LIGGGHTS' line of the same (model, L, w, seed), then
w_t (largest fluctuation of h) and w_50 (half the piles jam) per host over
the same piles, ± the bootstrap standard deviation over piles ({REPLICATES}
replicates; w_t's floored at a quarter of the width step, as in the
results table), and LIGGGHTS' whole ensemble beside them (d):

{chr(10).join(table)}

{verdict}

Cost, user + system CPU of the engine processes per pile (its build and
every discharge), one at a time at nice {NICE} on a loaded machine (median
[min–max]):

{chr(10).join(cost)}

Today's LIGGGHTS binary on the piles it ran for the cost: {sum(c == 'identical' for c in checked)}
of {len(checked)} lines identical to the recorded ensemble's.

{benchlib.provenance()}
- LAMMPS: {benchlib.binary_identity(hosts.LAMMPS_BINARY)}; plugin
  `{os.environ.get('SILOKIT_LAMMPS_PLUGIN', 'silokit_lammps.so (next to lmp)')}`
"""
    raw += summary_lines
    return text, "\n".join(raw) + "\n"


def repository_paths(text):
    """The driver's records with their paths made relative to the clone's
    root (`/any/clone/bench/work/...` -> `bench/work/...`)."""
    return ABSOLUTE_WORK_PATH.sub("", text)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="2 seeds, L = 20 d, 3 widths, under bench/work/quick/")
    parser.add_argument("--seeds", type=int, default=20, help="piles per model (the ensemble's first N)")
    parser.add_argument("--liggghts-seeds", dest="liggghts_seeds", type=int, default=1,
                        help="piles per model also run in LIGGGHTS, for its CPU per pile (default 1)")
    parser.add_argument("--report-only", dest="report_only", action="store_true",
                        help="no engine: report the records already in the work directory")
    args = parser.parse_args()
    length = 20.0 if args.quick else 50.0
    if args.quick:
        benchlib.use_smoke_outputs()
        args.seeds = 2
        work = benchlib.WORK / "quick" / SECTION
        page, records = benchlib.WORK / "quick" / "pile2d.md", benchlib.WORK / "quick" / "data" / SECTION
    else:
        work = benchlib.WORK / SECTION
        page, records = PAGE, RECORDS
    work.mkdir(parents=True, exist_ok=True)
    cpu_file = work / "cpu.txt"
    liggghts_lines, plans = {}, {}
    for model in MODELS:
        lines = {k: v for k, v in record_lines(LIGGGHTS_RECORDS[model]).items() if k[0] == model}
        liggghts_lines.update(lines)
        seeds, widths = ensemble_plan(model, length, lines)
        if args.quick:
            widths = [widths[0], widths[len(widths) // 2], widths[-1]]
        plans[model] = (seeds[:args.seeds], widths)
    if not args.report_only:
        for model in MODELS:
            seeds, widths = plans[model]
            for seed in seeds[:args.liggghts_seeds]:
                benchlib.progress(f"LIGGGHTS {model} L={length:g} seed {seed}: {len(widths)} widths")
                run_pile("liggghts", work / "liggghts", model, length, seed, widths, cpu_file)
        # seed by seed, the models alternating: an interrupted run has both
        for k in range(args.seeds):
            for model in MODELS:
                seeds, widths = plans[model]
                if k < len(seeds):
                    benchlib.progress(f"LAMMPS {model} L={length:g} seed {seeds[k]}: {len(widths)} widths")
                    run_pile("lammps", work / "lammps", model, length, seeds[k], widths, cpu_file)
    lammps_dir = work / "lammps"
    lammps_lines = record_lines(lammps_dir / "discharges.txt") if (lammps_dir / "discharges.txt").exists() else {}
    check_file = work / "liggghts" / "discharges.txt"
    check_lines = record_lines(check_file) if check_file.exists() else {}
    text, raw = report(length, plans, liggghts_lines, lammps_lines, check_lines, cpu_file)
    raw_path = benchlib.write_raw(SECTION, raw)
    records.mkdir(parents=True, exist_ok=True)
    for name in ("piles.txt", "discharges.txt", "driver_commands.txt"):
        if (lammps_dir / name).exists():
            (records / name).write_text(repository_paths((lammps_dir / name).read_text()))
    if cpu_file.exists():
        shutil.copyfile(cpu_file, records / "cpu.txt")
    benchlib.write_page_section(page, SECTION, text, "# pile2d cross-host (smoke run)\n")
    print(text)
    print(f"wrote {benchlib.shown_path(raw_path)}, {benchlib.shown_path(page)}, {benchlib.shown_path(records)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
