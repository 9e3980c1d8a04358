"""The rotating-bottom silo deck (inputs/silo3d_rotating/in.silo3d_rotating)
in its quick variant (-var quick 1: Dc = 12 d, 900 spheres, orifice 5 d,
dt = t_c/40, 0.4 s of settling and 0.6 s of discharge).

- It discharges: grains leave through the orifice, and the records agree
  with each other (mass_out = n_out m for equal spheres, counts never
  decrease, one row every 0.01 s from t_open) and with the deck's
  parameters (run.txt).
- Two MPI ranks give the same flow rate as one, within the statistical
  uncertainty: the initial gas comes from LIGGGHTS' insert/pack, which draws
  per sub-domain, so the two runs are different realisations of the same
  silo, not the same trajectory (that is tested on a small bed in
  test_wall_gran_rotating.py).
- The hardest case of the scene, the fastest rotation of the paper
  (1.28 Hz) with reinjection, keeps every grain, stays finite and
  discharges.
"""

import math
import re

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_table
from analysis.silo3d_rotating.flow import stationary_flow_rate
from analysis.silo3d_rotating.records import read_run_info
from analysis.testing import LiggghtsError
from conftest import ROOT, has_mpirun

DECK = ROOT / "inputs" / "silo3d_rotating" / "in.silo3d_rotating"
MASS = 620.0 * math.pi / 6.0 * 0.0099 ** 3
SKIP_AFTER_OPEN = 0.1          # s: the start-up of the flow is left out of Q


def deck(**variables):
    lines = [f"variable {name} index {value}" for name, value in variables.items()]
    lines += [f"variable inputs index {ROOT / 'inputs'}", f"include {DECK}"]
    return "\n".join(lines) + "\n"


def quick_deck(**variables):
    return deck(**variables, quick=1)


def discharge_rows(output):
    """The discharge's thermo rows (step time atoms ke n_out mass_out Q),
    split into their printed fields."""
    return [line.split() for line in output.splitlines()
            if len(line.split()) == 7 and line.split()[0].isdigit()]


def discharge_atoms(output):
    """The atom counts of the discharge's thermo rows, as printed."""
    return [row[2] for row in discharge_rows(output)]


def ranks(output):
    """The number of MPI ranks LIGGGHTS ran on: the product of its
    processor grid (`1 by 2 by 1 MPI processor grid`)."""
    grid = re.search(r"(\d+) by (\d+) by (\d+) MPI processor grid", output)
    return math.prod(int(n) for n in grid.groups())


def out_times(record):
    """The times of the records in which n_out has grown since the record
    before: when grains first show as out (to the records' 0.01 s)."""
    return record["t"][np.flatnonzero(np.diff(record["n_out"]) > 0) + 1]


def done_line(output):
    """The deck's last line, `silo3d_rotating: done at t = T s: N grains
    (M kg) out since t_open`, as (T, N). Numbers only: the echoed print
    command carries ${t} and ${n_end} in their place."""
    final = re.search(r"done at t = ([-+.0-9eE]+) s: (\d+) grains", output)
    return float(final.group(1)), int(final.group(2))


def solid_rod_mass(length, aspect):
    """A spherocylinder of density 620 kg/m^3, L end to end, d = L/aspect:
    a cylinder of L - d and a sphere of d, written out here."""
    d = length / aspect
    return 620.0 * (math.pi * d ** 3 / 6 + math.pi * d ** 2 / 4 * (length - d))


def flow_rate(record, t_open):
    """The analysis' stationary flow rate (analysis.silo3d_rotating.flow) after
    the start-up, with its standard error from block averages."""
    flow = stationary_flow_rate(record["t"], record["n_out"], record["mass_out"],
                                t_open + SKIP_AFTER_OPEN, record["t"][-1])
    return flow.q_mass, flow.q_mass_se


@pytest.fixture(scope="module")
def serial_run(tmp_path_factory, liggghts_binary):
    from conftest import run_liggghts
    workdir = tmp_path_factory.mktemp("silo3d_serial")
    output = run_liggghts(quick_deck(), workdir)
    return workdir, output


