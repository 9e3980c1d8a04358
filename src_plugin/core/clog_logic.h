/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The host-free part of fix clog (doc/fix_clog.md), shared by the
   LIGGGHTS fix (src_plugin/liggghts/fix_clog.*) and the LAMMPS one
   (src_plugin/lammps/fix_clog_lammps.*): the keywords, the stop criterion
   and its bookkeeping (attempts, the last exit, Ec/Ep), gathering the
   grains and the contacts over the ranks, the arch walk on them
   (core/arch_walk.h), the records of doc/silo2d_records.md with their
   formats, the screen line, and the restart list. The hosts hand in their
   per-atom arrays and their contacts (core/contact_sample.h), and raise
   the errors whose text this file words.
------------------------------------------------------------------------- */

#ifndef SILOKIT_CLOG_LOGIC_H
#define SILOKIT_CLOG_LOGIC_H

#include "arch_walk.h"
#include "contact_sample.h"
#include "fix_common.h"        // number_for, integer_for: the same error texts
#include "silokit_mpi.h"
#include "silokit_record.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace silokit {
namespace clog {

/* ----------------------------------------------------------------------
   the keywords: fix ID group clog reinject <fix-ID> base <group-ID>
   orifice <x> bottom <h> [every N] [quiet_time t] [ratio r] [max_time t]
   [action stop|break] [arches n] [directory path] [contacts compute-ID]
------------------------------------------------------------------------- */

struct Settings {
  std::string reinject_id;
  std::string base_group_id;
  double orifice_centre;       // horizontal (x) coordinate of the middle of the outlet
  double bottom;               // height of the silo bottom surface
  int every;                   // check every N steps
  double quiet_time;           // no exit for this long, and ...
  double energy_ratio;         // ... Ec/Ep below this: the flow has stopped
  double max_time;             // an attempt longer than this is "no clog" (0: no limit)
  bool break_arches;           // action break (else stop)
  int arches_wanted;           // action break: done after this many arches
  std::string directory;
  std::string contacts_id;     // LIGGGHTS: the compute pair/gran/local read at a clog

  Settings() : orifice_centre(0.0), bottom(0.0), every(1000), quiet_time(0.1), energy_ratio(1e-4),
               max_time(0.0), break_arches(false), arches_wanted(1), directory(".") {}
};

// Reads the words after `fix ID group clog` into `settings`. Returns the
// text of the first error (naming the keyword and what it allows), empty
// when all is well. with_contacts: the host takes the `contacts` keyword
// (LIGGGHTS; LAMMPS gets the contacts from its pair style).
inline std::string parse_settings(const std::vector<std::string> &words, bool with_contacts,
                                  Settings &settings)
{
  bool have_orifice = false, have_bottom = false, have_arches = false;
  std::string problem;
  for (std::size_t iarg = 0; iarg < words.size(); iarg += 2) {
    const std::string &keyword = words[iarg];
    if (iarg + 1 >= words.size()) return "keyword '" + keyword + "' needs a value";
    const std::string &value = words[iarg + 1];
    if (keyword == "reinject") {
      settings.reinject_id = value;
    } else if (keyword == "base") {
      settings.base_group_id = value;
    } else if (keyword == "orifice") {
      problem = number_for("orifice", value, settings.orifice_centre);
      have_orifice = true;
    } else if (keyword == "bottom") {
      problem = number_for("bottom", value, settings.bottom);
      have_bottom = true;
    } else if (keyword == "every") {
      problem = integer_for("every", value, settings.every);
      if (problem.empty() && settings.every < 1) return "'every' must be an integer >= 1";
    } else if (keyword == "quiet_time") {
      problem = number_for("quiet_time", value, settings.quiet_time);
      if (problem.empty() && !(settings.quiet_time > 0.0)) return "'quiet_time' must be > 0";
    } else if (keyword == "ratio") {
      problem = number_for("ratio", value, settings.energy_ratio);
      if (problem.empty() && !(settings.energy_ratio > 0.0)) return "'ratio' must be > 0";
    } else if (keyword == "max_time") {
      problem = number_for("max_time", value, settings.max_time);
      if (problem.empty() && settings.max_time < 0.0)
        return "'max_time' must be >= 0 (0: no limit)";
    } else if (keyword == "action") {
      if (value == "stop") settings.break_arches = false;
      else if (value == "break") settings.break_arches = true;
      else return "'action' must be 'stop' or 'break'";
    } else if (keyword == "arches") {
      problem = integer_for("arches", value, settings.arches_wanted);
      if (problem.empty() && settings.arches_wanted < 1) return "'arches' must be an integer >= 1";
      have_arches = true;
    } else if (keyword == "directory") {
      settings.directory = value;
    } else if (keyword == "contacts" && with_contacts) {
      settings.contacts_id = value;
    } else {
      return "unknown keyword '" + keyword + "' (known: reinject, base, orifice, bottom, every, "
             "quiet_time, ratio, max_time, action, arches, directory" +
             (with_contacts ? ", contacts)" : ")");
    }
    if (!problem.empty()) return problem;
  }
  if (settings.reinject_id.empty()) return "'reinject <fix-ID>' is required";
  if (settings.base_group_id.empty()) return "'base <group-ID>' is required";
  if (!have_orifice) return "'orifice <x of the outlet centre>' is required";
  if (!have_bottom) return "'bottom <height of the silo bottom>' is required";
  if (have_arches && !settings.break_arches)
    return "'arches' needs 'action break' (action stop ends at the first clog)";
  return "";
}

/* ----------------------------------------------------------------------
   the stop criterion and the counts, kept across restarts
------------------------------------------------------------------------- */

enum class Verdict { flowing, stopped, timed_out };

class Attempts {
 public:
  Attempts() : attempts(0), arches_found(0), done(false), attempt_start(-1.0),
               last_exit_time(0.0), last_grains_out(0.0), last_ratio(0.0) {}

