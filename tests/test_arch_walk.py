"""The arch walk of fix clog (src_plugin/core/arch_walk.h) on hand-built
configurations, through a small driver compiled here with g++.

Geometry: discs of diameter 1 in the plane (horizontal, vertical); two
grains are in contact when their centres are 1 apart. The bottom of the
silo is a row of fixed (base) grains at height 0; the two rim grains of the
orifice stand at -2 and +2, 4 d apart as in the paper (R = 3). Each
configuration is built from chains of touching grains (a step of length 1
in a given direction, or the apex touching two grains), its contact list is
computed from the distances, and it is checked to have neither overlaps nor
near misses, so that the contacts are exactly the ones drawn. Expected
angles come from the construction (link directions) or from an
independent formula (interior angle by atan2 of cross and dot products,
reflex when the grain lies below the line of its neighbours), never from
the driver."""

import copy
import math
import random
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DRIVER_SOURCE = ROOT / "tests" / "arch_walk_driver.cpp"
RIM = 2.0                     # horizontal distance of the rim grains from the orifice centre
BASE_ROW_LENGTH = 4           # base grains on each side, from the rim outwards
TOUCH_TOLERANCE = 1e-9        # |distance - 1| below which two grains touch
NEAR_MISS = 1e-3              # no pair may be closer than this to touching without touching
ANGLE_TOLERANCE = 1e-9        # degrees
LENGTH_TOLERANCE = 1e-12


@pytest.fixture(scope="session")
def arch_walk(tmp_path_factory):
    """Compiles the driver once; returns run(silo) -> parsed driver output."""
    executable = tmp_path_factory.mktemp("arch_walk") / "arch_walk_driver"
    build = subprocess.run(
        ["g++", "-std=c++11", "-O1", "-Wall", "-Wextra", "-Werror", "-pedantic",
         f"-I{ROOT / 'src_plugin' / 'core'}", str(DRIVER_SOURCE), "-o", str(executable)],
        capture_output=True, text=True)
    if build.returncode != 0:
        pytest.fail(f"arch_walk_driver does not compile:\n{build.stderr}")

    def run(silo, contacts=None):
        result = subprocess.run([str(executable)], input=silo.driver_input(contacts),
                                capture_output=True, text=True, check=True, timeout=10)
        return parse_output(result.stdout)
    return run


def parse_output(text):
    fields = {}
    for line in text.splitlines():
        key, _, value = line.partition(" ")
        fields[key] = value
    return {
        "status": fields["status"],
        "reason": fields["reason"],
        "walk": [int(word) for word in fields["walk"].split()],
        "members": [int(word) for word in fields["members"].split()],
        "phi": [float(word) for word in fields["phi"].split()],
        "eta": int(fields["eta"]),
        "span": float(fields["span"]),
        # the two feet (rule 8), printed only when an arch is found
        "feet": [int(word) for word in fields.get("feet", "").split()],
        "foot_bases": [int(word) for word in fields.get("foot_bases", "").split()],
        "foot_phi": [float(word) for word in fields.get("foot_phi", "").split()],
        "foot_on_floor": [int(word) for word in fields.get("foot_on_floor", "").split()],
    }


# ---------------------------------------------------------------- geometry

def step(point, degrees):
    """The centre 1 away from `point` in the direction `degrees` (polar)."""
    return (point[0] + math.cos(math.radians(degrees)),
            point[1] + math.sin(math.radians(degrees)))


def apex(a, b):
    """The centre touching both a and b, on the left of the way from a to b
    (above it when a is left of b)."""
    half_x, half_y = (b[0] - a[0]) / 2, (b[1] - a[1]) / 2
    half = math.hypot(half_x, half_y)
    assert half <= 1.0, "the two grains are too far apart for a grain to touch both"
    rise = math.sqrt(1.0 - half * half) / half
    return (a[0] + half_x - rise * half_y, a[1] + half_y + rise * half_x)


def lower_side_angle(previous, at, following):
    """phi at `at` for a walk from `previous` to `following`, computed as the
    interior angle and made reflex when `at` lies below (right of) the line
    from `previous` to `following`."""
    u = (previous[0] - at[0], previous[1] - at[1])
    w = (following[0] - at[0], following[1] - at[1])
    interior = math.degrees(math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u[0] * w[0] + u[1] * w[1]))
    chord = (following[0] - previous[0], following[1] - previous[1])
    offset = (at[0] - previous[0], at[1] - previous[1])
    below = chord[0] * offset[1] - chord[1] * offset[0] < 0
    return 360.0 - interior if below else interior


