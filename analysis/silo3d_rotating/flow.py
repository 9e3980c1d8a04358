"""Flow rate of the rotating-bottom silo (Pongó, Börzsönyi and Hidalgo
2022, sec. III): the analysis window of a run's discharge record, its
no-flow intervals and effective time, the stationary flow rate with block
standard errors (FlowRate), the runs' labels and their grouping by (f, D),
means and Student-t intervals over seeds, the change of Q from f = 0 paired
by seed, and the Beverloo and exponential fits of Q(D); also the defaults
that the fields share (BLOCKS, CONFIDENCE) and the progress line.

The window, the no-flow rule and the errors are defined in
doc/silo3d_rotating_records.md (the record format too); runs come from
analysis.silo3d_rotating.records.load_run.
"""

from dataclasses import dataclass, replace

import numpy as np
from scipy import optimize

from analysis.common.stats import t_quantile

# Stationary-window defaults (s, or a fraction of the grains), see
# doc/silo3d_rotating_records.md.
TRANSIENT = 1.0
MIN_GAP = 1.0
MIN_FLOWING_FRACTION = 0.5
END_FRACTION = 0.6
BLOCKS = 10
CONFIDENCE = 0.95


def progress(message):
    print(f"silo3d_rotating: {message}", flush=True)


# ---------------------------------------------------------------- flow rate

def analysis_window(tau, mass_out, total_mass, reinject, transient=TRANSIENT,
                    end_fraction=END_FRACTION):
    """(start, end) in time since opening, on sample times: the first
    sample at or after `transient`; the last sample, or for a run without
    reinjection the first sample at which the discharged mass reaches
    end_fraction of all the grains' mass (the silo nearly empty)."""
    tau = np.asarray(tau, dtype=float)
    after = np.flatnonzero(tau >= transient)
    if after.size == 0:
        return np.nan, np.nan
    start = tau[after[0]]
    end = tau[-1]
    if not reinject:
        emptied = np.flatnonzero(np.asarray(mass_out) >= end_fraction * total_mass)
        if emptied.size:
            end = tau[emptied[0]]
    return start, max(start, end)


def flow_spans(tau, n_out, start, end):
    """The spans between consecutive marks, as an (k, 2) array: marks are
    the window's ends and every sample in (start, end] whose n_out exceeds
    the previous sample's (a grain left in the sampling interval ending
    there). A span is a time without a grain out, known to one sampling
    interval."""
    tau = np.asarray(tau, dtype=float)
    n_out = np.asarray(n_out, dtype=float)
    exits = tau[1:][(n_out[1:] > n_out[:-1]) & (tau[1:] > start) & (tau[1:] <= end)]
    marks = np.unique(np.concatenate([[start], exits, [end]]))
    return np.column_stack([marks[:-1], marks[1:]])


def no_flow_intervals(tau, n_out, start, end, min_gap=MIN_GAP):
    """The spans without a grain out (flow_spans) longer than min_gap."""
    spans = flow_spans(tau, n_out, start, end)
    return spans[spans[:, 1] - spans[:, 0] > min_gap]


def pauses(tau, n_out, start, end):
    """How intermittent the flow of [start, end] is, short of the no-flow
    intervals that Q leaves out: (the longest span without a grain out,
    flow_spans; the share of the sampling intervals ending in (start, end]
    in which no grain left). NaNs for a window without a sampling
    interval."""
    tau = np.asarray(tau, dtype=float)
    n_out = np.asarray(n_out, dtype=float)
    inside = (tau[1:] > start) & (tau[1:] <= end)
    if not inside.any():
        return np.nan, np.nan
    spans = flow_spans(tau, n_out, start, end)
    idle = (n_out[1:] == n_out[:-1])[inside]
    return float(np.max(spans[:, 1] - spans[:, 0])), float(np.mean(idle))


def effective_time(tau, start, gaps):
    """Time since `start` with the no-flow intervals cut out of the time
    base (a sample inside a gap sits at the gap's start)."""
    tau = np.asarray(tau, dtype=float)
    removed = np.zeros_like(tau)
    for gap_start, gap_end in gaps:
        removed += np.clip(tau - gap_start, 0.0, gap_end - gap_start)
    return tau - start - removed


