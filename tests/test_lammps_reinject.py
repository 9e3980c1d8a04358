"""fix reinject in LAMMPS (our plugin; doc/fix_reinject_lammps.md): grains
that fall below the exit plane re-enter at a free spot of the injection
region, at rest, and are counted, as with the LIGGGHTS fix of the same name.

The scene: 48 grains start as a lattice in a box periodic in x and y with
an open bottom and rain through the exit plane z = 0, so that within 0.6 s
every grain leaves and re-enters about twice. The same scene runs in
LIGGGHTS with its fix reinject (LIGGGHTS' pair gran hooke/stiffness with
tangential history here, pair granular/jiang with the same law in LAMMPS).
A re-entry is read from the trajectories alone: a grain at the exit plane
in one frame and inside the injection region in the next (reentries() of
tests/test_reinject.py: the exit plane, the bottom of the region, the time
step and gravity are those of its scene).
"""

import math

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump, thermo_rows
from analysis.common.tables import read_table
from analysis.testing import LiggghtsError, liggghts_binary, run_deck
from lammps_host import has_mpirun, needs_lammps, run_lammps
from test_reinject import DENSITY, DIAMETER, DT, EXIT, G, RATE_WINDOW, REGION as LIGGGHTS_REGION
from test_reinject import BAD_INPUT, reentries
from test_reinject import check_no_spot_overlaps_the_image, image_deck

pytestmark = needs_lammps

MASS = 4.0 / 3.0 * math.pi * (DIAMETER / 2) ** 3 * DENSITY
N_GRAINS = 48
HALF_WIDTH = 0.03                                     # the box: |x|, |y| < 0.03, periodic
# x, y, z bounds of region top: narrower than in test_reinject.py, as high
REGION = (-0.025, 0.025, -0.025, 0.025) + LIGGGHTS_REGION[4:]
SEED = 15485863
FIX_LINE = (f"fix out all reinject exit z {EXIT} region top seed {SEED} file exits.txt "
            f"rate_window {RATE_WINDOW}")
# the rain's contact law in LAMMPS (LIGGGHTS' hooke/stiffness in rain_deck)
LAMMPS_CONTACTS = ("pair_style granular/jiang\n"
                   "pair_coeff * * normal hooke/stiffness 1e4 2857 100 50 friction 0.5")
THERMO_COLUMNS = 7                                    # step atoms f_out[1..5]
DUMP_FORMAT = " ".join(["%d"] + ["%.17g"] * 8)
LAMMPS_DUMP_FORMAT = f'dump_modify d format line "{DUMP_FORMAT}"'


def start_positions():
    """A 4 x 4 x 3 cubic lattice of spacing 0.012 at 0.15 < z < 0.19, each
    site moved by up to 0.9 mm (whole layers would otherwise cross the exit
    plane in the same step, in an order that rounding can change)."""
    rng = np.random.default_rng(11)
    sites = [(-0.018 + 0.012 * i, -0.018 + 0.012 * j, 0.156 + 0.012 * k)
             for k in range(3) for j in range(4) for i in range(4)]
    jitter = rng.uniform(-0.0009, 0.0009, (len(sites), 3))
    return "\n".join(f"create_atoms 1 single {x + dx!r} {y + dy!r} {z + dz!r} units box"
                     for (x, y, z), (dx, dy, dz) in zip(sites, jitter))


# the deck's first lines in LAMMPS (granular_setup's in LIGGGHTS)
LAMMPS_HEAD = """plugin load ${plugin}
units si
atom_style sphere
atom_modify map array
boundary p p f
newton off
comm_modify vel yes"""
ORTHOGONAL_BOX = f"block {-HALF_WIDTH} {HALF_WIDTH} {-HALF_WIDTH} {HALF_WIDTH} -0.05 0.3"


def rain_deck(host="lammps", steps=6000, fix_line=FIX_LINE, processors="", dump_every=1,
              tail="", box=ORTHOGONAL_BOX):
    """The rain in `host` (lammps or liggghts): the same grains, contact
    law, region, fix reinject line, thermo and dump."""
    if host == "lammps":
        head = LAMMPS_HEAD
        contacts = LAMMPS_CONTACTS
        dump_format = LAMMPS_DUMP_FORMAT
    else:
        head = granular_setup(boundary="p p f")
        contacts = (hooke_materials(1e4, 2857, gamman=100, gammat=50, mu=0.5) +
                    "pair_style gran model hooke/stiffness tangential history\npair_coeff * *")
        dump_format = f'dump_modify d format "{DUMP_FORMAT}"'
    return f"""
{head}
{processors}
region box {box} units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{contacts}
timestep {DT}
{start_positions()}
set group all diameter {DIAMETER} density {DENSITY}
{motion_and_output(fix_line, dump_every, "dump.all", dump_format)}
run {steps}
{tail}
"""


