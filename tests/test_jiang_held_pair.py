"""rolling_friction jiang, test (a): two spheres held in place (no time
integration) spin in opposite senses, like meshing gears, so that the contact
does not slip and only the rolling spring is loaded. The torque must follow
eq. 1 of Magalhaes et al. (2014) step by step: -k_r delta_r until it reaches
mu_r f_el, stay there, and unload with slope k_r when the spin reverses.
Expected values are computed here from the contact geometry."""

import math

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair
from held_pair_eq1 import (DISTANCE, DT, FIXED_LENGTH, KN, MU, OMEGA, RADIUS, assert_follows_eq1,
                           contact_length_of, eq1_torques, hooke_spring, measured_torque,
                           steps_for)

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)


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


@pytest.mark.parametrize("mode", ["fixed", "overlap", "depth"])
def test_torque_loads_saturates_and_unloads(run, tmp_path, mode):
    settings, properties = {
        "fixed": ("", per_pair("rollingContactLength", FIXED_LENGTH)),
        "depth": ("contactLengthFromDepth on", ""),
        "overlap": ("contactLengthFromOverlap on", ""),
    }[mode]
    stiffness, limit = hooke_spring(contact_length_of(mode))
    load, unload = steps_for(stiffness, limit)
    run(held_pair_deck(settings, properties, load, unload))
    assert_follows_eq1(measured_torque(tmp_path / "dump.torque"),
                       eq1_torques(stiffness, limit, load, unload), limit, load, unload)


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
    load, unload = steps_for(stiffness, limit)
    deck = held_pair_deck("", "", load, unload).replace(
        "model hooke/stiffness", "model hertz")
    deck = deck[:deck.index("fix m_kn")] + materials + deck[deck.index("pair_style"):]
    run(deck)
    tz1, _, _ = measured_torque(tmp_path / "dump.torque")
    expected = eq1_torques(stiffness, limit, load, unload)
    np.testing.assert_allclose(tz1, expected, rtol=1e-6, atol=1e-9 * limit)
    assert np.isclose(tz1[load - 1], -limit, rtol=1e-6)
