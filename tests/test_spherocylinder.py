"""Rods: atom_style spherocylinder, set_spherocylinder, surface
spherocylinder, fix nve/spherocylinder, compute spherocylinder/axis, run
by the built LIGGGHTS on decks of one to a few dozen rods.

Expected values come from closed forms (a linear spring of stiffness k_n
pressed by delta gives k_n delta; the torque is the arm to the contact
point crossed with the force; a torque-free symmetric top turns its axis
about the fixed angular momentum L at |L|/I_transverse), from stock
LIGGGHTS (a rod with L = d is a sphere: atom_style sphere and fix
nve/sphere give the same trajectory), or from conservation laws; never
from the styles under test.

Rods: diameter D, length LENGTH end to end (core segment LENGTH - D),
density RHO; contacts hooke/stiffness with tangential history."""

import math

import numpy as np
import pytest

from analysis.common.deck_blocks import hooke_materials
from analysis.common.lammps_io import read_dump
from analysis.testing import LiggghtsError
from conftest import has_mpirun, run_liggghts

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

D = 0.01
LENGTH = 0.03
RHO = 1000.0
KN = 1.0e4
RADIUS = D / 2
HALF_SEGMENT = (LENGTH - D) / 2
SKIN = 0.2 * D         # the neighbour skin of rod_contacts
ROD_MODEL = "model hooke/stiffness tangential history surface spherocylinder"
SPHERE_MODEL = "model hooke/stiffness tangential history"


def solid_rod(d=D, length=LENGTH, rho=RHO):
    """Mass and principal moments (axial, transverse) of a solid
    spherocylinder, written out independently of the C++ header: cylinder
    of length a = L - d plus a sphere split into two hemispheres whose
    centres of mass sit 3r/8 beyond the cylinder's ends."""
    r = d / 2
    a = length - d
    m_cyl = rho * math.pi * r * r * a
    m_sph = rho * 4.0 / 3.0 * math.pi * r ** 3
    axial = m_cyl * r * r / 2 + m_sph * 2 * r * r / 5
    # a hemisphere about its own centre of mass (transverse): 83/320 m r^2
    hemi = m_sph / 2
    transverse = (m_cyl * (r * r / 4 + a * a / 12)
                  + 2 * (83.0 / 320.0 * hemi * r * r + hemi * (a / 2 + 3 * r / 8) ** 2))
    return m_cyl + m_sph, axial, transverse


def rod_lines(index, position, axis, velocity=(0, 0, 0), omega=(0, 0, 0), d=D, length=LENGTH):
    x, y, z = position
    vx, vy, vz = velocity
    return f"""create_atoms 1 single {x!r} {y!r} {z!r} units box
group rod{index} id {index}
set_spherocylinder rod{index} diameter {d!r} length {length!r} density {RHO!r} axis {axis[0]!r} {axis[1]!r} {axis[2]!r} omega {omega[0]!r} {omega[1]!r} {omega[2]!r}
velocity rod{index} set {vx!r} {vy!r} {vz!r} units box
"""


def rod_system(boundary="f f f"):
    """The opening lines of every rod deck."""
    return f"""units si
atom_style spherocylinder
atom_modify map array
boundary {boundary}
newton off
communicate single vel yes"""


def rod_contacts(dt, gamman=0.0, gammat=0.0, mu=0.5):
    """Neighbour list, materials, the rod pair style and the time step."""
    return f"""neighbor {SKIN!r} bin
neigh_modify delay 0
{hooke_materials(KN, 2.0 / 7.0 * KN, gamman=gamman, gammat=gammat, mu=mu)}
pair_style gran {ROD_MODEL}
pair_coeff * *
timestep {dt!r}"""


