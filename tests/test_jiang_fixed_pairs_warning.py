"""rolling_friction jiang: with contactLengthFromOverlap (or FromDepth) on,
a type pair given rollingContactLength > 0 keeps that fixed l_c. A deck
written when the property was ignored in these modes may hold a
placeholder there, so LIGGGHTS says which type pairs keep a fixed l_c:
one WARNING line per model (pair style, each wall), at the first run,
from rank 0 only, naming the pairs and their l_c. Nothing is printed in
the fixed mode, or when every pair has 0.

The decks are test_jiang_errors' (two grains in contact, or one grain on
a wall).
"""

import pytest

from analysis.common.deck_blocks import per_pair
from conftest import has_mpirun, run_liggghts
from test_jiang_errors import deck

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

WARNING = "keeps the fixed l_c of rollingContactLength"
# type pair 1-2 fixed, 1-1 and 2-2 from the contact
MIXED = "fix m_lc all property/global rollingContactLength peratomtypepair 2 0.0 5e-4 5e-4 0.0\n"


def warnings(output):
    return [line for line in output.splitlines()
            if line.startswith("WARNING") and "rolling_friction jiang" in line]


@pytest.mark.parametrize("mode", ["contactLengthFromOverlap", "contactLengthFromDepth"])
def test_the_pairs_that_keep_a_fixed_contact_length_are_named_once(tmp_path, mode):
    text = deck("pair", f"{mode} on", properties=MIXED, ntypes=2)
    text = text.replace("run 2\n", "run 2\nrun 2\n")          # two runs, one warning
    lines = warnings(run_liggghts(text, tmp_path, timeout=120))
    assert len(lines) == 1, lines
    assert f"{mode} is on, but type pair 1-2 (0.0005) {WARNING}" in lines[0], lines[0]
    assert "1-1" not in lines[0] and "2-2" not in lines[0]


def test_several_pairs_and_a_wall(tmp_path):
    text = deck("wall", "contactLengthFromOverlap on", properties=per_pair("rollingContactLength", 1e-3))
    (line,) = warnings(run_liggghts(text, tmp_path, timeout=120))
    assert "type pair 1-1 (0.001) keeps the fixed l_c" in line
    text = deck("pair", "contactLengthFromOverlap on",
                properties=per_pair("rollingContactLength", 1e-3, ntypes=2), ntypes=2)
    (line,) = warnings(run_liggghts(text, tmp_path / "pairs", timeout=120))
    assert "type pairs 1-1 (0.001), 1-2 (0.001), 2-2 (0.001) keep the fixed l_c" in line


@pytest.mark.parametrize("settings, properties", [
    ("contactLengthFromOverlap on", per_pair("rollingContactLength", 0.0)),
    ("contactLengthFromOverlap on", ""),
    ("", per_pair("rollingContactLength", 1e-3)),          # the fixed mode: l_c is meant fixed
])
def test_no_warning_when_no_pair_keeps_a_fixed_length_by_surprise(tmp_path, settings, properties):
    output = run_liggghts(deck("pair", settings, properties=properties), tmp_path, timeout=120)
    assert warnings(output) == []


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_warn_once(tmp_path):
    text = deck("pair", "contactLengthFromOverlap on", properties=MIXED, ntypes=2)
    output = run_liggghts(text, tmp_path, nprocs=2, timeout=120)
    assert len(warnings(output)) == 1
