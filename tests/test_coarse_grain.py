"""analysis.common.coarse_grain against values worked out by hand: kernel
normalisation, the line integral of eq. 3 against brute-force quadrature,
conservation of mass, momentum and the virial, a uniform lattice and a rigid
rotation written by LIGGGHTS itself, kinetic stress of gases, orientation
tensors, orifice-region averages."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from analysis.common import coarse_grain as cg  # noqa: E402
from analysis.common.deck_blocks import granular_setup, hooke_materials  # noqa: E402
from analysis.common.lammps_io import iter_dump  # noqa: E402
from analysis.silo3d_rotating.records import frame_particles  # noqa: E402

RHO = 620.0


def truncation_error(kernel, spacing):
    """Expected relative error of int phi dV by the midpoint rule on cells
    of size `spacing`: the Gaussian part is integrated to ~exp(-2 pi^2 w^2/h^2)
    (nothing), but phi jumps by J = exp(-c^2/2)/A_w at r_c. The ~4 pi r_c^2/h^2
    cells cut by that sphere err by up to J h^3 each with signs that vary
    from cell to cell, so the sum errs by ~J h^3 sqrt(4 pi r_c^2/h^2).
    Tests allow 10 times that (at h = w/3: 3e-4, below the 1.1e-3 that
    normalising over all space instead of the ball would cost)."""
    jump = math.exp(-0.5 * kernel.cutoff_in_widths ** 2) / kernel.normalisation
    return 10 * jump * spacing ** 3 * math.sqrt(4 * math.pi) * kernel.cutoff / spacing


def cartesian_grid(low, high, spacing):
    """Cell centres of a box and the cell volume."""
    axes = [np.arange(lo + 0.5 * spacing, hi, spacing) for lo, hi in zip(low, high)]
    mesh = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([m.ravel() for m in mesh]), spacing ** 3


# ------------------------------------------------------------------ kernel

def test_kernel_normalised_over_truncated_ball():
    kernel = cg.GaussianKernel(0.3)
    total, _ = integrate.quad(lambda r: 4 * math.pi * r * r * kernel.value(r), 0, kernel.cutoff,
                              epsabs=0, epsrel=1e-13)
    assert total == pytest.approx(1.0, rel=1e-12)
    # A_w against the untruncated Gaussian: erf(2 sqrt 2) - 4 sqrt(2/pi) e^-8 = 0.998866...
    by_hand = math.erf(2 * math.sqrt(2)) - 4 * math.sqrt(2 / math.pi) * math.exp(-8)
    assert kernel.normalisation / ((2 * math.pi) ** 1.5 * 0.3 ** 3) == pytest.approx(by_hand, rel=1e-14)
    assert by_hand == pytest.approx(0.998866, abs=1e-6)
    assert kernel.value(kernel.cutoff * 1.0001) == 0.0


def test_default_width_is_half_the_volume_equivalent_diameter():
    d = 0.0099
    mass = RHO * math.pi / 6 * d ** 3
    assert cg.default_kernel([mass, mass], RHO).width == pytest.approx(d / 2, rel=1e-12)


def brute_force_segment(kernel, offset, branch):
    """int_0^1 phi(offset + s branch) ds by adaptive quadrature, split
    where the line crosses the cutoff sphere (phi jumps there)."""
    length_sq = branch @ branch
    s_closest = -(offset @ branch) / length_sq
    distance_sq = offset @ offset - (offset @ branch) ** 2 / length_sq
    breaks = []
    if distance_sq < kernel.cutoff ** 2:
        half = math.sqrt((kernel.cutoff ** 2 - distance_sq) / length_sq)
        breaks = [s for s in (s_closest - half, s_closest + half) if 0 < s < 1]
    value, _ = integrate.quad(lambda s: kernel.value(np.linalg.norm(offset + s * branch)), 0, 1,
                              points=breaks or None, epsabs=1e-15, epsrel=1e-12, limit=200)
    return value


def test_segment_integral_against_brute_force():
    kernel = cg.GaussianKernel(0.5)
    rng = np.random.default_rng(7)
    # offsets up to beyond r_c = 2 and branches up to longer than r_c, so
    # that segments lie inside, cross the cutoff sphere once or twice, or miss it
    offsets = rng.uniform(-2.6, 2.6, (300, 3))
    branches = rng.normal(size=(300, 3)) * rng.uniform(0.05, 3.0, (300, 1))
    closed_form = kernel.segment_integral(offsets, branches)
    brute = np.array([brute_force_segment(kernel, a, b) for a, b in zip(offsets, branches)])
    assert np.count_nonzero(brute == 0) > 10 and np.count_nonzero(brute > 0) > 100
    assert np.max(np.abs(closed_form - brute)) < 1e-12 * kernel.value(0.0)


def test_segment_through_kernel_centre_by_hand():
    # point at the middle of a segment of length L < 2 r_c:
    # int_0^1 phi = 1/A_w int_{-L/2}^{L/2} e^{-x^2/2w^2} dx / L = w sqrt(2 pi) erf(L/(2 sqrt 2 w)) / (A_w L)
    kernel = cg.GaussianKernel(0.5)
    length = 0.9
    by_hand = 0.5 * math.sqrt(2 * math.pi) * math.erf(length / (2 * math.sqrt(2) * 0.5)) / (
        kernel.normalisation * length)
    value = kernel.segment_integral([[-0.45, 0, 0]], [[length, 0, 0]])[0]
    assert value == pytest.approx(by_hand, rel=1e-13)


# ------------------------------------------------------------------ conservation

def test_mass_and_momentum_conserved_on_a_cartesian_grid():
    kernel = cg.GaussianKernel(0.004)
    rng = np.random.default_rng(3)
    positions = rng.uniform(-0.01, 0.01, (6, 3))
    masses = rng.uniform(1e-4, 3e-4, 6)
    velocities = rng.normal(size=(6, 3))
    spacing = kernel.width / 3
    points, cell = cartesian_grid(positions.min(0) - kernel.cutoff, positions.max(0) + kernel.cutoff + spacing,
                                  spacing)
    fields = cg.particle_sums(points, cg.Particles(positions, velocities, masses), kernel)
    bound = truncation_error(kernel, spacing)
    assert fields["density"].sum() * cell == pytest.approx(masses.sum(), rel=bound)
    assert fields["number_density"].sum() * cell == pytest.approx(6.0, rel=bound)
    momentum = fields["momentum"].sum(axis=0) * cell
    assert np.allclose(momentum, masses @ velocities, rtol=0, atol=bound * np.abs(masses[:, None] * velocities).sum())


def test_mass_conserved_on_the_cylindrical_grid():
    kernel = cg.GaussianKernel(0.005)
    rng = np.random.default_rng(5)
    radius, height = 0.04, 0.05
    angle = rng.uniform(0, 2 * np.pi, 20)
    r = radius * np.sqrt(rng.uniform(0, 1, 20))
    positions = np.column_stack([r * np.cos(angle), r * np.sin(angle), rng.uniform(0, height, 20)])
    masses = rng.uniform(1e-4, 2e-4, 20)
    spacing = kernel.width / 2
    grid = cg.CylindricalGrid(np.arange(0, radius + kernel.cutoff + spacing, spacing),
                              np.arange(-kernel.cutoff, height + kernel.cutoff + spacing, spacing),
                              arc_spacing=spacing)
    particles = cg.Particles(positions, np.zeros((20, 3)), masses)
    fields = cg.cylindrical_raw_fields(grid, particles, kernel)
    total = (fields["density"] * grid.cell_volumes).sum()
    # The midpoint rule in r, applied to g(r) = 2 pi r rho(r) on [0, inf),
    # is not spectral: Euler-Maclaurin leaves -(dr^2/24)(g'(inf) - g'(0)) =
    # (dr^2/24) 2 pi rho(r=0), an excess from the axis, integrated over z
    # (rho on the axis taken at Cartesian points).
    on_axis = np.column_stack([np.zeros_like(grid.z), np.zeros_like(grid.z), grid.z])
    axis_density = cg.particle_sums(on_axis, particles, kernel)["density"]
    axis_excess = spacing ** 2 / 24 * 2 * np.pi * axis_density.sum() * spacing
    assert axis_excess > truncation_error(kernel, spacing) * masses.sum()
    # a cell is about `spacing` wide in r, z and theta
    assert total - axis_excess == pytest.approx(masses.sum(), rel=truncation_error(kernel, spacing))


# ------------------------------------------------------------------ LIGGGHTS-written lattice

LATTICE = 0.01            # sc lattice constant (m)
DIAMETER = 0.0099         # grains do not touch
OMEGA = 2.0               # rad/s
LATTICE_RADIUS = 0.105    # the lattice fills a cylinder of this radius ...
LATTICE_HALF_HEIGHT = 0.0805   # ... from -this to +this


def lattice_deck(vz="0.0"):
    return f"""
{granular_setup()}
region box block -0.12 0.12 -0.12 0.12 -0.1 0.1 units box
create_box 1 box
neighbor 0.001 bin
{hooke_materials(1000.0, 285.0)}
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
timestep 1e-6
lattice sc {LATTICE}
region cylinder cylinder z 0 0 {LATTICE_RADIUS} -{LATTICE_HALF_HEIGHT} {LATTICE_HALF_HEIGHT} units box
create_atoms 1 region cylinder
set group all diameter {DIAMETER}
set group all density {RHO}
variable vx atom -{OMEGA}*y
variable vy atom {OMEGA}*x
variable vz atom {vz}
velocity all set v_vx v_vy v_vz
fix integ all nve/sphere
dump cg all custom 1 dump.cg id type x y z vx vy vz radius mass
dump_modify cg format "%d %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g"
run 0
"""


@pytest.fixture
def rotating_lattice(run, tmp_path):
    """The sc lattice filling a cylinder, in rigid rotation about z at
    OMEGA, as LIGGGHTS writes it, read by the scene's dump reader."""
    run(lattice_deck())
    (_, columns), = list(iter_dump(tmp_path / "dump.cg"))
    return frame_particles(columns)


