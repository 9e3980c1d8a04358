"""The open 2D pile's decks for LAMMPS (inputs/pile2d/in.build.lammps,
in.discharge.lammps and in.runon.lammps, doc/pile2d.md "LAMMPS"), in
their quick variant (L = 20 d), run by our lmp with the plugin:

- the quick build finishes in equilibrium and writes a piles.txt line
  whose header and columns are LIGGGHTS' (the same file, text for text:
  the cross-host check below), and that agrees with the dumped pile;
- against LIGGGHTS, same seed, every model: the same pile. The rain is the
  same grains to the bit in both hosts (fix insert/rain2d shares its
  drawing code), and the contacts are the same core functions; the
  settling is chaotic (below), so any difference in a contact's force,
  even in the last bit, would grow to a different pile within some 3000
  steps of 38000. Measured: the quick pile of each of the four models is
  the same to the bit in both hosts (every column of every grain of the
  final dump, 252 to 258 grains after 38000 to 79000 steps), so the
  tolerance on n_pile, h0 and the dumped pile is 0: a difference is a
  difference between the hosts' contact handling to trace (e.g. LIGGGHTS
  keeps a parted pair's tangential spring until the next neighbour build,
  LAMMPS zeroes it at once: doc/pair_granular_jiang.md), not noise;
- on 2 ranks: the same grains (the rain is rank-independent), the same
  frames to the bit while the rows fall and land one by one, then round-off
  from the other order of the force sums that grows by about ten every
  350 steps (chaos): within 1e-9 d up to step 4984, a different pile in
  the end, whose grain count and h0 lie within the spread between seeds,
  and which LIGGGHTS on 2 ranks builds too (the same piles.txt line) and
  discharges on 2 ranks as LAMMPS does (the same record);
- the discharge reads the built pile (a LAMMPS restart file), opens the
  orifice and writes its record, a jam at 1 d (the same record as
  LIGGGHTS') and a collapse at 8 d;
- the run-on check (in.runon.lammps) reads the built pile and runs it on,
  unchanged, for 10 times its relaxation: it stays (what LIGGGHTS' test of
  in.runon asserts), and LIGGGHTS' in.runon on its pile of the same seed
  writes the same line, text for text;
- a LIGGGHTS-only switch (vtk_every) or a bad value stops any of the decks
  with an ERROR naming it.
"""

from pathlib import Path

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from analysis.common.tables import read_rows
from analysis.testing import LiggghtsError, liggghts_binary, run_deck
from lammps_host import ROOT, has_mpirun, needs_lammps, run_lammps
from test_pile2d_deck import check_equilibrium, check_substrate, surface_height

pytestmark = needs_lammps

INPUTS = ROOT / "inputs"
DECKS = INPUTS / "pile2d"
L = 20.0
SUBSTRATE = 200                     # 10 L discs of diameter 0.1
SEED = 15485863
FRAME_STEPS = 178                   # dump every 0.5 sqrt(d/g) (dt = t_c/25)
# the spread between piles of model fixed at L = 20 d: standard deviations
# over the 20 LIGGGHTS piles of doc/data/pile2d_discharges.txt (h0 5.33 d
# on average, n_pile 61.5)
H0_SD, N_PILE_SD = 0.71, 5.9


def lammps_build(workdir, model="fixed", nprocs=1, **variables):
    run = run_lammps(DECKS / "in.build.lammps", workdir, nprocs=nprocs, timeout=900,
                     variables={"quick": 1, "model": model, "seed": SEED, "inputs": INPUTS,
                                "pile": "pile.restart", "piles": "piles.txt", "final_dump": 1,
                                **variables})
    return run, read_rows(Path(workdir) / "piles.txt")[-1]


def liggghts_build(workdir, model="fixed", **variables):
    run_deck(DECKS / "in.build", workdir, binary=liggghts_binary(), timeout=900,
             variables={"quick": 1, "model": model, "seed": SEED, "inputs": INPUTS,
                        "pile": "pile.restart", "piles": "piles.txt", "final_dump": 1,
                        **variables})
    return read_rows(Path(workdir) / "piles.txt")[-1]


