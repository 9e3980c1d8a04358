"""The rotating-bottom silo's results against Pongó, Börzsönyi and Hidalgo
(2022), from the run records in doc/data: every ratio of two flow rates
taken over the SAME window of time since the opening in both runs, paired
by packing where both runs share one.

The rods' flow at rest still rises with time (the first two packings at
D = 60 mm: 0.139 kg/s over 1-4 s, 0.176 kg/s over 4-8 s), so a ratio of a
rate over one window to a rate over another is biased by as much; here
both rates of a ratio come from one window, read from each run's
discharge.txt (analysis.silo3d_rotating.flow.stationary_flow_rate between the first
sample at or after the window's start and the last at or before its end,
10 blocks for the standard error).

    /usr/bin/python3 -m analysis.silo3d_rotating.results --write   # the tables in doc/data
    /usr/bin/python3 -m analysis.silo3d_rotating.results --check   # exit 1 if they differ
    /usr/bin/python3 -m analysis.silo3d_rotating.results --print   # the page's rows

The tables: doc/data/silo3d_rods_fig2c/same_window_ratios.md (frequency)
and doc/data/silo3d_rods_orifices/same_window_ratios.md (orifice).
`results_rows(data_dir)` gives the rows of doc/silo3d_rotating.md's
results table (analysis.results_tables).
"""

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analysis.results_tables import DATA_DIR, Row
from analysis.silo3d_rotating.flow import BLOCKS, fit_exponential, last_exit, stationary_flow_rate
from analysis.silo3d_rotating.records import load_run
from analysis.common.cli import command_line

# the rods' three packings at D = 60 mm (the kept packings' seeds)
PACKINGS = {"1st": 32452843, "2nd": 15485863, "3rd": 49979687}
FREQUENCIES = (0.0, 0.16, 0.32, 0.64, 0.96, 1.28)

# run records, relative to doc/data: (packing, f in Hz) -> directory, rods
# L/d = 3.3, D = 60 mm, reinjection (the Fig. 2c campaign; runs of the same
# protocol archived before its store are taken from where they are)
FIG2C = {
    ("1st", 0.0): "silo3d_rods_drop_8s/D0.06_f0_s32452843",            # 8 s
    ("2nd", 0.0): "silo3d_rods_fig2c/D0.06_f0_s15485863",              # 8 s
    ("3rd", 0.0): "silo3d_rods_fig2c/D0.06_f0_s49979687",              # clogged at 1.37 s
    ("1st", 0.16): "silo3d_rods_drop_8s/D0.06_f0.16_s32452843",        # 8 s
    ("2nd", 0.16): "silo3d_rods_drop_8s/D0.06_f0.16_s15485863",        # 8 s
    ("3rd", 0.16): "silo3d_rods_fig2c/D0.06_f0.16_s49979687",          # 8 s
    ("1st", 0.64): "silo3d_rods_transient/D0.06_f0.64_s32452843",      # 4 s
    **{(p, f): f"silo3d_rods_fig2c/D0.06_f{f:g}_s{PACKINGS[p]}"        # 4 s
       for p in PACKINGS for f in (0.32, 0.64, 0.96, 1.28) if (p, f) != ("1st", 0.64)},
}
# rods at rest, orifices of the second packing (and the first's 54 mm):
# (packing, D in mm) -> directory
ORIFICES = {
    ("2nd", 50): "silo3d_rods_orifices/D0.05_f0_s15485863",            # 2 s
    ("2nd", 54): "silo3d_rods_long/D0.054_f0_s15485863",               # 4 s
    ("2nd", 60): "silo3d_rods_long/D0.06_f0_s15485863",                # 4 s (the 8 s run's first 4 s)
    ("2nd", 70): "silo3d_rods_orifices/D0.07_f0_s15485863",            # 2 s
    ("2nd", 80): "silo3d_rods_orifices/D0.08_f0_s15485863",            # 2 s
    ("1st", 54): "silo3d_rods_orifices_first_packing/D0.054_f0_s32452843",   # 4 s
    ("1st", 60): "silo3d_rods_drop_4s/D0.06_f0_s32452843",             # 4 s (the 8 s run's first 4 s)
}
# spheres: (D in mm, f, seed) -> directory; 2 s runs, reinjection
# (at 60 mm the three packings of the cross-host campaign's LIGGGHTS runs,
# the same deck and protocol as the first packing's runs in
# silo3d_rods_axial_acceleration/spheres_f*_2s)
SPHERES = {
    **{(60, f, s): f"silo3d_cross_host/liggghts_D0.06_f{f:g}_s{s}" for f in (0.0, 0.32, 1.28)
       for s in PACKINGS.values()},
    **{(42, f, s): f"silo3d_seeds/D0.042_f{f:g}_s{s}" for f in (0.0, 1.28) for s in PACKINGS.values()},
}
ACCELERATION = "silo3d_rods_axial_acceleration"

