#!/usr/bin/python3
"""The clogging silo in LAMMPS against LIGGGHTS' 207 arches at mu = 0.4
(issue 46, part 3; doc/silo2d.md, "LAMMPS").

Runs (or resumes) a LAMMPS campaign through analysis.silo2d.driver --host
lammps ($SILOKIT_LMP, the plugin from $SILOKIT_LAMMPS_PLUGIN, the decks from
$SILOKIT_INPUTS) in the campaign directory given on the command line, with
the paper's silo and the parameters of LIGGGHTS' campaign
(doc/data/silo2d_scan/mu0.4/parameters.txt: dt 2e-5 s, seed 32452843),
until --arches; one engine at a time, at nice 10. The two hosts' flows part
within about a second (the plates' Coulomb cap: doc/silo2d.md, "LAMMPS"),
so they are compared by their statistics, not clog by clog.

Per quantity, with analysis.silo2d's own reductions and the filters of the
page's results table (analysis.silo2d.results: the plain walk `members` for
the angles and forces, the bulk window 27 < h/d < 48, |x| < 12 d):

- each host's value and 95 % interval by the page's method: mean eta
  Student t over arches; the eta mode, <f_n,b>, <f_n,a> and their ratio
  bootstrapped over clogs (analysis.silo2d.scan, bootstrap seed 1; the
  LIGGGHTS column is therefore the results table's row); the mean angle
  bootstrapped over clogs (seed 2); the avalanche size (grains out
  between two arches), which the page does not give, Student t;
- LAMMPS - LIGGGHTS with its 95 % interval: Welch for the means over
  arches (eta, avalanche), else the percentile bootstrap over each host's
  clogs (2000 resamples);
- a two-sample test of the distributions: eta (integers) Mann-Whitney U
  and chi-square on the counts (sizes pooled so that every expected count
  is >= 5); the avalanche sizes (one per arch) Kolmogorov-Smirnov;
  phi, f_n of the bulk contacts and of the arch grains Kolmogorov-Smirnov
  with its p-value from 1000 permutations of whole clogs between the hosts
  (the grains and contacts of one clog are not independent: the iid
  p-value, also written to the raw file, is far too small); the force
  ratio, a permutation test over clogs of |difference|.

The weak-contact tail, and the plates: the fraction of each clog's bulk
contacts with f_n < 0.1 m g, per host, with the plates' friction of the
campaign (mu_plate = mu) and with frictionless plates (mu_plate = 0, where
both hosts' plates are the same law): LIGGGHTS' run
doc/data/silo2d_plate/mu0.4_plate0 and a LAMMPS one, run with
--plate0-campaign DIR (to --plate0-arches, default 5) and reduced into
doc/data/silo2d_cross_host/mu0.4_plate0/. Per run the mean over clogs with
its Student-t interval; between the hosts, Mann-Whitney U on the clogs'
fractions.

CPU: LAMMPS' from the campaign's segments.txt (the engine's user + system
time per segment), LIGGGHTS' from doc/data/silo2d_scan/mu0.4/segments.txt.

Writes bench/results/silo2d_cross_host.txt, the LAMMPS run reduced as the
scan's runs are (analysis.campaign.silo2d_archive: the bulk window's and
the walks' contacts, surfaces and profile sums) into
doc/data/silo2d_cross_host/mu0.4/, and the section `silo2d_cross_host` of
doc/silo2d.md.

    SILOKIT_LMP=... SILOKIT_LAMMPS_PLUGIN=... /usr/bin/python3 bench/silo2d_cross_host.py runs/silo2d_cross_host
        # 100 arches, ~45 CPU-min; the same command resumes, a larger --arches extends
    SILOKIT_LMP=... /usr/bin/python3 bench/silo2d_cross_host.py runs/silo2d_cross_host \
        --plate0-campaign runs/silo2d_lammps_plate0   # and the frictionless plates' run, ~25 CPU-min more
    /usr/bin/python3 bench/silo2d_cross_host.py --report-only      # no engine: doc/data alone
    /usr/bin/python3 bench/silo2d_cross_host.py --quick            # the small silo, 3 arches, ~1 CPU-min
"""

import argparse
import os
import shutil
import sys
from pathlib import Path

