/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix insert/rain2d: see fix_insert_rain2d.h and doc/fix_insert_rain2d.md.

   How: at the end of every step the ranks find the highest grain of the
   last row released (one MPI_Allreduce); once it is `fall` below the line
   the release is scheduled for the next step, whose pre_exchange (a
   neighbor-list build is forced) draws the row and creates it. Every rank
   draws the same random numbers in the same order (one generator, same
   seed, no per-rank offset) and creates only the grains whose centre lies
   in its own sub-domain; tags are assigned in drawing order from a counter
   all ranks share. So a row, grain by grain and tag by tag, does not depend
   on the number of ranks. Grains that leave the box through non-periodic
   boundaries are deleted by LIGGGHTS itself (lost atoms, see the doc).
------------------------------------------------------------------------- */

#include "fix_insert_rain2d.h"

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "modify.h"
#include "random_park.h"
#include "rain_row.h"
#include "silokit_args.h"
#include "silokit_mpi.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const double pi = 3.14159265358979323846;

// the state written to restart files: how many values, 9 scalars, the samples
const int restart_scalars = 10;

}  // namespace

/* ---------------------------------------------------------------------- */

FixInsertRain2d::FixInsertRain2d(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  grain_type(0), mean_diameter(0.0), polydispersity(0.05), density(0.0),
  line_lo(0.0), line_hi(0.0), line_height(0.0), fill(0.5), fall(-1.0),
  window(10), tolerance(0.01), max_grains(0), max_rows(0),
  next_tag(0), rows(0), inserted(0), stop_reason(still_raining),
  last_row_first_tag(0), last_row_last_tag(-1), release_step(-1), last_release_step(-1),
  grains_per_row(0)
{
  if (domain->dimension != 2)
    error->fix_error(FLERR, this, "is for 2D simulations (dimension 2); in 3D use LIGGGHTS' fix insert/* styles");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->fix_error(FLERR, this, "needs per-atom radius, mass and omega (atom_style sphere)");
  if (!atom->tag_enable)
    error->fix_error(FLERR, this, "needs atom IDs");
  if (domain->triclinic)
    error->fix_error(FLERR, this, "does not support triclinic boxes");

  parse_arguments(narg, arg);
  grains_per_row = silokit::rain_row_count(line_hi - line_lo, fill, mean_diameter);

  nevery = 1;
  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;
}

FixInsertRain2d::~FixInsertRain2d() = default;

/* ---------------------------------------------------------------------- */

void FixInsertRain2d::parse_arguments(int narg, char **arg)
{
  bool have_type = false, have_line = false, have_fall = false;
  int iarg = 3;
  while (iarg < narg) {
    const std::string keyword(arg[iarg]);
    const int values = keyword == "line" ? 3 : 1;
    if (iarg + values >= narg) {
      const std::string message = "keyword '" + keyword + "' needs " +
                                  (values == 3 ? "three values (x_lo x_hi y)" : "a value");
      error->fix_error(FLERR, this, message.c_str());
    }
    const char *value = arg[iarg+1];
    if (keyword == "seed") {
      const int seed = silokit::keyword_integer(this, error, value, "seed");
      if (!silokit::liggghts_seed_accepted(seed))
        error->fix_error(FLERR, this, "'seed' must be a prime number > 10000 (LIGGGHTS' random generator requires it)");
      // RanPark reads its text with atoi: give it the integer's digits
      random.reset(new RanPark(lmp, std::to_string(seed).c_str()));
    } else if (keyword == "type") {
      grain_type = silokit::keyword_integer(this, error, value, "type");
      have_type = true;
    } else if (keyword == "diameter") {
      mean_diameter = silokit::keyword_number(this, error, value, "diameter");
      if (!(mean_diameter > 0.0)) error->fix_error(FLERR, this, "'diameter' must be > 0");
    } else if (keyword == "polydispersity") {
      polydispersity = silokit::keyword_number(this, error, value, "polydispersity");
      if (!(polydispersity >= 0.0 && polydispersity < 1.0))
        error->fix_error(FLERR, this, "'polydispersity' must be in [0, 1) (diameters uniform in d(1 -+ p))");
    } else if (keyword == "density") {
      density = silokit::keyword_number(this, error, value, "density");
      if (!(density > 0.0)) error->fix_error(FLERR, this, "'density' must be > 0");
    } else if (keyword == "line") {
      line_lo = silokit::keyword_number(this, error, arg[iarg+1], "line");
      line_hi = silokit::keyword_number(this, error, arg[iarg+2], "line");
      line_height = silokit::keyword_number(this, error, arg[iarg+3], "line");
      if (!(line_hi > line_lo)) error->fix_error(FLERR, this, "'line x_lo x_hi y' needs x_hi > x_lo");
      have_line = true;
    } else if (keyword == "fill") {
      fill = silokit::keyword_number(this, error, value, "fill");
      if (!(fill > 0.0 && fill < 1.0))
        error->fix_error(FLERR, this, "'fill' must be in (0, 1) (sum of diameters / row length)");
    } else if (keyword == "fall") {
      fall = silokit::keyword_number(this, error, value, "fall");
      if (!(fall > 0.0)) error->fix_error(FLERR, this, "'fall' must be > 0");
      have_fall = true;
    } else if (keyword == "window") {
      window = silokit::keyword_integer(this, error, value, "window");
      if (window < 1) error->fix_error(FLERR, this, "'window' must be an integer >= 1 (rows)");
    } else if (keyword == "tolerance") {
      tolerance = silokit::keyword_number(this, error, value, "tolerance");
      if (!(tolerance >= 0.0)) error->fix_error(FLERR, this, "'tolerance' must be >= 0");
    } else if (keyword == "max_grains") {
      max_grains = silokit::keyword_integer(this, error, value, "max_grains");
      if (max_grains < 0) error->fix_error(FLERR, this, "'max_grains' must be >= 0 (0: no limit)");
    } else if (keyword == "max_rows") {
      max_rows = silokit::keyword_integer(this, error, value, "max_rows");
      if (max_rows < 0) error->fix_error(FLERR, this, "'max_rows' must be >= 0 (0: no limit)");
    } else {
      const std::string message = "unknown keyword '" + keyword + "' (known: seed, type, diameter, "
        "polydispersity, density, line, fill, fall, window, tolerance, max_grains, max_rows)";
      error->fix_error(FLERR, this, message.c_str());
    }
    iarg += values + 1;
  }
  if (!random) error->fix_error(FLERR, this, "'seed <prime > 10000>' is required");
  if (!have_type) error->fix_error(FLERR, this, "'type <atom type>' is required");
  if (grain_type < 1 || grain_type > atom->ntypes) {
    std::ostringstream message;
    message << "'type' must be an atom type from 1 to " << atom->ntypes;
    error->fix_error(FLERR, this, message.str().c_str());
  }
  if (mean_diameter == 0.0) error->fix_error(FLERR, this, "'diameter <mean diameter>' is required");
  if (density == 0.0) error->fix_error(FLERR, this, "'density <mass density>' is required");
  if (!have_line) error->fix_error(FLERR, this, "'line <x_lo> <x_hi> <y>' is required");
  const double largest = mean_diameter*(1.0 + polydispersity);
  if (!have_fall) fall = largest;
  if (fall < largest)
    error->fix_error(FLERR, this, "'fall' must be at least the largest diameter, d(1 + p), or rows could overlap");
  if (line_hi - line_lo < largest)
    error->fix_error(FLERR, this, "'line': the row is shorter than the largest grain");

  // the line and the grains on it must lie inside the box
  const double margin = 0.5*largest;
  if (line_lo < domain->boxlo[0] || line_hi > domain->boxhi[0] ||
      line_height - margin < domain->boxlo[1] || line_height + margin > domain->boxhi[1])
    error->fix_error(FLERR, this, "'line': the row of grains must lie inside the simulation box");
}

/* ---------------------------------------------------------------------- */

double FixInsertRain2d::max_rad(int type)
{
  return type == grain_type ? 0.5*mean_diameter*(1.0 + polydispersity) : 0.0;
}

double FixInsertRain2d::min_rad(int type)
{
  return type == grain_type ? 0.5*mean_diameter*(1.0 - polydispersity) : 0.0;
}

/* ---------------------------------------------------------------------- */

int FixInsertRain2d::setmask()
{
  return END_OF_STEP | PRE_EXCHANGE;
}

void FixInsertRain2d::init()
{
  if (atom->map_style == 0)
    error->fix_error(FLERR, this, "needs an atom map (atom_modify map array or hash)");
}

/* ----------------------------------------------------------------------
   the first row falls on the first step of the first run. Between runs a
   release that is pending (or was written to a restart file) is always due
   on the next step, since end_of_step schedules it for the step after its
   own, and the last release lies in the past. reset_timestep, before or
   after read_restart, moves the step counter either way: both steps are
   therefore set again from the step this run starts at. (Left as they
   were, a backward reset would put the release far in the future and keep
   the row from counting as having moved, which the blocked-line test
   needs: the rain would stall.)
------------------------------------------------------------------------- */

void FixInsertRain2d::setup(int)
{
  if (stop_reason != still_raining) return;
  if (release_step >= 0 || rows == 0) release_step = update->ntimestep + 1;
  last_release_step = std::min(last_release_step, update->ntimestep);
  if (release_step >= 0) next_reneighbor = release_step;
}

/* ----------------------------------------------------------------------
   schedule the next row once the last one has fallen
------------------------------------------------------------------------- */

void FixInsertRain2d::end_of_step()
{
  if (stop_reason != still_raining || release_step > update->ntimestep) return;
  const RowState state = last_row_state();
  if (state == row_blocked) {
    stop(line_blocked, grains_present());
    return;
  }
  if (state == row_falling) return;
  release_step = update->ntimestep + 1;
  next_reneighbor = release_step;
}

/* ----------------------------------------------------------------------
   row_fallen when every grain of the last row still present is `fall`
   below the line (a grain lost through a boundary no longer counts).
   row_blocked when one of them has not fallen so far but no longer moves
   down: it rests on the pile or bounced off it, so the pile has grown up
   to the line; without this the release would wait for ever. (A grain in
   free fall always has v_y < 0 at the end of a step after its release.)
------------------------------------------------------------------------- */

FixInsertRain2d::RowState FixInsertRain2d::last_row_state() const
{
  if (rows == 0) return row_fallen;
  // highest y of the row, and 1 if a grain above the threshold does not fall
  double local[2] = { -std::numeric_limits<double>::max(), 0.0 };
  const double threshold = line_height - fall;
  const bool moved = update->ntimestep > last_release_step;
  for (int i = 0; i < atom->nlocal; ++i) {
    const int tag = atom->tag[i];
    if (tag < last_row_first_tag || tag > last_row_last_tag) continue;
    local[0] = std::max(local[0], atom->x[i][1]);
    if (moved && atom->x[i][1] > threshold && atom->v[i][1] >= 0.0) local[1] = 1.0;
  }
  double global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, world);
  if (global[1] > 0.0) return row_blocked;
  return global[0] <= threshold ? row_fallen : row_falling;
}

