"""rolling_friction jiang, test (g): an isolated system of discs with sliding
friction and rolling resistance never gains energy over 10^6 steps.

16 discs in a fully periodic 2D box, no gravity, no walls, no normal or
tangential damping (gamman = gammat = 0), so that the only sinks are the
friction cap of `tangential history`, the cap of the rolling spring and the
springs forgotten when a contact opens. Two configurations:

- "gas": a dilute bidisperse gas, random velocities and spins, short
  collisions that open and close all the time;
- "lattice": a pre-compressed hexagonal crystal, every disc touching six
  neighbours for the whole run, so that the rolling springs stay loaded and
  exchange energy with the spins all along.

The energy is everything the engine integrates and stores:

    E = sum_i 1/2 m_i v_i^2 + 1/2 I_i w_i^2                       (grains)
      + sum_c 1/2 k_n d_n^2 + 1/2 k_t |xi|^2 + 1/2 k_r |delta_r|^2 (contacts)

with, in 2D, m = pi r^2 rho (set.cpp, atom_vec_sphere.cpp: the mass is
dumped and checked) and I = 1/2 m r^2 (fix_nve_sphere.cpp integrates
d omega/dt = torque / (0.5 m r^2) when dimension == 2; note that
`compute erotate/sphere` would use 0.4 m r^2, so it is not used here).
xi (shearx/y/z) and delta_r (jiang_rolling_angle_x/y/z) are the contact
history dumped by `compute pair/gran/local id history delta`.

Velocity Verlet does not conserve E exactly: while grains are in contact the
sampled E oscillates about the conserved "shadow" energy by a relative
amount of order (omega dt)^2/4, and stick-slip transitions and contacts that
open or close add errors of the same order that do not cancel. With
dt = t_c/50 (gas), (omega_n dt)^2/4 = (pi/50)^2/4 = 1e-3; the crystal, whose
fastest modes are a few times faster than a pair collision, uses t_c/100.
The tolerances below are set from that estimate, the measured rises are far
below them, and they are checked to be small against what the rolling model
moves (test_lattice_bookkeeping_resolves_rolling_spring): a rolling torque
that created energy (wrong sign, torque on j not opposite to that on i,
history not capped, spring not reset, ...) would show rises far above them.

With contactLengthFromOverlap on, k_r = k_n l_c(d_n)^2 changes with the
overlap while no normal force acts back on it, so 1/2 k_r |delta_r|^2 is no
potential: the model's rule for a changing stiffness (the torque stays when
k_r grows, drops with it when k_r falls) makes every such change release
energy. The vibrating crystal, whose 48 contacts never open, checks it
(measured: largest rise 1.6e-4 of the free energy, 2.6 % of it left).
"""

import math

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

KN = 1.0e5
KT = 2.0 / 7.0 * KN
MU = 0.5
DENSITY = 2500.0
STEPS = 1_000_000
EVERY = 1000

# contact-dump layout: id (3 values), history, delta. The history is in the
# order in which the sub-models register their values: tangential history
# (shearx/y/z), then rolling (jiang_rolling_angle_x/y/z, jiang_last_step,
# jiang_stiffness). Checked below: in 2D the shear has no z and the rolling
# angle only z, jiang_last_step is the step of the sample for every contact,
# and jiang_stiffness is k_r = k_n l_c^2 of the contact's geometry.
COLUMNS = ["id1", "id2", "periodic", "shearx", "sheary", "shearz",
           "rollx", "rolly", "rollz", "rollstep", "rollstiffness", "delta"]


def disc_mass(radius):
    return math.pi * radius ** 2 * DENSITY


def contact_time(radius):
    """Duration of a Hooke collision of two discs of this radius."""
    return math.pi * math.sqrt(0.5 * disc_mass(radius) / KN)


def num(value):
    """A number as LIGGGHTS input, all its digits (also for numpy scalars)."""
    return repr(float(value))


