"""Analysis of open-pile discharges (Magalhaes et al. 2014, section III):
the order parameter h against the orifice width w with its fluctuation,
the PDF of h at three widths, the threshold width w_t(L) where the
fluctuation of h is largest, and the critical width w_c = lim w_t(L) for
L -> infinity from a linear fit of w_t against 1/L.

Reads the file in.discharge appends to (one line per discharge, columns
named by its `#` header: model L w seed h n_out h0 n_pile w_gap t_end
status ...; doc/pile2d.md, "Records").

Widths sampled for fewer than half of the piles of a (model, L) are left
out. Uncertainties: the mean of h with a Student t interval, its standard
deviation with a chi-square interval (normal approximation; h is bimodal
near w_t, so the bootstrap below is the one to trust there); w_t with a
bootstrap over seeds (a seed is one pile, discharged at every width, so
whole seeds are resampled); w_c with the standard error of a weighted
least-squares fit (weights 1/sigma(w_t)^2, scaled by sqrt(chi2/dof) when
that exceeds 1) and the spread of w_c over joint bootstrap replicates of
all sizes. Beside w_t, w_50: the width where half the piles jam (keep
more than half their height), with its bootstrap spread.

CLI:  python3 -m analysis.pile2d discharges.txt --out DIR [--bootstrap 2000]
"""

import math
import sys
from pathlib import Path

import numpy as np
from scipy import stats

from analysis.common.stats import t_quantile
from analysis.common.tables import read_rows
from analysis.common.cli import command_line

# w_c of the paper (section III), in d: model -> (value, uncertainty)
# Both "overlap" (l_c = chord of the overlap) and "depth" (l_c = overlap
# depth) are readings of the paper's "k_r ~ l_c^2" model (doc/pile2d.md).
PAPER_CRITICAL_WIDTH = {"none": (5.0, 0.1), "overlap": (5.3, 0.1), "depth": (5.3, 0.1),
                        "fixed": (7.6, 0.2)}
MODEL_LABELS = {"none": "no rolling resistance", "overlap": "k_r ~ l_c^2 (l_c = overlap chord)",
                "depth": "k_r ~ l_c^2 (l_c = overlap depth)", "fixed": "fixed l_c = 0.05 d"}
MODEL_ORDER = ("none", "overlap", "depth", "fixed")


# ---------------------------------------------------------------- reading

def height_table(rows, model, length, settled_only=False):
    """(widths, seeds, H): H[i, j] = h of seed i at width j (NaN where the
    sample is missing), for one model and substrate length."""
    chosen = [r for r in rows if r["model"] == model and r["L"] == length
              and (not settled_only or r.get("status", 1.0) == 1.0)]
    widths = sorted({round(r["w"], 6) for r in chosen})
    seeds = sorted({int(r["seed"]) for r in chosen})
    table = np.full((len(seeds), len(widths)), np.nan)
    for r in chosen:
        table[seeds.index(int(r["seed"])), widths.index(round(r["w"], 6))] = r["h"]
    return np.array(widths), seeds, table


def well_sampled(widths, table, fraction=0.5):
    """The widths (and table columns) sampled for at least `fraction` of
    the piles: a width run for a few piles only (an earlier, finer grid)
    would put a noisy standard deviation next to well-sampled ones."""
    table = np.asarray(table, dtype=float)
    counts = np.sum(~np.isnan(table), axis=0)
    keep = counts >= fraction * table.shape[0]
    return np.asarray(widths)[keep], table[:, keep]


# ---------------------------------------------------------------- statistics

def mean_std_ci(values, level=0.95):
    """mean, sample std, (mean_lo, mean_hi) Student t, (std_lo, std_hi)
    chi-square; NaN intervals with fewer than 2 values."""
    values = np.asarray(values, dtype=float)
    values = values[~np.isnan(values)]
    n = values.size
    if n == 0:
        return math.nan, math.nan, (math.nan, math.nan), (math.nan, math.nan)
    mean = float(values.mean())
    if n < 2:
        return mean, math.nan, (math.nan, math.nan), (math.nan, math.nan)
    std = float(values.std(ddof=1))
    alpha = 1.0 - level
    half = t_quantile(level, n - 1) * std / math.sqrt(n)
    std_lo = std * math.sqrt((n - 1) / stats.chi2.ppf(1 - alpha / 2, n - 1))
    std_hi = std * math.sqrt((n - 1) / stats.chi2.ppf(alpha / 2, n - 1))
    return mean, std, (mean - half, mean + half), (std_lo, std_hi)


