"""rolling_friction jiang against a peer model, across MPI ranks and across a
restart.

(d) Peer check against stock `rolling_friction epsd3` (Ai et al. 2011,
    LIGGGHTS' rolling_model_epsd3.h). epsd3 is the same elastic-perfectly
    plastic rolling spring, parametrised differently:

        epsd3:  k_r = rollingStiffness k_n rmu^2 reff^2,  cap |F_n| reff rmu
        jiang:  k_r = a k_n l_c^2,                        cap b mu l_c f_el

    With a = b = 1, a fixed l_c, equal radii (so reff = r/2 for every
    grain-grain contact) and gamman = 0 (so |F_n| = k_n delta_n = f_el), the
    choice rmu = mu l_c / reff, rollingStiffness = 1/mu^2 makes both the
    stiffness and the cap identical. The two then agree to round-off only
    because of further conditions that this comparison deliberately meets:

    * epsd3 stores the spring *torque* and adds k_r omega dt each step, jiang
      stores the *angle* and multiplies by the current k_r. Identical while
      k_r is constant (hooke/stiffness with fixed l_c); for hertz (k_n grows
      with the overlap) or contactLengthFromOverlap (l_c changes) the two
      differ: a loaded jiang spring stiffens with the overlap, epsd3 keeps
      the torque it had.
    * epsd3 caps with the total normal force |F_n| including the normal
      dashpot (and any cohesion), jiang with the elastic part k_n delta_n
      only: they differ as soon as gamman > 0.
    * epsd3 does not turn its stored torque with the contact (no rotation
      into the current tangent plane, only the increment has its twisting
      part removed); jiang rotates the stored angle into the tangent plane,
      keeping its length. In 2D the stored vector is along z and the contact
      normal in the xy plane, so the rotation is the identity there: hence a
      2D comparison. In 3D they differ once contacts rotate.
    * epsd3 scales with reff = r_i r_j/(r_i + r_j), jiang uses an absolute
      l_c (or the overlap chord): with unequal radii one rmu cannot match one
      l_c for every pair.
    * a contact that opens and closes again between two neighbor-list
      builds: LIGGGHTS 3.8 keeps a pair's history until the next build
      (surfacesClose, which resets it, is only called for pairs within
      `neigh_modify contact_distance_factor` > 1), so epsd3 starts such a
      contact with its old torque, whereas jiang recognises it (the step
      stamp in its history) and starts unloaded. The pile therefore uses
      contact_distance_factor 1.01, which makes both reset on opening.
    * at a wall (fix wall/gran) epsd3 uses reff = r_i, twice the pair value
      for equal grains, so a single rmu cannot match jiang for pair and wall
      contacts at once: the comparison uses grain contacts only (the floor
      and sides are fixed grains).

    Cases: the held pair of test_jiang_held_pair.py (identical torque
    sequences, both l_c modes since the overlap is constant there) and some
    tens of discs colliding in a cup of fixed discs under gravity, compared
    over a run short enough for chaotic amplification of round-off to stay
    near 1e-11 (measured); a 1% error in k_r or in the cap deviates by 1e-4
    after 1000 steps, see test_peer_sensitivity_controls.

(e) MPI: the same kind of pile straddling the rank boundary x = 0
    (`processors * 1 1`), with contacts across the boundary and grains
    changing rank during the run, must reproduce the serial trajectory to
    1e-10 (positions relative to the diameter), both l_c modes, 2D and 3D
    (3D exercises the full three-component history and its rotation).

(f) Restart. How the history gets into the restart file (LIGGGHTS 3.8.0
    source): pair gran creates `fix contacthistory` (id and style
    "contacthistory", pair_gran.cpp init_style) holding every owned atom's
    partner tags and history values, ours included (jiang registers three
    values with newton flag 1 -> the partner's copy is negated,
    FixContactHistory::pre_exchange). The fix has restart_peratom = 1:
    write_restart stores partners and values per atom (pack_restart), and
    only dnum/maxtouch globally (write_restart; restart() refuses a file
    written with a different dnum, i.e. a different contact model). After
    read_restart the pair style must be given again (the model is not
    restored from the file); when it re-creates fix contacthistory with the
    same id and style, Modify::add_fix hands it the stored per-atom data
    (unpack_restart), and setup_pre_exchange leaves it alone because no
    pair compute has run yet. The property/global fixes, integrators and
    dumps are not in the file and are re-specified too.

    Held pair: restart in the middle of the elastic branch; the torque
    sequence afterwards (through saturation) must equal the uninterrupted
    run to 1e-12. Dynamic pile: the restarted run must equal a run that is
    split at the same step in one input (`run N` twice) to 1e-10.

    A restarted run continues an uninterrupted one exactly: the force call
    of a run's setup returns the torque of the stored angle without
    advancing it (as stock tangential history does), and a contact that
    opened since the last neighbor-list build restarts unloaded whether or
    not a run boundary (which rebuilds the lists) falls in between.
"""

