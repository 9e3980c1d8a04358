"""The rotating-bottom silo's analysis: the readers of
analysis.silo3d_rotating.records on real LIGGGHTS output (dump custom, dump local of
compute pair/gran/local and its force convention), the stationary flow rate
of analysis.silo3d_rotating.flow on synthetic discharge records whose answer is
worked out here by hand, seed statistics, the Beverloo and exponential fits,
and the CLI (analysis.silo3d_rotating.analyse, with the fields of
analysis.silo3d_rotating.fields) on synthetic run directories."""

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from analysis.common import coarse_grain as cg  # noqa: E402
from analysis.silo3d_rotating import flow as silo3d_flow  # noqa: E402
from analysis.silo3d_rotating import records as silo3d_records  # noqa: E402
from analysis.silo3d_rotating import analyse as silo  # noqa: E402
from analysis.common.deck_blocks import granular_setup, hooke_materials  # noqa: E402
from analysis.common.lammps_io import dump_steps, iter_dump  # noqa: E402
from analysis.silo3d_rotating.fields import analyse_fields  # noqa: E402
from analysis.common.tables import read_table

KN = 1000.0
RHO = 620.0


# ------------------------------------------------------------------ readers on LIGGGHTS output

def chain_deck(steps=0, every=1, gravity=""):
    """Three grains of d = 1 cm on the x axis, 9 mm apart (overlap 1 mm:
    elastic force kn * 1 mm = 1 N), at rest, no damping."""
    return f"""
{granular_setup()}
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box
create_box 1 box
neighbor 0.002 bin
{hooke_materials(KN, 2 / 7 * KN)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep 1e-6
create_atoms 1 single 0.0 0.0 0.0 units box
create_atoms 1 single 0.009 0.0 0.0 units box
create_atoms 1 single 0.018 0.0 0.0 units box
set group all diameter 0.01
set group all density {RHO}
{gravity}
fix integ all nve/sphere
compute pgl all pair/gran/local pos id force
dump cg all custom {every} dump.cg id type x y z vx vy vz radius mass
dump_modify cg format "%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
dump contacts all local {every} dump.contacts c_pgl[1] c_pgl[2] c_pgl[3] c_pgl[4] c_pgl[5] c_pgl[6] c_pgl[7] c_pgl[8] c_pgl[9] c_pgl[10] c_pgl[11] c_pgl[12]
dump_modify contacts format "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run {steps}
"""


@pytest.mark.engine
def test_pair_gran_local_force_is_on_the_first_grain(run, tmp_path):
    run(chain_deck())
    (_, columns), = list(iter_dump(tmp_path / "dump.contacts"))
    named = silo3d_records.contact_columns(columns)
    assert len(named["id1"]) == 2 and np.all(named["periodic"] == 0)
    first = np.column_stack([named["x1"], named["y1"], named["z1"]])
    second = np.column_stack([named["x2"], named["y2"], named["z2"]])
    force = np.column_stack([named["fx"], named["fy"], named["fz"]])
    away_from_second = (first - second) / np.linalg.norm(first - second, axis=1, keepdims=True)
    # repulsion of 1 N pushing the first grain away from the second
    assert np.allclose(force, KN * 0.001 * away_from_second, rtol=1e-9, atol=1e-12)
    # the positions are those of the ids in the same row
    (_, atoms), = list(iter_dump(tmp_path / "dump.cg"))
    x_of_id = dict(zip(atoms["id"].astype(int), atoms["x"]))
    assert np.allclose(named["x1"], [x_of_id[int(i)] for i in named["id1"]])


@pytest.mark.engine
def test_contacts_from_liggghts_give_the_chain_virial(run, tmp_path):
    # by hand: two contacts, each f (x) r = (1 N)(9 mm) e_x e_x, compressive
    run(chain_deck())
    (_, columns), = list(iter_dump(tmp_path / "dump.contacts"))
    contacts = silo3d_records.frame_contacts(columns)
    virial = np.einsum("ka,kb->ab", contacts.forces, contacts.starts - contacts.ends)
    expected = np.zeros((3, 3))
    expected[0, 0] = 2 * (KN * 0.001) * 0.009
    assert np.allclose(virial, expected, rtol=1e-9, atol=1e-12)
    kernel = cg.GaussianKernel(0.005)
    stress = cg.contact_stress([[0.009, 0, 0]], contacts, kernel)[0]
    assert np.trace(stress) / 3 > 0


@pytest.mark.engine
def test_iter_dump_streams_frames_and_skips_unwanted(run, tmp_path):
    """lammps_io.iter_dump (read_dump is its list) on real LIGGGHTS output:
    every frame with its step and all rows, and the `wanted` filter."""
    run(chain_deck(steps=300, every=100, gravity="fix gravi all gravity 9.81 vector 0.0 0.0 -1.0"))
    for name in ("dump.cg", "dump.contacts"):
        streamed = list(iter_dump(tmp_path / name))
        assert [s for s, _ in streamed] == [0, 100, 200, 300]
        rows = {len(next(iter(columns.values()))) for _, columns in streamed}
        assert rows == ({3} if name == "dump.cg" else {2})      # three grains, two contacts
        assert dump_steps(tmp_path / name).tolist() == [0, 100, 200, 300]
        picked = list(iter_dump(tmp_path / name, wanted=lambda step: step in (100, 300)))
        assert [s for s, _ in picked] == [100, 300]
    (_, frame), = list(iter_dump(tmp_path / "dump.cg", wanted=lambda step: step == 300))
    particles = silo3d_records.frame_particles(frame)
    assert particles.orientations is None
    # grains fell freely for 300 steps of 1 us: v_z = -g t (the chain is horizontal)
    assert np.allclose(particles.velocities[:, 2], -9.81 * 300e-6, rtol=1e-6)
    assert np.allclose(particles.masses, RHO * math.pi / 6 * 0.01 ** 3, rtol=1e-12)


def test_orientation_columns_are_normalised():
    columns = {name: np.array([1.0, 0.0]) for name in ("x", "y", "z", "vx", "vy", "vz", "mass")}
    columns.update({"ox": np.array([3.0, 0.0]), "oy": np.array([4.0, 0.0]), "oz": np.array([0.0, -2.0])})
    assert np.allclose(silo3d_records.frame_particles(columns).orientations, [[0.6, 0.8, 0.0], [0.0, 0.0, -1.0]])


