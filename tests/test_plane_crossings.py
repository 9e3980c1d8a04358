"""The out-of-tree style example (examples/extend, doc/extend.md): the fix
plane/crossings built through -DSILOKIT_USER_STYLES, checked against free
fall, and the option's refusals of bad input.

The binary under test ($SILOKIT_LIGGGHTS or build/bin/liggghts) normally
lacks the example style: the default build carries none. The tests then
build their own tree, build/extend-test (no PGO or LTO, through ccache),
once; later runs rebuild it incrementally in seconds. Set
SILOKIT_EXTEND_BUILD=0 to skip them instead.
"""

import math
import os
import subprocess

import numpy as np
import pytest

from analysis.testing import LiggghtsError, read_frame, read_record, run_deck
from conftest import LIGGGHTS, ROOT, has_mpirun

# builds and runs LIGGGHTS (tools/test.sh --fast leaves it out)
pytestmark = pytest.mark.engine

EXAMPLE = ROOT / "examples" / "extend"
DECK = EXAMPLE / "in.crossings"
TREE = ROOT / "build" / "extend-test"
G, DT, PLANE, EVERY = 9.81, 1e-4, 0.06, 200
GRAIN_MASS = 2500 * math.pi / 6 * 0.01 ** 3


def debian_tarball():
    """Debian's LIGGGHTS tarball the default build fetched, if it did: a
    configure from it needs no network."""
    fetched = LIGGGHTS.parent.parent / "download" / "liggghts_3.8.0+repack1.orig.tar.xz"
    return fetched if fetched.exists() else None


def has_style(binary, style="plane/crossings"):
    if not binary.exists():
        return False
    listing = subprocess.run([str(binary), "-h"], capture_output=True, text=True,
                             errors="replace", cwd=binary.parent).stdout
    return style in listing.split()


@pytest.fixture(scope="module")
def binary():
    if has_style(LIGGGHTS):
        return LIGGGHTS
    if os.environ.get("SILOKIT_EXTEND_BUILD") == "0":
        pytest.skip(f"{LIGGGHTS} lacks fix plane/crossings and SILOKIT_EXTEND_BUILD=0: "
                    "build with -DSILOKIT_USER_STYLES=examples/extend to run these tests")
    configure = ["cmake", "-S", str(ROOT), "-B", str(TREE), f"-DSILOKIT_USER_STYLES={EXAMPLE}",
                 "-DSILOKIT_PGO=OFF", "-DSILOKIT_LTO=OFF", "-DSILOKIT_LAMMPS=OFF"]
    if debian_tarball():
        configure.append(f"-DLIGGGHTS_TARBALL={debian_tarball()}")
    jobs = os.environ.get("SILOKIT_BUILD_JOBS", str(os.cpu_count() or 1))
    for command in (configure, ["cmake", "--build", str(TREE), "-j", jobs]):
        result = subprocess.run(command, capture_output=True, text=True)
        assert result.returncode == 0, f"{' '.join(command)}:\n{result.stdout[-3000:]}{result.stderr[-3000:]}"
    built = TREE / "bin" / "liggghts"
    assert has_style(built)
    return built


def check_free_fall(run):
    """Each of the 144 grains crosses once, at its start x, y, with the
    free-fall velocity of its start height. The velocity written is that of
    the step's update (v at the half step): within g dt / 2 of the exact
    one at the crossing."""
    start = read_frame(run.path("start.dump"))
    crossings = read_record(run.path("crossings.txt"), required=["id", "x", "y", "vz"])
    ids = crossings["id"].astype(int)
    assert len(start) == 144 and sorted(ids) == start.ids.tolist()
    z0 = np.array([start.atom(i)["z"] for i in ids])
    exact = -np.sqrt(2 * G * (z0 - PLANE))
    assert np.max(np.abs(crossings["vz"] - exact)) <= 0.5 * G * DT * (1 + 1e-9)
    assert np.array_equal(crossings["x"], [start.atom(i)["x"] for i in ids])
    assert np.all(crossings["vx"] == 0) and np.all(crossings["vy"] == 0)
    # the time of each crossing is that of the step it was found at
    assert np.allclose(crossings["time"], crossings["step"] * DT, rtol=1e-12)

    rate = read_record(run.path("rate.txt"), required=["grains", "mass", "grains_per_time"])
    assert rate["step"].tolist() == list(range(EVERY, 2001, EVERY))
    assert rate["grains"].sum() == 144
    assert rate["mass"].sum() == pytest.approx(144 * GRAIN_MASS, rel=1e-9)
    assert np.allclose(rate["grains_per_time"], rate["grains"] / (EVERY * DT), rtol=1e-9)
    # a line's grains are those of crossings.txt in its window
    for step, grains in zip(rate["step"], rate["grains"]):
        in_window = (crossings["step"] > step - EVERY) & (crossings["step"] <= step)
        assert np.count_nonzero(in_window) == grains
    thermo = run.thermo()
    assert thermo["crossed"][-1] == 144


