#!/usr/bin/python3
"""Accuracy against cost of `rolling_friction jiang` at time steps
dt/t_c = 1/200, 1/100, 1/50, 1/20, 1/10, with t_c = pi sqrt(m_eff/k_n) the
contact duration of the undamped linear spring, on three checks, each with
the fixed contact length (l_c = 0.05 d) and with l_c from the overlap:

(a) two held spheres spun in opposite senses (the held-pair test): the
    torque against the continuous-time eq. 1, at every step and at fixed
    physical times;
(b) the paper's Fig. 2 case: a disc resting on one fixed disc, 1.5 deg off
    the vertical, with rolling damping: residual of the static balance
    k_r delta_r = m g r_c sin(theta) at the end, and the final angle;
(c) a sphere rolling on a flat wall: measured deceleration against
    a = M / (r_c (m + I/r_c^2)), M = mu l_c m g.

The cost is LIGGGHTS' loop time of each run (one or two grains: mostly
fixed overhead per step, so it shows how the step count grows, nothing
about the contact law's own cost; that is bench/rolling_cost.py).

Writes its section of doc/accuracy_cost_rolling.md and
bench/results/rolling_accuracy.txt.

    /usr/bin/python3 bench/rolling_accuracy.py            # all five dt, ~1-2 min
    /usr/bin/python3 bench/rolling_accuracy.py --quick    # dt/t_c = 1/20, 1/10 only
"""

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import benchlib  # noqa: E402
import core_geometry  # noqa: E402

sys.path.insert(0, str(benchlib.ROOT))
from analysis.common.deck_blocks import granular_setup  # noqa: E402
from analysis.common.lammps_io import read_dump  # noqa: E402
from analysis.common.tables import read_table  # noqa: E402

DT_FRACTIONS = [200, 100, 50, 20, 10]        # t_c / dt
MODES = ["fixed", "overlap"]
DIAMETER = 0.01
RADIUS = DIAMETER / 2
DENSITY = 2500.0
KN = 1.0e5
KT = 2.0 / 7.0 * KN
MU = 0.5
GRAVITY = 9.81
FIXED_LENGTH = 0.05 * DIAMETER

SPHERE_MASS = 4.0 / 3.0 * math.pi * RADIUS ** 3 * DENSITY
DISC_MASS = math.pi * RADIUS ** 2 * DENSITY      # LIGGGHTS' 2D mass


def contact_time(effective_mass):
    return math.pi * math.sqrt(effective_mass / KN)


def materials(gamman, gammat, mode, rolling_damping=None):
    lines = [f"fix m_kn all property/global kn peratomtypepair 1 {KN!r}",
             f"fix m_kt all property/global kt peratomtypepair 1 {KT!r}",
             f"fix m_gn all property/global gamman peratomtypepair 1 {gamman!r}",
             f"fix m_gt all property/global gammat peratomtypepair 1 {gammat!r}",
             f"fix m_mu all property/global coefficientFriction peratomtypepair 1 {MU!r}"]
    if mode == "fixed":
        lines.append(f"fix m_lc all property/global rollingContactLength peratomtypepair 1 "
                     f"{FIXED_LENGTH!r}")
    if rolling_damping is not None:
        lines.append(f"fix m_rd all property/global coefficientRollingViscousDamping "
                     f"peratomtypepair 1 {rolling_damping!r}")
    return "\n".join(lines) + "\n"


def rolling_keywords(mode, damping=False):
    words = "rolling_friction jiang"
    if mode == "overlap":
        words += " contactLengthFromOverlap on"
    if damping:
        words += " rollingDamping on"
    return words


RECORD = "  # record"


def run_recorded_and_timed(deck, workdir):
    """Runs the deck as it is, for the measurement, then once more without
    its recording commands (lines ending in RECORD), for the cost: the loop
    time of the second run, summed over its runs."""
    result = benchlib.run_deck(deck, workdir)
    bare = "\n".join(line for line in deck.splitlines() if not line.endswith(RECORD))
    timing = benchlib.run_deck(bare, workdir / "timing")
    return result, sum(loop[0] for loop in timing["loops"])