def rod_deck(rods, steps, dump_every=1, gamman=0.0, gammat=0.0, mu=0.5, dt=1e-6,
             box="-0.1 0.1 -0.1 0.1 -0.1 0.1", boundary="f f f", integrate=True, extra=""):
    """`rods`: list of (position, axis, velocity, omega). Dumps id, x, v,
    omega, angmom, force, torque and the axis (c_axis[1..3]) to rods.dump."""
    atoms = "".join(rod_lines(k + 1, *rod) for k, rod in enumerate(rods))
    integration = "fix move all nve/spherocylinder" if integrate else ""
    return f"""{rod_system(boundary)}
region box block {box} units box
create_box 1 box
{atoms}
{rod_contacts(dt, gamman, gammat, mu)}
{integration}
compute axis all spherocylinder/axis
dump rods all custom {dump_every} rods.dump id x y z vx vy vz omegax omegay omegaz angmomx angmomy angmomz fx fy fz tqx tqy tqz c_axis[1] c_axis[2] c_axis[3]
dump_modify rods sort id format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
{extra}
run {steps}
"""


def frames(tmp_path, name="rods.dump"):
    return read_dump(tmp_path / name)


def vector(columns, prefix, row, names=("x", "y", "z")):
    return np.array([columns[prefix + n][row] for n in names])


# ---- contact geometry against closed forms ------------------------------------

def test_crossing_rods_pressed_together_give_the_spring_force_at_the_crossing_point(run, tmp_path):
    """Rod 1 along x at the origin, rod 2 along y above it, centred over
    x = a, overlapping by delta: the force is k_n delta along z at the
    crossing point (a, 0, r - delta/2); it turns rod 1 about y by
    a k_n delta and leaves rod 2 (pushed through its centre line) alone."""
    delta, a = 1.0e-4, 0.006
    run(rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0)),
                  ((a, 0, D - delta), (0, 1, 0), (0, 0, 0), (0, 0, 0))], steps=0, integrate=False))
    _, c = frames(tmp_path)[0]
    force = KN * delta
    np.testing.assert_allclose(vector(c, "f", 0), [0, 0, -force], atol=1e-12 * force)
    np.testing.assert_allclose(vector(c, "f", 1), [0, 0, force], atol=1e-12 * force)
    np.testing.assert_allclose(vector(c, "tq", 0), [0, a * force, 0], atol=1e-12 * force * D)
    np.testing.assert_allclose(vector(c, "tq", 1), [0, 0, 0], atol=1e-12 * force * D)


@pytest.mark.parametrize("shift", [0.0, 0.004])
def test_parallel_rods_touch_at_the_middle_of_their_overlap(run, tmp_path, shift):
    """Two parallel rods along x, one above the other, the upper one
    shifted by s along its axis: a line contact, taken as one force k_n
    delta at the middle of the overlap of the two segments, x = s/2. With
    s = 0 no torque at all; otherwise each rod turns by (s/2) k_n delta
    about y, and the total angular momentum is conserved (x2 x F2 + the
    two torques = 0)."""
    delta = 2.0e-4
    run(rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0)),
                  ((shift, 0, D - delta), (1, 0, 0), (0, 0, 0), (0, 0, 0))], steps=0, integrate=False))
    _, c = frames(tmp_path)[0]
    force = KN * delta
    np.testing.assert_allclose(vector(c, "f", 0), [0, 0, -force], atol=1e-12 * force)
    for row in (0, 1):
        np.testing.assert_allclose(vector(c, "tq", row), [0, shift / 2 * force, 0],
                                   atol=1e-12 * force * D)


def test_rods_apart_feel_nothing_though_their_bounding_spheres_overlap(run, tmp_path):
    """Two parallel rods side by side, 0.1 d apart: their bounding spheres
    (radius L/2) overlap, the rods do not."""
    run(rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0)),
                  ((0, 0, 1.1 * D), (1, 0, 0), (0, 0, 0), (0, 0, 0))], steps=0, integrate=False))
    _, c = frames(tmp_path)[0]
    assert np.all(np.abs(np.concatenate([c["fx"], c["fy"], c["fz"]])) == 0.0)