def test_contact_columns_refuse_other_layouts():
    with pytest.raises(ValueError, match="pos id force"):
        silo3d_records.contact_columns({f"c_pgl[{k}]": np.zeros(1) for k in range(1, 10)})


def test_time_since_opening_from_the_discharge_record():
    # the record starts at step 5000, t = 0.5 s; dt = 1e-4; t_open = 0.5
    discharge = {"step": np.array([5000.0, 5100.0]), "t": np.array([0.5, 0.51])}
    info = {"dt": 1e-4, "t_open": 0.5}
    assert silo3d_records.time_since_opening([5000, 15000, 4000], discharge, info) == pytest.approx([0.0, 1.0, -0.1])


# ------------------------------------------------------------------ flow rate

SAMPLE = 0.01


def regular_exits(rate, until, gaps=()):
    """Exit times 1/(2 rate), 3/(2 rate), ... up to `until`, none inside
    the open intervals `gaps`; never on a sample time."""
    times = (np.arange(int(until * rate)) + 0.5) / rate
    for low, high in gaps:
        times = times[(times <= low) | (times >= high)]
    return times


def record(exit_times, until, grain_mass=1e-3):
    """Samples every SAMPLE s from 0 to `until`: tau, n_out, mass_out."""
    tau = np.round(np.arange(0, until + 0.5 * SAMPLE, SAMPLE), 10)
    n_out = np.searchsorted(np.sort(exit_times), tau, side="right").astype(float)
    return tau, n_out, n_out * grain_mass


def test_stationary_rate_removes_long_no_flow_intervals_by_hand():
    # 20 grains/s at tau = 0.025 + 0.05 j for 20 s, none in (5, 8) (3 s)
    # or in (12, 12.5) (0.5 s, kept: shorter than 1 s)
    exits = regular_exits(20.0, 20.0, gaps=[(5.0, 8.0), (12.0, 12.5)])
    tau, n_out, mass_out = record(exits, 20.0)
    start, end = silo3d_flow.analysis_window(tau, mass_out, total_mass=1.0, reinject=True, transient=1.0)
    assert (start, end) == (1.0, 20.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, start, end, min_gap=1.0, blocks=10)
    # exits in (1, 20]: j = 20 ... 399 (380), less j = 100 ... 159 in the
    # 3-s gap (60) and j = 240 ... 249 in the short one (10): 310 grains.
    # The 3-s gap is seen from the sample after the exit at 4.975 (4.98)
    # to the sample after the exit at 8.025 (8.03): 3.05 s removed.
    assert np.allclose(flow.gaps, [[4.98, 8.03]])
    assert flow.effective_duration == pytest.approx(19.0 - 3.05)
    assert flow.q_grains == pytest.approx(310 / 15.95, rel=1e-12)
    assert flow.q_mass == pytest.approx(310e-3 / 15.95, rel=1e-12)
    assert not flow.clogged_at_end
    # blocks of 1.595 s hold 31 or 32 regular exits, except the one with the
    # short gap, 10 grains (6.3 grains/s) fewer: the spread of the ten block
    # rates is ~6.3 sqrt(0.1 * 0.9 * 10/9) = 2.0, so se ~ 2.0/sqrt(10) = 0.63
    assert flow.q_grains_se == pytest.approx(0.63, abs=0.1)
    # how intermittent: the longest time without a grain is the 3-s gap as
    # seen (3.05 s); of the 1900 sampling intervals of 0.01 s ending in
    # (1, 20], the 310 exits fall in 310 of them (one per 0.05 s)
    assert flow.longest_pause == pytest.approx(3.05)
    assert flow.idle_share == pytest.approx((1900 - 310) / 1900, rel=1e-12)
    # without the long gap, the longest pause is the short one as seen,
    # from the sample after the exit at 11.975 (11.98) to the one after
    # the exit at 12.525 (12.53)
    assert silo3d_flow.pauses(tau, n_out, 9.0, 20.0)[0] == pytest.approx(0.55)
    assert np.isnan(silo3d_flow.pauses(tau, n_out, 20.0, 25.0)).all()


def test_window_start_transient_and_end_when_nearly_empty():
    # 400 grains of 1 g at 20 grains/s; without reinjection the window ends
    # when 0.6 * 0.4 kg = 240 grains are out: exit j = 239 at 11.975 s,
    # seen at the sample 11.98
    exits = regular_exits(20.0, 20.0)
    tau, n_out, mass_out = record(exits, 20.0)
    assert silo3d_flow.analysis_window(tau, mass_out, 0.4, reinject=False, transient=2.0,
                                       end_fraction=0.6) == pytest.approx((2.0, 11.98))
    assert silo3d_flow.analysis_window(tau, mass_out, 0.4, reinject=True, transient=2.0) == pytest.approx((2.0, 20.0))


def test_flow_that_stops_for_good_is_cut_and_flagged():
    # exits until 15 s, then nothing up to 20 s: [14.98, 20] is removed
    exits = regular_exits(20.0, 15.0)
    tau, n_out, mass_out = record(exits, 20.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 1.0, 20.0, min_gap=1.0)
    assert np.allclose(flow.gaps, [[14.98, 20.0]])
    assert flow.clogged_at_end
    # exits j = 20 ... 299 (280) over 13.98 s
    assert flow.q_grains == pytest.approx(280 / 13.98, rel=1e-12)


def test_a_clog_with_a_grain_or_two_after_it_has_no_stationary_flow():
    # the flow of a clogged small orifice (the 4.2 d runs): 20 grains/s up
    # to 0.3 s, then one grain at 1.755 s in a 2 s record. Window [0.5, 2]:
    # no exit in (0.5, 1.76], so [0.5, 1.76] (1.26 s) is cut and the 0.24 s
    # left hold one grain: flowing 0.24 s < 0.5 x 1.5 s, no stationary flow
    exits = np.append(regular_exits(20.0, 0.3), 1.755)
    tau, n_out, mass_out = record(exits, 2.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.5, 2.0, min_gap=1.0)
    assert np.allclose(flow.gaps, [[0.5, 1.76]])
    assert flow.effective_duration == pytest.approx(0.24)
    assert not flow.stationary and np.isnan(flow.q_grains) and np.isnan(flow.q_mass_se)
    # its pauses are still told: 1.26 s without a grain, and one sampling
    # interval of the 150 in (0.5, 2] with one
    assert (flow.longest_pause, flow.idle_share) == pytest.approx((1.26, 149 / 150))
    # without the rule, that one grain would be a flow rate of 1/0.24 grains/s
    kept = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.5, 2.0, min_gap=1.0, min_flowing_fraction=0.0)
    assert kept.stationary and kept.q_grains == pytest.approx(1 / 0.24, rel=1e-9)


