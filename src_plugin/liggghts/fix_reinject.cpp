/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix reinject: see fix_reinject.h and doc/fix_reinject.md.

   How: every N steps (end_of_step) the ranks count the grains below the
   exit plane; when there are any, a neighbor-list build is requested for
   the next step, and in its pre_exchange every rank gathers the leavers and
   the grains near the injection region, draws the same free spots with the
   same random sequence (leavers sorted by id), and moves the leavers it
   owns. The exchange that follows hands each moved grain to its new rank.
   So the result does not depend on the number of ranks.
------------------------------------------------------------------------- */

#include "fix_reinject.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "input.h"
#include "random_park.h"
#include "region.h"
#include "silokit_args.h"
#include "silokit_mpi.h"
#include "silokit_record.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// first value of the restart data. -3: with the pending re-entries and
// the flow-rate samples; -2: without them (silokit up to commit eaa418e);
// before the restart clock the data began with the count of grains out (>= 0)
const double restart_layout = -3.0;
const double restart_layout_without_pending = -2.0;

bool overlaps(const double *centre, double radius, const double *other_centre, double other_radius)
{
  double distance_squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = centre[k] - other_centre[k];
    distance_squared += d*d;
  }
  const double contact = radius + other_radius;
  return distance_squared < contact*contact;
}

}  // namespace

/* ---------------------------------------------------------------------- */

