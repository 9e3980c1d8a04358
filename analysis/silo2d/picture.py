"""A picture of one clogging arch of the quasi-2D silo: the grains around
the outlet as discs (free grains grey, the fixed grains of the walls and
bottom dark, the arch red and numbered in walk order), and the contact force
network as segments between grain centres, their width proportional to the
normal force.

Needs the records of `fix clog` (arches.txt, contacts.txt; see
doc/silo2d_records.md) and the grain positions at that clog: the silo2d
deck, run with `-var stop_at_first 1`, writes them to clog_state.dump when
it stops at its first clog.

CLI:  python3 -m analysis.silo2d.picture RECORD_DIR [--dump FILE] [--clog N] [--figure PNG]
"""

import sys
from pathlib import Path

import numpy as np

from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_table
from analysis.common.cli import command_line

FREE_TYPE = 1        # the deck's type of the free grains (2: fixed grains)


def window_mask(x, z, half_width, height):
    """Grains inside the picture: |x| <= half_width, z <= height."""
    return (np.abs(x) <= half_width) & (z <= height)


def force_segments(contacts, clog, positions):
    """(x1, z1, x2, z2, fn) of each contact of `clog` between two grains
    whose positions (a dict id -> (x, z)) are known."""
    rows = contacts["clog"] == clog
    segments = []
    for id1, id2, fn in zip(contacts["id1"][rows], contacts["id2"][rows], contacts["fn"][rows]):
        a, b = positions.get(int(id1)), positions.get(int(id2))
        if a is not None and b is not None:
            segments.append((a[0], a[1], b[0], b[1], fn))
    return segments


def draw(dump_path, arches, contacts, clog, out, d, half_width_d=8.0, height_d=10.0, feet=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Circle

    _, grains = read_dump(dump_path)[-1]
    x, z, radius = grains["x"], grains["z"], grains["radius"]
    inside = window_mask(x, z, half_width_d * d, height_d * d)
    members = arches["id"][arches["clog"] == clog].astype(int)
    order = arches["order"][arches["clog"] == clog].astype(int)
    is_member = np.isin(grains["id"].astype(int), members)
    foot_ids = feet["id"][feet["clog"] == clog].astype(int) if feet is not None else np.array([], int)
    is_foot = np.isin(grains["id"].astype(int), foot_ids)

    fig, ax = plt.subplots(figsize=(7, 4.8))
    for selection, colour in ((inside & (grains["type"] != FREE_TYPE), "0.25"),
                              (inside & (grains["type"] == FREE_TYPE) & ~is_member & ~is_foot, "0.8"),
                              (inside & is_foot, "tab:orange"),
                              (inside & is_member, "tab:red")):
        discs = [Circle((xi / d, zi / d), ri / d) for xi, zi, ri in
                 zip(x[selection], z[selection], radius[selection])]
        ax.add_collection(PatchCollection(discs, facecolor=colour, edgecolor="0.4", linewidth=0.4))

    positions = {int(i): (xi, zi) for i, xi, zi in zip(grains["id"], x, z)}
    segments = force_segments(contacts, clog, positions)
    if segments:
        seg = np.array(segments)
        keep = window_mask(seg[:, 0], seg[:, 1], half_width_d * d, height_d * d)
        seg = seg[keep]
        mean = seg[:, 4].mean() if seg.size else 1.0
        lines = [((a / d, b / d), (c / d, e / d)) for a, b, c, e, _ in seg]
        ax.add_collection(LineCollection(lines, linewidths=1.5 * seg[:, 4] / mean, colors="k"))
    for member, rank in zip(members, order):
        px, pz = positions[int(member)]
        ax.text(px / d, pz / d, str(rank), ha="center", va="center", fontsize=7, color="white")
    ax.set_xlim(-half_width_d, half_width_d)
    ax.set_ylim(-1.0, height_d)
    ax.set_aspect("equal")
    ax.set_xlabel("x/d")
    ax.set_ylabel("h/d")
    feet_text = "; its feet orange" if foot_ids.size else ""
    ax.set_title(f"clog {clog}: arch of {members.size} grains (red, walk order){feet_text}; "
                 "contact normal forces (line width)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = command_line("analysis.silo2d.picture", __doc__,
                          "/usr/bin/python3 -m analysis.silo2d.picture runs/silo2d_one --figure "
                          "runs/silo2d_one/arch.png")
    parser.add_argument("record_dir", type=Path)
    parser.add_argument("--dump", type=Path, default=None, help="grain positions (default RECORD_DIR/clog_state.dump)")
    parser.add_argument("--clog", type=int, default=None, help="clog index (default: the last clog with an arch)")
    parser.add_argument("--d", type=float, default=1.0 / 32, help="grain diameter (m)")
    parser.add_argument("--figure", type=Path, default=None, metavar="PNG",
                        help="the figure (default RECORD_DIR/arch.png)")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    clogs = read_table(args.record_dir / "clogs.txt")
    arches = read_table(args.record_dir / "arches.txt")
    contacts = read_table(args.record_dir / "contacts.txt")
    found = clogs["clog"][clogs["status"] == 1].astype(int)
    if not found.size:
        raise SystemExit("error: no clog with an arch in clogs.txt")
    clog = args.clog if args.clog is not None else int(found[-1])
    out = args.figure or args.record_dir / "arch.png"
    feet_path = args.record_dir / "feet.txt"
    feet = read_table(feet_path) if feet_path.exists() else None
    draw(args.dump or args.record_dir / "clog_state.dump", arches, contacts, clog, out, args.d, feet=feet)
    print(f"silo2d_picture: clog {clog} drawn in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
