/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   pair_style granular/jiang (doc/pair_granular_jiang.md). The neighbor
   list, FixNeighHistory and cutoff handling follow LAMMPS'
   pair_gran_hooke_history.cpp (LAMMPS 20220106); the contact itself is
   core/contact_law.h and core/rolling_law_jiang.h, called in the order of
   LIGGGHTS' pair gran (normal model, tangential model, rolling model).
------------------------------------------------------------------------- */

#include "pair_granular_jiang.h"

#include "contact_law.h"
#include "contact_law_keywords.h"
#include "lammps_compat.h"
#include "rolling_law_jiang.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "fix_dummy.h"
#include "fix_neigh_history.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using silokit_lammps::LENGTH_DEPTH;
using silokit_lammps::LENGTH_OVERLAP;
using silokit_lammps::NORMAL_HOOKE;

namespace {

const char *const STYLE = "pair_coeff granular/jiang";
}    // namespace

/* ---------------------------------------------------------------------- */

PairGranularJiang::PairGranularJiang(LAMMPS *lmp) : Pair(lmp)
{
  single_enable = 1;
  no_virial_fdotr_compute = 1;
  centroidstressflag = CENTROID_NOTAVAIL;
  finitecutflag = 1;
  restartinfo = 1;
  // the stored k_r keeps its sign when j takes the pair over from i
  nondefault_history_transfer = 1;

  // compute pair/local and compute fabric read svector: fs1..3, fs, vn1..3, vt1..3
  single_extra = 10;
  svector = new double[single_extra];

  stride = 0;
  freeze_group_bit = 0;
  neighprev = 0;
  onerad_dynamic = onerad_frozen = maxrad_dynamic = maxrad_frozen = nullptr;

  // a placeholder for FixNeighHistory, so that the fix order stays that of
  // the input script (replaced in init_style)
  fix_history = nullptr;
  fix_dummy = (FixDummy *) modify->add_fix(history_id() + "_DUMMY all DUMMY");
}

/* ---------------------------------------------------------------------- */

PairGranularJiang::~PairGranularJiang()
{
  if (copymode) return;
  delete[] svector;
  if (!fix_history)
    modify->delete_fix(history_id() + "_DUMMY");
  else
    modify->delete_fix(history_id());
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    delete[] onerad_dynamic;
    delete[] onerad_frozen;
    delete[] maxrad_dynamic;
    delete[] maxrad_frozen;
  }
}

std::string PairGranularJiang::history_id() const
{
  return "NEIGH_HISTORY_GRANULAR_JIANG" + std::to_string(instance_me);
}

/* ----------------------------------------------------------------------
   one contact of i and j (touching), with the pair's history; the history
   is advanced only when advance is true
------------------------------------------------------------------------- */