# ---------------------------------------------------------------- (a) held pair

HELD_DISTANCE = 0.0099          # overlap 1e-4 m
HELD_OMEGA = 10.0               # rad/s each, relative rotation 2 omega
HELD_SAMPLES = 37               # fixed physical times compared


def held_pair(mode, fraction, workdir):
    t_c = contact_time(SPHERE_MASS / 2)
    dt = t_c / fraction
    elastic_force = KN * (DIAMETER - HELD_DISTANCE)
    length = FIXED_LENGTH if mode == "fixed" else core_geometry.overlap_chord(RADIUS, RADIUS, HELD_DISTANCE)
    stiffness = KN * length ** 2
    cap = MU * length * elastic_force
    rate = 2 * HELD_OMEGA
    time_to_cap = cap / (stiffness * rate)
    # phase lengths in whole steps of the coarsest dt (t_c/10), so that every
    # dt reverses the spin at the same physical time
    coarse = t_c / 10
    load_time = round(1.6 * time_to_cap / coarse) * coarse
    unload_time = round(1.2 * time_to_cap / coarse) * coarse
    load_steps = round(load_time / dt)
    unload_steps = round(unload_time / dt)
    deck = f"""{granular_setup()}
region box block -0.02 0.03 -0.02 0.02 -0.02 0.02 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
{materials(0.0, 0.0, mode)}
pair_style gran model hooke/stiffness tangential history {rolling_keywords(mode)}
pair_coeff * *
timestep {dt!r}
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {HELD_DISTANCE!r} 0 0 units box
set group all diameter {DIAMETER!r} density {DENSITY!r}
set atom 1 omegaz {HELD_OMEGA!r}
set atom 2 omegaz {-HELD_OMEGA!r}
dump torques all custom 1 dump.torque id tqz  # record
dump_modify torques format "%d %.17g"  # record
run {load_steps}
set atom 1 omegaz {-HELD_OMEGA!r}
set atom 2 omegaz {HELD_OMEGA!r}
run {unload_steps}
"""
    result, loop = run_recorded_and_timed(deck, workdir)
    by_step = {}
    for step, columns in read_dump(workdir / "dump.torque"):
        by_step.setdefault(step, columns["tqz"][0])   # first dump of a step: the run's own
    steps = np.arange(0, load_steps + unload_steps + 1)
    measured = np.array([0.0] + [by_step[s] for s in steps[1:]])
    times = steps * dt

    def exact(t):
        loading = np.minimum(rate * t, cap / stiffness)
        at_reversal = min(rate * load_time, cap / stiffness)
        unloading = np.maximum(at_reversal - rate * (t - load_time), -cap / stiffness)
        return -stiffness * np.where(t <= load_time, loading, unloading)

    at_steps = np.max(np.abs(measured - exact(times))) / cap
    # evenly spaced times, and the onset of saturation: the one instant at
    # which the exact torque has a kink between two steps
    samples = np.append(np.linspace(0, load_time + unload_time, HELD_SAMPLES + 1)[1:],
                        time_to_cap)
    at_times = np.max(np.abs(np.interp(samples, times, measured) - exact(samples))) / cap
    return {"dt": dt, "t_c": t_c, "error_steps": at_steps, "error_times": at_times,
            "loop": loop,
            "steps": load_steps + unload_steps, "time_to_cap": time_to_cap,
            "cap": cap}


# ---------------------------------------------------------------- (b) Fig. 2

FIG2_ANGLE = 1.5                # deg from the vertical
FIG2_TIME = 1.0                 # s simulated
FIG2_GAMMAN = 2000.0            # per unit m_eff (as in examples/demo/in.demo)
FIG2_GAMMAT = 1000.0
FIG2_ROLLING_DAMPING = 0.5