class Silo:
    """Base rows on both sides of an orifice centred at 0, plus named free
    grains; ids count from 1 in the order grains are added."""

    def __init__(self, rim=RIM):
        self.grains = []      # [id, horizontal, vertical, base]
        self.ids = {}
        self.orifice_centre = 0.0
        for k in range(BASE_ROW_LENGTH):
            self.add(f"base_left_{k}", (-rim - k, 0.0), "left")
            self.add(f"base_right_{k}", (rim + k, 0.0), "right")
        self.rim_left = self.position("base_left_0")
        self.rim_right = self.position("base_right_0")

    def add(self, name, position, base="free"):
        grain_id = len(self.grains) + 1
        self.grains.append([grain_id, position[0], position[1], base])
        self.ids[name] = grain_id
        return position

    def position(self, name):
        grain = next(g for g in self.grains if g[0] == self.ids[name])
        return (grain[1], grain[2])

    def touching(self, name_a, name_b):
        a, b = self.position(name_a), self.position(name_b)
        return abs(math.hypot(a[0] - b[0], a[1] - b[1]) - 1.0) <= TOUCH_TOLERANCE

    def names(self, ids):
        by_id = {grain_id: name for name, grain_id in self.ids.items()}
        return [by_id[grain_id] for grain_id in ids]

    def contacts(self):
        """Index pairs of touching grains; fails on overlaps and near misses."""
        pairs = []
        for i, a in enumerate(self.grains):
            for j in range(i + 1, len(self.grains)):
                b = self.grains[j]
                gap = math.hypot(a[1] - b[1], a[2] - b[2]) - 1.0
                assert gap > -TOUCH_TOLERANCE, f"grains {a[0]} and {b[0]} overlap by {-gap}"
                assert not TOUCH_TOLERANCE < gap < NEAR_MISS, \
                    f"grains {a[0]} and {b[0]} nearly touch (gap {gap}): ambiguous configuration"
                if gap <= TOUCH_TOLERANCE:
                    pairs.append((i, j))
        return pairs

    def driver_input(self, contacts=None):
        contacts = self.contacts() if contacts is None else contacts
        lines = [f"orifice_centre {self.orifice_centre!r}", f"grains {len(self.grains)}"]
        lines += [f"{gid} {h!r} {v!r} {base}" for gid, h, v, base in self.grains]
        lines += [f"contacts {len(contacts)}"] + [f"{i} {j}" for i, j in contacts]
        return "\n".join(lines) + "\n"

    def expected_phi(self, walk_names, member_names):
        """phi of each member from its neighbours in the walk."""
        angles = []
        for name in member_names:
            k = walk_names.index(name)
            angles.append(lower_side_angle(*(self.position(n) for n in walk_names[k - 1:k + 2])))
        return angles

    def mirrored(self):
        """Left and right exchanged: horizontal -> -horizontal, base sides
        swapped, same ids and names."""
        mirror = copy.deepcopy(self)
        swap = {"left": "right", "right": "left", "free": "free"}
        mirror.grains = [[gid, -h, v, swap[base]] for gid, h, v, base in self.grains]
        mirror.orifice_centre = -self.orifice_centre
        mirror.rim_left = mirror.position("base_right_0")
        mirror.rim_right = mirror.position("base_left_0")
        return mirror


def assert_angles(actual, expected):
    assert len(actual) == len(expected)
    for got, want in zip(actual, expected):
        assert got == pytest.approx(want, abs=ANGLE_TOLERANCE)


# ---------------------------------------------------------- configurations

BETA_2 = math.degrees(math.acos(1.0 - math.cos(math.radians(70.0))))


