"""The contact geometry of spherocylinders (src_plugin/core/spherocylinder_geometry.h),
through a small driver compiled here with g++.

A rod is its centre, unit axis, half-length h of its core segment and
radius r; its core points are centre + t axis, |t| <= h. Expected values
come from closed forms worked out here, or from brute force written here
independently of the header, never from the driver:

- two segments: a dense scan over t1, each sample with the exact nearest
  point of the other segment, refined by the root of the slope on the best
  bracket, and a dense 2D grid over (t1, t2) that the driver's distance may
  never exceed;
- the plate with a hole: this file's own nearest point of the plate
  (orifice_plate.h's rule, written geometrically), its rim crossings from
  the quadratic s(t)^2 = R^2, a dense scan of the distance f(t) over the
  piece of the core over the hole refined by Brent's method, and the
  header's rules 8 and 10 applied to what the scan finds;
- the mass properties: quadrature over slices normal to the axis.

Tolerances, and why: distances of random segment pairs 1e-9 (asked for;
the driver meets about 1e-15); nearly parallel pairs 2e-8 times their size
(rule 2 of the header: the error of either branch near the threshold angle
1e-8); swapping two rods: exact, bit for bit (rule 3); wall contacts
against brute force: overlaps 1e-10, t and wall points 1e-6, normals 1e-5
(the brute force finds a minimum of f only to about sqrt(machine epsilon)
in t, f being flat there); closed forms 1e-12.
"""

import math
import subprocess
from collections import namedtuple
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

ROOT = Path(__file__).resolve().parent.parent
DRIVER_SOURCE = ROOT / "tests" / "spherocylinder_geometry_driver.cpp"

EXACT = 1e-12                 # closed forms
RANDOM_DISTANCE = 1e-9        # random segment pairs against brute force
NEAR_PARALLEL_DISTANCE = 2e-8 # per unit of the rods' size, at the parallel threshold
WALL_OVERLAP = 1e-10          # wall contacts against brute force
WALL_POSITION = 1e-6          # t and wall points against brute force
WALL_NORMAL = 1e-5

WallContact = namedtuple("WallContact", "t wall_point normal overlap")
RodContact = namedtuple("RodContact", "t1 t2 distance overlap separation normal point")
Plate = namedtuple("Plate", "centre axis hole_radius")
Cylinder = namedtuple("Cylinder", "axis_point axis radius")


class Rod:
    def __init__(self, centre, axis, half_length, radius=0.25):
        self.centre = np.array(centre, dtype=float)
        axis = np.array(axis, dtype=float)
        self.axis = axis / np.linalg.norm(axis)
        self.half_length = float(half_length)
        self.radius = float(radius)

    def core(self, t):
        """The core point(s) at parameter(s) t."""
        return self.centre + np.multiply.outer(t, self.axis)

    def ends(self):
        return [-self.half_length, self.half_length] if self.half_length > 0 else [0.0]


def unit(vector):
    vector = np.array(vector, dtype=float)
    return vector / np.linalg.norm(vector)


def tilted(degrees):
    """Unit vector in the xz plane, `degrees` above the x axis."""
    return np.array([math.cos(math.radians(degrees)), 0.0, math.sin(math.radians(degrees))])


def words(*values):
    """The numbers (scalars or vectors) as driver input, exactly."""
    flat = []
    for value in values:
        flat.extend(np.atleast_1d(np.asarray(value, dtype=float)).tolist())
    return " ".join(repr(number) for number in flat)


def rod_words(rod):
    return words(rod.centre, rod.axis, rod.half_length, rod.radius)


# ------------------------------------------------------------------ driver

class Driver:
    """Each method takes a batch of cases and runs them in one process."""

    def __init__(self, executable):
        self.executable = executable

    def run(self, lines):
        result = subprocess.run([str(self.executable)], input="\n".join(lines) + "\n",
                                capture_output=True, text=True, check=True, timeout=60)
        rows = [line.split() for line in result.stdout.splitlines()]
        assert len(rows) == len(lines)
        return [[float(word) for word in row[1:]] for row in rows]

    def closest_points(self, pairs):
        lines = [f"segments {words(a.centre, a.axis, a.half_length, b.centre, b.axis, b.half_length)}"
                 for a, b in pairs]
        return [tuple(row) for row in self.run(lines)]

    def rod_contacts(self, pairs):
        rows = self.run([f"rod_contact {rod_words(a)} {rod_words(b)}" for a, b in pairs])
        return [RodContact(*row[:4], np.array(row[4:7]), np.array(row[7:10]), np.array(row[10:13]))
                for row in rows]

    def touching(self, pairs):
        """None for rods that do not touch, else the numbers of rod_contact."""
        rows = self.run([f"touching {rod_words(a)} {rod_words(b)}" for a, b in pairs])
        return [row[1:] if row[0] == 1.0 else None for row in rows]

    def within(self, pairs):
        return [row[0] == 1.0 for row in self.run([f"within {rod_words(a)} {rod_words(b)}" for a, b in pairs])]

    def plane_contacts(self, rods, point, normal):
        return self._wall([f"plane {rod_words(rod)} {words(point, normal)}" for rod in rods])

    def cylinder_contacts(self, rods, cylinder):
        return self._wall([f"cylinder {rod_words(rod)} {words(*cylinder)}" for rod in rods])

    def plate_contacts(self, rods, plate):
        return self._wall([f"plate {rod_words(rod)} {words(*plate)}" for rod in rods])

    def sphere_plate(self, points, plate):
        rows = self.run([f"sphere_plate {words(point, *plate)}" for point in points])
        return [(row[0], np.array(row[1:4]), np.array(row[4:7])) for row in rows]

    def mass(self, cases):
        return [tuple(row) for row in self.run([f"mass {words(*case)}" for case in cases])]

    def _wall(self, lines):
        results = []
        for row in self.run(lines):
            count = int(row[0])
            assert len(row) == 1 + 8 * count
            results.append([WallContact(row[k], np.array(row[k + 1:k + 4]), np.array(row[k + 4:k + 7]),
                                        row[k + 7]) for k in range(1, len(row), 8)])
        return results


@pytest.fixture(scope="session")
def driver(tmp_path_factory):
    """Compiles the driver once."""
    executable = tmp_path_factory.mktemp("spherocylinder_geometry") / "spherocylinder_geometry_driver"
    build = subprocess.run(
        ["g++", "-std=c++11", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic",
         f"-I{ROOT / 'src_plugin' / 'core'}", str(DRIVER_SOURCE), "-o", str(executable)],
        capture_output=True, text=True)
    if build.returncode != 0:
        pytest.fail(f"spherocylinder_geometry_driver does not compile:\n{build.stderr}")
    return Driver(executable)


# ------------------------------------------------ brute force: two segments

def nearest_on_core(points, rod):
    """Parameters of the core points of `rod` nearest to `points`."""
    return np.clip((points - rod.centre) @ rod.axis, -rod.half_length, rod.half_length)


def brute_force_closest(rod1, rod2, samples=2001):
    """(t1, t2, distance) of the closest core points: a dense scan over t1,
    each sample with the exact nearest point of segment 2, refined on the
    best bracket by the root of the slope of that convex function."""
    def gap(t1):
        p1 = rod1.core(t1)
        return p1 - rod2.core(nearest_on_core(p1, rod2))

    def slope(t1):
        return float(gap(t1) @ rod1.axis)

    h1 = rod1.half_length
    scan = np.linspace(-h1, h1, samples)
    distances = np.linalg.norm(gap(scan), axis=-1)
    best = int(np.argmin(distances))
    lower, upper = scan[max(best - 1, 0)], scan[min(best + 1, samples - 1)]
    if slope(lower) >= 0.0:
        t1 = lower
    elif slope(upper) <= 0.0:
        t1 = upper
    else:
        t1 = brentq(slope, lower, upper, xtol=1e-15)
    refined = float(np.linalg.norm(gap(t1)))
    if distances[best] < refined:
        t1, refined = scan[best], float(distances[best])
    return float(t1), float(nearest_on_core(rod1.core(t1), rod2)), refined