def interior_grid(kernel):
    """(r, z) cells whose kernel ball lies inside the lattice (with half a
    lattice constant to spare)."""
    margin = kernel.cutoff + 0.5 * LATTICE
    r_max = LATTICE_RADIUS - margin
    z_max = LATTICE_HALF_HEIGHT - margin
    return cg.CylindricalGrid(np.linspace(0, r_max, 25), np.linspace(-z_max, z_max, 5), kernel.width)


# The lattice sum of the truncated kernel deviates from its mean density
# because lattice points sit unevenly just inside or outside r_c, where phi
# jumps by e^{-8}/A_w: a^3 e^{-8}/A_w = 2.1e-5 of the mean per point at
# w = a (the smooth Gaussian part contributes e^{-2 pi^2} = 3e-9). 1e-3
# allows an imbalance of ~50 of the ~200 points in that shell.
LATTICE_RIPPLE = 1e-3


@pytest.mark.engine
def test_uniform_lattice_gives_its_packing_fraction(rotating_lattice):
    particles = rotating_lattice
    assert len(particles.masses) == 5933          # lattice points in the cylinder, as LIGGGHTS made them
    kernel = cg.GaussianKernel(LATTICE)           # w = a, see LATTICE_RIPPLE
    grid = interior_grid(kernel)
    fields = cg.derived_fields(cg.cylindrical_raw_fields(grid, particles, kernel), RHO)
    by_hand = math.pi / 6 * DIAMETER ** 3 / LATTICE ** 3      # one sphere per cube a^3
    assert np.allclose(fields["packing_fraction"], by_hand, rtol=LATTICE_RIPPLE, atol=0)
    # the same in Cartesian points anywhere inside
    points = np.random.default_rng(1).uniform(-0.03, 0.03, (300, 3))
    raw = cg.particle_sums(points, particles, kernel)
    assert np.allclose(raw["density"] / RHO, by_hand, rtol=LATTICE_RIPPLE, atol=0)