FixReinject::FixReinject(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  axis(-1), exit_coordinate(0.0), region(nullptr),
  max_attempts(1000), rate_window(0.1), restored(false),
  grains_out(0.0), mass_out(0.0), avalanche(0.0)
{
  if (!atom->radius_flag || !atom->rmass_flag)
    error->fix_error(FLERR, this, "needs per-atom radius and mass (atom_style sphere or granular)");

  nevery = 1;
  parse_arguments(narg, arg);

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;
}

/* ---------------------------------------------------------------------- */

void FixReinject::parse_arguments(int narg, char **arg)
{
  bool have_exit = false, have_seed = false;
  int iarg = 3;
  while (iarg < narg) {
    const std::string keyword(arg[iarg]);
    const int values = keyword == "exit" ? 2 : 1;
    if (iarg + values >= narg) {
      std::string message = "keyword '" + keyword + "' needs " +
                            (values == 2 ? "two values" : "a value");
      error->fix_error(FLERR, this, message.c_str());
    }
    const char *value = arg[iarg+1];
    if (keyword == "exit") {
      if (strcmp(value, "x") == 0) axis = 0;
      else if (strcmp(value, "y") == 0) axis = 1;
      else if (strcmp(value, "z") == 0) axis = 2;
      else error->fix_error(FLERR, this, "'exit' takes an axis x, y or z, then a coordinate");
      exit_coordinate = silokit::keyword_number(this, error, arg[iarg+2], "exit");
      have_exit = true;
    } else if (keyword == "region") {
      region_id = value;
    } else if (keyword == "seed") {
      const int seed = silokit::keyword_integer(this, error, value, "seed");
      if (seed <= 0) error->fix_error(FLERR, this, "'seed' must be a positive integer");
      if (!silokit::liggghts_seed_accepted(seed) && input->seed_check_throw_error())
        error->fix_error(FLERR, this, "'seed' must be a prime number > 10000 "
                                      "(LIGGGHTS' random generator requires it)");
      // RanPark reads its text with atoi: give it the integer's digits
      random.reset(new RanPark(lmp, std::to_string(seed).c_str()));
      have_seed = true;
    } else if (keyword == "every") {
      nevery = silokit::keyword_integer(this, error, value, "every");
      if (nevery < 1) error->fix_error(FLERR, this, "'every' must be >= 1");
    } else if (keyword == "maxattempt") {
      max_attempts = silokit::keyword_integer(this, error, value, "maxattempt");
      if (max_attempts < 1) error->fix_error(FLERR, this, "'maxattempt' must be >= 1");
    } else if (keyword == "rate_window") {
      rate_window = silokit::keyword_number(this, error, value, "rate_window");
      if (!(rate_window > 0.0)) error->fix_error(FLERR, this, "'rate_window' must be > 0");
    } else if (keyword == "file") {
      file_name = value;
      if (file_name.empty()) error->fix_error(FLERR, this, "'file' needs a file name");
    } else {
      std::string message = "unknown keyword '" + keyword +
        "' (known: exit, region, seed, every, maxattempt, rate_window, file)";
      error->fix_error(FLERR, this, message.c_str());
    }
    iarg += values + 1;
  }
  if (!have_exit) error->fix_error(FLERR, this, "'exit <axis> <coordinate>' is required");
  if (region_id.empty()) error->fix_error(FLERR, this, "'region <region-ID>' is required");
  if (!have_seed) error->fix_error(FLERR, this, "'seed <positive integer>' is required");
  if (domain->dimension == 2 && axis == 2)
    error->fix_error(FLERR, this, "in 2D the vertical axis is x or y, not z");
}

/* ----------------------------------------------------------------------
   opened at the first init, not in the constructor: LIGGGHTS calls
   restart() after it, and a restored fix appends to the record, so that
   the pieces of a restarted run write one file (silokit_record.h); its
   clock then reads the time the restart file was written at
------------------------------------------------------------------------- */

void FixReinject::open_record_file()
{
  if (file_name.empty() || record) return;
  int opened = 1;
  if (comm->me == 0) {
    char plane[64];
    snprintf(plane, sizeof(plane), "%c = %g", "xyz"[axis], exit_coordinate);
    const std::string header = std::string("# fix reinject ") + id +
      ": grains re-entered after leaving below " + plane + "\n# step t n_out mass_out avalanche";
    // after a restart: lines past the time the restart file was written at
    // are removed (the run repeats those steps)
    const silokit::KeptRows kept = { 1, simulated_time() };
    long dropped = 0;
    record = silokit::open_record(file_name, restored, header.c_str(), kept, &dropped);
    opened = record != nullptr;
    if (dropped > 0) {
      char message[256];
      snprintf(message, sizeof(message), "fix reinject: removed %ld line(s) past t = %.10g from '%s', "
               "written after the restart file by the run that wrote it; this run records them again",
               dropped, kept.last, file_name.c_str());
      error->message(FLERR, message);
    }
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened) {
    const std::string message = "cannot open file '" + file_name + "'";
    error->fix_error(FLERR, this, message.c_str());
  }
}

/* ---------------------------------------------------------------------- */

FixReinject::~FixReinject() = default;   // closes the record

/* ---------------------------------------------------------------------- */

int FixReinject::setmask()
{
  return END_OF_STEP | PRE_EXCHANGE;
}

/* ---------------------------------------------------------------------- */

void FixReinject::init()
{
  const int iregion = domain->find_region(region_id.c_str());
  if (iregion == -1) {
    std::string message = "region '" + region_id + "' does not exist";
    error->fix_error(FLERR, this, message.c_str());
  }
  region = domain->regions[iregion];
  if (!region->bboxflag)
    error->fix_error(FLERR, this, "the region must have a bounding box (e.g. block, cylinder)");
  const double region_bottom = axis == 0 ? region->extent_xlo
                             : axis == 1 ? region->extent_ylo : region->extent_zlo;
  if (region_bottom <= exit_coordinate)
    error->fix_error(FLERR, this, "the region must lie above the exit plane");

  open_record_file();
}

/* ----------------------------------------------------------------------
   the time of the whole run, across restarts (silokit_clock.h): that of
   the file's lines and of the flow-rate samples
------------------------------------------------------------------------- */

void FixReinject::setup(int)
{
  clock.run_set_up();
}

double FixReinject::simulated_time() const
{
  return clock.time(update->get_cur_time());
}

/* ---------------------------------------------------------------------- */

bool FixReinject::is_leaver(int i) const
{
  return (atom->mask[i] & groupbit) && atom->x[i][axis] < exit_coordinate;
}

bool FixReinject::is_requested(int i) const
{
  return !requested.empty() && requested.count(atom->tag[i]) > 0;
}

int FixReinject::count_local_leavers() const
{
  int count = 0;
  for (int i = 0; i < atom->nlocal; ++i)
    if (is_leaver(i)) ++count;
  return count;
}

/* ----------------------------------------------------------------------
   every N steps: ask for a neighbor-list build next step if grains left
------------------------------------------------------------------------- */

void FixReinject::end_of_step()
{
  int local = count_local_leavers(), total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_INT, MPI_SUM, world);
  if (total > 0) next_reneighbor = update->ntimestep + 1;
  record_sample();
}

/* ---------------------------------------------------------------------- */

