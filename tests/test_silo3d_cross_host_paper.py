"""bench/silo3d_cross_host_paper.py without an engine: what a rerun of an
interrupted campaign runs again, keeps or copies (fake run directories),
and the report's numbers from hand-made records of known flow rates."""

import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "bench"))
import silo3d_cross_host_paper as driver  # noqa: E402

MASS = 3.15e-4


def write_run(directory, seed, f, finished=True, discharge_time=2.0, N=10000, D=0.06):
    directory.mkdir(parents=True, exist_ok=True)
    lines = ["d 0.0099", "rho 620", f"mass {MASS}", "g 9.8", "Dc 0.19", f"D {D}", f"f {f:g}",
             f"seed {seed}", f"N {N}", "dt 3.9e-06", "t_open 0", "reinject 1",
             f"discharge_time {discharge_time}", "step_open 0"]
    if finished:
        lines.append(f"finished {discharge_time}")
    (directory / "run.txt").write_text("\n".join(lines) + "\n")


def names(runs):
    return [run.name(driver.PAPER) for run in runs]


def test_a_rerun_keeps_finished_runs_and_starts_the_others_again(tmp_path):
    campaign, records = tmp_path / "campaign", tmp_path / "records"
    runs = driver.campaign_runs([11, 13], [0.0, 0.32])
    # seed 11, LIGGGHTS: f = 0 archived, 0.32 finished but not archived
    # (the driver stopped between the run and the copy), its packing ready
    write_run(records / "liggghts_D0.06_f0_s11", 11, 0.0)
    write_run(campaign / "liggghts_D0.06_f0.32_s11", 11, 0.32)
    write_run(campaign / "liggghts_packing_s11", 11, 0.0)
    (campaign / "liggghts_packing_s11" / "packing.restart").write_text("restart")
    # seed 11, LAMMPS: the settling was interrupted, f = 0 never finished
    write_run(campaign / "lammps_packing_s11", 11, 0.0, finished=False)
    write_run(campaign / "lammps_D0.06_f0_s11", 11, 0.0, finished=False)
    # seed 13, LIGGGHTS: both archived, the campaign directory gone
    write_run(records / "liggghts_D0.06_f0_s13", 13, 0.0)
    write_run(records / "liggghts_D0.06_f0.32_s13", 13, 0.32)
    # seed 13, LAMMPS: a finished settling whose packing file is gone
    write_run(campaign / "lammps_packing_s13", 13, 0.0)
    write_run(records / "lammps_packing_s13", 13, 0.0)
    # an archive cut short by an interruption does not count
    write_run(records / "lammps_D0.06_f0_s13.part", 13, 0.0)

    to_run, to_copy, done = driver.plan(runs, driver.PAPER, campaign, records)

    assert names(to_run) == ["lammps_packing_s11", "lammps_D0.06_f0_s11", "lammps_D0.06_f0.32_s11",
                             "lammps_packing_s13", "lammps_D0.06_f0_s13", "lammps_D0.06_f0.32_s13"]
    assert names(to_copy) == ["liggghts_packing_s11", "liggghts_D0.06_f0.32_s11"]
    assert names(done) == ["liggghts_D0.06_f0_s11", "liggghts_D0.06_f0_s13", "liggghts_D0.06_f0.32_s13",
                           "lammps_packing_s13"]


def test_the_copy_is_whole_and_leaves_the_packing_file(tmp_path):
    campaign, records = tmp_path / "campaign", tmp_path / "records"
    run, packing = driver.Run("lammps", 11, 0.32), driver.Run("lammps", 11)
    write_run(campaign / run.name(driver.PAPER), 11, 0.32)
    (campaign / run.name(driver.PAPER) / "discharge.txt").write_text("# step t n_out mass_out\n0 0 0 0\n")
    (campaign / run.name(driver.PAPER) / "screen.txt").write_text("screen")
    write_run(campaign / packing.name(driver.PAPER), 11, 0.0)
    (campaign / packing.name(driver.PAPER) / "discharge.txt").write_text("# step t n_out mass_out\n")
    (campaign / packing.name(driver.PAPER) / "packing.restart").write_text("restart")
    for each in (run, packing):
        driver.copy_records(each, driver.PAPER, campaign, records)
    assert sorted(p.name for p in (records / run.name(driver.PAPER)).iterdir()) == ["discharge.txt", "run.txt"]
    assert sorted(p.name for p in (records / packing.name(driver.PAPER)).iterdir()) == ["run.txt"]
    assert not list(records.glob("*.part"))


def test_a_finished_run_of_another_protocol_is_refused(tmp_path):
    records = tmp_path / "records"
    run = driver.Run("liggghts", 11, 0.0)
    write_run(records / run.name(driver.PAPER), 11, 0.0, discharge_time=1.0)
    with pytest.raises(SystemExit, match="discharge_time"):
        driver.check_protocol(run, driver.PAPER, records / run.name(driver.PAPER))


def write_flow(directory, seed, f, host, q, cpu):
    """Records of a run whose discharged mass grows at exactly q kg/s."""
    write_run(directory, seed, f)
    t = np.arange(0.0, 2.0 + 1e-9, 0.01)
    rows = [f"{k} {time:.2f} {q * time / MASS:.6f} {q * time:.9f}" for k, time in enumerate(t)]
    (directory / "discharge.txt").write_text("# step t n_out mass_out\n" + "\n".join(rows) + "\n")
    (directory / "cost.txt").write_text(f"cpu_seconds {cpu}\nwall_seconds {cpu + 1}\nbinary build/bin/{host} abc\n")


def test_the_report_of_known_flow_rates(tmp_path):
    records = tmp_path / "records"
    flows = {"liggghts": (0.10, 0.11, 0.12), "lammps": (0.13, 0.14, 0.15)}
    for host, rates in flows.items():
        for seed, q in zip((11, 13, 17), rates):
            write_flow(records / f"{host}_D0.06_f0_s{seed}", seed, 0.0, host, q, cpu=600)
    # an archive cut short by an interruption is no run
    write_flow(records / "liggghts_D0.06_f0_s23.part", 23, 0.0, "liggghts", 0.5, cpu=600)
    # a run the deck stopped at a clog at rest has no Q over the window
    clogged = records / "liggghts_D0.06_f0_s19"
    write_flow(clogged, 19, 0.0, "liggghts", 0.2, cpu=600)
    with open(clogged / "run.txt", "a") as run_txt:
        run_txt.write("clogged 0.85\n")
    runs = driver.campaign_runs([11, 13, 17, 19], [0.0])
    text = driver.report(driver.read_records(records, 0.5), runs, driver.PAPER, records)
    # mean 0.11, sd 0.01, t(0.975, 2) = 4.303: ± 0.0248
    assert "| LIGGGHTS | 0 | 3 | 0.1100 ± 0.0248 | 0.0100 |" in text
    assert "| LAMMPS | 0 | 3 | 0.1400 ± 0.0248 | 0.0100 |" in text
    # Welch: equal variances 1e-4/3 each, dof 4, t = 2.776, half width
    # 2.776 sqrt(2e-4/3) = 0.0227: the 0.03 apart are outside it
    assert "LAMMPS − LIGGGHTS = +0.0300 ± 0.0227 kg/s" in text
    assert "differ by more than the interval" in text
    assert "7 of the 8 discharges asked for are finished; missing: lammps_D0.06_f0_s19." in text
    assert "| liggghts_D0.06_f0_s19 | clogged at rest at t = 0.85 s |" in text
    assert "| LIGGGHTS | — (0) | 600 (4) | 601 | 2400 s = 0.67 h |" in text
