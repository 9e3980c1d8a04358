/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix clog for LAMMPS: see fix_clog_lammps.h and doc/fix_clog_lammps.md.

   How (as the LIGGGHTS fix): every N steps (end_of_step, after the
   velocities of the step are final) the fix reads the exit count of fix
   reinject and sums Ec and Ep over its group. When no grain has left for
   quiet_time and Ec/Ep is below the ratio, every rank gathers all grains
   and, from pair_style granular/jiang, all touching pairs with the forces
   of the step's positions and stored history (read, not advanced); both
   lists are sorted by id, so every rank runs the same arch walk on the
   same data. Rank 0 writes the records. Then the run stops the way fix
   halt stops one (Timer::force_timeout: Verlet leaves its loop at the next
   step), or the arch re-enters at the top through fix reinject.
------------------------------------------------------------------------- */

#include "fix_clog_lammps.h"

#include "fix_reinject_lammps.h"
#include "lammps_compat.h"
#include "pair_granular_jiang.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "timer.h"
#include "update.h"

#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

const char *const STYLE = "fix clog";

// first value of the restart data: the list of core/clog_logic.h, then
// the clock's three values
const double restart_layout = -1.0;

}    // namespace

/* ---------------------------------------------------------------------- */

FixClog::FixClog(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), reinject(nullptr), pair(nullptr), restored(false), halted(false)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "{} needs atom attributes radius, rmass and omega (atom_style sphere)",
               STYLE);
  if (!atom->tag_enable) error->all(FLERR, "{} needs atom IDs", STYLE);
  // the arch walk (arch_walk.h) takes grains for discs or spheres
  if (atom->ellipsoid_flag || atom->line_flag || atom->tri_flag || atom->body_flag)
    error->all(FLERR, "{} finds arches of spheres: ellipsoids, lines, triangles and bodies "
               "are not supported", STYLE);

  const std::vector<std::string> words(arg + 3, arg + narg);
  const std::string problem = silokit::clog::parse_settings(words, false, settings);
  if (!problem.empty()) error->all(FLERR, "{}: {}", STYLE, problem);
  nevery = settings.every;

  const int base_group = group->find(settings.base_group_id);
  if (base_group == -1)
    error->all(FLERR, "{}: base group '{}' does not exist", STYLE, settings.base_group_id);
  scene = {{settings.orifice_centre, settings.bottom, 2, 1}, groupbit, group->bitmask[base_group],
           0.0, domain->dimension == 2};

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;

  // the clock starts at LAMMPS' time now (0 in a fresh run), as fix reinject's
  clock.start(update->atime + (update->ntimestep - update->atimestep) * update->dt,
              update->ntimestep, update->dt);
}

FixClog::~FixClog() = default;    // closes the records

/* ---------------------------------------------------------------------- */

int FixClog::setmask()
{
  return END_OF_STEP | POST_RUN;
}

/* ---------------------------------------------------------------------- */

void FixClog::init()
{
  Fix *named = silokit_lammps::fix_by_id(modify, settings.reinject_id);
  if (!named || strcmp(named->style, "reinject") != 0)
    error->all(FLERR, "{}: 'reinject' names no fix reinject: '{}'", STYLE, settings.reinject_id);
  reinject = static_cast<FixReinject *>(named);
  scene.frame.vertical = reinject->vertical_axis();
  if (scene.frame.vertical == 0)
    error->all(FLERR, "{}: the outlet plane of fix reinject must be normal to y or z: fix clog "
               "takes x as the horizontal axis of the silo", STYLE);
  scene.frame.off_plane = 3 - scene.frame.vertical;

  if (group->find(settings.base_group_id) == -1)
    error->all(FLERR, "{}: base group '{}' no longer exists", STYLE, settings.base_group_id);

  pair = dynamic_cast<PairGranularJiang *>(force->pair);
  if (!pair)
    error->all(FLERR, "{} needs pair_style granular/jiang, which gives it the contacts", STYLE);

  Fix *gravity_fix = silokit_lammps::first_fix_by_style(modify, "^gravity");
  if (!gravity_fix) error->all(FLERR, "{} needs fix gravity (for the potential energy)", STYLE);
  int dim = 0;
  const double *acceleration = static_cast<const double *>(gravity_fix->extract("gvec", dim));
  if (!acceleration) error->all(FLERR, "{}: fix gravity gives no vector", STYLE);
  scene.gravity = -acceleration[scene.frame.vertical];
  if (!(scene.gravity > 0.0))
    error->all(FLERR, "{}: gravity must point down the vertical axis of fix reinject", STYLE);

  // a new time step (the timestep command between runs): the clock goes
  // on from the time reached with the old one
  clock.use_time_step(update->ntimestep, update->dt);
  open_records();
}

