"""fix reinject: grains that fall below the exit plane re-enter at a free
spot of the injection region, at rest, and are counted.

The scene: 196 grains start as a lattice in a walled box with an open
bottom (no floor: the exit plane z = 0 is crossed by everyone) and rain
through it, so that within 0.6 s every grain leaves and re-enters about
twice. Every step is dumped, and the checks are made from the trajectories
alone: a re-entry is a grain at the exit plane in one frame and inside the
injection region in the next.
"""

import math

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump, thermo_rows
from analysis.common.tables import read_table
from analysis.testing import LiggghtsError
from conftest import has_mpirun

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

DIAMETER = 0.01
DENSITY = 2500.0
DT = 1.0e-4
G = 9.81
N_GRAINS = 196
EXIT = 0.0
REGION = (-0.045, 0.045, -0.045, 0.045, 0.2, 0.29)   # x, y, z bounds of region top
RATE_WINDOW = 0.1


def start_positions():
    """A 7 x 7 x 4 cubic lattice of spacing 0.012 at 0.15 < z < 0.2, each site
    moved by up to 0.9 mm: whole layers would otherwise cross the exit plane
    in the same step, in an order that rounding can change. Made here, not
    with displace_atoms, whose random numbers depend on the number of ranks."""
    rng = np.random.default_rng(7)
    sites = [(-0.036 + 0.012 * i, -0.036 + 0.012 * j, 0.156 + 0.012 * k)
             for k in range(4) for j in range(7) for i in range(7)]
    jitter = rng.uniform(-0.0009, 0.0009, (len(sites), 3))
    return "\n".join(f"create_atoms 1 single {x + dx!r} {y + dy!r} {z + dz!r} units box"
                     for (x, y, z), (dx, dy, dz) in zip(sites, jitter))


ORTHOGONAL_BOX = "block -0.05 0.05 -0.05 0.05 -0.05 0.3"


def rain_deck(steps=6000, fix_options="", processors="", dump_every=1, tail="",
              box=ORTHOGONAL_BOX):
    xlo, xhi, ylo, yhi, zlo, zhi = REGION
    return f"""
{granular_setup()}
{processors}
region box {box} units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{hooke_materials(1e4, 2.857e3, gamman=100, gammat=50, mu=0.5)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep {DT}
{start_positions()}
set group all diameter {DIAMETER} density {DENSITY}
fix sides all wall/gran model hooke/stiffness tangential history primitive type 1 xplane -0.05
fix sides2 all wall/gran model hooke/stiffness tangential history primitive type 1 xplane 0.05
fix sides3 all wall/gran model hooke/stiffness tangential history primitive type 1 yplane -0.05
fix sides4 all wall/gran model hooke/stiffness tangential history primitive type 1 yplane 0.05
region top block {xlo} {xhi} {ylo} {yhi} {zlo} {zhi} units box
fix gravi all gravity {G} vector 0 0 -1
fix integr all nve/sphere
fix out all reinject exit z {EXIT} region top seed 15485863 file exits.txt rate_window {RATE_WINDOW} {fix_options}
thermo_style custom step atoms f_out[1] f_out[2] f_out[3] f_out[4] f_out[5]
thermo_modify format float %.15g
thermo 100
dump d all custom {dump_every} dump.all id x y z vx vy vz radius mass
dump_modify d format "%d %.15g %.15g %.15g %.15g %.15g %.15g %.15g %.15g"
run {steps}
{tail}
"""


def reentries(frames):
    """(step, id, columns-of-that-frame, row) for every grain that jumped from
    the exit plane up into the injection region between two frames. Such a
    grain was below the plane either in the earlier frame or during the
    step (the fix moves grains that crossed it in the step's own position
    update too), hence the one-step travel allowed above the plane."""
    events = []
    for (_, before), (step, after) in zip(frames[:-1], frames[1:]):
        assert np.array_equal(before["id"], after["id"])
        one_step_travel = np.abs(before["vz"]) * DT + G * DT ** 2
        jumped = np.nonzero((before["z"] < EXIT + one_step_travel) &
                            (after["z"] > REGION[4]))[0]
        events += [(step, int(after["id"][k]), after, k) for k in jumped]
    return events


