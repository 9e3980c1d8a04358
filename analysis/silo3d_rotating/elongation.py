"""The flow-rate cut against elongation at D = 60 mm: the paper's Fig. 3
(Pongó, Börzsönyi and Hidalgo 2022) from our run records, with the
orifice averages <phi>, <v_z>, <O_zz> at each of its points.

Fig. 3a is Q_min/Q(f = 0), Fig. 3b Q(1.28 Hz)/Q_min, against L/d = 1
(spheres), 2.5, 3.3 and 4.0. Q_min is Q at 0.32 Hz at every L/d: 0.32 Hz
is where the mean Q of the three packings of the L/d = 3.3 rods is
lowest over 2-4 s (results.minimum_frequency; the paper puts its minima
at 0.16-0.32 Hz), and it is the only slow frequency the elongation
campaign runs. Both rates of a ratio are taken over the same window, per
packing, and the packings' ratios are combined (results.paired,
results.spheres_paired, results.combine):

- L/d = 1: the spheres' 2 s runs at 60 mm (results.SPHERES: the LIGGGHTS
  runs of bench/silo3d_cross_host_paper.py, f = 0, 0.32 and 1.28 Hz),
  0.5-2 s.
- L/d = 3.3: the Fig. 2c campaign's runs (results.FIG2C), 2-4 s.
- L/d = 2.5 and 4.0: the elongation campaign's archives
  (examples/silo3d_rotating/rods_elongation.sh),
  doc/data/silo3d_rods_elongation_L<aspect>/D0.06_f<f>_s<seed>/, seeds
  32452843 and 15485863, 2-4 s. A run that is not archived, or whose
  records end before the window's end, is left out, and its cell gives
  the number of packings it has ("under way" when there are none). New
  runs are picked up as they are archived.

Fig. 3a is taken over 4-8 s too (LATE), the issue's window where the rate
at rest still rises at 4 s, as it does at 2.5 and 3.3
(doc/campaigns/silo3d_rotating.md, "Which window"): the first two
packings of every rod L/d, from 8 s runs at f = 0 and 0.32 Hz; at 3.3
the 8 s runs at rest of earlier campaigns (silo3d_rods_drop_8s,
silo3d_rods_fig2c) and the elongation campaign's
(its stage 7) at 0.32 Hz, in silo3d_rods_elongation_L3.3/. Fig. 3b
stays over 2-4 s (its 1.28 Hz runs last 4 s).

The orifice averages per (L/d, f), as in the paper's Figs. 8a, 8b and 9a:
<X> = int X phi dV / int phi dV over the 1 cm high cylinder above the
orifice. Each run's orifice_timeseries.md (one row per dump frame, from
the analysis of the whole run before its archive) is averaged over its
frames inside the window's stationary flow. The frames are those
fields.in_flow keeps for the FlowRate the run's Q comes from, and the
mean and block error are fields.orifice_summary's. The packings are then
averaged, with a standard error from flow.seed_mean_ci (their spread
when there are two or more, the one run's block error otherwise). The
archived series do not all cover 2-4 s:
- The 3.3 runs at rest are 8 s runs, and their series is over 4-8 s.
  Their 2-4 s series comes from their 4 s twins (results.ORIFICES at
  60 mm). A twin is the same trajectory up to 4 s: its discharge.txt is
  the 8 s run's to round-off (tests/test_silo3d_elongation.py checks
  this).
- The third packing clogs at rest, so it has no average.
- The spheres' runs of the cross-host bench kept neither dumps nor an
  orifice series. The campaign's stage 8 runs them again (the same deck,
  seeds and settling) with dumps, into SPHERES_STORE; their averages are
  over the spheres' 0.5-2 s, from the three packings. Spheres have no
  O_zz.
A series that does not cover the window (to within 1.5 frame spacings
at each end) is left out.

    /usr/bin/python3 -m analysis.silo3d_rotating.elongation --write    # the table in doc/data and in the page
    /usr/bin/python3 -m analysis.silo3d_rotating.elongation --check    # exit 1 if either differs
    /usr/bin/python3 -m analysis.silo3d_rotating.elongation --print    # the table and the results-table rows
    /usr/bin/python3 -m analysis.silo3d_rotating.elongation --figure doc/img/silo3d_rods_fig3_elongation.png
    /usr/bin/python3 -m analysis.silo3d_rotating.elongation --figure-by-f doc/img/silo3d_rods_elongation_by_f.png

`results_rows(data_dir)` gives Fig. 3's two trends as rows of the page's
results table (results.results_rows adds them).
"""

