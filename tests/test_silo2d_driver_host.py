"""analysis.silo2d.driver --host lammps: the segment command lines it
builds for each host, the campaign's one host (host.txt, and a campaign
from before the switch taken as LIGGGHTS'), and the small silo run in
LAMMPS in segments, cut in a segment and resumed: the records those of the
uncut campaign, byte for byte, as tests/test_silo2d_driver.py checks for
LIGGGHTS (the same helper)."""

import os
from pathlib import Path

import pytest

from analysis.common import hosts
from analysis.silo2d import driver
from lammps_host import LMP, PLUGIN, ROOT, needs_lammps
from test_silo2d_driver import CAMPAIGN, assert_cut_campaign_resumes_as_uncut

VARIABLES = {"mu": "0.4", "dt": "2e-05", "seed": "32452843", "quick": "1", "narches": "1000000000"}


def test_lammps_segment_takes_the_lammps_deck_binary_and_plugin(monkeypatch):
    monkeypatch.setattr(hosts, "LAMMPS_BINARY", Path("/x/lmp"))
    monkeypatch.setattr(hosts, "LIGGGHTS_BINARY", Path("/x/liggghts"))
    monkeypatch.setattr(driver, "INPUTS", Path("/in"))
    monkeypatch.setenv("SILOKIT_LAMMPS_PLUGIN", "/y/silokit_lammps.so")
    command = driver.segment_command("lammps", 3, VARIABLES, 20.0, nice=10)
    assert command == ["nice", "-n", "10", "stdbuf", "-oL", "/x/lmp", "-in", "/in/silo2d/in.silo2d.lammps",
                       "-log", "none", "-echo", "none", "-var", "inputs", "/in",
                       "-var", "mu", "0.4", "-var", "dt", "2e-05", "-var", "seed", "32452843",
                       "-var", "quick", "1", "-var", "narches", "1000000000",
                       "-var", "segment", "3", "-var", "segment_time", "20", "-var", "state", "state",
                       "-var", "plugin", "/y/silokit_lammps.so"]
    # LIGGGHTS: its binary and deck, no plugin; mpirun outside stdbuf
    command = driver.segment_command("liggghts", 1, VARIABLES, 2.5, nprocs=2)
    assert command[:7] == ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", "stdbuf", "-oL"]
    assert command[7:10] == ["/x/liggghts", "-in", "/in/silo2d/in.silo2d"]
    assert "plugin" not in command
    assert command[-9:] == ["-var", "segment", "1", "-var", "segment_time", "2.5", "-var", "state", "state"]


def test_lammps_without_plugin_variable_leaves_the_decks_default(monkeypatch):
    monkeypatch.delenv("SILOKIT_LAMMPS_PLUGIN", raising=False)
    assert "plugin" not in driver.segment_command("lammps", 1, VARIABLES, 2.0)
    # --var plugin=... wins over the environment
    monkeypatch.setenv("SILOKIT_LAMMPS_PLUGIN", "/y.so")
    command = driver.segment_command("lammps", 1, {**VARIABLES, "plugin": "/z.so"}, 2.0)
    assert command.count("plugin") == 1 and command[command.index("plugin") + 1] == "/z.so"


def test_host_switch_parses_and_defaults_to_liggghts():
    base = ["--campaign", "x", "--mu", "0.4", "--arches", "3"]
    assert driver.parse(base).host == "liggghts"
    assert driver.parse(base + ["--host", "lammps", "--nice", "10"]).host == "lammps"
    with pytest.raises(SystemExit):
        driver.parse(base + ["--host", "gromacs"])


def test_a_campaign_keeps_its_host(tmp_path, monkeypatch):
    """host.txt is written on the first call; the other host is refused
    with exit code 2 before anything runs (the binaries here do not run)."""
    for name in ("LAMMPS_BINARY", "LIGGGHTS_BINARY"):
        monkeypatch.setattr(hosts, name, Path("/bin/false"))
    options = ["--campaign", str(tmp_path), "--mu", "0.4", "--arches", "3", "--max-segments", "0"]
    assert driver.main(options + ["--host", "lammps"]) == 0
    assert (tmp_path / "host.txt").read_text() == "lammps\n"
    assert driver.main(options + ["--host", "lammps"]) == 0
    assert driver.main(options) == 2
    assert (tmp_path / "host.txt").read_text() == "lammps\n"
    assert driver.completed_segments(tmp_path / "mu0.4") == []


def test_a_campaign_from_before_the_switch_is_liggghts(tmp_path, monkeypatch):
    """A run with a complete segment and no host.txt was LIGGGHTS' (its
    restart files are): --host lammps must not take it over."""
    run = tmp_path / "mu0.4"
    run.mkdir()
    (run / "segments.txt").write_text(driver.SEGMENTS_HEADER + "\n1 24.98 16 16 459.7 502.6\n")
    monkeypatch.setattr(hosts, "LAMMPS_BINARY", Path("/bin/false"))
    assert driver.main(["--campaign", str(tmp_path), "--mu", "0.4", "--arches", "3",
                        "--host", "lammps"]) == 2
    assert (tmp_path / "host.txt").read_text() == "liggghts\n"
    # an empty campaign directory (no segment yet) is anyone's
    fresh = tmp_path / "fresh"
    (fresh / "mu0.4").mkdir(parents=True)
    (fresh / "mu0.4" / "segments.txt").write_text(driver.SEGMENTS_HEADER + "\n")
    driver.claim_campaign_host(fresh, "lammps")
    assert (fresh / "host.txt").read_text() == "lammps\n"


@needs_lammps[0]
@needs_lammps[1]
def test_a_cut_lammps_campaign_resumed_records_what_an_uncut_one_does(tmp_path):
    """The small silo at dt = 2e-5 s in segments of 2 s in LAMMPS (each
    segment from the LAMMPS restart file of the one before), cut after a
    clog in a resumed segment and called again."""
    environment = dict(os.environ, SILOKIT_LMP=str(LMP), SILOKIT_LAMMPS_PLUGIN=str(PLUGIN),
                       PYTHONPATH=str(ROOT))
    assert_cut_campaign_resumes_as_uncut(tmp_path, environment, CAMPAIGN + ["--host", "lammps", "--nice", "10"])
    for name in ("uncut", "cut"):
        assert (tmp_path / name / "host.txt").read_text() == "lammps\n"
        log = (tmp_path / name / "mu0.4" / "logs" / "segment2.txt").read_text()
        # the deck's own line: the segment ran in LAMMPS
        assert "silo2d: LAMMPS, quick 1" in log
