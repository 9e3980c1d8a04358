/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   atom_style spherocylinder (atom_vec_spherocylinder.h says what each
   array holds and how the buffers are laid out).
------------------------------------------------------------------------- */

#include "atom_vec_spherocylinder.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "compute_pair_gran_local.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "fix_insert.h"
#include "fix_wall_gran.h"
#include "force.h"
#include "pair_gran.h"
#include "math_extra.h"
#include "memory.h"
#include "modify.h"
#include "spherocylinder_geometry.h"
#include "spherocylinder_model_check.h"

using namespace LAMMPS_NS;

namespace {

// The unit quaternion of the shortest rotation that turns the x axis onto
// the unit vector `axis`: about x cross axis, by the angle between them,
// i.e. (1 + axis_x, x cross axis) normalised; a rod along -x is turned
// half a turn about z.
void quaternion_turning_x_onto(const double *axis, double *q)
{
  q[0] = 1.0 + axis[0];
  q[1] = 0.0;
  q[2] = -axis[2];
  q[3] = axis[1];
  const double norm = std::sqrt(q[0]*q[0] + q[2]*q[2] + q[3]*q[3]);
  if (norm < 1e-150) {
    q[0] = q[1] = q[2] = 0.0;
    q[3] = 1.0;
    return;
  }
  for (int k = 0; k < 4; ++k) q[k] /= norm;
}

}  // namespace

/* ---------------------------------------------------------------------- */

AtomVecSpherocylinder::AtomVecSpherocylinder(LAMMPS *lmp) :
  AtomVecSphere(lmp), quaternion(nullptr), angmom(nullptr), shape(nullptr), inertia(nullptr)
{
  comm_x_only = 0;
  size_forward = SPHERE_COMM + ROD_COMM;
  size_border = 9 + ROD_BORDER;
  size_velocity = 6;
  // id type diameter length density x y z qw qi qj qk
  size_data_atom = 12;
  xcol_data = 6;
  atom->angmom_flag = 1;
}

/* ---------------------------------------------------------------------- */

void AtomVecSpherocylinder::init()
{
  AtomVecSphere::init();
  // mass, inertia and the contact geometry are those of the 3D solid
  if (domain->dimension != 3) error->all(FLERR, "atom_style spherocylinder is for 3D runs (dimension 3) only");
  // the sphere's init turns x-only communication back on; ghosts need
  // their orientation at every step
  comm_x_only = 0;
  size_forward = SPHERE_COMM + ROD_COMM;
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i]->rad_mass_vary_flag)
      error->all(FLERR, "atom_style spherocylinder: fixes that change the particle radius "
                        "(fix adapt, ...) are not supported");
  check_styles_take_rods();
}

/* ----------------------------------------------------------------------
   The rule for rods (doc/atom_style_spherocylinder.md, "Which styles take rods"). To
   a stock style a rod is its bounding sphere (radius L/2), so:
   - the styles that know rods, and stock ones that never read the radius,
     are listed below, and run;
   - any other fix that moves, places or touches particles (an integrator,
     an insertion, a granular wall, multisphere), or that judges the time
     step by the radius (check/timestep/gran), is refused: it would give
     rods the physics of spheres, and nothing in the output would show it;
   - any other fix or compute runs with a warning (once per ID): where it
     reads the radius (outputs, mostly) it gets the bounding sphere's;
   - the pair style must be gran with surface spherocylinder.
------------------------------------------------------------------------- */

namespace {

const char *const rod_fixes[] = {
  // know rods
  "nve/spherocylinder", "wall/gran/spherocylinder", "wall/gran/rotating", "reinject",
  // never read the radius
  "gravity", "property/global", "property/atom", "contacthistory", "print", "ave/time",
};
const char *const rod_computes[] = {
  // know rods
  "spherocylinder/axis",
  // never read the radius (the thermo output's three, and reductions)
  "temp", "pressure", "pe", "ke", "reduce",
};

template <size_t n>
bool listed(const char *const (&names)[n], const std::string &style)
{
  for (size_t k = 0; k < n; ++k)
    if (style == names[k]) return true;
  return false;
}

// What an unlisted fix would do wrong with rods, and what to use instead;
// empty for one that may run (with a warning)
std::string sphere_physics_of(Fix *fix)
{
  const std::string style = fix->style;
  if (fix->time_integrate) return "use fix nve/spherocylinder";
  if (dynamic_cast<FixInsert *>(fix))
    return "use create_atoms on a lattice and set_spherocylinder ... axis random";
  if (dynamic_cast<FixWallGran *>(fix))
    return "use fix wall/gran/spherocylinder or fix wall/gran/rotating";
  if (style.compare(0, 11, "multisphere") == 0) return "rods are rigid bodies of their own (this atom style)";
  if (style == "check/timestep/gran")
    return "fix nve/spherocylinder checks the time step against the contact time of rods";
  return "";
}

// Whether compute pair/gran/local stores nothing it takes from the radius
// (the overlap 'delta', the contact area, the contact point)
bool pair_gran_local_without_radius(Compute *compute)
{
  ComputePairGranLocal *local = dynamic_cast<ComputePairGranLocal *>(compute);
  return local && local->offset_delta() < 0 && local->offset_area() < 0 &&
         local->offset_contact_point() < 0;
}

}  // namespace