import math

import numpy as np
import pytest

from analysis.common.lammps_io import read_dump
from conftest import has_mpirun
from analysis.common.deck_blocks import granular_setup, hooke_materials, per_pair

pytestmark = pytest.mark.engine   # runs the built LIGGGHTS (tools/test.sh --fast leaves it out)

RADIUS = 0.005
DIAMETER = 2 * RADIUS
KN = 1.0e5
KT = 0.4 * KN
MU = 0.5
DT = 1.0e-5
FIXED_LENGTH = 1.0e-3        # l_c = 0.1 d: rolling cap = 20% of mu f r
REFF = RADIUS / 2            # pair reff of two equal grains, used by epsd3
DENSITY = 2500

# held pair (as in test_jiang_held_pair.py): overlap 1e-4 m, each grain
# spins at OMEGA in opposite senses, relative rotation 2 OMEGA
HELD_DISTANCE = 0.0099
OMEGA = 10.0
OVERLAP_CHORD = 2 * math.sqrt(RADIUS ** 2 - (HELD_DISTANCE / 2) ** 2)

SEED = 20240601
PILE_Z_PERIOD = 3 * 0.0102  # 3D pile: three fixed layers 1.02 d apart, periodic


def gamman_for(damping_ratio, dimension):
    """hooke/stiffness gamman (a rate: the dashpot is meff*gamman) for the
    given fraction of critical damping between two equal grains. LIGGGHTS'
    `set density` gives a disc the mass pi r^2 rho in 2D."""
    mass = (math.pi * RADIUS ** 2 if dimension == 2 else 4 / 3 * math.pi * RADIUS ** 3) * DENSITY
    effective_mass = mass / 2
    return damping_ratio * 2 * math.sqrt(KN * effective_mass) / effective_mass


def epsd3_properties(contact_length, mu=MU):
    """property/global block that makes epsd3's k_r and cap equal jiang's
    for equal grains (reff = r/2) and gamman = 0 (see module docstring):
    rmu reff = mu l_c and rollingStiffness rmu^2 reff^2 = l_c^2."""
    rmu = mu * contact_length / REFF
    stiffness = 1.0 / mu ** 2   # 4 here: epsd3 insists on >= 1 in SI units
    return (per_pair("coefficientRollingFriction", rmu)
            + per_pair("coefficientRollingViscousDamping", 0.0)
            + f"fix m_rs all property/global rollingStiffness scalar {stiffness!r}\n")


# ---------------------------------------------------------------- decks

def held_pair_deck(rolling, properties, phases, restart_file=None, restart_after=None):
    """Two grains held in place (not integrated) spinning in opposite senses
    for each (steps, sign) in phases; optionally write_restart after phase
    number restart_after."""
    runs = []
    for k, (steps, sign) in enumerate(phases):
        runs.append(f"set atom 1 omegaz {sign * OMEGA}\nset atom 2 omegaz {-sign * OMEGA}\n"
                    f"run {steps}")
        if restart_after == k:
            runs.append(f"write_restart {restart_file}")
    return f"""
{granular_setup()}
region box block -0.02 0.03 -0.02 0.02 -0.02 0.02 units box
create_box 1 box
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {HELD_DISTANCE} 0 0 units box
set group all diameter {DIAMETER} density {DENSITY}
{held_pair_model(rolling, properties)}
{chr(10).join(runs)}
"""


