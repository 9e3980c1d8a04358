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

    python3 -m analysis.checkpoint resume RUN_DIR   # cuts, prints "-var name value ..."
    python3 -m analysis.checkpoint clean RUN_DIR    # removes the checkpoint files

`resume` prints nothing when there is no checkpoint to go on from.
"""

import argparse
import os
import sys
from pathlib import Path

from analysis.silo3d_records import read_run_info

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
        lines = handle.readlines()
    # (a line cut short by the interruption has no newline: dropped)
    kept = [line for line in lines if line.endswith("\n") and
            (line.startswith("#") or not line.split() or int(line.split()[0]) <= step)]
    _replace(path, kept)


def cut_frames(path, step):
    """Drops the frames of a text dump from `step` on."""
    if not path.exists():
        return
    kept, keep = [], True
    with open(path) as handle:
        lines = handle.readlines()
    for number, line in enumerate(lines):
        if line.startswith("ITEM: TIMESTEP"):
            keep = number + 1 < len(lines) and lines[number + 1].strip().isdigit() \
                and int(lines[number + 1]) < step
        if keep:
            kept.append(line)
    _replace(path, kept)


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


def remove_checkpoints(run_dir):
    for path in Path(run_dir).glob("checkpoint.*.restart"):
        path.unlink()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("action", choices=("resume", "clean"))
    parser.add_argument("run_dir")
    args = parser.parse_args(argv)
    if args.action == "clean":
        remove_checkpoints(args.run_dir)
        return 0
    variables = resume_variables(args.run_dir)
    if variables:
        print(" ".join(f"-var {name} {value}" for name, value in variables.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
