"""The grains of bench/spherocylinder_cost.py and their beds: rods (L = 20
mm, L/d = 3.3, rho = 620 kg/m^3, the contact law of
inputs/silo3d_rotating/in.silo3d_rotating -var shape rod), spheres of the
volume-equivalent diameter and clumps of glued spheres; their contact
times; the decks that settle a bed in a box of five planes (cached under a
hash of the deck) and measure it from its restart file; and the contacts
of a dumped bed, counted from its geometry."""

import hashlib
import math

import numpy as np
from scipy.spatial import cKDTree

import benchlib
import core_geometry
from analysis.common.lammps_io import read_dump

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
        self.rod_mass, self.rod_axial, self.rod_transverse = core_geometry.solid_rod(self.rod_d, LENGTH, RHO)
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


# ---- contacts from the geometry (rods: the core header, core_geometry.py) ----------

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
        touching = core_geometry.rods_touching(x[i], axis[i], x[j], axis[j], half_core, bed.grains.rod_d / 2)
        return {"broad": len(pairs) / bed.count, "contacts": int(np.sum(touching)) / bed.count}
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
