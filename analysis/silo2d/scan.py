"""The friction scan of the clogging silo (Hidalgo et al. 2013, R = 3 and
mu = 0.2, 0.4, 0.8): several record directories of fix clog, one per
friction coefficient (analysis.silo2d.driver writes them), side by side.

For each run and each reading of which grains make the arch
(analysis.silo2d.clogs.READINGS), the table gives the arches, eta (mean with its
Student-t interval, mode, decay rate of the exponential tail), phi (peak,
defect fraction), <f_n,b> and <f_n,a> in units of m g and their ratio, each
with a 95 % interval, beside the paper's values; and it draws the paper's
Figs. 2-8 with one curve per mu.

Intervals: mean eta, Student t over arches; the eta mode, the tail rate,
the phi peak and the force ratio, percentile bootstrap over clogs (the
grains and contacts of one clog are not independent); the defect fraction,
Wilson over arch grains (a lower bound on its width, for the same reason);
<f_n,b> and <f_n,a>, the paper's "95 % confidence interval of an
exponential distribution" (analysis.silo2d.clogs.exponential_mean_ci) and the
bootstrap over clogs beside it. The surface height of the clogged silo
(analysis.silo2d.clogs.surface_heights; the paper's is 80 d) is given too: the
bulk window's force depends on its depth.

CLI:  python3 -m analysis.silo2d.scan RUN_DIR [RUN_DIR ...] --out DIR [--reading outlet|members|feet]
"""

import sys
from pathlib import Path

import numpy as np

from analysis.common.stats import mean_t_ci
from analysis.silo2d import clogs as silo2d
from analysis.common.tables import read_table
from analysis.common.cli import command_line

PHI_BIN = 10.0
RESAMPLES = 2000
# Paper: the eta PDF peaks "around eta = R + 2" (Fig. 2); the phi PDF has
# its maximum "at around 150-160 degrees" (Fig. 3); Table 1.
PAPER_PHI_PEAK = (150.0, 160.0)


def paper_ratio(mu):
    """<f_n,a>/<f_n,b> of Table 1 with its uncertainty propagated from the
    two quoted ones (independent, first order); None for another mu."""
    values = silo2d.PAPER_TABLE1.get(round(mu, 3))
    if values is None:
        return None
    (bulk, bulk_error), (arch, arch_error) = values
    ratio = arch / bulk
    return ratio, ratio * np.hypot(arch_error / arch, bulk_error / bulk)


def phi_peak(phi, bin_width=PHI_BIN):
    """Centre of the fullest bin of phi (bins of bin_width from 0)."""
    counts, edges = np.histogram(phi, bins=np.arange(0.0, 360.0 + bin_width, bin_width))
    k = int(np.argmax(counts))
    return 0.5 * (edges[k] + edges[k + 1])


def load_run(record_dir, d_default=1.0 / 32):
    """The records of one run: tables, geometry (silo.txt), the bulk mask."""
    record_dir = Path(record_dir)
    tables = silo2d.read_records(record_dir)
    geometry = {"d": d_default, "g": 10.0, "R": 3.0, "rho": 7580.0}
    if (record_dir / "silo.txt").exists():
        geometry.update(silo2d.read_silo(record_dir / "silo.txt"))
    if "mu" not in geometry:
        raise SystemExit(f"error: {record_dir}/silo.txt gives no mu")
    geometry.setdefault("mass", geometry["rho"] * np.pi * geometry["d"] ** 3 / 6)
    contacts = tables["contacts"]
    bulk = silo2d.bulk_mask(contacts["x"], contacts["z"], geometry["d"])
    # an archive (analysis.campaign.silo2d_archive) keeps the profiles as sums and
    # the surfaces, which need every contact
    profiles = record_dir / "profiles.txt"
    if (record_dir / "surfaces.txt").exists():
        surfaces = read_table(record_dir / "surfaces.txt")["surface"]
    else:
        surfaces = silo2d.surface_heights(contacts["clog"], contacts["x"], contacts["z"], geometry["d"])[1]
    return {"dir": record_dir, "tables": tables, "feet": silo2d.read_feet(record_dir),
            "geometry": geometry, "bulk": bulk, "surfaces": np.atleast_1d(surfaces),
            "profile_sums": read_table(profiles) if profiles.exists() else None}


