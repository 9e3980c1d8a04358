/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix ID group nve/spherocylinder [integration_scheme 0|1|2|3]

   Velocity Verlet for the translation and the rigid-body rotation of rods
   (atom_style spherocylinder): LIGGGHTS' FixNVEAsphereBase, which the
   superquadric integrator uses too, with its default no-squish scheme
   (Miller et al. 2002, integration_scheme 1); 0 is Richardson's
   iteration. The integrator reads the body-frame inertia and the
   quaternion of atom_style spherocylinder and keeps omega consistent with
   the angular momentum. A time step above a tenth of the contact time of
   two rods crossing at their ends warns. Documentation:
   doc/spherocylinder.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(nve/spherocylinder,FixNVESpherocylinder)

#else

#ifndef LMP_FIX_NVE_SPHEROCYLINDER_H
#define LMP_FIX_NVE_SPHEROCYLINDER_H

#include "fix_nve_asphere_base.h"

namespace LAMMPS_NS {

class FixNVESpherocylinder : public FixNVEAsphereBase {
 public:
  FixNVESpherocylinder(class LAMMPS *, int, char **);
  void init();

 private:
  static int checked_arguments(class LAMMPS *, int narg, char **arg);
  void warn_if_time_step_is_coarse();
};

}

#endif
#endif