@pytest.mark.engine
def test_rigid_rotation_gives_v_theta_omega_r(rotating_lattice):
    kernel = cg.GaussianKernel(LATTICE)
    grid = interior_grid(kernel)
    fields = cg.derived_fields(cg.cylindrical_raw_fields(grid, rotating_lattice, kernel), RHO)
    velocity = fields["velocity"]
    scale = OMEGA * LATTICE
    # V = Omega x (kernel-weighted mean position), which is r up to the ripple
    assert np.allclose(velocity[..., 1], OMEGA * grid.r[:, None], rtol=0, atol=LATTICE_RIPPLE * scale)
    assert np.abs(velocity[..., 0]).max() < 1e-9 * scale
    assert np.abs(velocity[..., 2]).max() < 1e-9 * scale
    # A velocity gradient inside the kernel shows up as kinetic stress: in-plane
    # velocity variance Omega^2 <x^2 + y^2>_phi with <x^2>_phi = w^2 (3 - c^3 e^{-c^2/2}/S2)/3,
    # S2 = sqrt(pi/2) erf(c/sqrt2) - c e^{-c^2/2}, c = 4  (<x^2>_phi = 0.99428 w^2)
    c = kernel.cutoff_in_widths
    s2 = math.sqrt(math.pi / 2) * math.erf(c / math.sqrt(2)) - c * math.exp(-c * c / 2)
    second_moment = kernel.width ** 2 * (3 - c ** 3 * math.exp(-c * c / 2) / s2) / 3
    expected = 2 * OMEGA ** 2 * second_moment * fields["density"] / 3
    assert np.allclose(fields["kinetic_pressure"], expected, rtol=2 * LATTICE_RIPPLE, atol=0)


