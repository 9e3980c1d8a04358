"""Coarse graining of discrete-particle data into continuum fields
(Babic 1997, Goldhirsch 2010, Weinhart et al. 2012), as used by Pongó,
Börzsönyi and Hidalgo (2022), eqs. 1-5. Method, conventions and checks:
doc/coarse_graining.md.

Kernel: truncated Gaussian

    phi(r) = exp(-|r|^2 / 2 w^2) / A_w   for |r| < r_c = 4 w, else 0,

with A_w the integral of the Gaussian over the truncated ball,

    A_w = (2 pi)^(3/2) w^3 [erf(c / sqrt 2) - sqrt(2/pi) c exp(-c^2/2)],  c = r_c / w,

so that phi integrates to exactly 1 and every field conserves what it
coarse-grains (mass, momentum, the virial). The paper normalises over all of
space; at c = 4 the two differ by 0.11 %, and only ours conserves mass.

Raw (linear) fields at a point r, sums over particles i and contacts (i, j):

    rho(r)        = sum_i m_i phi(r - r_i)                    mass density
    n(r)          = sum_i phi(r - r_i)                        number density
    P(r)          = sum_i m_i v_i phi(r - r_i)                momentum density
    M(r)          = sum_i m_i v_i (x) v_i phi(r - r_i)        momentum flux
    L(r)          = sum_i l_i (x) l_i phi(r - r_i)            orientation sum
    sigma_c(r)    = sum_(i,j) f_ij (x) r_ij  int_0^1 phi(r - r_i + s r_ij) ds

(contact stress: each contact once, f_ij the force on i from j, r_ij = r_i - r_j).
Linear fields add over frames and over azimuthal samples; the derived fields
are computed from the averaged linear ones (as MercuryCG does):

    packing fraction  phi_p = rho / rho_p                                (eq. 1)
    velocity          V = P / rho                                        (eq. 2, mass weighted)
    kinetic stress    sigma_k = sum_i m_i v'_i (x) v'_i phi = M - rho V (x) V,  v'_i = v_i - V(r)   (eq. 4)
    orientation       O = L / n,  tr O = 1                               (eq. 5, normalised)
    nematic order     S = largest eigenvalue of O
                      (over a region about the axis the paper does not say in
                      which basis O is averaged first: S of the cylindrical
                      components, or S_lab of the Cartesian ones, see
                      orifice_averages)
    pressures         p_k = tr(sigma_k) / 3,  p_c = tr(sigma_c) / 3

Stress sign: compression positive (the granular convention): a compressed
contact (f_ij along r_ij) and a gas give positive pressure. The paper's
eqs. 3-4 carry a minus sign (tension positive); its double sum over i != j
counts each contact twice against its 1/2. So sigma(paper) = -sigma(here).
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np
from scipy.spatial import cKDTree
from scipy.special import erf

CUTOFF_IN_WIDTHS = 4.0
# About this many (point, particle) or (point, contact) pairs are held in
# memory at once (some 150 bytes each with the temporaries of a contact).
PAIRS_PER_CHUNK = 2_000_000
# Fewest azimuthal samples per ring: below this the average of a vector over
# the ring is not even symmetric.
MIN_AZIMUTHAL_SAMPLES = 4


# ---------------------------------------------------------------- kernel

@dataclass(frozen=True)
class GaussianKernel:
    """Gaussian of standard deviation `width` truncated at
    `cutoff_in_widths` widths and normalised over the truncated ball."""
    width: float
    cutoff_in_widths: float = CUTOFF_IN_WIDTHS

    @property
    def cutoff(self):
        return self.cutoff_in_widths * self.width

    @property
    def normalisation(self):
        """A_w = integral of exp(-r^2/2w^2) over the ball |r| < r_c."""
        c = self.cutoff_in_widths
        shell = erf(c / np.sqrt(2.0)) - np.sqrt(2.0 / np.pi) * c * np.exp(-0.5 * c * c)
        return (2.0 * np.pi) ** 1.5 * self.width ** 3 * shell

    def value(self, distance):
        """phi at the given distances from the particle."""
        distance = np.asarray(distance, dtype=float)
        inside = distance < self.cutoff
        return np.where(inside, np.exp(-0.5 * (distance / self.width) ** 2), 0.0) / self.normalisation

    def segment_integral(self, offset, branch):
        """int_0^1 phi(offset + s branch) ds for rows of `offset` (r - r_i)
        and `branch` (r_ij), closed form: with L = |b|, s0 = -a.b/L^2 and h
        the distance of r from the line, |a + s b|^2 = h^2 + L^2 (s - s0)^2,
        the kernel is nonzero for |s - s0| < sqrt(r_c^2 - h^2)/L, and

            int_lo^hi phi ds = exp(-h^2/2w^2)/A_w * w sqrt(pi/2)/L
                               * [erf(L (hi - s0)/(sqrt 2 w)) - erf(L (lo - s0)/(sqrt 2 w))]

        with [lo, hi] that interval clipped to [0, 1]. Branches must not
        be of zero length."""
        offset = np.atleast_2d(np.asarray(offset, dtype=float))
        branch = np.atleast_2d(np.asarray(branch, dtype=float))
        length_sq = np.einsum("ij,ij->i", branch, branch)
        along = np.einsum("ij,ij->i", offset, branch)
        distance_sq = np.einsum("ij,ij->i", offset, offset) - along * along / length_sq
        s_closest = -along / length_sq
        half_chord = np.sqrt(np.maximum(self.cutoff ** 2 - distance_sq, 0.0) / length_sq)
        # the erf only where the segment enters the ball
        crosses = (distance_sq < self.cutoff ** 2) & (s_closest + half_chord > 0) & (s_closest - half_chord < 1)
        integral = np.zeros(len(offset))
        length = np.sqrt(length_sq[crosses])
        s0 = s_closest[crosses]
        low = np.maximum(0.0, s0 - half_chord[crosses])
        high = np.minimum(1.0, s0 + half_chord[crosses])
        scale = np.sqrt(2.0) * self.width / length
        integral[crosses] = (np.exp(-0.5 * np.maximum(distance_sq[crosses], 0.0) / self.width ** 2)
                             * (np.sqrt(np.pi / 2.0) * self.width / self.normalisation) / length
                             * (erf((high - s0) / scale) - erf((low - s0) / scale)))
        return integral


def equivalent_diameter(volume):
    """d* = (6 V / pi)^(1/3), the diameter of the sphere of volume V. (The
    paper prints (3 V / 4 pi)^(1/3), which is that sphere's radius; its
    spheres, d = d* = 9.9 mm, show the diameter is meant.)"""
    return (6.0 * np.asarray(volume, dtype=float) / np.pi) ** (1.0 / 3.0)


def default_kernel(masses, particle_density):
    """The paper's kernel: w = d*/2, d* from the mean particle volume m/rho_p."""
    volume = np.mean(np.asarray(masses, dtype=float)) / particle_density
    return GaussianKernel(0.5 * float(equivalent_diameter(volume)))


