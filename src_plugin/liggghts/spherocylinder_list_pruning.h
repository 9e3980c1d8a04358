/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The rods' neighbour list, cut to the pairs whose cores can meet.

   LIGGGHTS lists a pair when the bounding spheres (radius L/2) come
   within the skin; for rods of L/d = 3.3 that is 4.7 times the pairs of
   spheres of the same volume, and most of them can never touch before the
   next build: the pair loop pays for each one every step. After each
   build, this helper keeps only the pairs whose core segments are closer
   than r_i + r_j + skin (or whose tangential spring is in use), in place, in
   the pair style's list and its history list together.

   That list stays complete as long as no point of any rod's core has
   moved more than skin/2 since the build (two rods then approach by at
   most the skin). LIGGGHTS checks the centres only; a rod turning about
   its centre moves its ends by up to h |delta axis|. So the helper sums,
   per rod, |delta centre| + h |delta axis| over the steps since the build
   (a bound on the travel of every point of the core) and asks for a
   build when one exceeds skin/2. The sums are per local index, which is
   valid between builds: atoms change rank or order only at a build.

   Used by fix nve/spherocylinder (keyword prune_list, default yes):
   before_move/after_move around the integrator's position update (or, by
   an integrator that has each rod's centre and axis before and after its
   move at hand, start_moves, add_move per rod and build_needed, which
   spares computing them again), and prune_after_build in pre_force.
   Documentation: doc/fix_nve_spherocylinder.md, "Neighbour list".
------------------------------------------------------------------------- */

#ifndef SILOKIT_SPHEROCYLINDER_LIST_PRUNING_H
#define SILOKIT_SPHEROCYLINDER_LIST_PRUNING_H

#include <vector>

#include "pointers.h"

namespace LAMMPS_NS {

class SpherocylinderListPruning : protected Pointers {
 public:
  explicit SpherocylinderListPruning(class LAMMPS *);

  // the positions and orientations of the group's rods before a move
  void before_move(int groupbit);
  // after the move: add each rod's travel bound; true on every rank when
  // some rod anywhere has travelled more than skin/2 since the last build
  bool after_move(int groupbit);
  // the same, rod by rod: start_moves before the first add_move of the
  // step, add_move once the rod has moved (x holds its new centre),
  // build_needed after the last one (on every rank: it communicates)
  void start_moves();
  void add_move(int i, const double *old_centre, const double *old_axis, const double *axis);
  bool build_needed();
  // if the list was built this step: cut it and restart the travel sums
  void prune_after_build();

  // totals over all ranks since the start: pairs listed by LIGGGHTS, pairs
  // kept, builds asked for because a rod turned (for the bench and tests)
  double pairs_listed() const;
  double pairs_kept() const;
  double builds_asked() const { return builds_asked_; }

 private:
  bool cores_near(int i, int j, double reach) const;

  class AtomVecSpherocylinder *avec_;
  std::vector<double> old_centre_, old_axis_, travel_, axes_;
  // the largest travel_ of this step's moves on this rank
  double farthest_;
  double pairs_listed_, pairs_kept_, builds_asked_;
};

}

#endif