void AtomVecSpherocylinder::check_styles_take_rods()
{
  for (int i = 0; i < modify->nfix; i++) {
    Fix *fix = modify->fix[i];
    if (listed(rod_fixes, fix->style)) continue;
    const std::string instead = sphere_physics_of(fix);
    if (!instead.empty())
      error->all(FLERR, ("atom_style spherocylinder: fix " + std::string(fix->id) + " (" + fix->style +
                         ") treats rods as spheres; " + instead).c_str());
    warn_once("fix", fix->id, fix->style);
  }
  for (int i = 0; i < modify->ncompute; i++) {
    Compute *compute = modify->compute[i];
    if (listed(rod_computes, compute->style) || pair_gran_local_without_radius(compute)) continue;
    warn_once("compute", compute->id, compute->style);
  }
  PairGran *pair = force->pair ? dynamic_cast<PairGran *>(force->pair) : nullptr;
  if (force->pair && !pair)
    error->all(FLERR, "atom_style spherocylinder: the pair style must be gran with surface spherocylinder");
  if (pair) {
    const std::string problem = silokit::rod_model_problem(*pair);
    if (!problem.empty()) error->all(FLERR, ("atom_style spherocylinder: pair_style gran " + problem).c_str());
  }
}

void AtomVecSpherocylinder::warn_once(const char *kind, const char *id, const char *style)
{
  const std::string what = std::string(kind) + " " + id + " (" + style + ")";
  if (!warned_.insert(what).second || comm->me != 0) return;
  error->warning(FLERR, ("atom_style spherocylinder: " + what + " is not known to take rods: "
                         "where it reads the radius, it gets the bounding sphere's (L/2)").c_str());
}

/* ---------------------------------------------------------------------- */

void AtomVecSpherocylinder::grow(int n)
{
  AtomVecSphere::grow(n);
  quaternion = memory->grow(atom->quaternion, nmax, 4, "atom:quaternion");
  angmom = memory->grow(atom->angmom, nmax, 3, "atom:angmom");
  shape = memory->grow(atom->shape, nmax, 3, "atom:shape");
  inertia = memory->grow(atom->inertia, nmax, 3, "atom:inertia");
}

void AtomVecSpherocylinder::grow_reset()
{
  AtomVecSphere::grow_reset();
  quaternion = atom->quaternion;
  angmom = atom->angmom;
  shape = atom->shape;
  inertia = atom->inertia;
}

void AtomVecSpherocylinder::copy(int i, int j, int delflag)
{
  for (int k = 0; k < 4; ++k) quaternion[j][k] = quaternion[i][k];
  for (int k = 0; k < 3; ++k) {
    angmom[j][k] = angmom[i][k];
    shape[j][k] = shape[i][k];
    inertia[j][k] = inertia[i][k];
  }
  // last: the sphere's copy also lets the fixes copy their values
  AtomVecSphere::copy(i, j, delflag);
}

/* ----------------------------------------------------------------------
   forward communication: the sphere's values (x; x, v, omega), then the
   quaternions of the same atoms
------------------------------------------------------------------------- */

int AtomVecSpherocylinder::pack_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  const int m = AtomVecSphere::pack_comm(n, list, buf, pbc_flag, pbc);
  return m + pack_quaternions(n, list, &buf[m]);
}

int AtomVecSpherocylinder::pack_comm_vel(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  const int m = AtomVecSphere::pack_comm_vel(n, list, buf, pbc_flag, pbc);
  return m + pack_quaternions(n, list, &buf[m]);
}