@pytest.fixture(scope="module")
def rain(tmp_path_factory, liggghts_binary):
    from conftest import run_liggghts
    workdir = tmp_path_factory.mktemp("rain")
    output = run_liggghts(rain_deck(), workdir)
    return workdir, output, read_dump(workdir / "dump.all")


def test_count_never_changes_and_every_exit_is_counted(rain):
    workdir, output, frames = rain
    assert all(len(columns["id"]) == N_GRAINS for _, columns in frames)
    events = reentries(frames)
    # the rain really cycles: every grain leaves at least once
    assert len({grain for _, grain, _, _ in events}) == N_GRAINS
    assert len(events) > 1.5 * N_GRAINS

    rows = thermo_rows(output, 7)
    last = max(rows)
    atoms, grains_out, mass_out, avalanche = rows[last][:4]
    assert atoms == N_GRAINS
    assert grains_out == len(events)
    assert avalanche == len(events)     # no fix clog closes avalanches here
    masses = [columns["mass"][k] for _, _, columns, k in events]
    assert mass_out == pytest.approx(sum(masses), rel=1e-12)
    # 2 pi r^3 rho / 3 * 4: each grain's mass, independently of the engine
    assert masses[0] == pytest.approx(4 / 3 * math.pi * (DIAMETER / 2) ** 3 * DENSITY, rel=1e-12)

    # the file: one line per step with re-entries, cumulative counts
    table = read_table(workdir / "exits.txt")
    steps_with_events = sorted({step for step, _, _, _ in events})
    assert list(table["step"].astype(int)) == steps_with_events
    assert table["n_out"][-1] == len(events)
    assert table["mass_out"][-1] == pytest.approx(mass_out, rel=1e-9)
    np.testing.assert_allclose(table["t"], table["step"] * DT, rtol=1e-12)


def test_reentered_grains_are_at_rest_inside_the_region_and_overlap_nothing(rain):
    _, _, frames = rain
    xlo, xhi, ylo, yhi, zlo, zhi = REGION
    radius = DIAMETER / 2
    for step, grain, columns, k in reentries(frames):
        position = np.array([columns["x"][k], columns["y"][k], columns["z"][k]])
        # whole grain inside the region
        assert xlo + radius <= position[0] <= xhi - radius
        assert ylo + radius <= position[1] <= yhi - radius
        assert zlo + radius <= position[2] <= zhi - radius
        # placed in pre_exchange, after this step's position update: the only
        # velocity is the half kick of gravity of this step's final_integrate
        # (it touches nothing, see below)
        velocity = np.array([columns["vx"][k], columns["vy"][k], columns["vz"][k]])
        np.testing.assert_allclose(velocity, [0.0, 0.0, -G * DT / 2], rtol=1e-9, atol=1e-15)
        # no overlap with any other grain of the same frame
        others = np.stack([columns["x"], columns["y"], columns["z"]], axis=1)
        distance = np.linalg.norm(others - position, axis=1)
        distance[k] = np.inf
        assert distance.min() >= DIAMETER, (step, grain, distance.min())