  // the first run's set-up: the first attempt starts (not again after an
  // earlier run or a restart)
  void start(double now, double grains_out)
  {
    if (attempt_start >= 0.0) return;
    attempt_start = last_exit_time = now;
    last_grains_out = grains_out;
  }

  // a check at `now`: fix reinject's exit count and Ec/Ep
  Verdict check(double now, double grains_out, double ratio, const Settings &settings)
  {
    if (grains_out != last_grains_out) {
      last_grains_out = grains_out;
      last_exit_time = now;
    }
    last_ratio = ratio;
    const double quiet_since = std::max(attempt_start, last_exit_time);
    if (now - quiet_since >= settings.quiet_time && last_ratio < settings.energy_ratio)
      return Verdict::stopped;
    if (settings.max_time > 0.0 && now - attempt_start >= settings.max_time)
      return Verdict::timed_out;
    return Verdict::flowing;
  }

  // an attempt ended with `status` (a row of clogs.txt); true when the
  // deck may stop (the flag), else a new attempt starts at `now`
  bool record(int status, double now, const Settings &settings)
  {
    ++attempts;
    if (status == 1) ++arches_found;
    if (!settings.break_arches || arches_found >= settings.arches_wanted) {
      done = true;
      return true;
    }
    attempt_start = last_exit_time = now;
    return false;
  }

  int clogs() const { return attempts; }
  int arches() const { return arches_found; }
  bool finished() const { return done; }

  // the output vector: 0 clogs recorded (all statuses), 1 arches found,
  // 2 done (1: the deck may stop), 3 Ec/Ep at the last check, 4 time
  // since the flow last moved
  double output(int index, double now) const
  {
    switch (index) {
      case 0: return attempts;
      case 1: return arches_found;
      case 2: return done ? 1.0 : 0.0;
      case 3: return last_ratio;
      case 4: return attempt_start < 0.0 ? 0.0 : now - std::max(attempt_start, last_exit_time);
    }
    return 0.0;
  }

  // restart data: layout, then 6 values; a host appends its time after them
  std::vector<double> restart_list(double layout) const
  {
    return { layout, static_cast<double>(attempts), static_cast<double>(arches_found),
             done ? 1.0 : 0.0, attempt_start, last_exit_time, last_grains_out };
  }
  // reads what restart_list wrote; returns the first value past it
  const double *read_restart_list(const double *list)
  {
    attempts = static_cast<int>(list[1]);
    arches_found = static_cast<int>(list[2]);
    done = list[3] != 0.0;
    attempt_start = list[4];
    last_exit_time = list[5];
    last_grains_out = list[6];
    return list + 7;
  }

