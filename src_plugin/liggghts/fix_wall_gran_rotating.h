/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix wall/gran/rotating: the flat bottom of a silo with an orifice (a
   circular hole in 3D, a slot in 2D), which may rotate about the silo axis:
   a `fix wall/gran` primitive plane whose contacts are resolved against the
   plate with its hole (orifice_plate.h) and whose velocity at a contact
   point is omega x r. Every contact model of fix wall/gran applies.
   Rods (atom_style spherocylinder) touch it at their ends and at the rim
   (spherocylinder_geometry.h, rule 8; fix_wall_gran_rod_contacts.h).
   Documentation: doc/fix_wall_gran_rotating.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(wall/gran/rotating,FixWallGranRotating)

#else

#ifndef LMP_FIX_WALL_GRAN_ROTATING_H
#define LMP_FIX_WALL_GRAN_ROTATING_H

#include "fix_wall_gran_rod_contacts.h"
#include "silokit_clock.h"

#include <vector>

namespace LAMMPS_NS {

class FixWallGranRotating : public FixWallGranRodContacts {
 public:
  FixWallGranRotating(class LAMMPS *, int, char **);
  void setup(int vflag);
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);

  // the simulated time `start` and `open` refer to: LIGGGHTS' time plus
  // the time reached before the restart file this run was read from
  double schedule_time() const;
  // angular velocity (rad/s) at the current time: 0 before `start`
  double angular_velocity() const;
  // radius of the hole at the current time: 0 (closed) before `open`
  double hole_radius_now() const;

 protected:
  void post_force_primitive(int vflag);
  // omega x r of the plate at a rod's contact point
  void wall_velocity(const double *point, double *velocity) const;

 private:
  double centre[3];         // a point of the axis, in the plane of the plate
  double axis[3];           // unit vector: plate normal, rotation sense
  double hole_radius;       // D/2
  double omega;             // angular velocity once rotating (rad/s), >= 0
  double start_time;        // schedule time at which the rotation starts
  double open_time;         // schedule time at which the hole opens

  // LIGGGHTS 3.8 does not keep the time in restart files and restarts its
  // clock at 0 with the first run after read_restart
  // (doc/liggghts_quirks.md); the schedule keeps its own in our restart data
  silokit::RestartClock clock;

  // sums over this rank's contacts in the last force evaluation, and their
  // reduction over all ranks, done once per step on demand
  double local_sums[3];     // axial force, axial torque on the plate, contacts
  double global_sums[3];
  bigint reduced_step;

  int extensive[4];         // extlist: which outputs are extensive

  // the command's arguments: FixWallGran's, and our keywords with their values
  struct Arguments {
    std::vector<char *> stock;
    std::vector<char *> own;
  };
  static Arguments split_arguments(class LAMMPS *, int narg, char **arg);
  FixWallGranRotating(class LAMMPS *, Arguments arguments);
  void parse_own_keywords(const std::vector<char *> &arg);
  void read_plane(const std::vector<char *> &arg);
  void check_geometry();
  // the contact of sphere i with the plate, through the contact model;
  // returns whether it touches
  bool sphere_contact(int i, double **history, double spin, double hole, double *plate_spin);
  void rod_contacts(int i, double hole);
};

}

#endif
#endif