# ---------------------------------------------------------------- inputs

@dataclass
class Particles:
    """One frame: positions (N,3), velocities (N,3), masses (N,) and
    optionally unit orientation vectors (N,3) (rods; None for spheres)."""
    positions: np.ndarray
    velocities: np.ndarray
    masses: np.ndarray
    orientations: Optional[np.ndarray] = None


@dataclass
class Contacts:
    """One frame's contacts, each once: the force on the first body
    `forces` (K,3), and the segment from `starts` (r_i) to `ends` (r_j, or
    the contact point for a wall contact, whose whole virial then lies on
    the grain's side). The branch vector is r_ij = starts - ends."""
    starts: np.ndarray
    ends: np.ndarray
    forces: np.ndarray


# ---------------------------------------------------------------- raw fields

def _point_chunks(n_points, pairs_per_point):
    """Slices of the points such that each holds about PAIRS_PER_CHUNK pairs."""
    size = max(1, int(PAIRS_PER_CHUNK / max(pairs_per_point, 1.0)))
    return [slice(start, min(start + size, n_points)) for start in range(0, n_points, size)]


def _pairs_per_point(sources, reach):
    """Mean number of sources within `reach` of a point of their bounding
    box: sizes the chunks (memory), nothing else depends on it."""
    box = np.ptp(sources, axis=0) + 2 * reach
    return len(sources) * (4.0 / 3.0 * np.pi * reach ** 3) / np.prod(box)


def _per_particle_quantities(particles):
    """Columns summed with the kernel as weight: m, 1, m v (3), m v v (9)
    and, for rods, l l (9)."""
    masses = np.asarray(particles.masses, dtype=float)
    velocities = np.asarray(particles.velocities, dtype=float)
    columns = [masses[:, None], np.ones((len(masses), 1)), masses[:, None] * velocities,
               (masses[:, None, None] * velocities[:, :, None] * velocities[:, None, :]).reshape(-1, 9)]
    if particles.orientations is not None:
        axis = np.asarray(particles.orientations, dtype=float)
        columns.append((axis[:, :, None] * axis[:, None, :]).reshape(-1, 9))
    return np.hstack(columns)


