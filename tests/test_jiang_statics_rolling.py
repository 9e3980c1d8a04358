"""rolling_friction jiang against two analytic results of rigid-body
mechanics, with the real engine on one- and two-grain decks.

(b) The paper's Fig. 2 (Magalhaes et al. 2014): in 2D a disc (mass m,
radius r) resting on ONE fixed disc of the same size, the line of centres at
angle theta from the vertical, under gravity. Static threshold: for the top
disc, with n the unit normal from the bottom centre to the top centre,

  forces along n:        N   = m g cos(theta)     (normal force)
  forces along tangent:  F_t = m g sin(theta)     (friction, pointing uphill)
  torque about centre:   F_t r_c = M              (rolling torque)

Gravity acts at the centre and has no torque; friction acts at the contact
point with the lever arm LIGGGHTS uses, r_c = r - delta_n/2, so the rolling
spring must carry M = m g r_c sin(theta). At rest every velocity vanishes, so
every damping force and torque (gamman, gammat, rolling damping) is zero
and N equals the elastic force f_el = k_n delta_n, delta_n = m g cos(theta)/k_n.
An equilibrium exists if and only if both caps hold:

  sliding: F_t <= mu N        ->  tan(theta) <= mu
  rolling: M   <= mu_r f_el   ->  tan(theta) <= mu_r / r_c = b mu l_c / r_c

(b = rollingFrictionFactor = 1 here). Damping does not enter: it only
decides how the disc reaches the equilibrium, not where it is or whether it
exists. Above the threshold there is no equilibrium, and since the driving
moment grows with theta the disc rolls (or slides) off like an inverted
pendulum: from 15% above the threshold it is past 30 degrees within ~0.25 s.

Transients and overshoot: the top disc starts at its equilibrium overlap,
but the tangential and rolling springs start unloaded, so the disc moves
until they carry F_t and M. A suddenly loaded undamped spring overshoots its
static deflection by up to 2x, so a disc at 85% of a cap would briefly ask
for 170% of it and slip plastically. Here the tangential spring and the
rolling spring are critically damped (gammat; rollingDamping on with
coefficientRollingViscousDamping 1: for a disc rolling on a fixed disc the
effective inertia of the rolling angle is 0.75 m r^2, which is the reduced
I_r the model uses), gamman gives 0.3 of critical, and the springs'
deflections are small (k_n large; in overlap mode rollingStiffnessFactor 10,
which leaves the threshold unchanged: with a = 1 the rolling spring alone
would tilt the contact by tan(theta_c)/8, eating most of the 15% margin).
Then no cap is ever reached below the threshold, and the disc comes to rest
exactly where the elastic springs put it: rolling by delta_r = M/k_r (which
turns the line of centres by r_c delta_r / D, D = 2r - delta_n, rolling
without slip on an equal disc) plus the tangential spring's deflection
F_t/k_t (turning it by F_t/(k_t D)). This prediction is checked to 1e-6 of
the tilt (a few hundredths of a degree, small next to the 15% margin); the
engine meets it to ~1e-10.

(c) A sphere rolling on a flat wall (3D) with v0 and omega = v0/r_c (pure
rolling; r_c = r - delta_n/2 is LIGGGHTS' lever arm for walls too): the
rolling spring saturates within 1e-3 s and the wall's rolling torque stays at
M = mu_r f_el = mu l_c m g while the contact sticks. Newton and Euler with
the contact friction F (pointing backwards), no slip (v = omega r_c):
  m dv/dt = -F,  I domega/dt = F r_c - M
  -> dv/dt = -a,  a = M / (r_c (m + I/r_c^2)),  I = 2/5 m r^2
(I with the true radius, as fix nve/sphere has it).
"""

import math

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

G = 9.81
DENSITY = 2500.0

# ---------------------------------------------------------------------------
# (b) a disc on one fixed disc, 2D
# ---------------------------------------------------------------------------