def test_end_on_contact_of_collinear_rods(run, tmp_path):
    """Two rods on one line, cap to cap, overlapping by delta: the force is
    along the line, through both centres, no torque."""
    delta = 1.0e-4
    run(rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0)),
                  ((LENGTH - delta, 0, 0), (-1, 0, 0), (0, 0, 0), (0, 0, 0))], steps=0, integrate=False))
    _, c = frames(tmp_path)[0]
    force = KN * delta
    np.testing.assert_allclose(vector(c, "f", 0), [-force, 0, 0], atol=1e-12 * force)
    np.testing.assert_allclose(vector(c, "tq", 0), [0, 0, 0], atol=1e-12 * force * D)


# ---- the rigid body ------------------------------------------------------------

def mass_properties_from_dump(c, row):
    """(axial, transverse) moments the run used, from L and omega in the
    body frame (the axis and two normals to it)."""
    axis = vector(c, "c_axis[", row, names=("1]", "2]", "3]"))
    angmom = vector(c, "angmom", row)
    omega = vector(c, "omega", row)
    axial = angmom @ axis / (omega @ axis)
    l_perp = angmom - (angmom @ axis) * axis
    w_perp = omega - (omega @ axis) * axis
    return axial, np.linalg.norm(l_perp) / np.linalg.norm(w_perp)


def top_run(tmp_path, dt, duration, omega=(3.0, -2.0, 40.0), scheme="symmetric_top"):
    axis = np.array([1.0, 0.0, 0.0])
    deck = rod_deck([((0, 0, 0), tuple(axis), (0, 0, 0), omega)],
                    steps=round(duration / dt), dump_every=round(duration / dt), dt=dt)
    deck = deck.replace("fix move all nve/spherocylinder",
                        f"fix move all nve/spherocylinder integration_scheme {scheme}")
    run_liggghts(deck, tmp_path)
    return frames(tmp_path)


def top_errors(tmp_path, dt, duration, scheme):
    """A rod spun about an axis that is not principal, integrated for
    `duration`: checks its mass properties and the conservation of L, and
    returns (relative energy error, error of the axis) against the free
    symmetric top, whose axis turns about the fixed L at |L|/I_t."""
    mass, axial, transverse = solid_rod()
    (_, start), (_, end) = top_run(tmp_path, dt, duration, scheme=scheme)
    np.testing.assert_allclose(mass_properties_from_dump(start, 0), (axial, transverse), rtol=1e-9)
    angmom = vector(start, "angmom", 0)
    np.testing.assert_allclose(vector(end, "angmom", 0), angmom, rtol=1e-12, atol=1e-12 * np.linalg.norm(angmom))
    energy = [0.5 * vector(f, "angmom", 0) @ vector(f, "omega", 0) for f in (start, end)]
    axis0 = vector(start, "c_axis[", 0, names=("1]", "2]", "3]"))
    axis1 = vector(end, "c_axis[", 0, names=("1]", "2]", "3]"))
    # rotate axis0 about L by |L| T / I_t (Rodrigues)
    unit = angmom / np.linalg.norm(angmom)
    angle = np.linalg.norm(angmom) / transverse * duration
    expected = (axis0 * math.cos(angle) + np.cross(unit, axis0) * math.sin(angle)
                + unit * (unit @ axis0) * (1 - math.cos(angle)))
    return abs(energy[1] / energy[0] - 1), np.linalg.norm(axis1 - expected)


def test_the_no_squish_scheme_turns_a_free_rod_as_a_symmetric_top(tmp_path):
    """integration_scheme 1 (LIGGGHTS' no-squish): L and the energy stay,
    the axis follows the free top with an error that falls as dt^2."""
    errors = [top_errors(tmp_path / f"dt{k}", dt, 0.05, "1") for k, dt in enumerate((4e-5, 2e-5))]
    assert errors[0][1] < 2e-3
    # second order: halving dt divides the axis error by about 4
    assert 3.0 < errors[0][1] / errors[1][1] < 5.0
    assert errors[1][0] < 1e-6


def test_the_symmetric_top_scheme_turns_a_free_rod_exactly(tmp_path):
    """The default scheme moves a torque-free rod by the exact free motion
    of the top: after 1250 steps at a coarse dt (the axis turns 2.7 rad)
    the axis and the energy are right to round-off, where no-squish is
    off by 1e-3 (the test above)."""
    energy_error, axis_error = top_errors(tmp_path, 4e-5, 0.05, "symmetric_top")
    assert axis_error < 1e-11
    assert energy_error < 1e-12


