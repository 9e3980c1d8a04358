"""Carrying a campaign of the rotating-bottom silo from one machine to the
next, through the repository.

A session's files may not outlive it (each session can start on a new
machine, and a run of 8 s of rods outlasts a session). Between sessions a
campaign lives in two places of the repository:

    STORE/<run>/            each finished run's reduced records
                            (analysis.campaign.silo3d_archive: run.txt, discharge.txt,
                            reinject.txt.xz and, when the run was analysed,
                            orifice_timeseries.md and fields.npz) and its
                            screen.txt.xz (the loop times: the run's cost).
                            STORE is in doc/data (e.g.
                            doc/data/silo3d_rods_fig2c): no dumps there.
    carry/<campaign>/<run>/ each UNFINISHED run's last checkpoint, its
                            records up to it, its dump's frames before it
                            (the orifice region and the --dump-cylinder
                            ones) and screen.txt.xz (analysis.campaign.checkpoint
                            keep). <campaign> is STORE's name; carry/ is at
                            the top of the git work tree that holds STORE
                            (beside STORE outside one); --carry DIR
                            chooses another. It is emptied as the runs
                            finish: a campaign that has ended carries
                            nothing.
    carry/<campaign>/packings/
                            the campaign's settled packings
                            (packing_s<seed>.restart.xz and its _run.txt,
                            _screen.txt: run.sh's PACKINGS reads them), and
    carry/<campaign>/settling_s<seed>/
                            a settling cut short (run.sh's SETTLE_CHECKPOINT):
                            its last checkpoint. `drop-packings` removes the
                            packings when the campaign's runs are all done.

    python3 -m analysis.campaign.silo3d_carry keep RUN_DIR STORE [--dump-cylinder R Z ...]
            [--analysis OUT] [--carry DIR] [--no-fields]
        Archives the finished runs of RUN_DIR that STORE lacks (with the
        tables and fields of OUT/runs/<label>/, OUT being RUN_DIR/analysis
        by default, when that analysis holds the run; --no-fields: the
        tables only, for a campaign that uses no maps), removing their
        carried checkpoint, and carries the last checkpoint of every
        unfinished one, in place of the one carried before. Safe while the
        runs go on (a checkpoint is listed once it is whole, and the
        records are cut back to it). A run made longer than its archive
        (run.sh with a larger DISCHARGE) is carried while it goes on and
        replaces its archive when it has finished.
    python3 -m analysis.campaign.silo3d_carry reopen STORE RUN_DIR --length F T [--length F T ...] [--carry DIR]
        After `restore`: each run of RUN_DIR restored from an archive
        whose discharge is shorter than T s, its frequency being F Hz (a
        protocol made longer), is replaced by its newest carried folder
        in the git history (its last checkpoint before it finished, and
        its records up to it), from which run.sh goes on to the new
        length. A run never carried (it finished within one session) is
        emptied instead, so that run.sh runs it again from its packing;
        its archive stays in STORE until the longer run replaces it.
    python3 -m analysis.campaign.silo3d_carry to-analyse RUN_DIR STORE [--analysis OUT]
        Prints the finished runs of RUN_DIR whose orifice tables and fields
        are still to make: neither restored from nor kept in an archive,
        nor analysed into OUT (RUN_DIR/analysis) since they finished.
    python3 -m analysis.campaign.silo3d_carry carry-dir STORE
        Prints where STORE's campaign carries its runs and packings.
    python3 -m analysis.campaign.silo3d_carry drop-packings STORE [--carry DIR]
        Removes the carried packings once the campaign's runs are done.
    python3 -m analysis.campaign.silo3d_carry restore STORE RUN_DIR [--also ARCHIVE ...] [--carry DIR]
        On the next machine: puts each archive (STORE's and the --also
        ones, archives of the same protocol kept elsewhere in doc/data)
        into RUN_DIR as a finished run (its records, run.sh's `finished`
        file, `archived_in` saying where from), and restores each carried
        run that is not archived, or is made longer than its archive, so
        that run.sh, given the campaign's variables and PACKINGS, skips the
        first and resumes the second.

--dump-cylinder: cylinders about the z axis whose grains a carried run's
dump keeps besides the orifice region (r < 6 cm, z < 5 cm); e.g.
`0.025 0.2`, the column over the axis of the axial acceleration
(analysis.silo3d_rotating.acceleration). A finished run's dump is not kept: analyse
the run (analysis.silo3d_rotating RUN_DIR/D* --out RUN_DIR/analysis ...)
before `keep` archives it.
"""

