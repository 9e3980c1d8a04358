"""examples/silo3d_rotating/run.sh with PEER_OF: the glued-sphere peer of a
rod campaign starts from the rods' own packings (quick silo, 300 grains).

The rods' campaign settles its packing; the clumps' campaign writes that
packing's poses, places a clump on every rod, relaxes them and discharges
without reinjection. (The resuming of run.sh is tested in
test_silo3d_rotating_checkpoint.py.)
"""

import os
import subprocess

from analysis.lammps_io import read_dump, read_table
from analysis.silo3d_records import read_run_info
from conftest import LIGGGHTS, ROOT

RUN_SH = ROOT / "examples" / "silo3d_rotating" / "run.sh"


def campaign(run_dir, **environment):
    settings = {**os.environ, "SILOKIT_LIGGGHTS": str(LIGGGHTS), "DS": "0.05", "FS": "0.32",
                "SEEDS": "32452843", "DISCHARGE": "0.05", "TRANSIENT": "0.0", "FIELDS": "",
                "REINJECT": "0", "CHECKPOINT": "0", "ASPECT": "3.3", **environment}
    return subprocess.run(["bash", str(RUN_SH), str(run_dir)], env=settings, capture_output=True,
                          text=True, timeout=900)


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
