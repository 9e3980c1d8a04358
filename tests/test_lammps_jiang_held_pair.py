"""pair_style granular/jiang in LAMMPS, the held pair: two spheres held in
place (no time integration) spin in opposite senses, like meshing gears, so
that the contact does not slip and only the rolling spring is loaded. The
torque must follow eq. 1 of Magalhaes et al. (2014) step by step: -k_r
delta_r until it reaches mu_r f_el, stay there, and unload with slope k_r
when the spin reverses. Expected values are computed here from the contact
geometry, for each contact-length mode (fixed l_c, the overlap's chord, the
overlap's depth); tests/test_jiang_held_pair.py is the same check in
LIGGGHTS."""

import math

import numpy as np
import pytest

from analysis.testing import read_frames
from lammps_host import has_mpirun, needs_lammps, run_lammps

pytestmark = needs_lammps

RADIUS = 0.005
DISTANCE = 0.0099            # overlap 1e-4 m
KN = 1.0e5
MU = 0.5
DT = 1.0e-5
OMEGA = 10.0                 # rad/s, each grain; relative rotation 2 OMEGA
FIXED_LENGTH = 1.0e-3


def held_pair_deck(length, load_steps, unload_steps, extra=""):
    return f"""
plugin load ${{plugin}}
units si
atom_style sphere
boundary f f f
newton off
comm_modify vel yes
{extra}
region box block -0.02 0.03 -0.02 0.02 -0.02 0.02 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
pair_style granular/jiang
pair_coeff * * normal hooke/stiffness {KN} {0.4 * KN} 0 0 friction {MU} rolling jiang 1 1 lc {length}
timestep {DT}
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {DISTANCE} 0 0 units box
set group all diameter {2 * RADIUS} density 2500
set atom 1 omega 0 0 {OMEGA}
set atom 2 omega 0 0 {-OMEGA}
dump torques all custom 1 dump.torque id tqx tqy tqz
dump_modify torques format line "%d %.17g %.17g %.17g"
run {load_steps}
set atom 1 omega 0 0 {-OMEGA}
set atom 2 omega 0 0 {OMEGA}
run {unload_steps}
"""


def contact_length_of(mode):
    if mode == "fixed":
        return FIXED_LENGTH
    if mode == "depth":
        return 2 * RADIUS - DISTANCE      # l_c = the overlap depth delta_n
    # chord of two equal circles whose centres are DISTANCE apart
    return 2 * math.sqrt(RADIUS ** 2 - (DISTANCE / 2) ** 2)


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
    by_step = {}
    for frame in read_frames(path):
        by_step.setdefault(frame.step, frame)
    steps = sorted(s for s in by_step if s >= 1)
    tz1 = np.array([by_step[s].atom(1)["tqz"] for s in steps])
    tz2 = np.array([by_step[s].atom(2)["tqz"] for s in steps])
    txy = np.array([np.abs(by_step[s]["tqx"]).max() + np.abs(by_step[s]["tqy"]).max()
                    for s in steps])
    return tz1, tz2, txy


def steps_for(mode):
    _, limit, stiffness = expected_torque(contact_length_of(mode), 0, 0)
    steps_to_cap = limit / (stiffness * 2 * OMEGA * DT)
    return int(steps_to_cap * 1.6), int(steps_to_cap * 1.2)


@pytest.mark.parametrize("mode", ["fixed", "overlap", "depth"])
def test_torque_loads_saturates_and_unloads(tmp_path, mode):
    length = {"fixed": FIXED_LENGTH, "overlap": "overlap", "depth": "depth"}[mode]
    load, unload = steps_for(mode)
    run_lammps(held_pair_deck(length, load, unload), tmp_path)
    expected, limit, _ = expected_torque(contact_length_of(mode), load, unload)
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


@pytest.mark.skipif(not has_mpirun(), reason="mpirun is not installed")
def test_two_ranks_give_the_same_torques(tmp_path):
    """One grain on each rank (the pair is a ghost pair on both, newton off):
    the history travels with FixNeighHistory and the torques are those of
    one rank, to the last bit (one contact: nothing to sum in another order)."""
    load, unload = steps_for("overlap")
    run_lammps(held_pair_deck("overlap", load, unload), tmp_path / "np1")
    run_lammps(held_pair_deck("overlap", load, unload, extra="processors 2 1 1"),
               tmp_path / "np2", nprocs=2)
    serial = measured_torque(tmp_path / "np1" / "dump.torque")
    parallel = measured_torque(tmp_path / "np2" / "dump.torque")
    for a, b in zip(serial, parallel):
        np.testing.assert_array_equal(a, b)


def test_restart_mid_contact_continues_the_spring(tmp_path):
    """write_restart in the middle of the loading, read_restart in a new
    deck: the coefficients come back from the restart file (no pair_style
    or pair_coeff in the second deck), the rolling spring from
    FixNeighHistory's restart data, and the set-up force call does not
    advance it: the torques after the restart are those of the run that
    went on, to the last bit (the grains are held, so nothing else moves)."""
    load, unload = steps_for("overlap")
    half = load // 2
    whole = held_pair_deck("overlap", load, unload)
    run_lammps(whole, tmp_path / "whole")

    first = held_pair_deck("overlap", half, 0)
    first = first[:first.index("set atom 1 omega 0 0 -")] + "write_restart held.restart\n"
    run_lammps(first, tmp_path / "split")
    second = f"""
plugin load ${{plugin}}
read_restart held.restart
dump torques all custom 1 dump.second id tqx tqy tqz
dump_modify torques format line "%d %.17g %.17g %.17g"
run {load - half}
set atom 1 omega 0 0 {-OMEGA}
set atom 2 omega 0 0 {OMEGA}
run {unload}
"""
    run = run_lammps(second, tmp_path / "split")
    assert "granular/jiang" in run.output
    whole_torques = measured_torque(tmp_path / "whole" / "dump.torque")
    split_torques = measured_torque(tmp_path / "split" / "dump.second")
    # the second deck's dump starts with step `half` (its set-up call)
    for a, b in zip(whole_torques, split_torques):
        np.testing.assert_array_equal(a[half - 1:], b)