@dataclass
class FlowRate:
    """Stationary flow rate of one run (mass and grains per second), its
    standard error from block averages, and the window it comes from."""
    q_mass: float
    q_mass_se: float
    q_grains: float
    q_grains_se: float
    blocks: int
    start: float
    end: float
    effective_duration: float
    gaps: np.ndarray
    clogged_at_end: bool
    stationary: bool = True
    # the mass rate's block error again with B // 2 blocks twice as long: well
    # above q_mass_se, the blocks are shorter than the flow's correlation time
    # and q_mass_se is too small (doc/silo3d_rotating_records.md)
    q_mass_se_2x: float = np.nan
    # the rate's relative change across the window, from the line through
    # the mass rates of the blocks (block_trend), and its standard error: a
    # flow still settling into its regime (rods under a slow rotation)
    # shows a trend well beyond its error, which q_mass_se does not show
    trend: float = np.nan
    trend_se: float = np.nan
    # how intermittent the flow is inside the window (pauses): the longest
    # time without a grain out, s, and the share of sampling intervals
    # without one (the rods' flow under slow rotation comes in bursts)
    longest_pause: float = np.nan
    idle_share: float = np.nan

    @property
    def removed(self):
        return float(np.sum(self.gaps[:, 1] - self.gaps[:, 0])) if len(self.gaps) else 0.0


def last_sample_at_or_before(times, edges, tolerance=0.0):
    """Index of the last sample at or before each edge (the first sample
    for an edge before it): block and window rates are the increases of
    the cumulative counts between these samples. With a relative
    `tolerance`, an edge that round-off puts a hair before a sample takes
    that sample."""
    edges = np.asarray(edges, dtype=float) * (1 + tolerance)
    return np.maximum(np.searchsorted(times, edges, side="right") - 1, 0)


def block_rates(tau_eff, cumulative, duration, blocks):
    """Rates of `blocks` equal blocks of effective time: the increase of a
    cumulative count over each block, the count at a block edge being that
    of the last sample at or before it (a gap's end sample, at the same
    effective time as its start, is the later one and counts)."""
    edges = np.linspace(0.0, duration, blocks + 1)
    at_edges = np.asarray(cumulative, dtype=float)[last_sample_at_or_before(tau_eff, edges)]
    return np.diff(at_edges) / np.diff(edges)


