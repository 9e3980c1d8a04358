"""Checkpoints of the rotating-bottom silo's discharge and resuming from
them (inputs/run_until_done.in, the deck's `resume`, analysis.campaign.checkpoint,
examples/silo3d_rotating/run.sh).

- On the engine: a quick run with reinjection and dumps, checkpointed
  every 0.1 s, is cut back to its first checkpoint (as an interruption
  after it would leave it) and resumed: the records it ends with are those
  of the uninterrupted run, every count and mass to the last digit and the
  times to round-off.
- The driver: run.sh killed once its run has a checkpoint (or its
  LIGGGHTS stopped by SIGTERM, which LIGGGHTS ends with status 0) and
  started again finishes the run from there, with records that have no gap
  and no repeated row or frame, and removes the checkpoint files.
- The cutting and the resume variables on hand-made files.
"""

import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from analysis.campaign import checkpoint
from analysis.campaign import silo3d_carry
from analysis.silo3d_rotating import analyse as silo
from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_table
from analysis.silo3d_rotating.records import DumpCut, read_dump_cut, read_run_info
from conftest import LIGGGHTS, ROOT, has_mpirun, run_liggghts

DECK = ROOT / "inputs" / "silo3d_rotating" / "in.silo3d_rotating"
QUICK = {"inputs": ROOT / "inputs", "quick": 1, "reinject": 1, "f": 0.32, "dump_every_time": 0.05,
         "checkpoint_every_time": 0.1, "discharge_time": 0.3}


def run_deck(workdir, variables, nprocs=1):
    return run_liggghts(f"include {DECK}\n", workdir, nprocs=nprocs, variables=variables)


def assert_same_row_records(whole_dir, resumed_dir):
    """discharge.txt and reinject.txt of a resumed run are the uninterrupted
    run's: every count and mass to the last digit, the times to round-off."""
    for name in ("discharge.txt", "reinject.txt"):
        whole, resumed = read_table(whole_dir / name), read_table(resumed_dir / name)
        assert list(whole) == list(resumed) and len(whole["step"]) == len(resumed["step"]) > 10
        for column in whole:
            if column == "t":
                np.testing.assert_allclose(resumed[column], whole[column], rtol=0, atol=1e-12)
            else:
                np.testing.assert_array_equal(resumed[column], whole[column])


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory, liggghts_binary):
    workdir = tmp_path_factory.mktemp("uninterrupted")
    run_deck(workdir, QUICK)
    return workdir


def test_a_run_cut_back_to_its_checkpoint_and_resumed_ends_as_the_uninterrupted_one(uninterrupted, tmp_path):
    listed = (uninterrupted / "checkpoints.txt").read_text().split("\n")
    assert len([line for line in listed if line]) == 2     # after 0.1 and 0.2 s, not at the end
    # an interruption after the first checkpoint: the copy keeps every
    # record written after it, which the cut must remove
    interrupted = tmp_path / "interrupted"
    shutil.copytree(uninterrupted, interrupted)
    (interrupted / "checkpoints.txt").write_text(listed[0] + "\n")
    variables = checkpoint.resume_variables(interrupted)
    first_step = int(listed[0].split()[0])
    assert variables["checkpoint"] == str((interrupted / f"checkpoint.{first_step}.restart").resolve())
    run_deck(interrupted, {**QUICK, **variables})

    assert_same_row_records(uninterrupted, interrupted)
    assert (interrupted / "dump.cg").read_text() == (uninterrupted / "dump.cg").read_text()
    assert [step for step, _ in read_dump(interrupted / "dump.contacts")] == \
        [step for step, _ in read_dump(uninterrupted / "dump.contacts")]
    finished = [line for line in (interrupted / "run.txt").read_text().splitlines() if line.startswith("finished")]
    assert len(finished) == 1