def column_std(table):
    """Sample standard deviation of each column, NaN entries left out."""
    table = np.asarray(table, dtype=float)
    if table.ndim == 2 and table.shape[0] >= 2 and not np.isnan(table).any():
        # no NaN (the bootstrap's usual case): numpy's std(ddof=1) step by
        # step, each column a contiguous row, so the sums are the same
        # pairwise sums and the result the same bit for bit; 5x faster
        columns = np.ascontiguousarray(table.T)
        n = columns.shape[1]
        deviations = columns - np.add.reduce(columns, axis=1, keepdims=True) / n
        np.multiply(deviations, deviations, out=deviations)
        return np.sqrt(np.add.reduce(deviations, axis=1) / (n - 1))
    result = []
    for column in table.T:
        values = column[~np.isnan(column)]
        result.append(values.std(ddof=1) if values.size >= 2 else math.nan)
    return np.array(result)


def threshold_width(widths, fluctuations):
    """The width of largest fluctuation (the paper's w_t); when several
    widths share the largest value, their mean. NaN if all are NaN."""
    fluctuations = np.asarray(fluctuations, dtype=float)
    if np.all(np.isnan(fluctuations)):
        return math.nan
    largest = np.nanmax(fluctuations)
    tied = np.asarray(widths, dtype=float)[fluctuations == largest]
    return float(tied.mean())


def jammed_table(table, h0):
    """J[i, j] = 1 where pile i kept more than half its height h0[i] at
    width j (an arch held), 0 where it did not, NaN where height_table's
    cell is missing."""
    table = np.asarray(table, dtype=float)
    jammed = (table > 0.5 * np.asarray(h0, dtype=float)[:, None]).astype(float)
    jammed[np.isnan(table)] = np.nan
    return jammed


def half_jam_width(widths, jammed):
    """w_50: the width where the fraction of jammed piles first falls
    through 1/2, linear between the two grid widths around the crossing
    (a width where exactly half jam is w_50 itself); NaN if the fraction
    never crosses 1/2 on the grid. A second statistic of the transition
    beside w_t: it uses every pile at the two widths around the crossing,
    not the argmax of a noisy standard deviation, so its bootstrap spread
    is smaller; on a symmetric transition the two agree."""
    fraction = np.nanmean(np.asarray(jammed, dtype=float), axis=0)
    widths = np.asarray(widths, dtype=float)
    for k in range(len(widths) - 1):
        if fraction[k] >= 0.5 > fraction[k + 1]:
            return float(widths[k] + (fraction[k] - 0.5) / (fraction[k] - fraction[k + 1])
                         * (widths[k + 1] - widths[k]))
    return math.nan


def bootstrap_half_jam(widths, jammed, replicates, rng):
    """w_50 of `replicates` tables of rows (seeds) drawn with replacement."""
    jammed = np.asarray(jammed, dtype=float)
    n = jammed.shape[0]
    return np.array([half_jam_width(widths, jammed[rng.integers(0, n, n)])
                     for _ in range(replicates)])


def bootstrap_threshold(widths, table, replicates, rng):
    """w_t of `replicates` tables made of rows (seeds) drawn with
    replacement."""
    table = np.asarray(table, dtype=float)
    n = table.shape[0]
    values = np.empty(replicates)
    for k in range(replicates):
        values[k] = threshold_width(widths, column_std(table[rng.integers(0, n, n)]))
    return values


def fit_critical_width(lengths, thresholds, sigmas=None):
    """Weighted least squares of w_t = w_c + a / L. Returns (w_c, a,
    se(w_c), se(a)); with sigmas the standard errors are those of the
    weights (absolute), without them of the residual scatter (needs 3
    points or more, else NaN)."""
    x = 1.0 / np.asarray(lengths, dtype=float)
    y = np.asarray(thresholds, dtype=float)
    design = np.column_stack([np.ones_like(x), x])
    if sigmas is None:
        weights = np.ones_like(x)
    else:
        weights = 1.0 / np.asarray(sigmas, dtype=float) ** 2
    normal = design.T @ (design * weights[:, None])
    covariance = np.linalg.inv(normal)
    parameters = covariance @ (design.T @ (weights * y))
    if sigmas is None:
        dof = len(x) - 2
        if dof <= 0:
            return float(parameters[0]), float(parameters[1]), math.nan, math.nan
        residual = y - design @ parameters
        covariance = covariance * float(residual @ residual) / dof
    return (float(parameters[0]), float(parameters[1]),
            float(math.sqrt(covariance[0, 0])), float(math.sqrt(covariance[1, 1])))


