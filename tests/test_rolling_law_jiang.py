"""Jiang's rolling resistance law (src_plugin/core/rolling_law_jiang.h) against
hand values, through a small driver compiled here with g++.

The law is eq. 1 of Magalhaes et al. (2014), the simplified model of
Jiang, Yu & Harris (2005):

    tau = -k_r delta_r                       while k_r |delta_r| <= mu_r f_el
    tau = -mu_r f_el delta_r / |delta_r|     otherwise
    k_r = k_n l_c^2,  mu_r = mu l_c          (times rollingStiffnessFactor a
                                              and rollingFrictionFactor b)

with f_el = k_n delta_n the elastic normal force. The contact length l_c
is fixed (rollingContactLength), the depth of the overlap delta_n
(contactLengthFromDepth), or the chord of the overlap of the two discs
(the diameter of the contact circle in 3D; contactLengthFromOverlap),
which this file computes with Heron's formula for the triangle of the two
radii and the distance of the centres, independently of the header's
formula. Every expected torque is worked out here from these equations,
never taken from the driver; units are the paper's (d = 1, k_n = 1000,
mu = 0.5).
"""

import math
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DRIVER_SOURCE = ROOT / "tests" / "rolling_law_jiang_driver.cpp"

KN = 1000.0
MU = 0.5
RELATIVE = 1e-12


@pytest.fixture(scope="session")
def driver(tmp_path_factory):
    """Compiles the driver once; returns run(commands) -> one list of
    fields per command."""
    executable = tmp_path_factory.mktemp("rolling_law_jiang") / "rolling_law_jiang_driver"
    build = subprocess.run(
        ["g++", "-std=c++11", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic",
         f"-I{ROOT / 'src_plugin' / 'core'}", str(DRIVER_SOURCE), "-o", str(executable)],
        capture_output=True, text=True)
    if build.returncode != 0:
        pytest.fail(f"rolling_law_jiang_driver does not compile:\n{build.stderr}")

    def run(*commands):
        result = subprocess.run([str(executable)], input="\n".join(commands) + "\n",
                                capture_output=True, text=True, check=True, timeout=10)
        lines = result.stdout.splitlines()
        assert len(lines) == len(commands), result.stdout
        return [line.split() for line in lines]
    return run


def roll(fields):
    """(torque, rolls, angle) from a 'roll' reply."""
    assert fields[0] == "torque" and fields[4] == "rolls" and fields[6] == "angle"
    return ([float(v) for v in fields[1:4]], fields[5] == "1", [float(v) for v in fields[7:10]])


def close(actual, expected, scale=1.0):
    return all(abs(a - e) <= RELATIVE * max(abs(e), scale) for a, e in zip(actual, expected))


def chord_by_heron(radius_i, radius_j, distance):
    """Twice the height over the side `distance` of the triangle with
    sides radius_i, radius_j, distance: the length of the common chord."""
    s = 0.5 * (radius_i + radius_j + distance)
    area = math.sqrt(s * (s - radius_i) * (s - radius_j) * (s - distance))
    return 4.0 * area / distance


def spring_command(overlap, contact_length, stiffness_factor=1.0, friction_factor=1.0):
    return f"spring {KN!r} {overlap!r} {MU!r} {contact_length!r} {stiffness_factor!r} {friction_factor!r}"


# ---------------------------------------------------------------- k_r and the cap

@pytest.mark.parametrize("overlap, contact_length, a, b", [
    (0.01, 0.05, 1.0, 1.0),      # the paper's fixed-l_c model: l_c = 0.05 d
    (0.01, 0.05, 2.0, 3.0),      # with both factors
    (0.002, 0.002, 1.0, 1.0),    # contactLengthFromDepth: l_c = delta_n
])
def test_stiffness_and_cap_are_jiangs(driver, overlap, contact_length, a, b):
    (reply,) = driver(spring_command(overlap, contact_length, a, b))
    stiffness = a * KN * contact_length ** 2          # k_r = k_n l_c^2
    torque_limit = b * MU * contact_length * KN * overlap   # mu_r f_el = mu l_c k_n delta_n
    assert reply[0] == "spring"
    assert close([float(reply[1]), float(reply[2])], [stiffness, torque_limit])


