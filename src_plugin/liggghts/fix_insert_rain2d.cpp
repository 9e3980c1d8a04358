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
   The schedule, the stop rules, the rows, the outputs and the restart
   data are core/rain2d_logic.h, which the LAMMPS fix calls too.
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
#include "silokit_args.h"
#include "update.h"

#include <algorithm>
#include <cstdio>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const double pi = 3.14159265358979323846;

// LIGGGHTS' random generator wants a prime > 10000 (silokit_args.h)
const silokit::rain2d::SeedRule liggghts_seed = {
  &silokit::liggghts_seed_accepted, "prime > 10000",
  "a prime number > 10000 (LIGGGHTS' random generator requires it)" };

}  // namespace

/* ---------------------------------------------------------------------- */

FixInsertRain2d::FixInsertRain2d(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg)
{
  const std::string unfit = silokit::rain2d::host_problem(
    domain->dimension, atom->radius_flag && atom->rmass_flag && atom->omega_flag,
    atom->tag_enable, domain->triclinic, "LIGGGHTS' fix insert/* styles");
  if (!unfit.empty()) error->fix_error(FLERR, this, unfit.c_str());

  const std::vector<std::string> words(arg + 3, arg + narg);
  silokit::rain2d::Settings settings;
  const std::string problem = silokit::rain2d::parse_settings(
    words, liggghts_seed, atom->ntypes, domain->boxlo, domain->boxhi, settings);
  if (!problem.empty()) error->fix_error(FLERR, this, problem.c_str());
  rain.reset(new silokit::rain2d::Rain(settings));
  // RanPark reads its text with atoi: give it the integer's digits
  random.reset(new RanPark(lmp, std::to_string(settings.seed).c_str()));

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

double FixInsertRain2d::max_rad(int type)
{
  return type == rain->settings.grain_type ? 0.5*rain->settings.largest_diameter() : 0.0;
}

double FixInsertRain2d::min_rad(int type)
{
  return type == rain->settings.grain_type ? 0.5*rain->settings.smallest_diameter() : 0.0;
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
   the pending release is set again from the step this run starts at
   (Rain::run_set_up says why)
------------------------------------------------------------------------- */

void FixInsertRain2d::setup(int)
{
  const long long release = rain->run_set_up(update->ntimestep);
  if (release >= 0) next_reneighbor = release;
}

/* ----------------------------------------------------------------------
   schedule the next row once the last one has fallen
------------------------------------------------------------------------- */

void FixInsertRain2d::end_of_step()
{
  const silokit::rain2d::StepVerdict verdict =
    rain->end_of_step(update->ntimestep, atom->nlocal, atom->tag, atom->x, atom->v, world);
  if (verdict == silokit::rain2d::stop_blocked) stop(silokit::rain2d::line_blocked, grains_present());
  else if (verdict == silokit::rain2d::release_next_step) next_reneighbor = rain->pending_release();
}

/* ---------------------------------------------------------------------- */

int FixInsertRain2d::grains_present() const
{
  return static_cast<int>(group->count(igroup));
}

/* ----------------------------------------------------------------------
   the release step: stop or draw and create a row
------------------------------------------------------------------------- */

void FixInsertRain2d::pre_exchange()
{
  const silokit::rain2d::Release release = rain->release(
    update->ntimestep, [this]() { return grains_present(); }, atom->nlocal, atom->tag, atom->x,
    atom->radius,
    silokit::periodic_image_shifts(domain->periodicity, domain->h, domain->dimension == 2),
    [this]() { return random->uniform(); }, world);
  if (release.outcome == silokit::rain2d::Release::does_not_fit)
    error->fix_error(FLERR, this, "the grains of a row do not fit on the line: lower 'fill'");
  if (release.outcome == silokit::rain2d::Release::stopped) stop(release.reason, release.present);
  if (release.outcome != silokit::rain2d::Release::row_drawn) return;
  create_owned_grains(release.row);
  rain->released(release.row, update->ntimestep);
}

/* ----------------------------------------------------------------------
   each rank creates the grains whose centre is in its sub-domain (the test
   create_atoms uses), at rest; then, as LIGGGHTS' fix insert does after an
   insertion, the atom count and the atom map are brought up to date
------------------------------------------------------------------------- */

void FixInsertRain2d::create_owned_grains(const std::vector<silokit::rain2d::Disc> &row)
{
  const double *lo = domain->sublo, *hi = domain->subhi;
  for (int j = 0; j < modify->nfix; ++j)
    if (modify->fix[j]->create_attribute) modify->fix[j]->pre_set_arrays();

  for (size_t n = 0; n < row.size(); ++n) {
    double centre[3] = { row[n].x, rain->settings.line_height, 0.0 };
    if (centre[0] < lo[0] || centre[0] >= hi[0] || centre[1] < lo[1] || centre[1] >= hi[1] ||
        centre[2] < lo[2] || centre[2] >= hi[2]) continue;
    atom->avec->create_atom(rain->settings.grain_type, centre);
    const int m = atom->nlocal - 1;
    const double radius = 0.5*row[n].diameter;
    atom->tag[m] = static_cast<int>(row[n].tag);
    atom->mask[m] = 1 | groupbit;
    atom->radius[m] = radius;
    atom->density[m] = rain->settings.density;
    atom->rmass[m] = pi*radius*radius*rain->settings.density;     // a disc: LIGGGHTS' 2D mass
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

void FixInsertRain2d::stop(silokit::rain2d::StopReason reason, int present)
{
  const std::string line = rain->stop(reason, id, update->ntimestep, present);
  next_reneighbor = -1;
  if (comm->me == 0) {
    if (screen) { fputs(line.c_str(), screen); fflush(screen); }
    if (logfile) { fputs(line.c_str(), logfile); fflush(logfile); }
  }
  if (reason == silokit::rain2d::line_blocked && comm->me == 0)
    error->warning(FLERR, "fix insert/rain2d: the pile has reached the release line; raise the line");
}

/* ----------------------------------------------------------------------
   the outputs: Rain::output
------------------------------------------------------------------------- */

double FixInsertRain2d::compute_vector(int index)
{
  return rain->output(index);
}

/* ---------------------------------------------------------------------- */

void FixInsertRain2d::write_restart(FILE *fp)
{
  if (comm->me == 0) silokit::write_restart_data(fp, rain->restart_list(random->state()));
}

void FixInsertRain2d::restart(char *buf)
{
  random->reset(rain->read_restart_list(reinterpret_cast<double *>(buf)));
}