def test_a_run_resumed_with_a_longer_discharge_time_goes_on_to_it_and_says_so(uninterrupted, tmp_path):
    # a campaign extended from its last checkpoint: the resumed run must
    # run to the new end, and run.txt must give the new discharge_time
    # (its last line of the key) rather than the start's
    listed = (uninterrupted / "checkpoints.txt").read_text().split("\n")
    extended = tmp_path / "extended"
    shutil.copytree(uninterrupted, extended)
    (extended / "checkpoints.txt").write_text(listed[1] + "\n")
    variables = checkpoint.resume_variables(extended)
    run_deck(extended, {**QUICK, **variables, "discharge_time": 0.45})
    run = read_run_info(extended)
    assert run["discharge_time"] == 0.45 and read_run_info(uninterrupted)["discharge_time"] == 0.3
    t = read_table(extended / "discharge.txt")["t"]
    assert t[-1] - run["t_open"] == pytest.approx(0.45, abs=0.01)
    whole = read_table(uninterrupted / "discharge.txt")
    np.testing.assert_array_equal(read_table(extended / "discharge.txt")["n_out"][:len(whole["n_out"])],
                                  whole["n_out"])      # the same run up to the old end


def test_a_run_carried_to_another_machine_at_its_checkpoint_ends_as_the_uninterrupted_one(uninterrupted, tmp_path):
    # analysis.campaign.silo3d_carry: a run stopped after its first checkpoint is
    # kept in a store and restored into another directory (another
    # machine), whose deck resumes it: the records are the uninterrupted
    # run's, and the dump too from the checkpoint on (before it, the kept
    # cylinder's grains)
    listed = (uninterrupted / "checkpoints.txt").read_text().split("\n")
    stopped = tmp_path / "machine1" / "D0.05_f0.32_s1"
    shutil.copytree(uninterrupted, stopped)
    (stopped / "checkpoints.txt").write_text(listed[0] + "\n")
    run_txt = stopped / "run.txt"
    run_txt.write_text("".join(line for line in run_txt.read_text().splitlines(keepends=True)
                               if not line.startswith("finished")))
    [line] = silo3d_carry.keep(tmp_path / "machine1", tmp_path / "store", [(0.01, 1.0)])
    assert "unfinished, kept at its checkpoint" in line
    shutil.rmtree(tmp_path / "machine1")
    silo3d_carry.restore(tmp_path / "store", tmp_path / "machine2")
    carried = tmp_path / "machine2" / "D0.05_f0.32_s1"
    run_deck(carried, {**QUICK, **checkpoint.resume_variables(carried)})

    assert_same_row_records(uninterrupted, carried)
    first_step = int(listed[0].split()[0])
    whole, resumed = read_dump(uninterrupted / "dump.cg"), read_dump(carried / "dump.cg")
    assert [step for step, _ in whole] == [step for step, _ in resumed]
    for (step, frame), (_, part) in zip(whole, resumed):
        r2 = frame["x"] ** 2 + frame["y"] ** 2
        kept = ((r2 < 0.06 ** 2) & (frame["z"] < 0.05)) | (r2 < 0.01 ** 2)
        expected = frame["id"] if step >= first_step else frame["id"][kept]
        assert list(part["id"]) == list(expected)
        if step < first_step:
            assert 0 < kept.sum() < len(kept)
    assert "finished" in read_run_info(carried)

    # the analysis of the carried run: the orifice averages are the
    # uninterrupted run's (but the contact pressure, whose contact dump
    # starts at the checkpoint); its maps are made of the frames from the
    # checkpoint on, whose first window (before it) is empty
    options = ["--transient", "0", "--map-times", "0.05", "0.25", "--map-width", "0.1", "--map-frames", "2"]
    for source, out in ((uninterrupted, tmp_path / "out_whole"), (carried, tmp_path / "out_carried")):
        assert silo.main([str(source), "--out", str(out), *options]) == 0
    whole, resumed = read_table(tmp_path / "out_whole" / "orifice.txt"), read_table(tmp_path / "out_carried" / "orifice.txt")
    assert np.isfinite(whole["p_c"]).all()
    for column in whole:
        if column.startswith("p_c"):
            assert np.isnan(resumed[column]).all()
        else:
            np.testing.assert_array_equal(resumed[column], whole[column])
    [label] = [path.name for path in (tmp_path / "out_whole" / "runs").iterdir()]
    with np.load(tmp_path / "out_whole" / "runs" / label / "fields.npz") as maps:
        assert list(maps["frames"]) == [2, 2]
        later = maps["packing_fraction_1"]
    with np.load(tmp_path / "out_carried" / "runs" / label / "fields.npz") as maps:
        assert list(maps["frames"]) == [0, 2] and "packing_fraction_0" not in maps.files
        np.testing.assert_allclose(maps["packing_fraction_1"], later, rtol=1e-12)


