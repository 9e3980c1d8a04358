"""fix wall/gran/rotating: a flat silo bottom with an orifice, turning about
the silo axis.

(a) Peer: without hole and rotation the plate is the stock primitive plane:
    trajectories of grains bouncing, sliding and rolling on it are
    identical, bit for bit, to those on `fix wall/gran ... primitive
    zplane`, for Hooke, Hooke with rolling_friction jiang, and Hertz.
(b) Rotation, analytic: a grain that cannot roll (`fix nve`: its spin is
    never integrated) is dragged into co-rotation, tangential speed Omega r;
    a sphere that rolls without slipping obeys the turntable theorem
    (dv/dt = 2/7 Omega x v: after the short slip its centre circles the axis
    at its starting radius at 2/7 Omega r). The stock mesh peer (an annulus
    in `fix mesh/surface ... surface_ang_vel`) gives the same orbit.
    The plate's outputs: its load is m g; the time integral of its torque
    about the axis is minus the angular momentum the grain gains.
(c) Times: nothing turns before `start`; the hole is closed before `open`.
(d) The rim: a sphere resting on the plate with the hole under part of it
    stays; one whose centre is over the hole rolls off the rim edge and
    falls through; a sphere rolling over the rim and fast impacts on the
    rim edge and on the plate never tunnel, never gain energy, and the force
    on the plate changes continuously. The 2D slot does the same.
(e) Two MPI ranks reproduce one bit for bit; a restart continues a loaded
    contact exactly.
(f) Bad input: a clear ERROR naming the keyword.
"""

import math

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair
from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_table
from analysis.common.stl import annulus_triangles, write_stl
from analysis.testing import LiggghtsError
from conftest import has_mpirun, run_liggghts

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

RADIUS = 0.005
DENSITY = 2500.0
G = 9.81
KN = 1.0e4
DT = 1.0e-5
HOLE = 0.04                     # orifice diameter
MASS_3D = DENSITY * 4.0 / 3.0 * math.pi * RADIUS ** 3
MASS_2D = DENSITY * math.pi * RADIUS ** 2
HOOKE = "model hooke/stiffness tangential history"
MATERIALS = hooke_materials(KN, 2.0 / 7.0 * KN, gamman=100.0, gammat=100.0, mu=0.5)
RECORD = ("step time x y z vx vy vz wx wy wz om fa ta nc")


def plate(options="", model=HOOKE, style="wall/gran/rotating", plane="zplane 0.0"):
    return f"fix bottom all {style} {model} primitive type 1 {plane} {options}"


def deck(atoms, wall, steps, record_every=100, integrate="nve/sphere", dimension=3,
         materials=MATERIALS, extra="", box="-0.1 0.1 -0.1 0.1 -0.1 0.1", gravity="0 0 -1",
         restart_file=None):
    """One or more spheres (`atoms`: create_atoms lines) of radius RADIUS
    on the plate `wall`. Atom 1 is recorded in record.txt (columns RECORD)
    every record_every steps; the plate's outputs are om, fa, ta, nc.
    With restart_file, the box and the grains come from it instead."""
    if restart_file:
        system = f"atom_modify map array\nread_restart {restart_file}\nnewton off\ncommunicate single vel yes"
    else:
        boundary = "f f p" if dimension == 2 else "f f f"
        system = f"""{granular_setup(dimension=dimension, boundary=boundary)}
region box block {box} units box
create_box 1 box
{atoms}
set group all diameter {2 * RADIUS} density {DENSITY}"""
    outputs = ("variable om equal f_bottom[1]\nvariable fa equal f_bottom[2]\n"
               "variable ta equal f_bottom[3]\nvariable nc equal f_bottom[4]")
    if "wall/gran/rotating" not in wall:
        outputs = "\n".join(f"variable {name} equal 0" for name in ("om", "fa", "ta", "nc"))
    return f"""
{system}
neighbor 0.001 bin
neigh_modify delay 0
{materials}
pair_style gran {HOOKE}
pair_coeff * *
timestep {DT}
{extra}
{wall}
fix gravity all gravity {G} vector {gravity}
fix integrate all {integrate}
{outputs}
variable x equal x[1]
variable y equal y[1]
variable z equal z[1]
variable vx equal vx[1]
variable vy equal vy[1]
variable vz equal vz[1]
variable wx equal omegax[1]
variable wy equal omegay[1]
variable wz equal omegaz[1]
variable t equal time
fix record all print {record_every} "${{t}} ${{x}} ${{y}} ${{z}} ${{vx}} ${{vy}} ${{vz}} ${{wx}} ${{wy}} ${{wz}} ${{om}} ${{fa}} ${{ta}} ${{nc}}" file record.txt screen no title "# time x y z vx vy vz wx wy wz om fa ta nc"
thermo 10000
run {steps}
"""


