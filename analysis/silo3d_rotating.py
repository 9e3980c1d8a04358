"""Analysis of the cylindrical silo with a rotating bottom (Pongó, Börzsönyi
and Hidalgo 2022, sections II-III): flow rate Q(f, D) with uncertainties over
seeds, Beverloo and exponential fits, and coarse-grained fields (packing
fraction, velocity, kinetic and contact pressure, orientation) on an (r, z)
grid in time windows and averaged over the orifice region.

Reads the run directories the deck writes (record contract and outputs:
doc/silo3d_rotating_records.md; coarse graining: doc/coarse_graining.md).

CLI:  python3 -m analysis.silo3d_rotating RUN_DIR [RUN_DIR ...] --out DIR [options]
"""

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import optimize, stats

from analysis import coarse_grain as cg
from analysis.lammps_io import dump_steps, iter_dump, read_table

RUN_KEYS = ("d", "rho", "mass", "Dc", "D", "f", "seed", "N", "dt", "t_open", "reinject")
DISCHARGE_COLUMNS = ("step", "t", "n_out", "mass_out")
# compute pair/gran/local pos id force: the 12 columns of one contact
CONTACT_COLUMNS = ("x1", "y1", "z1", "x2", "y2", "z2", "id1", "id2", "periodic", "fx", "fy", "fz")
# a grain's axis in dump.cg: the deck's rods write c_rod_axis[1-3]
# (compute spherocylinder/axis); ox oy oz is the name other tools use
ORIENTATION_COLUMN_SETS = (("c_rod_axis[1]", "c_rod_axis[2]", "c_rod_axis[3]"), ("ox", "oy", "oz"))

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


# ---------------------------------------------------------------- records

def read_run_info(run_dir, required=RUN_KEYS):
    """run.txt: `key value` lines, '#' comments; numbers as floats, words
    (`shape rod`) as strings; the keys of `required` (RUN_KEYS for the
    analysis) must be there (an error names the file and the missing keys)."""
    path = Path(run_dir) / "run.txt"
    info = {}
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            key, value = line.split()[:2]
            try:
                info[key] = float(value)
            except ValueError:
                info[key] = value
    missing = [key for key in required if key not in info]
    if missing:
        raise ValueError(f"{path}: missing keys {missing}")
    return info


def read_discharge(run_dir):
    """discharge.txt as a dict of arrays; columns looked up by name."""
    path = Path(run_dir) / "discharge.txt"
    table = read_table(path)
    missing = [name for name in DISCHARGE_COLUMNS if name not in table]
    if missing:
        raise ValueError(f"{path}: missing columns {missing}")
    return table


def frame_particles(columns):
    """cg.Particles of a dump.cg frame; orientations (normalised) when the
    frame has the axes (ORIENTATION_COLUMN_SETS, the first set present)."""
    positions = np.column_stack([columns["x"], columns["y"], columns["z"]])
    velocities = np.column_stack([columns["vx"], columns["vy"], columns["vz"]])
    orientations = None
    for names in ORIENTATION_COLUMN_SETS:
        if all(name in columns for name in names):
            axes = np.column_stack([columns[name] for name in names])
            orientations = axes / np.linalg.norm(axes, axis=1, keepdims=True)
            break
    return cg.Particles(positions, velocities, columns["mass"], orientations)


def contact_columns(columns):
    """Names the 12 columns of `compute pair/gran/local pos id force` in a
    dump local frame (c_ID[1] ... c_ID[12], in that order): pos of the
    first and second grain, their ids, the periodic flag, and the force on
    the first grain (checked against LIGGGHTS in the tests)."""
    names = list(columns)
    if len(names) != len(CONTACT_COLUMNS):
        raise ValueError(f"dump.contacts: expected the {len(CONTACT_COLUMNS)} columns of "
                         f"'compute pair/gran/local pos id force' ({' '.join(CONTACT_COLUMNS)}), "
                         f"got {len(names)}: {' '.join(names)}")
    return {meaning: columns[name] for meaning, name in zip(CONTACT_COLUMNS, names)}


def frame_contacts(columns):
    """cg.Contacts of a dump.contacts frame: from grain 1 to grain 2, the
    force on grain 1. A contact across a periodic boundary would have its
    branch vector wrong (LIGGGHTS writes remapped positions): refused."""
    named = contact_columns(columns)
    if np.any(named["periodic"] != 0):
        raise ValueError("dump.contacts: contacts across periodic boundaries are not supported")
    starts = np.column_stack([named["x1"], named["y1"], named["z1"]])
    ends = np.column_stack([named["x2"], named["y2"], named["z2"]])
    forces = np.column_stack([named["fx"], named["fy"], named["fz"]])
    return cg.Contacts(starts, ends, forces)


def time_since_opening(steps, discharge, run):
    """tau = t - t_open of dump steps, from the discharge record's first
    (step, t) and the time step (the deck does not change dt after opening)."""
    step0, time0 = discharge["step"][0], discharge["t"][0]
    return time0 + (np.asarray(steps, dtype=float) - step0) * run["dt"] - run["t_open"]


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


