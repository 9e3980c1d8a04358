/* ----------------------------------------------------------------------
   fix plane/crossings: see fix_plane_crossings.h and doc/extend.md.

   How: after the positions are updated (post_integrate), a grain that is
   below the plane now and was at or above it one step ago has crossed.
   Its position one step ago is x - v dt: the integrators of granular runs
   (fix nve/sphere) move x by v dt with the v they leave in the array. Each
   rank finds the crossings of its own grains; rank 0 gathers and writes
   them, sorted by id, so that the record does not depend on the number of
   ranks.
------------------------------------------------------------------------- */

#include "fix_plane_crossings.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include <algorithm>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

static const int row_size = 7;  // id x y vx vy vz mass

FixPlaneCrossings::FixPlaneCrossings(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), plane_z(0.0), crossings_file(nullptr), rate_file(nullptr), write_each_crossing(false),
  total_grains(0.0), total_mass(0.0), window_grains(0.0), window_mass(0.0), window_start(0)
{
  // fix ID group plane/crossings z Z [every N] [crossings FILE] [rate FILE]
  if (narg < 5 || strcmp(arg[3], "z") != 0)
    error->fix_error(FLERR, this, "expects z and the height of the plane");
  plane_z = force->numeric(FLERR, arg[4]);
  nevery = 1000;
  const char *crossings_path = nullptr, *rate_path = nullptr;
  for (int k = 5; k < narg; k += 2) {
    const std::string keyword = arg[k];
    if (k + 1 >= narg)
      error->fix_error(FLERR, this, ("'" + keyword + "' needs a value").c_str());
    if (strcmp(arg[k], "every") == 0) {
      nevery = force->inumeric(FLERR, arg[k+1]);
      if (nevery < 1) error->fix_error(FLERR, this, "'every' must be a positive number of steps");
    } else if (strcmp(arg[k], "crossings") == 0) {
      crossings_path = arg[k+1];
    } else if (strcmp(arg[k], "rate") == 0) {
      rate_path = arg[k+1];
    } else {
      error->fix_error(FLERR, this, ("unknown keyword '" + keyword + "' (allowed: every, crossings, rate)").c_str());
    }
  }

  vector_flag = 1;              // f_ID[1]: grains crossed, f_ID[2]: their mass
  size_vector = 2;
  global_freq = 1;
  extvector = 0;

  write_each_crossing = crossings_path != nullptr;
  if (crossings_path)
    crossings_file = open_record("crossings", crossings_path, "# step time id x y vx vy vz");
  if (rate_path)
    rate_file = open_record("rate", rate_path, "# step time grains mass grains_per_time mass_per_time");
  window_start = update->ntimestep;
}

FixPlaneCrossings::~FixPlaneCrossings()
{
  if (crossings_file) fclose(crossings_file);
  if (rate_file) fclose(rate_file);
}

FILE *FixPlaneCrossings::open_record(const char *keyword, const char *path, const char *header)
{
  int opened = 1;
  FILE *file = nullptr;
  if (comm->me == 0) {
    file = fopen(path, "w");
    opened = file != nullptr;
    if (file) fprintf(file, "%s\n", header);
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened) {
    const std::string message = std::string("cannot open the '") + keyword + "' file " + path;
    error->fix_error(FLERR, this, message.c_str());
  }
  return file;
}

int FixPlaneCrossings::setmask()
{
  return POST_INTEGRATE | END_OF_STEP;
}

void FixPlaneCrossings::post_integrate()
{
  double **x = atom->x, **v = atom->v;
  double *rmass = atom->rmass;
  const double dt = update->dt;
  found.clear();
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double z_before = x[i][2] - v[i][2]*dt;
    if (x[i][2] < plane_z && z_before >= plane_z) {
      const double mass = rmass ? rmass[i] : atom->mass[atom->type[i]];
      const double row[row_size] = { double(atom->tag[i]), x[i][0], x[i][1],
                                     v[i][0], v[i][1], v[i][2], mass };
      found.insert(found.end(), row, row + row_size);
    }
  }

  // every rank learns how many grains crossed and their mass
  double local[2] = { double(found.size()/row_size), 0.0 }, sum[2];
  for (size_t k = 0; k < found.size(); k += row_size) local[1] += found[k + 6];
  MPI_Allreduce(local, sum, 2, MPI_DOUBLE, MPI_SUM, world);
  if (sum[0] == 0.0) return;
  total_grains += sum[0];
  total_mass += sum[1];
  window_grains += sum[0];
  window_mass += sum[1];
  if (!write_each_crossing) return;

  // rank 0 gathers the rows and writes them
  const int nprocs = comm->nprocs;
  int local_values = found.size();
  std::vector<int> counts(nprocs), offsets(nprocs, 0);
  MPI_Gather(&local_values, 1, MPI_INT, &counts[0], 1, MPI_INT, 0, world);
  for (int r = 1; r < nprocs; ++r) offsets[r] = offsets[r-1] + counts[r-1];
  std::vector<double> rows(comm->me == 0 ? row_size*size_t(sum[0]) : 0);
  MPI_Gatherv(found.empty() ? nullptr : &found[0], local_values, MPI_DOUBLE,
              rows.empty() ? nullptr : &rows[0], &counts[0], &offsets[0], MPI_DOUBLE, 0, world);
  if (comm->me == 0) write_crossings(rows);
}

void FixPlaneCrossings::write_crossings(const std::vector<double> &rows)
{
  std::vector<const double *> order;
  for (size_t k = 0; k < rows.size(); k += row_size) order.push_back(&rows[k]);
  std::sort(order.begin(), order.end(),
            [](const double *a, const double *b) { return a[0] < b[0]; });
  const double time = update->ntimestep*update->dt;
  for (const double *row : order)
    fprintf(crossings_file, BIGINT_FORMAT " %.10g %.0f %.10g %.10g %.10g %.10g %.10g\n",
            update->ntimestep, time, row[0], row[1], row[2], row[3], row[4], row[5]);
  fflush(crossings_file);
}

void FixPlaneCrossings::end_of_step()
{
  // called every nevery steps: the rate over the steps since the last line
  const double window_time = (update->ntimestep - window_start)*update->dt;
  if (comm->me == 0 && rate_file && window_time > 0.0) {
    fprintf(rate_file, BIGINT_FORMAT " %.10g %.0f %.10g %.10g %.10g\n",
            update->ntimestep, update->ntimestep*update->dt, window_grains, window_mass,
            window_grains/window_time, window_mass/window_time);
    fflush(rate_file);
  }
  window_grains = window_mass = 0.0;
  window_start = update->ntimestep;
}

double FixPlaneCrossings::compute_vector(int n)
{
  return n == 0 ? total_grains : total_mass;
}
