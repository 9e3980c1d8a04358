"""Vertical acceleration along the axis of the rotating-bottom silo
(Pongó, Börzsönyi and Hidalgo 2022, Fig. 10): the paper's
a_eff(z) = < Δv_z / Δt_p >, the change of each grain's vertical velocity
between two consecutive dump frames (Δt_p = 50 ms in the paper, the
deck's dump_every_time 0.05), averaged over the grains in a cylinder of
diameter 3 cm about the axis (D/2 at D = 60 mm) in bins of height z, and
over the frames of a stationary window. Where a_eff differs from zero the
grains accelerate: the paper reads from it that rotation of the bottom
shrinks the "free fall arch" region of rods, and with it the velocity at
the orifice (v_z² at the bottom is the integral of 2 a_eff dz from above,
for a steady flow along the axis).

A grain is placed at the midpoint of its two positions. A grain in only
one of the two frames (it left the box) is left out, and so is one that
moved where its two velocities do not take it (|Δz − ½(v_z + v_z')Δt_p|
above `jump`, 5 cm): fix reinject took it from below the orifice to the
top of the column, or it landed there from its re-entry within the
interval (a change of velocity of 2 m/s or more within 50 ms). A grain
flowing in the column changes its velocity far less and stays in.
Grains near the orifice that leave within Δt_p are in one frame only:
the lowest bins hold the grains that stayed, as in the paper's records.

    python3 -m analysis.silo3d_rotating.acceleration RUN_DIR:T_FROM:T_TO ... --out DIR

T_FROM, T_TO: the window in s since the opening (both frames of a pair
within it). Writes DIR/axial_acceleration.{md,txt} (a profile per run),
DIR/axial_acceleration_summary.{md,txt} (per run: the area under a_eff,
the exit speed it gives and the one measured) and
DIR/axial_acceleration.png. Records: doc/silo3d_rotating_records.md.
"""

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analysis.common.lammps_io import dump_steps, iter_dump
from analysis.silo3d_rotating.flow import BLOCKS, progress
from analysis.silo3d_rotating.records import load_run, once_each, time_since_opening
from analysis.silo3d_rotating.analyse import _figure, _save, write_table
from analysis.common.cli import command_line

AXIS_DIAMETER = 0.03      # m: the paper's cylinder (Fig. 10's caption; D/2 at D = 60 mm)
JUMP = 0.05               # m: a displacement this far from its velocities' is not a free motion
Z_MAX_IN_D = 3.0          # the profile from the plate to 3 D
BINS_PER_D = 10


@dataclass
class AxialProfile:
    """a_eff(z) and <v_z>(z) in the bins z_edges, with block standard errors."""
    z_edges: np.ndarray
    acceleration: np.ndarray       # m/s^2, per bin
    acceleration_se: np.ndarray
    velocity: np.ndarray           # m/s, the grains' mean v_z over the pair, per bin
    velocity_se: np.ndarray
    counts: np.ndarray             # grain-pairs per bin
    pairs: int                     # frame pairs
    interval: float                # their spacing Δt_p (s)
    left_out: int                  # grain pairs in the cylinder left out (moved by the deck or an impact)
    blocks: int
    area: float                    # integral of a_eff dz between the first and last bin centres (m^2/s^2)
    area_se: float

    @property
    def z(self):
        return _centres(self.z_edges)

    @property
    def exit_speed_from_area(self):
        """|v_z| at the first bin's centre from that at the last and the
        area: v² = v_top² − 2 ∫ a_eff dz (steady flow along the axis,
        the fluctuations' part left out)."""
        return float(np.sqrt(self.velocity[-1] ** 2 - 2 * self.area))


def profile_edges(D, z_min=0.0, z_max=Z_MAX_IN_D, bins_per_D=BINS_PER_D):
    """Bin edges from z_min D to z_max D, bins_per_D bins per D."""
    return np.linspace(z_min * D, z_max * D, int(round((z_max - z_min) * bins_per_D)) + 1)


def _centres(edges):
    return 0.5 * (edges[1:] + edges[:-1])


