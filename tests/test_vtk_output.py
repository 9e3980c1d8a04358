"""ParaView output: LIGGGHTS' own VTK dump styles, compiled in when VTK is
installed (doc/vtk_output.md), as in Debian's liggghts.

- Style list: every style Debian's /usr/bin/liggghts lists in `-h` is in
  ours (ours has more). The seven VTK dump styles are checked apart: a
  build without VTK lacks them, and that test then fails and says why
  (the binary is no drop-in replacement for Debian's), unless VTK was
  switched off on purpose (-DSILOKIT_USE_VTK=OFF: it skips); every other
  style must be there in any build.
- Frames: a small pile of spheres in a cylinder on a meshed disc writes,
  at one step, a plain `dump custom`, custom/vtk, local/gran/vtk (the
  contact network of a compute pair/gran/local), mesh/vtk, and the other
  VTK styles. VTK's own readers (python3-vtk9, what ParaView uses) read
  them back: as many points as grains, at the positions of the plain dump
  (the VTK files hold them in single precision: equal to the plain dump's
  doubles rounded to float); one line per contact, between the two grains'
  centres, as many as the compute gives and as the pairs that overlap in
  the plain dump; the mesh's triangles at the STL's vertices. On 1 and 2
  ranks (output gathered into one file).
- The scene decks' -var vtk_every N switch writes custom/vtk frames of the
  grains (and mesh/vtk of the meshed bottom of the rotating silo) at the
  steps and positions of the decks' own plain dumps.

Without VTK in the build (or without python3-vtk9) the frame tests skip
with the reason.
"""

import locale
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump
from analysis.common.stl import annulus_triangles, write_stl
from conftest import LIGGGHTS, ROOT, has_mpirun, run_liggghts

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

DEBIAN_LIGGGHTS = Path("/usr/bin/liggghts")
VTK_DUMP_STYLES = {"atom/vtk", "custom/vtk", "custom/vtm", "local/gran/vtk",
                   "mesh/gran/VTK", "mesh/vtk", "mesh/vtm"}

RADIUS = 0.005
PLATE_TRIANGLES = annulus_triangles(0.0, 0.05, segments=16)   # a disc: 16 triangles
STEPS = 12000                   # 0.48 s at dt 4e-5 (t_c/20): the grains have landed
N_GRAINS = 96                   # the lattice sites in the gas cylinder


def compiled_styles(binary):
    """{section of `-h`: set of style names} from `binary -h`, e.g.
    styles["Dump styles"] = {"custom", "local", ...}."""
    output = subprocess.run([str(binary), "-h"], capture_output=True, text=True,
                            timeout=60).stdout
    _, _, listing = output.partition("Style options compiled with this executable")
    styles, section = {}, None
    for line in listing.splitlines():
        if line.startswith("* "):           # "* Dump styles:", "* Fix styles"
            section = line[2:].rstrip(":").strip()
            styles[section] = set()
        elif section:
            styles[section].update(line.split())
    return styles


@pytest.fixture(scope="module")
def our_styles(liggghts_binary):
    return compiled_styles(liggghts_binary)


@pytest.fixture(scope="module")
def debian_styles():
    if not DEBIAN_LIGGGHTS.exists():
        pytest.skip(f"{DEBIAN_LIGGGHTS} (Debian's liggghts, tools/install_deps.sh) is not installed")
    return compiled_styles(DEBIAN_LIGGGHTS)


def built_without_vtk_on_purpose():
    cache = LIGGGHTS.parent.parent / "CMakeCache.txt"
    return cache.exists() and "SILOKIT_USE_VTK:BOOL=OFF" in cache.read_text()


@pytest.fixture(scope="module")
def vtk_build(our_styles):
    """Skips a frame test when the binary or Python cannot do VTK."""
    if "custom/vtk" not in our_styles.get("Dump styles", set()):
        pytest.skip(f"{LIGGGHTS} was built without VTK: its VTK dump styles are absent "
                    "(install libvtk9-dev, as tools/install_deps.sh does, and rebuild)")
    pytest.importorskip("vtkmodules.vtkIOXML",
                        reason="VTK's Python bindings are not installed (python3-vtk9)")


# ------------------------------------------------------------- style list