def test_an_opening_contact_holds_no_torque(driver):
    """f_el < 0 (delta_n < 0, within contact_distance_factor): no cap, so
    any rolling angle is cut to zero."""
    spring, reply = driver(spring_command(-0.001, 0.05), "roll 0.01 0 0")
    assert float(spring[2]) == 0.0
    torque, rolls, angle = roll(reply)
    assert torque == [0.0, 0.0, 0.0] and angle == [0.0, 0.0, 0.0]


def test_zero_contact_length_switches_rolling_resistance_off(driver):
    """rollingContactLength 0 in the fixed mode: k_r = mu_r = 0."""
    spring, reply = driver(spring_command(0.01, 0.0), "roll 0.3 -0.2 0.1")
    assert float(spring[1]) == 0.0 and float(spring[2]) == 0.0
    torque, rolls, _ = roll(reply)
    assert torque == [0.0, 0.0, 0.0] and not rolls


# ---------------------------------------------------------------- contact lengths

@pytest.mark.parametrize("radius_i, radius_j, distance", [
    (0.5, 0.5, 0.98),            # equal discs overlapping by 0.02 d
    (0.5, 0.45, 0.94),           # the paper's 5 % polydispersity
    (0.5, 0.05, 0.54),           # a grain on a substrate grain (d_s = 0.1 d)
])
def test_contact_length_from_overlap_is_the_chord(driver, radius_i, radius_j, distance):
    (reply,) = driver(f"chord {radius_i!r} {radius_j!r} {distance!r}")
    assert close([float(reply[1])], [chord_by_heron(radius_i, radius_j, distance)])


def test_equal_discs_chord_by_hand(driver):
    # r = 0.5, overlap 0.02: the chord's half is sqrt(r^2 - (r - 0.01)^2) = sqrt(0.0099)
    (reply,) = driver("chord 0.5 0.5 0.98")
    assert close([float(reply[1])], [2.0 * math.sqrt(0.0099)])


def test_wall_contact_length_is_the_chord_of_a_flat(driver):
    # a disc of radius r pressed delta into a flat: half-chord sqrt(r^2 - (r - delta)^2)
    radius, overlap = 0.5, 0.02
    (reply,) = driver(f"wall_chord {radius!r} {overlap!r}")
    assert close([float(reply[1])], [2.0 * math.sqrt(radius ** 2 - (radius - overlap) ** 2)])


def test_separate_grains_have_no_contact_length(driver):
    replies = driver("chord 0.5 0.5 1.01", "wall_chord 0.5 -0.01")
    assert [float(r[1]) for r in replies] == [0.0, 0.0]


# ---------------------------------------------------------------- eq. 1, both branches

def overlap_mode_spring(overlap):
    """Equal discs of radius 0.5 overlapping by `overlap`, l_c from the
    overlap: returns (k_r, mu_r f_el) by hand."""
    contact_length = chord_by_heron(0.5, 0.5, 1.0 - overlap)
    return KN * contact_length ** 2, MU * contact_length * KN * overlap, contact_length


def spring_by_hand(mode, overlap):
    """(k_r, mu_r f_el, l_c) by hand, l_c from the overlap's chord or its depth."""
    if mode == "overlap":
        return overlap_mode_spring(overlap)
    contact_length = overlap
    return KN * contact_length ** 2, MU * contact_length * KN * overlap, contact_length


@pytest.mark.parametrize("mode", ["overlap", "depth"])
def test_elastic_branch_is_minus_k_r_delta_r(driver, mode):
    overlap = 0.02
    stiffness, limit, contact_length = spring_by_hand(mode, overlap)
    delta_r = 0.5 * limit / stiffness              # half way to the cap
    _, reply = driver(spring_command(overlap, contact_length), f"roll {delta_r!r} 0 0")
    torque, rolls, angle = roll(reply)
    assert not rolls
    assert close(torque, [-stiffness * delta_r, 0.0, 0.0], scale=limit)
    assert close(angle, [delta_r, 0.0, 0.0], scale=delta_r)


