"""fix insert/rain2d: rows of discs released at rest on a line, the next
row once the last has fallen `fall`, until the grain count is stationary.

Most checks use a box with no floor: the rows fall through it and leave at
the bottom, so no grain ever touches another and everything the fix does
(where, when, how big, which tag) can be read back from a dump taken every
step and checked against the fix's own rules, recomputed here. The
normalised units of the pile scene are used (d = 1, g = 1, k_n = 1000).
"""

import math

import numpy as np
import pytest
from scipy import stats

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump, thermo_rows
from analysis.testing import LiggghtsError
from conftest import has_mpirun

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

D = 1.0
POLY = 0.05
D_MAX = D * (1 + POLY)
RHO = 4.0 / (math.pi * D_MAX ** 2)   # largest grain: mass 1
DT = 0.003
LINE = (-5.0, 5.0, 10.0)             # x_lo x_hi y: 5 grains per row at fill 0.5
PER_ROW = 5
SEED = 15485863


def rain_deck(steps, fix_options="", processors="", dump_every=1, substrate="",
              dimension=2, box="-6 6 0 12 -0.5 0.5", extra="", tail="", thermo_every=1,
              line=LINE, boundary="f f p"):
    x_lo, x_hi, y = line
    return f"""
{granular_setup(dimension=dimension, boundary=boundary)}
{processors}
region box block {box} units box
create_box 2 box
neighbor 0.2 bin
neigh_modify delay 0
{hooke_materials(1000.0, 1000.0 / 3, gamman=40.0, gammat=13.0, mu=0.5, ntypes=2)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep {DT}
{substrate}
group grains type 1
fix gravi grains gravity 1.0 vector 0 -1 0
fix integr grains nve/sphere
fix rain grains insert/rain2d seed {SEED} type 1 diameter {D} polydispersity {POLY} density {RHO!r} line {x_lo} {x_hi} {y} {fix_options}
{extra}
thermo_style custom step atoms f_rain[1] f_rain[2] f_rain[3] f_rain[4] f_rain[5]
thermo_modify lost ignore norm no format float %.15g
thermo {thermo_every}
dump d all custom {dump_every} dump.rain id type x y vx vy omegaz radius mass
dump_modify d format "%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run {steps}
{tail}
"""


def first_appearances(frames):
    """id -> (step, row of that frame's columns) of each grain's first frame."""
    seen = {}
    for step, columns in frames:
        for k, grain in enumerate(columns["id"].astype(int)):
            if grain not in seen:
                seen[grain] = (step, {name: values[k] for name, values in columns.items()})
    return seen


@pytest.fixture(scope="module")
def falling_rows(tmp_path_factory, liggghts_binary):
    """3000 steps of rain through the open box: ~6 rows, every step dumped."""
    from conftest import run_liggghts
    workdir = tmp_path_factory.mktemp("rain2d")
    output = run_liggghts(rain_deck(3000, processors="processors * 1 1"), workdir)
    return workdir, output, read_dump(workdir / "dump.rain")


def test_rows_are_released_at_rest_on_the_line_without_overlap(falling_rows):
    _, _, frames = falling_rows
    x_lo, x_hi, y_line = LINE
    born = first_appearances(frames)
    steps = sorted({step for step, _ in born.values()})
    assert len(steps) >= 5
    for release in steps:
        row = sorted((grain, columns) for grain, (step, columns) in born.items() if step == release)
        assert len(row) == PER_ROW          # fill 0.5 of 10 d with d = 1
        # tags run on with x (drawing order, left to right)
        tags = [grain for grain, _ in row]
        assert tags == list(range(tags[0], tags[0] + PER_ROW))
        x = np.array([c["x"] for _, c in row])
        r = np.array([c["radius"] for _, c in row])
        assert np.all(np.diff(x) > 0)
        # on the line, inside the segment, not overlapping one another
        for _, c in row:
            assert c["y"] == y_line
            assert c["vx"] == 0.0 and c["omegaz"] == 0.0
            # created at rest: by the end of its first step gravity has
            # given it half a step of velocity (velocity Verlet)
            assert c["vy"] == pytest.approx(-0.5 * DT, rel=1e-12)
        assert x[0] - r[0] >= x_lo - 1e-12 and x[-1] + r[-1] <= x_hi + 1e-12
        assert np.all(np.diff(x) >= (r[:-1] + r[1:]) - 1e-12)
        # diameters within d (1 -+ p), masses of discs pi r^2 rho
        assert np.all((2 * r >= D * (1 - POLY)) & (2 * r <= D * (1 + POLY)))
        for _, c in row:
            assert c["mass"] == pytest.approx(math.pi * c["radius"] ** 2 * RHO, rel=1e-12)


