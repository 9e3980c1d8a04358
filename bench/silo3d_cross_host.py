#!/usr/bin/python3
"""The rotating-bottom silo in both hosts: the quick silo (Dc = 12 d, 900
spheres, D = 5 d, dt = t_c/40, 0.4 s of settling) discharged at one
frequency (default f = 0, no reinjection) by the LIGGGHTS deck
(inputs/silo3d_rotating/in.silo3d_rotating, build/bin/liggghts) and by the
LAMMPS deck (in.silo3d_rotating.lammps, build/bin/lmp with our plugin),
--seeds gas seeds each. Each run settles its own gas, so every run is
another packing: the hosts are compared against the spread between seeds.

Per run: the stationary flow rate Q of analysis.silo3d_rotating (the
window from --transient s after the opening to the end, block standard
errors). Per host: the mean over seeds with its 95 % Student-t interval and
the standard deviation between seeds; the difference LAMMPS - LIGGGHTS with
its Welch 95 % interval.

Each run's own packing makes the comparison weak (the spread between
packings is several per cent), so each LAMMPS packing is also written as
a data file at the opening and discharged from there by both hosts, with
the same walls, law and time step in two small decks written here
(without contact histories, in both): the difference of Q, paired by
packing, tests the hosts' dynamics alone.

The LAMMPS side wall is LAMMPS' own fix wall/gran hooke/history, whose
Coulomb cap acts on the spring plus the tangential dashpot (ours: the
spring alone); the two differ only through that dashpot while a grain
slides on the wall. Each LAMMPS packing (written at the opening) is
discharged a second time without the side wall's tangential dashpot
(-var side_tangential_damping 0): the change of Q, paired by packing,
bounds what the dashpot's convention can do to Q.

A run that clogs has no stationary Q: no grain out at the end of its
window, the deck's clog at rest, or no grain out for more than half of
the window (IDLE_LIMIT: an arch that holds, breaks, holds again; flowing
runs of the quick silo are idle 0-2 % of it). It is left out of its
host's mean and of every pair it belongs to, and the report lists it.

Writes bench/results/silo3d_cross_host.txt (every run) and the section
`silo3d_cross_host` of doc/silo3d_rotating.md.

    /usr/bin/python3 bench/silo3d_cross_host.py            # 6 seeds, ~7 min serial
    /usr/bin/python3 bench/silo3d_cross_host.py --quick    # 2 seeds, 0.3 s of discharge, ~1.5 min
    /usr/bin/python3 bench/silo3d_cross_host.py --reanalyse  # the last runs analysed again, no engine
"""

import argparse
import math
import os
import re
import sys
from pathlib import Path

import numpy as np
from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.stats import mean_t_ci  # noqa: E402
from analysis.silo3d_rotating.flow import analyse_flow, stationary_flow_rate  # noqa: E402
from analysis.silo3d_rotating.records import load_run, read_discharge  # noqa: E402

LMP = Path(os.environ.get("SILOKIT_LMP", benchlib.ROOT / "build" / "bin" / "lmp"))
PLUGIN = Path(os.environ.get("SILOKIT_LAMMPS_PLUGIN",
                             benchlib.ROOT / "build" / "lib" / "silokit_lammps.so"))
DECKS = {"liggghts": benchlib.INPUTS / "silo3d_rotating" / "in.silo3d_rotating",
         "lammps": benchlib.INPUTS / "silo3d_rotating" / "in.silo3d_rotating.lammps"}
PAGE = benchlib.ROOT / "doc" / "silo3d_rotating.md"
SECTION = "silo3d_cross_host"
# primes > 10000 (LIGGGHTS' insert/pack wants them), not the grain
# template's 86028121 and 86028157
SEEDS = (32452843, 15485863, 49979687, 67867967, 104395301, 122949829)
CONFIDENCE = 0.95
IDLE_LIMIT = 0.5   # more of the window than this without a grain out: clogged


