"""The open 2D pile's results against Magalhaes et al. 2014, made from
doc/data (doc/pile2d.md, "Results against the paper").

`results_rows(data_dir)` returns the rows of the page's results table
(analysis.results_tables puts them between the page's markers):

- w_c per model, from `analysis.pile2d.discharges.summarize` over the records the
  page names: models none and depth from the standing piles
  (pile2d_standing/) with their L = 200 d records (pile2d_L200_none/,
  pile2d_L200_depth/), models fixed and overlap from the first ensemble
  (pile2d_discharges.txt) with theirs (pile2d_L200/, pile2d_L200_overlap/);
  all four summarised together, 2000 bootstrap replicates from seed 1, as
  the page's command does (the bootstrap draws from one generator for all
  the models of a file, so the set of models is part of the result);
- w_t at L = 100 d (the paper's Fig. 4 size), and w_50 there, the width
  where half the piles jam;
- the PDF of h near w_t (the paper's Fig. 6): how many piles keep more
  than half their height, how many are empty;
- the piles' shape (pile2d_repose/shapes.txt, shapes_peak_margin10.txt):
  the spreading piles on the paper's substrate as written, the slope over
  the whole flank and the flank beyond the summit.

    /usr/bin/python3 -m analysis.pile2d.results    # prints the table
"""

import functools
import math
import sys
from pathlib import Path

import numpy as np

from analysis.common.tables import read_rows
from analysis.pile2d.discharges import PAPER_CRITICAL_WIDTH, mean_std_ci, summarize
from analysis.results_tables import DATA_DIR, Row, markdown_table
from analysis.common.cli import command_line

# the page's sections (GitHub anchors of doc/pile2d.md's headings)
SECTION_NONE = "w_c-without-rolling-resistance"
SECTION_FIXED = "w_c-of-the-fixed-l_c-model"
SECTION_OVERLAP = "the-contact-length-model-two-readings-of-l_c"
SECTION_SUBSTRATE = "the-substrate-piles-that-stand"
SECTION_SHAPE = "the-angle-of-repose"
SECTION_AGREES = "what-agrees"

LABELS = {"none": "no rolling resistance", "fixed": "fixed l_c = 0.05 d",
          "depth": "l_c from the overlap, read as its depth δ_n",
          "overlap": "l_c from the overlap, read as its chord"}
NAMES = {"none": "none", "depth": "depth", "fixed": "fixed", "overlap": "chord"}
PAPER_LABEL = {"none": "", "fixed": "", "depth": " (its l_c-from-overlap model)",
               "overlap": " (its l_c-from-overlap model)"}

# (record, models taken from it): the page's "all four models" command
ENSEMBLE = (("pile2d_standing/discharges.txt", ("none", "depth")),
            ("pile2d_L200_none/discharges.txt", ("none",)),
            ("pile2d_L200_depth/discharges.txt", ("depth",)),
            ("pile2d_discharges.txt", ("fixed", "overlap")),
            ("pile2d_L200/discharges.txt", ("fixed",)),
            ("pile2d_L200_overlap/discharges.txt", ("overlap",)))
REPLICATES, BOOTSTRAP_SEED = 2000, 1


def ensemble_rows(data_dir=DATA_DIR):
    """The discharges of the four models at L = 20 ... 200 d."""
    rows = []
    for name, models in ENSEMBLE:
        rows += [r for r in read_rows(Path(data_dir) / name) if r["model"] in models]
    return rows


@functools.lru_cache(maxsize=4)
def _cached_summary(data_dir):
    return summarize(ensemble_rows(data_dir), replicates=REPLICATES, seed=BOOTSTRAP_SEED)


def ensemble_summary(data_dir=DATA_DIR):
    """analysis.pile2d.discharges.summarize of the four models (cached per directory:
    the bootstrap takes some 15 CPU-seconds)."""
    return _cached_summary(str(Path(data_dir).resolve()))


def _signed(value):
    return f"{value:+.2f}".replace("-", "−")


def _piles_per_length(entry):
    return "/".join(str(len(entry["lengths"][length]["seeds"])) for length in entry["critical"]["L"])


def _lengths(entry):
    return ", ".join(f"{length:g}" for length in entry["critical"]["L"])


