"""analysis.pile2d.discharges and the driver's record handling on hand-computed inputs."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from analysis.pile2d import discharges as pile2d
from analysis.common.tables import read_rows
from analysis.common import hosts
from analysis.pile2d import driver as pile2d_driver

ROOT = Path(__file__).resolve().parent.parent

HEADER = "# model L w seed h n_out h0 n_pile w_gap t_end status dt_fraction damping rolling_damping\n"


def record(model, length, w, seed, h, status=1):
    return f"{model} {length} {w} {seed} {h} 10 12.0 300 {w} 50.0 {status} 25 0.3 0.3\n"


def test_read_discharges_skips_a_cut_line_and_keeps_the_model_name(tmp_path):
    path = tmp_path / "d.txt"
    path.write_text(HEADER + record("fixed", 50, 4.2, 15485863, 3.5)
                    + HEADER + record("none", 20, 1, 15485867, 0) + "overlap 20 1 1548")
    rows = read_rows(path)
    assert [r["model"] for r in rows] == ["fixed", "none"]
    assert rows[0]["w"] == 4.2 and rows[0]["h"] == 3.5 and rows[1]["seed"] == 15485867.0


def test_height_table_places_each_sample_by_seed_and_width():
    rows = [{"model": "fixed", "L": 20.0, "w": w, "seed": s, "h": h, "status": 1.0}
            for w, s, h in [(1.0, 11, 5.0), (2.0, 11, 4.0), (1.0, 13, 6.0)]]
    rows.append({"model": "none", "L": 20.0, "w": 1.0, "seed": 11, "h": 9.0, "status": 1.0})
    widths, seeds, table = pile2d.height_table(rows, "fixed", 20.0)
    assert list(widths) == [1.0, 2.0] and seeds == [11, 13]
    assert table[0, 0] == 5.0 and table[0, 1] == 4.0 and table[1, 0] == 6.0
    assert math.isnan(table[1, 1])


def test_well_sampled_drops_widths_run_for_few_piles():
    table = np.array([[5.0, 1.0, 0.0], [4.0, np.nan, 0.0], [6.0, np.nan, np.nan], [5.0, np.nan, 0.0]])
    widths, kept = pile2d.well_sampled([1.0, 1.4, 1.8], table)
    assert list(widths) == [1.0, 1.8]           # 1.4: 1 of 4 piles; 1.8: 3 of 4
    assert kept.shape == (4, 2) and kept[0, 1] == 0.0


def test_mean_std_ci_by_hand():
    # 1, 2, 3, 4: mean 2.5, s = sqrt(5/3) = 1.290994; t(0.975, 3) = 3.182446
    # -> half width 3.182446 * 1.290994 / 2 = 2.054252; chi2(0.975, 3) =
    # 9.348404, chi2(0.025, 3) = 0.215795 -> s sqrt(3/9.348404) = 0.731335,
    # s sqrt(3/0.215795) = 4.813534
    mean, std, (lo, hi), (s_lo, s_hi) = pile2d.mean_std_ci([1, 2, 3, 4])
    assert mean == 2.5
    assert std == pytest.approx(1.290994, abs=1e-6)
    assert (lo, hi) == pytest.approx((2.5 - 2.054252, 2.5 + 2.054252), abs=1e-5)
    assert (s_lo, s_hi) == pytest.approx((0.731335, 4.813534), abs=1e-5)
    assert math.isnan(pile2d.mean_std_ci([3.0])[1])


def test_threshold_width_is_the_width_of_largest_fluctuation():
    assert pile2d.threshold_width([1, 2, 3, 4], [0.0, 1.0, 3.0, 2.0]) == 3.0
    # a plateau of two widths: their middle
    assert pile2d.threshold_width([1, 2, 3, 4], [1.0, 3.0, 3.0, 0.0]) == 2.5
    assert pile2d.threshold_width([1, 2], [math.nan, 0.5]) == 2.0
    assert math.isnan(pile2d.threshold_width([1, 2], [math.nan, math.nan]))


def test_bootstrap_of_identical_seeds_does_not_move():
    # identical rows give std 0 at every width -> a tie over all widths ->
    # their mean, in every replicate
    table = np.tile([5.0, 5.0, 0.0, 0.0], (8, 1))
    values = pile2d.bootstrap_threshold([1, 2, 3, 4], table, 50, np.random.default_rng(3))
    assert np.all(values == 2.5)


def test_bootstrap_follows_the_seeds():
    # half the seeds collapse at w = 3, the other half at w = 4: only the
    # column w = 3 has a spread. A replicate drawing only one kind has std 0
    # at every width -> the mean of all widths, 2.5.
    table = np.array([[5.0, 5.0, 0.0, 0.0]] * 5 + [[5.0, 5.0, 5.0, 0.0]] * 5)
    assert pile2d.threshold_width([1, 2, 3, 4], pile2d.column_std(table)) == 3.0
    values = pile2d.bootstrap_threshold([1, 2, 3, 4], table, 400, np.random.default_rng(5))
    assert set(np.unique(values)) <= {2.5, 3.0}
    # P(all 10 draws from one half) = 2 / 2^10: nearly all replicates say 3
    assert np.mean(values == 3.0) > 0.98


def test_half_jam_width_by_hand():
    # jammed fractions 1, 3/4, 1/4, 0 at w = 1..4: half between 2 and 3
    jammed = np.array([[1, 1, 1, 0], [1, 1, 0, 0], [1, 1, 0, 0], [1, 0, 0, 0]], dtype=float)
    assert pile2d.half_jam_width([1, 2, 3, 4], jammed) == pytest.approx(2.5)
    # fractions 1, 0.6, 0.2: 0.5 is a quarter of the way from 0.6 to 0.2
    jammed = np.array([[1, 1, 1], [1, 1, 0], [1, 1, 0], [1, 0, 0], [1, 0, 0]], dtype=float)
    assert pile2d.half_jam_width([2.0, 2.4, 2.8], jammed) == pytest.approx(2.5)
    # exactly half at a grid width: that width; missing samples are left out
    jammed = np.array([[1, 1, 0], [1, 0, 0], [1, np.nan, 0]])
    assert pile2d.half_jam_width([1, 2, 3], jammed) == pytest.approx(2.0)
    # never below one half on the grid: NaN
    assert math.isnan(pile2d.half_jam_width([1, 2], np.ones((3, 2))))


def test_jammed_table_marks_piles_that_kept_more_than_half_their_height():
    # pile 0 (h0 10): h 6 and 4 at two widths; pile 1 (h0 10): 9.9, missing
    table = np.array([[6.0, 4.0], [9.9, np.nan]])
    jammed = pile2d.jammed_table(table, [10.0, 10.0])
    assert jammed[0].tolist() == [1.0, 0.0]
    assert jammed[1, 0] == 1.0 and math.isnan(jammed[1, 1])
    # exactly half is not a jam
    assert pile2d.jammed_table([[5.0]], [10.0])[0, 0] == 0.0


def test_fit_critical_width_exact_line_and_standard_errors_by_hand():
    # w_t = 5 + 20 / L exactly
    lengths = [20.0, 50.0, 100.0]
    w_c, slope, _, _ = pile2d.fit_critical_width(lengths, [5 + 20 / L for L in lengths],
                                                 [0.1, 0.1, 0.1])
    assert w_c == pytest.approx(5.0, abs=1e-10) and slope == pytest.approx(20.0, abs=1e-8)
    # x = 1/L = 0.01, 0.02, 0.03 with sigma 1: var(w_c) = sum x^2 / (n sum x^2
    # - (sum x)^2) = 0.0014 / (0.0042 - 0.0036) = 7/3; var(a) = n / 0.0006 = 5000
    _, _, se_c, se_a = pile2d.fit_critical_width([100.0, 50.0, 100.0 / 3], [1.0, 2.0, 4.0],
                                                 [1.0, 1.0, 1.0])
    assert se_c == pytest.approx(math.sqrt(7 / 3), rel=1e-9)
    assert se_a == pytest.approx(math.sqrt(5000), rel=1e-9)
    # unweighted: errors from the residuals; two points -> no estimate
    assert math.isnan(pile2d.fit_critical_width([20.0, 50.0], [6.0, 5.0])[2])


def test_critical_width_from_tables_recovers_the_lines_w_c():
    # synthetic ensembles whose w_t is exactly 4 + 40/L (L = 20, 40, 80 ->
    # 6, 5, 4.5): half the seeds jam up to w_t, the other half collapse from
    # w_t on, so only the column w = w_t has a spread
    def table(w_t, widths):
        late = [5.0 if w < w_t + 0.25 else 0.0 for w in widths]
        early = [5.0 if w < w_t - 0.25 else 0.0 for w in widths]
        return np.array([late] * 6 + [early] * 6)
    widths = np.arange(1.0, 9.0, 0.5)
    tables = {length: (widths, table(4 + 40 / length, widths)) for length in (20.0, 40.0, 80.0)}
    # a size with a single pile is left out
    tables[160.0] = (widths, table(4.25, widths)[:1])
    result = pile2d.critical_width(tables, 200, np.random.default_rng(7))
    assert result["L"] == [20.0, 40.0, 80.0]
    assert result["w_t"] == [6.0, 5.0, 4.5]
    assert result["w_c"] == pytest.approx(4.0)
    assert result["slope"] == pytest.approx(40.0)
    assert result["chi2_dof"] == pytest.approx(0.0, abs=1e-12)
    # nearly every replicate keeps every w_t, so the joint bootstrap agrees
    assert result["w_c_bootstrap_mean"] == pytest.approx(4.0, abs=0.1)


def test_probability_density_integrates_to_one():
    centres, density = pile2d.probability_density([0, 0, 1, 5, 5, 5], bins=np.linspace(0, 6, 7))
    assert np.sum(density * 1.0) == pytest.approx(1.0)
    assert density[0] == pytest.approx(2 / 6) and density[5] == pytest.approx(3 / 6)
    assert list(centres) == [0.5, 1.5, 2.5, 3.5, 4.5, 5.5]


def test_choose_pdf_widths():
    widths = [1.0, 1.4, 1.8, 2.2, 2.6, 3.0, 3.4, 3.8]
    assert pile2d.choose_pdf_widths(widths, 2.3) == [1.0, 2.2, 3.4]
    assert pile2d.choose_pdf_widths(widths, 3.4) == [1.0, 3.4, 3.8]


def test_cli_writes_the_report_and_figures(tmp_path):
    rng = np.random.default_rng(11)
    lines = [HEADER]
    for model, base in (("none", 2.0), ("fixed", 4.0)):
        for length in (20, 50):
            w_t = base + 20.0 / length
            for seed in pile2d_driver.prime_seeds(8):
                collapse_at = w_t + rng.normal(0, 0.4)
                for w in np.arange(1.0, 8.0, 0.4):
                    h = 10.0 + rng.normal(0, 0.5) if w < collapse_at else 0.0
                    lines.append(record(model, length, round(w, 1), seed, h))
    path = tmp_path / "discharges.txt"
    path.write_text("".join(lines))
    out = tmp_path / "analysis"
    result = subprocess.run([sys.executable, "-m", "analysis.pile2d", str(path), "--out", str(out),
                             "--bootstrap", "100"], cwd=ROOT, capture_output=True, text=True,
                            timeout=300)
    assert result.returncode == 0, result.stderr
    report = (out / "summary.md").read_text()
    assert "| fixed | 20 | 8 |" in report and "| none |" in report
    for name in ("fig4_h_vs_w.png", "fig5_wt_vs_inverse_L.png", "fig6_pdf_h_none.png",
                 "fig6_pdf_h_fixed.png"):
        assert (out / name).stat().st_size > 1000


# ---------------------------------------------------------------- driver

def test_prime_seeds_are_the_primes_from_the_first():
    assert pile2d_driver.prime_seeds(3, 10000) == [10007, 10009, 10037]
    assert pile2d_driver.prime_seeds(2) == [15485863, 15485867]


def test_driver_reads_done_samples_and_ignores_a_cut_line(tmp_path):
    path = tmp_path / "d.txt"
    path.write_text(HEADER + record("fixed", 50, 4.2, 15485863, 3.5) + "fixed 50 4.6 154")
    done = pile2d_driver.read_records(path, ("model", "L", "w", "seed"))
    assert done == {("fixed", 50.0, 4.2, 15485863.0)}
    assert pile2d_driver.width_key("4.2") == pile2d_driver.width_key(4.2000000001)


def test_driver_refuses_bad_seeds_and_vars():
    with pytest.raises(SystemExit):
        pile2d_driver.parse(["--campaign", "x", "--L", "20", "--widths", "1", "--seed-list", "15485864"])
    with pytest.raises(SystemExit):
        pile2d_driver.parse(["--campaign", "x", "--L", "20", "--widths", "1", "--var", "quick"])


def test_driver_resumes_a_copied_record_without_rebuilding_its_finished_piles(tmp_path, monkeypatch):
    """A finished pile's record copied without its restart file: nothing to
    run, so the driver must not start LIGGGHTS (here: would fail loudly)."""
    seed = pile2d_driver.prime_seeds(1)[0]
    (tmp_path / "piles.txt").write_text(
        pile2d_driver.PILES_HEADER + "\n"
        f"fixed 20.0 {seed} 120 5.1 20 200 30.0 90.0 1 25 0.3 0.3 gone.restart 0.1 0.05\n")
    (tmp_path / "discharges.txt").write_text(
        pile2d_driver.DISCHARGES_HEADER + "\n" +
        "".join(f"fixed 20.0 {w} {seed} 0 100 5.1 120 {w} 50 1 25 0.3 0.3\n" for w in (3.0, 4.0)))
    monkeypatch.setattr(hosts, "LIGGGHTS_BINARY", tmp_path / "no_such_liggghts")
    args = pile2d_driver.parse(["--campaign", str(tmp_path), "--models", "fixed", "--L", "20",
                                "--seeds", "1", "--widths", "3", "4"])
    runner = pile2d_driver.Runner(args)
    assert runner.run() == []
    assert runner.total == 0 and runner.done == 0
    # one width more: the pile is rebuilt for it (and LIGGGHTS is called)
    args = pile2d_driver.parse(["--campaign", str(tmp_path), "--models", "fixed", "--L", "20",
                                "--seeds", "1", "--widths", "3", "4", "5"])
    runner = pile2d_driver.Runner(args)
    failures = runner.run()
    assert runner.total == 2 and len(failures) == 1 and "in.build" in failures[0]


FAKE_LIGGGHTS = """#!/bin/bash
# stands in for LIGGGHTS in the driver's tests: in.build appends a pile line
# with $FAKE_N_PILE grains (and, as the deck, the header to an empty file)
# and writes the restart; in.discharge a record line
while [ $# -gt 0 ]; do
    case $1 in
        -in) deck=$2; shift 2 ;;
        -var) eval "var_$2=\\$3"; shift 3 ;;
        *) shift ;;
    esac