def grid_least_distance(rod1, rod2, samples=201):
    """Least distance over a grid of (t1, t2): no closest pair can beat it."""
    p1 = rod1.core(np.linspace(-rod1.half_length, rod1.half_length, samples))
    p2 = rod2.core(np.linspace(-rod2.half_length, rod2.half_length, samples))
    return float(np.min(np.linalg.norm(p1[:, None, :] - p2[None, :, :], axis=-1)))


def driver_distance(rod1, rod2, t1, t2):
    return float(np.linalg.norm(rod1.core(t1) - rod2.core(t2)))


def any_normal_to(axis):
    """The fallback direction of orifice_plate.h: the axis crossed with the
    first coordinate direction least parallel to it."""
    e = np.zeros(3)
    e[int(np.argmin(np.abs(axis)))] = 1.0
    return unit(np.cross(axis, e))


# ---------------------------------------------- brute force: plate with hole

def in_plane_distance(points, plate):
    offset = points - plate.centre
    height = offset @ plate.axis
    return np.linalg.norm(offset - np.multiply.outer(height, plate.axis), axis=-1)


def nearest_plate_point(point, plate):
    """(nearest point, distance): the foot on the plane over the plate, else
    the rim point in the direction of the point (any_normal_to on the axis)."""
    offset = point - plate.centre
    height = offset @ plate.axis
    in_plane = offset - height * plate.axis
    s = np.linalg.norm(in_plane)
    if s >= plate.hole_radius:
        nearest = point - height * plate.axis
    else:
        direction = in_plane / s if s > 0 else any_normal_to(plate.axis)
        nearest = plate.centre + plate.hole_radius * direction
    return nearest, float(np.linalg.norm(point - nearest))


def plate_distance(rod, plate, t):
    return nearest_plate_point(rod.core(t), plate)[1]


def plate_distances(rod, plate, ts):
    """plate_distance at each t of the array ts at once (the same rule as
    nearest_plate_point, in numpy over the points: the dense scan's values)."""
    points = rod.core(ts)
    offset = points - plate.centre
    height = offset @ plate.axis
    in_plane = offset - np.multiply.outer(height, plate.axis)
    s = np.linalg.norm(in_plane, axis=-1)
    over_plate = s >= plate.hole_radius
    with np.errstate(invalid="ignore", divide="ignore"):
        direction = np.where((s > 0)[:, None], in_plane / s[:, None], any_normal_to(plate.axis))
    nearest = np.where(over_plate[:, None], points - np.multiply.outer(height, plate.axis),
                       plate.centre + plate.hole_radius * direction)
    return np.linalg.norm(points - nearest, axis=-1)


def hole_piece(rod, plate):
    """The closed piece [begin, end] of the core over the hole, from the
    roots of s(t)^2 = R^2, or None."""
    h, radius = rod.half_length, plate.hole_radius
    offset = rod.centre - plate.centre
    u0 = offset - (offset @ plate.axis) * plate.axis
    w = rod.axis - (rod.axis @ plate.axis) * plate.axis
    if w @ w == 0.0:
        inside = u0 @ u0 < radius * radius
        return (-h, h) if inside else None
    roots = np.roots([w @ w, 2.0 * (u0 @ w), u0 @ u0 - radius * radius])
    if np.iscomplexobj(roots) or roots[0] == roots[1]:
        return None
    first, last = sorted(float(root) for root in roots)
    if not (first < h and last > -h):
        return None
    return max(first, -h), min(last, h)


def minima_by_scan(f, begin, end, samples=4001, f_many=None):
    """Local minima of f over the closed interval: the discrete minima of a
    dense scan (ends included), each refined by Brent's method on its
    bracket, an end kept when the refinement does no better. f_many(ts),
    if given, is f over an array at once (the scan's values; the
    refinement calls f)."""
    if begin == end:
        return [begin]
    scan = np.linspace(begin, end, samples)
    values = f_many(scan) if f_many is not None else np.array([f(t) for t in scan])
    lower_ok = np.ones(samples, dtype=bool)
    upper_ok = np.ones(samples, dtype=bool)
    lower_ok[1:] = values[1:] < values[:-1]
    upper_ok[:-1] = values[:-1] <= values[1:]
    minima = []
    for k in np.flatnonzero(lower_ok & upper_ok):
        k = int(k)
        bracket = (scan[max(k - 1, 0)], scan[min(k + 1, samples - 1)])
        refined = minimize_scalar(f, bounds=bracket, method="bounded", options={"xatol": 1e-14}).x
        if k in (0, samples - 1) and f(scan[k]) <= f(refined):
            refined = scan[k]
        minima.append(float(refined))
    return minima


def brute_force_plate_candidates(rod, plate):
    """The header's rule 8, from a scan: t of the segment ends over the plate
    and of the local minima of f over the closed piece over the hole (a
    minimum at a segment end over the plate being that end), penetrating or
    not."""
    piece = hole_piece(rod, plate)
    over_plate = [t for t in rod.ends()
                  if piece is None or not (piece[0] <= t <= piece[1])
                  or in_plane_distance(rod.core(t), plate) >= plate.hole_radius]
    candidates = list(over_plate)
    if piece is not None:
        for t in minima_by_scan(lambda t: plate_distance(rod, plate, t), *piece,
                                f_many=lambda ts: plate_distances(rod, plate, ts)):
            if not any(t == end for end in over_plate):
                candidates.append(t)
    return sorted(candidates)


def wall_contact_at(rod, plate, t):
    """The contact of rules 8 and 10 at core point t (penetrating or not)."""
    point = rod.core(t)
    nearest, distance = nearest_plate_point(point, plate)
    normal = (point - nearest) / distance if distance > 0 else plate.axis
    return WallContact(t, nearest, normal, rod.radius - distance)


def brute_force_plate_contacts(rod, plate):
    contacts = [wall_contact_at(rod, plate, t) for t in brute_force_plate_candidates(rod, plate)]
    return [contact for contact in contacts if contact.overlap > 0]


def assert_same_contacts(actual, expected, overlap=WALL_OVERLAP, position=WALL_POSITION,
                         normal=WALL_NORMAL):
    assert len(actual) == len(expected), (actual, expected)
    for got, want in zip(actual, expected):
        assert got.t == pytest.approx(want.t, abs=position)
        assert got.overlap == pytest.approx(want.overlap, abs=overlap)
        assert np.allclose(got.wall_point, want.wall_point, rtol=0, atol=position)
        assert np.allclose(got.normal, want.normal, rtol=0, atol=normal)


def assert_matches_brute_force(driver, rods, plate):
    for rod, contacts in zip(rods, driver.plate_contacts(rods, plate)):
        assert_same_contacts(contacts, brute_force_plate_contacts(rod, plate))