import numpy as np
from scipy import stats

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.campaign import silo2d_archive  # noqa: E402
from analysis.common import hosts  # noqa: E402
from analysis.common.stats import mean_t_ci  # noqa: E402
from analysis.silo2d import clogs as silo2d  # noqa: E402
from analysis.silo2d import driver  # noqa: E402
from analysis.silo2d import results  # noqa: E402
from analysis.silo2d import scan as silo2d_scan  # noqa: E402

SECTION = "silo2d_cross_host"
PAGE = benchlib.ROOT / "doc" / "silo2d.md"
DATA = benchlib.ROOT / "doc" / "data"
LIGGGHTS_RUN = DATA / "silo2d_scan" / "mu0.4"
SCAN_RUNS = tuple(str(DATA / "silo2d_scan" / f"mu{mu:g}") for mu in results.MUS)
RECORDS = DATA / SECTION / "mu0.4"
# frictionless plates: LIGGGHTS' run of the plate test, and the LAMMPS one's records
LIGGGHTS_PLATE0 = DATA / "silo2d_plate" / "mu0.4_plate0"
PLATE0_RECORDS = DATA / SECTION / "mu0.4_plate0"
WEAK = 0.1          # m g: a bulk contact below this is in the weak tail
MU = 0.4
NICE = 10
SEGMENT_TIME = 10.0
RESAMPLES = 2000
PERMUTATIONS = 1000
DIFFERENCE_SEED, PERMUTATION_SEED = 3, 4
LEVEL = 0.95
PLAIN, OUTLET = results.PLAIN, results.OUTLET


# ---------------------------------------------------------------- the campaign

def liggghts_parameters():
    """dt and seed of LIGGGHTS' campaign (its parameters.txt)."""
    values = dict(line.split() for line in (LIGGGHTS_RUN / "parameters.txt").read_text().splitlines())
    return float(values["dt"]), int(values["seed"])


def run_campaign(campaign, arches, quick, plate_friction=None):
    """The LAMMPS campaign through the driver until `arches` (with the
    plates' friction `plate_friction` if given, else mu); its exit code."""
    dt, seed = liggghts_parameters()
    argv = ["--host", "lammps", "--nice", str(NICE), "--campaign", str(campaign), "--mu", f"{MU:g}",
            "--arches", str(arches), "--dt", f"{dt:g}", "--seed", str(seed),
            "--segment-time", f"{2.0 if quick else SEGMENT_TIME:g}"]
    if quick:
        argv.append("--quick")
    if plate_friction is not None:
        argv += ["--var", f"mu_plate={plate_friction:g}"]
    benchlib.progress(f"LAMMPS campaign: analysis.silo2d.driver {' '.join(argv)}")
    return driver.main(argv)


def cpu_per_arch(run_dir):
    """(CPU seconds of the complete segments, arches after them) of a run."""
    segments = driver.completed_segments(Path(run_dir))
    if not segments:
        return 0.0, 0
    return sum(float(s["cpu_s"]) for s in segments), int(segments[-1]["arches"])


# ---------------------------------------------------------------- per host

def host_data(run_dir):
    """What the comparison needs of one host's run: the clog groups of the
    plain walk (analysis.silo2d.scan.clog_groups) with each clog's arch
    angles, arch-grain and bulk forces (in m g), and eta under both readings
    and the avalanche sizes, one per arch."""
    run = silo2d_scan.load_run(run_dir)
    tables, geometry = run["tables"], run["geometry"]
    weight = geometry["mass"] * geometry["g"]
    arches = silo2d.arch_grains(tables["arches"], run["feet"], PLAIN)
    groups = silo2d_scan.clog_groups(run, arches)
    contacts = tables["contacts"]
    bulk_clog, bulk_fn = contacts["clog"][run["bulk"]], contacts["fn"][run["bulk"]]
    clogs = tables["clogs"]
    found = np.atleast_1d(clogs["status"]) == 1
    for group, clog in zip(groups, np.atleast_1d(clogs["clog"])[found]):
        group["arch_fn"] = arches["fn"][arches["clog"] == clog] / weight
        group["bulk_fn"] = bulk_fn[bulk_clog == clog] / weight
    return {"groups": groups, "weight": weight,
            "eta": {reading: silo2d.arch_sizes(clogs, run["feet"], reading) for reading in (PLAIN, OUTLET)},
            "avalanche": np.atleast_1d(clogs["avalanche"])[found].astype(float)}