def discharge(deck, workdir, pile_dir, w, model="fixed", binary=None):
    variables = {"quick": 1, "model": model, "seed": SEED, "inputs": INPUTS, "w": w,
                 "pile": Path(pile_dir) / "pile.restart", "results": "discharges.txt",
                 "final_dump": 1}
    if binary is None:
        run_lammps(DECKS / deck, workdir, variables=variables, timeout=900)
    else:
        run_deck(DECKS / deck, workdir, binary=binary, variables=variables, timeout=900)
    return read_rows(Path(workdir) / "discharges.txt")[-1]


def run_on(deck, workdir, pile_dir, pile, binary=None):
    """Runs the pile of pile_dir (its piles.txt line `pile`) on for 10
    times its relaxation (t_end - t_rain), as tests/test_pile2d_deck.py
    does in LIGGGHTS; returns the runon.txt line."""
    variables = {"model": pile["model"], "L": L, "seed": SEED, "inputs": INPUTS,
                 "pile": Path(pile_dir) / "pile.restart", "runon": "runon.txt",
                 "time": 10 * (pile["t_end"] - pile["t_rain"])}
    if binary is None:
        run_lammps(DECKS / deck, workdir, variables=variables, timeout=900)
    else:
        run_deck(DECKS / deck, workdir, binary=binary, variables=variables, timeout=900)
    return read_rows(Path(workdir) / "runon.txt")[-1]


def by_id(columns):
    order = np.argsort(columns["id"])
    return {name: values[order] for name, values in columns.items()}


def assert_same_to_the_bit(first, second):
    first, second = by_id(first), by_id(second)
    assert set(first) == set(second)
    for name in first:
        np.testing.assert_array_equal(first[name], second[name], err_msg=name)


@pytest.fixture(scope="module")
def quick_pile(tmp_path_factory):
    """Model fixed on one rank, a frame every 0.5 sqrt(d/g)."""
    workdir = tmp_path_factory.mktemp("lammps_pile")
    run, record = lammps_build(workdir, dump_every=FRAME_STEPS)
    return workdir, run, record


def test_quick_build_reaches_equilibrium_and_records_it(quick_pile):
    workdir, run, record = quick_pile
    header = (workdir / "piles.txt").read_text().splitlines()[0]
    assert header == ("# model L seed n_pile h0 rows inserted t_rain t_end status dt_fraction "
                      "damping rolling_damping pile substrate_d substrate_lc")
    assert record["model"] == "fixed" and record["L"] == L and record["seed"] == SEED
    assert record["status"] == 1 and record["pile"] == "pile.restart"
    assert record["substrate_d"] == 0.1 and record["substrate_lc"] == 0.05
    assert (record["dt_fraction"], record["damping"], record["rolling_damping"]) == (25, 0.3, 0.3)
    columns = read_dump(workdir / "pile.restart.dump")[-1][1]
    free = columns["type"] == 1
    check_substrate(columns)
    # discs: mass pi r^2 rho = d^2 / d_max^2 (set density/disc, insert/rain2d)
    d = 2 * columns["radius"]
    np.testing.assert_allclose(columns["mass"], (d / 1.05) ** 2, rtol=1e-12)
    assert np.all((d[free] >= 0.95 - 1e-12) & (d[free] <= 1.05 + 1e-12))
    assert np.all(columns["y"][free] > 0.3)
    assert record["n_pile"] == free.sum() >= 30
    assert record["inserted"] > record["n_pile"]         # grains did leave over the ends
    assert record["inserted"] == 10 * record["rows"]     # L/(2 d) grains per row
    assert record["h0"] == pytest.approx(surface_height(columns), abs=1e-9)
    assert record["h0"] > 3.0
    assert record["t_end"] > record["t_rain"] > 0
    check_equilibrium(columns)