void PairGranularJiang::contact(int i, int j, const Coeff &c, double *history, bool advance,
                                Result &out)
{
  namespace law = silokit::contact;
  namespace jiang = silokit::jiang;

  double **x = atom->x;
  double **v = atom->v;
  double **omega = atom->omega;
  const double radi = atom->radius[i];
  const double radj = atom->radius[j];
  const double mi = atom->rmass[i];
  const double mj = atom->rmass[j];
  const int *mask = atom->mask;

  const law::Kinematics k =
      law::pair_kinematics(x[i], x[j], v[i], v[j], omega[i], omega[j], radi, radj);

  // a grain of the freeze group counts as infinitely heavy
  double meff = law::pair_effective_mass(mi, mj);
  if (mask[i] & freeze_group_bit) meff = mj;
  if (mask[j] & freeze_group_bit) meff = mi;

  law::NormalSpring spring;
  if (c.normal_model == NORMAL_HOOKE)
    spring = law::hooke(c.youngs_effective, c.restitution, c.characteristic_velocity, meff,
                            law::pair_effective_radius(radi, radj),
                            c.tangential_damping != 0.0);
  else
    spring = law::hooke_stiffness(c.kn, c.kt, c.gamman, c.gammat, meff,
                                      c.absolute_damping != 0.0, c.tangential_damping != 0.0);

  const double dt = update->dt;
  const law::ContactForces f = law::contact_forces(
      k, spring, c.mu, dt, c.limit_force != 0.0, advance, &history[HISTORY_SHEAR]);

  for (int d = 0; d < 3; ++d) {
    out.force_i[d] = f.force_i[d];
    out.torque_i[d] = f.torque_i[d];
    out.torque_j[d] = f.torque_j[d];
    out.ft[d] = f.ft[d];
    out.n[d] = k.n[d];
  }
  out.fn = f.fn;
  out.vn = k.vn;
  out.overlap = k.overlap;
  out.rinv = k.rinv;

  if (c.rolling == 0.0) return;

  // Jiang's rolling spring, as rolling_model_jiang.h drives it in LIGGGHTS
  double relative_omega[3];
  for (int d = 0; d < 3; ++d) relative_omega[d] = omega[i][d] - omega[j][d];
  jiang::remove_normal_component(relative_omega, k.n);

  double contact_length;
  if (c.length_mode == LENGTH_DEPTH)
    contact_length = std::max(k.overlap, 0.0);
  else if (c.length_mode == LENGTH_OVERLAP)
    contact_length = jiang::overlap_contact_length(radi, radj, k.r);
  else {
    contact_length = c.contact_length;
    const double smallest_diameter = 2.0 * std::min(radi, radj);
    if (contact_length > smallest_diameter)
      error->one(FLERR,
                 "pair granular/jiang: rolling jiang lc {} for types {} {} is larger than the "
                 "diameter {} of a grain in contact",
                 contact_length, atom->type[i], atom->type[j], smallest_diameter);
  }

  const jiang::RollingSpring rolling = jiang::rolling_spring(
      spring.kn, k.overlap, c.mu, contact_length, c.stiffness_factor, c.friction_factor);

  double *stored = &history[HISTORY_ROLLING];
  double angle[3] = {stored[0], stored[1], stored[2]};
  double torque[3];
  const bool rolls = jiang::step_rolling_spring(angle, history[HISTORY_STIFFNESS], k.n,
                                                relative_omega, rolling, dt, advance, torque);
  if (advance) {
    for (int d = 0; d < 3; ++d) stored[d] = angle[d];
    history[HISTORY_STIFFNESS] = rolling.stiffness;
  }

  // reduced inertia about the contact point: disc 3/2 m r^2, sphere 7/5 m r^2
  if (c.rolling_damping > 0.0 && !rolls) {
    const double factor = domain->dimension == 2 ? 1.5 : 1.4;
    const double inertia_i = factor * mi * radi * radi;
    const double inertia_j = factor * mj * radj * radj;
    jiang::add_rolling_damping(c.rolling_damping, inertia_i * inertia_j / (inertia_i + inertia_j),
                               rolling.stiffness, relative_omega, torque);
  }

  for (int d = 0; d < 3; ++d) {
    out.torque_i[d] += torque[d];
    out.torque_j[d] -= torque[d];
  }
}

/* ---------------------------------------------------------------------- */

