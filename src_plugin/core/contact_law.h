/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The contact law of a sphere pair (or a sphere and a wall) as LIGGGHTS 3.8
   computes it with `model hooke/stiffness` or `model hooke`,
   `tangential history` and `surface default`: a linear normal
   spring-dashpot and a tangential spring with history, projected onto the
   contact plane and capped by Coulomb's law. Plain functions on plain
   numbers, free of host types, so that a LAMMPS pair style or wall fix
   computes the same numbers as LIGGGHTS, to the last bit: every formula
   below keeps LIGGGHTS' order of operations (sources: surface_model_default.h,
   normal_model_hooke_stiffness.h, normal_model_hooke.h,
   tangential_model_history.h, pair_gran_base.h, fix_wall_gran_base.h,
   fix_wall_gran.cpp, global_properties.cpp of LIGGGHTS-PUBLIC 3.8).
   tests/test_contact_law.py checks it against LIGGGHTS itself.

   API (namespace silokit::contact):

     struct NormalSpring { kn, kt, gamman, gammat }
     NormalSpring hooke_stiffness(kn, kt, gamman, gammat, meff,
                                  absolute_damping, tangential_damping,
                                  nktv2p = 1)
     NormalSpring hooke(Yeff, restitution, characteristic_velocity, meff, reff,
                        tangential_damping, kt_to_kn = false, nktv2p = 1)
     double effective_youngs_modulus(Y_i, nu_i, Y_j, nu_j)       // Y*
     double pair_effective_mass(m_i, m_j)   (a wall: the grain's mass)
     double pair_effective_radius(r_i, r_j) (a wall: the grain's radius)

     struct Kinematics { n[3], r, overlap, vn, vtr[3], cri, crj }
     Kinematics pair_kinematics(x_i, x_j, v_i, v_j, omega_i, omega_j, r_i, r_j)
     Kinematics wall_kinematics(delta, wall_overlap, v_i, v_wall, omega_i, r_i)
     bool touching(x_i, x_j, r_i, r_j)        (LIGGGHTS' test rsq < radsum^2)

     double normal_force(spring, overlap, vn, limit_force)        // Fn
     bool tangential_history(shear[3], vtr, n, dt, kt, gammat, mu, Fn,
                             update, Ft[3])                       // slides?
     void torque_from_tangential(n, Ft, cri, crj, torque_i[3], torque_j[3])
     void total_force(Fn, n, Ft, force_i[3])   (grain j gets -force_i)

     struct ContactForces { force_i[3], torque_i[3], torque_j[3], Fn, Ft[3], slides }
     ContactForces contact_forces(kinematics, spring, mu, dt, limit_force,
                                  update, shear[3])   (all of the above, in order)

   Conventions: i is the grain the force is computed for, j its partner (or
   the wall); n points from j to i; overlap > 0 in contact; vn = (v_i - v_j).n
   is negative while the grains approach. `shear` is the contact's
   tangential history (3 values; zero when a contact starts or ends); the
   caller keeps it per contact. `update` is LIGGGHTS'
   computeflag && shearupdate: false during a run's set-up force call and for
   compute pair/gran/local's re-evaluation, which read the history without
   advancing it.
------------------------------------------------------------------------- */

#ifndef SILOKIT_CONTACT_LAW_H
#define SILOKIT_CONTACT_LAW_H

#include <algorithm>
#include <cmath>

namespace silokit {
namespace contact {

// ---------------------------------------------------------------- normal spring

// Spring and dashpot constants of one contact. kn, kt in N/m, gamman,
// gammat in kg/s (absolute damping coefficients).
struct NormalSpring {
  double kn;
  double kt;
  double gamman;
  double gammat;
};

// Rule 1 (`model hooke/stiffness`, normal_model_hooke_stiffness.h):
// kn, kt as given; gamman = meff*gamman_coefficient (1/s) unless
// absolute_damping (then the coefficients are in kg/s and used as given);
// gammat = 0 unless tangential_damping (LIGGGHTS' default: on). kn and kt
// are divided by nktv2p (1 in SI) after the damping is formed, as LIGGGHTS
// does.
inline NormalSpring hooke_stiffness(double kn, double kt, double gamman, double gammat,
                                    double meff, bool absolute_damping,
                                    bool tangential_damping, double nktv2p = 1.0)
{
  NormalSpring s;
  if (absolute_damping) {
    s.gamman = gamman;
    s.gammat = gammat;
  } else {
    s.gamman = meff*gamman;
    s.gammat = meff*gammat;
  }
  if (!tangential_damping) s.gammat = 0.0;
  s.kn = kn/nktv2p;
  s.kt = kt/nktv2p;
  return s;
}

// Rule 2 (global_properties.cpp, createYeff): the effective Young's modulus
// of a type pair, 1/((1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j), with pow(nu, 2.) as
// LIGGGHTS writes it. For a wall, i and j are the grain's and the wall's
// types.
inline double effective_youngs_modulus(double youngs_i, double poisson_i,
                                       double youngs_j, double poisson_j)
{
  return 1./((1.-std::pow(poisson_i, 2.))/youngs_i + (1.-std::pow(poisson_j, 2.))/youngs_j);
}

// Rule 3 (pair_gran_base.h): meff = m_i m_j/(m_i + m_j) for two grains. A
// grain in the pair's freeze group counts as infinitely heavy (meff = the
// other's mass); a wall too: fix_wall_gran_base.h sets meff = m_i (the
// rigid body's mass for a grain in a rigid body; not covered here).
inline double pair_effective_mass(double mass_i, double mass_j)
{
  return mass_i*mass_j/(mass_i + mass_j);
}

// Rule 4 (normal_model_hooke.h): reff = r_i r_j/(r_i + r_j); a wall: r_i.
inline double pair_effective_radius(double radius_i, double radius_j)
{
  return radius_i*radius_j/(radius_i + radius_j);
}

// Rule 5 (`model hooke`, normal_model_hooke.h), in LIGGGHTS' order:
//   kn = 16/15 sqrt(reff) Y* (15 meff v_char^2 / (16 sqrt(reff) Y*))^(1/5)
//   kt = kn (times 0.285714286, LIGGGHTS' rounded 2/7, with ktToKnUser)
//   gamman = sqrt(4 meff kn ln^2(e) / (ln^2(e) + pi^2)),  from kn before the
//            division by nktv2p
//   gammat = gamman with tangential_damping (LIGGGHTS' default), else 0
// pow(., 0.2) and sqrt as LIGGGHTS calls them. LIGGGHTS' hooke also reads
// Geff (shear modulus) but does not use it. Not covered: the `viscous`
// option (restitution from a Stokes number).
inline NormalSpring hooke(double youngs_effective, double restitution,
                          double characteristic_velocity, double meff, double reff,
                          bool tangential_damping, bool kt_to_kn = false,
                          double nktv2p = 1.0)
{
  const double log_restitution = std::log(restitution);   // createCoeffRestLog
  const double sqrtval = std::sqrt(reff);
  double kn = 16./15.*sqrtval*(youngs_effective)*
              std::pow(15.*meff*characteristic_velocity*characteristic_velocity/
                       (16.*sqrtval*youngs_effective), 0.2);
  double kt = kn;
  if (kt_to_kn) kt *= 0.285714286;
  const double log_squared = log_restitution*log_restitution;
  const double pi = 3.14159265358979323846;   // M_PI's digits (M_PI is not ISO C++)
  const double gamman = std::sqrt(4.*meff*kn*log_squared/(log_squared + pi*pi));
  NormalSpring s;
  s.gamman = gamman;
  s.gammat = tangential_damping ? gamman : 0.0;
  s.kn = kn/nktv2p;
  s.kt = kt/nktv2p;
  return s;
}

// Rule 6 (both normal models): Fn = -gamman vn + kn overlap (damping first,
// as LIGGGHTS adds them); with limit_force (LIGGGHTS' limitForce) a
// negative (attractive) Fn becomes 0. The force on i is Fn n.
inline double normal_force(const NormalSpring &spring, double overlap, double vn,
                           bool limit_force)
{
  const double damping = -spring.gamman*vn;
  const double contact = spring.kn*overlap;
  double fn = damping + contact;
  if (limit_force && fn < 0.0) fn = 0.0;
  return fn;
}

// ---------------------------------------------------------------- kinematics

// What surface_model_default.h hands to the normal and tangential models.
struct Kinematics {
  double n[3];      // unit normal, from j (or the wall) to i
  double r;         // centre distance (a wall: r_i - overlap)
  double rinv;      // 1/r
  double overlap;   // delta_n = r_i + r_j - r (a wall: r_i - r)
  double vn;        // (v_i - v_j).n, < 0 approaching
  double vtr[3];    // relative tangential velocity of the contact point
  double cri;       // lever arm of i: r_i - overlap/2
  double crj;       // lever arm of j: r_j - overlap/2 (a wall: unused, 0)
};

namespace detail {

// Rule 7 (surface_model_default.h): from the normal n and the scaled
// relative angular velocity w = (cri omega_i + crj omega_j)/r, with
// delta = x_i - x_j (n = delta/r):
//   vn  = (v_i - v_j).n,   vt = (v_i - v_j) - vn n
//   vtr = vt - (delta x w)
// i.e. vt minus (cri omega_i + crj omega_j) x n, written as LIGGGHTS
// does, through delta and 1/r (not through n), component by component.
inline void relative_velocity(Kinematics &k, const double delta[3], const double v_i[3],
                              const double v_j[3], const double wr[3])
{
  const double vr1 = v_i[0] - v_j[0];
  const double vr2 = v_i[1] - v_j[1];
  const double vr3 = v_i[2] - v_j[2];
  const double vn = vr1*k.n[0] + vr2*k.n[1] + vr3*k.n[2];
  const double vt1 = vr1 - vn*k.n[0];
  const double vt2 = vr2 - vn*k.n[1];
  const double vt3 = vr3 - vn*k.n[2];
  const double dx = delta[0], dy = delta[1], dz = delta[2];
  k.vn = vn;
  k.vtr[0] = vt1 - (dz*wr[1] - dy*wr[2]);
  k.vtr[1] = vt2 - (dx*wr[2] - dz*wr[0]);
  k.vtr[2] = vt3 - (dy*wr[0] - dx*wr[1]);
}

}  // namespace detail

// Rule 8 (pair_gran_base.h): the contact test of two spheres, rsq < radsum^2.
inline bool touching(const double x_i[3], const double x_j[3], double radius_i, double radius_j)
{
  const double delx = x_i[0] - x_j[0];
  const double dely = x_i[1] - x_j[1];
  const double delz = x_i[2] - x_j[2];
  const double rsq = delx*delx + dely*dely + delz*delz;
  const double radsum = radius_i + radius_j;
  return rsq < radsum*radsum;
}

// Rule 9 (pair_gran_base.h, surface_model_default.h): two spheres in
// contact. r = sqrt(rsq), n = delta*(1/r) (a multiplication by 1/r, not a
// division), overlap = (r_i + r_j) - r, lever arms r_i - overlap/2 and
// r_j - overlap/2 (written radi - 0.5*deltan).
inline Kinematics pair_kinematics(const double x_i[3], const double x_j[3],
                                  const double v_i[3], const double v_j[3],
                                  const double omega_i[3], const double omega_j[3],
                                  double radius_i, double radius_j)
{
  Kinematics k;
  const double delta[3] = { x_i[0] - x_j[0], x_i[1] - x_j[1], x_i[2] - x_j[2] };
  const double rsq = delta[0]*delta[0] + delta[1]*delta[1] + delta[2]*delta[2];
  const double radsum = radius_i + radius_j;
  k.r = std::sqrt(rsq);
  k.rinv = 1.0/k.r;
  for (int d = 0; d < 3; ++d) k.n[d] = delta[d]*k.rinv;
  k.overlap = radsum - k.r;
  k.cri = radius_i - 0.5*k.overlap;
  k.crj = radius_j - 0.5*k.overlap;
  double wr[3];
  for (int d = 0; d < 3; ++d) wr[d] = (k.cri*omega_i[d] + k.crj*omega_j[d])*k.rinv;
  detail::relative_velocity(k, delta, v_i, v_j, wr);
  return k;
}

// Rule 10 (fix_wall_gran.cpp, fix_wall_gran_base.h, surface_model_default.h):
// a sphere against a wall. The wall reports delta (the vector from the
// wall's nearest point to the centre of i) and its overlap (r_i minus the
// distance, as the wall computes it: a plane at z0 gives
// -((z - z0) - r_i)). LIGGGHTS then takes r = r_i - overlap (not |delta|),
// n = delta*(1/r), the lever arm r_i - overlap/2 from the wall's overlap,
// and then replaces the overlap by r_i - r (which can differ from the
// wall's in the last bit) for the normal force. The lever arm is
// r_i - overlap/2, as for a pair (not r_i). v_wall is the wall's velocity
// at the contact (0 for a fixed wall). A primitive wall counts a contact
// when its gap (distance - r_i) is <= 0, a pair only when rsq < radsum^2
// (Rule 8): a grain exactly touching a wall feels it, a grain exactly
// touching another does not.
inline Kinematics wall_kinematics(const double delta[3], double wall_overlap,
                                  const double v_i[3], const double v_wall[3],
                                  const double omega_i[3], double radius_i)
{
  Kinematics k;
  k.r = radius_i - wall_overlap;
  k.rinv = 1.0/k.r;
  for (int d = 0; d < 3; ++d) k.n[d] = delta[d]*k.rinv;
  k.cri = radius_i - 0.5*wall_overlap;
  k.crj = 0.0;
  k.overlap = radius_i - k.r;          // radsum - r, radsum = r_i
  double wr[3];
  for (int d = 0; d < 3; ++d) wr[d] = k.cri*omega_i[d]*k.rinv;
  detail::relative_velocity(k, delta, v_i, v_wall, wr);
  return k;
}

// ---------------------------------------------------------------- tangential spring

// Rule 11 (`tangential history`, tangential_model_history.h), step for step:
//   a. if update: shear += vtr dt, then its normal component is removed
//      (shear -= (shear.n) n); its length is NOT restored (LIGGGHTS 3.8
//      does not rescale, unlike LAMMPS' gran/hooke/history);
//   b. spring force Ft = -kt shear;
//   c. Coulomb cap on the spring force alone: if kt |shear| > mu |Fn|,
//      Ft is scaled to length mu |Fn| (Ft = 0 if shear is 0) and, if
//      update, shear = -Ft/kt; no damping while sliding;
//   d. otherwise (sticking) Ft -= gammat vtr.
// The comparison is kt*|shear| > mu*|Fn| with |shear| from sqrt, as
// LIGGGHTS computes it. Returns true when the contact slides (c).
inline bool tangential_history(double shear[3], const double vtr[3], const double n[3],
                               double dt, double kt, double gammat, double mu, double fn,
                               bool update, double ft[3])
{
  if (update) {
    shear[0] += vtr[0]*dt;
    shear[1] += vtr[1]*dt;
    shear[2] += vtr[2]*dt;
    const double rsht = shear[0]*n[0] + shear[1]*n[1] + shear[2]*n[2];
    shear[0] -= rsht*n[0];
    shear[1] -= rsht*n[1];
    shear[2] -= rsht*n[2];
  }
  const double shrmag = std::sqrt(shear[0]*shear[0] + shear[1]*shear[1] + shear[2]*shear[2]);
  for (int d = 0; d < 3; ++d) ft[d] = -(kt*shear[d]);
  const double ft_shear = kt*shrmag;
  const double ft_friction = mu*std::fabs(fn);
  if (ft_shear > ft_friction) {
    if (shrmag != 0.0) {
      const double ratio = ft_friction/ft_shear;
      for (int d = 0; d < 3; ++d) ft[d] *= ratio;
      if (update)
        for (int d = 0; d < 3; ++d) shear[d] = -ft[d]/kt;
    } else {
      ft[0] = ft[1] = ft[2] = 0.0;
    }
    return true;
  }
  for (int d = 0; d < 3; ++d) ft[d] -= gammat*vtr[d];
  return false;
}

// Rule 12 (tangential_model_history.h): the torques of the tangential force,
// -cri (n x Ft) on i and -crj (n x Ft) on j (the same sign: Ft acts on i,
// -Ft on j, at lever arms pointing the opposite ways). A wall takes none.
inline void torque_from_tangential(const double n[3], const double ft[3], double cri,
                                   double crj, double torque_i[3], double torque_j[3])
{
  const double tor1 = n[1]*ft[2] - n[2]*ft[1];
  const double tor2 = n[2]*ft[0] - n[0]*ft[2];
  const double tor3 = n[0]*ft[1] - n[1]*ft[0];
  torque_i[0] = -cri*tor1;
  torque_i[1] = -cri*tor2;
  torque_i[2] = -cri*tor3;
  torque_j[0] = -crj*tor1;
  torque_j[1] = -crj*tor2;
  torque_j[2] = -crj*tor3;
}

// Rule 13 (normal model, then tangential model, into one ForceData): the
// force on i is (Fn n) + Ft, summed in that order; j gets exactly
// -force_i.
inline void total_force(double fn, const double n[3], const double ft[3], double force_i[3])
{
  for (int d = 0; d < 3; ++d) force_i[d] = fn*n[d] + ft[d];
}

// ---------------------------------------------------------------- one contact

struct ContactForces {
  double force_i[3];    // on i; j gets -force_i
  double torque_i[3];
  double torque_j[3];   // zero for a wall
  double fn;            // normal force (> 0 repulsive)
  double ft[3];         // tangential force on i
  bool slides;
};

// The whole contact, in LIGGGHTS' order: normal model (Rule 6), tangential
// model (Rule 11), torques (Rule 12), force (Rule 13). shear is advanced
// when update is true.
inline ContactForces contact_forces(const Kinematics &k, const NormalSpring &spring,
                                    double mu, double dt, bool limit_force, bool update,
                                    double shear[3])
{
  ContactForces c;
  c.fn = normal_force(spring, k.overlap, k.vn, limit_force);
  c.slides = tangential_history(shear, k.vtr, k.n, dt, spring.kt, spring.gammat, mu, c.fn,
                                update, c.ft);
  torque_from_tangential(k.n, c.ft, k.cri, k.crj, c.torque_i, c.torque_j);
  total_force(c.fn, k.n, c.ft, c.force_i);
  return c;
}

}  // namespace contact
}  // namespace silokit

#endif
