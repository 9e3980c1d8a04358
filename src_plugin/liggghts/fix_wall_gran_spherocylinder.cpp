/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix wall/gran/spherocylinder (fix_wall_gran_spherocylinder.h).
------------------------------------------------------------------------- */

#include "fix_wall_gran_spherocylinder.h"

#include <cmath>
#include <cstring>
#include <string>

#include "atom.h"
#include "error.h"
#include "primitive_wall.h"
#include "silokit_args.h"

using namespace LAMMPS_NS;

// planes and cylinders touch a rod at its two end points at most
static const int WALL_SLOTS = 2;

FixWallGranSpherocylinder::FixWallGranSpherocylinder(LAMMPS *lmp, int narg, char **arg) :
  FixWallGranRodContacts(lmp, narg, arg, WALL_SLOTS), shape_(PLANE), radius_(0.0)
{
  if (meshwall_ != 0 || !primitiveWall_)
    error->fix_error(FLERR, this, "needs a primitive wall: 'primitive type <T> xplane|yplane|zplane <c>' "
                                  "or 'zcylinder <R> <cx> <cy>'");
  if (shear_) error->fix_error(FLERR, this, "'shear' is not supported with rods");
  read_primitive(narg, arg);
}

/* ----------------------------------------------------------------------
   The wall of the stock 'primitive type T <style> <values>' arguments.
------------------------------------------------------------------------- */

void FixWallGranSpherocylinder::read_primitive(int narg, char **arg)
{
  for (int k = 0; k < 3; ++k) point_[k] = normal_[k] = 0.0;
  for (int i = 3; i + 4 < narg; ++i) {
    if (strcmp(arg[i], "primitive") != 0) continue;
    const std::string wall = arg[i+3];
    const char *planes[] = {"xplane", "yplane", "zplane"};
    for (int k = 0; k < 3; ++k)
      if (wall == planes[k]) {
        shape_ = PLANE;
        normal_[k] = 1.0;
        point_[k] = silokit::keyword_number(this, error, arg[i+4], planes[k]);
        return;
      }
    if (wall == "zcylinder") {
      if (i + 6 >= narg) error->fix_error(FLERR, this, "'zcylinder' needs a radius and the axis' x and y");
      shape_ = CYLINDER;
      radius_ = silokit::keyword_number(this, error, arg[i+4], "zcylinder");
      point_[0] = silokit::keyword_number(this, error, arg[i+5], "zcylinder");
      point_[1] = silokit::keyword_number(this, error, arg[i+6], "zcylinder");
      normal_[2] = 1.0;
      if (!(radius_ > 0.0)) error->fix_error(FLERR, this, "the radius of 'zcylinder' must be > 0");
      return;
    }
    error->fix_error(FLERR, this, ("primitive '" + wall + "' is not one rods can touch "
                                   "(xplane, yplane, zplane, zcylinder)").c_str());
  }
}

/* ---------------------------------------------------------------------- */

void FixWallGranSpherocylinder::post_force_primitive(int vflag)
{
  if (!rods()) {
    FixWallGran::post_force_primitive(vflag);
    return;
  }
  const int *mask = atom->mask;
  int *neighbors;
  const int count = primitiveWall_->getNeighbors(neighbors);
  for (int n = 0; n < count; ++n) {
    const int i = neighbors[n];
    if (mask[i] & groupbit) apply_rod_contacts(i, contacts_of(i));
  }
}

// Returned by value straight into apply_rod_contacts' argument: an
// assignment would copy the 33 words of WallContacts for every rod near
// the wall, a third of the cost of its contacts with a plane.
silokit::WallContacts FixWallGranSpherocylinder::contacts_of(int i) const
{
  double axis[3], half_length, radius;
  rod_of(i, axis, half_length, radius);
  const double *centre = atom->x[i];
  if (shape_ == PLANE) {
    // either side: the one the rod's centre is on
    double side[3];
    double height = 0.0;
    for (int k = 0; k < 3; ++k) height += (centre[k] - point_[k])*normal_[k];
    for (int k = 0; k < 3; ++k) side[k] = height >= 0.0 ? normal_[k] : -normal_[k];
    return silokit::rod_plane_contacts(centre, axis, half_length, radius, point_, side);
  }
  const double dx = centre[0] - point_[0], dy = centre[1] - point_[1];
  if (dx*dx + dy*dy > radius_*radius_)
    error->one(FLERR, "fix wall/gran/spherocylinder: a rod's centre is outside the zcylinder; "
                      "rods are held inside a cylinder only");
  return silokit::rod_cylinder_contacts(centre, axis, half_length, radius, point_, normal_, radius_);
}
