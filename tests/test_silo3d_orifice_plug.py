"""The grains over the orifice against the bottom's rotation
(analysis.silo3d_rotating.orifice_plug), on a hand-built run at f = 0.5 Hz: a plug
over the orifice turning rigidly at 0.3 of the bottom's angular speed,
whose grains stay for the first frames and are then replaced a quarter
at a time, falling faster frame by frame; a ring of grains on the plate
turning at 0.6; grains outside both regions that must not count."""

import math

import numpy as np
import pytest

from analysis.silo3d_rotating import orifice_plug as plug
from analysis.common.tables import read_table
from test_silo3d_acceleration import dump_frame, write_run_records

DT = 1e-5
T_OPEN = 0.1
F = 0.5
OMEGA = 2 * math.pi * F
FRAMES = np.arange(0, 8) * 0.05     # s since the opening


def grain(i, r, angle, z, turn, vz=0.0):
    """A dump row: at (r, angle, z), moving azimuthally at turn * OMEGA * r."""
    speed = turn * OMEGA * r
    x, y = r * math.cos(angle), r * math.sin(angle)
    vx, vy = -speed * math.sin(angle), speed * math.cos(angle)
    return f"{i} 1 {x:.17g} {y:.17g} {z:.17g} {vx:.17g} {vy:.17g} {vz:.17g} 0.003 3e-4\n"


def write_run(directory):
    """8 grains over the orifice (r = 1 cm, z = 1 cm, v_z = -0.01 (k + 1)
    m/s in the k-th frame),
    ids 1-8 up to the 4th frame (tau = 0.15 s), then two of them replaced
    by new ids in each frame to the last (all 8 new); 12 on the plate at r = 5 cm, z = 5 mm; one at
    r = 1 cm but z = 3 cm (above the region), one at r = 5 cm, z = 2 cm
    (above the plate), one at r = 8 cm on the plate (outside the ring)."""
    directory.mkdir(parents=True)
    write_run_records(directory, F, 23, FRAMES[-1], t_open=T_OPEN, dt=DT)
    with open(directory / "dump.cg", "w") as dump:
        for k, tau in enumerate(FRAMES):
            replaced = 2 * max(0, k - 3)            # from the 5th frame on, two more new ids each frame
            over = [grain(100 + j if j < replaced else j + 1, 0.01, 0.3 * OMEGA * tau + j * math.pi / 4, 0.01,
                          0.3, vz=-0.01 * (k + 1)) for j in range(8)]
            ring = [grain(20 + j, 0.05, 0.6 * OMEGA * tau + j * math.pi / 6, 0.005, 0.6) for j in range(12)]
            others = [grain(40, 0.01, 0.0, 0.03, 1.0), grain(41, 0.05, 0.0, 0.02, 1.0), grain(42, 0.08, 0.0, 0.005, 1.0)]
            rows = over + ring + others
            dump.write(dump_frame(tau, rows, t_open=T_OPEN, dt=DT))
    return directory


def test_a_plug_turning_slower_than_the_plate_ring_and_then_renewed(tmp_path, capsys):
    run = write_run(tmp_path / "run")
    out = tmp_path / "out"
    assert plug.main([str(run), "--window", "0", "0.15", "--window", "0.2", "0.35", "--blocks", "2",
                      "--out", str(out)]) == 0
    frames = read_table(out / "orifice_plug.txt")
    assert frames["t"] == pytest.approx(FRAMES, abs=1e-9)
    assert np.all(frames["n_over"] == 8) and np.all(frames["n_ring"] == 12)
    assert frames["turn_over"] == pytest.approx(np.full(8, 0.3), rel=1e-9)
    assert frames["turn_ring"] == pytest.approx(np.full(8, 0.6), rel=1e-9)
    assert frames["vz_over"] == pytest.approx(-0.01 * np.arange(1, 9), rel=1e-9)
    # stayed: none before the first frame; all up to 0.15 s; then 6 of
    # the 8 of the frame before (two replaced each frame)
    assert math.isnan(frames["stayed"][0])
    assert frames["stayed"][1:] == pytest.approx([1, 1, 1, 0.75, 0.75, 0.75, 0.75])
    windows = read_table(out / "orifice_plug_windows.txt")
    assert windows["frames"].tolist() == [4, 4]
    assert windows["stayed"] == pytest.approx([1.0, 0.75]) and windows["stayed_se"] == pytest.approx([0.0, 0.0])
    # a grain stays 0.05 s / (1 - 0.75) = 0.2 s in the second window; for ever in the first
    assert windows["residence"] == pytest.approx([math.inf, 0.2])
    # v_z of the second window's frames: -0.05 ... -0.08; two blocks of
    # two frames, means -0.055 and -0.075, std(ddof=1) 0.02/sqrt(2), over
    # sqrt(2): 0.01 (over single frames it would be 0.0065)
    assert windows["vz_over"] == pytest.approx([-0.025, -0.065], rel=1e-9)
    assert windows["vz_over_se"][1] == pytest.approx(0.01, rel=1e-9)
    # blocks of 0.075 s: both windows' grains stay longer, and it is said
    said = capsys.readouterr().out
    assert "0-0.15 s: the grains stay over the orifice inf s" in said
    assert "0.2-0.35 s: the grains stay over the orifice 0.2 s" in said and "understate" in said
    assert windows["turn_over"] == pytest.approx([0.3, 0.3], rel=1e-9)
    assert windows["turn_ring"] == pytest.approx([0.6, 0.6], rel=1e-9)


@pytest.mark.parametrize("change, message", [
    ({"f": "0"}, "at rest there is no bottom speed"),
    ({"window": ["0.3", "0.2"]}, "the end must be after the start"),
    ({"window": ["5", "6"]}, "no dump frame in the windows"),
    ({"blocks": "1"}, "needs at least 2 blocks"),
])
def test_what_it_cannot_measure_is_refused(tmp_path, capsys, change, message):
    run = write_run(tmp_path / "run")
    if "f" in change:
        text = (run / "run.txt").read_text().replace(f"f {F}\n", f"f {change['f']}\n")
        (run / "run.txt").write_text(text)
    window = change.get("window", ["0", "0.1"])
    with pytest.raises(SystemExit) as stop:
        plug.main([str(run), "--window", *window, "--blocks", change.get("blocks", "2"), "--out", str(tmp_path / "out")])
    assert stop.value.code == 2 and message in capsys.readouterr().err


def test_a_window_with_no_frame_before_has_no_residence():
    """The first frame has no `stayed` (no frame before): a window holding
    only it has an unknown residence, not an infinite one; a window where
    every grain stayed has an infinite one."""
    rows = np.array([[0.0, 8, np.nan, -0.1, 0.3, 12, 0.6],
                     [0.05, 8, 1.0, -0.1, 0.3, 12, 0.6]])
    assert math.isnan(plug.window_means(rows, 0.0, 0.01)[3])
    assert plug.window_means(rows, 0.04, 0.06)[3] == math.inf