void PairGranularJiang::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);

  // the force call of a run's set-up reads the history without advancing
  // it, as LAMMPS' gran/hooke/history and LIGGGHTS' models do
  const bool update_history = !update->setupflag;

  double **x = atom->x;
  double **f = atom->f;
  double **torque = atom->torque;
  double *radius = atom->radius;
  int *type = atom->type;
  const int nlocal = atom->nlocal;
  const int newton_pair = force->newton_pair;

  const int inum = list->inum;
  int *ilist = list->ilist;
  int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;
  int **firsttouch = fix_history->firstflag;
  double **firsthistory = fix_history->firstvalue;

  Result r;
  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double xtmp = x[i][0];
    const double ytmp = x[i][1];
    const double ztmp = x[i][2];
    const double radi = radius[i];
    int *touch = firsttouch[i];
    double *allhistory = firsthistory[i];
    int *jlist = firstneigh[i];
    const int jnum = numneigh[i];

    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double delx = xtmp - x[j][0];
      const double dely = ytmp - x[j][1];
      const double delz = ztmp - x[j][2];
      const double rsq = delx * delx + dely * dely + delz * delz;
      const double radsum = radi + radius[j];
      double *history = &allhistory[HISTORY_SIZE * jj];

      if (rsq >= radsum * radsum) {
        // apart: the next contact of this pair starts unloaded
        touch[jj] = 0;
        for (int m = 0; m < HISTORY_SIZE; m++) history[m] = 0.0;
        continue;
      }

      touch[jj] = 1;
      contact(i, j, coeffs[type[i] * stride + type[j]], history, update_history, r);

      for (int d = 0; d < 3; ++d) {
        f[i][d] += r.force_i[d];
        torque[i][d] += r.torque_i[d];
      }
      if (newton_pair || j < nlocal) {
        for (int d = 0; d < 3; ++d) {
          f[j][d] -= r.force_i[d];
          torque[j][d] += r.torque_j[d];
        }
      }
      if (evflag)
        ev_tally_xyz(i, j, nlocal, newton_pair, 0.0, 0.0, r.force_i[0], r.force_i[1],
                     r.force_i[2], delx, dely, delz);
    }
  }
}

/* ---------------------------------------------------------------------- */

void PairGranularJiang::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  stride = n + 1;
  coeffs.assign(stride * stride, Coeff());
  onerad_dynamic = new double[n + 1];
  onerad_frozen = new double[n + 1];
  maxrad_dynamic = new double[n + 1];
  maxrad_frozen = new double[n + 1];
}

/* ---------------------------------------------------------------------- */

void PairGranularJiang::settings(int narg, char **)
{
  if (narg != 0)
    error->all(FLERR,
               "pair_style granular/jiang takes no arguments: the contact law goes to pair_coeff "
               "(doc/pair_granular_jiang.md)");
}

/* ----------------------------------------------------------------------
   pair_coeff I J normal hooke/stiffness kn kt gamman gammat
                  | normal hooke Y nu e v_char
                  friction mu
                  [rolling jiang a b lc <length | overlap | depth>]
                  [rolling_damping eta] [tangential_damping yes|no]
                  [absolute_damping yes|no] [limit_force yes|no]
------------------------------------------------------------------------- */

void PairGranularJiang::coeff(int narg, char **arg)
{
  if (narg < 2) error->all(FLERR, "{}: expected I J and keywords", STYLE);
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  Coeff c = silokit_lammps::default_contact_law();
  int iarg = 2;
  while (iarg < narg) {
    const int next = silokit_lammps::parse_contact_law_keyword(error, STYLE, narg, arg, iarg, c);
    if (next == iarg)
      error->all(FLERR,
                 "{}: unknown keyword '{}' (normal, friction, rolling, rolling_damping, "
                 "tangential_damping, absolute_damping, limit_force)",
                 STYLE, arg[iarg]);
    iarg = next;
  }
  silokit_lammps::check_contact_law(error, STYLE, c);

  int count = 0;
  for (int i = ilo; i <= ihi; i++) {
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      coeff_of(i, j) = c;
      coeff_of(j, i) = c;
      setflag[i][j] = 1;
      count++;
    }
  }
  if (count == 0) error->all(FLERR, "{}: no type pair in {} {}", STYLE, arg[0], arg[1]);
}

/* ---------------------------------------------------------------------- */

