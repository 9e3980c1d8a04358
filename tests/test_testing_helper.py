"""analysis.testing, the helper users' test suites import (doc/testing.md):
it passes what agrees, and fails where it should (a moved atom, a missing
id, a renamed column, a changed thermo value) with a message naming the
atom or step and the column. The last tests run the built binary."""

import numpy as np
import pytest

from analysis.testing import (Frame, LiggghtsError, assert_dumps_close, assert_thermo_close,
                              read_frame, read_frames, read_record, read_thermo, run_deck)
from analysis.common.deck_blocks import granular_setup, hooke_materials


def write_dump(path, frames, names=("id", "type", "x", "y", "z", "vx")):
    """A `dump custom` text file; frames: (step, rows) with rows in the
    order they are written (not sorted by id, as several ranks write)."""
    with open(path, "w") as out:
        for step, rows in frames:
            out.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(rows)}\n"
                      "ITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
                      f"ITEM: ATOMS {' '.join(names)}\n")
            for row in rows:
                out.write(" ".join(repr(v) for v in row) + "\n")
    return path


ROWS = [(3, 1, 0.1, 0.2, 0.3, -0.5), (1, 1, 0.4, 0.5, 0.6, 0.0), (2, 2, 0.7, 0.8, 0.9, 1.5)]


@pytest.fixture
def reference(tmp_path):
    return write_dump(tmp_path / "reference.dump", [(0, ROWS), (100, ROWS)])


def changed(rows, atom_id, column, delta):
    names = ("id", "type", "x", "y", "z", "vx")
    k = names.index(column)
    return [tuple(v + delta if (j == k and row[0] == atom_id) else v for j, v in enumerate(row))
            for row in rows]


def test_the_reader_sorts_by_id_and_keeps_the_columns_asked_for(reference):
    frames = read_frames(reference)
    assert [f.step for f in frames] == [0, 100]
    assert frames[0].ids.tolist() == [1, 2, 3]
    assert frames[0]["x"].tolist() == [0.4, 0.7, 0.1]
    assert frames[1].atom(3)["vx"] == -0.5
    last = read_frame(reference, columns=["vx"])
    assert last.step == 100 and list(last.columns) == ["id", "vx"]
    with pytest.raises(KeyError, match="no column \\['vy'\\]"):
        read_frame(reference, columns=["vy"])
    with pytest.raises(KeyError, match="no frame at step 50"):
        read_frame(reference, step=50)


def test_the_same_atoms_in_another_order_agree(tmp_path, reference):
    other = write_dump(tmp_path / "b.dump", [(0, ROWS[::-1]), (100, ROWS[1:] + ROWS[:1])])
    assert_dumps_close(reference, other, rtol=0, atol=0)
    assert_dumps_close(read_frame(reference), read_frame(other), rtol=0, atol=0)


def test_a_moved_atom_fails_naming_its_id_and_column(tmp_path, reference):
    moved = changed(ROWS, 2, "y", 1e-3)
    other = write_dump(tmp_path / "b.dump", [(0, ROWS), (100, moved)])
    with pytest.raises(AssertionError, match="step 100: worst atom id 2, column 'y'"):
        assert_dumps_close(reference, other, rtol=1e-6)
    # inside a wide enough tolerance it passes; outside the columns asked for too
    assert_dumps_close(reference, other, atol=2e-3)
    assert_dumps_close(reference, other, rtol=0, columns=["x", "z"])


def test_the_worst_of_several_differences_is_named(tmp_path, reference):
    rows = changed(changed(ROWS, 1, "x", 1e-5), 3, "vx", 1e-2)
    other = write_dump(tmp_path / "b.dump", [(0, rows), (100, rows)])
    with pytest.raises(AssertionError) as failure:
        assert_dumps_close(reference, other, rtol=1e-9)
    message = str(failure.value)
    assert "worst atom id 3, column 'vx'" in message and "2 value(s) out of tolerance" in message


def test_a_missing_atom_fails_naming_its_id(tmp_path, reference):
    other = write_dump(tmp_path / "b.dump", [(0, ROWS), (100, ROWS[:2])])
    with pytest.raises(AssertionError, match="atom id 2 is in a .* but not in b"):
        assert_dumps_close(reference, other)


def test_a_renamed_column_fails_naming_it(tmp_path, reference):
    names = ("id", "type", "x", "y", "z", "v_x")
    other = write_dump(tmp_path / "b.dump", [(0, ROWS), (100, ROWS)], names)
    with pytest.raises(AssertionError, match="alone has \\['vx'\\].*alone has \\['v_x'\\]"):
        assert_dumps_close(reference, other)
    with pytest.raises(AssertionError, match="column 'vx' is missing from b"):
        assert_dumps_close(reference, other, columns=["x", "vx"])


