"""What the grains over the orifice do when the flow of the rotating-bottom
silo stalls: are they a plug that the rotation carries round, or sheared?

Per dump frame of a run (dump.cg), the grains over the orifice (centres at
r < D/2 and 0 < z < `height`, default 2 cm: a rod's length above the
plate): how many, the share of them still there one frame later (by id:
a plug stays, a flowing region renews), their mean v_z, and their mean
azimuthal velocity over the bottom's, v_θ/(2π f r); and the same ratio
for the grains lying on the plate around the orifice (a ring r_in < r <
r_out, 0 < z < `plate_height`, default 4–6 cm and 1 cm, inside the
cylinder that the campaign's cut dumps keep). A plug that turns as the
ring does is carried with it; the bottom slides under both.

    python3 -m analysis.silo3d_rotating.orifice_plug RUN_DIR --window T_FROM T_TO ... --out DIR

Writes DIR/orifice_plug.{md,txt} (per frame from the first window's start
to the last one's end) and DIR/orifice_plug_windows.{md,txt} (per window:
means over its frames with block standard errors, std(ddof=1)/sqrt(B) of
the means of B consecutive blocks of frames, and the grains' residence
over the orifice, frame spacing / (1 - stayed)). Successive frames share
most of their grains, so errors over single frames would understate;
blocks longer than the residence are nearly independent. Where a window's
blocks are shorter than the residence (a stall: the plug stays longer
than the window), even the block errors understate, and the analysis says
so. Needs f > 0 (at rest there is no bottom speed to compare with).
"""

import sys
from pathlib import Path

import numpy as np

from analysis.common.lammps_io import iter_dump
from analysis.silo3d_rotating.acceleration import frame_spacing, in_window, window_frames
from analysis.silo3d_rotating.fields import block_standard_error
from analysis.silo3d_rotating.flow import progress
from analysis.silo3d_rotating.records import load_run, once_each
from analysis.silo3d_rotating.analyse import write_table
from analysis.common.cli import command_line

HEIGHT = 0.02           # m: over the orifice, a rod's length above the plate
RING = (0.04, 0.06)     # m: the plate around a 60 mm orifice, inside the cut dumps' r < 6 cm
PLATE_HEIGHT = 0.01     # m: grains lying on the plate
BLOCKS = 4              # blocks per window: of ~0.2 s in the 0.7 s windows of a stall and the flow around it

COLUMNS = ["t", "n_over", "stayed", "vz_over", "turn_over", "n_ring", "turn_ring"]


def azimuthal_velocity(columns):
    """(r, v_θ) of a frame's grains, v_θ positive in the sense of +z."""
    x, y = columns["x"], columns["y"]
    r = np.hypot(x, y)
    with np.errstate(invalid="ignore", divide="ignore"):
        return r, (x * columns["vy"] - y * columns["vx"]) / r


def frame_row(columns, before_ids, D, f, height=HEIGHT, ring=RING, plate_height=PLATE_HEIGHT):
    """One frame's numbers (COLUMNS after t) and the ids over the orifice.
    `stayed` is the share of the grains over the orifice in the frame
    before (before_ids; None for the first frame) that are over it still."""
    r, v_theta = azimuthal_velocity(columns)
    z = columns["z"]
    over = (r < D / 2) & (z > 0) & (z < height)
    on_ring = (r > ring[0]) & (r < ring[1]) & (z > 0) & (z < plate_height)
    ids = set(columns["id"][over].astype(int))
    stayed = len(ids & before_ids) / len(before_ids) if before_ids else np.nan
    omega = 2 * np.pi * f

    def turn(mask):
        return float(np.mean(v_theta[mask] / (omega * r[mask]))) if mask.any() else np.nan

    return [int(over.sum()), stayed, float(np.mean(columns["vz"][over])) if over.any() else np.nan,
            turn(over), int(on_ring.sum()), turn(on_ring)], ids


def window_means(rows, t_from, t_to, blocks=BLOCKS):
    """[t_from, t_to, frames, residence] and, per column after t, the mean
    over the frames within [t_from, t_to] (in_window, as window_frames;
    NaN-free frames only) and its block standard error (NaN with fewer
    such frames than blocks). residence: the frame spacing over 1 - the
    window's mean `stayed` (inf if all stayed)."""
    inside = rows[in_window(rows[:, 0], t_from, t_to)]
    stayed_frames = inside[:, COLUMNS.index("stayed")]
    stayed = np.nanmean(stayed_frames) if np.isfinite(stayed_frames).any() else np.nan
    spacing = frame_spacing(rows[:, 0])
    out = [t_from, t_to, len(inside), np.inf if stayed >= 1 else spacing / (1 - stayed)]   # NaN stays NaN
    for k in range(1, rows.shape[1]):
        values = inside[:, k][np.isfinite(inside[:, k])]
        out += [values.mean() if values.size else np.nan, block_standard_error(values, blocks)]
    return out


