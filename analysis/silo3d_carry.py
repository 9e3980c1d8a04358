"""Carrying a campaign of the rotating-bottom silo from one machine to the
next, through the repository.

A session's files may not outlive it (each session can start on a new
machine, and a run of 8 s of rods outlasts a session). Between sessions a
campaign lives in two places of the repository:

    STORE/<run>/            each finished run's reduced records
                            (analysis.silo3d_archive: run.txt, discharge.txt,
                            reinject.txt.xz and, when the run was analysed,
                            orifice_timeseries.md and fields.npz) and its
                            screen.txt.xz (the loop times: the run's cost).
                            STORE is in doc/data (e.g.
                            doc/data/silo3d_rods_fig2c): no dumps there.
    carry/<campaign>/<run>/ each UNFINISHED run's last checkpoint, its
                            records up to it, its dump's frames before it
                            (the orifice region and the --dump-cylinder
                            ones) and screen.txt.xz (analysis.checkpoint
                            keep). <campaign> is STORE's name; carry/ is at
                            the top of the git work tree that holds STORE
                            (beside STORE outside one); --carry DIR
                            chooses another. It is emptied as the runs
                            finish: a campaign that has ended carries
                            nothing.

    python3 -m analysis.silo3d_carry keep RUN_DIR STORE [--dump-cylinder R Z ...]
            [--analysis OUT] [--carry DIR]
        Archives the finished runs of RUN_DIR that STORE lacks (with the
        tables and fields of OUT/runs/<label>/, OUT being RUN_DIR/analysis
        by default, when that analysis holds the run), removing their
        carried checkpoint, and carries the last checkpoint of every
        unfinished one, in place of the one carried before. Safe while the
        runs go on (a checkpoint is listed once it is whole, and the
        records are cut back to it).
    python3 -m analysis.silo3d_carry restore STORE RUN_DIR [--also ARCHIVE ...] [--carry DIR]
        On the next machine: puts each archive (STORE's and the --also
        ones, archives of the same protocol kept elsewhere in doc/data)
        into RUN_DIR as a finished run (its records, run.sh's `finished`
        file, `archived_in` saying where from), and restores each carried
        run that is not archived, so that run.sh, given the campaign's
        variables and PACKINGS, skips the first and resumes the second.

--dump-cylinder: cylinders about the z axis whose grains a carried run's
dump keeps besides the orifice region (r < 6 cm, z < 5 cm); e.g.
`0.025 0.2`, the column over the axis of the axial acceleration
(analysis.silo3d_acceleration). A finished run's dump is not kept: analyse
the run (analysis.silo3d_rotating RUN_DIR/D* --out RUN_DIR/analysis ...)
before `keep` archives it.
"""

import argparse
import lzma
import shutil
import sys
from pathlib import Path

from analysis import checkpoint
from analysis import silo3d_archive
from analysis.silo3d_records import read_run_info

CARRY = "carry"
MARK = "archived_in"      # in RUN_DIR: this finished run came from that archive
ORIFICE_REGION = (0.06, 0.05)   # r < 6 cm, z < 5 cm: the orifice averages for D up to 8 cm


def run_dirs(directory):
    return sorted(p for p in Path(directory).glob("D*_f*_s*") if (p / "run.txt").exists())


def carry_dir(store):
    """Where the unfinished runs of STORE's campaign are carried:
    carry/<STORE's name> at the top of the git work tree that holds STORE,
    or beside STORE (STORE/../carry/<name>) outside one."""
    store = Path(store).resolve()
    top = next((p for p in store.parents if (p / ".git").exists()), store.parent)
    return top / CARRY / store.name


def pack_screen(run_dir, target_dir):
    if (run_dir / "screen.txt").exists():
        with open(run_dir / "screen.txt", "rb") as source, lzma.open(target_dir / "screen.txt.xz", "wb") as packed:
            shutil.copyfileobj(source, packed)


def drop_carried(carried):
    """Removes a finished run's carried checkpoint, and the campaign's carry
    directory once it holds nothing."""
    shutil.rmtree(carried, ignore_errors=True)
    for directory in (carried.parent, carried.parent.parent):
        if directory.is_dir() and not any(directory.iterdir()):
            directory.rmdir()