def test_every_style_of_debians_liggghts_is_in_ours_vtk_dumps_apart(our_styles, debian_styles):
    missing = {section: sorted(names - our_styles.get(section, set()) - VTK_DUMP_STYLES)
               for section, names in debian_styles.items()}
    missing = {section: names for section, names in missing.items() if names}
    assert not missing, f"styles of {DEBIAN_LIGGGHTS} missing in {LIGGGHTS}: {missing}"
    # the sections were read: a change of the -h layout must not pass unseen
    assert {"Atom styles", "Pair styles", "Fix styles", "Compute styles",
            "Dump styles"} <= set(debian_styles)
    assert len(debian_styles["Fix styles"]) > 100


def test_debians_vtk_dump_styles_are_in_ours(our_styles, debian_styles):
    assert VTK_DUMP_STYLES <= debian_styles["Dump styles"]
    missing = sorted(VTK_DUMP_STYLES - our_styles["Dump styles"])
    if missing and built_without_vtk_on_purpose():
        pytest.skip(f"{LIGGGHTS} was configured with -DSILOKIT_USE_VTK=OFF: no {missing}")
    assert not missing, (
        f"{LIGGGHTS} lacks Debian's dump styles {missing}: it was built without VTK "
        "(install libvtk9-dev, as tools/install_deps.sh does, and rebuild)")


# ------------------------------------------------------------- frames

def vtk_read(path):
    """The dataset in a VTK file, read by VTK's reader for its kind."""
    from vtkmodules.vtkIOLegacy import vtkGenericDataObjectReader
    from vtkmodules.vtkIOXML import (vtkXMLMultiBlockDataReader, vtkXMLPolyDataReader,
                                     vtkXMLUnstructuredGridReader)
    readers = {".vtu": vtkXMLUnstructuredGridReader, ".vtp": vtkXMLPolyDataReader,
               ".vtm": vtkXMLMultiBlockDataReader, ".vtk": vtkGenericDataObjectReader}
    assert Path(path).exists(), f"{path} was not written"
    reader = readers[Path(path).suffix]()
    reader.SetFileName(str(path))
    # VTK's legacy reader leaves the process in the C locale: Python would
    # then decode the later tests' subprocess output as ASCII
    saved = locale.setlocale(locale.LC_ALL)
    try:
        reader.Update()
    finally:
        locale.setlocale(locale.LC_ALL, saved)
    return reader.GetOutput()


def points_of(dataset):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    return vtk_to_numpy(dataset.GetPoints().GetData())


def array_of(data, name):
    """A named array of a vtkPointData/vtkCellData as numpy."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    array = data.GetArray(name)
    assert array is not None, f"no array {name!r}"
    return vtk_to_numpy(array)


def as_float32(values):
    """What VTK's float points hold: the doubles rounded to single precision."""
    return np.asarray(values, dtype=np.float64).astype(np.float32)


def overlapping_pairs(grains):
    """(id1, id2) with id1 < id2 of the grains that overlap in a dump frame."""
    xyz = np.column_stack([grains["x"], grains["y"], grains["z"]])
    distance = np.linalg.norm(xyz[:, None, :] - xyz[None, :, :], axis=2)
    reach = grains["radius"][:, None] + grains["radius"][None, :]
    i, j = np.nonzero(np.triu(distance < reach, k=1))
    ids = grains["id"].astype(int)
    return {(min(a, b), max(a, b)) for a, b in zip(ids[i], ids[j])}


def cell_point_ids(dataset, cell):
    """The point ids of a cell, copied out (GetCell() hands back one cell
    object that the next call overwrites)."""
    ids = dataset.GetCell(cell).GetPointIds()
    return [ids.GetId(k) for k in range(ids.GetNumberOfIds())]


def assert_same_triangles(mesh, triangles, tolerance=1e-7):
    """The cells of a VTK mesh are the triangles given (3 vertices each),
    each once, in any order and with their vertices in any order (LIGGGHTS
    may reorder both)."""
    points = points_of(mesh)
    left = [as_float32(triangle) for triangle in triangles]
    for cell in range(mesh.GetNumberOfCells()):
        corners = points[cell_point_ids(mesh, cell)]
        assert len(corners) == 3
        same = [k for k, triangle in enumerate(left)
                if all(np.linalg.norm(triangle - corner, axis=1).min() < tolerance for corner in corners)]
        assert same, f"a mesh cell that is no triangle of the STL (or one twice): {corners}"
        left.pop(same[0])
    assert not left


