#!/usr/bin/python3
"""What do rods cost? Instructions per particle-step, counted by valgrind's
callgrind (repeatable on a busy machine, unlike wall-clock time), of:

(a) spheres before and after the rods: the stock deck of
    bench/stock_speed.py (its `deck()`, imported; Hertz, tangential
    history, spheres of 2.5 and 3 mm in a box) run by the binary built
    before the rods and the build flag NONSPHERICAL_ACTIVE_FLAG (--before,
    read only) and by ours, in two windows: the spheres falling just after
    their insertion, and the settled heap;
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
counted from their geometry here (rod cores closer than d, spheres closer
than the sum of radii, clump spheres of different clumps).

Also printed: the contact times t_c of the rods' contact law (head on, an
end on the floor, two rods crossing at their ends; doc/spherocylinder.md,
"Time step"), of the spheres and of the clumps.

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
import hashlib
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402
import stock_speed  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.lammps_io import read_dump  # noqa: E402

BEFORE_BINARY = Path(os.environ.get("SILOKIT_LIGGGHTS_BEFORE", "/work/campaign/liggghts"))
PAGE_NAME = "accuracy_cost_spherocylinder.md"
SECTION = "spherocylinder_cost"

# ---- the grains and their contact law (inputs/silo3d_rotating/in.silo3d_rotating) ----

LENGTH = 0.020            # rod length end to end (m)
ASPECT = 3.3              # L/d
RHO = 620.0               # kg/m^3, the paper's wooden rods
SPHERE_D = 0.0099         # the deck's volume-equivalent sphere diameter d* (m)
G = 9.8
MU = 0.5
RESTITUTION = 0.9         # e_n of two grains meeting head on (the deck's gamma_n)
BOX = 0.10                # the container: planes at x, y = +-BOX/2 and a floor z = 0
DT_FRACTION = 20          # dt = (the rods' shortest contact time) / DT_FRACTION, for all beds
SEEDS = {"axis": 32452843, "insert": 32452843, "template": 86028121, "distribution": 86028157}
ROD_MODEL = "model hooke/stiffness tangential history surface spherocylinder"
SPHERE_MODEL = "model hooke/stiffness tangential history"


def solid_rod(d, length, rho):
    """Mass and principal moments (axial, transverse) of a solid
    spherocylinder (doc/spherocylinder.md, atom_style spherocylinder)."""
    r, a = d / 2, length - d
    m_cyl = rho * math.pi * r * r * a
    m_sph = rho * 4.0 / 3.0 * math.pi * r ** 3
    axial = m_cyl * r * r / 2 + m_sph * 2.0 / 5.0 * r * r
    transverse = (m_cyl * (a * a / 12 + r * r / 4)
                  + m_sph * (2.0 / 5.0 * r * r + a * a / 4 + 3.0 / 8.0 * a * r))
    return m_cyl + m_sph, axial, transverse


def silbert_law(mass, d):
    """The deck's contact law: k_n = 2e5 m g / d, k_t = 2/7 k_n, an absolute
    dashpot gamma_n = gamma_t for e_n = 0.9 between two grains (m_eff = m/2)."""
    kn = 2e5 * mass * G / d
    gamman = math.sqrt(2 * kn * mass / ((math.pi / math.log(RESTITUTION)) ** 2 + 1))
    return {"kn": kn, "kt": 2.0 / 7.0 * kn, "gamman": gamman}


def contact_time(kn, gamman, inverse_meff, contacts=1):
    """Damped half period of `contacts` equal springs and dashpots in
    parallel acting on the effective mass 1/inverse_meff."""
    meff = 1.0 / inverse_meff
    k, gamma = contacts * kn, contacts * gamman
    return math.pi / math.sqrt(k / meff - (gamma / (2 * meff)) ** 2)


class Grains:
    """Everything derived from the constants above."""

    def __init__(self, clump_spheres):
        self.rod_d = LENGTH / ASPECT
        self.rod_mass, self.rod_axial, self.rod_transverse = solid_rod(self.rod_d, LENGTH, RHO)
        self.rod_law = silbert_law(self.rod_mass, self.rod_d)
        self.sphere_mass = RHO * math.pi * SPHERE_D ** 3 / 6
        self.sphere_law = silbert_law(self.sphere_mass, SPHERE_D)
        self.clump_spheres = clump_spheres
        self.times = self.contact_times()
        self.rod_tc_min = min(t for shape, _, t in self.times if shape == "rod")
        self.dt = self.rod_tc_min / DT_FRACTION

    def contact_times(self):
        """(shape, configuration, t_c) as in doc/fix_nve_spherocylinder.md, "Time step":
        a contact at the end of the core, normal to the axis, counts the rod
        with 1/m + s^2/I_t in 1/m_eff (s = (L - d)/2)."""
        m, s = self.rod_mass, (LENGTH - self.rod_d) / 2
        end = 1 / m + s * s / self.rod_transverse
        rod = (self.rod_law["kn"], self.rod_law["gamman"])
        sphere = (self.sphere_law["kn"], self.sphere_law["gamman"])
        n = self.clump_spheres
        return [
            ("rod", "two rods head on (end to end, or side by side)", contact_time(*rod, 2 / m)),
            ("rod", "an end on the floor", contact_time(*rod, end)),
            ("rod", "two rods crossing at their ends", contact_time(*rod, 2 * end)),
            ("sphere", f"two spheres d* = {SPHERE_D * 1e3:g} mm head on (their own law)",
             contact_time(*sphere, 2 / self.sphere_mass)),
            ("sphere", "a sphere on the floor", contact_time(*sphere, 1 / self.sphere_mass)),
            ("clump", "two clumps crossing at their ends (one sphere contact)", contact_time(*rod, 2 * end)),
            ("clump", f"two clumps side by side ({n} sphere contacts in parallel)",
             contact_time(*rod, 2 / m, contacts=n)),
            ("clump", f"a clump lying flat on the floor ({n} contacts)", contact_time(*rod, 1 / m, contacts=n)),
        ]


# ---- decks ------------------------------------------------------------------------

def materials(law, model):
    return f"""pair_style gran {model} absolute_damping on
