/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix reinject for LAMMPS: see fix_reinject_lammps.h and
   doc/fix_reinject_lammps.md.

   How (as the LIGGGHTS fix, and as LAMMPS' own fix deposit and fix pour
   insert): every N steps (end_of_step) the ranks count the grains below
   the exit plane; when there are any, next_reneighbor asks for a
   neighbor-list build on the next step, and in its pre_exchange every rank
   gathers the leavers and the grains near the injection region, draws the
   same free spots with the same random sequence (leavers sorted by id),
   and moves the leavers it owns (core/reinject_logic.h, as the LIGGGHTS
   fix). Each moved grain is then sent straight to the rank that owns its
   spot (Irregular): LAMMPS' exchange that follows passes atoms to the
   neighbouring ranks only, and the top of the silo may be several ranks
   away from its outlet. The result does not depend on the number of ranks.
------------------------------------------------------------------------- */

#include "fix_reinject_lammps.h"
#include "lammps_compat.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "irregular.h"
#include "random_park.h"
#include "region.h"
#include "update.h"

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *const STYLE = "fix reinject";

// first value of the restart data: the list of core/reinject_logic.h,
// then the clock's three values
const double restart_layout = -1.0;

}    // namespace

/* ---------------------------------------------------------------------- */

FixReinject::FixReinject(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), region(nullptr), restored(false), state(0.1)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "{} needs atom attributes radius, rmass and omega (atom_style sphere)",
               STYLE);
  if (atom->ellipsoid_flag || atom->line_flag || atom->tri_flag || atom->body_flag)
    error->all(FLERR, "{}: spheres only in LAMMPS; rods (LIGGGHTS' atom_style "
               "spherocylinder), ellipsoids, lines, triangles and bodies are not re-entered",
               STYLE);

  const std::vector<std::string> words(arg + 3, arg + narg);
  const std::string problem =
      silokit::reinject::parse_settings(words, domain->dimension == 2, settings);
  if (!problem.empty()) error->all(FLERR, "{}: {}", STYLE, problem);
  random.reset(new RanPark(lmp, settings.seed));
  nevery = settings.every;
  state.flow.set_window(settings.rate_window);

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;

  // the clock starts at LAMMPS' time now (0 in a fresh run)
  clock.start(update->atime + (update->ntimestep - update->atimestep) * update->dt,
              update->ntimestep, update->dt);
}

FixReinject::~FixReinject() = default;    // closes the record

/* ---------------------------------------------------------------------- */

int FixReinject::setmask()
{
  return END_OF_STEP | PRE_EXCHANGE;
}

void FixReinject::init()
{
  region = silokit_lammps::region_by_id(domain, settings.region_id);
  if (!region) error->all(FLERR, "{}: region '{}' does not exist", STYLE, settings.region_id);
  if (!region->bboxflag)
    error->all(FLERR, "{}: the region must have a bounding box (e.g. block, cylinder)", STYLE);
  const std::string problem = silokit::reinject::check_region(*region, settings);
  if (!problem.empty()) error->all(FLERR, "{}: {}", STYLE, problem);

  // a new time step (the timestep command between runs): the clock goes
  // on from the time reached with the old one
  clock.use_time_step(update->ntimestep, update->dt);
  open_record_file();
}

/* ----------------------------------------------------------------------
   opened at the first init: LAMMPS calls restart() after the constructor,
   and a restored fix appends to its record, so that the pieces of a
   restarted run write one file (silokit_record.h)
------------------------------------------------------------------------- */

void FixReinject::open_record_file()
{
  if (settings.file_name.empty() || record) return;
  int opened = 1;
  if (comm->me == 0) {
    std::string notice;
    record = silokit::reinject::open_reinject_record(settings, id, restored, simulated_time(),
                                                     notice);
    opened = record != nullptr;
    if (!notice.empty()) utils::logmesg(lmp, notice + "\n");
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened) error->all(FLERR, "{}: cannot open file '{}'", STYLE, settings.file_name);
}

/* ---------------------------------------------------------------------- */

double FixReinject::simulated_time() const
{
  return clock.time(update->ntimestep);
}

bool FixReinject::is_leaver(int i) const
{
  return (atom->mask[i] & groupbit) && atom->x[i][settings.axis] < settings.exit_coordinate;
}

/* ----------------------------------------------------------------------
   every N steps: ask for a neighbor-list build next step if grains left
------------------------------------------------------------------------- */

