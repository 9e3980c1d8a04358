"""Resuming an interrupted discharge of the rotating-bottom silo from its
last checkpoint.

A run with `-var checkpoint_every_time T` writes a restart file every T s
of discharge and, once the file is complete, appends "step file" to
checkpoints.txt (inputs/run_until_done.in). To go on after an
interruption, this module

- finds the last checkpoint whose file exists,
- cuts the records back to it: the rows of discharge.txt and reinject.txt
  after its step, and the frames of dump.cg and dump.contacts from its step
  on (the resumed run writes that frame again when it sets up), and a
  `finished` line of run.txt (the resumed run writes its own),
- and gives the deck variables of the resumed run: the checkpoint file,
  the run's time at it (LIGGGHTS' own time restarts at 0 after
  read_restart), and the step and grain count at the opening, from run.txt.

    python3 -m analysis.campaign.checkpoint resume RUN_DIR   # cuts, prints "-var name value ..."
    python3 -m analysis.campaign.checkpoint settle-resume PACKING_DIR
                                                    # the same for a settling cut short
    python3 -m analysis.campaign.checkpoint last RUN_DIR     # prints "step file" of the checkpoint
                                                    # resume would go on from, or nothing
    python3 -m analysis.campaign.checkpoint clean RUN_DIR    # removes the checkpoint files
                                                    # (and LIGGGHTS' forced restart)
    python3 -m analysis.campaign.checkpoint clean RUN_DIR --keep-last
                                                    # all but the last: a finished
                                                    # run can then be made longer

`resume` prints nothing when there is no checkpoint to go on from.

A machine whose files do not outlive the session (ours: each session
starts on a new one) keeps an unfinished run in the repository instead:

    python3 -m analysis.campaign.checkpoint keep RUN_DIR KEPT [--dump-cylinder R Z]
    python3 -m analysis.campaign.checkpoint restore KEPT RUN_DIR

`keep` writes the last checkpoint (xz), its line of checkpoints.txt,
run.txt, the row records up to it and dump.cg's frames before it (xz; with
--dump-cylinder only the grains with r < R and z < Z about the z axis, the
orifice region, which keeps the orifice averages but not the maps, and
dump_cut.txt says so: the analysis then makes the maps from the frames
from the checkpoint on); dump.contacts is not kept. `restore` unpacks
KEPT into a new RUN_DIR, from which `resume` (and so run.sh) goes on.
"""

import lzma
import os
import shutil
import sys
from pathlib import Path

from analysis.common.lammps_io import iter_dump
from analysis.silo3d_rotating.records import DUMP_CUT, read_dump_cut, read_run_info, write_dump_cut
from analysis.common.cli import command_line

CHECKPOINTS = "checkpoints.txt"
ROW_RECORDS = ("discharge.txt", "reinject.txt")   # one row per step, step first
DUMPS = ("dump.cg", "dump.contacts")


def last_checkpoint(run_dir):
    """(step, path) of the last checkpoint listed whose file exists, or None."""
    listing = Path(run_dir) / CHECKPOINTS
    if not listing.exists():
        return None
    for line in reversed(listing.read_text().splitlines()):
        words = line.split()
        if len(words) == 2 and (Path(run_dir) / words[1]).exists():
            return int(words[0]), Path(run_dir) / words[1]
    return None


def _replace(path, lines):
    """Writes `lines` to path through a temporary file, so that an
    interruption leaves either the old file or the new one."""
    temporary = path.with_name(path.name + ".cut")
    temporary.write_text("".join(lines))
    os.replace(temporary, path)


def cut_rows(path, step):
    """Drops the rows of a `# header` + "step ..." table after `step`."""
    if not path.exists():
        return
    with open(path) as handle:
        _replace(path, rows_up_to(handle.readlines(), step))


def rows_up_to(lines, step):
    """The lines of a `# header` + "step ..." table up to `step` (a line cut
    short by an interruption has no newline: dropped)."""
    return [line for line in lines if line.endswith("\n") and
            (line.startswith("#") or not line.split() or int(line.split()[0]) <= step)]


def cut_frames(path, step):
    """Drops the frames of a text dump from `step` on."""
    if not path.exists():
        return
    with open(path) as handle:
        _replace(path, frames_before(handle.readlines(), step))