import io
import lzma
import shutil
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

from analysis.campaign import checkpoint
from analysis.campaign import silo3d_archive
from analysis.silo3d_rotating.records import read_run_info
from analysis.common.cli import command_line

CARRY = "carry"
MARK = "archived_in"      # in RUN_DIR: this finished run came from that archive
ORIFICE_REGION = (0.06, 0.05)   # r < 6 cm, z < 5 cm: the orifice averages for D up to 8 cm


PACKINGS = "packings"


def discharge_time(run):
    """The run's discharge_time, s, or None: run.txt's last line of the key
    (a run made longer says its new end there)."""
    value = read_run_info(run, required=()).get("discharge_time")
    return None if value is None else float(value)


def made_longer(run, archived):
    """Whether run (a run directory or a carried one) goes on past the end
    of its archive in the store."""
    if not archived.exists():
        return False
    ends = discharge_time(run), discharge_time(archived)
    return None not in ends and ends[0] > ends[1]


def run_dirs(directory):
    return sorted(p for p in Path(directory).glob("D*_f*_s*") if (p / "run.txt").exists())


def packing_dirs(directory):
    return sorted(p for p in Path(directory).glob("packing_s*") if p.is_dir())


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


def carry_checkpoint(run, carried, cylinders=None):
    """Writes run's last checkpoint and its records up to it into `carried`
    (analysis.campaign.checkpoint.keep) through a .part folder, so that a carry cut
    short leaves the one before whole; returns the checkpoint's step."""
    partial = carried.with_name(carried.name + ".part")
    shutil.rmtree(partial, ignore_errors=True)
    partial.parent.mkdir(parents=True, exist_ok=True)
    step = checkpoint.keep(run, partial, cylinders)
    pack_screen(run, partial)
    shutil.rmtree(carried, ignore_errors=True)
    partial.rename(carried)
    return step


def drop_carried(carried):
    """Removes a finished run's carried checkpoint, and the campaign's carry
    directory once it holds nothing."""
    shutil.rmtree(carried, ignore_errors=True)
    for directory in (carried.parent, carried.parent.parent):
        if directory.is_dir() and not any(directory.iterdir()):
            directory.rmdir()


def to_analyse(run_dir, store, analysis=None):
    """The finished runs of run_dir whose fields analysis.silo3d_rotating
    has still to make: not restored from an archive (MARK), not archived in
    store yet, and with no orifice table in `analysis` (run_dir/analysis by
    default) written since the run finished. The others are not read
    again: a 4 s dump of 22 500 rods takes some 10 minutes to analyse."""
    run_dir, store = Path(run_dir), Path(store)
    analysis = Path(analysis) if analysis is not None else run_dir / "analysis"
    pending = []
    for run in run_dirs(run_dir):
        info = read_run_info(run, required=())
        if "finished" not in info or (run / MARK).exists():
            continue
        if (store / run.name).exists() and not made_longer(run, store / run.name):
            continue
        table = analysis / "runs" / silo3d_archive.run_label(info) / "orifice_timeseries.txt"
        finished = run / "finished" if (run / "finished").exists() else run / "run.txt"
        if not table.exists() or table.stat().st_mtime < finished.stat().st_mtime:
            pending.append(run)
    return pending