def held_pair_model(rolling, properties):
    """Everything a restarted held-pair run has to specify again."""
    return f"""
neighbor 0.001 bin
neigh_modify delay 0
{hooke_materials(KN, KT, mu=MU)}
{properties}
pair_style gran model hooke/stiffness tangential history rolling_friction {rolling}
pair_coeff * *
timestep {DT}
dump torques all custom 1 dump.torque id tqx tqy tqz
dump_modify torques format "%d %.17g %.17g %.17g"
"""


def held_pair_restarted_deck(rolling, properties, restart_file, steps):
    return f"""
units si
atom_modify map array
read_restart {restart_file}
newton off
communicate single vel yes
{held_pair_model(rolling, properties)}
run {steps}
"""


def pile_layout(dimension, drift=0.0, seed=SEED):
    """A cup of fixed grains (a floor row and two side columns, 1% apart so
    that they do not touch) and 40 (2D) or 64 (3D) mobile grains on a loose
    lattice just above the floor, centred on x = 0, with random velocities
    (+-0.3 m/s, plus `drift` along x) and spins (+-30 rad/s). Returns
    (fixed, mobile) with mobile rows (position, velocity, omega), each a
    3-tuple."""
    rng = np.random.default_rng(seed)
    step = 1.01 * DIAMETER
    layers = [0.0] if dimension == 2 else [-0.0102, 0.0, 0.0102]
    fixed = []
    for z in layers:
        fixed += [(k * step, 0.0, z) for k in range(-6, 7)]
        fixed += [(side * 6 * step, k * step, z) for k in range(1, 7) for side in (-1, 1)]
    mobile_layers = [0.0] if dimension == 2 else [-0.0051, 0.0102]
    rows = 5 if dimension == 2 else 4
    mobile = []
    for z in mobile_layers:
        for j in range(rows):
            for i in range(8):
                x = (i - 3.5) * 1.05 * DIAMETER + rng.uniform(-2e-4, 2e-4)
                y = (j + 1) * 1.03 * DIAMETER
                velocity = (drift + rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3),
                            0.0 if dimension == 2 else rng.uniform(-0.3, 0.3))
                omega = ((0.0, 0.0) if dimension == 2 else
                         (rng.uniform(-30, 30), rng.uniform(-30, 30))) + (rng.uniform(-30, 30),)
                mobile.append(((x, y, z), velocity, omega))
    return fixed, mobile


def pile_model(rolling, properties, gamman, dimension, dump_every, neighbor_options=""):
    """Everything a restarted pile run has to specify again."""
    twod = "fix twod all enforce2d" if dimension == 2 else ""
    return f"""
neighbor 0.001 bin
neigh_modify delay 0 {neighbor_options}
{hooke_materials(KN, KT, gamman=gamman, mu=MU)}
{properties}
pair_style gran model hooke/stiffness tangential history rolling_friction {rolling}
pair_coeff * *
timestep {DT}
fix grav all gravity 9.81 vector 0 -1 0
fix integr mobile nve/sphere
{twod}
dump traj all custom {dump_every} dump.traj id x y z vx vy vz omegax omegay omegaz tqz
dump_modify traj format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
"""


def pile_header(dimension):
    # `processors * 1 1`: with 2 ranks the boundary between them is x = 0,
    # through the middle of the pile; with 1 rank it changes nothing
    half = PILE_Z_PERIOD / 2 if dimension == 3 else 0.005
    z = f"{-half!r} {half!r}"
    return f"""
{granular_setup(dimension=dimension, boundary="f f p")}
processors * 1 1
region box block -0.08 0.08 -0.01 0.1 {z} units box
"""


