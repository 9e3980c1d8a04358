"""analysis.campaign.silo3d_archive: a finished run reduced to the records that stay
in doc/data. The archive holds the run's records, and its orifice table
and fields from an analysis of the whole run; no dump, checkpoint or
restart. Restored, it gives the flow rate of the full run directory, every
printed digit, and its kept fields give the full run's maps; an unfinished
run is refused."""

import lzma

import numpy as np

from analysis.campaign import checkpoint
from analysis.campaign import silo3d_archive
from analysis.silo3d_rotating import analyse as silo
from analysis.silo3d_rotating.maps import mean_fields
from test_silo3d_rotating_analysis import write_run

REINJECT = "# step t n_out mass_out avalanche\n100 0.1 1 0.001 1\n200 0.2 3 0.003 3\n"


def test_the_archive_keeps_the_records_and_the_analysis_tables_but_no_dump(tmp_path):
    run = tmp_path / "run"
    write_run(run, 0.32, 0.03, 1, 20.0, fields=True)
    (run / "reinject.txt").write_text(REINJECT)
    (run / "checkpoint.100.restart").write_bytes(b"state")
    full = tmp_path / "full"
    assert silo.main([str(run), "--out", str(full), "--map-frames", "2"]) == 0
    [analysed] = (full / "runs").iterdir()
    kept = tmp_path / "kept"
    assert silo3d_archive.main([str(run), str(kept), "--analysis", str(full)]) == 0
    assert sorted(p.name for p in kept.iterdir()) == [
        "discharge.txt", "fields.npz", "orifice_timeseries.md", "reinject.txt.xz", "run.txt"]
    for name in ("run.txt", "discharge.txt"):
        assert (kept / name).read_text() == (run / name).read_text()
    assert lzma.open(kept / "reinject.txt.xz", "rt").read() == REINJECT
    assert (kept / "orifice_timeseries.md").read_text() == (analysed / "orifice_timeseries.md").read_text()
    # the fields as float32: the maps' means of the full run within 1e-7 of each field's scale;
    # the stress tensors left out, their traces (the pressures) kept
    whole, archived = mean_fields(analysed / "fields.npz"), mean_fields(kept / "fields.npz")
    assert "kinetic_stress" in whole["maps"] and "kinetic_pressure" in whole["maps"]
    assert sorted(archived["maps"]) == sorted(set(whole["maps"]) - set(silo3d_archive.DROPPED_FIELDS))
    assert "orientation" not in whole["maps"]
    for name, values in archived["maps"].items():
        values = whole["maps"][name]
        finite = np.isfinite(values)
        assert np.array_equal(finite, np.isfinite(archived["maps"][name]))
        assert np.max(np.abs(archived["maps"][name][finite] - values[finite])) <= 1e-7 * np.max(np.abs(values[finite]))
    np.testing.assert_array_equal(archived["z_edges"], whole["z_edges"])
    # restored, the archive gives the full run's flow rate to the table's digits
    restored = tmp_path / "restored"
    checkpoint.restore(kept, restored)
    assert (restored / "reinject.txt").read_text() == REINJECT
    out_kept = tmp_path / "from_kept"
    assert silo.main([str(restored), "--out", str(out_kept), "--map-frames", "2"]) == 0
    assert (out_kept / "flow_rate_runs.md").read_text().split("\n")[1:] == \
        (full / "flow_rate_runs.md").read_text().split("\n")[1:]      # the title names the paths
    assert not (out_kept / "runs" / analysed.name / "fields.npz").exists()
    # without the maps: the same records and orifice table, no fields.npz
    lean = tmp_path / "lean"
    assert silo3d_archive.main([str(run), str(lean), "--analysis", str(full), "--no-fields"]) == 0
    assert sorted(p.name for p in lean.iterdir()) == [
        "discharge.txt", "orifice_timeseries.md", "reinject.txt.xz", "run.txt"]
    assert (lean / "orifice_timeseries.md").read_text() == (analysed / "orifice_timeseries.md").read_text()


def test_without_an_analysis_the_archive_holds_the_records_only(tmp_path, capsys):
    run = tmp_path / "run"
    write_run(run, 0.32, 0.03, 1, 20.0, fields=True)
    kept = tmp_path / "kept"
    assert silo3d_archive.main([str(run), str(kept)]) == 0
    assert sorted(p.name for p in kept.iterdir()) == ["discharge.txt", "run.txt"]
    assert "no dumps, checkpoints or restarts" in capsys.readouterr().out
    # an analysis of another run is refused, as is an archive over another one or the run
    other = tmp_path / "other"
    write_run(other, 0.64, 0.03, 1, 20.0)
    assert silo.main([str(other), "--out", str(tmp_path / "out_other"), "--no-fields"]) == 0
    assert silo3d_archive.main([str(run), str(tmp_path / "k2"), "--analysis", str(tmp_path / "out_other")]) == 2
    assert "no runs/f0.32_D30mm_seed1: not an analysis of" in capsys.readouterr().err
    assert not (tmp_path / "k2").exists()
    for target in (kept, run):
        assert silo3d_archive.main([str(run), str(target)]) == 2
        assert "not empty; an archive goes into a new directory" in capsys.readouterr().err


def test_an_unfinished_run_is_refused(tmp_path, capsys):
    run = tmp_path / "run"
    write_run(run, 0.32, 0.03, 1, 20.0, finished=False)
    assert silo3d_archive.main([str(run), str(tmp_path / "kept")]) == 2
    assert "unfinished (run.txt has no 'finished' line)" in capsys.readouterr().err
    assert not (tmp_path / "kept").exists()
    assert silo3d_archive.main([str(tmp_path / "nothing"), str(tmp_path / "kept")]) == 2
    assert "no run.txt" in capsys.readouterr().err