import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analysis.common.cli import command_line
from analysis.results_tables import DATA_DIR, ROOT, Row, markdown_table, replace_block
from analysis.silo3d_rotating.acceleration import frame_spacing
from analysis.silo3d_rotating.fields import in_flow, orifice_summary
from analysis.silo3d_rotating.flow import BLOCKS, progress, seed_mean_ci
from analysis.silo3d_rotating.records import key_value, load_run, read_run_info
from analysis.silo3d_rotating.results import (FIG2C, ORIFICES, PACKINGS, PAGE_SECTIONS, SPHERES, markdown_rows,
                                              paired, rate_text, spheres_paired, window_rate, window_text)

D_MM = 60
ASPECTS = (1.0, 2.5, 3.3, 4.0)
CAMPAIGN_PACKINGS = ("1st", "2nd")         # its seeds: PACKINGS' first two
SEED_NAMES = {seed: name for name, seed in PACKINGS.items()}   # spheres_paired names packings by seed
F_MIN = 0.32                               # Q_min = Q(0.32 Hz) at every L/d (the module's docstring)
F_FAST = 1.28
FREQUENCIES = (0.0, F_MIN, F_FAST)
EARLY = (2, 4)                             # the rods, at every L/d: Fig. 3b, and Fig. 3a as first measured
LATE = (4, 8)                              # Fig. 3a over the 8 s runs at f = 0 and 0.32 Hz (the docstring)
WINDOWS = {"a": (EARLY, LATE), "b": (EARLY,)}
LATE_FREQUENCIES = (0.0, F_MIN)            # the runs that last 8 s
RUN_WINDOWS = ((EARLY, FREQUENCIES), (LATE, LATE_FREQUENCIES))   # each window and the runs read over it
SPHERES_WINDOW = (0.5, 2)                  # the spheres' 2 s runs
SPHERES_STORE = "silo3d_rods_elongation_spheres"   # stage 8: the spheres' runs with orifice series
ORIFICE_QUANTITIES = {"phi": "⟨φ⟩", "v_z": "⟨v_z⟩ (m/s)", "O_zz": "⟨O_zz⟩"}
PANELS = {"a": (F_MIN, 0.0), "b": (F_FAST, F_MIN)}   # Fig. 3's panels: (f, f_ref) of Q(f)/Q(f_ref)

TABLE = "silo3d_rods_elongation.md"        # under doc/data
PAGE = "doc/silo3d_rotating.md"
PAGE_BLOCK = "silo3d_rods_elongation"      # the page's <!-- results-table silo3d_rods_elongation --> block
FIGURE = "doc/img/silo3d_rods_fig3_elongation.png"
FIGURE_BY_F = "doc/img/silo3d_rods_elongation_by_f.png"

# What the paper (/work/shared/papers/pongo2022_rotating_bottom_silo_rods.md)
# says about its Fig. 3. Neither the text nor the caption gives a value of
# either ratio at any L/d, so those cells read "not stated".
# - On Fig. 3: "the particle aspect ratio has a significant impact on the
#   system flow rate, which could drop by even 70% for very elongated
#   grains"; the abstract: "reduces the flow rate Q by up to 70% compared
#   with stationary bottom". So Q_min/Q(0) is 0.30 at its deepest, for its
#   longest rods; the orifice is not given.
PAPER_DEEPEST_DROP = 0.30
# - On Fig. 2a (spheres): "a weak nonmonotonic behavior (≈ 5% initial drop
#   then ≈ 5% increase) for the larger orifices which we consider". That
#   is Q_min/Q(0) ≈ 0.95, and Q(1.28)/Q_min ≈ 1.05 if the increase is read
#   from the minimum. The orifices are not named.
PAPER_SPHERES = {"a": 0.95, "b": 1.05}
# - The trends: "The increasing aspect ratio of the particles causes a
#   larger decrease in the flow rate" (Fig. 3a); "the relative increase
#   gets larger as the grains are more elongated or as the orifice size is
#   decreased" (Fig. 3b).
PAPER_TRENDS = {"a": "falls as L/d grows (“a larger decrease in the flow rate”)",
                "b": "grows with L/d (“the relative increase gets larger as the grains are more elongated”)"}


# ---------------------------------------------------------------- runs

def store(aspect):
    """The elongation campaign's store of one aspect ratio, under doc/data."""
    return f"silo3d_rods_elongation_L{aspect:.1f}"