def test_the_integrator_keywords_in_either_order_give_the_same_run(tmp_path):
    """FixNVEAsphereBase knows only its numbered integration_scheme: the
    fix hands it a list of its own with that pair, wherever the pair
    stands among ours (and leaves the deck's list alone). Richardson's
    scheme (0) after prune_list or before it: the same free top, bit for
    bit, and neither LIGGGHTS' default scheme (1, no-squish) nor ours."""
    dumps = {}
    for name, keywords in (("after", "prune_list no integration_scheme 0"),
                           ("before", "integration_scheme 0 prune_list no"),
                           ("no_squish", "prune_list no integration_scheme 1"),
                           ("symmetric_top", "prune_list no")):
        deck = rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (3.0, -2.0, 40.0))],
                        steps=200, dump_every=200, dt=4e-5)
        deck = deck.replace("fix move all nve/spherocylinder\n",
                            f"fix move all nve/spherocylinder {keywords}\n")
        run_liggghts(deck, tmp_path / name)
        dumps[name] = (tmp_path / name / "rods.dump").read_text()
    assert dumps["after"] == dumps["before"]
    assert dumps["after"] != dumps["no_squish"]
    assert dumps["after"] != dumps["symmetric_top"]


def test_a_rod_as_long_as_wide_moves_as_the_stock_sphere(tmp_path):
    """L = d: the rod is a sphere. Two of them colliding off centre with
    spin, damping and friction follow the trajectories of atom_style
    sphere with fix nve/sphere and the stock surface model."""
    rods = [((0, 0, 0), (1, 0, 0), (0.3, 0, 0), (0, 20.0, 5.0)),
            ((0.0105, 0.004, 0.001), (0, 0, 1), (-0.2, 0.05, 0), (10.0, 0, -3.0))]
    steps = 30000
    rod = rod_deck(rods, steps, dump_every=steps, gamman=50.0, gammat=50.0, dt=1e-6)
    rod = rod.replace(f"length {LENGTH!r}", f"length {D!r}")
    run_liggghts(rod, tmp_path / "rod")
    sphere = rod.replace("atom_style spherocylinder", "atom_style sphere")
    sphere = sphere.replace(ROD_MODEL, SPHERE_MODEL).replace("nve/spherocylinder", "nve/sphere")
    sphere = sphere.replace("compute axis all spherocylinder/axis\n", "")
    sphere = sphere.replace(" angmomx angmomy angmomz", "").replace(" c_axis[1] c_axis[2] c_axis[3]", "")
    sphere = "\n".join(
        f"set group {line.split()[1]} diameter {D!r} density {RHO!r}\nset group {line.split()[1]} "
        + " ".join(f"omega{axis} {value}" for axis, value in zip("xyz", line.split("omega ")[1].split()[:3]))
        if line.startswith("set_spherocylinder") else line
        for line in sphere.splitlines())
    sphere = sphere.replace('format "%d' + " %.17g" * 21 + '"', 'format "%d' + " %.17g" * 15 + '"')
    run_liggghts(sphere, tmp_path / "sphere")
    (_, rod_end), = [f for f in frames(tmp_path / "rod") if f[0] == steps]
    (_, sphere_end), = [f for f in frames(tmp_path / "sphere") if f[0] == steps]
    # they did collide: both spins changed
    assert abs(rod_end["omegaz"][0] - 5.0) > 0.1
    for name in ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"):
        np.testing.assert_allclose(rod_end[name], sphere_end[name], rtol=1e-9,
                                   atol=1e-12 * max(1.0, np.abs(sphere_end[name]).max()))