def clog_groups(run, arches):
    """Per clog with an arch: its eta-independent samples for the bootstrap
    (phi of its arch grains, force sums of its arch grains and bulk contacts)."""
    clogs, contacts = run["tables"]["clogs"], run["tables"]["contacts"]
    found = np.atleast_1d(clogs["clog"])[np.atleast_1d(clogs["status"]) == 1]
    bulk_clog = contacts["clog"][run["bulk"]]
    bulk_fn = contacts["fn"][run["bulk"]]
    groups = []
    for clog in found:
        own = arches["clog"] == clog
        group = silo2d.force_sums(arches["fn"][own], bulk_fn[bulk_clog == clog])
        group["phi"] = arches["phi"][own]
        groups.append(group)
    return groups


def with_walk_forces(run, arches):
    """arches with `fn` replaced by each grain's walk-contact mean
    (silo2d.walk_contact_forces); an error if the records lack them."""
    if run["feet"] is None:
        raise SystemExit(f"error: {run['dir']}: --arch-force walk needs feet.txt")
    if "walks" not in run:
        # once per run (every reading asks): the walks, and the few contacts
        # along them out of the run's hundreds of thousands
        contacts = run["tables"]["contacts"]
        run["walks"] = silo2d.walk_pairs(run["tables"]["arches"], run["feet"])
        on_walk = silo2d.walk_contact_mask(run["walks"], contacts)
        run["walk_contacts"] = {c: np.atleast_1d(contacts[c])[on_walk] for c in ("clog", "id1", "id2", "fn")}
    forces = silo2d.walk_contact_forces(arches, run["walks"], run["walk_contacts"])
    if np.isnan(forces).any():
        raise SystemExit(f"error: {run['dir']}: {int(np.isnan(forces).sum())} of {forces.size} arch "
                         "grains lack a walk contact in contacts.txt (an archive made before "
                         "silo2d_archive kept them: archive the run again)")
    return {**arches, "fn": forces}


def summarize(run, reading, rng, arch_force="all"):
    """The row of the scan table for one run and one reading; arch_force
    "walk" takes each arch grain's force from its two walk contacts."""
    geometry, tables = run["geometry"], run["tables"]
    weight = geometry["mass"] * geometry["g"]
    arches = silo2d.arch_grains(tables["arches"], run["feet"], reading)
    if arch_force == "walk":
        arches = with_walk_forces(run, arches)
    eta = silo2d.arch_sizes(tables["clogs"], run["feet"], reading)
    groups = clog_groups(run, arches)
    for group, size in zip(groups, eta):
        group["eta"] = size
    mode = silo2d.most_frequent(eta) if eta.size else np.nan

    def mode_of(sample):
        return silo2d.most_frequent([g["eta"] for g in sample])

    def tail_of(sample):
        return silo2d.exponential_tail_rate([g["eta"] for g in sample], mode + 1)

    def peak_of(sample):
        return phi_peak(np.concatenate([g["phi"] for g in sample]))

    bulk_fn = tables["contacts"]["fn"][run["bulk"]] / weight
    arch_fn = arches["fn"] / weight
    defects = int(np.sum(arches["phi"] > 180.0))
    return {
        "mu": geometry["mu"], "R": geometry["R"],
        "reading": reading if arch_force == "all" else f"{reading}, walk forces", "arches": int(eta.size),
        "clogs": int(np.size(tables["clogs"]["clog"])),
        "eta_mean": mean_t_ci(eta), "eta_mode": mode,
        "eta_mode_ci": silo2d.bootstrap_over_clogs(groups, mode_of, rng, RESAMPLES),
        "tail_rate": silo2d.exponential_tail_rate(eta, mode + 1),
        "tail_rate_ci": silo2d.bootstrap_over_clogs(groups, tail_of, rng, RESAMPLES),
        "phi_peak": phi_peak(arches["phi"]),
        "phi_peak_ci": silo2d.bootstrap_over_clogs(groups, peak_of, rng, RESAMPLES),
        "phi_mean": float(np.mean(arches["phi"])),
        "defects": silo2d.wilson_interval(defects, arches["phi"].size),
        "fn_b": silo2d.exponential_mean_ci(bulk_fn),
        "fn_a": silo2d.exponential_mean_ci(arch_fn),
        "fn_b_boot": silo2d.bootstrap_over_clogs(
            groups, lambda s: sum(g["bulk_sum"] for g in s) / max(sum(g["bulk_n"] for g in s), 1) / weight,
            rng, RESAMPLES),
        "fn_a_boot": silo2d.bootstrap_over_clogs(
            groups, lambda s: sum(g["arch_sum"] for g in s) / max(sum(g["arch_n"] for g in s), 1) / weight,
            rng, RESAMPLES),
        "ratio": silo2d.force_ratio(groups),
        "ratio_ci": silo2d.bootstrap_over_clogs(groups, silo2d.force_ratio, rng, RESAMPLES),
        "n_bulk": int(bulk_fn.size),
        "surface": mean_t_ci(run["surfaces"]),
    }


