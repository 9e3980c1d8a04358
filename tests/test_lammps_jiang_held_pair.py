"""pair_style granular/jiang in LAMMPS, the held pair: two spheres held in
place (no time integration) spin in opposite senses, like meshing gears, so
that the contact does not slip and only the rolling spring is loaded. The
torque must follow eq. 1 of Magalhaes et al. (2014) step by step: -k_r
delta_r until it reaches mu_r f_el, stay there, and unload with slope k_r
when the spin reverses. Expected values are computed here from the contact
geometry, for each contact-length mode (fixed l_c, the overlap's chord, the
overlap's depth); tests/test_jiang_held_pair.py is the same check in
LIGGGHTS."""

import numpy as np
import pytest

from held_pair_eq1 import (DISTANCE, DT, FIXED_LENGTH, KN, MU, OMEGA, RADIUS, assert_follows_eq1,
                           contact_length_of, eq1_torques, hooke_spring, measured_torque,
                           steps_for)
from lammps_host import has_mpirun, needs_lammps, run_lammps

pytestmark = needs_lammps


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


def load_and_unload_steps(mode):
    return steps_for(*hooke_spring(contact_length_of(mode)))


@pytest.mark.parametrize("mode", ["fixed", "overlap", "depth"])
def test_torque_loads_saturates_and_unloads(tmp_path, mode):
    length = {"fixed": FIXED_LENGTH, "overlap": "overlap", "depth": "depth"}[mode]
    load, unload = load_and_unload_steps(mode)
    run_lammps(held_pair_deck(length, load, unload), tmp_path)
    stiffness, limit = hooke_spring(contact_length_of(mode))
    assert_follows_eq1(measured_torque(tmp_path / "dump.torque"),
                       eq1_torques(stiffness, limit, load, unload), limit, load, unload)


@pytest.mark.skipif(not has_mpirun(), reason="mpirun is not installed")
def test_two_ranks_give_the_same_torques(tmp_path):
    """One grain on each rank (the pair is a ghost pair on both, newton off):
    the history travels with FixNeighHistory and the torques are those of
    one rank, to the last bit (one contact: nothing to sum in another order)."""
    load, unload = load_and_unload_steps("overlap")
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
    load, unload = load_and_unload_steps("overlap")
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
