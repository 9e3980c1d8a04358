"""analysis.silo2d.clogs on hand-made inputs whose answers are worked out here, by
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

from analysis.common.stats import mean_t_ci  # noqa: E402
from analysis.silo2d import clogs as silo2d  # noqa: E402


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
    assert "3 clogs, 1 with an arch, 3 arch grains (members reading), 6 contacts" in result.stdout
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


# ------------------------------------------------------------------ arch readings

def write_feet(directory):
    """The two feet of clog 1 (orders 0 and eta + 1 = 4), resting on base
    grains 1 and 5: left foot phi 100, fn 200 N, in the pocket beside its
    outlet grain (on the floor); right foot phi 250, fn 600 N, on its
    outlet grain alone."""
    write_table(directory / "feet.txt", "clog order id x y z phi fn ft base floor",
                [(1, 0, 10, -2.5, 0.0, 0.5, 100.0, 200.0, 5.0, 1, 1),
                 (1, 4, 14, 1.5, 0.0, 0.5, 250.0, 600.0, 15.0, 5, 0)])


def test_eta_and_arch_grains_under_each_reading(tmp_path):
    """One arch of 3 members (clog 1), a time-out (clog 2), no arch (3):
    members -> eta [3], grains 11 12 13; feet -> eta [5], grains 10..14
    in walk order, with the feet's angles and forces."""
    write_records(tmp_path)
    write_feet(tmp_path)
    tables = silo2d.read_records(tmp_path)
    feet = silo2d.read_feet(tmp_path)
    clogs, arches = tables["clogs"], tables["arches"]
    assert silo2d.arch_sizes(clogs, feet, "members").tolist() == [3]
    assert silo2d.arch_sizes(clogs, feet, "outlet").tolist() == [4]
    assert silo2d.arch_sizes(clogs, feet, "feet").tolist() == [5]
    outlet = silo2d.arch_grains(arches, feet, "outlet")
    assert outlet["id"].tolist() == [11, 12, 13, 14]     # the foot on the floor is left out
    members = silo2d.arch_grains(arches, feet, "members")
    assert members["id"].tolist() == [11, 12, 13]
    grains = silo2d.arch_grains(arches, feet, "feet")
    assert grains["id"].tolist() == [10, 11, 12, 13, 14]
    assert grains["order"].tolist() == [0, 1, 2, 3, 4]
    assert grains["phi"].tolist() == [100.0, 150.0, 200.0, 150.0, 250.0]
    # <f_n,a>: (300 + 400 + 500) / 3 = 400 N -> (200 + 300 + 400 + 500 + 600) / 5 = 400 N;
    # defects (phi > 180): 1 of 3 -> 2 of 5
    assert grains["fn"].mean() == pytest.approx(400.0)
    assert np.sum(grains["phi"] > 180) == 2


def test_feet_reading_needs_two_feet_per_arch(tmp_path):
    write_records(tmp_path)
    assert silo2d.read_feet(tmp_path) is None
    with pytest.raises(ValueError, match="needs feet.txt"):
        silo2d.arch_sizes(silo2d.read_records(tmp_path)["clogs"], None, "feet")
    write_table(tmp_path / "feet.txt", "clog order id x y z phi fn ft base floor",
                [(1, 0, 10, -2.0, 0.0, 0.5, 100.0, 200.0, 5.0, 1, 0)])
    with pytest.raises(ValueError, match=r"clogs \[1\] do not have exactly two feet"):
        silo2d.arch_sizes(silo2d.read_records(tmp_path)["clogs"], silo2d.read_feet(tmp_path), "feet")
    with pytest.raises(ValueError, match="reading must be one of"):
        silo2d.arch_sizes(silo2d.read_records(tmp_path)["clogs"], None, "bottom")


