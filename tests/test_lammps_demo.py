"""The demo in both hosts: examples/demo/in.demo (LIGGGHTS) and its twin
examples/demo/in.demo.lammps (LAMMPS with our plugin). A disc rests on a
fixed disc 1.5 deg off the vertical; without rolling resistance it rolls
off, with Jiang's (l_c = 0.05 d) it stays. Each deck prints, per model,

    silokit demo: rolling_friction <model>: contact angle 1.5 deg -> <angle> deg after 0.2 s

The tests run the decks as shipped, with one dump added before the run
(x, y, v, omega_z every 2000 steps, %.17g).

Tolerance 0. Both hosts compute the one contact with the same core
functions (core/contact_law.h, core/rolling_law_jiang.h) in the same order,
add the same m g, and integrate discs with the same velocity Verlet
(nve/sphere; LAMMPS told `density/disc` and `disc`), as in the two-grain
collision of tests/test_lammps_cross_host.py, which agrees to the last bit.
With one contact there is nothing to sum in another order, on one rank or
two. Measured: the printed angles agree in all 15 digits and the dumped
trajectories bit for bit. A difference means that a host computes something
differently (a disc's mass or inertia, the damping's effective mass, the
rolling damping's inertia factor).

Physics, independent of either host: Jiang's law holds the disc below its
limit angle theta_max = atan(mu l_c / r) (eq. 1 of Magalhaes et al. 2014:
the rolling torque is capped at mu l_c F_n, the gravity moment is
m g r sin(theta)), and without it the disc rolls past the horizontal
(more than 90 deg from the vertical)."""

import math
import re
from functools import lru_cache
from pathlib import Path

import pytest

from analysis.testing import assert_dumps_close, liggghts_binary, read_frames, run_deck
from lammps_host import LMP, PLUGIN, has_mpirun, needs_lammps

pytestmark = needs_lammps

ROOT = Path(__file__).resolve().parent.parent
DECKS = {"liggghts": ROOT / "examples" / "demo" / "in.demo",
         "lammps": ROOT / "examples" / "demo" / "in.demo.lammps"}

# the decks' parameters (both decks set the same)
DIAMETER = 0.01
MU = 0.5
CONTACT_LENGTH = 0.05 * DIAMETER
THETA_MAX = math.degrees(math.atan(MU * CONTACT_LENGTH / (DIAMETER / 2)))   # 2.862 deg

LINE = re.compile(r"^silokit demo: rolling_friction (off|jiang): contact angle 1\.5 deg -> "
                  r"(\S+) deg after (\S+) s$", re.MULTILINE)
COLUMNS = "id x y vx vy omegaz"
FORMAT = " ".join(["%d"] + ["%.17g"] * 5)
# one disc on each of the two ranks (the cut at x = 1e-4 m, between the
# centres: the bottom disc at 0, the top one at 2.6e-4 m and to the right)
SPLIT = "balance 1.0 x {:.6f}".format((0.03 + 1e-4) / 0.06)


def with_dump(host, split=False):
    """The deck's text with a dump of each model's run (dump.off,
    dump.jiang); split: a LAMMPS deck whose two ranks own one disc each."""
    deck = DECKS[host].read_text()
    modify = (f'dump_modify d format line "{FORMAT}"' if host == "lammps"
              else f'dump_modify d format "{FORMAT}"')
    run = "run ${steps}\n"
    assert deck.count(run) == 1, f"{DECKS[host]} has no single `{run.strip()}`"
    deck = deck.replace(run, f"dump d all custom 2000 dump.${{model}} {COLUMNS}\n{modify}\n"
                             f"{run}undump d\n")
    if split:
        anchor = "group base id 1\n"
        assert deck.count(anchor) == 1
        deck = deck.replace(anchor, f"{SPLIT}\n{anchor}")
    return deck


@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    """demo(host, nprocs, split=False) -> (printed lines {model: (angle,
    time)}, dumps {model: frames}, screen output); each run once."""
    root = tmp_path_factory.mktemp("demo")

    @lru_cache(maxsize=None)
    def run(host, nprocs, split=False):
        workdir = root / f"{host}_np{nprocs}{'_split' if split else ''}"
        deck = with_dump(host, split)
        if host == "liggghts":
            if not liggghts_binary().exists():
                pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
            result = run_deck(deck, workdir, nprocs=nprocs)
        else:
            # our build's layout: the deck's default, the plugin's bare name,
            # must find it (as `build/bin/lmp -in examples/demo/in.demo.lammps`
            # does); another LAMMPS gets the plugin's path
            variables = {} if PLUGIN.parent == LMP.parent.parent / "lib" else {"plugin": PLUGIN}
            result = run_deck(deck, workdir, nprocs=nprocs, binary=LMP, variables=variables,
                              log_file="log.lammps")
        lines = {model: (angle, time) for model, angle, time in LINE.findall(result.output)}
        assert sorted(lines) == ["jiang", "off"], \
            f"{host} printed {lines}:\n{result.output[-2000:]}"
        dumps = {model: read_frames(workdir / f"dump.{model}") for model in lines}
        return lines, dumps, result.output

    return run


def check_physics(lines):
    off, jiang = float(lines["off"][0]), float(lines["jiang"][0])
    assert lines["off"][1] == lines["jiang"][1] == "0.2"
    assert off > 90.0, f"without rolling resistance the disc rolls off: {off} deg"
    assert 1.5 < jiang < THETA_MAX, f"Jiang's law holds the disc below {THETA_MAX:.3f} deg: {jiang}"


def assert_same_run(a, b):
    lines_a, dumps_a, _ = a
    lines_b, dumps_b, _ = b
    assert lines_a == lines_b
    for model in ("off", "jiang"):
        assert len(dumps_a[model]) == 101
        assert_dumps_close(dumps_a[model], dumps_b[model], rtol=0, atol=0)


def test_lammps_demo_is_the_liggghts_demo(demo):
    lammps = demo("lammps", 1)
    check_physics(lammps[0])
    assert_same_run(lammps, demo("liggghts", 1))


@pytest.mark.skipif(not has_mpirun(), reason="mpirun is not installed")
def test_lammps_demo_on_two_ranks(demo):
    """As shipped, both discs end on one of the two ranks (the cut at x = 0
    leaves the bottom disc, at x = 0, to the right): the deck must still run
    and print the same. With the cut moved between them, one disc on each
    rank, the pair is a ghost pair on both, and the run is the same too."""
    serial = demo("lammps", 1)
    shipped = demo("lammps", 2)
    check_physics(shipped[0])
    assert_same_run(shipped, serial)
    assert_same_run(demo("liggghts", 2), serial)

    split = demo("lammps", 2, split=True)
    assert split[2].count("Nlocal:        1.00000 ave           1 max           1 min") == 2
    assert_same_run(split, serial)
