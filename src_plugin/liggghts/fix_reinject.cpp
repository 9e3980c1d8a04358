/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix reinject: see fix_reinject.h and doc/fix_reinject.md.

   How: every N steps (end_of_step) the ranks count the grains below the
   exit plane; when there are any, a neighbor-list build is requested for
   the next step, and in its pre_exchange every rank gathers the leavers and
   the grains near the injection region, draws the same free spots with the
   same random sequence (leavers sorted by id), and moves the leavers it
   owns. A moved grain whose new rank is more than one rank away is sent
   straight there (Irregular): LIGGGHTS' exchange, which follows, passes
   atoms to the neighbouring ranks only. So the result does not depend on
   the number of ranks. The keywords, the gathering, the placement, the
   counts, the flow rate, the record and the restart data are
   core/reinject_logic.h, shared with the LAMMPS fix; this adapter hands it
   LIGGGHTS' arrays, random generator, region and errors.
------------------------------------------------------------------------- */

#include "fix_reinject.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "input.h"
#include "irregular.h"
#include "random_park.h"
#include "region.h"
#include "silokit_args.h"
#include "update.h"

#include <map>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// first value of the restart data. -3: with the pending re-entries and
// the flow-rate samples; -2: without them (silokit up to commit eaa418e);
// before the restart clock the data began with the count of grains out (>= 0)
const double restart_layout = -3.0;
const double restart_layout_without_pending = -2.0;

}  // namespace

/* ---------------------------------------------------------------------- */

FixReinject::FixReinject(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg), region(nullptr), restored(false), state(0.1)
{
  if (!atom->radius_flag || !atom->rmass_flag)
    error->fix_error(FLERR, this, "needs per-atom radius and mass (atom_style sphere or granular)");

  const std::vector<std::string> words(arg + 3, arg + narg);
  const std::string problem =
    silokit::reinject::parse_settings(words, domain->dimension == 2, settings);
  if (!problem.empty()) error->fix_error(FLERR, this, problem.c_str());
  if (!silokit::liggghts_seed_accepted(settings.seed) && input->seed_check_throw_error())
    error->fix_error(FLERR, this, "'seed' must be a prime number > 10000 "
                                  "(LIGGGHTS' random generator requires it)");
  // RanPark reads its text with atoi: give it the integer's digits
  random.reset(new RanPark(lmp, std::to_string(settings.seed).c_str()));
  nevery = settings.every;
  state.flow.set_window(settings.rate_window);

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
  force_reneighbor = 1;
  next_reneighbor = -1;
}

FixReinject::~FixReinject() = default;   // closes the record

/* ---------------------------------------------------------------------- */

int FixReinject::setmask()
{
  return END_OF_STEP | PRE_EXCHANGE;
}

void FixReinject::init()
{
  const int iregion = domain->find_region(settings.region_id.c_str());
  if (iregion == -1) {
    std::string message = "region '" + settings.region_id + "' does not exist";
    error->fix_error(FLERR, this, message.c_str());
  }
  region = domain->regions[iregion];
  if (!region->bboxflag)
    error->fix_error(FLERR, this, "the region must have a bounding box (e.g. block, cylinder)");
  const std::string problem = silokit::reinject::check_region(*region, settings);
  if (!problem.empty()) error->fix_error(FLERR, this, problem.c_str());

  open_record_file();
}

/* ----------------------------------------------------------------------
   opened at the first init, not in the constructor: LIGGGHTS calls
   restart() after it, and a restored fix appends to the record, so that
   the pieces of a restarted run write one file (silokit_record.h); its
   clock then reads the time the restart file was written at
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
    if (!notice.empty()) error->message(FLERR, notice.c_str());
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened) {
    const std::string message = "cannot open file '" + settings.file_name + "'";
    error->fix_error(FLERR, this, message.c_str());
  }
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

  // rods (atom_style spherocylinder) turn with their angular momentum
  const silokit::reinject::Grains<int> grains = {
    atom->nlocal, atom->tag, atom->x, atom->v, atom->omega, atom->angmom, atom->radius,
    atom->rmass };
  // a spot where the whole grain lies in the region
  auto inside = [this](double *spot, double radius) {
    return region->match_shrinkby_cut(spot, radius) != 0;
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
    error->fix_error(FLERR, this, silokit::reinject::no_free_spot(settings, unplaced).c_str());
  if (reentered == 0) return;
  send_to_owners();
  if (record)
    silokit::reinject::write_record_line(record.get(), update->ntimestep, simulated_time(),
                                         state.counts);
}

/* ----------------------------------------------------------------------
   LIGGGHTS' exchange, which follows, passes an atom to a neighbouring
   rank only, and a rank in between drops it: a grain moved from the
   outlet to the top of a silo cut into three or more slabs would be
   lost (LIGGGHTS ignores lost atoms by default). When any atom is more
   than one rank away from the rank of its sub-domain, Irregular sends
   each atom outside its rank's sub-domain straight to that rank, with
   its per-atom fix data (fix property/atom, contact history: the
   contacthistory fixes, which LIGGGHTS calls first in pre_exchange, have
   already copied it out of the neighbor list). Otherwise nothing
   changes: the exchange moves them as before. All ranks take part.
------------------------------------------------------------------------- */

void FixReinject::send_to_owners()
{
  if (comm->nprocs == 1) return;
  // Irregular works in fractional coordinates in a triclinic box, as the
  // exchange does
  if (domain->triclinic) domain->x2lamda(atom->nlocal);
  Irregular irregular(lmp);
  if (irregular.migrate_check()) irregular.migrate_atoms();
  if (domain->triclinic) domain->lamda2x(atom->nlocal);
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
   counts, random state and clock, then what is pending so that the
   restarted run goes on as an uninterrupted one: the step of a re-entry
   requested for the next step (grains found below the exit at the last
   check, or tags from fix clog), those tags, and the flow-rate samples
------------------------------------------------------------------------- */

void FixReinject::write_restart(FILE *fp)
{
  const silokit::reinject::RestartHead head = {
    random->state(), simulated_time(), static_cast<double>(next_reneighbor) };
  const std::vector<double> list = silokit::reinject::restart_list(restart_layout, state, head);
  if (comm->me == 0) silokit::write_restart_data(fp, list);
}

void FixReinject::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  if (list[0] != restart_layout && list[0] != restart_layout_without_pending)
    error->fix_error(FLERR, this, "the restart file holds its data in the layout of an older silokit, "
                     "whose times cannot be continued: define the fix with another ID to start anew");
  silokit::reinject::RestartHead head = { 0, 0.0, static_cast<double>(next_reneighbor) };
  silokit::reinject::read_restart_list(list, list[0] == restart_layout, state, head);
  random->reset(head.random_state);
  clock.restored(head.time);
  next_reneighbor = static_cast<bigint>(head.pending_step);
  restored = true;
}