@pytest.mark.parametrize("mode", ["overlap", "depth"])
def test_plastic_branch_is_capped_at_mu_r_f_el(driver, mode):
    overlap = 0.02
    stiffness, limit, contact_length = spring_by_hand(mode, overlap)
    delta_r = 3.0 * limit / stiffness              # three times past the cap
    _, reply = driver(spring_command(overlap, contact_length), f"roll 0 {-delta_r!r} 0")
    torque, rolls, angle = roll(reply)
    assert rolls
    # -delta_r/|delta_r| mu_r f_el: delta_r points along -y, the torque along +y
    assert close(torque, [0.0, limit, 0.0], scale=limit)
    # the spring is cut back to the cap, so a reversal unloads from there
    assert close(angle, [0.0, -limit / stiffness, 0.0], scale=limit / stiffness)


def test_the_cap_itself_is_elastic(driver):
    """k_r |delta_r| = mu_r f_el exactly (all numbers binary-exact):
    eq. 1's first case (<=)."""
    # k_n 1024, l_c = delta_n = 1/16: k_r = 4, mu_r f_el = 0.5 / 16 * 64 = 2
    spring = "spring 1024 0.0625 0.5 0.0625 1 1"
    replies = driver(spring, "roll 0.5 0 0")
    assert [float(v) for v in replies[0][1:]] == [4.0, 2.0]
    torque, rolls, _ = roll(replies[1])
    assert not rolls and torque == [-2.0, 0.0, 0.0]
    _, past = driver(spring, "roll 0.5000001 0 0")
    torque, rolls, _ = roll(past)
    assert rolls and close(torque, [-2.0, 0.0, 0.0])


def test_torque_opposes_the_rolling_angle_in_any_direction(driver):
    stiffness, limit = KN * 0.05 ** 2, MU * 0.05 * KN * 0.01     # 2.5, 0.25
    for direction in ([0.6, 0.8, 0.0], [-0.6, 0.0, 0.8], [0.0, -1.0, 0.0]):
        elastic = [0.04 * c for c in direction]                  # k_r |delta_r| = 0.1 < 0.25
        plastic = [0.4 * c for c in direction]                   # 1.0 > 0.25
        _, small = driver(spring_command(0.01, 0.05), "roll " + " ".join(map(repr, elastic)))
        _, large = driver(spring_command(0.01, 0.05), "roll " + " ".join(map(repr, plastic)))
        assert close(roll(small)[0], [-stiffness * v for v in elastic], scale=limit)
        assert close(roll(large)[0], [-limit * c for c in direction], scale=limit)


def test_zero_rotation_gives_zero_torque(driver):
    _, reply = driver(spring_command(0.01, 0.05), "roll 0 0 0")
    torque, rolls, angle = roll(reply)
    assert torque == [0.0, 0.0, 0.0] and not rolls and angle == [0.0, 0.0, 0.0]


def test_rolling_back_unloads_elastically_from_the_cap(driver):
    stiffness, limit = KN * 0.05 ** 2, MU * 0.05 * KN * 0.01     # 2.5, 0.25: cap at 0.1 rad
    replies = driver(spring_command(0.01, 0.05), "roll 0.4 0 0", "roll -0.04 0 0",
                     "roll -0.06 0 0", "roll -0.3 0 0")
    assert close(roll(replies[1])[0], [-limit, 0.0, 0.0])        # slides at the cap
    torque, rolls, _ = roll(replies[2])                          # 0.1 - 0.04 = 0.06 rad
    assert not rolls and close(torque, [-stiffness * 0.06, 0.0, 0.0], scale=limit)
    torque, rolls, _ = roll(replies[3])                          # back to zero
    assert not rolls and close(torque, [0.0, 0.0, 0.0], scale=limit)
    torque, rolls, _ = roll(replies[4])                          # the cap the other way
    assert rolls and close(torque, [limit, 0.0, 0.0])