def welch_difference(a, b, level=LEVEL):
    """mean(b) - mean(a) and its Welch interval."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    va, vb = a.var(ddof=1) / a.size, b.var(ddof=1) / b.size
    dof = (va + vb) ** 2 / (va ** 2 / (a.size - 1) + vb ** 2 / (b.size - 1))
    half = stats.t.ppf(0.5 + level / 2, dof) * np.sqrt(va + vb)
    difference = b.mean() - a.mean()
    return difference, difference - half, difference + half


def bootstrap_difference(groups_a, groups_b, statistic, rng, resamples=RESAMPLES, level=LEVEL):
    """statistic(b) - statistic(a) and its percentile interval, resampling
    each host's clogs."""
    na, nb = len(groups_a), len(groups_b)
    values = np.array([statistic([groups_b[k] for k in rng.integers(0, nb, nb)])
                       - statistic([groups_a[k] for k in rng.integers(0, na, na)])
                       for _ in range(resamples)])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return np.nan, np.nan, np.nan
    tail = 100 * (1 - level) / 2
    return (statistic(groups_b) - statistic(groups_a), float(np.percentile(values, tail)),
            float(np.percentile(values, 100 - tail)))


def pooled(groups, key):
    return np.concatenate([g[key] for g in groups]) if groups else np.zeros(0)


def largest_cdf_gap(a, b):
    """(value, F_a, F_b) where the two empirical distributions differ most:
    where the KS distance sits."""
    values = np.sort(np.concatenate([a, b]))
    cdf_a = np.searchsorted(np.sort(a), values, side="right") / a.size
    cdf_b = np.searchsorted(np.sort(b), values, side="right") / b.size
    k = int(np.argmax(np.abs(cdf_a - cdf_b)))
    return float(values[k]), float(cdf_a[k]), float(cdf_b[k])


def ks_distance(sorted_values, first, n_first):
    """Two-sample KS distance of the values (sorted) split by the mask
    `first` (n_first of them true): max |F_1 - F_2| over the ends of runs
    of equal values."""
    cdf_first = np.cumsum(first) / n_first
    cdf_second = np.cumsum(~first) / (first.size - n_first)
    ends = np.flatnonzero(np.append(sorted_values[1:] != sorted_values[:-1], True))
    return float(np.max(np.abs(cdf_first[ends] - cdf_second[ends])))


def ks_over_clogs(groups_a, groups_b, key, rng, permutations=PERMUTATIONS):
    """KS statistic of the pooled values `key` of two hosts' clogs, its iid
    p-value, and its p-value from permutations of whole clogs (nan for
    an empty sample)."""
    if pooled(groups_a, key).size == 0 or pooled(groups_b, key).size == 0:
        return np.nan, np.nan, np.nan
    observed = stats.ks_2samp(pooled(groups_a, key), pooled(groups_b, key), method="asymp")
    every = list(groups_a) + list(groups_b)
    values = pooled(every, key)
    clog_of_value = np.repeat(np.arange(len(every)), [np.size(g[key]) for g in every])
    order = np.argsort(values, kind="stable")
    values, clog_of_value = values[order], clog_of_value[order]
    sizes = np.array([np.size(g[key]) for g in every])
    # the distance as this function computes it, so that the permuted ones compare alike
    in_a = np.arange(len(every)) < len(groups_a)
    distance = ks_distance(values, in_a[clog_of_value], sizes[in_a].sum())
    exceed = 0
    for _ in range(permutations):
        in_first = np.zeros(len(every), dtype=bool)
        in_first[rng.permutation(len(every))[:len(groups_a)]] = True
        exceed += ks_distance(values, in_first[clog_of_value], sizes[in_first].sum()) >= distance - 1e-12
    return observed.statistic, observed.pvalue, (exceed + 1) / (permutations + 1)


def permutation_test(groups_a, groups_b, statistic, rng, permutations=PERMUTATIONS):
    """p-value of |statistic(b) - statistic(a)| under exchange of whole clogs."""
    observed = abs(statistic(groups_b) - statistic(groups_a))
    if not np.isfinite(observed):
        return np.nan
    every = list(groups_a) + list(groups_b)
    exceed = 0
    for _ in range(permutations):
        order = rng.permutation(len(every))
        first = [every[k] for k in order[:len(groups_a)]]
        second = [every[k] for k in order[len(groups_a):]]
        exceed += abs(statistic(second) - statistic(first)) >= observed
    return (exceed + 1) / (permutations + 1)