# the paper's values (Pongó et al. 2022)
KAPPA_PAPER = 0.084            # 1/mm, kappa_sim, its Figs. 4-5
# the relative spread of Q over a 1 s window between realizations of the
# rods' flow at rest (the three 1 s windows of the 4 s run at 60 mm, second
# packing: 19 %; doc/campaigns/silo3d_rotating.md): the error given to each
# point of the kappa fit, as the block errors of 1 s windows are 2-3 times
# too small
WINDOW_SPREAD = 0.19

PAGE_SECTIONS = {
    "spheres": "spheres-q-barely-changes",
    "drop": "rods-a-slow-rotation-cuts-q",
    "rise": "rods-q-rises-again-at-fast-rotation",
    "elongation": "elongation-ld--25-and-40",
    "orifice": "rods-qd-at-rest-the-exponential-above-60-mm",
    "acceleration": "rods-the-accelerating-region-shrinks-fig-10",
    "order": "rods-orientation-at-the-orifice-fig-9",
}


@dataclass
class Rate:
    q: float          # kg/s
    se: float         # block standard error
    t_from: float
    t_to: float
    flow: object = None     # its FlowRate: the samples it lies between and the gaps cut out


@dataclass
class Ratio:
    value: float
    se: float
    n: int            # packings (or pairs of runs)
    parts: tuple = ()       # per packing: (packing, value, se)
    chi2: float = np.nan    # of the packings' values about their weighted mean

    def percent_change(self):
        return f"{100 * (self.value - 1):+.0f} ± {100 * self.se:.0f} %"


def window_rate(run_dir, t_from, t_to, blocks=BLOCKS):
    """Q over [t_from, t_to] s since the opening of one run, from its
    discharge.txt: between the first sample at or after t_from and the
    last at or before t_to (no-flow intervals of more than 1 s cut out, as
    everywhere). None if the run ended before t_to, or has no stationary
    flow in the window (a clog)."""
    run = load_run(run_dir)
    tau = run.tau
    sample = np.min(np.diff(tau))
    if tau[-1] < t_to - sample:
        return None
    start = tau[np.flatnonzero(tau >= t_from - 1e-9)[0]]
    end = tau[np.flatnonzero(tau <= t_to + 1e-9)[-1]]
    flow = stationary_flow_rate(tau, run.discharge["n_out"], run.discharge["mass_out"], start, end,
                                blocks=blocks)
    # a run the deck stopped at a clog at rest (run.txt's `clogged`) has no
    # rate in a window that ends after its last grain left
    if not flow.stationary or run.clogged_at_rest and last_exit(tau, run.discharge["n_out"]) < t_to:
        return None
    return Rate(flow.q_mass, flow.q_mass_se, t_from, t_to, flow)


def ratio_of(a, b):
    """a.q / b.q with the two block errors propagated (independent runs)."""
    value = a.q / b.q
    return value, value * np.hypot(a.se / a.q, b.se / b.q)


def combine(parts):
    """The packings' ratios (packing, value, se) combined: the weighted
    mean and its standard error, scaled up by sqrt(chi2/dof) when the
    packings disagree beyond their errors (chi2/dof > 1)."""
    if not parts:
        return Ratio(np.nan, np.nan, 0)
    values = np.array([p[1] for p in parts])
    ses = np.array([p[2] for p in parts])
    weights = 1 / ses ** 2
    mean = np.sum(weights * values) / np.sum(weights)
    se = 1 / np.sqrt(np.sum(weights))
    chi2 = float(np.sum(((values - mean) / ses) ** 2))
    if len(parts) > 1 and chi2 / (len(parts) - 1) > 1:
        se *= np.sqrt(chi2 / (len(parts) - 1))
    return Ratio(float(mean), float(se), len(parts), tuple(parts), chi2 if len(parts) > 1 else np.nan)


