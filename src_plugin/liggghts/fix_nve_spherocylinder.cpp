/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix nve/spherocylinder (fix_nve_spherocylinder.h).
------------------------------------------------------------------------- */

#include "fix_nve_spherocylinder.h"

#include <cstring>
#include <string>
#include <vector>

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "error.h"
#include "fix_property_global.h"
#include "math_const.h"
#include "math_extra.h"
#include "modify.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace LAMMPS_NS;

FixNVESpherocylinder::FixNVESpherocylinder(LAMMPS *lmp, int narg, char **arg) :
  FixNVESpherocylinder(lmp, narg, arg, base_arguments(lmp, narg, arg))
{
}

// `base` lives until this constructor returns: FixNVEAsphereBase reads it
// while it is constructed and keeps no pointer to it
FixNVESpherocylinder::FixNVESpherocylinder(LAMMPS *lmp, int narg, char **arg,
                                           std::vector<char *> base) :
  FixNVEAsphereBase(lmp, static_cast<int>(base.size()), base.data()),
  rods_(dynamic_cast<AtomVecSpherocylinder *>(atom->avec)),
  symmetric_top_(keyword_value(narg, arg, "integration_scheme", "symmetric_top") == "symmetric_top")
{
  if (!rods_) error->fix_error(FLERR, this, "needs atom_style spherocylinder");
  if (keyword_value(narg, arg, "prune_list", "yes") == "yes") {
    pruning_.reset(new SpherocylinderListPruning(lmp));
    // the builds a turning rod needs: Neighbor::decide checks next_reneighbor
    force_reneighbor = 1;
    next_reneighbor = -1;
  }
  vector_flag = 1;
  size_vector = 3;
  global_freq = 1;
  extvector = 0;
}

FixNVESpherocylinder::~FixNVESpherocylinder() = default;

int FixNVESpherocylinder::setmask()
{
  return FixNVEAsphereBase::setmask() | FixConst::PRE_FORCE;
}

/* ----------------------------------------------------------------------
   FixNVEAsphereBase reads its keyword unchecked (a missing value is read
   past the arguments, scheme 4 needs CFD coupling and crashes without it,
   another number stops the first step): check them first. Then the list
   it gets, a copy of the pointers (the caller's list stays as it is): id,
   group, style and the numbered integration_scheme pairs, in their order;
   it knows no other keyword.
------------------------------------------------------------------------- */

std::vector<char *> FixNVESpherocylinder::base_arguments(LAMMPS *lmp, int narg, char **arg)
{
  for (int i = 3; i < narg; i += 2) {
    const std::string keyword = arg[i];
    const std::string value = i + 1 < narg ? arg[i + 1] : "";
    if (keyword == "integration_scheme") {
      if (value != "symmetric_top" && value != "0" && value != "1" && value != "2" && value != "3")
        lmp->error->all(FLERR, "fix nve/spherocylinder: 'integration_scheme' takes symmetric_top "
                               "(the default), 0 (Richardson), 1 (no-squish), 2 or 3");
    } else if (keyword == "prune_list") {
      if (value != "yes" && value != "no")
        lmp->error->all(FLERR, "fix nve/spherocylinder: 'prune_list' takes yes (the default) or no");
    } else {
      lmp->error->all(FLERR, ("fix nve/spherocylinder: unknown keyword '" + keyword +
                              "' (integration_scheme, prune_list)").c_str());
    }
  }
  std::vector<char *> base(arg, arg + (narg < 3 ? narg : 3));
  for (int i = 3; i < narg; i += 2) {
    if (std::string(arg[i]) != "integration_scheme" || std::string(arg[i + 1]) == "symmetric_top")
      continue;
    base.push_back(arg[i]);
    base.push_back(arg[i + 1]);
  }
  return base;
}

// the value given to `keyword` (the last one if given twice), or `fallback`;
// the arguments were checked by base_arguments
std::string FixNVESpherocylinder::keyword_value(int narg, char **arg, const std::string &keyword,
                                                const std::string &fallback)
{
  std::string value = fallback;
  for (int i = 3; i + 1 < narg; i += 2)
    if (keyword == arg[i]) value = arg[i + 1];
  return value;
}

