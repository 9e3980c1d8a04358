"""The rods' geometry for the benchmarks, from the one copy the styles use:
src_plugin/core/spherocylinder_geometry.h, through the driver that its
tests run (tests/spherocylinder_geometry_driver.cpp; its header comment
lists the commands). The driver is compiled once with g++ into
bench/work/geometry_driver/, under a hash of its sources."""

import hashlib
import subprocess

import numpy as np

import benchlib

DRIVER_SOURCE = benchlib.ROOT / "tests" / "spherocylinder_geometry_driver.cpp"
CORE = benchlib.ROOT / "src_plugin" / "core"


def driver():
    """The compiled driver's path (compiled here if its sources changed)."""
    digest = hashlib.sha256(DRIVER_SOURCE.read_bytes())
    for header in sorted(CORE.glob("*.h")):
        digest.update(header.read_bytes())
    executable = benchlib.WORK / "geometry_driver" / f"spherocylinder_geometry_driver_{digest.hexdigest()[:12]}"
    if not executable.exists():
        executable.parent.mkdir(parents=True, exist_ok=True)
        build = subprocess.run(["g++", "-std=c++11", "-O2", f"-I{CORE}", str(DRIVER_SOURCE),
                                "-o", str(executable)], capture_output=True, text=True)
        if build.returncode != 0:
            raise RuntimeError(f"{DRIVER_SOURCE.name} does not compile:\n{build.stderr}")
    return executable


def run_driver(lines):
    """The driver's output rows (the numbers after the command's name),
    one per input line."""
    if not lines:
        return []
    result = subprocess.run([str(driver())], input="\n".join(lines) + "\n", capture_output=True,
                            text=True, check=True)
    rows = [line.split()[1:] for line in result.stdout.splitlines()]
    if len(rows) != len(lines):
        raise RuntimeError(f"the geometry driver answered {len(rows)} of {len(lines)} lines")
    return [[float(word) for word in row] for row in rows]


def solid_rod(d, length, rho):
    """Mass and principal moments (axial, transverse) of a solid
    spherocylinder (spherocylinder_mass_properties)."""
    (mass, axial, transverse), = run_driver([f"mass {d!r} {length!r} {rho!r}"])
    return mass, axial, transverse


def rods_touching(centres_1, axes_1, centres_2, axes_2, half_core, radius):
    """Per row, whether two rods of the same half core length and radius
    touch: their cores come closer than 2 radius (cores_within)."""
    def rod(centre, axis):
        return " ".join(repr(float(v)) for v in (*centre, *axis, half_core, radius))
    lines = [f"within {rod(c1, a1)} {rod(c2, a2)}"
             for c1, a1, c2, a2 in zip(centres_1, axes_1, centres_2, axes_2)]
    return np.array([row[0] == 1.0 for row in run_driver(lines)], dtype=bool)
