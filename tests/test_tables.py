"""analysis.common.tables, the one reader of `#`-header tables, on
hand-written files: both shapes follow the same rules, and the shapes its
callers depend on (columns of floats; rows with the model as text; rows all
text for the pile driver's records)."""

import lzma
from pathlib import Path

import numpy as np
import pytest

from analysis.common.tables import read_rows, read_table

HEADER = "# model L w seed h\n"


def test_columns_of_floats_with_a_cut_line_skipped_and_a_repeated_header():
    path = _write("discharge.txt", "# step t n_out\n0 0.0 0\n\n# step t n_out\n50 0.5 3\n100 1.0")
    table = read_table(path, required=("t",))
    assert sorted(table) == ["n_out", "step", "t"]
    np.testing.assert_array_equal(table["step"], [0, 50])
    assert table["t"].dtype == float


def test_a_header_without_rows_gives_empty_columns():
    table = read_table(_write("empty.txt", "# clog t\n"))
    assert table["clog"].size == 0 and table["t"].size == 0


def test_xz_tables_read_as_the_plain_ones(tmp_path):
    text = "# a b\n1 2\n3 4\n"
    packed = tmp_path / "t.txt.xz"
    with lzma.open(packed, "wt") as handle:
        handle.write(text)
    plain = _write("t.txt", text)
    assert {k: v.tolist() for k, v in read_table(packed).items()} == \
        {k: v.tolist() for k, v in read_table(plain).items()}
    assert read_rows(packed) == read_rows(plain)


def test_errors_name_the_file():
    with pytest.raises(ValueError, match="no '#' header"):
        read_table(_write("bare.txt", "1 2\n"))
    with pytest.raises(ValueError, match="no '#' header"):
        read_rows(_write("bare_rows.txt", "1 2\n# a b\n"))
    with pytest.raises(ValueError, match=r"missing columns \['h'\]"):
        read_table(_write("short.txt", "# a b\n1 2\n"), required=("a", "h"))
    with pytest.raises(ValueError, match=r"long.txt:3: 3 fields, the header names 2"):
        read_table(_write("long.txt", "# a b\n1 2\n1 2 3\n"))


def test_rows_keep_the_model_and_words_as_text_and_numbers_as_floats():
    path = _write("d.txt", HEADER + "fixed 50 4.2 15485863 3.5\n" + HEADER + "none 20 1 15485867 n/a\n"
                  + "overlap 20 1 1548")
    rows = read_rows(path)
    assert rows == [{"model": "fixed", "L": 50.0, "w": 4.2, "seed": 15485863.0, "h": 3.5},
                    {"model": "none", "L": 20.0, "w": 1.0, "seed": 15485867.0, "h": "n/a"}]


def test_text_rows_are_the_fields_as_written_and_a_missing_file_may_have_none(tmp_path):
    path = _write("piles.txt", HEADER + "fixed 50 4.20 15485863 3.5\n")
    assert read_rows(path, text=True) == [{"model": "fixed", "L": "50", "w": "4.20", "seed": "15485863",
                                           "h": "3.5"}]
    assert read_rows(tmp_path / "none.txt", text=True, missing_ok=True) == []
    with pytest.raises(FileNotFoundError):
        read_rows(tmp_path / "none.txt")


@pytest.fixture(autouse=True)
def _here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def _write(name, text):
    """A file of the test's own folder (its working directory)."""
    path = Path(name)
    path.write_text(text)
    return path
