/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix wall/gran/rotating for LAMMPS: see fix_wall_gran_rotating_lammps.h
   and doc/fix_wall_gran_rotating_lammps.md. The force loop is that of
   LIGGGHTS' fix (src_plugin/liggghts/fix_wall_gran_rotating.cpp) for
   spheres: each grain of the group is resolved against the plate with its
   hole (orifice_plate.h) and the contact law of contact_law.h is called
   with the plate's velocity at the contact point, in LIGGGHTS' order
   (wall_kinematics, then contact_forces).
------------------------------------------------------------------------- */

#include "fix_wall_gran_rotating_lammps.h"

#include "contact_law.h"
#include "orifice_plate.h"
#include "rolling_law_jiang.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "lammps_args.h"
#include "math_const.h"
#include "memory.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *const STYLE = "fix wall/gran/rotating";
const double UNIT_TOLERANCE = 1e-6;
}    // namespace

/* ---------------------------------------------------------------------- */

FixWallGranRotating::FixWallGranRotating(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), law(silokit_lammps::default_contact_law()), normal(-1), hole_radius(0.0), omega(0.0), start_time(0.0),
    open_time(0.0), history(nullptr),
    reduced_step(-1)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "{} needs atom attributes radius, rmass, omega and torque "
               "(atom_style sphere)", STYLE);
  for (int k = 0; k < 3; ++k) centre[k] = axis[k] = 0.0;
  parse(narg, arg);
  check_geometry();

  // the schedule starts at LAMMPS' time now (0 in a fresh run)
  clock.start(update->atime + (update->ntimestep - update->atimestep) * update->dt,
              update->ntimestep, update->dt);

  vector_flag = 1;
  size_vector = 4;
  global_freq = 1;
  extvector = -1;
  extlist = extensive;
  extensive[0] = 0;    // angular velocity
  extensive[1] = 1;    // axial force on the plate
  extensive[2] = 1;    // axial torque on the plate
  extensive[3] = 1;    // grains in contact
  for (int k = 0; k < 3; ++k) local_sums[k] = global_sums[k] = 0.0;

  restart_global = 1;
  restart_peratom = 1;
  create_attribute = 1;

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++)
    for (int m = 0; m < HISTORY_SIZE; m++) history[i][m] = 0.0;
}

FixWallGranRotating::~FixWallGranRotating()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(history);
}

/* ----------------------------------------------------------------------
   fix ID group wall/gran/rotating
       normal hooke/stiffness kn kt gamman gammat | normal hooke Y nu e v_char
       friction mu [rolling jiang a b lc <length|overlap|depth>]
       [rolling_damping eta] [tangential_damping yes|no]
       [absolute_damping yes|no] [limit_force yes|no]
       xplane|yplane|zplane c
       [orifice D] [center x y z] [axis ax ay az] [omega w | frequency f]
       [start t0] [open t1]
------------------------------------------------------------------------- */