def one_atom(x, y, z):
    return f"create_atoms 1 single {x!r} {y!r} {z!r} units box"


def record(path):
    return read_table(path / "record.txt")


# ---------------------------------------------------------------- (a) peer

SPHERES = """create_atoms 1 single 0.03 0.0 0.012 units box
create_atoms 1 single -0.02 0.03 0.006 units box
create_atoms 1 single 0.0 -0.04 0.0049 units box
create_atoms 1 single -0.05 -0.01 0.02 units box
velocity all set 0.0 0.0 0.0 units box
set atom 1 vx 0.3 vy -0.1
set atom 2 omegax 20.0 omegay -5.0
set atom 3 vx -0.2 vy 0.2 omegaz 50.0
set atom 4 vz -1.0 omegay 30.0
"""
PEER_DUMP = "dump final all custom 50 dump.final id x y z vx vy vz omegax omegay omegaz\n" \
            "dump_modify final sort id format \"%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\""

HERTZ_MATERIALS = """
fix m_E all property/global youngsModulus peratomtype 5e6
fix m_nu all property/global poissonsRatio peratomtype 0.3
fix m_e all property/global coefficientRestitution peratomtypepair 1 0.7
"""
PEER_MODELS = {
    "hooke": (HOOKE, MATERIALS),
    "hooke+jiang": (HOOKE + " rolling_friction jiang",
                    MATERIALS + per_pair("rollingContactLength", 5.0e-4)),
    # the grains among themselves stay Hooke (pair_style): the plate is Hertz
    "hertz": ("model hertz tangential history", MATERIALS + HERTZ_MATERIALS),
}


@pytest.mark.parametrize("name", sorted(PEER_MODELS))
def test_plate_without_hole_or_rotation_is_the_stock_plane(run, tmp_path, name):
    model, materials = PEER_MODELS[name]
    for style in ("wall/gran", "wall/gran/rotating"):
        run(deck(SPHERES, plate(model=model, style=style), 10000, materials=materials,
                 extra=PEER_DUMP), subdir=style.replace("/", "_"))
    ours = read_dump(tmp_path / "wall_gran_rotating" / "dump.final")
    stock = read_dump(tmp_path / "wall_gran" / "dump.final")
    # every grain touched the plate (pressed into it in some frame) and moved
    assert np.all(np.min([frame["z"] for _, frame in ours], axis=0) < RADIUS)
    assert np.all(np.hypot(ours[-1][1]["x"] - ours[0][1]["x"], ours[-1][1]["y"] - ours[0][1]["y"]) > 1e-3)
    assert len(ours) == len(stock) == 201
    for (_, a), (_, b) in zip(ours, stock):
        # bit for bit: both loops do the same arithmetic (dumped with 17 digits)
        for column in ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"):
            np.testing.assert_array_equal(a[column], b[column], err_msg=f"{name}: {column}")


# ---------------------------------------------------------------- (b) rotation

FREQUENCY = 0.5
OMEGA = 2.0 * math.pi * FREQUENCY
R0 = 0.05


def tangential_speed(rec):
    r = np.hypot(rec["x"], rec["y"])
    return (rec["x"] * rec["vy"] - rec["y"] * rec["vx"]) / r, r


@pytest.mark.parametrize("integrate, expected_fraction",
                         [("nve", 1.0), ("nve/sphere", 2.0 / 7.0)])
def test_grain_on_turning_plate_moves_as_analytic(run, tmp_path, integrate, expected_fraction):
    """nve: no rolling, co-rotation at Omega r0 (friction mu g = 4.9 m/s^2
    holds the centripetal Omega^2 r0 = 0.49 m/s^2). nve/sphere: rolling
    without slipping, the turntable orbit at 2/7 Omega r0 about the axis."""
    run(deck(one_atom(R0, 0.0, RADIUS), plate(f"orifice {HOLE} frequency {FREQUENCY}"), 100000,
             integrate=integrate, record_every=1000))
    rec = record(tmp_path)
    speed, r = tangential_speed(rec)
    late = rec["time"] >= 0.2
    expected = expected_fraction * OMEGA * R0
    assert np.all(np.abs(speed[late] / expected - 1.0) < 2e-3), speed[late]
    assert np.all(np.abs(r / R0 - 1.0) < 1e-3)
    # it went round: more than a quarter turn about the axis in 1 s
    angle = np.unwrap(np.arctan2(rec["y"], rec["x"]))
    assert angle[-1] - angle[0] > expected_fraction * OMEGA * 0.9 * 0.8
    assert np.allclose(rec["om"], OMEGA, rtol=1e-12)
    # load on the plate: the grain's weight, pushing along -axis
    assert np.allclose(rec["fa"][late], -MASS_3D * G, rtol=1e-4)
    assert np.all(rec["nc"] == 1)


