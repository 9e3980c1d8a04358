"""The build options SILOKIT_LTO and SILOKIT_PGO (cmake/Optimization.cmake)
without building LIGGGHTS again: the profile step on stand-in files, the
configure step of a PGO tree, and the built binary itself."""

import collections
import os
import subprocess
from pathlib import Path

import pytest

from conftest import LIGGGHTS, ROOT

PROFILE_SCRIPT = ROOT / "cmake" / "PgoProfile.cmake"


def liggghts_tarball():
    """Debian's source tarball the tested binary was built from: fetched
    into its build tree, or given to it as LIGGGHTS_TARBALL."""
    build = LIGGGHTS.parent.parent
    fetched = build / "download" / "liggghts_3.8.0+repack1.orig.tar.xz"
    if fetched.exists():
        return fetched
    cache = build / "CMakeCache.txt"
    if cache.exists():
        for line in cache.read_text().splitlines():
            if line.startswith("LIGGGHTS_TARBALL:") and line.split("=", 1)[1]:
                return Path(line.split("=", 1)[1])
    return fetched


TARBALL = liggghts_tarball()


def make_profile(raw, profile, header, **replace):
    args = {"RAW": raw, "PROFILE": profile, "HEADER": header,
            "FROM": "liggghts_instrumented.dir", "TO": "liggghts.dir", **replace}
    return subprocess.run(["cmake"] + [f"-D{k}={v}" for k, v in args.items()]
                          + ["-P", str(PROFILE_SCRIPT)], capture_output=True, text=True)


def test_the_profile_is_renamed_for_the_liggghts_target_and_its_header_changes_only_with_it(tmp_path):
    raw, profile, header = tmp_path / "raw", tmp_path / "profile", tmp_path / "profile.h"
    raw.mkdir()
    names = ["CMakeFiles#liggghts_instrumented.dir#liggghts#src#pair_gran.cpp.gcda",
             "CMakeFiles#liggghts_instrumented.dir#liggghts#src#fix_clog.cpp.gcda"]
    for k, name in enumerate(names):
        (raw / name).write_bytes(bytes([k]) * 16)
    assert make_profile(raw, profile, header).returncode == 0
    assert sorted(p.name for p in profile.iterdir()) == sorted(
        n.replace("liggghts_instrumented.dir", "liggghts.dir") for n in names)
    assert (profile / names[0].replace("_instrumented", "")).read_bytes() == bytes([0]) * 16
    first = header.read_text()
    assert first.startswith("/* silokit PGO profile: 2 files, sha256 ") and first.endswith("*/\n")

    # the same counts again: the header is left alone (nothing recompiles)
    os.utime(header, (0, 0))
    assert make_profile(raw, profile, header).returncode == 0
    assert header.stat().st_mtime == 0 and header.read_text() == first
    # other counts: a new header (every liggghts source recompiles)
    (raw / names[1]).write_bytes(b"\x07" * 16)
    assert make_profile(raw, profile, header).returncode == 0
    assert header.read_text() != first


def test_the_profile_step_stops_on_an_empty_training(tmp_path):
    (tmp_path / "raw").mkdir()
    result = make_profile(tmp_path / "raw", tmp_path / "profile", tmp_path / "profile.h")
    assert result.returncode != 0 and "wrote no profile" in result.stderr


@pytest.mark.engine
def test_the_built_binary_is_not_the_instrumented_one():
    """An instrumented liggghts would write .gcda files wherever it runs."""
    if not LIGGGHTS.exists():
        pytest.fail(f"{LIGGGHTS} is missing: build it with tools/build.sh")
    assert b"__gcov_merge_add" not in LIGGGHTS.read_bytes()