SETTLE = {"inputs": ROOT / "inputs", "quick": 1, "shape": "rod", "settle_time": 0.25,
          "settle_checkpoint_every_time": 0.1, "write_packing": 1, "write_poses": 1, "discharge_time": 0}


@pytest.mark.parametrize("nprocs", [1, pytest.param(2, marks=pytest.mark.skipif(not has_mpirun(),
                                                                               reason="mpirun not available"))])
def test_a_settling_resumed_from_its_checkpoint_ends_as_the_uninterrupted_one(tmp_path, liggghts_binary, nprocs):
    """The quick rods settle 0.25 s with a checkpoint every 0.1 s: two
    chunks with a restart file after each, then the 0.05 s short of a
    third. The settling resumed from its first checkpoint (what
    settle-resume prints) writes the same packing: every rod's centre and
    axis at the opening to the poses file's 15 digits; and the bottom
    opens at 0.25 s, as in the run that was not cut. On one rank and on
    two (each run and its resumption on the same count: a restart file
    read on two ranks spreads the rods over both)."""
    whole = tmp_path / "whole"
    run_deck(whole, SETTLE, nprocs)
    listed = [line.split() for line in (whole / "checkpoints.txt").read_text().splitlines()]
    steps = [int(step) for step, _ in listed]
    chunk = round(0.1 / read_run_info(whole)["dt"])
    assert steps == [chunk, 2 * chunk]

    cut = tmp_path / "cut"
    cut.mkdir()
    shutil.copy(whole / f"checkpoint.{steps[0]}.restart", cut)
    (cut / "checkpoints.txt").write_text(f"{steps[0]} checkpoint.{steps[0]}.restart\n")
    variables = checkpoint.settle_resume_variables(cut)
    assert variables == {"settle_resume": 1, "checkpoint": str((cut / f"checkpoint.{steps[0]}.restart").resolve()),
                         "settled_steps": steps[0]}
    run_deck(cut, {**SETTLE, **variables}, nprocs)
    assert (cut / "poses.dump").read_text() == (whole / "poses.dump").read_text()
    resumed, uncut = read_run_info(cut), read_run_info(whole)
    assert resumed["step_open"] == uncut["step_open"] == round(0.25 / uncut["dt"])
    assert resumed["t_open"] == uncut["t_open"]
    np.testing.assert_allclose(read_table(cut / "discharge.txt")["t"], read_table(whole / "discharge.txt")["t"],
                               rtol=0, atol=1e-12)
    # nothing to resume from: settle-resume prints nothing
    assert checkpoint.settle_resume_variables(tmp_path) is None


def test_settle_resume_with_a_packing_read_is_refused_with_its_message(tmp_path, liggghts_binary):
    from analysis.testing import LiggghtsError
    with pytest.raises(LiggghtsError) as error:
        run_deck(tmp_path, {**SETTLE, "settle_resume": 1, "read_packing": 1, "checkpoint": "x"})
    assert "settle_resume goes on with a settling" in error.value.output