def keep(run_dir, store, more=(), analysis=None, carry=None):
    """Archives or carries each run of run_dir (store: the finished runs'
    archives; carry: the unfinished ones', carry_dir(store) by default;
    analysis: an analysis.silo3d_rotating --out directory, run_dir/analysis
    by default); returns one line per run."""
    run_dir, store = Path(run_dir), Path(store)
    carry = Path(carry) if carry is not None else carry_dir(store)
    analysis = Path(analysis) if analysis is not None else run_dir / "analysis"
    cylinders = [ORIFICE_REGION, *more]
    lines = []
    for run in run_dirs(run_dir):
        archived, carried = store / run.name, carry / run.name
        if (run / MARK).exists():
            continue                               # restored from an archive
        info = read_run_info(run)
        if "finished" in info:
            if archived.exists():
                lines.append(f"{run.name}: archived before")
                drop_carried(carried)
                continue
            analysed = (analysis if (analysis / "runs" / silo3d_archive.run_label(info)).is_dir()
                        else None)
            partial = archived.with_name(archived.name + ".part")
            shutil.rmtree(partial, ignore_errors=True)
            names = silo3d_archive.archive(run, partial, analysed)
            pack_screen(run, partial)
            partial.rename(archived)
            drop_carried(carried)
            lines.append(f"{run.name}: finished, archived (" + ", ".join(names) + ")"
                         + ("" if analysed else f"; no analysis of it in {analysis}: no orifice table, no fields"))
            continue
        if checkpoint.last_checkpoint(run) is None:
            lines.append(f"{run.name}: no checkpoint yet, nothing carried")
            continue
        partial = carried.with_name(carried.name + ".part")
        shutil.rmtree(partial, ignore_errors=True)
        partial.parent.mkdir(parents=True, exist_ok=True)
        step = checkpoint.keep(run, partial, cylinders)
        pack_screen(run, partial)
        shutil.rmtree(carried, ignore_errors=True)
        partial.rename(carried)
        info = read_run_info(run, required=("dt", "t_open", "step_open"))
        t = (step - info["step_open"]) * info["dt"]
        lines.append(f"{run.name}: unfinished, kept at its checkpoint of step {step} ({t:.2f} s of discharge) "
                     f"in {carry}")
    return lines


def restore(store, run_dir, also=(), carry=None):
    """Puts the archives of store (and the `also` archives) and the runs
    carried in carry (carry_dir(store) by default) into run_dir; returns
    one line per run."""
    store, run_dir = Path(store), Path(run_dir)
    carry = Path(carry) if carry is not None else carry_dir(store)
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
    for carried in run_dirs(carry):
        target = run_dir / carried.name
        if carried.name in names:
            lines.append(f"{carried.name}: carried checkpoint ignored, the run is archived")
        elif target.exists():
            lines.append(f"{carried.name}: in {run_dir} already, left as it is")
        else:
            checkpoint.restore(carried, target)
            step, _ = checkpoint.last_checkpoint(target)
            lines.append(f"{carried.name}: unfinished, restored at its checkpoint of step {step}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m analysis.silo3d_carry", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    actions = parser.add_subparsers(dest="action", required=True)
    carry_help = ("where the unfinished runs are carried [carry/<STORE's name> at the top of the git "
                  "work tree that holds STORE]")
    keeping = actions.add_parser("keep", help="archive the finished runs, carry the unfinished ones' checkpoints")
    keeping.add_argument("run_dir", type=Path)
    keeping.add_argument("store", type=Path)
    keeping.add_argument("--dump-cylinder", nargs=2, type=float, action="append", default=[],
                         metavar=("R", "Z"), help="an unfinished run's dump also keeps its grains with "
                                                  "r < R and z < Z (m)")
    keeping.add_argument("--analysis", type=Path, metavar="OUT",
                         help="the analysis.silo3d_rotating --out directory of the runs [RUN_DIR/analysis]")
    keeping.add_argument("--carry", type=Path, metavar="DIR", help=carry_help)
    restoring = actions.add_parser("restore", help="put the store's and the carried runs into a run directory")
    restoring.add_argument("store", type=Path)
    restoring.add_argument("run_dir", type=Path)
    restoring.add_argument("--also", nargs="+", type=Path, default=[], metavar="ARCHIVE",
                           help="more finished runs' archives (analysis.silo3d_archive)")
    restoring.add_argument("--carry", type=Path, metavar="DIR", help=carry_help)
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        if args.action == "keep":
            if not args.run_dir.is_dir():
                raise ValueError(f"{args.run_dir}: no such directory")
            for radius, top in args.dump_cylinder:
                if not radius > 0:
                    raise ValueError(f"--dump-cylinder {radius:g} {top:g}: the radius must be > 0 m")
            lines = keep(args.run_dir, args.store, [tuple(c) for c in args.dump_cylinder],
                         args.analysis, args.carry)
        else:
            lines = restore(args.store, args.run_dir, args.also, args.carry)
    except (ValueError, FileNotFoundError) as error:
        print(f"silo3d_carry: ERROR: {error}", file=sys.stderr)
        return 2
    for line in lines or ["no runs"]:
        print(f"silo3d_carry: {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
