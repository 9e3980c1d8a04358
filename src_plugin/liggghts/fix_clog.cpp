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
   its forces without applying them or advancing the springs.
------------------------------------------------------------------------- */

#include "fix_clog.h"

#include "arch_walk.h"
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
#include "silokit_args.h"
#include "silokit_mpi.h"
#include "silokit_record.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <sstream>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

// first value of the restart data; the layout of silokit before the
// restart clock began with the clog count (>= 0) and held LIGGGHTS' times
const double restart_layout = -2.0;

const int grain_fields = 6;     // tag, horizontal, off-plane, height, radius, kind
const int contact_fields = 6;   // id1, id2, horizontal, height, |F_n|, |F_t|

double magnitude(const double *v) { return std::sqrt(v[0]*v[0] + v[1]*v[1] + v[2]*v[2]); }

}  // namespace

/* ---------------------------------------------------------------------- */

FixClog::FixClog(LAMMPS *lmp, int narg, char **arg) :
  Fix(lmp, narg, arg),
  reinject(nullptr), base_groupbit(0),
  orifice_centre(0.0), bottom(0.0), quiet_time(0.1), energy_ratio(1e-4), max_time(0.0),
  break_arches(false), arches_wanted(1), directory("."),
  own_contacts_compute(false), contacts(nullptr), vertical(2), off_plane(1), gravity(0.0),
  attempts(0), arches_found(0), done(false), attempt_start(-1.0), last_exit_time(0.0),
  last_grains_out(0.0), last_ratio(0.0), restored(false)
{
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->fix_error(FLERR, this, "needs per-atom radius, mass and omega (atom_style sphere or granular)");
  if (!atom->tag_enable)
    error->fix_error(FLERR, this, "needs atom IDs");
  // the arch walk (arch_walk.h) takes grains for discs or spheres
  if (dynamic_cast<AtomVecSpherocylinder *>(atom->avec))
    error->fix_error(FLERR, this, "finds arches of spheres: rods (atom_style spherocylinder) are not supported");

  nevery = 1000;
  parse_arguments(narg, arg);

  vector_flag = 1;
  size_vector = 5;
  global_freq = 1;
  extvector = 0;
  restart_global = 1;
}

/* ---------------------------------------------------------------------- */