def campaign_runs(data_dir, aspect):
    """{(packing, f): directory under data_dir} for the runs the store of
    `aspect` holds (those with a discharge.txt). A run.txt that does not
    match the run's place in the store is an error."""
    return stored_runs(data_dir, store(aspect), CAMPAIGN_PACKINGS, {"shape": "rod", "aspect": aspect})


def stored_runs(data_dir, store_name, packings, grains):
    """{(packing, f): directory under data_dir} for the runs of a store
    (those with a discharge.txt), each run.txt checked against the run's
    place in the store and the store's `grains` (run.txt values)."""
    runs = {}
    for packing in packings:
        for f in FREQUENCIES:
            name = f"{store_name}/D0.06_f{f:g}_s{PACKINGS[packing]}"
            if (data_dir / name / "discharge.txt").exists():
                wanted = {**grains, "D": D_MM / 1000, "f": f, "seed": PACKINGS[packing]}
                info = read_run_info(data_dir / name, required=tuple(wanted))
                wrong = {key: info[key] for key, value in wanted.items() if not same_value(info[key], value)}
                if wrong:
                    raise ValueError(f"{data_dir / name}/run.txt: {wrong}, but the store's layout says {wanted}")
                runs[packing, f] = name
    return runs


def same_value(found, wanted):
    """run.txt's value against the store's: numbers within round-off, words as written."""
    if isinstance(wanted, str):
        return found == wanted
    return not isinstance(found, str) and key_value(found) == key_value(wanted)


def rod_runs(data_dir, aspect, window=EARLY):
    """The rods' runs of one aspect ratio over a window, {(packing, f):
    directory}, and the packings planned for it."""
    if aspect != 3.3:
        return campaign_runs(data_dir, aspect), CAMPAIGN_PACKINGS
    if window == EARLY:
        return FIG2C, tuple(PACKINGS)
    at_rest = {(packing, 0.0): FIG2C[packing, 0.0] for packing in CAMPAIGN_PACKINGS}    # 8 s runs
    return {**campaign_runs(data_dir, aspect), **at_rest}, CAMPAIGN_PACKINGS


def run_status(data_dir, name, window):
    """(Rate over the window, "") of a run; (None, why) without one."""
    if name is None or not (data_dir / name / "discharge.txt").exists():
        return None, "not archived yet"
    rate = window_rate(data_dir / name, *window)
    if rate is not None:
        return rate, ""
    tau = load_run(data_dir / name).tau
    if tau[-1] < window[1] - np.min(np.diff(tau)):
        return None, f"records end at {tau[-1]:.2f} s"
    return None, "no flow in the window: a clog"


# ---------------------------------------------------------------- Fig. 3

@dataclass
class Point:
    aspect: float
    panel: str            # "a": Q_min/Q(0), "b": Q(1.28)/Q_min
    ratio: object         # results.Ratio (n = 0: no value)
    window: tuple
    planned: int          # packings the point has runs for, or will have
    missing: str = ""     # why there is no value

    def value_cell(self, digits=2):
        if not self.ratio.n:
            return self.missing
        return f"{self.ratio.value:.{digits}f} ± {self.ratio.se:.{digits}f}"


def fig3_points(data_dir=DATA_DIR):
    """Fig. 3's points, L/d by L/d, panel a before b (the module's docstring)."""
    data_dir = Path(data_dir)
    points = [Point(1.0, panel, spheres_paired(data_dir, D_MM, *PANELS[panel], window=SPHERES_WINDOW),
                    SPHERES_WINDOW, len(PACKINGS)) for panel in PANELS]
    points += [rod_point(data_dir, aspect, panel, window)
               for panel in PANELS for window in WINDOWS[panel] for aspect in ASPECTS[1:]]
    return points


def rod_point(data_dir, aspect, panel, window=EARLY):
    """The rods' point of one panel at one L/d over a window, paired by packing."""
    runs, packings = rod_runs(Path(data_dir), aspect, window)
    ratio = paired(Path(data_dir), *PANELS[panel], window, packings=packings, runs=runs)
    return Point(aspect, panel, ratio, window, len(packings), "" if ratio.n else "under way")