def grain_accelerations(a, b, interval, jump=JUMP, place="midpoint"):
    """(r, z, v_z, a_z, moved) of the grains in both frames a and b
    (iter_dump columns), at the midpoint of their two positions (or, with
    place="first", at the first; the paper does not say which): a_z =
    Δv_z/interval, v_z their mean; `moved` is true for those to be left
    out, whose displacement is more than `jump` from the one their
    velocities give (the deck moved them, or an impact stopped them)."""
    _, ia, ib = np.intersect1d(a["id"], b["id"], assume_unique=True, return_indices=True)
    za, zb = a["z"][ia], b["z"][ib]
    vza, vzb = a["vz"][ia], b["vz"][ib]
    moved = np.abs(zb - za - 0.5 * (vza + vzb) * interval) > jump
    weight = {"midpoint": 0.5, "first": 0.0}[place]      # of the second position
    x = (1 - weight) * a["x"][ia] + weight * b["x"][ib]
    y = (1 - weight) * a["y"][ia] + weight * b["y"][ib]
    z = (1 - weight) * za + weight * zb
    return np.hypot(x, y), z, 0.5 * (vza + vzb), (vzb - vza) / interval, moved


def frame_spacing(tau):
    """The frames' spacing at the times tau (their median step; NaN for
    fewer than two frames)."""
    return float(np.median(np.diff(tau))) if np.size(tau) > 1 else np.nan


def in_window(tau, t_from, t_to):
    """Which of the frames at the times tau lie within [t_from, t_to]. The
    deck's frames are round(T/dt) steps apart, not exactly T: a frame
    within 1 % of their spacing of an end is in."""
    tau = np.asarray(tau, dtype=float)
    spacing = frame_spacing(tau)
    slack = 0.01 * spacing if np.isfinite(spacing) else 0.0
    return (tau >= t_from - slack) & (tau <= t_to + slack)


def window_frames(run, t_from, t_to):
    """Steps and times since the opening of run's dump.cg frames within
    [t_from, t_to] (in_window), each step once (a frame may be written
    twice)."""
    steps = np.unique(dump_steps(run.path / "dump.cg"))
    tau = time_since_opening(steps, run.discharge, run.info)
    inside = in_window(tau, t_from, t_to)
    return steps[inside], tau[inside]


def _block_mean_se(sums, counts):
    """Mean over all blocks (per bin: sums over counts) and the standard
    error of the block means; NaN where fewer than two blocks have data."""
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = sums.sum(axis=0) / counts.sum(axis=0)
        block_means = np.where(counts > 0, sums / counts, np.nan)
    n = np.count_nonzero(counts > 0, axis=0)
    se = np.full(n.shape, np.nan)
    several = n >= 2
    se[several] = np.nanstd(block_means[:, several], axis=0, ddof=1) / np.sqrt(n[several])
    return mean, se


def _integral(values, z):
    """Trapezoidal integral over z along the last axis (NaN where a bin has no data)."""
    return np.sum(0.5 * (values[..., 1:] + values[..., :-1]) * np.diff(z), axis=-1)


def axial_profile(run, t_from, t_to, radius=AXIS_DIAMETER / 2, z_edges=None, blocks=BLOCKS, jump=JUMP,
                  place="midpoint"):
    """AxialProfile of `run` (analysis.silo3d_rotating.records.Run) over the window;
    z_edges default to profile_edges(D): BINS_PER_D bins per D from the
    plate to Z_MAX_IN_D D.
    The frame pairs are split into `blocks` runs of consecutive pairs for
    the standard errors."""
    if z_edges is None:
        z_edges = profile_edges(run.info["D"])
    steps, tau = window_frames(run, t_from, t_to)
    if steps.size < 2:
        raise ValueError(f"{run.path}: {steps.size} dump frame(s) in {t_from:g}-{t_to:g} s since the "
                         f"opening; a profile needs two or more")
    intervals = np.diff(steps) * run.info["dt"]
    if np.ptp(intervals) > 1e-6 * intervals.max():
        raise ValueError(f"{run.path}: dump frames in {t_from:g}-{t_to:g} s are not evenly spaced "
                         f"({intervals.min():.6g}-{intervals.max():.6g} s): a frame is missing")
    interval = float(intervals.mean())
    n_pairs = steps.size - 1
    blocks = max(1, min(blocks, n_pairs))
    block_of_pair = np.repeat(np.arange(blocks), [len(c) for c in np.array_split(np.arange(n_pairs), blocks)])
    n_bins = len(z_edges) - 1
    a_sum, v_sum, count = (np.zeros((blocks, n_bins)) for _ in range(3))
    left_out, previous = 0, None
    for k, (step, columns) in enumerate(iter_dump(run.path / "dump.cg", once_each(steps))):
        if previous is not None:
            r, z, vz, az, moved = grain_accelerations(previous, columns, interval, jump, place)
            inside = (r < radius) & (z >= z_edges[0]) & (z < z_edges[-1])
            left_out += int(np.count_nonzero(inside & moved))
            inside &= ~moved
            bins = np.searchsorted(z_edges, z[inside], side="right") - 1
            block = block_of_pair[k - 1]
            a_sum[block] += np.bincount(bins, az[inside], n_bins)
            v_sum[block] += np.bincount(bins, vz[inside], n_bins)
            count[block] += np.bincount(bins, minlength=n_bins)
        if k % 20 == 0:
            progress(f"{run.path}: axial acceleration, frame {k + 1}/{steps.size}")
        previous = columns
    acceleration, acceleration_se = _block_mean_se(a_sum, count)
    velocity, velocity_se = _block_mean_se(v_sum, count)
    centres = _centres(z_edges)
    with np.errstate(invalid="ignore", divide="ignore"):
        block_areas = _integral(a_sum / count, centres)
    good = np.isfinite(block_areas)
    area_se = float(np.std(block_areas[good], ddof=1) / np.sqrt(good.sum())) if good.sum() >= 2 else np.nan
    return AxialProfile(np.asarray(z_edges, float), acceleration, acceleration_se, velocity, velocity_se,
                        count.sum(axis=0), n_pairs, interval, left_out, blocks,
                        float(_integral(acceleration, centres)), area_se)


