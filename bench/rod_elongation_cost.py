#!/usr/bin/python3
"""Why does a rod-step of L/d = 4.0 cost about twice one of L/d = 3.3 in
the rotating silo (issue 48; doc/campaigns/silo3d_rotating.md, "Elongation",
"Cost")? Measured, not guessed, on the states the campaign runs:

- **4.0**: the campaign's settling checkpoint (carry/silo3d_rods_elongation_L4.0/
  settling_s32452843/checkpoint.534462.restart.xz, 22 500 rods of d = 5 mm
  after 1.5 s of settling, landed, a few rattlers left on top), decompressed
  into bench/work/rod_elongation_cost/;
- **3.3**: a settled packing of 10 000 rods of d = 6.06 mm, made here by the
  production deck (inputs/silo3d_rotating/in.silo3d_rotating -var shape rod
  -var aspect 3.3), 1.5 s of settling at t_c/20 (half the campaign's steps:
  the packing only has to be a settled one) and cached;
- and cuts of both (the rods above a height deleted after `run 0`) holding
  about 10 000 and 3000 rods: the same packing with fewer rods.

Every measured run reads one of these restart files into a deck of this
script that repeats inputs/silo3d_rotating/system.in for rods (the same
contact law, side wall, closed rotating bottom, gravity and
fix nve/spherocylinder; Δt = t_c/40 of each L/d, as the campaign), `run 0`,
the cut if any, and `run N`. What is measured:

1. **States** (interleaved over repetitions): LIGGGHTS' Loop time per step
   and its breakdown (Pair, Neigh, Comm, Other = the fixes: integration,
   walls, gravity, the list pruning's travel sums), per rod-step; the
   neighbour list per rod at the builds (bounding-sphere pairs LIGGGHTS
   lists, pairs fix nve/spherocylinder keeps: its f_ID[1], f_ID[2]); the
   list builds per 1000 steps and how many of them the rods' turning asked
   for (f_ID[3]); contacts per rod, from a dump, by the styles' own core
   geometry (bench/core_geometry.py); the instructions per rod-step
   (callgrind, load-free: the difference of runs to N and 2N steps) split
   into pair loop, integration, walls and gravity, neighbour lists.
2. **Settings** on the full 4.0 checkpoint, each over the same steps: the
   neighbour skin (0.05, 0.1 = the deck's, 0.2, 0.3 d), `neigh_modify
   every`, the bin size, the atoms' spatial sort, and glibc's transparent
   huge pages for malloc (GLIBC_TUNABLES=glibc.malloc.hugetlb=1, an
   environment setting): ms per step (median over repetitions, each
   setting's ratio to the deck's within a repetition), and the physics
   check against the deck's setting after the same steps: the kinetic
   energy and the positions of five rods and of all rods. A setting that
   only moves the list builds to other steps changes the sums' order, so
   the trajectories part at round-off and the difference grows; for its
   scale, the deck's own setting is run once more with the atoms sorted at
   other steps (`atom_modify sort 999`), which changes nothing but that.

Writes bench/results/rod_elongation_cost.txt and the section
`rod_elongation_cost` of doc/accuracy_cost_spherocylinder.md; --quick
(a 1000-rod cut of the 4.0 checkpoint, 300 rods of 3.3 in the quick silo,
two settings, a few hundred steps; < 3 min) writes under
bench/work/quick/ instead.

    nice -n 5 /usr/bin/python3 bench/rod_elongation_cost.py           # ~45 min CPU, 15 of them settling the 3.3 bed once (cached)
    nice -n 5 /usr/bin/python3 bench/rod_elongation_cost.py --quick   # smoke run
"""

import argparse
import hashlib
import lzma
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
import callgrind  # noqa: E402
import core_geometry  # noqa: E402
from analysis.common.lammps_io import read_dump  # noqa: E402

NAME = "rod_elongation_cost"
PAGE = benchlib.ROOT / "doc" / "accuracy_cost_spherocylinder.md"
CHECKPOINT_40 = (benchlib.ROOT / "carry" / "silo3d_rods_elongation_L4.0" / "settling_s32452843"
                 / "checkpoint.534462.restart.xz")

# ---- the grains and the contact law of inputs/silo3d_rotating (derived.in, rod.in) ----

