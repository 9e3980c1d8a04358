"""fix insert/poses: the bodies of a stock particle distribution placed once
at the positions and axes of a file.

A box without gravity or contacts between the bodies (they are placed
apart), one step run: the spheres of each clump must lie where the pose
and the template say, computed here from the pose alone (the template's
sphere offsets along the axis, the axis normalised); spheres at their
positions; two ranks place the same spheres; bad input gets an ERROR that
names what is wrong.
"""

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump
from analysis.testing import LiggghtsError
from conftest import has_mpirun

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

# three spheres of 3 mm radius along the template's x axis, 7 mm apart
OFFSETS = (-0.007, 0.0, 0.007)
RADIUS = 0.003
# x y z ax ay az: along x, against x (the half turn), a slanted axis given
# unnormalised, along z, and one across the middle of the box in x and y
# (wherever two ranks cut it, this clump's spheres lie on both sides)
POSES = [
    (0.0, 0.0, 0.05, 1.0, 0.0, 0.0),
    (0.03, 0.0, 0.05, -1.0, 0.0, 0.0),
    (-0.03, 0.02, 0.05, 1.0, 2.0, 2.0),
    (0.0, -0.03, 0.05, 0.0, 0.0, 1.0),
    (0.025, 0.03, 0.02, 0.3, -0.4, -0.5),
    (0.0, 0.0, 0.02, 1.0, 1.0, 0.0),
]


def poses_text(poses=POSES):
    return "# x y z ax ay az\n" + "".join(" ".join(repr(v) for v in pose) + "\n" for pose in poses)


def poses_deck(template="clump", fix_options="file poses.txt", before_fix="", steps=1):
    if template == "clump":
        spheres = " ".join(f"{s} 0 0 {RADIUS}" for s in OFFSETS)
        particles = (f"fix ms all multisphere allow_group_and_set yes\n"
                     f"fix template all particletemplate/multisphere 86028121 atom_type 1 density constant 1000 "
                     f"nspheres {len(OFFSETS)} ntry 100000 spheres {spheres} type 1")
    else:
        particles = ("fix template all particletemplate/sphere 86028121 atom_type 1 density constant 1000 "
                     f"radius constant {RADIUS}\nfix integrate all nve/sphere")
    return f"""
{granular_setup()}
region box block -0.06 0.06 -0.06 0.06 0 0.1 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(1e4, 1e4, gamman=0.1, gammat=0.1, mu=0.5)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep 1e-6
{particles}
fix distribution all particledistribution/discrete 86028157 1 template 1.0
{before_fix}
fix ins all insert/poses seed 15485863 distributiontemplate distribution {fix_options}
run {steps}
dump d all custom 1 atoms.txt id x y z radius
dump_modify d sort id format "%d %.17g %.17g %.17g %.17g"
run 0
"""


def placed_spheres(run, tmp_path, deck, nprocs=1, poses=None, subdir="."):
    (tmp_path / subdir).mkdir(parents=True, exist_ok=True)
    (tmp_path / subdir / "poses.txt").write_text(poses if poses is not None else poses_text())
    run(deck, nprocs=nprocs, subdir=subdir)
    _, frame = read_dump(tmp_path / subdir / "atoms.txt")[-1]
    return np.column_stack([frame["x"], frame["y"], frame["z"]]), np.asarray(frame["radius"])


def expected_clump_spheres(poses=POSES):
    centres = []
    for pose in poses:
        position, axis = np.array(pose[:3]), np.array(pose[3:])
        axis = axis / np.linalg.norm(axis)
        centres += [position + s * axis for s in OFFSETS]
    return np.array(centres)


def sorted_rows(points):
    return points[np.lexsort(points.T[::-1])]


def test_the_spheres_of_each_clump_lie_on_its_pose(run, tmp_path):
    # one step without gravity or contacts: nothing moves, so the dump shows
    # the placement; each pose's three spheres, in the order of the file
    # (one rank: bodies and spheres are tagged in insertion order)
    centres, radii = placed_spheres(run, tmp_path, poses_deck("clump"))
    assert centres.shape == (3 * len(POSES), 3)
    np.testing.assert_allclose(centres, expected_clump_spheres(), rtol=0, atol=1e-12)
    np.testing.assert_allclose(radii, RADIUS, rtol=1e-12)


