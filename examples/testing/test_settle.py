"""The example test of doc/testing.md: run a deck with silokit's liggghts
and compare its dump with a reference dump kept next to it.

    /usr/bin/python3 -m pytest -q examples/testing/test_settle.py
"""

from pathlib import Path

from analysis.testing import assert_dumps_close, assert_thermo_close, read_frame, run_deck

HERE = Path(__file__).resolve().parent
DECK = HERE / "in.settle"
REFERENCE = HERE / "reference" / "settle.dump"


def test_the_run_reproduces_the_reference_dump(tmp_path):
    run = run_deck(DECK, tmp_path)
    # every frame, atoms matched by id; positions to 1e-12 m, velocities to 1e-9 m/s
    assert_dumps_close(run.path("settle.dump"), REFERENCE, rtol=0, atol=1e-12,
                       columns=["x", "y", "z"])
    assert_dumps_close(run.path("settle.dump"), REFERENCE, rtol=0, atol=1e-9,
                       columns=["vx", "vy", "vz"])


def test_two_ranks_give_the_same_run(tmp_path):
    serial = run_deck(DECK, tmp_path / "serial", variables={"steps": 2000})
    parallel = run_deck(DECK, tmp_path / "parallel", variables={"steps": 2000}, nprocs=2)
    assert_dumps_close(serial.frame("settle.dump"), parallel.frame("settle.dump"), rtol=1e-10)
    assert_thermo_close(serial.output, parallel.output, rtol=1e-10, columns=["KinEng"])
    # the last frame of the shorter run is a frame of the reference
    assert_dumps_close(serial.frame("settle.dump"), read_frame(REFERENCE, step=2000), rtol=1e-10)
