"""fix clog on hand-built scenes.

A frozen arch: grains placed by hand over an outlet between two base
grains, with one defect, and a grain resting on the arch. None of the
grains is integrated, so the scene is exactly at rest (Ec = 0) and the
contacts are exactly as built: every expected record (which grains, in
which order, the angles, the contact points, the forces k_n * delta of a
contact without motion or tangential history) is computed here from the
construction, independently of the fix.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from analysis.common.deck_blocks import granular_setup, hooke_materials
from analysis.common.lammps_io import read_dump, thermo_rows
from analysis.common.tables import read_table
from analysis.testing import LiggghtsError
from conftest import has_mpirun

ROOT = Path(__file__).resolve().parent.parent
D = 0.01
R = D / 2
KN = 1.0e4
DENSITY = 2500.0
G = 9.81
STEP = 0.99 * D            # centre distance along the arch: overlap 0.01 d
TOP_STEP = 0.98 * D        # the grain on the arch presses harder on one member


def arch_scene():
    """Base grains (left, right), the walk from left foot to right foot,
    and the extra grain on top; positions (x, z) in the plane y = 0.

    The arch: headings of the four steps between feet and members are
    a1 = 64.18, a2 = -20, a3 = 10, a4 = -47.11 degrees, chosen so that the
    chain closes from a foot resting at 60 degrees on the left outlet grain
    to its mirror on the right. The member angle is phi = 180 + (a_next -
    a_previous): 95.8 (regular), 210 (the defect), 122.9 (regular)."""
    base = [(-(2 + k) * D, -R) for k in range(4)] + [((2 + k) * D, -R) for k in range(4)]
    left_foot = np.array([-2 * D + STEP * math.cos(math.radians(60)),
                          -R + STEP * math.sin(math.radians(60))])
    a2, a3 = math.radians(-20.0), math.radians(10.0)
    # the first and last headings close the chain on the mirror foot
    span = 2 * abs(left_foot[0]) / STEP - math.cos(a2) - math.cos(a3)
    rise = -(math.sin(a2) + math.sin(a3))
    mean = math.atan2(rise, span)
    half = math.acos(span / (2 * math.cos(mean)))
    headings = [mean + half, a2, a3, mean - half]
    walk = [left_foot]
    for heading in headings:
        walk.append(walk[-1] + STEP * np.array([math.cos(heading), math.sin(heading)]))
    # the top grain: TOP_STEP from member 1, STEP from member 2, above them
    m1, m2 = walk[1], walk[2]
    gap = np.linalg.norm(m2 - m1)
    along = (TOP_STEP**2 - STEP**2 + gap**2) / (2 * gap)
    height = math.sqrt(TOP_STEP**2 - along**2)
    unit = (m2 - m1) / gap
    top = m1 + along * unit + height * np.array([-unit[1], unit[0]])
    return base, walk, top


def lower_side_phi(previous, at, following):
    """Counter-clockwise from the direction of `previous` to that of
    `following`, seen from `at`, in degrees in [0, 360)."""
    a = math.atan2(previous[1] - at[1], previous[0] - at[0])
    b = math.atan2(following[1] - at[1], following[0] - at[0])
    return math.degrees(b - a) % 360.0


def clog_deck(fix_options="action stop", processors="", atoms_order=None, quiet_time=0.001,
              more_atoms="", extra="", gravity_group="all", max_chunks=20, run_loop=True,
              restart_file=None, tail=""):
    """Atom ids: base 1-8, then the walk (feet and members) 9-13, top 14.
    atoms_order permutes the creation order (ids follow creation).
    more_atoms: lines after the groups are made (not with restart_file);
    extra: lines after the materials; restart_file: the box, the atoms and
    the groups come from it; tail: lines after the run loop (run_loop False:
    no run)."""
    base, walk, top = arch_scene()
    points = [(x, z, "base") for x, z in base] + [(x, z, "free") for x, z in walk] + \
             [(top[0], top[1], "free")]
    creates = "\n".join(f"create_atoms 1 single {x!r} 0.0 {z!r} units box" for x, z, _ in points)
    base_ids = " ".join(str(i + 1) for i in range(len(base)))
    free_ids = f"{len(base) + 1}:{len(points)}"
    if restart_file:
        system = f"atom_modify map array\nread_restart {restart_file}\nnewton off\ncommunicate single vel yes"
    else:
        system = f"""{granular_setup()}
{processors}
region box block -0.06 0.06 -0.01 0.01 -0.05 0.1 units box
create_box 1 box
{creates}
set group all diameter {D} density {DENSITY}
group base id {base_ids}
group grains id {free_ids}
{more_atoms}"""
    loop = f"include {ROOT}/inputs/run_until_done.in" if run_loop else ""
    return f"""
{system}
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(KN, KN * 2 / 7, gamman=0.0, gammat=0.0, mu=0.5)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep 1e-5
{extra}
fix gravity {gravity_group} gravity {G} vector 0 0 -1
region top block -0.04 0.04 -0.01 0.01 0.06 0.09 units box
fix reinject grains reinject exit z -0.03 region top seed 15485863 every 10
fix clog grains clog reinject reinject base base orifice 0.0 bottom 0.0 every 10 quiet_time {quiet_time} {fix_options}
variable done equal f_clog[3]
variable chunk_steps equal 50
variable max_chunks equal {max_chunks}
thermo_style custom step atoms f_clog[1] f_clog[2] f_clog[3] f_clog[4] f_clog[5]
thermo_modify format float %.15g
thermo 50
{loop}
variable steps_run equal step
print "steps run: ${{steps_run}}"
{tail}
"""


def expected_records():
    base, walk, top = arch_scene()
    positions = {i + 1: p for i, p in enumerate(base)}
    positions.update({len(base) + 1 + k: p for k, p in enumerate(walk)})
    top_id = len(base) + len(walk) + 1
    positions[top_id] = top
    feet = (len(base) + 1, len(base) + len(walk))
    members = list(range(feet[0] + 1, feet[1]))
    contacts = []
    ids = sorted(positions)
    for a in ids:
        for b in ids:
            if a >= b or (a <= len(base) and b <= len(base)):
                continue
            distance = np.linalg.norm(np.array(positions[a]) - np.array(positions[b]))
            if distance < D:
                delta = D - distance
                unit = (np.array(positions[b]) - np.array(positions[a])) / distance
                point = np.array(positions[a]) + unit * (R - delta / 2)
                contacts.append((a, b, point[0], point[1], KN * delta))
    return positions, members, contacts


def test_scene_is_what_the_docstring_says():
    """The construction itself: overlaps 0.01 d along the walk, 0.02 d from
    the top grain to member 1, no other contact, members off the base."""
    positions, members, contacts = expected_records()
    pairs = {(a, b): fn for a, b, _, _, fn in contacts}
    assert set(pairs) == {(1, 9), (9, 10), (10, 11), (11, 12), (12, 13),
                          (5, 13), (10, 14), (11, 14)}
    assert pairs[(10, 14)] == pytest.approx(KN * 0.02 * D, rel=1e-9)
    assert pairs[(9, 10)] == pytest.approx(KN * 0.01 * D, rel=1e-9)
    phis = [lower_side_phi(positions[m - 1], positions[m], positions[m + 1]) for m in members]
    assert phis == pytest.approx([95.8, 210.0, 122.9], abs=0.1)


def check_records(workdir, time=0.001, avalanche=0):
    """time: when the clog is detected (default: at the first check with
    quiet_time 0.001 s behind it); avalanche: grains that left before."""
    positions, members, contacts = expected_records()
    clogs = read_table(workdir / "clogs.txt")
    assert list(clogs["clog"]) == [1]
    assert list(clogs["status"]) == [1]
    assert list(clogs["eta"]) == [3]
    assert list(clogs["avalanche"]) == [avalanche]
    assert clogs["time"][0] == pytest.approx(time, abs=1e-12)

    arches = read_table(workdir / "arches.txt")
    assert list(arches["id"]) == members
    assert list(arches["order"]) == [1, 2, 3]
    expected_phi = [lower_side_phi(positions[m - 1], positions[m], positions[m + 1]) for m in members]
    np.testing.assert_allclose(arches["phi"], expected_phi, rtol=0, atol=1e-9)
    np.testing.assert_allclose(arches["x"], [positions[m][0] for m in members], rtol=0, atol=1e-13)
    # z above the bottom surface, the top of the base grains (centres at -r)
    np.testing.assert_allclose(arches["z"], [positions[m][1] for m in members], rtol=0, atol=1e-13)
    for row, member in enumerate(members):
        own = [fn for a, b, _, _, fn in contacts if member in (a, b)]
        assert arches["fn"][row] == pytest.approx(np.mean(own), rel=1e-6)
        # no tangential spring: only the rounding of "total minus normal part"
        assert arches["ft"][row] < 1e-12

    # the feet (arch_walk.h rule 8): the walk's first and last grains, each
    # with its one base grain (left 1, right 5) as the missing neighbour
    feet = read_table(workdir / "feet.txt")
    left_foot, right_foot = members[0] - 1, members[-1] + 1
    assert list(feet["id"]) == [left_foot, right_foot]
    assert list(feet["order"]) == [0, len(members) + 1]
    assert list(feet["base"]) == [1, 5]
    assert list(feet["floor"]) == [0, 0]     # each foot rests on its outlet grain alone
    expected_foot_phi = [lower_side_phi(positions[1], positions[left_foot], positions[members[0]]),
                         lower_side_phi(positions[members[-1]], positions[right_foot], positions[5])]
    np.testing.assert_allclose(feet["phi"], expected_foot_phi, rtol=0, atol=1e-9)
    np.testing.assert_allclose(feet["x"], [positions[f][0] for f in (left_foot, right_foot)],
                               rtol=0, atol=1e-13)
    np.testing.assert_allclose(feet["z"], [positions[f][1] for f in (left_foot, right_foot)],
                               rtol=0, atol=1e-13)
    for row, foot in enumerate((left_foot, right_foot)):
        own = [fn for a, b, _, _, fn in contacts if foot in (a, b)]
        assert feet["fn"][row] == pytest.approx(np.mean(own), rel=1e-6)

    table = read_table(workdir / "contacts.txt")
    assert [(int(a), int(b)) for a, b in zip(table["id1"], table["id2"])] == \
           [(a, b) for a, b, *_ in contacts]
    np.testing.assert_allclose(table["x"], [c[2] for c in contacts], rtol=0, atol=1e-12)
    np.testing.assert_allclose(table["z"], [c[3] for c in contacts], rtol=0, atol=1e-12)
    np.testing.assert_allclose(table["fn"], [c[4] for c in contacts], rtol=1e-6)
    assert np.all(table["ft"] < 1e-12)
    in_arch = [int(a in members and b in members) for a, b, *_ in contacts]
    np.testing.assert_array_equal(table["arch"], in_arch)
    return clogs, arches, table


@pytest.mark.engine
def test_frozen_arch_with_a_defect_is_found_exactly(run, tmp_path):
    output = run(clog_deck())
    check_records(tmp_path)
    assert "fix clog clog: clog 1 at t = 0.001 s (step 100), avalanche 0 grains, arch of 3 grains" in output
    # the deck's loop stopped at the chunk in which the flag was raised
    assert "steps run: 100" in output


@pytest.mark.engine
@pytest.mark.skipif(not has_mpirun(), reason="needs mpirun")
def test_frozen_arch_same_records_on_two_ranks(run, tmp_path):
    """The processor boundary x = 0 cuts the arch between members 2 and 3."""
    run(clog_deck(processors="processors 2 1 1"), nprocs=2)
    for name in ("clogs.txt", "arches.txt", "feet.txt", "contacts.txt"):
        assert (tmp_path / name).exists()
    check_records(tmp_path)


def read_final_positions(path):
    """id -> (x, y, z) from the one-frame dump written at the end."""
    _, frame = read_dump(path)[-1]
    return {int(i): (x, y, z) for i, x, y, z in zip(frame["id"], frame["x"], frame["y"], frame["z"])}


@pytest.mark.engine
def test_break_moves_the_arch_to_the_top_and_goes_on(run, tmp_path):
    """action break: the three members re-enter in the injection region
    without overlap; what is left over the outlet (the feet and the top
    grain) blocks nothing, so the next check finds no arch (status -1) and
    clears the outlet zone; the flag is never raised (2 arches wanted), so
    the loop ends after max_chunks chunks."""
    deck = clog_deck(fix_options="action break arches 2").replace(
        'print "steps run', 'dump final all custom 1 final.dump id x y z\nrun 0\nprint "steps run')
    output = run(deck)
    clogs = read_table(tmp_path / "clogs.txt")
    assert list(clogs["status"][:2]) == [1, -1]
    assert clogs["time"][1] == pytest.approx(0.002, abs=1e-12)  # quiet_time after the break
    assert "no arch (no_start" in output
    assert "steps run: 1000" in output

    final = read_final_positions(tmp_path / "final.dump")
    _, members, _ = expected_records()
    moved = members + [9, 13, 14]     # the members at clog 1, the rest at clog 2
    for tag in moved:
        x, y, z = final[tag]
        assert -0.04 + R <= x <= 0.04 - R and 0.06 + R <= z <= 0.09 - R
    for a in moved:
        for b in final:
            if a != b:
                assert np.linalg.norm(np.subtract(final[a], final[b])) >= D
    # nothing was counted as out: the arch grains did not leave through the exit
    assert list(clogs["avalanche"]) == [0] * len(clogs["avalanche"])


# ---------------------------------------------- restart: the clock goes on
# LIGGGHTS 3.8 restarts its time at 0 after read_restart; fix clog keeps the
# time of the whole run in its restart data. The frozen arch plus one grain
# that leaves: a flowing silo would not do, since a restarted flow drifts
# from the uninterrupted one (rounding differences grow: tried on a 35-grain
# silo, the same arch came out with forces 0.5 % apart, or 100 steps later).

DT = 1e-5
CHECK_EVERY = 10                 # fix reinject and fix clog
FALLER = 15                      # the grain that leaves
FALLER_START = -0.01202          # under the outlet, below the base: touches nothing
FALLER_SPEED = 4.0               # m/s, down
EXIT = -0.03
QUIET = 0.00105                  # not a multiple of the checks' 1e-4 s: no rounding tie


def faller_deck(**options):
    """The frozen arch of clog_deck and grain 15, which flies down at a
    constant speed under the outlet, leaves and re-enters at rest at the
    top, where it stays: gravity acts only on the base, which is not
    integrated (fix clog reads g from it for Ep). Before it leaves, its
    kinetic energy keeps Ec/Ep far above the ratio; after, Ec = 0."""
    faller = (f"create_atoms 1 single 0.0 0.0 {FALLER_START!r} units box\n"
              f"set atom {FALLER} diameter {D} density {DENSITY}\n"
              f"group faller id {FALLER}\n"
              f"group grains id {FALLER}\n"
              f"velocity faller set 0.0 0.0 {-FALLER_SPEED!r} units box")
    return clog_deck(quiet_time=QUIET, more_atoms=faller, gravity_group="base",
                     extra="fix integrate faller nve/sphere", **options)


def expected_clog_step():
    """The step of the clog, from the faller's flight: it crosses the exit
    plane in step `crossed` (z = z0 - n v dt), fix reinject sees it at its
    next check and re-enters it in the step after, fix clog sees the count
    change at its next check, and the clog is the first check QUIET later."""
    crossed = next(n for n in range(1, 10000) if FALLER_START - n * FALLER_SPEED * DT < EXIT)
    seen = -(-crossed // CHECK_EVERY) * CHECK_EVERY
    noticed = seen + CHECK_EVERY
    return next(step for step in range(noticed, 10000, CHECK_EVERY)
                if (step - noticed) * DT >= QUIET * (1 - 1e-9)), noticed


@pytest.mark.engine
@pytest.mark.parametrize("pieces", [
    (6, 14),                     # restart at step 300: before the grain leaves (step 450)
    (10, 10),                    # at 500: after fix clog saw it leave (460), before the clog (570)
    (3, 7, 10),                  # at 150 and 500
    (6, None, 14),               # at 300, and the file written again before any run
], ids=["before-the-exit", "after-the-exit", "twice", "rewritten-before-a-run"])
def test_a_restarted_run_finds_the_same_clog_at_the_same_time(run, tmp_path, pieces):
    """A run cut by write_restart/read_restart (pieces: chunks of 50 steps
    per piece, None: read and written again without a run) writes the same
    records as the uninterrupted run, whose clog is at the step predicted
    from the faller's flight, with the time of that step; output 5 (time
    since the flow last moved) is the same at every thermo step. (With
    LIGGGHTS' own time, which restarts at 0, the restarted clog came late,
    or at the same step with the time since the restart.)"""
    clog_step, noticed = expected_clog_step()
    assert (clog_step, noticed) == (570, 460)    # what the pieces are cut around
    whole = run(faller_deck(), subdir="whole")
    check_records(tmp_path / "whole", time=clog_step * DT, avalanche=1)
    clogs = read_table(tmp_path / "whole" / "clogs.txt")
    assert clogs["step"][0] == clog_step
    assert f"clog 1 at t = {clog_step * DT:g} s (step {clog_step})" in whole
    assert f"steps run: {-(-clog_step // 50) * 50}" in whole

    # every piece in one directory: the records are appended to after a restart
    outputs = []
    for k, chunks in enumerate(pieces):
        restart_file = f"state{k - 1}.restart" if k else None
        tail = f"write_restart state{k}.restart" if k < len(pieces) - 1 else ""
        if chunks is None:
            deck = faller_deck(restart_file=restart_file, run_loop=False, tail=tail)
        else:
            deck = faller_deck(restart_file=restart_file, max_chunks=chunks, tail=tail)
        outputs.append(run(deck, subdir="pieces"))
        if restart_file:
            assert "Resetting global state of Fix clog Style clog" in outputs[-1]
    assert f"clog 1 at t = {clog_step * DT:g} s (step {clog_step})" in outputs[-1]
    for name in ("clogs.txt", "arches.txt", "feet.txt", "contacts.txt"):
        assert (tmp_path / "pieces" / name).read_text() == (tmp_path / "whole" / name).read_text(), name

    since_moved = {step: values[-1] for step, values in thermo_rows(whole, 7).items()}
    pieced = {}
    for output in outputs:
        pieced.update({step: values[-1] for step, values in thermo_rows(output, 7).items()})
    assert sorted(pieced) == sorted(since_moved)
    for step, value in since_moved.items():
        assert pieced[step] == pytest.approx(value, rel=1e-12, abs=1e-15), step
    # before the faller left, since the start; after, since it left
    assert since_moved[400] == pytest.approx(400 * DT)
    assert since_moved[550] == pytest.approx((550 - noticed) * DT)


@pytest.mark.engine
def test_an_arch_broken_on_the_restart_step_re_enters_after_the_restart(run, tmp_path):
    """With `action break`, the arch found at step 570 is broken by asking
    fix reinject to move its grains to the top on step 571. A run cut by
    write_restart on step 570 itself carries that request in fix reinject's
    restart data: the restarted run moves the same grains to the same spots
    on step 571, and the records (the clog, then the next attempt over the
    emptied outlet) are those of the uninterrupted run. (Before, the
    request was lost at the restart and the arch stayed in place.)"""
    clog_step, _ = expected_clog_step()
    assert clog_step == 570
    options = "action break arches 2"
    walk_ids = range(9, 15)
    where = "\n".join(f"variable x{i} equal x[{i}]\nvariable z{i} equal z[{i}]\n"
                      f"print \"grain {i} at ${{x{i}}} ${{z{i}}}\"" for i in walk_ids)
    whole = run(faller_deck(fix_options=options, run_loop=False, tail=f"run 700\n{where}"), subdir="whole")
    run(faller_deck(fix_options=options, run_loop=False, tail="run 570\nwrite_restart state.restart"),
        subdir="pieces")
    pieced = run(faller_deck(fix_options=options, restart_file="state.restart", run_loop=False,
                             tail=f"run 130\n{where}"), subdir="pieces")

    def positions(output):
        return {int(w[1]): (float(w[3]), float(w[4])) for w in
                (line.split() for line in output.splitlines()) if len(w) == 5 and w[0] == "grain"}
    moved = positions(whole)
    assert positions(pieced) == moved
    _, members, _ = expected_records()
    # the arch's grains were moved up into the injection region (z > 0.06)
    assert members and all(moved[m][1] > 0.06 for m in members)
    for name in ("clogs.txt", "arches.txt", "feet.txt", "contacts.txt"):
        assert (tmp_path / "pieces" / name).read_text() == (tmp_path / "whole" / name).read_text(), name
    assert read_table(tmp_path / "whole" / "clogs.txt")["clog"].tolist() == [1, 2]


@pytest.mark.engine
def test_a_run_resumed_from_an_older_restart_records_each_clog_once(run, tmp_path):
    """The first piece writes its restart file at step 500 (before the clog
    at 570), runs on through the clog and stops, as a run cut by a time
    limit; resumed from that file in the same directory, the run finds the
    clog again. The records the first piece wrote after its restart file
    are removed when the resumed fix opens them (with a message), so the
    records are those of the uninterrupted run, each clog once."""
    whole = tmp_path / "whole"
    run(faller_deck(), subdir="whole")
    first = run(faller_deck(max_chunks=10, tail="write_restart state0.restart\nrun 200"), subdir="pieces")
    assert "clog 1 at t = 0.0057 s (step 570)" in first
    assert read_table(tmp_path / "pieces" / "clogs.txt")["clog"].tolist() == [1]
    resumed = run(faller_deck(restart_file="state0.restart", max_chunks=10), subdir="pieces")
    assert "clog 1 at t = 0.0057 s (step 570)" in resumed
    for name in ("clogs.txt", "arches.txt", "feet.txt", "contacts.txt"):
        rows = len((whole / name).read_text().splitlines()) - 1
        assert f"fix clog: removed {rows} line(s) of clogs after clog 0 from '{name}'" in resumed, name
        assert (tmp_path / "pieces" / name).read_text() == (whole / name).read_text(), name


FIX_LINE = ("fix clog grains clog reinject reinject base base orifice 0.0 bottom 0.0 "
            "every 10 quiet_time 0.001 action stop")


# (what FIX_LINE has, what replaces it, words of the ERROR); the LAMMPS fix
# takes the same lines but the `contacts` one (tests/test_lammps_clog.py)
BAD_INPUT = [
    ("action stop", "action stop bogus 1", "unknown keyword 'bogus'"),
    ("action stop", "action stop every", "keyword 'every' needs a value"),
    ("reinject reinject ", "", "'reinject <fix-ID>' is required"),
    ("base base ", "", "'base <group-ID>' is required"),
    ("orifice 0.0 ", "", "'orifice <x of the outlet centre>' is required"),
    ("bottom 0.0 ", "", "'bottom <height of the silo bottom>' is required"),
    ("base base", "base nowhere", "base group 'nowhere' does not exist"),
    ("orifice 0.0", "orifice left", "'orifice' expects a number, got 'left'"),
    ("every 10", "every 0", "'every' must be an integer >= 1"),
    ("every 10", "every 2.5", "'every' expects an integer, got '2.5'"),
    ("quiet_time 0.001", "quiet_time 0", "'quiet_time' must be > 0"),
    ("action stop", "action stop ratio -1", "'ratio' must be > 0"),
    ("action stop", "action stop max_time -2", "'max_time' must be >= 0"),
    ("action stop", "action halt", "'action' must be 'stop' or 'break'"),
    ("action stop", "action stop arches 5", "'arches' needs 'action break'"),
    ("action stop", "action break arches 0", "'arches' must be an integer >= 1"),
    ("action stop", "action break arches 1.5", "'arches' expects an integer, got '1.5'"),
    ("reinject reinject", "reinject gravity", "'reinject' names no fix reinject: 'gravity'"),
    ("action stop", "action stop directory /nonexistent/dir",
     "cannot write clogs.txt, arches.txt, feet.txt, contacts.txt in directory '/nonexistent/dir'"),
    ("action stop", "action stop contacts nothing", "'contacts' names no compute pair/gran/local"),
]


@pytest.mark.engine
@pytest.mark.parametrize("old, new, message", BAD_INPUT)
def test_bad_input_is_a_clear_error(run, old, new, message):
    assert old in FIX_LINE
    deck = clog_deck().replace(FIX_LINE, FIX_LINE.replace(old, new, 1))
    with pytest.raises(LiggghtsError) as error:
        run(deck)
    assert message in error.value.message


@pytest.mark.engine
@pytest.mark.parametrize("change, message", [
    (("fix gravity all gravity 9.81 vector 0 0 -1", "fix gravity all gravity 9.81 vector 0 0 1"),
     "gravity must point down the vertical axis of fix reinject"),
    (("fix gravity all gravity 9.81 vector 0 0 -1\n", ""), "needs fix gravity"),
    (("exit z -0.03", "exit x -0.05"), "must be normal to y or z"),
    (("variable done equal", "run 10\nvariable done equal"), None),
])
def test_bad_scene_is_a_clear_error(run, change, message):
    deck = clog_deck()
    assert change[0] in deck
    deck = deck.replace(change[0], change[1], 1)
    if message is None:
        # fix clog defined after a first run: its compute cannot be created
        deck = deck.replace(FIX_LINE + "\n", "").replace("run 10\n", "run 10\n" + FIX_LINE + "\n")
        message = "must be defined before the first run"
    with pytest.raises(LiggghtsError) as error:
        run(deck)
    assert message in error.value.message