def assert_continuous(rods, steps, bound):
    """Over a scan of small changes of a rod, each contact continues one of
    the step before (core point, wall point and overlap within `bound`) or
    appears or disappears with an overlap below `bound`; the total overlap
    never changes by more than 2 `bound` per step."""
    for k in range(1, len(steps)):
        before, after = list(steps[k - 1]), steps[k]
        for contact in after:
            core = rods[k].core(contact.t)
            match = None
            for old in before:
                moved = max(np.linalg.norm(core - rods[k - 1].core(old.t)),
                            np.linalg.norm(contact.wall_point - old.wall_point),
                            abs(contact.overlap - old.overlap))
                if moved <= bound:
                    match = old
                    break
            if match is None:
                assert contact.overlap <= bound, f"step {k}: a contact appears at {contact}"
            else:
                before.remove(match)
        for old in before:
            assert old.overlap <= bound, f"step {k}: a contact disappears at {old}"
        total_change = sum(c.overlap for c in after) - sum(c.overlap for c in steps[k - 1])
        assert abs(total_change) <= 2 * bound, f"step {k}: total overlap jumps by {total_change}"


# ================================================================== tests
# ------------------------------------------------------- segment, segment

X, Y, Z = np.eye(3)


def test_segments_crossing_at_right_angles(driver):
    """Closed form: the common perpendicular of the x axis and a line along
    y through (0.3, -0.2, 0.5) joins (0.3, 0, 0) and (0.3, 0, 0.5)."""
    inside = (Rod([0, 0, 0], X, 1.0), Rod([0.3, -0.2, 0.5], Y, 1.0))
    beyond_an_end = (Rod([0, 0, 0], X, 1.0), Rod([2.0, -0.2, 0.5], Y, 1.0))
    [(t1, t2), (u1, u2)] = driver.closest_points([inside, beyond_an_end])
    assert (t1, t2) == pytest.approx((0.3, 0.2), abs=EXACT)
    assert driver_distance(*inside, t1, t2) == pytest.approx(0.5, abs=EXACT)
    # the foot falls beyond the end of rod 1: its end x = 1 and the foot on rod 2
    assert (u1, u2) == pytest.approx((1.0, 0.2), abs=EXACT)
    assert driver_distance(*beyond_an_end, u1, u2) == pytest.approx(math.hypot(1.0, 0.5), abs=EXACT)


SKEW_PAIRS = [
    (Rod([0.1, 0.2, 0.3], [1, 2, 0.5], 0.8), Rod([-0.4, 0.6, 0.9], [0.3, -1, 2], 1.1)),
    (Rod([0, 0, 0], [1, 0.1, 0], 0.5), Rod([0.2, 1.5, 0.1], [0.2, 1, 0.3], 0.4)),    # end to end
    (Rod([0, 0, 0], [1, 1, 1], 2.0), Rod([0.5, -0.5, 0.05], [1, -1, 0.2], 0.3)),    # crossing inside
    (Rod([1, 2, 3], [0.9, 0.1, -0.4], 0.01), Rod([1.3, 2.1, 2.7], [-0.2, 0.9, 0.1], 3.0)),
]


def test_skew_segments_match_brute_force(driver):
    for (rod1, rod2), (t1, t2) in zip(SKEW_PAIRS, driver.closest_points(SKEW_PAIRS)):
        b1, b2, distance = brute_force_closest(rod1, rod2)
        assert driver_distance(rod1, rod2, t1, t2) == pytest.approx(distance, abs=EXACT)
        assert (t1, t2) == pytest.approx((b1, b2), abs=1e-9)
        assert driver_distance(rod1, rod2, t1, t2) <= grid_least_distance(rod1, rod2) + EXACT


def test_parallel_overlapping_segments_meet_at_the_middle_of_the_overlap(driver):
    """Rod 1 covers x in [-2, 2], rod 2 x in [1.5, 3.5], 0.3 away: the
    overlap is [1.5, 2], its middle x = 1.75."""
    parallel = (Rod([0, 0, 0], X, 2.0), Rod([2.5, 0.3, 0], X, 1.0))
    antiparallel = (Rod([0, 0, 0], X, 2.0), Rod([2.5, 0.3, 0], -X, 1.0))
    [(t1, t2), (u1, u2)] = driver.closest_points([parallel, antiparallel])
    assert (t1, t2) == pytest.approx((1.75, -0.75), abs=EXACT)
    assert (u1, u2) == pytest.approx((1.75, 0.75), abs=EXACT)
    assert driver_distance(*parallel, t1, t2) == pytest.approx(0.3, abs=EXACT)


def test_parallel_disjoint_segments_meet_at_their_nearest_ends(driver):
    """Rod 2 covers x in [4, 6]: the ends x = 2 and x = 4."""
    parallel = (Rod([0, 0, 0], X, 2.0), Rod([5.0, 0.3, 0], X, 1.0))
    antiparallel = (Rod([0, 0, 0], X, 2.0), Rod([5.0, 0.3, 0], -X, 1.0))
    collinear = (Rod([0, 0, 0], X, 2.0), Rod([3.5, 0, 0], X, 1.0))
    touching = (Rod([0, 0, 0], X, 2.0), Rod([3.0, 0, 0], -X, 1.0))
    results = driver.closest_points([parallel, antiparallel, collinear, touching])
    assert results[0] == pytest.approx((2.0, -1.0), abs=EXACT)
    assert results[1] == pytest.approx((2.0, 1.0), abs=EXACT)
    assert results[2] == pytest.approx((2.0, -1.0), abs=EXACT)
    assert results[3] == pytest.approx((2.0, 1.0), abs=EXACT)
    assert driver_distance(*parallel, *results[0]) == pytest.approx(math.hypot(2.0, 0.3), abs=EXACT)
    assert driver_distance(*collinear, *results[2]) == pytest.approx(0.5, abs=EXACT)
    assert driver_distance(*touching, *results[3]) == pytest.approx(0.0, abs=EXACT)


def test_degenerate_segments(driver):
    """h = 0: a point against a segment is its projection, clamped; two
    points are themselves; a point on a parallel axis projects likewise."""
    point = Rod([0.5, 1.0, 0.0], Y, 0.0)
    segment = Rod([0, 0, 0], X, 1.0)
    beyond = Rod([3.0, 1.0, 0.0], [1, 1, 1], 0.0)
    other_point = Rod([1, 1, 1], Z, 0.0)
    on_parallel_axis = Rod([0.25, 0.5, 0.0], X, 0.0)
    results = driver.closest_points([(point, segment), (segment, point), (beyond, segment),
                                     (point, other_point), (on_parallel_axis, segment)])
    assert results[0] == pytest.approx((0.0, 0.5), abs=EXACT)
    assert results[1] == pytest.approx((0.5, 0.0), abs=EXACT)
    assert results[2] == pytest.approx((0.0, 1.0), abs=EXACT)
    assert results[3] == (0.0, 0.0)
    assert results[4] == pytest.approx((0.0, 0.25), abs=EXACT)


def random_rod(generator, radius=0.25, degenerate_fraction=0.1):
    half_length = 0.0 if generator.random() < degenerate_fraction else generator.uniform(0.05, 1.5)
    return Rod(generator.uniform(-1.5, 1.5, 3), generator.normal(size=3), half_length, radius)


def pairs_near_touching(seed, count=400):
    """Random pairs of rods with radii from 0.1 to 1.2: about half touch."""
    generator = np.random.default_rng(seed)
    pairs = []
    for _ in range(count):
        rod1, rod2 = random_rod(generator), random_rod(generator)
        rod1 = Rod(rod1.centre, rod1.axis, rod1.half_length, generator.uniform(0.1, 1.2))
        rod2 = Rod(rod2.centre, rod2.axis, rod2.half_length, generator.uniform(0.1, 1.2))
        pairs.append((rod1, rod2))
    return pairs