RADIUS_2D = 0.005
# LIGGGHTS 3.8 in 2D: `set density` gives m = pi r^2 rho and fix nve/sphere
# uses I = 1/2 m r^2 (discs)
MASS_2D = math.pi * RADIUS_2D ** 2 * DENSITY
KN_2D = 1.0e6               # delta_n = m g / k_n = 1.9e-6 m = 3.9e-4 r
KT_2D = 2.0 / 7.0 * KN_2D
DT_2D = 1.0e-5              # normal period 2 pi sqrt(m/k_n) = 2.8e-3 s: 280 steps
TIME_2D = 0.5               # s, twice what a disc 15% past the threshold needs to fall
DUMP_EVERY_2D = 500
MARGIN = 0.15               # tan(theta) = (1 -+ MARGIN) tan(theta_c)
NORMAL_DAMPING = 0.3        # fractions of critical damping
TANGENTIAL_DAMPING = 1.0
ROLLING_DAMPING = 1.0
FALLEN = math.radians(30.0)  # it has rolled off once the contact angle passes this


def damping_coefficient(ratio, stiffness):
    """gamman/gammat value for `ratio` of critical damping of the top disc on
    a spring `stiffness`: hooke/stiffness multiplies the value by the pair's
    reduced mass m/2 (even though the bottom disc does not move)."""
    return ratio * 2.0 * math.sqrt(MASS_2D * stiffness) / (MASS_2D / 2)


def equilibrium_overlap(theta):
    return MASS_2D * G * math.cos(theta) / KN_2D


def lever_arm(delta):
    return RADIUS_2D - delta / 2


def disc_chord(delta):
    """l_c of two equal discs overlapping by delta: the model's formula with
    r_i = r_j = r and centre distance 2r - delta, so x = r - delta/2."""
    return 2 * math.sqrt(RADIUS_2D ** 2 - lever_arm(delta) ** 2)


def solve_threshold(tan_of_overlap):
    """tan(theta_c) solving tan(theta) = tan_of_overlap(delta_n(theta)), by
    fixed-point iteration (delta_n depends on theta only through cos(theta),
    so this converges in a few steps)."""
    tan_c = tan_of_overlap(equilibrium_overlap(0.0))
    for _ in range(100):
        tan_c = tan_of_overlap(equilibrium_overlap(math.atan(tan_c)))
    return tan_c


class Support:
    """One way of holding the top disc: pair_style keywords, property blocks,
    mu, the threshold tan(theta_c), the rolling stiffness k_r(delta_n) (None
    without rolling resistance) and whether the cap that fails first is the
    rolling one."""

    def __init__(self, mode):
        rolling_damping = per_pair("coefficientRollingViscousDamping", ROLLING_DAMPING)
        if mode == "fixed":
            # the paper's fixed l_c = 0.05 d; rolling limit tan = mu l_c / r_c
            # = 0.05 (theta_c = 2.86 deg), sliding limit tan = mu = 0.5
            self.mu = 0.5
            contact_length = 0.05 * 2 * RADIUS_2D
            self.keywords = "rolling_friction jiang rollingDamping on"
            self.properties = per_pair("rollingContactLength", contact_length) + rolling_damping
            self.tan_c = solve_threshold(lambda d: self.mu * contact_length / lever_arm(d))
            self.rolling_stiffness = lambda d: KN_2D * contact_length ** 2
            self.rolling_limited = True
        elif mode == "overlap":
            # l_c = chord of the overlap delta_n = m g cos(theta)/k_n, so
            # tan(theta_c) = mu l_c(delta_n(theta_c)) / r_c: ~0.0196, 1.12 deg
            self.mu = 0.5
            stiffness_factor = 10.0
            self.keywords = ("rolling_friction jiang contactLengthFromOverlap on "
                             f"rollingStiffnessFactor {stiffness_factor} rollingDamping on")
            self.properties = rolling_damping
            self.tan_c = solve_threshold(lambda d: self.mu * disc_chord(d) / lever_arm(d))
            self.rolling_stiffness = lambda d: stiffness_factor * KN_2D * disc_chord(d) ** 2
            self.rolling_limited = True
        elif mode == "sliding":
            # small mu, large l_c = 0.8 d: the rolling cap would hold up to
            # tan = mu l_c / r_c = 1.6 mu, so sliding (tan = mu) fails first
            self.mu = 0.1
            contact_length = 0.8 * 2 * RADIUS_2D
            self.keywords = "rolling_friction jiang rollingDamping on"
            self.properties = per_pair("rollingContactLength", contact_length) + rolling_damping
            self.tan_rolling = solve_threshold(lambda d: self.mu * contact_length / lever_arm(d))
            self.tan_c = self.mu
            self.rolling_stiffness = lambda d: KN_2D * contact_length ** 2
            self.rolling_limited = False
        elif mode == "zero":
            # rolling_friction jiang with rollingContactLength 0 for the
            # pair: k_r = mu_r = 0, no rolling resistance (what the pile's
            # decks use to give it to grain-substrate contacts only)
            self.mu = 0.5
            self.keywords = "rolling_friction jiang rollingDamping on"
            self.properties = per_pair("rollingContactLength", 0.0) + rolling_damping
            self.tan_c = 0.0
            self.rolling_stiffness = None
            self.rolling_limited = True
        else:
            # plain hooke/stiffness + tangential history: nothing resists
            # rolling, no equilibrium at any theta > 0
            self.mu = 0.5
            self.keywords = ""
            self.properties = ""
            self.tan_c = 0.0
            self.rolling_stiffness = None
            self.rolling_limited = True

    def equilibrium_angle(self, theta0):
        """Where the disc placed at theta0 comes to rest while no cap is
        reached: the contact angle turns by (F_t/k_t + r_c delta_r)/D."""
        theta = theta0
        for _ in range(100):
            delta = equilibrium_overlap(theta)
            tangential_force = MASS_2D * G * math.sin(theta)
            shear = tangential_force / KT_2D
            rolling_angle = tangential_force * lever_arm(delta) / self.rolling_stiffness(delta)
            theta = theta0 + (shear + lever_arm(delta) * rolling_angle) / (2 * RADIUS_2D - delta)
        return theta


