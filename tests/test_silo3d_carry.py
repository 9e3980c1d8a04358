"""analysis.campaign.silo3d_carry: a campaign carried from one machine to the next
through a store directory (finished runs, reduced) and a carry directory
(unfinished runs' checkpoints). On hand-made run directories: the finished
run is stored as its records, orifice table, fields and cost, without a
dump or checkpoint, and comes back finished; the unfinished one is carried
outside the store and resumes from the same checkpoint as before; a run
that finishes after being carried is archived and its carried checkpoint
removed."""

import lzma
import os
import shutil
import subprocess

import numpy as np

from analysis.campaign import checkpoint
from analysis.campaign import silo3d_archive
from analysis.campaign import silo3d_carry
from analysis.campaign import silo3d_status
from analysis.silo3d_rotating import analyse as silo
from analysis.common.lammps_io import read_dump
from analysis.silo3d_rotating.records import read_run_info
from test_silo3d_rotating_analysis import DT, T_OPEN, write_run

SCREEN = "Loop time of 360 on 1 procs for 500 steps with 100 atoms\n"


def make_campaign(directory):
    """A finished run at 0.32 Hz and, at rest, one stopped after its
    checkpoint at 2 s of discharge (records and dump past it)."""
    finished, stopped = directory / "D0.03_f0.32_s11", directory / "D0.03_f0_s11"
    write_run(finished, 0.32, 0.03, 11, 20.0, duration=3.0, fields=True)
    write_run(stopped, 0.0, 0.03, 11, 20.0, duration=3.0, fields=True, finished=False)
    step_open = round(T_OPEN / DT)
    with open(stopped / "run.txt", "a") as run_txt:
        run_txt.write(f"step_open {step_open}\ndischarge_time 8.0\n")
    checkpoint_step = step_open + 2000
    (stopped / "checkpoints.txt").write_text(f"{checkpoint_step} checkpoint.{checkpoint_step}.restart\n")
    (stopped / f"checkpoint.{checkpoint_step}.restart").write_bytes(bytes(range(256)) * 8)
    for run in (finished, stopped):
        (run / "screen.txt").write_text("setting up\n" + SCREEN)
    return finished, stopped, checkpoint_step


def assert_orifice_region_and_axis_column(whole, carried, before=None):
    """The carried dump holds the frames of the whole one (those before the
    step `before`), each with the grains of the orifice region and of the
    column over the axis, and no other."""
    whole = [(step, frame) for step, frame in read_dump(whole) if before is None or step < before]
    carried = read_dump(carried)
    assert [s for s, _ in whole] == [s for s, _ in carried] and len(whole) >= 2
    for (_, frame), (_, part) in zip(whole, carried):
        r2 = frame["x"] ** 2 + frame["y"] ** 2
        orifice, column = (r2 < 0.06 ** 2) & (frame["z"] < 0.05), (r2 < 0.025 ** 2) & (frame["z"] < 0.2)
        assert (column & ~orifice).any() and not (orifice | column).all()
        assert list(part["id"]) == list(frame["id"][orifice | column])


def assert_no_dump_or_checkpoint(directory):
    names = [path.name for path in directory.rglob("*")]
    assert not [n for n in names if n.startswith(("dump", "checkpoint")) or ".restart" in n], names