std::vector<FixReinject::Leaver> FixReinject::gather_leavers() const
{
  std::vector<double> local;
  for (int i = 0; i < atom->nlocal; ++i) {
    const bool left = is_leaver(i);
    if (!left && !is_requested(i)) continue;
    local.push_back(atom->tag[i]);
    local.push_back(atom->radius[i]);
    local.push_back(atom->rmass[i]);
    local.push_back(left ? 1.0 : 0.0);
  }
  const std::vector<double> all = silokit::allgather(local, world);
  std::vector<Leaver> leavers;
  for (size_t k = 0; k + 3 < all.size(); k += 4) {
    Leaver leaver = { static_cast<int>(all[k]), all[k+1], all[k+2], all[k+3] != 0.0 };
    leavers.push_back(leaver);
  }
  // the same order on every rank, whatever the decomposition
  std::sort(leavers.begin(), leavers.end(),
            [](const Leaver &a, const Leaver &b) { return a.tag < b.tag; });
  return leavers;
}

/* ----------------------------------------------------------------------
   every grain (of any group) whose centre is within `margin` of the
   region's bounding box: what a re-entering grain must not overlap
------------------------------------------------------------------------- */

std::vector<FixReinject::Sphere> FixReinject::gather_spheres_near_region(double margin) const
{
  const double lo[3] = { region->extent_xlo - margin, region->extent_ylo - margin,
                         region->extent_zlo - margin };
  const double hi[3] = { region->extent_xhi + margin, region->extent_yhi + margin,
                         region->extent_zhi + margin };
  std::vector<double> local;
  for (int i = 0; i < atom->nlocal; ++i) {
    const double *x = atom->x[i];
    if (x[0] < lo[0] || x[0] > hi[0] || x[1] < lo[1] || x[1] > hi[1] ||
        x[2] < lo[2] || x[2] > hi[2]) continue;
    local.insert(local.end(), x, x + 3);
    local.push_back(atom->radius[i]);
  }
  const std::vector<double> all = silokit::allgather(local, world);
  std::vector<Sphere> spheres;
  for (size_t k = 0; k + 3 < all.size(); k += 4) {
    Sphere sphere = { { all[k], all[k+1], all[k+2] }, all[k+3] };
    spheres.push_back(sphere);
  }
  return spheres;
}

/* ----------------------------------------------------------------------
   a random spot where the whole grain lies in the region and touches no
   other grain; the same on every rank (same seed, same sequence)
------------------------------------------------------------------------- */

bool FixReinject::find_free_spot(double radius, const std::vector<Sphere> &occupied, double *spot)
{
  const double lo[3] = { region->extent_xlo, region->extent_ylo, region->extent_zlo };
  const double hi[3] = { region->extent_xhi, region->extent_yhi, region->extent_zhi };
  for (int attempt = 0; attempt < max_attempts; ++attempt) {
    for (int k = 0; k < 3; ++k) spot[k] = lo[k] + random->uniform()*(hi[k] - lo[k]);
    if (domain->dimension == 2) spot[2] = 0.0;
    if (!region->match_shrinkby_cut(spot, radius)) continue;
    bool free = true;
    for (size_t s = 0; s < occupied.size() && free; ++s)
      free = !overlaps(spot, radius, occupied[s].x, occupied[s].radius);
    if (free) return true;
  }
  return false;
}

/* ---------------------------------------------------------------------- */

void FixReinject::move_local_grains(const std::map<int, Sphere> &spots)
{
  for (int i = 0; i < atom->nlocal; ++i) {
    const std::map<int, Sphere>::const_iterator found = spots.find(atom->tag[i]);
    if (found == spots.end()) continue;
    for (int k = 0; k < 3; ++k) {
      atom->x[i][k] = found->second.x[k];
      atom->v[i][k] = 0.0;
      atom->omega[i][k] = 0.0;
      // rods (atom_style spherocylinder) turn with their angular momentum
      if (atom->angmom) atom->angmom[i][k] = 0.0;
    }
  }
}

/* ----------------------------------------------------------------------
   on the step after grains left: move them to the top
------------------------------------------------------------------------- */