def test_no_two_grains_ever_overlap(falling_rows):
    _, _, frames = falling_rows
    for _, c in frames:
        x, y, r = c["x"], c["y"], c["radius"]
        distance = np.hypot(x[:, None] - x[None, :], y[:, None] - y[None, :])
        contact = r[:, None] + r[None, :]
        np.fill_diagonal(distance, np.inf)
        assert np.all(distance >= contact - 1e-12)


def check_release_schedule(frames):
    """Release at step s exactly when the previous row's highest grain was
    d_max below the line at the end of step s-1 and not at step s-2, in
    frames of every step."""
    by_step = dict(frames)
    born = first_appearances(frames)
    releases = sorted({step for step, _ in born.values()})
    threshold = LINE[2] - D_MAX
    for previous, release in zip(releases[:-1], releases[1:]):
        previous_row = [g for g, (s, _) in born.items() if s == previous]

        def highest(step):
            c = by_step[step]
            return c["y"][np.isin(c["id"], previous_row)].max()
        assert highest(release - 1) <= threshold < highest(release - 2)
    # free fall from rest: d_max takes sqrt(2 d_max / g), ~483 steps
    period = math.sqrt(2 * D_MAX) / DT
    assert np.diff(releases) == pytest.approx(np.full(len(releases) - 1, period), abs=2)


def test_next_row_waits_until_the_last_one_has_fallen_a_largest_diameter(falling_rows):
    _, _, frames = falling_rows
    check_release_schedule(frames)


def test_grains_below_the_box_are_deleted(falling_rows):
    """f boundaries: a grain that leaves the box is gone at the next
    neighbor-list build (skin 0.2, so within 0.1 + one step of travel)."""
    _, output, frames = falling_rows
    lowest = min(c["y"].min() for _, c in frames if len(c["y"]))
    assert -0.2 < lowest < 0.0
    born = first_appearances(frames)
    last_ids = set(frames[-1][1]["id"].astype(int))
    gone = [g for g in born if g not in last_ids]
    assert len(gone) >= 2 * PER_ROW
    # every grain that disappeared was at the bottom when last seen
    last_seen = {}
    for _, c in frames:
        for k, grain in enumerate(c["id"].astype(int)):
            last_seen[grain] = c["y"][k]
    assert all(last_seen[g] < 0.2 for g in gone)
    # LIGGGHTS' atom count and the fix's count agree with the dump
    thermo = thermo_rows(output, 7)
    final = thermo[max(thermo)]
    assert final[0] == len(last_ids)
    assert final[1] == len(born)


def test_gaps_are_uniform_spacings(tmp_path, run):
    """The free length before the first grain, as a fraction of the row's
    free length, is the smallest of n uniform numbers: Beta(1, n). 120 rows,
    Kolmogorov-Smirnov at the 0.1 % level (a wrong law, e.g. gaps of equal
    size or a first gap drawn like the others' sum, fails by far)."""
    steps = 120 * 484
    run(rain_deck(steps, "window 500", dump_every=50, box="-6 6 8.5 12 -0.5 0.5",
                  thermo_every=10000))
    frames = read_dump(tmp_path / "dump.rain")
    born = first_appearances(frames)
    releases = sorted({step for step, _ in born.values()})
    assert len(releases) >= 100
    x_lo, x_hi, _ = LINE
    fractions = []
    for release in releases:
        row = sorted((c["x"], c["radius"]) for g, (s, c) in born.items() if s == release)
        free = (x_hi - x_lo) - sum(2 * r for _, r in row)
        fractions.append((row[0][0] - row[0][1] - x_lo) / free)
    assert stats.kstest(fractions, stats.beta(1, PER_ROW).cdf).pvalue > 1e-3