@pytest.mark.parametrize("model, variables", [
    ("fixed", {}), ("none", {}), ("overlap", {}), ("depth", {}),
    # the paper's model none as written (rolling none everywhere), and
    # another l_c without rolling damping
    ("none", {"substrate_lc": 0}), ("fixed", {"l_c": 0.1, "rolling_damping": 0}),
])
def test_quick_pile_is_liggghts_pile(model, variables, quick_pile, tmp_path):
    """The same seed in both hosts: the same piles.txt, text for text, and
    the same pile to the bit (the module's docstring says why 0)."""
    if model == "fixed" and not variables:
        lammps_dir = quick_pile[0]
    else:
        lammps_dir = tmp_path / "lammps"
        lammps_build(lammps_dir, model=model, **variables)
    liggghts_build(tmp_path / "liggghts", model=model, **variables)
    lammps_text = (lammps_dir / "piles.txt").read_text()
    liggghts_text = (tmp_path / "liggghts" / "piles.txt").read_text()
    assert lammps_text == liggghts_text
    assert_same_to_the_bit(read_dump(lammps_dir / "pile.restart.dump")[-1][1],
                           read_dump(tmp_path / "liggghts" / "pile.restart.dump")[-1][1])


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
def test_two_ranks_rain_the_same_grains(quick_pile, tmp_path):
    workdir, _, serial = quick_pile
    run, parallel = lammps_build(tmp_path, nprocs=2, dump_every=FRAME_STEPS)
    assert "2 by 1 by 1 MPI processor grid" in run.output
    serial_frames = dict(read_dump(workdir / "dump.build"))
    parallel_frames = dict(read_dump(tmp_path / "dump.build"))
    common_steps = sorted(set(serial_frames) & set(parallel_frames))
    assert len(common_steps) > 100
    largest_gap = {}
    for step in common_steps:
        one, two = by_id(serial_frames[step]), by_id(parallel_frames[step])
        ids, in_one, in_two = np.intersect1d(one["id"], two["id"], return_indices=True)
        assert ids.size >= SUBSTRATE + 10 * (step > 0)     # a row falls from step 1
        # the same grains: a tag has the same diameter on 1 and 2 ranks, always
        np.testing.assert_array_equal(one["radius"][in_one], two["radius"][in_two])
        if step <= 2136:
            # rows falling and landing one at a time: the same to the bit
            assert np.array_equal(one["id"], two["id"]), step
            for name in ("x", "y", "vx", "vy", "omegaz"):
                np.testing.assert_array_equal(one[name], two[name], err_msg=f"{name} at {step}")
        largest_gap[step] = np.max(np.hypot(one["x"][in_one] - two["x"][in_two],
                                            one["y"][in_one] - two["y"][in_two]))
    # then round-off from the order of the force sums on two ranks, which
    # the pile amplifies (measured: 1e-16 d at step 2314, 6e-11 d at 4984,
    # 3e-4 d at 7476, order d from 9000)
    assert max(gap for step, gap in largest_gap.items() if step <= 4984) < 1e-9
    assert max(largest_gap.values()) > 0.1          # a chaotic pile: it does diverge
    # another realisation of the quick pile: in equilibrium, its size
    # within the spread between seeds (3 sd of a difference of two piles)
    assert parallel["status"] == 1 and parallel["h0"] > 3.0
    columns = read_dump(tmp_path / "pile.restart.dump")[-1][1]
    check_equilibrium(columns)
    assert parallel["h0"] == pytest.approx(surface_height(columns), abs=1e-9)
    assert abs(parallel["h0"] - serial["h0"]) < 3 * np.sqrt(2) * H0_SD
    assert abs(parallel["n_pile"] - serial["n_pile"]) < 3 * np.sqrt(2) * N_PILE_SD
    # and LIGGGHTS on 2 ranks, which cuts the box in the same place, builds
    # this same pile (measured: to the bit)
    run_deck(DECKS / "in.build", tmp_path / "liggghts", nprocs=2, binary=liggghts_binary(),
             timeout=900, variables={"quick": 1, "model": "fixed", "seed": SEED, "inputs": INPUTS,
                                     "pile": "pile.restart", "piles": "piles.txt"})
    assert ((tmp_path / "liggghts" / "piles.txt").read_text()
            == (tmp_path / "piles.txt").read_text())
    # each host's 2-rank pile discharged on 2 ranks (w = 2.2 d): the same
    # record (measured: h 5.59519105958579, 3 grains out)
    variables = {"quick": 1, "model": "fixed", "seed": SEED, "inputs": INPUTS, "w": 2.2,
                 "results": "discharges.txt"}
    run_lammps(DECKS / "in.discharge.lammps", tmp_path / "w_lammps", nprocs=2, timeout=900,
               variables={**variables, "pile": tmp_path / "pile.restart"})
    run_deck(DECKS / "in.discharge", tmp_path / "w_liggghts", nprocs=2, binary=liggghts_binary(),
             timeout=900, variables={**variables, "pile": tmp_path / "liggghts" / "pile.restart"})
    lammps_record = (tmp_path / "w_lammps" / "discharges.txt").read_text()
    assert lammps_record == (tmp_path / "w_liggghts" / "discharges.txt").read_text()
    assert read_rows(tmp_path / "w_lammps" / "discharges.txt")[-1]["status"] == 1


