"""cmake/LammpsSource.cmake and cmake/LammpsHost.cmake at configure time
(configure runs only, in one tree, no compile): a user's LAMMPS tree builds
only the plugin, a tree without the PLUGIN package and a tarball with
another sha256 stop with a message, -DSILOKIT_LAMMPS=OFF has no LAMMPS
targets. The build itself is checked by the other tests/test_lammps_*.py,
which run its lmp and plugin."""

import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LIGGGHTS_TARBALL = ROOT / "build" / "download" / "liggghts_3.8.0+repack1.orig.tar.xz"

pytestmark = pytest.mark.skipif(
    not LIGGGHTS_TARBALL.exists(),
    reason=f"{LIGGGHTS_TARBALL} (fetched by the default build) is absent: a configure would download it")


@pytest.fixture(scope="module")
def configure(tmp_path_factory):
    tree = tmp_path_factory.mktemp("lammps-configure") / "build"

    def run(*options):
        result = subprocess.run(
            ["cmake", "-S", str(ROOT), "-B", str(tree), f"-DLIGGGHTS_TARBALL={LIGGGHTS_TARBALL}",
             "-DSILOKIT_PGO=OFF", "-DSILOKIT_LTO=OFF", "-DSILOKIT_USE_VTK=OFF",
             "-ULAMMPS_*", *options],
            capture_output=True, text=True)
        targets = ""
        if result.returncode == 0:
            targets = subprocess.run(["cmake", "--build", str(tree), "--target", "help"],
                                     capture_output=True, text=True).stdout
        return result, " ".join((result.stdout + result.stderr).split()), targets
    return run


def fake_lammps_tree(path, plugin_header=True):
    (path / "src").mkdir(parents=True)
    (path / "src" / "lammps.cpp").write_text("")
    if plugin_header:
        (path / "src" / "lammpsplugin.h").write_text("")
    return path


def test_a_users_tree_builds_the_plugin_only(configure, tmp_path):
    tree = fake_lammps_tree(tmp_path / "lammps")
    result, output, targets = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={tree}")
    assert result.returncode == 0, output
    assert f"LAMMPS plugin against {tree}/src (LAMMPS itself not built)" in output
    assert "... silokit_lammps\n" in targets
    assert "... lammps\n" not in targets


def test_a_tree_without_the_plugin_package_stops(configure, tmp_path):
    tree = fake_lammps_tree(tmp_path / "old-lammps", plugin_header=False)
    result, output, _ = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={tree}")
    assert result.returncode != 0
    assert f"LAMMPS_SOURCE_DIR={tree} has no src/lammpsplugin.h" in output
    assert "predates the PLUGIN package" in output


def test_a_tarball_with_another_sum_stops(configure, tmp_path):
    tarball = tmp_path / "lammps_20220106.git7586adbb6a+ds1.orig.tar.xz"
    tarball.write_bytes(b"not LAMMPS")
    result, output, _ = configure("-DSILOKIT_LAMMPS=ON", "-DLAMMPS_SOURCE_DIR=",
                                  f"-DLAMMPS_TARBALL={tarball}")
    assert result.returncode != 0
    assert "expected 65146c615ad24d8b8bc64f4e05e86226a7f1fdb45c0b5ea9416562b9f3863082" in output


def test_lammps_off_has_no_lammps_targets(configure):
    result, output, targets = configure("-DSILOKIT_LAMMPS=OFF")
    assert result.returncode == 0, output
    assert "... liggghts\n" in targets
    assert "silokit_lammps" not in targets
    assert "... lammps\n" not in targets