def deck(host, variables):
    """The host's deck with `variables` set ahead of it (as -var would)."""
    variables = {**variables, "inputs": benchlib.INPUTS}
    if host == "lammps":
        variables["plugin"] = PLUGIN
    lines = [f"variable {name} index {value}" for name, value in variables.items()]
    return "\n".join(lines + [f"include {DECKS[host]}"]) + "\n"


def stopped(flow):
    """Whether a run's flow stopped: clogged at its end, or idle for more
    than IDLE_LIMIT of the window."""
    return bool(flow.clogged_at_end or flow.idle_share > IDLE_LIMIT)


def scene_row(run_dir, name, host, seed, transient, cpu):
    """The row of a run of a host's scene deck, from its records."""
    run = load_run(run_dir)
    flow = analyse_flow(run, transient=transient)
    return announce({"name": name, "host": host, "seed": seed, "Q": flow.q_mass, "Q_se": flow.q_mass_se,
                     "n_out": float(run.discharge["n_out"][-1]), "cpu": cpu, "clogged": stopped(flow)})


def same_packing_row(run_dir, host, seed, transient, cpu):
    """The row of a same-packing discharge, from its discharge.txt."""
    record = read_discharge(run_dir)
    flow = stationary_flow_rate(record["t"], record["n_out"], record["mass_out"],
                                record["t"][0] + transient, record["t"][-1])
    return announce({"name": f"same_packing_{host}_s{seed}", "host": host, "seed": seed, "Q": flow.q_mass,
                     "Q_se": flow.q_mass_se, "n_out": float(record["n_out"][-1]), "cpu": cpu,
                     "clogged": stopped(flow)})


def announce(row):
    benchlib.progress(f"{row['name']}: Q = {row['Q']:.4f} +- {row['Q_se']:.4f} kg/s, "
                      f"{row['n_out']:.0f} out, {row['cpu']:.0f} s CPU"
                      + (", clogged: left out of the means" if row["clogged"] else ""))
    return row


def run_one(work, name, host, variables, transient):
    """One run of a host's scene deck: its row, and its screen output."""
    run_dir = work / name
    result = benchlib.run_deck(deck(host, variables), run_dir,
                               binary=LMP if host == "lammps" else benchlib.OUR_BINARY)
    return scene_row(run_dir, name, host, variables["seed"], transient, result["cpu"]), result["output"]


# Both hosts discharge one packing (a LAMMPS data file written at the
# opening): the scene's walls and law, no gas, no settling, the bottom open
# from the start; `discharge.txt` as the decks write it. The numbers come
# from the LAMMPS run that wrote the packing (its run.txt and the line it
# prints with kn and gamman).
SAME_PACKING_HEAD = {
    "lammps": """plugin load {plugin}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
read_data packing.data
pair_style granular/jiang
pair_coeff * * normal hooke/stiffness {kn!r} {kt!r} {gamman!r} {gamman!r} friction {mu!r} absolute_damping yes
fix side all wall/gran hooke/history {kn!r} {kt!r} {gamman_per_mass!r} {gamman_per_mass!r} {mu!r} 1 zcylinder {Rc!r}
fix bottom all wall/gran/rotating normal hooke/stiffness {kn!r} {kt!r} {gamman!r} {gamman!r} friction {mu!r} absolute_damping yes zplane 0.0 orifice {D!r} frequency {f!r}
""",
    "liggghts": """units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
communicate single vel yes
read_data packing.data
fix m_kn all property/global kn peratomtypepair 1 {kn!r}
fix m_kt all property/global kt peratomtypepair 1 {kt!r}
fix m_gn all property/global gamman_abs peratomtypepair 1 {gamman!r}
fix m_gt all property/global gammat_abs peratomtypepair 1 {gamman!r}
fix m_mu all property/global coefficientFriction peratomtypepair 1 {mu!r}
pair_style gran model hooke/stiffness tangential history absolute_damping on
pair_coeff * *
fix side all wall/gran model hooke/stiffness tangential history primitive type 1 zcylinder {Rc!r} 0.0 0.0 absolute_damping on
fix bottom all wall/gran/rotating model hooke/stiffness tangential history primitive type 1 zplane 0.0 absolute_damping on orifice {D!r} frequency {f!r}
"""}
SAME_PACKING_TAIL = """timestep {dt!r}
neighbor {skin!r} bin
neigh_modify delay 0
fix gravity all gravity {g!r} vector 0 0 -1
fix integrate all nve/sphere
variable n_out equal {n0}-count(all)
variable mass_out equal {n0}*{mass!r}-mass(all)
variable t equal time
variable step equal step
fix discharge all print {record_steps} "${{step}} ${{t}} ${{n_out}} ${{mass_out}}" file discharge.txt screen no title "# step t n_out mass_out"
thermo_modify lost ignore norm no
thermo {record_steps}
run {steps}
"""
SCENE_LINE = re.compile(r"^silo3d_rotating: LAMMPS, .* kn (\S+) N/m, gamman (\S+) N s/m", re.MULTILINE)


