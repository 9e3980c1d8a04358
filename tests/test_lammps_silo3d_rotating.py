"""The rotating-bottom silo deck for LAMMPS (inputs/silo3d_rotating/
in.silo3d_rotating.lammps, doc/silo3d_rotating.md "LAMMPS"), run by our
lmp with the plugin on the quick silo made smaller and shorter (N, the
settling and the discharge cut by -var), so that each run takes seconds:

- the closed bottom holds while the silo settles (no grain below the
  plate, none lost), and grains flow out only after t_open;
- run.txt and discharge.txt read with analysis.silo3d_rotating's reader,
  and the analysis' command line runs on the run directory; the records
  agree with each other (mass_out = n_out m, with mass_out taken from the
  grains' total mass, not from n_out) and with the deck's parameters;
- it runs on 2 ranks, with the same flow rate within the errors (the
  gas's velocities are drawn per rank: another realisation of the silo);
- a packing written once is read back and discharged, turning;
- stop_fraction ends the run early (fix halt);
- bad switches stop it with an ERROR naming them;
- with `reinject 1` every grain stays; at rest a clog stops the run
  (fix halt), a turning bottom runs on.
"""

import math
import re
import subprocess
import sys

import numpy as np
import pytest

from analysis.silo3d_rotating.flow import stationary_flow_rate
from analysis.silo3d_rotating.records import RUN_KEYS, read_discharge, read_run_info
from analysis.testing import LiggghtsError
from lammps_host import ROOT, has_mpirun, needs_lammps, run_lammps

pytestmark = needs_lammps

DECK = ROOT / "inputs" / "silo3d_rotating" / "in.silo3d_rotating.lammps"
D_GRAIN = 0.0099
MASS = 620.0 * math.pi / 6.0 * D_GRAIN ** 3
# the quick silo (Dc = 12 d, D = 5 d, t_c/40) with 400 grains: a bed of
# about 3 d, settled in 0.2 s, discharged for 0.2 s
SMALL = {"quick": 1, "N": 400, "settle_time": 0.2, "discharge_time": 0.2}
SKIP_AFTER_OPEN = 0.05         # s: the start-up of the flow is left out of Q


def deck(**variables):
    lines = [f"variable {name} index {value}" for name, value in variables.items()]
    lines += [f"variable inputs index {ROOT / 'inputs'}", f"include {DECK}"]
    return "\n".join(lines) + "\n"


def small_deck(**variables):
    return deck(**{**SMALL, **variables})


def thermo_rows(output, columns):
    """The thermo rows with `columns` numbers, as float arrays: the
    settling's (step t atoms ke zmin: 5) or the discharge's (step t atoms
    ke n_out mass_out Q: 7)."""
    rows = []
    for line in output.splitlines():
        words = line.split()
        if len(words) != columns or not words[0].isdigit():
            continue
        try:
            rows.append([float(word) for word in words])
        except ValueError:
            continue
    return np.array(rows)


def ranks(output):
    grid = re.search(r"(\d+) by (\d+) by (\d+) MPI processor grid", output)
    return math.prod(int(n) for n in grid.groups())


def flow_rate(record, t_open):
    flow = stationary_flow_rate(record["t"], record["n_out"], record["mass_out"],
                                t_open + SKIP_AFTER_OPEN, record["t"][-1])
    return flow.q_mass, flow.q_mass_se