pair_coeff * *
fix m_kn all property/global kn peratomtypepair 1 {law['kn']!r}
fix m_kt all property/global kt peratomtypepair 1 {law['kt']!r}
fix m_gn all property/global gamman_abs peratomtypepair 1 {law['gamman']!r}
fix m_gt all property/global gammat_abs peratomtypepair 1 {law['gamman']!r}
fix m_mu all property/global coefficientFriction peratomtypepair 1 {MU!r}
"""


def walls(shape):
    """The box: a floor and four side planes."""
    if shape == "rod":
        style, model = "wall/gran/spherocylinder", ROD_MODEL
    else:
        style, model = "wall/gran", SPHERE_MODEL
    planes = [("zplane", 0.0), ("xplane", -BOX / 2), ("xplane", BOX / 2),
              ("yplane", -BOX / 2), ("yplane", BOX / 2)]
    return "".join(f"fix wall{k} all {style} {model} primitive type 1 {plane} {position!r} absolute_damping on\n"
                   for k, (plane, position) in enumerate(planes))


INTEGRATOR = {"rod": "fix integrate all nve/spherocylinder\n",
              "sphere": "fix integrate all nve/sphere\n",
              "clump": "fix ms all multisphere\n"}
# the rods as they were before the symmetric-top scheme and the pruned
# list (commit d5a97bb), measured in the same run: name -> (label, integrator)
ROD_VARIANTS = {
    "rod_no_squish": ("rods, no-squish rotation (integration_scheme 1)",
                      "fix integrate all nve/spherocylinder integration_scheme 1\n"),
    "rod_whole_list": ("rods, the whole list (prune_list no)",
                       "fix integrate all nve/spherocylinder prune_list no\n"),
    "rod_before": ("rods, both (no-squish, whole list)",
                   "fix integrate all nve/spherocylinder integration_scheme 1 prune_list no\n"),
}


class Bed:
    """One settled bed: its settling deck (native, cached) and the decks
    measured from its restart file."""

    def __init__(self, shape, grains, count, settle_time, workdir):
        self.shape, self.grains, self.count = shape, grains, count
        self.atoms_per_particle = grains.clump_spheres if shape == "clump" else 1
        self.diameter = SPHERE_D if shape == "sphere" else grains.rod_d
        self.law = grains.sphere_law if shape == "sphere" else grains.rod_law
        self.model = ROD_MODEL if shape == "rod" else SPHERE_MODEL
        self.skin = 0.1 * self.diameter               # the deck's skin, 0.1 d
        self.settle_time = settle_time
        text = self.settle_deck()
        self.key = hashlib.sha256(text.encode()).hexdigest()[:12]
        self.dir = workdir / "beds" / f"{shape}_{count}_{self.key}"
        self.restart = self.dir / "bed.restart"

    def header(self):
        style = "spherocylinder" if self.shape == "rod" else "sphere"
        return f"""units si
