"""The contact law of src_plugin/core/contact_law.h (normal spring-dashpot
of LIGGGHTS' `model hooke/stiffness` and `model hooke`, tangential spring
of `tangential history`), through a small driver compiled here with g++.

Two parts:

- Hand values (no LIGGGHTS, the fast tier): a held contact gives
  Fn = kn delta_n along the normal, an approaching one adds -gamman vn; a
  tangential drag loads the spring by vtr dt per step until kt |shear|
  reaches mu Fn, stays there (shear = mu Fn / kt) and unloads elastically
  when the drag reverses; the lever arm is r - delta_n/2 (also at a wall);
  the torque is the cross product of the lever arm and the force; a
  rotating normal removes the normal part of the shear without restoring
  its length; `model hooke`'s stiffness and damping from Y*, e, the
  characteristic velocity, meff and reff. Expected values are worked out
  here from those equations, never taken from the driver.
- Against LIGGGHTS itself (marked `engine`): a pair of grains and a grain
  on a plane, moved by `fix move` through approach, stick, slip both ways,
  spin and separation, with `model hooke/stiffness` and `model hooke`; the
  driver replays LIGGGHTS' dumped kinematics and must give its forces,
  torques and tangential history to 1e-12 relative. The header repeats
  LIGGGHTS' operations in LIGGGHTS' order, so the two agree bit for bit
  (they do, on this machine); 1e-12 only leaves room for a compiler that
  rounds an operation differently, and is far below any difference of
  convention (the numbers: comment above ENGINE_TOLERANCE).
"""

import math
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DRIVER_SOURCE = ROOT / "tests" / "contact_law_driver.cpp"

# hand values: the formulas here and in the header round differently
# (e.g. a sum taken in another order), so they agree to a few ulps
HAND = 1e-12

RADIUS_I = 0.005
RADIUS_J = 0.004
MASS_I = 1.3e-3
MASS_J = 0.7e-3
KN = 1.0e5
KT = 4.0e4
MU = 0.4
DT = 1.0e-5


@pytest.fixture(scope="session")
def driver(tmp_path_factory):
    """Compiles the driver once; returns run(commands) -> one list of
    fields per command."""
    executable = tmp_path_factory.mktemp("contact_law") / "contact_law_driver"
    build = subprocess.run(
        ["g++", "-std=c++11", "-O2", "-Wall", "-Wextra", "-Werror", "-pedantic",
         f"-I{ROOT / 'src_plugin' / 'core'}", str(DRIVER_SOURCE), "-o", str(executable)],
        capture_output=True, text=True)
    if build.returncode != 0:
        pytest.fail(f"contact_law_driver does not compile:\n{build.stderr}")

    def run(commands):
        result = subprocess.run([str(executable)], input="\n".join(commands) + "\n",
                                capture_output=True, text=True, check=True, timeout=60)
        lines = result.stdout.splitlines()
        assert len(lines) == len(commands), result.stdout
        return [line.split() for line in lines]
    return run


def parse_contact(fields):
    """A 'contact' reply as a dict of floats and 3-lists; None for 'apart'."""
    if fields[0] == "apart":
        return None
    assert fields[0] == "contact", fields
    reply = {"fn": float(fields[2]), "slides": fields[4] == "1", "overlap": float(fields[6])}
    at = 7
    for name in ("force", "torque_i", "torque_j", "shear"):
        assert fields[at] == name, fields
        reply[name] = [float(v) for v in fields[at + 1:at + 4]]
        at += 4
    return reply


def numbers(values):
    return " ".join(repr(float(v)) for v in values)


def stiffness_model(gamman=0.0, gammat=0.0, absolute=0, tangential_damping=1, limit=0,
                    kn=KN, kt=KT, mu=MU):
    return (f"model hooke/stiffness {kn!r} {kt!r} {gamman!r} {gammat!r} {mu!r} "
            f"{absolute} {tangential_damping} {limit}")


def pair_step(x_j, v_i=(0, 0, 0), v_j=(0, 0, 0), omega_i=(0, 0, 0), omega_j=(0, 0, 0),
              update=1, x_i=(0, 0, 0)):
    """Grain i (radius 5 mm) at x_i, grain j (4 mm) at x_j."""
    return (f"pair {update} {DT!r} {numbers(x_i)} {numbers(x_j)} {numbers(v_i)} "
            f"{numbers(v_j)} {numbers(omega_i)} {numbers(omega_j)} "
            f"{RADIUS_I!r} {RADIUS_J!r} {MASS_I!r} {MASS_J!r}")