def test_stock_mesh_peer_gives_the_same_orbit(run, tmp_path):
    """The same rolling sphere on the stock mesh bottom: an annulus of 64
    sectors in fix mesh/surface with surface_ang_vel (velocity Omega x r at
    its nodes, interpolated linearly: exact for a rigid rotation)."""
    (tmp_path / "mesh").mkdir()
    write_stl(tmp_path / "mesh" / "plate.stl", annulus_triangles(HOLE / 2, 0.099))
    mesh = (f"fix plate all mesh/surface file plate.stl type 1 surface_ang_vel origin 0 0 0 "
            f"axis 0 0 1 omega {OMEGA!r}\n"
            f"fix bottom all wall/gran {HOOKE} mesh n_meshes 1 meshes plate")
    run(deck(one_atom(R0, 0.0, RADIUS), mesh, 50000, record_every=1000), subdir="mesh")
    run(deck(one_atom(R0, 0.0, RADIUS), plate(f"orifice {HOLE} omega {OMEGA!r}"), 50000,
             record_every=1000), subdir="ours")
    stock, ours = record(tmp_path / "mesh"), record(tmp_path / "ours")
    for column in ("x", "y", "z", "vx", "vy", "vz"):
        np.testing.assert_allclose(ours[column], stock[column], rtol=0, atol=1e-9, err_msg=column)


def test_plate_torque_integrates_to_the_angular_momentum_given(run, tmp_path):
    """A grain that cannot roll is spun up from rest to Omega r0; the
    torque the grain exerts on the plate about the axis, summed over every
    step (fix ave/time), is minus the grain's gain of angular momentum
    m r0 (Omega r0) (its spin stays zero under fix nve)."""
    steps = 20000
    wall = plate(f"orifice {HOLE} frequency {FREQUENCY}") + \
        f"\nfix torque all ave/time 1 {steps} {steps} f_bottom[3] file torque.txt"
    run(deck(one_atom(R0, 0.0, RADIUS), wall, steps, integrate="nve"))
    mean_torque = float(open(tmp_path / "torque.txt").read().split()[-1])
    rec = record(tmp_path)
    speed, r = tangential_speed(rec)
    gained = MASS_3D * r[-1] * speed[-1]
    assert abs(speed[-1] / (OMEGA * R0) - 1.0) < 2e-3
    assert mean_torque * steps * DT == pytest.approx(-gained, rel=5e-3)


# ---------------------------------------------------------------- (c) start, open

def test_nothing_turns_before_start(run, tmp_path):
    run(deck(one_atom(R0, 0.0, RADIUS), plate(f"orifice {HOLE} frequency {FREQUENCY} start 0.1"),
             20000, integrate="nve", record_every=500))
    rec = record(tmp_path)
    before = rec["time"] < 0.1 - 1e-9
    after = rec["time"] > 0.15
    assert np.all(rec["om"][before] == 0.0)
    assert np.all(rec["om"][rec["time"] >= 0.1] == pytest.approx(OMEGA))
    assert np.all(np.hypot(rec["vx"][before], rec["vy"][before]) < 1e-12)
    speed, _ = tangential_speed(rec)
    assert np.all(speed[after] / (OMEGA * R0) > 0.99)


def test_the_hole_is_closed_before_open(run, tmp_path):
    """A sphere resting over the hole on the closed plate stays until
    `open`, then falls through."""
    run(deck(one_atom(0.5 * HOLE_RADIUS, 0.0, RADIUS - MASS_3D * G / KN),
             plate(f"orifice {HOLE} open 0.1"), 20000, record_every=100))
    rec = record(tmp_path)
    closed = rec["time"] < 0.1 - 1e-9
    assert np.all(np.abs(rec["z"][closed] - (RADIUS - MASS_3D * G / KN)) < 1e-8)
    assert np.all(rec["nc"][closed] == 1)
    assert rec["z"][-1] < -RADIUS and rec["nc"][-1] == 0


# ---------------------------------------------------------------- (d) the rim

HOLE_RADIUS = HOLE / 2


def rim_distance(rec):
    s = np.hypot(rec["x"], rec["y"])
    return np.hypot(HOLE_RADIUS - s, rec["z"])


def plate_distance(rec):
    """Distance from the centre to the plate with its hole (computed here,
    independently of orifice_plate.h)."""
    s = np.hypot(rec["x"], rec["y"])
    return np.where(s >= HOLE_RADIUS, np.abs(rec["z"]), rim_distance(rec))