# ---------------------------------------------------------------- CLI

def parse_run(text):
    """RUN_DIR:T_FROM:T_TO -> (Path, t_from, t_to)."""
    parts = text.rsplit(":", 2)
    try:
        path, t_from, t_to = Path(parts[0]), float(parts[1]), float(parts[2])
    except (IndexError, ValueError):
        raise argparse.ArgumentTypeError(f"{text!r}: expected RUN_DIR:T_FROM:T_TO (s since the opening)")
    if not t_to > t_from:
        raise argparse.ArgumentTypeError(f"{text!r}: T_TO must be after T_FROM")
    return path, t_from, t_to


def parse_args(argv):
    parser = command_line("analysis.silo3d_rotating.acceleration", __doc__,
                          "/usr/bin/python3 -m analysis.silo3d_rotating.acceleration "
                          "runs/rods_fig2c/D0.06_f0.16_s32452843:4:8 --out runs/rods_fig2c/acceleration "
                          "--z-max-D 3")
    parser.add_argument("runs", nargs="+", type=parse_run, help="RUN_DIR:T_FROM:T_TO")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="the directory the tables and figures go to")
    parser.add_argument("--diameter", type=float, default=AXIS_DIAMETER,
                        help="diameter of the cylinder about the axis (m, default %(default)s)")
    parser.add_argument("--z-min-D", dest="z_min", type=float, default=0.0,
                        help="bottom of the profile in D (default 0, the plate; the area starts there)")
    parser.add_argument("--z-max-D", dest="z_max", type=float, default=Z_MAX_IN_D,
                        help="top of the profile in D (default 3)")
    parser.add_argument("--place", choices=("midpoint", "first"), default="midpoint",
                        help="a grain's position: the midpoint of its two (default) or the first")
    parser.add_argument("--bins-per-D", type=int, default=BINS_PER_D, help="bins per D (default 10)")
    parser.add_argument("--blocks", type=int, default=BLOCKS, help="blocks for standard errors (default 10)")
    parser.add_argument("--jump", type=float, default=JUMP,
                        help="a grain whose displacement is this far from the one its velocities give (moved "
                             "by the deck, or stopped by an impact) is left out (m, default %(default)s)")
    args = parser.parse_args(argv)
    if not (args.diameter > 0 and args.z_max > 0 and args.bins_per_D > 0 and args.blocks > 0 and args.jump > 0):
        parser.error("--diameter, --z-max-D, --bins-per-D, --blocks and --jump must be positive")
    if not 0 <= args.z_min < args.z_max:
        parser.error(f"--z-min-D must be at least 0 and below --z-max-D, not {args.z_min:g}")
    return args


def run_label(run, t_from, t_to):
    shape = run.info.get("shape", "sphere")
    return (f"{shape}s, f = {run.info['f']:g} Hz, D = {run.info['D'] * 1e3:g} mm, seed {run.info['seed']:.0f}, "
            f"{t_from:g}-{t_to:g} s" + ("" if run.info["reinject"] else ", no reinjection"))