@pytest.mark.skipif(not TARBALL.exists(), reason=f"{TARBALL} (fetched by the default build) is absent")
def test_a_pgo_tree_configures_with_its_instrumented_target_and_training_step(tmp_path):
    """Configure only (a few seconds): the targets the PGO build adds."""
    build = tmp_path / "build"
    configure = subprocess.run(
        ["cmake", "-S", str(ROOT), "-B", str(build), f"-DLIGGGHTS_TARBALL={TARBALL}",
         "-DSILOKIT_PGO=ON", "-DSILOKIT_LTO=ON", "-DSILOKIT_USE_VTK=OFF", "-DSILOKIT_LAMMPS=OFF"],
        capture_output=True, text=True)
    assert configure.returncode == 0, configure.stdout + configure.stderr
    assert "profile-guided optimisation on" in configure.stdout
    assert "link-time optimisation on" in configure.stdout
    targets = subprocess.run(["cmake", "--build", str(build), "--target", "help"],
                             capture_output=True, text=True).stdout
    for target in ("liggghts", "liggghts_instrumented", "pgo_profile"):
        assert f"... {target}\n" in targets


@pytest.mark.skipif(not TARBALL.exists(), reason=f"{TARBALL} (fetched by the default build) is absent")
def test_a_reconfigure_leaves_the_version_header_as_it_was(tmp_path):
    """tools/build.sh configures every time, and LIGGGHTS' Make.sh rewrites
    version_liggghts.h with the date each time it runs: the header must come
    out with our stable text and, when that text is unchanged, its old time
    (else universe.cpp recompiles and, with PGO, everything after a new
    training)."""
    build = tmp_path / "build"
    command = ["cmake", "-S", str(ROOT), "-B", str(build), f"-DLIGGGHTS_TARBALL={TARBALL}",
               "-DSILOKIT_PGO=OFF", "-DSILOKIT_LTO=OFF", "-DSILOKIT_USE_VTK=OFF", "-DSILOKIT_LAMMPS=OFF"]
    header = build / "liggghts" / "src" / "version_liggghts.h"
    stable = '#define LIGGGHTS_VERSION "LIGGGHTS-PUBLIC 3.8.0, with silokit styles"\n'

    first = subprocess.run(command, capture_output=True, text=True)
    assert first.returncode == 0, first.stdout + first.stderr
    assert header.read_text() == stable
    os.utime(header, (1_000_000, 1_000_000))
    again = subprocess.run(command, capture_output=True, text=True)
    assert again.returncode == 0, again.stdout + again.stderr
    assert header.read_text() == stable and header.stat().st_mtime == 1_000_000

    # a header with another text (a tree configured by an older silokit) is
    # replaced, with a new time
    header.write_text('#define LIGGGHTS_VERSION "compiled yesterday"\n')
    os.utime(header, (1_000_000, 1_000_000))
    third = subprocess.run(command, capture_output=True, text=True)
    assert third.returncode == 0, third.stdout + third.stderr
    assert header.read_text() == stable and header.stat().st_mtime > 1_000_000
    assert not (build / "liggghts" / ".silokit-version_liggghts.h").exists()


def listed_functions(variable):
    """The symbols a list of CMakeLists.txt names: SILOKIT_SCALAR_FUNCTIONS
    (GCC's SLP vectoriser leaves them alone), SILOKIT_ROLLED_FUNCTIONS (its
    loop unroller does)."""
    text = (ROOT / "CMakeLists.txt").read_text()
    block = text[text.index(f"set({variable}"):]
    block = block[:block.index(")\n")]
    return [line.strip() for line in block.splitlines()[1:]
            if line.strip() and not line.strip().startswith("#")]


def text_symbols():
    """{symbol: (address, size)} of the code in the tested binary."""
    if not LIGGGHTS.exists():
        pytest.fail(f"{LIGGGHTS} is missing: build it with tools/build.sh")
    symbols = {}
    for line in subprocess.run(["nm", "-S", str(LIGGGHTS)], capture_output=True, text=True,
                               check=True).stdout.splitlines():
        fields = line.split()
        if len(fields) == 4 and fields[2] in "Tt":
            symbols[fields[3]] = (int(fields[0], 16), int(fields[1], 16))
    return symbols