def mechanical_energy(rec, mass, inertia):
    """Kinetic + potential + the elastic energy of the normal spring
    (Hooke, k_n = KN); the tangential spring's is left out (it is small
    next to the tolerances used)."""
    v2 = rec["vx"] ** 2 + rec["vy"] ** 2 + rec["vz"] ** 2
    w2 = rec["wx"] ** 2 + rec["wy"] ** 2 + rec["wz"] ** 2
    overlap = np.maximum(RADIUS - plate_distance(rec), 0.0)
    return 0.5 * mass * v2 + 0.5 * inertia * w2 + mass * G * rec["z"] + 0.5 * KN * overlap ** 2


def resting_height(s):
    """Height of a sphere centred at in-plane distance s that rests on the
    plate (s >= R) or on the rim edge (s < R) under its weight (overlap m g/k
    along the contact normal, to first order)."""
    overlap = MASS_3D * G / KN
    if s >= HOLE_RADIUS:
        return RADIUS - overlap
    return math.sqrt((RADIUS - overlap) ** 2 - (HOLE_RADIUS - s) ** 2)


def test_sphere_with_the_hole_under_its_edge_stays(run, tmp_path):
    s = HOLE_RADIUS + 0.05 * RADIUS
    run(deck(one_atom(s, 0.0, resting_height(s)), plate(f"orifice {HOLE}"), 30000, record_every=100))
    rec = record(tmp_path)
    assert np.all(np.abs(np.hypot(rec["x"], rec["y"]) - s) < 1e-9)
    assert np.all(np.abs(rec["z"] - resting_height(s)) < 2e-8)
    assert np.all(np.abs(rec["fa"][1:] + MASS_3D * G) < 0.02 * MASS_3D * G)


def test_sphere_centred_over_the_hole_rolls_off_the_rim_and_falls(run, tmp_path):
    s = HOLE_RADIUS - 0.2 * RADIUS
    run(deck(one_atom(s, 0.0, resting_height(s)), plate(f"orifice {HOLE}"), 15000, record_every=1))
    rec = record(tmp_path)
    assert rec["z"][-1] < -2 * RADIUS                       # fell through
    assert np.all(np.hypot(rec["x"], rec["y"]) < HOLE_RADIUS)  # inside the hole all along
    assert np.all(rim_distance(rec) > 0.99 * RADIUS)        # never through the rim
    assert np.max(np.abs(np.diff(rec["fa"]))) < 0.01 * MASS_3D * G
    energy = mechanical_energy(rec, MASS_3D, 0.4 * MASS_3D * RADIUS ** 2)
    assert np.max(energy - np.minimum.accumulate(energy)) < 1e-3 * MASS_3D * G * RADIUS


def test_sphere_rolling_over_the_rim_falls_smoothly(run, tmp_path):
    """Rolling inward along -x at 0.05 m/s (spin v/r about -y... rolling
    without slipping) from 3 radii outside the rim: its load on the plate
    decreases continuously to zero as it tips over the edge."""
    s, speed = HOLE_RADIUS + 3 * RADIUS, 0.05
    atoms = one_atom(s, 0.0, resting_height(s)) + f"\nset atom 1 vx {-speed!r} omegay {-speed / RADIUS!r}"
    run(deck(atoms, plate(f"orifice {HOLE}"), 40000, record_every=2))
    rec = record(tmp_path)
    assert rec["z"][-1] < -2 * RADIUS
    assert np.all(rim_distance(rec) > 0.99 * RADIUS)
    assert np.all(rec["z"][rec["x"] > HOLE_RADIUS] > 0.99 * RADIUS)
    assert np.max(np.abs(np.diff(rec["fa"]))) < 0.01 * MASS_3D * G
    assert np.all(rec["fa"] <= 1e-15) and np.all(rec["fa"] > -1.01 * MASS_3D * G)
    energy = mechanical_energy(rec, MASS_3D, 0.4 * MASS_3D * RADIUS ** 2)
    assert np.max(energy - np.minimum.accumulate(energy)) < 1e-3 * MASS_3D * G * RADIUS