void FixReinject::end_of_step()
{
  auto left_through_exit = [this](int i) { return is_leaver(i); };
  if (state.check(simulated_time(), atom->nlocal, left_through_exit, world))
    next_reneighbor = update->ntimestep + 1;
}

/* ----------------------------------------------------------------------
   on the step after grains left: move them to the top
------------------------------------------------------------------------- */

void FixReinject::pre_exchange()
{
  if (next_reneighbor != update->ntimestep) return;
  next_reneighbor = -1;

  const silokit::reinject::Grains<tagint> grains = {
      atom->nlocal, atom->tag, atom->x, atom->v, atom->omega, atom->angmom, atom->radius,
      atom->rmass};
  // a spot where the whole grain lies in the region: inside it, no
  // surface within its radius (LIGGGHTS' match_shrinkby_cut)
  region->prematch();
  auto inside = [this](double *spot, double radius) {
    return region->match(spot[0], spot[1], spot[2]) &&
        region->surface(spot[0], spot[1], spot[2], radius) == 0;
  };
  auto uniform = [this]() { return random->uniform(); };
  std::map<int, silokit::reinject::Sphere> spots;
  int unplaced = 0;
  auto left_through_exit = [this](int i) { return is_leaver(i); };
  const int reentered = silokit::reinject::reenter(
      state, grains, left_through_exit, silokit::reinject::bounding_box(*region),
      domain->dimension == 2,
      silokit::periodic_image_shifts(domain->periodicity, domain->h, domain->dimension == 2),
      settings.max_attempts, uniform, inside, world, spots, unplaced);
  if (reentered < 0)
    error->all(FLERR, "{}: {}", STYLE, silokit::reinject::no_free_spot(settings, unplaced));
  if (reentered == 0) return;
  send_to_owners(spots);
  if (record)
    silokit::reinject::write_record_line(record.get(), update->ntimestep, simulated_time(),
                                         state.counts);
}

/* ----------------------------------------------------------------------
   each moved grain to the rank whose sub-domain holds its spot, the
   others stay (LAMMPS' exchange then finds nothing to do for the moved
   ones); all ranks take part
------------------------------------------------------------------------- */

void FixReinject::send_to_owners(const std::map<int, silokit::reinject::Sphere> &spots)
{
  if (comm->nprocs == 1) return;
  comm->coord2proc_setup();
  std::vector<int> owner(atom->nlocal, comm->me);
  for (int i = 0; i < atom->nlocal; ++i) {
    if (spots.find(static_cast<int>(atom->tag[i])) == spots.end()) continue;
    double lamda[3];
    double *coordinate = atom->x[i];
    if (domain->triclinic) {
      domain->x2lamda(atom->x[i], lamda);
      coordinate = lamda;
    }
    int igx, igy, igz;
    owner[i] = comm->coord2proc(coordinate, igx, igy, igz);
  }
  Irregular irregular(lmp);
  irregular.migrate_atoms(0, 1, owner.data());
}

/* ---------------------------------------------------------------------- */

int FixReinject::close_avalanche()
{
  return state.counts.close_avalanche();
}

void FixReinject::request_reinjection(const std::vector<int> &tags)
{
  if (state.request(tags)) next_reneighbor = update->ntimestep + 1;
}

double FixReinject::compute_vector(int index)
{
  return state.output(index);
}

/* ----------------------------------------------------------------------
   counts, random state, the step of a pending re-entry (grains found
   below the exit at the last check, or tags from fix clog), those tags,
   the flow-rate samples, then the clock: a restarted run goes on as the
   uninterrupted one
------------------------------------------------------------------------- */

void FixReinject::write_restart(FILE *fp)
{
  const silokit::reinject::RestartHead head = {random->state(), simulated_time(),
                                                static_cast<double>(next_reneighbor)};
  std::vector<double> list = silokit::reinject::restart_list(restart_layout, state, head);
  double clock_values[3];
  clock.write(clock_values);
  list.insert(list.end(), clock_values, clock_values + 3);
  if (comm->me == 0) silokit::write_restart_data(fp, list);
}

void FixReinject::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  if (list[0] != restart_layout)
    error->all(FLERR, "{}: the restart data of fix '{}' is not in the layout of this version; "
               "define the fix with another ID to start anew", STYLE, id);
  silokit::reinject::RestartHead head = {0, 0.0, -1.0};
  const double *clock_values = silokit::reinject::read_restart_list(list, true, state, head);
  random->reset(head.random_state);
  clock.read(clock_values);
  next_reneighbor = static_cast<bigint>(head.pending_step);
  restored = true;
}
