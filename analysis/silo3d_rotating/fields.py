"""Coarse-grained fields of the rotating-bottom silo (Pongó, Börzsönyi and
Hidalgo 2022, sec. II-III): packing fraction, velocity, kinetic and contact
pressure and orientation on an (r, z) grid in time windows (the maps), and
averaged over the orifice cylinder frame by frame in the flowing
stationary window (the orifice averages), per run and over seeds.

Frames come from analysis.silo3d_rotating.records (record format:
doc/silo3d_rotating_records.md); the coarse graining is
analysis.common.coarse_grain (doc/coarse_graining.md).
"""

from dataclasses import dataclass

import numpy as np

from analysis.common import coarse_grain as cg
from analysis.common.lammps_io import dump_steps, iter_dump
from analysis.silo3d_rotating.flow import BLOCKS, CONFIDENCE, group_by_key, progress, seed_mean_ci
from analysis.silo3d_rotating.records import DUMP_CUT, frames_with_contacts, read_dump_cut, time_since_opening


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
    flowing = np.flatnonzero(in_flow(frame_tau, run.flow))[::settings.orifice_every]
    windows = map_windows(run.flow.start, run.flow.end, settings.map_times, settings.map_width)
    # a cut frame (an archive's, a carried run's before its checkpoint)
    # lacks the grains outside the kept cylinders: the maps take whole
    # frames only, the orifice averages the cut ones too if the cylinders
    # hold the orifice cylinder with the kernel's reach
    cut = read_dump_cut(run.path)
    whole = steps >= cut.whole_from
    if not whole.all():
        reach = (0.5 * run.info["D"] + settings.kernel.cutoff, settings.orifice_height + settings.kernel.cutoff)
        orifice_whole = cut.holds(*reach)
        if not orifice_whole:
            flowing = flowing[whole[flowing]]
        progress(f"{run.label}: dump.cg holds only the grains of the cylinders " +
                 ", ".join(f"r < {r:g} m, z < {z:g} m" for r, z in cut.cylinders) +
                 (f" before step {cut.whole_from}" if whole.any() else " in every frame") + f" ({DUMP_CUT}): "
                 "maps from the whole frames only; orifice averages from " +
                 ("every frame" if orifice_whole else f"the whole frames only (they read r < {reach[0]:.3g} m, "
                  f"z < {reach[1]:.3g} m)"))
    flowing = set(flowing.tolist())
    map_frames = pick_map_frames(np.where(whole, frame_tau, np.nan), windows, settings.map_frames)
    fill_height = cut.fill_height
    if fill_height is None:
        fill_height = first_fill_height(run.path / "dump.cg", steps, frame_tau)
    z_max = settings.z_max or fill_height + settings.kernel.cutoff
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
    for done, (step, particles, contacts) in enumerate(frames_with_contacts(run, steps[wanted], cut.whole_from)):
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


def block_standard_error(series, blocks=BLOCKS):
    """std(ddof=1)/sqrt(B) of the means of B consecutive blocks of a
    series of frames; nan when there are fewer frames than blocks."""
    if not series.size >= blocks > 1:
        return np.nan
    block_means = [block.mean() for block in np.array_split(series, blocks)]
    return np.std(block_means, ddof=1) / np.sqrt(blocks)


def orifice_summary(rows, blocks=BLOCKS):
    """Per-run means of the orifice time series and their block standard
    errors (block_standard_error)."""
    summary = {}
    if not rows:
        return summary
    for name in rows[0]:
        if name == "t":
            continue
        series = np.array([row[name] for row in rows], dtype=float)
        summary[name] = (float(series.mean()), float(block_standard_error(series, blocks)))
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
