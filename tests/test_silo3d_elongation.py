"""analysis.silo3d_rotating.elongation (the paper's Fig. 3 from our
records): its L/d = 3.3 point against rates computed here from the runs'
discharge.txt, its orifice averages against the campaign analysis' own
tables, a store laid out like the elongation campaign's picked up
without a code change (and a run cut short left out), and the committed
table. Reads doc/data only; no engine."""

import shutil

import numpy as np
import pytest

from analysis.results_tables import DATA_DIR
from analysis.silo3d_rotating import elongation
from analysis.silo3d_rotating.results import FIG2C, ORIFICES, PACKINGS, SPHERES, markdown_rows

SEED = PACKINGS["2nd"]


def discharge(run_dir):
    """(time since the opening, mass out) of a run, read here without the analysis."""
    t_open = next(float(line.split()[1]) for line in (run_dir / "run.txt").read_text().splitlines()
                  if line.startswith("t_open "))
    table = np.loadtxt(run_dir / "discharge.txt")        # step t n_out mass_out
    return table[:, 1] - t_open, table[:, 3]


def campaign_run(aspect, packing, f):
    """Where the elongation campaign archives a run (named here, not by the module)."""
    return DATA_DIR / elongation.store(aspect) / f"D0.06_f{f:g}_s{PACKINGS[packing]}"


def rates_over(run_dir, t_from=2.0, t_to=4.0):
    """Q over [t_from, t_to] two ways: the slope of a straight line through
    mass_out against time, and the mass between the first and the last
    sample in the window over their time apart."""
    tau, mass = discharge(run_dir)
    inside = (tau >= t_from) & (tau <= t_to)
    slope = np.polyfit(tau[inside], mass[inside], 1)[0]
    ends = (mass[inside][-1] - mass[inside][0]) / (tau[inside][-1] - tau[inside][0])
    return slope, ends


def assert_parts_are_rate_ratios(point, run_dir, f, f_ref, window, within):
    """Each packing's ratio in `point` is the rate of its run at f over
    that at f_ref (run_dir(packing, f)), both over `window`, from the
    mass between the window's end samples over their time apart; a
    straight line through the bursts gives it within `within` times its
    error; the mean lies among the parts."""
    for packing, value, se in point.ratio.parts:
        slope_f, ends_f = rates_over(run_dir(packing, f), *window)
        slope_ref, ends_ref = rates_over(run_dir(packing, f_ref), *window)
        assert value == pytest.approx(ends_f / ends_ref, rel=1e-9)
        assert abs(value - slope_f / slope_ref) < within * se, (packing, value, slope_f / slope_ref, se)
    values = [p[1] for p in point.ratio.parts]
    assert min(values) <= point.ratio.value <= max(values)
    assert point.window == window


@pytest.mark.parametrize("panel, f, f_ref", [("a", 0.32, 0.0), ("b", 1.28, 0.32)])
def test_the_3_3_point_is_the_ratio_of_the_two_runs_rates_per_packing(panel, f, f_ref):
    """No pause of 1 s or more in these windows, so the ends give the
    rate, and a straight line through the bursts lands within its error."""
    point = elongation.rod_point(DATA_DIR, 3.3, panel)
    # the third packing clogs at rest: over 2-4 s not one rod leaves
    tau, mass = discharge(DATA_DIR / FIG2C["3rd", 0.0])
    inside = (tau >= 2) & (tau <= 4)
    assert mass[inside][-1] == mass[inside][0]
    expected = ["1st", "2nd"] if panel == "a" else ["1st", "2nd", "3rd"]
    assert [p[0] for p in point.ratio.parts] == expected
    assert_parts_are_rate_ratios(point, lambda packing, freq: DATA_DIR / FIG2C[packing, freq],
                                 f, f_ref, (2, 4), within=1)
    assert point.planned == 3


@pytest.mark.parametrize("panel, f, f_ref", [("a", 0.32, 0.0), ("b", 1.28, 0.32)])
def test_the_spheres_point_is_the_ratio_of_the_two_runs_rates_per_packing(panel, f, f_ref):
    """L/d = 1: the spheres' 2 s runs at 60 mm (the cross-host bench's
    LIGGGHTS runs), over 0.5-2 s, all three packings. Two estimates of one
    rate, a straight line through 1.5 s of bursts and the ends, differ by
    noise, within two of its errors."""
    point = next(p for p in elongation.fig3_points(DATA_DIR) if p.aspect == 1.0 and p.panel == panel)
    assert [p[0] for p in point.ratio.parts] == list(PACKINGS.values())
    assert_parts_are_rate_ratios(point, lambda seed, freq: DATA_DIR / SPHERES[60, freq, seed],
                                 f, f_ref, (0.5, 2), within=2)
    assert point.planned == 3


