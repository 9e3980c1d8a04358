"""The same two-grain collision in LIGGGHTS (our build/bin/liggghts with
`pair_style gran ... rolling_friction jiang`) and in LAMMPS (build/bin/lmp
with `pair_style granular/jiang` from our plugin): an oblique impact with
spin, so that the contact is damped, slides, turns and loads the rolling
spring, then both grains fly apart; spheres in 3D, discs in 2D.

Both hosts integrate with velocity Verlet (`fix nve/sphere`) and both call
the same core functions (core/contact_law.h, core/rolling_law_jiang.h) in
the same order, with one contact to sum: measured, the trajectories agree
to the last bit at every step (positions, velocities, angular velocities),
so the test asks for that (rtol = atol = 0). A difference here means that a
host computes the contact differently; doc/lammps_host.md, section 6.

The box is split between two ranks at x = 0.005, between the grains: under
mpirun -np 2 each rank owns one grain and sees the other as a ghost, and
LAMMPS gives the run of one rank, to the last bit, with newton off and on."""

import pytest

from analysis.testing import assert_dumps_close, liggghts_binary, run_deck
from lammps_host import has_mpirun, needs_lammps, run_lammps

pytestmark = needs_lammps

DUMP_COLUMNS = "id x y z vx vy vz omegax omegay omegaz"
FORMAT = " ".join(["%d"] + ["%.17g"] * 9)

# (LIGGGHTS' pair_style gran arguments, its property/global lines,
#  LAMMPS' pair_coeff arguments)
CASES = {
    "hooke_stiffness_fixed_lc": (
        "model hooke/stiffness tangential history rolling_friction jiang",
        """fix m_kn all property/global kn peratomtypepair 1 1e5
fix m_kt all property/global kt peratomtypepair 1 4e4
fix m_gn all property/global gamman peratomtypepair 1 200
fix m_gt all property/global gammat peratomtypepair 1 100
fix m_mu all property/global coefficientFriction peratomtypepair 1 0.3
fix m_lc all property/global rollingContactLength peratomtypepair 1 0.002""",
        "normal hooke/stiffness 1e5 4e4 200 100 friction 0.3 rolling jiang 1 1 lc 0.002"),
    "hooke_overlap_lc_rolling_damping": (
        "model hooke tangential history rolling_friction jiang contactLengthFromOverlap on "
        "rollingDamping on",
        """fix m_Y all property/global youngsModulus peratomtype 5e6
fix m_nu all property/global poissonsRatio peratomtype 0.3
fix m_e all property/global coefficientRestitution peratomtypepair 1 0.8
fix m_v all property/global characteristicVelocity scalar 1.0
fix m_mu all property/global coefficientFriction peratomtypepair 1 0.3
fix m_rv all property/global coefficientRollingViscousDamping peratomtypepair 1 0.2""",
        "normal hooke 5e6 0.3 0.8 1.0 friction 0.3 rolling jiang 1 1 lc overlap rolling_damping 0.2"),
    "hooke_stiffness_options_depth_lc": (
        "model hooke/stiffness tangential history rolling_friction jiang absolute_damping on "
        "limitForce on tangential_damping off contactLengthFromDepth on rollingStiffnessFactor 2 "
        "rollingFrictionFactor 0.5",
        """fix m_kn all property/global kn peratomtypepair 1 1e5
fix m_kt all property/global kt peratomtypepair 1 4e4
fix m_gn all property/global gamman_abs peratomtypepair 1 1.0
fix m_gt all property/global gammat_abs peratomtypepair 1 0.5
fix m_mu all property/global coefficientFriction peratomtypepair 1 0.3""",
        "normal hooke/stiffness 1e5 4e4 1.0 0.5 friction 0.3 rolling jiang 2 0.5 lc depth "
        "absolute_damping yes limit_force yes tangential_damping no"),
}