@pytest.mark.parametrize("omega", [0.0, 1.0, 3.0])
def test_rolling_resistance_holds_a_grain_on_the_turning_rim(run, tmp_path, omega):
    """rolling_friction jiang (l_c = r/2 fixed: tipping is resisted while
    tan(theta) < mu l_c / r = 0.25) holds a sphere on the rim edge with its
    centre 8 degrees inside the hole. On a turning plate it must go round
    with the plate, at the plate's angular velocity: the model is told the
    plate's own spin, so a grain at rest on the plate does not roll relative
    to it. (Given a plate that does not turn, as stock walls are, the rim's
    spin would read as rolling: the spurious resisting torque drives the
    grain round 3.8 % faster than the plate at omega = 1 rad/s, measured.)"""
    theta = math.radians(8.0)
    overlap = MASS_3D * G / KN
    s = HOLE_RADIUS - (RADIUS - overlap) * math.sin(theta)
    model = HOOKE + " rolling_friction jiang"
    materials = MATERIALS + per_pair("rollingContactLength", RADIUS / 2)
    run(deck(one_atom(s, 0.0, (RADIUS - overlap) * math.cos(theta)),
             plate(f"orifice {HOLE} omega {omega!r}", model=model), 100000, materials=materials,
             record_every=1000))
    rec = record(tmp_path)
    late = rec["time"] >= 0.5          # the start-up oscillation has decayed below 1e-3
    speed, r = tangential_speed(rec)
    print(f"omega {omega}: r {np.ptp(r[late]):.2e}, z {np.ptp(rec['z'][late]):.2e}, "
          f"speed/(omega r) - 1 up to {np.max(np.abs(speed[late] / (omega * r[late]) - 1.0)) if omega else 0:.2e}")
    assert np.ptp(r[late]) < 1e-6 and np.ptp(rec["z"][late]) < 1e-6     # held in place on the plate
    assert np.all(r < HOLE_RADIUS) and np.all(rim_distance(rec) > 0.99 * RADIUS)
    if omega > 0:
        assert np.all(np.abs(speed[late] / (omega * r[late]) - 1.0) < 2e-3)
    else:
        assert np.all(np.abs(speed) < 1e-9)


@pytest.mark.parametrize("where", ["rim", "plate"])
def test_fast_impact_neither_tunnels_nor_gains_energy(run, tmp_path, where):
    """A sphere thrown down at 2 m/s (overlap at impact ~ v sqrt(m/k) =
    0.14 r) onto the rim edge (centre 0.3 r inside the hole) or onto the
    plate: it bounces, off the rim along the edge's normal."""
    s = HOLE_RADIUS - 0.3 * RADIUS if where == "rim" else HOLE_RADIUS + 2 * RADIUS
    atoms = one_atom(s, 0.0, 1.5 * RADIUS) + "\nset atom 1 vz -2.0"
    run(deck(atoms, plate(f"orifice {HOLE}"), 3000, record_every=1))
    rec = record(tmp_path)
    # out of contact (no spring loaded, the tangential one included) the
    # energy after the impact is below the energy before
    energy = mechanical_energy(rec, MASS_3D, 0.4 * MASS_3D * RADIUS ** 2)
    free = rec["nc"] == 0
    contact_steps = np.flatnonzero(~free)
    assert contact_steps.size > 10
    before = energy[:contact_steps[0]]
    after = free.copy()
    after[:contact_steps[-1] + 1] = False
    assert np.ptp(before) < 1e-6 * energy[0]      # free flight
    assert np.max(energy[after]) < np.min(before)
    if where == "rim":
        assert np.all(rim_distance(rec) > 0.8 * RADIUS)
        assert np.any(rec["nc"] == 1)
        # the rim's normal at impact leans 17 degrees towards the axis: the
        # grain bounces up and inwards, above the plate
        assert rec["vz"][-1] > 0.0 and rec["vx"][-1] < 0.0
        assert np.all(np.hypot(rec["x"], rec["y"]) < HOLE_RADIUS)
    else:
        assert np.all(rec["z"] > 0.8 * RADIUS)
        assert rec["vz"][-1] > 0.0


@pytest.mark.parametrize("offset, falls", [(0.05, False), (-0.2, True)])
def test_2d_slot_holds_or_drops_a_disc_at_its_edge(run, tmp_path, offset, falls):
    """dimension 2: the plate is the line y = 0 with the slot |x| < D/2;
    discs (mass pi r^2 rho) rest on it with gravity along -y."""
    s = HOLE_RADIUS + offset * RADIUS
    overlap = MASS_2D * G / KN
    height = RADIUS - overlap if not falls else math.sqrt((RADIUS - overlap) ** 2 - (HOLE_RADIUS - s) ** 2)
    run(deck(f"create_atoms 1 single {s!r} {height!r} 0.0 units box",
             plate(f"orifice {HOLE}", plane="yplane 0.0"), 15000, record_every=10,
             dimension=2, box="-0.1 0.1 -0.1 0.1 -0.01 0.01", gravity="0 -1 0"))
    rec = record(tmp_path)
    if falls:
        assert rec["y"][-1] < -2 * RADIUS
        # never deeper into the slot's edge than twice the static overlap
        assert np.all(np.hypot(HOLE_RADIUS - np.abs(rec["x"]), rec["y"]) > RADIUS - 2 * overlap)
    else:
        assert np.all(np.abs(rec["x"] - s) < 1e-9)
        assert np.allclose(rec["fa"][10:], -MASS_2D * G, rtol=0.02)