def critical_width(tables, replicates, rng):
    """From {L: (widths, table)} (sizes with fewer than 2 piles left out):
    w_t(L), its bootstrap std, and w_c: a weighted fit of the w_t values in
    1/L (weights from the bootstrap std, floored at a quarter of the
    smallest width step so that a w_t that never moved in the bootstrap
    does not take all the weight), its standard error, and the mean and std
    of the same fit over joint bootstrap replicates (every size resampled
    at once). Needs 2 lengths or more."""
    # a size with fewer than 2 piles has no fluctuation to locate
    lengths = sorted(length for length, (_, table) in tables.items()
                     if np.sum(np.any(~np.isnan(table), axis=1)) >= 2)
    thresholds, spreads, replicas = [], [], []
    for length in lengths:
        widths, table = tables[length]
        thresholds.append(threshold_width(widths, column_std(table)))
        values = bootstrap_threshold(widths, table, replicates, rng)
        replicas.append(values)
        step = np.min(np.diff(widths)) if len(widths) > 1 else 1.0
        spreads.append(max(float(np.std(values, ddof=1)) if replicates > 1 else 0.0, step / 4))
    result = {"L": lengths, "w_t": thresholds, "w_t_sigma": spreads,
              "w_t_replicates": replicas}
    if len(lengths) >= 2:
        w_c, slope, se_c, se_slope = fit_critical_width(lengths, thresholds, spreads)
        # the same weighted fit on each joint replicate: the spread of the
        # reported estimator
        joint = np.array([fit_critical_width(lengths, [r[k] for r in replicas], spreads)[0]
                          for k in range(replicates)])
        # chi^2 per degree of freedom of the weighted fit: above 1 the w_t
        # scatter more than their bootstrap errors say, and the standard
        # error is scaled by its square root (Birge ratio)
        residual = (np.array(thresholds) - (w_c + slope / np.array(lengths))) / np.array(spreads)
        dof = len(lengths) - 2
        chi2_dof = float(residual @ residual) / dof if dof > 0 else math.nan
        scale = math.sqrt(max(1.0, chi2_dof)) if dof > 0 else 1.0
        result.update({"w_c": w_c, "slope": slope, "w_c_se": se_c * scale, "chi2_dof": chi2_dof,
                       "w_c_bootstrap_mean": float(joint.mean()),
                       "w_c_bootstrap_std": float(joint.std(ddof=1)) if replicates > 1 else math.nan})
    return result


def probability_density(values, bins):
    """Histogram density of the values (integral 1 over the bins)."""
    density, edges = np.histogram(np.asarray(values, dtype=float), bins=bins, density=True)
    return 0.5 * (edges[1:] + edges[:-1]), density


# ---------------------------------------------------------------- report

def summarize(rows, replicates=2000, seed=1, settled_only=False):
    """Per model: {L: per-width statistics} and the critical-width result."""
    rng = np.random.default_rng(seed)
    # w_50's bootstrap draws from its own generator, so that w_t's and
    # w_c's replicates are those of the same seed as before w_50 existed
    rng_w50 = np.random.default_rng([seed, 50])
    models = [m for m in MODEL_ORDER if any(r["model"] == m for r in rows)]
    models += sorted({r["model"] for r in rows} - set(models))
    summary = {}
    for model in models:
        lengths = sorted({r["L"] for r in rows if r["model"] == model})
        per_length, tables = {}, {}
        for length in lengths:
            widths, seeds, table = height_table(rows, model, length, settled_only)
            widths, table = well_sampled(widths, table)
            tables[length] = (widths, table)
            # h0 is the pile's, the same on each of its rows
            h0 = {int(r["seed"]): r["h0"] for r in rows if r["model"] == model and r["L"] == length}
            jammed = jammed_table(table, [h0[s] for s in seeds])
            w50 = bootstrap_half_jam(widths, jammed, replicates, rng_w50)
            per_length[length] = {"widths": widths, "seeds": seeds, "table": table,
                                  "stats": [mean_std_ci(table[:, j]) for j in range(len(widths))],
                                  "jammed": jammed, "w_50": half_jam_width(widths, jammed),
                                  "w_50_sigma": float(np.nanstd(w50, ddof=1))
                                  if np.sum(~np.isnan(w50)) > 1 else math.nan}
        summary[model] = {"lengths": per_length, "critical": critical_width(tables, replicates, rng)}
    return summary


