/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The rolling resistance law of Jiang, Yu & Harris (2005) in its simplified
   form, as used by Magalhaes, Atman, Combe & Moreira (2014), eq. 1:

       tau = -k_r delta_r            while k_r |delta_r| <= mu_r f_el
       tau = -mu_r f_el delta_r/|delta_r|  otherwise

   written as plain functions of plain numbers, free of LIGGGHTS types, so
   that rolling_model_jiang.h stays a thin adapter and the law can be reused
   (or ported to modern LAMMPS) unchanged.
------------------------------------------------------------------------- */

#ifndef SILOKIT_ROLLING_LAW_JIANG_H
#define SILOKIT_ROLLING_LAW_JIANG_H

#include <algorithm>
#include <cmath>

namespace silokit {
namespace jiang {

// Length of the contact line between two discs (2D: the chord of their
// overlap) or diameter of the contact circle of two spheres (3D); both are
// 2a, with a the radius of the intersection of the two circles/spheres of
// radii radius_i, radius_j whose centres are `distance` apart.
inline double overlap_contact_length(double radius_i, double radius_j, double distance)
{
  // distance from centre i to the plane (line) of the intersection
  const double x = (distance*distance + radius_i*radius_i - radius_j*radius_j) / (2.0*distance);
  const double a_squared = radius_i*radius_i - x*x;
  return a_squared > 0.0 ? 2.0*std::sqrt(a_squared) : 0.0;
}

// The same for a disc or sphere of radius `radius` pressed `overlap` deep
// into a flat wall (the limit radius_j -> infinity of the above).
inline double wall_overlap_contact_length(double radius, double overlap)
{
  const double a_squared = overlap*(2.0*radius - overlap);
  return a_squared > 0.0 ? 2.0*std::sqrt(a_squared) : 0.0;
}

// Jiang's stiffness and cap at one contact, from the contact length l_c:
//   k_r   = a k_n l_c^2                 (a: stiffness_factor)
//   mu_r  = b mu l_c                    (b: friction_factor)
//   limit = mu_r max(f_el, 0), f_el = k_n delta_n (an opening contact holds
//           no torque)
// k_n is the normal model's (secant) stiffness, delta_n the overlap.
struct RollingSpring {
  double stiffness;       // k_r
  double torque_limit;    // mu_r f_el
};

inline RollingSpring rolling_spring(double normal_stiffness, double overlap, double friction,
                                    double contact_length, double stiffness_factor,
                                    double friction_factor)
{
  const double elastic_normal_force = normal_stiffness*overlap;
  RollingSpring spring;
  spring.stiffness = stiffness_factor*normal_stiffness*contact_length*contact_length;
  spring.torque_limit = friction_factor*friction*contact_length*
                        std::max(elastic_normal_force, 0.0);
  return spring;
}

// Removes from v its component along the unit normal, then restores the
// length v had: the stored rolling angle turns with the contact instead of
// shrinking as the contact rotates, as LIGGGHTS does with the tangential
// spring.
inline void rotate_into_tangent_plane(double v[3], const double normal[3])
{
  const double along_normal = v[0]*normal[0] + v[1]*normal[1] + v[2]*normal[2];
  if (along_normal == 0.0) return;  // in the plane already (always so in 2D)
  const double length_squared = v[0]*v[0] + v[1]*v[1] + v[2]*v[2];
  const double in_plane_squared = length_squared - along_normal*along_normal;
  for (int k = 0; k < 3; ++k) v[k] -= along_normal*normal[k];
  // (an angle normal to the plane has no direction in it: it goes.) The
  // test is written so that no operand is subnormal: 1e-300*length_squared
  // is below 2.2e-308 for angles under ~1.5e-4 rad, and a product that
  // small takes the processor's slow path (33 ns a call instead of 10 ns;
  // 13 % of a 3D LAMMPS run with Jiang's law, bench/lammps_pair_cost.py)
  const double scale = in_plane_squared*1e300 > length_squared
                     ? std::sqrt(length_squared/in_plane_squared) : 0.0;
  for (int k = 0; k < 3; ++k) v[k] *= scale;
}

// Removes from w its component along the unit normal (the twisting part of
// a relative rotation, which rolling resistance ignores).
inline void remove_normal_component(double w[3], const double normal[3])
{
  const double along_normal = w[0]*normal[0] + w[1]*normal[1] + w[2]*normal[2];
  for (int k = 0; k < 3; ++k) w[k] -= along_normal*normal[k];
}

// Adapts the stored rolling angle to a stiffness that changed since the
// last step (contact length from the overlap, or a non-linear normal
// model). The paper does not say what happens then; we take Jiang's picture
// of a contact line of springs: springs that join at the rim of a growing
// contact start unstretched, so the torque stays (the angle shrinks by
// old/new), and springs lost at the rim of a shrinking contact take their
// load with them, so the angle stays and the torque drops with k_r. Either
// way the spring energy k_r |angle|^2 / 2 never grows without a relative
// rotation: a contact whose overlap oscillates cannot pump energy into the
// rolling mode.
inline void adapt_to_stiffness(double rolling_angle[3], double old_stiffness,
                               double new_stiffness)
{
  if (new_stiffness > old_stiffness) {
    const double scale = old_stiffness/new_stiffness;
    for (int k = 0; k < 3; ++k) rolling_angle[k] *= scale;
  }
}

// The elastic-perfectly plastic rolling spring. rolling_angle (radians,
// a vector in the tangent plane) is the accumulated relative rotation; when
// the spring torque would exceed torque_limit, rolling_angle is cut back to
// the limit so that a reversal unloads elastically from there. Writes the
// torque on grain i (grain j gets the opposite) and returns true when the
// contact rolls (spring saturated).
inline bool spring_torque(double rolling_angle[3], double stiffness, double torque_limit,
                          double torque[3])
{
  // compare squares: the square root is needed only on the plastic branch
  const double angle_squared = rolling_angle[0]*rolling_angle[0] +
                               rolling_angle[1]*rolling_angle[1] +
                               rolling_angle[2]*rolling_angle[2];
  const bool saturated = stiffness*stiffness*angle_squared > torque_limit*torque_limit;
  if (saturated) {
    const double scale = torque_limit/(stiffness*std::sqrt(angle_squared));
    for (int k = 0; k < 3; ++k) rolling_angle[k] *= scale;
  }
  for (int k = 0; k < 3; ++k) torque[k] = -stiffness*rolling_angle[k];
  return saturated;
}

// One step of a contact's rolling spring. rolling_angle holds the angle
// stored at the last step (zero for a new contact) and, on return, this
// step's; with `advance` it is first turned into the present tangent plane,
// adapted to the present stiffness (old_stiffness: k_r of the last step)
// and grown by relative_omega dt. Without `advance` (the force call that
// sets up a run) the stored angle gives the torque as it is, so that a run
// split in two or restarted continues exactly. Writes the torque on grain i
// and returns true when the contact rolls. Every host adapter stores
// rolling_angle and spring.stiffness back when advancing.
inline bool step_rolling_spring(double rolling_angle[3], double old_stiffness,
                                const double normal[3], const double relative_omega[3],
                                const RollingSpring &spring, double dt, bool advance,
                                double torque[3])
{
  if (advance) {
    rotate_into_tangent_plane(rolling_angle, normal);
    adapt_to_stiffness(rolling_angle, old_stiffness, spring.stiffness);
    for (int k = 0; k < 3; ++k) rolling_angle[k] += relative_omega[k]*dt;
  }
  return spring_torque(rolling_angle, spring.stiffness, spring.torque_limit, torque);
}

// Viscous rolling damping, for the elastic branch only (as LIGGGHTS'
// epsd3: a rolling contact already dissipates through its cap): `ratio` of
// the critical damping 2 sqrt(I k_r), with I the reduced inertia about the
// contact point.
inline void add_rolling_damping(double ratio, double inertia, double stiffness,
                                const double relative_omega[3], double torque[3])
{
  const double damping = ratio*2.0*std::sqrt(inertia*stiffness);
  for (int k = 0; k < 3; ++k) torque[k] -= damping*relative_omega[k];
}

}  // namespace jiang
}  // namespace silokit

#endif