def disc_on_disc_deck(support, theta):
    """Bottom disc fixed at the origin (not integrated), top disc at angle
    theta (rad) from the vertical, at its equilibrium overlap."""
    distance = 2 * RADIUS_2D - equilibrium_overlap(theta)
    materials = hooke_materials(KN_2D, KT_2D, damping_coefficient(NORMAL_DAMPING, KN_2D),
                                damping_coefficient(TANGENTIAL_DAMPING, KT_2D), support.mu)
    return f"""
{granular_setup(dimension=2, boundary="f f p")}
region box block -1.0 1.0 -2.0 0.05 -0.005 0.005 units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{materials}
{support.properties}
pair_style gran model hooke/stiffness tangential history {support.keywords}
pair_coeff * *
timestep {DT_2D}
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {distance * math.sin(theta)!r} {distance * math.cos(theta)!r} 0 units box
set group all diameter {2 * RADIUS_2D} density {DENSITY}
group top id 2
fix gravi all gravity {G} vector 0 -1 0
fix integr top nve/sphere
fix twod all enforce2d
dump top top custom {DUMP_EVERY_2D} dump.top id x y vx vy omegaz
dump_modify top format "%d %.17g %.17g %.17g %.17g %.17g"
run {int(round(TIME_2D / DT_2D))}
"""


def top_disc_history(run, tmp_path, support, theta, subdir):
    run(disc_on_disc_deck(support, theta), subdir=subdir)
    frames = read_dump(tmp_path / subdir / "dump.top")
    columns = {name: np.array([c[name][0] for _, c in frames])
               for name in ("x", "y", "vx", "vy", "omegaz")}
    columns["time"] = np.array([step for step, _ in frames]) * DT_2D
    # contact angle from the vertical; the bottom disc sits at the origin
    columns["angle"] = np.arctan2(columns["x"], columns["y"])
    return columns