@pytest.mark.engine
def test_paper_width_on_a_lattice_ripples_as_its_fourier_estimate(rotating_lattice):
    # with w = a/2 (the paper's w = d*/2 on a crystal of touching grains) the
    # lattice shows through: the first reciprocal shell (|G| = 2 pi/a, six
    # vectors) gives a ripple up to 6 exp(-2 pi^2 w^2/a^2) = 4.3 %
    kernel = cg.GaussianKernel(LATTICE / 2)
    points = np.random.default_rng(2).uniform(-0.03, 0.03, (400, 3))
    phi = cg.particle_sums(points, rotating_lattice, kernel)["density"] / RHO
    by_hand = math.pi / 6 * DIAMETER ** 3 / LATTICE ** 3
    bound = 6 * math.exp(-2 * math.pi ** 2 * 0.25)
    deviation = np.abs(phi / by_hand - 1)
    assert deviation.max() < bound + LATTICE_RIPPLE
    assert deviation.max() > 0.3 * bound          # and it is really there


# ------------------------------------------------------------------ kinetic stress

def test_two_stream_gas_has_kinetic_pressure_rho_u2_over_3():
    # two coincident grains per site moving at +u and -u along x: V = 0 and
    # sigma_k = rho u^2 e_x e_x exactly, wherever the density is
    rng = np.random.default_rng(4)
    sites = rng.uniform(-0.02, 0.02, (50, 3))
    u = 0.3
    positions = np.vstack([sites, sites])
    velocities = np.vstack([np.tile([u, 0, 0], (50, 1)), np.tile([-u, 0, 0], (50, 1))])
    masses = np.full(100, 2e-4)
    points = rng.uniform(-0.01, 0.01, (40, 3))
    kernel = cg.GaussianKernel(0.005)
    fields = cg.derived_fields(cg.particle_sums(points, cg.Particles(positions, velocities, masses), kernel), RHO)
    rho = fields["density"]
    assert np.all(rho > 0)
    assert np.abs(fields["velocity"]).max() < 1e-12
    expected = np.zeros((40, 3, 3))
    expected[:, 0, 0] = rho * u * u
    assert np.allclose(fields["kinetic_stress"], expected, rtol=1e-12, atol=1e-12 * rho.max() * u * u)
    assert np.allclose(fields["kinetic_pressure"], rho * u * u / 3, rtol=1e-12)
    assert np.all(fields["kinetic_pressure"] > 0)


def test_kinetic_stress_is_the_fluctuation_sum_of_eq_4():
    # brute force of sum_i m_i v'_i v'_i phi(r - r_i), v'_i = v_i - V(r),
    # V(r) = sum m v phi / sum m phi, against the code's M - rho V V
    rng = np.random.default_rng(8)
    positions = rng.uniform(-0.01, 0.01, (30, 3))
    velocities = rng.normal(size=(30, 3)) + [0.5, -0.2, 1.0]
    masses = rng.uniform(1e-4, 3e-4, 30)
    kernel = cg.GaussianKernel(0.004)
    points = rng.uniform(-0.008, 0.008, (10, 3))
    fields = cg.derived_fields(cg.particle_sums(points, cg.Particles(positions, velocities, masses), kernel), RHO)
    for point, stress, velocity in zip(points, fields["kinetic_stress"], fields["velocity"]):
        weights = np.array([kernel.value(np.linalg.norm(point - x)) for x in positions])
        mean_velocity = (masses * weights) @ velocities / (masses * weights).sum()
        fluctuation = velocities - mean_velocity
        by_definition = sum(m * phi * np.outer(v, v) for m, phi, v in zip(masses, weights, fluctuation))
        assert np.allclose(velocity, mean_velocity, rtol=1e-12)
        assert np.allclose(stress, by_definition, rtol=1e-10, atol=1e-12 * np.abs(by_definition).max())


