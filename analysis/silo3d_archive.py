"""A compact copy of a finished rotating-bottom silo run, for doc/data:
what the flow-rate analysis and the orifice averages need, in a few per
cent of the space.

The archive keeps run.txt, discharge.txt and reinject.txt as they are
(small), and dump.cg.xz: the frames of dump.cg with only the grains inside
the given cylinders about the z axis (r < R and z < Z; by default the
orifice region, r < 6 cm and z < 5 cm, which holds the orifice cylinder,
1 cm high, of every D up to 8 cm with the reach of the rods' kernel, 4 w
= 2 cm: the orifice averages, but not the maps), compressed with xz. dump.contacts is not kept (no contact
stress from an archive). Once unpacked (`xz -dk dump.cg.xz`),
`analysis.silo3d_rotating` reads an archive as it reads a run directory;
`analysis.silo3d_acceleration` too, when the column over the axis is kept
(`--dump-cylinder 0.025 0.2` added).

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

from analysis.checkpoint import frames_in_cylinder

RECORDS = ("run.txt", "discharge.txt", "reinject.txt")
ORIFICE_REGION = (0.06, 0.05)


def is_finished(run_dir):
    """The deck writes a `finished` line into run.txt when its discharge ends."""
    with open(Path(run_dir) / "run.txt") as handle:
        return any(line.split()[:1] == ["finished"] for line in handle)


def archive(run_dir, archive_dir, cylinders=(ORIFICE_REGION,)):
    """Writes the archive of a finished run (the module's docstring);
    returns the number of frames of its dump (0 without dump.cg)."""
    run_dir, archive_dir = Path(run_dir), Path(archive_dir)
    if not (run_dir / "run.txt").exists():
        raise ValueError(f"{run_dir}: no run.txt, not a run directory")
    if not is_finished(run_dir):
        raise ValueError(f"{run_dir}: unfinished (run.txt has no 'finished' line); "
                         "analysis.checkpoint keep keeps a run that is to go on")
    if not cylinders:
        raise ValueError("at least one cylinder (R, Z) is needed")
    archive_dir.mkdir(parents=True, exist_ok=True)
    for name in RECORDS:
        if (run_dir / name).exists():
            shutil.copyfile(run_dir / name, archive_dir / name)
    if not (run_dir / "dump.cg").exists():
        return 0
    with open(run_dir / "dump.cg") as handle:
        frames = frames_in_cylinder(handle.readlines(), *cylinders[0], *cylinders[1:])
    with lzma.open(archive_dir / "dump.cg.xz", "wt", preset=9) as packed:
        packed.writelines(frames)
    return sum(line.startswith("ITEM: TIMESTEP") for line in frames)


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m analysis.silo3d_archive", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("archive_dir", type=Path)
    parser.add_argument("--dump-cylinder", nargs=2, type=float, action="append", metavar=("R", "Z"),
                        help="keep the grains with r < R and z < Z (m) about the z axis; may be repeated "
                             f"(a grain inside any is kept); default {ORIFICE_REGION[0]:g} {ORIFICE_REGION[1]:g}")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    cylinders = [tuple(c) for c in args.dump_cylinder] if args.dump_cylinder else [ORIFICE_REGION]
    for radius, top in cylinders:
        if not radius > 0:
            parser.error(f"--dump-cylinder {radius:g} {top:g}: the radius must be > 0 m")
    try:
        frames = archive(args.run_dir, args.archive_dir, cylinders)
    except ValueError as error:
        print(f"silo3d_archive: ERROR: {error}", file=sys.stderr)
        return 2
    print(f"silo3d_archive: {args.run_dir} -> {args.archive_dir} ({frames} dump frames, grains within "
          + " or ".join(f"r < {r:g} m, z < {z:g} m" for r, z in cylinders) + ")")
    return 0


if __name__ == "__main__":
    sys.exit(main())