def test_a_carried_campaign_skips_its_finished_run_and_resumes_the_other_where_it_was(tmp_path):
    finished, stopped, checkpoint_step = make_campaign(tmp_path / "machine1")
    (finished / "reinject.txt").write_text("# step t n_out mass_out avalanche\n100 0.1 1 0.001 1\n")
    analysis = tmp_path / "machine1" / "analysis"       # rods_fig2c.sh's analysis of the campaign
    assert silo.main([str(finished), "--out", str(analysis), "--map-frames", "2"]) == 0
    [analysed] = (analysis / "runs").iterdir()
    store = tmp_path / "store"
    assert silo3d_carry.main(["keep", str(tmp_path / "machine1"), str(store),
                              "--dump-cylinder", "0.025", "0.2"]) == 0
    # the finished run: its records, orifice table, fields (float32) and cost; no dump
    archived = store / finished.name
    assert sorted(p.name for p in archived.iterdir()) == [
        "discharge.txt", "fields.npz", "orifice_timeseries.md", "reinject.txt.xz", "run.txt", "screen.txt.xz"]
    assert (archived / "orifice_timeseries.md").read_text() == (analysed / "orifice_timeseries.md").read_text()
    assert lzma.open(archived / "reinject.txt.xz", "rt").read() == (finished / "reinject.txt").read_text()
    with np.load(analysed / "fields.npz") as whole, np.load(archived / "fields.npz") as kept:
        dropped = [key for key in whole.files if key.rsplit("_", 1)[0] in silo3d_archive.DROPPED_FIELDS]
        assert "kinetic_stress_0" in dropped
        assert sorted(kept.files) == sorted(set(whole.files) - set(dropped))
        for key in kept.files:
            np.testing.assert_allclose(kept[key], whole[key], rtol=1e-6, atol=1e-30)
        assert kept["packing_fraction_0"].dtype == np.float32 and kept["r"].dtype == whole["r"].dtype
    assert_no_dump_or_checkpoint(store)
    # the unfinished run: carried outside the store, beside it here (no git work tree)
    carried = tmp_path / "carry" / "store" / stopped.name
    assert silo3d_carry.carry_dir(store) == tmp_path / "carry" / "store"
    assert (carried / f"checkpoint.{checkpoint_step}.restart.xz").exists()
    assert not (store / stopped.name).exists() and not (store / "kept").exists()
    assert not (tmp_path / "carry" / "store" / finished.name).exists()

    again = tmp_path / "machine2"
    assert silo3d_carry.main(["restore", str(store), str(again)]) == 0
    # the finished run: run.sh's mark, where it came from, the records as they were
    assert (again / finished.name / "finished").exists()
    assert (again / finished.name / "archived_in").read_text().strip() == str(archived.resolve())
    assert (again / finished.name / "discharge.txt").read_text() == (finished / "discharge.txt").read_text()
    assert (again / finished.name / "reinject.txt").read_text() == (finished / "reinject.txt").read_text()
    assert not (again / finished.name / "dump.cg").exists()
    # the unfinished run resumes from the same step and time, with its own copy of the checkpoint
    expected, got = checkpoint.resume_variables(stopped), checkpoint.resume_variables(again / stopped.name)
    assert got.pop("checkpoint") == str((again / stopped.name / f"checkpoint.{checkpoint_step}.restart").resolve())
    expected.pop("checkpoint")
    assert got == expected and got["t_resume"] == repr(T_OPEN + 2000 * DT)
    assert_orifice_region_and_axis_column(stopped / "dump.cg", again / stopped.name / "dump.cg",
                                          before=checkpoint_step)
    # both keep their cost: the campaign's table reads the same loop hours
    for run in (finished, stopped):
        assert silo3d_status.run_status(again / run.name)["cpu_hours"] == 0.1

    # keeping the second machine's campaign: the restored archive is left
    # alone, the unfinished run carried again; once it has finished, it is
    # archived (without an analysis of it: records only) and the carry
    # directory, then empty, removed
    mtime = (archived / "discharge.txt").stat().st_mtime_ns
    assert silo3d_carry.keep(again, store) == [
        f"{stopped.name}: unfinished, kept at its checkpoint of step {checkpoint_step} (2.00 s of discharge) "
        f"in {tmp_path / 'carry' / 'store'}"]
    assert (archived / "discharge.txt").stat().st_mtime_ns == mtime
    with open(again / stopped.name / "run.txt", "a") as run_txt:
        run_txt.write("finished 8.5\n")
    [line] = silo3d_carry.keep(again, store)
    assert line.startswith(f"{stopped.name}: finished, archived") and "no orifice table" in line
    assert not (tmp_path / "carry").exists()
    assert sorted(p.name for p in (store / stopped.name).iterdir()) == ["discharge.txt", "run.txt", "screen.txt.xz"]
    assert lzma.open(store / stopped.name / "screen.txt.xz", "rt").read() == "setting up\n" + SCREEN
    assert_no_dump_or_checkpoint(store)


def test_the_carry_directory_is_at_the_top_of_the_store_s_work_tree(tmp_path):
    (tmp_path / "repo" / ".git").mkdir(parents=True)
    store = tmp_path / "repo" / "doc" / "data" / "campaign"
    assert silo3d_carry.carry_dir(store) == tmp_path / "repo" / "carry" / "campaign"


