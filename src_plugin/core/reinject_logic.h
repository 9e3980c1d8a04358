/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The host-free part of fix reinject (doc/fix_reinject.md), shared by the
   LIGGGHTS fix (src_plugin/liggghts/fix_reinject.*) and the LAMMPS one
   (src_plugin/lammps/fix_reinject_lammps.*): the keywords, gathering the
   leavers and the grains near the injection region over the ranks, the
   search for a free spot among them, the counts (grains out, mass out,
   avalanche), the flow-rate window, the record file and the restart
   data. The hosts hand in their per-atom arrays, their random generator
   (a callable returning uniform numbers in (0, 1)) and their region test
   (a callable saying whether a sphere lies wholly inside the region), and
   raise the errors whose text this file words.
------------------------------------------------------------------------- */

#ifndef SILOKIT_REINJECT_LOGIC_H
#define SILOKIT_REINJECT_LOGIC_H

#include "fix_common.h"
#include "periodic_images.h"
#include "silokit_mpi.h"
#include "silokit_record.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace silokit {
namespace reinject {

/* ----------------------------------------------------------------------
   the keywords: fix ID group reinject exit <axis> <coordinate>
   region <region-ID> seed <seed> [every N] [maxattempt M]
   [rate_window t] [file name]
------------------------------------------------------------------------- */

struct Settings {
  int axis;                    // 0, 1, 2: the vertical axis (gravity along -axis)
  double exit_coordinate;      // a grain whose centre is below this has left
  std::string region_id;       // where grains re-enter
  int seed;
  int every;                   // check every N steps
  int max_attempts;            // random draws per grain
  double rate_window;          // time over which the flow rate is averaged
  std::string file_name;       // of the record, empty without 'file'

  Settings() : axis(-1), exit_coordinate(0.0), seed(0), every(1), max_attempts(1000),
               rate_window(0.1) {}
};

// Reads the words after `fix ID group reinject` into `settings`. Returns
// the text of the first error (naming the keyword and what it allows),
// empty when all is well. Any positive seed passes: LIGGGHTS' adapter adds
// its host's rule (a prime > 10000).
inline std::string parse_settings(const std::vector<std::string> &words, bool two_d,
                                  Settings &settings)
{
  bool have_exit = false, have_seed = false;
  std::string problem;
  for (std::size_t iarg = 0; iarg < words.size() && problem.empty(); ) {
    const std::string &keyword = words[iarg];
    const std::size_t values = keyword == "exit" ? 2 : 1;
    if (iarg + values >= words.size())
      return "keyword '" + keyword + "' needs " + (values == 2 ? "two values" : "a value");
    const std::string &value = words[iarg + 1];
    if (keyword == "exit") {
      const std::string axes = "xyz";
      if (value.size() != 1 || axes.find(value) == std::string::npos)
        return "'exit' takes an axis x, y or z, then a coordinate";
      settings.axis = static_cast<int>(axes.find(value));
      problem = number_for("exit", words[iarg + 2], settings.exit_coordinate);
      have_exit = true;
    } else if (keyword == "region") {
      settings.region_id = value;
    } else if (keyword == "seed") {
      problem = integer_for("seed", value, settings.seed);
      if (problem.empty() && settings.seed <= 0) return "'seed' must be a positive integer";
      have_seed = true;
    } else if (keyword == "every") {
      problem = integer_for("every", value, settings.every);
      if (problem.empty() && settings.every < 1) return "'every' must be >= 1";
    } else if (keyword == "maxattempt") {
      problem = integer_for("maxattempt", value, settings.max_attempts);
      if (problem.empty() && settings.max_attempts < 1) return "'maxattempt' must be >= 1";
    } else if (keyword == "rate_window") {
      problem = number_for("rate_window", value, settings.rate_window);
      if (problem.empty() && !(settings.rate_window > 0.0)) return "'rate_window' must be > 0";
    } else if (keyword == "file") {
      settings.file_name = value;
      if (value.empty()) return "'file' needs a file name";
    } else {
      return "unknown keyword '" + keyword +
             "' (known: exit, region, seed, every, maxattempt, rate_window, file)";
    }
    iarg += values + 1;
  }
  if (!problem.empty()) return problem;
  if (!have_exit) return "'exit <axis> <coordinate>' is required";
  if (settings.region_id.empty()) return "'region <region-ID>' is required";
  if (!have_seed) return "'seed <positive integer>' is required";
  if (two_d && settings.axis == 2) return "'exit': in 2D the vertical axis is x or y, not z";
  return "";
}

/* ----------------------------------------------------------------------
   spheres and leavers
------------------------------------------------------------------------- */

struct Sphere { double x[3]; double radius; };
struct Leaver { int tag; double radius; double mass; bool left_through_exit; };
struct Box { double lo[3], hi[3]; };

// `sphere` and its images (shifted by `shifts`) into `spheres`.
inline void add_with_images(const Sphere &sphere, const std::vector<Shift> &shifts,
                            std::vector<Sphere> &spheres)
{
  spheres.push_back(sphere);
  for (const Shift &shift : shifts) {
    Sphere image = sphere;
    for (int k = 0; k < 3; ++k) image.x[k] += shift.d[k];
    spheres.push_back(image);
  }
}

inline bool overlaps(const double *centre, double radius, const double *other_centre,
                     double other_radius)
{
  double distance_squared = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = centre[k] - other_centre[k];
    distance_squared += d*d;
  }
  const double contact = radius + other_radius;
  return distance_squared < contact*contact;
}