LENGTH, RHO, G, E_N, MU = 0.020, 620.0, 9.8, 0.9, 0.5
DT_FRACTION = 40                 # the campaign's Δt = t_c/40
SKIN_FACTOR = 0.1                # system.in: neighbor 0.1 d bin
MODEL = "model hooke/stiffness tangential history surface spherocylinder"
TRACKED = 5                      # rods whose positions the physics check prints


class Rods:
    """A rod of L = 20 mm and L/d = aspect and its contact law, as the deck
    derives them (derived.in: Silbert's k_n = 2e5 m g/d, an absolute dashpot
    for e_n = 0.9 between two rods, t_c of two rods head on)."""

    def __init__(self, aspect):
        self.aspect = aspect
        self.d = LENGTH / aspect
        self.mass = RHO * (math.pi * self.d ** 3 / 6 + math.pi * self.d ** 2 / 4 * (LENGTH - self.d))
        self.kn = 2e5 * self.mass * G / self.d
        self.kt = 2.0 / 7.0 * self.kn
        self.gamman = math.sqrt(2 * self.kn * self.mass / ((math.pi / math.log(E_N)) ** 2 + 1))
        meff = self.mass / 2
        self.t_c = math.pi / math.sqrt(self.kn / meff - (self.gamman / (2 * meff)) ** 2)
        self.dt = self.t_c / DT_FRACTION


class State:
    """A restart file of rods in the silo (side wall radius `rc`), with the
    rods above `cut` (m) deleted after `run 0` (None: all)."""

    def __init__(self, name, label, rods, restart, rc, cut=None):
        self.name, self.label, self.rods, self.restart, self.rc, self.cut = name, label, rods, restart, rc, cut


class Setting:
    """A way to run the same physics: the skin in units of d, lines added
    after the deck's `neigh_modify delay 0`, environment variables."""

    def __init__(self, name, label, skin=SKIN_FACTOR, lines="", env=None):
        self.name, self.label, self.skin, self.lines, self.env = name, label, skin, lines, env or {}


REFERENCE = Setting("deck", "the deck: skin 0.1 d, bins ½ cutoff, sort every 1000 steps")
# the deck's own setting, with the atoms sorted at other steps: the
# trajectories part by round-off only, the scale for the other settings
ROUNDOFF = Setting("sort999", "the deck, atoms sorted every 999 steps (round-off control)",
                   lines="atom_modify sort 999 0.0\n")


def settings(rods, quick):
    """The settings tried on the 4.0 checkpoint."""
    cutoff = LENGTH + SKIN_FACTOR * rods.d        # LIGGGHTS' cutneighmax: the bounding spheres, L/2 each, plus the skin
    if quick:
        return [REFERENCE, Setting("skin0.2", "skin 0.2 d", skin=0.2)]
    return [
        REFERENCE,
        ROUNDOFF,
        Setting("skin0.05", "skin 0.05 d", skin=0.05),
        Setting("skin0.2", "skin 0.2 d", skin=0.2),
        Setting("skin0.3", "skin 0.3 d", skin=0.3),
        # the fix asks for every build it needs (next_reneighbor, which
        # Neighbor::decide honours whatever every/check say), and its bound
        # |Δx| + h |Δu| covers the centres' check of LIGGGHTS: that check
        # can go
        Setting("fix_only", "neigh_modify every 100000 check yes: the fix's builds only",
                lines="neigh_modify every 100000 check yes\n"),
        Setting("every10", "neigh_modify every 10 check yes", lines="neigh_modify every 10 check yes\n"),
        Setting("bin0.25", "bins ¼ cutoff", lines=f"neigh_modify binsize {0.25 * cutoff!r}\n"),
        Setting("bin1", "bins 1 cutoff", lines=f"neigh_modify binsize {cutoff!r}\n"),
        Setting("nosort", "atoms not sorted", lines="atom_modify sort 0 0.0\n"),
        Setting("sort100", "atoms sorted every 100 steps", lines="atom_modify sort 100 0.0\n"),
        Setting("sortd", "atoms sorted every 1000 steps in bins of d", lines=f"atom_modify sort 1000 {rods.d!r}\n"),
        Setting("hugepages", "malloc on transparent huge pages (GLIBC_TUNABLES=glibc.malloc.hugetlb=1)",
                env={"GLIBC_TUNABLES": "glibc.malloc.hugetlb=1"}),
    ]