@pytest.mark.parametrize("aspect", [2.5, 4.0])
def test_the_campaign_points_are_the_ratio_of_the_two_runs_rates_per_packing(aspect):
    """L/d = 2.5 and 4.0, Fig. 3a: each packing whose runs at rest and at
    0.32 Hz are both archived in the campaign's store gives a part (the
    first packing, at least), from the same 2-4 s of both; a straight line
    through the bursts lands within two of its errors."""
    point = elongation.rod_point(DATA_DIR, aspect, "a")

    def run_dir(packing, f):
        return campaign_run(aspect, packing, f)

    both = [p for p in elongation.CAMPAIGN_PACKINGS
            if all((run_dir(p, f) / "discharge.txt").exists() for f in (0.0, 0.32))]
    assert "1st" in both
    assert [p[0] for p in point.ratio.parts] == both
    assert_parts_are_rate_ratios(point, run_dir, 0.32, 0.0, (2, 4), within=2)
    assert point.planned == 2


def test_q_against_f_is_the_mean_of_the_packings_rates(tmp_path):
    """The by-f figure's Q at L/d = 3.3: the mean of the packings' rates
    over 2-4 s, each from the mass between the window's end samples, ± the
    standard error of their spread; at rest the third packing clogs and is
    left out. At 2.5 and 4.0 the mean over the packings archived so far."""
    points = {(p.aspect, p.f): p for p in elongation.rate_points(DATA_DIR) if p.window != elongation.LATE}
    for f, packings in ((0.32, ("1st", "2nd", "3rd")), (0.0, ("1st", "2nd"))):
        ends = [rates_over(DATA_DIR / FIG2C[packing, f])[1] for packing in packings]
        point = points[3.3, f]
        assert point.n == len(packings)
        assert point.q == pytest.approx(np.mean(ends), rel=1e-9)
        assert point.se == pytest.approx(np.std(ends, ddof=1) / np.sqrt(len(ends)), rel=1e-9)
    # the elongation campaign's aspect ratios: the packings archived so far
    # (both have the first packing at rest and at 0.32 Hz, 2026-11-30)
    for aspect in (2.5, 4.0):
        for f in elongation.FREQUENCIES:
            runs = [campaign_run(aspect, packing, f) for packing in elongation.CAMPAIGN_PACKINGS]
            ends = [rates_over(run)[1] for run in runs if (run / "discharge.txt").exists()]
            if not ends:
                assert (aspect, f) not in points
                continue
            assert points[aspect, f].n == len(ends)
            assert points[aspect, f].q == pytest.approx(np.mean(ends), rel=1e-9)
    assert points[2.5, 0.32].n >= 1 and points[4.0, 0.32].n >= 1
    assert elongation.main(["--figure-by-f", str(tmp_path / "by_f.png")]) == 0
    assert (tmp_path / "by_f.png").stat().st_size > 10_000


def test_the_orifice_averages_at_0_32_hz_are_the_campaign_analysis_own():
    """The 0.32 Hz runs were analysed over 2-4 s, the window of their
    protocol: their rows in the campaign's per-packing tables (made by
    analysis.silo3d_rotating from the same series) are the module's."""
    for packing, name in (("1st", "first"), ("2nd", "second"), ("3rd", "third")):
        table = markdown_rows(DATA_DIR / "silo3d_rods_fig2c" / f"orifice_runs_{name}_packing.md")
        row = next(r for r in table if r["f"] == 0.32)
        means = elongation.run_orifice_means(DATA_DIR / FIG2C[packing, 0.32], (2, 4))
        for quantity in ("phi", "v_z", "O_zz"):
            assert means[quantity][0] == pytest.approx(row[quantity], rel=2e-5), (packing, quantity)
            assert means[quantity][1] == pytest.approx(row[f"{quantity}_se"], rel=2e-4), (packing, quantity)