@pytest.fixture(scope="module")
def serial_run(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("lammps_silo3d_serial")
    run = run_lammps(small_deck(write_packing=1), workdir)
    return workdir, run.output


def test_the_closed_bottom_holds_while_settling(serial_run):
    workdir, output = serial_run
    t_open = read_run_info(workdir)["t_open"]
    settling = thermo_rows(output, 5)
    assert len(settling) >= 4 and settling[-1, 1] == pytest.approx(t_open, rel=1e-7)
    # every grain in the box, and none below the plate: a grain resting
    # on it has its centre at r less an overlap of microns (the weight of
    # the column above it over kn)
    assert np.all(settling[:, 2] == SMALL["N"])
    assert np.all(settling[:, 4] > 0.45 * D_GRAIN)
    # the gas has landed: the lowest grain touches the plate at the end
    assert settling[-1, 4] == pytest.approx(D_GRAIN / 2, abs=0.01 * D_GRAIN)


def test_grains_flow_out_after_the_opening_and_not_before(serial_run):
    workdir, output = serial_run
    info = read_run_info(workdir)
    record = read_discharge(workdir)
    t_open = info["t_open"]
    # rows on whole multiples of the record interval, as in LIGGGHTS: the
    # first within 0.01 s of the opening
    assert 0 <= record["t"][0] - t_open < 0.0101
    assert record["n_out"][0] == 0
    # the first grain is out of the box (6 d below the plate) after it
    # has fallen 5.5 d from rest at least: sqrt(2 5.5 d / g) = 0.1 s
    first_out = record["t"][np.flatnonzero(record["n_out"] > 0)[0]]
    assert first_out - t_open > math.sqrt(2 * 5.5 * D_GRAIN / 9.8) - 0.01
    assert np.all(np.diff(record["n_out"]) >= 0)
    assert record["n_out"][-1] > 20
    discharging = thermo_rows(output, 7)
    assert discharging[-1, 2] == SMALL["N"] - record["n_out"][-1]


def test_records_read_with_the_analysis_and_agree(serial_run, tmp_path):
    workdir, output = serial_run
    info = read_run_info(workdir, required=RUN_KEYS)
    assert info["host"] == "lammps" and info["shape"] == "sphere"
    assert info["N"] == SMALL["N"] and info["D"] == 0.05 and info["f"] == 0
    assert info["Dc"] == 0.1188 and info["reinject"] == 0
    assert info["mass"] == pytest.approx(MASS, rel=1e-12)
    # dt = t_c/40 with the contact time of derived.in's kn and gamman
    kn = 2e5 * MASS * 9.8 / D_GRAIN
    gamman = math.sqrt(2 * kn * MASS / ((math.pi / math.log(0.9)) ** 2 + 1))
    meff = MASS / 2
    t_c = math.pi / math.sqrt(kn / meff - (gamman / (2 * meff)) ** 2)
    assert info["dt"] == pytest.approx(t_c / 40, rel=1e-12)
    assert info["finished"] == pytest.approx(info["t_open"] + SMALL["discharge_time"], abs=info["dt"])
    record = read_discharge(workdir)
    spacing = np.diff(record["t"])
    assert np.allclose(spacing, 0.01, rtol=0.01)
    assert record["t"][-1] == pytest.approx(info["t_open"] + SMALL["discharge_time"], abs=0.011)
    # mass_out is the fall of the grains' total mass (mass(all)) since
    # the opening, counted apart from n_out
    np.testing.assert_allclose(record["mass_out"], record["n_out"] * MASS, rtol=1e-9, atol=1e-12)
    out = tmp_path / "analysis"
    result = subprocess.run([sys.executable, "-m", "analysis.silo3d_rotating", str(workdir), "--out", str(out),
                             "--transient", str(SKIP_AFTER_OPEN), "--no-fields"],
                            cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr
    assert re.search(r": Q = [0-9.]+ \+- ", result.stdout), result.stdout
    assert (out / "runs").is_dir()


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_give_the_same_flow_rate(serial_run, tmp_path):
    workdir, _ = serial_run
    run = run_lammps(small_deck(), tmp_path, nprocs=2)
    assert ranks(run.output) == 2
    info = read_run_info(tmp_path)
    assert info["N"] == SMALL["N"] and "finished" in info
    q1, s1 = flow_rate(read_discharge(workdir), info["t_open"])
    q2, s2 = flow_rate(read_discharge(tmp_path), info["t_open"])
    print(f"np 1: Q = {q1:.4f} +- {s1:.4f}, np 2: Q = {q2:.4f} +- {s2:.4f} kg/s")
    assert q1 > 0 and q2 > 0
    assert abs(q1 - q2) < 3.0 * math.hypot(s1, s2)


def test_a_packing_read_back_opens_at_once_and_turns(serial_run, tmp_path):
    workdir, _ = serial_run
    packing = workdir / "packing.restart"
    assert packing.exists()
    run = run_lammps(small_deck(read_packing=1, packing=packing, f=1.28, discharge_time=0.15,
                                dump_every_time=0.05), tmp_path)
    info = read_run_info(tmp_path)
    assert info["t_open"] == 0 and info["f"] == 1.28 and info["N"] == SMALL["N"]
    assert "finished" in info
    record = read_discharge(tmp_path)
    assert record["t"][0] < 0.0101 and record["n_out"][0] == 0 and record["n_out"][-1] > 10
    # the plate turns from the start (its clock came with the packing):
    # the grains on it, outside the hole, are dragged about +z
    frame = run.frame("dump.cg")
    x, y, z = frame["x"], frame["y"], frame["z"]
    on_plate = (z < 0.6 * D_GRAIN) & (np.hypot(x, y) > 0.025 + D_GRAIN / 2)
    v_azimuthal = (x * frame["vy"] - y * frame["vx"]) / np.hypot(x, y)
    assert on_plate.sum() > 20
    assert np.mean(v_azimuthal[on_plate]) > 0.05


def test_stop_fraction_ends_the_run_early(tmp_path):
    # 10 grains out of 400: the run halts at the first record after that
    run = run_lammps(small_deck(stop_fraction=0.025, discharge_time=0.6), tmp_path)
    info = read_run_info(tmp_path)
    record = read_discharge(tmp_path)
    assert record["n_out"][-1] >= 10 and record["n_out"][-2] < 10
    assert info["finished"] == pytest.approx(record["t"][-1], abs=1e-9)
    assert info["finished"] < info["t_open"] + 0.6 - 0.05
    assert "Fix halt condition" in run.output


@pytest.mark.parametrize("name, value, says", [
    ("shape", "rod", "shape is sphere in LAMMPS, not rod"),
    ("aspect", "3.3", "aspect (3.3) is a rods variable"),
    ("mesh_bottom", "1", "mesh_bottom has no meaning in LAMMPS"),
    ("plane_bottom", "1", "plane_bottom has no meaning in LAMMPS"),
    ("vtk_every", "1000", "vtk_every has no meaning in LAMMPS"),
    ("write_poses", "1", "write_poses has no meaning in LAMMPS"),
    ("resume", "1", "resume has no meaning in LAMMPS"),
    ("reinject", "2", "reinject is 0 or 1, not 2"),
    ("clog_stop", "0.5", "clog_stop is 0 or 1, not 0.5"),
])
def test_bad_switches_stop_with_an_error_naming_them(tmp_path, name, value, says):
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(small_deck(**{name: value}), tmp_path)
    assert caught.value.message.startswith("ERROR: in.silo3d_rotating.lammps: " + says)
    assert "create_box" not in caught.value.output.split("ERROR: in.silo3d_rotating.lammps")[0]


def skip_without_reinject(workdir):
    """The reinjection tests need fix reinject in the plugin."""
    styles = run_lammps("plugin load ${plugin}\nplugin list\n", workdir).output
    if "fix style plugin reinject" not in styles:
        pytest.skip("fix reinject is not in the LAMMPS plugin")


def test_with_reinjection_every_grain_stays(tmp_path):
    skip_without_reinject(tmp_path / "styles")
    run = run_lammps(small_deck(reinject=1, f=1.28), tmp_path)
    info = read_run_info(tmp_path)
    record = read_discharge(tmp_path)
    assert info["reinject"] == 1 and "finished" in info
    assert record["n_out"][-1] > 20
    np.testing.assert_allclose(record["mass_out"], record["n_out"] * MASS, rtol=1e-9)
    atoms = thermo_rows(run.output, 7)[:, 2]
    assert np.all(atoms == SMALL["N"])


@pytest.mark.parametrize("f, clogs", [(0.0, True), (0.32, False)])
def test_a_clog_at_rest_stops_the_run_and_a_turning_bottom_runs_on(tmp_path, f, clogs):
    # a bottom without a hole (D = 0): no grain ever leaves. At rest, with
    # reinjection, the run stops once none has left for 0.5 s (and not
    # before 0.6 s after the opening); a turning bottom may break an arch
    # and runs to the end
    skip_without_reinject(tmp_path / "styles")
    run_lammps(small_deck(N=150, settle_time=0.15, reinject=1, D=0.0, f=f, discharge_time=0.8), tmp_path)
    info = read_run_info(tmp_path)
    record = read_discharge(tmp_path)
    assert np.all(record["n_out"] == 0)
    assert ("clogged" in info) == clogs
    end = info["finished"] - info["t_open"]
    if clogs:
        assert info["clogged"] == info["finished"]
        assert 0.6 < end <= 0.6 + 0.0101
    else:
        assert end == pytest.approx(0.8, abs=info["dt"])