void FixClog::parse_arguments(int narg, char **arg)
{
  bool have_orifice = false, have_bottom = false, have_arches = false;
  int iarg = 3;
  while (iarg < narg) {
    const std::string keyword(arg[iarg]);
    if (iarg + 1 >= narg) {
      const std::string message = "keyword '" + keyword + "' needs a value";
      error->fix_error(FLERR, this, message.c_str());
    }
    const char *value = arg[iarg+1];
    if (keyword == "reinject") {
      reinject_id = value;
    } else if (keyword == "base") {
      base_group_id = value;
    } else if (keyword == "orifice") {
      orifice_centre = silokit::keyword_number(this, error, value, "orifice");
      have_orifice = true;
    } else if (keyword == "bottom") {
      bottom = silokit::keyword_number(this, error, value, "bottom");
      have_bottom = true;
    } else if (keyword == "every") {
      nevery = silokit::keyword_integer(this, error, value, "every");
      if (nevery < 1) error->fix_error(FLERR, this, "'every' must be an integer >= 1");
    } else if (keyword == "quiet_time") {
      quiet_time = silokit::keyword_number(this, error, value, "quiet_time");
      if (!(quiet_time > 0.0)) error->fix_error(FLERR, this, "'quiet_time' must be > 0");
    } else if (keyword == "ratio") {
      energy_ratio = silokit::keyword_number(this, error, value, "ratio");
      if (!(energy_ratio > 0.0)) error->fix_error(FLERR, this, "'ratio' must be > 0");
    } else if (keyword == "max_time") {
      max_time = silokit::keyword_number(this, error, value, "max_time");
      if (max_time < 0.0) error->fix_error(FLERR, this, "'max_time' must be >= 0 (0: no limit)");
    } else if (keyword == "action") {
      if (strcmp(value, "stop") == 0) break_arches = false;
      else if (strcmp(value, "break") == 0) break_arches = true;
      else error->fix_error(FLERR, this, "'action' must be 'stop' or 'break'");
    } else if (keyword == "arches") {
      arches_wanted = silokit::keyword_integer(this, error, value, "arches");
      if (arches_wanted < 1) error->fix_error(FLERR, this, "'arches' must be an integer >= 1");
      have_arches = true;
    } else if (keyword == "directory") {
      directory = value;
    } else if (keyword == "contacts") {
      contacts_id = value;
    } else {
      const std::string message = "unknown keyword '" + keyword + "' (known: reinject, base, "
        "orifice, bottom, every, quiet_time, ratio, max_time, action, arches, directory, contacts)";
      error->fix_error(FLERR, this, message.c_str());
    }
    iarg += 2;
  }
  if (reinject_id.empty()) error->fix_error(FLERR, this, "'reinject <fix-ID>' is required");
  if (base_group_id.empty()) error->fix_error(FLERR, this, "'base <group-ID>' is required");
  if (!have_orifice) error->fix_error(FLERR, this, "'orifice <x of the outlet centre>' is required");
  if (!have_bottom) error->fix_error(FLERR, this, "'bottom <height of the silo bottom>' is required");
  if (have_arches && !break_arches)
    error->fix_error(FLERR, this, "'arches' needs 'action break' (action stop ends at the first clog)");

  const int base_group = group->find(base_group_id.c_str());
  if (base_group == -1) {
    const std::string message = "base group '" + base_group_id + "' does not exist";
    error->fix_error(FLERR, this, message.c_str());
  }
  base_groupbit = group->bitmask[base_group];
}

/* ---------------------------------------------------------------------- */

FixClog::~FixClog() = default;   // closes the records

/* ----------------------------------------------------------------------
   the contact forces come from a compute pair/gran/local; pair gran takes
   only one, so a deck that already has one names it with 'contacts'
------------------------------------------------------------------------- */

void FixClog::post_create()
{
  if (!contacts_id.empty()) return;
  if (update->ntimestep > 0 && !modify->fix_restart_in_progress())
    error->fix_error(FLERR, this, "must be defined before the first run (it creates a compute "
                     "pair/gran/local, which LIGGGHTS allows only then), or name a compute "
                     "pair/gran/local defined before the first run with 'contacts'");
  if (!force->pair || !force->pair_match("gran", 0))
    error->fix_error(FLERR, this, "needs pair_style gran, defined before this fix");
  contacts_id = std::string(id) + "_contacts";
  const char *compute_args[] = { contacts_id.c_str(), "all", "pair/gran/local", "id", "pos",
                                 "force_normal", "force_tangential", "delta" };
  modify->add_compute(8, const_cast<char **>(compute_args));
  own_contacts_compute = true;
}

void FixClog::pre_delete(bool unfixflag)
{
  if (unfixflag && own_contacts_compute && modify->find_compute(contacts_id.c_str()) >= 0)
    modify->delete_compute(contacts_id.c_str());
}

/* ---------------------------------------------------------------------- */

int FixClog::setmask()
{
  return END_OF_STEP;
}

/* ---------------------------------------------------------------------- */