// The bounding box of a host's region (both hosts name it extent_*).
template <class Region>
Box bounding_box(const Region &region)
{
  const Box box = { { region.extent_xlo, region.extent_ylo, region.extent_zlo },
                    { region.extent_xhi, region.extent_yhi, region.extent_zhi } };
  return box;
}

// The region must stay as it was defined and its bounding box lie above
// the exit plane: "" or the error's text. Both hosts keep a region's
// bounding box (where the spots are drawn) from its definition, so spots
// drawn in it would miss a region that moves or changes shape.
// (LAMMPS' dynamic_check() counts a variable shape, LIGGGHTS' does not.)
template <class Region>
std::string check_region(Region &region, const Settings &settings)
{
  if (region.dynamic_check() || region.varshape)
    return "region '" + settings.region_id + "' moves or changes shape; the region must be static";
  if (bounding_box(region).lo[settings.axis] <= settings.exit_coordinate)
    return "the region must lie above the exit plane";
  return "";
}

// The per-atom arrays of a host (Tag: its atom ID type).
template <class Tag>
struct Grains {
  int nlocal;
  const Tag *tag;
  double **x, **v, **omega;
  double **angmom;             // nullptr unless the host keeps one (LIGGGHTS' rods)
  const double *radius, *mass;
};

/* ----------------------------------------------------------------------
   gathering over the ranks: every rank ends with the same answers
------------------------------------------------------------------------- */

// Whether a grain of any rank has left (left_through_exit(i) of its rank).
template <class LeftThroughExit>
bool any_left(int nlocal, LeftThroughExit left_through_exit, MPI_Comm world)
{
  int local = 0, total = 0;
  for (int i = 0; i < nlocal; ++i)
    if (left_through_exit(i)) ++local;
  MPI_Allreduce(&local, &total, 1, MPI_INT, MPI_SUM, world);
  return total > 0;
}

// The grains of this rank that left (left_through_exit(i)) or that fix
// clog asked to re-enter (requested(i)), of all ranks, sorted by tag: the
// same order on every rank, whatever the decomposition.
template <class Tag, class LeftThroughExit, class Requested>
std::vector<Leaver> gather_leavers(const Grains<Tag> &grains, LeftThroughExit left_through_exit,
                                   Requested requested, MPI_Comm world)
{
  std::vector<double> local;
  for (int i = 0; i < grains.nlocal; ++i) {
    const bool left = left_through_exit(i);
    if (!left && !requested(i)) continue;
    local.push_back(grains.tag[i]);
    local.push_back(grains.radius[i]);
    local.push_back(grains.mass[i]);
    local.push_back(left ? 1.0 : 0.0);
  }
  const std::vector<double> all = allgather(local, world);
  std::vector<Leaver> leavers;
  for (std::size_t k = 0; k + 3 < all.size(); k += 4) {
    Leaver leaver = { static_cast<int>(all[k]), all[k+1], all[k+2], all[k+3] != 0.0 };
    leavers.push_back(leaver);
  }
  std::sort(leavers.begin(), leavers.end(),
            [](const Leaver &a, const Leaver &b) { return a.tag < b.tag; });
  return leavers;
}

// The largest radius of any grain on any rank.
inline double largest_radius(int nlocal, const double *radius, MPI_Comm world)
{
  double largest_local = 0.0, largest = 0.0;
  for (int i = 0; i < nlocal; ++i) largest_local = std::max(largest_local, radius[i]);
  MPI_Allreduce(&largest_local, &largest, 1, MPI_DOUBLE, MPI_MAX, world);
  return largest;
}