def particle_sums(points, particles, kernel):
    """The linear particle fields at `points` (n,3): dict with 'density'
    (n,), 'number_density' (n,), 'momentum' (n,3), 'momentum_flux' (n,3,3)
    and, with orientations, 'orientation_sum' (n,3,3); Cartesian
    components. The kernel values of all (point, particle) pairs within r_c
    form a sparse matrix that multiplies the per-particle quantities."""
    points = np.atleast_2d(np.asarray(points, dtype=float))
    positions = np.asarray(particles.positions, dtype=float).reshape(-1, 3)
    quantities = _per_particle_quantities(particles)
    sums = np.zeros((len(points), quantities.shape[1]))
    if len(points) and len(positions):
        particle_tree = cKDTree(positions)
        for chunk in _point_chunks(len(points), _pairs_per_point(positions, kernel.cutoff)):
            weights = cKDTree(points[chunk]).sparse_distance_matrix(
                particle_tree, kernel.cutoff, output_type="coo_matrix")
            weights.data = kernel.value(weights.data)
            sums[chunk] = weights.tocsr() @ quantities
    fields = {"density": sums[:, 0], "number_density": sums[:, 1],
              "momentum": sums[:, 2:5], "momentum_flux": sums[:, 5:14].reshape(-1, 3, 3)}
    if particles.orientations is not None:
        fields["orientation_sum"] = sums[:, 14:23].reshape(-1, 3, 3)
    return fields


def contact_stress(points, contacts, kernel):
    """sigma_c at `points` (n,3,3), Cartesian, compression positive:
    sum over contacts of f_ij (x) r_ij times the kernel's line integral
    along the segment (GaussianKernel.segment_integral, closed form)."""
    points = np.atleast_2d(np.asarray(points, dtype=float))
    starts = np.asarray(contacts.starts, dtype=float).reshape(-1, 3)
    stress = np.zeros((len(points), 9))
    if len(points) == 0 or len(starts) == 0:
        return stress.reshape(-1, 3, 3)
    branches = starts - np.asarray(contacts.ends, dtype=float).reshape(-1, 3)
    forces = np.asarray(contacts.forces, dtype=float).reshape(-1, 3)
    virials = (forces[:, :, None] * branches[:, None, :]).reshape(-1, 9)
    midpoints = starts - 0.5 * branches
    # a point within r_c of a segment is within r_c + |r_ij|/2 of its middle
    reach = kernel.cutoff + 0.5 * np.sqrt((branches ** 2).sum(axis=1)).max()
    contact_tree = cKDTree(midpoints)
    for chunk in _point_chunks(len(points), _pairs_per_point(midpoints, reach)):
        weights = cKDTree(points[chunk]).sparse_distance_matrix(
            contact_tree, reach, output_type="coo_matrix")
        offsets = points[chunk][weights.row] - starts[weights.col]
        weights.data = kernel.segment_integral(offsets, branches[weights.col])
        stress[chunk] = weights.tocsr() @ virials
    return stress.reshape(-1, 3, 3)


def raw_fields(points, particles, kernel, contacts=None):
    """All linear fields at `points`: particle_sums, plus 'contact_stress'
    when contacts are given."""
    fields = particle_sums(points, particles, kernel)
    if contacts is not None:
        fields["contact_stress"] = contact_stress(points, contacts, kernel)
    return fields


def mean_of_raw_fields(frames):
    """Mean of an iterable of raw-field dicts (time window); linear fields
    average before anything is derived from them."""
    total, count = None, 0
    for fields in frames:
        total = dict(fields) if total is None else {k: total[k] + fields[k] for k in total}
        count += 1
    if count == 0:
        raise ValueError("no frame to average")
    return {k: v / count for k, v in total.items()}


# ---------------------------------------------------------------- derived fields

def nematic_order(orientation):
    """Largest eigenvalue of each (symmetric) orientation tensor (...,3,3);
    nan where the tensor is undefined."""
    orientation = np.asarray(orientation, dtype=float)
    valid = np.all(np.isfinite(orientation), axis=(-2, -1))
    order = np.full(orientation.shape[:-2], np.nan)
    order[valid] = np.linalg.eigvalsh(orientation[valid])[..., -1]
    return order


