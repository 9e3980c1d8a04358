"""analysis.pile2d.repose on hand-built piles: the slope of a staircase
heap built to a given angle, a flat layer, and the bottom layer's motion;
the expected numbers come from the construction, not from the code."""

import math

import numpy as np
import pytest

from analysis.pile2d import repose as pile2d_repose

ROW_HEIGHT = math.sqrt(3) / 2        # rows of touching unit discs, hexagonal


def write_dump(path, frames):
    """A LIGGGHTS custom dump: frames = [(step, columns dict)]."""
    with open(path, "w") as handle:
        for step, columns in frames:
            names = list(columns)
            n = len(columns[names[0]])
            handle.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{n}\n"
                         "ITEM: BOX BOUNDS ff ff pp\n-30 30\n-1 60\n-0.5 0.5\n"
                         f"ITEM: ATOMS {' '.join(names)}\n")
            for k in range(n):
                handle.write(" ".join(repr(float(columns[c][k])) for c in names) + "\n")


def discs_under(half_width):
    """Unit discs in hexagonal rows on y = 0, each row centred on x = 0 and
    as wide as half_width(top of its discs) allows; rows stop when a row
    would be narrower than one disc."""
    xs, ys = [], []
    row = 0
    while True:
        y = 0.5 + ROW_HEIGHT * row
        half = half_width(y + 0.5)
        if half < 0.5:
            break
        offset = 0.0 if row % 2 == 0 else 0.5
        x = -half + 0.5 + offset
        while x <= half - 0.5 + 1e-9:
            xs.append(x)
            ys.append(y)
            x += 1.0
        row += 1
    n = len(xs)
    return {"id": np.arange(1, n + 1), "type": np.ones(n), "x": np.array(xs), "y": np.array(ys),
            "radius": np.full(n, 0.5)}


def staircase_heap(length, slope):
    """Rows whose disc tops stay under the line y = slope (L/2 - |x|)."""
    return discs_under(lambda top: length / 2 - top / slope)


@pytest.mark.parametrize("slope", [0.3, 0.45])
def test_slope_of_a_staircase_heap(tmp_path, slope):
    length = 60.0
    write_dump(tmp_path / "pile.dump", [(0, staircase_heap(length, slope))])
    shape = pile2d_repose.pile_shape(tmp_path / "pile.dump", length)
    # the tops of the rows follow the line to within one row step, so the
    # fitted slope is the construction's within a few per cent
    assert shape["slope"] == pytest.approx(slope, rel=0.08)
    assert shape["angle"] == pytest.approx(math.degrees(math.atan(shape["slope"])))
    assert abs(shape["peak"]) < 0.6
    assert shape["residual"] < 0.5


def heap_with_a_summit(length, slope, summit_slope, summit_width):
    """Rows under the profile y = slope (L/2 - u) for u = |x| >= summit_width,
    steepened to summit_slope within it."""
    shoulder = slope * (length / 2 - summit_width)
    return discs_under(lambda top: length / 2 - top / slope if top <= shoulder
                       else summit_width - (top - shoulder) / summit_slope)


def test_peak_margin_leaves_out_a_steep_summit(tmp_path):
    """A flank of slope 0.4 with a summit of slope 1.5 within 10 d of the
    peak: fitted beyond 10 d the slope is the flank's; over the whole flank
    (the default margin of 1 d) the summit steepens it."""
    length = 80.0
    write_dump(tmp_path / "pile.dump", [(0, heap_with_a_summit(length, 0.4, 1.5, 10.0))])
    flank = pile2d_repose.pile_shape(tmp_path / "pile.dump", length, peak_margin=10.0)
    whole = pile2d_repose.pile_shape(tmp_path / "pile.dump", length)
    assert flank["slope"] == pytest.approx(0.4, rel=0.08)
    assert whole["slope"] > 0.5


def test_a_flat_layer_has_no_slope_and_grains_off_the_substrate_do_not_count(tmp_path):
    n = 20
    columns = {"id": np.arange(1, n + 3), "type": np.ones(n + 2),
               "x": np.concatenate([np.arange(n) - 9.5, [12.0, -12.5]]),
               "y": np.concatenate([np.full(n, 0.5), [0.5, -3.0]]),
               "radius": np.full(n + 2, 0.5)}
    write_dump(tmp_path / "flat.dump", [(0, columns)])
    shape = pile2d_repose.pile_shape(tmp_path / "flat.dump", 20.0)
    assert shape["grains"] == n
    assert abs(shape["slope"]) < 1e-9
    # the vertical lines run 0.05 d beside the discs' centres (a 0.1 d grid from -L/2 + 0.05)
    assert shape["top"] == pytest.approx(0.5 + math.sqrt(0.25 - 0.05 ** 2))


def test_base_motion_tells_rolling_from_sliding(tmp_path):
    """Three bottom-layer discs over a substrate of type 2: two roll (v_x =
    -omega r), one slides without turning; a disc above the layer and one
    beyond the substrate's ends are not counted."""
    columns = {"id": np.arange(1, 8), "type": np.array([1, 1, 1, 1, 1, 2, 2]),
               "x": np.array([-2.0, 0.0, 2.0, 0.0, 9.0, -5.0, 5.0]),
               "y": np.array([0.5, 0.5, 0.5, 1.4, 0.5, -0.05, -0.05]),
               "vx": np.array([0.2, -0.1, 0.05, 1.0, 3.0, 0.0, 0.0]),
               "omegaz": np.array([-0.4, 0.2, 0.0, 0.0, 0.0, 0.0, 0.0]),
               "radius": np.array([0.5, 0.5, 0.5, 0.5, 0.5, 0.05, 0.05])}
    write_dump(tmp_path / "dump.build", [(100, columns)])
    (time, grains, base, moving, speed, slip), = pile2d_repose.base_motion(tmp_path / "dump.build", 0.01)
    assert time == pytest.approx(1.0)
    assert (grains, base, moving) == (4, 3, 3)
    assert speed == pytest.approx((0.2 + 0.1 + 0.05) / 3)
    assert slip == pytest.approx(0.05 / 3)