def test_the_resume_variables_come_from_the_last_checkpoint_on_disk_and_run_txt(tmp_path):
    (tmp_path / "run.txt").write_text("# run\ndt 0.001\nt_open 0.4\nN 900\nstep_open 400\nfinished 0.9\n")
    (tmp_path / "checkpoints.txt").write_text("500 checkpoint.500.restart\n600 checkpoint.600.restart\n")
    (tmp_path / "checkpoint.500.restart").write_text("a file")   # 600's was never written whole
    # the interruption cut the last row short: "6" of "650 0.65 250 0.1"
    (tmp_path / "discharge.txt").write_text("# step t n_out mass_out\n" +
                                            "".join(f"{s} {s / 1000} {s - 400} 0.1\n" for s in range(400, 650, 50))
                                            + "6")
    frames = "".join(f"ITEM: TIMESTEP\n{s}\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id x\n1 0.5\n"
                     for s in (400, 450, 500, 550))
    (tmp_path / "dump.cg").write_text(frames + "ITEM: TIMESTEP\n")
    variables = checkpoint.resume_variables(tmp_path)
    assert variables == {"resume": 1, "checkpoint": str((tmp_path / "checkpoint.500.restart").resolve()),
                         "t_resume": repr(0.4 + 100 * 0.001), "n_open_resumed": 900,
                         "step_open_resumed": 400}
    assert list(read_table(tmp_path / "discharge.txt")["step"]) == [400, 450, 500]
    assert [step for step, _ in read_dump(tmp_path / "dump.cg")] == [400, 450]   # 500 is written again
    assert "finished" not in (tmp_path / "run.txt").read_text()
    (tmp_path / "checkpoint.500.restart").unlink()
    assert checkpoint.resume_variables(tmp_path) is None


def signal_processes(session, name, signum):
    """Sends signum to the processes of a session whose name is `name`
    (from /proc/<pid>/stat); returns how many."""
    hit = 0
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        process_name = stat[stat.index("(") + 1:stat.rindex(")")]
        process_session = int(stat[stat.rindex(")") + 2:].split()[3])   # after: state ppid pgrp session
        if process_name == name and process_session == session:
            os.kill(int(entry.name), signum)
            hit += 1
    return hit