def test_uniform_motion_has_no_kinetic_stress():
    rng = np.random.default_rng(9)
    positions = rng.uniform(-0.01, 0.01, (40, 3))
    drift = np.array([0.1, -0.4, -2.0])
    kernel = cg.GaussianKernel(0.004)
    fields = cg.derived_fields(cg.particle_sums(rng.uniform(-0.005, 0.005, (20, 3)),
                                                cg.Particles(positions, np.tile(drift, (40, 1)),
                                                             rng.uniform(1e-4, 2e-4, 40)), kernel), RHO)
    assert np.allclose(fields["velocity"], drift, rtol=1e-12)
    assert np.abs(fields["kinetic_stress"]).max() < 1e-12 * (fields["density"].max() * 4.0)


def test_time_window_averages_linear_fields_then_derives():
    # frame 1 all at +u, frame 2 all at -u: each frame alone has no kinetic
    # stress; the window's V = 0 and its sigma_k = rho u^2 e_x e_x (the
    # temporal fluctuation within the window is part of it, as in MercuryCG)
    rng = np.random.default_rng(10)
    positions = rng.uniform(-0.01, 0.01, (40, 3))
    masses = np.full(40, 1e-4)
    kernel = cg.GaussianKernel(0.004)
    points = np.zeros((1, 3))
    u = 0.2
    frames = [cg.particle_sums(points, cg.Particles(positions, np.tile([s * u, 0, 0], (40, 1)), masses), kernel)
              for s in (1, -1)]
    window = cg.derived_fields(cg.mean_of_raw_fields(frames), RHO)
    rho = window["density"][0]
    assert abs(window["velocity"][0, 0]) < 1e-12
    assert window["kinetic_stress"][0, 0, 0] == pytest.approx(rho * u * u, rel=1e-12)


# ------------------------------------------------------------------ contact stress

def chain_and_pair():
    """Three grains on the x axis squeezed by F (two contacts, branch L)
    and a separate pair along y pulled apart by T (one tensile contact,
    branch H): contacts listed once with the force on the first grain."""
    F, L, T, H = 3.0, 0.009, 0.5, 0.0095
    x = [np.array([0.0, 0, 0]), np.array([L, 0, 0]), np.array([2 * L, 0, 0])]
    y = [np.array([0.0, 0.05, 0]), np.array([0.0, 0.05 + H, 0])]
    starts = np.array([x[0], x[2], y[0]])
    ends = np.array([x[1], x[1], y[1]])
    # compressive: the force on the first grain points away from the second;
    # tensile: towards it
    forces = np.array([[-F, 0, 0], [F, 0, 0], [0, T, 0]])
    return cg.Contacts(starts, ends, forces), F, L, T, H


def test_contact_stress_integrates_to_the_virial():
    # int sigma_c dV = sum over contacts f_ij (x) r_ij; by hand:
    # chain: 2 contacts, f (x) r = (-F e_x)(x)(-L e_x) = F L e_x e_x each -> xx: 2 F L
    # pair: f = T e_y on grain at y, r = -H e_y -> yy: -T H (tension: negative)
    contacts, F, L, T, H = chain_and_pair()
    kernel = cg.GaussianKernel(0.004)
    spacing = kernel.width / 3
    low = np.minimum(contacts.starts.min(0), contacts.ends.min(0)) - kernel.cutoff
    high = np.maximum(contacts.starts.max(0), contacts.ends.max(0)) + kernel.cutoff + spacing
    points, cell = cartesian_grid(low, high, spacing)
    integral = cg.contact_stress(points, contacts, kernel).sum(axis=0) * cell
    expected = np.zeros((3, 3))
    expected[0, 0] = 2 * F * L
    expected[1, 1] = -T * H
    bound = truncation_error(kernel, spacing)
    assert np.allclose(integral, expected, rtol=0, atol=bound * (2 * F * L + T * H))


def test_compressed_contact_gives_positive_pressure_tensile_negative():
    contacts, F, L, T, H = chain_and_pair()
    kernel = cg.GaussianKernel(0.004)
    # mid-points of the first chain contact and of the pair, each far
    # (> r_c) from the other group
    points = np.array([[L / 2, 0, 0], [0, 0.05 + H / 2, 0]])
    stress = cg.contact_stress(points, contacts, kernel)
    pressure = np.trace(stress, axis1=1, axis2=2) / 3
    assert pressure[0] > 0 and pressure[1] < 0
    # at the pair's middle only its own contact counts: -T H * (segment through the centre)
    # (offset r - r_i = +H/2 e_y, branch r_ij = -H e_y)
    through_centre = kernel.segment_integral([[0, H / 2, 0]], [[0, -H, 0]])[0]
    assert stress[1, 1, 1] == pytest.approx(-T * H * through_centre, rel=1e-12)