def same_packing_decks(lammps_run_dir, lammps_output, discharge):
    """The two decks that discharge the packing of a LAMMPS run, keyed by host."""
    info = load_run(lammps_run_dir).info
    kn, gamman = (float(x) for x in SCENE_LINE.search(lammps_output).groups())
    numbers = {"plugin": PLUGIN, "kn": kn, "kt": 2.0 / 7.0 * kn, "gamman": gamman,
               "gamman_per_mass": gamman / info["mass"], "mu": info["mu"], "Rc": info["Dc"] / 2,
               "D": info["D"], "f": info["f"], "dt": info["dt"], "skin": 0.1 * info["d"], "g": info["g"],
               "n0": int(info["N"]), "mass": info["mass"], "record_steps": round(0.01 / info["dt"]),
               "steps": round(discharge / info["dt"])}
    return {host: (head + SAME_PACKING_TAIL).format(**numbers) for host, head in SAME_PACKING_HEAD.items()}


def run_same_packing(work, seed, lammps_output, args):
    """The packing of lammps_s<seed> discharged by both hosts: two rows."""
    source = work / f"lammps_s{seed}"
    convert = work / f"same_packing_s{seed}"
    benchlib.run_deck(f"plugin load {PLUGIN}\nread_restart {source / 'packing.restart'}\n"
                      f"write_data {convert / 'packing.data'}\n", convert, binary=LMP)
    rows = []
    for host, text in same_packing_decks(source, lammps_output, args.discharge).items():
        run_dir = convert / host
        run_dir.mkdir(parents=True, exist_ok=True)
        (run_dir / "packing.data").write_bytes((convert / "packing.data").read_bytes())
        result = benchlib.run_deck(text, run_dir, binary=LMP if host == "lammps" else benchlib.OUR_BINARY)
        rows.append(same_packing_row(run_dir, host, seed, args.transient, result["cpu"]))
    return rows


def measure(work, args):
    common = {"quick": 1, "f": args.f, "discharge_time": args.discharge}
    rows = []
    for seed in args.seeds:
        rows.append(run_one(work, f"liggghts_s{seed}", "liggghts", {**common, "seed": seed},
                            args.transient)[0])
        row, output = run_one(work, f"lammps_s{seed}", "lammps",
                              {**common, "seed": seed, "write_packing": 1}, args.transient)
        rows.append(row)
        packing = work / f"lammps_s{seed}" / "packing.restart"
        rows.append(run_one(work, f"lammps_no_side_dashpot_s{seed}", "lammps",
                            {**common, "seed": seed, "read_packing": 1, "packing": packing,
                             "side_tangential_damping": 0}, args.transient)[0])
        rows += run_same_packing(work, seed, output, args)
    return rows