def energy_deck(box, positions, radii, velocities, spins, rolling_settings, properties,
                dt, steps=STEPS, every=EVERY, output=None):
    atoms = "\n".join(f"create_atoms 1 single {num(x)} {num(y)} 0 units box"
                      for x, y in positions)
    sets = "\n".join(
        f"set atom {k + 1} diameter {num(2 * r)} density {num(DENSITY)} "
        f"vx {num(v[0])} vy {num(v[1])} omegaz {num(w)}"
        for k, (r, v, w) in enumerate(zip(radii, velocities, spins)))
    columns = " ".join(f"c_pgl[{k + 1}]" for k in range(len(COLUMNS)))
    doubles = " ".join(["%.17g"] * len(COLUMNS))
    if output is None:
        output = f"""
dump atoms all custom {every} dump.atoms id mass radius vx vy vz omegax omegay omegaz
dump_modify atoms format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
dump contacts all local {every} dump.contacts {columns}
dump_modify contacts format "{doubles}"
run {steps}
"""
    return f"""
{granular_setup(dimension=2, boundary="p p p")}
region box block 0 {num(box[0])} 0 {num(box[1])} -0.01 0.01 units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{hooke_materials(KN, KT, mu=MU)}
{properties}
pair_style gran model hooke/stiffness tangential history rolling_friction jiang {rolling_settings}
pair_coeff * *
timestep {num(dt)}
{atoms}
{sets}
fix integ all nve/sphere
fix flat all enforce2d
compute pgl all pair/gran/local id history delta
thermo_style custom step atoms ke
thermo 100000
{output}
"""


def chord(radius_i, radius_j, distance):
    """Common chord of two circles: l_c of contactLengthFromOverlap on."""
    x = (distance ** 2 + radius_i ** 2 - radius_j ** 2) / (2 * distance)
    return 2 * np.sqrt(np.maximum(radius_i ** 2 - x ** 2, 0.0))


class Ledger:
    """Energy components of every sampled frame, and the per-contact
    quantities the checks need."""

    def __init__(self, workdir, n_atoms, fixed_length=None, inertia_factor=0.5):
        atoms = read_dump(workdir / "dump.atoms")
        contacts = read_dump(workdir / "dump.contacts")
        assert [s for s, _ in atoms] == [s for s, _ in contacts]
        self.steps = np.array([s for s, _ in atoms])
        rows = []
        self.saturation = []          # k_r |delta_r| / (mu_r f_el), per contact
        self.out_of_plane = 0.0       # |shearz| and |rollx|,|rolly| (must be 0 in 2D)
        self.n_contacts = []
        for (step, a), (_, c) in zip(atoms, contacts):
            # no atom lost or duplicated, nothing NaN
            assert np.array_equal(a["id"], np.arange(1, n_atoms + 1)), step
            assert all(np.all(np.isfinite(v)) for v in a.values()), step
            mass, radius = a["mass"], a["radius"]
            translation = 0.5 * mass * (a["vx"] ** 2 + a["vy"] ** 2 + a["vz"] ** 2)
            spin = 0.5 * inertia_factor * mass * radius ** 2 * (
                a["omegax"] ** 2 + a["omegay"] ** 2 + a["omegaz"] ** 2)
            normal = tangential = rolling = 0.0
            count = len(c.get("c_pgl[1]", []))
            self.n_contacts.append(count)
            if count:
                col = {name: c[f"c_pgl[{k + 1}]"] for k, name in enumerate(COLUMNS)}
                assert all(np.all(np.isfinite(v)) for v in col.values()), step
                if step > 0:
                    assert np.all(col["rollstep"] == step), step
                i = col["id1"].astype(int) - 1
                j = col["id2"].astype(int) - 1
                overlap = col["delta"]
                shear = np.stack([col["shearx"], col["sheary"], col["shearz"]], axis=1)
                angle = np.sqrt(col["rollx"] ** 2 + col["rolly"] ** 2 + col["rollz"] ** 2)
                self.out_of_plane = max(self.out_of_plane, np.abs(col["shearz"]).max(),
                                        np.abs(col["rollx"]).max(), np.abs(col["rolly"]).max())
                if fixed_length is None:
                    length = chord(radius[i], radius[j], radius[i] + radius[j] - overlap)
                else:
                    length = fixed_length
                k_r = KN * length ** 2
                if step > 0:
                    np.testing.assert_allclose(col["rollstiffness"], k_r, rtol=1e-9)
                normal = 0.5 * KN * np.sum(overlap ** 2)
                tangential = 0.5 * KT * np.sum(shear ** 2)
                rolling = 0.5 * np.sum(k_r * angle ** 2)
                limit = MU * length * KN * overlap
                self.saturation.extend(k_r * angle / limit)
            rows.append((translation.sum(), spin.sum(), normal, tangential, rolling))
        self.parts = np.array(rows)
        self.saturation = np.array(self.saturation)
        self.mass = atoms[0][1]["mass"]
        self.radius = atoms[0][1]["radius"]

    def total(self, without=()):
        names = ["translation", "spin", "normal", "tangential", "rolling"]
        keep = [k for k, name in enumerate(names) if name not in without]
        return self.parts[:, keep].sum(axis=1)


