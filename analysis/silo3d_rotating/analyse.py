"""Analysis of the cylindrical silo with a rotating bottom (Pongó, Börzsönyi
and Hidalgo 2022, sections II-III): flow rate Q(f, D) with uncertainties over
seeds, Beverloo and exponential fits, and coarse-grained fields (packing
fraction, velocity, kinetic and contact pressure, orientation) on an (r, z)
grid in time windows and averaged over the orifice region.

Reads the run directories the deck writes (record contract and outputs:
doc/silo3d_rotating_records.md; coarse graining: doc/coarse_graining.md).

CLI:  python3 -m analysis.silo3d_rotating RUN_DIR [RUN_DIR ...] --out DIR [options]
"""

# The docstring above is the command line's --help. This module holds the
# command line, its tables and plots; the analysis is in
# analysis.silo3d_rotating.records (reading a run's records), analysis.silo3d_rotating.flow
# (flow rate, fits) and analysis.silo3d_rotating.fields (coarse-grained fields,
# orifice averages).

import sys
from pathlib import Path

import numpy as np

from analysis.common import coarse_grain as cg
from analysis.common.lammps_io import iter_dump
from analysis.common.tables import read_rows
from analysis.silo3d_rotating.fields import FieldSettings, analyse_fields, orifice_groups, orifice_summary
from analysis.silo3d_rotating.flow import (BLOCKS, END_FRACTION, MIN_FLOWING_FRACTION, MIN_GAP, TRANSIENT,
                                           analyse_flow, beverloo, drop_and_recovery, exponential, flow_changes,
                                           flow_fits, flow_groups, last_exit, progress, run_labels, smoothed_rate,
                                           window_rates)
from analysis.silo3d_rotating.records import key_value, load_run
from analysis.common.cli import command_line


# ---------------------------------------------------------------- tables