def close(actual, expected, scale):
    return all(abs(a - e) <= HAND * scale for a, e in zip(actual, expected))


# ---------------------------------------------------------------- normal force

def test_held_contact_pushes_apart_with_kn_overlap(driver):
    overlap = 1.0e-4
    distance = RADIUS_I + RADIUS_J - overlap
    reply = parse_contact(driver([stiffness_model(), pair_step((distance, 0, 0))])[1])
    fn = KN * overlap
    assert math.isclose(reply["fn"], fn, rel_tol=1e-9)   # the overlap itself rounds
    assert math.isclose(reply["overlap"], overlap, rel_tol=1e-9)
    # j sits at +x: the force on i points to -x, with no tangential part
    assert close(reply["force"], [-reply["fn"], 0.0, 0.0], fn)
    assert [abs(t) for t in reply["torque_i"]] == [0.0, 0.0, 0.0]
    assert not reply["slides"]


def test_damping_uses_meff_unless_absolute(driver):
    overlap, approach = 1.0e-4, 0.2       # i moves towards j at 0.2 m/s
    distance = RADIUS_I + RADIUS_J - overlap
    gamman = 50.0                         # 1/s, times meff
    meff = MASS_I * MASS_J / (MASS_I + MASS_J)
    replies = driver([
        stiffness_model(gamman=gamman),
        pair_step((distance, 0, 0), v_i=(approach, 0, 0)),
        stiffness_model(gamman=gamman, absolute=1),
        pair_step((distance, 0, 0), v_i=(approach, 0, 0)),
    ])
    elastic = KN * parse_contact(replies[1])["overlap"]
    # vn = (v_i - v_j).n = approach * (-1) < 0: the dashpot pushes harder
    assert math.isclose(parse_contact(replies[1])["fn"], elastic + gamman * meff * approach,
                        rel_tol=HAND)
    assert math.isclose(parse_contact(replies[3])["fn"], elastic + gamman * approach,
                        rel_tol=HAND)


def test_limit_force_clips_an_attractive_normal_force(driver):
    overlap, separation = 1.0e-6, 1.0      # fast separation: damping exceeds the spring
    distance = RADIUS_I + RADIUS_J - overlap
    replies = driver([
        stiffness_model(gamman=5000.0),
        pair_step((distance, 0, 0), v_i=(-separation, 0, 0)),
        stiffness_model(gamman=5000.0, limit=1),
        pair_step((distance, 0, 0), v_i=(-separation, 0, 0)),
    ])
    assert parse_contact(replies[1])["fn"] < 0.0
    assert parse_contact(replies[3])["fn"] == 0.0


def test_apart_is_no_contact_and_clears_the_history(driver):
    replies = driver([stiffness_model(), "shear 1e-5 2e-5 0",
                      pair_step((RADIUS_I + RADIUS_J, 0, 0)),   # touching exactly: apart
                      pair_step((RADIUS_I + RADIUS_J - 1e-6, 0, 0))])
    assert replies[2] == ["apart"]
    assert parse_contact(replies[3])["shear"] == [0.0, 0.0, 0.0]


# ---------------------------------------------------------------- tangential spring

def test_drag_loads_the_spring_caps_at_mu_fn_and_unloads(driver):
    """i held against j (normal -x), dragged along +y at u, then back."""
    overlap, u = 1.0e-4, 0.05
    distance = RADIUS_I + RADIUS_J - overlap
    gammat = 20.0                          # 1/s, times meff; acts while sticking only
    meff = MASS_I * MASS_J / (MASS_I + MASS_J)
    load, unload = 300, 500
    commands = [stiffness_model(gammat=gammat)]
    for step in range(load + unload):
        commands.append(pair_step((distance, 0, 0), v_i=(0, u if step < load else -u, 0)))
    replies = [parse_contact(fields) for fields in driver(commands)[1:]]
    fn = replies[0]["fn"]
    cap = MU * fn
    shear, expected_slides = 0.0, []
    for step, reply in enumerate(replies):
        rate = u if step < load else -u
        shear += rate * DT
        if KT * abs(shear) > cap:
            shear = math.copysign(cap / KT, shear)
            force = -KT * shear
            expected_slides.append(True)
        else:
            force = -KT * shear - gammat * meff * rate
            expected_slides.append(False)
        assert math.isclose(reply["shear"][1], shear, rel_tol=1e-9, abs_tol=1e-18), step
        assert math.isclose(reply["force"][1], force, rel_tol=1e-9, abs_tol=1e-12 * cap), step
        assert abs(reply["shear"][0]) + abs(reply["shear"][2]) == 0.0
        assert math.isclose(reply["force"][0], -fn, rel_tol=HAND)
    assert [r["slides"] for r in replies] == expected_slides
    # all three regimes happen: sticking, sliding (at the cap), elastic unloading
    # through zero, and sliding the other way
    assert not expected_slides[0] and expected_slides[load - 1]
    assert not expected_slides[load] and expected_slides[-1]
    assert replies[load - 1]["force"][1] == pytest.approx(-cap, rel=HAND)
    assert replies[-1]["force"][1] == pytest.approx(cap, rel=HAND)


