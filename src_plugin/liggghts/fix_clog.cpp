/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix clog: see fix_clog.h and doc/fix_clog.md.

   How: every N steps (end_of_step, after the velocities of the step are
   final) the fix reads the exit count of fix reinject and sums Ec and Ep
   over its group. When no grain has left for quiet_time and Ec/Ep is below
   the ratio, every rank gathers all grains (id, position, radius, kind)
   and, from a compute pair/gran/local, all contacts with their forces;
   both lists are sorted by id, so every rank runs the same arch walk on
   the same data and the result does not depend on the number of ranks.
   Rank 0 writes the records. The contact forces are those of the step's
   positions and stored tangential springs: the compute asks pair gran for
   its forces without applying them or advancing the springs. All but
   the LIGGGHTS calls is core/clog_logic.h, shared with the LAMMPS fix.
------------------------------------------------------------------------- */

#include "fix_clog.h"

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "comm.h"
#include "compute_pair_gran_local.h"
#include "domain.h"
#include "error.h"
#include "fix_gravity.h"
#include "fix_reinject.h"
#include "force.h"
#include "group.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// first value of the restart data; the layout of silokit before the
// restart clock began with the clog count (>= 0) and held LIGGGHTS' times
const double restart_layout = -2.0;

}  // namespace

/* ---------------------------------------------------------------------- */

FixClog::FixClog(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  reinject(nullptr), own_contacts_compute(false), contacts(nullptr), restored(false)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->fix_error(FLERR, this, "needs per-atom radius, mass and omega (atom_style sphere or granular)");
  if (!atom->tag_enable)
    error->fix_error(FLERR, this, "needs atom IDs");
  // the arch walk (arch_walk.h) takes grains for discs or spheres
  if (dynamic_cast<AtomVecSpherocylinder *>(atom->avec))
    error->fix_error(FLERR, this, "finds arches of spheres: rods (atom_style spherocylinder) are not supported");

  const std::vector<std::string> words(arg + 3, arg + narg);
  const std::string problem = silokit::clog::parse_settings(words, true, settings);
  if (!problem.empty()) error->fix_error(FLERR, this, problem.c_str());
  nevery = settings.every;

  const int base_group = group->find(settings.base_group_id.c_str());
  if (base_group == -1) {
    const std::string message = "base group '" + settings.base_group_id + "' does not exist";
    error->fix_error(FLERR, this, message.c_str());
  }
  const silokit::clog::Scene defined = { { settings.orifice_centre, settings.bottom, 2, 1 },
                                          groupbit, group->bitmask[base_group], 0.0,
                                          domain->dimension == 2 };
  scene = defined;

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
}

/* ---------------------------------------------------------------------- */

FixClog::~FixClog() = default;   // closes the records

/* ----------------------------------------------------------------------
   the contact forces come from a compute pair/gran/local; pair gran takes
   only one, so a deck that already has one names it with 'contacts'
------------------------------------------------------------------------- */

void FixClog::post_create()
{
  if (!settings.contacts_id.empty()) return;
  if (update->ntimestep > 0 && !modify->fix_restart_in_progress())
    error->fix_error(FLERR, this, "must be defined before the first run (it creates a compute "
                     "pair/gran/local, which LIGGGHTS allows only then), or name a compute "
                     "pair/gran/local defined before the first run with 'contacts'");
  if (!force->pair || !force->pair_match("gran", 0))
    error->fix_error(FLERR, this, "needs pair_style gran, defined before this fix");
  settings.contacts_id = std::string(id) + "_contacts";
  const char *compute_args[] = { settings.contacts_id.c_str(), "all", "pair/gran/local", "id", "pos",
                                 "force_normal", "force_tangential", "delta" };
  modify->add_compute(8, const_cast<char **>(compute_args));
  own_contacts_compute = true;
}

void FixClog::pre_delete(bool unfixflag)
{
  if (unfixflag && own_contacts_compute && modify->find_compute(settings.contacts_id.c_str()) >= 0)
    modify->delete_compute(settings.contacts_id.c_str());
}

/* ---------------------------------------------------------------------- */

int FixClog::setmask()
{
  return END_OF_STEP;
}

/* ---------------------------------------------------------------------- */

void FixClog::init()
{
  const int ireinject = modify->find_fix(settings.reinject_id.c_str());
  if (ireinject < 0 || strcmp(modify->fix[ireinject]->style, "reinject") != 0) {
    const std::string message = "'reinject' names no fix reinject: '" + settings.reinject_id + "'";
    error->fix_error(FLERR, this, message.c_str());
  }
  reinject = static_cast<FixReinject *>(modify->fix[ireinject]);
  scene.frame.vertical = reinject->vertical_axis();
  if (scene.frame.vertical == 0)
    error->fix_error(FLERR, this, "the outlet plane of fix reinject must be normal to y or z: "
                     "fix clog takes x as the horizontal axis of the silo");
  scene.frame.off_plane = 3 - scene.frame.vertical;

  if (group->find(settings.base_group_id.c_str()) == -1) {
    const std::string message = "base group '" + settings.base_group_id + "' no longer exists";
    error->fix_error(FLERR, this, message.c_str());
  }

  const int icompute = modify->find_compute(settings.contacts_id.c_str());
  if (icompute < 0 || strcmp(modify->compute[icompute]->style, "pair/gran/local") != 0) {
    const std::string message = "'contacts' names no compute pair/gran/local: '" + settings.contacts_id + "'";
    error->fix_error(FLERR, this, message.c_str());
  }
  contacts = static_cast<ComputePairGranLocal *>(modify->compute[icompute]);
  if (contacts->offset_id1() < 0 || contacts->offset_x1() < 0 || contacts->offset_fn() < 0 ||
      contacts->offset_ft() < 0 || contacts->offset_delta() < 0)
    error->fix_error(FLERR, this, "the compute pair/gran/local named by 'contacts' must store "
                     "id pos force_normal force_tangential delta");
  if (contacts->groupbit != 1)
    error->fix_error(FLERR, this, "the compute pair/gran/local named by 'contacts' must be of group all");

  FixGravity *fix_gravity = static_cast<FixGravity *>(modify->find_fix_style("gravity", 0));
  if (!fix_gravity) error->fix_error(FLERR, this, "needs fix gravity (for the potential energy)");
  double acceleration[3];
  fix_gravity->get_gravity(acceleration);
  scene.gravity = -acceleration[scene.frame.vertical];
  if (!(scene.gravity > 0.0))
    error->fix_error(FLERR, this, "gravity must point down the vertical axis of fix reinject");

  open_records();
}