def paper_cell(aspect, panel):
    if aspect == 1.0:
        words = {"a": "“≈ 5 % initial drop”", "b": "“then ≈ 5 % increase”"}[panel]
        return f"≈ {PAPER_SPHERES[panel]:.2f} (Fig. 2a's text, {words}, larger orifices)"
    if aspect == max(ASPECTS) and panel == "a":
        return (f"not stated; its deepest drop, for its longest rods, “by even 70 %” "
                f"(so ≥ {PAPER_DEEPEST_DROP:.2f}; orifice not given)")
    return "not stated"


def _aspect(aspect):
    return "1 (spheres)" if aspect == 1.0 else f"{aspect:.1f}"


def _ratio_name(panel):
    f, f_ref = PANELS[panel]
    return f"Q({f:g} Hz)/Q({f_ref:g})" if f_ref == 0 else f"Q({f:g} Hz)/Q({f_ref:g} Hz)"


def fig3_table(points, detail=True):
    """Markdown: one row per point; with `detail` each packing's ratio and chi2."""
    header = ["Fig.", "L/d", "ratio", "window", "ours", "packings"] + (["per packing", "χ²"] if detail else []) + [
        "the paper"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    # per panel: the spheres, then the rods window by window
    for point in sorted(points, key=lambda p: (p.panel, p.aspect != 1.0, p.window, p.aspect)):
        cells = [f"3{point.panel}", _aspect(point.aspect), _ratio_name(point.panel), window_text(point.window),
                 point.value_cell(), f"{point.ratio.n} of {point.planned}" if point.planned else "—"]
        if detail:
            per = ", ".join(f"{SEED_NAMES.get(packing, packing)} {value:.3f} ± {se:.3f}"
                            for packing, value, se in point.ratio.parts)
            cells += [per or "—", "" if np.isnan(point.ratio.chi2) else f"{point.ratio.chi2:.1f}"]
        lines.append("| " + " | ".join(cells + [paper_cell(point.aspect, point.panel)]) + " |")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- orifice averages

def covers(frame_times, flow):
    """Whether frames at frame_times span the flow's window (to within 1.5
    frame spacings at each end)."""
    if len(frame_times) < 2:
        return False
    slack = 1.5 * frame_spacing(frame_times)
    return frame_times[0] - flow.start <= slack and flow.end - frame_times[-1] <= slack


def run_orifice_means(run_dir, window):
    """{quantity: (mean, block se)} of a run's orifice series over its frames
    in the window's stationary flow; None if the run has no rate there,
    has no series, or its series does not cover the window."""
    rate = window_rate(run_dir, *window)
    path = Path(run_dir) / "orifice_timeseries.md"
    if rate is None or not path.exists():
        return None
    rows = markdown_rows(path)
    times = np.array([row["t"] for row in rows])
    keep = np.flatnonzero(in_flow(times, rate.flow))
    if not covers(times[keep], rate.flow):
        return None
    summary = orifice_summary([rows[i] for i in keep])
    return {name: summary[name] for name in ORIFICE_QUANTITIES if name in summary}   # spheres: no O_zz


def orifice_series(aspect, f, runs, packing, window=EARLY):
    """The run (directory under doc/data) whose orifice series gives the
    rods' (aspect, f) over `window` in `packing`: over 2-4 s the 3.3 runs
    at rest are the 8 s runs' 4 s twins (the module's docstring)."""
    if aspect == 3.3 and f == 0.0 and window == EARLY:
        return ORIFICES.get((packing, D_MM))
    return runs.get((packing, f))


@dataclass
class OrificePoint:
    aspect: float
    f: float
    window: tuple
    values: dict          # quantity -> (mean over the packings, its se)
    n: int
    planned: int
    note: str = ""


def packing_means(per_run):
    """{quantity: (mean over the runs, its se)} of the quantities every run
    has (flow.seed_mean_ci: the runs' spread, or one run's block error)."""
    if not per_run:
        return {}
    return {q: seed_mean_ci([m[q][0] for m in per_run], [m[q][1] for m in per_run],
                            [BLOCKS - 1] * len(per_run))[:2]
            for q in ORIFICE_QUANTITIES if all(q in m for m in per_run)}


def spheres_orifice_point(data_dir, f):
    """The spheres' averages at f over their window, from stage 8's runs."""
    runs = stored_runs(data_dir, SPHERES_STORE, tuple(PACKINGS), {"shape": "sphere"})
    per_run = [means for (packing, run_f), name in runs.items()
               if run_f == f and (means := run_orifice_means(data_dir / name, SPHERES_WINDOW)) is not None]
    note = "" if per_run else "under way (stage 8: the bench's runs again, with dumps)"
    return OrificePoint(1.0, f, SPHERES_WINDOW, packing_means(per_run), len(per_run), len(PACKINGS), note)


def orifice_points(data_dir=DATA_DIR):
    data_dir = Path(data_dir)
    points = [spheres_orifice_point(data_dir, f) for f in FREQUENCIES]
    for window, frequencies in RUN_WINDOWS:
        for aspect in ASPECTS[1:]:
            runs, packings = rod_runs(data_dir, aspect, window)
            for f in frequencies:
                per_run = [means for packing in packings
                           if (name := orifice_series(aspect, f, runs, packing, window)) is not None
                           and (means := run_orifice_means(data_dir / name, window)) is not None]
                values = packing_means(per_run)
                note = ""
                if aspect == 3.3 and f == 0.0:
                    note = ("the 8 s runs' 4 s twins; the 3rd packing clogs at rest" if window == EARLY
                            else "earlier campaigns' 8 s runs (drop_8s, fig2c)")
                elif not per_run:
                    note = "under way"
                points.append(OrificePoint(aspect, f, window, values, len(per_run), len(packings), note))
    return points


def orifice_table(points):
    header = ["L/d", "f (Hz)", "window", "packings"] + list(ORIFICE_QUANTITIES.values()) + ["note"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for point in points:
        cells = [_aspect(point.aspect), f"{point.f:g}", window_text(point.window), f"{point.n} of {point.planned}"]
        for q in ORIFICE_QUANTITIES:
            cells.append(f"{point.values[q][0]:.3f} ± {point.values[q][1]:.3f}" if q in point.values else "—")
        lines.append("| " + " | ".join(cells + [point.note]) + " |")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- Q against f

@dataclass
class RatePoint:
    aspect: float
    f: float
    window: tuple
    q: float              # kg/s, the mean over the packings with a rate in the window
    se: float             # their spread's standard error (one packing: its block error)
    n: int


def rate_points(data_dir=DATA_DIR):
    """Q (kg/s) per (L/d, f) over each L/d's window, the mean over the
    packings that have a rate there (a clog or a run not archived has
    none), as the paper's Figs. 2a-2d at D = 60 mm."""
    data_dir = Path(data_dir)
    rates = {}
    for aspect, f, _, name, window in planned_runs(data_dir):
        rate = run_status(data_dir, name, window)[0]
        rates.setdefault((aspect, f, window), []).extend([rate] if rate is not None else [])
    points = []
    for (aspect, f, window), mine in rates.items():
        if mine:
            q, se, _ = seed_mean_ci([r.q for r in mine], [r.se for r in mine], [BLOCKS - 1] * len(mine))
            points.append(RatePoint(aspect, f, window, q, se, len(mine)))
    return points


def plot_by_frequency(data_dir, path):
    """Q and the orifice averages against f, a line per L/d: the paper's
    Figs. 2a-2d and 8a, 8b, 9a at D = 60 mm, at our three frequencies."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rates = [p for p in rate_points(data_dir) if p.window in (EARLY, SPHERES_WINDOW)]
    orifice = [p for p in orifice_points(data_dir) if p.n and p.window in (EARLY, SPHERES_WINDOW)]
    fig, axes = plt.subplots(1, 4, figsize=(13, 3.6))
    fig.subplots_adjust(left=0.05, right=0.99, top=0.85, bottom=0.25, wspace=0.33)
    colours = dict(zip(ASPECTS, ("tab:grey", "tab:green", "tab:blue", "tab:purple")))
    for aspect in ASPECTS:
        label = f"L/d = {_aspect(aspect)}"
        mine = sorted((p for p in rates if p.aspect == aspect), key=lambda p: p.f)
        if mine:
            axes[0].errorbar([p.f for p in mine], [p.q for p in mine], yerr=[p.se for p in mine], marker="o",
                             color=colours[aspect], capsize=2, label=label)
            for p in mine:
                axes[0].annotate(str(p.n), (p.f, p.q), xytext=(4, 3), textcoords="offset points", fontsize=6,
                                 color=colours[aspect])
        for ax, quantity in zip(axes[1:], ORIFICE_QUANTITIES):
            theirs = sorted((p for p in orifice if p.aspect == aspect and quantity in p.values), key=lambda p: p.f)
            if theirs:
                ax.errorbar([p.f for p in theirs], [p.values[quantity][0] for p in theirs],
                            yerr=[p.values[quantity][1] for p in theirs], marker="o", color=colours[aspect],
                            capsize=2)
    axes[0].set_ylabel("Q (kg/s)")
    axes[0].set_ylim(bottom=0)
    for ax, name in zip(axes[1:], ORIFICE_QUANTITIES.values()):
        ax.set_ylabel(name)
    for ax in axes:
        ax.set_xlabel("f (Hz)")
        ax.set_xticks(FREQUENCIES)
        ax.set_xlim(-0.12, F_FAST + 0.17)
    fig.legend(loc="lower center", ncols=len(ASPECTS), fontsize=8)
    fig.suptitle(f"D = {D_MM} mm: Q (the number: packings) and the orifice averages against f, "
                 f"over {window_text(EARLY)} (spheres: {window_text(SPHERES_WINDOW)})",
                 fontsize=9)
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ---------------------------------------------------------------- tables

def planned_runs(data_dir):
    """(L/d, f, packing, run directory under data_dir, window) of every run
    Fig. 3 uses or waits for; a run not archived yet under the name the
    campaign will give it."""
    planned = [(1.0, f, packing, SPHERES[D_MM, f, seed], SPHERES_WINDOW)
               for f in FREQUENCIES for packing, seed in PACKINGS.items()]
    for window, frequencies in RUN_WINDOWS:
        for aspect in ASPECTS[1:]:
            runs, packings = rod_runs(data_dir, aspect, window)
            default = {(p, f): f"{store(aspect)}/D0.06_f{f:g}_s{PACKINGS[p]}" for p in packings for f in frequencies}
            planned += [(aspect, f, p, runs.get((p, f), default[p, f]), window) for f in frequencies for p in packings]
    return planned


def runs_table(data_dir):
    """Q of every run Fig. 3 uses or waits for, over its window."""
    lines = ["| L/d | f (Hz) | packing | window | Q (kg/s) | run |", "|---|---|---|---|---|---|"]
    for aspect, f, packing, name, window in planned_runs(data_dir):
        rate, why = run_status(data_dir, name, window)
        q = rate_text(rate) if rate else f"— ({why})"
        lines.append(f"| {_aspect(aspect)} | {f:g} | {packing} | {window_text(window)} | {q} | {name} |")
    return "\n".join(lines) + "\n"


def data_table(data_dir=DATA_DIR):
    """The Markdown of doc/data/silo3d_rods_elongation.md."""
    data_dir = Path(data_dir)
    progress("elongation: Fig. 3's ratios")
    points = fig3_points(data_dir)
    progress("elongation: the orifice averages")
    orifice = orifice_points(data_dir)
    lines = ["# The flow-rate cut against elongation at D = 60 mm (Pongó et al. 2022, Fig. 3)",
             "",
             "Made by `/usr/bin/python3 -m analysis.silo3d_rotating.elongation --write` from the runs'",
             "records (analysis/silo3d_rotating/elongation.py says which). Q in kg/s ± its block standard",
             "error (10 blocks), over the window, in time since the opening; both rates of a ratio over",
             "the same window. A ratio over packings is the weighted mean of the packings' ratios, each",
             "± the two runs' block errors propagated, its error scaled up by sqrt(χ²/dof) when the",
             "packings disagree (analysis.silo3d_rotating.results.combine). Q_min is Q(0.32 Hz) at every",
             "L/d (the lowest mean Q of the three L/d = 3.3 packings over 2–4 s). Fig. 3a also over 4–8 s",
             "of 8 s runs (the rate at rest still rises at 4 s; the module's docstring). L/d = 2.5 and 4.0 come",
             f"from the elongation campaign's stores ({store(2.5)}/, {store(4.0)}/; seeds",
             f"{PACKINGS['1st']} = 1st, {PACKINGS['2nd']} = 2nd) as their runs are archived. \"under way\": none",
             "archived yet. The paper gives no value of either ratio for any L/d; its statements are",
             "quoted in the module.",
             "",
             "## Fig. 3: (a) Q_min/Q(0) and (b) Q(1.28 Hz)/Q_min, paired by packing",
             "",
             fig3_table(points).rstrip("\n"),
             "",
             "## Q per run (the paper's Figs. 2a–2d at D = 60 mm, f = 0, 0.32, 1.28 Hz)",
             "",
             runs_table(data_dir).rstrip("\n"),
             "",
             "## Orifice averages over the same window (as the paper's Figs. 8a, 8b, 9a)",
             "",
             "⟨X⟩ = ∫Xφ dV/∫φ dV over the 1 cm cylinder above the orifice, per dump frame",
             "(each run's orifice_timeseries.md). The mean over the frames in the window's stationary",
             "flow, then the mean over the packings ± its standard error (one packing: its block error).",
             "",
             orifice_table(orifice).rstrip("\n")]
    return "\n".join(lines) + "\n"


def page_table(data_dir=DATA_DIR):
    """The page's generated block: Fig. 3's points and the orifice averages."""
    return (fig3_table(fig3_points(data_dir), detail=False) + "\n"
            + orifice_table(orifice_points(data_dir)))


# ---------------------------------------------------------------- the page's results rows

def _packings(n):
    return f"{n} packing{'s' if n != 1 else ''}"


def results_rows(data_dir=DATA_DIR):
    """Fig. 3's two trends as rows of the page's results table (added
    there by results.results_rows). Their verdict stays "open": the trend
    needs L/d = 2.5 and 4.0, and then a person reads it."""
    points = fig3_points(data_dir)
    rows = []
    for panel, quantity in (("a", f"Q_min/Q(0) against L/d, D = {D_MM} mm (Fig. 3a; Q_min = Q({F_MIN:g} Hz))"),
                            ("b", f"Q({F_FAST:g} Hz)/Q_min against L/d, D = {D_MM} mm (Fig. 3b)")):
        groups = []
        for window in WINDOWS[panel]:
            mine = [p for p in points if p.panel == panel and (p.window == window or
                                                                 (window == EARLY and p.aspect == 1.0))]
            groups.append(f"over {window_text(window)}: " + "; ".join(
                f"L/d = {_aspect(p.aspect)}: {p.value_cell()}" + (f" ({_packings(p.ratio.n)})" if p.ratio.n else "")
                for p in mine))
        ours = " — ".join(groups)
        paper = PAPER_TRENDS[panel] + (f"; down to {PAPER_DEEPEST_DROP:.2f} (“by even 70 %”) for its longest rods"
                                       if panel == "a" else "")
        window = ("0.5–2 s (spheres), " + " and ".join(window_text(w) for w in WINDOWS[panel])
                  + " (rods), both runs")
        # the cut against L/d is the paper's central claim: a headline
        rows.append(Row(quantity, paper, ours, window, "open", PAGE_SECTIONS["elongation"], headline=panel == "a"))
    return rows


# ---------------------------------------------------------------- figure

def plot_fig3(data_dir, path):
    """Fig. 3's two panels from our runs, the paper's statements marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    points = fig3_points(data_dir)
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.3))
    fig.subplots_adjust(left=0.07, right=0.98, top=0.86, bottom=0.24, wspace=0.25)
    styles = {EARLY: ("o", "tab:blue", 0.0), LATE: ("s", "tab:orange", 0.2), SPHERES_WINDOW: ("o", "tab:blue", 0.0)}
    packing_step = 0.06       # each packing's point right of the mean, one step apart
    for ax, panel in zip(axes, PANELS):
        ax.axhline(1, color="grey", lw=0.6)
        for point in (p for p in points if p.panel == panel):
            marker, colour, shift = styles[point.window]
            if not point.ratio.n:
                if point.window == LATE:
                    continue          # the early point's note says "under way" where neither has runs
                # beside the paper's star at L/d = 1
                where = (point.aspect + 0.12, 0.03) if point.aspect == 1.0 else (point.aspect, 0.03)
                ax.annotate("under way", where,
                            xycoords=("data", "axes fraction"), rotation=90, fontsize=7, ha="center",
                            va="bottom", color="grey")
                continue
            x = point.aspect + shift
            for k, (_, value, se) in enumerate(point.ratio.parts):
                ax.errorbar(x + packing_step * (k + 1), value, yerr=se, fmt=".", color=colour, alpha=0.4,
                            ms=4, capsize=1.5)
            ax.errorbar(x, point.ratio.value, yerr=point.ratio.se, fmt=marker, color=colour, capsize=3)
            # the early point's label on its left, the late one's right of its packings, so
            # that the two at one L/d do not overlap; the rods' early label below its error
            # bar, clear of the late packings of the L/d before it
            label = f"{_packings(point.ratio.n)},\n{window_text(point.window)}"
            if point.window == LATE:
                anchor = (x + packing_step * len(point.ratio.parts), point.ratio.value)
                offset, align, vertical = 6, "left", "center"
            elif point.aspect == 1.0:
                anchor, offset, align, vertical = (x, point.ratio.value), -8, "right", "center"
            else:
                anchor = (x, point.ratio.value - point.ratio.se)
                offset, align, vertical = -8, "right", "top"
            ax.annotate(label, anchor, xytext=(offset, 0), textcoords="offset points",
                        fontsize=7, ha=align, va=vertical)
        ax.plot(1.0, PAPER_SPHERES[panel], "*", color="tab:red", ms=9, mfc="none")
        ax.set_xticks(ASPECTS)
        ax.set_xlim(0.5, 4.8)      # room for the 4–8 s labels right of L/d = 4.0
        ax.set_xlabel("L/d (1: spheres)")
    axes[0].axhline(PAPER_DEEPEST_DROP, color="tab:red", ls=":", lw=1)
    axes[0].text(0.55, PAPER_DEEPEST_DROP - 0.02, "paper: “by even 70 %”\n(its longest rods, any orifice)",
                 color="tab:red", fontsize=7, ha="left", va="top")
    axes[0].set_ylabel(f"Q_min/Q(0)   (Q_min = Q({F_MIN:g} Hz))")
    axes[0].set_ylim(0, 1.2)
    axes[0].set_title("(a) the cut", fontsize=10)
    axes[1].set_ylabel(f"Q({F_FAST:g} Hz)/Q_min")
    axes[1].set_ylim(bottom=0.5)
    axes[1].set_title("(b) the rise after the minimum", fontsize=10)
    handles = [axes[1].plot([], [], "o", color="tab:blue")[0],
               axes[1].plot([], [], "s", color="tab:orange")[0],
               axes[1].plot([], [], ".", color="tab:blue", alpha=0.4)[0],
               axes[1].plot([], [], "*", color="tab:red", mfc="none")[0]]
    fig.legend(handles, [f"ours over {window_text(EARLY)} (spheres {window_text(SPHERES_WINDOW)}): "
                         "weighted mean over the packings ± se",
                         f"ours over {window_text(LATE)} (8 s runs)", "each packing ± its runs' block errors",
                         "paper, spheres: “≈ 5 % drop then ≈ 5 % increase” (Fig. 2a's text)"],
               loc="lower center", ncols=2, fontsize=7)
    fig.suptitle(f"D = {D_MM} mm: Fig. 3 of Pongó et al. 2022 from our runs (both rates of a ratio over one window)",
                 fontsize=9)
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ---------------------------------------------------------------- command line

