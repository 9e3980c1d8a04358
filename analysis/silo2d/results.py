"""The clogging silo's results against Hidalgo et al. (2013), computed from
the arch and contact records in doc/data (the rows of doc/silo2d.md's
results table; analysis.results_tables puts them in the page).

Records: doc/data/silo2d_scan/mu{0.2,0.4,0.8} (the friction scan, about 200
arches each) and doc/data/silo2d_plate/mu{0.4,0.8}_plate0.3 (the same silo
with the flat plates' friction at 0.3, the test of the bulk force).

Statistics are those of analysis.silo2d.scan, in the order its command line
computes them (bootstrap seed 1, the three readings of each run in turn), so
every number here is also in the table of

    /usr/bin/python3 -m analysis.silo2d.scan doc/data/silo2d_scan/mu0.2 \\
        doc/data/silo2d_scan/mu0.4 doc/data/silo2d_scan/mu0.8 --out plots/

(`--arch-force walk` for the arch forces along the walk), except the mean
angle's interval, a bootstrap over clogs of its own (seed 2).

Two readings of the arch size eta (doc/silo2d.md, "Arch size"):
the plain walk (`members`: the grains between the two the walk starts
and ends on, the paper's rule "the particles in contact with the bottom of
the silo are not considered to be members of the bridge" read literally)
and `outlet` (those, and the end grains resting on an outlet grain alone).
The angles and forces are those of the plain walk.

    /usr/bin/python3 -m analysis.silo2d.results      # print the rows
"""

import functools
import sys
from pathlib import Path

import numpy as np

from analysis.silo2d import clogs as silo2d
from analysis.silo2d import scan as silo2d_scan
from analysis.results_tables import DATA_DIR, Row
from analysis.common.cli import command_line

MUS = (0.2, 0.4, 0.8)
PLAIN = "members"           # the plain walk
OUTLET = "outlet"
PLATE_RUNS = {0.4: "mu0.4_plate0.3", 0.8: "mu0.8_plate0.3"}
PLATE_FRICTION = 0.3
PHI_MEAN_SEED = 2
# an interval that overlaps the paper's by less than this (m g) agrees "at the edge"
EDGE = 0.1

# the sections of doc/silo2d.md that discuss the rows
SECTION_ETA = "arch-size-the-papers-rule-read-two-ways"
SECTION_PHI = "arch-angles-and-defects"
SECTION_BULK = "table-1-the-bulk-force-and-the-plates-of-the-gap"
SECTION_ARCH = "table-1-the-arch-force-and-which-contacts-count"
SECTION_RATIO = "table-1-the-force-ratio"


@functools.lru_cache(maxsize=None)
def _runs(directories):
    return {d: silo2d_scan.load_run(d) for d in directories}


@functools.lru_cache(maxsize=None)
def scan_rows(directories, arch_force="all"):
    """{(mu, reading): analysis.silo2d.scan.summarize row} of the runs in
    `directories` (a tuple of record directories), as
    `analysis.silo2d.scan DIRS... [--arch-force walk]` computes them."""
    runs = sorted(_runs(directories).values(), key=lambda run: run["geometry"]["mu"])
    rng = np.random.default_rng(1)
    rows = {}
    for run in runs:
        for reading in silo2d.READINGS:
            rows[(round(run["geometry"]["mu"], 3), reading)] = silo2d_scan.summarize(
                run, reading, rng, arch_force)
    return rows


@functools.lru_cache(maxsize=None)
def phi_means(directories, reading=PLAIN, resamples=silo2d_scan.RESAMPLES):
    """{mu: (mean phi, low, high)}: the mean angle of the arch grains under
    `reading`, with a 95 % percentile bootstrap over clogs."""
    rng = np.random.default_rng(PHI_MEAN_SEED)
    out = {}
    for run in sorted(_runs(directories).values(), key=lambda run: run["geometry"]["mu"]):
        arches = silo2d.arch_grains(run["tables"]["arches"], run["feet"], reading)
        groups = silo2d_scan.clog_groups(run, arches)

        def mean_phi(sample):
            return float(np.mean(np.concatenate([g["phi"] for g in sample])))

        low, high = silo2d.bootstrap_over_clogs(groups, mean_phi, rng, resamples)
        out[round(run["geometry"]["mu"], 3)] = (float(np.mean(arches["phi"])), low, high)
    return out


