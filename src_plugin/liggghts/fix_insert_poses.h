/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix insert/poses: inserts once, at positions and axes read from a file,
   the particles of a stock particle distribution (spheres, or multisphere
   clumps whose template lies along its x axis). Made to rebuild a settled
   packing of one grain model with another (a packing of our rods as
   glued-sphere clumps, doc/silo3d_rotating.md), so that the two can be
   compared from the same start.
   Documentation: doc/fix_insert_poses.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(insert/poses,FixInsertPoses)

#else

#ifndef LMP_FIX_INSERT_POSES_H
#define LMP_FIX_INSERT_POSES_H

#include "fix_insert.h"
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixInsertPoses : public FixInsert {
 public:
  FixInsertPoses(class LAMMPS *, int, char **);

  // the quaternion that turns the body x axis onto the unit vector `axis`
  // (the shortest turn; half a turn about z for -x)
  static void quaternion_turning_x_onto(const double *axis, double *q);

 protected:
  void calc_insertion_properties();
  int calc_ninsert_this();
  int distribute_ninsert_this(int);
  void x_v_omega(int, int &, int &, double &);
  double insertion_fraction();
  int is_nearby(int) { return 0; }  // no overlap check: nothing is near
  BoundingBox getBoundingBox();

 private:
  void read_poses(const std::string &path);
  void centre_on_pose(class ParticleToInsert *pti, const double *pose);

  std::vector<double> poses_;       // x y z ax ay az (unit axis) per body, every rank
  std::vector<int> local_poses_;    // indices of the poses this rank inserts
};

}

#endif
#endif
