"""Records of the rotating-bottom silo (Pongó, Börzsönyi and Hidalgo 2022):
reading one run directory that inputs/silo3d_rotating/in.silo3d_rotating
writes: its parameters (run.txt), discharge record (discharge.txt), the
frames of dump.cg as coarse_grain Particles and of dump.contacts as
coarse_grain Contacts, the time since the opening of dump steps, and the
Run that holds one run's records (and, once analysed, its flow rate).

The record format (files, columns, units, the deck's conventions):
doc/silo3d_rotating_records.md. The flow rate is in analysis.silo3d_rotating.flow,
the coarse-grained fields in analysis.silo3d_rotating.fields, the command line in
analysis.silo3d_rotating.analyse.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from analysis.common import coarse_grain as cg
from analysis.common.lammps_io import iter_dump
from analysis.common.tables import read_table

if TYPE_CHECKING:                      # Run.flow's annotation only
    from analysis.silo3d_rotating.flow import FlowRate

RUN_KEYS = ("d", "rho", "mass", "Dc", "D", "f", "seed", "N", "dt", "t_open", "reinject")
DISCHARGE_COLUMNS = ("step", "t", "n_out", "mass_out")
# compute pair/gran/local pos id force: the 12 columns of one contact
CONTACT_COLUMNS = ("x1", "y1", "z1", "x2", "y2", "z2", "id1", "id2", "periodic", "fx", "fy", "fz")
# a grain's axis in dump.cg: the deck's rods write c_rod_axis[1-3]
# (compute spherocylinder/axis); ox oy oz is the name other tools use
ORIENTATION_COLUMN_SETS = (("c_rod_axis[1]", "c_rod_axis[2]", "c_rod_axis[3]"), ("ox", "oy", "oz"))
# beside a dump.cg whose frames hold only the grains inside some cylinders
# (an archive's, or a run's carried from a checkpoint: analysis.campaign.silo3d_archive,
# analysis.campaign.checkpoint keep)
DUMP_CUT = "dump_cut.txt"


# ---------------------------------------------------------------- records

def read_run_info(run_dir, required=RUN_KEYS):
    """run.txt: `key value` lines, '#' comments; numbers as floats, words
    (`shape rod`) as strings; the keys of `required` (RUN_KEYS for the
    analysis) must be there (an error names the file and the missing keys)."""
    path = Path(run_dir) / "run.txt"
    info = {}
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            key, value = line.split()[:2]
            try:
                info[key] = float(value)
            except ValueError:
                info[key] = value
    missing = [key for key in required if key not in info]
    if missing:
        raise ValueError(f"{path}: missing keys {missing}")
    return info


def read_discharge(run_dir):
    """discharge.txt as a dict of arrays; columns looked up by name."""
    return read_table(Path(run_dir) / "discharge.txt", required=DISCHARGE_COLUMNS)


def frame_particles(columns):
    """cg.Particles of a dump.cg frame; orientations (normalised) when the
    frame has the axes (ORIENTATION_COLUMN_SETS, the first set present)."""
    positions = np.column_stack([columns["x"], columns["y"], columns["z"]])
    velocities = np.column_stack([columns["vx"], columns["vy"], columns["vz"]])
    orientations = None
    for names in ORIENTATION_COLUMN_SETS:
        if all(name in columns for name in names):
            axes = np.column_stack([columns[name] for name in names])
            orientations = axes / np.linalg.norm(axes, axis=1, keepdims=True)
            break
    return cg.Particles(positions, velocities, columns["mass"], orientations)


def contact_columns(columns):
    """Names the 12 columns of `compute pair/gran/local pos id force` in a
    dump local frame (c_ID[1] ... c_ID[12], in that order): pos of the
    first and second grain, their ids, the periodic flag, and the force on
    the first grain (checked against LIGGGHTS in the tests)."""
    names = list(columns)
    if len(names) != len(CONTACT_COLUMNS):
        raise ValueError(f"dump.contacts: expected the {len(CONTACT_COLUMNS)} columns of "
                         f"'compute pair/gran/local pos id force' ({' '.join(CONTACT_COLUMNS)}), "
                         f"got {len(names)}: {' '.join(names)}")
    return {meaning: columns[name] for meaning, name in zip(CONTACT_COLUMNS, names)}


def frame_contacts(columns):
    """cg.Contacts of a dump.contacts frame: from grain 1 to grain 2, the
    force on grain 1. A contact across a periodic boundary would have its
    branch vector wrong (LIGGGHTS writes remapped positions): refused."""
    named = contact_columns(columns)
    if np.any(named["periodic"] != 0):
        raise ValueError("dump.contacts: contacts across periodic boundaries are not supported")
    starts = np.column_stack([named["x1"], named["y1"], named["z1"]])
    ends = np.column_stack([named["x2"], named["y2"], named["z2"]])
    forces = np.column_stack([named["fx"], named["fy"], named["fz"]])
    return cg.Contacts(starts, ends, forces)


def time_since_opening(steps, discharge, run):
    """tau = t - t_open of dump steps, from the discharge record's first
    (step, t) and the time step (the deck does not change dt after opening)."""
    step0, time0 = discharge["step"][0], discharge["t"][0]
    return time0 + (np.asarray(steps, dtype=float) - step0) * run["dt"] - run["t_open"]


def once_each(steps):
    """An iter_dump predicate that is true the first time each of `steps`
    comes: LIGGGHTS may write a frame again at the set-up of the next run
    of a deck's run loop."""
    pending = set(int(s) for s in steps)

    def wanted(step):
        if step in pending:
            pending.remove(step)
            return True
        return False
    return wanted