void FixWallGranRotating::parse(int narg, char **arg)
{
  auto need = [&](int iarg, int count, const std::string &what) {
    if (iarg + count >= narg)
      error->all(FLERR, "{}: {} needs {} value{}", STYLE, what, count, count > 1 ? "s" : "");
  };
  bool have_omega = false, have_frequency = false, have_center = false, have_axis = false;
  double center_given[3] = {0.0, 0.0, 0.0}, axis_given[3] = {0.0, 0.0, 0.0};
  double plane = 0.0;

  int iarg = 3;
  while (iarg < narg) {
    const int next = silokit_lammps::parse_contact_law_keyword(error, STYLE, narg, arg, iarg, law);
    if (next != iarg) {
      iarg = next;
      continue;
    }
    const std::string keyword = arg[iarg];
    if (keyword == "xplane" || keyword == "yplane" || keyword == "zplane") {
      need(iarg, 1, keyword);
      if (normal >= 0) error->all(FLERR, "{}: {}: give one plane only", STYLE, keyword);
      normal = keyword[0] - 'x';
      plane = silokit_lammps::parse_number(error, STYLE, keyword, arg[iarg + 1]);
      iarg += 2;
    } else if (keyword == "orifice") {
      need(iarg, 1, "orifice");
      const double diameter = silokit_lammps::parse_number(error, STYLE, "orifice", arg[iarg + 1]);
      if (!(diameter >= 0.0)) error->all(FLERR, "{}: orifice (the diameter) must be >= 0", STYLE);
      hole_radius = 0.5 * diameter;
      iarg += 2;
    } else if (keyword == "center") {
      need(iarg, 3, "center");
      for (int k = 0; k < 3; ++k) center_given[k] = silokit_lammps::parse_number(error, STYLE, "center", arg[iarg + 1 + k]);
      have_center = true;
      iarg += 4;
    } else if (keyword == "axis") {
      need(iarg, 3, "axis");
      for (int k = 0; k < 3; ++k) axis_given[k] = silokit_lammps::parse_number(error, STYLE, "axis", arg[iarg + 1 + k]);
      have_axis = true;
      iarg += 4;
    } else if (keyword == "omega") {
      need(iarg, 1, "omega");
      omega = silokit_lammps::parse_number(error, STYLE, "omega", arg[iarg + 1]);
      if (!(omega >= 0.0))
        error->all(FLERR, "{}: omega must be >= 0 (the sense of rotation is that of axis)", STYLE);
      have_omega = true;
      iarg += 2;
    } else if (keyword == "frequency") {
      need(iarg, 1, "frequency");
      const double frequency = silokit_lammps::parse_number(error, STYLE, "frequency", arg[iarg + 1]);
      if (!(frequency >= 0.0))
        error->all(FLERR, "{}: frequency must be >= 0 (the sense of rotation is that of axis)",
                   STYLE);
      omega = 2.0 * MathConst::MY_PI * frequency;
      have_frequency = true;
      iarg += 2;
    } else if (keyword == "start" || keyword == "open") {
      need(iarg, 1, keyword);
      const double t = silokit_lammps::parse_number(error, STYLE, keyword, arg[iarg + 1]);
      if (!(t >= 0.0)) error->all(FLERR, "{}: {} (a simulated time) must be >= 0", STYLE, keyword);
      (keyword == "start" ? start_time : open_time) = t;
      iarg += 2;
    } else {
      error->all(FLERR,
                 "{}: unknown keyword '{}' (normal, friction, rolling, rolling_damping, "
                 "tangential_damping, absolute_damping, limit_force, xplane, yplane, zplane, orifice, center, axis, "
                 "omega, frequency, start, open)",
                 STYLE, keyword);
    }
  }

  silokit_lammps::check_contact_law(error, STYLE, law);
  if (normal < 0) error->all(FLERR, "{}: the plate is required: xplane, yplane or zplane c", STYLE);
  if (have_omega && have_frequency)
    error->all(FLERR, "{}: give either omega or frequency, not both", STYLE);

  axis[normal] = 1.0;
  centre[normal] = plane;
  if (have_center)
    // only the position in the plane matters; the plane's coordinate is kept
    for (int k = 0; k < 3; ++k)
      if (k != normal) centre[k] = center_given[k];
  if (have_axis) {
    const double length = std::sqrt(axis_given[0] * axis_given[0] + axis_given[1] * axis_given[1] +
                                    axis_given[2] * axis_given[2]);
    if (std::fabs(length - 1.0) > UNIT_TOLERANCE)
      error->all(FLERR, "{}: axis must be a unit vector (length 1 within 1e-6)", STYLE);
    if (std::fabs(std::fabs(axis_given[normal]) - 1.0) > UNIT_TOLERANCE)
      error->all(FLERR, "{}: axis must be normal to the plate (+-1 along the plane's normal)",
                 STYLE);
    axis[normal] = axis_given[normal] > 0.0 ? 1.0 : -1.0;
  }
}

/* ----------------------------------------------------------------------
   the hole must fit in the box; a 2D plate is an x or y plane at rest
------------------------------------------------------------------------- */

void FixWallGranRotating::check_geometry()
{
  const bool two_d = domain->dimension == 2;
  if (two_d && normal == 2)
    error->all(FLERR, "{}: zplane: in 2D the plate is an xplane or a yplane", STYLE);
  if (two_d && omega != 0.0)
    error->all(FLERR, "{}: omega: a 2D plate cannot rotate about its axis (omega x r would "
               "leave the plane): omega must be 0", STYLE);
  if (two_d && centre[2] != 0.0)
    error->all(FLERR, "{}: center: in 2D the center must have z = 0", STYLE);
  for (int k = 0; k < (two_d ? 2 : 3); ++k) {
    if (k == normal) continue;
    if (centre[k] - hole_radius < domain->boxlo[k] || centre[k] + hole_radius > domain->boxhi[k])
      error->all(FLERR,
                 "{}: orifice: the hole (diameter {} about {} = {}) does not fit in the "
                 "simulation box ({} to {})",
                 STYLE, 2.0 * hole_radius, "xyz"[k], centre[k], domain->boxlo[k],
                 domain->boxhi[k]);
  }
}

/* ---------------------------------------------------------------------- */

int FixWallGranRotating::setmask()
{
  int mask = 0;
  mask |= POST_FORCE;
  return mask;
}

void FixWallGranRotating::init()
{
  // a new time step (the timestep command between runs): the clock goes
  // on from the time reached with the old one
  clock.use_time_step(update->ntimestep, update->dt);
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, "{} does not support run_style respa", STYLE);
}