# ---------------------------------------------------------------- the spring's bookkeeping

def test_a_stiffer_contact_keeps_its_torque_a_softer_one_its_angle(driver):
    """adapt_to_stiffness: growing k_r shrinks the angle by old/new, so the
    torque stays; shrinking k_r keeps the angle, so the torque drops."""
    replies = driver(spring_command(0.01, 0.05), "roll 0.04 0 0", "restiffen 5.0",
                     "roll 0 0 0", "restiffen 1.0", "roll 0 0 0")
    before, _, _ = roll(replies[1])                              # -2.5 * 0.04 = -0.1
    assert close([float(v) for v in replies[2][1:]], [0.02, 0.0, 0.0])
    assert close(roll(replies[3])[0], before)
    assert close(roll(replies[5])[0], [-1.0 * 0.02, 0.0, 0.0])


def test_the_angle_turns_with_the_contact_and_twist_is_ignored(driver):
    """rotate_into_tangent_plane keeps |delta_r|; remove_normal_component
    drops the spin about the normal."""
    s = 1.0 / math.sqrt(2.0)
    replies = driver(spring_command(0.01, 0.05), "roll 0.03 0 0.04",
                     f"tangent {s!r} 0 {s!r}", "no_twist 1 2 3 0 0 1")
    angle = [float(v) for v in replies[2][1:]]
    # (0.03, 0, 0.04) without its part along (1, 0, 1)/sqrt 2 is (-0.005, 0, 0.005),
    # stretched back to the length 0.05
    assert close(angle, [-0.05 * s, 0.0, 0.05 * s], scale=0.05)
    assert [float(v) for v in replies[3][1:]] == [1.0, 2.0, 0.0]


# ---------------------------------------------------------------- one step, as the hosts call it

def test_one_step_turns_adapts_then_adds_the_rotation(driver):
    """step_rolling_spring, the step every host adapter takes: the stored
    angle (0.03, 0, 0.02) turns into the plane normal to z (its length
    kept), shrinks by old/new k_r = 2.5/5 (a stiffer contact keeps its
    torque), then grows by omega dt = (0, 0.01, 0); the torque is -k_r
    times that. Without `advance` (a run's set-up call) the held angle gives
    the torque as it is and stays."""
    replies = driver(spring_command(0.01, 0.05), "roll 0.03 0 0.02",
                     "step 5.0 0 0 1 0 2 0 0.005 0",
                     "step 5.0 0 0 1 0 2 0 0.005 1",
                     "roll 0 0 0")
    torque, rolls, angle = roll(replies[2])               # not advanced: the held angle, k_r 5
    assert not rolls
    assert close(angle, [0.03, 0.0, 0.02]) and close(torque, [-0.15, 0.0, -0.1])
    expected = [math.hypot(0.03, 0.02) * 2.5 / 5.0, 0.01, 0.0]
    torque, rolls, angle = roll(replies[3])
    assert not rolls                                       # |torque| 0.10 < the cap 0.25
    assert close(angle, expected, scale=0.01)
    assert close(torque, [-5.0 * a for a in expected], scale=0.05)
    assert close(roll(replies[4])[2], expected, scale=0.01)   # kept


def test_damping_is_a_fraction_of_critical_against_the_rotation(driver):
    """add_rolling_damping: torque -= ratio 2 sqrt(I k_r) omega."""
    inertia, ratio = 3.0e-4, 0.5
    replies = driver(spring_command(0.01, 0.05), f"damp {ratio} {inertia} 2 -1 0 0.1 0 0")
    damping = ratio * 2.0 * math.sqrt(inertia * KN * 0.05 ** 2)
    assert close([float(v) for v in replies[1][1:]],
                 [0.1 - 2 * damping, damping, 0.0], scale=0.1)