def regular_arch():
    """Feet on the rim grains, 30 degrees from the top towards the orifice;
    four members on links rising at 70 and BETA_2 degrees, a level link,
    then falling symmetrically (cos 70 + cos BETA_2 = 1 closes the 3 d gap
    between the feet)."""
    silo = Silo()
    left_foot = silo.add("left_foot", step(silo.rim_left, 60.0))
    m1 = silo.add("m1", step(left_foot, 70.0))
    m2 = silo.add("m2", step(m1, BETA_2))
    m3 = silo.add("m3", step(m2, 0.0))
    m4 = silo.add("m4", step(m3, -BETA_2))
    right_foot = silo.add("right_foot", step(silo.rim_right, 120.0))
    closure = step(m4, -70.0)
    assert math.hypot(closure[0] - right_foot[0], closure[1] - right_foot[1]) < LENGTH_TOLERANCE
    return silo


def defect_arch():
    """Same feet; m1 high on a 80 degree link, m2 lower (link at -30), m3
    higher again (link at 25): m2 lies below the line m1-m3, a defect; m4
    closes onto the right foot."""
    silo = Silo()
    left_foot = silo.add("left_foot", step(silo.rim_left, 60.0))
    m1 = silo.add("m1", step(left_foot, 80.0))
    m2 = silo.add("m2", step(m1, -30.0))
    m3 = silo.add("m3", step(m2, 25.0))
    right_foot = step(silo.rim_right, 120.0)
    silo.add("m4", apex(m3, right_foot))
    silo.add("right_foot", right_foot)
    return silo


def pile_on_defect_arch():
    """The defect arch inside a pile: grains on the base beside the feet,
    one on them and the arch on the left, grains resting on the arch
    (one in the hollow above the defect), one on top of those, and a stray
    grain hanging from the left rim, nearer the orifice than the left foot
    but touching nothing else."""
    silo = defect_arch()
    position = silo.position
    height = math.sqrt(3.0) / 2.0
    left_side = silo.add("left_side", (-2.5, height))
    silo.add("left_side_outer", (-3.5, height))
    silo.add("right_side", (2.5, height))
    silo.add("right_side_outer", (3.5, height))
    silo.add("on_left_side_and_m1", apex(left_side, position("m1")))
    over_defect = silo.add("in_hollow_over_defect", apex(position("m1"), position("m2")))
    over_m3 = silo.add("on_m3_m4", apex(position("m3"), position("m4")))
    silo.add("on_top", apex(over_defect, over_m3))
    silo.add("stray", step(silo.rim_left, -30.0))
    return silo


DEFECT_WALK = ["left_foot", "m1", "m2", "m3", "m4", "right_foot"]
DEFECT_MEMBERS = ["m1", "m2", "m3", "m4"]


# ------------------------------------------------------------------- tests

def test_regular_arch(arch_walk):
    silo = regular_arch()
    arch = arch_walk(silo)
    assert arch["status"] == "found" and arch["reason"] == "-"
    assert silo.names(arch["walk"]) == ["left_foot", "m1", "m2", "m3", "m4", "right_foot"]
    assert silo.names(arch["members"]) == ["m1", "m2", "m3", "m4"]
    assert arch["eta"] == 4
    # from the link directions: phi = 180 - (rise before - rise after)
    end_angle = 180.0 - (70.0 - BETA_2)
    middle_angle = 180.0 - BETA_2
    assert_angles(arch["phi"], [end_angle, middle_angle, middle_angle, end_angle])
    assert all(angle < 180.0 for angle in arch["phi"])
    assert arch["span"] == pytest.approx(3.0 - 2.0 * math.cos(math.radians(70.0)), abs=1e-12)


def test_feet_of_a_regular_arch_rest_on_the_rim(arch_walk):
    """Rule 8: the feet are the grains the arch rests on, each given the
    angle of rule 7 with its rim grain as the missing neighbour. Here the
    feet stand on the rim grains 30 degrees towards the orifice from their
    tops, so they lean over the opening: the line from the rim grain's
    centre to the first member passes on their outer side, and their
    angles exceed 180 degrees."""
    silo = regular_arch()
    arch = arch_walk(silo)
    assert silo.names(arch["feet"]) == ["left_foot", "right_foot"]
    assert silo.names(arch["foot_bases"]) == ["base_left_0", "base_right_0"]
    position = silo.position
    expected = [lower_side_angle(position("base_left_0"), position("left_foot"), position("m1")),
                lower_side_angle(position("m4"), position("right_foot"), position("base_right_0"))]
    assert_angles(arch["foot_phi"], expected)
    # by construction: the link rim -> foot rises at 60 degrees, foot -> m1 at 70
    assert_angles(arch["foot_phi"], [180.0 + 70.0 - 60.0] * 2)
    # each foot touches its rim (outlet) grain only: not the floor
    assert arch["foot_on_floor"] == [0, 0]