def test_lever_arm_is_radius_minus_half_overlap_and_torque_is_r_cross_f(driver):
    """i spins about z: its contact point (at -cri n from its centre, n = -x,
    so at +cri x) moves at omega z x (cri x) = cri omega y, and the spring
    pulls it back: Ft = -kt cri omega dt y (no damping), torque
    = (cri x) x Ft on i and (-crj x) x (-Ft) on j."""
    overlap, omega = 2.0e-4, 3.0
    distance = RADIUS_I + RADIUS_J - overlap
    cri, crj = RADIUS_I - overlap / 2, RADIUS_J - overlap / 2
    replies = driver([stiffness_model(),
                      pair_step((distance, 0, 0), omega_i=(0, 0, omega)),
                      stiffness_model(),
                      pair_step((distance, 0, 0), omega_j=(0, 0, omega))])
    spun_i, spun_j = parse_contact(replies[1]), parse_contact(replies[3])
    ft = -KT * cri * omega * DT
    assert math.isclose(spun_i["force"][1], ft, rel_tol=1e-9)
    assert close(spun_i["torque_i"], [0, 0, cri * ft], abs(cri * ft))
    assert close(spun_i["torque_j"], [0, 0, crj * ft], abs(cri * ft))
    # j's spin moves j's contact point (at -crj x from j) at omega z x (-crj x)
    # = -crj omega y; relative to it, i's point moves at +crj omega y
    ft_j = -KT * crj * omega * DT
    assert math.isclose(spun_j["force"][1], ft_j, rel_tol=1e-9)


def test_wall_lever_arm_is_radius_minus_half_overlap(driver):
    overlap, omega, mass = 1.0e-4, 2.0, 1.3e-3
    z = RADIUS_I - overlap
    replies = driver([stiffness_model(),
                      f"zplane 1 {DT!r} 0.0 0 0 {z!r} 0 0 0 {omega!r} 0 0 {RADIUS_I!r} {mass!r}"])
    reply = parse_contact(replies[1])
    cr = RADIUS_I - overlap / 2
    # the contact point (at -cr z) moves at omega x x (-cr z) = +cr omega y
    ft = -KT * cr * omega * DT
    assert math.isclose(reply["fn"], KN * overlap, rel_tol=1e-9)
    assert math.isclose(reply["force"][2], KN * overlap, rel_tol=1e-9)
    assert math.isclose(reply["force"][1], ft, rel_tol=1e-9)
    assert close(reply["torque_i"], [cr * ft, 0, 0], abs(cr * ft))  # (-cr z) x (ft y)
    assert [abs(t) for t in reply["torque_j"]] == [0.0, 0.0, 0.0]


def test_rotating_normal_projects_the_shear_without_restoring_its_length(driver):
    overlap, angle = 1.0e-4, 0.3
    distance = RADIUS_I + RADIUS_J - overlap
    turned = (distance * math.cos(angle), distance * math.sin(angle), 0.0)
    s = 2.0e-6     # below the cap: mu kn overlap / kt = 1e-4
    replies = driver([stiffness_model(), f"shear 0 {s!r} 0",
                      pair_step(turned)])       # held still: vtr = 0
    shear = parse_contact(replies[2])["shear"]
    # n = -(cos a, sin a, 0): shear - (shear.n) n, length s cos a
    expected = [-s * math.sin(angle) * math.cos(angle), s * math.cos(angle) ** 2, 0.0]
    assert close(shear, expected, s)
    assert math.isclose(math.hypot(*shear), s * math.cos(angle), rel_tol=HAND)