@pytest.mark.engine       # runs run.sh, which runs the built LIGGGHTS
@pytest.mark.parametrize("stop", ["kill run.sh", "SIGTERM to LIGGGHTS"])
def test_run_sh_killed_after_a_checkpoint_finishes_the_run_from_it(tmp_path, stop):
    # "kill run.sh": SIGKILL to the whole campaign (a session's end);
    # "SIGTERM to LIGGGHTS": LIGGGHTS alone gets it, writes its forced
    # restart and ends with status 0, run.sh goes on and must not take the
    # run for finished (nor delete its checkpoints)
    environment = {**os.environ, "SILOKIT_LIGGGHTS": str(LIGGGHTS), "DS": "0.05", "FS": "0.32",
                   "SEEDS": "32452843", "DISCHARGE": "0.5", "TRANSIENT": "0.1", "CHECKPOINT": "0.1",
                   "FIELDS": "0.05 0.32", "DECK_VARS": "quick 1"}
    command = ["bash", str(ROOT / "examples" / "silo3d_rotating" / "run.sh"), str(tmp_path / "runs")]
    run_dir = tmp_path / "runs" / "D0.05_f0.32_s32452843"
    listing = run_dir / "checkpoints.txt"
    first = subprocess.Popen(command, env=environment, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                             text=True, start_new_session=True)
    deadline = time.time() + 300
    while not (listing.exists() and listing.read_text().strip()) and time.time() < deadline:
        assert first.poll() is None, "run.sh ended before its first checkpoint"
        time.sleep(0.2)
    assert listing.exists(), "no checkpoint within 300 s"
    if stop == "kill run.sh":
        os.killpg(first.pid, signal.SIGKILL)
        first.wait()
    else:
        # the campaign's session holds run.sh, its subshells and LIGGGHTS,
        # whose process name is the binary's
        assert signal_processes(first.pid, LIGGGHTS.name, signal.SIGTERM) == 1
        first.wait(timeout=300)
        assert list(run_dir.glob("restart_forced_liggghts_*.data")), "LIGGGHTS did not get the SIGTERM"
        assert "stopped before the end of its discharge" in first.stdout.read()
        assert list(run_dir.glob("checkpoint.*.restart"))
        assert "finished" not in read_run_info(run_dir)
    assert not (run_dir / "finished").exists()

    second = subprocess.run(command, env=environment, capture_output=True, text=True, timeout=600)
    assert second.returncode == 0, second.stdout + second.stderr
    assert "resuming" in second.stdout and (run_dir / "finished").exists()
    # all checkpoints but the last are cleaned, and the forced restart with them
    assert [path.name for path in run_dir.glob("checkpoint.*.restart")] == [checkpoint.last_checkpoint(run_dir)[1].name]
    assert not list(run_dir.glob("restart_forced_liggghts_*.data"))
    steps = read_table(run_dir / "discharge.txt")["step"]
    assert np.all(np.diff(steps) == steps[1] - steps[0])      # no gap, no repeated row
    t = read_table(run_dir / "discharge.txt")["t"]
    run = read_run_info(run_dir)
    assert t[-1] - run["t_open"] == pytest.approx(0.5, abs=0.01)
    frames = [step for step, _ in read_dump(run_dir / "dump.cg")]
    interval = frames[1] - frames[0]
    assert np.all(np.diff(frames) == interval)                # one frame every 0.05 s, none twice
    assert frames[0] - int(run["step_open"]) < interval and steps[-1] - frames[-1] < interval
    reinjected = read_table(run_dir / "reinject.txt")
    assert np.all(np.diff(reinjected["step"]) > 0) and np.all(np.diff(reinjected["n_out"]) > 0)
    assert (run_dir / "screen.txt").read_text().count("silo3d_rotating: done at") == 1
    if stop != "kill run.sh":
        return
    # the finished run made longer: it goes on from the checkpoint it kept,
    # its records cut back to it and continued without a gap
    last_step = checkpoint.last_checkpoint(run_dir)[0]
    old = read_table(run_dir / "discharge.txt")
    longer = subprocess.run(command, env={**environment, "DISCHARGE": "0.6"}, capture_output=True, text=True,
                            timeout=600)
    assert longer.returncode == 0, longer.stdout + longer.stderr
    assert "done before with a discharge of 0.5 s: made longer, to 0.6 s" in longer.stdout
    assert f"checkpoint {run_dir.resolve()}/checkpoint.{last_step}.restart" in longer.stdout
    assert (run_dir / "finished").exists() and read_run_info(run_dir)["discharge_time"] == 0.6
    new = read_table(run_dir / "discharge.txt")
    steps = new["step"]
    assert np.all(np.diff(steps) == steps[1] - steps[0])
    assert new["t"][-1] - run["t_open"] == pytest.approx(0.6, abs=0.01)
    kept = old["step"] <= last_step     # the rows up to the checkpoint are the old run's
    np.testing.assert_array_equal(new["n_out"][:kept.sum()], old["n_out"][kept])
    frames = [step for step, _ in read_dump(run_dir / "dump.cg")]
    assert np.all(np.diff(frames) == interval) and steps[-1] - frames[-1] < interval
    assert [line.split()[0] for line in (run_dir / "run.txt").read_text().splitlines()].count("finished") == 1
    # shorter than it ran, or no checkpoint left to go on from (a restart
    # file that checkpoints.txt does not list is none): skipped
    for discharge, checkpoints in (("0.5", True), ("0.7", False)):
        if not checkpoints:
            checkpoint.remove_checkpoints(run_dir)
            (run_dir / "checkpoint.1.restart").write_bytes(b"not listed")
        again = subprocess.run(command, env={**environment, "DISCHARGE": discharge}, capture_output=True,
                               text=True, timeout=600)
        assert f"done before with a discharge of 0.6 s, not {discharge}: skipped" in again.stdout
    assert read_run_info(run_dir)["discharge_time"] == 0.6