/* ---------------------------------------------------------------------- */

int FixInsertRain2d::grains_present() const
{
  return static_cast<int>(group->count(igroup));
}

/* ----------------------------------------------------------------------
   the stop criterion: with n_k the grains present (in the fix group) just
   before release k, the mean of n over the last `window` releases exceeds
   the mean over the `window` releases before by at most `tolerance` times
   the newer mean. (While the rain runs at a constant rate, the grains in
   the air are a constant number of rows, so n is stationary when the
   number in the pile is.)
------------------------------------------------------------------------- */

double FixInsertRain2d::relative_growth() const
{
  const size_t n = present_at_release.size();
  if (n < 2*static_cast<size_t>(window)) return std::numeric_limits<double>::infinity();
  double older = 0.0, newer = 0.0;
  for (int k = 0; k < window; ++k) {
    older += present_at_release[n - 2*window + k];
    newer += present_at_release[n - window + k];
  }
  if (!(newer > 0.0)) return std::numeric_limits<double>::infinity();
  return (newer - older)/newer;
}

/* ----------------------------------------------------------------------
   the release step: stop or draw and create a row
------------------------------------------------------------------------- */

void FixInsertRain2d::pre_exchange()
{
  if (release_step != update->ntimestep) return;
  release_step = -1;
  if (stop_reason != still_raining) return;

  const int present = grains_present();
  present_at_release.push_back(present);
  while (present_at_release.size() > 2*static_cast<size_t>(window))
    present_at_release.erase(present_at_release.begin());

  if (relative_growth() <= tolerance) { stop(stationary, present); return; }
  if (max_rows > 0 && rows >= max_rows) { stop(max_rows_reached, present); return; }
  if (max_grains > 0 && inserted + grains_per_row > max_grains) {
    stop(max_grains_reached, present);
    return;
  }

  const std::vector<Disc> row = draw_row();
  if (row_overlaps_grains(row)) { stop(line_blocked, present); return; }
  create_owned_grains(row);

  rows += 1;
  inserted += static_cast<int>(row.size());
  last_row_first_tag = row.front().tag;
  last_row_last_tag = row.back().tag;
  last_release_step = update->ntimestep;
}

