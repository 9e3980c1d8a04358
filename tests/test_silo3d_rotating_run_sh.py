"""examples/silo3d_rotating/run.sh with PEER_OF: the glued-sphere peer of a
rod campaign starts from the rods' own packings (quick silo, 300 grains).

The rods' campaign settles its packing; the clumps' campaign writes that
packing's poses, places a clump on every rod, relaxes them and discharges
without reinjection. (The resuming of run.sh is tested in
test_silo3d_rotating_checkpoint.py.)
"""

import os
import re
import subprocess

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_table
from analysis.silo3d_rotating.records import read_run_info
from conftest import LIGGGHTS, ROOT

RUN_SH = ROOT / "examples" / "silo3d_rotating" / "run.sh"


def campaign(run_dir, **environment):
    settings = {**os.environ, "SILOKIT_LIGGGHTS": str(LIGGGHTS), "DS": "0.05", "FS": "0.32",
                "SEEDS": "32452843", "DISCHARGE": "0.05", "TRANSIENT": "0.0", "FIELDS": "",
                "REINJECT": "0", "CHECKPOINT": "0", "ASPECT": "3.3", **environment}
    return subprocess.run(["bash", str(RUN_SH), str(run_dir)], env=settings, capture_output=True,
                          text=True, timeout=900)


@pytest.mark.engine       # runs run.sh, which runs the built LIGGGHTS
def test_peer_of_places_a_clump_on_every_rod_of_the_rods_packing(tmp_path):
    # FS="": only the packing (the defaults are for an unset FS)
    settled = campaign(tmp_path / "rods", SHAPE="rod", FS="", DECK_VARS="quick 1 settle_time 0.5")
    assert settled.returncode == 0, settled.stdout + settled.stderr
    assert "packings made" in settled.stdout
    assert (tmp_path / "rods" / "packing_s32452843" / "finished").exists()
    assert not list((tmp_path / "rods").glob("D*"))
    rods = campaign(tmp_path / "rods", SHAPE="rod", DECK_VARS="quick 1 settle_time 0.5")
    assert rods.returncode == 0, rods.stdout + rods.stderr
    assert "settling" not in rods.stdout          # the packing above, reused
    clumps = campaign(tmp_path / "clumps", SHAPE="clump", PEER_OF=str(tmp_path / "rods"), RELAX="0.01",
                      DECK_VARS="quick 1")
    assert clumps.returncode == 0, clumps.stdout + clumps.stderr
    packing = tmp_path / "clumps" / "packing_s32452843"
    _, poses = read_dump(packing / "rod_poses.dump")[0]
    assert len(poses["x"]) == 300
    assert "inserted 300 particle templates" in (packing / "screen.txt").read_text()
    # the rods' poses are those of their packing: the rods' own discharge
    # from it starts with the same grains
    assert read_run_info(tmp_path / "rods" / "D0.05_f0.32_s32452843")["N"] == 300
    run = tmp_path / "clumps" / "D0.05_f0.32_s32452843"
    parameters = read_run_info(run)
    assert parameters["shape"] == "clump" and parameters["N"] == 300 and "finished" in parameters
    assert read_table(run / "discharge.txt")["n_out"][0] == 0


def test_peer_of_needs_clumps(tmp_path):
    result = campaign(tmp_path / "rods", SHAPE="rod", PEER_OF=str(tmp_path))
    assert result.returncode == 2 and "PEER_OF places clumps on rods" in result.stderr


def kept_quick_packing(tmp_path):
    """A quick silo's rod packing settled by run.sh and kept as PACKINGS
    wants (xz, with its settling's run.txt): (its directory, the kept one)."""
    settled = campaign(tmp_path / "rods", SHAPE="rod", FS="", DECK_VARS="quick 1 settle_time 0.3")
    assert settled.returncode == 0, settled.stdout + settled.stderr
    packing = tmp_path / "rods" / "packing_s32452843"
    kept = tmp_path / "kept"
    kept.mkdir()
    with open(kept / "packing_s32452843.restart.xz", "wb") as archive:
        subprocess.run(["xz", "-c", str(packing / "packing.restart")], stdout=archive, check=True)
    (kept / "packing_s32452843_run.txt").write_bytes((packing / "run.txt").read_bytes())
    return packing, kept


