"""analysis.silo2d on hand-made inputs whose answers are worked out here, by
hand, not with the functions under test."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import optimize

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from analysis import silo2d  # noqa: E402


# ------------------------------------------------------------------ PDFs

def test_pdf_normalisation_and_last_edge_closed():
    # bin [0,1): 0.5 ; bin [1,2]: 1.5, 1.5 and 2.0 (last edge is inside) -> 1/4, 3/4
    centres, density = silo2d.pdf([0.5, 1.5, 1.5, 2.0], [0.0, 1.0, 2.0])
    assert centres.tolist() == [0.5, 1.5]
    assert density.tolist() == pytest.approx([0.25, 0.75])


def test_pdf_unequal_widths_divides_by_width():
    # counts 1 and 3 of 4; widths 1 and 2 -> 0.25/1 and 0.75/2
    centres, density = silo2d.pdf([0.5, 1.5, 2.5, 2.9], [0.0, 1.0, 3.0])
    assert centres.tolist() == [0.5, 2.0]
    assert density.tolist() == pytest.approx([0.25, 0.375])
    assert np.sum(density * np.array([1.0, 2.0])) == pytest.approx(1.0)


def test_integer_pdf_bins_centred_on_integers():
    centres, density = silo2d.integer_pdf(np.array([3, 3, 4, 6]))
    assert centres.tolist() == [3.0, 4.0, 5.0, 6.0]
    assert density.tolist() == pytest.approx([0.5, 0.25, 0.0, 0.25])


# ------------------------------------------------------------------ binned means

def test_binned_mean_values_sem_and_edges():
    x = [0.1, 0.2, 0.9, 1.0, -0.1, 3.0, 3.01]
    y = [1.0, 3.0, 5.0, 7.0, 100.0, 9.0, 100.0]
    centres, mean, sem, count = silo2d.binned_mean(x, y, [0.0, 1.0, 2.0, 3.0])
    assert centres.tolist() == [0.5, 1.5, 2.5]
    # bin 0: 1, 3, 5 -> mean 3, sample std 2, sem 2/sqrt(3)
    # bin 1: x = 1.0 belongs to [1, 2) -> single sample 7, sem undefined
    # bin 2: x = 3.0 is on the closed last edge -> 9; -0.1 and 3.01 are outside
    assert count.tolist() == [3, 1, 1]
    assert mean.tolist() == pytest.approx([3.0, 7.0, 9.0])
    assert sem[0] == pytest.approx(2.0 / math.sqrt(3.0))
    assert np.isnan(sem[1]) and np.isnan(sem[2])


def test_binned_mean_empty_bin_is_nan():
    _, mean, sem, count = silo2d.binned_mean([0.5], [2.0], [0.0, 1.0, 2.0])
    assert count.tolist() == [1, 0]
    assert mean[0] == 2.0 and np.isnan(mean[1]) and np.isnan(sem[1])


# ------------------------------------------------------------------ selections

def test_region_boundaries_belong_to_outer_region():
    d = 0.5
    x = d * np.array([0.0, 3.99, 4.0, -4.0, 11.99, 12.0, -13.0, 16.0])
    assert silo2d.region_of(x, d).tolist() == ["C", "C", "I", "I", "I", "W", "W", "W"]


def test_region_limits_are_parameters():
    assert silo2d.region_of([2.5, 6.0], 1.0, centre_max=2.0, wall_min=6.0).tolist() == ["I", "W"]


def test_bulk_window_exclusive_and_no_wall():
    d = 2.0
    x = d * np.array([0.0, 0.0, 0.0, 0.0, 5.0, 12.0, -11.0])
    h = np.array([27.0, 27.01, 48.0, 47.99, 30.0, 30.0, 30.0])
    expected = [False, True, False, True, True, False, True]
    assert silo2d.bulk_mask(x, d * h, d).tolist() == expected


def test_force_profiles_per_region():
    d = 1.0
    x = np.array([0.0, 1.0, 5.0, 13.0, 0.5])
    z = np.array([0.2, 0.7, 0.5, 1.5, 1.2])
    fn = np.array([2.0, 4.0, 10.0, 20.0, 6.0])
    profiles = silo2d.force_profiles(x, z, fn, d)
    centres, mean, _, count = profiles["C"]
    assert centres.tolist() == [0.5, 1.5]
    assert count.tolist() == [2, 1] and mean.tolist() == pytest.approx([3.0, 6.0])
    assert profiles["I"][1][0] == 10.0 and profiles["I"][3].tolist() == [1, 0]
    assert profiles["W"][3].tolist() == [0, 1] and profiles["W"][1][1] == 20.0


# ------------------------------------------------------------------ confidence interval

def test_exponential_ci_single_sample_closed_form():
    # chi2 with 2 dof has quantile q_p = -2 ln(1 - p): the interval for one
    # sample x is [x / -ln(0.025), x / -ln(0.975)].
    mean, low, high = silo2d.exponential_mean_ci([2.0])
    assert mean == 2.0
    assert low == pytest.approx(2.0 / -math.log(0.025), rel=1e-9)
    assert high == pytest.approx(2.0 / -math.log(0.975), rel=1e-9)


def chi2_even_cdf(x, dof):
    """CDF of chi2 with even dof 2k: 1 - exp(-x/2) sum_{j<k} (x/2)^j / j!."""
    k = dof // 2
    return 1.0 - math.exp(-x / 2) * sum((x / 2) ** j / math.factorial(j) for j in range(k))


def chi2_even_quantile(p, dof):
    return optimize.brentq(lambda x: chi2_even_cdf(x, dof) - p, 1e-12, 1e4, xtol=1e-14)


def exponential_ci_by_hand(values):
    n = len(values)
    total = 2.0 * sum(values)
    return total / chi2_even_quantile(0.975, 2 * n), total / chi2_even_quantile(0.025, 2 * n)


def test_exponential_ci_three_samples_independent_quantiles():
    values = [1.0, 2.0, 6.0]
    low, high = exponential_ci_by_hand(values)
    mean, got_low, got_high = silo2d.exponential_mean_ci(values)
    assert mean == pytest.approx(3.0)
    assert (got_low, got_high) == pytest.approx((low, high), rel=1e-8)


def test_exponential_ci_coverage_monte_carlo():
    # 4000 samples of size 10 from an exponential of mean 3; the 95 % interval
    # must cover 3 in 95 % of them. Binomial sd = sqrt(.95 * .05 / 4000) =
    # 0.0034; allow 0.012 (3.5 sd). Swapped quantiles cover ~0 %, a normal
    # interval of n=10 exponentials ~91 %: both fail.
    rng = np.random.default_rng(12345)
    trials = 4000
    covered = 0
    for _ in range(trials):
        _, low, high = silo2d.exponential_mean_ci(rng.exponential(3.0, size=10))
        covered += low <= 3.0 <= high
    assert abs(covered / trials - 0.95) < 0.012


# ------------------------------------------------------------------ friction

def test_mobilized_friction_drops_zero_normal_force():
    ratio = silo2d.mobilized_friction([10.0, 0.0, 4.0], [2.0, 1.0, 4.0], 0.5)
    assert ratio.tolist() == pytest.approx([0.4, 2.0])


# ------------------------------------------------------------------ records and CLI

def write_table(path, header, rows):
    text = "# " + header + "\n" + "".join(" ".join(str(v) for v in row) + "\n" for row in rows)
    path.write_text(text)


def write_records(directory):
    """d = 1 m, m = 1 kg, g = 10: forces in m g are forces in N divided by 10."""
    write_table(directory / "clogs.txt", "clog step time avalanche eta status",
                [(1, 1000, 0.001, 50, 3, 1), (2, 9000, 0.009, 80, 0, 0), (3, 12000, 0.012, 20, 0, -1)])
    write_table(directory / "arches.txt", "clog order id x y z phi fn ft",
                [(1, 1, 11, -1.0, 0.0, 1.0, 150.0, 300.0, 10.0),
                 (1, 2, 12, 0.0, 0.0, 1.6, 200.0, 400.0, 60.0),
                 (1, 3, 13, 1.0, 0.0, 1.0, 150.0, 500.0, 20.0)])
    write_table(directory / "contacts.txt", "clog id1 id2 x z fn ft arch",
                [(1, 20, 21, 0.0, 30.0, 100.0, 10.0, 0),    # bulk, centre
                 (1, 22, 23, 5.0, 40.0, 300.0, 30.0, 0),    # bulk, intermediate
                 (1, 24, 25, 13.0, 40.0, 1000.0, 0.0, 0),   # wall: not bulk
                 (1, 26, 27, 0.0, 27.0, 5000.0, 0.0, 0),    # h/d = 27: excluded
                 (1, 28, 29, 0.0, 48.0, 5000.0, 0.0, 0),    # h/d = 48: excluded
                 (1, 11, 12, -0.5, 1.3, 350.0, 20.0, 1)])   # arch contact, low
    (directory / "silo.txt").write_text("# geometry\nd 1.0\nmass 1.0\ng 10\nmu 0.4\nR 3\n")


def test_read_records_names_missing_column(tmp_path):
    write_records(tmp_path)
    write_table(tmp_path / "arches.txt", "clog order id x y z phi fn", [])
    with pytest.raises(ValueError, match="arches.txt.*'ft'"):
        silo2d.read_records(tmp_path)


def test_table1_rows_in_units_of_mg():
    rows = silo2d.table1([100.0, 300.0], [300.0, 400.0, 500.0], mass=2.0, g=5.0, mu=0.2)
    (lb, mb, _, _, nb, pb), (la, ma, lowa, higha, na, pa) = rows
    assert (lb, mb, nb, pb) == ("<fn_b>", pytest.approx(20.0), 2, (24.0, 2.0))
    assert (la, ma, na, pa) == ("<fn_a>", pytest.approx(40.0), 3, (44.0, 3.0))
    assert (lowa, higha) == pytest.approx(exponential_ci_by_hand([30.0, 40.0, 50.0]), rel=1e-8)


def test_cli_end_to_end(tmp_path):
    records = tmp_path / "records"
    records.mkdir()
    write_records(records)
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "analysis.silo2d", str(records), "--out", str(out)],
                            cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "silo2d: reading records" in result.stdout
    assert "3 clogs, 1 with an arch, 3 arch grains, 6 contacts" in result.stdout
    # bulk: 100 and 300 N -> 200 N = 20 m g; arch grains 300, 400, 500 N -> 40 m g
    assert "<f_n,b> = 200 N over 2 bulk contacts" in result.stdout
    table = (out / "table1.md").read_text()
    low_b, high_b = exponential_ci_by_hand([10.0, 30.0])
    low_a, high_a = exponential_ci_by_hand([30.0, 40.0, 50.0])
    assert f"| <fn_b> | 20.000 | [{low_b:.3f}, {high_b:.3f}] | 2 | 20 ± 1 |" in table
    assert f"| <fn_a> | 40.000 | [{low_a:.3f}, {high_a:.3f}] | 3 | 35 ± 3 |" in table
    for name in ("eta_pdf", "phi_pdf", "force_vs_phi", "fn_profiles", "fn_pdf", "ft_pdf",
                 "mobilized_friction"):
        png = out / f"{name}.png"
        assert png.exists() and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name


def test_cli_options_override_silo_file(tmp_path):
    write_records(tmp_path)
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "analysis.silo2d", str(tmp_path), "--out", str(out),
                             "--mass", "2.0", "--mu", "0.8"],
                            cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    table = (out / "table1.md").read_text()
    assert "mu = 0.8" in table
    assert "| <fn_b> | 10.000 |" in table and "21 ± 2" in table