def plot_profiles(path, results, g):
    """a_eff/g and <v_z> against z/D, as the paper's Fig. 10: the bottom
    at rest solid, turning dashed."""
    fig, axes = _figure(2)
    for label, run, profile in results:
        D, style = run.info["D"], "-" if run.info["f"] == 0 else "--"
        line = axes[0, 0].errorbar(profile.z / D, profile.acceleration / g, yerr=profile.acceleration_se / g,
                                   fmt=".", ls=style, capsize=2, label=label)
        axes[0, 1].errorbar(profile.z / D, profile.velocity, yerr=profile.velocity_se, fmt=".", ls=style,
                            capsize=2, color=line[0].get_color())
    axes[0, 0].axhline(0.0, color="grey", lw=0.5)
    axes[0, 0].set_ylabel("a_eff / g  (-1: free fall)")
    axes[0, 1].set_ylabel("<v_z> (m/s)")
    for ax in axes[0]:
        ax.set_xlabel("z / D")
    # the velocity panel's lower right is empty: a slow flow high up
    axes[0, 1].legend(*axes[0, 0].get_legend_handles_labels(), fontsize="x-small", loc="lower right")
    return _save(fig, path)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    args.out.mkdir(parents=True, exist_ok=True)
    results = []
    for path, t_from, t_to in args.runs:
        run = load_run(path)
        if not (run.path / "dump.cg").exists():
            progress(f"ERROR: {run.path}: no dump.cg (the deck's dump_every_time)")
            return 2
        edges = profile_edges(run.info["D"], args.z_min, args.z_max, args.bins_per_D)
        try:
            profile = axial_profile(run, t_from, t_to, args.diameter / 2, edges, args.blocks, args.jump,
                                    args.place)
        except ValueError as error:
            progress(f"ERROR: {error}")
            return 2
        label = run_label(run, t_from, t_to)
        progress(f"{label}: {profile.pairs} frame pairs {profile.interval:.4g} s apart, "
                 f"{int(profile.counts.sum())} grain pairs in the cylinder, {profile.left_out} more "
                 f"left out (moved by the deck or an impact); area {profile.area:.4g} +- "
                 f"{profile.area_se:.2g} m^2/s^2, "
                 f"exit speed from it {profile.exit_speed_from_area:.3g} m/s against "
                 f"{-profile.velocity[0]:.3g} m/s measured")
        results.append((label, run, profile))
    rows = [[run.info["f"], run.info["D"], run.info["seed"], t_from, t_to, z, z / run.info["D"],
             a / run.info["g"], a_se / run.info["g"], v, v_se, n]
            for (label, run, p), (_, t_from, t_to) in zip(results, args.runs)
            for z, a, a_se, v, v_se, n in zip(p.z, p.acceleration, p.acceleration_se, p.velocity,
                                              p.velocity_se, p.counts)]
    write_table(args.out / "axial_acceleration", ["f", "D", "seed", "t_from", "t_to", "z", "z_over_D", "a_over_g",
                                                  "a_over_g_se", "v_z", "v_z_se", "grain_pairs"], rows,
                f"a_eff(z) = <dv_z/dt_p> in a cylinder of diameter {args.diameter:g} m about the axis "
                f"(analysis.silo3d_rotating.acceleration); standard errors from {args.blocks} blocks of frame pairs")
    summary = [[run.info["f"], run.info["D"], run.info["seed"], t_from, t_to, p.pairs, p.interval,
                int(p.counts.sum()), p.left_out, p.area, p.area_se, p.exit_speed_from_area, -p.velocity[0],
                p.velocity_se[0]]
               for (label, run, p), (_, t_from, t_to) in zip(results, args.runs)]
    write_table(args.out / "axial_acceleration_summary",
                ["f", "D", "seed", "t_from", "t_to", "frame_pairs", "dt_p", "grain_pairs", "left_out",
                 "area", "area_se", "exit_speed_from_area", "exit_speed", "exit_speed_se"], summary,
                "Area under a_eff(z) from the first to the last bin centre (m^2/s^2), and the |v_z| at "
                "the first bin that it gives with the last bin's (steady flow along the axis) against "
                "the measured one")
    plot_profiles(args.out / "axial_acceleration.png", results, results[0][1].info["g"])
    progress(f"done; outputs in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
