"""fix wall/gran/rotating in LAMMPS (our plugin; doc/fix_wall_gran_rotating_lammps.md):
the flat plate with an orifice, turning about the silo axis. A grain resting
on the plate loads it with its weight; a grain that cannot roll is carried at
the plate's speed; a grain over the hole falls through and one on the rim
edge feels the edge; the same grain-on-plate sequence as LIGGGHTS' fix of the
same name; two ranks as one; a restart in the middle of a contact; bad
input stops with an ERROR naming the keyword."""

import math

import numpy as np
import pytest

from analysis.testing import LiggghtsError, assert_dumps_close, liggghts_binary, run_deck
from lammps_host import has_mpirun, needs_lammps, run_lammps

pytestmark = needs_lammps

RADIUS = 0.005
DENSITY = 2500.0
MASS = DENSITY * 4.0 / 3.0 * math.pi * RADIUS ** 3
G = 9.81
KN = 1.0e5
KT = 4.0e4
MU = 0.5
DT = 1.0e-5

DUMP_COLUMNS = "id x y z vx vy vz omegax omegay omegaz fx fy fz"
FORMAT = " ".join(["%d"] + ["%.17g"] * 12)
WALL_LAW = f"normal hooke/stiffness {KN} {KT} 100 50 friction {MU}"
PLATE_OUTPUTS = """variable spin equal f_bottom[1]
variable load equal f_bottom[2]
variable torque equal f_bottom[3]
variable contacts equal f_bottom[4]"""


def deck(atoms, plate, steps, integrate="nve/sphere", gravity=True, extra="", thermo=1000):
    """A LAMMPS deck: grains (`create_atoms` lines) on the plate `plate`
    (the fix's arguments after the contact law), no pair style (grains
    apart), a dump every 100 steps and the plate's outputs in thermo."""
    return f"""
plugin load ${{plugin}}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
{extra}
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box
create_box 1 box
neighbor 0.001 bin
{atoms}
set group all diameter {2 * RADIUS} density {DENSITY}
{"fix grav all gravity 9.81 vector 0 0 -1" if gravity else ""}
fix bottom all wall/gran/rotating {WALL_LAW} {plate}
fix integrate all {integrate}
{PLATE_OUTPUTS}
timestep {DT}
thermo_style custom step v_spin v_load v_torque v_contacts
thermo_modify format float %.17g
thermo {thermo}
dump d all custom 100 dump.traj {DUMP_COLUMNS}
dump_modify d format line "{FORMAT}"
run {steps}
"""


def test_a_resting_grain_loads_the_plate_with_its_weight(tmp_path):
    """Placed at its equilibrium overlap m g / kn, the grain stays; the load
    output is -m g (the grains push the plate against its axis), one
    contact, no torque, no spin."""
    z = RADIUS - MASS * G / KN
    run = run_lammps(deck(f"create_atoms 1 single 0.02 0.01 {z!r} units box", "zplane 0", 2000),
                     tmp_path)
    thermo = run.thermo()
    np.testing.assert_allclose(thermo["v_load"], -MASS * G, rtol=1e-9)
    assert np.all(thermo["v_contacts"] == 1)
    assert np.all(thermo["v_spin"] == 0)
    assert np.all(np.abs(thermo["v_torque"]) < 1e-15)
    last = run.frames("dump.traj")[-1]
    assert abs(last["z"][0] - z) < 1e-12


def test_a_grain_on_the_turning_plate_reaches_the_plate_speed(tmp_path):
    """A grain that cannot roll (fix nve: its spin stays 0) dropped at rest
    on a plate turning at omega is dragged up to omega x r, and then moves
    with the plate (direction and size); while it speeds up the plate feels
    a torque against its rotation."""
    omega = 5.0
    z = RADIUS - MASS * G / KN
    run = run_lammps(deck(f"create_atoms 1 single 0.02 0.0 {z!r} units box",
                          f"zplane 0 omega {omega}", 30000, integrate="nve"), tmp_path)
    last = run.frames("dump.traj")[-1]
    x, y = last["x"][0], last["y"][0]
    velocity = np.array([last["vx"][0], last["vy"][0]])
    plate = omega * np.array([-y, x])
    np.testing.assert_allclose(velocity, plate, rtol=1e-3, atol=1e-4 * omega * 0.02)
    thermo = run.thermo()
    assert np.all(thermo["v_spin"] == omega)
    # the grain is being accelerated in the sense of rotation: the plate is braked
    assert thermo["v_torque"][0] < 0