def critical_rows(summary):
    rows = []
    for model in ("none", "fixed", "depth", "overlap"):
        entry = summary[model]
        c = entry["critical"]
        paper, paper_se = PAPER_CRITICAL_WIDTH[model]
        gap = c["w_c"] - paper
        gap_se = math.hypot(c["w_c_se"], paper_se)
        ours = (f"{c['w_c']:.2f} ± {c['w_c_se']:.2f} d "
                f"({_signed(gap)} ± {gap_se:.2f}, {abs(gap) / gap_se:.1f} se)")
        window = (f"fit of w_t = w_c + a/L over L = {_lengths(entry)} d "
                  f"({_piles_per_length(entry)} piles), χ²/dof {c['chi2_dof']:.1f}")
        if model == "none":
            row = Row(f"w_c, {LABELS[model]}", f"{paper} ± {paper_se} d (from its ref. [27])", ours,
                      window, "open", SECTION_NONE, headline=True,
                      cause="damping, time step and substrate tested: none raises it")
        elif model == "fixed":
            row = Row(f"w_c, {LABELS[model]}", f"{paper} ± {paper_se} d", ours, window, "open",
                      SECTION_FIXED, headline=True,
                      cause="no parameter the paper leaves open raises it; "
                            "4 × eq. 1's rolling resistance does")
        else:
            row = Row(f"w_c, {LABELS[model]}", f"{paper} ± {paper_se} d{PAPER_LABEL[model]}", ours,
                      window, "differs", SECTION_OVERLAP,
                      cause="the paper does not define its l_c from the overlap; "
                            "our two readings bracket its 5.3 d")
        rows.append(row)
    # the ratio, which no length unit changes
    none, fixed = summary["none"]["critical"], summary["fixed"]["critical"]
    ratio = fixed["w_c"] / none["w_c"]
    ratio_se = ratio * math.hypot(fixed["w_c_se"] / fixed["w_c"], none["w_c_se"] / none["w_c"])
    (p_fixed, s_fixed), (p_none, s_none) = PAPER_CRITICAL_WIDTH["fixed"], PAPER_CRITICAL_WIDTH["none"]
    p_ratio = p_fixed / p_none
    p_ratio_se = p_ratio * math.hypot(s_fixed / p_fixed, s_none / p_none)
    rows.append(Row("w_c(fixed l_c) / w_c(none), free of the length unit",
                    f"{p_ratio:.2f} ± {p_ratio_se:.2f}", f"{ratio:.2f} ± {ratio_se:.2f}",
                    "the two fits above", "open", SECTION_FIXED,
                    cause="as w_c of the fixed l_c"))
    return rows


def threshold_row(summary, length=100.0):
    """w_t at L = `length` per model: the paper shows h(w) and its
    fluctuation at L = 100 d (Fig. 4) and w_t(L) in Fig. 5, without giving
    a value in its text."""
    parts, piles = [], []
    for model in ("none", "depth", "fixed", "overlap"):
        entry = summary[model]
        k = entry["critical"]["L"].index(length)
        parts.append(f"{NAMES[model]} {entry['critical']['w_t'][k]:.2f} ± "
                     f"{entry['critical']['w_t_sigma'][k]:.2f}")
        piles.append(str(len(entry["lengths"][length]["seeds"])))
    return Row(f"w_t at L = {length:g} d (d)", "in Figs. 4 and 5 only", "; ".join(parts),
               f"{'/'.join(piles)} piles, bootstrap over the piles", "open", SECTION_AGREES,
               cause="the paper gives no value in its text")


def shift_row(summary, length=100.0):
    """Fig. 4: the drop of h(w) moves to larger w with rolling resistance."""
    parts, piles = [], []
    for model in ("none", "depth", "fixed", "overlap"):
        data = summary[model]["lengths"][length]
        parts.append(f"{NAMES[model]} {data['w_50']:.2f} ± {data['w_50_sigma']:.2f}")
        piles.append(str(len(data["seeds"])))
    return Row(f"h(w) at L = {length:g} d: where half the piles jam (w_50, d)",
               "the drop moves to larger w with rolling resistance (Fig. 4)", "; ".join(parts),
               f"{'/'.join(piles)} piles, bootstrap over the piles", "agrees", SECTION_AGREES)