def paired(data_dir, f, f_ref, window, packings=PACKINGS, runs=FIG2C):
    """Q(f)/Q(f_ref) over one window, per packing that has both runs
    ({(packing, f): directory under data_dir}, FIG2C by default) with a
    flow in it, combined (combine)."""
    parts = []
    for packing in packings:
        if (packing, f) not in runs or (packing, f_ref) not in runs:
            continue
        a = window_rate(data_dir / runs[packing, f], *window)
        b = window_rate(data_dir / runs[packing, f_ref], *window)
        if a is None or b is None:
            continue
        parts.append((packing, *ratio_of(a, b)))
    return combine(parts)


def spheres_paired(data_dir, D, f, f_ref, window=(0.5, 2)):
    """The spheres' Q(f)/Q(f_ref) at orifice D (mm), per packing whose two
    2 s runs both flow over the window, combined (combine)."""
    parts = []
    for seed in PACKINGS.values():
        a = window_rate(data_dir / SPHERES[D, f, seed], *window)
        b = window_rate(data_dir / SPHERES[D, f_ref, seed], *window)
        if a is not None and b is not None:
            parts.append((seed, *ratio_of(a, b)))
    return combine(parts)


def frequency_rates(data_dir, window):
    """{f: [(packing, Rate)]} over one window, the runs that reach its end
    with a flow in it."""
    rates = {}
    for f in FREQUENCIES:
        for packing in PACKINGS:
            rate = window_rate(data_dir / FIG2C[packing, f], *window)
            if rate is not None:
                rates.setdefault(f, []).append((packing, rate))
    return rates


def minimum_frequency(rates):
    """The f > 0 whose mean Q over the packings is lowest."""
    means = {f: np.mean([r.q for _, r in members]) for f, members in rates.items() if f > 0}
    return min(means, key=means.get)


# ---------------------------------------------------------------- orifices

def orifice_rates(data_dir, packing, window):
    return {D: window_rate(data_dir / path, *window)
            for (p, D), path in ORIFICES.items() if p == packing}


def orifice_ratio(data_dir, packing, D, D_ref, window):
    rates = orifice_rates(data_dir, packing, window)
    if rates.get(D) is None or rates.get(D_ref) is None:
        return Ratio(np.nan, np.nan, 0)
    value, se = ratio_of(rates[D], rates[D_ref])
    return Ratio(value, se, 1, ((packing, value, se),))


def kappa_fit(data_dir, sizes, window, packing="2nd", relative_sigma=WINDOW_SPREAD):
    """The exponential Q = A e^{kappa D} through the orifices `sizes` (mm),
    all over one window; each point's error relative_sigma * Q (the spread
    of a 1 s window between realizations), or with relative_sigma None its
    block standard error. kappa in 1/mm."""
    rates = orifice_rates(data_dir, packing, window)
    D = np.array(sizes, dtype=float)
    Q = np.array([rates[s].q for s in sizes])
    sigma = Q * relative_sigma if relative_sigma else np.array([rates[s].se for s in sizes])
    fit = fit_exponential(D, Q, sigma)
    return {"kappa": fit["kappa"], "kappa_se": fit["kappa_se"], "chi2": fit["chi2_dof"] * fit["dof"],
            "dof": fit["dof"]}


def power_fit(data_dir, sizes, window, packing="2nd", relative_sigma=WINDOW_SPREAD):
    """The power law Q = B D^n through the orifices `sizes` (mm), all over
    one window: a straight line in ln Q against ln D, each ln Q ±
    relative_sigma (weighted least squares, absolute errors). Returns
    (n, its standard error)."""
    rates = orifice_rates(data_dir, packing, window)
    x = np.log(np.array(sizes, dtype=float))
    y = np.log([rates[s].q for s in sizes])
    weights = np.full(x.size, 1 / relative_sigma)
    (slope, _), covariance = np.polyfit(x, y, 1, w=weights, cov="unscaled")
    return float(slope), float(np.sqrt(covariance[0, 0]))