def keep(run_dir, store, more=(), analysis=None, carry=None, fields=True):
    """Archives or carries each run of run_dir (store: the finished runs'
    archives, with their maps' fields.npz if `fields`; carry: the unfinished
    ones', carry_dir(store) by default; analysis: an analysis.silo3d_rotating
    --out directory, run_dir/analysis by default); returns one line per run."""
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
            replaced = made_longer(run, archived)
            if archived.exists() and not replaced:
                lines.append(f"{run.name}: archived before")
                drop_carried(carried)
                continue
            analysed = (analysis if (analysis / "runs" / silo3d_archive.run_label(info)).is_dir()
                        else None)
            partial = archived.with_name(archived.name + ".part")
            shutil.rmtree(partial, ignore_errors=True)
            names = silo3d_archive.archive(run, partial, analysed, fields)
            pack_screen(run, partial)
            if replaced:      # the shorter archive goes only once the longer one is whole
                shorter = archived.with_name(archived.name + ".shorter")
                shutil.rmtree(shorter, ignore_errors=True)
                archived.rename(shorter)
                partial.rename(archived)
                shutil.rmtree(shorter)
            else:
                partial.rename(archived)
            drop_carried(carried)
            lines.append(f"{run.name}: finished, archived (" + ", ".join(names) + ")"
                         + (" in place of the shorter archive" if replaced else "")
                         + ("" if analysed else f"; no analysis of it in {analysis}: no orifice table, no fields"))
            continue
        if checkpoint.last_checkpoint(run) is None:
            lines.append(f"{run.name}: no checkpoint yet, nothing carried")
            continue
        step = carry_checkpoint(run, carried, cylinders)
        info = read_run_info(run, required=("dt", "t_open", "step_open"))
        t = (step - info["step_open"]) * info["dt"]
        lines.append(f"{run.name}: unfinished, kept at its checkpoint of step {step} ({t:.2f} s of discharge) "
                     f"in {carry}")
    return lines + keep_packings(run_dir, carry)


def keep_packings(run_dir, carry):
    """Carries run_dir's packings: a settled one (run.sh wrote `finished`)
    into carry/packings in the form run.sh's PACKINGS reads, once; a
    settling cut short at its last checkpoint into carry/settling_s<seed>.
    A packing already in carry/packings is not written again. Returns one line per packing."""
    carry, lines = Path(carry), []
    for packing in packing_dirs(run_dir):
        seed = packing.name[len("packing_s"):]
        settling = carry / f"settling_s{seed}"
        if (packing / "finished").exists() and (packing / "packing.restart").exists():
            kept = carry / PACKINGS / f"packing_s{seed}.restart.xz"
            if not kept.exists():
                kept.parent.mkdir(parents=True, exist_ok=True)
                partial = kept.with_name(kept.name + ".part")
                with open(packing / "packing.restart", "rb") as source, lzma.open(partial, "wb") as packed:
                    shutil.copyfileobj(source, packed)
                shutil.copyfile(packing / "run.txt", kept.parent / f"packing_s{seed}_run.txt")
                if (packing / "screen.txt").exists():
                    shutil.copyfile(packing / "screen.txt", kept.parent / f"packing_s{seed}_screen.txt")
                partial.rename(kept)
                lines.append(f"{packing.name}: settled, carried in {kept.parent}")
            shutil.rmtree(settling, ignore_errors=True)
            continue
        if checkpoint.last_checkpoint(packing) is None:
            lines.append(f"{packing.name}: settling, no checkpoint yet, nothing carried")
            continue
        step = carry_checkpoint(packing, settling)
        lines.append(f"{packing.name}: settling, kept at its checkpoint of step {step} in {settling}")
    return lines


def restore_packings(carry, run_dir):
    """Puts each settling carried in `carry` into run_dir/packing_s<seed>,
    where run.sh (with SETTLE_CHECKPOINT) goes on with it; the settled
    packings stay in carry/packings, which run.sh reads as PACKINGS."""
    carry, run_dir, lines = Path(carry), Path(run_dir), []
    for settling in sorted(carry.glob("settling_s*")):
        seed = settling.name[len("settling_s"):]
        target = run_dir / f"packing_s{seed}"
        if (carry / PACKINGS / f"packing_s{seed}.restart.xz").exists():
            lines.append(f"{settling.name}: ignored, its packing is settled")
        elif target.exists():
            lines.append(f"{settling.name}: {target} exists already, left as it is")
        else:
            checkpoint.restore(settling, target)
            lines.append(f"{settling.name}: settling, restored at step {checkpoint.last_checkpoint(target)[0]}")
    return lines


