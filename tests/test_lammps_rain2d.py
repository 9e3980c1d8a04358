"""fix insert/rain2d in LAMMPS (our plugin; doc/fix_insert_rain2d_lammps.md):
rows of discs released at rest on a line, the next row once the last has
fallen `fall`, until the grain count is stationary, as with the LIGGGHTS fix.

The scene is test_rain2d.py's: a box with no floor, so that the rows fall
through it and leave at the bottom without ever touching; everything the
fix does (where, when, how big, which tag) is read back from a dump taken
every step. The rows are checked against a hand computation (Park and
Miller's generator, which both hosts use, written out here, and the
row rule of doc/fix_insert_rain2d.md), against the LIGGGHTS fix on the
same deck and seed, on 2 ranks against 1, and across a restart.
"""

import math

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump, thermo_rows
from analysis.testing import LiggghtsError, liggghts_binary, run_deck
from lammps_host import has_mpirun, needs_lammps, run_lammps
from test_rain2d import BAD_INPUT, D, DT, GOOD, LINE, PER_ROW, POLY, RHO, SEED
from test_rain2d import SUBSTRATE, check_image_blocker, check_landing_loses_energy
from test_rain2d import check_release_schedule, image_blocker_deck
from test_rain2d import first_appearances, rain_deck as liggghts_rain_deck, tables_by_run

pytestmark = needs_lammps

THERMO_COLUMNS = 7                   # step atoms f_rain[1..5]
DUMP_FORMAT = " ".join(["%d", "%d"] + ["%.17g"] * 7)


def rain_deck(steps, fix_options="", processors="", dump_every=1, substrate="", tail="",
              box="-6 6 0 12 -0.5 0.5", dimension=2, fix_line=None, line=LINE,
              boundary="f f p"):
    """test_rain2d.py's deck in LAMMPS: the same box, grains, contact law
    (pair granular/jiang with LIGGGHTS' hooke/stiffness), thermo and dump;
    discs need `nve/sphere disc` here (LIGGGHTS takes a disc's inertia by
    itself in 2D)."""
    x_lo, x_hi, y = line
    if fix_line is None:
        fix_line = (f"fix rain grains insert/rain2d seed {SEED} type 1 diameter {D} "
                    f"polydispersity {POLY} density {RHO!r} line {x_lo} {x_hi} {y} {fix_options}")
    integrate = "nve/sphere disc" if dimension == 2 else "nve/sphere"
    return f"""plugin load ${{plugin}}
units si
dimension {dimension}
atom_style sphere
atom_modify map array
boundary {boundary}
newton off
comm_modify vel yes
{processors}
region box block {box} units box
create_box 2 box
neighbor 0.2 bin
neigh_modify delay 0
pair_style granular/jiang
pair_coeff * * normal hooke/stiffness 1000.0 {1000.0 / 3!r} 40.0 13.0 friction 0.5
timestep {DT}
{substrate}
group grains type 1
fix gravi grains gravity 1.0 vector 0 -1 0
fix integr grains {integrate}
{fix_line}
thermo_style custom step atoms f_rain[1] f_rain[2] f_rain[3] f_rain[4] f_rain[5]
thermo_modify lost ignore norm no format float %.15g
thermo 1
dump d all custom {dump_every} dump.rain id type x y vx vy omegaz radius mass
dump_modify d format line "{DUMP_FORMAT}"
run {steps}
{tail}
"""


# ------------------------------------------------------------ the rule, by hand

class ParkMiller:
    """Park and Miller's minimal standard generator, as LAMMPS' and
    LIGGGHTS' RanPark::uniform() compute it (the same integer steps, then
    the same double product)."""

    def __init__(self, seed):
        self.seed = seed

    def uniform(self):
        k = self.seed // 127773
        self.seed = 16807 * (self.seed - k * 127773) - 2836 * k
        if self.seed < 0:
            self.seed += 2147483647
        return (1.0 / 2147483647) * self.seed