def main(argv=None):
    parser = command_line("analysis.silo3d_rotating.elongation", __doc__.split("\n\n")[0],
                          "/usr/bin/python3 -m analysis.silo3d_rotating.elongation --check")
    action = parser.add_mutually_exclusive_group(required=True)
    action.add_argument("--write", action="store_true", help=f"write doc/data/{TABLE} and the page's block")
    action.add_argument("--check", action="store_true", help="exit 1 if the table or the page's block differs")
    action.add_argument("--print", action="store_true", help="print the table and the results-table rows")
    action.add_argument("--figure", type=Path, metavar="PNG", help=f"plot Fig. 3 (the page's: {FIGURE})")
    action.add_argument("--figure-by-f", type=Path, metavar="PNG",
                        help=f"plot Q and the orifice averages against f (the page's: {FIGURE_BY_F})")
    parser.add_argument("--data-dir", type=Path, default=DATA_DIR, help="doc/data (default %(default)s)")
    parser.add_argument("--page", type=Path, default=ROOT / PAGE, help="the scene's page (default %(default)s)")
    args = parser.parse_args(argv)
    if args.figure:
        plot_fig3(args.data_dir, args.figure)
        progress(f"elongation: wrote {args.figure}")
        return 0
    if args.figure_by_f:
        plot_by_frequency(args.data_dir, args.figure_by_f)
        progress(f"elongation: wrote {args.figure_by_f}")
        return 0
    text = data_table(args.data_dir)
    if args.print:
        print(text)
        print(markdown_table(results_rows(args.data_dir)))
        return 0
    path = args.data_dir / TABLE
    page = args.page.read_text()
    new_page = replace_block(page, PAGE_BLOCK, page_table(args.data_dir))
    if args.write:
        path.write_text(text)
        args.page.write_text(new_page)
        return 0
    stale = [str(p) for p, same in ((path, path.exists() and path.read_text() == text),
                                    (args.page, new_page == page)) if not same]
    for name in stale:
        print(f"{name} differs from the records "
              "(/usr/bin/python3 -m analysis.silo3d_rotating.elongation --write)", file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