# ---------------------------------------------------------------- gas

GAS_BOX = 0.06
GAS_RADII = (0.0045, 0.0055)
GAS_FIXED_LENGTH = 0.0045          # l_c = half the smaller diameter
GAS_DT = contact_time(GAS_RADII[0]) / 50
GAS_TOLERANCE = 1e-3


def largest_rise(energy):
    """Largest amount by which E exceeds its lowest earlier value, relative
    to that value: 0 for a system that never gains energy."""
    lowest_so_far = np.minimum.accumulate(energy)
    return ((energy - lowest_so_far) / lowest_so_far).max()


def gas_configuration(seed=1):
    rng = np.random.default_rng(seed)
    n = 4
    spacing = GAS_BOX / n
    positions = [((ix + 0.5) * spacing + rng.uniform(-0.002, 0.002),
                  (iy + 0.5) * spacing + rng.uniform(-0.002, 0.002))
                 for ix in range(n) for iy in range(n)]
    radii = rng.choice(GAS_RADII, n * n)
    velocities = rng.normal(0.0, 0.3, (n * n, 2))
    # no net momentum: the centre-of-mass motion could never be dissipated
    masses = np.array([disc_mass(r) for r in radii])
    velocities -= (masses[:, None] * velocities).sum(axis=0) / masses.sum()
    spins = rng.normal(0.0, 100.0, n * n)     # |w r| ~ |v|
    return positions, radii, velocities, spins


def rolling_input(mode, fixed_length):
    if mode == "fixed":
        return "", per_pair("rollingContactLength", fixed_length)
    return "contactLengthFromOverlap on", ""