// Every grain (of any group, of any rank), or periodic image of one
// (`shifts`, from periodic_image_shifts in periodic_images.h), whose centre lies within `margin`
// of `box`: what a re-entering grain must not overlap. A region next to a
// periodic side has the grains just across the other side as neighbours.
template <class Tag>
std::vector<Sphere> gather_spheres_near(const Box &box, double margin, const Grains<Tag> &grains,
                                        const std::vector<Shift> &shifts, MPI_Comm world)
{
  std::vector<double> local;
  for (int i = 0; i < grains.nlocal; ++i) {
    // the grain itself (n = -1), then its images
    for (int n = -1; n < static_cast<int>(shifts.size()); ++n) {
      double x[3];
      for (int k = 0; k < 3; ++k) x[k] = grains.x[i][k] + (n < 0 ? 0.0 : shifts[n].d[k]);
      bool near = true;
      for (int k = 0; k < 3 && near; ++k)
        near = !(x[k] < box.lo[k] - margin || x[k] > box.hi[k] + margin);
      if (!near) continue;
      local.insert(local.end(), x, x + 3);
      local.push_back(grains.radius[i]);
    }
  }
  const std::vector<double> all = allgather(local, world);
  std::vector<Sphere> spheres;
  for (std::size_t k = 0; k + 3 < all.size(); k += 4) {
    Sphere sphere = { { all[k], all[k+1], all[k+2] }, all[k+3] };
    spheres.push_back(sphere);
  }
  return spheres;
}

/* ----------------------------------------------------------------------
   placement
------------------------------------------------------------------------- */

// A random spot in `region_box` where a grain of `radius` lies wholly in
// the region (inside(spot, radius)) and overlaps none of `occupied`; up to
// max_attempts draws of three numbers from uniform(). In 2D the spot has
// z = 0 (the third number is drawn all the same). Every rank draws the
// same numbers from the same sequence, so the spots agree.
template <class Uniform, class Inside>
bool find_free_spot(const Box &region_box, bool two_d, double radius,
                    const std::vector<Sphere> &occupied, int max_attempts, Uniform &uniform,
                    Inside &inside, double *spot)
{
  for (int attempt = 0; attempt < max_attempts; ++attempt) {
    for (int k = 0; k < 3; ++k)
      spot[k] = region_box.lo[k] + uniform()*(region_box.hi[k] - region_box.lo[k]);
    if (two_d) spot[2] = 0.0;
    if (!inside(spot, radius)) continue;
    bool free = true;
    for (std::size_t s = 0; s < occupied.size() && free; ++s)
      free = !overlaps(spot, radius, occupied[s].x, occupied[s].radius);
    if (free) return true;
  }
  return false;
}

// Moves the grains of this rank that have a spot there, at rest: velocity,
// angular velocity and angular momentum (if any) zero.
template <class Tag>
void move_to_spots(const std::map<int, Sphere> &spots, const Grains<Tag> &grains)
{
  for (int i = 0; i < grains.nlocal; ++i) {
    const std::map<int, Sphere>::const_iterator found =
      spots.find(static_cast<int>(grains.tag[i]));
    if (found == spots.end()) continue;
    for (int k = 0; k < 3; ++k) {
      grains.x[i][k] = found->second.x[k];
      grains.v[i][k] = 0.0;
      grains.omega[i][k] = 0.0;
      if (grains.angmom) grains.angmom[i][k] = 0.0;
    }
  }
}

// The counts a fix reinject keeps (values 1-3 of its output vector).
struct Counts {
  double grains_out;
  double mass_out;
  double avalanche;      // grains out since fix clog last closed an avalanche

  Counts() : grains_out(0.0), mass_out(0.0), avalanche(0.0) {}

  // a grain re-entered; those fix clog asked for did not leave
  void add(const Leaver &leaver)
  {
    if (!leaver.left_through_exit) return;
    grains_out += 1.0;
    mass_out += leaver.mass;
    avalanche += 1.0;
  }

  int close_avalanche()
  {
    const int size = static_cast<int>(avalanche);
    avalanche = 0.0;
    return size;
  }
};

/* ----------------------------------------------------------------------
   the flow rate: the change of the counts over a window of time
------------------------------------------------------------------------- */

struct Sample { double time, grains, mass; };

class FlowRateWindow {
 public:
  explicit FlowRateWindow(double window) : window(window) {}

  void set_window(double length) { window = length; }

