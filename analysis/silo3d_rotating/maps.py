"""Coarse-grained maps of several runs side by side, as the paper's Figs.
6–7 set frequencies next to each other: for each run the mean of its map
windows (the `fields.npz` that analysis.silo3d_rotating.analyse writes per run,
each window weighted by its frames), one column per run, one row per
field, one colour scale per row, so that the runs compare by colour.

CLI:  python3 -m analysis.silo3d_rotating.maps FIELDS.npz[:LABEL] ... --figure PNG [--fields phi speed Ozz ...] [--z-max-m Z]

Fields: phi (packing fraction), speed ((v_r² + v_z²)^½, with the
streamlines of (v_r, v_z)), vtheta, pk (kinetic pressure), pc (contact
pressure), Ozz (orientation), S (nematic order, cylindrical average). A
field a run's maps lack (orientation for spheres, contact pressure
without dump.contacts) is refused with a message.
"""

import sys
from pathlib import Path

import numpy as np

from analysis.silo3d_rotating.analyse import draw_streamlines, in_plane_speed, map_field, map_key
from analysis.common.cli import command_line

# name: (title, the stored map it is made from, how)
FIELDS = {
    "phi": ("packing fraction", "packing_fraction", lambda m: m["packing_fraction"]),
    "speed": ("in-plane speed (m/s)", "velocity", in_plane_speed),
    "vtheta": ("v_theta (m/s)", "velocity", lambda m: m["velocity"][..., 1]),
    "pk": ("kinetic pressure (Pa)", "kinetic_pressure", lambda m: m["kinetic_pressure"]),
    "pc": ("contact pressure (Pa)", "contact_pressure", lambda m: m["contact_pressure"]),
    "Ozz": ("O_zz", "orientation", lambda m: m["orientation"][..., 2, 2]),
    "S": ("nematic order S", "nematic_order", lambda m: m["nematic_order"]),
}


def mean_fields(path):
    """r, z edges and centres, and each field averaged over the map
    windows, weighted by the frames each holds (cells empty in a window,
    NaN, are left out of that window's share)."""
    with np.load(path) as stored:
        frames = stored["frames"].astype(float)
        names = sorted({map_field(key) for key in stored.files} - {None})
        windows = [w for w in range(len(frames)) if frames[w] > 0 and map_key(names[0], w) in stored.files]
        if not windows:
            raise ValueError(f"{path}: no map window with frames")
        means = {}
        for name in names:
            values = np.stack([stored[map_key(name, w)] for w in windows])
            weights = np.broadcast_to(frames[windows].reshape((-1,) + (1,) * (values.ndim - 1)), values.shape)
            finite = np.isfinite(values)
            total = np.where(finite, weights, 0.0).sum(axis=0)
            with np.errstate(invalid="ignore"):
                means[name] = np.where(finite, values * weights, 0.0).sum(axis=0) / total
        return {"r_edges": stored["r_edges"], "z_edges": stored["z_edges"], "r": stored["r"], "z": stored["z"],
                "maps": means, "windows": stored["windows"][windows]}


def plot(path, runs, labels, fields, z_max=None):
    """Rows: fields; columns: runs; one colour scale per row over the
    shown part (z < z_max, the whole grid by default)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    first = runs[0]
    top = min(z_max or np.inf, first["z_edges"][-1])
    shown = first["z"] < top
    aspect = top / first["r_edges"][-1]
    fig, axes = plt.subplots(len(fields), len(runs), figsize=(2.6 * len(runs) + 0.8, (0.4 + 1.7 * aspect) * len(fields)),
                             squeeze=False, layout="constrained")
    for row, name in zip(axes, fields):
        title, _, values_of = FIELDS[name]
        values = [values_of(run["maps"]) for run in runs]
        low = min(np.nanmin(v[:, shown]) for v in values)
        high = max(np.nanmax(v[:, shown]) for v in values)
        for ax, run, value, label in zip(row, runs, values, labels):
            mesh = ax.pcolormesh(run["r_edges"], run["z_edges"], value.T, vmin=low, vmax=high, shading="flat")
            if name == "speed":
                draw_streamlines(ax, run["r"], run["z"], run["maps"])
            ax.set_ylim(0.0, top)
            ax.set_aspect("equal")
            ax.set_title(f"{label}: {title}", fontsize="small")
            ax.set_xlabel("r (m)")
        row[0].set_ylabel("z (m)")
        fig.colorbar(mesh, ax=list(row), shrink=0.6, format="%.3g")
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def main(argv=None):
    parser = command_line("analysis.silo3d_rotating.maps", __doc__,
                          "/usr/bin/python3 -m analysis.silo3d_rotating.maps "
                          "runs/rods_fig2c/analysis/runs/D0.06_f0_s32452843/fields.npz:'f = 0' --figure maps.png "
                          "--z-max-m 0.1")
    parser.add_argument("runs", nargs="+", help="FIELDS.npz[:LABEL], a run's fields.npz and its column's label")
    parser.add_argument("--figure", type=Path, required=True, metavar="PNG", help="the figure")
    parser.add_argument("--fields", nargs="+", default=["phi", "speed", "Ozz"], choices=sorted(FIELDS),
                        help="rows of the figure (default: phi speed Ozz)")
    parser.add_argument("--z-max-m", dest="z_max", type=float, metavar="Z",
                        help="show z < Z only (m); the colour scales follow")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    if args.z_max is not None and not args.z_max > 0:
        parser.error(f"--z-max-m must be > 0, not {args.z_max:g}")
    runs, labels = [], []
    for spec in args.runs:
        path, _, label = spec.partition(":")
        try:
            run = mean_fields(path)
        except (OSError, ValueError, KeyError) as error:
            print(f"silo3d_maps: ERROR: {spec}: {error}", file=sys.stderr)
            return 2
        missing = [name for name in args.fields if FIELDS[name][1] not in run["maps"]]
        if missing:
            print(f"silo3d_maps: ERROR: {path} has no map for {', '.join(missing)} "
                  "(no orientation for spheres, no contact pressure without dump.contacts)", file=sys.stderr)
            return 2
        runs.append(run)
        labels.append(label or Path(path).parent.name)
        spans = ", ".join(f"{low:.3g}-{high:.3g} s" for low, high in run["windows"])
        print(f"silo3d_maps: {labels[-1]}: mean of the windows {spans}")
    shapes = {run["maps"]["packing_fraction"].shape for run in runs}
    if len(shapes) > 1:
        print(f"silo3d_maps: ERROR: the runs' grids differ ({sorted(shapes)}): maps of one silo and spacing only",
              file=sys.stderr)
        return 2
    plot(args.figure, runs, labels, args.fields, args.z_max)
    print(f"silo3d_rotating.maps: {args.figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