def no_flow_intervals(tau, n_out, start, end, min_gap=MIN_GAP):
    """Intervals longer than min_gap without a grain out, as an (k, 2)
    array. Marks are the window's ends and every sample in (start, end]
    whose n_out exceeds the previous sample's (a grain left in the sampling
    interval ending there); a no-flow interval is the span between two
    consecutive marks, so it is known to one sampling interval."""
    tau = np.asarray(tau, dtype=float)
    n_out = np.asarray(n_out, dtype=float)
    exits = tau[1:][(n_out[1:] > n_out[:-1]) & (tau[1:] > start) & (tau[1:] <= end)]
    marks = np.unique(np.concatenate([[start], exits, [end]]))
    spans = np.column_stack([marks[:-1], marks[1:]])
    return spans[spans[:, 1] - spans[:, 0] > min_gap]


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

    @property
    def removed(self):
        return float(np.sum(self.gaps[:, 1] - self.gaps[:, 0])) if len(self.gaps) else 0.0


def block_rates(tau_eff, cumulative, duration, blocks):
    """Rates of `blocks` equal blocks of effective time: the increase of a
    cumulative count over each block, the count at a block edge being that
    of the last sample at or before it (a gap's end sample, at the same
    effective time as its start, is the later one and counts)."""
    edges = np.linspace(0.0, duration, blocks + 1)
    index = np.searchsorted(tau_eff, edges, side="right") - 1
    at_edges = np.asarray(cumulative, dtype=float)[np.maximum(index, 0)]
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
    if duration <= 0 or duration < min_flowing_fraction * (end - start):
        return FlowRate(np.nan, np.nan, np.nan, np.nan, blocks, start, end, max(duration, 0.0), gaps,
                        clogged, stationary=False)
    rates = {}
    for name, cumulative in (("mass", mass_out), ("grains", n_out)):
        cumulative = np.asarray(cumulative, dtype=float)[inside]
        per_block = block_rates(tau_eff, cumulative, duration, blocks)
        rates[name] = ((cumulative[-1] - cumulative[0]) / duration,
                       per_block.std(ddof=1) / np.sqrt(blocks))
    return FlowRate(*rates["mass"], *rates["grains"], blocks, start, end, duration, gaps, clogged)


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
    half = stats.t.ppf(0.5 + 0.5 * level, dof) * se if dof > 0 else np.nan
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

@dataclass
class Run:
    """A run directory with its run.txt, discharge record and flow rate."""
    path: Path
    info: dict
    discharge: dict
    tau: np.ndarray
    flow: FlowRate = None
    label: str = ""

    @property
    def finished(self):
        """The deck writes `finished <t>` to run.txt as its last act."""
        return "finished" in self.info

    @property
    def key(self):
        """(f, D) rounded so that equal deck values group together."""
        return (round(self.info["f"], 9), round(self.info["D"], 9))


def load_run(run_dir):
    info = read_run_info(run_dir)
    discharge = read_discharge(run_dir)
    return Run(Path(run_dir), info, discharge, discharge["t"] - info["t_open"])


def analyse_flow(run, transient=TRANSIENT, min_gap=MIN_GAP, end_fraction=END_FRACTION, blocks=BLOCKS,
                 min_flowing_fraction=MIN_FLOWING_FRACTION):
    total_mass = run.info["N"] * run.info["mass"]
    start, end = analysis_window(run.tau, run.discharge["mass_out"], total_mass,
                                 bool(run.info["reinject"]), transient, end_fraction)
    run.flow = stationary_flow_rate(run.tau, run.discharge["n_out"], run.discharge["mass_out"],
                                    start, end, min_gap, blocks, min_flowing_fraction)
    return run.flow


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


def flow_changes(runs, level=CONFIDENCE):
    """Rows per (f, D) with f > 0: the relative change of Q from f = 0,
    Q(f)/Q(0) - 1, paired by seed (the runs of one seed start from the same
    packing, so their difference is freer of the packing's own noise than
    the difference of the means). The mean over the seeds that have both
    runs, its standard error and CI half width as in seed_mean_ci: from the
    spread of the per-seed changes for n >= 2; for one seed from the two
    runs' block standard errors, propagated, with the smaller of their
    degrees of freedom."""
    at_rest = {(r.key[1], r.info["seed"]): r for r in runs
               if r.key[0] == 0.0 and np.isfinite(r.flow.q_mass) and r.flow.q_mass > 0}
    rows = []
    for (f, D), members in group_by_key(runs).items():
        if f == 0.0:
            continue
        changes, ses, dofs = [], [], []
        for run in members:
            rest = at_rest.get((D, run.info["seed"]))
            if rest is None or not np.isfinite(run.flow.q_mass):
                continue
            ratio = run.flow.q_mass / rest.flow.q_mass
            changes.append(ratio - 1.0)
            ses.append(ratio * np.hypot(run.flow.q_mass_se / run.flow.q_mass,
                                        rest.flow.q_mass_se / rest.flow.q_mass))
            dofs.append(min(run.flow.blocks, rest.flow.blocks) - 1)
        if changes:
            mean, se, half = seed_mean_ci(changes, ses, dofs, level)
            rows.append({"f": f, "D": D, "n": len(changes), "change": mean, "change_se": se,
                         "change_ci": half})
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


# ---------------------------------------------------------------- fields

