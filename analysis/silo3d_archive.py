"""A compact copy of a finished rotating-bottom silo run, for doc/data:
what the flow-rate analysis and the orifice averages need, in a few per
cent of the space.

The archive keeps run.txt, discharge.txt and reinject.txt as they are
(small), and dump.cg.xz: the frames of dump.cg with only the grains inside
cylinders about the z axis (r < R and z < Z), compressed with xz. The
orifice region, r < 6 cm and z < 5 cm, is always kept: it holds the
orifice cylinder (radius D/2, 1 cm high) with the reach of the default
kernel (4 w, w = d*/2: 2 cm for the spheres and the L/d = 3.3 rods), so
the orifice averages, for D up to 8 cm; more cylinders can be added. A
run whose orifice cylinder with that reach sticks out of the kept ones
gets a warning. Neither the maps nor dump.contacts are kept (no contact
stress from an archive); dump_cut.txt names the cylinders, and the
analysis makes no maps from an archive. Once unpacked (`xz -dk dump.cg.xz`),
`analysis.silo3d_rotating` reads an archive as it reads a run directory;
`analysis.silo3d_acceleration` too, when the column over the axis is
added (`--dump-cylinder 0.025 0.2`).

A run whose run.txt has no `finished` line is refused: its records are
cut at a checkpoint or still growing (`analysis.checkpoint keep` keeps an
unfinished run so that it can go on elsewhere).

CLI:  python3 -m analysis.silo3d_archive RUN_DIR ARCHIVE_DIR [--dump-cylinder R Z ...]
"""

import argparse
import lzma
import shutil
import sys
from pathlib import Path

from analysis import coarse_grain as cg
from analysis.checkpoint import frames_in_cylinder
from analysis.silo3d_fields import FieldSettings
from analysis.silo3d_records import DumpCut, read_run_info, write_dump_cut

RECORDS = ("run.txt", "discharge.txt", "reinject.txt")
ORIFICE_REGION = (0.06, 0.05)
ORIFICE_HEIGHT = FieldSettings.orifice_height     # the analysis' default (--orifice-height)


def orifice_reach(info):
    """(r, z) that the orifice averages read grains within: the orifice
    cylinder with the default kernel's cutoff around it."""
    reach = cg.default_kernel([info["mass"]], info["rho"]).cutoff
    return 0.5 * info["D"] + reach, ORIFICE_HEIGHT + reach


def archive(run_dir, archive_dir, more=()):
    """Writes the archive of a finished run (the module's docstring) with
    the orifice region and the `more` cylinders, (R, Z) pairs; returns the
    number of frames of its dump (0 without dump.cg) and a warning or None."""
    run_dir, archive_dir = Path(run_dir), Path(archive_dir)
    if not (run_dir / "run.txt").exists():
        raise ValueError(f"{run_dir}: no run.txt, not a run directory")
    info = read_run_info(run_dir, required=("D", "mass", "rho"))
    if "finished" not in info:         # the deck's last act (silo3d_records.Run.finished)
        raise ValueError(f"{run_dir}: unfinished (run.txt has no 'finished' line); "
                         "analysis.checkpoint keep keeps a run that is to go on")
    if archive_dir.exists() and (archive_dir.resolve() == run_dir.resolve() or any(archive_dir.iterdir())):
        raise ValueError(f"{archive_dir}: not empty; an archive goes into a new directory")
    cylinders = [ORIFICE_REGION, *more]
    radius, top = orifice_reach(info)
    warning = None
    if not DumpCut(cylinders=tuple(cylinders)).holds(radius, top):
        warning = (f"the orifice averages read grains within r < {radius:.3g} m, z < {top:.3g} m, "
                   "beyond the kept cylinders: the archive's averages will differ from the run's")
    archive_dir.mkdir(parents=True, exist_ok=True)
    for name in RECORDS:
        if (run_dir / name).exists():
            shutil.copyfile(run_dir / name, archive_dir / name)
    if not (run_dir / "dump.cg").exists():
        return 0, warning
    write_dump_cut(archive_dir, cylinders)     # every frame cut: the analysis makes no maps of it
    count = 0
    with open(run_dir / "dump.cg") as handle, lzma.open(archive_dir / "dump.cg.xz", "wt", preset=9) as packed:
        for frame in dump_frames(handle):
            kept = frames_in_cylinder(frame, *cylinders[0], *cylinders[1:])
            packed.writelines(kept)
            count += bool(kept)
    return count, warning


def dump_frames(handle):
    """The lines of a `dump custom` file frame by frame (9 header lines and
    the rows), so that a dump of some hundred MB is never held whole; a
    frame cut short comes last, as it is."""
    while True:
        head = [line for line in (handle.readline() for _ in range(9)) if line]
        if not head:
            return
        rows = int(head[3]) if len(head) > 3 and head[3].strip().isdigit() else 0
        yield head + [line for line in (handle.readline() for _ in range(rows)) if line]


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m analysis.silo3d_archive", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("archive_dir", type=Path)
    parser.add_argument("--dump-cylinder", nargs=2, type=float, action="append", default=[], metavar=("R", "Z"),
                        help="also keep the grains with r < R and z < Z (m) about the z axis; may be repeated "
                             f"(the orifice region, {ORIFICE_REGION[0]:g} {ORIFICE_REGION[1]:g}, is always kept)")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    more = [tuple(c) for c in args.dump_cylinder]
    for radius, top in more:
        if not radius > 0:
            parser.error(f"--dump-cylinder {radius:g} {top:g}: the radius must be > 0 m")
    cylinders = [ORIFICE_REGION, *more]
    try:
        frames, warning = archive(args.run_dir, args.archive_dir, more)
    except ValueError as error:
        print(f"silo3d_archive: ERROR: {error}", file=sys.stderr)
        return 2
    if warning:
        print(f"silo3d_archive: WARNING: {args.run_dir}: {warning}")
    print(f"silo3d_archive: {args.run_dir} -> {args.archive_dir} ({frames} dump frames, grains within "
          + " or ".join(f"r < {r:g} m, z < {z:g} m" for r, z in cylinders) + ")")
    return 0


if __name__ == "__main__":
    sys.exit(main())
