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
#include "modify.h"

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
}