void FixWallGranRotating::setup(int vflag)
{
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   time: after read_restart LAMMPS 20220106 reads its time as 0 at the
   restart's step (measured: thermo `time`). The schedule keeps its own
   clock (silokit_clock.h), a time at a step and dt per step since, and
   writes all three to the restart file: a continued run then computes the
   same time, with the same operations, as the uninterrupted one.
------------------------------------------------------------------------- */

double FixWallGranRotating::schedule_time() const
{
  return clock.time(update->ntimestep);
}

double FixWallGranRotating::angular_velocity() const
{
  return schedule_time() >= start_time ? omega : 0.0;
}

double FixWallGranRotating::hole_radius_now() const
{
  return schedule_time() >= open_time ? hole_radius : 0.0;
}

void FixWallGranRotating::write_restart(FILE *fp)
{
  double state[3];
  clock.write(state);
  if (comm->me == 0) {
    const int size = sizeof(state);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(state, sizeof(double), 3, fp);
  }
}

void FixWallGranRotating::restart(char *buf)
{
  double state[3];
  std::memcpy(state, buf, sizeof(state));
  clock.read(state);
}

/* ----------------------------------------------------------------------
   the contact of every grain of the group with the plate
------------------------------------------------------------------------- */

void FixWallGranRotating::post_force(int)
{
  namespace contact_law = silokit::contact;

  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  double **omega_atom = atom->omega;
  double **torque = atom->torque;
  double *radius = atom->radius;
  double *rmass = atom->rmass;
  int *mask = atom->mask;
  const int nlocal = atom->nlocal;

  // the force call of a run's set-up reads the history without advancing it
  const bool advance = !update->setupflag;
  const double spin = angular_velocity();
  const double hole = hole_radius_now();
  const double dt = update->dt;
  // the plate's own angular velocity: Jiang's law takes the rotation
  // relative to it (no change at a flat contact, where the plate's spin is
  // about the normal, but at the rim)
  double plate_spin[3];
  for (int k = 0; k < 3; ++k) plate_spin[k] = spin * axis[k];

  for (int k = 0; k < 3; ++k) local_sums[k] = 0.0;
  reduced_step = -1;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const silokit::PlateContact contact =
        silokit::nearest_plate_point(x[i], centre, axis, hole);
    const double gap = contact.distance - radius[i];
    // a primitive wall of LIGGGHTS counts a contact at gap <= 0; a centre
    // exactly on the plate has no contact direction
    if (gap > 0.0 || contact.distance == 0.0) {
      for (int m = 0; m < HISTORY_SIZE; m++) history[i][m] = 0.0;
      continue;
    }

    double wall_velocity[3], delta[3];
    silokit::plate_velocity(contact.point, centre, axis, spin, wall_velocity);
    for (int k = 0; k < 3; ++k) delta[k] = -contact.to_plate[k];
    const contact_law::Kinematics kin =
        contact_law::wall_kinematics(delta, -gap, v[i], wall_velocity, omega_atom[i], radius[i]);

    // a wall: the grain's own mass and radius
    contact_law::NormalSpring spring;
    if (law.normal_model == silokit_lammps::NORMAL_HOOKE)
      spring = contact_law::hooke(law.youngs_effective, law.restitution,
                                  law.characteristic_velocity, rmass[i], radius[i],
                                  law.tangential_damping != 0.0);
    else
      spring = contact_law::hooke_stiffness(law.kn, law.kt, law.gamman, law.gammat, rmass[i],
                                            law.absolute_damping != 0.0,
                                            law.tangential_damping != 0.0);
    contact_law::ContactForces c = contact_law::contact_forces(
        kin, spring, law.mu, dt, law.limit_force != 0.0, advance, &history[i][HISTORY_SHEAR]);
    if (law.rolling != 0.0) {
      double rolling[3];
      rolling_torque(i, kin.n, kin.overlap, spring.kn, plate_spin, advance, rolling);
      for (int k = 0; k < 3; ++k) c.torque_i[k] += rolling[k];
    }

    for (int k = 0; k < 3; ++k) {
      f[i][k] += c.force_i[k];
      torque[i][k] += c.torque_i[k];
    }

    // reaction on the plate: minus the force on the grain and minus its
    // moment about the axis point
    double arm[3];
    for (int k = 0; k < 3; ++k) arm[k] = x[i][k] - centre[k];
    const double *df = c.force_i;
    const double *dt_ = c.torque_i;
    const double moment[3] = {arm[1] * df[2] - arm[2] * df[1] + dt_[0],
                              arm[2] * df[0] - arm[0] * df[2] + dt_[1],
                              arm[0] * df[1] - arm[1] * df[0] + dt_[2]};
    for (int k = 0; k < 3; ++k) {
      local_sums[0] -= df[k] * axis[k];
      local_sums[1] -= moment[k] * axis[k];
    }
    local_sums[2] += 1.0;
  }
}