  // the counts at a check at `time`; keeps the newest sample at least a
  // window old, and all newer (with a tolerance for the rounding of
  // accumulated times)
  void add(double time, const Counts &counts)
  {
    const Sample now = { time, counts.grains_out, counts.mass_out };
    kept.push_back(now);
    const double window_start = now.time - window*(1.0 - 1e-9);
    while (kept.size() > 2 && kept[1].time <= window_start) kept.pop_front();
  }

  // grains (or mass) per unit time between the oldest and newest sample
  double rate(bool of_mass) const
  {
    if (kept.size() < 2) return 0.0;
    const Sample &first = kept.front(), &last = kept.back();
    const double span = last.time - first.time;
    if (!(span > 0.0)) return 0.0;
    return (of_mass ? last.mass - first.mass : last.grains - first.grains)/span;
  }

  const std::deque<Sample> &samples() const { return kept; }
  void restore(const std::deque<Sample> &samples) { kept = samples; }

 private:
  double window;
  std::deque<Sample> kept;
};

/* ----------------------------------------------------------------------
   what a fix reinject keeps between steps
------------------------------------------------------------------------- */

struct State {
  Counts counts;
  std::set<int> requested;    // tags fix clog asked to re-enter, not counted as out
  FlowRateWindow flow;

  explicit State(double rate_window) : flow(rate_window) {}

  // a check at `time`: adds a flow-rate sample; true when a grain of any
  // rank has left (left_through_exit(i)), to re-enter on the next step
  template <class LeftThroughExit>
  bool check(double time, int nlocal, LeftThroughExit left_through_exit, MPI_Comm world)
  {
    const bool left = any_left(nlocal, left_through_exit, world);
    flow.add(time, counts);
    return left;
  }

  // fix clog's tags; true when there are any to re-enter on the next step
  bool request(const std::vector<int> &tags)
  {
    requested.insert(tags.begin(), tags.end());
    return !requested.empty();
  }

  // the output vector: 0 grains out, 1 their mass, 2 grains in the
  // current avalanche, 3 grains and 4 mass per unit time over the window
  double output(int index) const
  {
    switch (index) {
      case 0: return counts.grains_out;
      case 1: return counts.mass_out;
      case 2: return counts.avalanche;
      case 3: return flow.rate(false);
      case 4: return flow.rate(true);
    }
    return 0.0;
  }
};

// The re-entry on a step after grains left: gathers those that left
// (left_through_exit(i)) and those fix clog asked for (state.requested,
// then emptied), places them in tag order at free spots of the region,
// counts them and moves those of this rank. `spots` gets each one's spot
// (tag -> sphere). Returns how many re-entered, or -1 when one found no
// spot in max_attempts draws (its tag in unplaced_tag): the host stops
// with an error (no_free_spot words it). `shifts` (periodic_image_shifts) are the box's periodic
// images, which a spot must not overlap either. Every rank takes part.
template <class Tag, class LeftThroughExit, class Uniform, class Inside>
int reenter(State &state, const Grains<Tag> &grains, LeftThroughExit left_through_exit,
            const Box &region_box, bool two_d, const std::vector<Shift> &shifts,
            int max_attempts, Uniform &uniform, Inside &inside, MPI_Comm world,
            std::map<int, Sphere> &spots, int &unplaced_tag)
{
  const std::set<int> &requested = state.requested;
  auto was_requested = [&](int i) {
    return !requested.empty() && requested.count(static_cast<int>(grains.tag[i])) > 0;
  };
  const std::vector<Leaver> leavers = gather_leavers(grains, left_through_exit, was_requested,
                                                     world);
  state.requested.clear();
  if (leavers.empty()) return 0;

  const double largest = largest_radius(grains.nlocal, grains.radius, world);
  std::vector<Sphere> occupied = gather_spheres_near(region_box, 2.0*largest, grains, shifts,
                                                     world);
  for (std::size_t n = 0; n < leavers.size(); ++n) {
    Sphere placed;
    placed.radius = leavers[n].radius;
    if (!find_free_spot(region_box, two_d, placed.radius, occupied, max_attempts, uniform,
                        inside, placed.x)) {
      unplaced_tag = leavers[n].tag;
      return -1;
    }
    add_with_images(placed, shifts, occupied);
    spots[leavers[n].tag] = placed;
    state.counts.add(leavers[n]);
  }
  move_to_spots(spots, grains);
  return static_cast<int>(leavers.size());
}