@pytest.mark.engine       # runs run.sh, which runs the built LIGGGHTS
def test_run_sh_killed_while_settling_goes_on_from_the_settling_s_checkpoint(tmp_path):
    """SETTLE_CHECKPOINT: run.sh making the quick rods' packing (0.7 s of
    settling, a checkpoint every 0.1 s), killed once the settling has a
    checkpoint and started again, resumes the settling from it (the
    settled steps of its last checkpoint), writes the packing and removes
    the checkpoint files."""
    environment = {**os.environ, "SILOKIT_LIGGGHTS": str(LIGGGHTS), "SHAPE": "rod", "DS": "", "FS": "",
                   "SEEDS": "32452843", "SETTLE_CHECKPOINT": "0.1", "DECK_VARS": "quick 1"}
    command = ["bash", str(ROOT / "examples" / "silo3d_rotating" / "run.sh"), str(tmp_path / "runs")]
    packing_dir = tmp_path / "runs" / "packing_s32452843"
    listing = packing_dir / "checkpoints.txt"
    first = subprocess.Popen(command, env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             start_new_session=True)
    deadline = time.time() + 300
    while not (listing.exists() and listing.read_text().strip()) and time.time() < deadline:
        assert first.poll() is None, "run.sh ended before the settling's first checkpoint"
        time.sleep(0.2)
    os.killpg(first.pid, signal.SIGKILL)
    first.wait()
    assert not (packing_dir / "packing.restart").exists()
    settled = checkpoint.last_checkpoint(packing_dir)[0]

    second = subprocess.run(command, env=environment, capture_output=True, text=True, timeout=600)
    assert second.returncode == 0, second.stdout + second.stderr
    assert f"resuming (-var settle_resume 1 -var checkpoint {packing_dir.resolve()}/checkpoint.{settled}.restart " \
           f"-var settled_steps {settled})" in second.stdout
    assert (packing_dir / "packing.restart").exists() and (packing_dir / "finished").exists()
    assert not list(packing_dir.glob("checkpoint.*.restart"))
    # the opening of the resumed settling is where the whole one's is
    run = read_run_info(packing_dir)
    assert run["step_open"] == round(0.7 / run["dt"])