def lab_frame_azimuthal_average(orientation):
    """The azimuthal mean of a tensor field given by its (r, theta, z)
    components, taken in Cartesian (lab) components instead: for the
    rotation R(theta) about z, <R T R^T>_theta has the xy block
    (T_rr + T_tt)/2 times the identity, T_zz, and no xz or yz part (those
    go as cos and sin theta). Radial rods all around the axis thus make an
    isotropic xy block, though every one of them points along e_r."""
    orientation = np.asarray(orientation, dtype=float)
    in_plane = 0.5 * (orientation[..., 0, 0] + orientation[..., 1, 1])
    lab = np.zeros_like(orientation)
    lab[..., 0, 0] = lab[..., 1, 1] = in_plane
    lab[..., 2, 2] = orientation[..., 2, 2]
    return lab


def derived_fields(raw, particle_density):
    """Fields of eqs. 1-5 from (averaged) raw fields, in whatever basis the
    raw fields are: 'packing_fraction', 'velocity' (nan where rho = 0),
    'kinetic_stress', 'kinetic_pressure' and, when present in raw,
    'contact_stress', 'contact_pressure', 'orientation', 'nematic_order'.
    Also passes 'density' through."""
    density = raw["density"]
    occupied = density > 0
    with np.errstate(invalid="ignore", divide="ignore"):
        velocity = np.where(occupied[..., None], raw["momentum"] / density[..., None], np.nan)
    mean_flux = density[..., None, None] * velocity[..., :, None] * velocity[..., None, :]
    kinetic = np.where(occupied[..., None, None], raw["momentum_flux"] - np.nan_to_num(mean_flux), 0.0)
    fields = {"density": density,
              "packing_fraction": density / particle_density,
              "velocity": velocity,
              "kinetic_stress": kinetic,
              "kinetic_pressure": np.trace(kinetic, axis1=-2, axis2=-1) / 3.0}
    if "contact_stress" in raw:
        fields["contact_stress"] = raw["contact_stress"]
        fields["contact_pressure"] = np.trace(raw["contact_stress"], axis1=-2, axis2=-1) / 3.0
    if "orientation_sum" in raw:
        counted = raw["number_density"] > 0
        with np.errstate(invalid="ignore", divide="ignore"):
            orientation = np.where(counted[..., None, None],
                                   raw["orientation_sum"] / raw["number_density"][..., None, None], np.nan)
        fields["orientation"] = orientation
        fields["nematic_order"] = nematic_order(orientation)
    return fields


# ---------------------------------------------------------------- cylindrical grid

@dataclass
class CylindricalGrid:
    """Cells of an (r, z) grid about the z axis through (x, y) = axis, each
    sampled at n_theta(r) = max(4, ceil(2 pi r / arc_spacing)) equally spaced
    azimuths at its centre (r_k, z_l). For a kernel of width w the
    trapezoidal rule on the circle errs by about exp(-2 pi^2 w^2 / h^2) for an
    arc spacing h: 3e-9 at h = w."""
    r_edges: np.ndarray
    z_edges: np.ndarray
    arc_spacing: float
    axis: tuple = (0.0, 0.0)

    def __post_init__(self):
        self.r_edges = np.asarray(self.r_edges, dtype=float)
        self.z_edges = np.asarray(self.z_edges, dtype=float)
        self.r = 0.5 * (self.r_edges[1:] + self.r_edges[:-1])
        self.z = 0.5 * (self.z_edges[1:] + self.z_edges[:-1])
        n_theta = np.maximum(MIN_AZIMUTHAL_SAMPLES,
                             np.ceil(2 * np.pi * self.r / self.arc_spacing)).astype(int)
        points, angles, counts = [], [], []
        # samples ordered (r, z, theta): each cell is one contiguous block
        for radius, n in zip(self.r, n_theta):
            theta = 2 * np.pi * (np.arange(n) + 0.5) / n
            ring_angles = np.tile(theta, len(self.z))
            heights = np.repeat(self.z, n)
            points.append(np.column_stack([self.axis[0] + radius * np.cos(ring_angles),
                                           self.axis[1] + radius * np.sin(ring_angles), heights]))
            angles.append(ring_angles)
            counts.append(np.full(len(self.z), n))
        self.points = np.concatenate(points)
        self.angles = np.concatenate(angles)
        self.samples_per_cell = np.concatenate(counts)
        self.cell_starts = np.concatenate([[0], np.cumsum(self.samples_per_cell)[:-1]])

    @property
    def shape(self):
        return (len(self.r), len(self.z))

    @property
    def cell_volumes(self):
        """pi (r_out^2 - r_in^2) dz per cell, shape (n_r, n_z)."""
        rings = np.pi * np.diff(self.r_edges ** 2)
        return rings[:, None] * np.diff(self.z_edges)[None, :]