def test_the_plate_torque_integrates_to_the_angular_momentum_given(tmp_path):
    """The torque output (the grains on the plate, about the axis) is what
    the plate gives the grains: over a spin-up of two grains that cannot
    roll, its time integral is minus their angular momentum about the axis
    (the grains start at rest; gravity has no moment about the axis).
    Measured with the trapezoid rule: equal to 3e-15; the test allows
    1e-10."""
    omega = 5.0
    z = RADIUS - MASS * G / KN
    atoms = (f"create_atoms 1 single 0.02 0.0 {z!r} units box\n"
             f"create_atoms 1 single -0.01 0.025 {z!r} units box")
    run = run_lammps(deck(atoms, f"zplane 0 omega {omega}", 20000, integrate="nve", thermo=1),
                     tmp_path)
    torque = run.thermo()["v_torque"]
    assert len(torque) == 20001
    impulse = DT * (torque.sum() - 0.5 * (torque[0] + torque[-1]))
    last = run.frames("dump.traj")[-1]
    momentum = MASS * np.sum(last["x"] * last["vy"] - last["y"] * last["vx"])
    assert momentum > 0.5 * MASS * omega * (0.02 ** 2 + 0.01 ** 2 + 0.025 ** 2)
    np.testing.assert_allclose(impulse, -momentum, rtol=1e-10)


def test_a_grain_over_the_hole_falls_through(tmp_path):
    """Centred over a hole three diameters wide, the grain never touches."""
    run = run_lammps(deck("create_atoms 1 single 0.001 0.0 0.008 units box",
                          "zplane 0 orifice 0.03", 10000), tmp_path)
    thermo = run.thermo()
    assert np.all(thermo["v_contacts"] == 0)
    assert run.frames("dump.traj")[-1]["z"][0] < -2 * RADIUS


def test_a_grain_beside_the_hole_stays_on_the_plate(tmp_path):
    """Centre over the plate (s > R), part of the grain over the hole: it
    rests on the flat face, loading the plate with its weight."""
    hole = 0.02
    z = RADIUS - MASS * G / KN
    run = run_lammps(deck(f"create_atoms 1 single {hole / 2 + 0.1 * RADIUS!r} 0.0 {z!r} units box",
                          f"zplane 0 orifice {hole}", 5000), tmp_path)
    np.testing.assert_allclose(run.thermo()["v_load"], -MASS * G, rtol=1e-9)
    assert abs(run.frames("dump.traj")[-1]["z"][0] - z) < 1e-12


def test_a_grain_on_the_rim_edge_is_pushed_along_the_rim_normal(tmp_path):
    """Centre over the hole (s < R) and touching the rim: the contact
    force points from the rim point to the centre, of size kn times the
    overlap (step 0, at rest: no damping, no tangential spring); the grain
    then slips off the edge into the hole."""
    hole_radius = 0.01
    inside = 0.2 * RADIUS              # centre this far inside the rim
    overlap = 1e-6
    distance = RADIUS - overlap
    height = math.sqrt(distance ** 2 - inside ** 2)
    run = run_lammps(deck(f"create_atoms 1 single {hole_radius - inside!r} 0.0 {height!r} units box",
                          f"zplane 0 orifice {2 * hole_radius}", 20000, gravity=False,
                          thermo=100),
                     tmp_path)
    first = run.frames("dump.traj")[0]
    normal = np.array([-inside, 0.0, height]) / distance
    expected = KN * overlap * normal
    force = np.array([first["fx"][0], first["fy"][0], first["fz"][0]])
    np.testing.assert_allclose(force, expected, rtol=1e-6, atol=1e-12 * KN * overlap)
    thermo = run.thermo()
    assert thermo["v_contacts"][0] == 1
    # pushed towards the axis, it leaves the edge
    assert thermo["v_contacts"][-1] == 0
    assert run.frames("dump.traj")[-1]["x"][0] < hole_radius - inside


