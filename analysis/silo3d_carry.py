"""Carrying a campaign of the rotating-bottom silo from one machine to the
next, through the repository.

A session's files may not outlive it (each session can start on a new
machine, and a run of 8 s of rods outlasts a session), so between sessions
a campaign lives in a store directory of the repository (e.g.
doc/data/silo3d_rods_fig2c):

    STORE/<run>/        each finished run's archive (analysis.silo3d_archive:
                        records and the dump's orifice region) and its
                        screen.txt.xz (the loop times: the run's cost)
    STORE/kept/<run>/   each unfinished run's last checkpoint and its records
                        up to it (analysis.checkpoint keep), and screen.txt.xz

    python3 -m analysis.silo3d_carry keep RUN_DIR STORE [--dump-cylinder R Z ...]
        At a session's end: archives the finished runs of RUN_DIR that STORE
        lacks (dropping their kept checkpoint), and keeps the last checkpoint
        of every unfinished one, in place of the one kept before. Safe
        while the runs go on (a checkpoint is listed once it is whole, and
        the records are cut back to it).
    python3 -m analysis.silo3d_carry restore STORE RUN_DIR [--also ARCHIVE ...]
        On the next machine: puts each archive (STORE's and the --also
        ones, archives of the same protocol kept elsewhere in doc/data)
        into RUN_DIR as a finished run (dump unpacked, run.sh's `finished`
        file, `archived_in` saying where from), and restores each kept run
        that is not archived, so that run.sh, given the campaign's
        variables and PACKINGS, skips the first and resumes the second.

--dump-cylinder: cylinders about the z axis whose grains the dumps keep
besides the orifice region (r < 6 cm, z < 5 cm); e.g. `0.025 0.2`, the
column over the axis of the axial acceleration (analysis.silo3d_acceleration).
The maps need the whole dump: they are not carried.
"""

import argparse
import lzma
import shutil
import sys
from pathlib import Path

from analysis import checkpoint
from analysis import silo3d_archive
from analysis.silo3d_records import read_run_info

KEPT = "kept"
MARK = "archived_in"      # in RUN_DIR: this finished run came from that archive


def run_dirs(directory):
    return sorted(p for p in Path(directory).glob("D*_f*_s*") if (p / "run.txt").exists())


def pack_screen(run_dir, target_dir):
    if (run_dir / "screen.txt").exists():
        with open(run_dir / "screen.txt", "rb") as source, lzma.open(target_dir / "screen.txt.xz", "wb") as packed:
            shutil.copyfileobj(source, packed)


def keep(run_dir, store, more=()):
    """Archives or keeps each run of run_dir into store; returns one line per run."""
    store = Path(store)
    cylinders = [silo3d_archive.ORIFICE_REGION, *more]
    lines = []
    for run in run_dirs(run_dir):
        archived, kept = store / run.name, store / KEPT / run.name
        if (run / MARK).exists():
            continue                               # restored from an archive
        if "finished" in read_run_info(run):
            if archived.exists():
                lines.append(f"{run.name}: archived before")
                continue
            partial = archived.with_name(archived.name + ".part")
            shutil.rmtree(partial, ignore_errors=True)
            frames, warning = silo3d_archive.archive(run, partial, more)
            pack_screen(run, partial)
            partial.rename(archived)
            shutil.rmtree(kept, ignore_errors=True)
            lines.append(f"{run.name}: finished, archived ({frames} dump frames)"
                         + (f"; WARNING: {warning}" if warning else ""))
            continue
        if checkpoint.last_checkpoint(run) is None:
            lines.append(f"{run.name}: no checkpoint yet, nothing kept")
            continue
        partial = kept.with_name(kept.name + ".part")
        shutil.rmtree(partial, ignore_errors=True)
        step = checkpoint.keep(run, partial, cylinders)
        pack_screen(run, partial)
        shutil.rmtree(kept, ignore_errors=True)
        partial.rename(kept)
        info = read_run_info(run, required=("dt", "t_open", "step_open"))
        t = (step - info["step_open"]) * info["dt"]
        lines.append(f"{run.name}: unfinished, kept at its checkpoint of step {step} ({t:.2f} s of discharge)")
    return lines


def restore(store, run_dir, also=()):
    """Puts the archives and kept runs of store (and the `also` archives)
    into run_dir; returns one line per run."""
    store, run_dir = Path(store), Path(run_dir)
    lines = []
    archives = run_dirs(store) + [Path(a) for a in also]
    names = [a.name for a in archives]
    duplicates = sorted({name for name in names if names.count(name) > 1})
    if duplicates:
        raise ValueError("two archives of the same run: " + ", ".join(duplicates))
    for archive in archives:       # all checked before any is copied
        if "finished" not in read_run_info(archive):
            raise ValueError(f"{archive}: run.txt has no 'finished' line: not a finished run's archive")
    run_dir.mkdir(parents=True, exist_ok=True)
    for archive in archives:
        target = run_dir / archive.name
        if target.exists():
            lines.append(f"{archive.name}: in {run_dir} already, left as it is")
            continue
        checkpoint.restore(archive, target)       # copies, unpacking the .xz files
        (target / MARK).write_text(f"{archive.resolve()}\n")
        (target / "finished").touch()
        lines.append(f"{archive.name}: finished, from {archive}")
    for kept in run_dirs(store / KEPT):
        target = run_dir / kept.name
        if kept.name in names:
            lines.append(f"{kept.name}: kept checkpoint ignored, the run is archived")
        elif target.exists():
            lines.append(f"{kept.name}: in {run_dir} already, left as it is")
        else:
            checkpoint.restore(kept, target)
            step, _ = checkpoint.last_checkpoint(target)
            lines.append(f"{kept.name}: unfinished, restored at its checkpoint of step {step}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m analysis.silo3d_carry", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    actions = parser.add_subparsers(dest="action", required=True)
    keeping = actions.add_parser("keep", help="archive the finished runs, keep the unfinished ones' checkpoints")
    keeping.add_argument("run_dir", type=Path)
    keeping.add_argument("store", type=Path)
    keeping.add_argument("--dump-cylinder", nargs=2, type=float, action="append", default=[],
                         metavar=("R", "Z"), help="also keep the dumps' grains with r < R and z < Z (m)")
    restoring = actions.add_parser("restore", help="put the store's runs into a run directory")
    restoring.add_argument("store", type=Path)
    restoring.add_argument("run_dir", type=Path)
    restoring.add_argument("--also", nargs="+", type=Path, default=[], metavar="ARCHIVE",
                           help="more finished runs' archives (analysis.silo3d_archive)")
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        if args.action == "keep":
            if not args.run_dir.is_dir():
                raise ValueError(f"{args.run_dir}: no such directory")
            for radius, top in args.dump_cylinder:
                if not radius > 0:
                    raise ValueError(f"--dump-cylinder {radius:g} {top:g}: the radius must be > 0 m")
            lines = keep(args.run_dir, args.store, [tuple(c) for c in args.dump_cylinder])
        else:
            lines = restore(args.store, args.run_dir, args.also)
    except (ValueError, FileNotFoundError) as error:
        print(f"silo3d_carry: ERROR: {error}", file=sys.stderr)
        return 2
    for line in lines or ["no runs"]:
        print(f"silo3d_carry: {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