void AtomVecSpherocylinder::unpack_comm(int n, int first, double *buf)
{
  AtomVecSphere::unpack_comm(n, first, buf);
  unpack_quaternions(n, first, &buf[n*SPHERE_COMM]);
}

void AtomVecSpherocylinder::unpack_comm_vel(int n, int first, double *buf)
{
  AtomVecSphere::unpack_comm_vel(n, first, buf);
  unpack_quaternions(n, first, &buf[n*SPHERE_COMM_VEL]);
}

int AtomVecSpherocylinder::pack_quaternions(int n, const int *list, double *buf) const
{
  int m = 0;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k) buf[m++] = quaternion[list[i]][k];
  return m;
}

void AtomVecSpherocylinder::unpack_quaternions(int n, int first, const double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; ++i)
    for (int k = 0; k < 4; ++k) quaternion[i][k] = buf[m++];
}

/* ----------------------------------------------------------------------
   borders: quaternion and shape of the n atoms first, then the sphere's
   values, which end with those of the fixes (whose sizes only they know)
------------------------------------------------------------------------- */

int AtomVecSpherocylinder::pack_border(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  const int m = pack_rod_border(n, list, buf);
  return m + AtomVecSphere::pack_border(n, list, &buf[m], pbc_flag, pbc);
}

int AtomVecSpherocylinder::pack_border_vel(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  const int m = pack_rod_border(n, list, buf);
  return m + AtomVecSphere::pack_border_vel(n, list, &buf[m], pbc_flag, pbc);
}

void AtomVecSpherocylinder::unpack_border(int n, int first, double *buf)
{
  // the sphere's part first: it grows the arrays for the new ghosts
  AtomVecSphere::unpack_border(n, first, &buf[n*ROD_BORDER]);
  unpack_rod_border(n, first, buf);
}

void AtomVecSpherocylinder::unpack_border_vel(int n, int first, double *buf)
{
  AtomVecSphere::unpack_border_vel(n, first, &buf[n*ROD_BORDER]);
  unpack_rod_border(n, first, buf);
}

int AtomVecSpherocylinder::pack_rod_border(int n, const int *list, double *buf) const
{
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const int j = list[i];
    for (int k = 0; k < 4; ++k) buf[m++] = quaternion[j][k];
    for (int k = 0; k < 3; ++k) buf[m++] = shape[j][k];
  }
  return m;
}

void AtomVecSpherocylinder::unpack_rod_border(int n, int first, const double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; ++i) {
    for (int k = 0; k < 4; ++k) quaternion[i][k] = buf[m++];
    for (int k = 0; k < 3; ++k) shape[i][k] = buf[m++];
  }
}

/* ----------------------------------------------------------------------
   all of a rod's own values, for exchange and restart
------------------------------------------------------------------------- */

int AtomVecSpherocylinder::pack_rod_all(int i, double *buf) const
{
  int m = 0;
  for (int k = 0; k < 4; ++k) buf[m++] = quaternion[i][k];
  for (int k = 0; k < 3; ++k) buf[m++] = angmom[i][k];
  for (int k = 0; k < 3; ++k) buf[m++] = shape[i][k];
  for (int k = 0; k < 3; ++k) buf[m++] = inertia[i][k];
  return m;
}

int AtomVecSpherocylinder::unpack_rod_all(int i, const double *buf)
{
  int m = 0;
  for (int k = 0; k < 4; ++k) quaternion[i][k] = buf[m++];
  for (int k = 0; k < 3; ++k) angmom[i][k] = buf[m++];
  for (int k = 0; k < 3; ++k) shape[i][k] = buf[m++];
  for (int k = 0; k < 3; ++k) inertia[i][k] = buf[m++];
  return m;
}

/* ----------------------------------------------------------------------
   exchange: the sphere's values (x first, as Comm::exchange reads it, and
   the fixes' values, each unpacked by its own size), then ours
------------------------------------------------------------------------- */

int AtomVecSpherocylinder::pack_exchange(int i, double *buf)
{
  int m = AtomVecSphere::pack_exchange(i, buf);
  m += pack_rod_all(i, &buf[m]);
  buf[0] = m;
  return m;
}

int AtomVecSpherocylinder::unpack_exchange(double *buf)
{
  int m = AtomVecSphere::unpack_exchange(buf);
  m += unpack_rod_all(atom->nlocal - 1, &buf[m]);
  return m;
}

