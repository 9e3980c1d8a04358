"""The verdicts of the clogging silo's results table (analysis.silo2d.results)
from made-up statistics: a row agrees when its interval meets the paper's,
differs only with a cause the records show, and says so when it agrees at
the edge. The rows from doc/data are checked by tests/test_results_tables.py."""

from analysis.silo2d import results
from analysis.silo2d.results import MUS, OUTLET, PLAIN


def summary(mode=3, mode_ci=(3, 4), fn_b=20.0, fn_b_ci=(19.5, 20.5), fn_a=35.0, fn_a_ci=(33.0, 37.0),
            ratio=1.75, ratio_ci=(1.6, 1.9), arches=200):
    return {"R": 3.0, "arches": arches, "eta_mode": mode, "eta_mode_ci": mode_ci,
            "eta_mean": (4.0, 0.2), "phi_peak": 155.0, "phi_peak_ci": (145.0, 165.0),
            "defects": (0.2, 0.18, 0.22), "fn_b": (fn_b, 0, 0), "fn_b_boot": fn_b_ci,
            "fn_a": (fn_a, 0, 0), "fn_a_boot": fn_a_ci, "ratio": ratio, "ratio_ci": ratio_ci}


def scan(**plain):
    return {(mu, reading): summary(**(plain if reading == PLAIN else {"mode": 5, "mode_ci": (5, 5)}))
            for mu in MUS for reading in (PLAIN, OUTLET)}


def test_the_plain_walk_mode_differs_with_the_outlet_reading_as_its_cause():
    plain, outlet = results.eta_rows(scan())[:2]
    assert plain.verdict == "differs" and "mode is 5 at every μ" in plain.cause
    assert plain.ours == "3 [3, 4] / 3 [3, 4] / 3 [3, 4]" and plain.headline
    assert outlet.verdict == "agrees" and not outlet.cause


def test_a_mode_interval_that_reaches_r_plus_2_agrees():
    plain = results.eta_rows(scan(mode=4, mode_ci=(3, 5)))[0]
    assert plain.verdict == "agrees"


def test_table1_bulk_force_differs_only_with_the_plate_runs():
    rows = scan(fn_b=18.0, fn_b_ci=(17.5, 18.5))
    plates = {mu: summary(fn_b=19.6, fn_b_ci=(18.1, 21.9), arches=59) for mu in (0.4, 0.8)}
    bulk = [row for row in results.table1_rows(rows, scan(), plates) if row.quantity.startswith("⟨f_n,b⟩")]
    # mu = 0.2: the paper's 24 +- 2 is not met, and no plate run: open
    assert [row.verdict for row in bulk] == ["open", "differs", "differs"]
    assert "19.6 [18.1, 21.9] (59 arches)" in bulk[1].cause


def test_table1_arch_force_at_the_edge_says_so():
    rows = scan(fn_a=28.0, fn_a_ci=(26.2, 30.05))          # the paper at mu = 0.8: 32 +- 2
    walk = scan(fn_a=33.8, fn_a_ci=(31.5, 36.3))
    arch = {row.quantity: row for row in results.table1_rows(rows, walk, {})}
    edge = arch["⟨f_n,a⟩ / m g, μ = 0.8"]
    assert edge.verdict == "agrees" and edge.cause.startswith("at the edge")
    below = arch["⟨f_n,a⟩ / m g, μ = 0.4"]                  # 35 +- 3: [32, 38] not met
    assert below.verdict == "differs" and "33.8 [31.5, 36.3]" in below.cause


def test_only_the_ratio_at_mu_04_is_a_headline():
    ratios = [row for row in results.table1_rows(scan(), scan(), {}) if "/⟨f_n,b⟩" in row.quantity]
    assert [row.headline for row in ratios] == [False, True, False]
    assert all(row.verdict == "agrees" for row in ratios)