/* ----------------------------------------------------------------------
   diameters uniform in d(1 -+ p), then the gaps (rain_row.h); the same
   numbers on every rank. Tags continue after the largest tag in use and
   never go back, so that a grain lost through a boundary never lends its
   tag to a new one.
------------------------------------------------------------------------- */

std::vector<FixInsertRain2d::Disc> FixInsertRain2d::draw_row()
{
  int largest_local = 0, largest = 0;
  for (int i = 0; i < atom->nlocal; ++i) largest_local = std::max(largest_local, atom->tag[i]);
  MPI_Allreduce(&largest_local, &largest, 1, MPI_INT, MPI_MAX, world);
  next_tag = std::max(next_tag, largest + 1);

  std::vector<double> diameters(grains_per_row), cuts(grains_per_row);
  for (int k = 0; k < grains_per_row; ++k)
    diameters[k] = mean_diameter*(1.0 + polydispersity*(2.0*random->uniform() - 1.0));
  for (int k = 0; k < grains_per_row; ++k) cuts[k] = random->uniform();
  const std::vector<double> centres = silokit::rain_row_centres(diameters, line_lo, line_hi, cuts);
  if (centres.size() != diameters.size())
    error->fix_error(FLERR, this, "the grains of a row do not fit on the line: lower 'fill'");

  std::vector<Disc> row(grains_per_row);
  for (int k = 0; k < grains_per_row; ++k) {
    row[k].tag = next_tag++;
    row[k].x = centres[k];
    row[k].diameter = diameters[k];
  }
  return row;
}