def frames_before(lines, step):
    """The lines of the frames of a text dump before `step`."""
    kept, keep = [], True
    for number, line in enumerate(lines):
        if line.startswith("ITEM: TIMESTEP"):
            keep = number + 1 < len(lines) and lines[number + 1].strip().isdigit() \
                and int(lines[number + 1]) < step
        if keep:
            kept.append(line)
    return kept


def frames_in_cylinder(lines, radius, z_max, *more):
    """The frames of a `dump custom` with x y z columns (9 header lines per
    frame), each with only the grains at r < radius and z < z_max (r about
    the z axis), or inside any of the `more` cylinders, (radius, z_max)
    pairs (the orifice region and the column over the axis, for the
    fields and the axial acceleration); a frame cut short is dropped."""
    cylinders = [(radius, z_max)] + [tuple(c) for c in more]
    kept, i = [], 0
    while i + 9 <= len(lines):
        head, n = lines[i:i + 9], int(lines[i + 3])
        rows = lines[i + 9:i + 9 + n]
        if len(rows) < n or not rows[-1].endswith("\n"):
            break
        columns = head[8].split()[2:]
        ix, iy, iz = (columns.index(name) for name in ("x", "y", "z"))
        inside = []
        for row in rows:
            words = row.split()
            z, r2 = float(words[iz]), float(words[ix]) ** 2 + float(words[iy]) ** 2
            if any(z < top and r2 < r ** 2 for r, top in cylinders):
                inside.append(row)
        kept += head[:3] + [f"{len(inside)}\n"] + head[4:] + inside
        i += 9 + n
    return kept


def resume_variables(run_dir):
    """Cuts the records of run_dir back to its last checkpoint and returns the
    deck variables that resume from it, or None without a checkpoint."""
    found = last_checkpoint(run_dir)
    if found is None:
        return None
    step, checkpoint = found
    run = read_run_info(run_dir, required=("dt", "t_open", "N", "step_open"))
    for name in ROW_RECORDS:
        cut_rows(Path(run_dir) / name, step)
    for name in DUMPS:
        cut_frames(Path(run_dir) / name, step)
    run_txt = Path(run_dir) / "run.txt"
    _replace(run_txt, [line for line in run_txt.read_text().splitlines(keepends=True)
                       if not line.startswith("finished")])
    step_open = int(run["step_open"])
    t_resume = run["t_open"] + (step - step_open) * run["dt"]
    return {"resume": 1, "checkpoint": str(checkpoint.resolve()), "t_resume": repr(t_resume),
            "n_open_resumed": int(run["N"]), "step_open_resumed": step_open}


def settle_resume_variables(packing_dir):
    """The deck variables that go on with a settling cut short, from its
    last checkpoint (-var settle_checkpoint_every_time), or None without
    one. A settling starts at step 0, so the checkpoint's step is the
    number of steps settled; the settling writes no records to cut (they
    start at the opening)."""
    found = last_checkpoint(packing_dir)
    if found is None:
        return None
    step, checkpoint = found
    return {"settle_resume": 1, "checkpoint": str(checkpoint.resolve()), "settled_steps": step}


def remove_checkpoints(run_dir, keep_last=False):
    """Removes the checkpoints of a finished run, and the restart LIGGGHTS
    writes by itself when a signal stops it (restart_forced_liggghts_<step>
    .data, 8 MB for 10 000 rods), which a resumed run leaves behind. With
    keep_last, the last checkpoint stays (19 MB for 22 500 rods): resumed
    with a longer discharge_time, the finished run goes on from it
    (run.sh) instead of starting again from its packing."""
    last = last_checkpoint(run_dir) if keep_last else None
    for pattern in ("checkpoint.*.restart", "restart_forced_liggghts_*.data"):
        for path in Path(run_dir).glob(pattern):
            if last is None or path != last[1]:
                path.unlink()