def fig2(mode, fraction, workdir):
    t_c = contact_time(DISC_MASS)          # the base does not move: m_eff = m
    dt = t_c / fraction
    steps = round(FIG2_TIME / dt)
    angle = math.radians(FIG2_ANGLE)
    deck = f"""{granular_setup(dimension=2, boundary="f f p")}
region box block -0.03 0.03 -0.02 0.03 -0.005 0.005 units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{materials(FIG2_GAMMAN, FIG2_GAMMAT, mode, FIG2_ROLLING_DAMPING)}
pair_style gran model hooke/stiffness tangential history {rolling_keywords(mode, damping=True)}
pair_coeff * *
timestep {dt!r}
create_atoms 1 single 0 0 0 units box
create_atoms 1 single {0.999 * DIAMETER * math.sin(angle)!r} {0.999 * DIAMETER * math.cos(angle)!r} 0 units box
set group all diameter {DIAMETER!r} density {DENSITY!r}
group top id 2
fix gravity all gravity {GRAVITY!r} vector 0 -1 0
fix integrate top nve/sphere
fix twod all enforce2d
compute contacts all pair/gran/local id history
variable angle equal atan2(x[2]-x[1],y[2]-y[1])*180/PI
fix record all print {fraction // 10} "${{angle}}" file angle.txt screen no title "# angle"  # record
thermo_style custom step ke
thermo {steps}
run {steps}
unfix record  # record
dump contacts all local 1 dump.contacts c_contacts[1] c_contacts[2] c_contacts[3] c_contacts[4] c_contacts[5] c_contacts[6] c_contacts[7] c_contacts[8] c_contacts[9]  # record
dump_modify contacts format "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"  # record
dump grains all custom 1 dump.grains id x y vx vy omegaz radius mass  # record
dump_modify grains format "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g"  # record
run 0
"""
    result, loop = run_recorded_and_timed(deck, workdir)
    _, grains = read_dump(workdir / "dump.grains")[-1]
    _, contact = read_dump(workdir / "dump.contacts")[-1]
    if len(contact["c_contacts[1]"]) != 1:
        raise RuntimeError(f"fig2 {mode} dt=t_c/{fraction}: the two discs are not in contact "
                           "at the end (the top disc rolled off)")
    dx = grains["x"][1] - grains["x"][0]
    dy = grains["y"][1] - grains["y"][0]
    distance = math.hypot(dx, dy)
    theta = math.atan2(dx, dy)
    radius_top, radius_base = grains["radius"][1], grains["radius"][0]
    mass = grains["mass"][1]
    # lever arm of the tangential force: LIGGGHTS' contact radius r_i - delta_n/2
    lever = radius_top - 0.5 * (radius_top + radius_base - distance)
    length = FIXED_LENGTH if mode == "fixed" else core_geometry.overlap_chord(radius_top, radius_base, distance)
    # columns: id1 id2 periodic flag, then the history: 3 values of the
    # tangential spring, then jiang's rolling angle (x y z), then what
    # follows it; in 2D the angle lies along z
    angle = [contact[f"c_contacts[{k}]"][0] for k in (7, 8, 9)]
    if not abs(angle[2]) > 1e3 * max(abs(angle[0]), abs(angle[1])):
        raise RuntimeError(f"fig2: history columns 7-9 {angle} do not look like a 2D "
                           "rolling angle; has the contact history layout changed?")
    rolling_angle = abs(angle[2])
    spring = KN * length ** 2 * rolling_angle
    gravity_moment = mass * GRAVITY * lever * math.sin(theta)
    kinetic = 0.5 * mass * (grains["vx"][1] ** 2 + grains["vy"][1] ** 2)
    peak = float(np.max(read_table(workdir / "angle.txt")["angle"]))
    return {"dt": dt, "t_c": t_c, "theta_deg": math.degrees(theta), "peak_deg": peak,
            "residual": abs(spring - gravity_moment) / gravity_moment,
            "rolling_torque": spring, "kinetic": kinetic, "contact_length": length,
            "loop": loop, "steps": steps}


