/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   compute ID group spherocylinder/axis

   Per rod (atom_style spherocylinder) the unit vector of its axis in the
   space frame, 3 columns (c_ID[1] c_ID[2] c_ID[3] in dump custom), 0 for
   atoms outside the group: what the coarse graining of orientation
   (analysis/common/coarse_grain.py, O_ij and S) is made from. Documentation:
   doc/spherocylinder.md.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS

ComputeStyle(spherocylinder/axis,ComputeSpherocylinderAxis)

#else

#ifndef LMP_COMPUTE_SPHEROCYLINDER_AXIS_H
#define LMP_COMPUTE_SPHEROCYLINDER_AXIS_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeSpherocylinderAxis : public Compute {
 public:
  ComputeSpherocylinderAxis(class LAMMPS *, int &iarg, int, char **);
  ~ComputeSpherocylinderAxis();
  void init() {}
  void compute_peratom();
  double memory_usage();

 private:
  int nmax;
  double **axes;
};

}

#endif
#endif