def test_every_grain_crosses_once_at_its_free_fall_velocity(binary, tmp_path):
    check_free_fall(run_deck(DECK, tmp_path, binary=binary))


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_write_the_same_records(binary, tmp_path):
    serial = run_deck(DECK, tmp_path / "serial", binary=binary)
    parallel = run_deck(DECK, tmp_path / "parallel", binary=binary, nprocs=2)
    check_free_fall(parallel)
    for name in ("crossings.txt", "rate.txt"):
        assert parallel.path(name).read_text() == serial.path(name).read_text()


@pytest.mark.parametrize("change, message", [
    ("z 0.06 every 0", "'every' must be a positive number of steps"),
    ("z 0.06 rate", "'rate' needs a value"),
    ("z 0.06 often 5", "unknown keyword 'often' (allowed: every, crossings, rate)"),
    ("z 0.06 rate /no/such/dir/rate.txt", "cannot open the 'rate' file /no/such/dir/rate.txt"),
    ("height 0.06", "expects z and the height of the plane"),
])
def test_bad_arguments_are_named(binary, tmp_path, change, message):
    deck = DECK.read_text().replace(
        "z ${plane} every ${every} crossings crossings.txt rate rate.txt", change)
    with pytest.raises(LiggghtsError) as failure:
        run_deck(deck, tmp_path, binary=binary)
    assert message in failure.value.message


# The option's refusals: configure runs only (a few seconds each, in one tree)

@pytest.fixture(scope="module")
def configure(tmp_path_factory):
    if not debian_tarball():
        pytest.skip("no Debian LIGGGHTS tarball fetched by the default build")
    tree = tmp_path_factory.mktemp("user-styles")

    def run(*user_dirs):
        return subprocess.run(
            ["cmake", "-S", str(ROOT), "-B", str(tree / "build"), f"-DLIGGGHTS_TARBALL={debian_tarball()}",
             "-DSILOKIT_PGO=OFF", "-DSILOKIT_LTO=OFF", "-DSILOKIT_USE_VTK=OFF", "-DSILOKIT_LAMMPS=OFF",
             "-DSILOKIT_USER_STYLES=" + ";".join(str(d) for d in user_dirs)],
            capture_output=True, text=True)
    return run


def test_a_missing_directory_stops_cmake_naming_it(configure, tmp_path):
    result = configure(tmp_path / "no_such_dir")
    assert result.returncode != 0
    assert f"SILOKIT_USER_STYLES: {tmp_path / 'no_such_dir'} is not a directory" in " ".join(result.stderr.split())


def test_a_clashing_file_or_style_stops_cmake_naming_both(configure, tmp_path):
    header = (EXAMPLE / "fix_plane_crossings.h").read_text()
    same_file = tmp_path / "same_file"
    same_file.mkdir()
    (same_file / "fix_clog.h").write_text(header)
    result = configure(same_file)
    stderr = " ".join(result.stderr.split())
    assert result.returncode != 0
    assert f"{same_file / 'fix_clog.h'} has the name of a file of silokit" in stderr

    same_style = tmp_path / "same_style"
    same_style.mkdir()
    (same_style / "fix_my_wall.h").write_text(header.replace("plane/crossings", "wall/gran"))
    result = configure(same_style)
    stderr = " ".join(result.stderr.split())
    assert result.returncode != 0
    assert f"{same_style / 'fix_my_wall.h'} declares 'FixStyle wall/gran', which LIGGGHTS" in stderr

    # the example twice: its own files clash
    result = configure(EXAMPLE, EXAMPLE)
    assert result.returncode != 0 and "fix_plane_crossings" in result.stderr
    # and once, alone: accepted
    result = configure(EXAMPLE)
    assert result.returncode == 0, result.stderr
    assert f"user styles from {EXAMPLE}" in result.stdout