# ---------------------------------------------------------------- (c) rolling on a wall

ROLL_DAMPING_RATIO = 0.3        # normal damping of the wall contact, fraction of critical
ROLL_DURATION = 0.15            # s until the sphere would stop: sets v0
ROLL_WINDOW = (0.2, 0.8)        # fraction of the stopping time fitted


def rolling_expectation(mode):
    """Static overlap, r_c, l_c and the expected deceleration. r_c is
    LIGGGHTS' contact radius r - delta_n/2: the arm of the tangential force
    and the radius in the contact's sliding velocity v - omega r_c."""
    overlap = SPHERE_MASS * GRAVITY / KN
    lever = RADIUS - overlap / 2
    length = FIXED_LENGTH if mode == "fixed" else core_geometry.wall_chord(RADIUS, overlap)
    moment = MU * length * SPHERE_MASS * GRAVITY
    inertia = 0.4 * SPHERE_MASS * RADIUS ** 2
    deceleration = moment / (lever * (SPHERE_MASS + inertia / lever ** 2))
    return overlap, lever, length, deceleration


def rolling_expectation_geometric_shift():
    """Relative change of the expected deceleration when r_c = r - delta_n
    (centre height) is used instead of r - delta_n/2."""
    overlap, _, length, deceleration = rolling_expectation("fixed")
    moment = MU * length * SPHERE_MASS * GRAVITY
    inertia = 0.4 * SPHERE_MASS * RADIUS ** 2
    lever = RADIUS - overlap
    return moment / (lever * (SPHERE_MASS + inertia / lever ** 2)) / deceleration - 1


def rolling(mode, fraction, workdir):
    t_c = contact_time(SPHERE_MASS)        # sphere on a wall: m_eff = m
    dt = t_c / fraction
    overlap, lever, length, deceleration = rolling_expectation(mode)
    v0 = deceleration * ROLL_DURATION
    steps = round(0.9 * ROLL_DURATION / dt)
    every = max(1, round(ROLL_DURATION / 300 / dt))
    gamman = 2 * ROLL_DAMPING_RATIO * math.sqrt(KN / SPHERE_MASS)
    deck = f"""{granular_setup()}
region box block -0.01 0.02 -0.01 0.01 -0.001 0.02 units box
create_box 1 box
neighbor 0.001 bin
neigh_modify delay 0
{materials(gamman, 0.5 * gamman, mode)}
pair_style gran model hooke/stiffness tangential history {rolling_keywords(mode)}
pair_coeff * *
# fix wall/gran reads the contact model's keywords after the wall arguments
fix floor all wall/gran model hooke/stiffness tangential history rolling_friction jiang primitive type 1 zplane 0.0 {rolling_keywords(mode).replace("rolling_friction jiang", "").strip()}
timestep {dt!r}
# resting on the wall at the static overlap m g / k_n
create_atoms 1 single 0 0 {RADIUS - overlap!r} units box
set group all diameter {DIAMETER!r} density {DENSITY!r}
set atom 1 vx {v0!r} omegay {v0 / lever!r}
fix gravity all gravity {GRAVITY!r} vector 0 0 -1
fix integrate all nve/sphere
variable t equal time
variable vx equal vx[1]
variable wy equal omegay[1]
variable z equal z[1]
fix record all print {every} "${{t}} ${{vx}} ${{wy}} ${{z}}" file rolling.txt screen no title "# t vx omegay z"  # record
thermo_style custom step ke
thermo {steps}
run {steps}
"""
    result, loop = run_recorded_and_timed(deck, workdir)
    table = read_table(workdir / "rolling.txt")
    window = (table["t"] >= ROLL_WINDOW[0] * ROLL_DURATION) & \
             (table["t"] <= ROLL_WINDOW[1] * ROLL_DURATION)
    slope = np.polyfit(table["t"][window], table["vx"][window], 1)[0]
    slip = np.max(np.abs(table["vx"][window] - table["omegay"][window] * lever)) / v0
    return {"dt": dt, "t_c": t_c, "measured": -slope, "expected": deceleration,
            "error": -slope / deceleration - 1, "slip": slip, "v0": v0,
            "contact_length": length, "loop": loop,
            "steps": steps}


