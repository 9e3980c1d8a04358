/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix wall/gran/rotating for LAMMPS (a plugin style, loaded with
   `plugin load silokit_lammps.so`): the flat bottom of a silo with an
   orifice (a circular hole in 3D, a slot in 2D), which may turn about the
   silo axis. Geometry from core/orifice_plate.h, the contact law from
   core/contact_law.h (LIGGGHTS' hooke/stiffness or hooke with tangential
   history), the wall velocity omega x r at the contact point, as the
   LIGGGHTS fix of the same name does.
   Documentation: doc/fix_wall_gran_rotating_lammps.md.

   Derived from LAMMPS' core Fix, not from FixWallGran (rewritten in
   2023): the per-atom contact history follows the pattern of
   FixWallGran of LAMMPS 20220106 (grow/copy/exchange/restart callbacks).
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_FIX_WALL_GRAN_ROTATING_H
#define SILOKIT_LAMMPS_FIX_WALL_GRAN_ROTATING_H

#include "fix.h"

#include "contact_law_keywords.h"
#include "silokit_clock.h"

namespace LAMMPS_NS {

class FixWallGranRotating : public Fix {
 public:
  FixWallGranRotating(class LAMMPS *, int, char **);
  ~FixWallGranRotating() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  double compute_vector(int) override;

  void write_restart(FILE *) override;
  void restart(char *) override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;

  // the simulated time of the whole simulation, across restarts
  double schedule_time() const;
  double angular_velocity() const;     // 0 before `start`
  double hole_radius_now() const;      // 0 (closed) before `open`

  // per-atom history: tangential spring (3), rolling angle (3), k_r of the
  // last step (1), as pair granular/jiang keeps it per pair
  enum { HISTORY_SHEAR = 0, HISTORY_ROLLING = 3, HISTORY_STIFFNESS = 6, HISTORY_SIZE = 7 };

 private:
  // contact law: the pair_coeff keywords of pair granular/jiang
  silokit_lammps::ContactLawSettings law;

  // the plate
  double centre[3];         // a point of the axis, in the plane of the plate
  double axis[3];           // unit plate normal, sense of rotation
  int normal;               // 0, 1, 2: the plane's normal direction
  double hole_radius;       // D/2
  double omega;             // rad/s once rotating, >= 0
  double start_time, open_time;

  // the schedule's clock, our own (LAMMPS 20220106 keeps no time in
  // restart files): rebased when dt changes between runs, written to
  // restart files
  silokit::StepClock clock;

  double **history;         // per atom: HISTORY_SIZE values

  // Jiang's rolling torque on grain i at its contact with the plate
  void rolling_torque(int i, const double *normal, double overlap, double kn,
                      const double *plate_spin, bool advance, double *torque);

  double local_sums[3];     // axial force, axial torque on the plate, contacts
  double global_sums[3];
  bigint reduced_step;
  int extensive[4];

  void parse(int narg, char **arg);
  void check_geometry();
};

}    // namespace LAMMPS_NS

#endif