@dataclass
class FieldSettings:
    """Coarse-graining choices for one run (lengths in m, times in s)."""
    kernel: cg.GaussianKernel
    spacing: float
    arc_spacing: float
    orifice_height: float = 0.01
    map_times: tuple = ()
    map_width: float = 1.0
    map_frames: int = 5
    orifice_every: int = 1
    z_max: float = None


def map_windows(start, end, map_times=(), width=1.0, count=4):
    """Time windows (since opening) of the maps: centred on map_times with
    the given width; by default `count` windows centred evenly in the
    stationary interval [start, end], each min(width, (end-start)/count) wide."""
    if len(map_times):
        return [(t - 0.5 * width, t + 0.5 * width) for t in map_times]
    span = (end - start) / count
    width = min(width, span)
    centres = start + span * (np.arange(count) + 0.5)
    return [(c - 0.5 * width, c + 0.5 * width) for c in centres]


def pick_map_frames(frame_tau, windows, per_window):
    """{frame index: window index}: up to per_window frames of each window,
    spread evenly over the frames inside it."""
    picked = {}
    for w, (low, high) in enumerate(windows):
        inside = np.flatnonzero((frame_tau >= low) & (frame_tau <= high))
        if inside.size > per_window:
            inside = inside[np.round(np.linspace(0, inside.size - 1, per_window)).astype(int)]
        picked.update({int(k): w for k in inside})
    return picked


def in_flow(tau, flow):
    """True for times inside the stationary window and outside its gaps."""
    tau = np.asarray(tau, dtype=float)
    keep = (tau >= flow.start) & (tau <= flow.end)
    for gap_start, gap_end in flow.gaps:
        keep &= ~((tau > gap_start) & (tau < gap_end))
    return keep


def orifice_row(derived_means, tau):
    """One line of the orifice time series from cg.orifice_averages."""
    row = {"t": tau, "phi": derived_means["packing_fraction"]}
    row.update(zip(("v_r", "v_theta", "v_z"), derived_means["velocity"]))
    row["p_k"] = derived_means["kinetic_pressure"]
    row["p_c"] = derived_means.get("contact_pressure", np.nan)
    if "orientation" in derived_means:
        row.update(zip(("O_rr", "O_tt", "O_zz"), np.diag(derived_means["orientation"])))
        row["S"] = derived_means["nematic_order"]
        row["S_lab"] = derived_means["nematic_order_lab"]
    return row


def once_each(steps):
    """An iter_dump predicate that is true the first time each of `steps`
    comes: LIGGGHTS may write a frame again at the set-up of the next run
    of a deck's run loop."""
    pending = set(int(s) for s in steps)

    def wanted(step):
        if step in pending:
            pending.remove(step)
            return True
        return False
    return wanted


def frames_with_contacts(run, steps):
    """(step, cg.Particles, cg.Contacts or None) of the frames at `steps`,
    reading dump.cg and, when present, dump.contacts side by side."""
    contacts_path = run.path / "dump.contacts"
    contact_frames = iter_dump(contacts_path, once_each(steps)) if contacts_path.exists() else None
    for step, columns in iter_dump(run.path / "dump.cg", once_each(steps)):
        contacts = None
        if contact_frames is not None:
            contact_step, contact_columns = next(contact_frames, (None, None))
            if contact_step != step:
                raise ValueError(f"{contacts_path}: no frame of step {step} in step with dump.cg")
            contacts = frame_contacts(contact_columns)
        yield step, frame_particles(columns), contacts


def map_grid(run, settings, z_max):
    """Cells of `settings.spacing` from the axis to the side wall and from
    the bottom to z_max."""
    radius = 0.5 * run.info["Dc"]
    n_r = int(np.ceil(radius / settings.spacing))
    n_z = int(np.ceil(z_max / settings.spacing))
    return cg.CylindricalGrid(np.linspace(0, radius, n_r + 1), np.linspace(0, z_max, n_z + 1),
                              settings.arc_spacing)


def analyse_fields(run, settings):
    """Scans the dumps once: coarse-grains the picked frames of each map
    window on the (r, z) grid and every orifice_every-th frame of the
    flowing stationary interval on the orifice cylinder. Returns (grid,
    windows, frames per window, derived map fields per window (None for an
    empty window), orifice rows)."""
    steps = dump_steps(run.path / "dump.cg")
    frame_tau = time_since_opening(steps, run.discharge, run.info)
    flowing = set(np.flatnonzero(in_flow(frame_tau, run.flow))[::settings.orifice_every].tolist())
    windows = map_windows(run.flow.start, run.flow.end, settings.map_times, settings.map_width)
    map_frames = pick_map_frames(frame_tau, windows, settings.map_frames)
    z_max = settings.z_max or first_fill_height(run.path / "dump.cg", steps, frame_tau) + settings.kernel.cutoff
    grid = map_grid(run, settings, z_max)
    orifice = cg.orifice_grid(run.info["D"], settings.orifice_height, settings.spacing / 2,
                              settings.arc_spacing)
    wanted = sorted(flowing | set(map_frames))
    progress(f"{run.label}: {len(steps)} frames; {len(flowing)} for the orifice averages, "
             f"{len(map_frames)} for the maps on {grid.shape[0]}x{grid.shape[1]} cells "
             f"({len(grid.points)} azimuthal samples)")
    index_of_step = {int(s): k for k, s in reversed(list(enumerate(steps)))}
    window_frames = [[] for _ in windows]
    rows = []
    for done, (step, particles, contacts) in enumerate(frames_with_contacts(run, steps[wanted])):
        k = index_of_step[step]
        if k in map_frames:
            window_frames[map_frames[k]].append(cg.cylindrical_raw_fields(grid, particles, settings.kernel, contacts))
        if k in flowing:
            raw = cg.cylindrical_raw_fields(orifice, particles, settings.kernel, contacts)
            rows.append(orifice_row(cg.orifice_averages(cg.derived_fields(raw, run.info["rho"]), orifice),
                                    frame_tau[k]))
        if (done + 1) % 50 == 0:
            progress(f"{run.label}: {done + 1}/{len(wanted)} frames coarse-grained")
    maps = [cg.derived_fields(cg.mean_of_raw_fields(frames), run.info["rho"]) if frames else None
            for frames in window_frames]
    return grid, windows, [len(frames) for frames in window_frames], maps, rows


