/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   atom_style spherocylinder: rods, i.e. a core segment of length L - d
   with hemispherical caps of diameter d. A sphere atom (atom_style sphere)
   plus, per rod:

     quaternion[4]  orientation; the rod's axis is the body x axis
     angmom[3]      angular momentum (space frame), what fix
                    nve/spherocylinder integrates
     shape[3]       half extents in the body frame: L/2, d/2, d/2
     inertia[3]     principal moments in the body frame: axial, transverse,
                    transverse (spherocylinder_geometry.h)

   radius is the bounding sphere's, L/2, so that the stock neighbour lists
   and PairGran::init_one's cut-off (2 radius + skin) hold every rod pair
   that can touch. Ghost rods carry quaternion and shape; angmom and
   inertia stay with the owner (only the integrator uses them).

   The sphere's packing routines are called where the buffer layout lets us
   add our values before or after theirs; exchange and restart need x first
   and the fixes' extra values last, so there ours go after the fixes'
   values (exchange, whose fixes return their sizes) or the sphere's
   routine is written out with ours in the middle (restart, whose extra
   values are sized from buf[0]). Documentation: doc/spherocylinder.md.
------------------------------------------------------------------------- */

#ifdef ATOM_CLASS

AtomStyle(spherocylinder,AtomVecSpherocylinder)

#else

#ifndef LMP_ATOM_VEC_SPHEROCYLINDER_H
#define LMP_ATOM_VEC_SPHEROCYLINDER_H

#include "atom_vec_sphere.h"

#include <set>
#include <string>

namespace LAMMPS_NS {

class AtomVecSpherocylinder : public AtomVecSphere {
 public:
  AtomVecSpherocylinder(class LAMMPS *);
  void init();
  void grow(int);
  void grow_reset();
  void copy(int, int, int);
  int pack_comm(int, int *, double *, int, int *);
  int pack_comm_vel(int, int *, double *, int, int *);
  void unpack_comm(int, int, double *);
  void unpack_comm_vel(int, int, double *);
  int pack_border(int, int *, double *, int, int *);
  int pack_border_vel(int, int *, double *, int, int *);
  void unpack_border(int, int, double *);
  void unpack_border_vel(int, int, double *);
  int pack_exchange(int, double *);
  int unpack_exchange(double *);
  int size_restart();
  int pack_restart(int, double *);
  int unpack_restart(double *);
  void create_atom(int, double *);
  void data_atom(double *, tagint, char **);
  void data_vel(int, char **);
  void pack_data(double **);
  void pack_data(double **buf, int tag_offset);
  void write_data(FILE *, int, double **);
  bigint memory_usage();

  // sets rod i's diameter, length end to end, density and axis (a unit
  // vector; the quaternion turns body x onto it), with its mass, inertia
  // and bounding radius; angular momentum from its omega
  void set_rod(int i, double diameter, double length, double density, const double *axis);
  // the space-frame axis of rod i (unit vector)
  void axis_of(int i, double *axis) const { axis_of_quaternion(quaternion[i], axis); }
  // the body x axis in space, q x q*: the first of the three axes
  // MathExtra::q_to_exyz builds, with its arithmetic (the same bits), and
  // inline. Rods need only this one, several times per rod and step (the
  // integrator, the list pruning, the walls, the pair style's pass)
  static void axis_of_quaternion(const double *q, double *axis)
  {
    axis[0] = q[0]*q[0] + q[1]*q[1] - q[2]*q[2] - q[3]*q[3];
    axis[1] = 2.0 * (q[1]*q[2] + q[0]*q[3]);
    axis[2] = 2.0 * (q[1]*q[3] - q[0]*q[2]);
  }
  // half the length of rod i's core segment, (L - d)/2 (shape holds L/2, d/2, d/2)
  double half_segment_of(int i) const { return shape[i][0] - shape[i][1]; }

 private:
  double **quaternion, **angmom, **shape, **inertia;
  // values per atom the sphere's routines pack (no radius-varying fixes:
  // init() refuses them)
  static const int SPHERE_COMM = 3, SPHERE_COMM_VEL = 9, SPHERE_RESTART = 17;
  // ours: quaternion in forward communication, quaternion and shape at
  // borders, all four arrays in exchange and restart
  static const int ROD_COMM = 4, ROD_BORDER = 7, ROD_ALL = 13;

  // IDs of the fixes and computes already warned of (check_styles_take_rods)
  std::set<std::string> warned_;

  // refuses the styles that would give rods the physics of spheres and
  // warns of the others not known to take rods (the .cpp gives the rule)
  void check_styles_take_rods();
  void warn_once(const char *kind, const char *id, const char *style);
  // the rods' part of forward communication (quaternions) and of borders
  // (quaternions and shapes), for the plain and the velocity variants
  int pack_quaternions(int n, const int *list, double *buf) const;
  void unpack_quaternions(int n, int first, const double *buf);
  int pack_rod_border(int n, const int *list, double *buf) const;
  void unpack_rod_border(int n, int first, const double *buf);
  int pack_rod_all(int i, double *buf) const;
  int unpack_rod_all(int i, const double *buf);
  void angmom_from_omega(int i);
};

}

#endif
#endif
