"""fix nve/spherocylinder's neighbour-list pruning (prune_list, default
yes; src_plugin/liggghts/spherocylinder_list_pruning.h), run by the built LIGGGHTS.

After each build the pair list keeps only the pairs whose cores are closer
than d + skin; a rod that turns asks for a build before its ends have
travelled skin/2. Checked against an independent count of the pairs
(segment distances computed here, by a convex search, not by the C++
geometry), and against the same runs with prune_list no."""

import numpy as np

from analysis.common.lammps_io import read_dump
from conftest import run_liggghts
from test_spherocylinder import D, HALF_SEGMENT, LENGTH, SKIN, gas_deck, rod_contacts, rod_deck, rod_system
import pytest

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)
PRUNING_VECTOR = """variable listed equal f_move[1]
variable kept equal f_move[2]
variable asked equal f_move[3]"""
PRINT_PRUNING = 'print "pruning ${listed} ${kept} ${asked}"'


def pruning_counts(screen):
    """(pairs listed, pairs kept, builds asked) from PRINT_PRUNING's line."""
    line = [l for l in screen.splitlines() if l.startswith("pruning ")][-1]
    return tuple(float(word) for word in line.split()[1:])


def without_pruning(deck):
    assert "fix move all nve/spherocylinder\n" in deck
    return deck.replace("fix move all nve/spherocylinder\n",
                        "fix move all nve/spherocylinder prune_list no\n")


def point_to_segment(points, centres, axes, half):
    """Distance of each point to the segment centre + t axis, |t| <= half."""
    t = np.clip(np.einsum("ij,ij->i", points - centres, axes), -half, half)
    return np.linalg.norm(points - centres - t[:, None] * axes, axis=1)


def segment_distances(c1, a1, c2, a2, half, iterations=200):
    """Least distance between segments, pairwise over rows: the distance
    from a point moving along segment 1 to segment 2 is convex in its
    parameter, so a ternary search finds the minimum."""
    lo = np.full(len(c1), -half)
    hi = np.full(len(c1), half)
    for _ in range(iterations):
        m1 = lo + (hi - lo) / 3
        m2 = hi - (hi - lo) / 3
        f1 = point_to_segment(c1 + m1[:, None] * a1, c2, a2, half)
        f2 = point_to_segment(c1 + m2[:, None] * a1, c2, a2, half)
        left = f1 < f2
        hi = np.where(left, m2, hi)
        lo = np.where(left, lo, m1)
    return point_to_segment(c1 + 0.5 * (lo + hi)[:, None] * a1, c2, a2, half)


def test_the_kept_pairs_are_those_whose_cores_come_within_d_plus_skin(run, tmp_path):
    """27 rods of random axes on a lattice of spacing 2.5 d in a closed box
    (no periodic images: each pair is listed once). At the first build
    LIGGGHTS lists the pairs whose centres are within L + skin; the kept
    ones must be exactly those whose cores are within d + skin."""
    spacing = 2.5 * D
    lattice = "\n".join(
        f"create_atoms 1 single {spacing * i!r} {spacing * j!r} {spacing * k!r} units box"
        for k in range(3) for j in range(3) for i in range(3))
    deck = f"""{rod_system()}
region box block -0.05 0.1 -0.05 0.1 -0.05 0.1 units box
create_box 1 box
{lattice}
set_spherocylinder all diameter {D!r} length {LENGTH!r} density 1000 axis random 15485863
{rod_contacts(1e-6)}
fix move all nve/spherocylinder
compute axis all spherocylinder/axis
{PRUNING_VECTOR}
run 0
{PRINT_PRUNING}
write_dump all custom rods.dump id x y z c_axis[1] c_axis[2] c_axis[3] modify sort id format "%d %.17g %.17g %.17g %.17g %.17g %.17g"
"""
    screen = run(deck)
    listed, kept, asked = pruning_counts(screen)
    (_, c), = read_dump(tmp_path / "rods.dump")
    centres = np.column_stack([c["x"], c["y"], c["z"]])
    axes = np.column_stack([c["c_axis[1]"], c["c_axis[2]"], c["c_axis[3]"]])
    i, j = np.triu_indices(len(centres), k=1)
    centre_distance = np.linalg.norm(centres[i] - centres[j], axis=1)
    core_distance = segment_distances(centres[i], axes[i], centres[j], axes[j], HALF_SEGMENT)
    # no pair so close to a threshold that round-off could decide it
    assert np.min(np.abs(centre_distance - (LENGTH + SKIN))) > 1e-9
    assert np.min(np.abs(core_distance - (D + SKIN))) > 1e-9
    assert listed == np.count_nonzero(centre_distance < LENGTH + SKIN)
    assert kept == np.count_nonzero(core_distance < D + SKIN)
    # the test means something: a good part of the list goes
    assert kept < 0.6 * listed
    assert asked == 0