def pile_deck():
    """Spheres from a jittered lattice fall into a cylinder (primitive wall)
    closed by a meshed disc and come to rest in a few layers; at the last
    step every dump writes, the plain ones in full precision."""
    return f"""
{granular_setup()}
region box block -0.05 0.05 -0.05 0.05 -0.01 0.11 units box
create_box 1 box
lattice sc 0.012 origin 0.5 0.5 0.5
region gas cylinder z 0.0 0.0 0.02 0.004 0.1 units box
create_atoms 1 region gas
displace_atoms all random 0.001 0.001 0.001 15485863 units box
set group all diameter {2 * RADIUS} density 2500
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(1e4, 2.0 / 7.0 * 1e4, gamman=100.0, gammat=100.0, mu=0.5)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep 4e-5
fix plate all mesh/surface file plate.stl type 1
fix floor all wall/gran model hooke/stiffness tangential history mesh n_meshes 1 meshes plate
fix side all wall/gran model hooke/stiffness tangential history primitive type 1 zcylinder 0.025 0.0 0.0
fix gravity all gravity 9.81 vector 0 0 -1
fix integrate all nve/sphere
compute contacts all pair/gran/local id pos force
thermo 1000
thermo_modify lost error

dump plain all custom {STEPS} plain.dump id type x y z radius
dump_modify plain sort id format "%d %d %.17g %.17g %.17g %.17g"
dump table all local {STEPS} contacts.dump c_contacts[1] c_contacts[2]
dump grains all custom/vtk {STEPS} grains_*.vtu id type vx vy vz radius
dump network all local/gran/vtk {STEPS} contacts_*.vtp contacts
dump mesh all mesh/vtk {STEPS} plate_*.vtk id plate
dump atoms all atom/vtk {STEPS} atoms_*.vtu
dump everything all custom/vtm {STEPS} ./frame_*.vtm particle_properties id radius meshes all local_gran contacts
dump mesh_vtm all mesh/vtm {STEPS} plate_*.vtm meshes plate
dump mesh_gran all mesh/gran/VTK {STEPS} plate_gran_*.vtk id plate
run {STEPS}
"""


@pytest.fixture(scope="module", params=[1, 2], ids=["np1", "np2"])
def pile(request, tmp_path_factory, vtk_build):
    if request.param > 1 and not has_mpirun():
        pytest.skip("needs mpirun")
    workdir = tmp_path_factory.mktemp(f"vtk_pile_np{request.param}")
    write_stl(workdir / "plate.stl", PLATE_TRIANGLES)
    output = run_liggghts(pile_deck(), workdir, nprocs=request.param)
    step, grains = read_dump(workdir / "plain.dump")[-1]
    assert step == STEPS
    return workdir, grains, output


def test_custom_vtk_has_every_grain_where_the_plain_dump_has_it(pile):
    workdir, grains, _ = pile
    frame = vtk_read(workdir / f"grains_{STEPS}.vtu")
    assert frame.GetNumberOfPoints() == grains["id"].size == N_GRAINS
    ids = array_of(frame.GetPointData(), "id")
    order = np.argsort(ids)
    np.testing.assert_array_equal(ids[order], grains["id"])
    expected = as_float32(np.column_stack([grains["x"], grains["y"], grains["z"]]))
    np.testing.assert_array_equal(points_of(frame)[order], expected)
    np.testing.assert_array_equal(array_of(frame.GetPointData(), "radius")[order], grains["radius"])
    # vx vy vz come as one vector array "v" (ParaView colours by its magnitude)
    assert array_of(frame.GetPointData(), "v").shape == (N_GRAINS, 3)