def pile_deck(rolling, properties, runs, gamman=0.0, dimension=2, drift=0.0, dump_every=100,
              restart_file=None, neighbor_options=""):
    """The pile, run for each entry of runs (several entries: the run is
    split in one input), then optionally write_restart."""
    fixed, mobile = pile_layout(dimension, drift)
    atoms = [f"create_atoms 1 single {x!r} {y!r} {z!r} units box" for x, y, z in fixed]
    atoms += [f"create_atoms 1 single {x!r} {y!r} {z!r} units box" for (x, y, z), _, _ in mobile]
    motion = [f"set atom {len(fixed) + k + 1} vx {v[0]!r} vy {v[1]!r} vz {v[2]!r} "
              f"omegax {w[0]!r} omegay {w[1]!r} omegaz {w[2]!r}"
              for k, (_, v, w) in enumerate(mobile)]
    tail = "\n".join(f"run {steps}" for steps in runs)
    if restart_file:
        tail += f"\nwrite_restart {restart_file}"
    return f"""{pile_header(dimension)}
create_box 1 box
{chr(10).join(atoms)}
set group all diameter {DIAMETER} density {DENSITY}
group fixed id <= {len(fixed)}
group mobile id > {len(fixed)}
{chr(10).join(motion)}
{pile_model(rolling, properties, gamman, dimension, dump_every, neighbor_options)}
thermo 1000
{tail}
"""


def pile_restarted_deck(rolling, properties, restart_file, steps, gamman=0.0, dimension=2,
                        dump_every=100):
    # box, atoms (x, v, omega, diameter, mass), groups and the contact
    # history come from the file; the rest is specified again
    return f"""
units si
atom_modify map array
processors * 1 1
read_restart {restart_file}
newton off
communicate single vel yes
{pile_model(rolling, properties, gamman, dimension, dump_every)}
thermo 1000
run {steps}
"""


# ---------------------------------------------------------------- analysis

def frames_by_step(path):
    """step -> columns; a step dumped twice (end of one run, setup of the
    next) keeps its first occurrence, the one of the step itself."""
    frames = {}
    for step, columns in read_dump(path):
        frames.setdefault(step, columns)
    return frames


def trajectory_deviation(a, b, steps=None):
    """Largest position difference over the common steps in units of the
    diameter, and largest omega difference relative to the largest |omega|
    of that frame."""
    common = sorted(set(a) & set(b) if steps is None else steps)
    assert common, "no common dump steps"
    position, omega = 0.0, 0.0
    for step in common:
        fa, fb = a[step], b[step]
        np.testing.assert_array_equal(fa["id"], fb["id"])
        position = max(position, max(np.abs(fa[c] - fb[c]).max() for c in ("x", "y", "z"))
                       / DIAMETER)
        scale = max(np.abs(fa[c]).max() for c in ("omegax", "omegay", "omegaz"))
        omega = max(omega, max(np.abs(fa[c] - fb[c]).max() for c in ("omegax", "omegay", "omegaz"))
                    / scale)
    return position, omega


def contact_pairs(columns, z_period=PILE_Z_PERIOD):
    """Index pairs (i < j) of grains closer than a diameter, nearest image
    in the periodic z direction."""
    xyz = np.stack([columns["x"], columns["y"], columns["z"]], axis=1)
    separation = xyz[:, None, :] - xyz[None, :, :]
    separation[..., 2] -= z_period * np.round(separation[..., 2] / z_period)
    distance = np.linalg.norm(separation, axis=2)
    i, j = np.triu_indices(len(xyz), 1)
    touching = distance[i, j] < DIAMETER
    return i[touching], j[touching]


def held_torques(path):
    frames = frames_by_step(path)
    steps = sorted(s for s in frames if s >= 1)
    return {s: frames[s]["tqz"][0] for s in steps}


# ---------------------------------------------------------------- (d) peers

@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_peer_epsd3_held_pair(run, tmp_path, mode):
    """Held pair: load through saturation, reverse, unload elastically; the
    torque sequences of jiang and the matched epsd3 coincide."""
    if mode == "fixed":
        jiang = ("jiang", per_pair("rollingContactLength", FIXED_LENGTH))
        length = FIXED_LENGTH
    else:
        # the overlap is constant, so a constant rmu matches the chord
        jiang = ("jiang contactLengthFromOverlap on", "")
        length = OVERLAP_CHORD
    stiffness = KN * length ** 2
    limit = MU * length * KN * (DIAMETER - HELD_DISTANCE)
    to_cap = limit / (stiffness * 2 * OMEGA * DT)     # 250 (fixed), 177 steps
    phases = [(int(1.6 * to_cap), 1), (int(1.2 * to_cap), -1)]
    run(held_pair_deck(*jiang, phases), subdir="jiang")
    run(held_pair_deck("epsd3", epsd3_properties(length), phases), subdir="epsd3")
    tj = held_torques(tmp_path / "jiang" / "dump.torque")
    te = held_torques(tmp_path / "epsd3" / "dump.torque")
    assert sorted(tj) == sorted(te) and len(tj) == sum(p[0] for p in phases)
    tj = np.array([tj[s] for s in sorted(tj)])
    te = np.array([te[s] for s in sorted(te)])
    # both regimes and the reversal occur ...
    assert np.isclose(tj.min(), -limit, rtol=1e-9)
    assert tj[-1] > 0
    # ... and the two laws agree to round-off (angle*k vs summed k*omega*dt)
    np.testing.assert_allclose(te, tj, rtol=0, atol=1e-12 * limit)