def assert_stays(history, support, theta0):
    angle = history["angle"]
    theta_c = math.atan(support.tan_c)
    expected = support.equilibrium_angle(theta0)
    # the elastic tilt is small next to the margin: the equilibrium is safely
    # inside the stable range (a sanity check of the set-up itself)
    assert expected - theta0 < 0.15 * (theta_c - theta0)
    # never came near the threshold during the transient
    assert angle.max() - theta0 < 0.2 * (theta_c - theta0)
    # at rest over the whole second half of the run, on the spot predicted by
    # the elastic springs (no cap was reached: no plastic slip or roll)
    late = history["time"] >= TIME_2D / 2
    assert np.ptp(angle[late]) < 1e-9
    assert np.abs(history["omegaz"][late]).max() < 1e-9
    # (measured to ~1e-10 of the tilt; 1e-6 leaves room for the terms of
    # order tilt * delta_n/r the kinematics neglect, and still catches k_r
    # off by a part in 1e5, or any plastic slip or roll)
    np.testing.assert_allclose(angle[-1] - theta0, expected - theta0, rtol=1e-6)


def assert_falls(history, rolls):
    """Past FALLEN within TIME_2D; while still on the bottom disc (angle up to
    20 deg) it rolls without slip (rolls=True: r_c omega_z = -D psi') or slides
    without turning (rolls=False: |omega_z| r_c << D psi')."""
    angle = history["angle"]
    assert angle.max() > FALLEN
    on_disc = (angle > angle[0] + math.radians(1.0)) & (angle < math.radians(20.0))
    assert on_disc.sum() >= 3
    # speed of the centre along the tangent, D psi', and of the contact point
    # of the top disc relative to it, r_c omega_z (delta_n/r < 4e-4, r_c ~ r)
    centre = (history["vx"] * np.cos(angle) - history["vy"] * np.sin(angle))[on_disc]
    spin = (RADIUS_2D * history["omegaz"])[on_disc]
    slip_fraction = (centre + spin) / centre
    # measured: 2e-5..4e-5 rolling (the tangential spring's load changes and
    # r vs r_c), 1 +- 2e-6 sliding
    if rolls:
        assert np.abs(slip_fraction).max() < 1e-3
    else:
        assert np.abs(slip_fraction - 1).max() < 1e-3


@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_disc_on_one_disc_rolling_limit(run, tmp_path, mode):
    """Rolling-limited (mu = 0.5, tan(theta_c) = mu l_c / r_c << mu): held at
    15% below the threshold in tan(theta), rolls off at 15% above."""
    support = Support(mode)
    assert support.tan_c < 0.2 * support.mu      # the rolling cap binds first
    below = math.atan((1 - MARGIN) * support.tan_c)
    above = math.atan((1 + MARGIN) * support.tan_c)
    assert_stays(top_disc_history(run, tmp_path, support, below, "below"), support, below)
    assert_falls(top_disc_history(run, tmp_path, support, above, "above"), rolls=True)


def test_disc_on_one_disc_sliding_limit(run, tmp_path):
    """Sliding-limited (mu = 0.1, l_c = 0.8 d: rolling would hold up to
    tan(theta) = 0.16): held at tan(theta) = 0.085, slides off at 0.115,
    hardly turning (the rolling spring holds the spin)."""
    support = Support("sliding")
    assert support.tan_rolling > (1 + 3 * MARGIN) * support.mu
    below = math.atan((1 - MARGIN) * support.mu)
    above = math.atan((1 + MARGIN) * support.mu)
    assert_stays(top_disc_history(run, tmp_path, support, below, "below"), support, below)
    assert_falls(top_disc_history(run, tmp_path, support, above, "above"), rolls=False)


def test_disc_on_one_disc_without_rolling_resistance(run, tmp_path):
    """Plain hooke/stiffness + tangential history: no equilibrium off the
    vertical. At 1 degree (a third of the fixed-l_c threshold 2.86 deg, and
    tan = 0.017 << mu) the disc rolls off without slip."""
    support = Support("none")
    assert_falls(top_disc_history(run, tmp_path, support, math.radians(1.0), "none"), rolls=True)