def arch_with_a_foot_in_a_pocket():
    """The left foot sits in the pocket between the rim grain and the next
    base grain (touching both); the right foot stands on the rim grain."""
    silo = Silo()
    left_foot = silo.add("left_foot", apex(silo.position("base_left_1"), silo.rim_left))
    m1 = silo.add("m1", step(left_foot, 50.0))
    m2 = silo.add("m2", step(m1, 20.0))
    m3 = silo.add("m3", step(m2, -20.0))
    right_foot = step(silo.rim_right, 120.0)
    silo.add("m4", apex(m3, right_foot))
    silo.add("right_foot", right_foot)
    return silo


@pytest.mark.parametrize("mirror", [False, True], ids=["as_built", "mirrored"])
def test_a_foot_in_a_pocket_takes_the_base_grain_on_the_orifice_side(arch_walk, mirror):
    silo = arch_with_a_foot_in_a_pocket()
    assert silo.touching("left_foot", "base_left_0") and silo.touching("left_foot", "base_left_1")
    position = silo.position
    inner = lower_side_angle(position("base_left_0"), position("left_foot"), position("m1"))
    outer = lower_side_angle(position("base_left_1"), position("left_foot"), position("m1"))
    assert inner == pytest.approx(180.0 - 60.0 + 50.0 - 60.0, abs=ANGLE_TOLERANCE)   # 110
    assert outer == pytest.approx(inner + 60.0, abs=ANGLE_TOLERANCE)
    right = lower_side_angle(position("m4"), position("right_foot"), position("base_right_0"))
    feet, bases, phi = ["left_foot", "right_foot"], ["base_left_0", "base_right_0"], [inner, right]
    on_floor = [1, 0]     # the pocket foot also touches base_left_1, beyond the outlet grain
    if mirror:
        silo = silo.mirrored()
        feet, bases, phi = feet[::-1], bases[::-1], phi[::-1]   # names stay with their grains
        on_floor = on_floor[::-1]

    arch = arch_walk(silo)
    assert arch["status"] == "found" and arch["eta"] == 4
    assert silo.names(arch["feet"]) == feet
    assert silo.names(arch["foot_bases"]) == bases
    assert_angles(arch["foot_phi"], phi)
    assert arch["foot_on_floor"] == on_floor


def test_no_feet_without_an_arch(arch_walk):
    """Feet are printed (and recorded) only for a found arch."""
    silo = Silo()
    silo.add("alone_on_left_rim", step(silo.rim_left, 60.0))
    arch = arch_walk(silo)
    assert arch["status"] == "no_start"
    assert arch["feet"] == [] and arch["foot_phi"] == []


def test_arch_with_defect(arch_walk):
    silo = defect_arch()
    arch = arch_walk(silo)
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == DEFECT_WALK
    assert silo.names(arch["members"]) == DEFECT_MEMBERS
    assert arch["eta"] == 4
    # m1: links at 80 then -30; m2: links at -30 then 25
    assert_angles(arch["phi"][:2], [180.0 + (-30.0 - 80.0), 180.0 + (25.0 + 30.0)])
    assert_angles(arch["phi"], silo.expected_phi(DEFECT_WALK, DEFECT_MEMBERS))
    assert [angle > 180.0 for angle in arch["phi"]] == [False, True, False, False]


def test_walk_takes_the_lowest_line_of_a_pile(arch_walk):
    silo = pile_on_defect_arch()
    for pair in [("left_foot", "left_side"), ("m1", "on_left_side_and_m1"),
                 ("m1", "in_hollow_over_defect"), ("m2", "in_hollow_over_defect"),
                 ("m3", "on_m3_m4"), ("right_foot", "right_side"), ("stray", "base_left_0")]:
        assert silo.touching(*pair), pair

    arch = arch_walk(silo)
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == DEFECT_WALK
    assert silo.names(arch["members"]) == DEFECT_MEMBERS
    assert_angles(arch["phi"], silo.expected_phi(DEFECT_WALK, DEFECT_MEMBERS))