def test_read_only_step_leaves_the_history(driver):
    """update = 0 (a run's set-up, compute pair/gran/local): the shear is
    read, capped in the force, but neither advanced nor cut back."""
    overlap = 1.0e-4
    distance = RADIUS_I + RADIUS_J - overlap
    big = 1.0e-3   # far beyond the cap mu kn overlap / kt = 1e-4
    replies = driver([stiffness_model(), f"shear 0 {big!r} 0",
                      pair_step((distance, 0, 0), v_i=(0, 1.0, 0), update=0),
                      pair_step((distance, 0, 0), v_i=(0, 1.0, 0), update=1)])
    read_only, updated = parse_contact(replies[2]), parse_contact(replies[3])
    cap = MU * read_only["fn"]
    assert read_only["shear"] == [0.0, big, 0.0]
    assert read_only["slides"] and math.isclose(read_only["force"][1], -cap, rel_tol=HAND)
    assert math.isclose(updated["shear"][1], cap / KT, rel_tol=HAND)


# ---------------------------------------------------------------- model hooke

def test_hooke_stiffness_and_damping_from_youngs_modulus(driver):
    youngs, poisson, restitution, v_char = 5.0e6, 0.3, 0.9, 1.0
    meff, reff = 4.0e-4, 2.2e-3
    youngs_eff = 1.0 / (2 * (1 - poisson ** 2) / youngs)
    kn = 16 / 15 * math.sqrt(reff) * youngs_eff * (
        15 * meff * v_char ** 2 / (16 * math.sqrt(reff) * youngs_eff)) ** 0.2
    log_e = math.log(restitution)
    gamman = math.sqrt(4 * meff * kn * log_e ** 2 / (log_e ** 2 + math.pi ** 2))
    for damping in (1, 0):
        fields = driver([f"model hooke {youngs!r} {poisson!r} {youngs!r} {poisson!r} "
                         f"{restitution!r} {v_char!r} {MU!r} {damping} 0",
                         f"spring {meff!r} {reff!r}"])[1]
        assert fields[0] == "spring"
        got = [float(v) for v in fields[1:]]
        assert got == pytest.approx([kn, kn, gamman, gamman if damping else 0.0], rel=HAND)
    # the restitution it stands for: a linear spring-dashpot of these
    # constants rebounds at exp(-pi / sqrt(4 meff kn / gamman^2 - 1))
    zeta = gamman / math.sqrt(4 * meff * kn)
    assert math.exp(-math.pi * zeta / math.sqrt(1 - zeta ** 2)) == pytest.approx(restitution)


# ================================================================ against LIGGGHTS
#
# Two grains (and, separately, a grain and the plane z = 0) moved by
# `fix move` along a scripted path: they approach, press (overlap up to
# 1e-4 m), slide to and fro in two directions while the normal turns, spin
# (the spins change between three runs of 100 steps, through `set`), and
# separate. Neither grain is integrated (fix move sets x and v; omega stays
# as set), so the dumped x, v, omega are the ones the contact saw. LIGGGHTS
# dumps every step with %.17g: the grains' f and torque (the contact's
# force and torques of the step, the only ones acting), for the pair also
# compute pair/gran/local's force, torque and tangential history (a
# re-evaluation at the end of the step that reads the history without
# advancing it), for the wall the wall's history (fix property/atom
# history_<wall id>). The driver replays the same kinematics.
#
# Tolerance: 1e-12 relative (to the largest |value| of that quantity along
# the run). contact_law.h performs LIGGGHTS' operations in LIGGGHTS' order
# on the same doubles (SSE2, no FMA, no -ffast-math in either build), so
# the sequences are expected to agree bit for bit; 1e-12 leaves room for
# a compiler that contracts or reorders an operation differently (n =
# delta/r instead of delta*(1/r) moves the results by 4e-16), and is far
# below any difference of convention: measured on these paths, a wall
# lever arm r_i instead of r_i - delta_n/2 moves the torque by 1e-2, a
# cap on spring plus damping force the force by 6e-3, restoring the
# shear's length after the projection the force by 7e-7 (the re-read
# force by 2e-3).