def test_flow_rate_is_the_count_over_the_window(rain):
    """f_ID[4] (grains/s) and f_ID[5] (kg/s): the change of the cumulative
    counts over the last rate_window of simulated time."""
    workdir, output, _ = rain
    table = read_table(workdir / "exits.txt")
    rows = thermo_rows(output, 7)
    window_steps = round(RATE_WINDOW / DT)

    def count_at(step):
        done = table["step"] <= step
        return (table["n_out"][done][-1], table["mass_out"][done][-1]) if done.any() else (0, 0)

    checked = 0
    for step, values in rows.items():
        if step < window_steps:
            continue
        grains_now, mass_now = count_at(step)
        grains_then, mass_then = count_at(step - window_steps)
        # values: atoms, out[1] ... out[5]
        assert values[4] == pytest.approx((grains_now - grains_then) / RATE_WINDOW, rel=1e-9, abs=1e-9)
        assert values[5] == pytest.approx((mass_now - mass_then) / RATE_WINDOW, rel=1e-9, abs=1e-12)
        checked += values[4] > 0
    assert checked >= 5


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_reinject_the_same_grains_at_the_same_spots(run, tmp_path):
    """The placements are drawn by every rank from the same sequence, with
    the leavers in id order: the first wave (all 196 grains, several per
    step, many of them owned by the other rank) lands on the same spots with
    1 and 2 ranks (`processors * 1 1`: with two ranks the boundary x = 0 splits the box)."""
    deck = rain_deck(steps=2100, processors="processors * 1 1")
    run(deck, subdir="one")
    run(deck, nprocs=2, subdir="two")
    one = reentries(read_dump(tmp_path / "one" / "dump.all"))
    two = reentries(read_dump(tmp_path / "two" / "dump.all"))
    assert len(one) == N_GRAINS and len(two) == N_GRAINS
    for (step1, grain1, c1, k1), (step2, grain2, c2, k2) in zip(one, two):
        assert (step1, grain1) == (step2, grain2)
        for axis in "xyz":
            assert c1[axis][k1] == pytest.approx(c2[axis][k2], abs=1e-12)
    # both sides of the rank boundary received grains
    xs = [c[k] for _, _, c, k in ((s, g, c["x"], k) for s, g, c, k in two)]
    assert min(xs) < 0 < max(xs)


@pytest.fixture(scope="module")
def first_wave(tmp_path_factory, liggghts_binary):
    """The rain's first wave (every grain leaves once) on one rank."""
    from conftest import run_liggghts
    workdir = tmp_path_factory.mktemp("first_wave")
    run_liggghts(rain_deck(steps=2100), workdir)
    return workdir, read_dump(workdir / "dump.all")


# A box leaning in x as it rises (tilt xz = 0.03 over its 0.35 of height),
# wide enough that the side walls at x = +-0.05 stay inside it at every height
TILTED_BOX = "prism -0.08 0.08 -0.05 0.05 -0.05 0.3 0 0.03 0"


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
@pytest.mark.parametrize("slabs, box", [(2, ORTHOGONAL_BOX), (4, ORTHOGONAL_BOX),
                                        (4, TILTED_BOX)], ids=["2", "4", "4-tilted"])
def test_vertical_slabs_keep_every_grain_and_reinject_as_one_rank(run, tmp_path, first_wave,
                                                                  slabs, box):
    """The box cut into 2 or 4 slabs along the vertical (`processors 1 1 N`
    on N ranks). Every grain leaves from the bottom slab (z < 0.0375 with 4
    slabs) and re-enters in the top slab or, with 4, also in the third
    (z < 0.2125), two ranks above: LIGGGHTS' exchange passes atoms to
    the neighbouring ranks only, so the fix sends those grains to their rank
    itself (before, 169 of the 196 grains were left with 4 slabs, silently).
    Every grain stays in every frame, and the record and the re-entries
    (steps, grains, spots) are those of one rank of the upright box.

    In the tilted box ranks own their sub-domains in fractional
    coordinates, and the fix converts the positions for the send and back
    (send_to_owners); without that, the re-entered grains (z > 0.2,
    fractional z > 0.71) are sent as if their z were fractional, to the
    bottom slabs, and lost there. Its walls and grains are those of the
    upright box."""
    one_dir, one_frames = first_wave
    run(rain_deck(steps=2100, processors=f"processors 1 1 {slabs}", box=box), nprocs=slabs)
    frames = read_dump(tmp_path / "dump.all")
    assert len(frames) == len(one_frames)
    assert all(len(columns["id"]) == N_GRAINS for _, columns in frames)
    assert (tmp_path / "exits.txt").read_text() == (one_dir / "exits.txt").read_text()

    one, many = reentries(one_frames), reentries(frames)
    assert len(one) == N_GRAINS and len(many) == N_GRAINS
    for (step1, grain1, c1, k1), (step2, grain2, c2, k2) in zip(one, many):
        assert (step1, grain1) == (step2, grain2)
        for axis in "xyz":
            assert c1[axis][k1] == pytest.approx(c2[axis][k2], abs=1e-12)
    if slabs == 4:
        top_slab_floor = -0.05 + 3 * (0.3 + 0.05) / 4      # the box spans -0.05 < z < 0.3
        assert sum(c["z"][k] < top_slab_floor for _, _, c, k in many) >= 10