def test_other_steps_and_nan_fail(tmp_path, reference):
    other = write_dump(tmp_path / "b.dump", [(0, ROWS), (200, ROWS)])
    with pytest.raises(AssertionError, match="other steps: a \\[0, 100\\], b \\[0, 200\\]"):
        assert_dumps_close(reference, other)
    frame = read_frame(reference)
    broken = Frame(frame.step, {**frame.columns, "z": np.array([0.6, np.nan, 0.3])}, "hand-made")
    with pytest.raises(AssertionError, match="worst atom id 2, column 'z'"):
        assert_dumps_close(frame, broken, atol=1.0)


THERMO = """LIGGGHTS (Version LIGGGHTS-PUBLIC 3.8.0)
Setting up run ...
Step Atoms KinEng c_1 Volume
       0        3            0            0        0.001
     100        3   0.25000001            0        0.001
WARNING: a fix's message inside the table
     200        3         0.75            0        0.001
Loop time of 0.01 on 1 procs for 200 steps with 3 atoms
Step Atoms KinEng c_1 Volume
     200        3         0.75            0        0.001
     300        3            1          0.5        0.001
Loop time of 0.01 on 1 procs for 100 steps with 3 atoms
"""


def test_thermo_is_read_over_runs_and_compared_by_step(tmp_path):
    table = read_thermo(THERMO)
    assert table["Step"].tolist() == [0, 100, 200, 300]
    assert table["KinEng"].tolist() == [0, 0.25000001, 0.75, 1]
    (tmp_path / "log").write_text(THERMO)
    assert_thermo_close(table, tmp_path / "log", rtol=0)
    other = THERMO.replace("0.25000001", "0.25000002")
    assert_thermo_close(THERMO, other, rtol=1e-7)
    with pytest.raises(AssertionError, match="worst step 100, column 'KinEng'"):
        assert_thermo_close(THERMO, other, rtol=1e-9)
    with pytest.raises(AssertionError, match="column 'c_2' is missing from a"):
        assert_thermo_close(THERMO, other, columns=["c_2"])


def test_repeated_thermo_headers_are_numbered():
    """LIGGGHTS heads f_flow[1] and f_flow[2] both "flow"."""
    table = read_thermo("Step flow flow flow#2x\n0 1 2 3\n10 4 5 6\nLoop time of 1\n")
    assert list(table) == ["Step", "flow", "flow#2", "flow#2x"]
    assert table["flow#2"].tolist() == [2, 5]


def test_a_record_lacking_a_column_is_an_error_naming_it(tmp_path):
    record = tmp_path / "rate.txt"
    record.write_text("# step time grains\n100 0.01 3\n200 0.02 5\n")
    assert read_record(record)["grains"].tolist() == [3, 5]
    with pytest.raises(ValueError, match="missing columns \\['mass'\\]"):
        read_record(record, required=["mass"])


def falling_deck(steps=200):
    """Three grains falling onto a floor: a dump every 100 steps."""
    return f"""
{granular_setup()}
region box block -0.05 0.05 -0.05 0.05 0 0.1 units box
create_box 1 box
neighbor 0.002 bin
{hooke_materials(1e4, 2.857e3, gamman=100, gammat=50, mu=0.5)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep 1e-4
create_atoms 1 single 0.00 0 0.02 units box
create_atoms 1 single 0.02 0 0.03 units box
create_atoms 1 single -0.02 0 0.04 units box
set group all diameter 0.01 density 2500
fix floor all wall/gran model hooke/stiffness tangential history primitive type 1 zplane 0
fix gravity all gravity 9.81 vector 0 0 -1
fix integrate all nve/sphere
thermo_style custom step atoms ke
thermo 100
dump positions all custom 100 positions.dump id type x y z vx vy vz
run {steps}
"""


def test_a_run_and_its_rerun_on_two_ranks_agree(liggghts_binary, tmp_path):
    serial = run_deck(falling_deck(), tmp_path / "serial", binary=liggghts_binary)
    assert serial.frame("positions.dump").step == 200
    assert serial.thermo()["Step"].tolist() == [0, 100, 200]
    parallel = run_deck(falling_deck(), tmp_path / "parallel", nprocs=2, binary=liggghts_binary)
    assert_dumps_close(serial.path("positions.dump"), parallel.path("positions.dump"), rtol=1e-10)
    assert_thermo_close(serial.output, parallel.output, rtol=1e-10)


def test_a_failing_deck_raises_liggghts_error_line(liggghts_binary, tmp_path):
    with pytest.raises(LiggghtsError, match="^ERROR.*Unknown command: no_such_command") as failure:
        run_deck(falling_deck() + "no_such_command 1\n", tmp_path, binary=liggghts_binary,
                 variables={"unused": 1})
    assert failure.value.workdir == tmp_path
    with pytest.raises(FileNotFoundError, match="wrote no missing.dump"):
        run_deck(falling_deck(0), tmp_path / "again", binary=liggghts_binary).path("missing.dump")