def test_the_orifice_series_at_rest_come_from_the_same_trajectories():
    """The 3.3 averages at rest are the 4 s twins' (the 8 s runs' series
    start at 4 s): a twin's discharge is the 8 s run's over its 4 s."""
    for packing in ("1st", "2nd"):
        twin, long = DATA_DIR / ORIFICES[packing, 60], DATA_DIR / FIG2C[packing, 0.0]
        tau_twin, mass_twin = discharge(twin)
        tau_long, mass_long = discharge(long)
        assert tau_twin[-1] > 3.99
        np.testing.assert_allclose(tau_long[:tau_twin.size], tau_twin, rtol=1e-12)
        np.testing.assert_array_equal(mass_long[:tau_twin.size], mass_twin)
        assert elongation.run_orifice_means(long, (2, 4)) is None          # its series: 4-8 s
        assert elongation.run_orifice_means(twin, (2, 4)) is not None


@pytest.fixture
def data_with_a_store(tmp_path):
    """doc/data (linked) with an L/d = 4.0 store holding the second
    packing's 3.3 runs at rest and at 0.32 Hz, named as the campaign names
    its runs (run.txt's aspect made 4.0). The campaign's own stores are
    left out: the test sees the same store whatever the campaign has
    archived, and never writes into doc/data through a link."""
    campaign_stores = {elongation.store(aspect) for aspect in elongation.ASPECTS[1:]} | {elongation.SPHERES_STORE}
    for entry in DATA_DIR.iterdir():
        if entry.name not in campaign_stores:
            (tmp_path / entry.name).symlink_to(entry)
    store = tmp_path / elongation.store(4.0)
    for f in (0.0, 0.32):
        run = store / f"D0.06_f{f:g}_s{SEED}"
        shutil.copytree(DATA_DIR / FIG2C["2nd", f], run)
        info = (run / "run.txt").read_text()
        assert "\naspect 3.3\n" in info
        (run / "run.txt").write_text(info.replace("\naspect 3.3\n", "\naspect 4.0\n"))
    return tmp_path


def test_a_store_is_picked_up_as_its_runs_land(data_with_a_store):
    data = data_with_a_store
    point = elongation.rod_point(data, 4.0, "a")
    slope_f, ends_f = rates_over(DATA_DIR / FIG2C["2nd", 0.32])
    slope_ref, ends_ref = rates_over(DATA_DIR / FIG2C["2nd", 0.0])
    assert point.ratio.n == 1 and point.planned == 2
    assert point.ratio.value == pytest.approx(ends_f / ends_ref, rel=1e-9)
    assert point.value_cell() == f"{point.ratio.value:.2f} ± {point.ratio.se:.2f}"
    assert elongation.rod_point(data, 4.0, "b").missing == "under way"      # no 1.28 Hz run yet
    table = elongation.data_table(data)
    assert f"| 3a | 4.0 | Q(0.32 Hz)/Q(0) | 2–4 s | {point.value_cell()} | 1 of 2 |" in table
    assert "| 3a | 2.5 | Q(0.32 Hz)/Q(0) | 2–4 s | under way | 0 of 2 |" in table
    # the orifice series of the copied run at rest covers 4-8 s only: left out
    orifice = {(p.aspect, p.f): p for p in elongation.orifice_points(data) if p.window == elongation.EARLY}
    assert orifice[4.0, 0.0].n == 0
    assert orifice[4.0, 0.32].n == 1
    own = elongation.run_orifice_means(DATA_DIR / FIG2C["2nd", 0.32], (2, 4))
    assert orifice[4.0, 0.32].values["v_z"] == pytest.approx(own["v_z"])


def copy_run(source, target, **changes):
    """A stored run copied to `target`, its run.txt's keys changed ("f": (old, new))."""
    shutil.copytree(source, target)
    info = (target / "run.txt").read_text()
    for key, (old, new) in changes.items():
        assert f"\n{key} {old}\n" in info
        info = info.replace(f"\n{key} {old}\n", f"\n{key} {new}\n")
    (target / "run.txt").write_text(info)


