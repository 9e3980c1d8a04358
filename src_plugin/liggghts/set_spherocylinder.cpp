/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   set_spherocylinder (syntax in set_spherocylinder.h).
------------------------------------------------------------------------- */

#include "set_spherocylinder.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "input.h"
#include "math_const.h"
#include "random_park.h"
#include "silokit_args.h"

using namespace LAMMPS_NS;

double SetSpherocylinder::number(const char *text, const char *keyword)
{
  char *end = nullptr;
  const double value = strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value))
    error->all(FLERR, (std::string("set_spherocylinder: '") + keyword + "' expects a number, got '" +
                       text + "'").c_str());
  return value;
}

void SetSpherocylinder::command(int narg, char **arg)
{
  AtomVecSpherocylinder *rods = dynamic_cast<AtomVecSpherocylinder *>(atom->avec);
  if (!rods) error->all(FLERR, "set_spherocylinder needs atom_style spherocylinder");
  if (narg < 3) error->all(FLERR, "set_spherocylinder: give a group and at least one keyword");
  const int igroup = group->find(arg[0]);
  if (igroup < 0) error->all(FLERR, (std::string("set_spherocylinder: no group '") + arg[0] + "'").c_str());
  const int groupbit = group->bitmask[igroup];

  double diameter = -1.0, length = -1.0, density = -1.0;
  double axis[3] = {0.0, 0.0, 0.0};
  double omega[3] = {0.0, 0.0, 0.0};
  bool axis_given = false, axis_random = false, omega_given = false;
  int seed = 0;
  const char *seed_text = nullptr;
  for (int iarg = 1; iarg < narg;) {
    const std::string keyword = arg[iarg];
    if (keyword == "diameter" || keyword == "length" || keyword == "density") {
      if (iarg + 2 > narg) error->all(FLERR, ("set_spherocylinder: '" + keyword + "' needs a value").c_str());
      const double value = number(arg[iarg + 1], keyword.c_str());
      if (!(value > 0.0)) error->all(FLERR, ("set_spherocylinder: '" + keyword + "' must be > 0").c_str());
      (keyword == "diameter" ? diameter : keyword == "length" ? length : density) = value;
      iarg += 2;
    } else if (keyword == "axis") {
      if (iarg + 2 > narg) error->all(FLERR, "set_spherocylinder: 'axis' needs x y z or 'random' and a seed");
      axis_given = true;
      if (strcmp(arg[iarg + 1], "random") == 0) {
        if (iarg + 3 > narg) error->all(FLERR, "set_spherocylinder: 'axis random' needs a seed");
        const double value = number(arg[iarg + 2], "axis random");
        if (value != std::floor(value) || value <= 0 || value > 900000000)
          error->all(FLERR, "set_spherocylinder: the seed of 'axis random' must be an integer in "
                            "[1, 900000000] (LIGGGHTS wants a prime > 10000)");
        seed = static_cast<int>(value);
        if (!silokit::liggghts_seed_accepted(seed) && input->seed_check_throw_error())
          error->all(FLERR, "set_spherocylinder: the seed of 'axis random' must be a prime "
                            "number > 10000 (LIGGGHTS' random generator requires it)");
        seed_text = arg[iarg + 2];
        axis_random = true;
        iarg += 3;
      } else {
        if (iarg + 4 > narg) error->all(FLERR, "set_spherocylinder: 'axis' needs x y z or 'random' and a seed");
        for (int k = 0; k < 3; ++k) axis[k] = number(arg[iarg + 1 + k], "axis");
        const double norm = std::sqrt(axis[0]*axis[0] + axis[1]*axis[1] + axis[2]*axis[2]);
        if (!(norm > 0.0)) error->all(FLERR, "set_spherocylinder: 'axis' must not be the zero vector");
        for (int k = 0; k < 3; ++k) axis[k] /= norm;
        iarg += 4;
      }
    } else if (keyword == "omega") {
      if (iarg + 4 > narg) error->all(FLERR, "set_spherocylinder: 'omega' needs wx wy wz");
      for (int k = 0; k < 3; ++k) omega[k] = number(arg[iarg + 1 + k], "omega");
      omega_given = true;
      iarg += 4;
    } else {
      error->all(FLERR, ("set_spherocylinder: unknown keyword '" + keyword +
                         "' (diameter, length, density, axis, omega)").c_str());
    }
  }

  // LIGGGHTS checks the seed again (on rank 0: a warning with -seedtolerant)
  RanPark random(lmp, axis_random ? seed_text : "32452843");
  int bad_length = 0;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double d = diameter > 0.0 ? diameter : 2.0*atom->shape[i][1];
    const double l = length > 0.0 ? length : 2.0*atom->shape[i][0];
    const double rho = density > 0.0 ? density : atom->density[i];
    if (l < d) { bad_length = 1; continue; }
    double a[3];
    if (axis_random) {
      // per rod, from the seed and its position: the same on any rank count
      random.reset(seed, atom->x[i]);
      const double phi = 2.0*MathConst::MY_PI*random.uniform();
      const double cos_theta = 2.0*random.uniform() - 1.0;
      const double sin_theta = std::sqrt(1.0 - cos_theta*cos_theta);
      a[0] = sin_theta*std::cos(phi); a[1] = sin_theta*std::sin(phi); a[2] = cos_theta;
    } else if (axis_given) {
      for (int k = 0; k < 3; ++k) a[k] = axis[k];
    } else {
      rods->axis_of(i, a);
    }
    if (omega_given)
      for (int k = 0; k < 3; ++k) atom->omega[i][k] = omega[k];
    rods->set_rod(i, d, l, rho, a);
  }
  int any_bad = 0;
  MPI_Allreduce(&bad_length, &any_bad, 1, MPI_INT, MPI_MAX, world);
  if (any_bad) error->all(FLERR, "set_spherocylinder: 'length' must be >= 'diameter' (end to end)");
}