def format_table(rows):
    """Markdown: one line per run and reading, the paper's values beside."""
    lines = ["| mu | reading | arches | surface h/d | mean eta | eta mode [95 %] | tail rate [95 %] | "
             "phi peak [95 %] | defects [95 %] | <f_n,b>/mg | <f_n,a>/mg | ratio [95 %] | "
             "paper: <f_n,b>, <f_n,a>, ratio |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        paper = silo2d.PAPER_TABLE1.get(round(r["mu"], 3))
        ratio = paper_ratio(r["mu"])
        paper_text = (f"{paper[0][0]:g} ± {paper[0][1]:g}, {paper[1][0]:g} ± {paper[1][1]:g}, "
                      f"{ratio[0]:.2f} ± {ratio[1]:.2f}") if paper else "—"
        eta_mean, eta_half = r["eta_mean"]
        p, p_low, p_high = r["defects"]
        lines.append(
            f"| {r['mu']:g} | {r['reading']} | {r['arches']} | "
            f"{r['surface'][0]:.1f} ± {r['surface'][1]:.1f} | {eta_mean:.2f} ± {eta_half:.2f} | "
            f"{r['eta_mode']} [{r['eta_mode_ci'][0]:g}, {r['eta_mode_ci'][1]:g}] | "
            f"{r['tail_rate']:.2f} [{r['tail_rate_ci'][0]:.2f}, {r['tail_rate_ci'][1]:.2f}] | "
            f"{r['phi_peak']:g} [{r['phi_peak_ci'][0]:g}, {r['phi_peak_ci'][1]:g}] | "
            f"{p:.3f} [{p_low:.3f}, {p_high:.3f}] | "
            f"{r['fn_b'][0]:.1f} [{r['fn_b_boot'][0]:.1f}, {r['fn_b_boot'][1]:.1f}] | "
            f"{r['fn_a'][0]:.1f} [{r['fn_a_boot'][0]:.1f}, {r['fn_a_boot'][1]:.1f}] | "
            f"{r['ratio']:.2f} [{r['ratio_ci'][0]:.2f}, {r['ratio_ci'][1]:.2f}] | {paper_text} |")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- figures

def _figure(ncols=1, width=5.0):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, ncols, figsize=(width * ncols, 4), squeeze=False)
    return fig, axes[0]


def _save(fig, path):
    import matplotlib.pyplot as plt
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def plot_eta(runs, out):
    """Fig. 2: PDF of eta per mu, semilog, under each reading."""
    fig, axes = _figure(len(silo2d.READINGS))
    for ax, reading in zip(axes, silo2d.READINGS):
        for run in runs:
            eta = silo2d.arch_sizes(run["tables"]["clogs"], run["feet"], reading)
            centres, density = silo2d.integer_pdf(eta)
            shown = density > 0
            ax.semilogy(centres[shown], density[shown], "o-", label=f"mu = {run['geometry']['mu']:g}")
        R = runs[0]["geometry"]["R"]
        ax.axvline(R + 2, ls=":", color="k", label=f"R + 2 = {R + 2:g} (paper's maximum)")
        ax.set_title(f"Fig. 2: eta, {reading} reading")
        ax.set_xlabel("eta (grains in the arch)")
        ax.set_ylabel("PDF")
        ax.legend(fontsize=8)
    return _save(fig, out / "scan_eta_pdf.png")