def test_a_carried_run_that_is_archived_too_is_not_restored_and_bad_stores_are_refused(tmp_path, capsys):
    finished, stopped, _ = make_campaign(tmp_path / "machine1")
    store = tmp_path / "store"
    silo3d_carry.keep(tmp_path / "machine1", store)
    # an archive given twice, and an unfinished "archive": refused, nothing restored
    assert silo3d_carry.main(["restore", str(store), str(tmp_path / "a"), "--also", str(store / finished.name)]) == 2
    assert "two archives of the same run: D0.03_f0.32_s11" in capsys.readouterr().err
    assert silo3d_carry.main(["restore", str(store), str(tmp_path / "b"), "--also", str(stopped)]) == 2
    assert "not a finished run's archive" in capsys.readouterr().err
    assert not list((tmp_path / "a").glob("D*")) and not list((tmp_path / "b").glob("D*"))
    # the same run archived elsewhere (--also) wins over its carried checkpoint
    elsewhere = tmp_path / "elsewhere" / stopped.name
    write_run(elsewhere, 0.0, 0.03, 11, 20.0, duration=3.0)
    lines = silo3d_carry.restore(store, tmp_path / "c", [elsewhere])
    assert f"{stopped.name}: carried checkpoint ignored, the run is archived" in lines
    assert (tmp_path / "c" / stopped.name / "finished").exists()
    assert not (tmp_path / "c" / stopped.name / "checkpoints.txt").exists()
    # a run directory already there is left as it is
    assert f"{finished.name}: in {tmp_path / 'c'} already, left as it is" in silo3d_carry.restore(store, tmp_path / "c")
    assert silo3d_carry.main(["keep", str(tmp_path / "nowhere"), str(store)]) == 2
    assert silo3d_carry.main(["keep", str(tmp_path / "machine1"), str(store), "--dump-cylinder", "0", "1"]) == 2


def test_packings_are_carried_settled_or_at_their_last_settling_checkpoint(tmp_path):
    """A settled packing goes to carry/packings in the form run.sh's
    PACKINGS reads (the restart, xz, and its run.txt); a settling cut short
    goes at its last checkpoint and comes back as a settling that run.sh's
    SETTLE_CHECKPOINT resumes from that step; drop-packings removes them."""
    machine1, store, carry = tmp_path / "machine1", tmp_path / "store", tmp_path / "carry"
    settled, settling = machine1 / "packing_s11", machine1 / "packing_s13"
    settled.mkdir(parents=True)
    settling.mkdir()
    restart = bytes(range(256)) * 16
    (settled / "packing.restart").write_bytes(restart)
    (settled / "run.txt").write_text("shape rod\naspect 4.0\nseed 11\n")
    (settled / "screen.txt").write_text(SCREEN)
    (settled / "finished").touch()
    (settling / "checkpoints.txt").write_text("1000 checkpoint.1000.restart\n2000 checkpoint.2000.restart\n")
    (settling / "checkpoint.1000.restart").write_bytes(b"first")
    (settling / "checkpoint.2000.restart").write_bytes(b"second")
    (settling / "screen.txt").write_text("settling\n")
    assert silo3d_carry.main(["keep", str(machine1), str(store), "--carry", str(carry)]) == 0
    kept = carry / "packings"
    assert sorted(p.name for p in kept.iterdir()) == [
        "packing_s11.restart.xz", "packing_s11_run.txt", "packing_s11_screen.txt"]
    assert lzma.open(kept / "packing_s11.restart.xz").read() == restart
    assert (kept / "packing_s11_run.txt").read_text() == "shape rod\naspect 4.0\nseed 11\n"
    assert sorted(p.name for p in (carry / "settling_s13").iterdir()) == [
        "checkpoint.2000.restart.xz", "checkpoints.txt", "screen.txt.xz"]

    machine2 = tmp_path / "machine2"
    assert silo3d_carry.main(["restore", str(store), str(machine2), "--carry", str(carry)]) == 0
    resumed = machine2 / "packing_s13"
    assert checkpoint.settle_resume_variables(resumed) == {
        "settle_resume": 1, "checkpoint": str((resumed / "checkpoint.2000.restart").resolve()),
        "settled_steps": 2000}
    assert (resumed / "checkpoint.2000.restart").read_bytes() == b"second"
    assert not (machine2 / "packing_s11").exists()     # run.sh reads it from carry/packings

    # the settling finishes on machine 2: carried as a packing, its checkpoint dropped
    (resumed / "packing.restart").write_bytes(b"settled 13")
    (resumed / "run.txt").write_text("seed 13\n")
    (resumed / "finished").touch()
    assert silo3d_carry.main(["keep", str(machine2), str(store), "--carry", str(carry)]) == 0
    assert lzma.open(kept / "packing_s13.restart.xz").read() == b"settled 13"
    assert not (carry / "settling_s13").exists()
    assert silo3d_carry.main(["drop-packings", str(store), "--carry", str(carry)]) == 0
    assert not carry.exists()


