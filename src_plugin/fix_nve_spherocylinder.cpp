/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix nve/spherocylinder (fix_nve_spherocylinder.h).
------------------------------------------------------------------------- */

#include "fix_nve_spherocylinder.h"

#include <cstring>
#include <string>

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "error.h"
#include "fix_property_global.h"
#include "math_const.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace LAMMPS_NS;

FixNVESpherocylinder::FixNVESpherocylinder(LAMMPS *lmp, int narg, char **arg) :
  FixNVEAsphereBase(lmp, checked_arguments(lmp, narg, arg), arg)
{
  if (!dynamic_cast<AtomVecSpherocylinder *>(atom->avec))
    error->fix_error(FLERR, this, "needs atom_style spherocylinder");
}

/* ----------------------------------------------------------------------
   FixNVEAsphereBase reads its keyword unchecked (a missing value is read
   past the arguments, scheme 4 needs CFD coupling and crashes without it,
   another number stops the first step): check them first.
------------------------------------------------------------------------- */

int FixNVESpherocylinder::checked_arguments(LAMMPS *lmp, int narg, char **arg)
{
  for (int i = 3; i < narg; i += 2) {
    const std::string keyword = arg[i];
    if (keyword != "integration_scheme")
      lmp->error->all(FLERR, ("fix nve/spherocylinder: unknown keyword '" + keyword +
                              "' (integration_scheme)").c_str());
    const std::string value = i + 1 < narg ? arg[i + 1] : "";
    if (value != "0" && value != "1" && value != "2" && value != "3")
      lmp->error->all(FLERR, "fix nve/spherocylinder: 'integration_scheme' takes 0 (Richardson), "
                             "1 (no-squish, the default), 2 or 3");
  }
  return narg;
}

void FixNVESpherocylinder::init()
{
  FixNVEAsphereBase::init();
  // a sphere integrator on the same rods would move them twice and turn
  // them as spheres
  for (int i = 0; i < modify->nfix; i++) {
    Fix *other = modify->fix[i];
    if (other == this || !other->time_integrate) continue;
    int shared = 0, shared_anywhere = 0;
    for (int j = 0; j < atom->nlocal; ++j)
      if ((atom->mask[j] & groupbit) && (atom->mask[j] & other->groupbit)) shared = 1;
    MPI_Allreduce(&shared, &shared_anywhere, 1, MPI_INT, MPI_MAX, world);
    if (!shared_anywhere) continue;
    error->fix_error(FLERR, this, (std::string("fix ") + other->id + " (" + other->style +
                                   ") also integrates these rods: use only nve/spherocylinder").c_str());
  }
  warn_if_time_step_is_coarse();
}

/* ----------------------------------------------------------------------
   The shortest contact of two rods is at their ends: a force normal to
   the axis at s from a rod's centre meets the inverse mass 1/m + s^2/I_t
   of that rod (translation and rotation), so two rods crossing at the
   ends of their cores (s = h) have 1/m_eff = 2 (1/m + h^2/I_t), and the
   undamped contact time of k_n is t_c = pi sqrt(m_eff/k_n). Velocity
   Verlet is stable below 2/pi t_c and resolves a contact with ten steps
   or more: warn above t_c/10. Needs the stiffness k_n of hooke/stiffness
   (property/global kn), the only normal model rods take.
------------------------------------------------------------------------- */

void FixNVESpherocylinder::warn_if_time_step_is_coarse()
{
  FixPropertyGlobal *stiffness = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("kn", "property/global", "peratomtypepair", 0, 0, style, false));
  if (!stiffness) return;
  double kn = 0.0;
  for (int i = 0; i < atom->ntypes; ++i)
    for (int j = 0; j < atom->ntypes; ++j) kn = std::max(kn, stiffness->compute_array(i, j));
  double lightest_end = 1e300;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double h = atom->shape[i][0] - atom->shape[i][1];
    lightest_end = std::min(lightest_end, 1.0/(1.0/atom->rmass[i] + h*h/atom->inertia[i][1]));
  }
  double lightest = lightest_end;
  MPI_Allreduce(&lightest_end, &lightest, 1, MPI_DOUBLE, MPI_MIN, world);
  if (!(kn > 0.0) || lightest >= 1e300) return;
  const double contact_time = MathConst::MY_PI*std::sqrt(0.5*lightest/kn);
  if (update->dt <= 0.1*contact_time) return;
  char message[512];
  snprintf(message, sizeof(message),
           "fix nve/spherocylinder: the time step %g s is %.1f%% of the contact time of two rods "
           "crossing at their ends, t_c = %g s (k_n %g N/m): below 10 steps per contact; "
           "Verlet becomes unstable above %g s", update->dt, 100.0*update->dt/contact_time,
           contact_time, kn, 2.0/MathConst::MY_PI*contact_time);
  error->warning(FLERR, message);
}