# ---------------------------------------------------------------- formatting

def _interval(value, low, high, digits=1):
    return f"{value:.{digits}f} [{low:.{digits}f}, {high:.{digits}f}]"


def _mode(row):
    return f"{row['eta_mode']} [{row['eta_mode_ci'][0]:g}, {row['eta_mode_ci'][1]:g}]"


def _per_mu(texts):
    return " / ".join(texts)


def _overlap(low, high, paper_low, paper_high):
    return low <= paper_high and paper_low <= high


def _arches(rows, reading=PLAIN):
    return "/".join(str(rows[(mu, reading)]["arches"]) for mu in MUS)


# ---------------------------------------------------------------- rows

def eta_rows(rows):
    """The arch size: mode and mean, plain walk first, then `outlet`."""
    peak = rows[(MUS[0], PLAIN)]["R"] + 2
    mu_text = "μ = " + " / ".join(f"{mu:g}" for mu in MUS)
    outlet_modes = {rows[(mu, OUTLET)]["eta_mode"] for mu in MUS}
    out = []
    for reading, name in ((PLAIN, "plain walk"), (OUTLET, "`outlet` reading")):
        selected = [rows[(mu, reading)] for mu in MUS]
        at_peak = all(r["eta_mode_ci"][0] <= peak <= r["eta_mode_ci"][1] for r in selected)
        cause = ""
        if not at_peak and len(outlet_modes) == 1:
            cause = ("the plain walk leaves out its two end grains, which rest on the outlet grains; "
                     f"with those on an outlet grain alone counted (`outlet`) the mode is "
                     f"{next(iter(outlet_modes))} at every μ")
        out.append(Row(
            quantity=f"η mode, {name}, {mu_text}",
            paper=f"maximum around η = R + 2 = {peak:g} (Fig. 2)",
            ours=_per_mu(_mode(r) for r in selected),
            window=f"`--reading {reading}`; {_arches(rows, reading)} arches",
            verdict="agrees" if at_peak else ("differs" if cause else "open"),
            section=SECTION_ETA, headline=True, cause=cause))
    for reading, name in ((PLAIN, "plain walk"), (OUTLET, "`outlet` reading")):
        means = [rows[(mu, reading)]["eta_mean"] for mu in MUS]
        grows = (means[0][0] + means[0][1] < means[-1][0] - means[-1][1]
                 and all(a[0] < b[0] for a, b in zip(means[:-1], means[1:])))
        out.append(Row(
            quantity=f"mean η, {name}, {mu_text}",
            paper="no value; \"larger arches are formed as μ increases\"",
            ours=_per_mu(f"{m:.2f} ± {h:.2f}" for m, h in means),
            window=f"`--reading {reading}`; Student t over arches",
            verdict="agrees" if grows else "open",
            section=SECTION_ETA))
    return out


def phi_rows(rows, means):
    """The angle phi per mu (fullest 10° bin and mean), and the defects."""
    low_peak, high_peak = silo2d_scan.PAPER_PHI_PEAK
    half_bin = silo2d_scan.PHI_BIN / 2
    out = []
    for mu in MUS:
        r = rows[(mu, PLAIN)]
        low, high = r["phi_peak_ci"]
        mean, mean_low, mean_high = means[mu]
        out.append(Row(
            quantity=f"φ (°), fullest 10° bin / mean, μ = {mu:g}",
            paper=f"maximum at {low_peak:g}–{high_peak:g} (Fig. 3); no mean",
            ours=f"{r['phi_peak']:g} [{low:g}, {high:g}] / {_interval(mean, mean_low, mean_high)}",
            window=f"plain walk; {r['arches']} arches",
            verdict="agrees" if _overlap(low - half_bin, high + half_bin, low_peak, high_peak) else "open",
            section=SECTION_PHI))
    defects = [rows[(mu, PLAIN)]["defects"] for mu in MUS]
    out.append(Row(
        quantity="defect fraction (φ > 180°), μ = " + " / ".join(f"{mu:g}" for mu in MUS),
        paper="no value; wider φ PDF as μ grows (Fig. 3)",
        ours=_per_mu(_interval(p, low, high, 3) for p, low, high in defects),
        window="plain walk; Wilson interval over arch grains",
        verdict="agrees" if defects[0][2] < defects[-1][1] else "open",
        section=SECTION_PHI))
    return out


