"""fix clog in LAMMPS (our plugin; doc/fix_clog_lammps.md) on the hand-built
scene of tests/test_clog.py: a frozen arch of three grains with a defect
over an outlet between two base grains, and a grain resting on it. No grain
is integrated, so the scene is exactly at rest and its contacts are those
built; the records expected (members, order, angles, feet, contact points,
forces k_n * delta) are computed from the construction by test_clog's
check_records, independently of either fix. The same scene runs in
LIGGGHTS with its fix clog, and both hosts must find the same arch.
"""

import re

import numpy as np
import pytest

from analysis.common.lammps_io import thermo_rows
from analysis.common.tables import read_table
from analysis.testing import LiggghtsError, liggghts_binary, run_deck
from lammps_host import has_mpirun, needs_lammps, run_lammps
from test_clog import (BAD_INPUT, D, DENSITY, FIX_LINE, G, KN, arch_scene, check_records,
                       clog_deck, expected_records)

pytestmark = needs_lammps

RECORDS = ("clogs.txt", "arches.txt", "feet.txt", "contacts.txt")
THERMO_COLUMNS = 7         # step atoms f_clog[1..5]


def lammps_deck(fix_line=FIX_LINE, processors="", steps=1000, restart_file=None, tail=""):
    """The scene of test_clog.clog_deck in LAMMPS: atom ids base 1-8, walk
    9-13, top 14; the same contact law (hooke/stiffness, kt = 2/7 kn, no
    damping, mu = 0.5), time step, gravity, fix reinject and fix clog
    lines. One `run steps`, then the steps run are printed. restart_file:
    the box, atoms, groups, pair and time step come from it."""
    base, walk, top = arch_scene()
    points = list(base) + list(walk) + [tuple(top)]
    if restart_file:
        system = f"read_restart {restart_file}"
    else:
        creates = "\n".join(f"create_atoms 1 single {x!r} 0.0 {z!r} units box" for x, z in points)
        system = f"""units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
{processors}
region box block -0.06 0.06 -0.01 0.01 -0.05 0.1 units box
create_box 1 box
{creates}
set group all diameter {D} density {DENSITY}
group base id {' '.join(str(i + 1) for i in range(len(base)))}
group grains id {len(base) + 1}:{len(points)}
pair_style granular/jiang
pair_coeff * * normal hooke/stiffness {KN!r} {KN * 2 / 7!r} 0 0 friction 0.5
timestep 1e-5"""
    return f"""plugin load ${{plugin}}
{system}
comm_modify vel yes
neighbor 0.001 bin
neigh_modify delay 0
fix gravity all gravity {G} vector 0 0 -1
region top block -0.04 0.04 -0.01 0.01 0.06 0.09 units box
fix reinject grains reinject exit z -0.03 region top seed 15485863 every 10
{fix_line}
thermo_style custom step atoms f_clog[1] f_clog[2] f_clog[3] f_clog[4] f_clog[5]
thermo_modify format float %.15g
thermo 50
run {steps}
variable steps_run equal step
print "steps run: ${{steps_run}}"
{tail}
"""