def test_a_run_the_deck_stopped_at_a_clog_is_clogged_whatever_its_window(tmp_path):
    # the deck at rest stops a clogged run 0.5 s after its last grain and
    # says `clogged t` in run.txt: 20 grains/s up to 1.0 s (exits up to
    # 0.975 s, seen at the sample 0.98), stopped at 1.5 s. With a transient
    # of 4 s its window would start after its end: no Q, and clogged; with
    # one of 0.5 s it flowed for 0.48 s of 1.0 s (< half): no Q, clogged
    exits = regular_exits(20.0, 1.0)
    tau, n_out, mass_out = record(exits, 1.5)
    assert silo3d_flow.last_exit(tau, n_out) == pytest.approx(0.98)
    assert np.isnan(silo3d_flow.last_exit(tau, np.zeros_like(n_out)))
    run = silo3d_records.Run(tmp_path, {"N": 400, "mass": 1e-3, "reinject": 1, "clogged": 1.5},
                             {"n_out": n_out, "mass_out": mass_out}, tau)
    for transient in (4.0, 0.5):
        flow = silo3d_flow.analyse_flow(run, transient=transient, min_gap=0.4)
        assert flow.clogged_at_end and not flow.stationary and np.isnan(flow.q_mass)
    # the same record without the deck's word: the window of 4 s is empty,
    # not a clog it saw
    del run.info["clogged"]
    assert not silo3d_flow.analyse_flow(run, transient=4.0).clogged_at_end


def test_block_error_of_a_poisson_flow():
    # Poisson exits at 50 grains/s for 200 s: the count in T has variance
    # 50 T, so se(Q) = sqrt(50 / 200) = 0.5 grains/s. With 40 blocks the
    # block estimate of it scatters by ~1/sqrt(2 * 39) = 11 %.
    rng = np.random.default_rng(12)
    exits = np.cumsum(rng.exponential(1 / 50.0, 12000))
    tau, n_out, mass_out = record(exits[exits < 200.0], 200.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 200.0, blocks=40)
    assert flow.q_grains == pytest.approx(50.0, abs=4 * 0.5)
    assert flow.q_grains_se == pytest.approx(0.5, rel=0.35)


def test_block_error_with_blocks_twice_as_long_by_hand():
    # 100 grains/s for 1 s, then 300 grains/s for 1 s (a flow that changes
    # on a time longer than the blocks). 10 blocks of 0.2 s: rates 5 x 100
    # and 5 x 300, sd = 100 sqrt(10/9), se = 100/3 grains/s. 5 blocks of
    # 0.4 s: 100, 100, 200, 300, 300, sd = 100, se = 100/sqrt(5): larger,
    # which is what the second error is there to show. Grains of 1 g.
    exits = np.concatenate([regular_exits(100.0, 1.0), 1.0 + regular_exits(300.0, 1.0)])
    tau, n_out, mass_out = record(exits, 2.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 2.0, blocks=10)
    assert flow.q_grains == pytest.approx(200.0, rel=1e-12)
    assert flow.q_grains_se == pytest.approx(100.0 / 3.0, rel=1e-9)
    assert flow.q_mass_se == pytest.approx(1e-3 * 100.0 / 3.0, rel=1e-9)
    assert flow.q_mass_se_2x == pytest.approx(1e-3 * 100.0 / math.sqrt(5.0), rel=1e-9)
    # fewer than 4 blocks leave no two for the longer ones
    assert math.isnan(silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 2.0, blocks=3).q_mass_se_2x)


def test_trend_across_the_window_by_hand():
    # The same flow, 100 then 300 grains/s: 10 block rates 100 x 5, 300 x 5
    # at the centres 0.1, 0.3, ..., 1.9 s. About their means (1 s, 200/s):
    # Sxx = 2 (0.81 + 0.49 + 0.25 + 0.09 + 0.01) = 3.3 s^2, Sxy = 100 x 2.5
    # x 2 = 500, slope = 500/3.3 grains/s^2; across the 2 s window over the
    # mean 200/s: trend = 2 (500/3.3) / 200 = 50/33. Residuals: Syy - slope
    # Sxy = 10^5 - 500^2/3.3 over 8 degrees of freedom; the slope's se is
    # sqrt(that/8/3.3), the trend's 2/200 of it.
    exits = np.concatenate([regular_exits(100.0, 1.0), 1.0 + regular_exits(300.0, 1.0)])
    tau, n_out, mass_out = record(exits, 2.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 2.0, blocks=10)
    assert flow.trend == pytest.approx(50.0 / 33.0, rel=1e-9)
    slope_se = math.sqrt((1e5 - 500.0 ** 2 / 3.3) / 8 / 3.3)
    assert flow.trend_se == pytest.approx(slope_se * 2.0 / 200.0, rel=1e-9)
    # a steady flow has none, and its line no residual
    tau, n_out, mass_out = record(regular_exits(100.0, 2.0), 2.0)
    steady = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 2.0, blocks=10)
    assert abs(steady.trend) < 1e-9 and steady.trend_se < 1e-9
    # a rate falling as 300 - 100 t over 2 s: the k-th exit where the count
    # 300 t - 50 t^2 reaches k - 1/2 (never on a block edge, where the count
    # is a whole number), so each block of 0.2 s holds the integral of the
    # rate over it and the line is exact: slope -100/s^2, mean 200/s,
    # trend -1, no residual
    counts = np.arange(1, 401) - 0.5
    falling = (300.0 - np.sqrt(300.0 ** 2 - 200.0 * counts)) / 100.0
    tau, n_out, mass_out = record(falling, 2.0)
    flow = silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 2.0, blocks=10)
    assert flow.trend == pytest.approx(-1.0, rel=1e-9) and flow.trend_se < 1e-9
    assert math.isnan(silo3d_flow.stationary_flow_rate(tau, n_out, mass_out, 0.0, 2.0, blocks=2).trend)