# ---- the deck -----------------------------------------------------------------------

# derived.in's formulas, evaluated by LIGGGHTS as the production deck does
# (and substituted as `${name}`, %.15g, as system.in does): the same time
# step and contact law to the last bit, so that the deck's setting follows
# the campaign's trajectory step for step
LAW = """variable L        equal {length!r}
variable aspect   equal {aspect!r}
variable rho      equal {rho!r}
variable g        equal {g!r}
variable e_n      equal {e_n!r}
variable d        equal v_L/v_aspect
variable mass     equal v_rho*(PI*v_d^3/6+PI*v_d^2/4*(v_L-v_d))
variable kn       equal 2e5*v_mass*v_g/v_d
variable kt       equal 2.0/7.0*v_kn
variable gamman   equal sqrt(2*v_kn*v_mass/((PI/ln(v_e_n))^2+1))
variable meff     equal v_mass/2
variable t_c      equal PI/sqrt(v_kn/v_meff-(v_gamman/(2*v_meff))^2)
variable dt_used  equal v_t_c/{dt_fraction}
variable skin     equal {skin!r}*v_d
"""


def deck(state, steps, setting=REFERENCE, dump_start=False, dump_end=False):
    """inputs/silo3d_rotating/system.in for rods, from `state`'s restart
    file; `run 0`, the cut, `run steps`. The bottom stays closed (its
    schedule opens it at 1000 s)."""
    rods = state.rods
    cut = ""
    if state.cut is not None:
        cut = (f"region above block INF INF INF INF {state.cut!r} INF units box\n"
               "delete_atoms region above compress no\n")
    dump = "write_dump all custom {name} id x y z vx vy vz c_axis[1] c_axis[2] c_axis[3] modify sort id format \"{fmt}\"\n"
    fmt = "%d" + " %.17g" * 9
    return f"""# bench/rod_elongation_cost.py: {state.label}; {setting.label}
atom_modify     map array
processors      * * 1
read_restart    {state.restart}
newton          off
communicate     single vel yes
{LAW.format(length=LENGTH, aspect=rods.aspect, rho=RHO, g=G, e_n=E_N, dt_fraction=DT_FRACTION, skin=setting.skin)}timestep        ${{dt_used}}
neighbor        ${{skin}} bin
neigh_modify    delay 0
{setting.lines}pair_style      gran {MODEL} absolute_damping on
pair_coeff      * *
fix m_kn  all property/global kn peratomtypepair 1 ${{kn}}
fix m_kt  all property/global kt peratomtypepair 1 ${{kt}}
fix m_gn  all property/global gamman_abs peratomtypepair 1 ${{gamman}}
fix m_gt  all property/global gammat_abs peratomtypepair 1 ${{gamman}}
fix m_mu  all property/global coefficientFriction peratomtypepair 1 {MU!r}
fix side all wall/gran/spherocylinder {MODEL} primitive type 1 zcylinder {state.rc!r} 0.0 0.0 absolute_damping on
fix bottom all wall/gran/rotating {MODEL} primitive type 1 zplane 0.0 absolute_damping on orifice 0.06 frequency 0.0 start 1000 open 1000
fix gravity all gravity {G!r} vector 0 0 -1
fix integrate all nve/spherocylinder
compute axis all spherocylinder/axis
thermo_style    custom step atoms ke f_integrate[1] f_integrate[2] f_integrate[3]
thermo          {max(steps, 1)}
thermo_modify   lost ignore norm no
run 0
{cut}{dump.format(name='start.dump', fmt=fmt) if dump_start else ''}run {steps}
{dump.format(name='end.dump', fmt=fmt) if dump_end else ''}"""


# ---- running and reading --------------------------------------------------------------

BREAKDOWN = re.compile(r"^(Pair |Neigh|Comm |Outpt|Other) time \(%\) = (\S+)", re.MULTILINE)
NEIGHBOURS = re.compile(r"^Total # of neighbors = (\d+)", re.MULTILINE)
BUILDS = re.compile(r"^Neighbor list builds = (\d+)", re.MULTILINE)
DANGEROUS = re.compile(r"^Dangerous builds = (\d+)", re.MULTILINE)