def main(argv=None):
    parser = command_line("analysis.silo3d_rotating.orifice_plug", __doc__,
                          "/usr/bin/python3 -m analysis.silo3d_rotating.orifice_plug "
                          "runs/rods_fig2c/D0.06_f0.16_s32452843 --window 4 8 --out runs/rods_fig2c/orifice_plug")
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--window", nargs=2, type=float, action="append", required=True,
                        metavar=("T_FROM", "T_TO"), help="s since the opening; may be repeated")
    parser.add_argument("--height", type=float, default=HEIGHT, help=f"m over the plate [{HEIGHT}]")
    parser.add_argument("--ring", nargs=2, type=float, default=RING, metavar=("R_IN", "R_OUT"),
                        help=f"m, the plate's ring [{RING[0]} {RING[1]}]")
    parser.add_argument("--plate-height", type=float, default=PLATE_HEIGHT, help=f"m [{PLATE_HEIGHT}]")
    parser.add_argument("--blocks", type=int, default=BLOCKS, help=f"blocks per window for the errors [{BLOCKS}]")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="the directory the tables and figures go to")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    for t_from, t_to in args.window:
        if not t_to > t_from:
            parser.error(f"--window {t_from:g} {t_to:g}: the end must be after the start")
    if args.blocks < 2:
        parser.error(f"--blocks {args.blocks}: a standard error needs at least 2 blocks")
    run = load_run(args.run_dir)
    f, D = run.info["f"], run.info["D"]
    if not f > 0:
        parser.error(f"{args.run_dir}: f = {f:g} Hz: at rest there is no bottom speed to compare with")
    if not (args.run_dir / "dump.cg").exists():
        parser.error(f"{args.run_dir}: no dump.cg (an archive's dump.cg.xz: restore it first, "
                     "python3 -m analysis.campaign.silo3d_carry restore)")
    steps, tau = window_frames(run, min(w[0] for w in args.window), max(w[1] for w in args.window))
    if not steps.size:
        parser.error(f"{args.run_dir}: no dump frame in the windows")
    time_of = dict(zip(steps.tolist(), tau.tolist()))
    rows, before = [], None
    for step, columns in iter_dump(args.run_dir / "dump.cg", once_each(steps)):
        row, before = frame_row(columns, before, D, f, args.height, args.ring, args.plate_height)
        rows.append([time_of[step]] + row)
        progress(f"{args.run_dir.name}: t = {time_of[step]:.2f} s: {row[0]} grains over the orifice, "
                 f"{row[1]:.0%} stayed, v_z {row[2]:+.3f} m/s, turning at {row[3]:+.2f} of the bottom "
                 f"(the ring on the plate {row[5]:+.2f})")
    rows = np.array(rows)
    args.out.mkdir(parents=True, exist_ok=True)
    where = (f"over the orifice: r < {D / 2:g} m, 0 < z < {args.height:g} m; the ring: {args.ring[0]:g} < r < "
             f"{args.ring[1]:g} m, 0 < z < {args.plate_height:g} m; turn = v_theta / (2 pi f r)")
    write_table(args.out / "orifice_plug", COLUMNS, rows.tolist(),
                f"{args.run_dir}: per frame ({where}; stayed: share of the frame before's grains over the "
                "orifice still there)")
    header = ["t_from", "t_to", "frames", "residence"] + [x for name in COLUMNS[1:] for x in (name, f"{name}_se")]
    windows = [window_means(rows, *w, args.blocks) for w in args.window]
    for t_from, t_to, _, residence in (w[:4] for w in windows):
        if residence > (t_to - t_from) / args.blocks:
            progress(f"{t_from:g}-{t_to:g} s: the grains stay over the orifice {residence:.2g} s, longer than a "
                     f"block ({(t_to - t_from) / args.blocks:.2g} s): its standard errors understate")
    write_table(args.out / "orifice_plug_windows", header, windows,
                f"{args.run_dir}: means over each window's frames, block standard errors ({args.blocks} blocks "
                f"of consecutive frames); residence: frame spacing / (1 - stayed), s ({where})")
    progress(f"done; outputs in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