# ---------------------------------------------------------------- driver

CHECKS = {"held_pair": held_pair, "fig2": fig2, "rolling": rolling}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true",
                        help="smoke run: dt/t_c = 1/20 and 1/10 only")
    parser.add_argument("--fractions", type=int, nargs="+", default=DT_FRACTIONS,
                        help="t_c/dt values (default: 200 100 50 20 10)")
    args = parser.parse_args()
    if args.quick:
        benchlib.use_smoke_outputs()
        args.fractions = [20, 10]

    start_load = benchlib.load_average()
    results = {}
    raw = ["# rolling_accuracy raw results: check mode t_c/dt then the measured values"]
    for check, function in CHECKS.items():
        for mode in MODES:
            for fraction in args.fractions:
                workdir = benchlib.WORK / "rolling_accuracy" / check / mode / f"tc_over_dt_{fraction}"
                result = function(mode, fraction, workdir)
                results[check, mode, fraction] = result
                raw.append(f"{check} {mode} {fraction} " + " ".join(
                    f"{key}={value:.10g}" for key, value in result.items()))
                benchlib.progress(f"{check:9s} {mode:7s} dt = t_c/{fraction:<3d} "
                                  f"{summary(check, result)}  loop {result['loop']:.3g} s")

    table = report(results, args.fractions, start_load)
    benchlib.write_section("rolling_accuracy", table)
    path = benchlib.write_raw("rolling_accuracy", "\n".join(raw) + "\n")
    benchlib.progress(f"wrote {benchlib.REPORT.relative_to(benchlib.ROOT)} and "
                      f"{path.relative_to(benchlib.ROOT)}")
    print(table)


def summary(check, result):
    if check == "held_pair":
        return (f"error/cap at steps {result['error_steps']:.2e}, "
                f"at fixed times {result['error_times']:.2e}")
    if check == "fig2":
        return (f"theta {result['theta_deg']:.6f} deg (peak {result['peak_deg']:.5f}), "
                f"residual {result['residual']:.2e}")
    return f"a {result['measured']:.5g} (expected {result['expected']:.5g}), " \
           f"error {result['error']:+.2e}"