# ------------------------------------------------------------------ orientation

def test_aligned_rods_have_order_one_and_isotropic_a_third():
    rng = np.random.default_rng(11)
    positions = rng.normal(scale=0.001, size=(20000, 3))
    kernel = cg.GaussianKernel(0.004)
    points = np.zeros((1, 3))
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    aligned = cg.derived_fields(cg.particle_sums(points, cg.Particles(
        positions[:50], np.zeros((50, 3)), np.full(50, 1e-4), np.tile(axis, (50, 1))), kernel), RHO)
    assert np.allclose(aligned["orientation"][0], np.outer(axis, axis), atol=1e-12)
    assert aligned["nematic_order"][0] == pytest.approx(1.0, abs=1e-12)
    directions = rng.normal(size=(20000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    isotropic = cg.derived_fields(cg.particle_sums(points, cg.Particles(
        positions, np.zeros((20000, 3)), np.full(20000, 1e-4), directions), kernel), RHO)
    assert np.trace(isotropic["orientation"][0]) == pytest.approx(1.0, abs=1e-12)
    # each entry of O scatters by ~sqrt((1/5 - 1/9)/N) = 0.002 about its
    # isotropic value; the largest eigenvalue is biased up by about that
    # (S, the largest eigenvalue of O, is >= 1/3 for any set of directions)
    assert isotropic["nematic_order"][0] == pytest.approx(1 / 3, abs=0.012)


def test_radial_rods_give_O_rr_one_after_azimuthal_averaging():
    # rods pointing away from the axis on a ring: in (r, theta, z) components
    # O = e_r e_r everywhere, though Cartesian O varies around the ring
    angle = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    radius = 0.05
    positions = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), np.zeros(400)])
    axes = positions / radius
    kernel = cg.GaussianKernel(0.004)
    grid = cg.CylindricalGrid([0.04, 0.05, 0.06], [-0.002, 0.002], kernel.width)
    fields = cg.derived_fields(cg.cylindrical_raw_fields(grid, cg.Particles(
        positions, np.zeros((400, 3)), np.full(400, 1e-4), axes), kernel), RHO)
    orientation = fields["orientation"]
    # the ring's neighbours at an azimuthal distance s tilt by s/r: O_rr =
    # <cos^2> = 1 - <s^2>/r^2 ~ 1 - w^2/r^2 (0.6 % here)
    assert np.allclose(orientation[..., 0, 0], 1.0, atol=(kernel.width / radius) ** 2 * 1.5)
    assert np.allclose(orientation[..., 2, 2], 0.0, atol=1e-14)
    assert np.allclose(np.trace(orientation, axis1=-2, axis2=-1), 1.0, atol=1e-12)