def reanalyse(work, args):
    """The rows of the runs measure() left in work, analysed again (the
    CPU seconds from the raw file of that measurement): for a change in
    the analysis, without running the engines again."""
    raw_path = benchlib.RESULTS / f"{SECTION}.txt"
    if not raw_path.exists():
        sys.exit(f"--reanalyse: {raw_path} is missing: run the bench first")
    cpu = {}
    for line in raw_path.read_text().splitlines():
        words = line.split()
        if line.startswith("#") or not words or words[0] == "name":
            continue
        cpu[words[0]] = float(words[6])
    rows = []
    for seed in args.seeds:
        for name, host in ((f"liggghts_s{seed}", "liggghts"), (f"lammps_s{seed}", "lammps"),
                           (f"lammps_no_side_dashpot_s{seed}", "lammps")):
            rows.append(scene_row(work / name, name, host, seed, args.transient, cpu.get(name, math.nan)))
        for host in ("lammps", "liggghts"):
            rows.append(same_packing_row(work / f"same_packing_s{seed}" / host, host, seed, args.transient,
                                         cpu.get(f"same_packing_{host}_s{seed}", math.nan)))
    return rows


def welch(a, b, level=CONFIDENCE):
    """mean(a) - mean(b) and the half width of its Welch t interval."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    va, vb = a.var(ddof=1) / a.size, b.var(ddof=1) / b.size
    dof = (va + vb) ** 2 / (va ** 2 / (a.size - 1) + vb ** 2 / (b.size - 1))
    return a.mean() - b.mean(), stats.t.ppf(0.5 + level / 2, dof) * math.sqrt(va + vb)


def summary(rows, args):
    """Each host's Q over the runs that flowed to their end: a run that
    clogged (no grain out at the end of its window) has no stationary Q and
    is left out, and so is its partner in every pairing by packing."""
    def by_seed(prefix):
        return {r["seed"]: r for r in rows if r["name"].startswith(prefix + "_s")}

    def flowing(prefix):
        return [r["Q"] for r in by_seed(prefix).values() if not r["clogged"]]

    def paired(a_prefix, b_prefix):
        a, b = by_seed(a_prefix), by_seed(b_prefix)
        seeds = [s for s in a if s in b and not a[s]["clogged"] and not b[s]["clogged"]]
        return np.array([a[s]["Q"] for s in seeds]), np.array([b[s]["Q"] for s in seeds])

    hosts = []
    for label, prefix in (("LIGGGHTS", "liggghts"), ("LAMMPS", "lammps"),
                          ("LAMMPS, no tangential dashpot at the side wall", "lammps_no_side_dashpot")):
        values = flowing(prefix)
        mean, half = mean_t_ci(values)
        hosts.append((label, mean, half, np.std(values, ddof=1), values))
    difference, difference_ci = welch(hosts[1][4], hosts[0][4])
    no_dashpot, with_dashpot = paired("lammps_no_side_dashpot", "lammps")
    dashpot, dashpot_ci = mean_t_ci(no_dashpot - with_dashpot)
    same_lammps, same_liggghts = paired("same_packing_lammps", "same_packing_liggghts")
    same = same_lammps - same_liggghts
    same_relative = same / same_liggghts
    return hosts, (difference, difference_ci), (dashpot, dashpot_ci), \
        (*mean_t_ci(same), *mean_t_ci(same_relative), same_relative)


def clogged_runs(rows):
    """'name (n out)' of every run left out as clogged."""
    return [f"{r['name']} ({r['n_out']:.0f} out)" for r in rows if r["clogged"]]


def report(rows, args):
    hosts, (difference, difference_ci), (paired, paired_ci), same = summary(rows, args)
    same_mean, same_ci, same_rel, same_rel_ci, same_each = same
    table = ["| runs | Q (kg/s), mean ± 95 % CI | sd between seeds | per seed |", "|---|---|---|---|"]
    for label, mean, half, sd, values in hosts:
        table.append(f"| {label} | {mean:.4f} ± {half:.4f} | {sd:.4f} | "
                     f"{', '.join(f'{q:.4f}' for q in values)} |")
    cpu = {host: sum(r["cpu"] for r in rows if r["host"] == host) for host in ("liggghts", "lammps")}
    agree = abs(difference) <= difference_ci
    return f"""Written by `bench/silo3d_cross_host.py` (its docstring says what it
runs). The quick silo (Dc = 12 d, 900 spheres, D = 5 d, dt = t_c/40,
0.4 s of settling), f = {args.f:g} Hz, no reinjection, {args.discharge:g} s of
discharge; Q over {args.transient:g}–{args.discharge:g} s after the opening
(analysis.silo3d_rotating, block errors); seeds {', '.join(map(str, args.seeds))},
each run its own packing.