# ---------------------------------------------------------------- acceleration (Fig. 10)

def acceleration_changes(data_dir):
    """The change of the area under a_eff(z) (the paper's Fig. 10) from
    rest to rotation, pairs with the same window in both runs: {label:
    (change, se, window)} from the summaries of analysis.silo3d_rotating.acceleration."""
    out = {}
    for name, label in (("rods", "rods"), ("spheres", "spheres")):
        table = np.loadtxt(data_dir / ACCELERATION / f"{name}_axial_acceleration_summary.txt", ndmin=2)
        # columns: f D seed t_from t_to frame_pairs dt_p grain_pairs left_out area area_se ...
        for row in table:
            f, seed, t_from, t_to, area, area_se = row[0], row[2], row[3], row[4], row[9], row[10]
            if f == 0:
                continue
            rest = [r for r in table if r[0] == 0 and r[2] == seed and r[3] == t_from and r[4] == t_to]
            if not rest:
                continue
            value = area / rest[0][9]
            se = value * np.hypot(area_se / area, rest[0][10] / rest[0][9])
            out[(label, f, int(seed), t_from, t_to)] = (value - 1, se)
    return out


# ---------------------------------------------------------------- orifice averages

def markdown_rows(path):
    """The rows of the Markdown table in `path` (the analysis' `.md`
    tables: a title, then one table) as dicts of floats."""
    lines = [line for line in Path(path).read_text().splitlines() if line.startswith("|")]
    header = [cell.strip() for cell in lines[0].strip("|").split("|")]
    return [dict(zip(header, (float(cell) for cell in line.strip("|").split("|")))) for line in lines[2:]]


def order_by_frequency(data_dir, name="orifice_three_packings.md"):
    """{f: (<S> cylindrical, its se)} over the packings, from the campaign's
    orifice table (each f over its own window: 4-8 s at 0 and 0.16 Hz,
    2-4 s at 0.32 Hz, 1-4 s above)."""
    return {row["f"]: (row["S"], row["S_se"]) for row in markdown_rows(data_dir / "silo3d_rods_fig2c" / name)}


# ---------------------------------------------------------------- tables in doc/data

def window_text(window):
    """A window of time since the opening as the tables write it: "2–4 s"."""
    return f"{window[0]:g}–{window[1]:g} s"


def rate_text(rate):
    """A Rate as the tables write it (kg/s ± its block error); "—" for None."""
    return "—" if rate is None else f"{rate.q:.4f} ± {rate.se:.4f}"


def _ratio_cells(ratio):
    per = ", ".join(f"{p} {v:.3f} ± {s:.3f}" for p, v, s in ratio.parts)
    chi2 = "" if np.isnan(ratio.chi2) else f"{ratio.chi2:.1f}"
    return [f"{ratio.value:.3f} ± {ratio.se:.3f}" if ratio.n else "—", str(ratio.n), per or "—", chi2]