def test_fig_3a_over_4_8_s_pairs_the_8_s_runs_and_leaves_4_s_runs_out(data_with_a_store):
    """Over 4-8 s (LATE): a store's 8 s runs give the point, from the same
    4-8 s of both; its 4 s runs none ("records end at"). At 3.3 the 8 s
    runs at rest are the Fig. 2c campaign's, the 0.32 Hz ones the
    elongation campaign's L/d = 3.3 store. Here both stores hold the
    second packing's 8 s run at 0.16 Hz as if at 0.32 Hz (the 4.0 store
    its run at rest too), so the two points are the same ratio."""
    data = data_with_a_store
    assert elongation.rod_point(data, 4.0, "a", elongation.LATE).ratio.n == 0     # the fixture's 0.32 Hz run: 4 s
    table = elongation.data_table(data)
    assert "| 4.0 | 0.32 | 2nd | 4–8 s | — (records end at " in table
    late_032 = DATA_DIR / "silo3d_rods_drop_8s" / f"D0.06_f0.16_s{SEED}"
    copy_run(late_032, data / elongation.store(3.3) / f"D0.06_f0.32_s{SEED}", f=(0.16, 0.32))
    store = data / elongation.store(4.0)
    shutil.rmtree(store)
    copy_run(DATA_DIR / FIG2C["2nd", 0.0], store / f"D0.06_f0_s{SEED}", aspect=(3.3, 4.0))
    copy_run(late_032, store / f"D0.06_f0.32_s{SEED}", f=(0.16, 0.32), aspect=(3.3, 4.0))
    at_3_3 = elongation.rod_point(data, 3.3, "a", elongation.LATE)
    at_4_0 = elongation.rod_point(data, 4.0, "a", elongation.LATE)
    assert [p[0] for p in at_3_3.ratio.parts] == ["2nd"] and at_3_3.planned == 2
    runs_3_3 = {0.0: data / FIG2C["2nd", 0.0], 0.32: data / elongation.store(3.3) / f"D0.06_f0.32_s{SEED}"}
    assert_parts_are_rate_ratios(at_3_3, lambda packing, f: runs_3_3[f], 0.32, 0.0, (4, 8), within=2)
    assert at_4_0.ratio.value == at_3_3.ratio.value and at_4_0.ratio.se == at_3_3.ratio.se
    # the same 8 s runs give the 2-4 s point too, and it differs
    early = elongation.rod_point(data, 4.0, "a")
    slope_f, ends_f = rates_over(late_032, 2, 4)
    assert early.ratio.value == pytest.approx(ends_f / rates_over(DATA_DIR / FIG2C["2nd", 0.0], 2, 4)[1], rel=1e-9)
    assert abs(early.ratio.value - at_4_0.ratio.value) > early.ratio.se + at_4_0.ratio.se
    # the orifice averages over 4-8 s: at 3.3 at rest the two 8 s runs' own
    orifice = {(p.aspect, p.f): p for p in elongation.orifice_points(data) if p.window == elongation.LATE}
    own = [elongation.run_orifice_means(DATA_DIR / FIG2C[packing, 0.0], (4, 8)) for packing in ("1st", "2nd")]
    assert orifice[3.3, 0.0].n == 2
    assert orifice[3.3, 0.0].values["v_z"][0] == pytest.approx(np.mean([m["v_z"][0] for m in own]))
    assert orifice[3.3, 0.32].n == 1 and orifice[4.0, 0.32].n == 1
    table = elongation.data_table(data)
    assert f"| 3a | 3.3 | Q(0.32 Hz)/Q(0) | 4–8 s | {at_3_3.value_cell()} | 1 of 2 |" in table
    assert "| 3b | 3.3 | Q(1.28 Hz)/Q(0.32 Hz) | 4–8 s" not in table        # Fig. 3b: 2-4 s only


def test_a_run_cut_short_of_4_s_is_left_out(data_with_a_store):
    data = data_with_a_store
    path = data / elongation.store(4.0) / f"D0.06_f0.32_s{SEED}" / "discharge.txt"
    lines = path.read_text().splitlines(keepends=True)
    tau, _ = discharge(path.parent)
    kept = [line for line in lines if line.startswith("#")] + \
           [line for line, t in zip((l for l in lines if not l.startswith("#")), tau) if t < 3.5]
    path.write_text("".join(kept))
    point = elongation.rod_point(data, 4.0, "a")
    assert point.ratio.n == 0 and point.value_cell() == "under way"
    table = elongation.data_table(data)
    assert f"| 4.0 | 0.32 | 2nd | 2–4 s | — (records end at {tau[tau < 3.5][-1]:.2f} s) |" in table


