"""Rods against walls: fix wall/gran/spherocylinder (planes, the inner
wall of a cylinder) and fix wall/gran/rotating (the plate with an orifice,
turning), run by the built LIGGGHTS.

Expected values come from statics (a rod lying flat rests on two springs,
each carrying m g / 2; on its cap on one, carrying m g), from symmetry
and energy (an elastic rod bouncing off a wall), from kinematics (a rod
dragged by a turning plate ends in rigid co-rotation, its centre at
Omega R0 and its spin Omega), and from geometry (a rod longer than the
orifice rests across it, one thinner than the orifice falls through it
end first); never from the styles under test."""

import math

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from conftest import has_mpirun, run_liggghts
from test_spherocylinder import D, KN, RADIUS, ROD_MODEL, rod_contacts, rod_lines, rod_system, solid_rod

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

G = 9.81
WALL_MODEL = ROD_MODEL
COLUMNS = ("id x y z vx vy vz omegax omegay omegaz angmomx angmomy angmomz fx fy fz "
           "c_axis[1] c_axis[2] c_axis[3]")


def wall_deck(rods, walls, steps, dt=1e-5, gamman=200.0, gammat=200.0, mu=0.5, gravity=True,
              dump_every=None, box="-0.2 0.2 -0.2 0.2 -0.2 0.2", length=0.03, before_run=""):
    """Rods (position, axis, velocity, omega) of diameter D and `length`,
    the wall fixes `walls`, contacts with damping; rods.dump every
    dump_every steps (default: first and last)."""
    atoms = "".join(rod_lines(k + 1, *rod, length=length) for k, rod in enumerate(rods))
    every = dump_every or steps
    columns = COLUMNS.split()
    fmt = "%d" + " %.17g" * (len(columns) - 1)
    return f"""{rod_system()}
region box block {box} units box
create_box 1 box
{atoms}
{rod_contacts(dt, gamman, gammat, mu)}
{walls}
{"fix gravity all gravity 9.81 vector 0 0 -1" if gravity else ""}
fix move all nve/spherocylinder
compute axis all spherocylinder/axis
dump rods all custom {every} rods.dump {COLUMNS}
dump_modify rods sort id format "{fmt}"
{before_run}
run {steps}
"""


def ends(tmp_path):
    frames = read_dump(tmp_path / "rods.dump")
    return frames[0][1], frames[-1][1]


def vec(c, names, row=0):
    return np.array([c[n][row] for n in names])


AXIS = ("c_axis[1]", "c_axis[2]", "c_axis[3]")
PLANE = f"fix floor all wall/gran/spherocylinder {WALL_MODEL} primitive type 1 zplane 0.0"


def test_a_rod_dropped_flat_rests_on_both_ends(tmp_path):
    """Dropped flat from 1 mm: at rest on two contacts of equal overlap,
    m g / (2 k_n) each, so its centre sits at r - m g / (2 k_n), level."""
    mass, _, _ = solid_rod()
    run_liggghts(wall_deck([((0, 0, RADIUS + 0.001), (1, 0, 0), (0, 0, 0), (0, 0, 0))], PLANE,
                           steps=50000), tmp_path)
    _, end = ends(tmp_path)
    overlap = mass * G / (2 * KN)
    assert end["z"][0] == pytest.approx(RADIUS - overlap, abs=1e-3 * overlap)
    assert abs(end["c_axis[3]"][0]) < 1e-9
    assert np.linalg.norm(vec(end, ("vx", "vy", "vz"))) < 1e-7


def test_a_rod_dropped_upright_stands_on_its_cap(tmp_path):
    """Upright: one contact, at the lower cap, carrying m g."""
    mass, _, _ = solid_rod()
    half_core = (0.03 - D) / 2
    run_liggghts(wall_deck([((0, 0, half_core + RADIUS + 0.001), (0, 0, 1), (0, 0, 0), (0, 0, 0))], PLANE,
                           steps=50000), tmp_path)
    _, end = ends(tmp_path)
    overlap = mass * G / KN
    assert end["z"][0] == pytest.approx(half_core + RADIUS - overlap, abs=1e-3 * overlap)
    np.testing.assert_allclose(vec(end, AXIS), [0, 0, 1], atol=1e-12)