def collision(host, case, dimension=3):
    """The deck of one host. In 2D the grains are discs: LIGGGHTS gives them
    the mass pi r^2 rho and the inertia m r^2 / 2 by itself, LAMMPS with
    `set density/disc` and `fix nve/sphere disc`."""
    gran_args, properties, coeff = CASES[case]
    if host == "liggghts":
        head = "atom_modify map array\ncommunicate single vel yes"
        pair = f"{properties}\npair_style gran {gran_args}\npair_coeff * *"
        spin = "set atom 2 omegax 3 omegay -20 omegaz 40\nset atom 1 omegaz -10"
        dump_format = f'dump_modify d format "{FORMAT}"'
    else:
        head = "comm_modify vel yes"
        pair = f"plugin load ${{plugin}}\npair_style granular/jiang\npair_coeff * * {coeff}"
        spin = "set atom 2 omega 3 -20 40\nset atom 1 omega 0 0 -10"
        dump_format = f'dump_modify d format line "{FORMAT}"'
    deck = f"""
units si
atom_style sphere
boundary f f f
newton off
{head}
region box block -0.05 0.06 -0.05 0.05 -0.05 0.05 units box
create_box 1 box
neighbor 0.002 bin
neigh_modify delay 0
{pair}
timestep 1e-6
create_atoms 1 single 0 0 0 units box
create_atoms 1 single 0.0102 0.002 0.0005 units box
set group all diameter 0.01 density 2500
set atom 2 vx -1.0 vy -0.1 vz 0.05
{spin}
fix integrate all nve/sphere
dump d all custom 5 dump.traj {DUMP_COLUMNS}
{dump_format}
run 1500
"""
    if dimension == 2:
        for three, two in (("boundary f f f", "dimension 2\nboundary f f p"),
                           ("single 0.0102 0.002 0.0005", "single 0.0102 0.002 0.0"),
                           ("vz 0.05", "vz 0.0"),
                           ("omegax 3 omegay -20 omegaz 40", "omegaz 40"),
                           ("omega 3 -20 40", "omega 0 0 40"),
                           ("fix integrate", "fix flat all enforce2d\nfix integrate")):
            deck = deck.replace(three, two)
        if host == "lammps":
            deck = deck.replace("density 2500", "density/disc 2500").replace(
                "all nve/sphere", "all nve/sphere disc")
    return deck


@pytest.mark.parametrize("dimension", [3, 2])
@pytest.mark.parametrize("case", sorted(CASES))
def test_two_grain_collision_is_the_same_in_both_hosts(tmp_path, case, dimension):
    if not liggghts_binary().exists():
        pytest.fail(f"{liggghts_binary()} is missing: build it with tools/build.sh")
    liggghts = run_deck(collision("liggghts", case, dimension), tmp_path / "liggghts")
    lammps = run_lammps(collision("lammps", case, dimension), tmp_path / "lammps")
    ours = lammps.frames("dump.traj")
    # the grains touched, and came apart again, within the run
    before, after = ours[0], ours[-1]
    assert abs(after["vx"][1] - before["vx"][1]) + abs(after["vy"][1] - before["vy"][1]) > 0.04
    assert abs(after["omegaz"][0] - before["omegaz"][0]) > 1.0
    assert_dumps_close(ours, liggghts.frames("dump.traj"), rtol=0, atol=0)


@pytest.mark.skipif(not has_mpirun(), reason="mpirun is not installed")
@pytest.mark.parametrize("newton", ["off", "on"])
def test_two_ranks_give_the_run_of_one(tmp_path, newton):
    deck = collision("lammps", "hooke_stiffness_fixed_lc")
    serial = run_lammps(deck, tmp_path / "np1")
    parallel = run_lammps(deck.replace("newton off", f"newton {newton}\nprocessors 2 1 1"),
                          tmp_path / "np2", nprocs=2)
    # one grain on each rank, the other its ghost
    assert "Nlocal:        1.00000 ave           1 max           1 min" in parallel.output
    assert_dumps_close(parallel.frames("dump.traj"), serial.frames("dump.traj"), rtol=0, atol=0)