def test_a_run_txt_that_does_not_match_its_place_in_the_store_is_an_error(data_with_a_store):
    run = data_with_a_store / elongation.store(4.0) / f"D0.06_f0_s{SEED}"
    (run / "run.txt").write_text((run / "run.txt").read_text().replace("\naspect 4.0\n", "\naspect 3.3\n"))
    with pytest.raises(ValueError, match="aspect"):
        elongation.rod_point(data_with_a_store, 4.0, "a")


def write_orifice_series(run_dir, times, columns):
    """A hand-built orifice_timeseries.md: one row per time, the columns given."""
    names = ["t", *columns]
    rows = ["| " + " | ".join(names) + " |", "|" + "---|" * len(names)]
    rows += ["| " + " | ".join(f"{v:.6g}" for v in (t, *(columns[n][k] for n in columns))) + " |"
             for k, t in enumerate(times)]
    (run_dir / "orifice_timeseries.md").write_text("test: orifice-region averages per frame\n\n" +
                                                    "\n".join(rows) + "\n")


def test_the_spheres_orifice_averages_come_from_stage_8s_runs(data_with_a_store):
    """Stage 8's store (the bench's sphere runs again, with dumps), laid
    out by hand: two packings' runs at 0.32 Hz, their records the bench's,
    each with a series of constant phi and v_z every 0.05 s over 0.5-2 s
    (no O_zz: spheres). The point is the mean of the two constants, its
    error their spread over sqrt(2); a series that starts after the
    window's start is left out; O_zz stays empty."""
    data = data_with_a_store
    constants = {PACKINGS["1st"]: (0.40, -0.31), PACKINGS["2nd"]: (0.42, -0.33)}
    times = np.arange(0.5, 2.0001, 0.05)
    for seed, (phi, v_z) in constants.items():
        run = data / elongation.SPHERES_STORE / f"D0.06_f0.32_s{seed}"
        shutil.copytree(DATA_DIR / SPHERES[60, 0.32, seed], run)
        write_orifice_series(run, times, {"phi": [phi] * times.size, "v_z": [v_z] * times.size})
    late = data / elongation.SPHERES_STORE / f"D0.06_f0_s{PACKINGS['1st']}"
    shutil.copytree(DATA_DIR / SPHERES[60, 0.0, PACKINGS["1st"]], late)
    write_orifice_series(late, times[10:], {"phi": [0.5] * (times.size - 10), "v_z": [-0.3] * (times.size - 10)})
    points = {p.f: p for p in elongation.orifice_points(data) if p.aspect == 1.0}
    at_032 = points[0.32]
    assert at_032.n == 2 and at_032.planned == 3 and at_032.window == (0.5, 2)
    assert at_032.values["phi"] == pytest.approx((0.41, 0.01))
    assert at_032.values["v_z"] == pytest.approx((-0.32, 0.01))
    assert "O_zz" not in at_032.values
    assert points[0.0].n == 0 and points[0.0].note.startswith("under way")
    table = elongation.data_table(data)
    assert "| 1 (spheres) | 0.32 | 0.5–2 s | 2 of 3 | 0.410 ± 0.010 | -0.320 ± 0.010 | — |  |" in table
    # a run.txt that says rods is an error, as in the rods' stores
    info = late / "run.txt"
    info.write_text(info.read_text().replace("\nshape sphere\n", "\nshape rod\n"))
    with pytest.raises(ValueError, match="shape"):
        elongation.orifice_points(data)


def test_stage_8s_spheres_are_the_bench_runs_whose_q_fig_3_uses():
    """The spheres' orifice averages and their Fig. 3 ratios come from the
    same trajectories: each archived stage-8 run's discharge.txt is the
    cross-host bench's LIGGGHTS run's (results.SPHERES), line for line."""
    runs = sorted((DATA_DIR / elongation.SPHERES_STORE).glob("D0.06_f*_s*"))
    if not runs:
        pytest.skip("stage 8 has archived no run yet")
    for run in runs:
        info = {line.split()[0]: line.split()[1] for line in (run / "run.txt").read_text().splitlines()
                if line and not line.startswith("#")}
        bench = DATA_DIR / SPHERES[60, float(info["f"]), int(info["seed"])]
        assert (run / "discharge.txt").read_text() == (bench / "discharge.txt").read_text(), run.name


def test_the_committed_table_and_page_block_agree_with_the_records():
    assert elongation.main(["--check"]) == 0
