"""The vertical acceleration along the silo's axis (analysis.silo3d_rotating.acceleration,
the paper's Fig. 10): on hand-built dumps of grains at a constant
acceleration it is that acceleration in every bin, with a grain that the
deck moved (reinjection), a grain outside the cylinder and a frame
written twice left out; and on the deck's own dump, rods falling from
their lattice before any of them lands accelerate at g, to round-off."""

import math

import numpy as np
import pytest

from analysis.silo3d_rotating import acceleration as acc
from analysis.common.tables import read_table
from analysis.silo3d_rotating.records import load_run
from test_silo3d_rotating_deck import quick_deck

DT = 1e-5
T_OPEN = 0.2
D = 0.06
A = -2.0                 # m/s^2: the hand-built grains' acceleration
FRAMES = np.arange(0, 11) * 0.05     # s since the opening


def write_run_records(directory, f, grains, duration, reinject=1, t_open=T_OPEN, dt=DT):
    """run.txt of a hand-built run of the deck's grains (D of this module)
    and its discharge.txt, every 0.01 s from the opening to `duration`
    after it, with no grain out."""
    (directory / "run.txt").write_text(
        f"d 0.006\nrho 620\nmass 3e-4\ng 9.8\nDc 0.19\nD {D}\nf {f}\nseed 7\nN {grains}\ndt {dt}\n"
        f"t_open {t_open}\nreinject {reinject}\nfinished {t_open + duration}\n")
    (directory / "discharge.txt").write_text("# step t n_out mass_out\n" + "".join(
        f"{round((t + t_open) / dt)} {t + t_open:.10g} 0 0\n" for t in np.arange(0, duration + 1e-9, 0.01)))


def dump_frame(tau, rows, t_open=T_OPEN, dt=DT):
    """A dump.cg frame at tau after the opening holding `rows`
    ("id type x y z vx vy vz radius mass" lines)."""
    return (f"ITEM: TIMESTEP\n{round((tau + t_open) / dt)}\nITEM: NUMBER OF ATOMS\n{len(rows)}\n"
            "ITEM: BOX BOUNDS ff ff ff\n-0.1 0.1\n-0.1 0.1\n-0.1 0.6\n"
            "ITEM: ATOMS id type x y z vx vy vz radius mass\n" + "".join(rows))


def write_constant_acceleration_run(directory, frames=FRAMES, twice=(3,)):
    """run.txt, discharge.txt and dump.cg of 600 grains near the axis
    (r = 5 mm) at z0 = 0 ... 0.599 m, at rest at the opening and then
    accelerating at A, so that every bin of 0-3 D has grains in every
    frame pair; a grain at r = 5 cm at rest (outside the cylinder);
    grain 1 is moved up to z = 0.2 m and stopped between the 6th and 7th
    frames, as fix reinject moves a grain (included, its midpoint at
    0.069 m would have a = +10 m/s^2). The frames of `twice` are
    written twice, as LIGGGHTS may at the set-up of a run."""
    directory.mkdir(parents=True)
    write_run_records(directory, 0.16, 601, frames[-1])
    z0 = 0.001 * np.arange(600)
    with open(directory / "dump.cg", "w") as dump:
        for k, tau in enumerate(frames):
            z, vz = z0 + 0.5 * A * tau ** 2, np.full(600, A * tau)
            x = np.full(600, 0.005)
            if k >= 6:                       # grain 1 re-entered at rest at z = 0.2 m
                z[0], vz[0] = 0.2, 0.0
            rows = [f"{i + 1} 1 {x[i]:.17g} 0 {z[i]:.17g} 0 0 {vz[i]:.17g} 0.003 3e-4\n" for i in range(600)]
            rows.append("601 1 0.05 0 0.1 0 0 0 0.003 3e-4\n")
            dump.write(dump_frame(tau, rows) * (2 if k in twice else 1))
    return directory