def keep(run_dir, kept, dump_cylinder=None):
    """Writes into `kept` what the run needs to go on elsewhere from its last
    checkpoint (the module's docstring); returns the checkpoint's step.
    dump_cylinder: (R, Z) pairs; dump.cg keeps the grains inside any."""
    found = last_checkpoint(run_dir)
    if found is None:
        raise ValueError(f"{run_dir}: no checkpoint to keep")
    step, checkpoint = found
    run_dir, kept = Path(run_dir), Path(kept)
    kept.mkdir(parents=True, exist_ok=True)
    (kept / CHECKPOINTS).write_text(f"{step} {checkpoint.name}\n")
    if (run_dir / "run.txt").exists():         # a settling writes it at its end
        shutil.copyfile(run_dir / "run.txt", kept / "run.txt")
    for name in ROW_RECORDS:
        if (run_dir / name).exists():
            with open(run_dir / name) as handle:
                (kept / name).write_text("".join(rows_up_to(handle.readlines(), step)))
    if (run_dir / "dump.cg").exists():
        with open(run_dir / "dump.cg") as handle:
            frames = frames_before(handle.readlines(), step)
        if dump_cylinder:
            frames = frames_in_cylinder(frames, *dump_cylinder[0], *dump_cylinder[1:])
            # the analysis makes its maps from the frames from the checkpoint
            # on, on the grid of the fill at the opening
            # (a run carried before has its fill height in its dump_cut.txt)
            fill_height = read_dump_cut(run_dir).fill_height
            if fill_height is None:
                step_open = read_run_info(run_dir, required=("step_open",))["step_open"]
                opening = next(iter_dump(run_dir / "dump.cg", lambda s: s >= step_open), None)
                fill_height = float(opening[1]["z"].max()) if opening else None
            write_dump_cut(kept, dump_cylinder, whole_from=step, fill_height=fill_height)
        elif (run_dir / DUMP_CUT).exists():       # cut before, at an earlier checkpoint
            shutil.copyfile(run_dir / DUMP_CUT, kept / DUMP_CUT)
        with lzma.open(kept / "dump.cg.xz", "wt") as packed:
            packed.writelines(frames)
    with open(checkpoint, "rb") as source, lzma.open(kept / (checkpoint.name + ".xz"), "wb") as packed:
        shutil.copyfileobj(source, packed)
    return step


def restore(kept, run_dir):
    """Unpacks a kept run into a new run directory."""
    kept, run_dir = Path(kept), Path(run_dir)
    if (run_dir / "run.txt").exists():
        raise ValueError(f"{run_dir} holds a run already: restore into a new directory")
    run_dir.mkdir(parents=True, exist_ok=True)
    for path in kept.iterdir():
        if path.suffix == ".xz":
            with lzma.open(path, "rb") as packed, open(run_dir / path.stem, "wb") as target:
                shutil.copyfileobj(packed, target)
        elif path.is_file():
            shutil.copyfile(path, run_dir / path.name)


def main(argv=None):
    parser = command_line("analysis.campaign.checkpoint", __doc__.split("\n\n")[0],
                          "/usr/bin/python3 -m analysis.campaign.checkpoint resume "
                          "runs/rods_fig2c/D0.06_f0.16_s32452843")
    actions = parser.add_subparsers(dest="action", required=True)
    for action in ("resume", "settle-resume", "last"):
        actions.add_parser(action).add_argument("run_dir")
    cleaning = actions.add_parser("clean", help="remove the checkpoint files")
    cleaning.add_argument("run_dir")
    cleaning.add_argument("--keep-last", action="store_true",
                          help="all but the last one, from which a longer discharge goes on")
    keeping = actions.add_parser("keep", help="the last checkpoint and the records up to it, into KEPT")
    keeping.add_argument("run_dir")
    keeping.add_argument("kept")
    keeping.add_argument("--dump-cylinder", nargs=2, type=float, metavar=("R", "Z"), action="append",
                         help="keep only the grains of dump.cg with r < R and z < Z (m); given again, "
                              "the grains inside any of the cylinders")
    restoring = actions.add_parser("restore", help="unpack KEPT into a new RUN_DIR")
    restoring.add_argument("kept")
    restoring.add_argument("run_dir")
    args = parser.parse_args(argv)
    if args.action == "last":
        found = last_checkpoint(args.run_dir)
        if found is not None:
            print(found[0], found[1].name)
        return 0
    if args.action == "clean":
        remove_checkpoints(args.run_dir, args.keep_last)
        return 0
    if args.action in ("keep", "restore"):
        try:
            if args.action == "keep":
                step = keep(args.run_dir, args.kept, args.dump_cylinder)
                print(f"checkpoint: kept step {step} of {args.run_dir} in {args.kept}")
            else:
                restore(args.kept, args.run_dir)
        except ValueError as error:
            print(f"checkpoint: {error}", file=sys.stderr)
            return 2
        return 0
    if args.action == "settle-resume":
        variables = settle_resume_variables(args.run_dir)
    else:
        variables = resume_variables(args.run_dir)
    if variables:
        print(" ".join(f"-var {name} {value}" for name, value in variables.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