def last_member_right_of_its_foot():
    """The last member stands on the right foot a little to its right (the
    foot is 10 degrees left of straight below it), and a grain of the pile
    rests on it and on the grain beside the foot. Measured from straight
    down, the foot would come after that grain and the walk would climb
    into the pile; measured from the previous member it comes first."""
    silo = Silo()
    left_foot = silo.add("left_foot", step(silo.rim_left, 60.0))
    right_foot = silo.add("right_foot", step(silo.rim_right, 120.0))
    beside_foot = silo.add("beside_right_foot", (right_foot[0] + 1.0, right_foot[1]))
    last = step(right_foot, 80.0)
    m1 = silo.add("m1", step(left_foot, 70.0))
    m2 = silo.add("m2", step(m1, 25.0))
    silo.add("m3", apex(m2, last))
    silo.add("m4", last)
    silo.add("on_m4", apex(last, beside_foot))
    return silo


@pytest.mark.parametrize("mirror", [False, True], ids=["as_built", "mirrored"])
def test_foot_under_the_last_member_ends_the_walk(arch_walk, mirror):
    silo = last_member_right_of_its_foot()
    assert silo.touching("m4", "on_m4") and silo.touching("on_m4", "beside_right_foot")
    walk = ["left_foot", "m1", "m2", "m3", "m4", "right_foot"]
    members = ["m1", "m2", "m3", "m4"]
    phi = silo.expected_phi(walk, members)
    if mirror:
        silo, walk, members, phi = silo.mirrored(), walk[::-1], members[::-1], phi[::-1]

    arch = arch_walk(silo)
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == walk
    assert silo.names(arch["members"]) == members
    assert_angles(arch["phi"], phi)


def test_grains_touching_the_base_are_not_members(arch_walk):
    """Left: a grain wedged against the inner side of the rim grain, nearer
    the orifice than anything else on the left base, so the walk starts
    there; its only free neighbour is the real foot of the arch, which
    also rests on the rim. Both touch the base: neither is a member, even
    though the wedged grain sits over the opening. Right: the walk ends at
    the first grain that touches the right base; the grain beside it on
    the base is never visited."""
    silo = Silo()
    wedged = silo.add("wedged", step(silo.rim_left, 10.0))
    foot = silo.add("foot", apex(silo.rim_left, wedged))
    m1 = silo.add("m1", step(foot, 70.0))
    m2 = silo.add("m2", step(m1, 30.0))
    m3 = silo.add("m3", step(m2, -15.0))
    right_foot = step(silo.rim_right, 120.0)
    silo.add("m4", apex(m3, right_foot))
    silo.add("right_foot", right_foot)
    silo.add("beside_right_foot", (right_foot[0] + 1.0, right_foot[1]))
    walk = ["wedged", "foot", "m1", "m2", "m3", "m4", "right_foot"]
    members = ["m1", "m2", "m3", "m4"]

    arch = arch_walk(silo)
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == walk
    assert silo.names(arch["members"]) == members
    assert_angles(arch["phi"], silo.expected_phi(walk, members))


def test_grains_before_the_last_left_base_contact_are_cut(arch_walk):
    """The walk starts at a wedged grain, climbs to a grain resting on it
    (not on the base), then has nowhere to go but down-left to the real foot
    on the rim: everything up to that foot is the base side, not the arch."""
    silo = Silo()
    wedged = silo.add("wedged", step(silo.rim_left, 10.0))
    pocket = silo.add("pocket", step(wedged, 100.0))
    foot = silo.add("foot", apex(silo.rim_left, pocket))
    m1 = silo.add("m1", step(foot, 100.0))
    m2 = silo.add("m2", step(m1, 20.0))
    m3 = silo.add("m3", step(m2, 0.0))
    m4 = silo.add("m4", step(m3, -20.0))
    right_foot = step(silo.rim_right, 120.0)
    silo.add("m5", apex(m4, right_foot))
    silo.add("right_foot", right_foot)
    walk = ["wedged", "pocket", "foot", "m1", "m2", "m3", "m4", "m5", "right_foot"]
    members = ["m1", "m2", "m3", "m4", "m5"]

    arch = arch_walk(silo)
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == walk
    assert silo.names(arch["members"]) == members
    assert arch["eta"] == 5
    assert_angles(arch["phi"], silo.expected_phi(walk, members))