void PairGranularJiang::init_style()
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR,
               "pair granular/jiang needs atom attributes radius, rmass, omega and torque "
               "(atom_style sphere)");
  if (comm->ghost_velocity == 0)
    error->all(FLERR, "pair granular/jiang needs ghost velocities: comm_modify vel yes");

  // a granular neighbor list with history
  silokit_lammps::request_size_history_list(neighbor, this, instance_me);

  // the first init replaces the placeholder with the fix that keeps the
  // history per pair (across reneighboring, MPI exchange and restarts)
  if (fix_history == nullptr) {
    const std::string cmd = fmt::format("{} all NEIGH_HISTORY {}", history_id(), (int) HISTORY_SIZE);
    fix_history = (FixNeighHistory *) modify->replace_fix(history_id() + "_DUMMY", cmd, 1);
    fix_history->pair = this;
    fix_dummy = nullptr;
  }
  fix_history = (FixNeighHistory *) silokit_lammps::fix_by_id(modify, history_id());
  if (!fix_history) error->all(FLERR, "pair granular/jiang: its fix {} is gone", history_id());

  const Fix *freeze = silokit_lammps::first_fix_by_style(modify, "^freeze");
  freeze_group_bit = freeze ? freeze->groupbit : 0;

  // the largest radius per type, of moving and of frozen grains, for the
  // cutoffs; grains that fix pour, deposit or insert/rain2d will insert
  // count as moving
  const char *const inserters[] = {"^pour", "^deposit", "^insert/rain2d"};
  for (int i = 1; i <= atom->ntypes; i++) {
    onerad_dynamic[i] = onerad_frozen[i] = 0.0;
    for (const char *inserter : inserters) {
      Fix *insert = silokit_lammps::first_fix_by_style(modify, inserter);
      if (!insert) continue;
      int itype = i;    // extract() sets it to 0 (a scalar): call it once
      const double announced = *((double *) insert->extract("radius", itype));
      onerad_dynamic[i] = MAX(onerad_dynamic[i], announced);
    }
  }
  double *radius = atom->radius;
  int *mask = atom->mask;
  int *type = atom->type;
  for (int i = 0; i < atom->nlocal; i++) {
    double &slot = (mask[i] & freeze_group_bit) ? onerad_frozen[type[i]] : onerad_dynamic[type[i]];
    slot = MAX(slot, radius[i]);
  }
  MPI_Allreduce(&onerad_dynamic[1], &maxrad_dynamic[1], atom->ntypes, MPI_DOUBLE, MPI_MAX, world);
  MPI_Allreduce(&onerad_frozen[1], &maxrad_frozen[1], atom->ntypes, MPI_DOUBLE, MPI_MAX, world);
}

/* ---------------------------------------------------------------------- */

double PairGranularJiang::init_one(int i, int j)
{
  if (setflag[i][j] == 0)
    error->all(FLERR,
               "pair granular/jiang: no pair_coeff for types {} {} (no mixing: give every "
               "type pair)",
               i, j);
  // sum of the largest radii, moving/moving and moving/frozen
  double cutoff = maxrad_dynamic[i] + maxrad_dynamic[j];
  cutoff = MAX(cutoff, maxrad_frozen[i] + maxrad_dynamic[j]);
  cutoff = MAX(cutoff, maxrad_dynamic[i] + maxrad_frozen[j]);
  return cutoff;
}

/* ---------------------------------------------------------------------- */

void PairGranularJiang::write_restart(FILE *fp)
{
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) fwrite(&coeff_of(i, j), sizeof(Coeff), 1, fp);
    }
}

void PairGranularJiang::read_restart(FILE *fp)
{
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (!setflag[i][j]) continue;
      Coeff c;
      if (me == 0) utils::sfread(FLERR, &c, sizeof(Coeff), 1, fp, nullptr, error);
      MPI_Bcast(&c, sizeof(Coeff), MPI_BYTE, 0, world);
      coeff_of(i, j) = c;
      coeff_of(j, i) = c;
    }
}

/* ----------------------------------------------------------------------
   FixNeighHistory hands the pair from i to j: the springs change sign,
   the stored k_r does not
------------------------------------------------------------------------- */

void PairGranularJiang::transfer_history(SILOKIT_TRANSFER_HISTORY_PARAMS)
{
  for (int m = 0; m < HISTORY_STIFFNESS; m++) target[m] = -source[m];
  target[HISTORY_STIFFNESS] = source[HISTORY_STIFFNESS];
}