def test_grains_at_a_constant_acceleration_give_it_in_every_bin(tmp_path):
    run = load_run(write_constant_acceleration_run(tmp_path / "run"))
    profile = acc.axial_profile(run, 0.0, 0.5, blocks=5)
    assert profile.pairs == 10 and profile.interval == pytest.approx(0.05, rel=1e-12)
    assert profile.left_out == 1                       # the re-entered grain, not the one outside
    assert np.all(profile.counts > 0) and len(profile.counts) == 30
    np.testing.assert_allclose(profile.acceleration, A, rtol=1e-9)
    np.testing.assert_allclose(profile.acceleration_se, 0.0, atol=1e-9)
    # the grains are at rest at the opening: each pair's mean v_z is A t_mid
    assert np.all(profile.velocity < 0) and np.all(profile.velocity > A * 0.5)
    # the area from the first bin's centre (3 mm) to the last's (177 mm)
    assert profile.area == pytest.approx(A * 0.174, rel=1e-9)
    assert profile.area_se == pytest.approx(0.0, abs=1e-9)


def test_a_grain_is_placed_at_its_midpoint_or_first_position():
    """One grain from (0.01, 0, 0.10) at -0.8 m/s to (0.03, 0, 0.05) at
    -1.2 m/s in 50 ms: a_z = -8 m/s^2, v_z -1 m/s, at z 0.075 and r 0.02
    (midpoint) or z 0.1 and r 0.01 (first)."""
    a = {"id": np.array([1.0]), "x": np.array([0.01]), "y": np.array([0.0]), "z": np.array([0.10]),
         "vz": np.array([-0.8])}
    b = {"id": np.array([1.0]), "x": np.array([0.03]), "y": np.array([0.0]), "z": np.array([0.05]),
         "vz": np.array([-1.2])}
    for place, (r_expected, z_expected) in {"midpoint": (0.02, 0.075), "first": (0.01, 0.10)}.items():
        r, z, vz, az, moved = acc.grain_accelerations(a, b, 0.05, place=place)
        np.testing.assert_allclose([r[0], z[0], vz[0], az[0]], [r_expected, z_expected, -1.0, -8.0], rtol=1e-12)
        assert not moved[0]


def test_a_window_of_part_of_the_run_takes_its_frames_only(tmp_path):
    run = load_run(write_constant_acceleration_run(tmp_path / "run"))
    profile = acc.axial_profile(run, 0.1, 0.3, blocks=2)
    assert profile.pairs == 4 and profile.left_out == 1
    in_bins = profile.counts > 0
    np.testing.assert_allclose(profile.acceleration[in_bins], A, rtol=1e-9)


def test_a_missing_frame_is_refused_with_its_message(tmp_path):
    frames = np.delete(FRAMES, 4)
    run = load_run(write_constant_acceleration_run(tmp_path / "run", frames=frames))
    with pytest.raises(ValueError, match="not evenly spaced"):
        acc.axial_profile(run, 0.0, 0.5)
    with pytest.raises(ValueError, match="1 dump frame"):
        acc.axial_profile(run, 0.1, 0.12)


def test_cli_writes_the_profile_and_its_summary(tmp_path):
    directory = write_constant_acceleration_run(tmp_path / "run")
    assert acc.main([f"{directory}:0:0.5", "--out", str(tmp_path / "out"), "--blocks", "5"]) == 0
    table = read_table(tmp_path / "out" / "axial_acceleration.txt")
    # (the table's 8 digits)
    np.testing.assert_allclose(table["a_over_g"], A / 9.8, rtol=1e-7)
    np.testing.assert_allclose(table["z_over_D"], (np.arange(30) + 0.5) / 10, rtol=1e-7)
    summary = read_table(tmp_path / "out" / "axial_acceleration_summary.txt")
    assert summary["left_out"][0] == 1 and summary["frame_pairs"][0] == 10
    assert summary["area"][0] == pytest.approx(A * 0.174, rel=1e-7)
    assert (tmp_path / "out" / "axial_acceleration.png").stat().st_size > 0
    # from 1 D up, grains at their first position: the same acceleration,
    # bins from 1.05 D, the area over 1.05-2.95 D
    assert acc.main([f"{directory}:0:0.5", "--out", str(tmp_path / "high"), "--z-min-D", "1",
                     "--place", "first"]) == 0
    table = read_table(tmp_path / "high" / "axial_acceleration.txt")
    np.testing.assert_allclose(table["a_over_g"], A / 9.8, rtol=1e-7)
    np.testing.assert_allclose(table["z_over_D"], 1 + (np.arange(20) + 0.5) / 10, rtol=1e-7)
    summary = read_table(tmp_path / "high" / "axial_acceleration_summary.txt")
    assert summary["area"][0] == pytest.approx(A * 1.9 * D, rel=1e-7)
    with pytest.raises(SystemExit):
        acc.main([f"{directory}:0:0.5", "--out", str(tmp_path / "bad"), "--z-min-D", "3"])