void FixNVESpherocylinder::init()
{
  FixNVEAsphereBase::init();
  // a sphere integrator on the same rods would move them twice and turn
  // them as spheres
  for (int i = 0; i < modify->nfix; i++) {
    Fix *other = modify->fix[i];
    if (other == this || !other->time_integrate) continue;
    int shared = 0, shared_anywhere = 0;
    for (int j = 0; j < atom->nlocal; ++j)
      if ((atom->mask[j] & groupbit) && (atom->mask[j] & other->groupbit)) shared = 1;
    MPI_Allreduce(&shared, &shared_anywhere, 1, MPI_INT, MPI_MAX, world);
    if (!shared_anywhere) continue;
    error->fix_error(FLERR, this, (std::string("fix ") + other->id + " (" + other->style +
                                   ") also integrates these rods: use only nve/spherocylinder").c_str());
  }
  warn_if_time_step_is_coarse();
}

void FixNVESpherocylinder::initial_integrate(int vflag)
{
  bool build = false;
  if (symmetric_top_) {
    // the rods' travel is added rod by rod, as each moves
    if (pruning_) pruning_->start_moves();
    symmetric_top_first_half();
    build = pruning_ && pruning_->build_needed();
  } else {
    if (pruning_) pruning_->before_move(groupbit);
    FixNVEAsphereBase::initial_integrate(vflag);
    build = pruning_ && pruning_->after_move(groupbit);
  }
  // Neighbor::decide runs after the integration, in this step
  if (build) next_reneighbor = update->ntimestep;
}

void FixNVESpherocylinder::final_integrate()
{
  if (symmetric_top_) symmetric_top_second_half();
  else FixNVEAsphereBase::final_integrate();
}

/* ----------------------------------------------------------------------
   integration_scheme symmetric_top. A rod is a symmetric top: moments
   I_a about its axis u (body x), I_t across it. Its angular velocity
   follows from the space-frame angular momentum L as
     omega = L/I_t + (1/I_a - 1/I_t) (L.u) u,
   and without torque L is constant and the motion is known exactly: u
   turns about L at |L|/I_t (the u-part of omega does not move u), while
   the body spins about u at (L.u)(1/I_a - 1/I_t). So a step is
     L += dt/2 torque; x += dt v (v kicked likewise);
     q <- rotation about L by |L| dt/I_t  *  q  *  rotation about body x
          by (L.u)(1/I_a - 1/I_t) dt;
     (forces) L += dt/2 torque; omega from L and the new u.
   The two rotations commute (one about a space axis, the other about
   a body axis): this is the free flow of the top, not an approximation.
------------------------------------------------------------------------- */

namespace {

// omega of a symmetric top with moments axial = I_a, transverse = I_t
void top_omega(const double *angmom, const double *axis, double axial, double transverse,
               double *omega)
{
  const double along = angmom[0]*axis[0] + angmom[1]*axis[1] + angmom[2]*axis[2];
  const double extra = along*(1.0/axial - 1.0/transverse);
  for (int k = 0; k < 3; ++k) omega[k] = angmom[k]/transverse + extra*axis[k];
}

}  // namespace

// the half kick of velocity Verlet: v by the force, L by the torque
void FixNVESpherocylinder::half_kick(int i)
{
  const double dtfm = dtf/atom->rmass[i];
  for (int k = 0; k < 3; ++k) {
    atom->v[i][k] += dtfm*atom->f[i][k];
    atom->angmom[i][k] += dtf*atom->torque[i][k];
  }
}