 private:
  int attempts;                // rows written to clogs.txt
  int arches_found;            // rows with status 1
  bool done;                   // the deck may stop
  double attempt_start;        // time the current attempt began
  double last_exit_time;       // time the exit count last changed
  double last_grains_out;
  double last_ratio;           // Ec/Ep at the last check
};

/* ----------------------------------------------------------------------
   the grains and contacts gathered at a clog
------------------------------------------------------------------------- */

// what the grains gathered at a clog are
enum Kind { free_grain, left_base, right_base, other_fixed };

struct GrainRecord {
  int tag;
  double horizontal, off_plane, height;   // x from the orifice centre, y, z above the bottom
  double radius;
  Kind kind;
};

struct ContactRecord {
  int id1, id2;                           // id1 < id2
  double horizontal, height;              // contact point, axes as GrainRecord
  double normal_force, tangential_force;  // magnitudes (N)
};

struct Outcome {
  int status;                             // 1 arch found, 0 no clog in time, -1 no arch
  std::string reason;                     // why there is no arch
  std::vector<int> member_tags;           // in walk order
  std::vector<double> member_phi;         // degrees
  std::vector<int> foot_tags;             // left, right (arch_walk.h rule 8); empty without arch
  std::vector<int> foot_base_tags;        // the base grain each foot's angle is taken from
  std::vector<double> foot_phi;           // degrees
  std::vector<int> foot_on_floor;         // 1: touches a base grain other than the outlet grain

  Outcome() : status(0) {}
};

// The silo's axes in the simulation: x horizontal, `vertical` (1 or 2)
// with gravity along -vertical, `off_plane` the third.
struct Frame {
  double orifice_centre;
  double bottom;
  int vertical;
  int off_plane;
};

// The per-atom arrays of a host (Tag: its atom ID type).
template <class Tag>
struct Atoms {
  int nlocal;
  const Tag *tag;
  const int *mask;
  double **x, **v, **omega;
  const double *radius, *mass;
};

inline double magnitude(const double *v) { return std::sqrt(v[0]*v[0] + v[1]*v[1] + v[2]*v[2]); }

// Ec/Ep over the grains of `groupbit`, all ranks: Ec = sum 1/2 m v^2 +
// 1/2 I w^2 (I = 0.4 m r^2 for spheres, 0.5 m r^2 for discs), Ep = sum m g
// (h - bottom); infinity when Ep is not positive.
template <class Tag>
double kinetic_to_potential_ratio(const Atoms<Tag> &atoms, int groupbit, const Frame &frame,
                                  double gravity, bool two_d, MPI_Comm world)
{
  const double inertia_factor = two_d ? 0.5 : 0.4;  // disc or sphere
  double local[2] = { 0.0, 0.0 }, total[2] = { 0.0, 0.0 };
  for (int i = 0; i < atoms.nlocal; ++i) {
    if (!(atoms.mask[i] & groupbit)) continue;
    const double m = atoms.mass[i], r = atoms.radius[i];
    const double *v = atoms.v[i], *w = atoms.omega[i];
    local[0] += 0.5*m*(v[0]*v[0] + v[1]*v[1] + v[2]*v[2])
              + 0.5*inertia_factor*m*r*r*(w[0]*w[0] + w[1]*w[1] + w[2]*w[2]);
    local[1] += m*gravity*(atoms.x[i][frame.vertical] - frame.bottom);
  }
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, world);
  if (!(total[1] > 0.0)) return std::numeric_limits<double>::infinity();
  return total[0]/total[1];
}

// Every grain of every rank, sorted by id, with its position relative to
// the outlet: free (groupbit), left or right base (base_groupbit, by the
// side of the orifice centre), or other fixed grains.
template <class Tag>
std::vector<GrainRecord> gather_grains(const Atoms<Tag> &atoms, int groupbit, int base_groupbit,
                                       const Frame &frame, MPI_Comm world)
{
  const int grain_fields = 6;     // tag, horizontal, off-plane, height, radius, kind
  std::vector<double> local;
  for (int i = 0; i < atoms.nlocal; ++i) {
    const double *x = atoms.x[i];
    Kind kind = other_fixed;
    if (atoms.mask[i] & base_groupbit) kind = x[0] < frame.orifice_centre ? left_base : right_base;
    else if (atoms.mask[i] & groupbit) kind = free_grain;
    const double fields[grain_fields] = { static_cast<double>(atoms.tag[i]),
                                          x[0] - frame.orifice_centre, x[frame.off_plane],
                                          x[frame.vertical] - frame.bottom, atoms.radius[i],
                                          static_cast<double>(kind) };
    local.insert(local.end(), fields, fields + grain_fields);
  }
  const std::vector<double> all = allgather(local, world);
  std::vector<GrainRecord> grains;
  for (std::size_t k = 0; k + grain_fields <= all.size(); k += grain_fields) {
    const GrainRecord grain = { static_cast<int>(all[k]), all[k+1], all[k+2], all[k+3], all[k+4],
                                static_cast<Kind>(static_cast<int>(all[k+5])) };
    grains.push_back(grain);
  }
  std::sort(grains.begin(), grains.end(),
            [](const GrainRecord &a, const GrainRecord &b) { return a.tag < b.tag; });
  return grains;
}

