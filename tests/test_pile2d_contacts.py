"""The pile scene's own contacts (inputs/pile2d/contacts.in and
model_<model>.in, included as the decks include them) on the paper's Fig. 2
case: a disc resting on ONE other disc, the line of centres at angle theta
from the vertical. The statics are derived in test_jiang_statics_rolling.py
(a disc on a disc, rigid-body balance): an equilibrium exists iff

    sliding:  tan(theta) <= mu
    rolling:  tan(theta) <= mu l_c / r_c,    r_c = r - delta_n / 2

with delta_n = m g cos(theta) / k_n; without rolling resistance there is
none off the vertical. Here with the scene's values (normalised units:
d = 1, g = 1, k_n = 1000, mu = 0.5, the largest grain of mass 1,
damping 0.3 of critical, rolling damping 0.3): fixed l_c = 0.05 d gives
tan(theta_c) = 0.0500 (2.86 deg), l_c from the overlap (the chord of two
unit discs overlapping by 9.1e-4 d) 0.0426 (2.44 deg). The margins are
+-30 % in tan(theta). The disc starts with unloaded springs; with 0.3 of
critical damping (not critical, as in test_jiang_statics_rolling.py) the
transient overshoots the static deflection and may roll it plastically a
little at the cap: below the threshold the disc is held if it comes to
rest within 3/4 of the angular margin (measured peak tilts: fixed l_c
0.0060 rad of a margin of 0.0150 rad, overlap l_c 0.0081 of 0.0128; the
elastic tilt alone, r_c M / (k_r D), is 0.0032 and 0.0037 rad). Above it,
the disc rolls past 30 degrees and falls off the box."""

import math
from pathlib import Path

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

ROOT = Path(__file__).resolve().parent.parent
DIAMETER = 1.0
RADIUS = 0.5
MASS = (DIAMETER / 1.05) ** 2          # m = d^2 / d_max^2
G, KN, MU = 1.0, 1000.0, 0.5
MARGIN = 0.3
DURATION = 60.0                        # sqrt(d/g) units
FALLEN = math.radians(30.0)


def overlap(theta):
    return MASS * G * math.cos(theta) / KN


def lever(theta):
    return RADIUS - overlap(theta) / 2


def chord(theta):
    return 2 * math.sqrt(RADIUS ** 2 - lever(theta) ** 2)


def threshold(model):
    """tan(theta_c) by fixed-point iteration (delta_n depends on theta)."""
    if model == "fixed":
        rolling_length = lambda theta: 0.05 * DIAMETER
    else:
        rolling_length = chord
    tan_c = MU * rolling_length(0.0) / lever(0.0)
    for _ in range(50):
        theta = math.atan(tan_c)
        tan_c = MU * rolling_length(theta) / lever(theta)
    return tan_c


def disc_on_disc_deck(model, theta):
    distance = DIAMETER - overlap(theta)
    return f"""
units si
dimension 2
atom_style sphere
atom_modify map array
boundary f f p
newton off
communicate single vel yes
region box block -3 3 -3 3 -0.5 0.5 units box
create_box 2 box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {distance * math.sin(theta)!r} {distance * math.cos(theta)!r} 0 units box
variable model index {model}
variable inputs index {ROOT / 'inputs'}
variable damping index 0.3
variable rolling_damping index 0.3
variable dt_fraction index 25
include {ROOT / 'inputs' / 'pile2d' / 'contacts.in'}
set group all diameter {DIAMETER} density ${{rho}}
group top id 2
fix gravity top gravity ${{g}} vector 0 -1 0
fix integrate top nve/sphere
fix plane all enforce2d
variable steps equal round({DURATION}/v_dt)
dump top top custom 100 dump.top id x y vx vy omegaz mass
dump_modify top format "%d %.17g %.17g %.17g %.17g %.17g %.17g"
run ${{steps}}
"""


def contact_angles(run, tmp_path, model, theta, subdir):
    run(disc_on_disc_deck(model, theta), subdir=subdir)
    frames = read_dump(tmp_path / subdir / "dump.top")
    # frames after the disc fell out of the box hold no atom
    c = [columns for _, columns in frames if len(columns["x"])]
    assert len(c) > 10
    assert c[0]["mass"][0] == pytest.approx(MASS, rel=1e-12)
    angle = np.array([math.atan2(f["x"][0], f["y"][0]) for f in c])
    speed = np.array([math.hypot(f["vx"][0], f["vy"][0]) + RADIUS * abs(f["omegaz"][0]) for f in c])
    return angle, speed, len(c) == len(frames)


@pytest.mark.parametrize("model", ["fixed", "overlap"])
def test_held_below_the_rolling_limit_and_rolls_off_above(run, tmp_path, model):
    tan_c = threshold(model)
    assert tan_c == pytest.approx({"fixed": 0.0500, "overlap": 0.0426}[model], abs=2e-4)
    below = math.atan((1 - MARGIN) * tan_c)
    above = math.atan((1 + MARGIN) * tan_c)
    angle, speed, stayed = contact_angles(run, tmp_path, model, below, "below")
    assert stayed
    # stays near where it was put and comes to rest
    assert np.abs(angle - below).max() < 0.75 * (math.atan(tan_c) - below)
    assert speed[-1] < 1e-6
    angle, _, _ = contact_angles(run, tmp_path, model, above, "above")
    assert angle.max() > FALLEN


def test_no_rolling_resistance_no_equilibrium(run, tmp_path):
    """Without rolling resistance a disc 1 degree off the vertical (a third
    of the fixed-l_c threshold, far inside the sliding limit) rolls off."""
    angle, _, _ = contact_angles(run, tmp_path, "none", math.radians(1.0), "none")
    assert angle.max() > FALLEN


def test_an_unknown_model_is_an_error(run):
    from analysis.testing import LiggghtsError
    with pytest.raises(LiggghtsError) as caught:
        run(disc_on_disc_deck("rough", 0.0))
    assert "Label wasn't found" in caught.value.message
    assert "rolling model rough (known: none, overlap, depth, fixed)" in caught.value.output