def disassembly(symbols, name):
    """The instructions of one function of the tested binary, found under its
    symbol or the one LTO gives a local copy (".lto_priv.0")."""
    found = [s for s in (name, name + ".lto_priv.0") if s in symbols]
    assert found, f"{name} is not in {LIGGGHTS}"
    start, size = symbols[found[0]]
    code = subprocess.run(["objdump", "-d", "--no-show-raw-insn", f"--start-address={start}",
                           f"--stop-address={start + size}", str(LIGGGHTS)],
                          capture_output=True, text=True, check=True).stdout
    assert code.count("\n") > 100, f"{found[0]}: no code disassembled"
    return code


@pytest.mark.engine
def test_the_hertz_contact_functions_are_built_scalar():
    """The Hertz model's functions of SILOKIT_SCALAR_FUNCTIONS are in the
    binary and execute no packed multiplication. With the vectoriser on,
    CI's build of d2ca70c had 6 `mulpd` in the normal model and 22 in the
    pair's compute_force (doc/build.md, "mesh_tet: a load the store buffer
    cannot serve"); a renamed or missing symbol fails here rather than
    silently leaving the function vectorised."""
    names = listed_functions("SILOKIT_SCALAR_FUNCTIONS")
    assert len(names) == 3 and all(name.startswith("_ZN8LIGGGHTS") for name in names)
    symbols = text_symbols()
    for name in names:
        assert "mulpd" not in disassembly(symbols, name), \
            f"{name} is vectorised: it has packed multiplications"


@pytest.mark.engine
def test_the_multicontact_pre_force_copies_inline():
    """FixMultiContactHalfSpace::pre_force copies its 4-double vectors
    inline, as Debian's binary does. Without -fno-tree-loop-distribute-patterns
    on its file (CMakeLists.txt), GCC made 7 memcpy calls of them (CI's
    builds of d2ca70c and 81138d3), and the hydrogel_multicontact tutorial
    ran 1.6-1.8 % slower than Debian's (doc/build.md, "hydrogel_multicontact:
    memcpy for four doubles")."""
    code = disassembly(text_symbols(), "_ZN9LAMMPS_NS24FixMultiContactHalfSpace9pre_forceEi")
    assert "call" in code, "pre_force calls nothing: not the function this test reads"
    calls = [line for line in code.splitlines() if "call" in line and ("memcpy" in line or "memmove" in line)]
    assert not calls, "pre_force calls memcpy:\n" + "\n".join(calls)


@pytest.mark.engine
def test_the_multicontact_pair_searches_its_partners_in_a_rolled_loop():
    """The Hertz pair with the multicontact surface (SILOKIT_ROLLED_FUNCTIONS)
    searches a contact's partner list in a rolled loop, as Debian's binary
    does. LIGGGHTS' -funroll-loops copied the search 8 times: 8
    conditional exits to one label, 15-17 to each of the function's three
    busiest (CI's build of b06b852), and the hydrogel_multicontact tutorial
    ran 0.5 % slower than Debian's; rolled, no label has more than 4
    (doc/build.md, "hydrogel_multicontact: the unrolled partner search")."""
    names = listed_functions("SILOKIT_ROLLED_FUNCTIONS")
    assert len(names) == 1 and "GranStyleILi3ELi2ELi0ELi0ELi2E" in names[0]
    code = disassembly(text_symbols(), names[0])
    targets = collections.Counter(
        fields[2] for fields in (line.split() for line in code.splitlines())
        if len(fields) >= 3 and fields[1].startswith("j") and fields[1] != "jmp")
    assert sum(targets.values()) > 50, "few conditional jumps: not the function this test reads"
    label, fan_in = targets.most_common(1)[0]
    assert fan_in < 8, f"{fan_in} conditional jumps to {label}: a loop unrolled 8 times"