/* ----------------------------------------------------------------------
   whether a grain of the row would overlap a grain already there (any
   group): only grains whose centre is within a largest diameter of the
   line can, and those are gathered on every rank
------------------------------------------------------------------------- */

bool FixInsertRain2d::row_overlaps_grains(const std::vector<Disc> &row) const
{
  const double reach = mean_diameter*(1.0 + polydispersity);
  std::vector<double> local;
  for (int i = 0; i < atom->nlocal; ++i) {
    if (std::fabs(atom->x[i][1] - line_height) > reach + atom->radius[i]) continue;
    local.push_back(atom->x[i][0]);
    local.push_back(atom->x[i][1]);
    local.push_back(atom->radius[i]);
  }
  const std::vector<double> near = silokit::allgather(local, world);
  for (size_t k = 0; k + 2 < near.size(); k += 3)
    for (size_t n = 0; n < row.size(); ++n) {
      const double dx = row[n].x - near[k], dy = line_height - near[k+1];
      const double contact = 0.5*row[n].diameter + near[k+2];
      if (dx*dx + dy*dy < contact*contact) return true;
    }
  return false;
}

/* ----------------------------------------------------------------------
   each rank creates the grains whose centre is in its sub-domain (the test
   create_atoms uses), at rest; then, as LIGGGHTS' fix insert does after an
   insertion, the atom count and the atom map are brought up to date
------------------------------------------------------------------------- */