void FixNVESpherocylinder::symmetric_top_first_half()
{
  double **x = atom->x, **v = atom->v;
  double **angmom = atom->angmom, **omega = atom->omega;
  double **quat = atom->quaternion, **inertia = atom->inertia;
  const int *mask = atom->mask;
  const int nlocal = igroup == atom->firstgroup ? atom->nfirst : atom->nlocal;
  for (int i = 0; i < nlocal; ++i) {
    if (!(mask[i] & groupbit)) continue;
    half_kick(i);
    const double old_centre[3] = {x[i][0], x[i][1], x[i][2]};
    for (int k = 0; k < 3; ++k) x[i][k] += dtv*v[i][k];
    const double axial = inertia[i][0], transverse = inertia[i][1];
    double old_axis[3], axis[3];
    rods_->axis_of(i, old_axis);
    for (int k = 0; k < 3; ++k) axis[k] = old_axis[k];
    const double along = angmom[i][0]*axis[0] + angmom[i][1]*axis[1] + angmom[i][2]*axis[2];
    const double size = std::sqrt(angmom[i][0]*angmom[i][0] + angmom[i][1]*angmom[i][1] +
                                  angmom[i][2]*angmom[i][2]);
    if (size > 0.0) {
      const double direction[3] = {angmom[i][0]/size, angmom[i][1]/size, angmom[i][2]/size};
      double precession[4], spin[4], spun[4], turned[4];
      const double body_x[3] = {1.0, 0.0, 0.0};
      MathExtra::axisangle_to_quat(direction, size/transverse*dtv, precession);
      MathExtra::axisangle_to_quat(body_x, along*(1.0/axial - 1.0/transverse)*dtv, spin);
      MathExtra::quatquat(quat[i], spin, spun);
      MathExtra::quatquat(precession, spun, turned);
      MathExtra::qnormalize(turned);
      for (int k = 0; k < 4; ++k) quat[i][k] = turned[k];
      rods_->axis_of(i, axis);
    }
    top_omega(angmom[i], axis, axial, transverse, omega[i]);
    if (pruning_) pruning_->add_move(i, old_centre, old_axis, axis);
  }
}

void FixNVESpherocylinder::symmetric_top_second_half()
{
  double **inertia = atom->inertia;
  const int *mask = atom->mask;
  const int nlocal = igroup == atom->firstgroup ? atom->nfirst : atom->nlocal;
  for (int i = 0; i < nlocal; ++i) {
    if (!(mask[i] & groupbit)) continue;
    half_kick(i);
    double axis[3];
    rods_->axis_of(i, axis);
    top_omega(atom->angmom[i], axis, inertia[i][0], inertia[i][1], atom->omega[i]);
  }
}

void FixNVESpherocylinder::setup_pre_force(int vflag)
{
  pre_force(vflag);
}

void FixNVESpherocylinder::pre_force(int)
{
  if (pruning_) pruning_->prune_after_build();
}

double FixNVESpherocylinder::compute_vector(int n)
{
  if (!pruning_) return 0.0;
  if (n == 0) return pruning_->pairs_listed();
  if (n == 1) return pruning_->pairs_kept();
  return pruning_->builds_asked();
}

/* ----------------------------------------------------------------------
   The shortest contact of two rods is at their ends: a force normal to
   the axis at s from a rod's centre meets the inverse mass 1/m + s^2/I_t
   of that rod (translation and rotation), so two rods crossing at the
   ends of their cores (s = h) have 1/m_eff = 2 (1/m + h^2/I_t), and the
   undamped contact time of k_n is t_c = pi sqrt(m_eff/k_n). Velocity
   Verlet is stable below 2/pi t_c and resolves a contact with ten steps
   or more: warn above t_c/10. Needs the stiffness k_n of hooke/stiffness
   (property/global kn), the only normal model rods take.
------------------------------------------------------------------------- */

void FixNVESpherocylinder::warn_if_time_step_is_coarse()
{
  FixPropertyGlobal *stiffness = static_cast<FixPropertyGlobal *>(
      modify->find_fix_property("kn", "property/global", "peratomtypepair", 0, 0, style, false));
  if (!stiffness) return;
  double kn = 0.0;
  for (int i = 0; i < atom->ntypes; ++i)
    for (int j = 0; j < atom->ntypes; ++j) kn = std::max(kn, stiffness->compute_array(i, j));
  double lightest_end = 1e300;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double h = rods_->half_segment_of(i);
    lightest_end = std::min(lightest_end, 1.0/(1.0/atom->rmass[i] + h*h/atom->inertia[i][1]));
  }
  double lightest = lightest_end;
  MPI_Allreduce(&lightest_end, &lightest, 1, MPI_DOUBLE, MPI_MIN, world);
  if (!(kn > 0.0) || lightest >= 1e300) return;
  const double contact_time = MathConst::MY_PI*std::sqrt(0.5*lightest/kn);
  if (update->dt <= 0.1*contact_time) return;
  char message[512];
  snprintf(message, sizeof(message),
           "fix nve/spherocylinder: the time step %g s is %.1f%% of the contact time of two rods "
           "crossing at their ends, t_c = %g s (k_n %g N/m): below 10 steps per contact; "
           "Verlet becomes unstable above %g s", update->dt, 100.0*update->dt/contact_time,
           contact_time, kn, 2.0/MathConst::MY_PI*contact_time);
  error->warning(FLERR, message);
}