def to_cylindrical(values, angles):
    """Rotate per-sample Cartesian vectors (n,3) or tensors (n,3,3) at
    azimuths `angles` into (r, theta, z) components; scalars pass."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 1:
        return values
    cos, sin = np.cos(angles), np.sin(angles)
    rotation = np.zeros((len(angles), 3, 3))
    rotation[:, 0, 0], rotation[:, 0, 1] = cos, sin       # e_r
    rotation[:, 1, 0], rotation[:, 1, 1] = -sin, cos      # e_theta
    rotation[:, 2, 2] = 1.0                               # e_z
    if values.ndim == 2:
        return np.einsum("nij,nj->ni", rotation, values)
    return np.einsum("nai,nij,nbj->nab", rotation, values, rotation)


def azimuthal_average(fields, grid):
    """Cartesian raw fields at grid.points -> their azimuthal means per cell
    in (r, theta, z) components, arrays shaped (n_r, n_z, ...)."""
    averaged = {}
    for name, values in fields.items():
        cylindrical = to_cylindrical(values, grid.angles)
        sums = np.add.reduceat(cylindrical, grid.cell_starts, axis=0)
        means = sums / grid.samples_per_cell.reshape((-1,) + (1,) * (sums.ndim - 1))
        averaged[name] = means.reshape(grid.shape + means.shape[1:])
    return averaged


def cylindrical_raw_fields(grid, particles, kernel, contacts=None):
    """Raw fields averaged over the azimuth on the grid's cells,
    (r, theta, z) components."""
    return azimuthal_average(raw_fields(grid.points, particles, kernel, contacts), grid)


# ---------------------------------------------------------------- region averages

def orifice_grid(orifice_diameter, height, spacing, arc_spacing, axis=(0.0, 0.0)):
    """Cells that tile the cylinder r < D/2, 0 < z < height exactly, about
    `spacing` wide, for the midpoint rule of region_average."""
    n_r = max(1, int(np.ceil(0.5 * orifice_diameter / spacing)))
    n_z = max(1, int(np.ceil(height / spacing)))
    return CylindricalGrid(np.linspace(0.0, 0.5 * orifice_diameter, n_r + 1),
                           np.linspace(0.0, height, n_z + 1), arc_spacing, axis)


def region_average(values, weight, cell_volumes):
    """<X> = int X w dV / int w dV by the midpoint rule over cells
    (values (n_r, n_z, ...), weight and cell_volumes (n_r, n_z)); cells of
    zero weight (no grain within reach, X undefined) are left out."""
    values = np.asarray(values, dtype=float)
    cell_weight = np.where(weight > 0, weight * cell_volumes, 0.0)
    total = cell_weight.sum()
    if total <= 0:
        return np.full(values.shape[2:], np.nan)
    extra = (1,) * (values.ndim - 2)
    filled = np.where(cell_weight.reshape(cell_weight.shape + extra) > 0, values, 0.0)
    return (filled * cell_weight.reshape(cell_weight.shape + extra)).sum(axis=(0, 1)) / total


def orifice_averages(derived, grid):
    """The paper's orifice-region means weighted by the packing fraction,
    <X> = int X phi dV / int phi dV, for every derived field on `grid`
    (cylindrical components); 'nematic_order' is the largest eigenvalue of
    the averaged orientation tensor (Fig. 9). The paper averages O over the
    orifice cylinder and takes its largest eigenvalue without saying in
    which basis it averages: 'nematic_order' averages the cylindrical
    components (order of rods all radial: 1), 'nematic_order_lab' the
    Cartesian ones (the same rods: 1/2)."""
    weight = derived["packing_fraction"]
    means = {name: region_average(values, weight, grid.cell_volumes)
             for name, values in derived.items() if name != "nematic_order"}
    if "orientation" in means:
        means["nematic_order"] = float(nematic_order(means["orientation"]))
        means["nematic_order_lab"] = float(nematic_order(lab_frame_azimuthal_average(means["orientation"])))
    return means
