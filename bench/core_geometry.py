"""Contact geometry for the benchmarks, from the one copy the styles use:
the host-free headers of src_plugin/core/, through the drivers their
tests run (tests/*_driver.cpp; each driver's header comment lists its
commands). A driver is compiled once with g++ into bench/work/drivers/,
under a hash of its sources.

- rods (spherocylinder_geometry.h): mass properties, whether two touch;
- rolling_friction jiang (rolling_law_jiang.h): the contact length of an
  overlapping pair or of a grain on a wall, the chord of their circles."""

import hashlib
import subprocess

import numpy as np

import benchlib

CORE = benchlib.ROOT / "src_plugin" / "core"
ROD_DRIVER = "spherocylinder_geometry_driver.cpp"
JIANG_DRIVER = "rolling_law_jiang_driver.cpp"


def driver(name):
    """The compiled driver tests/`name` (compiled here if its sources changed)."""
    source = benchlib.ROOT / "tests" / name
    digest = hashlib.sha256(source.read_bytes())
    for header in sorted(CORE.glob("*.h")):
        digest.update(header.read_bytes())
    executable = benchlib.WORK / "drivers" / f"{source.stem}_{digest.hexdigest()[:12]}"
    if not executable.exists():
        executable.parent.mkdir(parents=True, exist_ok=True)
        build = subprocess.run(["g++", "-std=c++11", "-O2", f"-I{CORE}", str(source),
                                "-o", str(executable)], capture_output=True, text=True)
        if build.returncode != 0:
            raise RuntimeError(f"{source.name} does not compile:\n{build.stderr}")
    return executable


def run_driver(name, lines):
    """The numbers of each output line of driver `name` (after the first
    word), one row per input line."""
    if not lines:
        return []
    result = subprocess.run([str(driver(name))], input="\n".join(lines) + "\n", capture_output=True,
                            text=True, check=True)
    rows = [line.split()[1:] for line in result.stdout.splitlines()]
    if len(rows) != len(lines):
        raise RuntimeError(f"{name} answered {len(rows)} of {len(lines)} lines")
    return [[float(word) for word in row] for row in rows]


def solid_rod(d, length, rho):
    """Mass and principal moments (axial, transverse) of a solid
    spherocylinder (spherocylinder_mass_properties)."""
    (mass, axial, transverse), = run_driver(ROD_DRIVER, [f"mass {d!r} {length!r} {rho!r}"])
    return mass, axial, transverse


def rods_touching(centres_1, axes_1, centres_2, axes_2, half_core, radius):
    """Per row, whether two rods of the same half core length and radius
    touch: their cores come closer than 2 radius (cores_within)."""
    def rod(centre, axis):
        return " ".join(repr(float(v)) for v in (*centre, *axis, half_core, radius))
    lines = [f"within {rod(c1, a1)} {rod(c2, a2)}"
             for c1, a1, c2, a2 in zip(centres_1, axes_1, centres_2, axes_2)]
    return np.array([row[0] == 1.0 for row in run_driver(ROD_DRIVER, lines)], dtype=bool)


def overlap_chord(radius_i, radius_j, distance):
    """The contact length of two grains whose centres are `distance`
    apart: the chord of their circles (overlap_contact_length)."""
    (length,), = run_driver(JIANG_DRIVER, [f"chord {radius_i!r} {radius_j!r} {distance!r}"])
    return length


def wall_chord(radius, overlap):
    """The contact length of a grain pressed `overlap` into a flat wall
    (wall_overlap_contact_length)."""
    (length,), = run_driver(JIANG_DRIVER, [f"wall_chord {radius!r} {overlap!r}"])
    return length