def test_discharge_jams_at_one_diameter_as_in_liggghts(quick_pile, tmp_path):
    pile_dir, _, pile = quick_pile
    result = discharge("in.discharge.lammps", tmp_path / "lammps", pile_dir, 1.0)
    header = (tmp_path / "lammps" / "discharges.txt").read_text().splitlines()[0]
    assert header == ("# model L w seed h n_out h0 n_pile w_gap t_end status dt_fraction "
                      "damping rolling_damping")
    columns = read_dump(tmp_path / "lammps" / "discharge.dump")[-1][1]
    substrate = columns["type"] == 2
    # the orifice: the 10 discs with |x| < 0.5 are gone, the gap is 1 d
    assert substrate.sum() == SUBSTRATE - 10
    assert np.abs(columns["x"][substrate]).min() == pytest.approx(0.55)
    assert result["w_gap"] == pytest.approx(1.0, abs=1e-6)
    # the pile read back is the one built: its h0 and grains
    assert result["h0"] == pile["h0"] and result["n_pile"] == pile["n_pile"]
    assert result["status"] == 1
    assert result["h"] == pytest.approx(surface_height(columns), abs=1e-9)
    assert result["h"] > 0.8 * pile["h0"]
    assert result["n_out"] == pile["n_pile"] - (columns["type"] == 1).sum()
    check_equilibrium(columns)
    # LIGGGHTS, its own pile from the same seed (the same pile: above),
    # discharged the same way: the same record
    liggghts_build(tmp_path / "liggghts_pile")
    discharge("in.discharge", tmp_path / "liggghts", tmp_path / "liggghts_pile", 1.0,
              binary=liggghts_binary())
    assert ((tmp_path / "lammps" / "discharges.txt").read_text()
            == (tmp_path / "liggghts" / "discharges.txt").read_text())


def test_discharge_collapses_at_eight_diameters(quick_pile, tmp_path):
    pile_dir, _, pile = quick_pile
    result = discharge("in.discharge.lammps", tmp_path, pile_dir, 8.0)
    columns = read_dump(tmp_path / "discharge.dump")[-1][1]
    free = columns["type"] == 1
    assert result["status"] == 1 and result["h"] == 0.0 and surface_height(columns) == 0.0
    assert result["w_gap"] == pytest.approx(8.0, abs=1e-6)
    assert result["n_out"] == pile["n_pile"] - free.sum() > 0.4 * pile["n_pile"]
    assert not np.any(np.abs(columns["x"][free]) < 4.0 - columns["radius"][free])
    check_equilibrium(columns)