def test_stops_when_the_count_is_stationary(run):
    """With no floor the count settles at the rows in the air. The stop rule
    recomputed from LIGGGHTS' own atom count: n_k = atoms at the end of the
    step before release k; stop at the first release k whose last `window`
    samples average at most (1 + tolerance) times the `window` before."""
    window, tolerance = 3, 0.01
    output = run(rain_deck(20000, f"window {window} tolerance {tolerance}", dump_every=100000))
    thermo = thermo_rows(output, 7)
    steps = sorted(thermo)
    # a release shows as a step where the inserted count grows; the attempt
    # that stopped the rain as the step where the stop reason is set
    releases = [s for s in steps[1:] if thermo[s][1] > thermo[s - 1][1]]
    stop_step = next(s for s in steps if thermo[s][3] != 0)
    attempts = releases + [stop_step]
    samples = [thermo[s - 1][0] for s in attempts]
    expected_stop = None
    for k in range(2 * window, len(samples) + 1):
        older = np.mean(samples[k - 2 * window:k - window])
        newer = np.mean(samples[k - window:k])
        if newer - older <= tolerance * newer:
            expected_stop = k
            break
    assert expected_stop == len(attempts)           # the rule stops at that attempt, not before
    assert len(releases) >= 2 * window + 1
    final = thermo[steps[-1]]
    assert final[3] == 1                            # reason: stationary
    assert final[2] == len(releases)
    assert final[4] == samples[-1]                  # present at the last attempt
    assert "the number of grains present is stationary" in output


@pytest.mark.parametrize("option, reason, rows", [("max_rows 3", 3, 3), ("max_grains 12", 2, 2)])
def test_stops_at_the_limits(run, option, reason, rows):
    thermo = thermo_rows(run(rain_deck(4000, option, dump_every=100000)), 7)
    final = thermo[max(thermo)]
    assert final[3] == reason and final[2] == rows and final[1] == rows * PER_ROW


def test_a_pile_at_the_line_stops_the_release(run):
    """A fixed grain just below the line: the first row falls past it, but
    the release stops (with a warning) instead of waiting for ever once a
    row comes to rest on it or a new row would overlap it."""
    blocker = "create_atoms 2 single 0.3 9.2 0 units box\nset type 2 diameter 1.0 density 1.0"
    output = run(rain_deck(3000, "fill 0.9", dump_every=100000, substrate=blocker))
    thermo = thermo_rows(output, 7)
    assert thermo[max(thermo)][3] == 4
    assert "the pile has reached the release line" in output


# A row on the line's left end, x in [-6, -4] (one grain, its centre in
# [-5.475, -4.525]), and a held 2.2 d grain at x = 5.99 on the line's
# height: far from the row itself, but across the periodic x side its image
# at x = -6.01 reaches to -4.91, so it overlaps the row's grain wherever the
# gaps put it (centre distance < 1.1 + 0.475 for a centre below -4.435).
IMAGE_LINE = (-6.0, -4.0, 10.0)
IMAGE_BLOCKER = "create_atoms 2 single 5.99 10.0 0 units box\nset type 2 diameter 2.2 density 1.0"


def image_blocker_deck(boundary, deck=None, processors=""):
    deck = deck or rain_deck
    return deck(200, dump_every=100000, substrate=IMAGE_BLOCKER, line=IMAGE_LINE,
                boundary=boundary, processors=processors)


def check_image_blocker(boundary, output):
    """In a box periodic in x the release stops at once, no grain created
    (reason 4: the pile has reached the line); with f sides the image does
    not exist and the first row is created and falls (the control)."""
    final = thermo_rows(output, 7)[200]
    if boundary.startswith("p"):
        assert final[:4] == [1, 0, 0, 4]       # atoms, inserted, rows, reason
        assert "release stopped at step 1" in output
    else:
        assert final[:4] == [2, 1, 1, 0]


@pytest.mark.parametrize("boundary", ["p f p", "f f p"])
def test_a_row_never_overlaps_the_periodic_image_of_a_grain(run, boundary):
    check_image_blocker(boundary, run(image_blocker_deck(boundary)))


@pytest.mark.skipif(not has_mpirun(), reason="needs mpirun")
def test_two_ranks_see_the_image_of_a_grain_on_the_other_rank(run):
    """The row on rank 0 (x < 0), the held grain on rank 1: the image comes
    from the other rank's gathering."""
    deck = image_blocker_deck("p f p", processors="processors 2 1 1")
    check_image_blocker("p f p", run(deck, nprocs=2))