/* ----------------------------------------------------------------------
   Jiang's rolling spring at the plate, as rolling_model_jiang.h drives it
   in LIGGGHTS for a wall: relative rotation to the plate's, l_c of a
   sphere against a flat wall, reduced inertia of the grain alone
------------------------------------------------------------------------- */

void FixWallGranRotating::rolling_torque(int i, const double *n, double overlap, double kn,
                                         const double *plate_spin, bool advance, double *torque)
{
  namespace jiang = silokit::jiang;
  double **omega_atom = atom->omega;
  const double radius = atom->radius[i];
  const double dt = update->dt;

  double relative_omega[3];
  for (int d = 0; d < 3; ++d) relative_omega[d] = omega_atom[i][d] - plate_spin[d];
  jiang::remove_normal_component(relative_omega, n);

  double length;
  if (law.length_mode == silokit_lammps::LENGTH_DEPTH)
    length = std::max(overlap, 0.0);
  else if (law.length_mode == silokit_lammps::LENGTH_OVERLAP)
    length = jiang::wall_overlap_contact_length(radius, overlap);
  else {
    length = law.contact_length;
    if (length > 2.0 * radius)
      error->one(FLERR, "{}: rolling jiang lc {} is larger than the diameter {} of a grain in "
                 "contact", STYLE, length, 2.0 * radius);
  }
  const jiang::RollingSpring spring =
      jiang::rolling_spring(kn, overlap, law.mu, length, law.stiffness_factor,
                            law.friction_factor);

  double *stored = &history[i][HISTORY_ROLLING];
  double angle[3] = {stored[0], stored[1], stored[2]};
  const bool rolls = jiang::step_rolling_spring(angle, history[i][HISTORY_STIFFNESS], n,
                                                relative_omega, spring, dt, advance, torque);
  if (advance) {
    for (int d = 0; d < 3; ++d) stored[d] = angle[d];
    history[i][HISTORY_STIFFNESS] = spring.stiffness;
  }

  // a wall: the grain's inertia about the contact point, disc 3/2 m r^2,
  // sphere 7/5 m r^2
  if (law.rolling_damping > 0.0 && !rolls) {
    const double factor = domain->dimension == 2 ? 1.5 : 1.4;
    jiang::add_rolling_damping(law.rolling_damping, factor * atom->rmass[i] * radius * radius,
                               spring.stiffness, relative_omega, torque);
  }
}

/* ---------------------------------------------------------------------- */

double FixWallGranRotating::compute_vector(int n)
{
  if (n == 0) return angular_velocity();
  if (reduced_step != update->ntimestep) {
    MPI_Allreduce(local_sums, global_sums, 3, MPI_DOUBLE, MPI_SUM, world);
    reduced_step = update->ntimestep;
  }
  return global_sums[n - 1];
}

/* ----------------------------------------------------------------------
   per-atom history: as LAMMPS' FixWallGran (20220106)
------------------------------------------------------------------------- */

void FixWallGranRotating::grow_arrays(int nmax)
{
  memory->grow(history, nmax, HISTORY_SIZE, "wall/gran/rotating:history");
}

void FixWallGranRotating::copy_arrays(int i, int j, int)
{
  for (int m = 0; m < HISTORY_SIZE; m++) history[j][m] = history[i][m];
}

void FixWallGranRotating::set_arrays(int i)
{
  for (int m = 0; m < HISTORY_SIZE; m++) history[i][m] = 0.0;
}

int FixWallGranRotating::pack_exchange(int i, double *buf)
{
  for (int m = 0; m < HISTORY_SIZE; m++) buf[m] = history[i][m];
  return HISTORY_SIZE;
}

int FixWallGranRotating::unpack_exchange(int nlocal, double *buf)
{
  for (int m = 0; m < HISTORY_SIZE; m++) history[nlocal][m] = buf[m];
  return HISTORY_SIZE;
}

int FixWallGranRotating::pack_restart(int i, double *buf)
{
  // the first value is the count, as other fixes read it
  buf[0] = HISTORY_SIZE + 1;
  for (int m = 0; m < HISTORY_SIZE; m++) buf[m + 1] = history[i][m];
  return HISTORY_SIZE + 1;
}

void FixWallGranRotating::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  for (int k = 0; k < HISTORY_SIZE; k++) history[nlocal][k] = extra[nlocal][m++];
}

int FixWallGranRotating::size_restart(int)
{
  return HISTORY_SIZE + 1;
}

int FixWallGranRotating::maxsize_restart()
{
  return HISTORY_SIZE + 1;
}

double FixWallGranRotating::memory_usage()
{
  return (double) atom->nmax * HISTORY_SIZE * sizeof(double);
}