void FixReinject::pre_exchange()
{
  if (next_reneighbor != update->ntimestep) return;
  next_reneighbor = -1;

  const std::vector<Leaver> leavers = gather_leavers();
  requested.clear();
  if (leavers.empty()) return;

  double largest_local = 0.0, largest = 0.0;
  for (int i = 0; i < atom->nlocal; ++i) largest_local = std::max(largest_local, atom->radius[i]);
  MPI_Allreduce(&largest_local, &largest, 1, MPI_DOUBLE, MPI_MAX, world);
  std::vector<Sphere> occupied = gather_spheres_near_region(2.0*largest);

  std::map<int, Sphere> spots;
  for (size_t n = 0; n < leavers.size(); ++n) {
    Sphere placed;
    placed.radius = leavers[n].radius;
    if (!find_free_spot(placed.radius, occupied, placed.x)) {
      std::ostringstream message;
      message << "no free spot in region '" << region_id << "' for grain " << leavers[n].tag
              << " after " << max_attempts << " attempts: enlarge the region or raise 'maxattempt'";
      error->fix_error(FLERR, this, message.str().c_str());
    }
    occupied.push_back(placed);
    spots[leavers[n].tag] = placed;
    if (!leavers[n].left_through_exit) continue;
    grains_out += 1.0;
    mass_out += leavers[n].mass;
    avalanche += 1.0;
  }
  move_local_grains(spots);

  if (record) {
    fprintf(record.get(), BIGINT_FORMAT " %.15g %.0f %.15g %.0f\n", update->ntimestep,
            simulated_time(), grains_out, mass_out, avalanche);
    fflush(record.get());
  }
}

/* ---------------------------------------------------------------------- */

void FixReinject::record_sample()
{
  const Sample now = { simulated_time(), grains_out, mass_out };
  samples.push_back(now);
  // keep the newest sample that is at least a window old, and all newer
  // (with a tolerance for the rounding of accumulated times)
  const double window_start = now.time - rate_window*(1.0 - 1e-9);
  while (samples.size() > 2 && samples[1].time <= window_start)
    samples.pop_front();
}

double FixReinject::rate(bool of_mass) const
{
  if (samples.size() < 2) return 0.0;
  const Sample &first = samples.front(), &last = samples.back();
  const double span = last.time - first.time;
  if (!(span > 0.0)) return 0.0;
  return ((of_mass ? last.mass - first.mass : last.grains - first.grains))/span;
}

/* ---------------------------------------------------------------------- */

int FixReinject::close_avalanche()
{
  const int size = static_cast<int>(avalanche);
  avalanche = 0.0;
  return size;
}

void FixReinject::request_reinjection(const std::vector<int> &tags)
{
  requested.insert(tags.begin(), tags.end());
  if (!requested.empty()) next_reneighbor = update->ntimestep + 1;
}

/* ----------------------------------------------------------------------
   1 grains out, 2 mass out, 3 grains in the current avalanche,
   4 grains per unit time and 5 mass per unit time over the rate window
------------------------------------------------------------------------- */

double FixReinject::compute_vector(int index)
{
  switch (index) {
    case 0: return grains_out;
    case 1: return mass_out;
    case 2: return avalanche;
    case 3: return rate(false);
    case 4: return rate(true);
  }
  return 0.0;
}

/* ---------------------------------------------------------------------- */

void FixReinject::write_restart(FILE *fp)
{
  // counts, random state and clock, then what is pending so that the
  // restarted run goes on as an uninterrupted one: the step of a re-entry
  // requested for the next step (grains found below the exit at the last
  // check, or tags from fix clog), those tags, and the flow-rate samples
  std::vector<double> list = { restart_layout, grains_out, mass_out, avalanche,
                               static_cast<double>(random->state()), simulated_time(),
                               static_cast<double>(next_reneighbor),
                               static_cast<double>(requested.size()),
                               static_cast<double>(samples.size()) };
  list.insert(list.end(), requested.begin(), requested.end());
  for (const Sample &sample : samples) {
    list.push_back(sample.time);
    list.push_back(sample.grains);
    list.push_back(sample.mass);
  }
  if (comm->me == 0) {
    const int size = list.size()*sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

void FixReinject::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  if (list[0] != restart_layout && list[0] != restart_layout_without_pending)
    error->fix_error(FLERR, this, "the restart file holds its data in the layout of an older silokit, "
                     "whose times cannot be continued: define the fix with another ID to start anew");
  grains_out = list[1];
  mass_out = list[2];
  avalanche = list[3];
  random->reset(static_cast<int>(list[4]));
  clock.restored(list[5]);
  restored = true;
  if (list[0] == restart_layout_without_pending) return;

  next_reneighbor = static_cast<bigint>(list[6]);
  const size_t tag_count = static_cast<size_t>(list[7]), sample_count = static_cast<size_t>(list[8]);
  const double *tags = list + 9;
  requested.clear();
  for (size_t k = 0; k < tag_count; ++k) requested.insert(static_cast<int>(tags[k]));
  const double *sample = tags + tag_count;
  samples.clear();
  for (size_t k = 0; k < sample_count; ++k, sample += 3) {
    const Sample restored_sample = { sample[0], sample[1], sample[2] };
    samples.push_back(restored_sample);
  }
}