def thermo_rows(output):
    """The numeric thermo rows of each run, as lists of floats."""
    runs, rows = [], None
    for line in output.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            rows = []
            runs.append(rows)
        elif rows is not None and words and words[0].isdigit() and len(words) == 6:
            rows.append([float(w) for w in words])
        elif line.startswith("Loop time"):
            rows = None
    return runs


def run(state, steps, setting, workdir, **dumps):
    """Runs the deck; what the last run measured."""
    saved = {k: os.environ.get(k) for k in setting.env}
    os.environ.update(setting.env)
    try:
        result = benchlib.run_deck(deck(state, steps, setting, **dumps), workdir)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    output = result["output"]
    benchlib.check_complete(output, steps, workdir)
    seconds, _, atoms = result["loops"][-1]
    parts = {k.strip(): float(v) for k, v in BREAKDOWN.findall(output[output.rindex("Loop time"):])}
    runs = thermo_rows(output)
    before, first, last = runs[-2][-1], runs[-1][0], runs[-1][-1]
    builds = benchlib.last_int(BUILDS, output)
    # f_integrate[1], [2] add up the pairs listed and kept at each build
    # since the fix was defined: the measured run's set-up build and its
    # `builds` builds
    lists = builds + 1
    return {"seconds": seconds, "steps": steps, "atoms": atoms, "ms": 1e3 * seconds / steps,
            "us_rod": 1e6 * seconds / steps / atoms,
            "parts_ms": {k: 1e3 * v / steps for k, v in parts.items()},
            "listed": (last[3] - before[3]) / lists / atoms, "kept": (last[4] - before[4]) / lists / atoms,
            "kept_end": benchlib.last_int(NEIGHBOURS, output) / atoms,
            "builds": builds, "asked": int(last[5] - first[5]) + int(first[5] - before[5]),
            "dangerous": benchlib.last_int(DANGEROUS, output), "ke": last[2], "cpu": result["cpu"],
            "load": os.getloadavg()[0]}


def snapshot(state, workdir):
    """A dump of the state's rods after the cut; its path."""
    benchlib.run_deck(deck(state, 0, dump_start=True), workdir)
    return workdir / "start.dump"