{chr(10).join(table)}

- LAMMPS − LIGGGHTS: {difference:+.4f} ± {difference_ci:.4f} kg/s (Welch, 95 %),
  {100 * difference / hosts[0][1]:+.1f} % of LIGGGHTS' Q: the hosts
  {"agree within the spread between packings" if agree else "differ by more than the spread between packings"}.
- The same packings (each LAMMPS packing as a data file) discharged by
  both hosts, paired: LAMMPS − LIGGGHTS = {same_mean:+.4f} ± {same_ci:.4f} kg/s,
  {100 * same_rel:+.1f} ± {100 * same_rel_ci:.1f} % (95 %; per packing
  {', '.join(f'{100 * x:+.1f} %' for x in same_each)}).
- Without the side wall's tangential dashpot (the term whose cap differs
  between LAMMPS' wall/gran and ours), paired by packing: Q changes by
  {paired:+.4f} ± {paired_ci:.4f} kg/s (95 %).
- Clogged, left out of the means and of their pairs: {', '.join(clogged_runs(rows)) or 'none'}.
- CPU, all runs: LIGGGHTS {cpu['liggghts']:.0f} s, LAMMPS {cpu['lammps']:.0f} s
  (LAMMPS also writes the packings and discharges each twice more).

{benchlib.provenance()}
- LAMMPS: `{benchlib.shown_path(LMP)}`, plugin `{benchlib.shown_path(PLUGIN)}`
"""


def raw(rows):
    lines = ["# every run of bench/silo3d_cross_host.py: Q over the window (kg/s), its block "
             "standard error, grains out at the end, process CPU seconds, clogged at the end (1: left out)",
             "name host seed Q Q_se n_out cpu clogged"]
    lines += [f"{r['name']} {r['host']} {r['seed']} {r['Q']:.6g} {r['Q_se']:.3g} {r['n_out']:.0f} "
              f"{r['cpu']:.1f} {int(r['clogged'])}" for r in rows]
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: 2 seeds, 0.3 s of discharge (writes to bench/work/quick/)")
    parser.add_argument("--seeds", type=int, nargs="+", default=list(SEEDS))
    parser.add_argument("--f", type=float, default=0.0, help="bottom frequency (Hz)")
    parser.add_argument("--discharge", type=float, default=0.6, help="discharge per run (s)")
    parser.add_argument("--transient", type=float, default=0.1, help="left out after the opening (s)")
    parser.add_argument("--reanalyse", action="store_true",
                        help="no engine runs: analyse the runs of the last measurement again (its work/ folder)")
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.seeds, args.discharge = list(SEEDS[:2]), 0.3
    for path in (LMP, PLUGIN, benchlib.OUR_BINARY):
        if not path.exists():
            sys.exit(f"{path} is missing: build it (tools/build.sh)")
    work = benchlib.WORK / ("quick" if args.quick else "") / "silo3d_cross_host"
    rows = reanalyse(work, args) if args.reanalyse else measure(work, args)
    text = report(rows, args)
    raw_path = benchlib.write_raw(SECTION, raw(rows))
    page = benchlib.WORK / "quick" / "silo3d_cross_host.md" if args.quick else PAGE
    benchlib.write_page_section(page, SECTION, text, "# silo3d cross-host (smoke run)\n")
    benchlib.progress(f"wrote {raw_path} and the section {SECTION} of {page}")
    print(text)


if __name__ == "__main__":
    main()
