/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The one entry point of build/lib/silokit_lammps.so: LAMMPS' `plugin load`
   calls lammpsplugin_init, which registers each of our LAMMPS styles. The
   styles are then used like built-in ones, restart files included.
------------------------------------------------------------------------- */

#include "lammpsplugin.h"
#include "version.h"

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  // registers each LAMMPS style of ours (none yet: pair granular/jiang comes next)
  (void) lmp;
  (void) handle;
  (void) regfunc;
}