def pooled_counts(a, b, minimum=5):
    """Contingency table of the integer samples a, b: sizes pooled from the
    ends inwards until every expected count is >= minimum. Returns (labels, 2 x k)."""
    values = np.arange(min(a.min(), b.min()), max(a.max(), b.max()) + 1)
    table = np.array([[np.sum(a == v) for v in values], [np.sum(b == v) for v in values]], float)
    labels = [str(int(v)) for v in values]

    def expected(t):
        return t.sum(axis=1, keepdims=True) * t.sum(axis=0, keepdims=True) / t.sum()

    while table.shape[1] > 2 and expected(table).min() < minimum:
        column = int(np.argmin(expected(table).min(axis=0)))
        neighbour = column + 1 if column == 0 else column - 1 if column == table.shape[1] - 1 else (
            column - 1 if table[:, column - 1].sum() <= table[:, column + 1].sum() else column + 1)
        low, high = sorted((column, neighbour))
        table[:, low] += table[:, high]
        labels[low] = f"{labels[low].split('-')[0]}-{labels[high].split('-')[-1]}"
        table = np.delete(table, high, axis=1)
        del labels[high]
    return labels, table


def pooled_mean(kind, weight):
    """<f_n> over the clogs of a sample, contacts (kind "bulk") or arch
    grains ("arch") pooled as analysis.silo2d.scan does, in units of `weight`."""
    def statistic(groups):
        n = sum(g[kind + "_n"] for g in groups)
        return sum(g[kind + "_sum"] for g in groups) / n / weight if n else np.nan
    return statistic


def phi_mean(groups):
    return float(np.mean(pooled(groups, "phi")))


# ---------------------------------------------------------------- the comparison