def table1_rows(rows, walk_rows, plate_rows):
    """Table 1: <f_n,b>, <f_n,a> and their ratio per mu (units of m g)."""
    bulk, arch, ratios = [], [], []
    for mu in MUS:
        r, walk = rows[(mu, PLAIN)], walk_rows[(mu, PLAIN)]
        (paper_b, error_b), (paper_a, error_a) = silo2d.PAPER_TABLE1[mu]
        paper_ratio, error_ratio = silo2d_scan.paper_ratio(mu)
        window = f"plain walk; {r['arches']} arches"
        arch_window = f"{window}; a grain's f_n over all its contacts"

        low, high = r["fn_b_boot"]
        agrees = _overlap(low, high, paper_b - error_b, paper_b + error_b)
        cause = ""
        if not agrees and mu in plate_rows:
            plate = plate_rows[mu]
            cause = (f"the flat plates carry more of the weight; with plate friction "
                     f"{PLATE_FRICTION:g}: {_interval(plate['fn_b'][0], *plate['fn_b_boot'])} "
                     f"({plate['arches']} arches)")
        bulk.append(Row(
            quantity=f"⟨f_n,b⟩ / m g, μ = {mu:g}",
            paper=f"{paper_b:g} ± {error_b:g}",
            ours=_interval(r["fn_b"][0], low, high),
            window=f"{window}; 27 < h/d < 48, |x| < 12 d",
            verdict="agrees" if agrees else ("differs" if cause else "open"),
            section=SECTION_BULK, cause=cause))

        low, high = r["fn_a_boot"]
        agrees = _overlap(low, high, paper_a - error_a, paper_a + error_a)
        walk_low, walk_high = walk["fn_a_boot"]
        walk_text = f"over its two contacts along the arch: {_interval(walk['fn_a'][0], walk_low, walk_high)}"
        cause = ""
        if not agrees and _overlap(walk_low, walk_high, paper_a - error_a, paper_a + error_a):
            cause = f"f_n averaged over all of a grain's contacts; {walk_text}"
        elif agrees and min(high - (paper_a - error_a), paper_a + error_a - low) < EDGE:
            cause = f"at the edge of the paper's interval; {walk_text}"
        arch.append(Row(
            quantity=f"⟨f_n,a⟩ / m g, μ = {mu:g}",
            paper=f"{paper_a:g} ± {error_a:g}",
            ours=_interval(r["fn_a"][0], low, high),
            window=arch_window,
            verdict="agrees" if agrees else ("differs" if cause else "open"),
            section=SECTION_ARCH, cause=cause))

        low, high = r["ratio_ci"]
        ratios.append(Row(
            quantity=f"⟨f_n,a⟩/⟨f_n,b⟩, μ = {mu:g}",
            paper=f"{paper_a:g}/{paper_b:g} = {paper_ratio:.2f} ± {error_ratio:.2f}",
            ours=_interval(r["ratio"], low, high, 2),
            window=arch_window,
            verdict=("agrees" if _overlap(low, high, paper_ratio - error_ratio, paper_ratio + error_ratio)
                     else "open"),
            section=SECTION_RATIO, headline=(mu == 0.4)))
    return bulk + arch + ratios


def results_rows(data_dir=DATA_DIR):
    """The rows of doc/silo2d.md's results table (analysis.results_tables)."""
    data_dir = Path(data_dir)
    scan = tuple(str(data_dir / "silo2d_scan" / f"mu{mu:g}") for mu in MUS)
    plates = {mu: (str(data_dir / "silo2d_plate" / name),) for mu, name in PLATE_RUNS.items()}
    rows = scan_rows(scan)
    walk_rows = scan_rows(scan, "walk")
    plate_rows = {mu: scan_rows(directory)[(mu, PLAIN)] for mu, directory in plates.items()}
    return (eta_rows(rows) + phi_rows(rows, phi_means(scan))
            + table1_rows(rows, walk_rows, plate_rows))


def main(argv=None):
    from analysis.results_tables import markdown_table
    parser = command_line("analysis.silo2d.results",
                          "Print the rows of doc/silo2d.md's results table, computed from doc/data "
                          "(about half a minute).",
                          "/usr/bin/python3 -m analysis.silo2d.results")
    parser.parse_args(argv)
    print(markdown_table(results_rows()), end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())