// The contacts of every rank (each rank's `local`) with at least one free
// grain, each pair once, sorted by (id1, id2); the contact point is on the
// line of centres at r1 - overlap/2 from grain 1.
inline std::vector<ContactRecord> gather_contacts(const std::vector<ContactSample> &samples,
                                                  const std::vector<GrainRecord> &grains,
                                                  const Frame &frame, MPI_Comm world)
{
  const int contact_fields = 6;   // id1, id2, horizontal, height, |F_n|, |F_t|
  std::map<int, const GrainRecord *> by_tag;
  for (std::size_t k = 0; k < grains.size(); ++k) by_tag[grains[k].tag] = &grains[k];

  std::vector<double> local;
  for (const ContactSample &sample : samples) {
    int id1 = sample.id1, id2 = sample.id2;
    const double *x1 = sample.x1, *x2 = sample.x2;
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
    const double reach = first->second->radius - 0.5*sample.overlap;
    double point[3];
    for (int k = 0; k < 3; ++k) point[k] = x1[k] + along[k]/distance*reach;
    const double fields[contact_fields] = { static_cast<double>(id1), static_cast<double>(id2),
                                            point[0] - frame.orifice_centre,
                                            point[frame.vertical] - frame.bottom,
                                            magnitude(sample.normal_force),
                                            magnitude(sample.tangential_force) };
    local.insert(local.end(), fields, fields + contact_fields);
  }
  const std::vector<double> all = allgather(local, world);
  std::vector<ContactRecord> contacts;
  for (std::size_t k = 0; k + contact_fields <= all.size(); k += contact_fields) {
    const ContactRecord contact = { static_cast<int>(all[k]), static_cast<int>(all[k+1]),
                                    all[k+2], all[k+3], all[k+4], all[k+5] };
    contacts.push_back(contact);
  }
  std::sort(contacts.begin(), contacts.end(),
            [](const ContactRecord &a, const ContactRecord &b) {
              return a.id1 != b.id1 ? a.id1 < b.id1 : a.id2 < b.id2; });
  // a pair with a ghost partner is listed by both ranks under `newton off`
  contacts.erase(std::unique(contacts.begin(), contacts.end(),
                             [](const ContactRecord &a, const ContactRecord &b) {
                               return a.id1 == b.id1 && a.id2 == b.id2; }),
                 contacts.end());
  return contacts;
}

/* ----------------------------------------------------------------------
   the walk of arch_walk.h over the free and base grains; the other fixed
   grains (side walls) take no part
------------------------------------------------------------------------- */