def test_window_rates_through_the_run_by_hand():
    # 100 grains/s for 1 s, then 300/s for 1 s (exits at (j + 1/2)/rate,
    # never on a sample): windows of 0.5 s give 100, 100, 300, 300; of
    # 0.75 s, 75 grains in the first (100/s) and 25 + 150 in the second
    # (175/0.75 = 233.3/s), and no third (2.25 s is past the record's end)
    exits = np.concatenate([regular_exits(100.0, 1.0), 1.0 + regular_exits(300.0, 1.0)])
    tau, n_out, mass_out = record(exits, 2.0)
    rows = silo3d_flow.window_rates(tau, n_out, mass_out, 0.5)
    assert rows[:, :2].tolist() == [[0.0, 0.5], [0.5, 1.0], [1.0, 1.5], [1.5, 2.0]]
    assert rows[:, 2] == pytest.approx([100.0, 100.0, 300.0, 300.0], rel=1e-12)
    assert rows[:, 3] == pytest.approx(1e-3 * rows[:, 2], rel=1e-12)
    rows = silo3d_flow.window_rates(tau, n_out, mass_out, 0.75)
    assert rows[:, 1] == pytest.approx([0.75, 1.5]) and rows[:, 2] == pytest.approx([100.0, 175.0 / 0.75])
    # samples before the opening (tau < 0) do not count; a record shorter
    # than one window has none; a width <= 0 is refused
    early = np.concatenate([[-0.2, -0.1], tau])
    rows = silo3d_flow.window_rates(early, np.concatenate([[0.0, 0.0], n_out]),
                                    np.concatenate([[0.0, 0.0], mass_out]), 0.5)
    assert rows[:, 2] == pytest.approx([100.0, 100.0, 300.0, 300.0], rel=1e-12)
    # a record that stops one sample short of 2 s (as a 4 s run's, sampled
    # every 0.01 s, ends at 3.9994 s) keeps its last window, from 1.5 s to
    # its last sample at 1.99 s: 397 - 250 grains in 0.49 s, still 300/s
    rows = silo3d_flow.window_rates(tau[:-1], n_out[:-1], mass_out[:-1], 0.5)
    assert rows[-1, :2] == pytest.approx([1.5, 1.99]) and rows[:, 2] == pytest.approx([100, 100, 300, 300])
    assert silo3d_flow.window_rates(tau, n_out, mass_out, 2.5).shape == (0, 4)
    with pytest.raises(ValueError, match="width must be > 0"):
        silo3d_flow.window_rates(tau, n_out, mass_out, 0.0)
    # a window shorter than the sampling would hold no sample
    with pytest.raises(ValueError, match="shorter than the record's sample interval"):
        silo3d_flow.window_rates(tau, n_out, mass_out, 0.004)


def test_seed_mean_ci_student_t_by_hand():
    # 1, 2, 3: mean 2, sample sd 1, se 1/sqrt 3, t(0.975, 2 dof) = 4.302652729911275
    mean, se, half = silo3d_flow.seed_mean_ci([1.0, 2.0, 3.0], [9.0, 9.0, 9.0], [9, 9, 9])
    assert (mean, se) == pytest.approx((2.0, 1 / math.sqrt(3)))
    assert half == pytest.approx(4.302652729911275 / math.sqrt(3), rel=1e-12)
    # a single seed: its own block se, t(0.975, 9 dof) = 2.262157162740992
    mean, se, half = silo3d_flow.seed_mean_ci([5.0], [0.2], [9])
    assert (mean, se, half) == pytest.approx((5.0, 0.2, 2.262157162740992 * 0.2), rel=1e-12)


def flow_run(f, D, seed, q, q_se, blocks=10):
    """A Run with only what flow_changes reads: f, D, seed and its FlowRate."""
    flow = silo3d_flow.FlowRate(q, q_se, np.nan, np.nan, blocks, 0.0, 1.0, 1.0, np.zeros((0, 2)), False)
    return silo3d_records.Run(Path("."), {"f": f, "D": D, "seed": seed}, {}, np.zeros(0), flow)


def test_relative_change_from_rest_is_paired_by_seed_by_hand():
    runs = [flow_run(0.0, 0.04, 1, 1.0, 0.05), flow_run(0.0, 0.04, 2, 2.0, 0.05),
            flow_run(1.28, 0.04, 1, 1.1, 0.05), flow_run(1.28, 0.04, 2, 2.4, 0.05),
            flow_run(0.0, 0.06, 1, 2.0, 0.1), flow_run(0.32, 0.06, 1, 2.2, 0.1),
            flow_run(0.32, 0.06, 2, 9.9, 0.1),             # seed 2 has no f = 0 run at 6 cm
            flow_run(0.32, 0.05, 1, 1.0, 0.1)]             # nor has any seed at 5 cm
    rows = {(r["f"], r["D"]): r for r in silo3d_flow.flow_changes(runs)}
    assert sorted(rows) == [(0.32, 0.06), (1.28, 0.04)]
    # two seeds: changes 0.1 and 0.2 (paired; the means would give 3.5/3 - 1 = 0.1667):
    # mean 0.15, se = sd/sqrt 2 = 0.05, t(0.975, 1 dof) = 12.706204736174707
    two = rows[(1.28, 0.04)]
    assert (two["n"], two["change"], two["change_se"]) == (2, pytest.approx(0.15), pytest.approx(0.05))
    assert two["change_ci"] == pytest.approx(12.706204736174707 * 0.05, rel=1e-9)   # 1.1/1 - 1 is 0.1 + 9e-17
    # one seed: 2.2/2.0 - 1 = 0.1, se = 1.1 hypot(0.1/2.2, 0.1/2.0), t(0.975, 9 dof)
    one = rows[(0.32, 0.06)]
    se = 1.1 * math.hypot(0.1 / 2.2, 0.1 / 2.0)
    assert (one["n"], one["change"], one["change_se"]) == (1, pytest.approx(0.1), pytest.approx(se, rel=1e-12))
    assert one["change_ci"] == pytest.approx(2.262157162740992 * se, rel=1e-12)