def compare(liggghts_dir, liggghts_scan, lammps_dir):
    """Rows of the comparison: dicts with the quantity, each host's value
    text, the difference (value, low, high), the test's name and p-value,
    and the raw lines."""
    page_rows = results.scan_rows(liggghts_scan)
    lammps_rows = results.scan_rows((str(lammps_dir),))
    page_phi = results.phi_means(liggghts_scan)
    lammps_phi = results.phi_means((str(lammps_dir),))
    mu = round(MU, 3)
    # the other run's own mu (0.4 in the campaign; another for a check of this script)
    (other_mu,) = {key[0] for key in lammps_rows}
    weight_rows = {"liggghts": {r: page_rows[(mu, r)] for r in (PLAIN, OUTLET)},
                   "lammps": {r: lammps_rows[(other_mu, r)] for r in (PLAIN, OUTLET)}}
    data = {"liggghts": host_data(liggghts_dir), "lammps": host_data(lammps_dir)}
    a, b = data["liggghts"], data["lammps"]
    rng_difference = np.random.default_rng(DIFFERENCE_SEED)
    rng_test = np.random.default_rng(PERMUTATION_SEED)
    rows, raw = [], []

    for reading, name in ((PLAIN, "plain walk"), (OUTLET, "`outlet` reading")):
        eta_a, eta_b = a["eta"][reading], b["eta"][reading]
        row_a, row_b = weight_rows["liggghts"][reading], weight_rows["lammps"][reading]
        u = stats.mannwhitneyu(eta_a, eta_b, alternative="two-sided")
        labels, table = pooled_counts(eta_a, eta_b)
        chi2 = stats.chi2_contingency(table)
        rows.append({"quantity": f"mean η, {name}",
                     "liggghts": f"{row_a['eta_mean'][0]:.2f} ± {row_a['eta_mean'][1]:.2f}",
                     "lammps": f"{row_b['eta_mean'][0]:.2f} ± {row_b['eta_mean'][1]:.2f}",
                     "difference": welch_difference(eta_a, eta_b), "digits": 2,
                     "test": f"Mann-Whitney U: p = {u.pvalue:.2g}; χ² ({table.shape[1] - 1} dof): "
                             f"p = {chi2.pvalue:.2g}",
                     "p": min(u.pvalue, chi2.pvalue)})
        rows.append({"quantity": f"η mode, {name}",
                     "liggghts": results._mode(row_a), "lammps": results._mode(row_b),
                     "difference": None, "test": "(the distribution: row above)", "p": None})
        raw.append(f"# eta {reading}: counts per size {labels}: LIGGGHTS {table[0].astype(int).tolist()}, "
                   f"LAMMPS {table[1].astype(int).tolist()}; Mann-Whitney U {u.statistic:g} p {u.pvalue:.4g}; "
                   f"chi2 {chi2.statistic:.4g} dof {chi2.dof} p {chi2.pvalue:.4g}")

    phi_difference = bootstrap_difference(a["groups"], b["groups"], phi_mean, rng_difference)
    ks = ks_over_clogs(a["groups"], b["groups"], "phi", rng_test)
    rows.append({"quantity": "mean φ (°), plain walk",
                 "liggghts": results._interval(*page_phi[mu]), "lammps": results._interval(*lammps_phi[other_mu]),
                 "difference": phi_difference, "digits": 1,
                 "test": f"KS D = {ks[0]:.3f}: p = {ks[2]:.2g} (clogs permuted)", "p": ks[2]})
    raw.append(f"# phi: KS D {ks[0]:.4g}, iid p {ks[1]:.4g}, clog-permutation p {ks[2]:.4g}")

    if not np.isclose(a["weight"], b["weight"], rtol=1e-6):
        raise SystemExit(f"{SECTION}: the grains' weights differ ({a['weight']} N, {b['weight']} N)")
    for key, label, kind, column in (("bulk_fn", "⟨f_n,b⟩ / m g", "bulk", "fn_b"),
                                     ("arch_fn", "⟨f_n,a⟩ / m g", "arch", "fn_a")):
        statistic = pooled_mean(kind, a["weight"])
        texts = []
        for host in ("liggghts", "lammps"):
            row = weight_rows[host][PLAIN]
            texts.append(f"{row[column][0]:.1f} [{row[column + '_boot'][0]:.1f}, {row[column + '_boot'][1]:.1f}]")
        difference = bootstrap_difference(a["groups"], b["groups"], statistic, rng_difference)
        ks = ks_over_clogs(a["groups"], b["groups"], key, rng_test)
        forces_a, forces_b = pooled(a["groups"], key), pooled(b["groups"], key)
        where = largest_cdf_gap(forces_a, forces_b) if forces_a.size and forces_b.size else (np.nan,) * 3
        rows.append({"quantity": label + ", plain walk", "liggghts": texts[0], "lammps": texts[1],
                     "difference": difference, "digits": 1,
                     "test": f"KS D = {ks[0]:.3f} (at {where[0]:.2g} m g): p = {ks[2]:.2g} (clogs permuted)",
                     "p": ks[2]})
        raw.append(f"# {key}: KS D {ks[0]:.4g}, iid p {ks[1]:.4g}, clog-permutation p {ks[2]:.4g}; "
                   f"values LIGGGHTS {forces_a.size}, LAMMPS {forces_b.size}; largest gap at "
                   f"{where[0]:.4g} m g: F LIGGGHTS {where[1]:.4f}, LAMMPS {where[2]:.4f}; fraction "
                   + ", ".join(f"<= {t:g} m g: LIGGGHTS {np.mean(forces_a <= t):.4f}, "
                               f"LAMMPS {np.mean(forces_b <= t):.4f}" for t in (0.1, 1.0, 10.0))
                   + f"; medians {np.median(forces_a):.4g}, {np.median(forces_b):.4g}" if forces_a.size
                   and forces_b.size else f"# {key}: an empty sample")

    ratio_difference = bootstrap_difference(a["groups"], b["groups"], silo2d.force_ratio, rng_difference)
    ratio_p = permutation_test(a["groups"], b["groups"], silo2d.force_ratio, rng_test)
    texts = [f"{weight_rows[h][PLAIN]['ratio']:.2f} [{weight_rows[h][PLAIN]['ratio_ci'][0]:.2f}, "
             f"{weight_rows[h][PLAIN]['ratio_ci'][1]:.2f}]" for h in ("liggghts", "lammps")]
    rows.append({"quantity": "⟨f_n,a⟩/⟨f_n,b⟩, plain walk", "liggghts": texts[0], "lammps": texts[1],
                 "difference": ratio_difference, "digits": 2,
                 "test": f"permutation of clogs, \\|Δ\\|: p = {ratio_p:.2g}", "p": ratio_p})

    av_a, av_b = a["avalanche"], b["avalanche"]
    ks = stats.ks_2samp(av_a, av_b)
    u = stats.mannwhitneyu(av_a, av_b, alternative="two-sided")
    texts = [f"{m:.1f} ± {h:.1f}" for m, h in (mean_t_ci(av_a), mean_t_ci(av_b))]
    rows.append({"quantity": "avalanche size (grains)", "liggghts": texts[0], "lammps": texts[1],
                 "difference": welch_difference(av_a, av_b), "digits": 1,
                 "test": f"KS D = {ks.statistic:.3f}: p = {ks.pvalue:.2g}", "p": ks.pvalue})
    raw.append(f"# avalanche: KS D {ks.statistic:.4g} p {ks.pvalue:.4g}; Mann-Whitney p {u.pvalue:.4g}; "
               f"medians LIGGGHTS {np.median(av_a):g}, LAMMPS {np.median(av_b):g}")
    arches = {"liggghts": weight_rows["liggghts"][PLAIN]["arches"], "lammps": weight_rows["lammps"][PLAIN]["arches"]}
    return rows, raw, arches