def bimodal_row(summary, model="fixed", length=50.0):
    """Fig. 6: at w_t the piles either keep nearly all their height or
    empty; counted at the grid width nearest w_t."""
    entry = summary[model]
    k = entry["critical"]["L"].index(length)
    w_t = entry["critical"]["w_t"][k]
    data = entry["lengths"][length]
    j = int(np.argmin(np.abs(np.asarray(data["widths"]) - w_t)))
    jammed = data["jammed"][:, j]
    heights = data["table"][:, j]
    present = ~np.isnan(heights)
    n = int(present.sum())
    kept = int(np.nansum(jammed))
    empty = int(np.sum(heights[present] == 0))
    return Row(f"PDF of h at w_t, {LABELS[model]}",
               "bimodal: a peak near h0 and one at h = 0 (Fig. 6)",
               f"{kept} of {n} piles keep > h0/2, {empty} empty, {n - kept - empty} between",
               f"L = {length:g} d, w = {data['widths'][j]:g} d", "agrees", SECTION_AGREES)


def _angle(shapes, run, model, length):
    values = [s["angle"] for s in shapes if s["run"] == run and s["model"] == model and s["L"] == length]
    mean, _, (lo, hi), _ = mean_std_ci(values)
    n = int(np.sum(~np.isnan(np.asarray(values, dtype=float))))
    return f"{mean:.1f}° [{lo:.1f}, {hi:.1f}]".replace("-", "−"), n


# (run of shapes.txt, model) of the piles built with today's defaults
STANDING_RUNS = (("sublc0.1", "none"), ("depth_sub0.1", "depth"), ("base", "fixed"), ("base", "overlap"))


def shape_rows(data_dir=DATA_DIR):
    shapes = read_rows(Path(data_dir) / "pile2d_repose" / "shapes.txt")
    flank = read_rows(Path(data_dir) / "pile2d_repose" / "shapes_peak_margin10.txt")
    rows = []
    spread = [(length, *_angle(shapes, "base", "none", length)) for length in (20.0, 50.0, 100.0)]
    held = [(length, *_angle(shapes, "sublc0.1", "none", length)) for length in (20.0, 50.0, 100.0)]
    rows.append(Row("pile of model none on the paper's substrate as written (0.1 d discs, no rolling resistance)",
                    "stands (Fig. 3, L = 100 d)",
                    "spreads: " + ", ".join(f"{a} at L = {length:g} d" for length, a, _ in spread),
                    f"{spread[0][2]} piles per L, slope of the whole flank", "differs",
                    SECTION_SUBSTRATE,
                    cause="its bottom layer rolls over the substrate's 5° grooves; with l_c = 0.1 d on "
                          "the substrate contacts (our default) it stands at "
                          + ", ".join(a.split(" ")[0] for _, a, _ in held)))
    whole = [(NAMES[m], *_angle(shapes, run, m, 50.0)) for run, m in STANDING_RUNS]
    rows.append(Row("slope of the piles, whole flank",
                    "steeper with rolling resistance (Fig. 3; no angle given)",
                    "; ".join(f"{name} {a}" for name, a, _ in whole),
                    f"L = 50 d, {'/'.join(str(n) for _, _, n in whole)} piles", "agrees", SECTION_SHAPE))
    beyond = [(NAMES[m], *_angle(flank, run, m, 50.0)) for run, m in STANDING_RUNS]
    rows.append(Row("angle of repose, flank ≥ 10 d from the peak",
                    "steeper with rolling resistance (Fig. 3; no angle given)",
                    "; ".join(f"{name} {a}" for name, a, _ in beyond),
                    f"L = 50 d, {'/'.join(str(n) for _, _, n in beyond)} piles", "open", SECTION_SHAPE,
                    cause="the same in every model: rolling resistance steepens only the summit"))
    return rows


def results_rows(data_dir=DATA_DIR):
    summary = ensemble_summary(data_dir)
    return (critical_rows(summary) + [threshold_row(summary), shift_row(summary), bimodal_row(summary)]
            + shape_rows(data_dir))


def main(argv=None):
    parser = command_line("analysis.pile2d.results", __doc__.split("\n\n")[0],
                          "/usr/bin/python3 -m analysis.pile2d.results --data-dir doc/data")
    parser.add_argument("--data-dir", type=Path, default=DATA_DIR, help="the records' folder (default doc/data)")
    args = parser.parse_args(argv)
    sys.stdout.write(markdown_table(results_rows(args.data_dir)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