def test_quick_deck_discharges_with_consistent_records(serial_run):
    workdir, output = serial_run
    params = read_run_info(workdir, required=())
    assert params["N"] == 900 and params["D"] == 0.05 and params["f"] == 0.0
    assert params["mass"] == pytest.approx(MASS, rel=1e-12)
    assert params["reinject"] == 0
    record = read_table(workdir / "discharge.txt")
    t_open = params["t_open"]
    # one row every 0.01 s from the opening to the end (0.6 s)
    assert record["t"][0] == pytest.approx(t_open, abs=0.011)
    assert np.allclose(np.diff(record["t"]), np.diff(record["t"])[0], rtol=1e-6)
    assert np.diff(record["t"])[0] == pytest.approx(0.01, rel=0.01)
    assert record["t"][-1] == pytest.approx(t_open + 0.6, abs=0.011)
    assert np.all(np.diff(record["n_out"]) >= 0)
    np.testing.assert_allclose(record["mass_out"], record["n_out"] * MASS, rtol=1e-9, atol=1e-12)
    # the silo flowed through its 5 d orifice: a clogged one would stop
    # within 0.1 s; the atom count the deck reports fell by as many grains
    assert record["n_out"][-1] > 100
    assert done_line(output)[1] == record["n_out"][-1]
    q, sigma = flow_rate(record, t_open)
    print(f"serial: Q = {q:.4f} +- {sigma:.4f} kg/s")
    assert q > 0


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_give_the_same_flow_rate(serial_run, tmp_path, run):
    workdir, _ = serial_run
    output = run(quick_deck(), nprocs=2)
    assert ranks(output) == 2
    serial = read_table(workdir / "discharge.txt")
    parallel = read_table(tmp_path / "discharge.txt")
    t_open = read_run_info(tmp_path, required=())["t_open"]
    q1, s1 = flow_rate(serial, t_open)
    q2, s2 = flow_rate(parallel, t_open)
    print(f"np 1: Q = {q1:.4f} +- {s1:.4f}, np 2: Q = {q2:.4f} +- {s2:.4f} kg/s")
    assert abs(q1 - q2) < 3.0 * math.hypot(s1, s2)


def test_fastest_rotation_with_reinjection_keeps_every_grain(run, tmp_path):
    output = run(quick_deck(f=1.28, reinject=1))
    def numbers(line):
        try:
            return [float(word) for word in line.split()]
        except ValueError:
            return []
    # thermo rows: step time atoms ke [n_out mass_out Q], all numbers
    atoms = [int(row[2]) for row in map(numbers, output.splitlines()) if len(row) in (4, 7)]
    # the gas is inserted at step 1 (insert/pack): 0 atoms at step 0, then 900 throughout
    assert atoms[0] == 0 and len(atoms) > 20 and set(atoms[1:]) == {900}
    assert "nan" not in output.lower()
    record = read_table(tmp_path / "discharge.txt")
    assert record["n_out"][-1] > 100
    reentries = read_table(tmp_path / "reinject.txt")
    assert reentries["n_out"][-1] == record["n_out"][-1]


def test_a_saved_packing_opens_at_once_when_read(run, tmp_path):
    """write_packing saves the settled silo; read_packing starts from it and
    opens the orifice at the first step: t_open = 0 in LIGGGHTS' time, which
    restarts at 0 after read_restart (doc/liggghts_quirks.md), and `open 0`
    for the bottom, whose schedule goes on from the settling time stored
    in the packing. Grains leave within 0.3 s."""
    run(quick_deck(write_packing=1, discharge_time=0.05), subdir="settle")
    output = run(quick_deck(read_packing=1, packing="../settle/packing.restart", discharge_time=0.3),
                 subdir="read")
    assert "Resetting global state of Fix bottom Style wall/gran/rotating" in output
    params = read_run_info(tmp_path / "read", required=())
    record = read_table(tmp_path / "read" / "discharge.txt")
    assert params["t_open"] == 0.0
    assert record["t"][0] == pytest.approx(0.01, abs=1e-3)
    assert record["t"][-1] == pytest.approx(0.3, abs=0.011)
    assert record["n_out"][-1] > 20
    # the deck's last act marks the run finished (the analysis leaves out others)
    assert params["discharge_time"] == 0.3
    assert params["finished"] == pytest.approx(record["t"][-1], abs=0.011)

    # a packing of another silo is refused, not run: another N (the full
    # silo's 10 000 where the quick one settled 900), a narrower side wall
    # (the quick silo's grains reach r = 5.4 cm; R_c = 4 cm)
    for variables, message in (({"N": 10000}, "holds 900 grains, not N = 10000 (a packing of another silo?)"),
                               ({"Dc": 0.08}, "atoms beyond the side wall R_c = 0.04 m (a packing of a wider silo?)")):
        with pytest.raises(LiggghtsError) as caught:
            run(quick_deck(read_packing=1, packing="../settle/packing.restart", discharge_time=0.3, **variables),
                subdir="other")
        assert message in caught.value.output
        assert not (tmp_path / "other" / "discharge.txt").exists()