def test_an_elastic_frictionless_collision_keeps_energy_and_momenta(tmp_path):
    """Two rods meeting off centre without damping or friction: after they
    part, the kinetic energy (translation and rotation), the momentum and
    the angular momentum about the origin are those before."""
    mass, _, _ = solid_rod()
    rods = [((-0.02, 0, 0), (0, 1, 0), (0.5, 0, 0), (0, 0, 0)),
            ((0.02, 0.008, 0.002), (0, 0, 1), (-0.5, 0, 0), (0, 0, 0))]
    steps = 80000
    run_liggghts(rod_deck(rods, steps, dump_every=steps, mu=0.0, dt=1e-6), tmp_path)
    (_, start), (_, end) = frames(tmp_path)

    def totals(c):
        p = sum(mass * vector(c, "v", k) for k in (0, 1))
        ang = sum(np.cross(vector(c, "", k), mass * vector(c, "v", k)) + vector(c, "angmom", k) for k in (0, 1))
        energy = sum(0.5 * mass * vector(c, "v", k) @ vector(c, "v", k)
                     + 0.5 * vector(c, "angmom", k) @ vector(c, "omega", k) for k in (0, 1))
        return p, ang, energy

    p0, l0, e0 = totals(start)
    p1, l1, e1 = totals(end)
    # they collided and turned
    assert np.linalg.norm(vector(end, "omega", 0)) > 1.0
    np.testing.assert_allclose(p1, p0, atol=1e-12 * mass)
    np.testing.assert_allclose(l1, l0, atol=1e-10 * np.linalg.norm(l0))
    assert abs(e1 / e0 - 1) < 1e-4


# ---- MPI and restart -------------------------------------------------------------

GAS_DT = 1e-5          # t_c/100 for two rods
# one create_atoms per rod, so that the ids do not depend on the ranks
GAS_LATTICE = "\n".join(f"create_atoms 1 single {0.02 + 0.04 * i!r} {0.02 + 0.04 * j!r} {0.02 + 0.04 * k!r} units box"
                        for k in range(3) for j in range(3) for i in range(3))


def gas_deck(steps, extra_before_run=""):
    """27 rods of random orientation on a lattice in a periodic box, with
    velocities up to 1 m/s from a hash of their positions, colliding for
    `steps` (all of them collide, some across the periodic boundaries and
    the boundary between two ranks' domains)."""
    return f"""{rod_system("p p p")}
region box block 0 0.12 0 0.12 0 0.12 units box
create_box 1 box
{GAS_LATTICE}
set_spherocylinder all diameter {D!r} length {LENGTH!r} density {RHO!r} axis random 15485863
variable vx atom 2.0*(((x*1009.0+0.3)*7.13)%1.0-0.5)
variable vy atom 2.0*(((y*997.0+0.7)*5.31)%1.0-0.5)
variable vz atom 2.0*(((z*1013.0+0.1)*3.77)%1.0-0.5)
velocity all set v_vx v_vy v_vz units box
{gas_run(steps, extra_before_run)}"""


def gas_run(steps, extra_before_run=""):
    """The gas' contacts, integrator and run, and its end state in end.dump."""
    return f"""{rod_contacts(GAS_DT, gamman=20.0, gammat=20.0)}
fix move all nve/spherocylinder
compute axis all spherocylinder/axis
{extra_before_run}
run {steps}
write_dump all custom end.dump id x y z vx vy vz omegax omegay omegaz c_axis[1] c_axis[2] c_axis[3] modify sort id format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
"""


@pytest.mark.skipif(not has_mpirun(), reason="mpirun missing")
def test_two_ranks_give_the_one_rank_gas(tmp_path):
    steps = 4000
    run_liggghts(gas_deck(steps), tmp_path / "np1")
    run_liggghts(gas_deck(steps), tmp_path / "np2", nprocs=2)
    (_, one), = frames(tmp_path / "np1", "end.dump")
    (_, two), = frames(tmp_path / "np2", "end.dump")
    assert len(one["id"]) == 27
    spin = np.sqrt(one["omegax"] ** 2 + one["omegay"] ** 2 + one["omegaz"] ** 2)
    assert np.count_nonzero(spin) >= 20, "too few collisions for the test to tell"
    for name, values in one.items():
        np.testing.assert_allclose(two[name], values, rtol=1e-9, atol=1e-10)