def test_a_tilted_rod_lands_on_one_end_tips_over_and_never_gains_energy(tmp_path):
    """Dropped at 30 degrees: it lands on its lower cap, tips over and
    comes to rest lying flat; its energy (translation, rotation, height)
    never rises above the start (beyond the elastic energy of the contacts,
    bounded here by k_n delta^2 with delta < 1e-4 m)."""
    mass, _, _ = solid_rod()
    tilt = math.radians(30)
    half_core = (0.03 - D) / 2
    z0 = half_core * math.sin(tilt) + RADIUS + 0.002
    run_liggghts(wall_deck([((0, 0, z0), (math.cos(tilt), 0, math.sin(tilt)), (0, 0, 0), (0, 0, 0))],
                           PLANE, steps=60000, dump_every=100), tmp_path)
    frames = read_dump(tmp_path / "rods.dump")
    energy = []
    for _, c in frames:
        v = vec(c, ("vx", "vy", "vz"))
        energy.append(0.5 * mass * v @ v + 0.5 * vec(c, ("angmomx", "angmomy", "angmomz"))
                      @ vec(c, ("omegax", "omegay", "omegaz")) + mass * G * c["z"][0])
    energy = np.array(energy)
    assert energy.max() <= energy[0] + KN * 1e-8
    end = frames[-1][1]
    assert abs(end["c_axis[3]"][0]) < 1e-6
    assert end["z"][0] == pytest.approx(RADIUS - mass * G / (2 * KN), abs=1e-3 * mass * G / KN)
    # it did tip: the axis passed from 30 degrees to flat
    assert max(abs(c["c_axis[3]"][0]) for _, c in frames[:5]) > 0.4


def test_a_rod_bounces_elastically_off_the_inside_of_a_cylinder(tmp_path):
    """No gravity, no damping, no friction: a rod lying along a chord
    (tangential) moving radially into the wall of a zcylinder touches it
    with both ends at once and comes back with its speed reversed and no
    spin."""
    rc = 0.05
    wall = f"fix side all wall/gran/spherocylinder {WALL_MODEL} primitive type 1 zcylinder {rc} 0.0 0.0"
    run_liggghts(wall_deck([((0.03, 0, 0), (0, 1, 0), (0.5, 0, 0), (0, 0, 0))], wall, steps=10000,
                           dt=5e-6, gamman=0.0, gammat=0.0, mu=0.0, gravity=False), tmp_path)
    _, end = ends(tmp_path)
    np.testing.assert_allclose(vec(end, ("vx", "vy", "vz")), [-0.5, 0, 0], atol=1e-4)
    assert np.linalg.norm(vec(end, ("omegax", "omegay", "omegaz"))) < 1e-9


def test_a_rod_on_a_turning_plate_is_dragged_into_co_rotation(tmp_path):
    """A rod lying tangentially at R0 on a plate that starts turning at
    Omega (no orifice): friction at its two ends spins it up to Omega and
    drags its centre to Omega R0 along the tangent within 0.05 s (the
    slip lasts about Omega R0 / (mu g) = 0.03 s).

    What it does afterwards is the stock tangential spring's, not rigid
    co-rotation: LIGGGHTS' history model (as the paper's, "kept parallel
    to the contact plane by truncation") does not turn the stored spring
    with the two bodies about the contact normal, so a contact stuck on a
    turning plate cannot keep pointing its force at the axis, and the rod
    creeps outwards (doc/fix_wall_gran_spherocylinder.md, "A rod stuck on
    the turning plate creeps outwards")."""
    omega, r0 = 2 * math.pi * 0.5, 0.05
    plate = (f"fix bottom all wall/gran/rotating {WALL_MODEL} primitive type 1 zplane 0.0 "
             f"orifice 0.0 omega {omega!r}")
    run_liggghts(wall_deck([((r0, 0, RADIUS), (0, 1, 0), (0, 0, 0), (0, 0, 0))], plate, steps=5000),
                 tmp_path)
    _, end = ends(tmp_path)
    x, y = end["x"][0], end["y"][0]
    radius = math.hypot(x, y)
    tangent = np.array([-y, x, 0]) / radius
    velocity = vec(end, ("vx", "vy", "vz"))
    assert radius == pytest.approx(r0, rel=1e-2)
    assert velocity @ tangent == pytest.approx(omega * radius, rel=1e-2)
    assert end["omegaz"][0] == pytest.approx(omega, rel=1e-3)


@pytest.mark.parametrize("axis, falls", [((0, 0, 1), True), ((1, 0, 0), False)])
def test_a_rod_passes_the_orifice_end_first_but_not_sideways(tmp_path, axis, falls):
    """Orifice of diameter 2 d, rod of diameter d and length 4 d above its
    centre: upright it falls through without touching the rim; lying flat
    it rests across the hole, on the plate beyond the rim."""
    length = 4 * D
    plate = f"fix bottom all wall/gran/rotating {WALL_MODEL} primitive type 1 zplane 0.0 orifice {2 * D!r}"
    z0 = (length / 2 if falls else RADIUS) + 0.001
    # 0.15 s: a free fall of 11 cm, inside the box
    run_liggghts(wall_deck([((0, 0, z0), axis, (0, 0, 0), (0, 0, 0))], plate, steps=15000, length=length),
                 tmp_path)
    _, end = ends(tmp_path)
    if falls:
        assert end["z"][0] < -length
        np.testing.assert_allclose(vec(end, ("vx", "vy")), [0, 0], atol=1e-12)
    else:
        assert end["z"][0] == pytest.approx(RADIUS, abs=1e-4 * D)
        assert np.linalg.norm(vec(end, ("vx", "vy", "vz"))) < 1e-6


