"""The rule for rods (atom_vec_spherocylinder.cpp, doc/spherocylinder.md):
to a stock style a rod is its bounding sphere (radius L/2), so the styles
that know rods, and stock ones that never read the radius, are listed;
any other fix that moves, places or touches particles is refused, naming
what to use instead; any other fix or compute runs with one WARNING (per
ID, from rank 0), since an output that reads the radius gets the bounding
sphere's. Each case adds one line to a one-rod deck of
test_spherocylinder.py, which by itself warns of nothing.
"""

import pytest

from analysis.testing import LiggghtsError
from conftest import has_mpirun, run_liggghts
from test_spherocylinder import rod_deck

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

ROD = [((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0))]
NOT_KNOWN = "is not known to take rods: where it reads the radius, it gets the bounding sphere's (L/2)"


def rule_warnings(output):
    return [line for line in output.splitlines() if line.startswith("WARNING") and NOT_KNOWN in line]


def two_runs(extra):
    return rod_deck(ROD, steps=1, extra=extra).replace("run 1\n", "run 1\nrun 1\n")


def test_the_rod_deck_uses_listed_styles_only(tmp_path):
    # nve/spherocylinder, property/global, contacthistory, spherocylinder/axis,
    # the thermo output's computes: no warning
    assert rule_warnings(run_liggghts(two_runs(""), tmp_path)) == []


@pytest.mark.parametrize("line, style", [
    ("fix slow all viscous 0.001", "fix slow (viscous)"),
    ("compute spin all erotate/sphere\nthermo_style custom step c_spin", "compute spin (erotate/sphere)"),
    ("compute pairs all pair/gran/local id pos delta", "compute pairs (pair/gran/local)"),
])
def test_an_unlisted_style_runs_with_one_warning(tmp_path, line, style):
    lines = rule_warnings(run_liggghts(two_runs(line), tmp_path))
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"WARNING: atom_style spherocylinder: {style} {NOT_KNOWN}"), lines[0]


def test_pair_gran_local_without_what_it_takes_from_the_radius_is_listed(tmp_path):
    output = run_liggghts(two_runs("compute pairs all pair/gran/local id pos force"), tmp_path)
    assert rule_warnings(output) == []


@pytest.mark.parametrize("line, message", [
    ("fix limited all nve/limit radius_ratio 0.01",
     "fix limited (nve/limit) treats rods as spheres; use fix nve/spherocylinder"),
    ("fix arches all clog", "finds arches of spheres: rods (atom_style spherocylinder) are not supported"),
])
def test_an_unlisted_style_that_would_move_rods_as_spheres_is_refused(tmp_path, line, message):
    with pytest.raises(LiggghtsError) as error:
        run_liggghts(rod_deck(ROD, steps=1, extra=line), tmp_path)
    assert message in error.value.message, error.value.message


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_warn_once(tmp_path):
    output = run_liggghts(two_runs("fix slow all viscous 0.001"), tmp_path, nprocs=2)
    assert len(rule_warnings(output)) == 1