def carried_in_history(carried):
    """(work tree, commit, the folder's path in it) of the newest commit in
    whose tree `carried` (a run's folder under carry/) held a checkpoint
    listing, or None: no git work tree above it, or never carried."""
    carried = Path(carried).resolve()
    top = next((p for p in carried.parents if (p / ".git").exists()), None)
    if top is None:
        return None
    folder = carried.relative_to(top)
    listing = str(folder / checkpoint.CHECKPOINTS)
    git = ["git", "-C", str(top)]
    commits = subprocess.run(git + ["log", "--format=%H", "--", listing], capture_output=True, text=True).stdout
    for commit in commits.split():       # newest first; a commit that removed it lists it too
        if subprocess.run(git + ["cat-file", "-e", f"{commit}:{listing}"], capture_output=True).returncode == 0:
            return top, commit, folder
    return None


def reopen(run_dir, store, lengths, carry=None):
    """Replaces each run of run_dir restored from an archive (MARK) whose
    discharge_time is shorter than lengths[f] by its newest carried folder
    in the git history, or by an empty folder when it was never carried
    (the module's docstring); returns one line per run that is too short."""
    run_dir, store = Path(run_dir), Path(store)
    carry = Path(carry) if carry is not None else carry_dir(store)
    lines = []
    for run in run_dirs(run_dir):
        info = read_run_info(run, required=("f",))
        wanted = next((t for f, t in lengths.items() if abs(f - info["f"]) < 1e-9), None)
        ran = discharge_time(run)
        if not (run / MARK).exists() or wanted is None or ran is None or ran >= wanted:
            continue
        found = carried_in_history(carry / run.name)
        if found is None:
            # nothing to go on from: the whole run again (the same trajectory,
            # in the same binary), rather than never the longer one
            shutil.rmtree(run)                   # a copy of its archive, which stays in the store
            run.mkdir()
            lines.append(f"{run.name}: {ran:g} s, shorter than {wanted:g} s, and no carried checkpoint in the "
                         "history: emptied, to run again from its packing")
            continue
        top, commit, folder = found
        packed = subprocess.run(["git", "-C", str(top), "archive", commit, str(folder)], capture_output=True,
                                check=True).stdout
        with tempfile.TemporaryDirectory() as temporary:
            with tarfile.open(fileobj=io.BytesIO(packed)) as tar:
                tar.extractall(temporary)        # our own history
            shutil.rmtree(run)                   # a copy of its archive, which stays in the store
            checkpoint.restore(Path(temporary) / folder, run)
        step, _ = checkpoint.last_checkpoint(run)
        lines.append(f"{run.name}: {ran:g} s, shorter than {wanted:g} s: reopened at its checkpoint of step {step}, "
                     f"carried in {commit[:7]}")
    return lines


def drop_packings(carry):
    """Removes the campaign's carried packings (and the carry directory once
    it holds nothing): the end of a campaign carries nothing."""
    drop_carried(Path(carry) / PACKINGS)
    return [f"packings dropped from {carry}"]


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
    # a run made longer than its archive goes on from its carried checkpoint
    longer = {carried.name for carried in run_dirs(carry) for archive in archives
              if archive.name == carried.name and made_longer(carried, archive)}
    run_dir.mkdir(parents=True, exist_ok=True)
    for archive in archives:
        target = run_dir / archive.name
        if archive.name in longer:
            continue
        if target.exists():
            lines.append(f"{archive.name}: in {run_dir} already, left as it is")
            continue
        checkpoint.restore(archive, target)       # copies, unpacking the .xz files
        (target / MARK).write_text(f"{archive.resolve()}\n")
        (target / "finished").touch()
        lines.append(f"{archive.name}: finished, from {archive}")
    for carried in run_dirs(carry):
        target = run_dir / carried.name
        if carried.name in names and carried.name not in longer:
            lines.append(f"{carried.name}: carried checkpoint ignored, the run is archived")
        elif target.exists():
            lines.append(f"{carried.name}: in {run_dir} already, left as it is")
        else:
            checkpoint.restore(carried, target)
            step, _ = checkpoint.last_checkpoint(target)
            lines.append(f"{carried.name}: unfinished, restored at its checkpoint of step {step}"
                         + (", made longer than its archive" if carried.name in longer else ""))
    return lines + restore_packings(carry, run_dir)