# ---------------------------------------------------------------- report

def interval_text(difference, digits):
    value, low, high = difference
    if not np.isfinite(value):
        return "n/a"
    return f"{value:+.{digits}f} [{low:+.{digits}f}, {high:+.{digits}f}]"


def agrees(row):
    """The interval of the difference holds 0 and the test does not reject
    at 5 %; rows without a difference or a test: None."""
    if row["difference"] is None or row["p"] is None or not np.isfinite(row["difference"][0]):
        return None
    _, low, high = row["difference"]
    return bool(low <= 0 <= high and row["p"] >= 0.05)


def cost_text(run_dir, host):
    cpu, arches = cpu_per_arch(run_dir)
    if not arches:
        return f"{host}: no complete segment with an arch", None
    per_100 = cpu / arches * 100 / 3600
    return (f"{host}: {arches} arches in {cpu / 3600:.2f} CPU-hours ({arches / cpu * 3600:.0f} arches per "
            f"CPU-hour), {per_100:.2f} CPU-hours per 100 arches"), per_100


def weak_fractions(run_dir):
    """Per clog of a run, the fraction of its bulk contacts (the table's
    window) with f_n below WEAK m g."""
    return np.array([np.mean(group["bulk_fn"] < WEAK) for group in host_data(run_dir)["groups"]])


def weak_tail_text(liggghts_dir, lammps_records, plate0_records):
    """The weak-contact tail per host, with the campaign's plates and with
    frictionless ones where both hosts' runs exist: a markdown table."""
    runs = [("μ_plate = μ = 0.4", liggghts_dir, lammps_records),
            ("μ_plate = 0", LIGGGHTS_PLATE0, plate0_records)]
    lines = [f"| plates | LIGGGHTS: clogs, fraction of bulk contacts with f_n < {WEAK:g} m g "
             "(mean over clogs, 95 %) | LAMMPS: the same | Mann-Whitney U over clogs |",
             "|---|---|---|---|"]
    for plates, liggghts_run, lammps_run in runs:
        if not ((Path(liggghts_run) / "clogs.txt").exists() and (Path(lammps_run) / "clogs.txt").exists()):
            lines.append(f"| {plates} | (not run) | | |")
            continue
        cells, fractions = [], []
        for run in (liggghts_run, lammps_run):
            values = weak_fractions(run)
            mean, half = mean_t_ci(values)
            fractions.append(values)
            cells.append(f"{values.size}: {100 * mean:.2f} ± {100 * half:.2f} %")
        test = stats.mannwhitneyu(fractions[0], fractions[1], alternative="two-sided")
        lines.append(f"| {plates} | {cells[0]} | {cells[1]} | p = {test.pvalue:.2g} |")
    return "\n".join(lines)