/* ----------------------------------------------------------------------
   restart: read_restart tests x (the first values), and the sphere's
   unpack keeps everything after its own values as the fixes' extra
   values, sized from buf[0]: ours go between the two, so the sphere's
   layout is written out here
------------------------------------------------------------------------- */

int AtomVecSpherocylinder::size_restart()
{
  const int nlocal = atom->nlocal;
  int n = (SPHERE_RESTART + ROD_ALL)*nlocal;
  for (int iextra = 0; iextra < atom->nextra_restart; iextra++)
    for (int i = 0; i < nlocal; i++)
      n += modify->fix[atom->extra_restart[iextra]]->size_restart(i);
  return n;
}

int AtomVecSpherocylinder::pack_restart(int i, double *buf)
{
  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  int m = 1;
  for (int k = 0; k < 3; ++k) buf[m++] = x[i][k];
  buf[m++] = ubuf(atom->tag[i]).d;
  buf[m++] = ubuf(atom->type[i]).d;
  buf[m++] = ubuf(atom->mask[i]).d;
  buf[m++] = ubuf(atom->image[i]).d;
  for (int k = 0; k < 3; ++k) buf[m++] = v[i][k];
  buf[m++] = atom->radius[i];
  buf[m++] = atom->rmass[i];
  buf[m++] = atom->density[i];
  for (int k = 0; k < 3; ++k) buf[m++] = omega[i][k];
  m += pack_rod_all(i, &buf[m]);
  for (int iextra = 0; iextra < atom->nextra_restart; iextra++)
    m += modify->fix[atom->extra_restart[iextra]]->pack_restart(i, &buf[m]);
  buf[0] = m;
  return m;
}

int AtomVecSpherocylinder::unpack_restart(double *buf)
{
  const int nlocal = atom->nlocal;
  if (nlocal == nmax) {
    grow(0);
    if (atom->nextra_store)
      memory->grow(atom->extra, nmax, atom->nextra_store, "atom:extra");
  }
  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  int m = 1;
  for (int k = 0; k < 3; ++k) x[nlocal][k] = buf[m++];
  atom->tag[nlocal] = (int) ubuf(buf[m++]).i;
  atom->type[nlocal] = (int) ubuf(buf[m++]).i;
  atom->mask[nlocal] = (int) ubuf(buf[m++]).i;
  atom->image[nlocal] = (tagint) ubuf(buf[m++]).i;
  for (int k = 0; k < 3; ++k) v[nlocal][k] = buf[m++];
  atom->radius[nlocal] = buf[m++];
  atom->rmass[nlocal] = buf[m++];
  atom->density[nlocal] = buf[m++];
  for (int k = 0; k < 3; ++k) omega[nlocal][k] = buf[m++];
  m += unpack_rod_all(nlocal, &buf[m]);
  if (atom->nextra_store) {
    const int size = static_cast<int>(buf[0]) - m;
    for (int k = 0; k < size; k++) atom->extra[nlocal][k] = buf[m++];
  }
  atom->nlocal++;
  return m;
}

/* ----------------------------------------------------------------------
   create_atoms: a rod of diameter 1 and length 1 (a sphere, as the
   sphere style's default) along x; set_spherocylinder gives it its size
------------------------------------------------------------------------- */

void AtomVecSpherocylinder::create_atom(int itype, double *coord)
{
  AtomVecSphere::create_atom(itype, coord);
  const double x_axis[3] = {1.0, 0.0, 0.0};
  const int i = atom->nlocal - 1;
  set_rod(i, 1.0, 1.0, atom->density[i], x_axis);
}

/* ----------------------------------------------------------------------
   data files: id type diameter length density x y z qw qi qj qk
------------------------------------------------------------------------- */