# The two differ by an ulp within the first few hundred steps (k_r*angle vs a
# sum of k_r*omega*dt); the pile amplifies that ~x10 per 2000 steps: 1e-14
# at 5000, 1e-12 d / 2e-11 (omega) at 10000 steps (0.1 s), 1e-10 d and 1e-9
# in omega at ~13000. Hence 10000 steps.
PEER_STEPS = 10000
PEER_TOLERANCE = 1e-9       # measured: 1.3e-12 d in positions, 3.6e-11 in omega


def peer_pile(run, tmp_path, name, rolling, properties):
    # contact_distance_factor: see the docstring, re-formed contacts
    run(pile_deck(rolling, properties, [PEER_STEPS],
                  neighbor_options="contact_distance_factor 1.01"), subdir=name)
    return frames_by_step(tmp_path / name / "dump.traj")


def test_peer_epsd3_pile(run, tmp_path):
    """40 discs, no normal damping, colliding in a cup of fixed discs: the
    jiang and the matched epsd3 trajectories agree to round-off."""
    jiang = peer_pile(run, tmp_path, "jiang", "jiang",
                      per_pair("rollingContactLength", FIXED_LENGTH))
    epsd3 = peer_pile(run, tmp_path, "epsd3", "epsd3", epsd3_properties(FIXED_LENGTH))
    assert sorted(jiang) == list(range(0, PEER_STEPS + 1, 100))
    # something happens: many grain contacts along the way
    contacts = [len(contact_pairs(jiang[s])[0]) for s in sorted(jiang)]
    assert max(contacts) >= 15 and np.mean(contacts) >= 10
    position, omega = trajectory_deviation(jiang, epsd3)
    print(f"jiang vs epsd3 over {PEER_STEPS} steps: positions {position:.2e} d, "
          f"omega {omega:.2e}")
    assert position < PEER_TOLERANCE
    assert omega < PEER_TOLERANCE


def test_peer_sensitivity_controls(run, tmp_path):
    """The comparison above can fail: 1% more rolling stiffness, or 1% more
    cap, moves the same pile far beyond PEER_TOLERANCE within 1000 steps,
    so both the elastic branch and the cap are exercised by the pile."""
    fixed = per_pair("rollingContactLength", FIXED_LENGTH)
    reference = peer_pile(run, tmp_path, "jiang", "jiang", fixed)
    steps = list(range(0, 1001, 100))
    for name, option in (("stiff", "rollingStiffnessFactor 1.01"),
                         ("cap", "rollingFrictionFactor 1.01")):
        other = peer_pile(run, tmp_path, name, f"jiang {option}", fixed)
        position, omega = trajectory_deviation(reference, other, steps)
        print(f"{option}: after 1000 steps positions {position:.2e} d, omega {omega:.2e}")
        # measured 4e-5 (cap) and 8e-5 d (k_r), 2e-3 in omega
        assert position > 1e3 * PEER_TOLERANCE
        assert omega > 1e3 * PEER_TOLERANCE


# ---------------------------------------------------------------- (e) MPI

# The trajectories are bit-identical for the first ~4000 steps; then the
# different order of summing forces on the two ranks leaves ulp differences
# that the pile amplifies ~x10 per 500 steps in 3D (just as much with
# rolling friction off): by 10000 steps 1e-9 d / 1e-7 in omega. Hence 5000.
MPI_STEPS = 5000
MPI_TOLERANCE = 1e-10       # measured: <= 2.5e-14 d and <= 1.1e-12 in omega


