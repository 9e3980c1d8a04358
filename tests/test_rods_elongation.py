"""examples/silo3d_rotating/rods_elongation.sh on the quick silo (300 rods):
a stage settles its packing with checkpoints and runs its two frequencies;
`keep` archives the finished runs (their orifice tables, no maps, from the
stage's analysis: no dump is read twice) and carries the packing; the next
machine takes the packing from carry/ (not settled again) and skips the
archived runs, which it does not analyse again. Stage 8 runs spheres,
settled without checkpoints, into their own store, with orifice series."""

import os
import subprocess

from analysis.silo3d_rotating.records import read_run_info
from conftest import LIGGGHTS, ROOT
import pytest

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

DRIVER = ROOT / "examples" / "silo3d_rotating" / "rods_elongation.sh"


def driver(action, run_dir, stores, **environment):
    settings = {**os.environ, "SILOKIT_LIGGGHTS": str(LIGGGHTS), "STORES": str(stores), "STAGES": "1",
                "PROTOCOL": "0 0.06 0.02  0.32 0.06 0.02  1.28 0.06 0.02", "CHECKPOINT": "0",
                "DECK_VARS": "quick 1 settle_time 0.3", **environment}
    result = subprocess.run(["bash", str(DRIVER), action, str(run_dir)], env=settings, capture_output=True,
                            text=True, timeout=900)
    return result, result.stdout + result.stderr


def test_a_stage_settles_runs_keeps_and_the_next_machine_goes_on_from_the_carried_packing(tmp_path):
    stores = tmp_path / "data"
    first, log = driver("run", tmp_path / "machine1", stores)
    assert first.returncode == 0, log
    assert "stage 1: L/d = 4.0, seeds 32452843, f = 0 0.32 Hz" in log
    runs = tmp_path / "machine1" / "L4.0"
    assert read_run_info(runs / "packing_s32452843")["aspect"] == 4.0
    for f in ("0", "0.32"):
        assert (runs / f"D0.06_f{f}_s32452843" / "finished").exists()
    kept, log = driver("keep", tmp_path / "machine1", stores)
    assert kept.returncode == 0, log
    assert "kernel w =" not in log     # the stage's analysis made the orifice tables: no dump read again
    store = stores / "silo3d_rods_elongation_L4.0"
    for f in ("0", "0.32"):
        assert (store / f"D0.06_f{f}_s32452843" / "orifice_timeseries.md").exists(), log
        assert not (store / f"D0.06_f{f}_s32452843" / "fields.npz").exists(), log   # KEEP_FIELDS=0
    carried = stores / "carry" / "silo3d_rods_elongation_L4.0" / "packings"   # beside the stores, outside a git tree
    assert (carried / "packing_s32452843.restart.xz").exists(), log

    second, log = driver("run", tmp_path / "machine2", stores)
    assert second.returncode == 0, log
    assert "packing of seed 32452843: the kept one" in log and "settling" not in log
    assert log.count("done before, skipped") == 2
    assert "archived in" in log and "not analysed again" in log

    wrong, log = driver("run", tmp_path / "machine3", stores, STAGES="1 9")
    assert wrong.returncode == 2 and "STAGES: no stage '9' (1-8)" in log
    assert not (tmp_path / "machine3").exists()


def test_the_spheres_stage_runs_three_packings_into_its_own_store(tmp_path):
    stores = tmp_path / "data"
    quick = "0 0.03 0.01  0.32 0.12 0.02  1.28 0.03 0.01"   # 0.32 Hz: dump frames at 0.05 and 0.1 s
    ran, log = driver("run", tmp_path / "machine1", stores, STAGES="8", SPHERES_PROTOCOL=quick, CHECKPOINT="0.05")
    assert ran.returncode == 0, log
    assert "stage 8: L/d = spheres, seeds 32452843 15485863 49979687, f = 0 0.32 1.28 Hz" in log
    runs = tmp_path / "machine1" / "spheres"
    for seed in (32452843, 15485863, 49979687):
        info = read_run_info(runs / f"packing_s{seed}")
        assert info["shape"] == "sphere" and info["aspect"] == 3.3     # the deck's default, as the bench's
        assert not list((runs / f"packing_s{seed}").glob("settle_checkpoint*"))   # settled in one run
        for f in ("0", "0.32", "1.28"):
            assert (runs / f"D0.06_f{f}_s{seed}" / "finished").exists(), log
            # in one run, as the bench's, although CHECKPOINT asks the rods for them
            assert not list((runs / f"D0.06_f{f}_s{seed}").glob("checkpoint*")), log
    kept, log = driver("keep", tmp_path / "machine1", stores, STAGES="8", SPHERES_PROTOCOL=quick)
    assert kept.returncode == 0, log
    series = stores / "silo3d_rods_elongation_spheres" / "D0.06_f0.32_s15485863" / "orifice_timeseries.md"
    header = series.read_text().splitlines()[2]
    assert "| phi |" in header and "| v_z |" in header and "O_zz" not in header