void FixClog::init()
{
  const int ireinject = modify->find_fix(reinject_id.c_str());
  if (ireinject < 0 || strcmp(modify->fix[ireinject]->style, "reinject") != 0) {
    const std::string message = "'reinject' names no fix reinject: '" + reinject_id + "'";
    error->fix_error(FLERR, this, message.c_str());
  }
  reinject = static_cast<FixReinject *>(modify->fix[ireinject]);
  vertical = reinject->vertical_axis();
  if (vertical == 0)
    error->fix_error(FLERR, this, "the outlet plane of fix reinject must be normal to y or z: "
                     "fix clog takes x as the horizontal axis of the silo");
  off_plane = 3 - vertical;

  if (group->find(base_group_id.c_str()) == -1) {
    const std::string message = "base group '" + base_group_id + "' no longer exists";
    error->fix_error(FLERR, this, message.c_str());
  }

  const int icompute = modify->find_compute(contacts_id.c_str());
  if (icompute < 0 || strcmp(modify->compute[icompute]->style, "pair/gran/local") != 0) {
    const std::string message = "'contacts' names no compute pair/gran/local: '" + contacts_id + "'";
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
  gravity = -acceleration[vertical];
  if (!(gravity > 0.0))
    error->fix_error(FLERR, this, "gravity must point down the vertical axis of fix reinject");

  open_records();
}

/* ---------------------------------------------------------------------- */

silokit::RecordFile FixClog::open_record(const char *name, const char *header)
{
  // after a restart: the clogs past those the restart file knows are
  // removed (the run finds them again); every record begins with the clog
  const silokit::KeptRows kept = { 0, static_cast<double>(attempts) };
  long dropped = 0;
  silokit::RecordFile file = silokit::open_record(directory + "/" + name, restored, header, kept,
                                                  &dropped);
  if (dropped > 0) {
    char message[256];
    snprintf(message, sizeof(message), "fix clog: removed %ld line(s) of clogs after clog %d from '%s', "
             "written after the restart file by the run that wrote it; this run records them again",
             dropped, attempts, name);
    error->message(FLERR, message);
  }
  return file;
}

// After a restart the records are appended to, so that one series of
// files holds the clogs of all the pieces of a run.
void FixClog::open_records()
{
  int opened = 1;
  if (comm->me == 0 && !clogs_file) {
    clogs_file = open_record("clogs.txt", "# clog step time avalanche eta status");
    arches_file = open_record("arches.txt", "# clog order id x y z phi fn ft");
    feet_file = open_record("feet.txt", "# clog order id x y z phi fn ft base floor");
    contacts_file = open_record("contacts.txt", "# clog id1 id2 x z fn ft arch");
    opened = clogs_file && arches_file && feet_file && contacts_file;
  }
  MPI_Bcast(&opened, 1, MPI_INT, 0, world);
  if (!opened) {
    const std::string message = "cannot write clogs.txt, arches.txt, feet.txt, contacts.txt in directory '"
                                + directory + "'";
    error->fix_error(FLERR, this, message.c_str());
  }
}

/* ---------------------------------------------------------------------- */

void FixClog::setup(int)
{
  clock.run_set_up();
  if (attempt_start >= 0.0) return;   // already started (an earlier run, or a restart)
  attempt_start = last_exit_time = simulated_time();
  last_grains_out = reinject->compute_vector(0);
}

/* ----------------------------------------------------------------------
   the time of the whole run, across restarts (silokit_clock.h): that of
   the attempts, the records and output 5
------------------------------------------------------------------------- */

double FixClog::simulated_time() const
{
  return clock.time(update->get_cur_time());
}

/* ---------------------------------------------------------------------- */

double FixClog::kinetic_to_potential_ratio() const
{
  const double inertia_factor = domain->dimension == 2 ? 0.5 : 0.4;  // disc or sphere
  double local[2] = { 0.0, 0.0 }, total[2] = { 0.0, 0.0 };
  for (int i = 0; i < atom->nlocal; ++i) {
    if (!(atom->mask[i] & groupbit)) continue;
    const double m = atom->rmass[i], r = atom->radius[i];
    const double *v = atom->v[i], *w = atom->omega[i];
    local[0] += 0.5*m*(v[0]*v[0] + v[1]*v[1] + v[2]*v[2])
              + 0.5*inertia_factor*m*r*r*(w[0]*w[0] + w[1]*w[1] + w[2]*w[2]);
    local[1] += m*gravity*(atom->x[i][vertical] - bottom);
  }
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, world);
  if (!(total[1] > 0.0)) return std::numeric_limits<double>::infinity();
  return total[0]/total[1];
}

