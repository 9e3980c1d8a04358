"""cmake/LammpsSource.cmake and cmake/LammpsHost.cmake at configure time
(configure runs only, in one tree, no compile): a user's LAMMPS tree builds
only the plugin, the checks of the LAMMPS calls that changed after
20220106 follow the tree, a tree without the PLUGIN package or with
unreadable headers and a tarball with another sha256 stop with a message,
-DSILOKIT_LAMMPS=OFF has no LAMMPS targets. The build itself is checked
by the other tests/test_lammps_*.py, which run its lmp and plugin."""

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


# Stand-ins for the headers that cmake/LammpsCompat.cmake compiles against:
# the declarations our adapters call, as LAMMPS 20220106 (ours) has them
# and as 4Feb2025 (Debian 13's) has them instead (checked by hand against
# both trees, doc/lammps_host.md section 7)
HEADERS_20220106 = {
    "pair.h": "namespace LAMMPS_NS { class Pair { public:\n"
              "  virtual ~Pair() = default;\n"
              "  virtual void transfer_history(double *, double *) {} }; }\n",
    "neighbor.h": "namespace LAMMPS_NS { class Neighbor { public:\n"
                  "  int request(void *, int instance = 0); }; }\n",
    "fix.h": "namespace LAMMPS_NS { class Fix {}; }\n",
    "modify.h": "namespace LAMMPS_NS { class Modify { public:\n"
                "  int find_fix_by_style(const char *); }; }\n",
    "region.h": "namespace LAMMPS_NS { class Region {}; }\n",
    "domain.h": "namespace LAMMPS_NS { class Domain { public:\n"
                "  int find_region(const char *); }; }\n",
}
HEADERS_4FEB2025 = {
    "pair.h": "namespace LAMMPS_NS { class Pair { public:\n"
              "  virtual ~Pair() = default;\n"
              "  virtual void transfer_history(double *, double *, int, int) {} }; }\n",
    "neighbor.h": "namespace LAMMPS_NS {\n"
                  "namespace NeighConst { enum { REQ_SIZE = 1 << 3, REQ_HISTORY = 1 << 4 }; }\n"
                  "class Pair;\n"
                  "class Neighbor { public:\n"
                  "  void add_request(Pair *, int flags = 0); }; }\n",
    "fix.h": HEADERS_20220106["fix.h"],
    "modify.h": "#include <string>\n#include <vector>\n"
                "namespace LAMMPS_NS { class Fix; class Modify { public:\n"
                "  std::vector<Fix *> get_fix_by_style(const std::string &) const; }; }\n",
    "region.h": HEADERS_20220106["region.h"],
    "domain.h": "#include <string>\n"
                "namespace LAMMPS_NS { class Region; class Domain { public:\n"
                "  Region *get_region_by_id(const std::string &) const; }; }\n",
}
API_CHECKS = ("SILOKIT_LAMMPS_ADD_REQUEST", "SILOKIT_LAMMPS_GET_FIX_BY_STYLE",
              "SILOKIT_LAMMPS_GET_REGION_BY_ID", "SILOKIT_LAMMPS_HISTORY_TYPES")


def fake_lammps_tree(path, plugin_header=True, headers=HEADERS_20220106):
    (path / "src").mkdir(parents=True)
    (path / "src" / "lammps.cpp").write_text("")
    if plugin_header:
        (path / "src" / "lammpsplugin.h").write_text("")
    for name, text in headers.items():
        (path / "src" / name).write_text(text)
    return path


def test_a_users_tree_builds_the_plugin_only(configure, tmp_path):
    tree = fake_lammps_tree(tmp_path / "lammps")
    result, output, targets = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={tree}")
    assert result.returncode == 0, output
    assert f"LAMMPS plugin against {tree}/src (LAMMPS itself not built)" in output
    assert "... silokit_lammps\n" in targets
    assert "... lammps\n" not in targets


def test_the_api_checks_follow_the_tree(configure, tmp_path):
    older = fake_lammps_tree(tmp_path / "lammps-20220106")
    newer = fake_lammps_tree(tmp_path / "lammps-4Feb2025", headers=HEADERS_4FEB2025)
    result, output, _ = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={older}")
    assert result.returncode == 0, output
    for check in API_CHECKS:
        assert f"Performing Test {check} - Failed" in output
    # the same build tree, another LAMMPS: the cached results are not reused
    result, output, _ = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={newer}")
    assert result.returncode == 0, output
    for check in API_CHECKS:
        assert f"Performing Test {check} - Success" in output
    # ... but they are for the same tree
    result, output, _ = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={newer}")
    assert result.returncode == 0, output
    assert "Performing Test" not in output


def test_unreadable_headers_stop_instead_of_choosing_the_old_api(configure, tmp_path):
    tree = fake_lammps_tree(tmp_path / "broken", headers={"pair.h": "#error broken header\n"})
    result, output, _ = configure("-DSILOKIT_LAMMPS=ON", f"-DLAMMPS_SOURCE_DIR={tree}")
    assert result.returncode != 0
    assert f"cannot compile against the LAMMPS headers in {tree}/src" in output


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
