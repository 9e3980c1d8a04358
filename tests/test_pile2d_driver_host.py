"""analysis.pile2d.driver --host lammps: the command lines it builds for
each host, the campaign's one host, and one small task run in LAMMPS whose
record is LIGGGHTS' line of the same pile in doc/data (on one rank the two
hosts build and discharge the same pile to the bit: doc/pile2d.md, "The
same piles")."""

from pathlib import Path

import pytest

from analysis.common import hosts
from analysis.pile2d import driver
from lammps_host import PLUGIN, ROOT, needs_lammps

SEED = 15485863


def test_lammps_command_takes_the_lammps_deck_binary_and_plugin(monkeypatch):
    monkeypatch.setattr(hosts, "LAMMPS_BINARY", Path("/x/lmp"))
    monkeypatch.setattr(hosts, "LIGGGHTS_BINARY", Path("/x/liggghts"))
    monkeypatch.setenv("SILOKIT_LAMMPS_PLUGIN", "/y/silokit_lammps.so")
    deck = Path("/in") / hosts.deck_name("lammps", "in.build")
    command = hosts.engine_command("lammps", deck, {"model": "fixed", "L": 50.0}, nice=15)
    assert command == ["nice", "-n", "15", "stdbuf", "-oL", "/x/lmp", "-in", "/in/in.build.lammps",
                       "-log", "none", "-var", "model", "fixed", "-var", "L", "50.0",
                       "-var", "plugin", "/y/silokit_lammps.so"]
    # a plugin named by --var wins over the environment
    command = hosts.engine_command("lammps", deck, {"plugin": "/z.so"})
    assert command[-3:] == ["-var", "plugin", "/z.so"] and command.count("plugin") == 1
    # LIGGGHTS: its own binary and deck, no plugin variable, mpirun outside nice's command
    command = hosts.engine_command("liggghts", Path("/in") / hosts.deck_name("liggghts", "in.discharge"),
                                    {"w": 4.2}, mpi=2)
    assert command == ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2", "stdbuf", "-oL",
                       "/x/liggghts", "-in", "/in/in.discharge", "-log", "none", "-var", "w", "4.2"]


def test_lammps_without_plugin_variable_leaves_the_decks_default(monkeypatch):
    monkeypatch.delenv("SILOKIT_LAMMPS_PLUGIN", raising=False)
    command = hosts.engine_command("lammps", Path("in.build.lammps"), {"w": 1})
    assert "plugin" not in command


def test_host_switch_parses_and_defaults_to_liggghts():
    base = ["--campaign", "x", "--L", "20"]
    assert driver.parse(base).host == "liggghts"
    assert driver.parse(base + ["--host", "lammps"]).host == "lammps"
    with pytest.raises(SystemExit):
        driver.parse(base + ["--host", "gromacs"])


def test_a_campaign_keeps_its_host(tmp_path):
    hosts.claim_host(tmp_path, "lammps")
    hosts.claim_host(tmp_path, "lammps")
    assert (tmp_path / "host.txt").read_text() == "lammps\n"
    with pytest.raises(ValueError, match="lammps campaign"):
        hosts.claim_host(tmp_path, "liggghts")
    # the CLI says so and runs nothing
    assert driver.main(["--campaign", str(tmp_path), "--L", "20", "--models", "none",
                        "--seed-list", str(SEED)]) == 2


def test_a_campaign_from_before_the_switch_is_liggghts(tmp_path):
    """A campaign with a built pile and no host.txt was LIGGGHTS' (its
    restart files are): --host lammps must not take it over."""
    (tmp_path / "piles.txt").write_text(driver.PILES_HEADER + "\n"
                                        "fixed 20.0 2 331 14.1 14 350 2.5 3.4 1 25 0.3 0.3 p.restart 0.1 0.05\n")
    assert driver.main(["--host", "lammps", "--campaign", str(tmp_path), "--L", "20", "--models", "fixed",
                        "--seed-list", str(SEED)]) == 2
    assert (tmp_path / "host.txt").read_text() == "liggghts\n"
    # a campaign directory without a pile yet is anyone's
    fresh = tmp_path / "fresh"
    fresh.mkdir()
    (fresh / "piles.txt").write_text(driver.PILES_HEADER + "\n")
    driver.claim_campaign_host(fresh, "lammps")
    assert (fresh / "host.txt").read_text() == "lammps\n"


def liggghts_line(model, length, w, seed):
    for line in (ROOT / "doc" / "data" / "pile2d_discharges.txt").read_text().splitlines():
        words = line.split()
        if words[:4] == [model, f"{length:.1f}", f"{w:.1f}", str(seed)]:
            return words
    raise AssertionError(f"no LIGGGHTS line for {model} {length} {w} {seed}")


@needs_lammps[0]
@needs_lammps[1]
def test_lammps_task_builds_and_discharges_liggghts_pile(tmp_path, monkeypatch):
    """One task (model fixed, L = 20 d, the ensemble's first seed, w = 1 d
    and 6.2 d: a jam and a collapse) in LAMMPS: the record lines are LIGGGHTS'
    lines of doc/data/pile2d_discharges.txt, text for text."""
    monkeypatch.setenv("SILOKIT_LAMMPS_PLUGIN", str(PLUGIN))
    out = tmp_path / "campaign"
    assert driver.main(["--host", "lammps", "--campaign", str(out), "--models", "fixed", "--L", "20",
                        "--seed-list", str(SEED), "--widths", "1", "6.2", "--nice", "15"]) == 0
    lines = [line.split() for line in (out / "discharges.txt").read_text().splitlines()]
    assert lines[0] == driver.DISCHARGES_HEADER.split()
    assert lines[1:] == [liggghts_line("fixed", 20, 1.0, SEED), liggghts_line("fixed", 20, 6.2, SEED)]
    assert (out / "piles" / f"fixed_L20_s{SEED}.restart").exists()
    assert (out / "host.txt").read_text() == "lammps\n"
    # resumable in LAMMPS as in LIGGGHTS: nothing left to run
    runner = driver.Runner(driver.parse(["--host", "lammps", "--campaign", str(out), "--models", "fixed",
                                         "--L", "20", "--seed-list", str(SEED), "--widths", "1", "6.2"]))
    assert runner.run() == [] and runner.total == 0