void AtomVecSpherocylinder::data_atom(double *coord, tagint imagetmp, char **values)
{
  // the sphere reads id, type, "diameter" (our bounding sphere is set
  // below), density in columns 0, 1, 2, 4 of its own layout: give it ours
  char *sphere_values[4] = {values[0], values[1], values[2], values[4]};
  AtomVecSphere::data_atom(coord, imagetmp, sphere_values);
  const int i = atom->nlocal - 1;
  const double diameter = atof(values[2]);
  const double length = atof(values[3]);
  if (!(diameter > 0.0) || !(length >= diameter))
    error->one(FLERR, "atom_style spherocylinder: Atoms section needs diameter > 0 and "
                      "length >= diameter");
  double q[4];
  for (int k = 0; k < 4; ++k) q[k] = atof(values[8 + k]);
  const double norm = std::sqrt(q[0]*q[0] + q[1]*q[1] + q[2]*q[2] + q[3]*q[3]);
  if (!(norm > 0.0))
    error->one(FLERR, "atom_style spherocylinder: Atoms section has a zero quaternion");
  for (int k = 0; k < 4; ++k) q[k] /= norm;
  double axis[3];
  axis_of_quaternion(q, axis);
  set_rod(i, diameter, length, atom->density[i], axis);
  // the quaternion as given (set_rod's is one of the many that turn x onto
  // the axis; the rod's spin about its axis is kept)
  for (int k = 0; k < 4; ++k) quaternion[i][k] = q[k];
}

// Velocities: vx vy vz wx wy wz as for spheres; the angular momentum
// follows from omega
void AtomVecSpherocylinder::data_vel(int m, char **values)
{
  AtomVecSphere::data_vel(m, values);
  angmom_from_omega(m);
}

void AtomVecSpherocylinder::pack_data(double **buf)
{
  pack_data(buf, 0);
}

void AtomVecSpherocylinder::pack_data(double **buf, int tag_offset)
{
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) {
    const tagint image = atom->image[i];
    buf[i][0] = ubuf(atom->tag[i] + tag_offset).d;
    buf[i][1] = ubuf(atom->type[i]).d;
    buf[i][2] = 2.0*shape[i][1];
    buf[i][3] = 2.0*shape[i][0];
    buf[i][4] = atom->density[i];
    for (int k = 0; k < 3; ++k) buf[i][5 + k] = atom->x[i][k];
    for (int k = 0; k < 4; ++k) buf[i][8 + k] = quaternion[i][k];
    buf[i][12] = ubuf((image & IMGMASK) - IMGMAX).d;
    buf[i][13] = ubuf((image >> IMGBITS & IMGMASK) - IMGMAX).d;
    buf[i][14] = ubuf((image >> IMG2BITS) - IMGMAX).d;
  }
}

void AtomVecSpherocylinder::write_data(FILE *fp, int n, double **buf)
{
  for (int i = 0; i < n; i++) {
    fprintf(fp, "%d %d", (int) ubuf(buf[i][0]).i, (int) ubuf(buf[i][1]).i);
    for (int k = 2; k < 12; ++k) fprintf(fp, " %-1.16e", buf[i][k]);
    fprintf(fp, " %d %d %d\n", (int) ubuf(buf[i][12]).i, (int) ubuf(buf[i][13]).i,
            (int) ubuf(buf[i][14]).i);
  }
}

/* ---------------------------------------------------------------------- */

bigint AtomVecSpherocylinder::memory_usage()
{
  bigint bytes = AtomVecSphere::memory_usage();
  if (atom->memcheck("quaternion")) bytes += memory->usage(quaternion, nmax, 4);
  if (atom->memcheck("angmom")) bytes += memory->usage(angmom, nmax, 3);
  if (atom->memcheck("shape")) bytes += memory->usage(shape, nmax, 3);
  if (atom->memcheck("inertia")) bytes += memory->usage(inertia, nmax, 3);
  return bytes;
}

/* ---------------------------------------------------------------------- */

void AtomVecSpherocylinder::set_rod(int i, double diameter, double length, double density,
                                    const double *axis)
{
  const silokit::MassProperties solid =
      silokit::spherocylinder_mass_properties(diameter, length, density);
  atom->density[i] = density;
  atom->rmass[i] = solid.mass;
  atom->radius[i] = 0.5*length;
  shape[i][0] = 0.5*length;
  shape[i][1] = shape[i][2] = 0.5*diameter;
  inertia[i][0] = solid.axial_inertia;
  inertia[i][1] = inertia[i][2] = solid.transverse_inertia;
  quaternion_turning_x_onto(axis, quaternion[i]);
  angmom_from_omega(i);
}

// L = R I R^T omega, R the rotation of the quaternion
void AtomVecSpherocylinder::angmom_from_omega(int i)
{
  double rotation[3][3], body_omega[3];
  MathExtra::quat_to_mat(quaternion[i], rotation);
  MathExtra::transpose_matvec(rotation, atom->omega[i], body_omega);
  for (int k = 0; k < 3; ++k) body_omega[k] *= inertia[i][k];
  MathExtra::matvec(rotation, body_omega, angmom[i]);
}