def test_local_gran_vtk_is_the_contact_network(pile):
    workdir, grains, _ = pile
    network = vtk_read(workdir / f"contacts_{STEPS}.vtp")
    _, table = read_dump(workdir / "contacts.dump")[-1]
    overlapping = overlapping_pairs(grains)
    assert len(overlapping) >= 20                        # a pile, not a gas
    # one line cell per contact of the compute, and those are the pairs
    # that overlap in the plain dump
    assert network.GetNumberOfLines() == network.GetNumberOfCells() == table["c_contacts[1]"].size
    id1 = array_of(network.GetCellData(), "id1").astype(int)
    id2 = array_of(network.GetCellData(), "id2").astype(int)
    assert {(min(a, b), max(a, b)) for a, b in zip(id1, id2)} == overlapping
    assert len(id1) == len(overlapping)                  # no pair twice (2 ranks)
    # each line runs from the centre of its first grain to that of its second
    where = {int(i): k for k, i in enumerate(grains["id"])}
    centres = as_float32(np.column_stack([grains["x"], grains["y"], grains["z"]]))
    points = points_of(network)
    for cell, (a, b) in enumerate(zip(id1, id2)):
        first, second = cell_point_ids(network, cell)
        np.testing.assert_array_equal(points[first], centres[where[a]])
        np.testing.assert_array_equal(points[second], centres[where[b]])
    assert array_of(network.GetCellData(), "force").shape == (len(id1), 3)


def test_mesh_vtk_is_the_stl(pile):
    workdir, _, _ = pile
    for name in (f"plate_{STEPS}.vtk", f"plate_gran_{STEPS}.vtk"):
        mesh = vtk_read(workdir / name)
        assert mesh.GetNumberOfCells() == len(PLATE_TRIANGLES) == 16
        assert_same_triangles(mesh, PLATE_TRIANGLES)


def test_the_other_vtk_styles_write_frames_paraview_reads(pile):
    """atom/vtk (an XML .vtu, whatever the file name says), custom/vtm (one
    multiblock file: mesh, contacts, grains, box) and mesh/vtm: read back
    with the right counts."""
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
    workdir, grains, _ = pile
    atoms = vtk_read(workdir / f"atoms_{STEPS}.vtu")
    assert atoms.GetNumberOfPoints() == grains["id"].size
    everything = vtk_read(workdir / f"frame_{STEPS}.vtm")
    assert isinstance(everything, vtkMultiBlockDataSet)
    blocks = {everything.GetMetaData(k).Get(vtkMultiBlockDataSet.NAME()): everything.GetBlock(k)
              for k in range(everything.GetNumberOfBlocks())}
    assert blocks["Particles"].GetNumberOfPoints() == grains["id"].size
    assert blocks["plate"].GetNumberOfCells() == len(PLATE_TRIANGLES)
    assert blocks["local_gran_contacts"].GetNumberOfLines() == len(overlapping_pairs(grains))
    meshes = vtk_read(workdir / f"plate_{STEPS}.vtm")
    assert meshes.GetNumberOfBlocks() == 1
    assert meshes.GetBlock(0).GetNumberOfCells() == len(PLATE_TRIANGLES)


# ------------------------------------------------------------- the scene decks' switch

INPUTS = ROOT / "inputs"


def run_deck(path, workdir, nprocs=1, **variables):
    return run_liggghts(Path(path).read_text(), workdir, nprocs=nprocs, timeout=900,
                        variables={"inputs": INPUTS, **variables})


def frames(workdir, prefix, suffix=".vtu"):
    """{step: path} of the frames <prefix>_<step><suffix> a deck wrote."""
    found = {}
    for path in Path(workdir).glob(f"{prefix}_*{suffix}"):
        step = path.name[len(prefix) + 1:-len(suffix)]
        if step.isdigit():
            found[int(step)] = path
    return found


def check_frames_against_plain_dump(workdir, prefix, dump_name, every):
    """The deck's custom/vtk frames come every `every` steps and hold, at
    each step its plain dump also has, the same grains at the same places
    (the plain dump is written with 6 digits: rtol 1e-5). Returns the
    frames (step -> dataset)."""
    written = {step: vtk_read(path) for step, path in frames(workdir, prefix).items()}
    assert written and all(step % every == 0 for step in written)
    common = 0
    for step, grains in read_dump(Path(workdir) / dump_name):
        if step not in written:
            continue
        frame = written[step]
        ids = array_of(frame.GetPointData(), "id")
        order = np.argsort(ids)
        np.testing.assert_array_equal(ids[order], grains["id"])
        np.testing.assert_array_equal(array_of(frame.GetPointData(), "type")[order], grains["type"])
        plain = np.column_stack([grains[c] if c in grains else np.zeros_like(grains["x"])
                                 for c in ("x", "y", "z")])
        np.testing.assert_allclose(points_of(frame)[order], plain, rtol=1e-5, atol=1e-9)
        np.testing.assert_allclose(array_of(frame.GetPointData(), "radius")[order],
                                   grains["radius"], rtol=1e-5)
        common += 1
    assert common >= 2
    return written