def plot_phi(runs, out, reading):
    """Fig. 3: PDF of phi per mu, linear and (inset) semilog."""
    fig, axes = _figure(2)
    edges = np.arange(0.0, 360.0 + PHI_BIN, PHI_BIN)
    for run in runs:
        arches = silo2d.arch_grains(run["tables"]["arches"], run["feet"], reading)
        centres, density = silo2d.pdf(arches["phi"], edges)
        label = f"mu = {run['geometry']['mu']:g}"
        axes[0].plot(centres, density, "o-", label=label)
        shown = density > 0
        axes[1].semilogy(centres[shown], density[shown], "o-", label=label)
    for ax, scale in zip(axes, ("linear", "semilog (the paper's inset)")):
        ax.axvline(180.0, ls=":", color="k")
        ax.axvspan(*PAPER_PHI_PEAK, color="0.85", label="paper's maximum")
        ax.set_title(f"Fig. 3: phi, {reading} reading, {scale}")
        ax.set_xlabel("phi (deg)")
        ax.set_ylabel("PDF")
        ax.legend(fontsize=8)
    return _save(fig, out / "scan_phi_pdf.png")


def plot_forces_vs_phi(runs, out, reading):
    """Fig. 5: <F_n> and <F_t> of arch grains against phi, per mu (m g)."""
    fig, axes = _figure(2)
    edges = np.arange(0.0, 360.0 + 2 * PHI_BIN, 2 * PHI_BIN)
    for run in runs:
        arches = silo2d.arch_grains(run["tables"]["arches"], run["feet"], reading)
        weight = run["geometry"]["mass"] * run["geometry"]["g"]
        for ax, name in zip(axes, ("fn", "ft")):
            c, mean, sem, _ = silo2d.binned_mean(arches["phi"], arches[name] / weight, edges)
            ax.errorbar(c, mean, yerr=sem, fmt="o-", label=f"mu = {run['geometry']['mu']:g}")
    for ax, label in zip(axes, ("<F_n>", "<F_t>")):
        ax.axvline(180.0, ls=":", color="k")
        ax.set_title(f"Fig. 5: {label} of arch grains, {reading} reading")
        ax.set_xlabel("phi (deg)")
        ax.set_ylabel(f"{label} / m g")
        ax.legend(fontsize=8)
    return _save(fig, out / "scan_force_vs_phi.png")


def plot_profiles(runs, out):
    """Fig. 4: mean normal force against h/d, regions W, I, C, one panel per mu."""
    fig, axes = _figure(len(runs), width=4.0)
    for ax, run in zip(axes, runs):
        contacts, geometry = run["tables"]["contacts"], run["geometry"]
        weight = geometry["mass"] * geometry["g"]
        if run["profile_sums"] is not None:
            profiles = silo2d.profiles_from_sums(run["profile_sums"])
        else:
            profiles = silo2d.force_profiles(contacts["x"], contacts["z"], contacts["fn"], geometry["d"])
        for name, (c, mean, sem, _) in profiles.items():
            ax.errorbar(c, mean / weight, yerr=sem / weight, fmt=".-", label=name)
        for h in (silo2d.BULK_H_MIN_D, silo2d.BULK_H_MAX_D):
            ax.axvline(h, ls=":", color="k")
        ax.set_title(f"Fig. 4: mu = {geometry['mu']:g}")
        ax.set_xlabel("h/d")
        ax.set_ylabel("<f_n> / m g")
        ax.legend(fontsize=8)
    return _save(fig, out / "scan_fn_profiles.png")


def plot_force_pdfs(runs, out, reading):
    """Figs. 6-7: PDFs of f_n and f_t over <f_n,b>, bulk and arch, per mu."""
    files = []
    for name, figure in (("fn", 6), ("ft", 7)):
        fig, axes = _figure(2)
        for run in runs:
            arches = silo2d.arch_grains(run["tables"]["arches"], run["feet"], reading)
            contacts = run["tables"]["contacts"]
            fn_b = contacts["fn"][run["bulk"]].mean()
            label = f"mu = {run['geometry']['mu']:g}"
            for ax, sample in zip(axes, (contacts[name][run["bulk"]], arches[name])):
                ratio = np.asarray(sample) / fn_b
                c, density = silo2d.pdf(ratio, np.linspace(0.0, max(ratio.max(), 1e-12), 26))
                shown = density > 0
                ax.semilogy(c[shown], density[shown], "o-", label=label)
        for ax, where in zip(axes, ("bulk", f"arch ({reading} reading)")):
            ax.set_title(f"Fig. {figure}: {name}/<f_n,b>, {where}")
            ax.set_xlabel(f"{name}/<f_n,b>")
            ax.set_ylabel("PDF")
            ax.legend(fontsize=8)
        files.append(_save(fig, out / f"scan_{name}_pdf.png"))
    return files