/* ---------------------------------------------------------------------- */

void FixClog::end_of_step()
{
  if (done) return;
  const double now = simulated_time();
  const double grains_out = reinject->compute_vector(0);
  if (grains_out != last_grains_out) {
    last_grains_out = grains_out;
    last_exit_time = now;
  }
  last_ratio = kinetic_to_potential_ratio();

  const double quiet_since = std::max(attempt_start, last_exit_time);
  const bool stopped = now - quiet_since >= quiet_time && last_ratio < energy_ratio;
  const bool timed_out = max_time > 0.0 && now - attempt_start >= max_time;
  if (!stopped && !timed_out) return;

  ++attempts;
  const int avalanche = reinject->close_avalanche();
  Outcome outcome;
  std::vector<GrainRecord> grains;
  std::vector<ContactRecord> contact_list;
  if (stopped) {
    grains = gather_grains();
    contact_list = gather_contacts(grains);
    outcome = identify_arch(grains, contact_list);
  } else {
    outcome.status = 0;
    outcome.reason = "the flow did not stop within max_time";
  }
  if (outcome.status == 1) ++arches_found;
  write_records(outcome, avalanche, grains, contact_list);
  report(outcome, avalanche);

  if (!break_arches || arches_found >= arches_wanted) {
    done = true;
    return;
  }
  if (outcome.status == 1) reinject->request_reinjection(outcome.member_tags);
  else if (outcome.status == -1) reinject->request_reinjection(grains_over_orifice(grains));
  end_attempt(now);
}

void FixClog::end_attempt(double now)
{
  attempt_start = last_exit_time = now;
}

/* ----------------------------------------------------------------------
   every grain, sorted by id, with its position relative to the outlet
------------------------------------------------------------------------- */

std::vector<FixClog::GrainRecord> FixClog::gather_grains() const
{
  std::vector<double> local;
  for (int i = 0; i < atom->nlocal; ++i) {
    const double *x = atom->x[i];
    Kind kind = other_fixed;
    if (atom->mask[i] & base_groupbit) kind = x[0] < orifice_centre ? left_base : right_base;
    else if (atom->mask[i] & groupbit) kind = free_grain;
    const double fields[grain_fields] = { static_cast<double>(atom->tag[i]), x[0] - orifice_centre,
                                          x[off_plane], x[vertical] - bottom, atom->radius[i],
                                          static_cast<double>(kind) };
    local.insert(local.end(), fields, fields + grain_fields);
  }
  const std::vector<double> all = silokit::allgather(local, world);
  std::vector<GrainRecord> grains;
  for (size_t k = 0; k + grain_fields <= all.size(); k += grain_fields) {
    const GrainRecord grain = { static_cast<int>(all[k]), all[k+1], all[k+2], all[k+3], all[k+4],
                                static_cast<Kind>(static_cast<int>(all[k+5])) };
    grains.push_back(grain);
  }
  std::sort(grains.begin(), grains.end(),
            [](const GrainRecord &a, const GrainRecord &b) { return a.tag < b.tag; });
  return grains;
}

/* ----------------------------------------------------------------------
   every contact with at least one free grain, each pair once, sorted by
   (id1, id2); the contact point is on the line of centres at r1 - delta/2
   from grain 1
------------------------------------------------------------------------- */