def test_a_kept_run_restored_elsewhere_resumes_from_the_same_checkpoint(tmp_path):
    """keep + restore on hand-made files: the restored directory gives the
    resume variables of the original (but its own checkpoint file), the
    checkpoint's bytes, the records up to it, and dump.cg's frames before it
    with only the grains inside the cylinder asked for."""
    run = tmp_path / "run"
    run.mkdir()
    (run / "run.txt").write_text("# run\ndt 0.001\nt_open 0.4\nN 3\nstep_open 400\n")
    (run / "checkpoints.txt").write_text("500 checkpoint.500.restart\n600 checkpoint.600.restart\n")
    payload = bytes(range(256)) * 40
    (run / "checkpoint.500.restart").write_bytes(b"older")
    (run / "checkpoint.600.restart").write_bytes(payload)
    (run / "discharge.txt").write_text("# step t n_out mass_out\n" +
                                       "".join(f"{s} {s / 1000} {s - 400} 0.1\n" for s in range(400, 750, 50)))
    (run / "reinject.txt").write_text("# step t n_out mass_out avalanche\n450 0.45 1 0.1 1\n650 0.65 2 0.2 2\n")
    # three grains: inside (r 0.01, z 0.01), too far out (r 0.1), too high (z 0.2)
    grains = "1 1 0.01 0 0.01\n2 1 0.1 0 0.01\n3 1 0 0.01 0.2\n"
    frames = "".join(f"ITEM: TIMESTEP\n{s}\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS ff ff ff\n"
                     f"-1 1\n-1 1\n0 1\nITEM: ATOMS id type x y z\n{grains}" for s in (450, 550, 650))
    (run / "dump.cg").write_text(frames)

    kept = tmp_path / "kept"
    assert checkpoint.main(["keep", str(run), str(kept), "--dump-cylinder", "0.05", "0.05"]) == 0
    assert sorted(path.name for path in kept.iterdir()) == [
        "checkpoint.600.restart.xz", "checkpoints.txt", "discharge.txt", "dump.cg.xz", "dump_cut.txt",
        "reinject.txt", "run.txt"]
    # the maps take the frames from the checkpoint on, on the grid of the fill
    # at the opening: the highest grain of the first frame from it, before the cut
    assert read_dump_cut(kept) == DumpCut(600, 0.2, ((0.05, 0.05),))
    restored = tmp_path / "restored"
    assert checkpoint.main(["restore", str(kept), str(restored)]) == 0
    assert (restored / "checkpoint.600.restart").read_bytes() == payload
    assert list(read_table(restored / "discharge.txt")["step"]) == [400, 450, 500, 550, 600]
    assert list(read_table(restored / "reinject.txt")["step"]) == [450]
    dumped = read_dump(restored / "dump.cg")
    assert [step for step, _ in dumped] == [450, 550]
    assert all(list(frame["id"]) == [1] for _, frame in dumped)

    expected = checkpoint.resume_variables(run)
    got = checkpoint.resume_variables(restored)
    assert got.pop("checkpoint") == str((restored / "checkpoint.600.restart").resolve())
    expected.pop("checkpoint")
    assert got == expected and got["t_resume"] == repr(0.4 + 200 * 0.001)
    # a second restore into the same directory would mix two runs: refused
    assert checkpoint.main(["restore", str(kept), str(restored)]) == 2


def test_a_kept_dump_holds_the_grains_of_any_of_its_cylinders(tmp_path):
    """--dump-cylinder twice: the orifice region (r < 6 cm, z < 5 cm) and
    the column over the axis (r < 2.5 cm, z < 20 cm) of the axial
    acceleration; a grain in neither is dropped."""
    run = tmp_path / "run"
    run.mkdir()
    (run / "run.txt").write_text("dt 0.001\nt_open 0\nN 4\nstep_open 0\n")
    (run / "checkpoints.txt").write_text("100 checkpoint.100.restart\n")
    (run / "checkpoint.100.restart").write_bytes(b"state")
    # in the orifice region only, in the axis column only, in both, in neither
    grains = "1 1 0.05 0 0.01\n2 1 0.02 0 0.15\n3 1 0 0 0.01\n4 1 0.05 0 0.15\n"
    (run / "dump.cg").write_text(f"ITEM: TIMESTEP\n50\nITEM: NUMBER OF ATOMS\n4\nITEM: BOX BOUNDS ff ff ff\n"
                                 f"-1 1\n-1 1\n0 1\nITEM: ATOMS id type x y z\n{grains}")
    kept = tmp_path / "kept"
    assert checkpoint.main(["keep", str(run), str(kept), "--dump-cylinder", "0.06", "0.05",
                            "--dump-cylinder", "0.025", "0.2"]) == 0
    checkpoint.restore(kept, tmp_path / "restored")
    [(step, frame)] = read_dump(tmp_path / "restored" / "dump.cg")
    assert step == 50 and list(frame["id"]) == [1, 2, 3]


def test_keep_without_a_checkpoint_is_refused(tmp_path, capsys):
    (tmp_path / "run.txt").write_text("dt 0.001\n")
    assert checkpoint.main(["keep", str(tmp_path), str(tmp_path / "kept")]) == 2
    assert "no checkpoint to keep" in capsys.readouterr().err