def test_a_steady_flow_gives_its_exit_speed_from_the_area(tmp_path):
    """Grains enter at z = 0.6 m every 0.5 ms at v_z = -0.2 m/s and fall
    at A along the axis, a steady flow: v_z(z)^2 = 0.04 + 2|A|(0.6 - z).
    The speed at the first bin's centre that the area gives from the last
    bin's is that, and so is the measured one (to the bins' and the
    midpoints' discretisation, 0.06 %; within 0.2 %)."""
    directory = tmp_path / "run"
    directory.mkdir()
    write_run_records(directory, 0, 2000, 0.5, reinject=0)
    entry = np.arange(-1.0, 0.5, 0.0005)
    with open(directory / "dump.cg", "w") as dump:
        for tau in FRAMES:
            age = tau - entry
            z = 0.6 - 0.2 * age + 0.5 * A * age ** 2
            vz = -0.2 + A * age
            here = np.flatnonzero((age >= 0) & (z > -0.1))
            dump.write(dump_frame(tau, [f"{i + 1} 1 0 0 {z[i]:.17g} 0 0 {vz[i]:.17g} 0.003 3e-4\n" for i in here]))
    profile = acc.axial_profile(load_run(directory), 0.0, 0.5, blocks=5)
    expected = math.sqrt(0.04 + 2 * abs(A) * (0.6 - 0.003))
    assert profile.exit_speed_from_area == pytest.approx(expected, rel=2e-3)
    assert -profile.velocity[0] == pytest.approx(expected, rel=2e-3)
    np.testing.assert_allclose(profile.acceleration, A, rtol=1e-9)


@pytest.mark.parametrize("text", ["run:1", "run:a:2", "run:2:1"])
def test_cli_refuses_a_window_it_cannot_read(tmp_path, text):
    with pytest.raises(SystemExit):
        acc.main([text, "--out", str(tmp_path)])


@pytest.mark.engine
def test_rods_falling_from_the_deck_s_lattice_accelerate_at_g(run, tmp_path):
    """The quick rod deck opens at 0.05 s, before its lattice column of
    300 rods (spacing 1.05 L: no two touch) lands; dumps every 0.05 s for
    0.1 s. The column (0.41 m tall) lands from the bottom up, and by
    0.15 s only the rods that started below 0.14 m have: above 0.16 m nothing
    has landed yet, nor could a rebound reach it: every rod there is in free fall, and the profile from the
    LIGGGHTS dump is -g to the dump's printed digits (velocity Verlet is
    exact at constant force). The frames are round(0.05/dt) steps apart,
    a little over 0.05 s: the window's last frame, at 0.1000026 s, is in."""
    run(quick_deck(shape="rod", settle_time=0.05, discharge_time=0.1, dump_every_time=0.05))
    silo = load_run(tmp_path)
    profile = acc.axial_profile(silo, 0.0, 0.1, radius=0.02, z_edges=np.linspace(0.16, 0.36, 5), blocks=2)
    assert profile.pairs == 2
    assert np.all(profile.counts >= 4)
    # to the dump's 6 printed digits of v_z
    np.testing.assert_allclose(profile.acceleration, -silo.info["g"], rtol=1e-5)
    # v_z of a rod at rest at t = 0, in the middle of a pair, is -g t_mid
    t_mid = silo.info["t_open"] + np.array([0.025, 0.075])
    assert np.all((profile.velocity <= -silo.info["g"] * t_mid[0] * (1 - 1e-3))
                  & (profile.velocity >= -silo.info["g"] * t_mid[1] * (1 + 1e-3)))
    assert math.isfinite(profile.area)