// The error's text when reenter() found no spot for grain `unplaced_tag`.
inline std::string no_free_spot(const Settings &settings, int unplaced_tag)
{
  return "no free spot in region '" + settings.region_id + "' for grain " +
         std::to_string(unplaced_tag) + " after " + std::to_string(settings.max_attempts) +
         " attempts: enlarge the region or raise 'maxattempt'";
}

/* ----------------------------------------------------------------------
   the record file (rank 0): a header, then one line per step with
   re-entries: step, time, the three counts after it
------------------------------------------------------------------------- */

inline std::string record_header(const std::string &fix_id, int axis, double exit_coordinate)
{
  char plane[64];
  snprintf(plane, sizeof(plane), "%c = %g", "xyz"[axis], exit_coordinate);
  return "# fix reinject " + fix_id + ": grains re-entered after leaving below " + plane +
         "\n# step t n_out mass_out avalanche";
}

// Opens the record (silokit_record.h): anew, or for appending when the
// fix was restored from a restart file written at time_reached, whose
// later lines are removed (the restarted run records those steps again);
// `notice` then gets a line saying so, for the screen. Empty if the file
// cannot be opened.
inline RecordFile open_reinject_record(const Settings &settings, const std::string &fix_id,
                                       bool restored, double time_reached, std::string &notice)
{
  const std::string header = record_header(fix_id, settings.axis, settings.exit_coordinate);
  const KeptRows kept = { 1, time_reached };
  long dropped = 0;
  RecordFile record = open_record(settings.file_name, restored, header.c_str(), kept, &dropped);
  if (dropped > 0) {
    char message[256];
    snprintf(message, sizeof(message), "fix reinject: removed %ld line(s) past t = %.10g from "
             "'%s', written after the restart file by the run that wrote it; this run records "
             "them again", dropped, kept.last, settings.file_name.c_str());
    notice = message;
  }
  return record;
}

inline void write_record_line(FILE *file, long long step, double time, const Counts &counts)
{
  fprintf(file, "%lld %.15g %.0f %.15g %.0f\n", step, time, counts.grains_out,
          counts.mass_out, counts.avalanche);
  fflush(file);
}

/* ----------------------------------------------------------------------
   restart data
------------------------------------------------------------------------- */

// The host's values in the restart data, besides the State.
struct RestartHead {
  int random_state;           // the random generator's state()
  double time;                // the host's clock
  double pending_step;        // the step of a requested re-entry, -1: none
};

// A list of doubles: the layout marker, the counts, the random state, the
// time, the pending step, the number of requested tags and of samples,
// the tags, the samples (time, grains, mass). A host may append values of
// its own after them.
inline std::vector<double> restart_list(double layout, const State &state, const RestartHead &head)
{
  std::vector<double> list = { layout, state.counts.grains_out, state.counts.mass_out,
                               state.counts.avalanche, static_cast<double>(head.random_state),
                               head.time, head.pending_step,
                               static_cast<double>(state.requested.size()),
                               static_cast<double>(state.flow.samples().size()) };
  list.insert(list.end(), state.requested.begin(), state.requested.end());
  for (const Sample &sample : state.flow.samples()) {
    list.push_back(sample.time);
    list.push_back(sample.grains);
    list.push_back(sample.mass);
  }
  return list;
}

// Reads what restart_list wrote. with_pending false: the layout of silokit
// up to commit eaa418e, which ends after the time; the pending step, the
// tags and the samples are then left as they are. Returns the first value
// past the data.
inline const double *read_restart_list(const double *list, bool with_pending, State &state,
                                       RestartHead &head)
{
  state.counts.grains_out = list[1];
  state.counts.mass_out = list[2];
  state.counts.avalanche = list[3];
  head.random_state = static_cast<int>(list[4]);
  head.time = list[5];
  if (!with_pending) return list + 6;
  head.pending_step = list[6];
  const std::size_t tag_count = static_cast<std::size_t>(list[7]);
  const std::size_t sample_count = static_cast<std::size_t>(list[8]);
  const double *tags = list + 9;
  state.requested.clear();
  for (std::size_t k = 0; k < tag_count; ++k) state.requested.insert(static_cast<int>(tags[k]));
  const double *sample = tags + tag_count;
  std::deque<Sample> samples;
  for (std::size_t k = 0; k < sample_count; ++k, sample += 3) {
    const Sample restored = { sample[0], sample[1], sample[2] };
    samples.push_back(restored);
  }
  state.flow.restore(samples);
  return sample;
}

}  // namespace reinject
}  // namespace silokit

#endif