def format_report(summary, rows, settled_only=False):
    unsettled = sum(1 for r in rows if r.get("status", 1) != 1)
    lines = ["# Open 2D pile: h(w), w_t(L), w_c", "",
             f"{len(rows)} discharges; {unsettled} did not reach equilibrium within max_time "
             f"({'left out' if settled_only else 'kept'}).", ""]
    lines += ["## Threshold and critical widths", "",
              "| model | L | piles | w_t (d) | bootstrap std (d) | w_50 (d) | bootstrap std (d) |",
              "|---|---|---|---|---|---|---|"]
    for model, entry in summary.items():
        critical = entry["critical"]
        for length, w_t, sigma in zip(critical["L"], critical["w_t"], critical["w_t_sigma"]):
            data = entry["lengths"][length]
            edge = " (grid edge)" if w_t in (data["widths"][0], data["widths"][-1]) else ""
            # w_50 off the grid (the fraction never falls through 1/2 on it): no value
            w50 = ("| - | - |" if math.isnan(data["w_50"])
                   else f"| {data['w_50']:.2f} | {data['w_50_sigma']:.2f} |")
            lines.append(f"| {model} | {length:g} | {len(data['seeds'])} | {w_t:.2f}{edge} | {sigma:.2f} {w50}")
    lines += ["", "| model | w_c (d), weighted fit ± se | chi2/dof | w_c bootstrap mean ± std | paper |",
              "|---|---|---|---|---|"]
    for model, entry in summary.items():
        c = entry["critical"]
        paper = PAPER_CRITICAL_WIDTH.get(model)
        paper_text = f"{paper[0]} ± {paper[1]}" if paper else "-"
        if "w_c" in c:
            lines.append(f"| {model} | {c['w_c']:.2f} ± {c['w_c_se']:.2f} | {c['chi2_dof']:.2f} | "
                         f"{c['w_c_bootstrap_mean']:.2f} ± {c['w_c_bootstrap_std']:.2f} | {paper_text} |")
        else:
            lines.append(f"| {model} | (one L only) | - | - | {paper_text} |")
    lines += ["", "## h(w): mean [95 % CI] and standard deviation [95 % CI]", ""]
    for model, entry in summary.items():
        for length, data in entry["lengths"].items():
            lines += [f"### {model}, L = {length:g} d ({len(data['seeds'])} piles)", "",
                      "| w (d) | n | mean h (d) | 95 % CI | std h (d) | 95 % CI |", "|---|---|---|---|---|---|"]
            for w, (mean, std, mean_ci, std_ci), column in zip(data["widths"], data["stats"],
                                                               data["table"].T):
                n = int(np.sum(~np.isnan(column)))
                lines.append(f"| {w:g} | {n} | {mean:.2f} | [{mean_ci[0]:.2f}, {mean_ci[1]:.2f}] | "
                             f"{std:.2f} | [{std_ci[0]:.2f}, {std_ci[1]:.2f}] |")
            lines.append("")
    return "\n".join(lines) + "\n"


def choose_pdf_widths(widths, w_t):
    """The paper's three widths for Fig. 6: the smallest (1 d), the grid
    width nearest w_t and the first grid width above w_t + 1 d (or the
    largest)."""
    widths = np.asarray(widths, dtype=float)
    first = widths[0]
    near = widths[np.argmin(np.abs(widths - w_t))]
    above = widths[widths >= w_t + 1.0]
    return [first, near, above[0] if above.size else widths[-1]]