def stationary_flow_rate(tau, n_out, mass_out, start, end, min_gap=MIN_GAP, blocks=BLOCKS,
                         min_flowing_fraction=MIN_FLOWING_FRACTION):
    """Q over [start, end] with the no-flow intervals longer than min_gap
    removed from the time base: Q = (m(end) - m(start)) / T_eff. Its
    standard error is std(Q_b, ddof=1)/sqrt(B) over B blocks of equal
    effective time (block averages: robust to the correlation of exits
    that a fit to the cumulative mass ignores). A run that flowed for less
    than min_flowing_fraction of the window has no stationary flow (a clog
    that a grain or two left in the remaining time would otherwise give a
    Q): its Q and errors are NaN and `stationary` is False."""
    tau = np.asarray(tau, dtype=float)
    inside = (tau >= start) & (tau <= end)
    gaps = no_flow_intervals(tau, n_out, start, end, min_gap)
    tau_eff = effective_time(tau[inside], start, gaps)
    duration = tau_eff[-1] if inside.any() else 0.0
    clogged = bool(len(gaps) and gaps[-1, 1] >= end)
    longest_pause, idle_share = pauses(tau, n_out, start, end)
    if duration <= 0 or duration < min_flowing_fraction * (end - start):
        return FlowRate(np.nan, np.nan, np.nan, np.nan, blocks, start, end, max(duration, 0.0), gaps,
                        clogged, stationary=False, longest_pause=longest_pause, idle_share=idle_share)
    inside_window = {name: np.asarray(cumulative, dtype=float)[inside]
                     for name, cumulative in (("mass", mass_out), ("grains", n_out))}
    rates = {name: ((cumulative[-1] - cumulative[0]) / duration,
                    block_error(tau_eff, cumulative, duration, blocks))
             for name, cumulative in inside_window.items()}
    se_2x = block_error(tau_eff, inside_window["mass"], duration, blocks // 2) if blocks >= 4 else np.nan
    trend, trend_se = block_trend(tau_eff, inside_window["mass"], duration, blocks)
    return FlowRate(*rates["mass"], *rates["grains"], blocks, start, end, duration, gaps, clogged,
                    q_mass_se_2x=se_2x, trend=trend, trend_se=trend_se, longest_pause=longest_pause,
                    idle_share=idle_share)


def block_error(tau_eff, cumulative, duration, blocks):
    """Standard error of the mean rate from `blocks` equal blocks:
    std(Q_b, ddof=1)/sqrt(B)."""
    per_block = block_rates(tau_eff, cumulative, duration, blocks)
    return per_block.std(ddof=1) / np.sqrt(blocks)


def block_trend(tau_eff, cumulative, duration, blocks):
    """The rate's relative change across the window: the least-squares line
    through the B block rates against the blocks' centres (effective
    time), its slope times the duration over the mean rate; and its
    standard error from the line's residuals (B - 2 degrees of freedom,
    blocks taken as independent, as for block_error). NaN for B < 3 or
    blocks without a grain (a grain that ends a removed gap counts at the
    window's effective start, before the first block)."""
    rates = block_rates(tau_eff, cumulative, duration, blocks) if blocks >= 3 else np.zeros(0)
    if not np.any(rates > 0):
        return np.nan, np.nan
    x = (np.arange(blocks) + 0.5) * duration / blocks
    x -= x.mean()
    sxx = np.sum(x * x)
    slope = np.sum(x * (rates - rates.mean())) / sxx
    residuals = rates - rates.mean() - slope * x
    slope_se = np.sqrt(np.sum(residuals ** 2) / (blocks - 2) / sxx)
    return slope * duration / rates.mean(), slope_se * duration / rates.mean()


def window_rates(tau, n_out, mass_out, width):
    """The raw rates of a whole discharge in consecutive windows of `width`
    seconds from the opening (tau = 0): clock time, nothing removed. Each
    window runs between the last samples at or before its nominal edges,
    and its rate is the increase of the counts over the time between those
    two samples (exact whatever the sampling). The last window is kept if
    the record reaches its end within one sample interval (a run of 4 s
    sampled every 0.01 s ends at a sample just before 4 s). Where the
    stationary Q gives one number for its window, these show how the rate
    moves through the run (a transient, a clog). Rows (t_from, t_to,
    grains/s, kg/s), times of the bounding samples; none if the record is
    shorter than one window."""
    tau = np.asarray(tau, dtype=float)
    if not width > 0:
        raise ValueError(f"window width must be > 0 s, not {width}")
    if len(tau) < 2:
        return np.zeros((0, 4))
    reach = tau[-1] + (tau[-1] - tau[-2])
    windows = int(np.floor(reach / width * (1 + 1e-12)))
    if windows < 1:
        return np.zeros((0, 4))
    edges = np.arange(windows + 1) * width
    index = last_sample_at_or_before(tau, edges, tolerance=1e-12)
    times = tau[index]
    if np.any(np.diff(times) <= 0):
        raise ValueError(f"window width {width:g} s is shorter than the record's sample interval "
                         f"(up to {np.max(np.diff(tau)):.3g} s): no sample inside some windows")
    counts = [np.asarray(cumulative, dtype=float)[index] for cumulative in (n_out, mass_out)]
    return np.column_stack([times[:-1], times[1:]] + [np.diff(c) / np.diff(times) for c in counts])


def smoothed_rate(tau, cumulative, window):
    """Q(tau) = [m(tau + window/2) - m(tau - window/2)] / window on the samples
    (cumulative interpolated linearly), for plots."""
    tau = np.asarray(tau, dtype=float)
    ahead = np.interp(tau + 0.5 * window, tau, cumulative)
    behind = np.interp(tau - 0.5 * window, tau, cumulative)
    span = np.minimum(tau + 0.5 * window, tau[-1]) - np.maximum(tau - 0.5 * window, tau[0])
    with np.errstate(invalid="ignore", divide="ignore"):
        return (ahead - behind) / span


def seed_mean_ci(means, standard_errors, dofs, level=CONFIDENCE):
    """Mean over seeds of per-run values, its standard error and the
    half width of its Student-t confidence interval: from the spread of the
    runs (n - 1 degrees of freedom) when there are n >= 2; for one run from
    its own standard error with that run's degrees of freedom."""
    means = np.asarray(means, dtype=float)
    n = means.size
    if n >= 2:
        se = means.std(ddof=1) / np.sqrt(n)
        dof = n - 1
    else:
        se, dof = float(standard_errors[0]), int(dofs[0])
    half = t_quantile(level, dof) * se if dof > 0 else np.nan
    return float(means.mean()), float(se), float(half)


# ---------------------------------------------------------------- fits

def beverloo(D, C, k, d):
    """Q = C (D - k d)^(5/2), zero below D = k d."""
    return C * np.clip(np.asarray(D, dtype=float) - k * d, 0.0, None) ** 2.5


def exponential(D, A, kappa):
    """Q = A exp(kappa D)."""
    return A * np.exp(kappa * np.asarray(D, dtype=float))


def _fit_summary(names, values, covariance, residuals, n_points):
    dof = n_points - len(values)
    errors = np.sqrt(np.diag(covariance))
    summary = {name: float(v) for name, v in zip(names, values)}
    summary.update({f"{name}_se": float(e) for name, e in zip(names, errors)})
    summary["dof"] = dof
    summary["chi2_dof"] = float(np.sum(residuals ** 2) / dof) if dof > 0 else np.nan
    return summary


def fit_beverloo(D, Q, sigma, d):
    """Weighted least squares of Q = C (D - k d)^(5/2) (curve_fit with
    absolute sigma: parameter errors are standard errors given sigma).
    Starts from the straight line Q^(2/5) = C^(2/5) (D - k d); k is bounded
    so that D - k d > 0 at every data point."""
    D, Q, sigma = (np.asarray(a, dtype=float) for a in (D, Q, sigma))
    slope, intercept = np.polyfit(D, Q ** 0.4, 1)
    guess = (slope ** 2.5, -intercept / (slope * d))
    k_max = D.min() / d * (1 - 1e-9)
    guess = (guess[0], min(guess[1], k_max * (1 - 1e-6)))
    values, covariance = optimize.curve_fit(
        lambda x, C, k: beverloo(x, C, k, d), D, Q, p0=guess, sigma=sigma,
        absolute_sigma=True, bounds=([0.0, -np.inf], [np.inf, k_max]))
    residuals = (Q - beverloo(D, *values, d)) / sigma
    return _fit_summary(("C", "k"), values, covariance, residuals, D.size)


def fit_exponential(D, Q, sigma):
    """Weighted least squares of Q = A exp(kappa D), started from the
    straight line ln Q = ln A + kappa D."""
    D, Q, sigma = (np.asarray(a, dtype=float) for a in (D, Q, sigma))
    kappa, log_a = np.polyfit(D, np.log(Q), 1)
    values, covariance = optimize.curve_fit(exponential, D, Q, p0=(np.exp(log_a), kappa),
                                            sigma=sigma, absolute_sigma=True)
    residuals = (Q - exponential(D, *values)) / sigma
    return _fit_summary(("A", "kappa"), values, covariance, residuals, D.size)


# ---------------------------------------------------------------- per-run flow

def analyse_flow(run, transient=TRANSIENT, min_gap=MIN_GAP, end_fraction=END_FRACTION, blocks=BLOCKS,
                 min_flowing_fraction=MIN_FLOWING_FRACTION):
    """run's FlowRate (also kept as run.flow). A run the deck stopped at a
    clog (run.txt's `clogged`: at rest, no grain out for its clog window)
    is clogged at its end, whether or not it stopped inside the window."""
    total_mass = run.info["N"] * run.info["mass"]
    start, end = analysis_window(run.tau, run.discharge["mass_out"], total_mass,
                                 bool(run.info["reinject"]), transient, end_fraction)
    run.flow = stationary_flow_rate(run.tau, run.discharge["n_out"], run.discharge["mass_out"],
                                    start, end, min_gap, blocks, min_flowing_fraction)
    if run.clogged_at_rest:
        run.flow = replace(run.flow, clogged_at_end=True)
    return run.flow


def last_exit(tau, n_out):
    """The time of the first sample at which n_out has its final value:
    by then the last grain had left (NaN if none left)."""
    n_out = np.asarray(n_out)
    if n_out.size == 0 or n_out[-1] <= 0:
        return np.nan
    return float(np.asarray(tau, dtype=float)[np.argmax(n_out >= n_out[-1])])


def run_labels(runs):
    """f<f>_D<D in mm>mm_seed<seed>, with a suffix when two runs share it."""
    labels = []
    for run in runs:
        base = f"f{run.info['f']:g}_D{run.info['D'] * 1e3:g}mm_seed{run.info['seed']:.0f}"
        label, k = base, 2
        while label in labels:
            label, k = f"{base}_{k}", k + 1
        labels.append(label)
    return labels


def group_by_key(runs):
    groups = {}
    for run in runs:
        groups.setdefault(run.key, []).append(run)
    return dict(sorted(groups.items()))


def flow_groups(runs, level=CONFIDENCE):
    """Rows per (f, D): f, D, n, Q mean, se, CI half width (kg/s), the
    same in grains/s, and n_no_flow, the runs without a stationary flow,
    which are left out of Q (as are runs without a finite Q)."""
    rows = []
    for (f, D), all_members in group_by_key(runs).items():
        members = [r for r in all_members if np.isfinite(r.flow.q_mass)]
        no_flow = sum(not r.flow.stationary for r in all_members)
        if not members:
            rows.append({"f": f, "D": D, "n": 0, "Q": np.nan, "Q_se": np.nan, "Q_ci": np.nan,
                         "Qn": np.nan, "Qn_se": np.nan, "Qn_ci": np.nan, "n_no_flow": no_flow})
            continue
        dofs = [r.flow.blocks - 1 for r in members]
        q = seed_mean_ci([r.flow.q_mass for r in members], [r.flow.q_mass_se for r in members], dofs, level)
        n = seed_mean_ci([r.flow.q_grains for r in members], [r.flow.q_grains_se for r in members], dofs, level)
        rows.append({"f": f, "D": D, "n": len(members), "Q": q[0], "Q_se": q[1], "Q_ci": q[2],
                     "Qn": n[0], "Qn_se": n[1], "Qn_ci": n[2], "n_no_flow": no_flow})
    return rows


def seed_flow(runs, key):
    """Per seed, the Q of its runs at key = (f, D) with a finite Q: {seed:
    (Q, se, blocks)}. A seed run more than once (realizations that differ
    at round-off) counts once, with the mean of its runs, the standard
    error of that mean from theirs, and the fewest blocks."""
    per_seed = {}
    for run in runs:
        if run.key == key and np.isfinite(run.flow.q_mass):
            per_seed.setdefault(run.info["seed"], []).append(run.flow)
    return {seed: (float(np.mean([r.q_mass for r in flows])),
                   float(np.sqrt(np.sum(np.square([r.q_mass_se for r in flows]))) / len(flows)),
                   min(r.blocks for r in flows))
            for seed, flows in per_seed.items()}


def paired_ratio(runs, f, f_ref, D, level=CONFIDENCE):
    """Q(f)/Q(f_ref) at the orifice D, paired by seed (the runs of one seed
    start from the same packing, so their ratio is freer of the packing's
    own noise than the ratio of the means): (mean, se, CI half width, n)
    over the n seeds that have both with a finite Q (the reference's > 0;
    a seed run more than once: seed_flow), as in seed_mean_ci: from the
    spread of the per-seed ratios for n >= 2; for one seed from the two
    Q's block standard errors, propagated, with the smaller of their
    degrees of freedom. n = 0: NaNs."""
    reference = {seed: flow for seed, flow in seed_flow(runs, (f_ref, D)).items() if flow[0] > 0}
    ratios, ses, dofs = [], [], []
    for seed, (q, q_se, blocks) in seed_flow(runs, (f, D)).items():
        if seed not in reference:
            continue
        q_ref, q_ref_se, ref_blocks = reference[seed]
        ratio = q / q_ref
        ratios.append(ratio)
        ses.append(ratio * np.hypot(q_se / q if q > 0 else np.nan, q_ref_se / q_ref))
        dofs.append(min(blocks, ref_blocks) - 1)
    if not ratios:
        return np.nan, np.nan, np.nan, 0
    return (*seed_mean_ci(ratios, ses, dofs, level), len(ratios))


def flow_changes(runs, level=CONFIDENCE):
    """Rows per (f, D) with f > 0: the relative change of Q from f = 0,
    Q(f)/Q(0) - 1, paired by seed (paired_ratio)."""
    rows = []
    for f, D in group_by_key(runs):
        if f == 0.0:
            continue
        ratio, se, half, n = paired_ratio(runs, f, 0.0, D, level)
        if n:
            rows.append({"f": f, "D": D, "n": n, "change": ratio - 1.0, "change_se": se, "change_ci": half})
    return rows


def drop_and_recovery(runs, groups, level=CONFIDENCE):
    """The paper's Fig. 3, per orifice D with runs at rest and turning:
    (a) the drop, Q_min/Q(0), where Q_min is the Q of the frequency f_min
    whose mean over seeds is the lowest (f > 0); (b) the recovery,
    Q(f_max)/Q_min, f_max the fastest frequency (the paper's 1.28 Hz).
    Both paired by seed (paired_ratio). f_min is picked from the same
    means, so with noisy means Q_min/Q(0) leans low: a sharp minimum
    within the intervals is not one."""
    rows = []
    for D in sorted({g["D"] for g in groups}):
        turning = [g for g in groups if g["D"] == D and g["f"] > 0 and np.isfinite(g["Q"])]
        if not turning or not any(g["D"] == D and g["f"] == 0.0 and g["Q"] > 0 for g in groups):
            continue
        f_min = min(turning, key=lambda g: g["Q"])["f"]
        f_max = max(g["f"] for g in turning)
        drop = paired_ratio(runs, f_min, 0.0, D, level)
        recovery = paired_ratio(runs, f_max, f_min, D, level) if f_max != f_min else (np.nan,) * 3 + (0,)
        rows.append({"D": D, "f_min": f_min, "n_min": drop[3], "min_over_rest": drop[0],
                     "min_over_rest_se": drop[1], "min_over_rest_ci": drop[2], "f_max": f_max,
                     "n_max": recovery[3], "max_over_min": recovery[0], "max_over_min_se": recovery[1],
                     "max_over_min_ci": recovery[2]})
    return rows


def flow_fits(rows, d):
    """Beverloo and exponential fits of Q(D) per f, with sigma = the
    standard error over seeds; f values with fewer than two orifice sizes
    (or a zero standard error) are skipped."""
    fits = {}
    for f in sorted({row["f"] for row in rows}):
        chosen = [r for r in rows if r["f"] == f and r["Q"] > 0 and r["Q_se"] > 0]
        if len({r["D"] for r in chosen}) < 2:
            continue
        D = np.array([r["D"] for r in chosen])
        Q = np.array([r["Q"] for r in chosen])
        sigma = np.array([r["Q_se"] for r in chosen])
        try:
            fits[f] = {"beverloo": fit_beverloo(D, Q, sigma, d), "exponential": fit_exponential(D, Q, sigma)}
        except (RuntimeError, ValueError) as failure:     # curve_fit found no minimum
            progress(f"f = {f:g} Hz: no fit ({failure})")
    return fits