std::vector<FixClog::ContactRecord> FixClog::gather_contacts(const std::vector<GrainRecord> &grains)
{
  std::map<int, const GrainRecord *> by_tag;
  for (size_t k = 0; k < grains.size(); ++k) by_tag[grains[k].tag] = &grains[k];

  contacts->compute_local();
  double **rows = contacts->get_data();
  const int nrows = contacts->get_ncount();
  const int o_id = contacts->offset_id1(), o_x1 = contacts->offset_x1(), o_x2 = contacts->offset_x2();
  const int o_fn = contacts->offset_fn(), o_ft = contacts->offset_ft(), o_delta = contacts->offset_delta();

  std::vector<double> local;
  for (int n = 0; n < nrows; ++n) {
    const double *row = rows[n];
    int id1 = static_cast<int>(row[o_id]), id2 = static_cast<int>(row[o_id+1]);
    const double *x1 = row + o_x1, *x2 = row + o_x2;
    if (id1 > id2) {
      std::swap(id1, id2);
      std::swap(x1, x2);
    }
    const std::map<int, const GrainRecord *>::const_iterator first = by_tag.find(id1),
                                                            second = by_tag.find(id2);
    if (first == by_tag.end() || second == by_tag.end()) continue;
    if (first->second->kind != free_grain && second->second->kind != free_grain) continue;

    double along[3] = { x2[0] - x1[0], x2[1] - x1[1], x2[2] - x1[2] };
    const double distance = magnitude(along);
    const double reach = first->second->radius - 0.5*row[o_delta];
    double point[3];
    for (int k = 0; k < 3; ++k) point[k] = x1[k] + along[k]/distance*reach;
    const double fields[contact_fields] = { static_cast<double>(id1), static_cast<double>(id2),
                                            point[0] - orifice_centre, point[vertical] - bottom,
                                            magnitude(row + o_fn), magnitude(row + o_ft) };
    local.insert(local.end(), fields, fields + contact_fields);
  }
  const std::vector<double> all = silokit::allgather(local, world);
  std::vector<ContactRecord> contact_list;
  for (size_t k = 0; k + contact_fields <= all.size(); k += contact_fields) {
    const ContactRecord contact = { static_cast<int>(all[k]), static_cast<int>(all[k+1]),
                                    all[k+2], all[k+3], all[k+4], all[k+5] };
    contact_list.push_back(contact);
  }
  std::sort(contact_list.begin(), contact_list.end(),
            [](const ContactRecord &a, const ContactRecord &b) {
              return a.id1 != b.id1 ? a.id1 < b.id1 : a.id2 < b.id2; });
  // a pair is stored by one rank only; the guard is for stock changes to that rule
  contact_list.erase(std::unique(contact_list.begin(), contact_list.end(),
                                 [](const ContactRecord &a, const ContactRecord &b) {
                                   return a.id1 == b.id1 && a.id2 == b.id2; }),
                     contact_list.end());
  return contact_list;
}

/* ----------------------------------------------------------------------
   the walk of arch_walk.h over the free and base grains; the other fixed
   grains (side walls) take no part
------------------------------------------------------------------------- */

FixClog::Outcome FixClog::identify_arch(const std::vector<GrainRecord> &grains,
                                        const std::vector<ContactRecord> &contact_list) const
{
  using namespace silokit::arch;
  std::vector<Grain> walk_grains;
  std::map<int, std::size_t> index_of;
  for (size_t k = 0; k < grains.size(); ++k) {
    if (grains[k].kind == other_fixed) continue;
    const Base base = grains[k].kind == left_base ? Base::left
                    : grains[k].kind == right_base ? Base::right : Base::none;
    const Grain grain = { grains[k].horizontal, grains[k].height, grains[k].tag, base };
    index_of[grains[k].tag] = walk_grains.size();
    walk_grains.push_back(grain);
  }
  std::vector<Contact> walk_contacts;
  for (size_t k = 0; k < contact_list.size(); ++k) {
    const std::map<int, std::size_t>::const_iterator a = index_of.find(contact_list[k].id1),
                                                     b = index_of.find(contact_list[k].id2);
    if (a != index_of.end() && b != index_of.end())
      walk_contacts.push_back(Contact(a->second, b->second));
  }

  const Arch arch = find_arch(walk_grains, walk_contacts, 0.0);
  Outcome outcome;
  outcome.status = arch.status == Status::found ? 1 : -1;
  if (arch.status != Status::found)
    outcome.reason = std::string(status_name(arch.status)) + ": " + arch.reason;
  for (size_t k = 0; k < arch.members.size(); ++k) {
    outcome.member_tags.push_back(static_cast<int>(walk_grains[arch.members[k].index].id));
    outcome.member_phi.push_back(arch.members[k].phi_degrees);
  }
  if (arch.status == Status::found) {
    for (const Foot &foot : {arch.left_foot, arch.right_foot}) {
      outcome.foot_tags.push_back(static_cast<int>(walk_grains[foot.index].id));
      outcome.foot_base_tags.push_back(static_cast<int>(walk_grains[foot.base_index].id));
      outcome.foot_phi.push_back(foot.phi_degrees);
      outcome.foot_on_floor.push_back(foot.on_floor ? 1 : 0);
    }
  }
  return outcome;
}

