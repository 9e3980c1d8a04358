"""Triclinic boxes in our LIGGGHTS build (cmake/liggghts-3.8.0-triclinic-lamda-box.patch).

LIGGGHTS 3.8.0 sets the fractional box's size (`Domain::prd_lamda`) to 0
where LAMMPS sets 1. A tilted box keeps positions in fractional
coordinates while it wraps atoms and sets up communication, so there:
a grain crossing a periodic side was not moved back into the box and
was lost, silently (LIGGGHTS ignores lost atoms by default); and the
number of ghost exchanges, computed by dividing by that size, was garbage,
so a parallel run could hang in its set-up (Debian's `liggghts` does, with
any processor grid; doc/liggghts_quirks.md). Here a lone grain in free
flight crosses the periodic sides of a tilted box on one rank and on two,
and every frame is checked against the position worked out here from the
box's edge vectors.
"""

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump
from conftest import has_mpirun

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS

DT = 1.0e-4
STEPS = 3000
DUMP_EVERY = 50
LO = np.array([0.0, 0.0, 0.0])
# edge vectors a = (xprd, 0, 0), b = (xy, yprd, 0), c = (xz, yz, zprd)
XPRD, YPRD, ZPRD, XY, XZ, YZ = 0.1, 0.1, 0.1, 0.03, 0.0, 0.0
START = np.array([0.05, 0.05, 0.05])
# 0.3 s of flight: 2.4 box lengths in x and 3.3 in y, crossing the tilted
# sides (x) and the sides the tilt shifts (y: x jumps by -xy at each)
VELOCITY = np.array([0.8, 1.1, 0.0])


def tilted_box_deck(processors):
    return f"""
{granular_setup(boundary="p p f")}
{processors}
region box prism {LO[0]} {XPRD} {LO[1]} {YPRD} {LO[2]} {ZPRD} {XY} {XZ} {YZ} units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{hooke_materials(1e4, 2.857e3)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep {DT}
create_atoms 1 single {START[0]!r} {START[1]!r} {START[2]!r} units box
set group all diameter 0.008 density 2500
velocity all set {VELOCITY[0]!r} {VELOCITY[1]!r} {VELOCITY[2]!r} units box
fix integr all nve/sphere
thermo 500
dump d all custom {DUMP_EVERY} dump.grain id x y z
dump_modify d format "%d %.15g %.15g %.15g"
run {STEPS}
"""


H = np.array([[XPRD, XY, XZ], [0.0, YPRD, YZ], [0.0, 0.0, ZPRD]])


def unfolded_fractional(t):
    return np.linalg.solve(H, START + VELOCITY * t - LO)


def expected_position(t):
    """The straight flight folded back into the box through its periodic
    sides (x and y): fractional coordinates modulo 1, back to box ones."""
    fractional = unfolded_fractional(t)
    fractional[:2] -= np.floor(fractional[:2])
    return LO + H @ fractional


def sides_crossed(t):
    return int(np.floor(unfolded_fractional(t)[:2]).sum())


@pytest.mark.parametrize("nprocs, processors", [
    (1, ""),
    pytest.param(2, "processors 2 1 1",
                 marks=pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")),
    pytest.param(2, "processors 1 2 1",
                 marks=pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")),
])
def test_a_grain_crossing_the_periodic_sides_of_a_tilted_box_comes_back_in(
        run, tmp_path, nprocs, processors):
    run(tilted_box_deck(processors), nprocs=nprocs)
    frames = read_dump(tmp_path / "dump.grain")
    assert len(frames) == STEPS // DUMP_EVERY + 1
    for step, columns in frames:
        assert len(columns["id"]) == 1, f"the grain is lost at step {step}"
        position = np.array([columns[axis][0] for axis in "xyz"])
        np.testing.assert_allclose(position, expected_position(step * DT), rtol=0, atol=1e-9,
                                   err_msg=f"step {step}")
    # through a tilted side once and three times through the others
    assert sides_crossed(STEPS * DT) == 4