def test_a_seed_run_twice_counts_once_in_the_paired_change():
    """Two realizations of one packing at 0.32 Hz (Q 1.1 and 1.3) against
    its one run at rest: one seed, whose Q is their mean 1.2 with the
    standard error of that mean, hypot(0.1, 0.3)/2; its blocks the
    fewer (8, so t with 7 degrees of freedom)."""
    runs = [flow_run(0.0, 0.06, 1, 1.0, 0.05), flow_run(0.32, 0.06, 1, 1.1, 0.1),
            flow_run(0.32, 0.06, 1, 1.3, 0.3, blocks=8)]
    ratio, se, half, n = silo3d_flow.paired_ratio(runs, 0.32, 0.0, 0.06)
    q_se = math.hypot(0.1, 0.3) / 2
    expected_se = 1.2 * math.hypot(q_se / 1.2, 0.05 / 1.0)
    assert (n, ratio, se) == (1, pytest.approx(1.2), pytest.approx(expected_se, rel=1e-12))
    assert half == pytest.approx(2.3646242510102993 * expected_se, rel=1e-12)   # t(0.975, 7 dof)
    # and the same run at rest twice (Q 1.0, 1.0): still one seed
    ratio, _, _, n = silo3d_flow.paired_ratio(runs + [flow_run(0.0, 0.06, 1, 1.0, 0.05)], 0.32, 0.0, 0.06)
    assert (n, ratio) == (1, pytest.approx(1.2))


# ------------------------------------------------------------------ fits

D_VALUES = np.array([0.03, 0.04, 0.05, 0.06, 0.07])
GRAIN = 0.0099


def test_beverloo_fit_recovers_exact_and_noisy_parameters():
    C, k = 40.0, 1.4
    Q = C * (D_VALUES - k * GRAIN) ** 2.5
    fit = silo3d_flow.fit_beverloo(D_VALUES, Q, 0.02 * Q, GRAIN)
    assert (fit["C"], fit["k"]) == pytest.approx((C, k), rel=1e-6)
    assert fit["dof"] == 3 and fit["chi2_dof"] < 1e-10
    sigma = 0.03 * Q
    noisy = Q + np.random.default_rng(13).normal(size=Q.size) * sigma
    fit = silo3d_flow.fit_beverloo(D_VALUES, noisy, sigma, GRAIN)
    assert abs(fit["C"] - C) < 3 * fit["C_se"] and abs(fit["k"] - k) < 3 * fit["k_se"]
    assert 0 < fit["k_se"] < 1.0


def test_exponential_fit_recovers_parameters():
    A, kappa = 2e-3, 84.0          # the paper's kappa = 0.084 /mm
    Q = A * np.exp(kappa * D_VALUES)
    fit = silo3d_flow.fit_exponential(D_VALUES, Q, 0.02 * Q)
    assert (fit["A"], fit["kappa"]) == pytest.approx((A, kappa), rel=1e-6)
    sigma = 0.05 * Q
    noisy = Q + np.random.default_rng(14).normal(size=Q.size) * sigma
    fit = silo3d_flow.fit_exponential(D_VALUES, noisy, sigma)
    assert abs(fit["kappa"] - kappa) < 3 * fit["kappa_se"]


# ------------------------------------------------------------------ CLI on synthetic runs

GRAIN_MASS = RHO * math.pi / 6 * GRAIN ** 3      # consistent with d and rho: w = d/2
DT = 1e-3
T_OPEN = 0.5
SILO_DIAMETER = 0.1
OMEGA = 2.0
FALL = 0.3          # v_z = -FALL in the synthetic dumps
LATTICE = 0.01


def write_run(directory, f, D, seed, rate, gaps=(), duration=12.0, fields=False, finished=True):
    """A run directory with run.txt (with the deck's last line `finished`
    unless not `finished`) and discharge.txt (regular exits at
    `rate` grains/s with no exit in `gaps`), and with `fields` also dump.cg
    and dump.contacts: a sc lattice filling the silo, v = Omega e_z x r -
    FALL e_z, each vertical lattice neighbour pair in contact pressing with
    1 N, frames every 0.5 s."""
    directory.mkdir(parents=True)
    (directory / "run.txt").write_text(
        f"# synthetic\nd {GRAIN} # m\nrho {RHO}\nmass {GRAIN_MASS}\ng 9.8\nDc {SILO_DIAMETER}\nD {D}\n"
        f"f {f}\nseed {seed}\nN 100000\ndt {DT}\nt_open {T_OPEN}\nreinject 1\n" +
        (f"finished {T_OPEN + duration}\n" if finished else ""))
    tau, n_out, mass_out = record(regular_exits(rate, duration, gaps), duration, GRAIN_MASS)
    steps = np.round((tau + T_OPEN) / DT)
    rows = "".join(f"{s:.0f} {t + T_OPEN:.10g} {n:.0f} {m:.10g} 0\n"
                   for s, t, n, m in zip(steps, tau, n_out, mass_out))
    (directory / "discharge.txt").write_text("# step t n_out mass_out extra\n" + rows)
    if fields:
        write_dumps(directory, np.arange(0.0, duration + 0.01, 0.5))


def write_dumps(directory, frame_tau):
    index = np.arange(-5, 6)
    mesh = np.meshgrid(index, index, np.arange(-4, 8), indexing="ij")      # below the orifice too
    sites = LATTICE * np.column_stack([m.ravel() for m in mesh]).astype(float) + [0, 0, 0.005]
    sites = sites[np.hypot(sites[:, 0], sites[:, 1]) < 0.5 * SILO_DIAMETER - 0.005]
    velocities = np.column_stack([-OMEGA * sites[:, 1], OMEGA * sites[:, 0], np.full(len(sites), -FALL)])
    below = {tuple(np.round(s / LATTICE, 3)): k for k, s in enumerate(sites)}
    pairs = [(k, below[key]) for k, s in enumerate(sites)
             if (key := tuple(np.round((s - [0, 0, LATTICE]) / LATTICE, 3))) in below]
    with open(directory / "dump.cg", "w") as cg_file, open(directory / "dump.contacts", "w") as contact_file:
        for tau in frame_tau:
            step = round((tau + T_OPEN) / DT)
            header = f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF {{}}\n{{}}\nITEM: BOX BOUNDS ff ff ff\n" \
                     "-0.1 0.1\n-0.1 0.1\n0 0.2\n"
            cg_file.write(header.format("ATOMS", len(sites)) + "ITEM: ATOMS id type x y z vx vy vz radius mass\n")
            for k, (x, v) in enumerate(zip(sites, velocities)):
                cg_file.write(f"{k + 1} 1 {x[0]} {x[1]} {x[2]} {v[0]} {v[1]} {v[2]} {GRAIN / 2} {GRAIN_MASS}\n")
            contact_file.write(header.format("ENTRIES", len(pairs)) + "ITEM: ENTRIES " +
                               " ".join(f"c_pgl[{c}]" for c in range(1, 13)) + "\n")
            for upper, lower in pairs:
                # force on the upper grain from the lower one: pushed up
                x1, x2 = sites[upper], sites[lower]
                contact_file.write(f"{x1[0]} {x1[1]} {x1[2]} {x2[0]} {x2[1]} {x2[2]} {upper + 1} {lower + 1} 0 0 0 1\n")


