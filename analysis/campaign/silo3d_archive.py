"""A finished rotating-bottom silo run, reduced to the records that stay in
doc/data (doc/data/README.md): its flow rate and, when the run has been
analysed, its orifice averages and maps, in a few per cent of the space.

The archive keeps
- run.txt and discharge.txt as they are, and reinject.txt as
  reinject.txt.xz (small; analysis.silo3d_rotating.analyse takes Q from them);
- from an analysis of the whole run directory (`--analysis OUT`, the
  `--out` of analysis.silo3d_rotating that read this run, with the
  campaign's windows): the run's orifice_timeseries.md (the orifice-region
  averages per frame) and fields.npz (the maps' fields, stored as float32,
  without the full stress tensors: DROPPED_FIELDS), unless `--no-fields`.

The dumps (dump.cg, dump.contacts), checkpoints and restart files of a
finished run are not kept: the analysis that needs them is done before
the archive, and its tables are kept. A finished run restored from its
archive gives Q but no new orifice averages or maps.

A run whose run.txt has no `finished` line is refused: its records are
cut at a checkpoint or still growing (analysis.campaign.silo3d_carry carries an
unfinished run to another machine outside doc/data, in carry/<campaign>/).

CLI:  python3 -m analysis.campaign.silo3d_archive RUN_DIR ARCHIVE_DIR [--analysis OUT] [--no-fields]
"""

import lzma
import shutil
import sys
from pathlib import Path

import numpy as np

from analysis.silo3d_rotating.analyse import map_field
from analysis.silo3d_rotating.records import read_run_info
from analysis.common.cli import command_line

RECORDS = ("run.txt", "discharge.txt")       # kept as they are
PACKED = ("reinject.txt",)                     # kept with xz
ANALYSED = ("orifice_timeseries.md",)          # from the analysis' runs/<label>/
# Fields left out of the archive: the pages, the maps (analysis.silo3d_rotating.maps)
# and the orifice tables use the stress tensors' traces, the kinetic and
# contact pressures, which are kept; the two tensors were half of a rods
# run's archive (doc/data/README.md, "Size").
DROPPED_FIELDS = ("kinetic_stress", "contact_stress")


def run_label(info):
    """The name analysis.silo3d_rotating.analyse gives the run's directory under
    OUT/runs (silo3d_flow.run_labels, without its suffix for twins)."""
    return f"f{info['f']:g}_D{info['D'] * 1e3:g}mm_seed{info['seed']:.0f}"


def pack_fields(source, target):
    """fields.npz with its fields (the arrays `<name>_<window>`) as float32,
    those of DROPPED_FIELDS left out: the map means changed by < 1e-7 of
    each field's scale; the grid and windows as they are. Source and target
    may be the same file (an archive packed again)."""
    with np.load(source) as stored:
        arrays = {key: stored[key] for key in stored.files if map_field(key) not in DROPPED_FIELDS}
    for key, values in arrays.items():
        if map_field(key) is not None and values.dtype == np.float64:
            arrays[key] = values.astype(np.float32)
    np.savez_compressed(target, **arrays)


def archive(run_dir, archive_dir, analysis_dir=None, fields=True):
    """Writes the archive of a finished run (the module's docstring), with
    the analysis' fields.npz if `fields`; returns the names of the files it
    holds."""
    run_dir, archive_dir = Path(run_dir), Path(archive_dir)
    if not (run_dir / "run.txt").exists():
        raise ValueError(f"{run_dir}: no run.txt, not a run directory")
    info = read_run_info(run_dir, required=("D", "f", "seed"))
    if "finished" not in info:         # the deck's last act (silo3d_records.Run.finished)
        raise ValueError(f"{run_dir}: unfinished (run.txt has no 'finished' line); "
                         "analysis.campaign.silo3d_carry keep carries a run that is to go on")
    if archive_dir.exists() and (archive_dir.resolve() == run_dir.resolve() or any(archive_dir.iterdir())):
        raise ValueError(f"{archive_dir}: not empty; an archive goes into a new directory")
    analysed = None
    if analysis_dir is not None:
        analysed = Path(analysis_dir) / "runs" / run_label(info)
        if not analysed.is_dir():
            raise ValueError(f"{analysis_dir}: no runs/{run_label(info)}: not an analysis of {run_dir}")
    archive_dir.mkdir(parents=True, exist_ok=True)
    for name in RECORDS:
        if (run_dir / name).exists():
            shutil.copyfile(run_dir / name, archive_dir / name)
    for name in PACKED:
        if (run_dir / name).exists():
            with open(run_dir / name, "rb") as source, lzma.open(archive_dir / f"{name}.xz", "wb", preset=9) as packed:
                shutil.copyfileobj(source, packed)
    if analysed is not None:
        for name in ANALYSED:
            if (analysed / name).exists():
                shutil.copyfile(analysed / name, archive_dir / name)
        if fields and (analysed / "fields.npz").exists():
            pack_fields(analysed / "fields.npz", archive_dir / "fields.npz")
    return sorted(path.name for path in archive_dir.iterdir())


def main(argv=None):
    parser = command_line("analysis.campaign.silo3d_archive", __doc__,
                          "/usr/bin/python3 -m analysis.campaign.silo3d_archive "
                          "runs/rods_fig2c/D0.06_f0.16_s32452843 "
                          "doc/data/silo3d_rods_fig2c/D0.06_f0.16_s32452843 --analysis runs/rods_fig2c/analysis")
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("archive_dir", type=Path)
    parser.add_argument("--analysis", type=Path, metavar="OUT",
                        help="an analysis.silo3d_rotating --out directory that analysed RUN_DIR: its "
                             "runs/<label>/orifice_timeseries.md and fields.npz go into the archive")
    parser.add_argument("--no-fields", action="store_true",
                        help="leave the analysis' fields.npz (the maps) out: a campaign whose pages use "
                             "the flow rate and the orifice tables only")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        names = archive(args.run_dir, args.archive_dir, args.analysis, not args.no_fields)
    except ValueError as error:
        print(f"silo3d_archive: ERROR: {error}", file=sys.stderr)
        return 2
    print(f"silo3d_archive: {args.run_dir} -> {args.archive_dir}: {', '.join(names)} "
          "(no dumps, checkpoints or restarts)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