def report(rows, raw, arches, lammps_records, quick, weak_tail=""):
    table = [f"| quantity | LIGGGHTS ({arches['liggghts']} arches) | LAMMPS ({arches['lammps']} arches) | "
             "LAMMPS − LIGGGHTS [95 %] | two-sample test | agree |",
             "|---|---|---|---|---|---|"]
    verdicts = []
    for row in rows:
        verdict = agrees(row)
        verdicts.append(verdict)
        difference = "" if row["difference"] is None else interval_text(row["difference"], row["digits"])
        p = "" if verdict is None else ("yes" if verdict else "**no**")
        table.append(f"| {row['quantity']} | {row['liggghts']} | {row['lammps']} | {difference} | "
                     f"{row['test']} | {p} |")
    judged = [v for v in verdicts if v is not None]
    differing = [row["quantity"] for row, v in zip(rows, verdicts) if v is False]
    tests = len(judged)
    if not differing:
        verdict = (f"All {tests} quantities agree: every difference's 95 % interval holds 0 and no test "
                   f"rejects at 5 %.")
    else:
        smallest = min(row["p"] for row, v in zip(rows, verdicts) if v is False)
        verdict = (f"{len(differing)} of {tests} quantities differ at 5 % ({'; '.join(differing)}; smallest "
                   f"p = {smallest:.2g}). With {tests} tests, one rejection at 5 % is expected by chance "
                   f"about {tests * 0.05:.1f} times; the Bonferroni threshold is p < {0.05 / tests:.3f}.")
    liggghts_cost, liggghts_100 = cost_text(LIGGGHTS_RUN, "LIGGGHTS (the scan, `doc/data/silo2d_scan/mu0.4/segments.txt`)")
    lammps_cost, lammps_100 = cost_text(lammps_records, "LAMMPS (`segments.txt` of the records)")
    ratio = (f" LAMMPS / LIGGGHTS = {lammps_100 / liggghts_100:.2f}." if liggghts_100 and lammps_100 else "")
    dt, seed = liggghts_parameters()
    shown = benchlib.shown_path(lammps_records)
    smoke = ("**Smoke run (`--quick`): the small silo against the paper's; the numbers mean "
             "nothing.**\n\n" if quick else "")
    text = f"""### LAMMPS against LIGGGHTS' arches at μ = 0.4 (bench/silo2d_cross_host.py)

{smoke}The {'small' if quick else "paper's"} silo at μ = 0.4 in LAMMPS (`analysis.silo2d.driver --host lammps`,
one rank, Δt = {dt:g} s, seed {seed}, the parameters of LIGGGHTS' scan) against
LIGGGHTS' scan at μ = 0.4 (`doc/data/silo2d_scan/mu0.4`); the LAMMPS records
are in [`{shown.relative_to('doc') if str(shown).startswith('doc') else shown}`]({shown.relative_to('doc') if str(shown).startswith('doc') else shown}/).
The flows part within about a second (above), so the hosts are compared by
their statistics. Values and 95 % intervals by the results table's methods
(its filters: the plain walk's angles and forces, the bulk window
27 < h/d < 48, |x| < 12 d; forces in m g); the LIGGGHTS column is the
table's. The difference: Welch for the means over arches, else a
percentile bootstrap over each host's clogs ({RESAMPLES} resamples). Tests:
η Mann-Whitney U and χ² on the counts (sizes pooled until every expected
count is ≥ 5); φ and the forces Kolmogorov-Smirnov with the p-value from
{PERMUTATIONS} permutations of whole clogs between the hosts (a clog's
grains and contacts are not independent); the ratio a permutation test of
clogs; the avalanche sizes (grains out between two arches, one per arch;
Student t) Kolmogorov-Smirnov. "agree": the difference's interval holds 0
and p ≥ 0.05 (for η, the smaller p of its two tests).

{chr(10).join(table)}

{verdict}

The weak-contact tail of the bulk force, with the campaign's plates and
with frictionless plates (where both hosts' plates are the same law; the
runs: `doc/data/silo2d_plate/mu0.4_plate0` and
`doc/data/silo2d_cross_host/mu0.4_plate0`):

{weak_tail}

CPU (user + system of the engine, one rank):
- {liggghts_cost};
- {lammps_cost}.{ratio}

{provenance()}
- LAMMPS records made by: {engine_text(lammps_records)}
"""
    raw_text = "\n".join([f"# {SECTION}: LAMMPS ({benchlib.shown_path(lammps_records)}) against LIGGGHTS "
                           f"({benchlib.shown_path(LIGGGHTS_RUN)})",
                          f"# {benchlib.command_line()}"]
                         + [f"{row['quantity']} | LIGGGHTS {row['liggghts']} | LAMMPS {row['lammps']} | "
                            f"difference {'' if row['difference'] is None else interval_text(row['difference'], 3)}"
                            f" | {row['test']}" for row in rows]
                         + raw + [f"# {liggghts_cost}", f"# {lammps_cost}", "# the weak-contact tail:"]
                         + weak_tail.splitlines()) + "\n"
    return text, raw_text


