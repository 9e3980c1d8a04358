"""The held pair of Jiang's rolling law, shared by the LIGGGHTS test
(tests/test_jiang_held_pair.py) and the LAMMPS one
(tests/test_lammps_jiang_held_pair.py): two spheres held in place spin in
opposite senses, like meshing gears, so that only the rolling spring is
loaded. Here: the geometry, eq. 1 of Magalhaes et al. (2014) stepped by
hand, the dumped torques, and the checks both hosts must pass."""

import math

import numpy as np

from analysis.common.lammps_io import read_dump

RADIUS = 0.005
DISTANCE = 0.0099            # overlap 1e-4 m
KN = 1.0e5
MU = 0.5
DT = 1.0e-5
OMEGA = 10.0                 # rad/s, each grain; relative rotation 2 OMEGA
FIXED_LENGTH = 1.0e-3


def contact_length_of(mode):
    """l_c of a contact-length mode: fixed, the overlap's chord, its depth."""
    if mode == "fixed":
        return FIXED_LENGTH
    if mode == "depth":
        return 2 * RADIUS - DISTANCE      # l_c = the overlap depth delta_n
    # chord of two equal circles whose centres are DISTANCE apart
    return 2 * math.sqrt(RADIUS ** 2 - (DISTANCE / 2) ** 2)


def eq1_torques(stiffness, limit, load_steps, unload_steps):
    """Torque on grain 1 (z) after each step 1..load+unload: the angle grows
    by 2 OMEGA DT per step (shrinks while unloading), capped at limit/k_r."""
    angle = 0.0
    torques = []
    for step in range(1, load_steps + unload_steps + 1):
        rate = 2 * OMEGA if step <= load_steps else -2 * OMEGA
        angle += rate * DT
        if abs(stiffness * angle) > limit:
            angle = math.copysign(limit / stiffness, angle)
        torques.append(-stiffness * angle)
    return np.array(torques)


def hooke_spring(contact_length):
    """k_r = k_n l_c^2 and mu_r f_el = mu l_c k_n delta_n (a = b = 1)."""
    elastic_force = KN * (2 * RADIUS - DISTANCE)
    return KN * contact_length ** 2, MU * contact_length * elastic_force


def steps_for(stiffness, limit):
    """Loading to 1.6 times, unloading 1.2 times the steps to the cap."""
    steps_to_cap = limit / (stiffness * 2 * OMEGA * DT)
    return int(steps_to_cap * 1.6), int(steps_to_cap * 1.2)


def measured_torque(path):
    """(tz of grain 1, tz of grain 2, |tx|+|ty| largest) per step >= 1. The
    last step of a run is dumped again by the set-up of the next, whose
    force call does not advance the history: the first one is kept."""
    by_step = {}
    for step, columns in read_dump(path):
        by_step.setdefault(step, columns)
    steps = sorted(s for s in by_step if s >= 1)
    # read_dump sorts the rows by id: grain 1 first
    tz1 = np.array([by_step[s]["tqz"][0] for s in steps])
    tz2 = np.array([by_step[s]["tqz"][1] for s in steps])
    txy = np.array([np.abs(by_step[s]["tqx"]).max() + np.abs(by_step[s]["tqy"]).max()
                    for s in steps])
    return tz1, tz2, txy


def assert_follows_eq1(torques, expected, limit, load_steps, unload_steps):
    """Eq. 1 step by step on both branches and through the reversal, action =
    reaction, no torque about the other axes."""
    tz1, tz2, txy = torques
    assert len(tz1) == load_steps + unload_steps
    np.testing.assert_allclose(tz1, expected, rtol=1e-6, atol=1e-9 * limit)
    np.testing.assert_allclose(tz2, -tz1, rtol=1e-12, atol=1e-15)
    assert txy.max() < 1e-12 * limit
    # the checks above cover all three regimes
    assert np.isclose(tz1[load_steps - 1], -limit, rtol=1e-6)
    assert -limit < tz1[0] < 0
    assert tz1[-1] > 0  # unloaded through zero, elastic the whole way
