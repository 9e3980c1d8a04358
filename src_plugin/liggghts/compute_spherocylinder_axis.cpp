/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   compute spherocylinder/axis (compute_spherocylinder_axis.h).
------------------------------------------------------------------------- */

#include "compute_spherocylinder_axis.h"

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "error.h"
#include "memory.h"
#include "update.h"

using namespace LAMMPS_NS;

ComputeSpherocylinderAxis::ComputeSpherocylinderAxis(LAMMPS *lmp, int &iarg, int narg, char **arg) :
  Compute(lmp, iarg, narg, arg), nmax(0), axes(nullptr)
{
  if (narg != iarg) error->compute_error(FLERR, this, "takes no arguments");
  if (!dynamic_cast<AtomVecSpherocylinder *>(atom->avec))
    error->compute_error(FLERR, this, "needs atom_style spherocylinder");
  peratom_flag = 1;
  size_peratom_cols = 3;
}

ComputeSpherocylinderAxis::~ComputeSpherocylinderAxis()
{
  memory->destroy(axes);
}

void ComputeSpherocylinderAxis::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    memory->destroy(axes);
    nmax = atom->nmax;
    memory->create(axes, nmax, 3, "spherocylinder/axis:axes");
    array_atom = axes;
  }
  const AtomVecSpherocylinder *rods = static_cast<AtomVecSpherocylinder *>(atom->avec);
  for (int i = 0; i < atom->nlocal; i++) {
    if (atom->mask[i] & groupbit) rods->axis_of(i, axes[i]);
    else axes[i][0] = axes[i][1] = axes[i][2] = 0.0;
  }
}

double ComputeSpherocylinderAxis::memory_usage()
{
  return 3.0*nmax*sizeof(double);
}