# ---------------------------------------------------------------- (e) MPI, restart

# a 10 x 10 x 3 lattice of spacing 0.0125 above the plate, one create_atoms
# single per grain so that the ids do not depend on the number of ranks
BED = "\n".join(one_atom(-0.05625 + 0.0125 * i, -0.05625 + 0.0125 * j, 0.0125 * (k + 1))
                 for k in range(3) for j in range(10) for i in range(10))
BED_DUMP = "dump traj all custom 2000 dump.traj id x y z vx vy vz omegax omegay omegaz\n" \
           "dump_modify traj sort id format \"%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\"\n" \
           "thermo_modify lost ignore\n"


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_reproduce_one(run, tmp_path):
    """A bed of 300 grains falls onto the turning plate (1 Hz) and through
    its hole; the ranks split at x = 0, through the axis and the hole."""
    side_walls = "\n".join(
        f"fix side{k} all wall/gran {HOOKE} primitive type 1 {p} {v}"
        for k, (p, v) in enumerate([("xplane", -0.07), ("xplane", 0.07), ("yplane", -0.07), ("yplane", 0.07)]))
    body = deck(BED, plate(f"orifice {HOLE} frequency 1.0") + "\n" + side_walls,
                10000, extra=BED_DUMP)
    body = body.replace("region box block", "processors * 1 1\nregion box block")
    run(body, subdir="one")
    output = run(body, nprocs=2, subdir="two")
    assert "2 by 1 by 1 MPI processor grid" in output
    one = read_dump(tmp_path / "one" / "dump.traj")
    two = read_dump(tmp_path / "two" / "dump.traj")
    assert len(one) == len(two) == 6
    final = one[-1][1]
    assert np.sum(final["z"] < 0.0) > 5                 # some fell through the hole
    assert np.sum(np.abs(final["x"]) < 2 * RADIUS) > 10  # grains about the rank boundary
    for (step1, a), (step2, b) in zip(one, two):
        assert step1 == step2
        np.testing.assert_array_equal(a["id"], b["id"])
        for column in ("x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"):
            deviation = np.max(np.abs(a[column] - b[column]))
            print(f"step {step1} {column}: {deviation:.2e}")
            assert deviation == 0.0, column            # bit for bit


def test_restart_continues_a_loaded_wall_contact_exactly(run, tmp_path):
    """A co-rotating grain (fix nve) is held on its circle by the static
    tangential spring of its plate contact; that spring is in the per-atom
    history the restart file carries. 20000 steps in one go equal
    10000 + write_restart/read_restart + 10000. Without damping: a run's
    set-up force call sees the full-step velocity where a step sees the
    half-step one (LAMMPS' velocity Verlet), so any velocity-dependent force
    makes a restart differ at the 1e-10 level, with stock walls too."""
    wall = plate(f"orifice {HOLE} frequency {FREQUENCY}")
    undamped = hooke_materials(KN, 2.0 / 7.0 * KN, mu=0.5)
    common = dict(integrate="nve", record_every=10000, materials=undamped)
    run(deck(one_atom(R0, 0.0, RADIUS), wall, 20000, **common), subdir="whole")
    first = deck(one_atom(R0, 0.0, RADIUS), wall, 10000, **common) + "write_restart grain.restart\n"
    run(first, subdir="first")
    second = deck("", wall, 10000, restart_file="../first/grain.restart", **common)
    run(second, subdir="second")
    whole = record(tmp_path / "whole")
    restarted = record(tmp_path / "second")
    for column in ("x", "y", "z", "vx", "vy", "vz"):
        assert restarted[column][-1] == pytest.approx(whole[column][-1], rel=0, abs=1e-14), column
    # the spring mattered: the grain is held against a centripetal force
    speed, _ = tangential_speed(whole)
    assert speed[-1] == pytest.approx(OMEGA * R0, rel=1e-2)   # undamped: oscillates a little about it


# Times of the schedule across restarts: LIGGGHTS 3.8 restarts its clock
# at 0 after read_restart; the fix keeps the time reached in its restart data.
SWITCH = 0.100005              # start and open: half-way between two steps
SCHEDULE_STEPS = 20000
RESTING = RADIUS - MASS_3D * G / KN
SCHEDULE_DUMP = ("dump grains all custom 100 dump.grains id x y z vx vy vz\n"
                 "dump_modify grains sort id format \"%d %.17g %.17g %.17g %.17g %.17g %.17g\"\n"
                 "variable step equal step\n"
                 "fix schedule all print 100 \"${step} ${om}\" file schedule.txt screen no\n"
                 "thermo_modify lost ignore")