def make_plots(summary, out, fig_length=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    written = []
    # Fig. 4: h and its fluctuation against w, at the largest L of each model
    fig, ax = plt.subplots(figsize=(6, 4))
    styles = {"none": ("o", "--"), "overlap": ("s", "-"), "depth": ("D", ":"), "fixed": ("^", "-")}
    for model, entry in summary.items():
        lengths = sorted(entry["lengths"])
        length = fig_length if fig_length in entry["lengths"] else lengths[-1]
        data = entry["lengths"][length]
        means = [s[0] for s in data["stats"]]
        stds = [s[1] for s in data["stats"]]
        marker, line = styles.get(model, ("x", ":"))
        ax.plot(data["widths"], means, marker, label=f"{model}: h (L = {length:g})")
        ax.plot(data["widths"], stds, line, label=f"{model}: std h")
    ax.set_xlabel("w / d")
    ax.set_ylabel("h / d")
    ax.legend(fontsize=7)
    fig.tight_layout()
    path = out / "fig4_h_vs_w.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    written.append(path)

    # Fig. 5: w_t against 1/L with the fits
    fig, ax = plt.subplots(figsize=(6, 4))
    for model, entry in summary.items():
        c = entry["critical"]
        x = 1.0 / np.array(c["L"])
        marker, _ = styles.get(model, ("x", ":"))
        points = ax.errorbar(x, c["w_t"], yerr=c["w_t_sigma"], fmt=marker, capsize=3, label=model)
        if "w_c" in c:
            line = np.linspace(0, x.max() * 1.05, 20)
            ax.plot(line, c["w_c"] + c["slope"] * line, "-", lw=0.8, color=points.lines[0].get_color())
        if model in PAPER_CRITICAL_WIDTH:
            # the paper's w_c on the axis, open, beside where our fit meets it
            value, error = PAPER_CRITICAL_WIDTH[model]
            ax.errorbar([0.0], [value], yerr=[error], fmt=marker, mfc="none", capsize=3,
                        color=points.lines[0].get_color(), clip_on=False)
    ax.set_xlabel("1 / L  (1/d); open at 1/L = 0: the paper's w_c")
    ax.set_ylabel("w_t / d")
    ax.set_xlim(left=0)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = out / "fig5_wt_vs_inverse_L.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    written.append(path)

    # Fig. 6: PDF of h at three widths, per model, largest L
    for model, entry in summary.items():
        lengths = sorted(entry["lengths"])
        length = fig_length if fig_length in entry["lengths"] else lengths[-1]
        data = entry["lengths"][length]
        w_t = threshold_width(data["widths"], [s[1] for s in data["stats"]])
        if math.isnan(w_t):
            continue
        fig, ax = plt.subplots(figsize=(6, 4))
        finite = data["table"][~np.isnan(data["table"])]
        top = max(float(finite.max()) if finite.size else 1.0, 1.0)
        bins = np.linspace(0, top * 1.05, 16)
        for w in choose_pdf_widths(data["widths"], w_t):
            column = data["table"][:, list(np.round(data["widths"], 6)).index(round(w, 6))]
            centres, density = probability_density(column[~np.isnan(column)], bins)
            ax.plot(centres, density, "-o", ms=3, label=f"w = {w:g} d")
        ax.set_xlabel("h / d")
        ax.set_ylabel("PDF")
        ax.set_title(f"{model}, L = {length:g} d, w_t = {w_t:g} d")
        ax.legend(fontsize=8)
        fig.tight_layout()
        path = out / f"fig6_pdf_h_{model}.png"
        fig.savefig(path, dpi=120)
        plt.close(fig)
        written.append(path)
    return written


def parse(argv):
    parser = command_line("analysis.pile2d", __doc__,
                          "/usr/bin/python3 -m analysis.pile2d runs/pile2d/discharges.txt --out "
                          "runs/pile2d/analysis")
    parser.add_argument("results", type=Path, help="the discharge record file (in.discharge's `results`)")
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="the directory the tables and figures go to (default: pile2d_analysis/ next to RESULTS)")
    parser.add_argument("--bootstrap", type=int, default=2000, help="bootstrap replicates")
    parser.add_argument("--seed", type=int, default=1, help="seed of the bootstrap's generator")
    parser.add_argument("--L", dest="fig_length", type=float, default=None,
                        help="substrate length (d) for Figs. 4 and 6 (default: each model's largest)")
    parser.add_argument("--settled-only", dest="settled_only", action="store_true",
                        help="leave out discharges that did not reach equilibrium (status 0)")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse(argv)
    rows = read_rows(args.results)
    if not rows:
        print(f"{args.results}: no discharge records", file=sys.stderr)
        return 1
    out = args.out or args.results.parent / "pile2d_analysis"
    out.mkdir(parents=True, exist_ok=True)
    summary = summarize(rows, args.bootstrap, args.seed, args.settled_only)
    report = format_report(summary, rows, args.settled_only)
    (out / "summary.md").write_text(report)
    written = make_plots(summary, out, args.fig_length)
    print(report)
    print("written: " + ", ".join(str(p) for p in [out / "summary.md"] + written))
    return 0