def test_a_2d_slot_holds_a_disc_beside_it_and_lets_one_over_it_fall(tmp_path):
    """dimension 2, a yplane with a slot of 3 diameters: a disc beside the
    slot rests on the plate with its weight (m = pi r^2 rho, set
    density/disc); one over the slot falls through."""
    slot = 0.03
    mass = DENSITY * math.pi * RADIUS ** 2
    y = RADIUS - mass * G / KN
    atoms = (f"create_atoms 1 single {slot / 2 + 0.2 * RADIUS!r} {y!r} 0 units box\n"
             "create_atoms 1 single -0.002 0.008 0 units box")
    text = deck(atoms, f"yplane 0 orifice {slot}", 10000)
    for three, two in (("boundary f f f", "dimension 2\nboundary f f p"),
                       ("density 2500.0", "density/disc 2500.0"),
                       ("vector 0 0 -1", "vector 0 -1 0"),
                       ("fix integrate all nve/sphere", "fix flat all enforce2d\nfix integrate all nve/sphere disc")):
        assert three in text
        text = text.replace(three, two)
    run = run_lammps(text, tmp_path)
    thermo = run.thermo()
    np.testing.assert_allclose(thermo["v_load"], -mass * G, rtol=1e-9)
    last = run.frames("dump.traj")[-1]
    assert abs(last.atom(1)["y"] - y) < 1e-12
    assert last.atom(2)["y"] < -2 * RADIUS


# ---------------------------------------------------------------- LIGGGHTS

# (LIGGGHTS' model arguments, its model settings (after the primitive), its
#  property/global lines, the LAMMPS fix's contact-law arguments)
HOST_CASES = {
    "hooke_stiffness": (
        "model hooke/stiffness tangential history", "",
        """fix m_kn all property/global kn peratomtypepair 1 1e5
fix m_kt all property/global kt peratomtypepair 1 4e4
fix m_gn all property/global gamman peratomtypepair 1 100
fix m_gt all property/global gammat peratomtypepair 1 50
fix m_mu all property/global coefficientFriction peratomtypepair 1 0.5""",
        "normal hooke/stiffness 1e5 4e4 100 50 friction 0.5"),
    "hooke_stiffness_jiang_fixed_lc": (
        "model hooke/stiffness tangential history rolling_friction jiang", "",
        """fix m_kn all property/global kn peratomtypepair 1 1e5
fix m_kt all property/global kt peratomtypepair 1 4e4
fix m_gn all property/global gamman peratomtypepair 1 100
fix m_gt all property/global gammat peratomtypepair 1 50
fix m_mu all property/global coefficientFriction peratomtypepair 1 0.5
fix m_lc all property/global rollingContactLength peratomtypepair 1 0.002""",
        "normal hooke/stiffness 1e5 4e4 100 50 friction 0.5 rolling jiang 1 1 lc 0.002"),
    "hooke_jiang_overlap_lc_rolling_damping": (
        "model hooke tangential history rolling_friction jiang",
        "contactLengthFromOverlap on rollingDamping on",
        """fix m_Y all property/global youngsModulus peratomtype 5e6
fix m_nu all property/global poissonsRatio peratomtype 0.3
fix m_e all property/global coefficientRestitution peratomtypepair 1 0.8
fix m_v all property/global characteristicVelocity scalar 1.0
fix m_mu all property/global coefficientFriction peratomtypepair 1 0.5
fix m_rv all property/global coefficientRollingViscousDamping peratomtypepair 1 0.2""",
        "normal hooke 5e6 0.3 0.8 1.0 friction 0.5 rolling jiang 1 1 lc overlap "
        "rolling_damping 0.2"),
}