# a substrate of touching 0.1 d discs with its top at y = 1, in fix freeze
SUBSTRATE = ("lattice sq 0.1 origin 0.5 0.5 0.0\n"
             "region band block -5.99 5.99 0.91 0.99 -0.05 0.05 units box\n"
             "create_atoms 2 region band\n"
             "set type 2 diameter 0.1 density 1.0\n"
             "group substrate type 2\n"
             "fix frozen substrate freeze")


def check_landing_loses_energy(frames):
    """Frames of one row (max_rows 1) dropped on SUBSTRATE: each grain's
    mechanical energy (disc inertia m r^2 / 2, heights above the
    substrate's top) ends well below half of what it was."""
    rain = frames[-1][1]["id"][frames[-1][1]["type"] == 1].astype(int)
    assert len(rain) == PER_ROW
    for grain in rain:
        energy = []
        for _, c in frames:
            k = np.nonzero(c["id"] == grain)[0]
            if len(k) == 0:
                continue
            k = k[0]
            m, r = c["mass"][k], c["radius"][k]
            energy.append(0.5 * m * (c["vx"][k] ** 2 + c["vy"][k] ** 2)
                          + 0.25 * m * r * r * c["omegaz"][k] ** 2 + m * (c["y"][k] - 1.0))
        start = energy[0]
        assert start > 8.0 * 0.8          # m g (10 - 1) for m >= 0.82
        assert max(energy[-20:]) < 0.5 * start


def test_landing_on_the_substrate_loses_energy(tmp_path, run):
    """One row dropped from y = 10 onto a substrate of touching 0.1 d discs
    (in fix freeze). The grains are created after the pair style's neighbor
    cutoff was sized: the fix must announce its largest radius (max_rad),
    or contacts are found only after deep overlap and the grains bounce back
    higher than they fell. With this damping (0.3 of critical for the mean
    pair) the mechanical energy after the impact is well below half of
    what it was."""
    run(rain_deck(2200, "max_rows 1", dump_every=20, substrate=SUBSTRATE))
    check_landing_loses_energy(read_dump(tmp_path / "dump.rain"))


@pytest.mark.skipif(not has_mpirun(), reason="needs mpirun")
def test_two_ranks_release_the_same_grains(run, tmp_path):
    """Same seed, 1 and 2 ranks (`processors * 1 1`: the rank boundary x = 0
    cuts every row): the same tags at the same places with the same sizes,
    frame by frame."""
    deck = rain_deck(2000, processors="processors * 1 1", dump_every=50)
    run(deck, subdir="one")
    run(deck, nprocs=2, subdir="two")
    one = read_dump(tmp_path / "one" / "dump.rain")
    two = read_dump(tmp_path / "two" / "dump.rain")
    assert len(one) == len(two)
    both_sides = False
    for (s1, c1), (s2, c2) in zip(one, two):
        assert s1 == s2
        assert np.array_equal(c1["id"], c2["id"])
        for name in ("x", "y", "vy", "radius", "mass"):
            np.testing.assert_array_equal(c1[name], c2[name])
        both_sides |= bool(np.any(c1["x"] < 0) and np.any(c1["x"] > 0))
    assert both_sides


def test_restart_continues_the_rain(run, tmp_path):
    """1000 steps, write_restart, read it in a new run with the fix given
    again, 1500 more: the same as 2500 steps in one go (the release pending
    at the restart step, the random sequence, the tag counter and the
    stationarity samples come from the file)."""
    options = "window 2 tolerance 0.01"
    run(rain_deck(2500, options, dump_every=500), subdir="straight")
    run(rain_deck(1000, options, dump_every=100000, tail="write_restart rain.restart"),
        subdir="first")
    x_lo, x_hi, y = LINE
    resumed = f"""
units si
atom_modify map array
read_restart ../first/rain.restart
newton off
communicate single vel yes
neighbor 0.2 bin
neigh_modify delay 0
{hooke_materials(1000.0, 1000.0 / 3, gamman=40.0, gammat=13.0, mu=0.5, ntypes=2)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep {DT}
group grains type 1
fix gravi grains gravity 1.0 vector 0 -1 0
fix integr grains nve/sphere
fix rain grains insert/rain2d seed {SEED} type 1 diameter {D} polydispersity {POLY} density {RHO!r} line {x_lo} {x_hi} {y} {options}
thermo_style custom step atoms f_rain[1] f_rain[2] f_rain[3] f_rain[4] f_rain[5]
thermo_modify lost ignore norm no
dump d all custom 500 dump.rain id type x y vx vy omegaz radius mass
dump_modify d format "%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run 1500
"""
    run(resumed, subdir="second")
    straight = read_dump(tmp_path / "straight" / "dump.rain")[-1]
    resumed_frames = read_dump(tmp_path / "second" / "dump.rain")
    assert straight[0] == resumed_frames[-1][0] == 2500
    a, b = straight[1], resumed_frames[-1][1]
    assert np.array_equal(a["id"], b["id"]) and len(a["id"]) > PER_ROW
    for name in ("x", "y", "vy", "radius", "mass"):
        np.testing.assert_allclose(a[name], b[name], rtol=0, atol=1e-12)