def provenance():
    """benchlib.provenance's lines but the LIGGGHTS binary's (no LIGGGHTS ran)."""
    info = benchlib.machine()
    return "\n".join([f"- machine: {info['nproc']} cores, {info['cpu']}, {info['system']}",
                      f"- date: {info['date']}; load average at the end (1/5/15 min): {info['load']}",
                      f"- command (from the repository root): `{benchlib.command_line()}`",
                      f"- silokit commit: {benchlib.git_commit()}"])


ENGINE_FILE = "engine.txt"


def engine_text(records):
    """The engine that made the records, as archive_run wrote it."""
    path = Path(records) / ENGINE_FILE
    return path.read_text().strip() if path.exists() else "(not recorded)"


def archive_run(run_dir, records):
    """The LAMMPS run reduced into `records` (analysis.campaign.silo2d_archive),
    with the campaign's host.txt and the engine's identity (engine.txt, for
    --report-only, which runs none)."""
    total, kept = silo2d_archive.archive(run_dir, records)
    host = Path(run_dir).parent / "host.txt"
    if host.exists():
        shutil.copyfile(host, records / "host.txt")
    plugin = os.environ.get("SILOKIT_LAMMPS_PLUGIN")
    plugin_text = benchlib.binary_identity(Path(plugin)) if plugin else "silokit_lammps.so (next to lmp)"
    (records / ENGINE_FILE).write_text(f"{benchlib.binary_identity(hosts.LAMMPS_BINARY)}; plugin "
                                       f"{plugin_text}\n")
    benchlib.progress(f"archived {run_dir} into {benchlib.shown_path(records)}: {kept} of {total} contacts")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("campaign", nargs="?", type=Path,
                        help="the LAMMPS campaign's directory (run or resumed there; not with --report-only)")
    parser.add_argument("--arches", type=int, default=100, help="arches wanted from LAMMPS (default 100)")
    parser.add_argument("--report-only", dest="report_only", action="store_true",
                        help="no engine: report from doc/data alone")
    parser.add_argument("--quick", action="store_true",
                        help="the small silo, 3 arches, under bench/work/quick/ (a smoke run)")
    parser.add_argument("--plate0-campaign", dest="plate0_campaign", type=Path,
                        help="also run (or resume) LAMMPS with frictionless plates there")
    parser.add_argument("--plate0-arches", dest="plate0_arches", type=int, default=5,
                        help="arches wanted from the frictionless plates' run (default 5)")
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        quick_dir = benchlib.WORK / "quick"
        campaign, arches = args.campaign or quick_dir / SECTION, 3
        page, records = quick_dir / "silo2d.md", quick_dir / "data" / SECTION / "mu0.4"
        plate0_records = quick_dir / "data" / SECTION / "mu0.4_plate0"
    else:
        campaign, arches = args.campaign, args.arches
        page, records, plate0_records = PAGE, RECORDS, PLATE0_RECORDS
        if campaign is None and not args.report_only:
            parser.error("the campaign directory is needed (or --report-only)")
    if not args.report_only:
        status = run_campaign(campaign, arches, args.quick)
        if status != 0:
            raise SystemExit(f"{SECTION}: the driver failed (exit {status})")
        archive_run(driver.run_directory(campaign, MU), records)
        if args.plate0_campaign:
            status = run_campaign(args.plate0_campaign, args.plate0_arches, args.quick, plate_friction=0)
            if status != 0:
                raise SystemExit(f"{SECTION}: the driver failed with frictionless plates (exit {status})")
            archive_run(driver.run_directory(args.plate0_campaign, MU), plate0_records)
    if not (records / "clogs.txt").exists():
        raise SystemExit(f"{SECTION}: no LAMMPS records in {records}: run the campaign first")
    benchlib.progress("comparing (about a minute: the scan's three runs for the LIGGGHTS rows)")
    rows, raw, arch_counts = compare(LIGGGHTS_RUN, SCAN_RUNS, records)
    weak_tail = weak_tail_text(LIGGGHTS_RUN, records, plate0_records)
    text, raw_text = report(rows, raw, arch_counts, records, args.quick, weak_tail)
    raw_path = benchlib.write_raw(SECTION, raw_text)
    benchlib.write_page_section(page, SECTION, text, "# silo2d cross-host (smoke run)\n")
    print(text)
    print(f"wrote {benchlib.shown_path(raw_path)}, {benchlib.shown_path(page)}, {benchlib.shown_path(records)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
