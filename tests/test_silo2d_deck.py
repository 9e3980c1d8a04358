"""The production deck inputs/silo2d/in.silo2d in its quick variant (12 d
wide, 230 grains, dt = t_c/24.5): it fills, flows, clogs, breaks its arches
and writes at least 3 of them; the records are checked against each other
and against geometry recomputed here (members in contact along the walk,
phi from the members' positions, per-grain forces from the contact table),
and the analysis CLI runs on them."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from analysis.common.tables import read_table
from conftest import has_mpirun, run_liggghts

ROOT = Path(__file__).resolve().parent.parent
D = 1.0 / 32
N_TOTAL = 312           # 230 free grains + 82 fixed grains of the quick silo


def run_quick_deck(workdir, nprocs=1, **variables):
    deck = (ROOT / "inputs" / "silo2d" / "in.silo2d").read_text()
    options = {"quick": 1, "inputs": ROOT / "inputs", **variables}
    return run_liggghts(deck, workdir, nprocs=nprocs, variables=options, timeout=900)


def lower_side_phi(previous, at, following):
    a = math.atan2(previous[1] - at[1], previous[0] - at[0])
    b = math.atan2(following[1] - at[1], following[0] - at[0])
    return math.degrees(b - a) % 360.0


def check_records(workdir):
    clogs = read_table(workdir / "clogs.txt")
    arches = read_table(workdir / "arches.txt")
    contacts = read_table(workdir / "contacts.txt")
    assert list(clogs["clog"]) == list(range(1, clogs["clog"].size + 1))
    found = clogs["clog"][clogs["status"] == 1]
    for clog, eta in zip(clogs["clog"], clogs["eta"]):
        rows = arches["clog"] == clog
        assert rows.sum() == eta
        assert list(arches["order"][rows]) == list(range(1, int(eta) + 1))
    for clog in found:
        rows = arches["clog"] == clog
        ids = arches["id"][rows].astype(int)
        here = contacts["clog"] == clog
        pairs = {(int(a), int(b)): k for k, (a, b) in
                 enumerate(zip(contacts["id1"][here], contacts["id2"][here]))}
        # consecutive members touch, and their contact carries the arch flag
        for a, b in zip(ids[:-1], ids[1:]):
            key = (min(a, b), max(a, b))
            assert key in pairs
            assert contacts["arch"][here][pairs[key]] == 1
        # phi of the inner members, from their neighbours' centres
        points = list(zip(arches["x"][rows], arches["z"][rows]))
        for k in range(1, len(points) - 1):
            assert arches["phi"][rows][k] == pytest.approx(
                lower_side_phi(points[k - 1], points[k], points[k + 1]), abs=1e-6)
        # each member's fn/ft: the mean over its contacts in contacts.txt
        for k, grain in enumerate(ids):
            own = here & ((contacts["id1"] == grain) | (contacts["id2"] == grain))
            assert arches["fn"][rows][k] == pytest.approx(contacts["fn"][own].mean(), rel=1e-8)
            assert arches["ft"][rows][k] == pytest.approx(contacts["ft"][own].mean(), rel=1e-8, abs=1e-12)
        # an arch carries load: every member is pressed by at least two grains
        for grain in ids:
            own = here & ((contacts["id1"] == grain) | (contacts["id2"] == grain))
            assert own.sum() >= 2 and np.all(contacts["fn"][own] > 0.0)
    return clogs, arches, contacts


def check_quick_run(workdir, output):
    """A finished quick run of either host's deck (its records in workdir,
    its screen output): the records hold together (check_records), at
    least 3 arches, a constant atom count, the avalanches within the grains
    counted out, silo.txt as the analysis needs it, and analysis.silo2d
    runs on them. Returns the clogs table and the analysis' directory."""
    clogs, _, _ = check_records(workdir)
    assert (clogs["status"] == 1).sum() >= 3
    assert "silo2d: done after" in output
    # the number of atoms never changes (thermo_modify lost error would stop the run)
    atoms = [int(line.split()[2]) for line in output.splitlines()
             if line.split()[:1] and line.split()[0].isdigit() and len(line.split()) >= 9]
    assert atoms and set(atoms) == {N_TOTAL}
    # avalanche sizes add up to the grains counted out by fix reinject
    out = read_table(workdir / "reinject.txt")
    assert clogs["avalanche"].sum() <= out["n_out"][-1]
    # silo.txt carries what the analysis needs
    silo = dict(line.split()[:2] for line in (workdir / "silo.txt").read_text().splitlines()
                if line and not line.startswith("#"))
    assert float(silo["d"]) == pytest.approx(D) and float(silo["mu"]) == 0.4

    analysis = subprocess.run([sys.executable, "-m", "analysis.silo2d", str(workdir),
                               "--bulk", "8", "14", "--out", str(workdir / "analysis")],
                              cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert analysis.returncode == 0, analysis.stderr
    assert (workdir / "analysis" / "table1.md").exists()
    return clogs, workdir / "analysis"


@pytest.mark.engine
def test_quick_deck_clogs_three_times(tmp_path):
    _, analysis = check_quick_run(tmp_path, run_quick_deck(tmp_path))
    assert len(list(analysis.glob("*.png"))) == 7


@pytest.mark.engine
@pytest.mark.skipif(not has_mpirun(), reason="needs mpirun")
def test_quick_deck_on_two_ranks(tmp_path):
    """Two ranks: the flow differs (chaotic), the records must hold together."""
    run_quick_deck(tmp_path, nprocs=2, narches=2)
    clogs, _, _ = check_records(tmp_path)
    assert (clogs["status"] == 1).sum() >= 2


@pytest.mark.engine
def test_stop_at_first_leaves_the_clogged_silo_for_a_picture(tmp_path):
    """-var stop_at_first 1: the deck stops at its first clog and dumps the
    grains; the silo stands still, so the arch members in the dump are where
    arches.txt recorded them at the clog, and the picture is drawn."""
    output = run_quick_deck(tmp_path, stop_at_first=1)
    assert "silo2d: done after 1 clogs" in output
    clogs, arches, _ = check_records(tmp_path)
    from analysis.common.lammps_io import read_dump
    _, grains = read_dump(tmp_path / "clog_state.dump")[-1]
    assert grains["id"].size == N_TOTAL
    where = {int(i): (x, z) for i, x, z in zip(grains["id"], grains["x"], grains["z"])}
    for member, x, z in zip(arches["id"], arches["x"], arches["z"]):
        assert math.hypot(where[int(member)][0] - x, where[int(member)][1] - z) < 1e-3 * D
    picture = subprocess.run([sys.executable, "-m", "analysis.silo2d.picture", str(tmp_path),
                              "--figure", str(tmp_path / "arch.png")],
                             cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert picture.returncode == 0, picture.stderr
    assert (tmp_path / "arch.png").stat().st_size > 10000


def test_picture_force_segments_join_known_grains():
    from analysis.silo2d.picture import force_segments, window_mask
    contacts = {"clog": np.array([1, 1, 1, 2]), "id1": np.array([1, 1, 2, 1]),
                "id2": np.array([2, 9, 3, 2]), "fn": np.array([5.0, 6.0, 7.0, 8.0])}
    positions = {1: (0.0, 0.0), 2: (1.0, 0.0), 3: (1.0, 1.0)}
    # contact 1-9: grain 9 unknown, left out; clog 2 not asked for
    assert force_segments(contacts, 1, positions) == [(0.0, 0.0, 1.0, 0.0, 5.0), (1.0, 0.0, 1.0, 1.0, 7.0)]
    assert list(window_mask(np.array([-2.0, 0.5, 3.0]), np.array([1.0, 4.0, 1.0]), 2.0, 3.0)) == [True, False, False]


@pytest.mark.engine
def test_a_clog_the_deck_calls_at_rest_stays_at_rest(tmp_path):
    """The silo the deck declares clogged (Ec/Ep < 1e-4 after 0.2 s without
    an exit) is run on for 1 s (1e5 steps): no grain leaves, the arch and
    its feet stay where they were recorded (measured: 3e-6 d), and no grain
    below the top 2 d of the column moves by a tenth of a diameter
    (measured: 0.05 d at most), so the arch recorded is the one that holds
    the silo, not a passing one. Grains of the free surface may still roll
    into place (one rolled 1.1 d): Ec/Ep < 1e-4 is a global criterion, the
    paper's."""
    deck = f"""
variable quick index 1
variable stop_at_first index 1
variable inputs index {ROOT / 'inputs'}
include {ROOT / 'inputs' / 'silo2d' / 'in.silo2d'}
variable out_at_clog equal f_reinject[1]
print "grains out at the clog: ${{out_at_clog}}"
write_dump all custom at_clog.dump id x z
run 100000
variable out_after equal f_reinject[1]
print "grains out 1 s later: ${{out_after}}"
write_dump all custom after.dump id x z
"""
    output = run_liggghts(deck, tmp_path, timeout=900)
    outs = [line.split(":")[1].strip() for line in output.splitlines() if line.startswith("grains out")]
    assert len(outs) == 2 and outs[0] == outs[1]
    from analysis.common.lammps_io import read_dump
    before, after = (read_dump(tmp_path / name)[-1][1] for name in ("at_clog.dump", "after.dump"))
    start = {int(i): (x, z) for i, x, z in zip(before["id"], before["x"], before["z"])}
    free = np.abs(before["x"]) < 6 * D          # inside the side walls of the quick silo
    surface = before["z"][free].max()
    moved = {int(i): math.hypot(x - start[int(i)][0], z - start[int(i)][1]) / D
             for i, x, z in zip(after["id"], after["x"], after["z"])}
    held = list(read_table(tmp_path / "arches.txt")["id"]) + list(read_table(tmp_path / "feet.txt")["id"])
    assert len(held) >= 3
    assert max(moved[int(i)] for i in held) < 1e-3
    buried = [int(i) for i, z in zip(before["id"], before["z"]) if z < surface - 2 * D]
    assert len(buried) > 150
    assert max(moved[i] for i in buried) < 0.1