@pytest.fixture(scope="module")
def clogged(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("lammps_clog")
    # a second run after the clog: the flag is up, so it does no step
    run = run_lammps(lammps_deck(tail="run 500\nprint \"after: ${steps_run}\""), workdir)
    return workdir, run.output


def test_the_hand_built_arch_is_found_exactly(clogged):
    workdir, output = clogged
    check_records(workdir)
    assert ("fix clog clog: clog 1 at t = 0.001 s (step 100), avalanche 0 grains, "
            "arch of 3 grains") in output


def test_the_run_stops_at_the_clog_as_with_fix_halt(clogged):
    """`run 1000` ends at step 100, the first check with quiet_time behind
    it; the flag (output 3) is up; a later run does no step."""
    _, output = clogged
    assert "fix clog clog: the run stops at step 100 (the flow clogged)" in output
    assert "for 100 steps with 14 atoms" in output
    assert "steps run: 100" in output
    assert "after: 100" in output
    assert "for 0 steps with 14 atoms" in output
    rows = thermo_rows(output, THERMO_COLUMNS)
    assert rows[100][1:4] == [1, 1, 1]       # clogs, arches, flag
    assert rows[50][1:4] == [0, 0, 0]


def test_the_same_arch_as_the_liggghts_fix(clogged, tmp_path):
    """The LIGGGHTS fix on the same scene (test_clog.clog_deck): the same
    headers and rows, every column to the printed digit (ids, order, base
    grains, flags; positions, angles phi, |F_n|: both hosts place the atoms
    from the same decimal text, run the same walk and compute k_n delta
    with the same operations), but |F_t|: LIGGGHTS' compute
    pair/gran/local gives the tangential force as the total minus the
    normal part, 1e-16 N of rounding here, where our pair gives 0
    (measured: the files differ in that column only)."""
    lammps_dir, _ = clogged
    if not liggghts_binary().exists():
        pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
    run_deck(clog_deck(), tmp_path)
    for name in RECORDS:
        ours_text, theirs_text = ((directory / name).read_text().splitlines()
                                  for directory in (lammps_dir, tmp_path))
        assert ours_text[0] == theirs_text[0], name
        assert len(ours_text) == len(theirs_text), name
        ours, theirs = read_table(lammps_dir / name), read_table(tmp_path / name)
        for column in ours:
            if column == "ft":
                np.testing.assert_allclose(ours[column], theirs[column], rtol=0, atol=1e-12,
                                           err_msg=name)
            else:
                np.testing.assert_array_equal(ours[column], theirs[column],
                                              err_msg=f"{name} {column}")
    assert len(read_table(lammps_dir / "arches.txt")["id"]) == 3


def test_moving_contacts_carry_the_forces_of_liggghts(tmp_path):
    """The same scene with the free grains integrated and damped contacts
    (gamman 2000/s, gammat 1000/s): in the 100 steps before the clog the
    grains sag under gravity and the arch comes apart, the tangential
    springs load and the dashpots act, so |F_t| and the damping part of
    |F_n| are those of the stored history and the current velocities.
    `ratio 1e10` takes the first check after quiet_time for the clog.
    Both hosts integrate with nve/sphere, but may sum forces in another
    order: the test allows rounding (1e-12 m, 1e-8 relative), far below
    the change the motion brings (over 10 % of |F_n|). Measured: the
    contact records are equal to the printed digit."""
    if not liggghts_binary().exists():
        pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
    options = "action stop ratio 1e10"
    moving = FIX_LINE.replace("action stop", options)
    deck = lammps_deck(fix_line=moving)
    assert " 0 0 friction 0.5" in deck
    deck = deck.replace(" 0 0 friction 0.5", " 2000.0 1000.0 friction 0.5")
    deck = deck.replace("fix gravity all", "fix integrate grains nve/sphere\nfix gravity all")
    run_lammps(deck, tmp_path / "lammps")
    liggghts = clog_deck(fix_options=options, extra="fix integrate grains nve/sphere")
    for name, value in (("gamman", 2000.0), ("gammat", 1000.0)):
        assert f"{name} peratomtypepair 1 0.0" in liggghts
        liggghts = liggghts.replace(f"{name} peratomtypepair 1 0.0", f"{name} peratomtypepair 1 {value}")
    run_deck(liggghts, tmp_path / "liggghts")

    ours = read_table(tmp_path / "lammps" / "contacts.txt")
    theirs = read_table(tmp_path / "liggghts" / "contacts.txt")
    for column in ("clog", "id1", "id2", "arch"):
        np.testing.assert_array_equal(ours[column], theirs[column], err_msg=column)
    for column in ("x", "z"):
        np.testing.assert_allclose(ours[column], theirs[column], rtol=0, atol=1e-12, err_msg=column)
    np.testing.assert_allclose(ours["fn"], theirs["fn"], rtol=1e-8)
    np.testing.assert_allclose(ours["ft"], theirs["ft"], rtol=1e-8)
    # the contacts did move: loaded tangential springs, normal forces far
    # from the static k_n delta of the construction
    static = {(a, b): fn for a, b, _, _, fn in expected_records()[2]}
    built = np.array([static[(int(a), int(b))] for a, b in zip(ours["id1"], ours["id2"])])
    assert len(ours["fn"]) >= 4 and ours["ft"].min() > 1e-3
    assert np.max(np.abs(ours["fn"] / built - 1.0)) > 0.1
    # the same outcome: the sagging arch has lost contacts (measured: the
    # walk meets a dead end at grain 10 in both hosts)
    clogs = [read_table(tmp_path / host / "clogs.txt") for host in ("lammps", "liggghts")]
    for column in ("step", "eta", "status"):
        np.testing.assert_array_equal(clogs[0][column], clogs[1][column], err_msg=column)


def test_in_2d_the_vertical_axis_is_y(tmp_path):
    """The same scene in `dimension 2`, the silo in the x-y plane: gravity
    and fix reinject's exit along y, so the fix takes y as the vertical
    (the records' z column) and z as the off-plane axis. The records are
    those computed from the construction, as in 3D."""
    deck = lammps_deck()
    swaps = [("units si\n", "units si\ndimension 2\n"), ("boundary f f f", "boundary f f p"),
             ("block -0.06 0.06 -0.01 0.01 -0.05 0.1", "block -0.06 0.06 -0.05 0.1 -0.01 0.01"),
             ("block -0.04 0.04 -0.01 0.01 0.06 0.09", "block -0.04 0.04 0.06 0.09 -0.01 0.01"),
             ("vector 0 0 -1", "vector 0 -1 0"), ("exit z -0.03", "exit y -0.03")]
    for old, new in swaps:
        assert old in deck, old
        deck = deck.replace(old, new)
    deck = re.sub(r"create_atoms 1 single (\S+) 0\.0 (\S+) units box",
                  r"create_atoms 1 single \1 \2 0.0 units box", deck)
    output = run_lammps(deck, tmp_path).output
    assert "steps run: 100" in output
    check_records(tmp_path)


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
@pytest.mark.parametrize("newton", ["newton off", "newton on"])
def test_two_ranks_write_the_records_of_one(clogged, tmp_path, newton):
    """The processor boundary x = 0 cuts the arch between members 2 and 3:
    the contacts across it are listed by both ranks (newton off) or by one
    (newton on), the grains by their owners; gathered, sorted and
    deduplicated, the records are those of one rank, to the byte."""
    one_dir, _ = clogged
    deck = lammps_deck(processors="processors 2 1 1").replace("newton off", newton)
    output = run_lammps(deck, tmp_path, nprocs=2).output
    assert "steps run: 100" in output
    check_records(tmp_path)
    for name in RECORDS:
        assert (tmp_path / name).read_text() == (one_dir / name).read_text(), name


def test_break_moves_the_arch_to_the_top_and_goes_on(tmp_path):
    """action break: the three members re-enter in the injection region
    through fix reinject; what is left over the outlet (the feet and the
    top grain) blocks nothing, so the next check, quiet_time later, finds
    no arch (status -1) and clears the outlet; with 2 arches wanted the
    flag never rises and the run goes to its end."""
    deck = lammps_deck(fix_line=FIX_LINE.replace("action stop", "action break arches 2"))
    output = run_lammps(deck, tmp_path).output
    clogs = read_table(tmp_path / "clogs.txt")
    assert list(clogs["status"][:2]) == [1, -1]
    assert clogs["time"][1] == pytest.approx(0.002, abs=1e-12)
    assert "no arch (no_start" in output
    assert "steps run: 1000" in output
    assert "the run stops" not in output
    assert list(clogs["avalanche"]) == [0] * len(clogs["avalanche"])
    rows = thermo_rows(output, THERMO_COLUMNS)
    assert rows[1000][2:4] == [1, 0]         # one arch, the flag down


def test_a_time_out_is_recorded_and_stops_the_run(tmp_path):
    """quiet_time 0.01 s cannot pass within max_time 0.002 s: the attempt
    times out at step 200 (status 0, no arch, no contacts written), and
    with action stop the run stops there."""
    fix_line = FIX_LINE.replace("quiet_time 0.001", "quiet_time 0.01 max_time 0.002")
    output = run_lammps(lammps_deck(fix_line=fix_line), tmp_path).output
    assert ("fix clog clog: clog 1 at t = 0.002 s (step 200), avalanche 0 grains, no arch "
            "(the flow did not stop within max_time)") in output
    assert "steps run: 200" in output
    clogs = read_table(tmp_path / "clogs.txt")
    assert list(clogs["status"]) == [0] and list(clogs["eta"]) == [0]
    for name in ("arches.txt", "feet.txt", "contacts.txt"):
        assert len(read_table(tmp_path / name)["clog"]) == 0, name


def test_a_run_split_by_a_restart_writes_the_records_of_the_whole_run(clogged, tmp_path):
    """Cut at step 50, before the clog: the restarted fix goes on with the
    attempt's start and the time of the whole run (LAMMPS' own time reads
    0 after read_restart), finds the clog at step 100 with t = 0.001 s
    and writes the records of the uninterrupted run."""
    whole_dir, whole_output = clogged
    run_lammps(lammps_deck(steps=50, tail="write_restart state.restart"), tmp_path)
    resumed = run_lammps(lammps_deck(steps=950, restart_file="state.restart"), tmp_path).output
    assert "clog 1 at t = 0.001 s (step 100)" in resumed
    assert "steps run: 100" in resumed
    for name in RECORDS:
        assert (tmp_path / name).read_text() == (whole_dir / name).read_text(), name
    whole = thermo_rows(whole_output, THERMO_COLUMNS)
    assert thermo_rows(resumed, THERMO_COLUMNS)[100] == whole[100]


# the LIGGGHTS fix's bad lines (the same parser, core/clog_logic.h) but its
# `contacts` keyword, which the LAMMPS fix does not take
BAD = [case for case in BAD_INPUT if "contacts" not in case[1]] + [
    ("action stop", "action stop contacts c1", "unknown keyword 'contacts'"),
]


def test_an_arch_broken_on_the_restart_step_re_enters_after_the_restart(tmp_path):
    """action break: the arch found at step 100 is to re-enter on step 101.
    A run cut by write_restart on step 100 itself carries that request in
    fix reinject's restart data; the restarted run moves the arch away
    and its next check finds no arch, as the uninterrupted run: the
    records of both are the same to the byte (with the request lost, the
    arch would be found again at step 200, status 1)."""
    fix_line = FIX_LINE.replace("action stop", "action break arches 5")
    run_lammps(lammps_deck(fix_line=fix_line, steps=300), tmp_path / "whole")
    run_lammps(lammps_deck(fix_line=fix_line, steps=100, tail="write_restart state.restart"),
               tmp_path / "pieces")
    run_lammps(lammps_deck(fix_line=fix_line, steps=200, restart_file="state.restart"),
               tmp_path / "pieces")
    assert list(read_table(tmp_path / "whole" / "clogs.txt")["status"]) == [1, -1, -1]
    for name in RECORDS:
        assert (tmp_path / "pieces" / name).read_text() == \
               (tmp_path / "whole" / name).read_text(), name


@pytest.mark.parametrize("old, new, message", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_input_is_an_error_naming_the_keyword(tmp_path, old, new, message):
    assert old in FIX_LINE
    deck = lammps_deck(fix_line=FIX_LINE.replace(old, new, 1), steps=10)
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck, tmp_path)
    assert "fix clog" in caught.value.message
    assert message in caught.value.message


@pytest.mark.parametrize("old, new, message", [
    ("fix gravity all gravity 9.81 vector 0 0 -1", "fix gravity all gravity 9.81 vector 0 0 1",
     "gravity must point down the vertical axis of fix reinject"),
    ("fix gravity all gravity 9.81 vector 0 0 -1\n", "", "needs fix gravity"),
    ("exit z -0.03", "exit x -0.05", "must be normal to y or z"),
    ("pair_style granular/jiang\npair_coeff * * normal hooke/stiffness",
     "pair_style gran/hooke/history 1e4 NULL 0 NULL 0.5 0\npair_coeff * *\n#",
     "needs pair_style granular/jiang"),
])
def test_bad_scene_is_a_clear_error(tmp_path, old, new, message):
    deck = lammps_deck(steps=10)
    assert old in deck
    with pytest.raises(LiggghtsError) as caught:
        run_lammps(deck.replace(old, new, 1), tmp_path)
    assert message in caught.value.message
