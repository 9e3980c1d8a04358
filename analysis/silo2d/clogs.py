"""Analysis of the quasi-2D silo clogging records (Hidalgo et al. 2013,
sections 3-5 and Table 1).

Reads the records `fix clog` writes (contract: doc/silo2d_records.md):
clogs.txt, arches.txt, contacts.txt and optionally silo.txt, and produces the
PDFs of eta and phi, <F_n>/<F_t> versus phi, normal-force profiles versus
height for the wall / intermediate / centre regions, the bulk reference
<f_n,b>, force and mobilized-friction PDFs for arch and bulk, and Table 1.

CLI:  python3 -m analysis.silo2d RECORD_DIR [--d D --mu MU --mass M ...] --out DIR
"""

import sys
from pathlib import Path

import numpy as np
from scipy import stats

from analysis.common.tables import read_table
from analysis.common.cli import command_line

# Paper's Table 1 (units of m g): mu -> ((fn_b, +-), (fn_a, +-)).
PAPER_TABLE1 = {
    0.2: ((24.0, 2.0), (44.0, 3.0)),
    0.4: ((20.0, 1.0), (35.0, 3.0)),
    0.8: ((21.0, 2.0), (32.0, 2.0)),
}

# Region limits in units of d, on |x| (silo centre at x = 0). The paper's
# Fig. 1, which draws the regions, is not in the text we have; these defaults
# split the 16 d half width into a centre strip as wide as the outlet region
# (|x| < 4 d: the outlet grains' centres are at +-2 d), a wall strip of 4 d
# and the intermediate band between them.
CENTRE_MAX_D = 4.0
WALL_MIN_D = 12.0
# Bulk window of the paper (section 4): 27 < h/d < 48, both ends exclusive.
BULK_H_MIN_D = 27.0
BULK_H_MAX_D = 48.0

REQUIRED_COLUMNS = {
    "clogs.txt": ("clog", "step", "time", "avalanche", "eta", "status"),
    "arches.txt": ("clog", "order", "id", "x", "y", "z", "phi", "fn", "ft"),
    "contacts.txt": ("clog", "id1", "id2", "x", "z", "fn", "ft", "arch"),
}
# feet.txt (fix clog since its feet were recorded) has the columns of
# arches.txt, `base` and `floor`; older records have none.
FEET_COLUMNS = REQUIRED_COLUMNS["arches.txt"] + ("base", "floor")

# Which grains make the arch (doc/silo2d.md, "Arch size: which grains
# count"), three readings of the paper's "the particles in contact with the
# bottom of the silo are not considered to be members of the bridge":
# "members": the bottom is every fixed grain under the silo, the outlet
#   grains included, so the two feet (resting on them) are not arch grains;
# "outlet": the bottom is the floor beside the two outlet grains, so a foot
#   resting on its outlet grain alone is an arch grain, one that also
#   touches the next bottom grain (in the pocket beside it) is not;
# "feet": both feet are always arch grains.
# The default is "outlet": with it the PDF of eta peaks at R + 2 = 5 for
# mu = 0.2, 0.4 and 0.8 (the paper's Fig. 2), with "members" at 2-3
# (doc/silo2d.md, "Arch size"). Records without feet.txt fall back to
# "members", and say so.
READINGS = ("members", "outlet", "feet")
DEFAULT_READING = "outlet"


def default_reading(have_feet):
    """DEFAULT_READING, or "members" (with a note) for records without feet.txt."""
    if have_feet:
        return DEFAULT_READING
    print(f"silo2d: no feet.txt in these records: the '{DEFAULT_READING}' reading needs it, "
          "using 'members'", flush=True)
    return "members"


# ---------------------------------------------------------------- statistics

def bin_index(values, edges):
    """Bin of each value, numpy.histogram's convention: bins [e_k, e_k+1)
    except the last, which is closed [e_n-1, e_n]; -1 for values outside.
    One convention for PDFs and binned means so their bins agree."""
    values = np.asarray(values, dtype=float)
    edges = np.asarray(edges, dtype=float)
    index = np.searchsorted(edges, values, side="right") - 1
    index[values == edges[-1]] = len(edges) - 2
    index[(values < edges[0]) | (values > edges[-1]) | np.isnan(values)] = -1
    return index