ENGINE_TOLERANCE = 1e-12
ENGINE_DT = 1.0e-5
STEPS_PER_RUN = 100
SPINS = [  # (omega of grain 1, omega of grain 2) in each of the three runs, rad/s
    ((0.0, 0.0, 20.0), (5.0, 0.0, -10.0)),
    ((10.0, -15.0, 0.0), (-5.0, 8.0, 0.0)),
    ((-5.0, 5.0, -30.0), (0.0, -12.0, 6.0)),
]
STIFFNESS = {"kn": 1.0e5, "kt": 4.0e4, "gamman": 60.0, "gammat": 25.0, "mu": 0.4}
HOOKE = {"Y": 5.0e7, "nu": 0.3, "e": 0.8, "v_char": 0.5, "mu": 0.8}
MODELS = {
    "hooke/stiffness": f"""
fix m_kn all property/global kn peratomtypepair 1 {STIFFNESS['kn']!r}
fix m_kt all property/global kt peratomtypepair 1 {STIFFNESS['kt']!r}
fix m_gn all property/global gamman peratomtypepair 1 {STIFFNESS['gamman']!r}
fix m_gt all property/global gammat peratomtypepair 1 {STIFFNESS['gammat']!r}
fix m_mu all property/global coefficientFriction peratomtypepair 1 {STIFFNESS['mu']!r}
""",
    "hooke": f"""
fix m_Y all property/global youngsModulus peratomtype {HOOKE['Y']!r}
fix m_nu all property/global poissonsRatio peratomtype {HOOKE['nu']!r}
fix m_e all property/global coefficientRestitution peratomtypepair 1 {HOOKE['e']!r}
fix m_mu all property/global coefficientFriction peratomtypepair 1 {HOOKE['mu']!r}
fix m_vc all property/global characteristicVelocity scalar {HOOKE['v_char']!r}
""",
}


def driver_model(model):
    if model == "hooke/stiffness":
        s = STIFFNESS
        return stiffness_model(gamman=s["gamman"], gammat=s["gammat"], kn=s["kn"],
                               kt=s["kt"], mu=s["mu"])
    h = HOOKE
    return (f"model hooke {h['Y']!r} {h['nu']!r} {h['Y']!r} {h['nu']!r} {h['e']!r} "
            f"{h['v_char']!r} {h['mu']!r} 1 0")


def format17(count, first="%.17g"):
    return '"' + " ".join([first] + ["%.17g"] * (count - 1)) + '"'


ATOM_COLUMNS = "id x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz radius mass"

# the path: overlap 1.1e-4 sin(pi t / 2.6 ms) - 1e-5 m (contact from step 8 to 252);
# the pair's normal swings by 22 mrad about z (period 1 ms) and 10 mrad out
# of plane (1.5 ms); grain 1 drifts at (2, -1, 3) mm/s
PAIR_PATH = """
variable t equal step*{dt}
variable D equal 0.009+1e-5-1.1e-4*sin(PI*v_t/2.6e-3)
variable Dd equal -1.1e-4*PI/2.6e-3*cos(PI*v_t/2.6e-3)
variable a equal 0.022*sin(2*PI*v_t/1e-3)
variable ad equal 0.022*2*PI/1e-3*cos(2*PI*v_t/1e-3)
variable b equal 0.01*sin(2*PI*v_t/1.5e-3)
variable bd equal 0.01*2*PI/1.5e-3*cos(2*PI*v_t/1.5e-3)
variable ux equal cos(v_a)*cos(v_b)
variable uy equal sin(v_a)*cos(v_b)
variable uz equal sin(v_b)
variable dux equal -v_ad*sin(v_a)*cos(v_b)-v_bd*cos(v_a)*sin(v_b)
variable duy equal v_ad*cos(v_a)*cos(v_b)-v_bd*sin(v_a)*sin(v_b)
variable duz equal v_bd*cos(v_b)
variable x2 equal 0.002*v_t+v_D*v_ux-(0.009+1e-5)
variable y2 equal -0.001*v_t+v_D*v_uy
variable z2 equal 0.003*v_t+v_D*v_uz
variable vx2 equal 0.002+v_Dd*v_ux+v_D*v_dux
variable vy2 equal -0.001+v_Dd*v_uy+v_D*v_duy
variable vz2 equal 0.003+v_Dd*v_uz+v_D*v_duz
fix m1 g1 move linear 0.002 -0.001 0.003
fix m2 g2 move variable v_x2 v_y2 v_z2 v_vx2 v_vy2 v_vz2
"""