def test_pile_stays_when_run_on_as_in_liggghts(quick_pile, tmp_path):
    """in.runon.lammps on the quick pile: LIGGGHTS' test of in.runon
    (test_pile_declared_in_equilibrium_stays_when_run_on) with its
    tolerances: no grain lost, h0 the same within 1e-3 d, no grain moved
    more than 1e-2 d, the equilibrium criteria still hold. Then LIGGGHTS'
    in.runon on its own pile of the same seed (the same pile to the bit:
    above): the same runon.txt, header and line, text for text (measured:
    165540 steps, h0 4.91422611473235 -> 4.91422301756493 d, largest
    displacement 3.36e-5 d in both hosts)."""
    pile_dir, _, pile = quick_pile
    record = run_on("in.runon.lammps", tmp_path / "lammps", pile_dir, pile)
    header = (tmp_path / "lammps" / "runon.txt").read_text().splitlines()[0]
    assert header == ("# model L seed time n_before n_after h0_before h0_after "
                      "max_displacement max_speed status")
    assert record["model"] == "fixed" and record["L"] == L and record["seed"] == SEED
    assert record["time"] == pytest.approx(10 * (pile["t_end"] - pile["t_rain"]), rel=1e-6)
    assert record["n_before"] == pile["n_pile"] == record["n_after"]
    assert record["h0_before"] == pytest.approx(pile["h0"], abs=1e-9)
    assert abs(record["h0_after"] - record["h0_before"]) < 1e-3
    # the grains do creep a little (the criteria allow speeds up to 1e-4):
    # a displacement of exactly 0 would mean displace/atom measured nothing
    assert 0 < record["max_displacement"] < 1e-2
    assert record["status"] == 1 and record["max_speed"] < 1e-4
    liggghts_build(tmp_path / "liggghts_pile")
    run_on("in.runon", tmp_path / "liggghts", tmp_path / "liggghts_pile", pile,
           binary=liggghts_binary())
    assert ((tmp_path / "lammps" / "runon.txt").read_text()
            == (tmp_path / "liggghts" / "runon.txt").read_text())


@pytest.mark.parametrize("deck, variables, says", [
    ("in.build.lammps", {"vtk_every": 100}, "vtk_every has no meaning in LAMMPS"),
    ("in.discharge.lammps", {"vtk_every": 100}, "vtk_every has no meaning in LAMMPS"),
    ("in.build.lammps", {"model": "rolling"}, "model is none, overlap, depth or fixed, not rolling"),
    ("in.build.lammps", {"L": 20.05}, "L = 20.05 must be a multiple of substrate_d"),
    ("in.build.lammps", {"fill": 1.0}, "fill = 1.0 must be in (0, 1)"),
    ("in.build.lammps", {"rain_height": 4}, "rain_height = 4 must be at least 5 d"),
    ("in.build.lammps", {"rolling_damping": -0.1}, "rolling_damping = -0.1 must be >= 0"),
    ("in.build.lammps", {"l_c": 0.6}, "l_c = 0.6 must be in (0, 0.5 d]"),
    ("in.build.lammps", {"substrate_lc": 0.2}, "substrate_lc = 0.2 must be in [0, 0.1 d]"),
    ("in.discharge.lammps", {"w": 0}, "w = 0 must be > 0"),
    ("in.runon.lammps", {"time": 0}, "in.runon.lammps: time = 0 must be > 0"),
])
def test_bad_input_is_refused_naming_it(deck, variables, says, tmp_path):
    with pytest.raises(LiggghtsError) as error:
        run_lammps(DECKS / deck, tmp_path, timeout=60,
                   variables={"quick": 1, "model": "fixed", "inputs": INPUTS,
                              "pile": tmp_path / "none.restart", **variables})
    assert error.value.message.startswith("ERROR")
    assert says in error.value.message, error.value.message
    for record in ("piles.txt", "discharges.txt", "runon.txt"):
        assert not (tmp_path / record).exists()