def frequency_table(data_dir):
    """The Markdown of silo3d_rods_fig2c/same_window_ratios.md."""
    lines = ["# Rods at D = 60 mm: flow rates and their ratios over the same window",
             "",
             "Made by `/usr/bin/python3 -m analysis.silo3d_rotating.results --write` from each run's",
             "discharge.txt (the directories in `analysis/silo3d_rotating/results.py`, FIG2C). Q in kg/s",
             "± its block standard error (10 blocks) over the window, in time since the opening;",
             "both rates of a ratio over the same window. A ratio over packings is the weighted",
             "mean of the packings' ratios (each ± the two runs' block errors propagated), its",
             "error scaled up by sqrt(chi2/dof) when the packings disagree; chi2 of the packings",
             "about the mean. The third packing clogs at rest (1.37 s), so ratios to Q(0) pair",
             "the first two packings only. The block errors of one run understate the spread",
             "between realizations (doc/campaigns/silo3d_rotating.md).",
             ""]
    windows = ((1, 2), (1, 4), (2, 4), (4, 8))
    lines += ["## Q per run", "", "| f (Hz) | packing | " + " | ".join(window_text(w) for w in windows) + " |",
              "|---|---|" + "---|" * len(windows)]
    for f in FREQUENCIES:
        for packing in PACKINGS:
            rates = [window_rate(data_dir / FIG2C[packing, f], *w) for w in windows]
            lines.append(f"| {f:g} | {packing} | " + " | ".join(rate_text(r) for r in rates) + " |")
    lines += ["", "(— : the run is shorter than the window, or clogged in it.)", "",
              "## Q(f)/Q(0), paired by packing", "",
              "| f (Hz) | window | Q(f)/Q(0) | packings | per packing | chi2 |", "|---|---|---|---|---|---|"]
    for f in FREQUENCIES[1:]:
        for window in windows:
            ratio = paired(data_dir, f, 0.0, window)
            if ratio.n:
                lines.append(f"| {f:g} | {window_text(window)} | " + " | ".join(_ratio_cells(ratio)) + " |")
    lines += ["", "## The minimum and the rise, paired by packing", "",
              "| ratio | window | value | packings | per packing | chi2 |", "|---|---|---|---|---|---|"]
    for window in ((2, 4), (1, 4)):
        rates = frequency_rates(data_dir, window)
        f_min = minimum_frequency(rates)
        means = ", ".join(f"{f:g} Hz {np.mean([r.q for _, r in m]):.4f} (n = {len(m)})"
                          for f, m in rates.items())
        lines.append(f"| mean Q over the packings per f: {means}; lowest mean at f > 0: {f_min:g} Hz "
                     f"| {window_text(window)} | | | | |")
        pairs = [(f_min, 0.0), (1.28, f_min)] + [p for p in ((1.28, 0.64), (1.28, 0.32)) if p[1] != f_min]
        for f, f_ref in pairs:
            ratio = paired(data_dir, f, f_ref, window)
            if ratio.n and f != f_ref:
                lines.append(f"| Q({f:g})/Q({f_ref:g}) | {window_text(window)} | "
                             + " | ".join(_ratio_cells(ratio)) + " |")
    return "\n".join(lines) + "\n"


def orifice_table(data_dir):
    """The Markdown of silo3d_rods_orifices/same_window_ratios.md."""
    lines = ["# Rods at rest: Q(D) and its ratios over the same window",
             "",
             "Made by `/usr/bin/python3 -m analysis.silo3d_rotating.results --write` from each run's",
             "discharge.txt (the directories in `analysis/silo3d_rotating/results.py`, ORIFICES). Q in",
             "kg/s ± its block standard error (10 blocks) over the window, in time since the",
             "opening; both rates of a ratio over the same window, each ratio ± the two runs'",
             "block errors propagated. The 50, 70 and 80 mm runs last 2 s, so their ratios are",
             "over 1–2 s. kappa: the exponential Q = A e^{kappa D} (analysis.silo3d_rotating.flow.fit_exponential),",
             f"each point ± {WINDOW_SPREAD:g} Q (the spread of a 1 s window between realizations)",
             "or ± its block error; the paper's kappa_sim = 0.084 /mm.",
             "",
             "## Q per run", "", "| packing | D (mm) | 1–2 s | 1–4 s | 2–4 s |", "|---|---|---|---|---|"]
    for (packing, D), path in ORIFICES.items():
        rates = [window_rate(data_dir / path, *w) for w in ((1, 2), (1, 4), (2, 4))]
        lines.append(f"| {packing} | {D} | " + " | ".join(rate_text(r) for r in rates) + " |")
    lines += ["", "## Ratios", "", "| ratio | packing | window | value | the paper's e^{kappa ΔD} | D^{5/2} |",
              "|---|---|---|---|---|---|"]
    for packing, D, D_ref, window in (("2nd", 70, 60, (1, 2)), ("2nd", 80, 60, (1, 2)), ("2nd", 80, 70, (1, 2)),
                                      ("2nd", 50, 60, (1, 2)), ("2nd", 54, 60, (1, 2)), ("2nd", 54, 60, (1, 4)),
                                      ("1st", 54, 60, (1, 2)), ("1st", 54, 60, (1, 4))):
        ratio = orifice_ratio(data_dir, packing, D, D_ref, window)
        lines.append(f"| Q({D})/Q({D_ref}) | {packing} | {window_text(window)} | {ratio.value:.3f} ± {ratio.se:.3f} "
                     f"| {np.exp(KAPPA_PAPER * (D - D_ref)):.2f} | {(D / D_ref) ** 2.5:.2f} |")
    lines += ["", "## kappa (1/mm), second packing, 1–2 s", "",
              "| orifices (mm) | errors | kappa | chi2 | dof |", "|---|---|---|---|---|"]
    for sizes in ((60, 70, 80), (50, 54, 60, 70, 80)):
        for sigma, name in ((WINDOW_SPREAD, f"{WINDOW_SPREAD:g} Q"), (None, "block")):
            fit = kappa_fit(data_dir, sizes, (1, 2), relative_sigma=sigma)
            lines.append(f"| {', '.join(map(str, sizes))} | {name} | {fit['kappa']:.4f} ± {fit['kappa_se']:.4f} "
                         f"| {fit['chi2']:.1f} | {fit['dof']} |")
    n, n_se = power_fit(data_dir, (60, 70, 80), (1, 2))
    lines += ["", f"The power law Q ∝ D^n through 60, 70 and 80 mm over 1–2 s (each ln Q ± {WINDOW_SPREAD:g}): "
              f"n = {n:.2f} ± {n_se:.2f} (Beverloo's large-orifice limit: 5/2)."]
    return "\n".join(lines) + "\n"