def test_the_quick_touch_test_agrees_with_brute_force(driver):
    """cores_within (the line-distance rejection, then the closest points)
    says two rods touch exactly when the brute-force distance of their
    cores is below the sum of the radii; pairs are drawn near touching
    (radii from 0.1 to 1.2), and both answers occur often."""
    pairs = pairs_near_touching(20261124)
    answers = driver.within(pairs)
    swapped = driver.within([(b, a) for a, b in pairs])
    assert answers == swapped
    touching = 0
    for (rod1, rod2), within in zip(pairs, answers):
        _, _, distance = brute_force_closest(rod1, rod2)
        reach = rod1.radius + rod2.radius
        if abs(distance - reach) > 1e-6:      # the brute force resolves the distance to ~1e-8
            assert within == (distance < reach)
        touching += within
    assert 80 < touching < 320


def test_rods_touching_is_the_touch_test_and_the_contact(driver):
    """rods_touching, the pair style's one call per listed pair, says two
    rods touch exactly when cores_within does and rod_contact's overlap is
    > 0, and then gives rod_contact's numbers to the last bit, in either
    order of the rods; among the pairs, parallel and antiparallel ones
    (rule 2) and cores that meet (rule 5)."""
    pairs = pairs_near_touching(20261125)
    for k in range(0, len(pairs), 10):     # every tenth pair (anti)parallel
        rod1, rod2 = pairs[k]
        axis = rod1.axis if k % 20 == 0 else -rod1.axis
        pairs[k] = (rod1, Rod(rod2.centre, axis, rod2.half_length, rod2.radius))
    crossing = Rod((0, 0, 0), X, 1.0, 0.3)
    pairs += [(crossing, Rod((0.2, 0, 0), Y, 1.0, 0.3)), (crossing, Rod((0.5, 0, 0), X, 0.5, 0.3))]
    touching_count = 0
    for ordered in (pairs, [(b, a) for a, b in pairs]):
        expected = driver.run([f"rod_contact {rod_words(a)} {rod_words(b)}" for a, b in ordered])
        within = driver.within(ordered)
        for numbers, inside, touching in zip(expected, within, driver.touching(ordered)):
            assert (touching is not None) == (inside and numbers[3] > 0.0)
            if touching is not None:
                assert touching == numbers
                touching_count += 1
    assert 200 < touching_count < 600


def best_edge_or_inside(rod1, rod2):
    """The least core distance over the stationary point (when inside
    both segments) and the four edges of the rectangle of (t1, t2), each
    an end of one segment and the nearest point of the other: the old
    search, against which the clamped projections are checked."""
    candidates = []
    for t1 in rod1.ends():
        candidates.append((t1, nearest_on_core(rod1.core(t1), rod2)))
    for t2 in rod2.ends():
        candidates.append((nearest_on_core(rod2.core(t2), rod1), t2))
    offset = rod1.centre - rod2.centre
    b, e1, e2 = rod1.axis @ rod2.axis, rod1.axis @ offset, rod2.axis @ offset
    if 1.0 - b * b > 1e-6:
        t1 = (b * e2 - e1) / (1.0 - b * b)
        t2 = e2 + b * t1
        if abs(t1) <= rod1.half_length and abs(t2) <= rod2.half_length:
            candidates.append((t1, t2))
    return min(driver_distance(rod1, rod2, t1, t2) for t1, t2 in candidates)


def test_the_clamped_projections_find_the_least_distance(driver):
    """Skew cores: the closest points (a clamp, a projection, at most one
    more clamp and projection) are as close as the best of the stationary
    point and the four edges, on 4000 random pairs (one in seven with the
    minimum inside, the others on an edge or at a corner)."""
    generator = np.random.default_rng(20261126)
    pairs = [(random_rod(generator, degenerate_fraction=0.0), random_rod(generator, degenerate_fraction=0.0))
             for _ in range(4000)]
    pairs = [(a, b) for a, b in pairs if np.linalg.norm(np.cross(a.axis, b.axis)) ** 2 > 1e-6]
    for (rod1, rod2), (t1, t2) in zip(pairs, driver.closest_points(pairs)):
        assert abs(t1) <= rod1.half_length and abs(t2) <= rod2.half_length
        assert driver_distance(rod1, rod2, t1, t2) == pytest.approx(best_edge_or_inside(rod1, rod2), abs=EXACT)


def test_random_segments_match_brute_force(driver):
    generator = np.random.default_rng(20240611)
    pairs = [(random_rod(generator), random_rod(generator)) for _ in range(300)]
    checked_points = 0
    for (rod1, rod2), (t1, t2) in zip(pairs, driver.closest_points(pairs)):
        b1, b2, distance = brute_force_closest(rod1, rod2)
        assert abs(t1) <= rod1.half_length and abs(t2) <= rod2.half_length
        assert driver_distance(rod1, rod2, t1, t2) == pytest.approx(distance, abs=RANDOM_DISTANCE)
        assert driver_distance(rod1, rod2, t1, t2) <= grid_least_distance(rod1, rod2, 101) + EXACT
        # the closest points are unique and well conditioned away from parallel
        if np.linalg.norm(np.cross(rod1.axis, rod2.axis)) ** 2 > 0.01:
            assert (t1, t2) == pytest.approx((b1, b2), abs=1e-7)
            checked_points += 1
    assert checked_points > 200


@pytest.mark.parametrize("angle", [1e-3, 1e-5, 1e-7, 3e-8, 1e-8, 3e-9, 1e-10, 1e-13, 0.0])
def test_nearly_parallel_segments(driver, angle):
    """Around the threshold angle of rule 2 (1e-8) the distance stays within
    2e-8 of the brute force, for overlapping, offset and crossing pairs."""
    axis = np.array([math.cos(angle), math.sin(angle) * 0.6, math.sin(angle) * 0.8])
    pairs = [(Rod([0, 0, 0], X, 1.0), Rod([0.7, 0.2, -0.1], axis, 1.2)),
             (Rod([0.1, 0, 0], X, 1.0), Rod([-0.4, 0.0, 0.05], -axis, 0.3)),
             (Rod([0, 0, 0], X, 1.0), Rod([2.5, 0.3, 0.0], axis, 1.0))]
    for (rod1, rod2), (t1, t2) in zip(pairs, driver.closest_points(pairs)):
        distance = brute_force_closest(rod1, rod2)[2]
        assert driver_distance(rod1, rod2, t1, t2) == pytest.approx(distance,
                                                                    abs=NEAR_PARALLEL_DISTANCE)


def pairs_to_swap():
    """Random pairs, the skew ones, and the special cases, radii 0.25 and 0.4."""
    generator = np.random.default_rng(7)
    pairs = [(random_rod(generator), random_rod(generator, radius=0.4)) for _ in range(100)]
    pairs += [(Rod(a.centre, a.axis, a.half_length), Rod(b.centre, b.axis, b.half_length, 0.4))
              for a, b in SKEW_PAIRS]
    pairs += [(Rod([0, 0, 0], X, 2.0), Rod([2.5, 0.3, 0], X, 1.0, 0.4)),     # parallel
              (Rod([0, 0, 0], X, 2.0), Rod([2.5, 0.3, 0], -X, 1.0, 0.4)),    # antiparallel
              (Rod([0, 0, 0], X, 1.0), Rod([0.5, 0, 0], X, 1.0, 0.4)),       # collinear, meeting
              (Rod([0, 0, 0], X, 1.0), Rod([0, 0, 0], Y, 1.0, 0.4))]         # crossing cores
    return pairs