def tables_by_run(output):
    """thermo_rows (7 columns) of each piece of a deck's output between two
    reset_timestep commands: the step numbers of the runs may repeat."""
    return [thermo_rows(piece, 7) for piece in output.split("\nreset_timestep")]


def reset_between_runs(run, steps, first, new_step, start=0, **deck_options):
    """`steps` steps from step `start` as one run, and as `first` steps, then
    reset_timestep new_step, then the rest. Returns the thermo rows of
    both, those of the split run keyed by the step the single run has at
    the same point."""
    begin = f"reset_timestep {start}" if start else ""
    straight = thermo_rows(run(rain_deck(steps, extra=begin, **deck_options), subdir="straight"), 7)
    deck = rain_deck(first, extra=begin, tail=f"reset_timestep {new_step}\nrun {steps - first}",
                     **deck_options)
    *_, before, after = tables_by_run(run(deck, subdir="split"))
    joined = dict(before)
    joined.update({step - new_step + start + first: values for step, values in after.items()})
    assert min(after) == new_step and sorted(joined) == sorted(straight)
    return straight, joined


@pytest.mark.parametrize("new_step", [0, 1000000])
@pytest.mark.parametrize("when", ["release pending", "row falling"])
def test_reset_timestep_between_runs_keeps_the_rain_going(run, new_step, when):
    """2000 steps in one go, and split in two runs with reset_timestep in
    between, back to 0 or forward to 10^6: grains inserted, rows, stop
    reason, grains present and growth are the same step for step (counted
    from the start). The split is at the step before a release (the release
    is pending when the first run ends) or half-way between two releases.
    (A release pending across a backward reset used to wait for its old
    step number: the rain stalled.)"""
    steps = 2000
    straight = thermo_rows(run(rain_deck(steps, dump_every=100000), subdir="probe"), 7)
    releases = [s for s in sorted(straight)[1:] if straight[s][1] > straight[s - 1][1]]
    k = next(k for k, s in enumerate(releases) if s > steps // 3)
    first = releases[k] - 1 if when == "release pending" else (releases[k] + releases[k + 1]) // 2
    assert len(releases) >= k + 3                  # rows are released after the split
    straight, joined = reset_between_runs(run, steps, first, new_step, dump_every=100000)
    for step in sorted(straight):
        assert joined[step][1:] == straight[step][1:], step


@pytest.mark.parametrize("new_step", [0, 1000000])
def test_reset_timestep_keeps_the_blocked_line_check(run, new_step):
    """A fixed grain 1.5 below the line: the first row is released clear of
    it, one of its grains lands on it before having fallen `fall`, and the
    release stops (the pile has reached the line). The run starts at step
    50000 and is split by reset_timestep while that row falls: the release
    stops at the same step, counted from the start, as without the reset.
    (Across a backward reset the row used to count as not having moved
    since its release, which turned the blocked-line check off: the rain
    waited for ever.)"""
    blocker = "create_atoms 2 single 0.3 8.5 0 units box\nset type 2 diameter 1.0 density 1.0"
    options = dict(fix_options="fill 0.9", dump_every=100000, substrate=blocker, start=50000)
    straight, joined = reset_between_runs(run, 600, 150, new_step, **options)
    stopped = [s for s in sorted(straight) if straight[s][3] == 4]
    assert stopped and stopped[0] > 50000 + 200 and straight[stopped[0]][2] == 1   # one row
    for step in sorted(straight):
        assert joined[step][1:] == straight[step][1:], step


# ------------------------------------------------------------ bad input

GOOD = f"seed {SEED} type 1 diameter {D} polydispersity {POLY} density {RHO!r} line -5.0 5.0 10.0"


def refused(run, options, **deck_options):
    deck = rain_deck(1, dump_every=100000, **deck_options).replace(
        f"fix rain grains insert/rain2d {GOOD} ", f"fix rain grains insert/rain2d {options}")
    with pytest.raises(LiggghtsError) as caught:
        run(deck)
    return caught.value.message


# (options, words the ERROR must hold); test_lammps_rain2d.py reuses those
# that are not about LIGGGHTS' seed rule
BAD_INPUT = [
    (GOOD.replace(f"seed {SEED} ", ""), "'seed <prime > 10000>' is required"),
    (GOOD.replace(f"seed {SEED}", "seed 15485864"), "'seed' must be a prime number > 10000"),
    (GOOD.replace(f"seed {SEED}", "seed 7"), "'seed' must be a prime number > 10000"),
    (GOOD.replace(f"seed {SEED}", "seed 1.5e7"), "'seed' must be a prime number > 10000"),
    (GOOD.replace(f"seed {SEED}", "seed abc"), "'seed' expects a number, got 'abc'"),
    (GOOD.replace("type 1 ", ""), "'type <atom type>' is required"),
    (GOOD.replace("type 1", "type 3"), "'type' must be an atom type from 1 to 2"),
    (GOOD.replace("type 1", "type 0"), "'type' must be an atom type from 1 to 2"),
    (GOOD.replace("type 1", "type -1"), "'type' must be an atom type from 1 to 2"),
    (GOOD.replace("type 1", "type 1.5"), "'type' expects an integer, got '1.5'"),
    (GOOD.replace("diameter 1.0 ", ""), "'diameter <mean diameter>' is required"),
    (GOOD.replace("diameter 1.0", "diameter -1"), "'diameter' must be > 0"),
    (GOOD.replace("polydispersity 0.05", "polydispersity 1"), "'polydispersity' must be in [0, 1)"),
    (GOOD.replace("polydispersity 0.05", "polydispersity -0.1"), "'polydispersity' must be in [0, 1)"),
    (GOOD.replace(f"density {RHO!r}", "density 0"), "'density' must be > 0"),
    (GOOD.replace(f"density {RHO!r} ", ""), "'density <mass density>' is required"),
    (GOOD.replace("line -5.0 5.0 10.0", ""), "'line <x_lo> <x_hi> <y>' is required"),
    (GOOD.replace("line -5.0 5.0 10.0", "line 5.0 -5.0 10.0"), "'line x_lo x_hi y' needs x_hi > x_lo"),
    (GOOD.replace("line -5.0 5.0 10.0", "line -7.0 5.0 10.0"), "'line': the row of grains must lie inside the simulation box"),
    (GOOD.replace("line -5.0 5.0 10.0", "line -5.0 5.0 11.8"), "'line': the row of grains must lie inside the simulation box"),
    (GOOD.replace("line -5.0 5.0 10.0", "line -0.5 0.5 10.0"), "'line': the row is shorter than the largest grain"),
    (GOOD.replace("line -5.0 5.0 10.0", "line -5.0 5.0"), "keyword 'line' needs three values"),
    (GOOD + " fill 1", "'fill' must be in (0, 1)"),
    (GOOD + " fill 0", "'fill' must be in (0, 1)"),
    (GOOD + " fall 0", "'fall' must be > 0"),
    (GOOD + " fall 1.0", "'fall' must be at least the largest diameter"),
    (GOOD + " window 0", "'window' must be an integer >= 1"),
    (GOOD + " tolerance -0.1", "'tolerance' must be >= 0"),
    (GOOD + " max_grains -1", "'max_grains' must be >= 0"),
    (GOOD + " max_rows -2", "'max_rows' must be >= 0"),
    (GOOD + " max_rows", "keyword 'max_rows' needs a value"),
    (GOOD + " colour red", "unknown keyword 'colour'"),
]


@pytest.mark.parametrize("options, expected", BAD_INPUT)
def test_bad_input(run, options, expected):
    assert expected in refused(run, options)


def test_refused_in_3d(run):
    message = refused(run, GOOD, dimension=3, box="-6 6 0 12 -1 1")
    assert "is for 2D simulations (dimension 2)" in message


def test_needs_an_atom_map(run):
    deck = rain_deck(1, dump_every=100000).replace("atom_modify map array\n", "")
    with pytest.raises(LiggghtsError) as caught:
        run(deck)
    assert "needs an atom map" in caught.value.message