def test_gap_over_the_orifice_is_no_arch(arch_walk):
    """Two leaning chains from the feet whose tops miss each other by 0.32 d."""
    silo = Silo()
    left_foot = silo.add("left_foot", step(silo.rim_left, 60.0))
    m1 = silo.add("m1", step(left_foot, 70.0))
    silo.add("m2", step(m1, 60.0))
    right_foot = silo.add("right_foot", step(silo.rim_right, 120.0))
    n1 = silo.add("n1", step(right_foot, 110.0))
    silo.add("n2", step(n1, 120.0))

    arch = arch_walk(silo)
    assert arch["status"] == "dead_end"
    assert silo.names(arch["walk"]) == ["left_foot", "m1", "m2"]
    assert f"grain id {silo.ids['m2']}" in arch["reason"]
    assert arch["members"] == [] and arch["eta"] == 0 and arch["span"] == 0.0


def test_nothing_to_depart_from_on_the_left_is_no_arch(arch_walk):
    """A chain leans on the right rim; on the left rim a grain rests alone."""
    silo = Silo()
    right_foot = silo.add("right_foot", step(silo.rim_right, 120.0))
    silo.add("n1", step(right_foot, 110.0))
    silo.add("alone_on_left_rim", step(silo.rim_left, 60.0))
    arch = arch_walk(silo)
    assert arch["status"] == "no_start"
    assert arch["walk"] == [] and arch["eta"] == 0


def test_feet_that_touch_each_other_leave_no_member(arch_walk):
    """Rims 2 d apart: the two feet close the orifice alone; the grain on
    top of them is above the lowest line and not reached."""
    silo = Silo(rim=1.0)
    left_foot = silo.add("left_foot", step(silo.rim_left, 60.0))
    right_foot = silo.add("right_foot", step(silo.rim_right, 120.0))
    silo.add("on_top", apex(left_foot, right_foot))
    arch = arch_walk(silo)
    assert arch["status"] == "no_member"
    assert silo.names(arch["walk"]) == ["left_foot", "right_foot"]
    assert arch["eta"] == 0


def test_contact_index_out_of_range_is_reported(arch_walk):
    silo = regular_arch()
    arch = arch_walk(silo, silo.contacts() + [(0, len(silo.grains))])
    assert arch["status"] == "bad_contact"
    assert str(len(silo.grains)) in arch["reason"]


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5])
def test_order_of_grains_and_contacts_does_not_matter(arch_walk, seed):
    """Grains in another order (as gathered from MPI ranks), contacts
    shuffled, each written either way round, some twice, one grain listed
    as touching itself."""
    silo = pile_on_defect_arch()
    generator = random.Random(seed)
    order = list(range(len(silo.grains)))
    generator.shuffle(order)
    new_index = {old: new for new, old in enumerate(order)}
    contacts = [(new_index[i], new_index[j]) for i, j in silo.contacts()]
    contacts += generator.sample(contacts, 5) + [(0, 0)]
    contacts = [pair if generator.random() < 0.5 else pair[::-1] for pair in contacts]
    generator.shuffle(contacts)
    silo.grains = [silo.grains[old] for old in order]

    arch = arch_walk(silo, contacts)
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == DEFECT_WALK
    assert silo.names(arch["members"]) == DEFECT_MEMBERS
    assert_angles(arch["phi"], silo.expected_phi(DEFECT_WALK, DEFECT_MEMBERS))


def test_mirrored_pile_gives_the_mirrored_arch(arch_walk):
    silo = pile_on_defect_arch()
    arch = arch_walk(silo.mirrored())
    assert arch["status"] == "found"
    assert silo.names(arch["walk"]) == DEFECT_WALK[::-1]
    assert silo.names(arch["members"]) == DEFECT_MEMBERS[::-1]
    assert arch["eta"] == 4
    assert_angles(arch["phi"], silo.expected_phi(DEFECT_WALK, DEFECT_MEMBERS)[::-1])
    span = silo.position("m4")[0] - silo.position("m1")[0]
    assert arch["span"] == pytest.approx(span, abs=1e-12)