/* ----------------------------------------------------------------------
   when the flow stopped but no arch was identified, the free grains near
   the outlet: centres within half the opening between the innermost base
   grains plus two diameters of the middle of the opening
------------------------------------------------------------------------- */

std::vector<int> FixClog::grains_over_orifice(const std::vector<GrainRecord> &grains) const
{
  const GrainRecord *left = nullptr, *right = nullptr;
  double largest_radius = 0.0;
  for (size_t k = 0; k < grains.size(); ++k) {
    const GrainRecord &grain = grains[k];
    largest_radius = std::max(largest_radius, grain.radius);
    if (grain.kind == left_base && (!left || grain.horizontal > left->horizontal)) left = &grain;
    if (grain.kind == right_base && (!right || grain.horizontal < right->horizontal)) right = &grain;
  }
  std::vector<int> tags;
  if (!left || !right) return tags;
  const double centre[2] = { 0.5*(left->horizontal + right->horizontal),
                             0.5*(left->height + right->height) };
  const double reach = 0.5*(right->horizontal - left->horizontal) + 4.0*largest_radius;
  for (size_t k = 0; k < grains.size(); ++k) {
    if (grains[k].kind != free_grain) continue;
    const double dx = grains[k].horizontal - centre[0], dz = grains[k].height - centre[1];
    if (dx*dx + dz*dz < reach*reach) tags.push_back(grains[k].tag);
  }
  return tags;
}

/* ----------------------------------------------------------------------
   rank 0 appends the clog to the records and flushes them
------------------------------------------------------------------------- */

void FixClog::write_records(const Outcome &outcome, int avalanche,
                            const std::vector<GrainRecord> &grains,
                            const std::vector<ContactRecord> &contact_list)
{
  if (comm->me != 0) return;
  const int clog = attempts;
  fprintf(clogs_file.get(), "%d " BIGINT_FORMAT " %.12g %d %d %d\n", clog, update->ntimestep,
          simulated_time(), avalanche, static_cast<int>(outcome.member_tags.size()),
          outcome.status);
  fflush(clogs_file.get());
  if (outcome.status == 0) return;

  // per grain: the mean over its contacts of |F_n| and |F_t|
  std::map<int, double> sum_normal, sum_tangential;
  std::map<int, int> count;
  for (size_t k = 0; k < contact_list.size(); ++k) {
    const ContactRecord &c = contact_list[k];
    const int ids[2] = { c.id1, c.id2 };
    for (int side = 0; side < 2; ++side) {
      sum_normal[ids[side]] += c.normal_force;
      sum_tangential[ids[side]] += c.tangential_force;
      count[ids[side]] += 1;
    }
  }
  std::map<int, const GrainRecord *> by_tag;
  for (size_t k = 0; k < grains.size(); ++k) by_tag[grains[k].tag] = &grains[k];
  // a grain's row of arches.txt or feet.txt, without the line's end
  auto write_grain = [&](FILE *file, int order, int tag, double phi) {
    const GrainRecord &grain = *by_tag[tag];
    const int n = std::max(count[tag], 1);
    fprintf(file, "%d %d %d %.12g %.12g %.12g %.12g %.10g %.10g", clog, order, tag,
            grain.horizontal, grain.off_plane, grain.height, phi, sum_normal[tag]/n,
            sum_tangential[tag]/n);
  };
  const int eta = static_cast<int>(outcome.member_tags.size());
  for (int k = 0; k < eta; ++k) {
    write_grain(arches_file.get(), k + 1, outcome.member_tags[k], outcome.member_phi[k]);
    fputc('\n', arches_file.get());
  }
  fflush(arches_file.get());
  // the left foot before the first member (order 0), the right one after the last
  for (size_t side = 0; side < outcome.foot_tags.size(); ++side) {
    write_grain(feet_file.get(), side == 0 ? 0 : eta + 1, outcome.foot_tags[side], outcome.foot_phi[side]);
    fprintf(feet_file.get(), " %d %d\n", outcome.foot_base_tags[side], outcome.foot_on_floor[side]);
  }
  fflush(feet_file.get());

  const std::set<int> members(outcome.member_tags.begin(), outcome.member_tags.end());
  for (size_t k = 0; k < contact_list.size(); ++k) {
    const ContactRecord &c = contact_list[k];
    const int in_arch = members.count(c.id1) && members.count(c.id2);
    fprintf(contacts_file.get(), "%d %d %d %.12g %.12g %.10g %.10g %d\n", clog, c.id1, c.id2,
            c.horizontal, c.height, c.normal_force, c.tangential_force, in_arch);
  }
  fflush(contacts_file.get());
}