def test_silo2d_deck_writes_paraview_frames(tmp_path, vtk_build):
    """Filling and 0.1 s of flow of the quick silo, frames every 10000 steps."""
    run_deck(INPUTS / "silo2d" / "in.silo2d", tmp_path, quick=1, total_time=0.1,
             vtk_every=10000, dump_every=10000)
    written = check_frames_against_plain_dump(tmp_path, "silo2d", "dump.silo2d", 10000)
    assert all(frame.GetNumberOfPoints() == 312 for frame in written.values())


@pytest.mark.skipif(not has_mpirun(), reason="needs mpirun")
def test_silo2d_deck_on_two_ranks_writes_one_file_per_frame(tmp_path, vtk_build):
    run_deck(INPUTS / "silo2d" / "in.silo2d", tmp_path, nprocs=2, quick=1, total_time=0.1,
             vtk_every=10000, dump_every=10000)
    check_frames_against_plain_dump(tmp_path, "silo2d", "dump.silo2d", 10000)
    assert not list(tmp_path.glob("silo2d_*_*.vtu"))      # no file per rank


def test_pile2d_decks_write_paraview_frames(tmp_path, vtk_build):
    """A small pile (30 grains) built and discharged, frames of both decks."""
    common = {"quick": 1, "model": "fixed", "dump_every": 300, "vtk_every": 300}
    run_deck(INPUTS / "pile2d" / "in.build", tmp_path, max_grains=30, settle_time=2,
             pile="pile.restart", piles="piles.txt", **common)
    run_deck(INPUTS / "pile2d" / "in.discharge", tmp_path, pile="pile.restart", w=4,
             max_time=2, results="discharges.txt", **common)
    for deck in ("build", "discharge"):
        check_frames_against_plain_dump(tmp_path, deck, f"dump.{deck}", 300)


SILO3D = INPUTS / "silo3d_rotating" / "in.silo3d_rotating"
SILO3D_DT = 4e-6                 # fixed, so that dump_every_time is a whole number of steps


@pytest.mark.parametrize("shape", ["sphere", "rod"])
def test_silo3d_rotating_deck_writes_paraview_frames(tmp_path, vtk_build, shape):
    """0.02 s of settling and 0.02 s of discharge of the quick silo; with
    spheres on the meshed bottom (mesh_bottom 1, turning): its frames from
    the opening on hold the STL's triangles; rods carry their unit axis."""
    every = 2000
    variables = {"quick": 1, "shape": shape, "settle_time": 0.02, "discharge_time": 0.02,
                 "dt": SILO3D_DT, "vtk_every": every, "dump_every_time": every * SILO3D_DT}
    if shape == "sphere":
        triangles = annulus_triangles(0.05 / 2, 0.1188 / 2, segments=32)
        write_stl(tmp_path / "bottom.stl", triangles)
        variables.update(mesh_bottom=1, f=1.0)
    run_deck(SILO3D, tmp_path, **variables)
    written = check_frames_against_plain_dump(tmp_path, "silo3d", "dump.cg", every)
    settling = written[every]                # spheres are inserted at step 1
    assert settling.GetNumberOfPoints() == (900 if shape == "sphere" else 300)
    if shape == "rod":
        axes = array_of(settling.GetPointData(), "c_rod_axis[1-3]")
        np.testing.assert_allclose(np.linalg.norm(axes, axis=1), 1.0, rtol=1e-9)
        return
    bottoms = frames(tmp_path, "bottom", ".vtk")
    t_open_step = round(0.02 / SILO3D_DT)
    assert bottoms and min(bottoms) == math.ceil(t_open_step / every) * every
    mesh = vtk_read(bottoms[max(bottoms)])
    assert mesh.GetNumberOfCells() == len(triangles) == 64
    assert_same_triangles(mesh, triangles)


def test_the_decks_write_no_frames_by_default(tmp_path, liggghts_binary):
    """vtk_every 0 (the default): no dump is defined, so a build without
    VTK runs the decks as before."""
    run_deck(INPUTS / "silo2d" / "in.silo2d", tmp_path, quick=1, total_time=0.1)
    assert not list(tmp_path.glob("*.vt?"))