def rows_by_hand(count):
    """The first `count` rows as doc/fix_insert_rain2d.md words the rule:
    n diameters uniform in d(1 -+ p), then n cuts of the free length,
    sorted, as the left edges with the grains' lengths taken out; tags from
    1 in drawing order. The operations are those of the C++, in its order,
    so the doubles are the same. Returns [(tag, x, diameter)] per row."""
    x_lo, x_hi, _ = LINE
    generator = ParkMiller(SEED)
    rows, tag = [], 1
    for _ in range(count):
        diameters = [D * (1.0 + POLY * (2.0 * generator.uniform() - 1.0)) for _ in range(PER_ROW)]
        cuts = sorted(generator.uniform() for _ in range(PER_ROW))
        occupied = 0.0
        for diameter in diameters:
            occupied += diameter
        free = (x_hi - x_lo) - occupied
        row, before = [], 0.0
        for cut, diameter in zip(cuts, diameters):
            row.append((tag, x_lo + free * cut + before + 0.5 * diameter, diameter))
            before += diameter
            tag += 1
        rows.append(row)
    return rows


@pytest.fixture(scope="module")
def falling_rows(tmp_path_factory):
    """3000 steps of rain through the open box: 7 rows, every step dumped."""
    workdir = tmp_path_factory.mktemp("lammps_rain2d")
    run = run_lammps(rain_deck(3000, processors="processors * 1 1"), workdir)
    return workdir, run.output, read_dump(workdir / "dump.rain")


def releases(born):
    return sorted({step for step, _ in born.values()})


def test_rows_are_those_of_the_rule(falling_rows):
    """Every row's tags, centres and diameters are the hand computation's,
    to the bit (the same operations on the same doubles; a tolerance would
    hide a changed order of drawing). Created at rest on the line with a
    disc's mass pi r^2 rho: at the end of the step of its release a grain
    has half a step of gravity in its velocity (velocity Verlet)."""
    _, _, frames = falling_rows
    born = first_appearances(frames)
    steps = releases(born)
    assert len(steps) >= 6
    assert steps[0] == 1                      # the first row falls on the first step
    for release, expected in zip(steps, rows_by_hand(len(steps))):
        row = sorted((grain, columns) for grain, (step, columns) in born.items()
                     if step == release)
        assert [grain for grain, _ in row] == [tag for tag, _, _ in expected]
        for (_, c), (_, x, diameter) in zip(row, expected):
            assert c["x"] == x and c["radius"] == 0.5 * diameter
            assert c["y"] == LINE[2] and c["type"] == 1
            assert c["vx"] == 0.0 and c["omegaz"] == 0.0
            assert c["vy"] == pytest.approx(-0.5 * DT, rel=1e-12)
            assert c["mass"] == pytest.approx(math.pi * c["radius"] ** 2 * RHO, rel=1e-14)


def test_next_row_waits_until_the_last_one_has_fallen_a_largest_diameter(falling_rows):
    """Release at step s exactly when the previous row's highest grain was
    d_max below the line at the end of step s-1 and not at step s-2."""
    _, _, frames = falling_rows
    check_release_schedule(frames)


def test_counts_and_lost_grains(falling_rows):
    """Grains below the box are lost atoms (thermo_modify lost ignore); the
    fix counts what it inserted and rows, and the grains present before
    each release (test_rain2d.py checks the stop rule on these numbers)."""
    _, output, frames = falling_rows
    born = first_appearances(frames)
    thermo = thermo_rows(output, THERMO_COLUMNS)
    final = thermo[max(thermo)]
    assert final[1] == len(born) == PER_ROW * len(releases(born))
    assert final[2] == len(releases(born)) and final[3] == 0
    gone = set(born) - set(frames[-1][1]["id"].astype(int))
    assert len(gone) >= 2 * PER_ROW
    last = releases(born)[-1]
    assert final[4] == len(frames[[s for s, _ in frames].index(last - 1)][1]["id"])