def first_fill_height(cg_path, steps, frame_tau):
    """Highest grain centre of the first frame at or after the opening
    (the settled fill), or of the last frame if none is."""
    after = np.flatnonzero(frame_tau >= 0)
    step = int(steps[after[0]] if after.size else steps[-1])
    _, columns = next(iter_dump(cg_path, lambda s: s == step))
    return float(columns["z"].max())


def orifice_summary(rows, blocks=BLOCKS):
    """Per-run means of the orifice time series and their block standard
    errors (std(ddof=1)/sqrt(B) of B consecutive blocks of frames; nan
    when there are fewer frames than blocks)."""
    summary = {}
    if not rows:
        return summary
    for name in rows[0]:
        if name == "t":
            continue
        series = np.array([row[name] for row in rows], dtype=float)
        se = np.nan
        if series.size >= blocks > 1:
            block_means = [block.mean() for block in np.array_split(series, blocks)]
            se = np.std(block_means, ddof=1) / np.sqrt(blocks)
        summary[name] = (float(series.mean()), float(se))
    return summary


def orifice_groups(runs, summaries, level=CONFIDENCE, blocks=BLOCKS):
    """Rows per (f, D): mean over seeds of each orifice quantity with
    its standard error and CI half width (seed_mean_ci)."""
    rows = []
    for (f, D), members in group_by_key([r for r in runs if summaries.get(r.label)]).items():
        names = summaries[members[0].label].keys()
        row = {"f": f, "D": D, "n": len(members)}
        for name in names:
            means = [summaries[r.label][name][0] for r in members]
            ses = [summaries[r.label][name][1] for r in members]
            row[name] = seed_mean_ci(means, ses, [blocks - 1] * len(members), level)
        rows.append(row)
    return rows


# ---------------------------------------------------------------- tables

def _number(value, digits):
    """Whole numbers (seeds, counts) in full, others to `digits` digits."""
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return f"{value:.{digits}g}"