def write_dump_cut(directory, cylinders, whole_from=None, fill_height=None):
    """Says, in directory's dump_cut.txt, that the frames of its dump.cg
    before the step whole_from (every frame, without it) hold only the
    grains inside the cylinders, (R, Z) pairs: r < R and z < Z about the
    z axis; and, for the maps' grid, the fill height at the opening (the
    highest grain of the first frame from it on, before the cut)."""
    lines = ["# dump.cg's frames " + ("before the step whole_from" if whole_from is not None else "(all)") +
             " hold only the grains inside these cylinders about the z axis, r < R and z < Z: no maps"
             " from them, and orifice averages only if a cylinder holds the orifice with the kernel's reach"
             " (doc/silo3d_rotating_records.md)\n"]
    if whole_from is not None:
        lines.append(f"whole_from {int(whole_from)}\n")
    if fill_height is not None:
        lines.append(f"fill_height {fill_height!r}\n")
    lines += [f"cylinder {r!r} {z!r}\n" for r, z in cylinders]
    (Path(directory) / DUMP_CUT).write_text("".join(lines))


@dataclass
class DumpCut:
    """What a directory's dump_cut.txt says: the first step from which
    dump.cg's frames hold every grain (0 for a whole dump, without
    dump_cut.txt; the step of the checkpoint a carried run went on from;
    math.inf for an archive, every frame cut), the fill height at the
    opening or None, and the kept cylinders, (R, Z) pairs."""
    whole_from: float = 0
    fill_height: float = None
    cylinders: tuple = ()

    def holds(self, radius, top):
        """Whether the cut frames hold every grain with r < radius, z < top."""
        return any(radius <= r and top <= z for r, z in self.cylinders)


def read_dump_cut(directory):
    """The DumpCut of a run or archive directory."""
    path = Path(directory) / DUMP_CUT
    if not path.exists():
        return DumpCut()
    values, cylinders = {}, []
    for line in path.read_text().splitlines():
        words = line.split()
        if len(words) == 2 and words[0] in ("whole_from", "fill_height"):
            values[words[0]] = float(words[1])
        elif len(words) == 3 and words[0] == "cylinder":
            cylinders.append((float(words[1]), float(words[2])))
    return DumpCut(int(values["whole_from"]) if "whole_from" in values else math.inf,
                   values.get("fill_height"), tuple(cylinders))


def frames_with_contacts(run, steps, whole_from=0):
    """(step, cg.Particles, cg.Contacts or None) of the frames at `steps`,
    reading dump.cg and, when present, dump.contacts side by side. Frames
    before the step whole_from (read_dump_cut) have no contacts: a run
    carried from a checkpoint has not its contact dump before it."""
    contacts_path = run.path / "dump.contacts"
    contact_frames = (iter_dump(contacts_path, once_each([s for s in steps if s >= whole_from]))
                      if contacts_path.exists() else None)
    for step, columns in iter_dump(run.path / "dump.cg", once_each(steps)):
        contacts = None
        if contact_frames is not None and step >= whole_from:
            contact_step, contact_columns = next(contact_frames, (None, None))
            if contact_step != step:
                raise ValueError(f"{contacts_path}: no frame of step {step} in step with dump.cg")
            contacts = frame_contacts(contact_columns)
        yield step, frame_particles(columns), contacts


# ---------------------------------------------------------------- runs

@dataclass
class Run:
    """A run directory with its run.txt, discharge record and flow rate."""
    path: Path
    info: dict
    discharge: dict
    tau: np.ndarray
    flow: FlowRate = None
    label: str = ""
    windows: np.ndarray = None      # rows (t_from, t_to, grains/s, kg/s) of silo3d_flow.window_rates

    @property
    def finished(self):
        """The deck writes `finished <t>` to run.txt as its last act."""
        return "finished" in self.info

    @property
    def clogged_at_rest(self):
        """The deck writes `clogged <t>` before `finished` when it stopped
        the run at a clog at rest (its clog_stop)."""
        return "clogged" in self.info

    @property
    def key(self):
        """(f, D) rounded so that equal deck values group together."""
        return (key_value(self.info["f"]), key_value(self.info["D"]))


def key_value(value):
    """A frequency or diameter as Run.key holds it: rounded to 9 decimals,
    so that values equal within round-off (run.txt's digits, a command
    line's) compare equal."""
    return round(value, 9)


def load_run(run_dir):
    info = read_run_info(run_dir)
    discharge = read_discharge(run_dir)
    return Run(Path(run_dir), info, discharge, discharge["t"] - info["t_open"])