def test_zero_contact_length_is_no_rolling_resistance(run, tmp_path):
    """rollingContactLength 0 switches the model off for the pair: the disc
    at 1 degree rolls off along the same trajectory as with the stock
    pair style without rolling_friction (the reference)."""
    theta = math.radians(1.0)
    zero = top_disc_history(run, tmp_path, Support("zero"), theta, "zero")
    stock = top_disc_history(run, tmp_path, Support("none"), theta, "stock")
    assert zero["angle"].max() > FALLEN
    for name in ("x", "y", "vx", "vy", "omegaz"):
        np.testing.assert_allclose(zero[name], stock[name], rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("geometric", ["contactLengthFromOverlap", "contactLengthFromDepth"])
def test_geometric_modes_keep_a_fixed_length_where_one_is_given(run, tmp_path, geometric):
    """With l_c from each contact, an optional rollingContactLength > 0 for
    a type pair fixes l_c there: the disc 15 % above the fixed-l_c
    threshold rolls off exactly as in fixed mode (the reference); with 0 for
    the pair the geometric l_c stays, exactly as without the property."""
    theta = math.atan((1 + MARGIN) * Support("fixed").tan_c)
    fixed = Support("fixed")
    given = Support("fixed")
    given.keywords = f"rolling_friction jiang {geometric} on rollingDamping on"
    reference = top_disc_history(run, tmp_path, fixed, theta, "fixed")
    overridden = top_disc_history(run, tmp_path, given, theta, "given")
    assert reference["angle"].max() > FALLEN
    for name in ("x", "y", "vx", "vy", "omegaz"):
        np.testing.assert_allclose(overridden[name], reference[name], rtol=1e-12, atol=1e-15)

    plain = Support("fixed")
    plain.keywords = given.keywords
    plain.properties = per_pair("coefficientRollingViscousDamping", ROLLING_DAMPING)
    zero = Support("fixed")
    zero.keywords = given.keywords
    zero.properties = plain.properties + per_pair("rollingContactLength", 0.0)
    geometric_only = top_disc_history(run, tmp_path, plain, theta, "plain")
    with_zero = top_disc_history(run, tmp_path, zero, theta, "zero")
    for name in ("x", "y", "vx", "vy", "omegaz"):
        np.testing.assert_allclose(with_zero[name], geometric_only[name], rtol=1e-12, atol=1e-15)
    # and the geometric l_c (about 1e-3 d or less here) is not the fixed one
    assert np.abs(geometric_only["angle"] - reference["angle"]).max() > 1e-3


# ---------------------------------------------------------------------------
# (c) a sphere rolling on a flat wall, 3D
# ---------------------------------------------------------------------------

RADIUS_3D = 0.005
MASS_3D = 4.0 / 3.0 * math.pi * RADIUS_3D ** 3 * DENSITY
KN_3D = 1.0e5               # delta_n = m g / k_n = 1.3e-7 m
KT_3D = 2.0 / 7.0 * KN_3D
MU_3D = 0.5
DT_3D = 1.0e-5              # normal period 2 pi sqrt(m/k_n) = 7.2e-4 s: 72 steps
SETTLE_TIME = 0.01          # s, at rest on the wall before the push
TRANSIENT = 0.01            # s, left out of the fit: the rolling spring saturates
                            # in < 1e-3 s, the (over)damped tangential mode
                            # decays with a time constant ~ 4e-4 s
DUMP_EVERY_3D = 50


def wall_rolling_case(mode):
    """keywords for fix wall/gran (after the wall arguments, where it reads
    its model settings), property block, l_c and v0 (chosen so that the
    sphere stops after ~0.3-0.4 s)."""
    overlap = MASS_3D * G / KN_3D
    if mode == "fixed":
        contact_length = 0.05 * 2 * RADIUS_3D
        return "", per_pair("rollingContactLength", contact_length), contact_length, 0.1
    # the wall formula: diameter of the contact circle of a sphere pressed
    # delta_n into a plane
    contact_length = 2 * math.sqrt(overlap * (2 * RADIUS_3D - overlap))
    return "contactLengthFromOverlap on", "", contact_length, 0.02


def sphere_on_wall_deck(keywords, properties, v0, roll_steps):
    overlap = MASS_3D * G / KN_3D
    lever = RADIUS_3D - overlap / 2
    # damping ratios as in (b); the wall's meff is the sphere's mass
    gamman = NORMAL_DAMPING * 2 * math.sqrt(MASS_3D * KN_3D) / MASS_3D
    gammat = TANGENTIAL_DAMPING * 2 * math.sqrt(MASS_3D * KT_3D) / MASS_3D
    return f"""
{granular_setup()}
region box block -0.02 0.08 -0.02 0.02 -0.01 0.03 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(KN_3D, KT_3D, gamman, gammat, MU_3D)}
{properties}
pair_style gran model hooke/stiffness tangential history rolling_friction jiang {keywords}
pair_coeff * *
fix floor all wall/gran model hooke/stiffness tangential history rolling_friction jiang primitive type 1 zplane 0.0 {keywords}
timestep {DT_3D}
create_atoms 1 single 0 0 {RADIUS_3D - overlap!r} units box
set group all diameter {2 * RADIUS_3D} density {DENSITY}
fix gravi all gravity {G} vector 0 0 -1
fix integr all nve/sphere
run {int(round(SETTLE_TIME / DT_3D))}
set atom 1 vx {v0!r} omegay {v0 / lever!r}
dump s all custom {DUMP_EVERY_3D} dump.sphere id x z vx vz omegay fx
dump_modify s format "%d %.17g %.17g %.17g %.17g %.17g %.17g"
run {roll_steps}
"""


@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_sphere_rolling_on_wall_decelerates_at_rolling_limit(run, tmp_path, mode):
    keywords, properties, contact_length, v0 = wall_rolling_case(mode)
    overlap = MASS_3D * G / KN_3D          # at rest: f_el = k_n delta_n = m g
    lever = RADIUS_3D - overlap / 2
    inertia = 0.4 * MASS_3D * RADIUS_3D ** 2
    torque = MU_3D * contact_length * MASS_3D * G             # M = mu_r f_el
    deceleration = torque / (lever * (MASS_3D + inertia / lever ** 2))
    stop_time = v0 / deceleration          # 0.285 s (fixed), 0.398 s (overlap)
    roll_steps = int(round((stop_time + 0.1) / DT_3D))
    run(sphere_on_wall_deck(keywords, properties, v0, roll_steps))

    frames = read_dump(tmp_path / "dump.sphere")
    steps = np.array([step for step, _ in frames])
    time = (steps - int(round(SETTLE_TIME / DT_3D))) * DT_3D    # since the push
    v = np.array([c["vx"][0] for _, c in frames])
    omega = np.array([c["omegay"][0] for _, c in frames])
    fx = np.array([c["fx"][0] for _, c in frames])
    assert time[0] == 0.0 and v[0] == v0

    rolling = (time > TRANSIENT) & (v > 0.2 * v0)
    assert rolling.sum() > 100
    slope, intercept = np.polyfit(time[rolling], v[rolling], 1)
    residual = v[rolling] - (slope * time[rolling] + intercept)
    # Once the transients have died out the forces are constant, and velocity
    # Verlet integrates a constant force exactly: measured agreement is ~1e-11.
    # 1e-6 still tells r_c from r (delta_n/2r = 1.3e-5) and the wall chord
    # from its small-overlap form 2 sqrt(2 r delta_n) (delta_n/4r = 6.4e-6).
    np.testing.assert_allclose(-slope, deceleration, rtol=1e-6)
    assert np.abs(residual).max() < 1e-8 * v0          # a constant deceleration
    # no slip: the contact point (lever arm r_c) is at rest, the static
    # friction m a stays well inside the Coulomb cap
    assert np.abs(v[rolling] - omega[rolling] * lever).max() < 1e-8 * v0
    np.testing.assert_allclose(-fx[rolling], MASS_3D * deceleration, rtol=1e-6)
    assert MASS_3D * deceleration < 0.2 * MU_3D * MASS_3D * G
    # and it stops: 0.05 s after v0/a it no longer rolls but rocks on the
    # rolling spring, unloaded from the cap: the rolling angle swings within
    # +-M/k_r, the centre within 2 r_c M/k_r (1.3e-6 m fixed, 4.5e-6 m overlap,
    # against 0.014 m and 0.004 m rolled; measured 0.92 and 1.0003 of it, 5%
    # allowed for the tangential spring and the lever arm r - delta_n vs r_c)
    stopped = time > stop_time + 0.05
    assert stopped.sum() > 10
    x = np.array([c["x"][0] for _, c in frames])
    rocking = 2 * lever * torque / (KN_3D * contact_length ** 2)
    assert np.ptp(x[stopped]) < 1.05 * rocking