def test_a_restart_continues_the_gas(tmp_path):
    steps = 5000
    # the same two runs (each starts with a neighbour-list build, so that
    # the pairs are summed in the same order) without the restart between
    whole = gas_deck(steps).replace(f"run {steps}\n", f"run {steps}\nrun {steps}\n")
    run_liggghts(whole, tmp_path / "whole")
    run_liggghts(gas_deck(steps, extra_before_run="") + "write_restart half.restart\n", tmp_path / "half")
    resumed = f"""units si
atom_modify map array
read_restart half.restart
newton off
communicate single vel yes
{gas_run(steps)}"""
    (tmp_path / "resume").mkdir()
    (tmp_path / "resume" / "half.restart").write_bytes((tmp_path / "half" / "half.restart").read_bytes())
    run_liggghts(resumed, tmp_path / "resume")
    (_, whole), = frames(tmp_path / "whole", "end.dump")
    (_, again), = frames(tmp_path / "resume", "end.dump")
    for name, values in whole.items():
        np.testing.assert_allclose(again[name], values, rtol=1e-12, atol=1e-14)


# ---- bad input -------------------------------------------------------------------

@pytest.mark.parametrize("line, message", [
    ("set_spherocylinder all diameter 0.01 length 0.005", "'length' must be >= 'diameter'"),
    ("set_spherocylinder all diameter -1", "'diameter' must be > 0"),
    ("set_spherocylinder all axis 0 0 0", "'axis' must not be the zero vector"),
    ("set_spherocylinder all axis random 0", "seed of 'axis random'"),
    ("set_spherocylinder all size 3", "unknown keyword 'size'"),
    ("set_spherocylinder nogroup diameter 0.01", "no group 'nogroup'"),
    ("fix twice all nve/sphere", "(nve/sphere) treats rods as spheres; use fix nve/spherocylinder"),
    ("fix twice all nve/noforce", "(nve/noforce) treats rods as spheres; use fix nve/spherocylinder"),
    ("fix move2 all nve/spherocylinder integration_scheme 4", "'integration_scheme' takes symmetric_top"),
    ("fix move2 all nve/spherocylinder integration_scheme", "'integration_scheme' takes symmetric_top"),
    ("fix move2 all nve/spherocylinder prune_list maybe", "'prune_list' takes yes"),
    ("fix move2 all nve/spherocylinder scheme 1", "unknown keyword 'scheme'"),
    ("fix check all check/timestep/gran 1000 0.1 0.1", "(check/timestep/gran) treats rods as spheres"),
    ("fix floor all wall/gran model hooke/stiffness tangential history primitive type 1 zplane -0.05",
     "(wall/gran) treats rods as spheres; use fix wall/gran/spherocylinder"),
    ("fix floor all wall/gran/spherocylinder model hooke/stiffness tangential history primitive type 1 zplane -0.05",
     "the wall's model needs 'surface spherocylinder'"),
    ("fix floor all wall/gran/spherocylinder model hooke/stiffness tangential history surface spherocylinder "
     "primitive type 1 xcylinder 0.05 0 0", "primitive 'xcylinder' is not one rods can touch"),
])
def test_bad_input_gets_a_clear_error(tmp_path, line, message):
    deck = rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0))], steps=1,
                    extra=line if line.startswith("fix") else "")
    if line.startswith("set_spherocylinder"):
        deck = deck.replace("velocity rod1", f"{line}\nvelocity rod1")
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(deck, tmp_path)
    assert message in error.value.message