def main(argv=None):
    parser = command_line("analysis.campaign.silo3d_carry", __doc__,
                          "/usr/bin/python3 -m analysis.campaign.silo3d_carry keep runs/rods_fig2c "
                          "doc/data/silo3d_rods_fig2c")
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
    keeping.add_argument("--no-fields", action="store_true",
                         help="archive no fields.npz (the maps): the orifice tables and Q only")
    restoring = actions.add_parser("restore", help="put the store's and the carried runs into a run directory")
    restoring.add_argument("store", type=Path)
    restoring.add_argument("run_dir", type=Path)
    restoring.add_argument("--also", nargs="+", type=Path, default=[], metavar="ARCHIVE",
                           help="more finished runs' archives (analysis.campaign.silo3d_archive)")
    restoring.add_argument("--carry", type=Path, metavar="DIR", help=carry_help)
    reopening = actions.add_parser("reopen", help="runs restored from archives shorter than the protocol: "
                                                  "back to their last carried checkpoint in the history")
    reopening.add_argument("store", type=Path)
    reopening.add_argument("run_dir", type=Path)
    reopening.add_argument("--length", nargs=2, type=float, action="append", required=True, metavar=("F", "T"),
                           help="the protocol's discharge T (s) at the frequency F (Hz)")
    reopening.add_argument("--carry", type=Path, metavar="DIR", help=carry_help)
    pending = actions.add_parser("to-analyse", help="print the finished runs whose orifice tables and "
                                                    "fields are still to make (not archived, not analysed)")
    pending.add_argument("run_dir", type=Path)
    pending.add_argument("store", type=Path)
    pending.add_argument("--analysis", type=Path, metavar="OUT",
                         help="the analysis.silo3d_rotating --out directory of the runs [RUN_DIR/analysis]")
    where = actions.add_parser("carry-dir", help="print where STORE's campaign carries its runs and packings")
    where.add_argument("store", type=Path)
    dropping = actions.add_parser("drop-packings", help="remove the campaign's carried packings (its runs are done)")
    dropping.add_argument("store", type=Path)
    dropping.add_argument("--carry", type=Path, metavar="DIR", help=carry_help)
    args = parser.parse_args(sys.argv[1:] if argv is None else argv)
    try:
        if args.action == "keep":
            if not args.run_dir.is_dir():
                raise ValueError(f"{args.run_dir}: no such directory")
            for radius, top in args.dump_cylinder:
                if not radius > 0:
                    raise ValueError(f"--dump-cylinder {radius:g} {top:g}: the radius must be > 0 m")
            lines = keep(args.run_dir, args.store, [tuple(c) for c in args.dump_cylinder],
                         args.analysis, args.carry, not args.no_fields)
        elif args.action == "to-analyse":
            for run in to_analyse(args.run_dir, args.store, args.analysis):
                print(run)
            return 0
        elif args.action == "carry-dir":
            print(carry_dir(args.store))
            return 0
        elif args.action == "restore":
            lines = restore(args.store, args.run_dir, args.also, args.carry)
        elif args.action == "reopen":
            lines = reopen(args.run_dir, args.store, dict(args.length), args.carry)
            if not lines:
                return 0
        else:
            lines = drop_packings(args.carry if args.carry is not None else carry_dir(args.store))
    except (ValueError, FileNotFoundError) as error:
        print(f"silo3d_carry: ERROR: {error}", file=sys.stderr)
        return 2
    for line in lines or ["no runs"]:
        print(f"silo3d_carry: {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