@pytest.mark.engine       # runs run.sh, which runs the built LIGGGHTS
def test_kept_packings_and_a_discharge_and_window_per_frequency(tmp_path):
    """PACKINGS: a seed whose packing is kept (xz, with its settling's
    run.txt) is unpacked, not settled, byte for byte; DISCHARGE_AT and
    TRANSIENT_AT: each frequency's run lasts its own time and its Q leaves
    out its own transient. A kept packing of other rods is refused."""
    packing, kept = kept_quick_packing(tmp_path)

    run_dir = tmp_path / "campaign"
    result = campaign(run_dir, SHAPE="rod", FS="0 0.32", PACKINGS=str(kept), DISCHARGE="0.1",
                      DISCHARGE_AT="0.32 0.2", TRANSIENT="0.05", TRANSIENT_AT="0.32 0.15",
                      DECK_VARS="quick 1 settle_time 0.3")
    assert result.returncode == 0, result.stdout + result.stderr
    assert "settling" not in result.stdout and "the kept one" in result.stdout
    assert (run_dir / "packing_s32452843" / "packing.restart").read_bytes() == \
        (packing / "packing.restart").read_bytes()
    for f, until in (("0", 0.1), ("0.32", 0.2)):
        info = read_run_info(run_dir / f"D0.05_f{f}_s32452843")
        # the deck's last line, the time it stopped at: `until` after the opening, to a step
        assert info["discharge_time"] == until and info["finished"] == pytest.approx(until, abs=2 * info["dt"])
        # its records every 0.01 s to the end
        assert until - 0.01 < read_table(run_dir / f"D0.05_f{f}_s32452843" / "discharge.txt")["t"][-1] <= until
    runs = read_table(run_dir / "analysis" / "flow_rate_runs.txt")
    assert sorted(runs["f"].tolist()) == [0.0, 0.32]
    rest, turning = np.flatnonzero(runs["f"] == 0)[0], np.flatnonzero(runs["f"] == 0.32)[0]
    # the first sample at or after each transient (samples every 0.01 s), the last one
    assert 0.05 <= runs["t_start"][rest] < 0.06 and 0.15 <= runs["t_start"][turning] < 0.16
    assert runs["t_end"][rest] == pytest.approx(0.1, abs=0.01) and runs["t_end"][turning] == pytest.approx(0.2, abs=0.01)
    # asked again for a longer run at 0.32 Hz: the finished one is kept, and the log says it is shorter
    again = campaign(run_dir, SHAPE="rod", FS="0 0.32", PACKINGS=str(kept), DISCHARGE="0.1",
                     DISCHARGE_AT="0.32 0.3", TRANSIENT="0.05", DECK_VARS="quick 1 settle_time 0.3")
    assert again.returncode == 0, again.stdout + again.stderr
    assert "D 0.05 f 0 seed 32452843: done before, skipped" in again.stdout
    assert "D 0.05 f 0.32 seed 32452843: done before with a discharge of 0.2 s, not 0.3: skipped" in again.stdout
    # asked for one frequency only: the analysis holds that run alone, over
    # its own window; the f = 0 run beside it is not analysed with this
    # command's transient
    part = campaign(run_dir, SHAPE="rod", FS="0.32", PACKINGS=str(kept), DISCHARGE="0.2", TRANSIENT="0.02",
                    TRANSIENT_AT="0.32 0.15", DECK_VARS="quick 1 settle_time 0.3")
    assert part.returncode == 0, part.stdout + part.stderr
    assert "analysing the 1 runs of DS, FS and SEEDS" in part.stdout
    runs = read_table(run_dir / "analysis" / "flow_rate_runs.txt")
    assert runs["f"].tolist() == [0.32] and 0.15 <= runs["t_start"][0] < 0.16

    other = campaign(tmp_path / "longer", SHAPE="rod", ASPECT="4.0", PACKINGS=str(kept), DECK_VARS="quick 1")
    assert other.returncode != 0
    assert "holds shape rod, aspect 3.3" in other.stdout and "not SHAPE=rod ASPECT=4.0" in other.stdout
    assert not (tmp_path / "longer" / "packing_s32452843" / "packing.restart").exists()


@pytest.mark.parametrize("environment, message", [
    ({"DISCHARGE_AT": "0.5 1"}, "DISCHARGE_AT: 0.5 is not one of FS"),
    ({"DISCHARGE_AT": "0.32"}, "DISCHARGE_AT needs \"f T\" pairs"),
    ({"TRANSIENT_AT": "0.32 x"}, "TRANSIENT_AT: 0.32 needs a time >= 0 in s, not 'x'"),
    ({"TRANSIENT_AT": "0.32 1 0.32 2"}, "TRANSIENT_AT: 0.32 is given more than once"),
    ({"PACKINGS": "/nonexistent"}, "PACKINGS: no directory /nonexistent"),
    ({"DISCHARGE": "1", "TRANSIENT_AT": "0.32 1"},
     "at f = 0.32 the discharge (1 s) must be longer than the transient left out (1 s)"),
])
def test_bad_per_frequency_settings_and_packings_are_refused(tmp_path, environment, message):
    result = campaign(tmp_path / "runs", SHAPE="rod", FS="0 0.32", **environment)
    assert result.returncode == 2 and message in result.stderr, result.stderr
    assert not (tmp_path / "runs").exists()