/* ----------------------------------------------------------------------
   opened at the first init: LAMMPS calls restart() after the constructor,
   and a restored fix appends to its records, so that the pieces of a
   restarted run write one series of files
------------------------------------------------------------------------- */

void FixClog::open_records()
{
  if (records.clogs) return;
  int opened = 1;
  if (comm->me == 0) {
    std::vector<std::string> notices;
    opened = silokit::clog::open_records(records, settings.directory, restored, attempts.clogs(),
                                         notices);
    for (const std::string &notice : notices) utils::logmesg(lmp, notice + "\n");
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened) error->all(FLERR, "{}: {}", STYLE, silokit::clog::records_error(settings.directory));
}

/* ----------------------------------------------------------------------
   a run set up with the flag already up (after the clog, or from a
   restart file written after it) does no step
------------------------------------------------------------------------- */

void FixClog::setup(int)
{
  if (attempts.finished()) {
    halt_run("the flag was already up when the run began");
    return;
  }
  attempts.start(simulated_time(), reinject->compute_vector(0));
}

double FixClog::simulated_time() const
{
  return clock.time(update->ntimestep);
}

silokit::clog::Atoms<tagint> FixClog::local_atoms() const
{
  const silokit::clog::Atoms<tagint> local = {atom->nlocal, atom->tag,   atom->mask,
                                              atom->x,      atom->v,     atom->omega,
                                              atom->radius, atom->rmass};
  return local;
}

/* ---------------------------------------------------------------------- */

void FixClog::end_of_step()
{
  if (attempts.finished()) return;
  auto close_avalanche = [this]() { return reinject->close_avalanche(); };
  auto contacts_here = [this]() { return pair->current_contacts(); };
  const silokit::clog::CheckResult result = silokit::clog::check_for_clog(
      settings, scene, local_atoms(), simulated_time(), update->ntimestep,
      reinject->compute_vector(0), id, close_avalanche, contacts_here, attempts, records,
      comm->me == 0, world);
  if (!result.recorded) return;
  if (comm->me == 0) utils::logmesg(lmp, result.line);
  if (result.done)
    halt_run(settings.break_arches ? "the arches wanted are found" : "the flow clogged");
  else
    reinject->request_reinjection(result.to_remove);
}

/* ----------------------------------------------------------------------
   the run ends at the next step, as with fix halt (error continue):
   LAMMPS' Verlet loop tests the timer's timeout at every step; post_run
   sets the timeout back, so that the deck's later commands run
------------------------------------------------------------------------- */

void FixClog::halt_run(const char *why)
{
  if (comm->me == 0)
    utils::logmesg(lmp, fmt::format("fix clog {}: the run stops at step {} ({})\n", id,
                                    update->ntimestep, why));
  timer->force_timeout();
  halted = true;
}

void FixClog::post_run()
{
  if (!halted) return;
  timer->reset_timeout();
  halted = false;
}

/* ----------------------------------------------------------------------
   the outputs of the LIGGGHTS fix (Attempts::output)
------------------------------------------------------------------------- */

double FixClog::compute_vector(int index)
{
  return attempts.output(index, simulated_time());
}

/* ---------------------------------------------------------------------- */

void FixClog::write_restart(FILE *fp)
{
  std::vector<double> list = attempts.restart_list(restart_layout);
  double clock_values[3];
  clock.write(clock_values);
  list.insert(list.end(), clock_values, clock_values + 3);
  if (comm->me == 0) silokit::write_restart_data(fp, list);
}

void FixClog::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  if (list[0] != restart_layout)
    error->all(FLERR, "{}: the restart data of fix '{}' is not in the layout of this version; "
               "define the fix with another ID to start anew", STYLE, id);
  clock.read(attempts.read_restart_list(list));
  restored = true;
}
