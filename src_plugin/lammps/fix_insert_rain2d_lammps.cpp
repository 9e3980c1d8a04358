/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix insert/rain2d for LAMMPS: see fix_insert_rain2d_lammps.h and
   doc/fix_insert_rain2d_lammps.md.

   How (as the LIGGGHTS fix, and as LAMMPS' own fix pour inserts): at the
   end of every step the ranks find the highest grain of the last row
   released (one MPI_Allreduce); once it is `fall` below the line,
   next_reneighbor asks for a neighbor-list build on the next step, whose
   pre_exchange draws the row and creates it. Every rank draws the same
   random numbers in the same order (one generator, same seed) and creates
   only the grains whose centre lies in its own sub-domain; tags come in
   drawing order from a counter all ranks share (as fix pour sets them,
   not Atom::tag_extend(), which numbers new atoms in rank order). So a
   row, grain by grain and tag by tag, does not depend on the number of
   ranks. Grains that leave the box through non-periodic boundaries are
   lost atoms (thermo_modify lost ignore).
------------------------------------------------------------------------- */

#include "fix_insert_rain2d_lammps.h"

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "modify.h"
#include "random_park.h"
#include "update.h"

#include <algorithm>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *const STYLE = "fix insert/rain2d";
const double pi = 3.14159265358979323846;

bool positive(int seed)
{
  return seed > 0;
}

// LAMMPS' RanPark takes any positive seed
const silokit::rain2d::SeedRule lammps_seed = {
    &positive, "positive integer", "a positive integer (LAMMPS' random generator requires it)"};

}    // namespace

/* ---------------------------------------------------------------------- */

FixInsertRain2d::FixInsertRain2d(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), announced_radius(0.0)
{
  const std::string unfit = silokit::rain2d::host_problem(
      domain->dimension, atom->radius_flag && atom->rmass_flag && atom->omega_flag,
      atom->tag_enable, domain->triclinic, "fix pour or fix deposit");
  if (!unfit.empty()) error->all(FLERR, "{} {}", STYLE, unfit);

  const std::vector<std::string> words(arg + 3, arg + narg);
  silokit::rain2d::Settings settings;
  const std::string problem = silokit::rain2d::parse_settings(
      words, lammps_seed, atom->ntypes, domain->boxlo, domain->boxhi, settings);
  if (!problem.empty()) error->all(FLERR, "{}: {}", STYLE, problem);
  rain.reset(new silokit::rain2d::Rain(settings));
  random.reset(new RanPark(lmp, settings.seed));

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

int FixInsertRain2d::setmask()
{
  return END_OF_STEP | PRE_EXCHANGE;
}

void *FixInsertRain2d::extract(const char *name, int &itype)
{
  if (strcmp(name, "radius") != 0) return nullptr;
  announced_radius =
      itype == rain->settings.grain_type ? 0.5 * rain->settings.largest_diameter() : 0.0;
  itype = 0;
  return &announced_radius;
}

/* ----------------------------------------------------------------------
   the pending release is set again from the step this run starts at
   (Rain::run_set_up says why)
------------------------------------------------------------------------- */

void FixInsertRain2d::setup(int)
{
  const bigint release = rain->run_set_up(update->ntimestep);
  if (release >= 0) next_reneighbor = release;
}

/* ----------------------------------------------------------------------
   schedule the next row once the last one has fallen
------------------------------------------------------------------------- */

void FixInsertRain2d::end_of_step()
{
  const silokit::rain2d::StepVerdict verdict =
      rain->end_of_step(update->ntimestep, atom->nlocal, atom->tag, atom->x, atom->v, world);
  if (verdict == silokit::rain2d::stop_blocked)
    stop(silokit::rain2d::line_blocked, grains_present());
  else if (verdict == silokit::rain2d::release_next_step)
    next_reneighbor = rain->pending_release();
}

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
    error->all(FLERR, "{}: the grains of a row do not fit on the line: lower 'fill'", STYLE);
  if (release.outcome == silokit::rain2d::Release::stopped) stop(release.reason, release.present);
  if (release.outcome != silokit::rain2d::Release::row_drawn) return;
  if (release.row.back().tag > MAXTAGINT)
    error->all(FLERR, "{}: new atom IDs exceed the largest ID", STYLE);
  create_owned_grains(release.row);
  rain->released(release.row, update->ntimestep);
}

/* ----------------------------------------------------------------------
   each rank creates the grains whose centre is in its sub-domain (the test
   of create_atoms), at rest, with a disc's mass pi r^2 rho (what `set
   density/disc` gives). The sequence is fix pour's: the ghosts (and the
   map) are cleared first, since new atoms overwrite them; then the atom
   count and the map are brought up to date. The count is summed over the
   ranks, not incremented: with `thermo_modify lost ignore` LAMMPS does not
   subtract the grains lost through the boundaries.
------------------------------------------------------------------------- */

void FixInsertRain2d::create_owned_grains(const std::vector<silokit::rain2d::Disc> &row)
{
  if (atom->map_style != Atom::MAP_NONE) atom->map_clear();
  atom->nghost = 0;
  atom->avec->clear_bonus();

  const silokit::rain2d::Settings &settings = rain->settings;
  const double *lo = domain->sublo, *hi = domain->subhi;
  for (const silokit::rain2d::Disc &disc : row) {
    double centre[3] = {disc.x, settings.line_height, 0.0};
    if (centre[0] < lo[0] || centre[0] >= hi[0] || centre[1] < lo[1] || centre[1] >= hi[1] ||
        centre[2] < lo[2] || centre[2] >= hi[2])
      continue;
    atom->avec->create_atom(settings.grain_type, centre);
    const int m = atom->nlocal - 1;
    const double radius = 0.5 * disc.diameter;
    atom->tag[m] = static_cast<tagint>(disc.tag);
    atom->mask[m] = 1 | groupbit;
    atom->radius[m] = radius;
    atom->rmass[m] = pi * radius * radius * settings.density;
    for (int k = 0; k < 3; ++k) {
      atom->v[m][k] = 0.0;
      atom->omega[m][k] = 0.0;
    }
    modify->create_attribute(m);
  }

  bigint owned = atom->nlocal;
  MPI_Allreduce(&owned, &atom->natoms, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (atom->map_style != Atom::MAP_NONE) {
    atom->map_init();
    atom->map_set();
  }
}

/* ---------------------------------------------------------------------- */

void FixInsertRain2d::stop(silokit::rain2d::StopReason reason, int present)
{
  const std::string line = rain->stop(reason, id, update->ntimestep, present);
  next_reneighbor = -1;
  if (comm->me == 0) utils::logmesg(lmp, line);
  if (reason == silokit::rain2d::line_blocked && comm->me == 0)
    error->warning(FLERR, "{}: the pile has reached the release line; raise the line", STYLE);
}

double FixInsertRain2d::compute_vector(int index)
{
  return rain->output(index);
}

/* ----------------------------------------------------------------------
   the random state, counters and steps (Rain::restart_list): a restarted
   run releases the same rows at the same steps
------------------------------------------------------------------------- */

void FixInsertRain2d::write_restart(FILE *fp)
{
  if (comm->me == 0) silokit::write_restart_data(fp, rain->restart_list(random->state()));
}

void FixInsertRain2d::restart(char *buf)
{
  random->reset(rain->read_restart_list(reinterpret_cast<double *>(buf)));
}