atom_style {style}
atom_modify map array
boundary f f f
newton off
communicate single vel yes
"""

    def gas(self):
        """Rods on a cubic lattice of spacing 1.05 L with random axes (stock
        insertion places spheres; as in the silo deck); spheres and clumps
        by insert/pack."""
        g, n = self.grains, self.count
        margin = 0.001
        if self.shape == "rod":
            a = 1.05 * LENGTH
            half = BOX / 2 - LENGTH / 2 - margin
            per_row = 2 * int(math.floor(half / a + 0.5))
            layers = math.ceil(n / per_row ** 2) + 1
            top = LENGTH / 2 + margin + (layers + 1) * a
            return top, f"""lattice sc {a!r} origin 0.5 0.5 0.5
region column block {-half!r} {half!r} {-half!r} {half!r} {LENGTH / 2 + margin!r} {top!r} units box
create_atoms 1 region column
variable n_made equal count(all)
if "${{n_made}} < {n}" then "print 'spherocylinder_cost: ERROR: the lattice holds ${{n_made}} < {n} rods'" "jump SELF too_few_rods"
group extra id > {n}
delete_atoms group extra
group extra delete
set_spherocylinder all diameter {g.rod_d!r} length {LENGTH!r} density {RHO!r} axis random {SEEDS['axis']}
"""
        if self.shape == "sphere":
            half = BOX / 2 - SPHERE_D / 2 - margin
            volume = math.pi * SPHERE_D ** 3 / 6
            top = margin + n * volume / (0.2 * (2 * half) ** 2)     # a gas at volume fraction 0.2
            template = (f"fix template all particletemplate/sphere {SEEDS['template']} atom_type 1 "
                        f"density constant {RHO!r} radius constant {SPHERE_D / 2!r}")
            orientation = ""
        else:
            half = BOX / 2 - LENGTH / 2 - margin
            volume = g.rod_mass / RHO
            top = LENGTH / 2 + margin + n * volume / (0.12 * (2 * half) ** 2)
            core = LENGTH - g.rod_d
            spheres = " ".join(f"{-core / 2 + k * core / (g.clump_spheres - 1)!r} 0.0 0.0 {g.rod_d / 2!r}"
                               for k in range(g.clump_spheres))
            # the clump's axis is x; mass and inertia of the solid rod given,
            # not Monte-Carlo'd from the union of the spheres (use_density:
            # volume = mass / density)
            template = (f"fix template all particletemplate/multisphere {SEEDS['template']} atom_type 1 "
                        f"density constant {RHO!r} nspheres {g.clump_spheres} ntry 100000 spheres {spheres} "
                        f"type 1 mass {g.rod_mass!r} inertia_tensor {g.rod_axial!r} 0 0 "
                        f"{g.rod_transverse!r} 0 {g.rod_transverse!r} use_density")
            orientation = "orientation random "
        bottom = margin if self.shape == "sphere" else LENGTH / 2 + margin
        # the clumps' integrator comes before their insertion; bound() at the
        # end of the settling deck needs allow_group_and_set
        multisphere = "fix ms all multisphere allow_group_and_set yes\n" if self.shape == "clump" else ""
        return top, f"""region gas block {-half!r} {half!r} {-half!r} {half!r} {bottom!r} {top!r} units box
{template}
fix distribution all particledistribution/discrete {SEEDS['distribution']} 1 template 1.0
{multisphere}fix gas all insert/pack seed {SEEDS['insert']} distributiontemplate distribution vel constant 0 0 0 {orientation}&
    insert_every once overlapcheck yes all_in yes particles_in_region {n} region gas ntry_mc 100000