inline Outcome identify_arch(const std::vector<GrainRecord> &grains,
                             const std::vector<ContactRecord> &contact_list)
{
  using namespace silokit::arch;
  std::vector<Grain> walk_grains;
  std::map<int, std::size_t> index_of;
  for (std::size_t k = 0; k < grains.size(); ++k) {
    if (grains[k].kind == other_fixed) continue;
    const Base base = grains[k].kind == left_base ? Base::left
                    : grains[k].kind == right_base ? Base::right : Base::none;
    const Grain grain = { grains[k].horizontal, grains[k].height, grains[k].tag, base };
    index_of[grains[k].tag] = walk_grains.size();
    walk_grains.push_back(grain);
  }
  std::vector<Contact> walk_contacts;
  for (std::size_t k = 0; k < contact_list.size(); ++k) {
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
  for (std::size_t k = 0; k < arch.members.size(); ++k) {
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

// When the flow stopped but no arch was identified, the free grains near
// the outlet: centres within half the opening between the innermost base
// grains plus two diameters of the middle of the opening.
inline std::vector<int> grains_over_orifice(const std::vector<GrainRecord> &grains)
{
  const GrainRecord *left = nullptr, *right = nullptr;
  double largest_radius = 0.0;
  for (std::size_t k = 0; k < grains.size(); ++k) {
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
  for (std::size_t k = 0; k < grains.size(); ++k) {
    if (grains[k].kind != free_grain) continue;
    const double dx = grains[k].horizontal - centre[0], dz = grains[k].height - centre[1];
    if (dx*dx + dz*dz < reach*reach) tags.push_back(grains[k].tag);
  }
  return tags;
}

// The grains fix reinject moves to break the clog: the arch, or for a
// clog without an arch the free grains over the outlet; none after a
// time-out.
inline std::vector<int> grains_to_remove(const Outcome &outcome,
                                         const std::vector<GrainRecord> &grains)
{
  if (outcome.status == 1) return outcome.member_tags;
  if (outcome.status == -1) return grains_over_orifice(grains);
  return std::vector<int>();
}

/* ----------------------------------------------------------------------
   the records (rank 0): clogs.txt, arches.txt, feet.txt, contacts.txt in
   the directory, flushed after every clog
------------------------------------------------------------------------- */

struct Records {
  RecordFile clogs, arches, feet, contacts;
  bool is_open() const { return clogs && arches && feet && contacts; }
};

inline std::string records_error(const std::string &directory)
{
  return "cannot write clogs.txt, arches.txt, feet.txt, contacts.txt in directory '" + directory +
         "'";
}

// Opens the four records in `directory` (silokit_record.h): anew, or after
// a restart (restored) for appending, with the clogs past the `clogs` the
// restart file knows removed (the run finds them again); every record
// begins with the clog. `notices` gets a line per record with removed
// rows, for the screen. False if one cannot be opened.
inline bool open_records(Records &records, const std::string &directory, bool restored, int clogs,
                         std::vector<std::string> &notices)
{
  const KeptRows kept = { 0, static_cast<double>(clogs) };
  auto open_one = [&](const char *name, const char *header) -> RecordFile {
    long dropped = 0;
    RecordFile file = open_record(directory + "/" + name, restored, header, kept, &dropped);
    if (dropped > 0) {
      char message[256];
      snprintf(message, sizeof(message), "fix clog: removed %ld line(s) of clogs after clog %d "
               "from '%s', written after the restart file by the run that wrote it; this run "
               "records them again", dropped, clogs, name);
      notices.push_back(message);
    }
    return file;
  };
  records.clogs = open_one("clogs.txt", "# clog step time avalanche eta status");
  records.arches = open_one("arches.txt", "# clog order id x y z phi fn ft");
  records.feet = open_one("feet.txt", "# clog order id x y z phi fn ft base floor");
  records.contacts = open_one("contacts.txt", "# clog id1 id2 x z fn ft arch");
  return records.is_open();
}

// Appends clog `clog` (its attempt's outcome) to the records and flushes
// them: a row of clogs.txt; for status 1 and -1 the contacts, for status
// 1 the arch and its feet.
inline void write_records(Records &records, int clog, long long step, double time, int avalanche,
                          const Outcome &outcome, const std::vector<GrainRecord> &grains,
                          const std::vector<ContactRecord> &contact_list)
{
  fprintf(records.clogs.get(), "%d %lld %.12g %d %d %d\n", clog, step, time, avalanche,
          static_cast<int>(outcome.member_tags.size()), outcome.status);
  fflush(records.clogs.get());
  if (outcome.status == 0) return;

  // per grain: the mean over its contacts of |F_n| and |F_t|
  std::map<int, double> sum_normal, sum_tangential;
  std::map<int, int> count;
  for (std::size_t k = 0; k < contact_list.size(); ++k) {
    const ContactRecord &c = contact_list[k];
    const int ids[2] = { c.id1, c.id2 };
    for (int side = 0; side < 2; ++side) {
      sum_normal[ids[side]] += c.normal_force;
      sum_tangential[ids[side]] += c.tangential_force;
      count[ids[side]] += 1;
    }
  }
  std::map<int, const GrainRecord *> by_tag;
  for (std::size_t k = 0; k < grains.size(); ++k) by_tag[grains[k].tag] = &grains[k];
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
    write_grain(records.arches.get(), k + 1, outcome.member_tags[k], outcome.member_phi[k]);
    fputc('\n', records.arches.get());
  }
  fflush(records.arches.get());
  // the left foot before the first member (order 0), the right one after the last
  for (std::size_t side = 0; side < outcome.foot_tags.size(); ++side) {
    write_grain(records.feet.get(), side == 0 ? 0 : eta + 1, outcome.foot_tags[side],
                outcome.foot_phi[side]);
    fprintf(records.feet.get(), " %d %d\n", outcome.foot_base_tags[side],
            outcome.foot_on_floor[side]);
  }
  fflush(records.feet.get());

  const std::set<int> members(outcome.member_tags.begin(), outcome.member_tags.end());
  for (std::size_t k = 0; k < contact_list.size(); ++k) {
    const ContactRecord &c = contact_list[k];
    const int in_arch = members.count(c.id1) && members.count(c.id2);
    fprintf(records.contacts.get(), "%d %d %d %.12g %.12g %.10g %.10g %d\n", clog, c.id1, c.id2,
            c.horizontal, c.height, c.normal_force, c.tangential_force, in_arch);
  }
  fflush(records.contacts.get());
}

// The line for the screen and the log, with its newline.
inline std::string report_line(const std::string &fix_id, int clog, double time, long long step,
                               int avalanche, const Outcome &outcome, const Settings &settings,
                               int arches_found)
{
  std::ostringstream line;
  line << "fix clog " << fix_id << ": clog " << clog << " at t = " << time << " s (step " << step
       << "), avalanche " << avalanche << " grains, ";
  if (outcome.status == 1) line << "arch of " << outcome.member_tags.size() << " grains";
  else line << "no arch (" << outcome.reason << ")";
  if (settings.break_arches)
    line << "; " << arches_found << " of " << settings.arches_wanted << " arches";
  line << "\n";
  return line.str();
}

// What fix clog checks on: the silo's axes, its groups (the free grains,
// the base), gravity along -vertical and whether the run is 2D.
struct Scene {
  Frame frame;
  int groupbit;
  int base_groupbit;
  double gravity;
  bool two_d;
};

// What a check did: nothing, or an attempt recorded (its screen line, for
// rank 0 to print), after which either the flag is up (done) or the host's
// fix reinject is to re-enter the grains `to_remove`.
struct CheckResult {
  bool recorded;
  bool done;
  std::string line;
  std::vector<int> to_remove;

  CheckResult() : recorded(false), done(false) {}
};

// One check at `now` (step `step`), on every rank: fix reinject's exit
// count grains_out, Ec/Ep, and at a clog the grains, the contacts
// (local_contacts(): this rank's ContactSamples), the walk, the records
// (written by the rank with `writer` true) and the counts;
// close_avalanche() is fix reinject's.
template <class Tag, class CloseAvalanche, class LocalContacts>
CheckResult check_for_clog(const Settings &settings, const Scene &scene, const Atoms<Tag> &atoms,
                           double now, long long step, double grains_out,
                           const std::string &fix_id, CloseAvalanche close_avalanche,
                           LocalContacts local_contacts, Attempts &attempts, Records &records,
                           bool writer, MPI_Comm world)
{
  CheckResult result;
  const double ratio = kinetic_to_potential_ratio(atoms, scene.groupbit, scene.frame,
                                                  scene.gravity, scene.two_d, world);
  const Verdict verdict = attempts.check(now, grains_out, ratio, settings);
  if (verdict == Verdict::flowing) return result;

  const int avalanche = close_avalanche();
  Outcome outcome;
  std::vector<GrainRecord> grains;
  std::vector<ContactRecord> contact_list;
  if (verdict == Verdict::stopped) {
    grains = gather_grains(atoms, scene.groupbit, scene.base_groupbit, scene.frame, world);
    contact_list = gather_contacts(local_contacts(), grains, scene.frame, world);
    outcome = identify_arch(grains, contact_list);
  } else {
    outcome.status = 0;
    outcome.reason = "the flow did not stop within max_time";
  }
  result.recorded = true;
  result.done = attempts.record(outcome.status, now, settings);
  if (writer) {
    write_records(records, attempts.clogs(), step, now, avalanche, outcome, grains, contact_list);
    result.line = report_line(fix_id, attempts.clogs(), now, step, avalanche, outcome, settings,
                              attempts.arches());
  }
  if (!result.done) result.to_remove = grains_to_remove(outcome, grains);
  return result;
}

}  // namespace clog
}  // namespace silokit

#endif