@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_gas_never_gains_energy(run, tmp_path, mode):
    positions, radii, velocities, spins = gas_configuration()
    settings, properties = rolling_input(mode, GAS_FIXED_LENGTH)
    output = run(energy_deck((GAS_BOX, GAS_BOX), positions, radii, velocities, spins,
                             settings, properties, GAS_DT))
    assert "16 atoms" in output
    ledger = Ledger(tmp_path, 16, GAS_FIXED_LENGTH if mode == "fixed" else None)
    energy = ledger.total()

    # the engine's 2D mass is what the ledger assumes (pi r^2 rho)
    np.testing.assert_allclose(ledger.mass, math.pi * ledger.radius ** 2 * DENSITY, rtol=1e-12)
    assert len(energy) == STEPS // EVERY + 1
    # 2D: spring vectors in the plane (shear) and along z (rolling angle);
    # also confirms that the history columns are the ones named in COLUMNS
    assert ledger.out_of_plane < 1e-20
    # the rolling model took part: its spring held energy, it saturated at
    # some sampled contact, and it never exceeded its cap mu_r f_el
    assert (ledger.parts[:, 4] / energy).max() > 1e-3      # measured 5e-3, 1.5e-2
    assert ledger.saturation.max() == pytest.approx(1.0, rel=1e-9)
    assert ledger.saturation.max() <= 1.0 + 1e-9
    assert ledger.saturation.min() < 0.5

    # never above the start, and never above any earlier sample by more than
    # the integration error (1e-3 of E, (omega_n dt)^2/4; the measured
    # largest rises are 3.9e-5 (fixed) and 4.3e-5 (overlap) of E)
    assert energy.max() <= energy[0] * (1 + 1e-9)
    assert largest_rise(energy) < GAS_TOLERANCE, largest_rise(energy)
    # that tolerance resolves the bookkeeping: with the inertia of spheres
    # (0.4 m r^2, not what fix nve/sphere integrates in 2D) the same check
    # fails (measured rises 9e-3 and 1.5e-2)
    assert largest_rise(energy - 0.2 * ledger.parts[:, 1]) > 3 * GAS_TOLERANCE
    # and friction plus rolling resistance dissipate nearly all of it
    # (measured: E_end/E_0 ~ 1e-5)
    assert energy[-1] < 1e-2 * energy[0]


# ------------------------------------------------------------ lattice

LATTICE_RADIUS = 0.005
LATTICE_OVERLAP = 1.0e-4           # 1 % of d, at each of the 48 contacts
LATTICE_CONTACTS = 48
LATTICE_FIXED_LENGTH = 0.005       # l_c = r
# Finer than the gas: the crystal's fastest modes (six neighbours, rolling
# springs k_n r^2 against I = m r^2/2) are a few times faster than a pair
# collision, and its stick-slip transitions never stop. Measured largest
# rise above the running minimum, relative to the free energy left:
# 2.1e-2 at t_c/50, 1.5e-3 at t_c/100, 1.6e-4 at t_c/200 -- it vanishes with
# dt (faster than dt^2), so it is integration error, not a source in the model.
LATTICE_DT = contact_time(LATTICE_RADIUS) / 100
LATTICE_TOLERANCE = 1e-2


def lattice_configuration(seed=2):
    """4 x 4 hexagonal crystal, lattice constant d - overlap, periodic."""
    rng = np.random.default_rng(seed)
    a = 2 * LATTICE_RADIUS - LATTICE_OVERLAP
    nx, ny = 4, 4
    box = (nx * a, ny * a * math.sqrt(3) / 2)
    positions = [((ix + 0.5 * (iy % 2) + 0.25) * a, (iy + 0.5) * a * math.sqrt(3) / 2)
                 for iy in range(ny) for ix in range(nx)]
    n = nx * ny
    # velocities well below overlap * omega_n (~0.1 m/s): contacts stay closed
    velocities = rng.normal(0.0, 0.02, (n, 2))
    velocities -= velocities.mean(axis=0)
    spins = rng.normal(0.0, 50.0, n)
    radii = [LATTICE_RADIUS] * n
    return box, positions, radii, velocities, spins


def lattice_deck(mode, **kwargs):
    box, positions, radii, velocities, spins = lattice_configuration()
    settings, properties = rolling_input(mode, LATTICE_FIXED_LENGTH)
    return energy_deck(box, positions, radii, velocities, spins, settings, properties,
                       LATTICE_DT, **kwargs)


# Energy of the crystal at rest, its 48 normal springs at the initial
# overlap: the part of E that cannot be dissipated. E - this is the "free"
# energy, the scale of everything that moves.
LATTICE_REST_ENERGY = LATTICE_CONTACTS * 0.5 * KN * LATTICE_OVERLAP ** 2