/* ---------------------------------------------------------------------- */

void FixClog::report(const Outcome &outcome, int avalanche)
{
  if (comm->me != 0) return;
  std::ostringstream line;
  line << "fix clog " << id << ": clog " << attempts << " at t = " << simulated_time()
       << " s (step " << update->ntimestep << "), avalanche " << avalanche << " grains, ";
  if (outcome.status == 1) line << "arch of " << outcome.member_tags.size() << " grains";
  else line << "no arch (" << outcome.reason << ")";
  if (break_arches) line << "; " << arches_found << " of " << arches_wanted << " arches";
  line << "\n";
  if (screen) { fputs(line.str().c_str(), screen); fflush(screen); }
  if (logfile) { fputs(line.str().c_str(), logfile); fflush(logfile); }
}

/* ----------------------------------------------------------------------
   1 clogs recorded (all statuses), 2 arches found, 3 done (1: the deck may
   stop), 4 Ec/Ep at the last check, 5 time since the flow last moved
------------------------------------------------------------------------- */

double FixClog::compute_vector(int index)
{
  switch (index) {
    case 0: return attempts;
    case 1: return arches_found;
    case 2: return done ? 1.0 : 0.0;
    case 3: return last_ratio;
    case 4: return attempt_start < 0.0 ? 0.0
                   : simulated_time() - std::max(attempt_start, last_exit_time);
  }
  return 0.0;
}

/* ---------------------------------------------------------------------- */

void FixClog::write_restart(FILE *fp)
{
  const int count = 8;
  const double list[count] = { restart_layout, static_cast<double>(attempts),
                               static_cast<double>(arches_found), done ? 1.0 : 0.0, attempt_start,
                               last_exit_time, last_grains_out, simulated_time() };
  if (comm->me == 0) {
    const int size = count*sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), count, fp);
  }
}

void FixClog::restart(char *buf)
{
  const double *list = reinterpret_cast<double *>(buf);
  if (list[0] != restart_layout)
    error->fix_error(FLERR, this, "the restart file holds its data in the layout of an older silokit, "
                     "whose times cannot be continued: define the fix with another ID to start "
                     "anew (in another 'directory' to keep the records)");
  attempts = static_cast<int>(list[1]);
  arches_found = static_cast<int>(list[2]);
  done = list[3] != 0.0;
  attempt_start = list[4];
  last_exit_time = list[5];
  last_grains_out = list[6];
  clock.restored(list[7]);
  restored = true;
}