def grain_on_plate(host, case):
    """A grain thrown with spin at a turning plate with a hole: it bounces
    along the plate (impacts, sliding, rolling), crosses the rim edge and
    falls through the hole, in both hosts with the same contact law."""
    model, settings, properties, law = HOST_CASES[case]
    atoms = "create_atoms 1 single 0.02 0.001 0.0052 units box"
    if host == "liggghts":
        head = "communicate single vel yes"
        plugin = ""
        wall = (f"{properties}\n"
                # LIGGGHTS needs a pair style for its neighbor bins (one grain: no pairs)
                f"pair_style gran {model} {settings}\npair_coeff * *\n"
                f"fix bottom all wall/gran/rotating {model} "
                f"primitive type 1 zplane 0.0 {settings} orifice 0.02 omega 3")
        spin = "set atom 1 vx -0.2 vy 0.02 vz -0.05 omegax 2 omegay -40 omegaz 5"
        fmt = f'dump_modify d format "{FORMAT}"'
    else:
        head = "comm_modify vel yes"
        plugin = "plugin load ${plugin}"
        wall = f"fix bottom all wall/gran/rotating {law} zplane 0 orifice 0.02 omega 3"
        spin = "set atom 1 vx -0.2 vy 0.02 vz -0.05\nset atom 1 omega 2 -40 5"
        fmt = f'dump_modify d format line "{FORMAT}"'
    return f"""
{plugin}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
{head}
region box block -0.05 0.05 -0.05 0.05 -0.3 0.05 units box
create_box 1 box
neighbor 0.001 bin
{atoms}
set group all diameter {2 * RADIUS} density {DENSITY}
{spin}
fix grav all gravity 9.81 vector 0 0 -1
{wall}
fix integrate all nve/sphere
timestep {DT}
dump d all custom 50 dump.traj {DUMP_COLUMNS}
{fmt}
run 25000
"""


@pytest.mark.parametrize("case", sorted(HOST_CASES))
def test_the_grain_on_the_plate_is_the_same_in_both_hosts(tmp_path, case):
    """Both hosts integrate with nve/sphere and reach the same core
    functions (orifice_plate.h and rolling_law_jiang.h; contact_law.h here,
    LIGGGHTS' own models there, which contact_law.h reproduces bit for
    bit): measured, the trajectories agree to the last bit, so the test
    asks for that."""
    if not liggghts_binary().exists():
        pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
    liggghts = run_deck(grain_on_plate("liggghts", case), tmp_path / "liggghts")
    lammps = run_lammps(grain_on_plate("lammps", case), tmp_path / "lammps")
    ours = lammps.frames("dump.traj", columns=DUMP_COLUMNS.split()[:10])
    theirs = liggghts.frames("dump.traj", columns=DUMP_COLUMNS.split()[:10])
    # the grain bounced on the plate many times, crossed the rim edge (centre
    # over the hole, within a radius of the plate) and fell through the hole
    z = np.array([f["z"][0] for f in ours])
    s = np.array([math.hypot(f["x"][0], f["y"][0]) for f in ours])
    assert np.sum((s >= 0.01) & (z < RADIUS)) >= 3
    assert np.sum((s < 0.01) & (np.abs(z) < RADIUS)) > 20
    assert z[-1] < -RADIUS
    assert_dumps_close(ours, theirs, rtol=0, atol=0)


# ---------------------------------------------------------------- MPI, restart

FOUR_GRAINS = "\n".join(f"create_atoms 1 single {x!r} {y!r} {RADIUS - MASS * G / KN!r} units box"
                        for x, y in ((0.02, 0.003), (-0.02, -0.003), (0.004, 0.025),
                                     (-0.003, -0.03)))


@pytest.mark.skipif(not has_mpirun(), reason="mpirun is not installed")
def test_two_ranks_give_the_run_of_one(tmp_path):
    """Four grains rolling on a turning plate (with Jiang's rolling
    resistance) cross the boundary between the two ranks (x = 0) with their
    contact history: the trajectories are
    those of one rank to the last bit; the plate's sums over the ranks to
    round-off (the one sum is taken in another order)."""
    plate = "zplane 0 orifice 0.01 omega 10"
    law = f"{WALL_LAW} rolling jiang 1 1 lc overlap rolling_damping 0.2"
    serial = run_lammps(deck(FOUR_GRAINS, plate, 20000).replace(WALL_LAW, law), tmp_path / "np1")
    parallel = run_lammps(deck(FOUR_GRAINS, plate, 20000, extra="processors 2 1 1").replace(
        WALL_LAW, law), tmp_path / "np2", nprocs=2)
    # the grains 3 and 4, placed near x = 0, went round far enough to
    # change rank
    frames = serial.frames("dump.traj")
    for i in (3, 4):
        assert frames[-1].atom(i)["x"] * frames[0].atom(i)["x"] < 0
    assert_dumps_close(parallel.frames("dump.traj"), frames, rtol=0, atol=0)
    a, b = serial.thermo(), parallel.thermo()
    for name in ("v_load", "v_torque", "v_contacts"):
        np.testing.assert_allclose(b[name], a[name], rtol=1e-12, atol=1e-15)