def test_a_clog_at_rest_stops_the_run_and_a_turning_bottom_runs_on(run, tmp_path):
    """At f = 0 with reinjection, an orifice of 2 d clogs within a few
    grains and nothing can open it: the deck stops once no grain has left
    for clog_window = 0.5 s (no sooner than 0.6 s after the opening, when
    fix reinject's rate has a whole window), writes `clogged t` before
    `finished t`, and its records are those of the same run with
    clog_stop 0 up to the stop, which then runs to its end without one
    more grain out. With the bottom turning the deck never stops for a
    pause: that run goes to its end. Two MPI ranks follow the same rule
    (the stop reads fix reinject's count, summed over the ranks): their
    trajectory is another one (forces summed in another order), so the
    two-rank run may clog later or not at all; either way it stops if and
    only if a pause of 0.5 s came."""
    run(quick_deck(write_packing=1, discharge_time=0.01), subdir="settle")
    # (the runs that go on stop at 0.8 s, past the earliest clog stop, 0.65 s)
    common = dict(read_packing=1, packing="../settle/packing.restart", D=0.02, reinject=1)
    output = run(quick_deck(discharge_time=1.2, **common), subdir="rest")
    run(quick_deck(clog_stop=0, discharge_time=0.8, **common), subdir="on")
    run(quick_deck(f=0.32, discharge_time=0.8, **common), subdir="turning")

    def assert_stopped_at_the_clog(subdir, output, discharge_time):
        params = read_run_info(tmp_path / subdir, required=())
        record = read_table(tmp_path / subdir / "discharge.txt")
        assert "clogged: no grain out for 0.5 s at f = 0" in output
        t_stop = params["finished"]
        assert params["clogged"] == t_stop == pytest.approx(record["t"][-1], abs=0.011)
        outs = out_times(record)
        t_last_out = outs[-1] if outs.size else 0.0
        # stopped at the first chunk end (0.05 s) past 0.5 s without a grain,
        # and not within the first 0.6 s
        assert t_stop - t_last_out >= 0.5 - 0.011
        assert t_stop <= max(t_last_out + 0.5, 0.6) + 0.05 + 0.011
        assert t_stop < discharge_time - 0.1
        return record

    record = assert_stopped_at_the_clog("rest", output, 1.2)
    if has_mpirun():
        output = run(quick_deck(discharge_time=1.5, **common), nprocs=2, subdir="rest_two_ranks")
        assert ranks(output) == 2
        if "clogged" in read_run_info(tmp_path / "rest_two_ranks", required=()):
            assert_stopped_at_the_clog("rest_two_ranks", output, 1.5)
        else:
            # no stop: no pause long enough to contain a whole empty window
            # at a chunk end (0.5 + 0.05 s), and the run reached its end
            flowing = read_table(tmp_path / "rest_two_ranks" / "discharge.txt")
            assert flowing["t"][-1] == pytest.approx(1.5, abs=0.011)
            pauses = np.diff(np.concatenate(([0.0], out_times(flowing), [flowing["t"][-1]])))
            assert pauses.max() < 0.5 + 0.05 + 0.011

    on = read_table(tmp_path / "on" / "discharge.txt")
    assert "clogged" not in read_run_info(tmp_path / "on", required=())
    assert on["t"][-1] == pytest.approx(0.8, abs=0.011)
    prefix = len(record["t"])
    np.testing.assert_array_equal(on["t"][:prefix], record["t"])
    np.testing.assert_array_equal(on["n_out"][:prefix], record["n_out"])
    assert on["n_out"][-1] == record["n_out"][-1]

    turning = read_table(tmp_path / "turning" / "discharge.txt")
    assert "clogged" not in read_run_info(tmp_path / "turning", required=())
    assert turning["t"][-1] == pytest.approx(0.8, abs=0.011)


@pytest.mark.parametrize("switch, value", [("clog_stop", 2), ("reinject", -1), ("resume", 0.5)])
def test_a_switch_other_than_0_or_1_is_refused_with_its_name(run, switch, value):
    """The deck reads some switches as `== 1` and others as a truth value,
    where a 2 would be off in the first and on in the second: any value
    but 0 or 1 is refused, with the switch's name, before anything is
    built."""
    with pytest.raises(LiggghtsError) as caught:
        run(quick_deck(**{switch: value}))
    assert f"in.silo3d_rotating: ERROR: {switch} is 0 or 1, not {value}" in caught.value.output
    assert "Created" not in caught.value.output    # stopped before the box