def test_swapping_the_rods_swaps_the_results_exactly(driver):
    """Rule 3: bit for bit (tolerance 0), points, normal and contact point."""
    pairs = pairs_to_swap()
    forward = driver.closest_points(pairs)
    backward = driver.closest_points([(b, a) for a, b in pairs])
    assert all((t1, t2) == (u2, u1) for (t1, t2), (u1, u2) in zip(forward, backward))
    forward = driver.rod_contacts(pairs)
    backward = driver.rod_contacts([(b, a) for a, b in pairs])
    for one, other in zip(forward, backward):
        assert (one.t1, one.t2, one.distance, one.overlap) == (other.t2, other.t1, other.distance,
                                                               other.overlap)
        assert np.array_equal(one.separation, -other.separation)
        assert np.array_equal(one.normal, -other.normal)
        assert np.array_equal(one.point, other.point)


# ------------------------------------------------------------ rod contact

def test_rod_contact_of_crossing_rods(driver):
    """Rod 1 on the x axis, rod 2 along y at height 0.5: normal -z (from
    rod 2 down to rod 1), overlap r1 + r2 - 0.5, contact point in the middle
    of the overlap: r2 - overlap/2 below rod 2's core point."""
    rod1, rod2 = Rod([0, 0, 0], X, 1.0, 0.2), Rod([0.3, -0.2, 0.5], Y, 1.0, 0.35)
    [contact] = driver.rod_contacts([(rod1, rod2)])
    overlap = 0.2 + 0.35 - 0.5
    assert contact.distance == pytest.approx(0.5, abs=EXACT)
    assert contact.overlap == pytest.approx(overlap, abs=EXACT)
    assert np.allclose(contact.normal, -Z, atol=EXACT)
    assert np.allclose(contact.separation, [0, 0, -0.5], atol=EXACT)
    assert np.allclose(contact.point, [0.3, 0, 0.5 - (0.35 - overlap / 2)], atol=EXACT)
    assert np.allclose(contact.point, [0.3, 0, 0.2 - overlap / 2], atol=EXACT)


def test_spheres_follow_the_liggghts_convention(driver):
    """h = 0 on both: the contact of two spheres, normal (x1 - x2)/|x1 - x2|,
    contact point at r1 - overlap/2 from x1 towards x2."""
    x1, x2, r1, r2 = np.array([0.1, 0.2, 0.3]), np.array([0.5, -0.1, 0.6]), 0.3, 0.4
    [contact] = driver.rod_contacts([(Rod(x1, [1, 2, 3], 0.0, r1), Rod(x2, [0, 0, 1], 0.0, r2))])
    distance = float(np.linalg.norm(x1 - x2))
    normal = (x1 - x2) / distance
    overlap = r1 + r2 - distance
    assert (contact.t1, contact.t2) == (0.0, 0.0)
    assert contact.overlap == pytest.approx(overlap, abs=EXACT)
    assert np.allclose(contact.normal, normal, atol=EXACT)
    assert np.allclose(contact.point, x1 - (r1 - overlap / 2) * normal, atol=EXACT)


def test_normal_of_meeting_cores(driver):
    """Rule 5: crossing cores give a1 x a2; collinear overlapping cores the
    fallback normal of the rod that comes first (lexicographic centre):
    any_normal_to(x) = z for rod 1, whichever order they are passed in."""
    crossing = (Rod([0, 0, 0], X, 1.0), Rod([0.2, -0.3, 0], Y, 1.0))
    collinear = (Rod([0, 0, 0], X, 1.0), Rod([0.5, 0, 0], X, 1.0))
    contacts = driver.rod_contacts([crossing, crossing[::-1], collinear, collinear[::-1]])
    assert contacts[0].distance == 0.0 and np.allclose(contacts[0].normal, Z, atol=EXACT)
    assert np.allclose(contacts[1].normal, -Z, atol=EXACT)
    assert (contacts[2].t1, contacts[2].t2) == pytest.approx((0.25, -0.25), abs=EXACT)
    assert contacts[2].distance == 0.0 and contacts[2].overlap == pytest.approx(0.5, abs=EXACT)
    assert np.allclose(contacts[2].normal, any_normal_to(X), atol=EXACT)
    assert np.allclose(contacts[2].normal, Z, atol=EXACT)
    assert np.allclose(contacts[3].normal, -Z, atol=EXACT)


# ------------------------------------------------------------------ plane

PLANE_POINT, PLANE_NORMAL = np.array([0.0, 0.0, 0.0]), Z


def plane_expected(rod, t, point=PLANE_POINT, normal=PLANE_NORMAL):
    core = rod.core(t)
    height = float((core - point) @ normal)
    return WallContact(t, core - height * normal, normal, rod.radius - height)


def test_flat_rod_on_a_plane_has_two_equal_contacts(driver):
    rod = Rod([0.3, -0.2, 0.2], [1, 1, 0], 0.75)
    [contacts] = driver.plane_contacts([rod], PLANE_POINT, PLANE_NORMAL)
    assert_same_contacts(contacts, [plane_expected(rod, -0.75), plane_expected(rod, 0.75)], EXACT,
                         EXACT, EXACT)
    assert contacts[0].overlap == pytest.approx(0.05, abs=EXACT)
    assert contacts[0].overlap == contacts[1].overlap


def test_tilted_rods_on_a_plane(driver):
    """20 degrees: the lower end alone; 1 degree: both ends, the upper one
    less deep; the lower end 0.2 above the plane in both."""
    steep = Rod(np.array([0, 0, 0.2]) + 0.75 * tilted(20), tilted(20), 0.75)
    shallow = Rod(np.array([0, 0, 0.2]) + 0.75 * tilted(1), tilted(1), 0.75)
    [steep_contacts, shallow_contacts] = driver.plane_contacts([steep, shallow], PLANE_POINT,
                                                               PLANE_NORMAL)
    assert_same_contacts(steep_contacts, [plane_expected(steep, -0.75)], EXACT, EXACT, EXACT)
    assert_same_contacts(shallow_contacts, [plane_expected(shallow, -0.75),
                                            plane_expected(shallow, 0.75)], EXACT, EXACT, EXACT)
    assert shallow_contacts[1].overlap == pytest.approx(0.25 - 0.2 - 1.5 * math.sin(math.radians(1)),
                                                        abs=EXACT)


def test_upper_end_joins_continuously_as_a_rod_tips_down(driver):
    """Tipping about its lower end from 5 degrees to level, 0.01 degree a
    step: the upper end's contact appears with a vanishing overlap."""
    angles = np.linspace(5.0, 0.0, 501)
    rods = [Rod(np.array([0, 0, 0.2]) + 0.75 * tilted(a), tilted(a), 0.75) for a in angles]
    steps = driver.plane_contacts(rods, PLANE_POINT, PLANE_NORMAL)
    assert [len(contacts) for contacts in (steps[0], steps[-1])] == [1, 2]
    assert_continuous(rods, steps, bound=1.5 * math.radians(0.01) + 1e-12)


def test_vertical_rod_stands_on_its_cap(driver):
    rod = Rod([0.1, 0.2, 0.75 + 0.2], Z, 0.75)
    [contacts] = driver.plane_contacts([rod], PLANE_POINT, PLANE_NORMAL)
    assert_same_contacts(contacts, [WallContact(-0.75, np.array([0.1, 0.2, 0]), Z, 0.05)],
                         EXACT, EXACT, EXACT)


