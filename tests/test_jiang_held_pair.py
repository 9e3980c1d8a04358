"""rolling_friction jiang, test (a): two spheres held in place (no time
integration) spin in opposite senses, like meshing gears, so that the contact
does not slip and only the rolling spring is loaded. The torque must follow
eq. 1 of Magalhaes et al. (2014) step by step: -k_r delta_r until it reaches
mu_r f_el, stay there, and unload with slope k_r when the spin reverses.
Expected values are computed here from the contact geometry."""

import math

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

RADIUS = 0.005
DISTANCE = 0.0099            # overlap 1e-4 m
KN = 1.0e5
MU = 0.5
DT = 1.0e-5
OMEGA = 10.0                 # rad/s, each grain; relative rotation 2 OMEGA
FIXED_LENGTH = 1.0e-3


def held_pair_deck(rolling_settings, properties, load_steps, unload_steps,
                   restart_at=None):
    return f"""
{granular_setup()}
region box block -0.02 0.03 -0.02 0.02 -0.02 0.02 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(KN, 0.4 * KN, mu=MU)}
{properties}
pair_style gran model hooke/stiffness tangential history rolling_friction jiang {rolling_settings}
pair_coeff * *
timestep {DT}
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {DISTANCE} 0 0 units box
set group all diameter {2 * RADIUS} density 2500
set atom 1 omegaz {OMEGA}
set atom 2 omegaz {-OMEGA}
dump torques all custom 1 dump.torque id tqx tqy tqz
dump_modify torques format "%d %.17g %.17g %.17g"
run {load_steps}
set atom 1 omegaz {-OMEGA}
set atom 2 omegaz {OMEGA}
run {unload_steps}
"""


def expected_torque(contact_length, load_steps, unload_steps):
    """Torque on grain 1 (z) after each step 1..load+unload, from eq. 1."""
    elastic_force = KN * (2 * RADIUS - DISTANCE)
    stiffness = KN * contact_length ** 2
    limit = MU * contact_length * elastic_force
    angle = 0.0
    torques = []
    for step in range(1, load_steps + unload_steps + 1):
        rate = 2 * OMEGA if step <= load_steps else -2 * OMEGA
        angle += rate * DT
        if abs(stiffness * angle) > limit:
            angle = math.copysign(limit / stiffness, angle)
        torques.append(-stiffness * angle)
    return np.array(torques), limit, stiffness


def measured_torque(path):
    frames = read_dump(path)
    # the last step of a run is dumped again by the setup of the next run,
    # whose force call does not advance the history: keep the first one
    by_step = {}
    for step, columns in frames:
        by_step.setdefault(step, columns)
    steps = sorted(s for s in by_step if s >= 1)
    tz1 = np.array([by_step[s]["tqz"][0] for s in steps])
    tz2 = np.array([by_step[s]["tqz"][1] for s in steps])
    txy = np.array([np.abs(by_step[s]["tqx"]).max() + np.abs(by_step[s]["tqy"]).max()
                    for s in steps])
    return tz1, tz2, txy


@pytest.mark.parametrize("mode", ["fixed", "overlap", "depth"])
def test_torque_loads_saturates_and_unloads(run, tmp_path, mode):
    if mode == "fixed":
        settings, properties = "", per_pair("rollingContactLength", FIXED_LENGTH)
        contact_length = FIXED_LENGTH
    elif mode == "depth":
        # l_c = the overlap depth delta_n = 1e-4 m
        settings, properties = "contactLengthFromDepth on", ""
        contact_length = 2 * RADIUS - DISTANCE
    else:
        settings, properties = "contactLengthFromOverlap on", ""
        # chord of two equal circles whose centres are DISTANCE apart
        contact_length = 2 * math.sqrt(RADIUS ** 2 - (DISTANCE / 2) ** 2)

    expected, limit, stiffness = expected_torque(contact_length, 0, 0)
    steps_to_cap = limit / (stiffness * 2 * OMEGA * DT)
    load = int(steps_to_cap * 1.6)
    unload = int(steps_to_cap * 1.2)
    run(held_pair_deck(settings, properties, load, unload))
    expected, limit, stiffness = expected_torque(contact_length, load, unload)
    tz1, tz2, txy = measured_torque(tmp_path / "dump.torque")

    assert len(tz1) == load + unload
    # eq. 1 step by step, both branches and the reversal
    np.testing.assert_allclose(tz1, expected, rtol=1e-6, atol=1e-9 * limit)
    # action = reaction, and no torque about the other axes
    np.testing.assert_allclose(tz2, -tz1, rtol=1e-12, atol=1e-15)
    assert txy.max() < 1e-12 * limit
    # the checks above cover all three regimes
    assert np.isclose(tz1[load - 1], -limit, rtol=1e-6)
    assert -limit < tz1[0] < 0
    assert tz1[-1] > 0  # unloaded through zero, elastic the whole way


def test_nonlinear_normal_model_uses_secant_stiffness(run, tmp_path):
    """With `model hertz`, k_n is the secant stiffness the normal model
    reports, 4/3 Y* sqrt(R* delta_n), and f_el = k_n delta_n its elastic
    force: the held pair's torque follows eq. 1 with those, computed here
    from the Hertz formula (Y* = Y / (2 (1 - nu^2)), R* = r / 2)."""
    youngs, poisson = 5.0e6, 0.3
    materials = f"""
fix m_Y all property/global youngsModulus peratomtype {youngs}
fix m_nu all property/global poissonsRatio peratomtype {poisson}
fix m_e all property/global coefficientRestitution peratomtypepair 1 0.9
fix m_mu all property/global coefficientFriction peratomtypepair 1 {MU}
{per_pair("rollingContactLength", FIXED_LENGTH)}
"""
    overlap = 2 * RADIUS - DISTANCE
    secant = 4.0 / 3.0 * youngs / (2 * (1 - poisson ** 2)) * math.sqrt(RADIUS / 2 * overlap)
    stiffness = secant * FIXED_LENGTH ** 2
    limit = MU * FIXED_LENGTH * secant * overlap
    steps_to_cap = limit / (stiffness * 2 * OMEGA * DT)
    load, unload = int(steps_to_cap * 1.6), int(steps_to_cap * 1.2)
    deck = held_pair_deck("", "", load, unload).replace(
        "model hooke/stiffness", "model hertz")
    deck = deck[:deck.index("fix m_kn")] + materials + deck[deck.index("pair_style"):]
    run(deck)
    tz1, _, _ = measured_torque(tmp_path / "dump.torque")
    angle, expected = 0.0, []
    for step in range(1, load + unload + 1):
        angle += (2 * OMEGA if step <= load else -2 * OMEGA) * DT
        if abs(stiffness * angle) > limit:
            angle = math.copysign(limit / stiffness, angle)
        expected.append(-stiffness * angle)
    np.testing.assert_allclose(tz1, expected, rtol=1e-6, atol=1e-9 * limit)
    assert np.isclose(tz1[load - 1], -limit, rtol=1e-6)
