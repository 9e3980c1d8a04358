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
- Against LIGGGHTS itself (marked `engine`): see the second half of this
  file.
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