def schedule_piece(steps, restart_file=None):
    """Grain 1 rests over the hole of the closed plate (it falls once the
    hole opens), grain 2 at R0 on the plate (fix nve: it is carried along
    once the plate turns); plate open and turning from SWITCH. Without
    damping, so that a restart continues exactly (see the test above).
    steps None: read the restart file and write it again, without a run."""
    wall = plate(f"orifice {HOLE} frequency {FREQUENCY} start {SWITCH} open {SWITCH}")
    grains = one_atom(0.5 * HOLE_RADIUS, 0.0, RESTING) + "\n" + one_atom(R0, 0.0, RADIUS)
    text = deck(grains, wall, steps or 0, integrate="nve", record_every=100000, extra=SCHEDULE_DUMP,
                materials=hooke_materials(KN, 2.0 / 7.0 * KN, mu=0.5), restart_file=restart_file)
    if steps is None:
        text = text.replace("\nrun 0\n", "\n")
    return text + "write_restart state.restart\n"


def schedule_frames(directories):
    """step -> dump frame and step -> angular velocity of the plate, over
    the pieces of a run (a restart's first frame repeats the last one)."""
    frames, omegas = {}, {}
    for directory in directories:
        if (directory / "dump.grains").exists():
            frames.update(read_dump(directory / "dump.grains"))
        for line in open(directory / "schedule.txt"):   # the title only when nothing ran
            if not line.startswith("#"):
                step, omega = line.split()
                omegas[int(step)] = float(omega)
    return frames, omegas


@pytest.mark.parametrize("pieces", [
    (6000, 14000),               # restart before start/open
    (14000, 6000),               # restart after start/open
    (4000, 4000, 12000),         # two restarts before: the offset accumulates
    (6000, None, 14000),         # written again right after read_restart, without a run
], ids=["before", "after", "twice-before", "rewritten-before-a-run"])
def test_a_restarted_run_keeps_the_schedule(run, tmp_path, pieces):
    """The schedule is in the simulated time of the whole run: with start =
    open = SWITCH, grain 1 stays at rest over the closed hole until then and
    falls through it after, grain 2 is at rest until then and carried at
    Omega R0 after; a run cut into pieces by write_restart/read_restart (the
    same fix ID and arguments) does step for step what the uninterrupted
    run does. (LIGGGHTS 3.8's time restarts at 0 after read_restart: compared
    with it, the plate would open and turn SWITCH after each restart.)"""
    run(schedule_piece(SCHEDULE_STEPS), subdir="whole")
    frames, omegas = schedule_frames([tmp_path / "whole"])
    assert len(frames) == SCHEDULE_STEPS // 100 + 1 and len(omegas) == SCHEDULE_STEPS // 100
    for step, grains in frames.items():
        before = step * DT < SWITCH
        # (printed with 15 digits)
        assert omegas.get(step, 0.0) == (0.0 if before else pytest.approx(OMEGA, rel=1e-14)), step
        speed = np.hypot(grains["vx"][1], grains["vy"][1])
        if before:
            assert abs(grains["z"][0] - RESTING) < 1e-8 and abs(grains["vz"][0]) < 1e-6, step
            assert speed < 1e-12, step
    last = frames[SCHEDULE_STEPS]
    assert last["z"][0] < -RADIUS                                # fell through the hole
    # carried along (undamped: the static friction spring oscillates a little)
    assert np.hypot(last["vx"][1], last["vy"][1]) == pytest.approx(OMEGA * R0, rel=0.05)

    previous = None
    directories = []
    for k, steps in enumerate(pieces):
        directory = f"piece{k}"
        restart_file = f"../{previous}/state.restart" if previous else None
        run(schedule_piece(steps, restart_file), subdir=directory)
        directories.append(tmp_path / directory)
        previous = directory
    pieced_frames, pieced_omegas = schedule_frames(directories)
    assert sorted(pieced_frames) == sorted(frames) and pieced_omegas == omegas
    for step, grains in frames.items():
        for column in ("x", "y", "z", "vx", "vy", "vz"):
            np.testing.assert_allclose(pieced_frames[step][column], grains[column], rtol=0, atol=1e-12,
                                       err_msg=f"step {step}, {column}")


# ---------------------------------------------------------------- (f) bad input

BAD_INPUT = [
    ("orifice 0.3", "does not fit in the simulation box"),
    ("orifice -0.01", "'orifice' (the diameter) must be >= 0"),
    ("frequency -1", "'frequency' must be >= 0"),
    ("omega -1", "'omega' must be >= 0"),
    ("omega 1 frequency 1", "either 'omega' or 'frequency'"),
    ("start -0.5", "'start' (a simulated time) must be >= 0"),
    ("open -1", "'open' (a simulated time) must be >= 0"),
    ("axis 0 0 2", "'axis' must be a unit vector"),
    ("axis 1 0 0", "'axis' must be normal to the plate"),
    ("orifice abc", "'orifice' expects a number, got 'abc'"),
    ("center 0 0", "keyword 'center' needs three values"),
    ("orifice", "keyword 'orifice' needs a value"),
    ("shear x 1.0", "'shear' is not for this style"),
    ("center 0.09 0 0 orifice 0.04", "does not fit in the simulation box"),
]