def test_help_documents_every_environment_variable_with_an_example():
    """run.sh --help prints its header comment (one place for its options)
    and exits 0 without running anything; every environment variable the
    script reads (`${NAME:-default}` or `${NAME-default}`) has its entry
    there, and the text shows an example command."""
    result = subprocess.run(["bash", str(RUN_SH), "--help"], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0 and result.stderr == ""
    text = RUN_SH.read_text()
    header = []
    for line in text.splitlines()[1:]:
        if not line.startswith("#"):
            break
        header.append(line[2:] if line.startswith("# ") else line[1:])
    assert result.stdout == "\n".join(header) + "\n"
    read = set(re.findall(r"\$\{([A-Z][A-Z0-9_]*):?-", text))
    assert {"DS", "FS", "DECK_VARS", "SILOKIT_LIGGGHTS", "PEER_OF"} <= read and len(read) >= 23
    missing = [name for name in sorted(read) if not re.search(rf"^  {name}\s", result.stdout, re.M)]
    assert not missing, f"not in run.sh --help: {missing}"
    assert "Example" in result.stdout and "bash examples/silo3d_rotating/run.sh /tmp/" in result.stdout


RODS_FIG2C = ROOT / "examples" / "silo3d_rotating" / "rods_fig2c.sh"


@pytest.mark.engine       # runs run.sh, which runs the built LIGGGHTS
def test_the_fig2c_driver_carries_a_finished_run_to_the_next_machine_and_analyses_each_window(tmp_path):
    """examples/silo3d_rotating/rods_fig2c.sh on a quick silo with a protocol
    of two frequencies: the first machine runs one of them and keeps it in
    the store; the second restores it as done, runs the other, and
    analyses both, each over its own window."""
    _, kept = kept_quick_packing(tmp_path)
    settings = {**os.environ, "SILOKIT_LIGGGHTS": str(LIGGGHTS), "PACKINGS": str(kept), "ALSO": "",
                "STORE": str(tmp_path / "store"), "DS": "0.05", "SEEDS": "32452843", "CHECKPOINT": "0",
                "PROTOCOL": "0 0.1 0.05  0.32 0.2 0.15", "DECK_VARS": "quick 1"}

    def driver(action, run_dir, **environment):
        result = subprocess.run(["bash", str(RODS_FIG2C), action, str(run_dir)], capture_output=True, text=True,
                                env={**settings, **environment}, timeout=900)
        return result, result.stdout + result.stderr

    first, log = driver("run", tmp_path / "machine1", FS="0.32")
    assert first.returncode == 0 and "D 0.05 f 0.32 seed 32452843: running 0.2 s (dumps every 0.05 s)" in log, log
    kept_runs, log = driver("keep", tmp_path / "machine1")
    assert kept_runs.returncode == 0 and "D0.05_f0.32_s32452843: finished, archived" in log, log
    second, log = driver("run", tmp_path / "machine2")
    assert second.returncode == 0, log
    assert "D0.05_f0.32_s32452843: finished, from" in log and "D 0.05 f 0.32 seed 32452843: done before, skipped" in log
    assert "D 0.05 f 0 seed 32452843: running 0.1 s" in log
    runs = read_table(tmp_path / "machine2" / "analysis" / "flow_rate_runs.txt")
    rest, turning = np.flatnonzero(runs["f"] == 0)[0], np.flatnonzero(runs["f"] == 0.32)[0]
    assert 0.05 <= runs["t_start"][rest] < 0.06 and 0.15 <= runs["t_start"][turning] < 0.16
    # the carried run's Q is the first machine's
    assert read_table(tmp_path / "machine1" / "analysis" / "flow_rate_runs.txt")["Q_kg_s"][0] == runs["Q_kg_s"][turning]

    wrong, log = driver("run", tmp_path / "machine3", FS="0.5")
    assert wrong.returncode == 2 and "FS: 0.5 is not one of the protocol's frequencies ( 0 0.32)" in log
    assert not (tmp_path / "machine3").exists()
    wrong, log = driver("run", tmp_path / "machine3", PROTOCOL="0 8")
    assert wrong.returncode == 2 and 'PROTOCOL needs "f discharge transient" triples' in log
    wrong, log = driver("walk", tmp_path / "machine3")
    assert wrong.returncode == 2 and "usage:" in log