def test_q_of_f_is_titled_with_the_paper_s_panel_for_the_grains():
    # the paper's Fig. 2 caption: (a) spheres, (b)-(d) rods of L/d = 2.5, 3.3, 4.0
    assert silo.fig2_panel({"shape": "sphere", "aspect": 1}) == "spheres (Fig. 2a)"
    assert silo.fig2_panel({"shape": "rod", "aspect": 2.5}) == "rods L/d 2.5 (Fig. 2b)"
    assert silo.fig2_panel({"shape": "rod", "aspect": 3.3}) == "rods L/d 3.3 (Fig. 2c)"
    assert silo.fig2_panel({"shape": "rod", "aspect": 4.0}) == "rods L/d 4 (Fig. 2d)"
    assert silo.fig2_panel({"shape": "clump", "aspect": 3.3}) == "glued-sphere rods L/d 3.3 (peer of Fig. 2c)"
    assert silo.fig2_panel({"shape": "rod", "aspect": 5.0}) == "rods L/d 5 (not in Fig. 2)"


def test_cli_writes_tables_and_plots(tmp_path):
    runs = []
    # three orifices at f = 0.32, two seeds each; rate in grains/s grows with D
    for D, rate in ((0.03, 20.0), (0.04, 40.0), (0.05, 80.0)):
        for seed, gaps in ((1, ()), (2, [(4.0, 6.0)])):
            runs.append(tmp_path / f"D{D}_s{seed}")
            write_run(runs[-1], 0.32, D, seed, rate, gaps, fields=(D == 0.03 and seed == 1))
    # a run that stopped early (no `finished` line) is left out with a message
    runs.append(tmp_path / "D0.06_s1_unfinished")
    write_run(runs[-1], 0.32, 0.06, 1, 1.0, duration=1.2, finished=False)
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "analysis.silo3d_rotating", *map(str, runs), "--out", str(out),
                             "--map-frames", "2"],
                            cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "silo3d_rotating: done" in result.stdout
    assert f"{runs[-1]}: unfinished" in result.stdout and "left out" in result.stdout

    per_run = read_table(out / "flow_rate_runs.txt")
    # by hand, transient 1 s, window [1, 12]: seed 1 has rate * 11 grains in
    # 11 s (regular exits at (j + 1/2)/rate, none on a sample);
    # seed 2 loses the exits in (4, 6) and the gap seen is 2 s + one
    # inter-exit interval (from the sample after the last exit before 4 to
    # the sample after the first exit after 6): 20/s: 3.975 -> 3.98 to
    # 6.025 -> 6.03; 40/s: 3.9875 -> 3.99 to 6.0125 -> 6.02; 80/s: 3.99375 ->
    # 4.00 to 6.00625 -> 6.01
    removed = {20.0: 2.05, 40.0: 2.03, 80.0: 2.01}
    for k, (D, rate) in enumerate(((0.03, 20.0), (0.03, 20.0), (0.04, 40.0), (0.04, 40.0),
                                   (0.05, 80.0), (0.05, 80.0))):
        row = {name: values[k] for name, values in per_run.items()}
        assert row["D"] == D
        if row["seed"] == 1:
            assert row["Q_grains_s"] == pytest.approx(rate, rel=1e-7)
        else:
            grains = rate * 11 - rate * 2
            assert row["removed"] == pytest.approx(removed[rate], rel=1e-7)
            assert row["Q_grains_s"] == pytest.approx(grains / (11 - removed[rate]), rel=1e-7)
        assert row["Q_kg_s"] == pytest.approx(row["Q_grains_s"] * GRAIN_MASS, rel=1e-7)

    groups = read_table(out / "flow_rate.txt")
    assert groups["n"].tolist() == [2, 2, 2] and groups["n_no_flow"].tolist() == [0, 0, 0]
    assert per_run["stationary"].tolist() == [1] * 6
    # the check of the block length is written for every run (its value: the
    # test of blocks twice as long, by hand, above)
    assert np.all(np.isfinite(per_run["Q_kg_s_se_2x"]))
    assert np.all(np.isfinite(per_run["Q_trend"])) and np.all(np.isfinite(per_run["Q_trend_se"]))
    # by hand from the rates above, two seeds per D; t(0.975, 1 dof) = 12.706204736174707
    for k, rate in enumerate((20.0, 40.0, 80.0)):
        seeds = np.array([rate, 9 * rate / (11 - removed[rate])]) * GRAIN_MASS
        assert groups["Q_kg_s"][k] == pytest.approx(seeds.mean(), rel=1e-7)
        assert groups["Q_kg_s_ci95"][k] == pytest.approx(12.706204736174707 * abs(seeds[1] - seeds[0]) / 2,
                                                          rel=1e-6)
    # the raw rate per 1 s window through the whole run (12 s): seed 1 is
    # the rate in every window; seed 2 has none from 4 to 6 s
    windows = read_table(out / "flow_rate_windows.txt")
    for D, rate in ((0.03, 20.0), (0.04, 40.0), (0.05, 80.0)):
        for seed in (1, 2):
            mine = (windows["D"] == D) & (windows["seed"] == seed)
            assert windows["t_from"][mine].tolist() == list(range(12))
            expected = [0.0 if seed == 2 and t in (4, 5) else rate for t in range(12)]
            assert windows["Q_grains_s"][mine] == pytest.approx(expected, rel=1e-9)
    assert f"f0.32_D30mm_seed1: grains/s per 1 s since the opening: {', '.join(['20'] * 12)}" in result.stdout
    fits = read_table(out / "flow_rate_fits.txt")
    assert fits["f"].tolist() == [0.32] and fits["beverloo_dof"].tolist() == [1]
    change = read_table(out / "flow_rate_change.txt")               # no run at f = 0: no rows
    assert list(change) == ["f", "D", "n", "change", "change_se", "change_ci95"]
    assert all(column.size == 0 for column in change.values())
    for name in ("Q_vs_f.png", "Q_vs_D_loglog.png", "Q_vs_D_semilog.png", "flow_rate.md", "flow_rate_fits.md",
                 "flow_rate_change.md"):
        assert (out / name).stat().st_size > 0

    # fields of the run with dumps
    label = "f0.32_D30mm_seed1"
    for name in ("map_phi.png", "map_speed.png", "map_vtheta.png", "map_pk.png", "map_pc.png", "fields.npz",
                 "orifice_timeseries.txt", "discharge.png"):
        assert (out / "runs" / label / name).stat().st_size > 0
    assert not (out / "runs" / label / "map_S.png").exists()          # no orientations
    series = read_table(out / "runs" / label / "orifice_timeseries.txt")
    # frames every 0.5 s inside [1, 12]: 1.0, 1.5, ..., 12.0
    assert series["t"] == pytest.approx(np.arange(1.0, 12.01, 0.5))
    assert series["v_z"] == pytest.approx(-FALL, rel=1e-9)
    assert np.all(series["v_theta"] > 0) and np.all(series["p_c"] > 0)
    orifice = read_table(out / "orifice.txt")
    assert orifice["D"].tolist() == [0.03]
    # lattice of spacing a = 1 cm: phi = m / (rho a^3); with w = d/2 ~ a/2 the
    # lattice ripples by up to 6 exp(-2 pi^2 w^2/a^2) = 4.4 %
    assert orifice["phi"][0] == pytest.approx(GRAIN_MASS / RHO / LATTICE ** 3, rel=0.05)
    assert (out / "orifice_vs_f.png").stat().st_size > 0
    fields = np.load(out / "runs" / label / "fields.npz")
    assert fields["frames"].tolist() == [2, 2, 2, 2]
    # v_theta = Omega r in the map, away from the lattice's edges (r < 2 cm, 2 cm < z < 5 cm)
    inner_r, inner_z = fields["r"] < 0.02, (fields["z"] > 0.02) & (fields["z"] < 0.05)
    v_theta = fields["velocity_0"][..., 1][np.ix_(inner_r, inner_z)]
    assert v_theta == pytest.approx(np.broadcast_to(OMEGA * fields["r"][inner_r][:, None], v_theta.shape),
                                    abs=0.05 * OMEGA * LATTICE)