TABLES = {
    "silo3d_rods_fig2c/same_window_ratios.md": frequency_table,
    "silo3d_rods_orifices/same_window_ratios.md": orifice_table,
}


# ---------------------------------------------------------------- the page's rows

def _pct(value, se):
    return f"{100 * value:+.0f} ± {100 * se:.0f} %".replace("-", "−")


def results_rows(data_dir=DATA_DIR):
    data_dir = Path(data_dir)
    rows = []

    # spheres: Q barely changes with f (paper: "a slight increase ... below
    # D = 48 mm", "≈ 5 % initial drop then ≈ 5 % increase" above)
    r60 = spheres_paired(data_dir, 60, 0.32, 0.0)
    rows.append(Row("spheres, D = 60 mm: Q(0.32 Hz)/Q(0) − 1",
                    "a weak non-monotonic change (≈ 5 % drop, then ≈ 5 % rise)",
                    f"{_pct(r60.value - 1, r60.se)} ({r60.n} packings)", "0.5–2 s, both runs", "agrees",
                    PAGE_SECTIONS["spheres"], headline=True))
    r42 = spheres_paired(data_dir, 42, 1.28, 0.0)
    rows.append(Row("spheres, D = 42 mm: Q(1.28 Hz)/Q(0) − 1",
                    "a slight increase with f below D = 48 mm; rotation makes a clogging silo flow",
                    f"{_pct(r42.value - 1, r42.se)} ({r42.n} packings; the 3rd clogs at rest and flows at 1.28 Hz)",
                    "0.5–2 s, both runs", "agrees", PAGE_SECTIONS["spheres"]))

    # rods, the drop: Q_min/Q(0) over 2-4 s and after most of a turn
    rates = frequency_rates(data_dir, (2, 4))
    f_min = minimum_frequency(rates)
    drop = paired(data_dir, f_min, 0.0, (2, 4))
    late = paired(data_dir, 0.16, 0.0, (4, 8))
    rows.append(Row(f"rods L/d = 3.3, D = 60 mm: Q_min/Q(0), Q_min at {f_min:g} Hz (the lowest mean of 3 packings)",
                    "a drop by tens of % (up to 70 % for the longest rods), minimum at 0.16–0.32 Hz (Figs. 2c, 3a)",
                    f"{drop.value:.2f} ± {drop.se:.2f} ({drop.n} packings)",
                    "2–4 s, both runs", "agrees", PAGE_SECTIONS["drop"], headline=True))
    early = paired(data_dir, 0.16, 0.0, (2, 4))
    rows.append(Row("rods, D = 60 mm: Q(0.16 Hz)/Q(0) within the first turn",
                    "as above", f"{early.value:.2f} ± {early.se:.2f} ({early.n} packings)",
                    "2–4 s, both runs", "agrees", PAGE_SECTIONS["drop"]))
    rows.append(Row("rods, D = 60 mm: Q(0.16 Hz)/Q(0) after most of a turn",
                    "as above", f"{late.value:.2f} ± {late.se:.2f} ({late.n} packings, χ² = {late.chi2:.1f})",
                    "4–8 s, both runs", "agrees", PAGE_SECTIONS["drop"]))
    for f in (0.64, 0.96, 1.28):
        r = paired(data_dir, f, 0.0, (1, 4))
        rows.append(Row(f"rods, D = 60 mm: Q({f:g} Hz)/Q(0)", "below 1, rising slowly with f (Fig. 2c)",
                        f"{r.value:.2f} ± {r.se:.2f} ({r.n} packings)", "1–4 s, both runs", "agrees",
                        PAGE_SECTIONS["drop"]))

    # rods, the rise: Q(1.28)/Q_min, paired in the three packings
    rise = paired(data_dir, 1.28, f_min, (2, 4))
    rows.append(Row(f"rods, D = 60 mm: Q(1.28 Hz)/Q_min (Q_min at {f_min:g} Hz)",
                    "a modest increase above the minimum (Fig. 3b)",
                    f"{rise.value:.2f} ± {rise.se:.2f} ({rise.n} packings)", "2–4 s, both runs", "agrees",
                    PAGE_SECTIONS["rise"], headline=True))
    rise14 = paired(data_dir, 1.28, 0.64, (1, 4))
    rows.append(Row("rods, D = 60 mm: Q(1.28 Hz)/Q(0.64 Hz)", "a modest increase (Fig. 3b)",
                    f"{rise14.value:.2f} ± {rise14.se:.2f} ({rise14.n} packings)", "1–4 s, both runs", "agrees",
                    PAGE_SECTIONS["rise"]))

    # the cut and the rise against elongation (Fig. 3): imported here, as
    # the elongation module imports this one
    from analysis.silo3d_rotating.elongation import results_rows as elongation_rows
    rows += elongation_rows(data_dir)

    # rods, Q(D) at rest
    r70 = orifice_ratio(data_dir, "2nd", 70, 60, (1, 2))
    rows.append(Row("rods at rest: Q(70 mm)/Q(60 mm)",
                    f"e^(κ·10 mm) = {np.exp(KAPPA_PAPER * 10):.2f} (κ = 0.084 /mm; D^(5/2): 1.47)",
                    f"{r70.value:.2f} ± {r70.se:.2f} (one packing)", "1–2 s, both runs", "agrees",
                    PAGE_SECTIONS["orifice"], headline=True))
    fit = kappa_fit(data_dir, (60, 70, 80), (1, 2))
    rows.append(Row("rods at rest: κ of Q ∝ e^(κD) through 60, 70, 80 mm",
                    "0.084 /mm (Figs. 4–5)",
                    f"{fit['kappa']:.3f} ± {fit['kappa_se']:.3f} /mm (one packing, each point ± {WINDOW_SPREAD:g} Q)",
                    "1–2 s, all three runs", "agrees", PAGE_SECTIONS["orifice"]))
    p1 = orifice_ratio(data_dir, "1st", 54, 60, (1, 4))
    p2 = orifice_ratio(data_dir, "2nd", 54, 60, (1, 4))
    rows.append(Row("rods at rest: Q(54 mm)/Q(60 mm)",
                    f"e^(−κ·6 mm) = {np.exp(-KAPPA_PAPER * 6):.2f} (D^(5/2): 0.77)",
                    f"{p1.value:.2f} ± {p1.se:.2f} and {p2.value:.2f} ± {p2.se:.2f} (two packings)",
                    "1–4 s, both runs", "open", PAGE_SECTIONS["orifice"]))

    # rods, the accelerating region (Fig. 10)
    acc = acceleration_changes(data_dir)
    rod16 = acc[("rods", 0.16, PACKINGS["1st"], 4, 8)]
    rod32 = acc[("rods", 0.32, PACKINGS["1st"], 0.5, 1.5)]
    sph = acc[("spheres", 0.32, PACKINGS["1st"], 0.5, 2)]
    rows.append(Row("area under a_eff(z) on the axis, change from rest (Fig. 10)",
                    "rods: “significantly lower” at 0.32 Hz; spheres: “notably smaller” change",
                    f"rods {_pct(*rod32)} at 0.32 Hz (0.5–1.5 s, no reinjection), {_pct(*rod16)} at 0.16 Hz "
                    f"(4–8 s); spheres {_pct(*sph)} at 0.32 Hz (0.5–2 s); one packing each",
                    "the same window in both runs of each pair", "agrees", PAGE_SECTIONS["acceleration"]))

    # rods, the order at the orifice
    order = order_by_frequency(data_dir)
    rows.append(Row("rods, D = 60 mm: order ⟨S⟩ at the orifice against f (Fig. 9d)",
                    "falls under a slow rotation, then rises with f to 1.28 Hz",
                    ", ".join(f"{order[f][0]:.3f}" for f in FREQUENCIES) + " at 0 … 1.28 Hz (± "
                    f"{min(v[1] for v in order.values()):.3f}–{max(v[1] for v in order.values()):.3f}; "
                    "cylindrical average, 3 packings, 2 at rest): falls, rises to 0.64 Hz only",
                    "each f over its own window: 0, 0.16 Hz 4–8 s; 0.32 Hz 2–4 s; faster 1–4 s", "open",
                    PAGE_SECTIONS["order"]))
    return rows