def test_a_spinning_rod_asks_for_the_build_that_finds_its_neighbour(run, tmp_path):
    """Rod 1 spins about z at its fixed centre, rod 2 lies parallel to its
    start 1.8 d away: at the first build their cores are 1.8 d apart
    (pruned), and the centres never move until they touch, so LIGGGHTS'
    own check never rebuilds. Rod 1's end reaches rod 2 after turning
    53 degrees; only the builds its turning asks for put the pair back.
    The run must then be that of the unpruned list: rod 1 bounces off
    rod 2, which moves away."""
    rods = [((0.0, 0.0, 0.0), (1, 0, 0), (0, 0, 0), (0, 0, 10.0)),
            ((0.0, 1.8 * D, 0.0), (1, 0, 0), (0, 0, 0), (0, 0, 0))]
    steps = 15000
    deck = rod_deck(rods, steps, dump_every=steps, dt=1e-5, extra=PRUNING_VECTOR) + PRINT_PRUNING + "\n"
    screen = run(deck, subdir="pruned")
    run(without_pruning(deck), subdir="whole")
    listed, kept, asked = pruning_counts(screen)
    *_, (_, pruned) = read_dump(tmp_path / "pruned" / "rods.dump")
    *_, (_, whole) = read_dump(tmp_path / "whole" / "rods.dump")
    # they collided: rod 2 was pushed along +y
    assert pruned["vy"][1] > 1e-3
    # the end travels h * 0.93 rad = 9.3 mm to the contact: about
    # 9.3 mm / (skin/2) = 9 builds asked before it, more after
    assert asked >= 9
    for name, values in whole.items():
        np.testing.assert_allclose(pruned[name], values, rtol=1e-9, atol=1e-12)


def test_the_gas_runs_as_with_the_whole_list(tmp_path):
    """The colliding gas of test_spherocylinder (27 rods, periodic) for
    4000 steps: pruned and unpruned runs agree to round-off (they sum the
    same forces; extra builds change the order of summation only)."""
    steps = 4000
    deck = gas_deck(steps, extra_before_run=PRUNING_VECTOR) + PRINT_PRUNING + "\n"
    screen = run_liggghts(deck, tmp_path / "pruned")
    run_liggghts(without_pruning(deck), tmp_path / "whole")
    listed, kept, _ = pruning_counts(screen)
    assert 0 < kept < listed
    (_, pruned), = read_dump(tmp_path / "pruned" / "end.dump")
    (_, whole), = read_dump(tmp_path / "whole" / "end.dump")
    spin = np.sqrt(whole["omegax"] ** 2 + whole["omegay"] ** 2 + whole["omegaz"] ** 2)
    assert np.count_nonzero(spin) >= 20, "too few collisions for the test to tell"
    for name, values in whole.items():
        np.testing.assert_allclose(pruned[name], values, rtol=1e-9, atol=1e-10)


def test_a_pair_that_touched_and_parted_is_cut_once_its_cores_are_far(run, tmp_path):
    """Two parallel rods start touching and part at 0.5 m/s, the list
    built at every step. While their cores are within d + skin the pair is
    kept; once beyond, it is cut at every build although their bounding
    spheres still overlap (the stock hooke/stiffness flags every such pair
    as if in contact: the cut must not rely on the flags)."""
    rods = [((0, 0, 0), (1, 0, 0), (0, 0, 0), (0, 0, 0)),
            ((0, D, 0), (1, 0, 0), (0, 0.5, 0), (0, 0, 0))]
    extra = PRUNING_VECTOR + "\nvariable y2 equal y[2]\nneigh_modify every 1 delay 0 check no\n"
    for steps in (100, 20):
        extra += f'run {steps}\nprint "pruning ${{listed}} ${{kept}} ${{asked}} ${{y2}}"\n'
    screen = run(rod_deck(rods, 1, dt=1e-4, extra=extra))
    rows = [[float(w) for w in line.split()[1:]] for line in screen.splitlines()
            if line.startswith("pruning ")]
    (listed0, kept0, _, y0), (listed1, kept1, _, y1) = rows
    # past d + skin after the first window, still within L + skin (listed)
    assert D + SKIN < y0 < y1 < LENGTH
    # 20 steps and the build of the run's set-up
    assert listed1 - listed0 == 21
    assert kept1 == kept0
    # and it was kept while near: the cores part by the skin 0.2 d in
    # 0.2 d / (0.5 m/s) / dt = 40 steps, 41 builds with the set-up's
    assert 40 <= kept0 <= 42