def test_sphere_on_a_tilted_plane(driver):
    """h = 0: one contact, the sphere's, on a plane of any orientation."""
    point, normal = np.array([0.3, -0.1, 0.2]), unit([0.2, -0.5, 1.0])
    along_plane = np.array([0.4, 0.1, 0.2]) - (np.array([0.4, 0.1, 0.2]) @ normal) * normal
    sphere = Rod(point + along_plane + 0.2 * normal, [1, 2, 3], 0.0)
    [contacts] = driver.plane_contacts([sphere], point, normal)
    assert_same_contacts(contacts, [plane_expected(sphere, 0.0, point, normal)], EXACT, EXACT, EXACT)
    assert contacts[0].overlap == pytest.approx(0.05, abs=EXACT)


def test_the_plane_is_one_sided(driver):
    """A rod behind the plane overlaps by more than its radius, pushed back
    along the plane's normal; one far in front does not touch."""
    behind, far = Rod([0, 0, -0.1], X, 0.5), Rod([0, 0, 0.3], X, 0.5)
    [behind_contacts, far_contacts] = driver.plane_contacts([behind, far], PLANE_POINT, PLANE_NORMAL)
    assert [c.overlap for c in behind_contacts] == pytest.approx([0.35, 0.35], abs=EXACT)
    assert all(np.array_equal(c.normal, Z) for c in behind_contacts)
    assert far_contacts == []


# --------------------------------------------------------------- cylinder

CYLINDER = Cylinder(np.array([0.0, 0.0, -1.0]), Z, 1.0)


def test_rod_touching_a_cylinder_with_one_end(driver):
    """Tilted 30 degrees, its upper end 0.8 from the axis, the lower one 0.5."""
    axis = tilted(30)
    rod = Rod(np.array([0.8, 0, 0.5]) - 0.75 * axis, axis, 0.75)
    [contacts] = driver.cylinder_contacts([rod], CYLINDER)
    upper = rod.core(0.75)
    assert_same_contacts(contacts, [WallContact(0.75, np.array([1.0, 0, upper[2]]), -X, 0.05)],
                         EXACT, EXACT, EXACT)


def test_horizontal_rods_in_a_vertical_cylinder_touch_with_both_ends(driver):
    """Across the axis, the ends 0.8 from it; along a chord 0.3 off the
    axis, the ends sqrt(0.75^2 + 0.3^2) from it; parallel to the axis, 0.8
    from it (a rod on the wall along its length)."""
    across = Rod([0, 0, 0.5], X, 0.8)
    chord = Rod([0, 0.3, 0.5], X, 0.75)
    upright = Rod([0, 0.8, 0.5], Z, 0.75)
    results = driver.cylinder_contacts([across, chord, upright], CYLINDER)
    assert_same_contacts(results[0], [WallContact(-0.8, np.array([-1.0, 0, 0.5]), X, 0.05),
                                      WallContact(0.8, np.array([1.0, 0, 0.5]), -X, 0.05)],
                         EXACT, EXACT, EXACT)
    s = math.hypot(0.75, 0.3)
    for contact, t in zip(results[1], [-0.75, 0.75]):
        outward = np.array([t, 0.3, 0.0]) / s
        assert contact.t == t
        assert contact.overlap == pytest.approx(0.25 - (1.0 - s), abs=EXACT)
        assert np.allclose(contact.normal, -outward, atol=EXACT)
        assert np.allclose(contact.wall_point, outward + [0, 0, 0.5], atol=EXACT)
    assert len(results[1]) == 2
    assert [c.overlap for c in results[2]] == pytest.approx([0.05, 0.05], abs=EXACT)
    assert [c.wall_point[2] for c in results[2]] == pytest.approx([-0.25, 1.25], abs=EXACT)


def test_sphere_and_rod_on_the_axis_of_a_cylinder(driver):
    """h = 0 gives one contact. A core point on the axis takes its wall
    point in the direction any_normal_to(axis) = y."""
    sphere = Rod([0.0, -0.9, 0.2], X, 0.0)
    on_axis = Rod([0.0, 0.0, 0.2], Z, 0.5, radius=1.1)
    results = driver.cylinder_contacts([sphere, on_axis], CYLINDER)
    assert_same_contacts(results[0], [WallContact(0.0, np.array([0, -1.0, 0.2]), Y, 0.15)],
                         EXACT, EXACT, EXACT)
    assert np.allclose(any_normal_to(Z), Y)
    assert_same_contacts(results[1], [WallContact(-0.5, np.array([0, 1.0, -0.3]), -Y, 0.1),
                                      WallContact(0.5, np.array([0, 1.0, 0.7]), -Y, 0.1)],
                         EXACT, EXACT, EXACT)


# ---------------------------------------------------------- plate with hole

PLATE = Plate(np.array([0.0, 0.0, 0.0]), Z, 1.0)
LEVEL_HEIGHT = 0.2            # a level rod of radius 0.25 at this height overlaps the plate by 0.05


def test_rod_across_the_hole_is_held_on_both_sides(driver):
    """Level, 0.3 off the axis, ends over the plate on both sides: its two
    ends and its two rim crossings (x = +-sqrt(1 - 0.3^2)), all 0.05 deep.
    Below the plate the same with the normal reversed (two-sided)."""
    above = Rod([0.2, 0.3, LEVEL_HEIGHT], X, 1.5)
    below = Rod([0.2, 0.3, -LEVEL_HEIGHT], X, 1.5)
    [contacts_above, contacts_below] = driver.plate_contacts([above, below], PLATE)
    crossing = math.sqrt(1.0 - 0.09)
    points = [(-1.3, 0.3), (-crossing, 0.3), (crossing, 0.3), (1.7, 0.3)]
    for contacts, normal in ((contacts_above, Z), (contacts_below, -Z)):
        expected = [WallContact(x - 0.2, np.array([x, y, 0.0]), normal, 0.05) for x, y in points]
        assert_same_contacts(contacts, expected, EXACT, EXACT, EXACT)
    assert_matches_brute_force(driver, [above, below], PLATE)


def test_level_rod_over_the_rim_rests_on_its_back_end_and_the_crossing(driver):
    """Back end at x = -2 over the plate, front end at x = -0.5 over the
    hole, crossing the rim at x = -1 (t = 0.25)."""
    rod = Rod([-1.25, 0, LEVEL_HEIGHT], X, 0.75)
    [contacts] = driver.plate_contacts([rod], PLATE)
    assert_same_contacts(contacts, [WallContact(-0.75, np.array([-2.0, 0, 0]), Z, 0.05),
                                    WallContact(0.25, np.array([-1.0, 0, 0]), Z, 0.05)],
                         EXACT, EXACT, EXACT)


def test_an_end_exactly_over_the_rim_counts_once(driver):
    """The back end at x = -1 exactly (s = R: over the plate, rule 8 (i)) is
    also the first point of the piece over the hole and its minimum there:
    one contact, not two."""
    rod = Rod([-0.25, 0, LEVEL_HEIGHT], X, 0.75)
    [contacts] = driver.plate_contacts([rod], PLATE)
    assert_same_contacts(contacts, [WallContact(-0.75, np.array([-1.0, 0, 0]), Z, 0.05)],
                         EXACT, EXACT, EXACT)
    assert_matches_brute_force(driver, [rod], PLATE)


def rod_tipped_about(pivot, pivot_t, degrees, half_length=0.75):
    """The rod whose core point at `pivot_t` stays at `pivot`, tilted
    `degrees` (front end up) in the xz plane."""
    axis = tilted(degrees)
    return Rod(np.array(pivot) - pivot_t * axis, axis, half_length)


