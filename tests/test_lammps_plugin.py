"""The LAMMPS plugin build/lib/silokit_lammps.so: it loads into our
build/bin/lmp serially and under mpirun -np 2 (`plugin list` names
granular/jiang), a deck with the pair style runs, and bad input to
pair_style / pair_coeff granular/jiang stops with an ERROR naming the
keyword (doc/pair_granular_jiang.md)."""

import pytest

from analysis.testing import LiggghtsError
from lammps_host import has_mpirun, needs_lammps, run_lammps

pytestmark = needs_lammps

COEFF = "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling jiang 1 1 lc 1e-3"


def two_grains(coeff=COEFF, pair_style="granular/jiang", steps=10):
    return f"""
plugin load ${{plugin}}
plugin list
units si
atom_style sphere
boundary f f f
newton off
comm_modify vel yes
region box block -0.02 0.03 -0.02 0.02 -0.02 0.02 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
pair_style {pair_style}
pair_coeff * * {coeff}
timestep 1e-5
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 0.0099 0 0 units box
set group all diameter 0.01 density 2500
fix integrate all nve/sphere
thermo_style custom step atoms ke
run {steps}
"""


def test_plugin_loads_and_the_pair_runs(tmp_path):
    run = run_lammps(two_grains(), tmp_path)
    assert "pair style plugin granular/jiang" in run.output
    assert "Loop time of" in run.output


@pytest.mark.skipif(not has_mpirun(), reason="mpirun is not installed")
def test_plugin_loads_under_mpirun_np2(tmp_path):
    deck = two_grains().replace("boundary f f f", "boundary f f f\nprocessors 2 1 1")
    run = run_lammps(deck, tmp_path, nprocs=2)
    assert "pair style plugin granular/jiang" in run.output
    assert "on 2 procs for 10 steps with 2 atoms" in run.output


BAD_INPUT = [
    # (what is wrong, pair_coeff arguments, words the ERROR must hold)
    ("unknown keyword", COEFF + " bogus 1", ["unknown keyword 'bogus'"]),
    ("friction not a number", "normal hooke/stiffness 1e5 4e4 0 0 friction abc",
     ["friction expects a number", "'abc'"]),
    ("negative friction", "normal hooke/stiffness 1e5 4e4 0 0 friction -0.5", ["friction must be >= 0"]),
    ("unknown normal model", "normal hertz 1e5 4e4 0 0 friction 0.5", ["normal model 'hertz'"]),
    ("kn zero", "normal hooke/stiffness 0 4e4 0 0 friction 0.5", ["hooke/stiffness kn must be > 0"]),
    ("normal values missing", "normal hooke/stiffness 1e5 4e4", ["normal hooke/stiffness", "needs 4 values"]),
    ("no normal", "friction 0.5", ["normal is required"]),
    ("no friction", "normal hooke/stiffness 1e5 4e4 0 0", ["friction is required"]),
    ("restitution above 1", "normal hooke 5e6 0.3 1.5 1.0 friction 0.5", ["normal hooke e must be in (0, 1]"]),
    ("stiffness factor zero", "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling jiang 0 1 lc 1e-3",
     ["rolling jiang a"]),
    ("lc misspelt", "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling jiang 1 1 length 1e-3",
     ["followed by lc", "'length'"]),
    ("lc negative", "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling jiang 1 1 lc -1",
     ["rolling jiang lc must be >= 0"]),
    ("unknown rolling model", "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling sds 1 1 lc 1",
     ["rolling model 'sds'"]),
    ("rolling damping without rolling", "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling_damping 0.1",
     ["rolling_damping needs rolling jiang"]),
    ("yes/no misspelt", COEFF + " limit_force on", ["limit_force expects yes or no", "'on'"]),
]


@pytest.mark.parametrize("what, coeff, words", BAD_INPUT, ids=[case[0] for case in BAD_INPUT])
def test_bad_pair_coeff_names_the_keyword(tmp_path, what, coeff, words):
    with pytest.raises(LiggghtsError) as error:
        run_lammps(two_grains(coeff=coeff), tmp_path)
    assert "pair_coeff granular/jiang" in error.value.message
    for word in words:
        assert word in error.value.message, what


def test_pair_style_takes_no_arguments(tmp_path):
    with pytest.raises(LiggghtsError) as error:
        run_lammps(two_grains(pair_style="granular/jiang 1e5"), tmp_path)
    assert "pair_style granular/jiang takes no arguments" in error.value.message


def test_fixed_contact_length_larger_than_a_grain_stops(tmp_path):
    """The fixed l_c is checked against the grains in contact (diameter 0.01)."""
    coeff = "normal hooke/stiffness 1e5 4e4 0 0 friction 0.5 rolling jiang 1 1 lc 0.02"
    with pytest.raises(LiggghtsError) as error:
        run_lammps(two_grains(coeff=coeff), tmp_path)
    assert "rolling jiang lc 0.02" in error.value.message
    assert "larger than the diameter" in error.value.message


def test_every_type_pair_needs_its_coefficients(tmp_path):
    deck = two_grains().replace("create_box 1 box", "create_box 2 box").replace(
        "pair_coeff * *", "pair_coeff 1 1")
    deck = deck.replace("pair_coeff 1 1 " + COEFF, f"pair_coeff 1 1 {COEFF}\npair_coeff 2 2 {COEFF}")
    with pytest.raises(LiggghtsError) as error:
        run_lammps(deck, tmp_path)
    assert "no pair_coeff for types 1 2" in error.value.message


def test_compute_pair_local_reads_single(tmp_path):
    """compute pair/local calls the style's single(): the held pair's normal
    force kn * overlap = 1e5 * 1e-4 = 10 N; a tangential drift of grain 2
    (0.01 m/s along y, no integration) loads the tangential spring by
    kt v dt = 4e4 * 0.01 * 1e-5 = 4e-3 N per step, below the cap mu Fn = 5 N."""
    deck = two_grains(steps=10).replace("fix integrate all nve/sphere", """
set atom 2 vy 0.01
compute pl all pair/local force p4 p8 p9 p10
dump pl all local 10 dump.local c_pl[1] c_pl[2] c_pl[3] c_pl[4] c_pl[5]
dump_modify pl format line "%.17g %.17g %.17g %.17g %.17g"
""")
    run_lammps(deck, tmp_path)
    lines = (tmp_path / "dump.local").read_text().splitlines()
    last = [float(value) for value in lines[-1].split()]
    force, ft, vt = last[0], last[1], last[2:5]
    assert force == pytest.approx(10.0, rel=1e-12)
    # after 10 steps: |shear| = 10 * 0.01 * 1e-5 = 1e-6 m, kt |shear| = 0.04 N
    # (gammat 0); vt = v1 - v2 = -0.01 along y (p8..p10: vt1..vt3)
    assert ft == pytest.approx(0.04, rel=1e-9)
    assert vt == pytest.approx([0.0, -0.01, 0.0], abs=1e-15)