def test_the_rows_are_those_of_liggghts(falling_rows, tmp_path):
    """The same deck and seed in LIGGGHTS (test_rain2d.py's): the same
    grains, released at the same steps, fall along the same trajectories
    and the fix's outputs agree, frame by frame and to the bit (both hosts
    draw from the same generator in the same order through the shared
    core/rain2d_logic.h, and both integrate free fall with the same
    velocity Verlet)."""
    if not liggghts_binary().exists():
        pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
    run = run_deck(liggghts_rain_deck(3000, processors="processors * 1 1"), tmp_path)
    theirs = read_dump(tmp_path / "dump.rain")
    _, output, ours = falling_rows
    assert [step for step, _ in ours] == [step for step, _ in theirs]
    for (step, a), (_, b) in zip(ours, theirs):
        for name in ("id", "type", "x", "y", "vx", "vy", "omegaz", "radius", "mass"):
            np.testing.assert_array_equal(a[name], b[name], err_msg=f"{name} at step {step}")
    lammps_thermo = thermo_rows(output, THERMO_COLUMNS)
    liggghts_thermo = thermo_rows(run.output, THERMO_COLUMNS)
    for step in lammps_thermo:
        assert lammps_thermo[step][1:] == liggghts_thermo[step][1:], step


# ------------------------------------------------------------ MPI

@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_release_the_same_grains(falling_rows, tmp_path):
    """Same seed, 2 ranks side by side (`processors * 1 1`: the rank
    boundary x = 0 cuts every row): the same tags at the same places with
    the same sizes, frame by frame, to the bit (no contacts: nothing is
    summed in another order)."""
    _, _, one = falling_rows
    run_lammps(rain_deck(2000, processors="processors * 1 1", dump_every=50), tmp_path, nprocs=2)
    two = read_dump(tmp_path / "dump.rain")
    one_by_step = dict(one)
    both_sides = False
    assert len(two) == 41
    for step, c2 in two:
        c1 = one_by_step[step]
        for name in ("id", "x", "y", "vy", "radius", "mass"):
            np.testing.assert_array_equal(c1[name], c2[name], err_msg=f"{name} at step {step}")
        both_sides |= bool(np.any(c1["x"] < 0) and np.any(c1["x"] > 0))
    assert both_sides


# ------------------------------------------------------------ restart

def restarted_deck(steps):
    """A deck that reads rain.restart and runs on with the fix given again
    (the same ID): the random state, tag counter, counts and a pending
    release come from the file."""
    fresh = rain_deck(steps, dump_every=100)
    lines = fresh.splitlines()
    keep = [line for line in lines if not line.startswith(("units", "dimension", "atom_style",
                                                           "atom_modify", "boundary", "newton",
                                                           "region", "create_box", "comm_modify"))]
    keep.insert(1, "read_restart rain.restart\ncomm_modify vel yes")
    return "\n".join(keep)


@pytest.mark.parametrize("when", ["row falling", "release pending"])
def test_a_run_split_by_a_restart_inserts_the_grains_of_the_whole_run(falling_rows, tmp_path,
                                                                       when):
    """2500 steps in one go, and cut by write_restart/read_restart half-way
    between two releases or on the step before one (the release is pending
    in the restart file): the rows after the cut are the same grains (tags,
    sizes, places) at the same steps, and every frame after the cut equals
    the whole run's, to the bit (free fall, no contacts: the set-up force
    call of the continued run computes the same forces)."""
    _, _, whole = falling_rows
    steps = releases(first_appearances(whole))
    cut = (steps[2] + steps[3]) // 2 if when == "row falling" else steps[3] - 1
    first = rain_deck(cut, dump_every=100000, tail="write_restart rain.restart")
    before = thermo_rows(run_lammps(first, tmp_path).output, THERMO_COLUMNS)[cut]
    resumed = run_lammps(restarted_deck(2500 - cut), tmp_path).output
    after = thermo_rows(resumed, THERMO_COLUMNS)
    # the fix's outputs (LAMMPS' atom count leaves out lost grains only
    # after the restart: with `lost ignore` it is not updated)
    assert after[cut][1:] == before[1:]
    assert max(after) == 2500 and after[2500][2] > before[2]     # rows released after the cut
    whole_by_step = dict(whole)
    pieced = [(step, c) for step, c in read_dump(tmp_path / "dump.rain") if step > cut]
    assert len(pieced) >= 10
    for step, c in pieced:
        for name in ("id", "x", "y", "vy", "radius", "mass"):
            np.testing.assert_array_equal(c[name], whole_by_step[step][name],
                                          err_msg=f"{name} at step {step}")