def test_fields_read_before_from_the_same_records_are_not_read_again(tmp_path, monkeypatch):
    # a campaign stage analyses all its runs again when its last one ends:
    # the dumps of those read before, with the same settings, are not read
    run_dir, out = tmp_path / "D0.03_s1", tmp_path / "out"
    write_run(run_dir, 0.32, 0.03, 1, 20.0, fields=True)
    arguments = [str(run_dir), "--out", str(out), "--map-frames", "2"]
    calls = []
    monkeypatch.setattr(silo, "analyse_fields", lambda run, settings: calls.append(settings) or
                        analyse_fields(run, settings))
    assert silo.main(arguments) == 0 and len(calls) == 1
    first = read_table(out / "orifice.txt")
    assert silo.main(arguments) == 0 and len(calls) == 1                    # read before: not read again
    again = read_table(out / "orifice.txt")
    assert list(again) == list(first)
    for name in first:       # the series read back has 8 significant digits
        assert again[name] == pytest.approx(first[name], rel=1e-7, nan_ok=True)
    assert first["v_z"][0] == pytest.approx(-FALL, rel=1e-9)
    # other settings, or a record written since: read again
    assert silo.main(arguments + ["--orifice-height", "0.02"]) == 0 and len(calls) == 2
    assert calls[1].orifice_height == 0.02
    assert silo.main(arguments + ["--orifice-height", "0.02"]) == 0 and len(calls) == 2
    dump = run_dir / "dump.cg"
    stat = dump.stat()
    os.utime(dump, ns=(stat.st_atime_ns, stat.st_mtime_ns + 10**9))
    assert silo.main(arguments + ["--orifice-height", "0.02"]) == 0 and len(calls) == 3


def test_a_frame_written_twice_is_read_once(tmp_path):
    # a deck's run loop can make LIGGGHTS dump the last step of a run again
    # at the set-up of the next run: the fields must not count it twice
    frame = ("ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS ff ff ff\n0 1\n0 1\n0 1\n"
             "ITEM: ATOMS id type x y z vx vy vz radius mass\n1 1 0 0 {step} 0 0 0 0.005 0.001\n")
    run_dir = tmp_path / "run"
    run_dir.mkdir()
    (run_dir / "dump.cg").write_text("".join(frame.format(step=s) for s in (10, 20, 20, 30)))
    run = silo3d_records.Run(run_dir, {}, {}, np.array([]))
    steps = dump_steps(run_dir / "dump.cg")
    assert steps.tolist() == [10, 20, 20, 30]
    read = [(step, particles.positions[0, 2], contacts)
            for step, particles, contacts in silo3d_records.frames_with_contacts(run, steps[[1, 2, 3]])]
    assert read == [(20, 20.0, None), (30, 30.0, None)]


@pytest.mark.engine
def test_the_rods_axes_of_the_deck_s_dump_are_read_as_orientations(run, tmp_path):
    """dump.cg of the deck with rods has c_rod_axis[1-3] (compute
    spherocylinder/axis): two rods set along given axes come back as
    those unit vectors."""
    axes = np.array([[1.0, 2.0, 2.0], [0.0, -3.0, 4.0]])
    rods = "\n".join(f"""create_atoms 1 single {0.05 * k!r} 0 0 units box
group r{k} id {k + 1}
set_spherocylinder r{k} diameter 0.01 length 0.03 density 620 axis {a[0]!r} {a[1]!r} {a[2]!r}"""
                     for k, a in enumerate(axes))
    run(f"""units si
atom_style spherocylinder
atom_modify map array sort 0 0
boundary f f f
newton off
region box block -0.1 0.2 -0.1 0.1 -0.1 0.1 units box
create_box 1 box
{rods}
compute rod_axis all spherocylinder/axis
dump cg all custom 1 dump.cg id type x y z vx vy vz radius mass c_rod_axis[1] c_rod_axis[2] c_rod_axis[3]
dump_modify cg sort id format "%d %d{' %.17g' * 12}"
run 0
""")
    (_, frame), = list(iter_dump(tmp_path / "dump.cg"))
    orientations = silo3d_records.frame_particles(frame).orientations
    np.testing.assert_allclose(orientations, axes / np.linalg.norm(axes, axis=1, keepdims=True), atol=1e-12)