def restart_decks(steps, cut):
    """The whole run, and the same cut by write_restart at step `cut` and
    continued in a second deck that defines the fix again. The plate starts
    turning at t = 0.1 s, after the cut: the schedule's time must come back
    from the restart file. No damping: a restarted LAMMPS run sees
    full-step velocities in its set-up force call (section 7 of
    doc/lammps_host.md)."""
    law = f"normal hooke/stiffness {KN} {KT} 0 0 friction {MU} rolling jiang 1 1 lc overlap"
    plate = "zplane 0 omega 6 start 0.1"
    whole = deck(FOUR_GRAINS, plate, steps).replace(WALL_LAW, law)
    first = deck(FOUR_GRAINS, plate, cut).replace(WALL_LAW, law)
    first += "write_restart cut.restart\n"
    second = f"""
plugin load ${{plugin}}
read_restart cut.restart
comm_modify vel yes
neighbor 0.001 bin
fix grav all gravity 9.81 vector 0 0 -1
fix bottom all wall/gran/rotating {law} {plate}
fix integrate all nve/sphere
{PLATE_OUTPUTS}
thermo_style custom step v_spin v_load v_torque v_contacts
thermo_modify format float %.17g
thermo 1000
dump d all custom 100 dump.second {DUMP_COLUMNS}
dump_modify d format line "{FORMAT}"
run {steps - cut}
"""
    return whole, first, second


def test_restart_mid_contact_continues_the_run(tmp_path):
    """Cut while the grains rest on the plate and while they roll on it
    (before and after the plate starts turning): the second deck continues
    the whole run to the last bit, tangential and rolling springs and the
    schedule included."""
    for cut in (6000, 14000):
        whole, first, second = restart_decks(20000, cut)
        reference = run_lammps(whole, tmp_path / f"whole{cut}")
        run_lammps(first, tmp_path / f"split{cut}")
        continued = run_lammps(second, tmp_path / f"split{cut}")
        frames = [f for f in reference.frames("dump.traj") if f.step >= cut]
        assert_dumps_close(continued.frames("dump.second"), frames, rtol=0, atol=0)
        spin = continued.thermo()["v_spin"]
        steps = continued.thermo()["Step"]
        # the plate turns from t = 0.1 s (step 10000) in the continued run too
        assert np.all(spin[steps < 10000] == 0) and np.all(spin[steps >= 10000] == 6)


def test_restart_with_damping_continues_the_run_to_round_off(tmp_path):
    """With damping the continued run differs from the uninterrupted one:
    its set-up force call sees the full-step velocities written to the
    restart file, where the uninterrupted run's force of that step saw the
    half-step ones. Measured (cut at step 14000, grains rolling): positions
    to 9e-14 m, velocities to 8e-10 m/s (of 0.06 m/s), spins to 4e-7 rad/s
    (of about 10 rad/s); the test allows 1e-6 (a lost or wrong history
    moves them by far more)."""
    cut = 14000
    undamped = f"normal hooke/stiffness {KN} {KT} 0 0"
    damped = f"normal hooke/stiffness {KN} {KT} 100 50"
    whole, first, second = (d.replace(undamped, damped) for d in restart_decks(20000, cut))
    reference = run_lammps(whole, tmp_path / "whole")
    run_lammps(first, tmp_path / "split")
    continued = run_lammps(second, tmp_path / "split")
    frames = [f for f in reference.frames("dump.traj") if f.step >= cut]
    assert_dumps_close(continued.frames("dump.second"), frames, rtol=1e-6, atol=1e-6)