# ------------------------------------------------------------ grains already there

def test_a_row_never_overlaps_a_grain_already_there(tmp_path):
    """A fixed grain on the line itself: the first row (9 grains on 10 d at
    fill 0.9) would overlap it, so the fix creates none, stops (reason 4:
    the pile has reached the line) and says so."""
    blocker = ("create_atoms 2 single 0.3 10.0 0 units box\n"
               "set type 2 diameter 1.0 density 1.0\n"
               "group blocker type 2\nfix frozen blocker freeze")
    run = run_lammps(rain_deck(200, "fill 0.9", dump_every=100000, substrate=blocker), tmp_path)
    final = thermo_rows(run.output, THERMO_COLUMNS)[200]
    assert final[:4] == [1, 0, 0, 4]       # atoms, inserted, rows, reason
    assert "the pile has reached the release line" in run.output
    assert "release stopped at step 1" in run.output


@pytest.mark.parametrize("boundary", ["p f p", "f f p"])
def test_a_row_never_overlaps_the_periodic_image_of_a_grain(tmp_path, boundary):
    """test_rain2d.py's scene: a held grain across the periodic x side
    from the row, whose image would overlap it."""
    check_image_blocker(boundary, run_lammps(image_blocker_deck(boundary, rain_deck),
                                             tmp_path).output)


def test_a_row_resting_on_the_pile_stops_the_release(tmp_path):
    """A fixed grain 1.5 below the line: a grain of the first row lands on
    it before having fallen `fall`, stops moving down, and the release
    stops (reason 4) instead of waiting for ever."""
    blocker = ("create_atoms 2 single 0.3 8.5 0 units box\n"
               "set type 2 diameter 1.0 density 1.0\n"
               "group blocker type 2\nfix frozen blocker freeze")
    run = run_lammps(rain_deck(1500, "fill 0.9", dump_every=100000, substrate=blocker), tmp_path)
    thermo = thermo_rows(run.output, THERMO_COLUMNS)
    stopped = [step for step in sorted(thermo) if thermo[step][3] == 4]
    assert stopped and thermo[stopped[0]][2] == 1 and stopped[0] > 100


def test_landing_on_the_substrate_loses_energy(tmp_path):
    """One row dropped from y = 10 onto a substrate of touching 0.1 d discs
    (in fix freeze). The grains do not exist when the pair sizes its
    cutoffs: the fix announces its largest radius (extract "radius", as
    fix pour does), or their contacts with the substrate are found late or
    never. The mechanical energy after the impact is well below half of
    what it was, and no grain passes the substrate's top (y = 1)."""
    run_lammps(rain_deck(2200, "max_rows 1", dump_every=20, substrate=SUBSTRATE), tmp_path)
    frames = read_dump(tmp_path / "dump.rain")
    check_landing_loses_energy(frames)
    assert min(c["y"][c["type"] == 1].min() for _, c in frames if np.any(c["type"] == 1)) > 1.0


# ------------------------------------------------------------ bad input