# ---- periodic images -------------------------------------------------------
# A box periodic in x and y, |x|, |y| < 0.05. A large grain held still
# (diameter 0.05, not integrated) sits at x = 0.04, against the +x side:
# its periodic image, 0.1 to the left at x = -0.06, reaches into the
# injection region, which lies against the -x side. Four small grains fall
# through the exit again and again; a spot that overlaps the image would
# put a grain into it (at the next neighbor build it is across the side).
IMAGE_BOX_HALF = 0.05
OBSTACLE = (0.04, 0.0, 0.25, 0.05)                 # x, y, z, diameter
IMAGE_REGION = (-0.05, -0.03, -0.03, 0.03, 0.22, 0.28)
IMAGE_STEPS = 10000


def image_deck(head, contacts, dump_format):
    """The deck on either host: `head` (units to boundary), `contacts`
    (pair style and its coefficients), `dump_format` (a dump_modify line)."""
    x, y, z, diameter = OBSTACLE
    small = "\n".join(f"create_atoms 1 single {0.01 * k - 0.015!r} {0.012 * k - 0.018!r} "
                      f"{0.05 + 0.03 * k!r} units box" for k in range(4))
    xlo, xhi, ylo, yhi, zlo, zhi = IMAGE_REGION
    return f"""
{head}
region box block {-IMAGE_BOX_HALF} {IMAGE_BOX_HALF} {-IMAGE_BOX_HALF} {IMAGE_BOX_HALF} -0.05 0.35 units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{contacts}
timestep {DT}
create_atoms 1 single {x} {y} {z} units box
{small}
set atom 1 diameter {diameter} density {DENSITY}
set atom 2*5 diameter {DIAMETER} density {DENSITY}
group small id 2:5
region top block {xlo} {xhi} {ylo} {yhi} {zlo} {zhi} units box
fix gravi small gravity {G} vector 0 0 -1
fix integr small nve/sphere
fix out all reinject exit z {EXIT} region top seed 15485863 file exits.txt
dump d all custom 1 dump.all id x y z vx vy vz radius mass
{dump_format}
run {IMAGE_STEPS}
"""


def check_no_spot_overlaps_the_image(frames):
    """Every re-entry lands clear of the held grain and of its images
    (nearest image in x and y), and there are enough of them for a spot
    drawn without regard to the image to have met it."""
    x0, y0, z0, diameter = OBSTACLE
    for step, columns in frames:
        assert len(columns["id"]) == 5, f"a grain is lost at step {step}"
    events = [event for event in reentries(frames) if event[1] != 1]
    assert len(events) >= 12
    period = 2 * IMAGE_BOX_HALF
    for step, grain, columns, k in events:
        dx = columns["x"][k] - x0
        dy = columns["y"][k] - y0
        dx -= period * round(dx / period)
        dy -= period * round(dy / period)
        distance = math.sqrt(dx * dx + dy * dy + (columns["z"][k] - z0) ** 2)
        assert distance >= (diameter + DIAMETER) / 2, (step, grain, distance)


def test_a_spot_does_not_overlap_a_grain_across_a_periodic_side(run, tmp_path):
    """fix reinject checks the spots against the periodic images of the
    grains (core/reinject_logic.h, periodic_image_shifts): the held grain's
    image fills about half of the region's centre positions."""
    run(image_deck(granular_setup(boundary="p p f"),
                   hooke_materials(1e4, 2.857e3, gamman=100, gammat=50, mu=0.5) +
                   "\npair_style gran model hooke/stiffness tangential history\npair_coeff * *",
                   'dump_modify d format "%d %.15g %.15g %.15g %.15g %.15g %.15g %.15g %.15g"'))
    check_no_spot_overlaps_the_image(read_dump(tmp_path / "dump.all"))