def test_a_finished_run_is_to_analyse_until_it_is_analysed_since_it_finished_or_archived(tmp_path, capsys):
    """`to-analyse` (rods_fig2c.sh reads no dump twice): the finished run
    until analysis.silo3d_rotating has written its orifice table, again
    once it has finished anew, never once archived or restored from an
    archive; the unfinished run never."""
    finished, _, _ = make_campaign(tmp_path / "machine1")
    runs, store, analysis = tmp_path / "machine1", tmp_path / "store", tmp_path / "machine1" / "analysis"
    assert silo3d_carry.to_analyse(runs, store) == [finished]
    assert silo.main([str(finished), "--out", str(analysis), "--map-frames", "2"]) == 0
    [table] = analysis.glob("runs/*/orifice_timeseries.txt")
    assert silo3d_carry.to_analyse(runs, store) == []
    finished_at = table.stat().st_mtime + 10                  # the run finished again after its analysis
    for name in ("run.txt", "finished"):
        if (finished / name).exists():
            os.utime(finished / name, (finished_at, finished_at))
    assert silo3d_carry.to_analyse(runs, store) == [finished]
    assert silo3d_carry.to_analyse(runs, store, tmp_path / "elsewhere") == [finished]
    capsys.readouterr()
    assert silo3d_carry.main(["to-analyse", str(runs), str(store)]) == 0
    assert capsys.readouterr().out == f"{finished}\n"
    silo3d_carry.keep(runs, store)
    assert silo3d_carry.to_analyse(runs, store) == []         # archived
    assert silo3d_carry.main(["restore", str(store), str(tmp_path / "machine2")]) == 0
    shutil.rmtree(store)                                      # the mark alone says it was archived
    assert silo3d_carry.to_analyse(tmp_path / "machine2", store) == []


def test_a_finished_run_made_longer_is_carried_and_then_replaces_its_archive(tmp_path):
    """run.sh made a finished, archived run longer: while it goes on it is
    carried, and the next machine resumes it rather than taking the shorter
    archive for done; once finished it is to analyse again and its archive
    is replaced."""
    machine1, machine2, store, carry = (tmp_path / name for name in ("machine1", "machine2", "store", "carry"))
    finished, _, _ = make_campaign(machine1)
    with open(finished / "run.txt", "a") as run_txt:
        run_txt.write("discharge_time 3.0\n")
    silo3d_carry.keep(machine1, store, carry=carry)
    assert silo3d_carry.discharge_time(store / finished.name) == 3.0
    # resumed to 6 s from a checkpoint at 2 s (run.sh: `finished` line cut, the new end written)
    lines = (finished / "run.txt").read_text().splitlines()
    step_open = round(T_OPEN / DT)
    (finished / "run.txt").write_text("\n".join(l for l in lines if not l.startswith("finished"))
                                      + f"\nstep_open {step_open}\ndischarge_time 6.0\n")
    (finished / "finished").unlink(missing_ok=True)
    step = step_open + 2000
    (finished / "checkpoints.txt").write_text(f"{step} checkpoint.{step}.restart\n")
    (finished / f"checkpoint.{step}.restart").write_bytes(b"state at 2 s")
    lines = silo3d_carry.keep(machine1, store, carry=carry)
    assert any(line.startswith(f"{finished.name}: unfinished, kept at its checkpoint of step {step}") for line in lines)
    assert silo3d_carry.discharge_time(store / finished.name) == 3.0      # the archive stays until it ends

    lines = silo3d_carry.restore(store, machine2, carry=carry)
    assert f"{finished.name}: unfinished, restored at its checkpoint of step {step}, made longer than its archive" \
        in lines
    resumed = machine2 / finished.name
    assert not (resumed / silo3d_carry.MARK).exists() and not (resumed / "finished").exists()
    assert checkpoint.last_checkpoint(resumed)[0] == step
    # ... and it finishes at 6 s
    shutil.rmtree(resumed)
    write_run(resumed, 0.32, 0.03, 11, 20.0, duration=6.0)
    with open(resumed / "run.txt", "a") as run_txt:
        run_txt.write("discharge_time 6.0\n")
    assert silo3d_carry.to_analyse(machine2, store) == [resumed]
    lines = silo3d_carry.keep(machine2, store, carry=carry)
    assert any(line.startswith(f"{finished.name}: finished, archived (") and "in place of the shorter archive" in line
               for line in lines), lines
    assert silo3d_carry.discharge_time(store / finished.name) == 6.0
    assert [p.name for p in store.iterdir()] == [finished.name]      # no .part, no .shorter left
    assert not (carry / finished.name).exists()
    assert silo3d_carry.keep(machine2, store, carry=carry)[0] == f"{finished.name}: archived before"


