"""analysis.silo3d_archive: a finished run's records and the orifice
region of its dump, for doc/data. The archive gives the orifice averages
(but the contact pressure) and the flow rate of the full run directory,
every printed digit; an unfinished run is refused."""

import lzma

import numpy as np
import pytest

from analysis import silo3d_archive
from analysis import silo3d_rotating as silo
from analysis.lammps_io import read_dump, read_table
from test_silo3d_rotating_analysis import write_run


def test_the_archive_gives_the_full_run_s_orifice_averages_and_flow_rate(tmp_path):
    # the synthetic lattice fills the silo (r < 5 cm) up to z = 7.5 cm; the
    # orifice (D = 3 cm) with the kernel's reach (w = 4.95 mm, 4 w) lies
    # within r < 3.5 cm, z < 3 cm, inside the default cylinder r < 6 cm, z < 5 cm
    run = tmp_path / "run"
    write_run(run, 0.32, 0.03, 1, 20.0, fields=True)
    kept = tmp_path / "kept"
    assert silo3d_archive.main([str(run), str(kept)]) == 0
    for name in ("run.txt", "discharge.txt"):
        assert (kept / name).read_text() == (run / name).read_text()
    assert not (kept / "dump.contacts").exists()
    (kept / "dump.cg").write_text(lzma.open(kept / "dump.cg.xz", "rt").read())     # xz -dk
    full, cut = read_dump(run / "dump.cg"), read_dump(kept / "dump.cg")
    assert [step for step, _ in full] == [step for step, _ in cut]
    for (_, whole), (_, part) in zip(full, cut):
        inside = (whole["x"] ** 2 + whole["y"] ** 2 < 0.06 ** 2) & (whole["z"] < 0.05)
        assert 0 < inside.sum() < len(whole["z"]) and len(part["z"]) == inside.sum()
        assert part["z"].max() < 0.05
    out_full, out_kept = tmp_path / "full", tmp_path / "from_kept"
    for source, out in ((run, out_full), (kept, out_kept)):
        assert silo.main([str(source), "--out", str(out), "--map-frames", "2"]) == 0
    # every average but the contact pressure (no dump.contacts), to the table's digits
    whole, archived = read_table(out_full / "orifice.txt"), read_table(out_kept / "orifice.txt")
    assert list(whole) == list(archived)
    for column in whole:
        if column.startswith("p_c"):
            assert np.isfinite(whole[column]).all() and np.isnan(archived[column]).all()
        else:
            np.testing.assert_array_equal(archived[column], whole[column])
    assert (out_kept / "flow_rate_runs.md").read_text().split("\n")[1:] == \
        (out_full / "flow_rate_runs.md").read_text().split("\n")[1:]      # the title names the paths
    # the maps: the full run's, none from the archive (its frames lack the grains outside the cylinders)
    [label] = [path.name for path in (out_full / "runs").iterdir()]
    assert (out_full / "runs" / label / "fields.npz").exists()
    assert not (out_kept / "runs" / label / "fields.npz").exists()
    assert not list((out_kept / "runs" / label).glob("map_*.png"))


def test_a_cylinder_is_added_to_the_orifice_region_and_a_wide_orifice_is_warned_of(tmp_path, capsys):
    # D = 9 cm: the orifice cylinder with the kernel's reach is r < 6.48 cm
    # (4.5 + 4 * 0.495 cm), wider than the orifice region: a warning
    run = tmp_path / "run"
    write_run(run, 0.32, 0.09, 1, 20.0, fields=True)
    kept = tmp_path / "kept"
    assert silo3d_archive.main([str(run), str(kept), "--dump-cylinder", "0.015", "0.2"]) == 0
    assert "WARNING" in capsys.readouterr().out
    for (_, whole), (_, part) in zip(read_dump(run / "dump.cg"), read_dump_xz(kept / "dump.cg.xz")):
        r2 = whole["x"] ** 2 + whole["y"] ** 2
        inside = ((r2 < 0.06 ** 2) & (whole["z"] < 0.05)) | ((r2 < 0.015 ** 2) & (whole["z"] < 0.2))
        assert inside.sum() > ((r2 < 0.06 ** 2) & (whole["z"] < 0.05)).sum()      # the column adds grains
        np.testing.assert_array_equal(part["z"], whole["z"][inside])
    # and the analysis of that archive leaves out the orifice averages,
    # which would miss grains, rather than giving them wrong
    assert silo.main([str(kept), "--out", str(tmp_path / "out"), "--map-frames", "2"]) == 0
    assert "orifice averages from the whole frames only (they read r < 0.0648 m" in capsys.readouterr().out
    assert (tmp_path / "out" / "flow_rate_runs.txt").exists() and not (tmp_path / "out" / "orifice.txt").exists()
    # the orifice of 3 cm is inside: no warning
    write_run(tmp_path / "small", 0.32, 0.03, 1, 20.0)
    assert silo3d_archive.main([str(tmp_path / "small"), str(tmp_path / "small_kept")]) == 0
    assert "WARNING" not in capsys.readouterr().out
    # an archive goes into a new directory, not over another one or the run
    for target in (kept, run):
        assert silo3d_archive.main([str(run), str(target)]) == 2
        assert "not empty; an archive goes into a new directory" in capsys.readouterr().err


def read_dump_xz(path):
    unpacked = path.with_suffix("")
    unpacked.write_text(lzma.open(path, "rt").read())
    return read_dump(unpacked)


def test_an_unfinished_run_and_bad_cylinders_are_refused(tmp_path, capsys):
    run = tmp_path / "run"
    write_run(run, 0.32, 0.03, 1, 20.0, finished=False)
    assert silo3d_archive.main([str(run), str(tmp_path / "kept")]) == 2
    assert "unfinished (run.txt has no 'finished' line)" in capsys.readouterr().err
    assert not (tmp_path / "kept").exists()
    assert silo3d_archive.main([str(tmp_path / "nothing"), str(tmp_path / "kept")]) == 2
    assert "no run.txt" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        silo3d_archive.main([str(run), str(tmp_path / "kept"), "--dump-cylinder", "0", "0.05"])
    assert "the radius must be > 0 m" in capsys.readouterr().err