# test_rain2d.py's bad lines but those of LIGGGHTS' seed rule (a prime >
# 10000), then LAMMPS' (any positive seed)
BAD = [(options, expected) for options, expected in BAD_INPUT if "prime" not in expected] + [
    (GOOD.replace(f"seed {SEED} ", ""), "'seed <positive integer>' is required"),
    (GOOD.replace(f"seed {SEED}", "seed 0"), "'seed' must be a positive integer"),
    (GOOD.replace(f"seed {SEED}", "seed -7"), "'seed' must be a positive integer"),
]


@pytest.mark.parametrize("options, expected", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_input_names_the_keyword(tmp_path, options, expected):
    deck = rain_deck(1, dump_every=100000, fix_line=f"fix rain grains insert/rain2d {options}")
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix insert/rain2d" in caught.value.message
    assert expected in caught.value.message


def test_a_small_seed_is_taken(tmp_path):
    """LAMMPS' generator takes any positive seed: 7 runs."""
    deck = rain_deck(10, dump_every=100000, fix_line=f"fix rain grains insert/rain2d "
                     f"{GOOD.replace(f'seed {SEED}', 'seed 7')}")
    assert thermo_rows(run_lammps(deck, tmp_path).output, THERMO_COLUMNS)[10][1] == PER_ROW


def test_refused_in_3d(tmp_path):
    deck = rain_deck(1, dump_every=100000, dimension=3, box="-6 6 0 12 -1 1")
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix insert/rain2d is for 2D simulations (dimension 2)" in caught.value.message


def test_needs_sphere_attributes(tmp_path):
    deck = rain_deck(1, dump_every=100000).replace("atom_style sphere", "atom_style atomic")
    deck = deck.replace("pair_style granular/jiang", "pair_style zero 1.0").replace(
        "pair_coeff * * normal", "pair_coeff * *\n# normal").replace("nve/sphere disc", "nve")
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix insert/rain2d needs per-atom radius, mass and omega" in caught.value.message


def test_no_atom_map_is_needed(tmp_path):
    """Without `atom_modify map` (LIGGGHTS' fix asks for one) the rows
    are those of the run with a map."""
    deck = rain_deck(600, dump_every=600).replace("atom_modify map array\n", "")
    run = run_lammps(deck, tmp_path)
    assert thermo_rows(run.output, THERMO_COLUMNS)[600][1:3] == [2 * PER_ROW, 2]
    grains = read_dump(tmp_path / "dump.rain")[-1][1]
    expected = [grain for row in rows_by_hand(2) for grain in row]
    assert list(grains["id"].astype(int)) == [tag for tag, _, _ in expected]
    assert list(grains["radius"]) == [0.5 * diameter for _, _, diameter in expected]


@pytest.mark.parametrize("new_step", [0, 1000000])
def test_reset_timestep_between_runs_keeps_the_rain_going(falling_rows, tmp_path, new_step):
    """2000 steps split in two runs at the step before a release (the
    release is pending when the first run ends), with reset_timestep back
    to 0 or forward to 10^6 in between: grains inserted, rows, stop reason,
    grains present and growth are those of the whole run step for step
    (counted from the start), as in LIGGGHTS (test_rain2d.py)."""
    _, output, frames = falling_rows
    whole = thermo_rows(output, THERMO_COLUMNS)
    first = releases(first_appearances(frames))[2] - 1
    deck = rain_deck(first, dump_every=100000,
                     tail=f"reset_timestep {new_step}\nrun {2000 - first}")
    pieces = tables_by_run(run_lammps(deck, tmp_path).output)
    before, after = pieces[-2], pieces[-1]
    assert min(after) == new_step and max(after) == new_step + 2000 - first
    joined = dict(before)
    joined.update({step - new_step + first: values for step, values in after.items()})
    assert sorted(joined) == list(range(2001))
    assert joined[2000][1] > whole[first][1]          # rows released after the split
    for step in range(2001):
        assert joined[step][1:] == whole[step][1:], step