def test_a_seed_equal_to_the_grain_template_s_is_refused_with_its_message(run):
    """The deck's seed must differ from the seeds of its particle template
    and distribution (86028121, 86028157): LIGGGHTS' insert/pack refuses
    equal seeds through Error::one, which prints without a flush before
    MPI_Abort; run under `stdbuf -oL` (conftest, the example scripts) the
    message still reaches whoever ran the deck (doc/liggghts_quirks.md)."""
    with pytest.raises(LiggghtsError) as caught:
        run(quick_deck(seed=86028121, write_packing=1, discharge_time=0))
    assert "Fix insert/pack" in caught.value.message and "random seeds" in caught.value.message


def test_the_quick_deck_discharges_rods_through_the_turning_bottom(run, tmp_path):
    """-var shape rod -var aspect 3.3: 300 spherocylinders (L = 20 mm,
    d = L/3.3) from a lattice column settle in the closed silo and
    discharge through the turning bottom (0.32 Hz): the styles of
    doc/spherocylinder.md working together. The records are those of the
    spheres' runs: mass_out is n_out times the solid rod's mass
    (solid_rod_mass), and no rod is lost."""
    length, aspect = 0.020, 3.3
    rod_mass = solid_rod_mass(length, aspect)
    output = run(quick_deck(shape="rod", aspect=aspect, f=0.32, reinject=1, discharge_time=0.3))
    params = read_run_info(tmp_path, required=())
    assert params["shape"] == "rod" and params["N"] == 300
    assert params["aspect"] == aspect and params["L"] == length
    assert params["mass"] == pytest.approx(rod_mass, rel=1e-12)
    record = read_table(tmp_path / "discharge.txt")
    assert np.all(np.diff(record["n_out"]) >= 0)
    np.testing.assert_allclose(record["mass_out"], record["n_out"] * rod_mass, rtol=1e-9, atol=1e-12)
    assert record["n_out"][-1] > 20
    assert params["finished"] == pytest.approx(record["t"][-1], abs=0.011)
    # with reinjection every rod stays in the box
    atoms = discharge_atoms(output)
    assert len(atoms) > 10 and set(atoms) == {"300"}
    assert "nan" not in output.lower()


def test_full_size_rods_of_aspect_4_are_22500_as_in_the_paper(run, tmp_path):
    """The paper (sec. II): N = 10000, "only in the case of L/d = 4.0 N is
    set to 22 500 to reach a bit higher initial packing". The full-size
    deck (not quick) with -var aspect 4.0 makes 22500 rods of d = 5 mm,
    all of them on its lattice column (it stops with an ERROR if the
    column holds fewer). Settling and discharge cut to a few steps."""
    output = run(deck(shape="rod", aspect=4.0, dt_fraction=40, settle_time=0.0001,
                      discharge_time=0.0001))
    params = read_run_info(tmp_path, required=())
    assert params["N"] == 22500 and params["aspect"] == 4.0
    assert params["Dc"] == 0.19 and params["D"] == 0.06
    assert set(discharge_atoms(output)) == {"22500"}