def motion_and_output(fix_line, dump_every, dump_name, dump_format):
    """The deck's lines from the injection region to the dump: the same in
    a fresh deck and in one that reads a restart file."""
    return f"""
region top block {' '.join(str(bound) for bound in REGION)} units box
fix gravi all gravity {G} vector 0 0 -1
fix integr all nve/sphere
{fix_line}
thermo_style custom step atoms f_out[1] f_out[2] f_out[3] f_out[4] f_out[5]
thermo_modify format float %.15g
thermo 100
dump d all custom {dump_every} {dump_name} id x y z vx vy vz radius mass
{dump_format}"""


def closest_approach(columns):
    """The smallest centre distance between two grains of a frame, with
    the periodic images in x and y."""
    position = np.stack([columns["x"], columns["y"], columns["z"]], axis=1)
    gap = position[:, None, :] - position[None, :, :]
    for k in (0, 1):
        gap[:, :, k] -= 2 * HALF_WIDTH * np.round(gap[:, :, k] / (2 * HALF_WIDTH))
    distance = np.linalg.norm(gap, axis=2)
    np.fill_diagonal(distance, np.inf)
    return distance.min()


@pytest.fixture(scope="module")
def rain(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("lammps_rain")
    run = run_lammps(rain_deck(), workdir)
    return workdir, run.output, read_dump(workdir / "dump.all")


@pytest.fixture(scope="module")
def liggghts_rain(tmp_path_factory):
    if not liggghts_binary().exists():
        pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
    workdir = tmp_path_factory.mktemp("liggghts_rain")
    run = run_deck(rain_deck("liggghts"), workdir)
    return workdir, run.output, read_dump(workdir / "dump.all")


# ------------------------------------------------------------ the rain in LAMMPS

def test_every_exit_re_enters_and_is_counted(rain):
    workdir, output, frames = rain
    assert all(len(columns["id"]) == N_GRAINS for _, columns in frames)
    events = reentries(frames)
    # the rain cycles: every grain leaves at least once, most twice
    assert len({grain for _, grain, _, _ in events}) == N_GRAINS
    assert len(events) > 1.5 * N_GRAINS

    rows = thermo_rows(output, THERMO_COLUMNS)
    atoms, grains_out, mass_out, avalanche = rows[max(rows)][:4]
    assert atoms == N_GRAINS
    assert grains_out == len(events)
    assert avalanche == len(events)     # no fix clog closes avalanches here
    masses = [columns["mass"][k] for _, _, columns, k in events]
    np.testing.assert_allclose(masses, MASS, rtol=1e-12)
    assert mass_out == pytest.approx(sum(masses), rel=1e-12)

    # the record: one line per step with re-entries, cumulative counts
    table = read_table(workdir / "exits.txt")
    assert list(table["step"].astype(int)) == sorted({step for step, _, _, _ in events})
    assert table["n_out"][-1] == len(events)
    assert table["mass_out"][-1] == pytest.approx(mass_out, rel=1e-9)
    np.testing.assert_allclose(table["t"], table["step"] * DT, rtol=1e-12)


def test_reentered_grains_are_at_rest_inside_the_region_and_overlap_nothing(rain):
    """Each re-entered grain lies wholly in the region, touches no other
    grain, and moves only with the half kick of gravity of the step it was
    placed in (placed in pre_exchange, after that step's position update,
    at rest)."""
    _, _, frames = rain
    events = reentries(frames)
    spots = np.array([[columns[axis][k] for axis in "xyz"] for _, _, columns, k in events])
    velocities = np.array([[columns[v][k] for v in ("vx", "vy", "vz")]
                           for _, _, columns, k in events])
    radius = DIAMETER / 2
    assert np.all(spots >= np.array(REGION[0::2]) + radius)
    assert np.all(spots <= np.array(REGION[1::2]) - radius)
    np.testing.assert_allclose(velocities, np.tile([0.0, 0.0, -G * DT / 2], (len(events), 1)),
                               rtol=1e-9, atol=1e-15)
    nearest = [np.delete(np.linalg.norm(np.stack([columns[a] for a in "xyz"], axis=1) - spot,
                                        axis=1), k).min()
               for spot, (_, _, columns, k) in zip(spots, events)]
    assert min(nearest) >= DIAMETER


# ------------------------------------------------------------ against LIGGGHTS

def test_the_record_and_the_counts_are_those_of_liggghts(rain, liggghts_rain):
    """The same rain in LIGGGHTS: the same record file, header and lines
    (step, t, n_out, mass_out, avalanche), the same thermo values (counts
    and flow rates: the rates' formula is checked on the LIGGGHTS fix, in
    test_reinject.py), and the re-entered grains on the same spots. Both hosts draw the spots from
    the same Park-Miller sequence (same seed) among the same grains in the
    same order, test the region in the same way, and integrate with
    nve/sphere; the contact law is the same. Measured: equal to the last
    printed digit, so the test asks for that."""
    lammps_dir, lammps_output, lammps_frames = rain
    liggghts_dir, liggghts_output, liggghts_frames = liggghts_rain
    ours = (lammps_dir / "exits.txt").read_text().splitlines()
    theirs = (liggghts_dir / "exits.txt").read_text().splitlines()
    assert ours[:2] == theirs[:2] == ["# fix reinject out: grains re-entered after leaving below z = 0",
                                      "# step t n_out mass_out avalanche"]
    assert len(ours) > 50
    assert ours == theirs
    assert thermo_rows(lammps_output, THERMO_COLUMNS) == thermo_rows(liggghts_output, THERMO_COLUMNS)
    a, b = reentries(lammps_frames), reentries(liggghts_frames)
    assert [(step, grain) for step, grain, _, _ in a] == [(step, grain) for step, grain, _, _ in b]
    for (_, _, c1, k1), (_, _, c2, k2) in zip(a, b):
        for axis in "xyz":
            assert c1[axis][k1] == c2[axis][k2]


def test_the_fix_may_come_before_pair_style(tmp_path, rain):
    """LAMMPS' granular pairs add their contact-history fix at pair_style,
    so a fix defined before it runs its pre_exchange first. The fix reads
    nothing of the pair and moves only grains below the exit plane: the
    same deck with fix reinject before pair_style writes the same
    trajectories to the bit (6000 steps, every grain re-entering about
    twice, contacts with history among the falling grains)."""
    workdir, _, _ = rain
    deck = rain_deck()
    assert deck.count(LAMMPS_CONTACTS) == 1
    late = deck.replace(LAMMPS_CONTACTS, "").replace(FIX_LINE, f"{FIX_LINE}\n{LAMMPS_CONTACTS}")
    assert late.index(FIX_LINE) < late.index("pair_style")
    run_lammps(late, tmp_path)
    assert (tmp_path / "dump.all").read_bytes() == (workdir / "dump.all").read_bytes()


# ------------------------------------------------------------ MPI

@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
@pytest.mark.parametrize("processors", ["processors 2 1 1", "processors 1 1 4"])
def test_more_ranks_reinject_the_same_grains_at_the_same_spots(tmp_path, rain, processors):
    """Every rank draws the spots from the same sequence, with the leavers
    in id order: the re-entries (step, grain, spot) and the record are
    those of one rank. With 2 ranks side by side (the boundary x = 0) the
    grains are moved across it; with 4 ranks stacked in z a grain leaves
    on the bottom rank and re-enters on the top one, three sub-domains
    away, farther than LAMMPS' own exchange passes atoms (it sends them to
    the two neighbouring ranks of each direction; LIGGGHTS' fix, which
    relies on it, loses grains there): the fix sends them, and none is
    lost (LAMMPS stops on lost atoms by default)."""
    ranks = 2 if processors.startswith("processors 2") else 4
    workdir, _, frames = rain
    run_lammps(rain_deck(steps=2500, processors=processors), tmp_path, nprocs=ranks)
    one = [event for event in reentries(frames) if event[0] <= 2500]
    many = reentries(read_dump(tmp_path / "dump.all"))
    assert len(one) >= N_GRAINS and len(many) == len(one)
    for (step1, grain1, c1, k1), (step2, grain2, c2, k2) in zip(one, many):
        assert (step1, grain1) == (step2, grain2)
        for axis in "xyz":
            assert c1[axis][k1] == pytest.approx(c2[axis][k2], abs=1e-12)
    whole = read_table(workdir / "exits.txt")
    parallel = read_table(tmp_path / "exits.txt")
    first = whole["step"] <= 2500
    for column in ("step", "n_out", "avalanche"):
        np.testing.assert_array_equal(parallel[column], whole[column][first])
    if ranks == 2:
        xs = [c["x"][k] for _, _, c, k in many]
        assert min(xs) < 0 < max(xs)


# Boxes twice as wide as the rain's, upright and leaning in x as they rise
# (tilt xz = 0.02 over the 0.35 of height): wide enough that every site of
# the start lattice lies inside the tilted box (in the rain's own width,
# create_atoms leaves out the 10 of the 48 sites that the tilt puts outside)
WIDE = 2 * HALF_WIDTH
WIDE_BOX = f"block {-WIDE} {WIDE} {-WIDE} {WIDE} -0.05 0.3"
TILTED_BOX = f"prism {-WIDE} {WIDE} {-WIDE} {WIDE} -0.05 0.3 0 0.02 0"


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_a_tilted_box_on_four_stacked_ranks_reinjects_as_one_rank_of_an_upright_one(tmp_path):
    """In a triclinic box ranks own their sub-domains in fractional
    coordinates, and the fix finds a moved grain's rank from its fractional
    position (send_to_owners). The rain in the box leaning in x on 4 ranks
    stacked in z, and in the upright box on one rank: the same grains
    re-enter at the same steps and spots (x taken modulo the period: the
    tilted box wraps x at other places), and none is lost (LAMMPS stops on
    lost atoms)."""
    run_lammps(rain_deck(steps=2500, box=WIDE_BOX), tmp_path / "upright")
    run_lammps(rain_deck(steps=2500, processors="processors 1 1 4", box=TILTED_BOX),
               tmp_path / "tilted", nprocs=4)
    one = reentries(read_dump(tmp_path / "upright" / "dump.all"))
    many = reentries(read_dump(tmp_path / "tilted" / "dump.all"))
    assert len(one) >= N_GRAINS and len(many) == len(one)
    period = 2 * WIDE
    for (step1, grain1, c1, k1), (step2, grain2, c2, k2) in zip(one, many):
        assert (step1, grain1) == (step2, grain2)
        shift = c2["x"][k2] - c1["x"][k1]
        assert shift - period * round(shift / period) == pytest.approx(0.0, abs=1e-12)
        for axis in "yz":
            assert c1[axis][k1] == pytest.approx(c2[axis][k2], abs=1e-12)
    # grains leave from the bottom sub-domain; some re-enter in the top one,
    # three sub-domains above, which only the fix's own send reaches
    top_floor = -0.05 + 3 * (0.3 + 0.05) / 4
    assert sum(c["z"][k] > top_floor for _, _, c, k in many) >= 10


def test_a_spot_does_not_overlap_a_grain_across_a_periodic_side(tmp_path):
    """The spots are checked against the grains' periodic images
    (test_reinject.py's scene: a held grain whose image reaches into the
    injection region across the -x side)."""
    run_lammps(image_deck(LAMMPS_HEAD, LAMMPS_CONTACTS, LAMMPS_DUMP_FORMAT), tmp_path)
    check_no_spot_overlaps_the_image(read_dump(tmp_path / "dump.all"))


# ------------------------------------------------------------ restart

def test_a_run_split_by_a_restart_writes_the_lines_of_the_whole_run(tmp_path, rain):
    """Cut at step N in the first wave, on a step whose leavers re-enter at
    N + 1; the first piece runs on for 300 steps after write_restart (as a
    run stopped by a time limit). The second deck, in the same directory,
    drops the lines written after the restart file, re-enters the pending
    grains at N + 1, and leaves a record with the lines of the whole run
    under one header, with the same times (the fix's own clock: LAMMPS'
    time reads 0 after read_restart); thermo (counts and flow rates) and
    the positions after the restart are those of the whole run. No grain
    touches another at the cut, so the set-up force call of the continued
    run sees the same forces as the whole run (with contacts, damping
    makes them differ at round-off: doc/lammps_host.md section 7)."""
    whole_dir, whole_output, whole_frames = rain
    whole = read_table(whole_dir / "exits.txt")
    restart_step = int(whole["step"][whole["step"] > 1900][0]) - 1
    end = 4500
    at_cut = next(columns for step, columns in whole_frames if step == restart_step)
    assert closest_approach(at_cut) > DIAMETER

    first = rain_deck(steps=restart_step, dump_every=100000,
                      tail="write_restart rain.restart\nrun 300")
    before = thermo_rows(run_lammps(first, tmp_path).output, THERMO_COLUMNS)[restart_step]
    ran_on = int((read_table(tmp_path / "exits.txt")["step"] > restart_step).sum())
    assert ran_on >= 3
    lines_before = (tmp_path / "exits.txt").read_text().splitlines()[:-ran_on]

    second = f"""
plugin load ${{plugin}}
read_restart rain.restart
comm_modify vel yes
neighbor 0.002 bin
neigh_modify delay 0
{motion_and_output(FIX_LINE, 100, "dump.second", LAMMPS_DUMP_FORMAT)}
run {end - restart_step}
"""
    resumed = run_lammps(second, tmp_path).output
    assert (f"fix reinject: removed {ran_on} line(s) past t = {restart_step * DT:.10g} "
            "from 'exits.txt'") in resumed
    after = thermo_rows(resumed, THERMO_COLUMNS)
    assert after[restart_step] == before
    assert before[1] > 0 and before[4] > 0           # grains out, and a flow rate to restore
    uninterrupted = thermo_rows(whole_output, THERMO_COLUMNS)
    later = [step for step in after if step > restart_step]
    assert len(later) >= 20
    for step in later:
        assert after[step] == uninterrupted[step], step

    whole_lines = (whole_dir / "exits.txt").read_text().splitlines()
    pieced_lines = (tmp_path / "exits.txt").read_text().splitlines()
    assert pieced_lines[:len(lines_before)] == lines_before
    kept = [line for line in whole_lines if line.startswith("#") or int(line.split()[0]) <= end]
    assert pieced_lines == kept
    assert str(restart_step + 1) in [line.split()[0] for line in pieced_lines]

    whole_by_step = dict(whole_frames)
    for step, columns in read_dump(tmp_path / "dump.second"):
        for name in ("x", "y", "z", "vx", "vy", "vz"):
            np.testing.assert_array_equal(columns[name], whole_by_step[step][name], err_msg=name)


# ------------------------------------------------------------ bad input

# the LIGGGHTS fix's bad lines (the same parser, core/reinject_logic.h),
# then what only this test exercises
BAD = BAD_INPUT + [
    ("fix out all reinject exit z 0.0 region top seed 15485863 rate_window x", "'rate_window' expects a number, got 'x'"),
    ("fix out all reinject exit z", "keyword 'exit' needs two values"),
    ("fix out all reinject exit z 0.0 region top seed 15485863 file /nonexistent/dir/x.txt",
     "cannot open file '/nonexistent/dir/x.txt'"),
]


@pytest.mark.parametrize("fix_line, expected", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_input_names_the_keyword(tmp_path, fix_line, expected):
    deck = rain_deck(steps=1, dump_every=100000, fix_line=fix_line)
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix reinject" in caught.value.message
    assert expected in caught.value.message


def test_no_free_spot_is_an_error(tmp_path):
    """A region thinner than a diameter holds no grain."""
    deck = rain_deck(steps=2500, dump_every=100000).replace(
        "region top block", "region top block -0.025 0.025 -0.025 0.025 0.2 0.205 units box\n"
        "region unused block")
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "no free spot in region 'top' for grain" in caught.value.message
    assert "after 1000 attempts: enlarge the region or raise 'maxattempt'" in caught.value.message


def test_rods_and_other_shapes_are_refused(tmp_path):
    """Spheres only in LAMMPS: an atom style with ellipsoids (what rods
    would need) stops with an ERROR saying so."""
    deck = rain_deck(steps=1, dump_every=100000).replace(
        "atom_style sphere", "atom_style hybrid sphere ellipsoid")
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix reinject: spheres only in LAMMPS" in caught.value.message


def test_in_2d_the_exit_axis_is_not_z(tmp_path):
    deck = """plugin load ${plugin}
units si
dimension 2
atom_style sphere
boundary p f p
region box block -0.03 0.03 -0.05 0.3 -0.5 0.5 units box
create_box 1 box
region top block -0.025 0.025 0.2 0.29 -0.5 0.5 units box
fix out all reinject exit z 0.0 region top seed 15485863
"""
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix reinject: 'exit': in 2D the vertical axis is x or y, not z" in caught.value.message
