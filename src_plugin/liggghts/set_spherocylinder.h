/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   set_spherocylinder group-ID keyword value ...

   Gives the rods of a group (atom_style spherocylinder) their diameter,
   length end to end, density and axis, with the mass, inertia and bounding
   radius that follow:

     diameter d        > 0
     length L          >= d (L = d: a sphere)
     density rho       > 0
     axis x y z        the same axis for every rod (normalised)
     axis random seed  uniform on the sphere, drawn per rod from the
                       seed (a prime > 10000) and the rod's position, so
                       the same on any number of MPI ranks
     omega wx wy wz    angular velocity (rad/s, space frame)

   The angular momentum, which fix nve/spherocylinder integrates, is
   computed here from each rod's omega: an omega set afterwards with the
   stock `set` command is overwritten at the next step; give it here.

   Keywords not given keep each rod's value. Documentation:
   doc/spherocylinder.md.
------------------------------------------------------------------------- */

#ifdef COMMAND_CLASS

CommandStyle(set_spherocylinder,SetSpherocylinder)

#else

#ifndef LMP_SET_SPHEROCYLINDER_H
#define LMP_SET_SPHEROCYLINDER_H

#include "pointers.h"

namespace LAMMPS_NS {

class SetSpherocylinder : protected Pointers {
 public:
  SetSpherocylinder(class LAMMPS *lmp) : Pointers(lmp) {}
  void command(int, char **);

 private:
  double number(const char *text, const char *keyword);
};

}

#endif
#endif