void FixInsertRain2d::create_owned_grains(const std::vector<Disc> &row)
{
  const double *lo = domain->sublo, *hi = domain->subhi;
  for (int j = 0; j < modify->nfix; ++j)
    if (modify->fix[j]->create_attribute) modify->fix[j]->pre_set_arrays();

  for (size_t n = 0; n < row.size(); ++n) {
    double centre[3] = { row[n].x, line_height, 0.0 };
    if (centre[0] < lo[0] || centre[0] >= hi[0] || centre[1] < lo[1] || centre[1] >= hi[1] ||
        centre[2] < lo[2] || centre[2] >= hi[2]) continue;
    atom->avec->create_atom(grain_type, centre);
    const int m = atom->nlocal - 1;
    const double radius = 0.5*row[n].diameter;
    atom->tag[m] = row[n].tag;
    atom->mask[m] = 1 | groupbit;
    atom->radius[m] = radius;
    atom->density[m] = density;
    atom->rmass[m] = pi*radius*radius*density;     // a disc: LIGGGHTS' 2D mass
    for (int k = 0; k < 3; ++k) {
      atom->v[m][k] = 0.0;
      atom->omega[m][k] = 0.0;
    }
    for (int j = 0; j < modify->nfix; ++j)
      if (modify->fix[j]->create_attribute) modify->fix[j]->set_arrays(m);
  }

  bigint owned = atom->nlocal;
  MPI_Allreduce(&owned, &atom->natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  atom->nghost = 0;
  atom->map_init();
  atom->map_set();
}

/* ---------------------------------------------------------------------- */

void FixInsertRain2d::stop(StopReason reason, int present)
{
  stop_reason = reason;
  next_reneighbor = -1;
  release_step = -1;
  static const char *why[] = { "", "the number of grains present is stationary",
                               "max_grains reached", "max_rows reached",
                               "the pile has reached the release line" };
  if (comm->me == 0) {
    std::ostringstream line;
    line << "fix insert/rain2d " << id << ": release stopped at step " << update->ntimestep
         << ": " << why[reason] << "; " << rows << " rows, " << inserted
         << " grains inserted, " << present << " present\n";
    if (screen) { fputs(line.str().c_str(), screen); fflush(screen); }
    if (logfile) { fputs(line.str().c_str(), logfile); fflush(logfile); }
  }
  if (reason == line_blocked && comm->me == 0)
    error->warning(FLERR, "fix insert/rain2d: the pile has reached the release line; raise the line");
}

/* ----------------------------------------------------------------------
   1 grains inserted, 2 rows released, 3 stop reason (0 while raining;
   1 stationary, 2 max_grains, 3 max_rows, 4 line blocked), 4 grains present
   at the last release, 5 relative growth between the last two windows
   (-1 before two windows of releases)
------------------------------------------------------------------------- */

double FixInsertRain2d::compute_vector(int index)
{
  switch (index) {
    case 0: return inserted;
    case 1: return rows;
    case 2: return stop_reason;
    case 3: return present_at_release.empty() ? 0.0 : present_at_release.back();
    case 4: {
      const double growth = relative_growth();
      return std::isfinite(growth) ? growth : -1.0;
    }
  }
  return 0.0;
}

/* ---------------------------------------------------------------------- */

void FixInsertRain2d::write_restart(FILE *fp)
{
  std::vector<double> list;
  list.push_back(0.0);                 // the length of the list, set below
  list.push_back(random->state());
  list.push_back(next_tag);
  list.push_back(rows);
  list.push_back(inserted);
  list.push_back(stop_reason);
  list.push_back(last_row_first_tag);
  list.push_back(last_row_last_tag);
  list.push_back(static_cast<double>(release_step));
  list.push_back(static_cast<double>(last_release_step));
  list.insert(list.end(), present_at_release.begin(), present_at_release.end());
  list[0] = static_cast<double>(list.size());
  if (comm->me == 0) {
    const int size = static_cast<int>(list.size()*sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(&list[0], sizeof(double), list.size(), fp);
  }
}

void FixInsertRain2d::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  const int count = static_cast<int>(list[0]);
  random->reset(static_cast<int>(list[1]));
  next_tag = static_cast<int>(list[2]);
  rows = static_cast<int>(list[3]);
  inserted = static_cast<int>(list[4]);
  stop_reason = static_cast<StopReason>(static_cast<int>(list[5]));
  last_row_first_tag = static_cast<int>(list[6]);
  last_row_last_tag = static_cast<int>(list[7]);
  release_step = static_cast<bigint>(list[8]);
  last_release_step = static_cast<bigint>(list[9]);
  present_at_release.assign(list + restart_scalars, list + count);
}