# the grain on the plane: the same overlap; it slides along x (period 1 ms,
# 2e-4 m) and y (1.3 ms, 1e-4 m)
WALL_PATH = """
variable t equal step*{dt}
variable x1 equal 2e-4*sin(2*PI*v_t/1e-3)
variable vx1 equal 2e-4*2*PI/1e-3*cos(2*PI*v_t/1e-3)
variable y1 equal 1e-4*sin(2*PI*v_t/1.3e-3)
variable vy1 equal 1e-4*2*PI/1.3e-3*cos(2*PI*v_t/1.3e-3)
variable z1 equal -1.1e-4*sin(PI*v_t/2.6e-3)
variable vz1 equal -1.1e-4*PI/2.6e-3*cos(PI*v_t/2.6e-3)
fix m1 g1 move variable v_x1 v_y1 v_z1 v_vx1 v_vy1 v_vz1
"""


def scripted_deck(model, wall, pair_path=None, spins=None, steps_per_run=STEPS_PER_RUN):
    """The deck: grain 1 (d = 10 mm, 2500 kg/m3) and, for the pair, grain 2
    (d = 8 mm, 2700 kg/m3); one run per entry of spins (default SPINS)."""
    if wall:
        model_args = f"model {model} tangential history"
        atoms = """
create_atoms 1 single 0 0 0.00501 units box
set atom 1 diameter 0.01 density 2500
group g1 id 1
"""
        contact = f"fix wall all wall/gran {model_args} primitive type 1 zplane 0.0\n"
        path = WALL_PATH
        columns = ATOM_COLUMNS + " f_history_wall[1] f_history_wall[2] f_history_wall[3]"
        local = ""
    else:
        atoms = """
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 0.00901 0 0 units box
set atom 1 diameter 0.01 density 2500
set atom 2 diameter 0.008 density 2700
group g1 id 1
group g2 id 2
"""
        contact = ""
        path = pair_path or PAIR_PATH
        columns = ATOM_COLUMNS
        local = f"""
compute pgl all pair/gran/local id force torque history
dump dl all local 1 dump.pair {' '.join(f'c_pgl[{k}]' for k in range(1, 13))}
dump_modify dl format {format17(12)}
"""
    runs = []
    for spin_1, spin_2 in spins or SPINS:
        runs.append("set atom 1 omegax {} omegay {} omegaz {}".format(*spin_1))
        if not wall:
            runs.append("set atom 2 omegax {} omegay {} omegaz {}".format(*spin_2))
        runs.append(f"run {steps_per_run}")
    runs = "\n".join(runs)
    return f"""
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
communicate single vel yes
region box block -0.03 0.03 -0.03 0.03 -0.03 0.03 units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{MODELS[model]}
pair_style gran model {model} tangential history
pair_coeff * *
timestep {ENGINE_DT!r}
{contact}
{atoms}
{path.format(dt=repr(ENGINE_DT))}
dump d all custom 1 dump.atoms {columns}
dump_modify d sort id format {format17(len(columns.split()), first="%d")}
{local}
thermo 100
{runs}
"""


def frames_by_step(path):
    from analysis.common.lammps_io import read_dump
    frames = {}
    for step, columns in read_dump(path):
        frames.setdefault(step, columns)   # a run's set-up repeats a step: keep the first
    return frames


def vec(columns, names, row):
    return [float(columns[name][row]) for name in names]


def worst(pairs):
    """Largest |a - b| over the run, relative to the largest |b|."""
    scale = max(abs(b) for _, b in pairs)
    return max(abs(a - b) for a, b in pairs) / scale, scale


def compare(label, ours, theirs, report):
    pairs = [(a, b) for a_vec, b_vec in zip(ours, theirs) for a, b in zip(a_vec, b_vec)]
    relative, scale = worst(pairs)
    exact = sum(a == b for a, b in pairs)
    report.append(f"{label}: worst {relative:.3g} of {scale:.3g}, {exact}/{len(pairs)} identical")
    return relative