def write_table(path_stem, header, rows, title):
    """rows (lists of numbers) as `<stem>.txt` (a '#' header naming the
    columns, for lammps_io.read_table) and `<stem>.md`."""
    text = "# " + " ".join(header) + "\n" + "".join(
        " ".join(_number(v, 8) for v in row) + "\n" for row in rows)
    Path(f"{path_stem}.txt").write_text(text)
    lines = [title, "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_number(v, 6) for v in row) + " |" for row in rows]
    Path(f"{path_stem}.md").write_text("\n".join(lines) + "\n")


def write_flow_tables(out, runs, groups, changes, fits, d):
    header = ["f", "D", "seed", "reinject", "Q_kg_s", "Q_kg_s_se", "Q_grains_s", "Q_grains_s_se",
              "blocks", "t_start", "t_end", "T_eff", "removed", "gaps", "clogged_at_end", "stationary"]
    rows = [[r.info["f"], r.info["D"], r.info["seed"], r.info["reinject"], r.flow.q_mass, r.flow.q_mass_se,
             r.flow.q_grains, r.flow.q_grains_se, r.flow.blocks, r.flow.start, r.flow.end,
             r.flow.effective_duration, r.flow.removed, len(r.flow.gaps), int(r.flow.clogged_at_end),
             int(r.flow.stationary)]
            for r in runs]
    write_table(out / "flow_rate_runs", header, rows,
                "Stationary flow rate per run (SI units; se = block standard error; times since opening). "
                "Runs: " + ", ".join(f"{r.label} = {r.path}" for r in runs))
    header = ["f", "D", "n", "Q_kg_s", "Q_kg_s_se", "Q_kg_s_ci95", "Q_grains_s", "Q_grains_s_se",
              "Q_grains_s_ci95", "n_no_flow"]
    rows = [[g["f"], g["D"], g["n"], g["Q"], g["Q_se"], g["Q_ci"], g["Qn"], g["Qn_se"], g["Qn_ci"],
             g["n_no_flow"]] for g in groups]
    write_table(out / "flow_rate", header, rows,
                "Q(f, D): mean over the n seeds with a stationary flow, standard error and 95 % CI half "
                "width (Student t; for a single seed from its block standard error); n_no_flow runs "
                "had no stationary flow (they flowed for less than the set fraction of the window)")
    header = ["f", "D", "n", "change", "change_se", "change_ci95"]
    rows = [[c["f"], c["D"], c["n"], c["change"], c["change_se"], c["change_ci"]] for c in changes]
    write_table(out / "flow_rate_change", header, rows,
                "Relative change of Q from f = 0, Q(f)/Q(0) - 1, paired by seed: mean over the n seeds "
                "with both runs, standard error and 95 % CI half width (Student t; for a single seed "
                "from the two runs' block standard errors)")
    header = ["f", "C", "C_se", "k", "k_se", "beverloo_dof", "beverloo_chi2_dof",
              "A", "A_se", "kappa", "kappa_se", "exp_dof", "exp_chi2_dof"]
    rows = [[f, b["C"], b["C_se"], b["k"], b["k_se"], b["dof"], b["chi2_dof"],
             e["A"], e["A_se"], e["kappa"], e["kappa_se"], e["dof"], e["chi2_dof"]]
            for f, fit in fits.items() for b, e in [(fit["beverloo"], fit["exponential"])]]
    write_table(out / "flow_rate_fits", header, rows,
                f"Fits per f of Q(D) in kg/s, D in m (d = {d:g} m): Q = C (D - k d)^(5/2) and "
                "Q = A exp(kappa D) (kappa in 1/m; the paper's 0.084 /mm is 84 /m); "
                "sigma = standard error over seeds, parameter errors are standard errors")


ORIFICE_NAMES = ("phi", "v_r", "v_theta", "v_z", "p_k", "p_c", "O_rr", "O_tt", "O_zz", "S", "S_lab")


def write_orifice_tables(out, runs, summaries, groups):
    names = [n for n in ORIFICE_NAMES if any(n in s for s in summaries.values())]
    header = ["f", "D", "seed"] + [x for n in names for x in (n, f"{n}_se")]
    rows = [[r.info["f"], r.info["D"], r.info["seed"]] +
            [x for n in names for x in summaries[r.label][n]] for r in runs if summaries.get(r.label)]
    write_table(out / "orifice_runs", header, rows,
                "Orifice-region averages <X> = int X phi dV / int phi dV per run, time-averaged over "
                "the flowing stationary interval (se from block averages); p in Pa, v in m/s")
    header = ["f", "D", "n"] + [x for n in names for x in (n, f"{n}_se", f"{n}_ci95")]
    rows = [[g["f"], g["D"], g["n"]] + [x for n in names for x in g[n]] for g in groups]
    write_table(out / "orifice", header, rows,
                "Orifice-region averages per (f, D): mean over seeds, standard error, 95 % CI half width")


# ---------------------------------------------------------------- plots

def _figure(ncols=1, nrows=1, size=(5, 4)):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(nrows, ncols, figsize=(size[0] * ncols, size[1] * nrows), squeeze=False,
                             layout="constrained")
    return fig, axes


def _save(fig, path):
    import matplotlib.pyplot as plt
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def plot_discharge(path, run, rate_window):
    fig, axes = _figure(1, 2, (7, 3))
    mass = run.discharge["mass_out"]
    axes[0, 0].plot(run.tau, mass)
    axes[0, 0].set_ylabel("discharged mass (kg)")
    axes[1, 0].plot(run.tau, smoothed_rate(run.tau, mass, rate_window))
    axes[1, 0].axhline(run.flow.q_mass, ls="--", color="k", label=f"stationary Q = {run.flow.q_mass:.4g} kg/s")
    axes[1, 0].set_ylabel(f"Q over {rate_window:g} s (kg/s)")
    axes[1, 0].set_xlabel("time since opening (s)")
    axes[1, 0].legend()
    for ax in axes[:, 0]:
        ax.axvspan(run.tau[0], run.flow.start, color="0.85")
        ax.axvspan(run.flow.end, run.tau[-1], color="0.85")
        for gap in run.flow.gaps:
            ax.axvspan(*gap, color="tab:red", alpha=0.2)
    axes[0, 0].set_title(f"{run.label}: grey excluded, red no-flow > gap")
    return _save(fig, path)


# Fig. 2's panels: (a) spheres, (b)-(d) rods of L/d = 2.5, 3.3, 4.0
FIG2_ROD_PANELS = {2.5: "b", 3.3: "c", 4.0: "d"}


def fig2_panel(info):
    """The grains of a run (its run.txt) and the panel of the paper's Fig. 2
    that shows them: 'spheres (Fig. 2a)', 'rods L/d 3.3 (Fig. 2c)', for
    glued spheres (`shape clump`) the panel of the rods they stand in for;
    an aspect ratio the paper did not simulate has no panel."""
    shape = info.get("shape", "sphere")
    if shape == "sphere":
        return "spheres (Fig. 2a)"
    aspect = float(info["aspect"])
    panel = next((p for a, p in FIG2_ROD_PANELS.items() if abs(aspect - a) < 1e-9), None)
    if shape == "clump":
        grains, reference = f"glued-sphere rods L/d {aspect:g}", "peer of Fig. 2"
    else:
        grains, reference = f"rods L/d {aspect:g}", "Fig. 2"
    return f"{grains} ({reference}{panel})" if panel else f"{grains} (not in Fig. 2)"


def plot_q_vs_f(path, groups, grains):
    fig, axes = _figure()
    ax = axes[0, 0]
    for D in sorted({g["D"] for g in groups}):
        rows = [g for g in groups if g["D"] == D]
        ax.errorbar([g["f"] for g in rows], [g["Q"] for g in rows], yerr=_error_bars([g["Q_ci"] for g in rows]),
                    fmt="o-", capsize=3, label=f"D = {D * 1e3:g} mm")
    ax.set_xlabel("f (Hz)")
    ax.set_ylabel("Q (kg/s)")
    ax.set_title(f"Q(f), {grains}, 95 % CI")
    ax.legend()
    return _save(fig, path)


def plot_q_vs_D(path, groups, fits, d, log_q_axis_only):
    """Q(D) per f: log-log with a D^(5/2) line and the Beverloo fits
    (Fig. 4), or semilog with the exponential fits (Fig. 5)."""
    fig, axes = _figure()
    ax = axes[0, 0]
    D_all = np.array([g["D"] for g in groups if g["Q"] > 0])
    if not D_all.size:
        # nothing to put on a log scale (e.g. a short run before the first
        # grain left); matplotlib would stop at saving
        ax.text(0.5, 0.5, "no run with Q > 0", ha="center", transform=ax.transAxes)
        ax.set_xlabel("D (m)")
        ax.set_ylabel("Q (kg/s)")
        return _save(fig, path)
    curve = np.linspace(D_all.min(), D_all.max(), 100)
    for f in sorted({g["f"] for g in groups}):
        rows = sorted((g for g in groups if g["f"] == f and g["Q"] > 0), key=lambda g: g["D"])
        line = ax.errorbar([g["D"] for g in rows], [g["Q"] for g in rows], yerr=_error_bars([g["Q_ci"] for g in rows]),
                           fmt="o", capsize=3, label=f"f = {f:g} Hz")
        if f in fits:
            model = (exponential(curve, fits[f]["exponential"]["A"], fits[f]["exponential"]["kappa"])
                     if log_q_axis_only else
                     beverloo(curve, fits[f]["beverloo"]["C"], fits[f]["beverloo"]["k"], d))
            ax.plot(curve, model, "-", color=line[0].get_color())
    ax.set_yscale("log")
    if not log_q_axis_only:
        ax.set_xscale("log")
        q_all = np.array([g["Q"] for g in groups if g["Q"] > 0])
        scale = np.exp(np.mean(np.log(q_all) - 2.5 * np.log(D_all)))
        ax.plot(curve, scale * curve ** 2.5, "k--", label="D^(5/2)")
    ax.set_xlabel("D (m)")
    ax.set_ylabel("Q (kg/s)")
    ax.set_title("Q(D), exponential fits (Fig. 5)" if log_q_axis_only else "Q(D), Beverloo fits (Fig. 4)")
    ax.legend(fontsize="small")
    return _save(fig, path)


def _map_panels(path, grid, windows, maps, title, values_of, streamlines=False, cmap="viridis"):
    """One colour map per time window (r horizontal, z vertical)."""
    shown = [(w, m) for w, m in zip(windows, maps) if m is not None]
    if not shown:
        return None
    aspect = grid.z_edges[-1] / grid.r_edges[-1]
    fig, axes = _figure(len(shown), 1, (3.0, 0.5 + 2.0 * aspect))
    for ax, ((low, high), fields) in zip(axes[0], shown):
        values = values_of(fields)
        mesh = ax.pcolormesh(grid.r_edges, grid.z_edges, values.T, cmap=cmap, shading="flat")
        if streamlines:
            empty = fields["packing_fraction"].T < 0.05
            v_r = np.ma.masked_where(empty, fields["velocity"][..., 0].T)
            v_z = np.ma.masked_where(empty, fields["velocity"][..., 2].T)
            ax.streamplot(grid.r, grid.z, v_r.filled(np.nan), v_z.filled(np.nan), color="w",
                          density=0.8, linewidth=0.6)
        ax.set_aspect("equal")
        ax.set_title(f"{0.5 * (low + high):.3g} s", fontsize="small")
        ax.set_xlabel("r (m)")
        fig.colorbar(mesh, ax=ax, shrink=0.6, format="%.3g")
    axes[0, 0].set_ylabel("z (m)")
    fig.suptitle(title, fontsize="small")
    return _save(fig, path)


def plot_maps(directory, grid, windows, maps):
    """The colour maps of one run; returns the files written."""
    speed = lambda m: np.hypot(m["velocity"][..., 0], m["velocity"][..., 2])
    specs = [("map_phi.png", "packing fraction (Fig. 6)", lambda m: m["packing_fraction"], False),
             ("map_speed.png", "in-plane speed (v_r^2+v_z^2)^1/2 (m/s), streamlines (Fig. 7)", speed, True),
             ("map_vtheta.png", "v_theta (m/s)", lambda m: m["velocity"][..., 1], False),
             ("map_pk.png", "kinetic pressure tr(sigma_k)/3 (Pa)", lambda m: m["kinetic_pressure"], False)]
    present = next(m for m in maps if m is not None)
    if "contact_pressure" in present:
        specs.append(("map_pc.png", "contact pressure tr(sigma_c)/3 (Pa)", lambda m: m["contact_pressure"], False))
    if "orientation" in present:
        specs.append(("map_Ozz.png", "O_zz", lambda m: m["orientation"][..., 2, 2], False))
        specs.append(("map_S.png", "nematic order S", lambda m: m["nematic_order"], False))
    return [_map_panels(directory / name, grid, windows, maps, title, values_of, stream)
            for name, title, values_of, stream in specs]


def _error_bars(values):
    """yerr for errorbar: None when no value is finite (one run: no spread
    over seeds), where matplotlib 3.6 stops with StopIteration."""
    values = np.asarray(values, dtype=float)
    return values if np.isfinite(values).any() else None


def plot_orifice_vs_f(path, groups, names, labels):
    fig, axes = _figure(len(names), 1, (3.5, 3))
    for ax, name, label in zip(axes[0], names, labels):
        sign = -1.0 if name == "v_z" else 1.0
        for D in sorted({g["D"] for g in groups}):
            rows = [g for g in groups if g["D"] == D]
            ax.errorbar([g["f"] for g in rows], [sign * g[name][0] for g in rows],
                        yerr=_error_bars([g[name][2] for g in rows]), fmt="o-", capsize=3, label=f"D = {D * 1e3:g} mm")
        ax.set_xlabel("f (Hz)")
        ax.set_ylabel(label)
    axes[0, 0].legend(fontsize="small")
    return _save(fig, path)


# ---------------------------------------------------------------- CLI

def parse_args(argv):
    parser = argparse.ArgumentParser(prog="python3 -m analysis.silo3d_rotating", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dirs", nargs="+", type=Path, help="run directories (run.txt, discharge.txt, ...)")
    parser.add_argument("--out", type=Path, required=True, help="output directory")
    parser.add_argument("--include-unfinished", action="store_true",
                        help="also analyse runs whose run.txt has no 'finished' line (left out by default)")
    flow = parser.add_argument_group("flow rate")
    flow.add_argument("--transient", type=float, default=TRANSIENT,
                      help="start transient left out after the opening (s, default %(default)s)")
    flow.add_argument("--gap", type=float, default=MIN_GAP,
                      help="no-flow intervals longer than this are cut from the time base (s, default %(default)s)")
    flow.add_argument("--min-flowing-fraction", type=float, default=MIN_FLOWING_FRACTION,
                      help="a run that flowed (no-flow intervals cut) for less than this fraction of its "
                           "window has no stationary flow and no Q (default %(default)s)")
    flow.add_argument("--end-fraction", type=float, default=END_FRACTION,
                      help="without reinjection, stop when this fraction of the grains' mass is out "
                           "(default %(default)s)")
    flow.add_argument("--blocks", type=int, default=BLOCKS, help="blocks for standard errors (default %(default)s)")
    flow.add_argument("--rate-window", type=float, default=0.5, help="smoothing of the Q(t) plot (s)")
    fields = parser.add_argument_group("coarse-grained fields (need dump.cg; dump.contacts optional)")
    fields.add_argument("--no-fields", action="store_true", help="flow rate only")
    fields.add_argument("--width", type=float, help="kernel width w (m); default d*/2 from m/rho")
    fields.add_argument("--cutoff", type=float, default=cg.CUTOFF_IN_WIDTHS, help="cutoff in widths (default 4)")
    fields.add_argument("--spacing", type=float, help="(r, z) cell size of the maps (m); default w "
                                                      "(the orifice cylinder uses half of it)")
    fields.add_argument("--arc-spacing", type=float, help="azimuthal sample spacing (m); default w")
    fields.add_argument("--orifice-height", type=float, default=0.01, help="orifice cylinder height (m)")
    fields.add_argument("--map-times", type=float, nargs="*", default=(),
                        help="centres of the map windows (s since opening); default 4 spread over the "
                             "stationary interval")
    fields.add_argument("--map-width", type=float, default=1.0, help="map window width (s)")
    fields.add_argument("--map-frames", type=int, default=5, help="frames coarse-grained per map window")
    fields.add_argument("--orifice-every", type=int, default=1, help="use every n-th frame for orifice averages")
    fields.add_argument("--zmax", type=float, help="top of the map grid (m); default fill height + r_c")
    return parser.parse_args(argv)


def field_settings(args, run, first_masses):
    """The CLI's choices; the kernel width defaults to d*/2 of the dumped grains."""
    width = args.width or cg.default_kernel(first_masses, run.info["rho"]).width
    kernel = cg.GaussianKernel(width, args.cutoff)
    return FieldSettings(kernel, args.spacing or kernel.width, args.arc_spacing or kernel.width,
                         args.orifice_height, tuple(args.map_times), args.map_width, args.map_frames,
                         args.orifice_every, args.zmax)


def run_fields(args, run, directory):
    """Maps and orifice series of one run; returns its orifice summary."""
    cg_path = run.path / "dump.cg"
    if not run.flow.effective_duration > 0:
        progress(f"{run.label}: no stationary interval, no fields")
        return {}
    _, first = next(iter_dump(cg_path))
    settings = field_settings(args, run, first["mass"])
    progress(f"{run.label}: kernel w = {settings.kernel.width:.4g} m, r_c = {settings.kernel.cutoff:.4g} m, "
             f"cells {settings.spacing:.4g} m" + ("" if (run.path / "dump.contacts").exists()
                                                  else "; no dump.contacts: no contact stress"))
    grid, windows, counts, maps, rows = analyse_fields(run, settings)
    if any(m is not None for m in maps):
        np.savez_compressed(directory / "fields.npz", r=grid.r, z=grid.z, r_edges=grid.r_edges,
                            z_edges=grid.z_edges, windows=np.array(windows), frames=np.array(counts),
                            **{f"{name}_{w}": values for w, m in enumerate(maps) if m is not None
                               for name, values in m.items()})
        plot_maps(directory, grid, windows, maps)
    if rows:
        names = list(rows[0])
        write_table(directory / "orifice_timeseries", names, [[row[n] for n in names] for row in rows],
                    f"{run.label}: orifice-region averages per frame")
    return orifice_summary(rows, args.blocks)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    args.out.mkdir(parents=True, exist_ok=True)
    runs = [load_run(path) for path in args.run_dirs]
    unfinished = [run for run in runs if not run.finished]
    for run in unfinished:
        progress(f"{run.path}: unfinished (run.txt has no 'finished' line: the deck stopped or is "
                 f"still running), {'kept' if args.include_unfinished else 'left out'}")
    if not args.include_unfinished:
        runs = [run for run in runs if run.finished]
    if not runs:
        progress("no finished run to analyse (--include-unfinished analyses the others)")
        return 1
    for run, label in zip(runs, run_labels(runs)):
        run.label = label
        flow = analyse_flow(run, args.transient, args.gap, args.end_fraction, args.blocks,
                            args.min_flowing_fraction)
        if flow.stationary:
            progress(f"{label}: Q = {flow.q_mass:.5g} +- {flow.q_mass_se:.2g} kg/s = {flow.q_grains:.5g} "
                     f"+- {flow.q_grains_se:.2g} grains/s over {flow.effective_duration:.3g} s "
                     f"({len(flow.gaps)} no-flow intervals, {flow.removed:.3g} s removed)")
        else:
            progress(f"{label}: no stationary flow: it flowed for {flow.effective_duration:.3g} s of the "
                     f"{flow.end - flow.start:.3g} s window ({len(flow.gaps)} no-flow intervals); no Q")
        directory = args.out / "runs" / label
        directory.mkdir(parents=True, exist_ok=True)
        plot_discharge(directory / "discharge.png", run, args.rate_window)
    groups = flow_groups(runs)
    d = runs[0].info["d"]
    fits = flow_fits(groups, d)
    changes = flow_changes(runs)
    write_flow_tables(args.out, runs, groups, changes, fits, d)
    for c in changes:
        progress(f"f = {c['f']:g} Hz, D = {c['D'] * 1e3:g} mm: Q changes by {100 * c['change']:+.1f} "
                 f"+- {100 * c['change_ci']:.1f} % (95 %) from f = 0 over {c['n']} seed(s)")
    for f, fit in fits.items():
        b, e = fit["beverloo"], fit["exponential"]
        progress(f"f = {f:g} Hz: Beverloo C = {b['C']:.4g} +- {b['C_se']:.2g}, k = {b['k']:.3g} +- "
                 f"{b['k_se']:.2g}; exponential kappa = {e['kappa'] * 1e-3:.4g} +- {e['kappa_se'] * 1e-3:.2g} /mm")
    if groups:
        plot_q_vs_f(args.out / "Q_vs_f.png", groups, fig2_panel(runs[0].info))
        plot_q_vs_D(args.out / "Q_vs_D_loglog.png", groups, fits, d, log_q_axis_only=False)
        plot_q_vs_D(args.out / "Q_vs_D_semilog.png", groups, fits, d, log_q_axis_only=True)
    progress(f"flow-rate tables and plots in {args.out}")
    if args.no_fields:
        return 0
    summaries = {}
    for run in runs:
        if not (run.path / "dump.cg").exists():
            progress(f"{run.label}: no dump.cg, no fields")
            continue
        summaries[run.label] = run_fields(args, run, args.out / "runs" / run.label)
    groups = orifice_groups(runs, summaries, blocks=args.blocks)
    if groups:
        write_orifice_tables(args.out, runs, summaries, groups)
        plot_orifice_vs_f(args.out / "orifice_vs_f.png", groups, ("phi", "v_z", "p_k"),
                          ("<phi>", "-<v_z> (m/s)", "<p_k> = <tr sigma_k>/3 (Pa)"))
        if "S" in groups[0]:
            plot_orifice_vs_f(args.out / "orientation_vs_f.png", groups, ("O_zz", "O_rr", "O_tt", "S", "S_lab"),
                              ("<O_zz>", "<O_rr>", "<O_tt>", "<S> (cylindrical average)",
                               "<S_lab> (Cartesian average)"))
    progress(f"done; outputs in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