def test_counts_times_and_pending_reentries_survive_a_restart(run, tmp_path, rain):
    """A run restarted at step N, chosen so that grains found below the exit
    at the end of step N re-enter at step N + 1, whose first piece ran on
    past N after writing the restart file, goes on as the uninterrupted
    rain: the re-entry still happens at N + 1 (the pending
    request is in the restart file; it was lost before, and the grains
    re-entered a step late), the counts, the random sequence and the
    flow-rate samples are restored (thermo at N identical, rates included),
    and the file's time column goes on from the time reached: the restarted
    run in the same directory appends to the same file, which then holds
    the lines of the uninterrupted rain up to step 4500, under one header,
    with t = step x dt. (LIGGGHTS 3.8's own time restarts at 0 after
    read_restart: with it, t was the time since the restart; and the file
    used to be opened anew, losing the first part's lines.)"""
    whole_dir, whole_output, _ = rain
    whole = read_table(whole_dir / "exits.txt")
    # in the first wave (exits from step 1780 to 1984): a flow rate to restore
    restart_step = int(whole["step"][whole["step"] > 1900][0]) - 1
    # the first piece runs on for 300 steps after writing the restart file
    # and then stops, as a run cut by a time limit: the lines it wrote
    # after the restart file are removed when the resumed run opens the file
    output = run(rain_deck(steps=restart_step, dump_every=100000,
                           tail="write_restart rain.restart\nrun 300"))
    before = thermo_rows(output, 7)[restart_step]
    ran_on = read_table(tmp_path / "exits.txt")["step"] > restart_step
    assert ran_on.sum() >= 5
    resumed = f"""
units si
atom_modify map array
read_restart rain.restart
newton off
communicate single vel yes
{hooke_materials(1e4, 2.857e3, gamman=100, gammat=50, mu=0.5)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep {DT}
fix sides all wall/gran model hooke/stiffness tangential history primitive type 1 xplane -0.05
fix sides2 all wall/gran model hooke/stiffness tangential history primitive type 1 xplane 0.05
fix sides3 all wall/gran model hooke/stiffness tangential history primitive type 1 yplane -0.05
fix sides4 all wall/gran model hooke/stiffness tangential history primitive type 1 yplane 0.05
region top block {' '.join(str(v) for v in REGION)} units box
fix gravi all gravity {G} vector 0 0 -1
fix integr all nve/sphere
fix out all reinject exit z {EXIT} region top seed 15485863 file exits.txt rate_window {RATE_WINDOW}
thermo_style custom step atoms f_out[1] f_out[2] f_out[3] f_out[4] f_out[5]
thermo_modify format float %.15g
thermo 100
run {4500 - restart_step}
"""
    lines_before = (tmp_path / "exits.txt").read_text().splitlines()[:-int(ran_on.sum())]
    resumed_output = run(resumed)
    assert (f"fix reinject: removed {ran_on.sum()} line(s) past t = {restart_step * DT:.10g} "
            "from 'exits.txt'") in resumed_output
    after = thermo_rows(resumed_output, 7)
    assert after[restart_step] == before
    assert before[2] > 0 and before[5] > 0       # grains out, and a flow rate to restore
    # thermo every 100 steps after the restart: as in the uninterrupted run
    uninterrupted = thermo_rows(whole_output, 7)
    later = [step for step in after if step > restart_step]
    assert len(later) >= 20
    for step in later:
        assert after[step] == pytest.approx(uninterrupted[step], rel=1e-12), step

    whole_lines = (whole_dir / "exits.txt").read_text().splitlines()
    pieced_lines = (tmp_path / "exits.txt").read_text().splitlines()
    # the first part's lines up to N are kept, those it wrote after the
    # restart file are not, the header is not repeated
    assert pieced_lines[:len(lines_before)] == lines_before
    header = [line for line in whole_lines if line.startswith("#")]
    assert len(header) == 2
    assert [line for line in pieced_lines if line.startswith("#")] == header

    pieced = read_table(tmp_path / "exits.txt")
    until_end = whole["step"] <= 4500
    assert (pieced["step"] <= restart_step).sum() >= 10 and (pieced["step"] > restart_step).sum() >= 10
    # the pending re-entry happens on the first step after the restart
    assert restart_step + 1 in pieced["step"]
    for column in ("step", "n_out", "avalanche"):
        np.testing.assert_array_equal(pieced[column], whole[column][until_end], err_msg=column)
    np.testing.assert_allclose(pieced["mass_out"], whole["mass_out"][until_end], rtol=1e-14)
    np.testing.assert_allclose(pieced["t"], pieced["step"] * DT, rtol=1e-12)
    np.testing.assert_allclose(pieced["t"], whole["t"][until_end], rtol=1e-12)