def test_the_quick_deck_discharges_clumps_of_glued_spheres(run, tmp_path):
    """-var shape clump: the stock peer of the rods, 300 clumps of ten
    spheres of d = L/3.3 (fix multisphere), the solid rod's mass given,
    settle and discharge through the turning bottom at half the rods'
    time step. A clump leaves whole: from its first sphere out of the box
    it counts as out (fix multisphere deletes its other spheres at a
    re-neighbour five steps later), so n_out is whole, the atoms on every
    thermo line are ten per clump left plus at most nine of a leaving one,
    and mass_out is n_out rod masses. discharge.txt is written every step,
    so that it holds records inside those five steps of each clump that
    leaves (where a count of atoms/10 gave tenths of a clump)."""
    rod_mass = solid_rod_mass(0.020, 3.3)
    rods = run(deck(quick=1, shape="rod", settle_time=0.0001, discharge_time=0.0001), subdir="rods")
    rod_dt = read_run_info(tmp_path / "rods", required=())["dt"]
    output = run(quick_deck(shape="clump", f=0.32, settle_time=0.3, discharge_time=0.15,
                            record_every_time=rod_dt / 2))
    params = read_run_info(tmp_path, required=())
    assert params["shape"] == "clump" and params["N"] == 300
    assert params["mass"] == pytest.approx(rod_mass, rel=1e-12)
    assert params["dt"] == pytest.approx(rod_dt / 2, rel=1e-12) and "nan" not in rods.lower()
    record = read_table(tmp_path / "discharge.txt")
    assert np.all(np.diff(record["step"]) == 1)
    assert np.all(np.diff(record["n_out"]) >= 0) and record["n_out"][-1] > 5
    np.testing.assert_array_equal(record["n_out"], np.round(record["n_out"]))
    np.testing.assert_allclose(record["mass_out"], record["n_out"] * rod_mass, rtol=1e-9)
    rows = discharge_rows(output)
    atoms = np.array([int(row[2]) for row in rows])
    assert atoms[0] == 3000 and atoms[-1] < 3000
    n_out = np.array([float(row[4]) for row in rows])
    np.testing.assert_array_equal(n_out, np.round(n_out))
    leaving = atoms - 10 * (300 - n_out)
    assert np.all((leaving >= 0) & (leaving <= 9)), leaving
    assert "nan" not in output.lower()
    # half the rods' dt does not divide 0.05 s: the run still ends after
    # 0.15 s of discharge, not a chunk of 0.05 s later
    t_done, _ = done_line(output)
    assert t_done - params["t_open"] == pytest.approx(0.15, abs=10 * params["dt"])


@pytest.mark.parametrize("variables, message", [
    ({"reinject": 1}, "shape clump has no reinjection"),
    ({"dump_every_time": 0.05}, "shape clump writes no dump.cg"),
])
def test_clumps_refuse_reinjection_and_dumps_with_a_message(run, variables, message):
    with pytest.raises(LiggghtsError) as caught:
        run(quick_deck(shape="clump", **variables))
    assert message in caught.value.output


def test_clumps_start_from_the_poses_of_a_rod_packing(run, tmp_path):
    """-var write_poses 1 (rods) writes the rods' centres and axes at the
    opening, the state the first frame of dump.cg holds; -var shape clump
    -var read_poses 1 places one clump at each (fix insert/poses, whose own
    tests check where its spheres go)."""
    run(quick_deck(shape="rod", settle_time=0.2, discharge_time=0.0001, write_poses=1,
                   dump_every_time=0.2), subdir="rods")
    step, poses = read_dump(tmp_path / "rods" / "poses.dump")[0]
    step_cg, grains = read_dump(tmp_path / "rods" / "dump.cg")[0]
    assert list(poses) == ["x", "y", "z", "c_rod_axis[1]", "c_rod_axis[2]", "c_rod_axis[3]"]
    assert len(poses["x"]) == 300
    axes = np.column_stack([poses[f"c_rod_axis[{k}]"] for k in (1, 2, 3)])
    np.testing.assert_allclose(np.linalg.norm(axes, axis=1), 1.0, rtol=0, atol=1e-12)
    # dump.cg (sorted by id, as the poses are; 6 digits) writes on multiples
    # of its interval, here the settling time: its first frame is the opening
    # (%g: 6 significant digits, half a unit of the last, 5e-6 relative)
    assert step_cg == step
    for column in poses:
        np.testing.assert_allclose(poses[column], grains[column], rtol=5.1e-6, atol=1e-12)
    output = run(quick_deck(shape="clump", read_poses=1, poses=tmp_path / "rods" / "poses.dump",
                            settle_time=0.01, discharge_time=0.0001))
    assert "inserted 300 particle templates" in output
    assert read_run_info(tmp_path, required=())["N"] == 300
    assert discharge_atoms(output)[-1] == "3000" and "nan" not in output.lower()


@pytest.mark.parametrize("variables, message", [
    ({"write_poses": 1}, "write_poses writes the poses of rods"),
    ({"read_poses": 1, "shape": "rod"}, "read_poses places clumps"),
])
def test_poses_are_refused_for_the_wrong_grains_with_a_message(run, variables, message):
    with pytest.raises(LiggghtsError) as caught:
        run(quick_deck(**variables))
    assert message in caught.value.output


def test_a_poses_file_with_fewer_clumps_than_N_is_refused(run, tmp_path):
    (tmp_path / "two.txt").write_text("0 0 0.02 1 0 0\n0.03 0 0.02 0 1 0\n")
    with pytest.raises(LiggghtsError) as caught:
        run(quick_deck(shape="clump", read_poses=1, poses=tmp_path / "two.txt", settle_time=0.0001))
    assert "the gas holds 2 < N = 300 clumps" in caught.value.output