def replay_pair(driver, model, atoms, pairs, steps, policy="zero"):
    """Replays LIGGGHTS' dumped pair kinematics through the driver: returns
    (ours, theirs, contact steps, slides), ours and theirs dicts of lists of
    3-vectors: f1, f2, t1, t2 the grains' force and torque of the step
    (history advanced), pgl_* compute pair/gran/local's re-evaluation at
    the end of the step (history read only) and the history."""
    commands = [driver_model(model), f"separated {policy}"]
    for step in steps:
        c = atoms[step]
        i, j = 0, 1      # rows of grains 1 and 2 (sorted by id)
        # x_i x_j v_i v_j omega_i omega_j
        kinematics = " ".join(numbers(vec(c, names, row))
                              for names in (("x", "y", "z"), ("vx", "vy", "vz"),
                                            ("omegax", "omegay", "omegaz"))
                              for row in (i, j))
        tail = numbers([c["radius"][i], c["radius"][j], c["mass"][i], c["mass"][j]])
        commands.append(f"pair 1 {ENGINE_DT!r} {kinematics} {tail}")
        commands.append(f"pair 0 {ENGINE_DT!r} {kinematics} {tail}")
    replies = driver(commands)[2:]
    stepped = [parse_contact(fields) for fields in replies[0::2]]
    reread = [parse_contact(fields) for fields in replies[1::2]]

    ours = {"f1": [], "f2": [], "t1": [], "t2": [], "pgl_f": [], "pgl_t": [], "pgl_h": []}
    theirs = {key: [] for key in ours}
    contact_steps = []
    for step, mine, again in zip(steps, stepped, reread):
        c, local = atoms[step], pairs[step]
        in_liggghts = len(local.get("c_pgl[1]", [])) == 1
        assert (mine is not None) == in_liggghts, f"step {step}: contact differs"
        if mine is None:
            assert not any(c[name][k] for name in ("fx", "fy", "fz", "tqx", "tqy", "tqz")
                           for k in (0, 1)), f"step {step}: a force without contact"
            continue
        contact_steps.append(step)
        assert (local["c_pgl[1]"][0], local["c_pgl[2]"][0]) == (1.0, 2.0)
        ours["f1"].append(mine["force"])
        ours["f2"].append([-v for v in mine["force"]])
        ours["t1"].append(mine["torque_i"])
        ours["t2"].append(mine["torque_j"])
        ours["pgl_f"].append(again["force"])
        ours["pgl_t"].append(again["torque_i"])
        ours["pgl_h"].append(mine["shear"])
        assert again["shear"] == mine["shear"]      # a read-only call leaves it
        theirs["f1"].append(vec(c, ("fx", "fy", "fz"), 0))
        theirs["f2"].append(vec(c, ("fx", "fy", "fz"), 1))
        theirs["t1"].append(vec(c, ("tqx", "tqy", "tqz"), 0))
        theirs["t2"].append(vec(c, ("tqx", "tqy", "tqz"), 1))
        pgl = [float(local[f"c_pgl[{k}]"][0]) for k in range(4, 13)]
        theirs["pgl_f"].append(pgl[0:3])
        theirs["pgl_t"].append(pgl[3:6])
        theirs["pgl_h"].append(pgl[6:9])
    slides = [mine["slides"] for mine in stepped if mine is not None]
    return ours, theirs, contact_steps, slides