# ---------------------------------------------------------------- figure

FIGURE = "doc/img/silo3d_rods_Q_vs_f_same_window.png"


def plot_same_window(data_dir, path):
    """Q(f) of the rods at D = 60 mm, each packing over 2-4 s and 4-8 s,
    with the mean over the packings per window."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 4), layout="constrained")
    markers = {"1st": "o", "2nd": "s", "3rd": "^"}
    for window, colour, shift in (((2, 4), "tab:blue", -0.012), ((4, 8), "tab:red", 0.012)):
        rates = frequency_rates(data_dir, window)
        for f, members in rates.items():
            for packing, rate in members:
                ax.errorbar(f + shift, rate.q, yerr=rate.se, fmt=markers[packing], color=colour, alpha=0.45,
                            ms=4, capsize=2)
        fs = sorted(rates)
        means = [np.mean([r.q for _, r in rates[f]]) for f in fs]
        ax.plot(np.array(fs) + shift, means, "-", color=colour, label=f"mean over the packings, {window_text(window)}")
    for packing, marker in markers.items():
        ax.plot([], [], marker, color="grey", label=f"{packing} packing (± block se)")
    ax.set_xlabel("f (Hz)")
    ax.set_ylabel("Q (kg/s)")
    ax.set_ylim(bottom=0)
    ax.set_title("rods L/d = 3.3, D = 60 mm: Q over one window", fontsize=10)
    ax.legend(fontsize=7)
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ---------------------------------------------------------------- command line

def main(argv=None):
    parser = command_line("analysis.silo3d_rotating.results", __doc__.split("\n\n")[0],
                          "/usr/bin/python3 -m analysis.silo3d_rotating.results --check")
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--write", action="store_true", help="write the same-window tables into doc/data")
    action.add_argument("--check", action="store_true", help="exit 1 naming the tables that differ from the records")
    action.add_argument("--print", action="store_true", help="print the tables and the page's rows")
    action.add_argument("--figure", type=Path, metavar="PNG",
                        help=f"plot the rods' Q(f) over 2-4 s and 4-8 s (the page's: {FIGURE})")
    parser.add_argument("--data-dir", type=Path, default=DATA_DIR, help="doc/data (default %(default)s)")
    args = parser.parse_args(argv)
    if args.figure:
        plot_same_window(args.data_dir, args.figure)
        return 0
    stale = []
    for name, make in TABLES.items():
        text = make(args.data_dir)
        path = args.data_dir / name
        if args.write:
            path.write_text(text)
        elif args.check:
            if not path.exists() or path.read_text() != text:
                stale.append(name)
        else:
            print(f"{name}:\n{text}")
    if args.print:
        from analysis.results_tables import markdown_table
        print(markdown_table(results_rows(args.data_dir)))
    for name in stale:
        print(f"{args.data_dir / name} differs from the records "
              "(/usr/bin/python3 -m analysis.silo3d_rotating.results --write)", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