@pytest.mark.skipif(not has_mpirun(), reason="mpirun not available")
@pytest.mark.parametrize("dimension", [2, 3])
@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_two_ranks_reproduce_serial(run, tmp_path, mode, dimension):
    if mode == "fixed":
        rolling, properties = "jiang", per_pair("rollingContactLength", FIXED_LENGTH)
    else:
        rolling, properties = "jiang contactLengthFromOverlap on", ""
    # a strong normal dashpot (damping ratio 0.8, so f_el and |F_n| differ
    # much) lets the grains settle into a pile with lasting contacts; the
    # drift of 0.3 m/s to the right carries grains across the rank boundary
    deck = pile_deck(rolling, properties, [MPI_STEPS], gamman=gamman_for(0.8, dimension),
                     dimension=dimension, drift=0.3)
    run(deck, subdir="serial")
    output = run(deck, nprocs=2, subdir="parallel")
    assert "2 by 1 by 1 MPI processor grid" in output
    serial = frames_by_step(tmp_path / "serial" / "dump.traj")
    parallel = frames_by_step(tmp_path / "parallel" / "dump.traj")
    assert sorted(serial) == sorted(parallel) == list(range(0, MPI_STEPS + 1, 100))

    # the test means something: contacts across the rank boundary x = 0 in
    # most frames, and grains that change sides (hence ranks) during the run
    crossing_frames = 0
    for step in sorted(serial):
        i, j = contact_pairs(serial[step])
        x = serial[step]["x"]
        crossing_frames += np.any((x[i] < 0) != (x[j] < 0))
    sides = np.array([serial[s]["x"] < 0 for s in sorted(serial)])
    migrants = np.any(sides != sides[0], axis=0).sum()
    print(f"{dimension}D {mode}: {crossing_frames}/{len(serial)} frames with contacts "
          f"across x=0, {migrants} grains changed rank")
    assert crossing_frames > 0.6 * len(serial)     # measured 78-90%
    assert migrants >= 3                            # measured 5 (2D), 8 (3D)

    position, omega = trajectory_deviation(serial, parallel)
    print(f"np=2 vs np=1: positions {position:.2e} d, omega {omega:.2e}")
    assert position < MPI_TOLERANCE
    assert omega < MPI_TOLERANCE


# ---------------------------------------------------------------- (f) restart

@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_restart_held_pair_continues_torque_sequence(run, tmp_path, mode):
    """Restart with the rolling spring 60% loaded; the continuation goes on
    into saturation. Steps N+1..2N equal the uninterrupted run."""
    if mode == "fixed":
        rolling, properties = "jiang", per_pair("rollingContactLength", FIXED_LENGTH)
        length = FIXED_LENGTH
    else:
        rolling, properties = "jiang contactLengthFromOverlap on", ""
        length = OVERLAP_CHORD
    stiffness = KN * length ** 2
    limit = MU * length * KN * (DIAMETER - HELD_DISTANCE)
    to_cap = limit / (stiffness * 2 * OMEGA * DT)
    half = int(0.6 * to_cap)                      # 150 (fixed), 106 steps
    run(held_pair_deck(rolling, properties, [(2 * half, 1)]), subdir="whole")
    run(held_pair_deck(rolling, properties, [(half, 1)], restart_file="pair.restart",
                       restart_after=0), subdir="first")
    run(held_pair_restarted_deck(rolling, properties, "../first/pair.restart", half),
        subdir="second")
    whole = held_torques(tmp_path / "whole" / "dump.torque")
    first = held_torques(tmp_path / "first" / "dump.torque")
    second = held_torques(tmp_path / "second" / "dump.torque")

    # restart point: partly loaded, elastic (-k_r * 2 omega * dt * N)
    expected_at_restart = -stiffness * 2 * OMEGA * DT * half
    assert np.isclose(first[half], expected_at_restart, rtol=1e-9)
    assert -0.7 * limit < first[half] < -0.5 * limit
    # the continuation reaches the cap, so both branches follow the restart
    assert np.isclose(whole[2 * half], -limit, rtol=1e-9)

    # from the setup frame (step N) of the restarted run on: the setup call
    # returns the stored torque without advancing the spring
    later = range(half, 2 * half + 1)
    continued = np.array([second[s] for s in later])
    uninterrupted = np.array([whole[s] for s in later])
    # a lost history would restart from 0 and miss by 0.6 limit
    np.testing.assert_allclose(continued, uninterrupted, rtol=1e-12, atol=1e-15 * limit)
    np.testing.assert_allclose([first[s] for s in range(1, half + 1)],
                               [whole[s] for s in range(1, half + 1)], rtol=1e-12)