def plot_mobilized_friction(runs, out, reading):
    """Fig. 8: PDF of f_t/(mu f_n), bulk and arch, per mu."""
    fig, axes = _figure(2)
    for run in runs:
        arches = silo2d.arch_grains(run["tables"]["arches"], run["feet"], reading)
        contacts, mu = run["tables"]["contacts"], run["geometry"]["mu"]
        samples = ((contacts["fn"][run["bulk"]], contacts["ft"][run["bulk"]]), (arches["fn"], arches["ft"]))
        for ax, (fn, ft) in zip(axes, samples):
            c, density = silo2d.pdf(np.minimum(silo2d.mobilized_friction(fn, ft, mu), 1.0),
                                    np.linspace(0, 1, 21))
            ax.plot(c, density, "o-", label=f"mu = {mu:g}")
    for ax, where in zip(axes, ("bulk", f"arch ({reading} reading)")):
        ax.set_title(f"Fig. 8: f_t/(mu f_n), {where}")
        ax.set_xlabel("f_t/(mu f_n)")
        ax.set_ylabel("PDF")
        ax.legend(fontsize=8)
    return _save(fig, out / "scan_mobilized_friction.png")


# ---------------------------------------------------------------- CLI

def parse_args(argv):
    parser = command_line("analysis.silo2d.scan", __doc__,
                          "/usr/bin/python3 -m analysis.silo2d.scan doc/data/silo2d_scan/mu0.2 "
                          "doc/data/silo2d_scan/mu0.4 doc/data/silo2d_scan/mu0.8 --out runs/silo2d_scan/analysis")
    parser.add_argument("run_dirs", type=Path, nargs="+", help="record directories, one per mu")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR", help="the directory the tables and figures go to")
    parser.add_argument("--reading", choices=silo2d.READINGS, default=None,
                        help="the reading of the figures other than Fig. 2 (which shows all); default "
                             f"{silo2d.DEFAULT_READING}, members for records without feet.txt")
    parser.add_argument("--arch-force", dest="arch_force", choices=("all", "walk"), default="all",
                        help="an arch grain's f_n in the table: the mean over all its contacts "
                             "(arches.txt's fn, the default) or over its two contacts along the "
                             "arch's walk (doc/silo2d.md, Table 1)")
    parser.add_argument("--seed", type=int, default=1, help="bootstrap seed")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    args.out.mkdir(parents=True, exist_ok=True)
    runs = []
    for directory in args.run_dirs:
        print(f"silo2d_scan: reading {directory}", flush=True)
        runs.append(load_run(directory))
    runs.sort(key=lambda run: run["geometry"]["mu"])
    all_have_feet = all(run["feet"] is not None for run in runs)
    readings = [r for r in silo2d.READINGS if r == "members" or all_have_feet]
    if args.reading is None:
        args.reading = silo2d.default_reading(all_have_feet)
    rng = np.random.default_rng(args.seed)
    rows = []
    for run in runs:
        for reading in readings:
            print(f"silo2d_scan: mu {run['geometry']['mu']:g}, {reading} reading: statistics", flush=True)
            rows.append(summarize(run, reading, rng, args.arch_force))
    text = format_table(rows)
    (args.out / "scan_table.md").write_text(text)
    print(text, flush=True)
    print("silo2d_scan: plotting", flush=True)
    files = [plot_phi(runs, args.out, args.reading), plot_forces_vs_phi(runs, args.out, args.reading),
             plot_profiles(runs, args.out), plot_mobilized_friction(runs, args.out, args.reading)]
    files += plot_force_pdfs(runs, args.out, args.reading)
    if len(readings) == len(silo2d.READINGS):
        files.append(plot_eta(runs, args.out))
    print(f"silo2d_scan: wrote scan_table.md and {len(files)} PNGs in {args.out}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