def test_lab_frame_order_of_tilted_radial_rods_is_that_of_their_cartesian_mean():
    # rods on a ring about the axis, each tilted by 30 degrees from e_r up
    # towards e_z: in (r, theta, z) components all share one axis (S = 1);
    # the plain Cartesian mean of l l over the ring (numpy, independent of
    # the grid) has the xy block cos^2/2 and zz = sin^2, so its largest
    # eigenvalue is cos^2(30)/2 = 0.375, which S_lab must give
    count, radius, tilt = 400, 0.012, np.radians(30.0)
    angle = np.linspace(0, 2 * np.pi, count, endpoint=False)
    e_r = np.column_stack([np.cos(angle), np.sin(angle), np.zeros(count)])
    axes = np.cos(tilt) * e_r + np.sin(tilt) * np.array([0.0, 0.0, 1.0])
    positions = radius * e_r + np.array([0.0, 0.0, 0.005])
    cartesian_mean = np.einsum("ni,nj->ij", axes, axes) / count
    expected = np.linalg.eigvalsh(cartesian_mean)[-1]
    assert expected == pytest.approx(np.cos(tilt) ** 2 / 2, rel=1e-12)
    kernel = cg.GaussianKernel(0.004)
    grid = cg.orifice_grid(0.03, 0.01, 0.002, 0.002)
    fields = cg.derived_fields(cg.cylindrical_raw_fields(grid, cg.Particles(
        positions, np.zeros((count, 3)), np.full(count, 1e-4), axes), kernel), RHO)
    means = cg.orifice_averages(fields, grid)
    # the kernel's azimuthal reach mixes in neighbours turned by ~ w/r about
    # z, which lowers the cylindrical order by ~(w/r)^2 ~ 0.1 (0.905 here);
    # it leaves every cell's O_rr + O_tt = cos^2 and O_zz = sin^2, so S_lab
    # is exact
    assert means["nematic_order"] == pytest.approx(1.0, abs=0.15)
    assert means["nematic_order_lab"] == pytest.approx(expected, rel=1e-9)
    assert means["nematic_order_lab"] < means["nematic_order"] - 0.4
    # vertical rods: no basis question, both orders are 1
    vertical = cg.derived_fields(cg.cylindrical_raw_fields(grid, cg.Particles(
        positions, np.zeros((count, 3)), np.full(count, 1e-4), np.tile([0.0, 0.0, 1.0], (count, 1))),
        kernel), RHO)
    vertical_means = cg.orifice_averages(vertical, grid)
    assert vertical_means["nematic_order"] == pytest.approx(1.0, abs=1e-12)
    assert vertical_means["nematic_order_lab"] == pytest.approx(1.0, abs=1e-12)

# ------------------------------------------------------------------ orifice average

def test_region_average_weights_by_phi_by_hand():
    # phi = z, X = z on the cylinder: <z> = int z^2 / int z; the midpoint
    # rule on n_z cells of dz gives sum z_c^2 dz = h^3/3 - h dz^2/12 and
    # sum z_c dz = h^2/2, so <z> = (h^3/3 - h dz^2/12) / (h^2/2)
    grid = cg.orifice_grid(0.06, 0.01, 0.001, 0.001)
    h, dz = 0.01, 0.001
    z = np.broadcast_to(grid.z, grid.shape)
    assert cg.region_average(z, z, grid.cell_volumes) == pytest.approx(
        (h ** 3 / 3 - h * dz ** 2 / 12) / (h ** 2 / 2), rel=1e-12)
    # cells of zero weight are left out even where X is undefined
    x = np.where(grid.r[:, None] > 0.02, np.nan, 1.0) * np.ones(grid.shape)
    weight = np.where(grid.r[:, None] > 0.02, 0.0, 1.0) * np.ones(grid.shape)
    assert cg.region_average(x, weight, grid.cell_volumes) == 1.0


def test_orifice_average_of_a_rotating_falling_lattice():
    # sc lattice (numpy), v = Omega x r - c e_z, extending well beyond the
    # orifice cylinder: <phi> = the lattice's, <v_z> = -c, and
    # <v_theta> = Omega <r>_phi = Omega sum r_c^2 dr / sum r_c dr
    #           = Omega (R^3/3 - R dr^2/12) / (R^2/2)   (midpoint rule, as above)
    a, c, omega = 0.005, 0.4, 3.0
    index = np.arange(-12, 13)
    mesh = np.meshgrid(index, index, np.arange(-10, 13), indexing="ij")
    positions = a * np.column_stack([m.ravel() for m in mesh]).astype(float)
    velocities = np.column_stack([-omega * positions[:, 1], omega * positions[:, 0],
                                  np.full(len(positions), -c)])
    masses = np.full(len(positions), RHO * a ** 3 * 0.5)       # phi = 0.5
    kernel = cg.GaussianKernel(a)
    D, h = 0.03, 0.01
    grid = cg.orifice_grid(D, h, a / 2, a)
    fields = cg.derived_fields(cg.cylindrical_raw_fields(grid, cg.Particles(positions, velocities, masses),
                                                         kernel), RHO)
    means = cg.orifice_averages(fields, grid)
    R, dr = D / 2, (D / 2) / grid.shape[0]
    assert means["packing_fraction"] == pytest.approx(0.5, rel=LATTICE_RIPPLE)
    assert means["velocity"][2] == pytest.approx(-c, rel=1e-12)
    assert means["velocity"][1] == pytest.approx(omega * (R ** 3 / 3 - R * dr ** 2 / 12) / (R ** 2 / 2),
                                                 rel=LATTICE_RIPPLE)
    assert abs(means["velocity"][0]) < 1e-12