def test_orifice_averages_of_single_runs_are_plotted_without_error_bars(tmp_path):
    # one run per (f, D): no spread over seeds, every interval NaN, on which
    # matplotlib's errorbar stops with StopIteration (run.sh's analysis of a
    # one-seed campaign did)
    groups = [{"f": f, "D": 0.05, "v_z": (-0.1 - f, np.nan, np.nan)} for f in (0.0, 0.32)]
    path = silo.plot_orifice_vs_f(tmp_path / "orifice.png", groups, ["v_z"], ["-<v_z> (m/s)"])
    assert Path(path).stat().st_size > 0
    assert silo._error_bars([np.nan, np.nan]) is None
    np.testing.assert_array_equal(silo._error_bars([0.1, np.nan]), [0.1, np.nan])


def test_q_of_d_without_any_flow_is_an_empty_plot_not_an_error(tmp_path):
    # a short run before the first grain left: Q = 0 everywhere, nothing
    # for the log axes (matplotlib stopped with "no positive values")
    groups = [{"f": 0.32, "D": 0.05, "Q": 0.0, "Q_ci": np.nan}]
    for log_q_axis_only in (False, True):
        path = silo.plot_q_vs_D(tmp_path / f"q_{log_q_axis_only}.png", groups, {}, 0.0099, log_q_axis_only)
        assert Path(path).stat().st_size > 0


def test_a_window_per_frequency_with_transient_at(tmp_path, capsys):
    # the same flow at f = 0 and 0.64 Hz: 40 grains/s for 12 s with no exit
    # in (2.0, 2.5) (0.5 s, shorter than --gap: kept in the time base).
    # --transient 4 --transient-at 0.64 1: the run at rest is counted over
    # [4, 12] (40/s, the gap left out), the one at 0.64 Hz over [1, 12],
    # 11 s with 440 - 20 exits, by hand
    runs = [tmp_path / "f0", tmp_path / "f0.64"]
    write_run(runs[0], 0.0, 0.05, 1, 40.0, gaps=[(2.0, 2.5)])
    write_run(runs[1], 0.64, 0.05, 1, 40.0, gaps=[(2.0, 2.5)])
    out = tmp_path / "out"
    assert silo.main([*map(str, runs), "--out", str(out), "--no-fields", "--transient", "4",
                      "--transient-at", "0.64", "1"]) == 0
    per_run = read_table(out / "flow_rate_runs.txt")
    assert per_run["f"].tolist() == [0.0, 0.64]
    assert per_run["t_start"] == pytest.approx([4.0, 1.0], abs=1e-9)
    assert per_run["Q_grains_s"] == pytest.approx([40.0, 420 / 11], rel=1e-7)     # the table's 8 digits
    change = read_table(out / "flow_rate_change.txt")
    assert change["change"] == pytest.approx([420 / 11 / 40 - 1], rel=1e-6)
    # a frequency without runs is named (a typo would otherwise pass unseen)
    assert silo.main([*map(str, runs), "--out", str(tmp_path / "typo"), "--no-fields",
                      "--transient-at", "0.46", "1"]) == 0
    assert "WARNING: --transient-at 0.46 1: no run at 0.46 Hz" in capsys.readouterr().out
    # without it, both over [4, 12]
    assert silo.main([*map(str, runs), "--out", str(tmp_path / "same"), "--no-fields", "--transient", "4"]) == 0
    assert read_table(tmp_path / "same" / "flow_rate_runs.txt")["Q_grains_s"] == pytest.approx([40.0, 40.0])
    # refused: a negative time, a frequency given twice
    for bad in (["--transient-at", "0.64", "-1"], ["--transient-at", "0.64", "1", "--transient-at", "0.64", "2"],
                ["--transient", "-0.5"]):
        with pytest.raises(SystemExit):
            silo.parse_args([str(runs[0]), "--out", str(out), *bad])
    error = capsys.readouterr().err
    assert "the frequency 0.64 Hz is given more than once" in error and "--transient must be >= 0 s" in error


def test_drop_and_recovery_of_the_paper_s_fig_3_by_hand(tmp_path):
    # two seeds, regular flows (Q = the rate over the window [1, 12]),
    # grains/s at f = 0, 0.16, 0.32, 1.28 Hz: seed 1 40, 20, 24, 30;
    # seed 2 50, 30, 28, 40. Means 45, 25, 26, 35: f_min = 0.16 Hz.
    # Q_min/Q(0) per seed 0.5 and 0.6; Q(1.28)/Q_min 1.5 and 4/3
    rates = {1: (40.0, 20.0, 24.0, 30.0), 2: (50.0, 30.0, 28.0, 40.0)}
    runs = []
    for seed, per_f in rates.items():
        for f, rate in zip((0.0, 0.16, 0.32, 1.28), per_f):
            runs.append(tmp_path / f"f{f}_s{seed}")
            write_run(runs[-1], f, 0.05, seed, rate)
    out = tmp_path / "out"
    assert silo.main([*map(str, runs), "--out", str(out), "--no-fields"]) == 0
    drop = read_table(out / "flow_rate_drop.txt")
    t1 = 12.706204736174707                      # t(0.975, 1 dof)
    assert drop["D"].tolist() == [0.05] and drop["f_min"].tolist() == [0.16] and drop["f_max"].tolist() == [1.28]
    assert drop["n_min"].tolist() == [2] and drop["n_max"].tolist() == [2]
    assert drop["Qmin_over_Q0"][0] == pytest.approx(0.55, rel=1e-6)
    assert drop["Qmin_over_Q0_se"][0] == pytest.approx(0.05, rel=1e-6)
    assert drop["Qmin_over_Q0_ci95"][0] == pytest.approx(t1 * 0.05, rel=1e-6)
    assert drop["Qmax_over_Qmin"][0] == pytest.approx((1.5 + 4 / 3) / 2, rel=1e-6)
    assert drop["Qmax_over_Qmin_se"][0] == pytest.approx((1.5 - 4 / 3) / 2, rel=1e-6)
    # the same pairs give flow_rate_change at 0.16 Hz: the drop minus 1
    change = read_table(out / "flow_rate_change.txt")
    assert change["change"][change["f"] == 0.16] == pytest.approx([-0.45], rel=1e-6)
    # without a run at rest there is nothing to drop from: no row
    assert silo.main([*map(str, runs[1:4]), "--out", str(tmp_path / "no_rest"), "--no-fields"]) == 0
    assert read_table(tmp_path / "no_rest" / "flow_rate_drop.txt")["D"].size == 0