"""

    def column_top(self):
        return self.gas()[0]

    def settle_deck(self):
        top, gas = self.gas()
        box_top = top + LENGTH
        steps = round(self.settle_time / self.grains.dt)
        integrator = "" if self.shape == "clump" else INTEGRATOR[self.shape]
        return f"""# bench/spherocylinder_cost.py: a bed of {self.count} {self.shape}s settles in the box
{self.header()}region box block {-BOX / 2 - 0.005!r} {BOX / 2 + 0.005!r} {-BOX / 2 - 0.005!r} {BOX / 2 + 0.005!r} -0.01 {box_top!r} units box
create_box 1 box
{gas}neighbor {self.skin!r} bin
neigh_modify delay 0
{materials(self.law, self.model)}{walls(self.shape)}fix gravity all gravity {G!r} vector 0 0 -1
{integrator}timestep {self.grains.dt!r}
thermo_style custom step time atoms ke
thermo {max(steps // 10, 1)}
thermo_modify lost ignore norm no
run {steps}
# the box's top lowered to L above the bed: the measured runs bin no empty
# space (LIGGGHTS refuses change_box right after read_restart)
variable bed_top equal bound(all,zmax)+{LENGTH!r}
change_box all z final -0.01 ${{bed_top}} units box
write_restart bed.restart
"""

    def settle(self):
        if self.restart.exists():
            benchlib.progress(f"{self.shape} bed: cached ({self.restart.relative_to(benchlib.ROOT)})")
            return
        benchlib.progress(f"{self.shape} bed: settling {self.count} grains for {self.settle_time:.2f} s "
                          f"(dt {self.grains.dt:.3g} s), natively")
        result = benchlib.run_deck(self.settle_deck(), self.dir)
        atoms = result["loops"][-1][2]
        if atoms != self.count * self.atoms_per_particle:
            self.restart.unlink(missing_ok=True)      # not a bed to measure
            raise benchlib.LiggghtsFailed(f"{self.shape} bed: {atoms} atoms after the settling, expected "
                                          f"{self.count * self.atoms_per_particle} (insertion or loss); "
                                          f"see {self.dir / 'screen.txt'}")
        benchlib.progress(f"{self.shape} bed: settled in {result['cpu']:.0f} s CPU")

    def measure_deck(self, steps, rebuild_every_step=False, extra="", integrator=None):
        """From the restart: the same walls, law and integrator (or
        `integrator`), `run steps`."""
        neigh = "neigh_modify every 1 delay 0 check no" if rebuild_every_step else "neigh_modify delay 0"
        return f"""# bench/spherocylinder_cost.py: {self.count} {self.shape}s, settled bed
atom_modify map array
read_restart {self.restart}
newton off
communicate single vel yes
neighbor {self.skin!r} bin
{neigh}
{materials(self.law, self.model)}{walls(self.shape)}fix gravity all gravity {G!r} vector 0 0 -1
{integrator or INTEGRATOR[self.shape]}timestep {self.grains.dt!r}
thermo_style custom step atoms ke
thermo {max(steps, 1)}
thermo_modify lost ignore norm no
{extra}run {steps}
"""

    def count_deck(self):
        if self.shape == "rod":
            columns = "id x y z c_axis[1] c_axis[2] c_axis[3]"
            extra = "compute axis all spherocylinder/axis\n"
        else:
            columns = "id x y z radius"
            extra = ""
        fmt = "%d" + " %.17g" * (len(columns.split()) - 1)
        extra += (f"dump grains all custom 1 grains.dump {columns}\n"
                  f"dump_modify grains sort id format \"{fmt}\"\n")
        return self.measure_deck(0, extra=extra)


# ---- contacts from the geometry ---------------------------------------------------

def segment_distances(p1, q1, p2, q2):
    """Distances between the segments p1-q1 and p2-q2 (rows), each of
    nonzero length: closest points by the clamped parametric solution."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    b = np.einsum("ij,ij->i", d1, d2)
    c = np.einsum("ij,ij->i", d1, r)
    f = np.einsum("ij,ij->i", d2, r)
    denom = a * e - b * b
    safe = np.where(denom > 1e-14 * a * e, denom, 1.0)
    s = np.where(denom > 1e-14 * a * e, np.clip((b * f - c * e) / safe, 0, 1), 0.0)
    t = (b * s + f) / e
    s = np.where(t < 0, np.clip(-c / a, 0, 1), np.where(t > 1, np.clip((b - c) / a, 0, 1), s))
    t = np.clip(t, 0, 1)
    return np.linalg.norm(p1 + d1 * s[:, None] - p2 - d2 * t[:, None], axis=1)


def count_contacts(bed, dump_path):
    """Pair counts per particle at the start of the window: `broad` pairs
    of bounding spheres that overlap (rods: centres closer than L),
    `contacts` pairs that touch; clumps also `clump_contacts`, distinct
    pairs of clumps that touch."""
    _, c = read_dump(dump_path)[0]
    x = np.column_stack([c["x"], c["y"], c["z"]])
    if bed.shape == "rod":
        axis = np.column_stack([c["c_axis[1]"], c["c_axis[2]"], c["c_axis[3]"]])
        half_core = (LENGTH - bed.grains.rod_d) / 2
        pairs = np.array(sorted(cKDTree(x).query_pairs(LENGTH)), dtype=int).reshape(-1, 2)
        i, j = pairs[:, 0], pairs[:, 1]
        distance = segment_distances(x[i] - half_core * axis[i], x[i] + half_core * axis[i],
                                     x[j] - half_core * axis[j], x[j] + half_core * axis[j])
        return {"broad": len(pairs) / bed.count, "contacts": int(np.sum(distance < bed.grains.rod_d)) / bed.count}
    radius = c["radius"]
    pairs = np.array(sorted(cKDTree(x).query_pairs(2 * radius.max())), dtype=int).reshape(-1, 2)
    i, j = pairs[:, 0], pairs[:, 1]
    touching = np.linalg.norm(x[i] - x[j], axis=1) < radius[i] + radius[j]
    if bed.shape == "sphere":
        return {"broad": int(np.sum(touching)) / bed.count, "contacts": int(np.sum(touching)) / bed.count}
    # clumps: insert/pack gives each clump's spheres consecutive IDs
    n = bed.grains.clump_spheres
    body = (c["id"].astype(int) - 1) // n
    check_clumps(x, body, n, LENGTH - bed.grains.rod_d)
    between = touching & (body[i] != body[j])
    clump_pairs = {tuple(sorted(p)) for p in zip(body[i][between], body[j][between])}
    return {"broad": None, "contacts": int(np.sum(between)) / bed.count,
            "clump_contacts": len(clump_pairs) / bed.count}


def check_clumps(x, body, n, core):
    """The spheres given one clump by their IDs are n, and the two farthest
    apart are the core length apart (else the ID rule above is wrong)."""
    for k in np.unique(body):
        members = x[body == k]
        span = max(np.linalg.norm(members - p, axis=1).max() for p in members)
        if len(members) != n or abs(span - core) > 1e-6 * core:
            raise RuntimeError(f"clump {k}: {len(members)} spheres spanning {span:.6g} m, expected {n} "
                               f"spanning {core:.6g} m: the clumps' spheres do not have consecutive IDs")


# ---- running under callgrind --------------------------------------------------------

COLLECTED = re.compile(r"Collected : (\d+)")
NEIGHBOURS = re.compile(r"^Total # of neighbors = (\d+)", re.MULTILINE)
BUILDS = re.compile(r"^Neighbor list builds = (\d+)", re.MULTILINE)


def run_counted(deck, workdir, binary):
    """Runs `deck` under callgrind; returns the instruction total, the
    screen output and the profile's path."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    profile = workdir / "callgrind.out"
    command = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={profile}",
               str(binary), "-in", "in.deck", "-log", "none"]
    with open(workdir / "screen.txt", "w") as screen, open(workdir / "valgrind.txt", "w") as log:
        process = subprocess.Popen(command, cwd=workdir, stdout=screen, stderr=log)
        _, status, usage = os.wait4(process.pid, 0)
    code = os.waitstatus_to_exitcode(status)
    output = (workdir / "screen.txt").read_text(errors="replace")
    report = (workdir / "valgrind.txt").read_text(errors="replace")
    errors = [line for line in (output + report).splitlines() if "ERROR" in line]
    collected = COLLECTED.search(report)
    if code != 0 or errors or not collected:
        tail = "\n".join(output.splitlines()[-10:])
        raise benchlib.LiggghtsFailed(f"{binary} under callgrind failed in {workdir}: "
                                      f"{errors[0] if errors else 'exit code %d' % code}\n{tail}")
    return {"instructions": int(collected.group(1)), "output": output, "profile": profile,
            "cpu": usage.ru_utime + usage.ru_stime}


def last_int(pattern, output):
    found = pattern.findall(output)
    return int(found[-1]) if found else None


def last_run_steps(output):
    """Steps between the first and the last thermo line of the last run (a
    run stopped early, by a signal say, still reports the steps it was
    asked for in its Loop time line)."""
    lines = output[:output.rindex("Loop time")].splitlines()
    header = max(k for k, line in enumerate(lines) if line.split()[:1] == ["Step"])
    steps = [int(line.split()[0]) for line in lines[header + 1:]
             if line.split()[:1] and line.split()[0].isdigit()]
    return steps[-1] - steps[0]


def check_complete(output, steps, where):
    done = last_run_steps(output)
    if done != steps:
        raise benchlib.LiggghtsFailed(f"{where}: the last run made {done} of its {steps} steps "
                                      f"(interrupted?)")


def final_ke(output):
    """KinEng of the last thermo line before the last Loop time."""
    lines = output[:output.rindex("Loop time")].splitlines()
    rows = [line.split() for line in lines if line.split()[:1] and line.split()[0].isdigit()]
    return rows[-1][2] if rows else "?"


# The profile split: inclusive instructions of these functions (the rest is
# "other": communication, exchange, output, pre/post neighbour hooks).
CATEGORIES = [
    ("pair", ["LAMMPS_NS::PairGran::compute(int, int)"]),
    ("integration", ["LAMMPS_NS::Modify::initial_integrate(int)", "LAMMPS_NS::Modify::final_integrate()"]),
    ("post_force", ["LAMMPS_NS::Modify::post_force(int)"]),
    ("neighbour", ["LAMMPS_NS::Neighbor::decide()", "LAMMPS_NS::Neighbor::build(int)"]),
]
ANNOTATE_LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(.*)$")


def profile_functions(profile, inclusive):
    """function name -> instructions, from callgrind_annotate."""
    command = ["callgrind_annotate", f"--inclusive={'yes' if inclusive else 'no'}", "--threshold=100", str(profile)]
    text = subprocess.run(command, capture_output=True, text=True, check=True).stdout
    functions = {}
    for line in text.splitlines():
        match = ANNOTATE_LINE.match(line)
        if not match or "PROGRAM TOTALS" in line:
            continue
        name = match.group(2)
        name = re.sub(r" \[[^\]]*\]$", "", name)          # the object file
        name = re.sub(r"^(\?\?\?|[^\s:()]+):", "", name)    # the source file
        functions[name] = functions.get(name, 0) + int(match.group(1).replace(",", ""))
    return functions


def window(short, long, steps):
    """Per-step costs of the window from the runs to N and to 2N steps."""
    per_step = (long["instructions"] - short["instructions"]) / steps
    inclusive = [profile_functions(r["profile"], True) for r in (short, long)]
    parts = {}
    for name, functions in CATEGORIES:
        parts[name] = sum(inclusive[1].get(f, 0) - inclusive[0].get(f, 0) for f in functions) / steps
    parts["other"] = per_step - sum(parts.values())
    builds = [last_int(BUILDS, r["output"]) or 0 for r in (short, long)]
    return {"per_step": per_step, "parts": parts, "neighbours": last_int(NEIGHBOURS, long["output"]),
            "builds": builds[1] - builds[0], "ke": final_ke(long["output"]),
            "cpu": short["cpu"] + long["cpu"], "runs": (short["instructions"], long["instructions"])}


def measure(label, deck, binary, steps, workdir, exclusive=False):
    """Instructions per step of the window N..2N of `deck(steps)`'s last run;
    with `exclusive`, also each function's own instructions in both runs."""
    runs = []
    for n in (steps, 2 * steps):
        runs.append(run_counted(deck(n), workdir / f"steps{n}", binary))
        check_complete(runs[-1]["output"], n, workdir / f"steps{n}")
    result = window(runs[0], runs[1], steps)
    result["atoms"] = int(benchlib.LOOP_TIME.findall(runs[1]["output"])[-1][3])
    if exclusive:
        result["exclusive"] = [profile_functions(r["profile"], False) for r in runs]
    benchlib.progress(f"{label}: {result['per_step']:,.0f} instructions per step "
                      f"({result['per_step'] / result['atoms']:,.0f} per atom), "
                      f"{result['neighbours']} list pairs, {result['builds']} builds in the window, "
                      f"{result['cpu']:.0f} s CPU")
    return result


def function_changes(before, after, steps, atoms, top=6):
    """The functions whose own (exclusive) instructions per step changed
    most between the two binaries, per atom-step."""
    def per_step(result, name):
        short, long = result["exclusive"]
        return (long.get(name, 0) - short.get(name, 0)) / steps
    # LIGGGHTS' own functions (C++ names): libc's string and thread
    # functions differ between the runs' set-ups by a few instructions
    names = {n for n in set(before["exclusive"][1]) | set(after["exclusive"][1]) if "::" in n}
    changes = [(per_step(after, n) - per_step(before, n), per_step(before, n), per_step(after, n), n)
               for n in names]
    changes.sort(key=lambda c: -abs(c[0]))
    return [(name, b / atoms, a / atoms, d / atoms) for d, b, a, name in changes[:top] if abs(d) >= 0.1 * atoms]


# ---- wall-clock mode -----------------------------------------------------------------

def wall_seconds(deck, binary, steps, workdir):
    """Loop time of the last run: (t(2N) - t(N)) / N per step."""
    times = []
    for n in (steps, 2 * steps):
        result = benchlib.run_deck(deck(n), workdir / f"steps{n}", binary=binary)
        check_complete(result["output"], n, workdir / f"steps{n}")
        times.append(result["loops"][-1][0])
    return (times[1] - times[0]) / steps, result["loops"][-1][2]


# ---- the three parts -------------------------------------------------------------------

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
    if args.before.exists():
        try:
            for name, (label, deck, binary) in stock_measurements(args).items():
                results[name] = measure(label, deck, binary, args.stock_steps, work / "stock" / name,
                                        exclusive=True)
        except benchlib.LiggghtsFailed as problem:
            failures["stock"] = str(problem)
            benchlib.progress(f"(a): FAILED: {str(problem).splitlines()[0]}")
    else:
        failures["stock"] = f"the before binary {args.before} is missing (--before)"
        benchlib.progress(f"(a) skipped: {failures['stock']}")
    before = args.before if args.before.exists() else None
    for shape, bed in beds.items():
        try:
            bed.settle()
            counts_dir = bed.dir / "count"
            benchlib.run_deck(bed.count_deck(), counts_dir)
            bed.counts = count_contacts(bed, counts_dir / "grains.dump")
        except (benchlib.LiggghtsFailed, RuntimeError) as problem:
            failures[shape] = str(problem)
            benchlib.progress(f"{shape}: FAILED: {str(problem).splitlines()[0]}")
            continue
        for name, (label, deck, binary) in bed_measurements({shape: bed}, args.rebuild_steps, before).items():
            steps = args.rebuild_steps if name.endswith("_rebuild") else args.steps
            try:
                results[name] = measure(label, deck, binary, steps, work / "beds_measured" / name,
                                        exclusive=name.startswith("sphere"))
            except benchlib.LiggghtsFailed as problem:
                failures[name] = str(problem)
                benchlib.progress(f"{name}: FAILED: {str(problem).splitlines()[0]}")
    return results, failures


def run_wall(args, grains, beds, work):
    """name -> list of seconds per step over repetitions."""
    items = {}
    if args.before.exists():
        items.update(stock_measurements(args))
    for shape, bed in beds.items():
        bed.settle()
    items.update(bed_measurements(beds, 0, args.before if args.before.exists() else None))
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


# ---- report ------------------------------------------------------------------------------

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
        f"### (a) Spheres, before and after the rods (`bench/stock_speed.py`'s deck)",
        "",
        f"The stock deck of `bench/stock_speed.py` (Hertz, tangential history, spheres of "
        f"radius 2.5 and 3 mm, a box of six walls) at volume fraction {args.volume_fraction}; "
        f"windows of {args.stock_steps} steps: **falling**, steps {args.stock_steps}–{2 * args.stock_steps} "
        f"after the insertion (the deck as it is, `run N` and `run 2N`), and **settled**, the "
        f"deck run to {args.stock_settle} steps and then `run N` / `run 2N` appended. "
        f"*before*: `{args.before}` (the commit before the rods, without "
        f"NONSPHERICAL_ACTIVE_FLAG); *after*: `build/bin/liggghts`.",
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
        changes = function_changes(before, after, steps, after["atoms"])
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
    parts = [f"## Instructions per step (`bench/spherocylinder_cost.py`)", "",
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
              f"- before binary: {benchlib.binary_identity(args.before) if args.before.exists() else 'missing'}",
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


def write_page_section(path, name, markdown):
    begin, end = f"<!-- BEGIN {name} -->", f"<!-- END {name} -->"
    text = path.read_text() if path.exists() else PAGE_HEADER
    if begin not in text:
        text = text.rstrip("\n") + f"\n\n{begin}\n{end}\n"
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"{head}{begin}\n{markdown.strip()}\n{end}{tail}")


# ---- main ------------------------------------------------------------------------------

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
    parser.add_argument("--before", type=Path, default=BEFORE_BINARY,
                        help="the binary built before the rods (read only; env SILOKIT_LIGGGHTS_BEFORE)")
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
        text = wall_section(seconds, atoms, args)
        raw = "# name atoms seconds_per_step...\n" + "".join(
            f"{name} {atoms[name]} " + " ".join(f"{v:.6g}" for v in values) + "\n"
            for name, values in seconds.items())
    else:
        results, failures = run_instruction_counts(args, grains, beds, work)
        end_cpu = os.times()
        elapsed = {"wall": time.perf_counter() - start_wall,
                   "cpu": sum(getattr(end_cpu, k) - getattr(start_cpu, k)
                              for k in ("user", "system", "children_user", "children_system"))}
        text = section(results, failures, beds, grains, args, elapsed)
        raw = raw_text(results, failures, beds, grains, args)
    # the binary can be rebuilt while this runs: then the numbers mix two builds
    if benchlib.binary_identity(benchlib.OUR_BINARY) != ours_at_start:
        warning = f"WARNING: build/bin/liggghts changed during the measurement (at the start: {ours_at_start})"
        benchlib.progress(warning)
        text += f"\n- {warning}"
        raw += f"# {warning}\n"
    name = SECTION + ("_wall" if args.wall else "")
    write_page_section(page, name, text)
    path = benchlib.write_raw(name, raw)
    benchlib.progress(f"wrote {page} and {path}")
    print(text)


if __name__ == "__main__":
    main()
