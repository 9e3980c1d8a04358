/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix ID group nve/spherocylinder [integration_scheme symmetric_top|0|1|2|3]
                                   [prune_list yes|no]

   Velocity Verlet for the translation and the rigid-body rotation of rods
   (atom_style spherocylinder). Rotation, integration_scheme:
   - symmetric_top (the default): a half kick of the space-frame angular
     momentum L by the torque, the exact free motion of a symmetric top
     for dt (the axis turns about L at |L|/I_t, the rod spins about its
     axis at (L.u)(1/I_a - 1/I_t)), a second half kick. A Strang splitting
     of exact flows: second order, symplectic, time-reversible, and exact
     without torque; two sine-cosine pairs per rod and step.
   - 0 to 3: LIGGGHTS' FixNVEAsphereBase (the superquadric integrator's),
     1 its no-squish scheme (Miller et al. 2002), 0 Richardson's
     iteration; they treat any inertia tensor and cost about seven times
     more.
   omega is kept consistent with the angular momentum. A time step above
   a tenth of the contact time of two rods crossing at their ends warns.

   With prune_list yes (the default) the fix also cuts the pair style's
   neighbour list to the pairs whose cores can meet before the next build,
   and asks for a build when a rod has turned far enough to need one
   (spherocylinder_list_pruning.h). Global vector: pairs listed by
   LIGGGHTS and pairs kept, summed over the builds since the fix was
   defined, and the builds it asked for. Documentation:
   doc/spherocylinder.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(nve/spherocylinder,FixNVESpherocylinder)

#else

#ifndef LMP_FIX_NVE_SPHEROCYLINDER_H
#define LMP_FIX_NVE_SPHEROCYLINDER_H

#include <memory>
#include <string>
#include <vector>

#include "fix_nve_asphere_base.h"
#include "spherocylinder_list_pruning.h"

namespace LAMMPS_NS {

class FixNVESpherocylinder : public FixNVEAsphereBase {
 public:
  FixNVESpherocylinder(class LAMMPS *, int, char **);
  ~FixNVESpherocylinder();
  int setmask();
  void init();
  void initial_integrate(int);
  void final_integrate();
  void setup_pre_force(int);
  void pre_force(int);
  double compute_vector(int);

 private:
  // the public constructor checks the arguments and hands `base`, the
  // ones FixNVEAsphereBase knows, to this one
  FixNVESpherocylinder(class LAMMPS *, int narg, char **arg, std::vector<char *> base);
  static std::vector<char *> base_arguments(class LAMMPS *, int narg, char **arg);
  static std::string keyword_value(int narg, char **arg, const std::string &keyword,
                                   const std::string &fallback);
  void warn_if_time_step_is_coarse();
  void half_kick(int i);
  void symmetric_top_first_half();
  void symmetric_top_second_half();

  class AtomVecSpherocylinder *rods_;
  bool symmetric_top_;

  // empty with prune_list no
  std::unique_ptr<SpherocylinderListPruning> pruning_;
};

}

#endif
#endif