def pdf(values, edges):
    """Normalised histogram: returns (centres, density) with
    sum(density * width) = 1 over the values inside the edges."""
    edges = np.asarray(edges, dtype=float)
    counts, _ = np.histogram(np.asarray(values, dtype=float), bins=edges)
    centres = 0.5 * (edges[1:] + edges[:-1])
    total = counts.sum()
    if total == 0:
        return centres, np.zeros(len(centres))
    return centres, counts / (total * np.diff(edges))


def integer_edges(values):
    """Edges k - 1/2 .. k + 1/2 for every integer from min to max, so that each
    integer value sits in the middle of its own unit-width bin."""
    values = np.asarray(values)
    if values.size == 0:
        return np.array([-0.5, 0.5])
    low, high = int(np.floor(values.min())), int(np.ceil(values.max()))
    return np.arange(low, high + 2) - 0.5


def integer_pdf(values):
    """PDF of integer data (eta) on unit bins centred on the integers;
    the density equals the fraction of samples with that value."""
    return pdf(values, integer_edges(values))


def binned_mean(x, y, edges):
    """Mean of y in bins of x with its standard error std(ddof=1)/sqrt(n).
    Returns (centres, mean, sem, count); mean is nan in empty bins and sem nan
    where n < 2 (one sample says nothing about the scatter)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    nbins = len(edges) - 1
    index = bin_index(x, edges)
    mean = np.full(nbins, np.nan)
    sem = np.full(nbins, np.nan)
    count = np.zeros(nbins, dtype=int)
    for k in range(nbins):
        sample = y[index == k]
        count[k] = sample.size
        if sample.size:
            mean[k] = sample.mean()
        if sample.size > 1:
            sem[k] = sample.std(ddof=1) / np.sqrt(sample.size)
    centres = 0.5 * (np.asarray(edges[1:], float) + np.asarray(edges[:-1], float))
    return centres, mean, sem, count


def exponential_mean_ci(values, level=0.95):
    """Mean and its confidence interval assuming exponential samples (the
    paper's Table 1): 2 n xbar / theta ~ chi2(2n), hence
    [2 n xbar / chi2_{1-a/2, 2n}, 2 n xbar / chi2_{a/2, 2n}]."""
    values = np.asarray(values, dtype=float)
    n = values.size
    if n == 0:
        return np.nan, np.nan, np.nan
    mean = values.mean()
    alpha = 1.0 - level
    low = 2 * n * mean / stats.chi2.ppf(1 - alpha / 2, 2 * n)
    high = 2 * n * mean / stats.chi2.ppf(alpha / 2, 2 * n)
    return mean, low, high


def mobilized_friction(fn, ft, mu):
    """f_t / (mu f_n) for the contacts with f_n > 0 (a zero normal force has
    no Coulomb threshold to compare with, so those entries are dropped)."""
    fn = np.asarray(fn, dtype=float)
    ft = np.asarray(ft, dtype=float)
    keep = fn > 0
    return ft[keep] / (mu * fn[keep])


def wilson_interval(successes, n, level=0.95):
    """A proportion and its Wilson score interval: (p, low, high)."""
    if n == 0:
        return np.nan, np.nan, np.nan
    z = stats.norm.ppf(0.5 + level / 2)
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return p, centre - half, centre + half


def bootstrap_over_clogs(groups, statistic, rng, resamples=2000, level=0.95):
    """Percentile interval of statistic(list of groups), resampling whole
    clogs: the grains and contacts of one clog are not independent."""
    n = len(groups)
    if n == 0:
        return np.nan, np.nan
    values = np.array([statistic([groups[k] for k in rng.integers(0, n, n)])
                       for _ in range(resamples)])
    values = values[np.isfinite(values)]
    if values.size == 0:
        return np.nan, np.nan
    tail = 100 * (1 - level) / 2
    return float(np.percentile(values, tail)), float(np.percentile(values, 100 - tail))


def force_sums(arch_fn, bulk_fn):
    """What a clog contributes to <f_n,a>/<f_n,b>: the sums and counts of
    its arch grains' and its bulk contacts' normal forces."""
    return {"arch_sum": float(np.sum(arch_fn)), "arch_n": int(np.size(arch_fn)),
            "bulk_sum": float(np.sum(bulk_fn)), "bulk_n": int(np.size(bulk_fn))}


def force_ratio(groups):
    """<f_n,a>/<f_n,b> over the clogs of `groups` (force_sums of each),
    each mean pooled over the clogs; nan if either has no sample."""
    total = {key: sum(g[key] for g in groups) for key in ("arch_sum", "arch_n", "bulk_sum", "bulk_n")}
    if total["arch_n"] == 0 or total["bulk_n"] == 0 or total["bulk_sum"] == 0:
        return np.nan
    return (total["arch_sum"] / total["arch_n"]) / (total["bulk_sum"] / total["bulk_n"])


def most_frequent(values):
    """The most frequent integer (the smallest one on a tie)."""
    values = np.asarray(values, dtype=int)
    counts = np.bincount(values - values.min())
    return int(np.argmax(counts) + values.min())


def exponential_tail_rate(eta, start):
    """Decay rate lambda of P(eta) ~ exp(-lambda eta) for eta >= start, by
    maximum likelihood for a geometric law of eta - start (mean excess m:
    lambda = ln(1 + 1/m)); nan with fewer than two values in the tail."""
    tail = np.asarray(eta, dtype=float)
    tail = tail[tail >= start] - start
    if tail.size < 2 or tail.mean() == 0:
        return np.nan
    return float(np.log1p(1.0 / tail.mean()))


# ---------------------------------------------------------------- selections

def region_of(x, d, centre_max=CENTRE_MAX_D, wall_min=WALL_MIN_D):
    """Region label per point from |x|/d: 'C' if |x|/d < centre_max,
    'W' if |x|/d >= wall_min, else 'I' (so a point on a boundary belongs to
    the region farther from the centre)."""
    distance = np.abs(np.asarray(x, dtype=float)) / d
    labels = np.full(distance.shape, "I", dtype="<U1")
    labels[distance < centre_max] = "C"
    labels[distance >= wall_min] = "W"
    return labels


def bulk_mask(x, z, d, h_min=BULK_H_MIN_D, h_max=BULK_H_MAX_D,
              centre_max=CENTRE_MAX_D, wall_min=WALL_MIN_D):
    """Contacts of the paper's bulk: central or intermediate region and
    h_min < h/d < h_max (both ends exclusive, as the paper writes it)."""
    h = np.asarray(z, dtype=float) / d
    inner = region_of(x, d, centre_max, wall_min) != "W"
    return inner & (h > h_min) & (h < h_max)


def profile_edges(h, bin_width_d=1.0):
    """Bins of h/d of width bin_width_d from 0 up to the highest point."""
    top = max(bin_width_d, np.ceil(h.max() / bin_width_d) * bin_width_d) if h.size else bin_width_d
    return np.arange(0.0, top + 0.5 * bin_width_d, bin_width_d)


def force_profiles(x, z, fn, d, bin_width_d=1.0, centre_max=CENTRE_MAX_D,
                   wall_min=WALL_MIN_D):
    """Mean normal force versus h/d per region: dict region ->
    (centres, mean, sem, count), bins of bin_width_d from h = 0."""
    h = np.asarray(z, dtype=float) / d
    edges = profile_edges(h, bin_width_d)
    labels = region_of(x, d, centre_max, wall_min)
    fn = np.asarray(fn, dtype=float)
    return {name: binned_mean(h[labels == name], fn[labels == name], edges)
            for name in ("W", "I", "C")}


SURFACE_QUANTILE = 99.0


def surface_heights(clog, x, z, d):
    """Per clog, the height (in d) of the free surface, taken as the height
    below which SURFACE_QUANTILE % of the contacts of regions C and I lie
    (the top layer's contacts are a few per cent of the column's): a
    measure within about a diameter. Returns (clogs, heights)."""
    clog, z = np.asarray(clog), np.asarray(z, dtype=float) / d
    inner = region_of(x, d) != "W"
    clogs = np.unique(clog)
    return clogs, np.array([np.percentile(z[inner & (clog == c)], SURFACE_QUANTILE) for c in clogs])


PROFILE_COLUMNS = ("region", "h_low", "h_high", "n", "mean_fn", "square_deviation_fn")
REGION_CODES = {"W": 0, "I": 1, "C": 2}


def profile_sums(x, z, fn, d, bin_width_d=1.0):
    """What force_profiles needs, for an archive that keeps the profiles
    but not every contact: rows (region code, h_low, h_high, n, mean f_n,
    sum of (f_n - mean)^2) of the non-empty bins, h in units of d (the
    squared deviations, not the sum of squares, keep the scatter's digits)."""
    h = np.asarray(z, dtype=float) / d
    edges = profile_edges(h, bin_width_d)
    labels = region_of(x, d)
    fn = np.asarray(fn, dtype=float)
    rows = []
    for name, code in REGION_CODES.items():
        mine = labels == name
        index = bin_index(h[mine], edges)
        for k in range(len(edges) - 1):
            sample = fn[mine][index == k]
            if sample.size:
                rows.append((code, edges[k], edges[k + 1], sample.size, sample.mean(),
                             np.square(sample - sample.mean()).sum()))
    return rows


def profiles_from_sums(table):
    """force_profiles' dict region -> (centres, mean, sem, count) from the
    rows of profile_sums (a read profiles.txt)."""
    result = {}
    for name, code in REGION_CODES.items():
        rows = np.atleast_1d(table["region"]) == code
        low, high = np.atleast_1d(table["h_low"])[rows], np.atleast_1d(table["h_high"])[rows]
        n = np.atleast_1d(table["n"])[rows]
        mean = np.atleast_1d(table["mean_fn"])[rows]
        deviations = np.atleast_1d(table["square_deviation_fn"])[rows]
        sem = np.where(n > 1, np.sqrt(deviations / np.maximum(n - 1, 1) / n), np.nan)
        result[name] = (0.5 * (low + high), mean, sem, n.astype(int))
    return result


# ---------------------------------------------------------------- records

def read_records(record_dir):
    """The three tables as dicts of arrays; missing columns are an error
    naming the file, so a wrong fix clog output fails loudly."""
    record_dir = Path(record_dir)
    tables = {}
    for name, columns in REQUIRED_COLUMNS.items():
        path = record_dir / name
        if not path.exists() and (record_dir / (name + ".xz")).exists():
            path = record_dir / (name + ".xz")     # an archive (analysis.campaign.silo2d_archive)
        tables[name.split(".")[0]] = read_table(path, required=columns)
    return tables


def read_feet(record_dir):
    """feet.txt as a dict of arrays, or None when the records have none."""
    path = Path(record_dir) / "feet.txt"
    if not path.exists():
        return None
    return read_table(path, required=FEET_COLUMNS)


def require_feet(feet):
    if feet is None:
        raise ValueError("the 'feet' reading needs feet.txt, which these records lack "
                         "(written by fix clog since its feet were recorded)")


def counted_feet(feet, reading):
    """Mask of the rows of feet.txt that are arch grains under `reading`."""
    if reading not in READINGS:
        raise ValueError(f"reading must be one of {READINGS}, not {reading!r}")
    if reading == "members":
        return None
    require_feet(feet)
    on_floor = np.atleast_1d(feet["floor"]) != 0
    return ~on_floor if reading == "outlet" else np.ones(on_floor.shape, dtype=bool)


def arch_grains(arches, feet, reading):
    """The arch grains under `reading` (READINGS): the rows of arches.txt,
    with the counted ones of feet.txt, sorted by clog and walk order."""
    counted = counted_feet(feet, reading)
    if counted is None:
        return arches
    columns = REQUIRED_COLUMNS["arches.txt"]
    merged = {c: np.concatenate([np.atleast_1d(arches[c]), np.atleast_1d(feet[c])[counted]])
              for c in columns}
    order = np.lexsort((merged["order"], merged["clog"]))
    return {c: values[order] for c, values in merged.items()}


def walk_pairs(arches, feet):
    """Per clog, the arch's walk as the grain pairs it steps along: foot
    base - left foot, left foot - member 1, member k - member k+1, ...,
    member eta - right foot, right foot - its base (src_plugin/core/arch_walk.h;
    feet.txt gives each foot's base grain). Returns {clog: {id: (pair,
    pair)}}, each grain's two walk contacts, pairs as (smaller id, larger
    id). Clogs without both feet are left out."""
    by_clog = {}
    for clog, order, grain in zip(np.atleast_1d(arches["clog"]), np.atleast_1d(arches["order"]),
                                  np.atleast_1d(arches["id"])):
        by_clog.setdefault(int(clog), []).append((int(order), int(grain)))
    feet_by_clog = {}
    for clog, order, grain, base in zip(np.atleast_1d(feet["clog"]), np.atleast_1d(feet["order"]),
                                        np.atleast_1d(feet["id"]), np.atleast_1d(feet["base"])):
        feet_by_clog.setdefault(int(clog), []).append((int(order), int(grain), int(base)))
    walks = {}
    for clog, members in by_clog.items():
        ends = sorted(feet_by_clog.get(clog, []))
        if len(ends) != 2:
            continue
        (_, left, left_base), (_, right, right_base) = ends
        chain = [left_base, left] + [grain for _, grain in sorted(members)] + [right, right_base]
        pairs = [tuple(sorted(step)) for step in zip(chain[:-1], chain[1:])]
        walks[clog] = {grain: (pairs[k], pairs[k + 1]) for k, grain in enumerate(chain[1:-1])}
    return walks


def _contact_keys(contacts):
    """(clog, (smaller id, larger id)) of each row of contacts.txt."""
    return [(int(clog), (min(int(a), int(b)), max(int(a), int(b))))
            for clog, a, b in zip(np.atleast_1d(contacts["clog"]), np.atleast_1d(contacts["id1"]),
                                  np.atleast_1d(contacts["id2"]))]


def walk_contact_mask(walks, contacts):
    """The rows of contacts.txt that lie along an arch's walk (walk_pairs)."""
    wanted = {(clog, pair) for clog, walk in walks.items() for two in walk.values() for pair in two}
    return np.array([key in wanted for key in _contact_keys(contacts)], dtype=bool)


def walk_contact_forces(grains, walks, contacts):
    """For each row of `grains` (arch_grains), the mean normal force of its
    two walk contacts (walk_pairs): the forces along the arch that set the
    grain's angle phi, where the `fn` of arches.txt averages all of its
    contacts. NaN where the clog has no walk or a contact is not in
    `contacts`."""
    on_walk = walk_contact_mask(walks, contacts)
    keys = _contact_keys(contacts)
    fn = np.atleast_1d(contacts["fn"])
    force = {keys[k]: float(fn[k]) for k in np.flatnonzero(on_walk)}
    means = []
    for clog, grain in zip(np.atleast_1d(grains["clog"]), np.atleast_1d(grains["id"])):
        two = walks.get(int(clog), {}).get(int(grain))
        values = [force.get((int(clog), pair)) for pair in two] if two else [None]
        means.append(np.nan if None in values else 0.5 * (values[0] + values[1]))
    return np.array(means)


def arch_sizes(clogs, feet, reading):
    """eta of every clog with an arch (status 1), in clog order, under
    `reading`; with the feet, each such clog must have its two feet."""
    found = np.atleast_1d(clogs["status"]) == 1
    eta = np.atleast_1d(clogs["eta"])[found]
    counted = counted_feet(feet, reading)
    if counted is None:
        return eta
    found_clogs = np.atleast_1d(clogs["clog"])[found]
    foot_clogs = np.atleast_1d(feet["clog"])
    rows = {clog: 0 for clog in found_clogs}
    for clog in foot_clogs:
        rows[clog] = rows.get(clog, 0) + 1
    wrong = [int(c) for c, n in rows.items() if n != 2]
    if wrong:
        raise ValueError(f"feet.txt: clogs {wrong[:5]} do not have exactly two feet")
    added = np.array([np.sum(counted[foot_clogs == clog]) for clog in found_clogs], dtype=int)
    return eta + added


def read_silo(path):
    """silo.txt: `key value` lines (d, half_width, mass, g, mu, R); '#' comments."""
    values = {}
    for line in Path(path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            key, value = line.split()[:2]
            values[key] = float(value)
    return values


def table1(fn_bulk, fn_arch, mass, g, mu):
    """Rows of Table 1 in units of m g: (label, mean, low, high, n, paper)."""
    weight = mass * g
    paper = PAPER_TABLE1.get(round(mu, 3))
    rows = []
    for k, (label, values) in enumerate((("<fn_b>", fn_bulk), ("<fn_a>", fn_arch))):
        mean, low, high = exponential_mean_ci(np.asarray(values) / weight)
        rows.append((label, mean, low, high, len(values), paper[k] if paper else None))
    return rows


def table1_markdown(rows, mu):
    lines = [f"Table 1 (Hidalgo et al. 2013), mu = {mu:g}, forces in units of m g;",
             "95 % CI of the mean of an exponential distribution "
             "[2n xbar/chi2(0.975,2n), 2n xbar/chi2(0.025,2n)].", "",
             "| quantity | this run | 95 % CI | n | paper |",
             "|---|---|---|---|---|"]
    for label, mean, low, high, n, paper in rows:
        reference = f"{paper[0]:g} ± {paper[1]:g}" if paper else "—"
        lines.append(f"| {label} | {mean:.3f} | [{low:.3f}, {high:.3f}] | {n} | {reference} |")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- plots

def _axes(title, xlabel, ylabel):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    return fig, ax


def _save(fig, path):
    import matplotlib.pyplot as plt
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_all(out, eta, R, phi, arches, contacts, bulk, fn_b, mu, d, phi_bin,
             bulk_window=(BULK_H_MIN_D, BULK_H_MAX_D)):
    """The PNGs of figures 2-8 of the paper; returns the list of files."""
    files = []
    centres, density = integer_pdf(eta)
    fig, ax = _axes("PDF of eta", "eta", "PDF")
    ax.plot(centres, density, "o-")
    ax.axvline(R + 2, ls=":", color="k", label=f"R+2 = {R + 2:g}")
    ax.legend()
    files.append(out / "eta_pdf.png"); _save(fig, files[-1])

    edges = np.arange(0.0, 360.0 + phi_bin, phi_bin)
    centres, density = pdf(phi, edges)
    fig, ax = _axes("PDF of phi", "phi (deg)", "PDF")
    ax.plot(centres, density, "o-")
    ax.axvline(180.0, ls=":", color="k")
    files.append(out / "phi_pdf.png"); _save(fig, files[-1])

    fig, ax = _axes("arch forces vs phi", "phi (deg)", "<F> (N)")
    for name, label in (("fn", "<F_n>"), ("ft", "<F_t>")):
        c, mean, sem, _ = binned_mean(arches["phi"], arches[name], edges)
        ax.errorbar(c, mean, yerr=sem, fmt="o-", label=label)
    ax.legend()
    files.append(out / "force_vs_phi.png"); _save(fig, files[-1])

    fig, ax = _axes("normal-force profiles", "h/d", "<f_n> (N)")
    for name, (c, mean, sem, _) in force_profiles(contacts["x"], contacts["z"], contacts["fn"], d).items():
        ax.errorbar(c, mean, yerr=sem, fmt=".-", label=name)
    for h in bulk_window:
        ax.axvline(h, ls=":", color="k")
    ax.legend()
    files.append(out / "fn_profiles.png"); _save(fig, files[-1])

    for name, label in (("fn", "f_n"), ("ft", "f_t")):
        fig, ax = _axes(f"PDF of {label}/<f_n,b>", f"{label}/<f_n,b>", "PDF")
        for sample, tag in ((arches[name], "arch"), (contacts[name][bulk], "bulk")):
            ratio = np.asarray(sample) / fn_b
            if ratio.size:
                c, density = pdf(ratio, np.linspace(0.0, max(ratio.max(), 1e-12), 21))
                ax.semilogy(c, np.where(density > 0, density, np.nan), "o-", label=tag)
        ax.legend()
        files.append(out / f"{name}_pdf.png"); _save(fig, files[-1])

    fig, ax = _axes("mobilized friction", "f_t/(mu f_n)", "PDF")
    for fn, ft, tag in ((arches["fn"], arches["ft"], "arch"),
                        (contacts["fn"][bulk], contacts["ft"][bulk], "bulk")):
        c, density = pdf(np.minimum(mobilized_friction(fn, ft, mu), 1.0), np.linspace(0, 1, 21))
        ax.plot(c, density, "o-", label=tag)
    ax.legend()
    files.append(out / "mobilized_friction.png"); _save(fig, files[-1])
    return files


# ---------------------------------------------------------------- CLI

def parse_args(argv):
    parser = command_line("analysis.silo2d", __doc__,
                          "/usr/bin/python3 -m analysis.silo2d runs/silo2d_quick/mu0.4 --reading members --bulk "
                          "8 14 --out runs/silo2d_quick/mu0.4/analysis")
    parser.add_argument("record_dir", type=Path)
    parser.add_argument("--out", type=Path, default=None, metavar="DIR",
                        help="the directory the tables and figures go to (default RECORD_DIR/analysis)")
    parser.add_argument("--silo", type=Path, default=None, help="geometry file (default RECORD_DIR/silo.txt if present)")
    parser.add_argument("--d", type=float, help="grain diameter (m); default 1/32")
    parser.add_argument("--mu", type=float, help="friction coefficient")
    parser.add_argument("--mass", type=float, help="grain mass (kg); default rho pi d^3/6")
    parser.add_argument("--rho", type=float, help="grain density (kg/m^3); default 7580")
    parser.add_argument("--g", type=float, help="gravity (m/s^2); default 10")
    parser.add_argument("--R", type=float, help="outlet size in d; default 3")
    parser.add_argument("--half-width", dest="half_width", type=float, help="silo half width (m); default 16 d")
    parser.add_argument("--phi-bin", dest="phi_bin", type=float, default=10.0, help="phi bin width (deg)")
    parser.add_argument("--reading", choices=READINGS, default=None,
                        help="which grains make the arch: the walk's members between its feet, those and "
                             "the feet that rest on the outlet grain alone, or those and both feet "
                             f"(doc/silo2d.md; default {DEFAULT_READING}, members for records without "
                             "feet.txt)")
    parser.add_argument("--bulk", nargs=2, type=float, metavar=("HMIN", "HMAX"),
                        default=(BULK_H_MIN_D, BULK_H_MAX_D),
                        help="bulk window HMIN < h/d < HMAX (default: the paper's 27 48; "
                             "a smaller silo needs a lower window)")
    return parser.parse_args(argv)


def resolve_geometry(args):
    """Command-line values override silo.txt, which overrides the paper's."""
    silo_path = args.silo or args.record_dir / "silo.txt"
    geometry = {"d": 1.0 / 32, "g": 10.0, "R": 3.0, "rho": 7580.0}
    if silo_path.exists():
        geometry.update(read_silo(silo_path))
    for key in ("d", "mu", "mass", "rho", "g", "R", "half_width"):
        if getattr(args, key) is not None:
            geometry[key] = getattr(args, key)
    if "mu" not in geometry:
        raise SystemExit("error: mu is needed (--mu or 'mu' in silo.txt)")
    geometry.setdefault("mass", geometry["rho"] * np.pi * geometry["d"] ** 3 / 6)
    geometry.setdefault("half_width", 16 * geometry["d"])
    return geometry


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    geo = resolve_geometry(args)
    out = args.out or args.record_dir / "analysis"
    out.mkdir(parents=True, exist_ok=True)
    print(f"silo2d: reading records in {args.record_dir}", flush=True)
    tables = read_records(args.record_dir)
    clogs, contacts = tables["clogs"], tables["contacts"]
    feet = read_feet(args.record_dir)
    if args.reading is None:
        args.reading = default_reading(feet is not None)
    try:
        arches = arch_grains(tables["arches"], feet, args.reading)
        eta = arch_sizes(clogs, feet, args.reading)
    except ValueError as error:
        raise SystemExit(f"error: {error}")
    print(f"silo2d: {len(clogs['clog'])} clogs, {eta.size} with an arch, "
          f"{arches['id'].size} arch grains ({args.reading} reading), "
          f"{contacts['fn'].size} contacts", flush=True)
    h_min, h_max = args.bulk
    bulk = bulk_mask(contacts["x"], contacts["z"], geo["d"], h_min, h_max)
    if not bulk.any():
        raise SystemExit(f"error: no contact in the bulk window {h_min:g} < h/d < {h_max:g} "
                         "of regions C and I (set it with --bulk HMIN HMAX)")
    fn_b = contacts["fn"][bulk].mean()
    print(f"silo2d: <f_n,b> = {fn_b:.6g} N over {bulk.sum()} bulk contacts", flush=True)
    rows = table1(contacts["fn"][bulk], arches["fn"], geo["mass"], geo["g"], geo["mu"])
    text = table1_markdown(rows, geo["mu"])
    (out / "table1.md").write_text(text)
    print(text, flush=True)
    print("silo2d: plotting", flush=True)
    files = plot_all(out, eta, geo["R"], arches["phi"], arches, contacts, bulk, fn_b,
                     geo["mu"], geo["d"], args.phi_bin, args.bulk)
    print(f"silo2d: wrote {out / 'table1.md'} and {len(files)} PNGs in {out}", flush=True)
    return 0
