/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The rods' neighbour list, cut to the pairs whose cores can meet
   (spherocylinder_list_pruning.h).
------------------------------------------------------------------------- */

#include "spherocylinder_list_pruning.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "contact_model_constants.h"
#include "force.h"
#include "mpi.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "spherocylinder_geometry.h"

using namespace LAMMPS_NS;

SpherocylinderListPruning::SpherocylinderListPruning(LAMMPS *lmp) :
  Pointers(lmp),
  avec_(dynamic_cast<AtomVecSpherocylinder *>(atom->avec)),
  farthest_(0.0), pairs_listed_(0.0), pairs_kept_(0.0), builds_asked_(0.0)
{}

void SpherocylinderListPruning::before_move(int groupbit)
{
  const int nlocal = atom->nlocal;
  old_centre_.resize(3*static_cast<size_t>(nlocal));
  old_axis_.resize(3*static_cast<size_t>(nlocal));
  for (int i = 0; i < nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    for (int k = 0; k < 3; ++k) old_centre_[3*i + k] = atom->x[i][k];
    avec_->axis_of(i, &old_axis_[3*i]);
  }
}

bool SpherocylinderListPruning::after_move(int groupbit)
{
  start_moves();
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    double axis[3];
    avec_->axis_of(i, axis);
    add_move(i, &old_centre_[3*i], &old_axis_[3*i], axis);
  }
  return build_needed();
}

void SpherocylinderListPruning::start_moves()
{
  // atoms arrive only with a build, which restarts the sums; a longer
  // array here would be a fix that added atoms without one: count them
  // from zero, as the centre check of LIGGGHTS does from their position
  if (travel_.size() < static_cast<size_t>(atom->nlocal)) travel_.resize(atom->nlocal, 0.0);
  farthest_ = 0.0;
}

void SpherocylinderListPruning::add_move(int i, const double *old_centre, const double *old_axis,
                                         const double *axis)
{
  double moved = 0.0, turned = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double dx = atom->x[i][k] - old_centre[k];
    const double du = axis[k] - old_axis[k];
    moved += dx*dx;
    turned += du*du;
  }
  travel_[i] += std::sqrt(moved) + avec_->half_segment_of(i)*std::sqrt(turned);
  farthest_ = std::max(farthest_, travel_[i]);
}

bool SpherocylinderListPruning::build_needed()
{
  double farthest_anywhere = farthest_;
  MPI_Allreduce(&farthest_, &farthest_anywhere, 1, MPI_DOUBLE, MPI_MAX, world);
  const bool build = farthest_anywhere > 0.5*neighbor->skin;
  if (build) builds_asked_ += 1.0;
  return build;
}

// Whether the cores of rods i and j are closer than `reach`, computed in
// the order of their tags, so that the two ranks holding a pair across
// their boundary decide alike.
bool SpherocylinderListPruning::cores_near(int i, int j, double reach) const
{
  if (atom->tag[i] > atom->tag[j]) std::swap(i, j);
  return silokit::cores_within(atom->x[i], &axes_[3*i], avec_->half_segment_of(i),
                               atom->x[j], &axes_[3*j], avec_->half_segment_of(j), reach);
}

void SpherocylinderListPruning::prune_after_build()
{
  if (neighbor->ago != 0) return;
  travel_.assign(atom->nlocal, 0.0);
  Pair *pair = force->pair;
  if (!pair || !pair->list) return;
  NeighList *list = pair->list;
  NeighList *history = pair->listgranhistory;
  const int dnum = history ? history->dnum : 0;

  const int all = atom->nlocal + atom->nghost;
  axes_.resize(3*static_cast<size_t>(all));
  for (int i = 0; i < all; ++i) avec_->axis_of(i, &axes_[3*i]);

  const double skin = neighbor->skin;
  double listed = 0.0, kept_total = 0.0;
  for (int ii = 0; ii < list->inum; ++ii) {
    const int i = list->ilist[ii];
    int *neighbours = list->firstneigh[i];
    int *touching = history ? history->firstneigh[i] : nullptr;
    double *values = history && dnum > 0 ? history->firstdouble[i] : nullptr;
    const int listed_i = list->numneigh[i];
    int kept = 0;
    for (int jj = 0; jj < listed_i; ++jj) {
      const int j = neighbours[jj] & NEIGHMASK;
      // a tangential spring in use stays, wherever the cores are now;
      // not any flag: the stock hooke/stiffness *sets* its own bit in
      // surfacesClose (`|=`, where the other models clear theirs), so
      // every pair whose bounding spheres overlap carries a flag
      const bool keep =
          (touching && (touching[jj] & LIGGGHTS::ContactModels::CONTACT_TANGENTIAL_MODEL)) ||
          cores_near(i, j, atom->shape[i][1] + atom->shape[j][1] + skin);
      if (!keep) continue;
      if (kept != jj) {
        neighbours[kept] = neighbours[jj];
        if (touching) touching[kept] = touching[jj];
        if (values) std::memmove(&values[dnum*kept], &values[dnum*jj], dnum*sizeof(double));
      }
      ++kept;
    }
    list->numneigh[i] = kept;
    listed += listed_i;
    kept_total += kept;
  }
  pairs_listed_ += listed;
  pairs_kept_ += kept_total;
}

double SpherocylinderListPruning::pairs_listed() const
{
  double total = 0.0;
  MPI_Allreduce(&pairs_listed_, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  return total;
}

double SpherocylinderListPruning::pairs_kept() const
{
  double total = 0.0;
  MPI_Allreduce(&pairs_kept_, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  return total;
}