def heap_deck(steps, before_run=""):
    """Eight rods of assorted orientations in two layers, dropped on the
    turning plate with an orifice inside a zcylinder, a floor below to
    catch what falls through: contacts with the plate, the rim, the side
    wall and each other."""
    rods = []
    for k in range(8):
        x, y = (0.02 if k % 2 else -0.02), (0.02 if (k // 2) % 2 else -0.02)
        axis = np.array([math.cos(k), 0.6 * math.sin(k), 0.8 * math.sin(2 * k)])
        rods.append(((x, y, 0.02 + 0.04 * (k // 4)), tuple(axis / np.linalg.norm(axis)), (0, 0, 0), (0, 0, 0)))
    walls = (f"fix side all wall/gran/spherocylinder {WALL_MODEL} primitive type 1 zcylinder 0.06 0.0 0.0\n"
             f"fix bottom all wall/gran/rotating {WALL_MODEL} primitive type 1 zplane 0.0 orifice 0.012 "
             f"frequency 1.0\n"
             f"fix catch all wall/gran/spherocylinder {WALL_MODEL} primitive type 1 zplane -0.1")
    return wall_deck(rods, walls, steps, dump_every=steps, before_run=before_run)


@pytest.mark.skipif(not has_mpirun(), reason="mpirun missing")
def test_two_ranks_give_the_one_rank_heap(tmp_path):
    steps = 20000
    run_liggghts(heap_deck(steps), tmp_path / "np1")
    run_liggghts(heap_deck(steps), tmp_path / "np2", nprocs=2)
    _, one = ends(tmp_path / "np1")
    _, two = ends(tmp_path / "np2")
    assert np.count_nonzero(one["omegax"]) == 8
    for name, values in one.items():
        np.testing.assert_allclose(two[name], values, rtol=1e-9, atol=1e-10)


def test_a_restart_keeps_the_wall_contacts(tmp_path):
    """Rods resting on the turning plate when the restart file is written:
    the resumed run (contact slots and their tangential history read back)
    is the uninterrupted one."""
    steps = 15000
    whole = heap_deck(steps).replace(f"run {steps}\n", f"run {steps}\nrun {steps}\n")
    run_liggghts(whole, tmp_path / "whole")
    run_liggghts(heap_deck(steps) + "write_restart half.restart\n", tmp_path / "half")
    tail = heap_deck(steps).split("neighbor", 1)[1]
    resumed = ("units si\natom_modify map array\nread_restart half.restart\nnewton off\n"
               "communicate single vel yes\nneighbor" + tail)
    (tmp_path / "resume").mkdir()
    (tmp_path / "resume" / "half.restart").write_bytes((tmp_path / "half" / "half.restart").read_bytes())
    run_liggghts(resumed, tmp_path / "resume")
    _, a = ends(tmp_path / "whole")
    _, b = ends(tmp_path / "resume")
    # resting on the plate and turning with it when the file was written
    assert np.count_nonzero(np.abs(a["fz"]) > 0) >= 4
    for name, values in a.items():
        np.testing.assert_allclose(b[name], values, rtol=1e-12, atol=1e-14)


def test_fix_reinject_re_enters_a_rod_at_rest_with_its_orientation(tmp_path):
    """A spinning rod thrown below the exit plane re-enters in the region
    at the top with its axis as it left, its velocity, spin and angular
    momentum zero; it then falls from rest, without turning."""
    axis = np.array([0.6, 0.0, 0.8])
    extra = ("region top block -0.05 0.05 -0.05 0.05 0.10 0.15 units box\n"
             "fix out all reinject exit z -0.05 region top seed 15485863\n")
    deck = wall_deck([((0, 0, -0.04), tuple(axis), (0, 0, -1.0), (5.0, -3.0, 20.0))], "", steps=2000,
                     dump_every=1, before_run=extra)
    run_liggghts(deck, tmp_path)
    frames = read_dump(tmp_path / "rods.dump")
    entry = next(k for k, (_, c) in enumerate(frames) if c["z"][0] > 0.05)
    before, first = frames[entry - 1][1], frames[entry][1]
    assert before["z"][0] < -0.05
    assert 0.10 <= first["z"][0] <= 0.15
    # kept, but for the turn of the step it re-enters on (|omega| dt)
    turn = np.linalg.norm(vec(before, ("omegax", "omegay", "omegaz"))) * 1e-5
    assert np.linalg.norm(vec(first, AXIS) - vec(before, AXIS)) < 1.01 * turn
    for names in (("omegax", "omegay", "omegaz"), ("angmomx", "angmomy", "angmomz")):
        assert np.all(vec(first, names) == 0.0)
    # from then on it falls without turning
    last = frames[-1][1]
    assert last["z"][0] < first["z"][0]
    np.testing.assert_allclose(vec(last, AXIS), vec(first, AXIS), atol=1e-15)
    assert np.all(vec(last, ("omegax", "omegay", "omegaz")) == 0.0)