@pytest.mark.parametrize("model, message", [
    (SPHERE_MODEL, "pair_style gran needs 'surface spherocylinder'"),
    ("model hertz tangential history surface spherocylinder", "rods take 'model hooke/stiffness' only"),
    ("model hooke/stiffness tangential history rolling_friction epsd2 surface spherocylinder",
     "rods take no rolling_friction model"),
])
def test_a_pair_model_rods_cannot_take_is_refused(tmp_path, model, message):
    # the properties hertz and epsd2 ask for, so that the run gets to the check
    properties = ("fix m_y all property/global youngsModulus peratomtype 1e7\n"
                  "fix m_p all property/global poissonsRatio peratomtype 0.3\n"
                  "fix m_e all property/global coefficientRestitution peratomtypepair 1 0.9\n"
                  "fix m_r all property/global coefficientRollingFriction peratomtypepair 1 0.1\n")
    deck = rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0))], steps=1).replace(ROD_MODEL, model)
    deck = deck.replace("pair_style gran", properties + "pair_style gran")
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(deck, tmp_path)
    assert message in error.value.message


def test_rods_are_for_3d_runs(tmp_path):
    deck = rod_deck([((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0))], steps=1, boundary="f f p")
    deck = deck.replace("atom_style spherocylinder", "dimension 2\natom_style spherocylinder")
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(deck, tmp_path)
    assert "for 3D runs (dimension 3) only" in error.value.message


def test_the_rod_styles_refuse_sphere_atoms(tmp_path):
    sphere = """units si
atom_style sphere
atom_modify map array
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
create_atoms 1 single 0 0 0 units box
"""
    for line, message in [("fix move all nve/spherocylinder", "needs atom_style spherocylinder"),
                          ("set_spherocylinder all length 2", "needs atom_style spherocylinder"),
                          ("compute axis all spherocylinder/axis", "needs atom_style spherocylinder")]:
        with pytest.raises(LiggghtsError) as error:
            run_liggghts(sphere + line + "\nrun 0\n", tmp_path / line.split()[1])
        assert message in error.value.message


def test_write_data_and_read_data_keep_the_rods(tmp_path):
    """write_data writes each rod's diameter, length, density, position
    and quaternion (Atoms) and its velocity and omega (Velocities);
    read_data gives back the same rods: axis, mass, inertia, angular
    momentum (from omega) as the rods written."""
    rods = [((0, 0, 0), (0.6, 0.0, 0.8), (0.1, -0.2, 0.3), (1.0, 2.0, -3.0)),
            ((0.05, 0, 0), (0, 1, 0), (0, 0, 0), (0, 0, 40.0))]
    run_liggghts(rod_deck(rods, steps=0, integrate=False, extra="write_data rods.data"), tmp_path / "write")
    (_, written), = frames(tmp_path / "write")
    reread = rod_deck([], steps=0, integrate=False).replace(
        "create_box 1 box\n", f"read_data {tmp_path / 'write' / 'rods.data'}\n").replace(
        "region box block -0.1 0.1 -0.1 0.1 -0.1 0.1 units box\n", "")
    run_liggghts(reread, tmp_path / "read")
    (_, read), = frames(tmp_path / "read")
    for name, values in written.items():
        if name.startswith(("f", "tq")):
            continue
        np.testing.assert_allclose(read[name], values, rtol=1e-14, atol=1e-15, err_msg=name)


def test_a_time_step_above_a_tenth_of_the_end_contact_time_warns(tmp_path):
    """Two rods crossing at the ends of their cores: 1/m_eff = 2 (1/m +
    h^2/I_t), t_c = pi sqrt(m_eff/k_n) (written out here from the solid's
    closed forms). A step of t_c/5 warns and names t_c; one of t_c/20
    does not."""
    mass, _, transverse = solid_rod()
    contact_time = math.pi * math.sqrt(0.5 / (1 / mass + HALF_SEGMENT ** 2 / transverse) / KN)
    rods = [((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0))]
    coarse = run_liggghts(rod_deck(rods, steps=1, dt=contact_time / 5), tmp_path / "coarse")
    warning = [line for line in coarse.splitlines() if "fix nve/spherocylinder: the time step" in line]
    assert len(warning) == 1
    assert f"t_c = {contact_time:.6g} s" in warning[0] and "20.0%" in warning[0]
    fine = run_liggghts(rod_deck(rods, steps=1, dt=contact_time / 20), tmp_path / "fine")
    assert "fix nve/spherocylinder: the time step" not in fine
