/* ----------------------------------------------------------------------
   An example of a user's own style, compiled into silokit's liggghts with
   -DSILOKIT_USER_STYLES=examples/extend (doc/extend.md).

   fix plane/crossings: counts the grains of a group that cross a
   horizontal plane downwards, writes each crossing with the grain's
   velocity, and the flow rate every N steps.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(plane/crossings,FixPlaneCrossings)

#else

#ifndef LMP_FIX_PLANE_CROSSINGS_H
#define LMP_FIX_PLANE_CROSSINGS_H

#include "fix.h"
#include <cstdio>
#include <vector>

namespace LAMMPS_NS {

class FixPlaneCrossings : public Fix {
 public:
  FixPlaneCrossings(class LAMMPS *, int, char **);
  ~FixPlaneCrossings();
  int setmask();
  void post_integrate();
  void end_of_step();
  double compute_vector(int);

 private:
  double plane_z;               // the plane: z = plane_z, horizontal
  FILE *crossings_file;         // one line per crossing (rank 0; may be null)
  FILE *rate_file;              // one line every nevery steps (rank 0; may be null)
  bool write_each_crossing;     // 'crossings' given (known to every rank)
  double total_grains, total_mass;     // crossings since the fix was defined
  double window_grains, window_mass;   // crossings since the last rate line
  bigint window_start;                 // step the current rate window began at
  // crossings of this step on this rank: id x y vx vy vz mass, flattened
  std::vector<double> found;

  FILE *open_record(const char *keyword, const char *path, const char *header);
  void write_crossings(const std::vector<double> &rows);
};

}

#endif
#endif