RESTART_STEPS = 2000        # N: restart after N, compare up to 2N
RESTART_TOLERANCE = 1e-10   # measured: bit-identical (0.0)


def restarted_pile(run, tmp_path, rolling, properties):
    run(pile_deck(rolling, properties, [RESTART_STEPS], restart_file="pile.restart"),
        subdir="first")
    run(pile_restarted_deck(rolling, properties, "../first/pile.restart", RESTART_STEPS),
        subdir="second")
    first = frames_by_step(tmp_path / "first" / "dump.traj")
    second = frames_by_step(tmp_path / "second" / "dump.traj")
    assert min(second) == RESTART_STEPS and max(second) == 2 * RESTART_STEPS
    # the restart file reproduces the state it was written from exactly
    assert trajectory_deviation(first, second, [RESTART_STEPS]) == (0.0, 0.0)
    return second


@pytest.mark.parametrize("mode", ["fixed", "overlap"])
def test_restart_pile_matches_split_run(run, tmp_path, mode):
    """The restarted pile continues exactly like the same run split in two
    `run` commands in one input (same setup call at step N): the contact
    histories (tangential and rolling) survive the restart file."""
    if mode == "fixed":
        rolling, properties = "jiang", per_pair("rollingContactLength", FIXED_LENGTH)
    else:
        rolling, properties = "jiang contactLengthFromOverlap on", ""
    restarted = restarted_pile(run, tmp_path, rolling, properties)
    run(pile_deck(rolling, properties, [RESTART_STEPS, RESTART_STEPS]), subdir="split")
    split = frames_by_step(tmp_path / "split" / "dump.traj")
    frames = [s for s in sorted(restarted) if s > RESTART_STEPS]
    # many loaded contacts at the restart point, so the histories matter
    assert len(contact_pairs(restarted[RESTART_STEPS])[0]) >= 10
    position, omega = trajectory_deviation(split, restarted, frames)
    print(f"restart vs split run: positions {position:.2e} d, omega {omega:.2e}")
    assert position < RESTART_TOLERANCE
    assert omega < RESTART_TOLERANCE


def test_restart_pile_without_rolling_matches_uninterrupted_run(run, tmp_path):
    """Control for the test below: with rolling friction off (and no
    dashpots) the restarted pile equals the uninterrupted run."""
    restarted = restarted_pile(run, tmp_path, "off", "")
    run(pile_deck("off", "", [2 * RESTART_STEPS]), subdir="whole")
    whole = frames_by_step(tmp_path / "whole" / "dump.traj")
    frames = [s for s in sorted(restarted) if s > RESTART_STEPS]
    position, omega = trajectory_deviation(whole, restarted, frames)
    assert position < RESTART_TOLERANCE
    assert omega < RESTART_TOLERANCE


def test_restart_pile_matches_uninterrupted_run(run, tmp_path):
    """The restarted jiang pile equals one uninterrupted `run 2N` (see the
    module docstring: setup force call, re-formed contacts)."""
    rolling, properties = "jiang", per_pair("rollingContactLength", FIXED_LENGTH)
    restarted = restarted_pile(run, tmp_path, rolling, properties)
    run(pile_deck(rolling, properties, [2 * RESTART_STEPS]), subdir="whole")
    whole = frames_by_step(tmp_path / "whole" / "dump.traj")
    frames = [s for s in sorted(restarted) if s > RESTART_STEPS]
    position, omega = trajectory_deviation(whole, restarted, frames)
    print(f"restart vs uninterrupted run: positions {position:.2e} d, omega {omega:.2e}")
    assert position < RESTART_TOLERANCE
    assert omega < RESTART_TOLERANCE