def git(top, *words):
    environment = {**os.environ, "GIT_AUTHOR_NAME": "t", "GIT_AUTHOR_EMAIL": "t@t", "GIT_COMMITTER_NAME": "t",
                   "GIT_COMMITTER_EMAIL": "t@t"}
    subprocess.run(["git", "-C", str(top), *words], check=True, capture_output=True, env=environment)


def test_an_archived_run_shorter_than_the_protocol_reopens_at_its_last_checkpoint_in_the_history(tmp_path):
    """A protocol made longer after its runs finished: on a new machine a
    finished run comes back from its archive, and `reopen` puts it back at
    its last checkpoint carried in the git history (the carry folder was
    removed when it finished), from where run.sh makes it longer. A run
    never carried is emptied, for run.sh to run it again from its packing,
    its archive left in the store; one as long as the protocol stays as it
    is. Called again, `reopen` finds nothing more to do."""
    top = tmp_path / "repo"
    store = top / "doc" / "data" / "campaign"
    git(tmp_path, "init", "-q", str(top))
    finished, stopped, step = make_campaign(tmp_path / "machine1")    # stopped: discharge_time 8.0
    with open(finished / "run.txt", "a") as run_txt:
        run_txt.write("discharge_time 3.0\n")
    silo3d_carry.keep(tmp_path / "machine1", store)
    git(top, "add", "-A")
    git(top, "commit", "-qm", "carried at 2 s")
    # the stopped run finishes (8 s) and is archived; its carried folder goes
    shutil.rmtree(stopped)
    write_run(stopped, 0.0, 0.03, 11, 20.0, duration=8.0)
    with open(stopped / "run.txt", "a") as run_txt:
        run_txt.write("discharge_time 8.0\n")
    silo3d_carry.keep(tmp_path / "machine1", store)
    assert not (top / "carry" / "campaign" / stopped.name).exists()
    git(top, "add", "-A")
    git(top, "commit", "-qm", "archived")

    machine2 = tmp_path / "machine2"
    silo3d_carry.restore(store, machine2)
    lines = silo3d_carry.reopen(machine2, store, {0.0: 10.0, 0.32: 10.0})
    reopened = machine2 / stopped.name
    assert lines[0] == f"{finished.name}: 3 s, shorter than 10 s, and no carried checkpoint in the history: " \
                       "emptied, to run again from its packing"
    assert lines[1].startswith(f"{stopped.name}: 8 s, shorter than 10 s: reopened at its checkpoint of step {step}, "
                               "carried in ") and len(lines) == 2
    assert not (reopened / silo3d_carry.MARK).exists() and "finished" not in read_run_info(reopened)
    assert checkpoint.last_checkpoint(reopened)[0] == step
    assert checkpoint.resume_variables(reopened)["step_open_resumed"] == round(T_OPEN / DT)
    never_carried = machine2 / finished.name                 # run.sh runs it again from its packing
    assert never_carried.is_dir() and not any(never_carried.iterdir())
    assert (store / finished.name / "run.txt").exists()                        # its archive stays
    assert silo3d_carry.reopen(machine2, store, {0.0: 10.0, 0.32: 10.0}) == []
    # as long as the protocol: nothing to do; outside a git work tree: nothing found
    silo3d_carry.restore(store, tmp_path / "machine3")
    assert silo3d_carry.reopen(tmp_path / "machine3", store, {0.0: 8.0, 0.32: 3.0}) == []
    assert silo3d_carry.carried_in_history(tmp_path / "elsewhere" / "carry" / "campaign" / stopped.name) is None