def test_spheres_sit_at_the_positions_given(run, tmp_path):
    centres, radii = placed_spheres(run, tmp_path, poses_deck("sphere"))
    np.testing.assert_allclose(centres, np.array([p[:3] for p in POSES]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(radii, RADIUS, rtol=1e-12)


def test_a_one_frame_dump_of_x_y_z_and_the_axis_is_read_as_the_poses(run, tmp_path):
    # the form `in.silo3d_rotating -var write_poses 1` writes
    rows = "".join(" ".join(repr(v) for v in pose) + "\n" for pose in POSES)
    dump = ("ITEM: TIMESTEP\n1000\nITEM: NUMBER OF ATOMS\n6\nITEM: BOX BOUNDS ff ff ff\n"
            "-0.06 0.06\n-0.06 0.06\n0 0.1\nITEM: ATOMS x y z c_axis[1] c_axis[2] c_axis[3]\n" + rows)
    centres, _ = placed_spheres(run, tmp_path, poses_deck("clump"), poses=dump)
    np.testing.assert_allclose(centres, expected_clump_spheres(), rtol=0, atol=1e-12)


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_place_the_same_spheres(run, tmp_path):
    # the box is cut in two through the last clump: its spheres are created
    # by the rank that holds its centre, and one migrates; tags follow the
    # ranks' order, so the sets are compared
    one, _ = placed_spheres(run, tmp_path, poses_deck("clump"), subdir="np1")
    two, _ = placed_spheres(run, tmp_path, poses_deck("clump"), nprocs=2, subdir="np2")
    np.testing.assert_allclose(sorted_rows(two), sorted_rows(one), rtol=0, atol=1e-15)


def refused(run, tmp_path, fix_options="file poses.txt", poses=None):
    (tmp_path / "poses.txt").write_text(poses if poses is not None else poses_text())
    with pytest.raises(LiggghtsError) as caught:
        run(poses_deck("clump", fix_options=fix_options))
    return caught.value.message


@pytest.mark.parametrize("fix_options, expected", [
    ("", "'file <poses>' is required"),
    ("file", "keyword 'file' needs a file name"),
    ("file nowhere.txt", "cannot open the file 'nowhere.txt'"),
    ("file poses.txt colour red", "unknown keyword 'colour'"),
    ("overlapcheck yes file poses.txt", "'overlapcheck yes' is not supported"),
    ("orientation random file poses.txt", "'orientation' is not supported"),
    ("all_in yes file poses.txt", "'all_in' is not supported"),
    ("nparticles 10 file poses.txt", "inserts one body per pose of its file"),
    ("insert_every 100 file poses.txt", "inserts its poses once"),
])
def test_bad_keywords(run, tmp_path, fix_options, expected):
    assert expected in refused(run, tmp_path, fix_options=fix_options)


@pytest.mark.parametrize("poses, expected", [
    ("0 0 0.05 1 0\n", "poses.txt, line 1: expected 6 finite numbers, x y z ax ay az"),
    ("0 0 0.05 1 0 0 7\n", "poses.txt, line 1: more than 6 values"),
    ("# header\n0 0 0.05 1 0 nan\n", "poses.txt, line 2: expected 6 finite numbers"),
    ("0 0 0.05 0 0 0\n", "poses.txt, line 1: the axis (ax ay az) is zero"),
    ("0 0 0.5 1 0 0\n", "pose 1 of 'poses.txt' (0 0 0.5) lies outside the simulation box"),
    ("# nothing\n", "the file 'poses.txt' holds no pose"),
    ("ITEM: TIMESTEP\n0\nITEM: ATOMS id x y z ax ay az\n1 0 0 0.05 1 0 0\n",
     "the dump's ATOMS section must have 6 columns"),
    ("ITEM: TIMESTEP\n0\nITEM: ATOMS x y z a b c\n0 0 0.05 1 0 0\nITEM: TIMESTEP\n1\n",
     "the dump holds more than one frame"),
])
def test_bad_files(run, tmp_path, poses, expected):
    assert expected in refused(run, tmp_path, poses=poses)