def _number(value, digits):
    """Whole numbers (seeds, counts) in full, others to `digits` digits."""
    value = float(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return f"{value:.{digits}g}"


def write_table(path_stem, header, rows, title):
    """rows (lists of numbers) as `<stem>.txt` (a '#' header naming the
    columns, for analysis.common.tables.read_table) and `<stem>.md`."""
    text = "# " + " ".join(header) + "\n" + "".join(
        " ".join(_number(v, 8) for v in row) + "\n" for row in rows)
    Path(f"{path_stem}.txt").write_text(text)
    lines = [title, "", "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_number(v, 6) for v in row) + " |" for row in rows]
    Path(f"{path_stem}.md").write_text("\n".join(lines) + "\n")


def write_flow_tables(out, runs, groups, changes, fits, d, drops=()):
    header = ["f", "D", "seed", "reinject", "Q_kg_s", "Q_kg_s_se", "Q_grains_s", "Q_grains_s_se",
              "blocks", "t_start", "t_end", "T_eff", "removed", "gaps", "clogged_at_end", "stationary",
              "Q_kg_s_se_2x", "Q_trend", "Q_trend_se", "longest_pause", "idle_share"]
    rows = [[r.info["f"], r.info["D"], r.info["seed"], r.info["reinject"], r.flow.q_mass, r.flow.q_mass_se,
             r.flow.q_grains, r.flow.q_grains_se, r.flow.blocks, r.flow.start, r.flow.end,
             r.flow.effective_duration, r.flow.removed, len(r.flow.gaps), int(r.flow.clogged_at_end),
             int(r.flow.stationary), r.flow.q_mass_se_2x, r.flow.trend, r.flow.trend_se,
             r.flow.longest_pause, r.flow.idle_share]
            for r in runs]
    write_table(out / "flow_rate_runs", header, rows,
                "Stationary flow rate per run (SI units; se = block standard error; se_2x = the same "
                "from blocks twice as long: well above se, se is too small; Q_trend = the rate's "
                "relative change across the window from the line through the block rates, with its se: "
                "well beyond it, the flow is not stationary yet; longest_pause = the longest time in the "
                "window without a grain out, s, idle_share = the share of its sampling intervals "
                "without one; times since opening). "
                "Runs: " + ", ".join(f"{r.label} = {r.path}" for r in runs))
    write_table(out / "flow_rate_windows", ["f", "D", "seed", "t_from", "t_to", "Q_grains_s", "Q_kg_s"],
                [[r.info["f"], r.info["D"], r.info["seed"], *row] for r in runs for row in r.windows],
                "Raw rate of each run in consecutive windows since the opening (times since opening, s; "
                "clock time, no-flow intervals included; the whole discharge, transient too): how the "
                "rate moves through the run. Runs: " + ", ".join(f"{r.label} = {r.path}" for r in runs))
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
    header = ["D", "f_min", "n_min", "Qmin_over_Q0", "Qmin_over_Q0_se", "Qmin_over_Q0_ci95", "f_max", "n_max",
              "Qmax_over_Qmin", "Qmax_over_Qmin_se", "Qmax_over_Qmin_ci95"]
    rows = [[r["D"], r["f_min"], r["n_min"], r["min_over_rest"], r["min_over_rest_se"], r["min_over_rest_ci"],
             r["f_max"], r["n_max"], r["max_over_min"], r["max_over_min_se"], r["max_over_min_ci"]]
            for r in drops]
    write_table(out / "flow_rate_drop", header, rows,
                "The paper's Fig. 3 per orifice: (a) Q_min/Q(0), Q_min the Q of the frequency f_min with the "
                "lowest mean over seeds; (b) Q(f_max)/Q_min, f_max the fastest frequency (the paper's 1.28 Hz). "
                "Paired by seed: mean over the n seeds with both runs, standard error and 95 % CI half width "
                "(Student t; for a single seed from the two runs' block standard errors). f_min is picked "
                "from the same means: Q_min/Q(0) leans low")
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


def plot_q_vs_f(path, groups, grains, runs=()):
    """Mean Q over seeds with its 95 % CI per orifice, and each run's Q
    (crosses): the spread between packings, which sets the CI."""
    fig, axes = _figure()
    ax = axes[0, 0]
    for D in sorted({g["D"] for g in groups}):
        rows = [g for g in groups if g["D"] == D]
        line = ax.errorbar([g["f"] for g in rows], [g["Q"] for g in rows],
                           yerr=_error_bars([g["Q_ci"] for g in rows]), fmt="o-", capsize=3,
                           label=f"D = {D * 1e3:g} mm")
        own = [(r.key[0], r.flow.q_mass) for r in runs if r.key[1] == D and np.isfinite(r.flow.q_mass)]
        if own:
            ax.plot(*zip(*own), "x", color=line[0].get_color(), alpha=0.6)
    ax.set_xlabel("f (Hz)")
    ax.set_ylabel("Q (kg/s)")
    ax.set_title(f"Q(f), {grains}\nmean and 95 % CI; x: each run" if runs else f"Q(f), {grains}, 95 % CI")
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
            draw_streamlines(ax, grid.r, grid.z, fields)
        ax.set_aspect("equal")
        ax.set_title(f"{0.5 * (low + high):.3g} s", fontsize="small")
        ax.set_xlabel("r (m)")
        fig.colorbar(mesh, ax=ax, shrink=0.6, format="%.3g")
    axes[0, 0].set_ylabel("z (m)")
    fig.suptitle(title, fontsize="small")
    return _save(fig, path)


def draw_streamlines(ax, r, z, fields):
    """White streamlines of (v_r, v_z) over a map, none where the cells
    are nearly empty (phi < 0.05)."""
    empty = fields["packing_fraction"].T < 0.05
    v_r = np.where(empty, np.nan, fields["velocity"][..., 0].T)
    v_z = np.where(empty, np.nan, fields["velocity"][..., 2].T)
    ax.streamplot(r, z, v_r, v_z, color="w", density=0.8, linewidth=0.6)


def in_plane_speed(fields):
    """(v_r^2 + v_z^2)^1/2, the paper's Fig. 7."""
    return np.hypot(fields["velocity"][..., 0], fields["velocity"][..., 2])


def plot_maps(directory, grid, windows, maps):
    """The colour maps of one run; returns the files written."""
    specs = [("map_phi.png", "packing fraction (Fig. 6)", lambda m: m["packing_fraction"], False),
             ("map_speed.png", "in-plane speed (v_r^2+v_z^2)^1/2 (m/s), streamlines (Fig. 7)", in_plane_speed,
              True),
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
    parser = command_line("analysis.silo3d_rotating", __doc__,
                          "/usr/bin/python3 -m analysis.silo3d_rotating runs/deck --out runs/deck/analysis "
                          "--transient 0.2 --no-fields")
    parser.add_argument("run_dirs", nargs="+", type=Path, help="run directories (run.txt, discharge.txt, ...)")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="the directory the tables and figures go to")
    parser.add_argument("--include-unfinished", action="store_true",
                        help="also analyse runs whose run.txt has no 'finished' line (left out by default)")
    flow = parser.add_argument_group("flow rate")
    flow.add_argument("--transient", type=float, default=TRANSIENT,
                      help="start transient left out after the opening (s, default %(default)s)")
    flow.add_argument("--transient-at", nargs=2, type=float, action="append", default=[], metavar=("F", "T"),
                      help="leave out T s instead at the frequency F (Hz); may be repeated. For runs "
                           "whose transient lasts a part of a turn of the bottom, not a fixed time")
    flow.add_argument("--gap", type=float, default=MIN_GAP,
                      help="no-flow intervals longer than this are cut from the time base (s, default %(default)s)")
    flow.add_argument("--min-flowing-fraction", type=float, default=MIN_FLOWING_FRACTION,
                      help="a run that flowed (no-flow intervals cut) for less than this fraction of its "
                           "window has no stationary flow and no Q (default %(default)s)")
    flow.add_argument("--end-fraction", type=float, default=END_FRACTION,
                      help="without reinjection, stop when this fraction of the grains' mass is out "
                           "(default %(default)s)")
    flow.add_argument("--blocks", type=int, default=BLOCKS, help="blocks for standard errors (default %(default)s)")
    flow.add_argument("--window-width", type=float, default=1.0,
                      help="width of the windows of flow_rate_windows, the raw rate through the whole run "
                           "(s, default %(default)s)")
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
    fields.add_argument("--z-max-m", dest="zmax", type=float,
                        help="top of the map grid (m); default fill height + r_c")
    args = parser.parse_args(argv)
    if not args.window_width > 0:
        parser.error(f"--window-width must be > 0 s, not {args.window_width:g}")
    if not args.transient >= 0:
        parser.error(f"--transient must be >= 0 s, not {args.transient:g}")
    frequencies = [key_value(f) for f, _ in args.transient_at]
    for f, t in args.transient_at:
        if not (f >= 0 and t >= 0):
            parser.error(f"--transient-at {f:g} {t:g}: the frequency and the time must be >= 0")
        if frequencies.count(key_value(f)) > 1:
            parser.error(f"--transient-at: the frequency {f:g} Hz is given more than once")
    return args


def transient_of(run, args):
    """The seconds after the opening left out of this run's window: those
    of --transient-at for its frequency, else --transient."""
    for f, t in args.transient_at:
        if key_value(f) == run.key[0]:
            return t
    return args.transient


def field_settings(args, run, first_masses):
    """The CLI's choices; the kernel width defaults to d*/2 of the dumped grains."""
    width = args.width or cg.default_kernel(first_masses, run.info["rho"]).width
    kernel = cg.GaussianKernel(width, args.cutoff)
    return FieldSettings(kernel, args.spacing or kernel.width, args.arc_spacing or kernel.width,
                         args.orifice_height, tuple(args.map_times), args.map_width, args.map_frames,
                         args.orifice_every, args.zmax)


def map_key(name, window):
    """The fields.npz array of field `name` in map window `window`."""
    return f"{name}_{window}"


def map_field(key):
    """The field of a fields.npz array `<name>_<window>` (map_key); None
    for the grid and the windows (r, z, r_edges, ..., frames)."""
    name, _, window = key.rpartition("_")
    return name if window.isdigit() else None


# what a run's fields in the analysis' runs/<label>/ were computed from
FIELDS_SOURCE = "fields_source.txt"


def fields_source(run, settings):
    """What the fields and orifice series of a run are computed from: the
    coarse-graining settings, the flow window and the size and time of
    every record read. Equal text, equal outputs."""
    flow = run.flow
    lines = [repr(settings), f"window {flow.start!r} {flow.end!r} gaps {np.asarray(flow.gaps).tolist()!r}"]
    for name in ("dump.cg", "dump.contacts", "discharge.txt", "run.txt"):
        path = run.path / name
        if path.exists():
            stat = path.stat()
            lines.append(f"{name} {stat.st_size} {stat.st_mtime_ns}")
    return "\n".join(lines) + "\n"


def fields_read_before(directory, source):
    """The orifice series (rows) of an analysis of the same source in
    `directory`, else None. The campaign drivers analyse a stage's runs
    again when its last one ends (rods_fig2c.sh): the dumps of the runs
    read before are not read again. The rows are those of
    orifice_timeseries.txt (8 significant digits; none when the analysis
    wrote no series)."""
    source_path = directory / FIELDS_SOURCE
    if not source_path.exists() or source_path.read_text() != source:
        return None
    return read_rows(directory / "orifice_timeseries.txt", missing_ok=True)


def run_fields(args, run, directory):
    """Maps and orifice series of one run; returns its orifice summary."""
    cg_path = run.path / "dump.cg"
    if not run.flow.effective_duration > 0:
        progress(f"{run.label}: no stationary interval, no fields")
        return {}
    _, first = next(iter_dump(cg_path))
    settings = field_settings(args, run, first["mass"])
    source = fields_source(run, settings)
    rows = fields_read_before(directory, source)
    if rows is not None:
        progress(f"{run.label}: fields as analysed before from the same records and settings "
                 f"({directory / FIELDS_SOURCE}); dumps not read again")
        return orifice_summary(rows, args.blocks)
    (directory / FIELDS_SOURCE).unlink(missing_ok=True)
    progress(f"{run.label}: kernel w = {settings.kernel.width:.4g} m, r_c = {settings.kernel.cutoff:.4g} m, "
             f"cells {settings.spacing:.4g} m" + ("" if (run.path / "dump.contacts").exists()
                                                  else "; no dump.contacts: no contact stress"))
    grid, windows, counts, maps, rows = analyse_fields(run, settings)
    if any(m is not None for m in maps):
        np.savez_compressed(directory / "fields.npz", r=grid.r, z=grid.z, r_edges=grid.r_edges,
                            z_edges=grid.z_edges, windows=np.array(windows), frames=np.array(counts),
                            **{map_key(name, w): values for w, m in enumerate(maps) if m is not None
                               for name, values in m.items()})
        plot_maps(directory, grid, windows, maps)
    if rows:
        names = list(rows[0])
        write_table(directory / "orifice_timeseries", names, [[row[n] for n in names] for row in rows],
                    f"{run.label}: orifice-region averages per frame")
    else:
        for suffix in (".txt", ".md"):
            (directory / f"orifice_timeseries{suffix}").unlink(missing_ok=True)
    (directory / FIELDS_SOURCE).write_text(source)       # last: the outputs above are whole
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
    for f, t in args.transient_at:
        if key_value(f) not in {run.key[0] for run in runs}:
            progress(f"WARNING: --transient-at {f:g} {t:g}: no run at {f:g} Hz")
    for run, label in zip(runs, run_labels(runs)):
        run.label = label
        flow = analyse_flow(run, transient_of(run, args), args.gap, args.end_fraction, args.blocks,
                            args.min_flowing_fraction)
        if flow.stationary:
            progress(f"{label}: Q = {flow.q_mass:.5g} +- {flow.q_mass_se:.2g} kg/s = {flow.q_grains:.5g} "
                     f"+- {flow.q_grains_se:.2g} grains/s over {flow.effective_duration:.3g} s "
                     f"({len(flow.gaps)} no-flow intervals, {flow.removed:.3g} s removed; "
                     f"se with blocks twice as long {flow.q_mass_se_2x:.2g} kg/s; "
                     f"trend across the window {flow.trend:+.0%} +- {flow.trend_se:.0%}; longest pause "
                     f"{flow.longest_pause:.3g} s, {flow.idle_share:.0%} of the samples without a grain out)")
        elif np.isnan(flow.start):
            progress(f"{label}: no stationary flow: the run ended at {run.tau[-1]:.3g} s, before its window "
                     f"starts ({transient_of(run, args):g} s after the opening); no Q")
        else:
            progress(f"{label}: no stationary flow: it flowed for {flow.effective_duration:.3g} s of the "
                     f"{flow.end - flow.start:.3g} s window ({len(flow.gaps)} no-flow intervals); no Q")
        if run.clogged_at_rest:
            progress(f"{label}: clogged at rest (run.txt says so): stopped at {run.tau[-1]:.3g} s after the opening; "
                     f"its last grain had left by {last_exit(run.tau, run.discharge['n_out']):.3g} s "
                     f"({run.discharge['n_out'][-1]:.0f} out)")
        try:
            run.windows = window_rates(run.tau, run.discharge["n_out"], run.discharge["mass_out"],
                                       args.window_width)
        except ValueError as error:
            progress(f"ERROR: {label}: --window-width: {error}")
            return 2
        progress(f"{label}: grains/s per {args.window_width:g} s since the opening: "
                 + (", ".join(f"{row[2]:.0f}" for row in run.windows) or "none (shorter than one window)"))
        directory = args.out / "runs" / label
        directory.mkdir(parents=True, exist_ok=True)
        plot_discharge(directory / "discharge.png", run, args.rate_window)
    groups = flow_groups(runs)
    d = runs[0].info["d"]
    fits = flow_fits(groups, d)
    changes = flow_changes(runs)
    drops = drop_and_recovery(runs, groups)
    write_flow_tables(args.out, runs, groups, changes, fits, d, drops)
    for c in changes:
        progress(f"f = {c['f']:g} Hz, D = {c['D'] * 1e3:g} mm: Q changes by {100 * c['change']:+.1f} "
                 f"+- {100 * c['change_ci']:.1f} % (95 %) from f = 0 over {c['n']} seed(s)")
    for r in drops:
        recovery = (f", Q({r['f_max']:g} Hz)/Q_min = {r['max_over_min']:.3f} +- {r['max_over_min_ci']:.3f} "
                    f"({r['n_max']} seed(s))" if r["n_max"] else "")
        progress(f"D = {r['D'] * 1e3:g} mm: Q_min/Q(0) = {r['min_over_rest']:.3f} +- {r['min_over_rest_ci']:.3f} "
                 f"(95 %, f_min = {r['f_min']:g} Hz, {r['n_min']} seed(s)){recovery}")
    for f, fit in fits.items():
        b, e = fit["beverloo"], fit["exponential"]
        progress(f"f = {f:g} Hz: Beverloo C = {b['C']:.4g} +- {b['C_se']:.2g}, k = {b['k']:.3g} +- "
                 f"{b['k_se']:.2g}; exponential kappa = {e['kappa'] * 1e-3:.4g} +- {e['kappa_se'] * 1e-3:.2g} /mm")
    if groups:
        plot_q_vs_f(args.out / "Q_vs_f.png", groups, fig2_panel(runs[0].info), runs)
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