def test_cli_feet_reading(tmp_path):
    write_records(tmp_path)
    write_feet(tmp_path)
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "analysis.silo2d", str(tmp_path), "--out", str(out),
                             "--reading", "feet"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "5 arch grains (feet reading)" in result.stdout
    # arch grains 200..600 N: mean 400 N = 40 m g
    assert "| <fn_a> | 40.000 |" in (out / "table1.md").read_text()
    (tmp_path / "feet.txt").unlink()
    result = subprocess.run([sys.executable, "-m", "analysis.silo2d", str(tmp_path), "--out", str(out),
                             "--reading", "feet"], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode != 0 and "needs feet.txt" in result.stderr


def test_cli_default_reading_is_outlet_and_members_without_feet(tmp_path):
    """The default reading is 'outlet' (4 grains: the three members and the
    right foot, on its outlet grain alone); records without feet.txt fall
    back to 'members' and say so."""
    write_records(tmp_path)
    write_feet(tmp_path)
    out = tmp_path / "out"
    command = [sys.executable, "-m", "analysis.silo2d", str(tmp_path), "--out", str(out)]
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "4 arch grains (outlet reading)" in result.stdout
    (tmp_path / "feet.txt").unlink()
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "no feet.txt in these records" in result.stdout
    assert "3 arch grains (members reading)" in result.stdout


# ------------------------------------------------------------------ statistics of a scan

def test_mean_t_ci_by_hand():
    # 1, 2, 3: mean 2, s = 1, t(0.975, 2) = 4.302653 -> half 4.302653 / sqrt(3)
    mean, half = mean_t_ci([1.0, 2.0, 3.0])
    assert mean == 2.0 and half == pytest.approx(4.302653 / math.sqrt(3), rel=1e-6)
    assert math.isnan(mean_t_ci([5.0])[1])


def test_wilson_interval_by_hand():
    # p = 0.2, n = 50, z = 1.959964: centre (0.2 + z^2/100) / (1 + z^2/50),
    # half z sqrt(0.2*0.8/50 + z^2/10000) / (1 + z^2/50)
    z = 1.959964
    centre = (0.2 + z * z / 100) / (1 + z * z / 50)
    half = z * math.sqrt(0.2 * 0.8 / 50 + z * z / 10000) / (1 + z * z / 50)
    p, low, high = silo2d.wilson_interval(10, 50)
    assert p == 0.2
    assert (low, high) == pytest.approx((centre - half, centre + half), rel=1e-6)


def test_force_ratio_pools_the_clogs():
    groups = [silo2d.force_sums([30.0, 50.0], [10.0]), silo2d.force_sums([40.0], [20.0, 30.0])]
    # arch mean (30 + 50 + 40) / 3 = 40, bulk mean (10 + 20 + 30) / 3 = 20
    assert silo2d.force_ratio(groups) == pytest.approx(2.0)
    assert math.isnan(silo2d.force_ratio([silo2d.force_sums([30.0], [])]))


def test_bootstrap_over_clogs_of_identical_clogs_has_no_width():
    groups = [silo2d.force_sums([3.0], [2.0])] * 5
    low, high = silo2d.bootstrap_over_clogs(groups, silo2d.force_ratio, np.random.default_rng(1))
    assert low == high == pytest.approx(1.5)


def test_most_frequent_and_exponential_tail_rate():
    assert silo2d.most_frequent([3, 5, 5, 4, 3]) == 3      # tie: the smaller
    assert silo2d.most_frequent([4, 5, 5, 6]) == 5
    # excess over 5 of [5, 6, 7, 8]: mean 1.5 -> lambda = ln(1 + 1/1.5) = ln(5/3)
    assert silo2d.exponential_tail_rate([2, 3, 5, 6, 7, 8], 5) == pytest.approx(math.log(5 / 3))
    # a large geometric sample of rate 0.4 gives back 0.4 within its spread
    rng = np.random.default_rng(7)
    sample = 5 + rng.geometric(1 - math.exp(-0.4), 20000) - 1
    assert silo2d.exponential_tail_rate(sample, 5) == pytest.approx(0.4, abs=0.02)
    assert math.isnan(silo2d.exponential_tail_rate([1, 2, 6], 5))