TIP_ANGLES = np.linspace(-8.0, 8.0, 801)     # 0.02 degree a step
TIP_BOUND = 2e-3   # per step: the ends move 1.5 x 0.02 degree = 5e-4, the rim contact drifts


def test_tipping_over_the_rim_about_the_back_end(driver):
    """Back end held at x = -2: tipping back (front up) the crossing stays
    the piece's minimum with a continuously shrinking overlap, 0.05 -
    tan(angle) (the crossing is 1 from the back end), gone at tan = 0.05;
    tipping forward the contact moves continuously into the hole, on the
    rim point (-1, 0, 0). Every tenth step against brute force."""
    rods = [rod_tipped_about([-2.0, 0, LEVEL_HEIGHT], -0.75, a) for a in TIP_ANGLES]
    steps = driver.plate_contacts(rods, PLATE)
    assert_continuous(rods, steps, TIP_BOUND)
    for angle, rod, contacts in zip(TIP_ANGLES, rods, steps):
        back, rim = contacts[0], contacts[1:]
        assert back.t == -0.75 and back.overlap == pytest.approx(0.05, abs=EXACT)
        crossing_t = -0.75 + 1.0 / math.cos(math.radians(angle))
        rim_overlap = 0.05 - math.tan(math.radians(angle))
        if angle > 0 and rim_overlap > 0:
            assert len(rim) == 1 and rim[0].t == pytest.approx(crossing_t, abs=1e-12)
            assert rim[0].overlap == pytest.approx(rim_overlap, abs=EXACT)
        elif angle < 0:
            assert len(rim) == 1 and rim[0].t > crossing_t
            assert np.allclose(rim[0].wall_point, [-1.0, 0, 0], atol=EXACT)
        elif angle > 0:
            assert rim == []
    assert_matches_brute_force(driver, rods[::10], PLATE)


def test_seesaw_on_the_rim(driver):
    """Tipped about the core point over the rim (t = 0.25): tipping forward
    the back end lifts off continuously and the contact moves into the hole;
    tipping back the back end sinks and the crossing stays."""
    rods = [rod_tipped_about([-1.0, 0, LEVEL_HEIGHT], 0.25, a) for a in TIP_ANGLES]
    steps = driver.plate_contacts(rods, PLATE)
    assert_continuous(rods, steps, TIP_BOUND)
    counts = [len(contacts) for contacts in steps]
    assert counts[0] == 1 and counts[400] == 2 and counts[-1] == 2
    assert_matches_brute_force(driver, rods[::10], PLATE)


def test_slanted_rod_through_the_middle_of_the_hole_rests_on_both_sides(driver):
    """Core through the centre at 10 degrees: f^2 = (1 - x)^2 + x^2 tan^2
    on either side, least at x = +-cos^2 (t = +-cos), where f = sin: two
    minima inside the piece over the hole, on the kink of s at the axis."""
    angle = math.radians(10.0)
    rod = Rod([0, 0, 0], tilted(10.0), 1.5)
    [contacts] = driver.plate_contacts([rod], PLATE)
    expected = []
    for side in (-1, 1):
        t = side * math.cos(angle)
        core = rod.core(t)
        rim = np.array([side * 1.0, 0, 0])
        expected.append(WallContact(t, rim, unit(core - rim), 0.25 - math.sin(angle)))
    assert_same_contacts(contacts, expected, EXACT, 1e-10, 1e-9)
    off_axis = [Rod([0, offset, 0.02], tilted(10.0), 1.5) for offset in (1e-9, 1e-3, 0.05, 0.3)]
    assert_matches_brute_force(driver, [rod] + off_axis, PLATE)


def test_core_in_the_plane_of_the_plate_through_the_rim(driver):
    """Rule 10: a level core in the plate's plane: the back end and the rim
    crossing are at distance 0, overlap r, normal +axis."""
    rod = Rod([-1.25, 0, 0], X, 0.75)
    [contacts] = driver.plate_contacts([rod], PLATE)
    assert_same_contacts(contacts, [WallContact(-0.75, np.array([-2.0, 0, 0]), Z, 0.25),
                                    WallContact(0.25, np.array([-1.0, 0, 0]), Z, 0.25)],
                         EXACT, EXACT, EXACT)


def test_the_jumps_the_header_states_for_rule_8(driver):
    """Documents the limit stated in the header (change it with the rule):
    a piece over the plate is held at its two ends whatever its length.
    A level rod sliding sideways until its core line crosses the rim circle
    goes from its two ends to four contacts (plus the two crossings, 0.05
    deep at once); a level rod whose front end passes over the rim from
    the plate into the hole loses one of its two contacts there."""
    offsets = [1.0 + 1e-6, 1.0 - 1e-6]
    sliding = [Rod([0, offset, LEVEL_HEIGHT], X, 1.5) for offset in offsets]
    before, after = driver.plate_contacts(sliding, PLATE)
    assert [c.overlap for c in before] == pytest.approx([0.05] * 2, abs=EXACT)
    assert [c.overlap for c in after] == pytest.approx([0.05] * 4, abs=1e-9)
    front_end_x = [1.0 + 1e-6, 1.0 - 1e-6]
    passing = [Rod([x - 0.75, 0, LEVEL_HEIGHT], X, 0.75) for x in front_end_x]
    before, after = driver.plate_contacts(passing, PLATE)
    assert [c.t for c in before] == pytest.approx([0.75 - 1e-6, 0.75], abs=1e-12)
    assert [c.overlap for c in before] == pytest.approx([0.05] * 2, abs=EXACT)
    assert [c.t for c in after] == [0.75]
    assert after[0].overlap == pytest.approx(0.05, abs=1e-9)
    # (the chord over the hole of the sliding rod, 3e-3 long with f flat to
    # 1e-12 on it, is below what the brute force's scan resolves)
    assert_matches_brute_force(driver, passing, PLATE)


def test_vertical_rod_falls_through_a_wide_hole_untouched(driver):
    """R = 1 > r: on the axis (the edge case of rule 10) and 0.5 off it, at
    every height from 2 above to 2 below the plate."""
    heights = np.linspace(2.0, -2.0, 401)
    rods = [Rod([0, 0, z], Z, 0.75) for z in heights] + [Rod([0.5, 0, z], Z, 0.75) for z in heights]
    assert all(contacts == [] for contacts in driver.plate_contacts(rods, PLATE))


def test_vertical_rod_meets_the_rim_of_a_narrow_hole(driver):
    """R = 0.2 < r = 0.25 on the axis: one contact, on the rim point
    R any_normal_to(z) = (0, 0.2, 0), overlap r - sqrt(R^2 + z^2) with z the
    height of the core point nearest the plate, while that is below
    sqrt(r^2 - R^2) = 0.15."""
    plate = Plate(PLATE.centre, Z, 0.2)
    heights = np.linspace(1.205, -1.195, 241)    # never where the overlap is 0 (z = 0.9)
    rods = [Rod([0, 0, z], Z, 0.75) for z in heights]
    for z, rod, contacts in zip(heights, rods, driver.plate_contacts(rods, plate)):
        t = float(np.clip(-z, -0.75, 0.75))
        nearest_height = z + t
        overlap = 0.25 - math.hypot(0.2, nearest_height)
        if overlap <= 0:
            assert contacts == []
            continue
        rim = np.array([0, 0.2, 0])
        # the normal tilts by the error in t (1e-12 h) over the distance 0.2
        assert_same_contacts(contacts, [WallContact(t, rim, unit(rod.core(t) - rim), overlap)],
                             EXACT, EXACT, 1e-10)
    assert_matches_brute_force(driver, rods[::8], plate)