def report(results, fractions, start_load):
    finest = max(fractions)
    held_tc = contact_time(SPHERE_MASS / 2)
    time_to_cap = {mode: results["held_pair", mode, finest]["time_to_cap"] for mode in MODES}
    fig2_tc = contact_time(DISC_MASS)
    roll_tc = contact_time(SPHERE_MASS)
    fig2_c = 0.5 * DISC_MASS * FIG2_GAMMAN      # LIGGGHTS' m_eff counts the base's mass
    fig2_damped = math.pi / math.sqrt(KN / DISC_MASS - (fig2_c / (2 * DISC_MASS)) ** 2)
    roll_damped = contact_time(SPHERE_MASS) / math.sqrt(1 - ROLL_DAMPING_RATIO ** 2)
    lines = [
        "## Accuracy against cost (`bench/rolling_accuracy.py`)",
        "",
        "Time step Δt as a fraction of t_c = π sqrt(m_eff/k_n), the duration of an "
        "undamped linear-spring contact (with a dashpot of damping ratio ζ it is "
        "t_c/sqrt(1 − ζ²), given per check). Grains: d = 1 cm, ρ = 2500 kg/m³, "
        f"k_n = {KN:g} N/m, k_t = 2/7 k_n, μ = {MU}; fixed mode l_c = 0.05 d; "
        "`hooke/stiffness`, `tangential history`. Loop time: LIGGGHTS' `Loop time`, "
        "summed over the runs of one deck, run a second time without its recording "
        "commands (dumps, fix print) so that output is not counted; with one or two grains it is per-step "
        "overhead and output, so it shows how the cost grows with the number of steps "
        "(∝ 1/Δt), not the cost of the contact law (see the rolling_cost section).",
        "",
        f"**(a) Held pair.** Two spheres 9.9 mm apart (overlap 0.1 mm), held in place, "
        f"spin at ±{HELD_OMEGA:g} rad/s, reversed after 1.6× the time to reach the cap "
        f"and run 1.2× that time more (both rounded to whole steps of t_c/10, so that "
        f"all Δt reverse at the same instant). Error = max |τ − τ_exact| / cap, with "
        f"τ_exact eq. 1 integrated in continuous time: at every step, and at "
        f"{HELD_SAMPLES} fixed physical times (measured torque interpolated linearly "
        f"between steps). m_eff = m/2, t_c = {held_tc:.3g} s; time to the cap: "
        f"{time_to_cap['fixed'] / held_tc:.1f} t_c (fixed), "
        f"{time_to_cap['overlap'] / held_tc:.1f} t_c (overlap); the sample times include "
        f"that instant.",
        "",
        "| Δt/t_c | fixed: error at steps | fixed: at fixed times | fixed: loop time (s) "
        "| overlap: error at steps | overlap: at fixed times | overlap: loop time (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for fraction in fractions:
        a, b = results["held_pair", "fixed", fraction], results["held_pair", "overlap", fraction]
        lines.append(f"| 1/{fraction} | {a['error_steps']:.1e} | {a['error_times']:.1e} | "
                     f"{a['loop']:.3g} | {b['error_steps']:.1e} | {b['error_times']:.1e} | "
                     f"{b['loop']:.3g} |")
    lines += [
        "",
        f"**(b) Fig. 2 case.** A 2D disc on one fixed disc, placed {FIG2_ANGLE}° off the "
        f"vertical (0.1 % overlap), under gravity, `rollingDamping on` "
        f"(c = {FIG2_ROLLING_DAMPING}), gamman = {FIG2_GAMMAN:g}, gammat = {FIG2_GAMMAT:g} "
        f"as in `examples/demo/in.demo`; {FIG2_TIME:g} s simulated. Residual = "
        f"|k_r δ_r − m g r_c sin θ| / (m g r_c sin θ) at the end, δ_r read from the "
        f"contact history (`compute pair/gran/local ... history`), θ the final angle of "
        f"the line of centres from the vertical, r_c = r − δ_n/2 LIGGGHTS' contact "
        f"radius (the arm of the tangential force; for equal discs the distance from "
        f"the top centre to the contact point). m_eff = m (the base does not move), t_c = "
        f"{fig2_tc:.3g} s; with the normal dashpot (ζ = {fig2_c / (2 * math.sqrt(KN * DISC_MASS)):.2f}) "
        f"the contact lasts {fig2_damped:.3g} s. Peak: the largest angle on the way "
        f"(sampled every t_c/10 at every Δt), a measure of the transient. Δ: minus "
        f"the value at Δt = t_c/{finest}.",
        "",
        "| Δt/t_c | fixed: residual | fixed: θ final (°) | Δ | fixed: peak θ (°) | Δ "
        "| fixed: loop time (s) | overlap: residual | overlap: θ final (°) | Δ "
        "| overlap: peak θ (°) | Δ | overlap: loop time (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for fraction in fractions:
        row = f"| 1/{fraction} |"
        for mode in MODES:
            r = results["fig2", mode, fraction]
            reference = results["fig2", mode, finest]
            delta = r["theta_deg"] - reference["theta_deg"]
            peak_delta = r["peak_deg"] - reference["peak_deg"]
            row += (f" {r['residual']:.1e} | {r['theta_deg']:.6f} | {delta:+.1e} | "
                    f"{r['peak_deg']:.5f} | {peak_delta:+.1e} | {r['loop']:.3g} |")
        lines.append(row)
    fixed_a = rolling_expectation("fixed")
    overlap_a = rolling_expectation("overlap")
    lines += [
        "",
        f"**(c) Rolling on a wall.** A sphere resting on `fix wall/gran ... "
        f"rolling_friction jiang primitive type 1 zplane 0.0` at its static overlap "
        f"m g/k_n is given v0 and ω = v0/r_c, with v0 = a "
        f"× {ROLL_DURATION} s so that it would stop after {ROLL_DURATION} s; "
        f"the deceleration is the slope of a straight-line fit of v_x(t) between "
        f"{ROLL_WINDOW[0]:g} and {ROLL_WINDOW[1]:g} of that time. Expected "
        f"a = M / (r_c (m + I/r_c²)), M = μ l_c m g, I = 0.4 m r²: "
        f"{fixed_a[3]:.4g} m/s² (fixed l_c), {overlap_a[3]:.4g} m/s² (overlap, "
        f"l_c = 2 sqrt(δ_n (2r − δ_n)) = {overlap_a[2] / DIAMETER:.4f} d). No rolling "
        f"damping; normal dashpot ζ = {ROLL_DAMPING_RATIO}. m_eff = m, t_c = "
        f"{roll_tc:.3g} s ({roll_damped:.3g} s with the dashpot). r_c = r − δ_n/2 is "
        f"LIGGGHTS' contact radius (the arm of the tangential force and the radius in "
        f"the contact's sliding velocity); with the centre height r − δ_n instead, "
        f"a_exact would change by a relative "
        f"{rolling_expectation_geometric_shift():+.1e}. Slip: max |v_x − ω r_c| / v0 "
        f"in the window.",
        "",
        "| Δt/t_c | fixed: a/a_exact − 1 | fixed: slip | fixed: loop time (s) "
        "| overlap: a/a_exact − 1 | overlap: slip | overlap: loop time (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for fraction in fractions:
        row = f"| 1/{fraction} |"
        for mode in MODES:
            r = results["rolling", mode, fraction]
            row += f" {r['error']:+.1e} | {r['slip']:.1e} | {r['loop']:.3g} |"
        lines.append(row)
    lines += ["", reading(results, fractions), "", benchlib.provenance(extra_load=start_load)]
    return "\n".join(lines)


def reading(results, fractions):
    """A few sentences computed from the numbers, so that they stay true
    when the script is rerun."""
    def largest(check, key):
        return max(abs(results[check, mode, f][key]) for mode in MODES for f in fractions)

    def spread(mode, key):
        values = [results["fig2", mode, f][key] for f in fractions]
        return max(values) - min(values)

    fine, coarse = max(fractions), min(fractions)
    return (
        "Reading: (a) at the steps the torque is eq. 1 to rounding "
        f"(≤ {largest('held_pair', 'error_steps'):.0e} of the cap): for a constant spin "
        "the update δ_r += ω Δt is exact; between steps only the kink at the onset of "
        f"saturation is missed, by up to {largest('held_pair', 'error_times'):.1e} of the cap "
        "(less than the torque change of one step, Δt/t_cap of the cap). (b) every run "
        f"ends static (residual ≤ {largest('fig2', 'residual'):.0e}); "
        f"from Δt = t_c/{fine} to t_c/{coarse} the final angle changes by "
        f"{spread('fixed', 'theta_deg'):.1e}° (fixed l_c) and "
        f"{spread('overlap', 'theta_deg'):.1e}° (l_c from the overlap), the peak angle by "
        f"{spread('fixed', 'peak_deg'):.1e}° and {spread('overlap', 'peak_deg'):.1e}°. "
        f"(c) the deceleration matches within {largest('rolling', 'error'):.0e} at every Δt "
        "(a constant force is integrated exactly).")


if __name__ == "__main__":
    main()