/* ----------------------------------------------------------------------
   the pair's force without advancing its history (compute pair/local,
   compute fabric): fforce = Fn/r, svector = fs1..3, |fs|, vn1..3, vt1..3
------------------------------------------------------------------------- */

double PairGranularJiang::single(int i, int j, int itype, int jtype, double rsq,
                                 double /*factor_coul*/, double /*factor_lj*/, double &fforce)
{
  const double radsum = atom->radius[i] + atom->radius[j];
  if (rsq >= radsum * radsum) {
    fforce = 0.0;
    for (int m = 0; m < single_extra; m++) svector[m] = 0.0;
    return 0.0;
  }

  // this pair's history: search i's neighbors for j, from where the last
  // call stopped (calls usually come in neighbor order)
  const int jnum = list->numneigh[i];
  int *jlist = list->firstneigh[i];
  double stored[HISTORY_SIZE] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int jj = 0; jj < jnum; jj++) {
    neighprev++;
    if (neighprev >= jnum) neighprev = 0;
    if ((jlist[neighprev] & NEIGHMASK) == j) {
      const double *history = &fix_history->firstvalue[i][HISTORY_SIZE * neighprev];
      for (int m = 0; m < HISTORY_SIZE; m++) stored[m] = history[m];
      break;
    }
  }

  Result r;
  contact(i, j, coeff_of(itype, jtype), stored, false, r);
  fforce = r.fn * r.rinv;

  double **v = atom->v;
  double vt[3];
  for (int d = 0; d < 3; ++d) vt[d] = (v[i][d] - v[j][d]) - r.vn * r.n[d];
  svector[0] = r.ft[0];
  svector[1] = r.ft[1];
  svector[2] = r.ft[2];
  svector[3] = std::sqrt(r.ft[0] * r.ft[0] + r.ft[1] * r.ft[1] + r.ft[2] * r.ft[2]);
  svector[4] = r.vn * r.n[0];
  svector[5] = r.vn * r.n[1];
  svector[6] = r.vn * r.n[2];
  svector[7] = vt[0];
  svector[8] = vt[1];
  svector[9] = vt[2];
  return 0.0;
}

/* ----------------------------------------------------------------------
   the touching pairs of the neighbor list, evaluated as single() does:
   on a copy of the history, so the trajectory does not change
------------------------------------------------------------------------- */

std::vector<silokit::ContactSample> PairGranularJiang::current_contacts()
{
  std::vector<silokit::ContactSample> samples;
  if (!list || !fix_history) return samples;
  double **x = atom->x;
  const double *radius = atom->radius;
  const int *type = atom->type;
  const tagint *tag = atom->tag;
  Result r;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    const int *jlist = list->firstneigh[i];
    const double *allhistory = fix_history->firstvalue[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!silokit::contact::touching(x[i], x[j], radius[i], radius[j])) continue;
      double stored[HISTORY_SIZE];
      for (int m = 0; m < HISTORY_SIZE; m++) stored[m] = allhistory[HISTORY_SIZE * jj + m];
      contact(i, j, coeffs[type[i] * stride + type[j]], stored, false, r);
      silokit::ContactSample sample;
      sample.id1 = static_cast<int>(tag[i]);
      sample.id2 = static_cast<int>(tag[j]);
      sample.overlap = r.overlap;
      for (int d = 0; d < 3; ++d) {
        sample.x1[d] = x[i][d];
        sample.x2[d] = x[j][d];
        sample.normal_force[d] = r.fn * r.n[d];
        sample.tangential_force[d] = r.ft[d];
      }
      samples.push_back(sample);
    }
  }
  return samples;
}

/* ---------------------------------------------------------------------- */

double PairGranularJiang::memory_usage()
{
  return (double) coeffs.size() * sizeof(Coeff);
}

double PairGranularJiang::atom2cut(int i)
{
  return atom->radius[i] * 2.0;
}

double PairGranularJiang::radii2cut(double r1, double r2)
{
  return r1 + r2;
}