done
case $deck in
    *in.build) touch "$var_pile"
        test -s "$var_piles" || echo "$FAKE_PILES_HEADER" > "$var_piles"
        echo "$var_model $var_L $var_seed $FAKE_N_PILE 5.1 20 200 30.0 90.0 1 25 0.3 0.3 $var_pile 0.1 0.05" >> "$var_piles" ;;
    *in.discharge) echo "$var_model $var_L $var_w $var_seed 0 100 5.1 120 $var_w 50 1 25 0.3 0.3" >> "$var_results" ;;
esac
"""


def fake_record_without_restart(tmp_path, monkeypatch, n_pile):
    """A pile recorded with 120 grains and one discharge, its restart gone,
    and a fake LIGGGHTS that rebuilds it with n_pile grains."""
    seed = pile2d_driver.prime_seeds(1)[0]
    (tmp_path / "piles.txt").write_text(
        pile2d_driver.PILES_HEADER + "\n"
        f"fixed 20.0 {seed} 120 5.1 20 200 30.0 90.0 1 25 0.3 0.3 gone.restart 0.1 0.05\n")
    (tmp_path / "discharges.txt").write_text(
        pile2d_driver.DISCHARGES_HEADER + "\n"
        f"fixed 20.0 3.0 {seed} 0 100 5.1 120 3.0 50 1 25 0.3 0.3\n")
    binary = tmp_path / "fake_liggghts"
    binary.write_text(FAKE_LIGGGHTS)
    binary.chmod(0o755)
    monkeypatch.setattr(hosts, "LIGGGHTS_BINARY", binary)
    monkeypatch.setenv("FAKE_N_PILE", str(n_pile))
    monkeypatch.setenv("FAKE_PILES_HEADER", pile2d_driver.PILES_HEADER)
    args = pile2d_driver.parse(["--campaign", str(tmp_path), "--models", "fixed", "--L", "20",
                                "--seeds", "1", "--widths", "3", "4"])
    return pile2d_driver.Runner(args), seed


def test_driver_rebuilds_the_recorded_pile_without_a_second_line(tmp_path, monkeypatch):
    runner, seed = fake_record_without_restart(tmp_path, monkeypatch, n_pile=120)
    assert runner.run() == []
    assert runner.total == 2 and runner.done == 2
    piles = read_rows(tmp_path / "piles.txt", text=True)
    assert [(row["seed"], row["n_pile"]) for row in piles] == [(str(seed), "120")]
    assert pile2d_driver.read_records(tmp_path / "discharges.txt", ("w",)) == {(3.0,), (4.0,)}


def test_driver_refuses_to_discharge_a_rebuilt_pile_that_is_not_the_recorded_one(
        tmp_path, monkeypatch):
    runner, seed = fake_record_without_restart(tmp_path, monkeypatch, n_pile=121)
    failures = runner.run()
    assert len(failures) == 1 and "n_pile 120 -> 121" in failures[0]
    # no discharge of the other pile, and its restart kept out of the next run
    assert pile2d_driver.read_records(tmp_path / "discharges.txt", ("w",)) == {(3.0,)}
    restart = runner.restart_path("fixed", 20.0, seed)
    assert not restart.exists() and restart.with_name(restart.name + ".differs").exists()
    assert len(read_rows(tmp_path / "piles.txt", text=True)) == 1
    assert pile2d_driver.rebuilt_pile_problem({"n_pile": "5", "h0": "1.5"},
                                              {"n_pile": "5", "h0": "1.5"}) is None


def test_driver_rebuilds_a_pile_only_when_discharges_need_it():
    needs = pile2d_driver.needs_build
    assert needs(recorded=False, restart_exists=False, missing_widths=[])      # build-only run
    assert needs(recorded=False, restart_exists=True, missing_widths=[4.2])    # no record: build
    assert needs(recorded=True, restart_exists=False, missing_widths=[4.2])    # restart gone, work left
    assert not needs(recorded=True, restart_exists=True, missing_widths=[4.2])
    # every discharge recorded: a copied record without its restart files stays as it is
    assert not needs(recorded=True, restart_exists=False, missing_widths=[])
