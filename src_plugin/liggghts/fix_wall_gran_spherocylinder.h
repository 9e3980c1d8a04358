/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix ID group wall/gran/spherocylinder model ... primitive type T
       xplane|yplane|zplane C | zcylinder R CX CY  [fix wall/gran keywords]

   fix wall/gran's primitive walls for rods (atom_style spherocylinder):
   a plane (either side, the side of the rod's centre) or the inner wall
   of a vertical cylinder, touched by the rod's core segment at its end
   points (spherocylinder_geometry.h, rules 6 and 7: a rod lying on the
   wall has two contacts, one at each end; a tilted one the lower end).
   Each contact has its own tangential history (fix_wall_gran_rod_contacts.h).
   The stock fix wall/gran would treat a rod as its bounding sphere, and
   atom_style spherocylinder refuses it. With spheres this style is the
   stock fix wall/gran on the same primitives. Documentation:
   doc/spherocylinder.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(wall/gran/spherocylinder,FixWallGranSpherocylinder)

#else

#ifndef LMP_FIX_WALL_GRAN_SPHEROCYLINDER_H
#define LMP_FIX_WALL_GRAN_SPHEROCYLINDER_H

#include "fix_wall_gran_rod_contacts.h"

namespace LAMMPS_NS {

class FixWallGranSpherocylinder : public FixWallGranRodContacts {
 public:
  FixWallGranSpherocylinder(class LAMMPS *, int, char **);

 protected:
  void post_force_primitive(int vflag);

 private:
  enum Shape { PLANE, CYLINDER } shape_;
  double point_[3];     // a point of the plane, or of the cylinder's axis
  double normal_[3];    // the plane's normal, or the cylinder's axis
  double radius_;       // the cylinder's

  void read_primitive(int narg, char **arg);
  // rod i's contacts with the wall
  silokit::WallContacts contacts_of(int i) const;
};

}

#endif
#endif
