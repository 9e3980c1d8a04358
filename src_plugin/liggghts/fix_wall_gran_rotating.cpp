/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix wall/gran/rotating: see fix_wall_gran_rotating.h and
   doc/fix_wall_gran_rotating.md.

   How: the stock FixWallGran parses the contact model and a primitive
   plane, registers the per-atom contact history (migrated with the atoms,
   written to restart files) and keeps the list of grains near the plane.
   This class only replaces the primitive-wall force loop: each grain of
   that list is resolved against the plate with its hole
   (orifice_plate.h), and the wall velocity handed to the contact model is
   that of the plate at the contact point. FixWallGran refuses keywords it
   does not know, so it gets a list of the stock arguments alone (the
   deck's list is left as it is), and this class reads its own keywords
   from the rest; both keep their order.
------------------------------------------------------------------------- */

#include "fix_wall_gran_rotating.h"

#include "atom.h"
#include "comm.h"
#include "contact_interface.h"
#include "domain.h"
#include "error.h"
#include "fix_property_atom.h"
#include "granular_wall.h"
#include "math_const.h"
#include "neighbor.h"
#include "orifice_plate.h"
#include "primitive_wall.h"
#include "silokit_args.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;
using namespace LIGGGHTS::ContactModels;

namespace {

// Values each of our keywords takes; -1 for a keyword that is not ours.
int own_keyword_values(const char *keyword)
{
  static const char *names[] = {"orifice", "center", "axis", "omega", "frequency", "start", "open"};
  static const int values[] = {1, 3, 3, 1, 1, 1, 1};
  for (int k = 0; k < 7; ++k)
    if (strcmp(keyword, names[k]) == 0) return values[k];
  return -1;
}

const double UNIT_TOLERANCE = 1e-6;
// a rod touches the plate at most at its two ends and twice at the rim
const int PLATE_SLOTS = silokit::max_wall_contacts;

}  // namespace

/* ---------------------------------------------------------------------- */

FixWallGranRotating::FixWallGranRotating(LAMMPS *lmp, int narg, char **arg) :
  FixWallGranRotating(lmp, split_arguments(lmp, narg, arg))
{
}

FixWallGranRotating::FixWallGranRotating(LAMMPS *lmp, Arguments arguments) :
  FixWallGranRodContacts(lmp, static_cast<int>(arguments.stock.size()), arguments.stock.data(),
                         PLATE_SLOTS),
  hole_radius(0.0), omega(0.0), start_time(0.0), open_time(0.0), reduced_step(-1)
{
  if (meshwall_ != 0 || !primitiveWall_)
    error->fix_error(FLERR, this, "needs a primitive plane: 'primitive type <T> xplane|yplane|zplane <coordinate>'");
  if (shear_)
    error->fix_error(FLERR, this, "'shear' is not for this style: give 'omega' or 'frequency'");
  read_plane(arguments.stock);
  parse_own_keywords(arguments.own);
  check_geometry();

  vector_flag = 1;
  size_vector = 4;
  global_freq = 1;
  extvector = -1;   // per element, extlist
  extlist = extensive;
  extensive[0] = 0;   // angular velocity
  extensive[1] = 1;   // axial force on the plate
  extensive[2] = 1;   // torque on the plate about the axis
  extensive[3] = 1;   // grains in contact
  for (int k = 0; k < 3; ++k) local_sums[k] = global_sums[k] = 0.0;
  restart_global = 1;
}

/* ----------------------------------------------------------------------
   The command's arguments in two lists, each in the order given: the
   stock FixWallGran's (id, group, style, then every argument that is not
   one of our keywords or its values) and ours.
------------------------------------------------------------------------- */

FixWallGranRotating::Arguments FixWallGranRotating::split_arguments(LAMMPS *lmp, int narg, char **arg)
{
  Arguments arguments;
  arguments.stock.assign(arg, arg + (narg < 3 ? narg : 3));
  for (int i = 3; i < narg;) {
    const int values = own_keyword_values(arg[i]);
    if (values < 0) {
      arguments.stock.push_back(arg[i++]);
      continue;
    }
    if (i + values >= narg) {
      const std::string message = std::string("Fix wall/gran/rotating (id ") + arg[0] +
        "): keyword '" + arg[i] + "' needs " + (values == 1 ? "a value" : "three values");
      lmp->error->all(FLERR, message.c_str());
    }
    arguments.own.insert(arguments.own.end(), arg + i, arg + i + values + 1);
    i += values + 1;
  }
  return arguments;
}

/* ----------------------------------------------------------------------
   The plate: the plane of the stock 'primitive type T xplane|yplane|zplane
   c' arguments. Sets the default axis (+ normal) and centre (the origin's
   projection on the plane).
------------------------------------------------------------------------- */

void FixWallGranRotating::read_plane(const std::vector<char *> &arg)
{
  int normal = -1;
  double coordinate = 0.0;
  const int nstock = static_cast<int>(arg.size());
  for (int i = 3; i + 4 < nstock; ++i) {
    if (strcmp(arg[i], "primitive") != 0) continue;
    const char *style = arg[i+3];
    if (strcmp(style, "xplane") == 0) normal = 0;
    else if (strcmp(style, "yplane") == 0) normal = 1;
    else if (strcmp(style, "zplane") == 0) normal = 2;
    else {
      const std::string message = std::string("the primitive must be a plane (xplane, yplane, zplane), not '") +
                                  style + "'";
      error->fix_error(FLERR, this, message.c_str());
    }
    coordinate = silokit::keyword_number(this, error, arg[i+4], style);
  }
  if (normal < 0) error->fix_error(FLERR, this, "needs a primitive plane: 'primitive type <T> xplane|yplane|zplane <coordinate>'");
  if (domain->dimension == 2 && normal == 2)
    error->fix_error(FLERR, this, "in 2D the plate is an xplane or a yplane (the zplane is the plane of the simulation)");
  for (int k = 0; k < 3; ++k) centre[k] = axis[k] = 0.0;
  axis[normal] = 1.0;
  centre[normal] = coordinate;
}

/* ---------------------------------------------------------------------- */

void FixWallGranRotating::parse_own_keywords(const std::vector<char *> &arg)
{
  bool have_omega = false, have_frequency = false;
  int normal = 0;
  for (int k = 1; k < 3; ++k)
    if (axis[k] != 0.0) normal = k;
  const int narg = static_cast<int>(arg.size());
  for (int i = 0; i < narg;) {
    const std::string keyword(arg[i]);
    const char *value = arg[i+1];
    if (keyword == "orifice") {
      const double diameter = silokit::keyword_number(this, error, value, "orifice");
      if (diameter < 0.0) error->fix_error(FLERR, this, "'orifice' (the diameter) must be >= 0");
      hole_radius = 0.5*diameter;
    } else if (keyword == "center") {
      // a point of the axis: only its position in the plane matters (its
      // coordinate along the normal must parse but is ignored: the plane's
      // coordinate is kept)
      for (int k = 0; k < 3; ++k) {
        const double coordinate = silokit::keyword_number(this, error, arg[i+1+k], "center");
        if (k != normal) centre[k] = coordinate;
      }
    } else if (keyword == "axis") {
      double direction[3], length_squared = 0.0;
      for (int k = 0; k < 3; ++k) {
        direction[k] = silokit::keyword_number(this, error, arg[i+1+k], "axis");
        length_squared += direction[k]*direction[k];
      }
      if (std::fabs(std::sqrt(length_squared) - 1.0) > UNIT_TOLERANCE)
        error->fix_error(FLERR, this, "'axis' must be a unit vector (length 1 within 1e-6)");
      if (std::fabs(std::fabs(direction[normal]) - 1.0) > UNIT_TOLERANCE)
        error->fix_error(FLERR, this, "'axis' must be normal to the plate: +-1 along the primitive plane's normal");
      for (int k = 0; k < 3; ++k) axis[k] = k == normal ? (direction[k] > 0.0 ? 1.0 : -1.0) : 0.0;
    } else if (keyword == "omega") {
      omega = silokit::keyword_number(this, error, value, "omega");
      if (omega < 0.0) error->fix_error(FLERR, this, "'omega' must be >= 0 (the sense of rotation is that of 'axis')");
      have_omega = true;
    } else if (keyword == "frequency") {
      const double frequency = silokit::keyword_number(this, error, value, "frequency");
      if (frequency < 0.0) error->fix_error(FLERR, this, "'frequency' must be >= 0 (the sense of rotation is that of 'axis')");
      omega = 2.0*MathConst::MY_PI*frequency;
      have_frequency = true;
    } else if (keyword == "start") {
      start_time = silokit::keyword_number(this, error, value, "start");
      if (start_time < 0.0) error->fix_error(FLERR, this, "'start' (a simulated time) must be >= 0");
    } else if (keyword == "open") {
      open_time = silokit::keyword_number(this, error, value, "open");
      if (open_time < 0.0) error->fix_error(FLERR, this, "'open' (a simulated time) must be >= 0");
    }
    i += own_keyword_values(arg[i]) + 1;
  }
  if (have_omega && have_frequency)
    error->fix_error(FLERR, this, "give either 'omega' or 'frequency', not both");
}

/* ----------------------------------------------------------------------
   The hole must fit in the simulation box, and a 2D plate cannot rotate.
------------------------------------------------------------------------- */

void FixWallGranRotating::check_geometry()
{
  const bool two_d = domain->dimension == 2;
  if (two_d && omega != 0.0)
    error->fix_error(FLERR, this, "a 2D plate cannot rotate about its axis (omega x r would leave the plane): omega must be 0");
  if (two_d && centre[2] != 0.0)
    error->fix_error(FLERR, this, "in 2D the 'center' must have z = 0");
  for (int k = 0; k < (two_d ? 2 : 3); ++k) {
    if (axis[k] != 0.0) continue;
    if (centre[k] - hole_radius < domain->boxlo[k] || centre[k] + hole_radius > domain->boxhi[k]) {
      char message[256];
      snprintf(message, sizeof(message),
               "the orifice (diameter %g about %c = %g) does not fit in the simulation box "
               "(%g to %g): the silo is narrower than its orifice",
               2.0*hole_radius, "xyz"[k], centre[k], domain->boxlo[k], domain->boxhi[k]);
      error->fix_error(FLERR, this, message);
    }
  }
}

/* ----------------------------------------------------------------------
   The schedule's clock goes on across restarts (silokit_clock.h).
------------------------------------------------------------------------- */

double FixWallGranRotating::schedule_time() const
{
  return clock.time(update->get_cur_time());
}

void FixWallGranRotating::setup(int vflag)
{
  clock.run_set_up();
  FixWallGran::setup(vflag);
}

void FixWallGranRotating::write_restart(FILE *fp)
{
  const double reached = schedule_time();
  if (comm->me == 0) {
    const int size = sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(&reached, sizeof(double), 1, fp);
  }
}

void FixWallGranRotating::restart(char *buf)
{
  clock.restored(*reinterpret_cast<double *>(buf));
}

/* ---------------------------------------------------------------------- */

double FixWallGranRotating::angular_velocity() const
{
  return schedule_time() >= start_time ? omega : 0.0;
}

/* ---------------------------------------------------------------------- */

double FixWallGranRotating::hole_radius_now() const
{
  return schedule_time() >= open_time ? hole_radius : 0.0;
}

/* ----------------------------------------------------------------------
   The primitive-wall force loop of FixWallGran (fix_wall_gran.cpp,
   post_force_primitive) for the plate with a hole: the same neighbor list,
   history and contact-model call for spheres (the stock loop's
   superquadric and multicontact branches do not apply to this wall), and
   the contacts of fix_wall_gran_rod_contacts.h for rods.
------------------------------------------------------------------------- */

void FixWallGranRotating::post_force_primitive(int)
{
  const int *mask = atom->mask;
  double **force = atom->f;
  double **torque = atom->torque;
  double **history = dnum() > 0 ? fix_history_primitive_->array_atom : nullptr;
  const double spin = angular_velocity();
  const double hole = hole_radius_now();
  const bool summing = computeflag_ != 0;
  if (summing) {
    for (int k = 0; k < 3; ++k) local_sums[k] = 0.0;
    reduced_step = -1;
  }

  // the plate's own angular velocity, for rolling models that take the
  // relative rotation (rolling_friction jiang); stock ones treat every wall
  // as not turning, which at a flat contact makes no difference (the
  // spin about the normal is not rolling) but not at the rim
  double plate_spin[3];
  for (int k = 0; k < 3; ++k) plate_spin[k] = spin*axis[k];

  int *neighbors;
  const int count = primitiveWall_->getNeighbors(neighbors);
  for (int n = 0; n < count; ++n) {
    const int i = neighbors[n];
    if (!(mask[i] & groupbit)) continue;
    double force_before[3], torque_before[3];
    for (int k = 0; k < 3; ++k) {
      force_before[k] = force[i][k];
      torque_before[k] = torque[i][k];
    }
    bool touching;
    if (rods()) {
      rod_contacts(i, hole);
      touching = true;
    } else {
      touching = sphere_contact(i, history, spin, hole, plate_spin);
    }
    if (!summing) continue;

    // reaction on the plate: minus the force on the grain, and minus its
    // moment about the axis point (force at the centre plus the torque)
    double df[3], dtorque[3], arm[3];
    for (int k = 0; k < 3; ++k) {
      df[k] = force[i][k] - force_before[k];
      dtorque[k] = torque[i][k] - torque_before[k];
      arm[k] = x_[i][k] - centre[k];
    }
    const double moment[3] = {arm[1]*df[2] - arm[2]*df[1] + dtorque[0],
                              arm[2]*df[0] - arm[0]*df[2] + dtorque[1],
                              arm[0]*df[1] - arm[1]*df[0] + dtorque[2]};
    for (int k = 0; k < 3; ++k) {
      local_sums[0] -= df[k]*axis[k];
      local_sums[1] -= moment[k]*axis[k];
    }
    // a rod counts when any of its contacts touches
    if (rods()) touching = df[0] != 0.0 || df[1] != 0.0 || df[2] != 0.0;
    if (touching) local_sums[2] += 1.0;
  }
}

bool FixWallGranRotating::sphere_contact(int i, double **history, double spin, double hole,
                                         double *plate_spin)
{
  // contact models may act on grains a little apart (surfacesClose), as in
  // the stock loop
  const double close_fraction = neighbor->contactDistanceFactor - 1.0;
  const double radius = radius_[i];
  const silokit::PlateContact contact = silokit::nearest_plate_point(x_[i], centre, axis, hole);
  const double gap = contact.distance - radius;      // < 0: the grain overlaps the plate
  const bool touching = gap <= 0.0;
  // a centre exactly on the plate has no contact direction: reachable only
  // through an overlap of a whole radius, which no time step allows
  if ((!touching && gap >= close_fraction*radius) || contact.distance == 0.0) {
    if (history) std::memset(history[i], 0, dnum_*sizeof(double));
    return false;
  }
  double wall_velocity[3];
  silokit::plate_velocity(contact.point, centre, axis, spin, wall_velocity);
  LIGGGHTS::ContactModels::SurfacesIntersectData sidata;
  sidata.is_wall = true;
  sidata.omega_j = plate_spin;
  sidata.i = i;
  sidata.radi = radius;
  sidata.contact_history = history ? history[i] : nullptr;
  sidata.deltan = -gap;
  for (int k = 0; k < 3; ++k) sidata.delta[k] = -contact.to_plate[k];
  impl->compute_force(this, sidata, touching, wall_velocity);
  return touching;
}

void FixWallGranRotating::rod_contacts(int i, double hole)
{
  double rod_axis[3], half_length, radius;
  rod_of(i, rod_axis, half_length, radius);
  apply_rod_contacts(i, silokit::rod_plate_contacts(x_[i], rod_axis, half_length, radius,
                                                    centre, axis, hole));
}

void FixWallGranRotating::wall_velocity(const double *point, double *velocity) const
{
  silokit::plate_velocity(point, centre, axis, angular_velocity(), velocity);
}

/* ---------------------------------------------------------------------- */

double FixWallGranRotating::compute_vector(int n)
{
  if (n == 0) return angular_velocity();
  if (reduced_step != update->ntimestep) {
    MPI_Allreduce(local_sums, global_sums, 3, MPI_DOUBLE, MPI_SUM, world);
    reduced_step = update->ntimestep;
  }
  return global_sums[n-1];
}
