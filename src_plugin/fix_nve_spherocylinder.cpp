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
  FixNVEAsphereBase(lmp, narg, arg)
{
  if (!dynamic_cast<AtomVecSpherocylinder *>(atom->avec))
    error->fix_error(FLERR, this, "needs atom_style spherocylinder");
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