/* ----------------------------------------------------------------------
   after a restart the records are appended to, so that one series of
   files holds the clogs of all the pieces of a run
------------------------------------------------------------------------- */

void FixClog::open_records()
{
  int opened = 1;
  if (comm->me == 0 && !records.clogs) {
    std::vector<std::string> notices;
    opened = silokit::clog::open_records(records, settings.directory, restored,
                                         attempts.clogs(), notices);
    for (const std::string &notice : notices) error->message(FLERR, notice.c_str());
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened)
    error->fix_error(FLERR, this, silokit::clog::records_error(settings.directory).c_str());
}

/* ---------------------------------------------------------------------- */

void FixClog::setup(int)
{
  clock.run_set_up();
  attempts.start(simulated_time(), reinject->compute_vector(0));
}

/* ----------------------------------------------------------------------
   the time of the whole run, across restarts (silokit_clock.h): that of
   the attempts, the records and output 5
------------------------------------------------------------------------- */

double FixClog::simulated_time() const
{
  return clock.time(update->get_cur_time());
}

silokit::clog::Atoms<int> FixClog::local_atoms() const
{
  const silokit::clog::Atoms<int> local = { atom->nlocal, atom->tag, atom->mask, atom->x, atom->v,
                                            atom->omega, atom->radius, atom->rmass };
  return local;
}

/* ---------------------------------------------------------------------- */

void FixClog::end_of_step()
{
  if (attempts.finished()) return;
  auto close_avalanche = [this]() { return reinject->close_avalanche(); };
  auto contacts_here = [this]() { return local_contacts(); };
  const silokit::clog::CheckResult result = silokit::clog::check_for_clog(
      settings, scene, local_atoms(), simulated_time(), update->ntimestep,
      reinject->compute_vector(0), id, close_avalanche, contacts_here, attempts, records,
      comm->me == 0, world);
  if (!result.recorded) return;
  if (comm->me == 0) {
    if (screen) { fputs(result.line.c_str(), screen); fflush(screen); }
    if (logfile) { fputs(result.line.c_str(), logfile); fflush(logfile); }
  }
  if (!result.done) reinject->request_reinjection(result.to_remove);
}

/* ----------------------------------------------------------------------
   this rank's rows of the compute pair/gran/local: the contact forces of
   the step's positions and stored tangential springs (the compute asks
   pair gran for its forces without applying them or advancing the springs)
------------------------------------------------------------------------- */

std::vector<silokit::ContactSample> FixClog::local_contacts()
{
  contacts->compute_local();
  double **rows = contacts->get_data();
  const int nrows = contacts->get_ncount();
  const int o_id = contacts->offset_id1(), o_x1 = contacts->offset_x1(), o_x2 = contacts->offset_x2();
  const int o_fn = contacts->offset_fn(), o_ft = contacts->offset_ft(), o_delta = contacts->offset_delta();

  std::vector<silokit::ContactSample> samples(nrows);
  for (int n = 0; n < nrows; ++n) {
    const double *row = rows[n];
    silokit::ContactSample &sample = samples[n];
    sample.id1 = static_cast<int>(row[o_id]);
    sample.id2 = static_cast<int>(row[o_id+1]);
    sample.overlap = row[o_delta];
    for (int k = 0; k < 3; ++k) {
      sample.x1[k] = row[o_x1+k];
      sample.x2[k] = row[o_x2+k];
      sample.normal_force[k] = row[o_fn+k];
      sample.tangential_force[k] = row[o_ft+k];
    }
  }
  return samples;
}

/* ----------------------------------------------------------------------
   1 clogs recorded (all statuses), 2 arches found, 3 done (1: the deck may
   stop), 4 Ec/Ep at the last check, 5 time since the flow last moved
------------------------------------------------------------------------- */

double FixClog::compute_vector(int index)
{
  return attempts.output(index, simulated_time());
}

/* ---------------------------------------------------------------------- */

void FixClog::write_restart(FILE *fp)
{
  std::vector<double> list = attempts.restart_list(restart_layout);
  list.push_back(simulated_time());
  if (comm->me == 0) silokit::write_restart_data(fp, list);
}

void FixClog::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  if (list[0] != restart_layout)
    error->fix_error(FLERR, this, "the restart file holds its data in the layout of an older silokit, "
                     "whose times cannot be continued: define the fix with another ID to start "
                     "anew (in another 'directory' to keep the records)");
  clock.restored(*attempts.read_restart_list(list));
  restored = true;
}