def largest_relative_rise(energy):
    """Largest amount by which E exceeds its lowest earlier value, relative to
    the free energy left at that lowest value."""
    lowest_so_far = np.minimum.accumulate(energy)
    return ((energy - lowest_so_far) / (lowest_so_far - LATTICE_REST_ENERGY)).max()


def check_lattice_preconditions(ledger, stays_closed=True, saturates=True):
    # all 48 contacts stay closed all along: the rolling springs are never
    # reset by an opening contact, they are loaded and unloaded in place
    if stays_closed:
        assert min(ledger.n_contacts) == max(ledger.n_contacts) == LATTICE_CONTACTS
    assert ledger.out_of_plane < 1e-20
    assert (ledger.parts[1:, 4] > 0).all()
    # the cap is respected, and reached (at the start, when the spins are
    # fast) at some sampled contact where the samples happen to catch it
    assert ledger.saturation.max() <= 1.0 + 1e-9
    if saturates:
        assert ledger.saturation.max() == pytest.approx(1.0, rel=1e-9)


@pytest.fixture(scope="module")
def fixed_lattice(tmp_path_factory, liggghts_binary):
    from conftest import run_liggghts
    workdir = tmp_path_factory.mktemp("lattice_fixed")
    run_liggghts(lattice_deck("fixed"), workdir)
    return Ledger(workdir, 16, LATTICE_FIXED_LENGTH)


def test_lattice_never_gains_energy(fixed_lattice):
    ledger = fixed_lattice
    energy = ledger.total()
    free = energy[0] - LATTICE_REST_ENERGY
    check_lattice_preconditions(ledger)

    assert energy.max() <= energy[0] * (1 + 1e-9)
    assert largest_relative_rise(energy) < LATTICE_TOLERANCE, largest_relative_rise(energy)
    # most of the free energy goes (measured: 93 %); what is left is a
    # vibration whose tangential and rolling springs no longer slip
    assert energy[-1] - LATTICE_REST_ENERGY < 0.3 * free


def test_lattice_bookkeeping_resolves_rolling_spring(fixed_lattice):
    """The tolerance above is small against what the rolling model stores
    and moves: leave its spring out of the bookkeeping (measured rise 0.21),
    or give the discs the inertia of spheres, 0.4 m r^2, which fix nve/sphere
    does not use in 2D (measured 0.087), and the check above fails."""
    ledger = fixed_lattice
    assert largest_relative_rise(ledger.total(without=("rolling",))) > 5 * LATTICE_TOLERANCE
    spin = ledger.parts[:, 1]
    assert largest_relative_rise(ledger.total() - 0.2 * spin) > 3 * LATTICE_TOLERANCE


def test_lattice_overlap_mode_never_gains_energy(run, tmp_path):
    """With l_c from the overlap, k_r = k_n l_c(d_n)^2 follows the normal
    vibration of every contact of the crystal. Storing the angle alone, a
    loaded spring would gain 1/2 |delta_r|^2 dk_r whenever k_r grows, with no
    work done on the grains, and the vibrating crystal would pump its normal
    vibration into the spins (measured before the rule below: the free
    energy climbed back to 7.4 times its lowest value and contacts opened).
    The model's rule (silokit::jiang::adapt_to_stiffness: when k_r grows the
    angle shrinks so that the torque stays; when it drops the torque drops)
    makes every stiffness change release energy, never add it: the same
    strict check as for the fixed length holds (measured rise 1.6e-4)."""
    run(lattice_deck("overlap"))
    ledger = Ledger(tmp_path, 16, None)
    check_lattice_preconditions(ledger, saturates=False)
    energy = ledger.total()
    free = energy[0] - LATTICE_REST_ENERGY
    assert energy.max() <= energy[0] * (1 + 1e-9)
    assert largest_relative_rise(energy) < LATTICE_TOLERANCE, largest_relative_rise(energy)
    assert energy[-1] - LATTICE_REST_ENERGY < 0.3 * free