# ------------------------------------------------------------ bad input

def refused(run, fix_line):
    deck = rain_deck(steps=1, dump_every=100000).replace(
        f"fix out all reinject exit z {EXIT} region top seed 15485863 file exits.txt "
        f"rate_window {RATE_WINDOW} ", fix_line)
    with pytest.raises(LiggghtsError) as caught:
        run(deck)
    return caught.value.message


# (fix line, what the ERROR says); the keywords are parsed by
# core/reinject_logic.h, and tests/test_lammps_reinject.py gives LAMMPS'
# fix the same lines
BAD_INPUT = [
    ("fix out all reinject region top seed 15485863", "'exit <axis> <coordinate>' is required"),
    ("fix out all reinject exit z 0.0 seed 15485863", "'region <region-ID>' is required"),
    ("fix out all reinject exit z 0.0 region top", "'seed <positive integer>' is required"),
    ("fix out all reinject exit w 0.0 region top seed 15485863", "'exit' takes an axis x, y or z"),
    ("fix out all reinject exit z low region top seed 15485863", "'exit' expects a number, got 'low'"),
    ("fix out all reinject exit z 0.0 region nowhere seed 15485863", "region 'nowhere' does not exist"),
    ("fix out all reinject exit z 0.25 region top seed 15485863", "the region must lie above the exit plane"),
    ("fix out all reinject exit z 0.0 region top seed -3", "'seed' must be a positive integer"),
    ("fix out all reinject exit z 0.0 region top seed 15485863.5", "'seed' expects an integer, got '15485863.5'"),
    ("fix out all reinject exit z 0.0 region top seed 1e12", "'seed' expects an integer, got '1e12'"),
    ("fix out all reinject exit z 0.0 region top seed prime", "'seed' expects a number, got 'prime'"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 every 0", "'every' must be >= 1"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 every 2.7", "'every' expects an integer, got '2.7'"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 every 1e12", "'every' expects an integer, got '1e12'"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 maxattempt 0", "'maxattempt' must be >= 1"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 maxattempt 10.5", "'maxattempt' expects an integer, got '10.5'"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 rate_window 0", "'rate_window' must be > 0"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 maxattempt", "keyword 'maxattempt' needs a value"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 colour red", "unknown keyword 'colour'"),
    # both hosts keep a region's bounding box from its definition and draw
    # the spots in it
    ("variable lift equal 0.01*time\n"
     "region spin block -0.02 0.02 -0.02 0.02 0.2 0.28 units box move NULL NULL v_lift\n"
     "fix out all reinject exit z 0.0 region spin seed 15485863",
     "region 'spin' moves or changes shape; the region must be static"),
    ("variable size equal 0.015\n"
     "region bulb sphere 0 0 0.25 v_size units box\n"
     "fix out all reinject exit z 0.0 region bulb seed 15485863",
     "region 'bulb' moves or changes shape; the region must be static"),
]


@pytest.mark.parametrize("fix_line, expected", BAD_INPUT)
def test_bad_input(run, fix_line, expected):
    assert expected in refused(run, fix_line)


def test_no_free_spot_is_an_error(run):
    # a region that holds no grain at all: it is thinner than a diameter
    deck = rain_deck(steps=2000, dump_every=100000).replace(
        "region top block", "region top block -0.045 0.045 -0.045 0.045 0.2 0.205 units box\n"
        "region unused block")
    with pytest.raises(LiggghtsError) as caught:
        run(deck)
    assert "no free spot in region 'top' for grain" in caught.value.message
    assert "after 1000 attempts: enlarge the region or raise 'maxattempt'" in caught.value.message