@pytest.mark.parametrize("options, message", BAD_INPUT)
def test_bad_input_is_refused_with_a_clear_error(tmp_path, liggghts_binary, options, message):
    text = deck(one_atom(R0, 0.0, RADIUS), plate(options), 2)
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(text, tmp_path, timeout=60)
    assert message in error.value.message, error.value.message
    assert "wall/gran/rotating" in error.value.message


@pytest.mark.parametrize("wall, message", [
    (plate("orifice 0.04", plane="zcylinder 0.05 0 0"), "the primitive must be a plane"),
    ("fix m all mesh/surface file plate.stl type 1\n"
     "fix bottom all wall/gran/rotating model hooke/stiffness tangential history mesh n_meshes 1 meshes m",
     "needs a primitive plane"),
])
def test_the_wall_must_be_a_primitive_plane(tmp_path, liggghts_binary, wall, message):
    write_stl(tmp_path / "plate.stl", annulus_triangles(HOLE / 2, 0.099))
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(deck(one_atom(R0, 0.0, RADIUS), wall, 2), tmp_path, timeout=60)
    assert message in error.value.message, error.value.message


@pytest.mark.parametrize("options, plane, message", [
    ("orifice 0.04 frequency 1", "yplane 0.0", "a 2D plate cannot rotate"),
    ("orifice 0.04", "zplane 0.0", "in 2D the plate is an xplane or a yplane"),
])
def test_2d_restrictions(tmp_path, liggghts_binary, options, plane, message):
    text = deck("create_atoms 1 single 0.05 0.005 0.0 units box", plate(options, plane=plane), 2,
                dimension=2, box="-0.1 0.1 -0.1 0.1 -0.01 0.01", gravity="0 -1 0")
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(text, tmp_path, timeout=60)
    assert message in error.value.message, error.value.message


def test_good_input_runs(run, tmp_path):
    """Positive control of the bad-input cases: the same deck with every
    keyword given right, in any order, also before the model."""
    wall = ("fix bottom all wall/gran/rotating orifice 0.04 model hooke/stiffness tangential history "
            "center 0 0 0.3 primitive type 1 zplane 0.0 axis 0 0 -1 frequency 1 start 0.0")
    output = run(deck(one_atom(R0, 0.0, RADIUS), wall, 200))
    rec = record(tmp_path)
    assert "ERROR" not in output
    # axis 0 0 -1: clockwise seen from above
    assert rec["vy"][-1] < 0.0


# keywords of ours anywhere among the stock ones: between the model's words,
# between the wall's and the model's settings, before everything (the stock
# ones keep the order fix wall/gran asks for: store_force before the
# model's settings)
JIANG_WALL = "model hooke/stiffness tangential history rolling_friction jiang"
SAME_WALL = [
    f"{JIANG_WALL} primitive type 1 zplane 0.0 store_force no rollingStiffnessFactor 2 "
    "orifice 0.04 center 0.01 0 0 axis 0 0 -1 frequency 1 start 0.002 open 0.001",
    "orifice 0.04 model hooke/stiffness tangential history frequency 1 rolling_friction jiang "
    "center 0.01 0 0.3 primitive type 1 zplane 0.0 open 0.001 store_force no axis 0 0 -1 "
    "rollingStiffnessFactor 2 start 0.002",
    f"start 0.002 axis 0 0 -1 {JIANG_WALL} primitive type 1 zplane 0.0 frequency 1 "
    "store_force no center 0.01 0 0 rollingStiffnessFactor 2 open 0.001 orifice 0.04",
]


def test_our_keywords_in_any_position_give_the_same_wall(run, tmp_path):
    """The plate's keywords are read apart from FixWallGran's, which gets
    the others in their order: every arrangement gives the same run, bit
    for bit (a grain rolling on the turning plate near the rim, with
    rolling resistance, so that the model's settings count too)."""
    materials = MATERIALS + per_pair("rollingContactLength", 5.0e-4)
    records = []
    for k, options in enumerate(SAME_WALL):
        wall = f"fix bottom all wall/gran/rotating {options}"
        run(deck(one_atom(0.035, 0.0, RADIUS), wall, 2000, record_every=10, materials=materials),
            subdir=f"order{k}")
        records.append((tmp_path / f"order{k}" / "record.txt").read_text())
    assert records[0].count("\n") > 200
    assert records[1] == records[0]
    assert records[2] == records[0]