@pytest.mark.engine
@pytest.mark.parametrize("model", ["hooke/stiffness", "hooke"])
def test_pair_matches_liggghts(run, tmp_path, driver, model):
    run(scripted_deck(model, wall=False))
    steps = list(range(1, len(SPINS) * STEPS_PER_RUN + 1))
    ours, theirs, contact_steps, slides = replay_pair(
        driver, model, frames_by_step(tmp_path / "dump.atoms"),
        frames_by_step(tmp_path / "dump.pair"), steps)
    report = [f"{model}: {len(contact_steps)} contact steps, {sum(slides)} sliding, "
              f"{sum(a and not b for a, b in zip(slides, slides[1:]))} slide-to-stick"]
    results = {key: compare(key, ours[key], theirs[key], report) for key in ours}
    report.append("".join("S" if x else "." for x in slides))
    print("\n".join(report))
    assert all(value <= ENGINE_TOLERANCE for value in results.values()), "\n".join(report)
    # the sequence is the one described: contact in each run, both branches
    # of the cap, and slip in both senses of both tangential directions
    assert any(a and not b for a, b in zip(slides, slides[1:]))   # slide -> stick
    assert any(b and not a for a, b in zip(slides, slides[1:]))   # stick -> slide
    assert {s // STEPS_PER_RUN for s in contact_steps} >= {0, 1, 2}


@pytest.mark.engine
@pytest.mark.parametrize("model", ["hooke/stiffness", "hooke"])
def test_wall_matches_liggghts(run, tmp_path, driver, model):
    run(scripted_deck(model, wall=True))
    atoms = frames_by_step(tmp_path / "dump.atoms")
    steps = list(range(1, len(SPINS) * STEPS_PER_RUN + 1))
    commands = [driver_model(model)]
    for step in steps:
        c = atoms[step]
        kinematics = " ".join(numbers(vec(c, names, 0))
                              for names in (("x", "y", "z"), ("vx", "vy", "vz"),
                                            ("omegax", "omegay", "omegaz")))
        tail = numbers([c["radius"][0], c["mass"][0]])
        commands.append(f"zplane 1 {ENGINE_DT!r} 0.0 {kinematics} {tail}")
    replies = [parse_contact(fields) for fields in driver(commands)[1:]]
    history = [f"f_history_wall[{k}]" for k in (1, 2, 3)]
    ours = {"f": [], "t": [], "history": []}
    theirs = {key: [] for key in ours}
    contact_steps = []
    for step, mine in zip(steps, replies):
        c = atoms[step]
        if mine is None:
            assert not any(c[name][0] for name in ("fx", "fy", "fz", "tqx", "tqy", "tqz")), \
                f"step {step}: a force without contact"
            assert not any(c[name][0] for name in history), f"step {step}: history kept"
            continue
        contact_steps.append(step)
        ours["f"].append(mine["force"])
        ours["t"].append(mine["torque_i"])
        ours["history"].append(mine["shear"])
        theirs["f"].append(vec(c, ("fx", "fy", "fz"), 0))
        theirs["t"].append(vec(c, ("tqx", "tqy", "tqz"), 0))
        theirs["history"].append(vec(c, history, 0))
    slides = [mine["slides"] for mine in replies if mine is not None]
    report = [f"{model} wall: {len(contact_steps)} contact steps, {sum(slides)} sliding, "
              f"{sum(a and not b for a, b in zip(slides, slides[1:]))} slide-to-stick",
              "".join("S" if x else "." for x in slides)]
    results = {key: compare(key, ours[key], theirs[key], report) for key in ours}
    print("\n".join(report))
    assert all(value <= ENGINE_TOLERANCE for value in results.values()), "\n".join(report)
    assert any(a and not b for a, b in zip(slides, slides[1:]))   # slide -> stick
    assert any(b and not a for a, b in zip(slides, slides[1:]))   # stick -> slide
    assert {s // STEPS_PER_RUN for s in contact_steps} >= {0, 1, 2}
    assert not replies[-1] and not replies[0]                     # starts and ends apart


@pytest.mark.engine
def test_a_separated_pair_keeps_its_history_until_the_neighbor_lists_are_rebuilt(
        run, tmp_path, driver):
    """LIGGGHTS 3.8 leaves a pair's tangential history alone when the
    grains part (pair_gran_base.h zeroes it only within
    neigh_modify contact_distance_factor, 1 by default), so a pair that
    touches again before the next neighbor build starts from its old,
    projected history; a build (here: none during the single run) drops
    it. The same path as above but pressing twice (period 1.3 ms) in one
    run: the replay matches bit for bit when the driver keeps the history
    of a separated pair, and not when it zeroes it (the host's choice,
    doc/lammps_host.md section 5.1)."""
    twice = PAIR_PATH.replace("sin(PI*v_t/2.6e-3)", "sin(2*PI*v_t/1.3e-3)").replace(
        "-1.1e-4*PI/2.6e-3*cos(PI*v_t/2.6e-3)", "-1.1e-4*2*PI/1.3e-3*cos(2*PI*v_t/1.3e-3)")
    assert twice.count("1.3e-3") == 3 and "2.6e-3" not in twice
    output = run(scripted_deck("hooke/stiffness", wall=False, pair_path=twice,
                               spins=SPINS[:1], steps_per_run=3 * STEPS_PER_RUN))
    assert "Neighbor list builds = 0" in output
    atoms = frames_by_step(tmp_path / "dump.atoms")
    pairs = frames_by_step(tmp_path / "dump.pair")
    steps = list(range(1, 3 * STEPS_PER_RUN + 1))
    report = []
    ours, theirs, contact_steps, _ = replay_pair(driver, "hooke/stiffness", atoms, pairs,
                                                  steps, policy="keep")
    episodes = 1 + sum(b - a > 1 for a, b in zip(contact_steps, contact_steps[1:]))
    assert episodes >= 2
    kept = {key: compare(key, ours[key], theirs[key], report) for key in ours}
    assert all(value <= ENGINE_TOLERANCE for value in kept.values()), "\n".join(report)
    ours, theirs, _, _ = replay_pair(driver, "hooke/stiffness", atoms, pairs, steps,
                                     policy="zero")
    # zeroing instead moves the history of the second contact by 3e-4 of its
    # largest value
    assert compare("pgl_h", ours["pgl_h"], theirs["pgl_h"], report) > 1e-6