def test_a_new_time_step_keeps_the_schedule(tmp_path):
    """`timestep` between two runs: the schedule's clock goes on from the
    time reached. 0.05 s at 1e-5 s, then 2e-5 s steps: the plate starts
    (t = 0.1 s) at step 5000 + 0.05 / 2e-5 = 7500."""
    text = deck(FOUR_GRAINS, "zplane 0 omega 6 start 0.1", 5000, thermo=100)
    text += "timestep 2e-5\nrun 5000\n"
    thermo = run_lammps(text, tmp_path).thermo()
    steps, spin = thermo["Step"], thermo["v_spin"]
    assert np.all(spin[steps < 7500] == 0) and np.all(spin[steps >= 7500] == 6)


# ---------------------------------------------------------------- bad input

BAD = [
    (f"{WALL_LAW} zplane 0 orifce 0.01", ["unknown keyword 'orifce'"]),
    (f"{WALL_LAW} zplane 0 orifice -0.01", ["orifice", ">= 0"]),
    (f"{WALL_LAW} zplane 0 orifice 0.2", ["orifice", "does not fit"]),
    (f"{WALL_LAW} zplane 0 omega -1", ["omega must be >= 0"]),
    (f"{WALL_LAW} zplane 0 omega 1 frequency 1", ["either omega or frequency"]),
    (f"{WALL_LAW} zplane 0 axis 1 0 0", ["axis must be normal to the plate"]),
    (f"{WALL_LAW} zplane 0 axis 0 0 2", ["axis must be a unit vector"]),
    (f"{WALL_LAW} zplane 0 start -1", ["start", ">= 0"]),
    (f"{WALL_LAW} zplane 0 open x", ["open expects a number, got 'x'"]),
    (f"{WALL_LAW} zplane 0 center 0 0", ["center needs 3 values"]),
    (f"{WALL_LAW} zplane 0 xplane 0", ["xplane: give one plane only"]),
    (f"{WALL_LAW}", ["the plate is required"]),
    ("friction 0.5 zplane 0", ["normal is required"]),
    (f"normal hooke/stiffness {KN} {KT} 100 50 zplane 0", ["friction is required"]),
    (f"normal hooke/stiffness 0 {KT} 100 50 friction 0.5 zplane 0", ["kn must be > 0"]),
    ("normal hertz 1 2 3 4 friction 0.5 zplane 0", ["unknown normal model 'hertz'"]),
    (f"{WALL_LAW} limit_force maybe zplane 0", ["limit_force expects yes or no"]),
    (f"{WALL_LAW} rolling sds 1 1 lc 0.001 zplane 0", ["unknown rolling model 'sds'"]),
    (f"{WALL_LAW} rolling jiang 1 1 0.001 zplane 0", ["followed by lc, got '0.001'"]),
    (f"{WALL_LAW} rolling jiang 0 1 lc 0.001 zplane 0", ["rolling jiang a", "> 0"]),
    (f"{WALL_LAW} rolling_damping 0.2 zplane 0", ["rolling_damping needs rolling jiang"]),
    (f"{WALL_LAW} rolling jiang 1 1 lc 0.02 zplane 0", ["rolling jiang lc 0.02",
                                                        "larger than the diameter"]),
]


@pytest.mark.parametrize("arguments,words", BAD, ids=[b[0].split()[-2] + "-" + str(i)
                                                       for i, b in enumerate(BAD)])
def test_bad_input_names_the_keyword(tmp_path, arguments, words):
    text = deck("create_atoms 1 single 0 0 0.0049 units box", "", 10).replace(
        f"wall/gran/rotating {WALL_LAW} ", f"wall/gran/rotating {arguments}")
    with pytest.raises(LiggghtsError) as error:
        run_lammps(text, tmp_path)
    assert "fix wall/gran/rotating" in error.value.message
    for word in words:
        assert word in error.value.message


def test_a_2d_plate_must_be_at_rest(tmp_path):
    text = deck("create_atoms 1 single 0 0.01 0 units box", "", 10)
    text = text.replace("boundary f f f", "dimension 2\nboundary f f p").replace(
        f"wall/gran/rotating {WALL_LAW} ", f"wall/gran/rotating {WALL_LAW} yplane 0 omega 1")
    with pytest.raises(LiggghtsError) as error:
        run_lammps(text, tmp_path)
    assert "omega: a 2D plate cannot rotate" in error.value.message