def test_sphere_equals_nearest_plate_point(driver):
    """h = 0: the contact of orifice_plate.h's nearest_plate_point for the
    same centre, bit for bit, and a single one; centres over the plate,
    over the hole, on the axis and exactly over the rim."""
    generator = np.random.default_rng(3)
    centres = [generator.uniform([-1.6, -1.6, -0.4], [1.6, 1.6, 0.4]) for _ in range(200)]
    centres += [np.array([0, 0, 0.1]), np.array([1.0, 0, 0.1]), np.array([0, -1.0, -0.2])]
    spheres = [Rod(centre, generator.normal(size=3), 0.0, radius=0.45) for centre in centres]
    touching = 0
    for sphere, contacts, (distance, to_plate, point) in zip(
            spheres, driver.plate_contacts(spheres, PLATE), driver.sphere_plate(centres, PLATE)):
        if 0.45 - distance <= 0:
            assert contacts == []
            continue
        touching += 1
        [contact] = contacts
        assert contact.t == 0.0
        assert contact.overlap == 0.45 - distance
        assert np.array_equal(contact.wall_point, point)
        assert np.array_equal(contact.normal, -to_plate / distance)
    assert touching > 50
    assert_matches_brute_force(driver, spheres[::4], PLATE)


def random_plate_rod(generator, hole_radius):
    """A rod near a plate whose centre is the origin and axis z: anywhere,
    nearly level (contacts on both sides, crossings), nearly upright
    (through the hole), or nearly level across the hole."""
    half_length = 0.0 if generator.random() < 0.1 else generator.uniform(0.1, 1.5)
    centre = generator.uniform([-1.8, -1.8, -0.5], [1.8, 1.8, 0.5])
    axis = generator.normal(size=3)
    shape = generator.random()
    if shape < 0.3:
        axis[2] *= 0.05
    elif shape < 0.4:
        axis[:2] *= 0.05
    elif shape < 0.5:
        axis[2] *= 0.01
        centre[:2] *= 0.5 * hole_radius / 1.8
        half_length = hole_radius + generator.uniform(0.0, 0.5)
    return Rod(centre, axis, half_length, generator.uniform(0.1, 0.6))


def on_plate(rod, plate):
    """The rod placed by random_plate_rod in the frame of `plate`."""
    e3 = plate.axis
    e1 = unit(np.cross(e3, [1.0, 0.0, 0.0] if abs(e3[0]) < 0.9 else [0.0, 1.0, 0.0]))
    frame = np.array([e1, np.cross(e3, e1), e3]).T
    return Rod(plate.centre + frame @ rod.centre, frame @ rod.axis, rod.half_length, rod.radius)


def test_random_rods_on_plates_match_brute_force(driver):
    """400 rods, hole radii 0.5-1.5: same contacts as the brute force.
    Cases where some candidate sits within 1e-7 of touching are left out
    (whether it counts is then a matter of round-off). The set must cover
    every kind of contact: ends, crossings, interior minima, two minima
    over the hole, four contacts."""
    generator = np.random.default_rng(11)
    kinds = {"end": 0, "crossing": 0, "interior": 0, "two over hole": 0, "four": 0}
    checked = 0
    for radius in (0.5, 1.0, 1.5):
        plate = Plate(generator.uniform(-0.2, 0.2, 3), unit(generator.normal(size=3) * [0.1, 0.1, 1]),
                      radius)
        rods = [on_plate(random_plate_rod(generator, radius), plate) for _ in range(134)]
        for rod, contacts in zip(rods, driver.plate_contacts(rods, plate)):
            candidates = [wall_contact_at(rod, plate, t)
                          for t in brute_force_plate_candidates(rod, plate)]
            if any(abs(c.overlap) < 1e-7 for c in candidates):
                continue
            expected = [c for c in candidates if c.overlap > 0]
            assert_same_contacts(contacts, expected)
            checked += 1
            piece = hole_piece(rod, plate)
            over_hole = [c for c in expected if piece and piece[0] <= c.t <= piece[1]
                         and c.t not in rod.ends()]
            kinds["end"] += sum(c.t in rod.ends() for c in expected)
            kinds["crossing"] += sum(c.t in piece for c in over_hole)
            kinds["interior"] += sum(c.t not in piece for c in over_hole)
            kinds["two over hole"] += len(over_hole) == 2
            kinds["four"] += len(expected) == 4
    assert checked > 350
    assert min(kinds.values()) >= 3, kinds


# -------------------------------------------------------- mass properties

def closed_form_mass_properties(diameter, length, density):
    """Cylinder of length H = L - d and radius r plus a sphere split in two
    hemispheres whose centres of mass sit H/2 + 3r/8 from the centre."""
    r, H = diameter / 2, length - diameter
    cylinder = density * math.pi * r ** 2 * H
    hemisphere = density * 2.0 / 3.0 * math.pi * r ** 3
    hemisphere_own = (2.0 / 5.0 - (3.0 / 8.0) ** 2) * hemisphere * r ** 2   # about its centre of mass
    arm = H / 2 + 3.0 * r / 8
    mass = cylinder + 2 * hemisphere
    axial = cylinder * r ** 2 / 2 + 2 * (2.0 / 5.0) * hemisphere * r ** 2
    transverse = cylinder * (r ** 2 / 4 + H ** 2 / 12) + 2 * (hemisphere_own + hemisphere * arm ** 2)
    return mass, axial, transverse


def sliced_mass_properties(diameter, length, density):
    """Quadrature over discs normal to the axis: a disc of radius a at x has
    mass rho pi a^2 dx, moment a^2/2 per mass about the axis and a^2/4 + x^2
    about a transverse axis through the centre."""
    r, H = diameter / 2, length - diameter

    def disc_radius_squared(x):
        beyond = max(abs(x) - H / 2, 0.0)
        return max(r * r - beyond * beyond, 0.0)

    def integral(per_mass):
        return quad(lambda x: density * math.pi * disc_radius_squared(x) * per_mass(x),
                    -length / 2, length / 2, points=[-H / 2, H / 2] if H > 0 else None,
                    epsabs=0, epsrel=1e-13, limit=200)[0]

    return (integral(lambda x: 1.0),
            integral(lambda x: disc_radius_squared(x) / 2),
            integral(lambda x: disc_radius_squared(x) / 4 + x * x))


def test_mass_properties_of_a_sphere(driver):
    """L = d: mass rho pi d^3/6, both moments 2/5 m r^2."""
    [(mass, axial, transverse)] = driver.mass([(0.004, 0.004, 2500.0)])
    sphere_mass = 2500.0 * math.pi * 0.004 ** 3 / 6
    assert mass == pytest.approx(sphere_mass, rel=1e-14)
    assert axial == pytest.approx(0.4 * sphere_mass * 0.002 ** 2, rel=1e-14)
    assert transverse == pytest.approx(axial, rel=1e-15)


@pytest.mark.parametrize("aspect", [1.0, 1.2, 2.0, 3.0, 6.0, 20.0])
def test_mass_properties_of_rods(driver, aspect):
    diameter, density = 0.003, 1150.0
    length = aspect * diameter
    [actual] = driver.mass([(diameter, length, density)])
    assert actual == pytest.approx(closed_form_mass_properties(diameter, length, density), rel=1e-12)
    assert actual == pytest.approx(sliced_mass_properties(diameter, length, density), rel=1e-10)