def contacts_per_rod(state, dump_path):
    """Pairs within d + skin (what the pruned list keeps, but for the
    springs in use) and touching (cores closer than d), per rod, from the
    styles' own geometry header; also the rods' heights."""
    from scipy.spatial import cKDTree
    _, c = read_dump(dump_path)[0]
    x = np.column_stack([c["x"], c["y"], c["z"]])
    axis = np.column_stack([c["c_axis[1]"], c["c_axis[2]"], c["c_axis[3]"]])
    d = state.rods.d
    pairs = np.array(sorted(cKDTree(x).query_pairs(LENGTH)), dtype=int).reshape(-1, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    touching = core_geometry.rods_touching(x[i], axis[i], x[j], axis[j], (LENGTH - d) / 2, d / 2)
    return {"rods": len(x), "contacts": int(np.sum(touching)) / len(x)}


# ---- the states -------------------------------------------------------------------------

def checkpoint_40():
    """The 4.0 settling checkpoint, decompressed once into work/ (never
    into carry/; the smoke run shares it)."""
    target = benchlib.WORK / NAME / "checkpoint_L4.0_534462.restart"
    target.parent.mkdir(parents=True, exist_ok=True)
    if not target.exists():
        benchlib.progress(f"decompressing {benchlib.shown_path(CHECKPOINT_40)}")
        with lzma.open(CHECKPOINT_40) as source, open(target.with_suffix(".tmp"), "wb") as sink:
            shutil.copyfileobj(source, sink)
        target.with_suffix(".tmp").rename(target)
    return target


def bed_33(work, quick):
    """A settled packing of L/d = 3.3 rods by the production deck, cached
    under a hash of its variables."""
    variables = {"shape": "rod", "aspect": 3.3, "write_packing": 1, "discharge_time": 0}
    if quick:
        variables["quick"] = 1
    else:
        variables.update({"N": 10000, "settle_time": 1.5, "dt_fraction": 20})
    text = benchlib.scene_deck("silo3d_rotating", variables)
    where = work / f"bed_L3.3_{hashlib.sha256(text.encode()).hexdigest()[:12]}"
    packing = where / "packing.restart"
    if packing.exists():
        benchlib.progress(f"3.3 bed: cached ({benchlib.shown_path(packing)})")
        return packing
    benchlib.progress(f"3.3 bed: settling with the production deck {variables}")
    result = benchlib.run_deck(text, where)
    if not packing.exists():
        raise benchlib.LiggghtsFailed(f"no packing.restart in {where}")
    benchlib.progress(f"3.3 bed: settled in {result['cpu']:.0f} s CPU")
    return packing


def make_states(work, quick):
    """The full packings and cuts of them holding `targets` rods (the cut
    height from a dump of the full packing); the smoke run measures only
    a small cut of 4.0 and the quick silo's 3.3 bed."""
    r40, r33 = Rods(4.0), Rods(3.3)
    full = [State("L4.0", "4.0, the campaign's checkpoint", r40, checkpoint_40(), 0.095),
            State("L3.3", "3.3, settled here", r33, bed_33(work, quick), 0.0594 if quick else 0.095)]
    targets = {"L4.0": [1000] if quick else [10000, 3000], "L3.3": [] if quick else [3000]}
    states, counts = [], {}
    for state in full:
        dump = snapshot(state, work / "count" / state.name)
        if not (quick and state.name == "L4.0"):
            counts[state.name] = contacts_per_rod(state, dump)
            states.append(state)
        _, c = read_dump(dump)[0]
        z = np.sort(c["z"])
        for n in targets[state.name]:
            height = 0.5 * (z[n - 1] + z[n])
            cut = State(f"{state.name}_cut{n}", f"{state.label}, the rods below z = {height * 100:.1f} cm",
                        state.rods, state.restart, state.rc, cut=height)
            counts[cut.name] = contacts_per_rod(cut, snapshot(cut, work / "count" / cut.name))
            states.append(cut)
    for state in states:
        benchlib.progress(f"{state.name}: {counts[state.name]['rods']} rods, "
                          f"{counts[state.name]['contacts']:.2f} contacts per rod")
    return states, counts


# ---- the measurements ------------------------------------------------------------------

def time_states(states, steps, repetitions, work):
    """Loop time of each state, states interleaved, order reversed every
    other repetition."""
    results = {s.name: [] for s in states}
    for rep in range(repetitions):
        order = states if rep % 2 == 0 else states[::-1]
        for state in order:
            r = run(state, steps, REFERENCE, work / "states" / state.name)
            results[state.name].append(r)
            benchlib.progress(f"states, repetition {rep + 1}: {state.name}: {r['ms']:.2f} ms per step, "
                              f"{r['us_rod']:.3f} µs per rod-step, {r['builds']} builds, load {r['load']:.2f}")
    return results


# The simulated last-level cache: half the machine's L3 of 32 MiB (16-way),
# the other half being the campaign's, which runs the same program on a
# state of the same size on the other core. (valgrind reads the L3 of this
# virtual machine as 320 MiB direct-mapped; L1 as detected, 32 KiB 8-way.)
LAST_LEVEL = "16777216,16,64"
EVENTS = re.compile(r"^==\d+== Events\s*:\s*(.*)$", re.MULTILINE)
COLLECTED = re.compile(r"^==\d+== Collected\s*:\s*(.*)$", re.MULTILINE)


def run_cache_counted(text, workdir):
    """callgrind.run_counted with the cache simulation on: the instruction
    total, every event's total, the screen output, the profile."""
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(text)
    profile = workdir / "callgrind.out"
    command = ["valgrind", "--tool=callgrind", "--cache-sim=yes", f"--LL={LAST_LEVEL}",
               f"--callgrind-out-file={profile}", str(benchlib.OUR_BINARY), "-in", "in.deck", "-log", "none"]
    with open(workdir / "screen.txt", "w") as screen, open(workdir / "valgrind.txt", "w") as log:
        process = subprocess.Popen(command, cwd=workdir, stdout=screen, stderr=log)
        _, status, usage = os.wait4(process.pid, 0)
    output = (workdir / "screen.txt").read_text(errors="replace")
    report = (workdir / "valgrind.txt").read_text(errors="replace")
    names, totals = EVENTS.search(report), COLLECTED.search(report)
    if os.waitstatus_to_exitcode(status) != 0 or "ERROR" in output or not totals:
        raise benchlib.LiggghtsFailed(f"callgrind run failed in {workdir}")
    events = dict(zip(names.group(1).split(), (int(v) for v in totals.group(1).split())))
    return {"instructions": events["Ir"], "events": events, "output": output, "profile": profile,
            "cpu": usage.ru_utime + usage.ru_stime}


def inclusive_instructions(profile):
    """function -> inclusive instructions (callgrind_annotate, the Ir
    column only: with the cache simulated the profile has more events)."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--show=Ir", "--threshold=100", str(profile)],
                          capture_output=True, text=True, check=True).stdout
    functions = {}
    for line in text.splitlines():
        match = callgrind.ANNOTATE_LINE.match(line)
        if match and "PROGRAM TOTALS" not in line:
            name = re.sub(r" \[[^\]]*\]$", "", match.group(2))
            name = re.sub(r"^(\?\?\?|[^\s:()]+):", "", name)
            functions[name] = functions.get(name, 0) + int(match.group(1).replace(",", ""))
    return functions


def window(short, long, steps):
    """callgrind.window for profiles with the cache simulated: per step of
    the window, the instructions and their split into callgrind.CATEGORIES."""
    per_step = (long["instructions"] - short["instructions"]) / steps
    inclusive = [inclusive_instructions(r["profile"]) for r in (short, long)]
    parts = {name: sum(inclusive[1].get(f, 0) - inclusive[0].get(f, 0) for f in functions) / steps
             for name, functions in callgrind.CATEGORIES}
    parts["other"] = per_step - sum(parts.values())
    builds = [benchlib.last_int(BUILDS, r["output"]) or 0 for r in (short, long)]
    return {"per_step": per_step, "parts": parts, "neighbours": benchlib.last_int(NEIGHBOURS, long["output"]),
            "builds": builds[1] - builds[0]}


def count_states(states, steps, work):
    """Instructions and simulated cache misses per rod-step (callgrind,
    the window of `steps` steps between runs to N and 2N steps), split
    into the parts of a step."""
    counted = {}
    for state in states:
        runs = []
        for n in (steps, 2 * steps):
            where = (work / "callgrind" / state.name / f"steps{n}").resolve()
            runs.append(run_cache_counted(deck(state, n), where))
            benchlib.check_complete(runs[-1]["output"], n, where)
        result = window(runs[0], runs[1], steps)
        result["atoms"] = int(benchlib.LOOP_TIME.findall(runs[1]["output"])[-1][3])
        result["events"] = {k: (runs[1]["events"][k] - runs[0]["events"][k]) / steps for k in runs[0]["events"]}
        counted[state.name] = result
        atoms = result["atoms"]
        benchlib.progress(f"{state.name} under callgrind: {result['per_step'] / atoms:,.0f} instructions per "
                          f"rod-step, {result['events']['D1mr'] / atoms:.1f} L1 and "
                          f"{(result['events']['DLmr'] + result['events']['DLmw']) / atoms:.2f} "
                          f"last-level misses, {result['builds']} builds in the window")
    return counted


def time_settings(state, choices, steps, repetitions, work):
    """Each setting over the same steps from the 4.0 checkpoint, interleaved;
    the first repetition also dumps the rods at the end."""
    results = {s.name: [] for s in choices}
    for rep in range(repetitions):
        order = choices if rep % 2 == 0 else choices[::-1]
        for setting in order:
            r = run(state, steps, setting, work / "settings" / setting.name, dump_end=(rep == 0))
            results[setting.name].append(r)
            benchlib.progress(f"settings, repetition {rep + 1}: {setting.name}: {r['ms']:.2f} ms per step, "
                              f"{r['builds']} builds, {r['kept']:.2f} kept / {r['listed']:.2f} listed per rod, "
                              f"load {r['load']:.2f}")
    return results


def physics_check(choices, work):
    """Each setting's rods after the run against the deck's: KE, the
    positions of TRACKED rods spread over the IDs, and of all rods."""
    def load(name):
        _, c = read_dump(work / "settings" / name / "end.dump")[0]
        return c["id"].astype(int), np.column_stack([c["x"], c["y"], c["z"]])
    ids, reference = load(REFERENCE.name)
    tracked = np.linspace(0, len(ids) - 1, TRACKED).astype(int)
    checks = {}
    for setting in choices:
        other_ids, x = load(setting.name)
        if not np.array_equal(ids, other_ids):
            raise RuntimeError(f"{setting.name}: other rods than the deck's at the end (lost rods?)")
        moved = np.linalg.norm(x - reference, axis=1)
        checks[setting.name] = {"tracked": float(moved[tracked].max()), "all": float(moved.max()),
                                "tracked_ids": ids[tracked].tolist(),
                                "tracked_z": reference[tracked, 2].tolist()}
    return checks


# ---- the report ----------------------------------------------------------------------------

def spread(values, digits=3):
    median, low, high = benchlib.spread(values)
    return f"{median:.{digits}g} [{low:.{digits}g}–{high:.{digits}g}]"


def states_table(states, counts, timed):
    lines = ["| L/d: state | rods | ms per step | µs per rod-step | Pair | Neigh | Other (fixes) | "
             "listed per rod (bounding spheres) | kept per rod (pruned) | contacts per rod | "
             "builds per 1000 steps (asked by a turning rod) |",
             "|" + "---|" * 11]
    for state in states:
        runs = timed[state.name]
        first = runs[0]
        part = {k: spread([r["parts_ms"].get(k, 0.0) for r in runs]) for k in ("Pair", "Neigh", "Other")}
        lines.append(f"| {state.label} | {first['atoms']} | {spread([r['ms'] for r in runs])} | "
                     f"{spread([r['us_rod'] for r in runs])} | {part['Pair']} | {part['Neigh']} | {part['Other']} | "
                     f"{first['listed']:.2f} | {first['kept']:.2f} | {counts[state.name]['contacts']:.2f} | "
                     f"{1000 * first['builds'] / first['steps']:.1f} ({1000 * first['asked'] / first['steps']:.1f}) |")
    return "\n".join(lines)


def counted_table(states, timed, counted):
    lines = ["| L/d: state | instructions per rod-step | pair loop | integration | walls, gravity | "
             "neighbour lists | other | pair loop per kept pair | L1 data misses per rod-step | "
             f"last-level misses per rod-step (LL {int(LAST_LEVEL.split(',')[0]) >> 20} MiB) | "
             "ns per instruction (fastest run) |",
             "|" + "---|" * 11]
    for state in states:
        if state.name not in counted:
            continue
        cg = counted[state.name]
        atoms = cg["atoms"]
        parts = cg["parts"]
        ev = cg["events"]
        fastest = min(r["us_rod"] for r in timed[state.name])
        lines.append(f"| {state.label} | {cg['per_step'] / atoms:,.0f} | {parts['pair'] / atoms:,.0f} | "
                     f"{parts['integration'] / atoms:,.0f} | {parts['post_force'] / atoms:,.0f} | "
                     f"{parts['neighbour'] / atoms:,.0f} | {parts['other'] / atoms:,.0f} | "
                     f"{parts['pair'] / cg['neighbours']:,.0f} | {ev['D1mr'] / atoms:.1f} | "
                     f"{(ev['DLmr'] + ev['DLmw']) / atoms:.2f} | {1e3 * fastest * atoms / cg['per_step']:.3f} |")
    return "\n".join(lines)


def settings_table(choices, timed, checks):
    reference = timed[REFERENCE.name]
    lines = ["| setting | ms per step | µs per rod-step | ÷ the deck's (same repetition) | listed per rod | "
             "kept per rod | builds per 1000 steps | dangerous builds | KE after (J) | "
             f"largest move of {TRACKED} rods vs the deck (m) | of all rods (m) | load (1 min) |",
             "|" + "---|" * 12]
    for setting in choices:
        runs = timed[setting.name]
        first = runs[0]
        ratios = [r["seconds"] / ref["seconds"] for r, ref in zip(runs, reference)]
        check = checks[setting.name]
        loads = [r["load"] for r in runs]
        lines.append(f"| {setting.label} | {spread([r['ms'] for r in runs])} | "
                     f"{spread([r['us_rod'] for r in runs])} | {spread(ratios)} | {first['listed']:.2f} | "
                     f"{first['kept']:.2f} | {1000 * first['builds'] / first['steps']:.1f} | {first['dangerous']} | "
                     f"{first['ke']:.10g} | {check['tracked']:.2g} | {check['all']:.2g} | "
                     f"{min(loads):.1f}–{max(loads):.1f} |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="smoke run, writes under bench/work/quick/")
    parser.add_argument("--steps", type=int, help="steps per state run (1000; quick 200)")
    parser.add_argument("--setting-steps", type=int, help="steps per setting run (2000; quick 200)")
    parser.add_argument("--count-steps", type=int, help="callgrind window (100; quick 20)")
    parser.add_argument("--repetitions", type=int, help="repetitions (3; quick 1)")
    args = parser.parse_args()
    quick = args.quick
    steps = args.steps or (200 if quick else 1000)
    setting_steps = args.setting_steps or (200 if quick else 2000)
    count_steps = args.count_steps or (20 if quick else 100)
    repetitions = args.repetitions or (1 if quick else 3)
    if quick:
        benchlib.use_smoke_outputs()
    work = benchlib.WORK / ("quick" if quick else "") / NAME
    work.mkdir(parents=True, exist_ok=True)
    load_start = benchlib.load_average()

    states, counts = make_states(work, quick)
    timed_states = time_states(states, steps, repetitions, work)
    counted = count_states(states, count_steps, work)
    full_40 = states[0]     # the whole checkpoint (the smoke run: its 1000-rod cut)
    choices = settings(full_40.rods, quick)
    timed_settings = time_settings(full_40, choices, setting_steps, repetitions, work)
    checks = physics_check(choices, work)

    provenance = benchlib.provenance(extra_load=load_start)
    tracked = checks[REFERENCE.name]
    r40, r33 = Rods(4.0), Rods(3.3)
    markdown = f"""## Cost of L/d = 4.0 per rod-step: the measurements (`bench/rod_elongation_cost.py`)

Rods L = 20 mm: L/d = 4.0 (d = {r40.d * 1e3:.2f} mm, Δt = {r40.dt:.4g} s) and 3.3 (d = {r33.d * 1e3:.2f} mm, Δt = {r33.dt:.4g} s), Δt = t_c/{DT_FRACTION}, the deck's contact law, side wall and closed bottom (D_c = 19 cm). Loop time of LIGGGHTS (serial, `nice -n 5`) on a machine shared with a campaign and other work: median [min–max] over {repetitions} repetitions, states and settings interleaved. Pair, Neigh, Other: LIGGGHTS' breakdown in ms per step (Other: the fixes). Listed and kept per rod: averages over the builds of a run (the set-up's included).

### States: {steps} steps each

{states_table(states, counts, timed_states)}

Under callgrind (window of {count_steps} steps, the cache simulated):

{counted_table(states, timed_states, counted)}

### Settings on {full_40.label} ({timed_settings[REFERENCE.name][0]['atoms']} rods): {setting_steps} steps each

{settings_table(choices, timed_settings, checks)}

Tracked rods: IDs {', '.join(str(i) for i in tracked['tracked_ids'])} (z = {', '.join(f'{z * 100:.1f}' for z in tracked['tracked_z'])} cm).

{provenance}
"""
    raw = markdown + "\n\n## Raw\n\n" + repr({"states": timed_states, "settings": timed_settings, "checks": checks,
                                              "counted": {k: {kk: vv for kk, vv in v.items() if kk != "exclusive"}
                                                          for k, v in counted.items()},
                                              "counts": {k: {kk: vv for kk, vv in v.items() if kk != "z"}
                                                         for k, v in counts.items()}})
    # a smoke run writes under work/quick/, never over a measurement
    page = benchlib.WORK / "quick" / PAGE.name if quick else PAGE
    path = benchlib.write_raw(NAME, raw)
    benchlib.write_page_section(page, NAME, markdown, header=f"# {PAGE.name} (smoke run)\n")
    benchlib.progress(f"wrote {benchlib.shown_path(path)} and the section {NAME} of {benchlib.shown_path(page)}")


if __name__ == "__main__":
    main()
