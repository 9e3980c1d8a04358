/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The host-free part of fix insert/rain2d (doc/fix_insert_rain2d.md),
   shared by the LIGGGHTS fix (src_plugin/liggghts/fix_insert_rain2d.*) and
   the LAMMPS one (src_plugin/lammps/fix_insert_rain2d_lammps.*): the
   keywords, the schedule (when the last row has fallen, is blocked, when a
   row is due), the stop rules (stationarity, limits), drawing a row
   (diameters from the polydispersity, gaps from rain_row.h, tags), the
   overlap check against grains already there and their periodic images
   (periodic_images.h), the outputs and the restart data. The hosts hand
   in their per-atom arrays, their random generator (a callable returning
   uniform numbers in (0, 1); every rank calls it the same number of times
   in the same order) and the group count, create the grains, and raise
   the errors whose text this file words.
------------------------------------------------------------------------- */

#ifndef SILOKIT_RAIN2D_LOGIC_H
#define SILOKIT_RAIN2D_LOGIC_H

#include "fix_common.h"
#include "periodic_images.h"
#include "rain_row.h"
#include "silokit_mpi.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace silokit {
namespace rain2d {

/* ----------------------------------------------------------------------
   the keywords: fix ID group insert/rain2d seed S type T diameter d
   density rho line x_lo x_hi y [polydispersity p] [fill f] [fall h]
   [window W] [tolerance t] [max_grains N] [max_rows N]
------------------------------------------------------------------------- */

struct Settings {
  int seed;
  int grain_type;
  double mean_diameter;
  double polydispersity;       // diameters uniform in mean*(1 -+ polydispersity)
  double density;              // mass = pi r^2 density (a disc)
  double line_lo, line_hi;     // the row spans [line_lo, line_hi] along x ...
  double line_height;          // ... with the centres at y = line_height
  double fill;                 // sum of diameters / row length
  double fall;                 // a row is released when the previous one has fallen this much
  int window;                  // stationarity: rows per averaging window
  double tolerance;            // stationarity: allowed relative growth between windows
  int max_grains;              // 0: no limit
  int max_rows;                // 0: no limit

  Settings() : seed(0), grain_type(0), mean_diameter(0.0), polydispersity(0.05), density(0.0),
               line_lo(0.0), line_hi(0.0), line_height(0.0), fill(0.5), fall(-1.0),
               window(10), tolerance(0.01), max_grains(0), max_rows(0) {}

  double largest_diameter() const { return mean_diameter*(1.0 + polydispersity); }
  double smallest_diameter() const { return mean_diameter*(1.0 - polydispersity); }
  int grains_per_row() const { return rain_row_count(line_hi - line_lo, fill, mean_diameter); }
};

// What a host's random generator takes as a seed: `accepts` says whether,
// `required` and `rejected` word the errors ("'seed <required>' is
// required", "'seed' must be <rejected>").
struct SeedRule {
  bool (*accepts)(int seed);
  const char *required;
  const char *rejected;
};

// Whether the host's simulation suits the fix: "" or the error's text,
// which follows the style's name; `in_3d` names what to use instead.
inline std::string host_problem(int dimension, bool sphere_attributes, bool atom_ids,
                                bool triclinic, const std::string &in_3d)
{
  if (dimension != 2) return "is for 2D simulations (dimension 2); in 3D use " + in_3d;
  if (!sphere_attributes) return "needs per-atom radius, mass and omega (atom_style sphere)";
  if (!atom_ids) return "needs atom IDs";
  if (triclinic) return "does not support triclinic boxes";
  return "";
}

// Reads the words after `fix ID group insert/rain2d` into `settings`,
// given the host's seed rule, its number of atom types and its box.
// Returns the text of the first error (naming the keyword and what it
// allows), empty when all is well.
inline std::string parse_settings(const std::vector<std::string> &words, const SeedRule &seed_rule,
                                  int ntypes, const double *box_lo, const double *box_hi,
                                  Settings &settings)
{
  bool have_seed = false, have_type = false, have_line = false, have_fall = false;
  std::string problem;
  for (std::size_t iarg = 0; iarg < words.size(); ) {
    const std::string &keyword = words[iarg];
    const std::size_t values = keyword == "line" ? 3 : 1;
    if (iarg + values >= words.size())
      return "keyword '" + keyword + "' needs " +
             (values == 3 ? "three values (x_lo x_hi y)" : "a value");
    const std::string &value = words[iarg + 1];
    if (keyword == "seed") {
      problem = integer_for("seed", value, settings.seed);
      if (problem.empty() && !seed_rule.accepts(settings.seed))
        return std::string("'seed' must be ") + seed_rule.rejected;
      have_seed = true;
    } else if (keyword == "type") {
      problem = integer_for("type", value, settings.grain_type);
      have_type = true;
    } else if (keyword == "diameter") {
      problem = number_for("diameter", value, settings.mean_diameter);
      if (problem.empty() && !(settings.mean_diameter > 0.0)) return "'diameter' must be > 0";
    } else if (keyword == "polydispersity") {
      problem = number_for("polydispersity", value, settings.polydispersity);
      if (problem.empty() && !(settings.polydispersity >= 0.0 && settings.polydispersity < 1.0))
        return "'polydispersity' must be in [0, 1) (diameters uniform in d(1 -+ p))";
    } else if (keyword == "density") {
      problem = number_for("density", value, settings.density);
      if (problem.empty() && !(settings.density > 0.0)) return "'density' must be > 0";
    } else if (keyword == "line") {
      problem = number_for("line", value, settings.line_lo);
      if (problem.empty()) problem = number_for("line", words[iarg + 2], settings.line_hi);
      if (problem.empty()) problem = number_for("line", words[iarg + 3], settings.line_height);
      if (problem.empty() && !(settings.line_hi > settings.line_lo))
        return "'line x_lo x_hi y' needs x_hi > x_lo";
      have_line = true;
    } else if (keyword == "fill") {
      problem = number_for("fill", value, settings.fill);
      if (problem.empty() && !(settings.fill > 0.0 && settings.fill < 1.0))
        return "'fill' must be in (0, 1) (sum of diameters / row length)";
    } else if (keyword == "fall") {
      problem = number_for("fall", value, settings.fall);
      if (problem.empty() && !(settings.fall > 0.0)) return "'fall' must be > 0";
      have_fall = true;
    } else if (keyword == "window") {
      problem = integer_for("window", value, settings.window);
      if (problem.empty() && settings.window < 1)
        return "'window' must be an integer >= 1 (rows)";
    } else if (keyword == "tolerance") {
      problem = number_for("tolerance", value, settings.tolerance);
      if (problem.empty() && !(settings.tolerance >= 0.0)) return "'tolerance' must be >= 0";
    } else if (keyword == "max_grains") {
      problem = integer_for("max_grains", value, settings.max_grains);
      if (problem.empty() && settings.max_grains < 0)
        return "'max_grains' must be >= 0 (0: no limit)";
    } else if (keyword == "max_rows") {
      problem = integer_for("max_rows", value, settings.max_rows);
      if (problem.empty() && settings.max_rows < 0)
        return "'max_rows' must be >= 0 (0: no limit)";
    } else {
      return "unknown keyword '" + keyword + "' (known: seed, type, diameter, "
             "polydispersity, density, line, fill, fall, window, tolerance, max_grains, max_rows)";
    }
    if (!problem.empty()) return problem;
    iarg += values + 1;
  }
  if (!have_seed) return std::string("'seed <") + seed_rule.required + ">' is required";
  if (!have_type) return "'type <atom type>' is required";
  if (settings.grain_type < 1 || settings.grain_type > ntypes) {
    std::ostringstream message;
    message << "'type' must be an atom type from 1 to " << ntypes;
    return message.str();
  }
  if (settings.mean_diameter == 0.0) return "'diameter <mean diameter>' is required";
  if (settings.density == 0.0) return "'density <mass density>' is required";
  if (!have_line) return "'line <x_lo> <x_hi> <y>' is required";
  const double largest = settings.largest_diameter();
  if (!have_fall) settings.fall = largest;
  if (settings.fall < largest)
    return "'fall' must be at least the largest diameter, d(1 + p), or rows could overlap";
  if (settings.line_hi - settings.line_lo < largest)
    return "'line': the row is shorter than the largest grain";

  // the line and the grains on it must lie inside the box
  const double margin = 0.5*largest;
  if (settings.line_lo < box_lo[0] || settings.line_hi > box_hi[0] ||
      settings.line_height - margin < box_lo[1] || settings.line_height + margin > box_hi[1])
    return "'line': the row of grains must lie inside the simulation box";
  return "";
}

/* ----------------------------------------------------------------------
   the rain's state and rules
------------------------------------------------------------------------- */

// why the release stopped (output 3 > 0); the values are part of the doc
enum StopReason { still_raining = 0, stationary = 1, max_grains_reached = 2,
                  max_rows_reached = 3, line_blocked = 4 };

enum RowState { row_falling, row_fallen, row_blocked };

struct Disc { long long tag; double x, diameter; };

// what the end of a step found
enum StepVerdict { keep_waiting, release_next_step, stop_blocked };

// what the release step came to: nothing due, the rain stopped (reason,
// with the grains present), a row that does not fit on the line (an
// error: lower `fill`), or a row to create
struct Release {
  enum Outcome { none, stopped, does_not_fit, row_drawn };
  Outcome outcome;
  StopReason reason;
  int present;                 // grains of the fix group present before the release
  std::vector<Disc> row;       // row_drawn: the grains to create, then Rain::released()
  Release() : outcome(none), reason(still_raining), present(0) {}
};

class Rain {
 public:
  explicit Rain(const Settings &settings_given) :
    settings(settings_given), grains_per_row(settings_given.grains_per_row()),
    next_tag(0), rows(0), inserted(0), stop_reason(still_raining),
    last_row_first_tag(0), last_row_last_tag(-1), release_step(-1), last_release_step(-1) {}

  const Settings settings;
  const int grains_per_row;

  bool raining() const { return stop_reason == still_raining; }
  // the step of the pending release, -1: none
  long long pending_release() const { return release_step; }

  /* the first row falls on the first step of the first run. Between runs
     a release that is pending (or was written to a restart file) is
     always due on the next step, since end_of_step schedules it for the
     step after its own, and the last release lies in the past.
     reset_timestep, before or after read_restart, moves the step counter
     either way: both steps are therefore set again from the step this run
     starts at. (Left as they were, a backward reset would put the release
     far in the future and keep the row from counting as having moved,
     which the blocked-line test needs: the rain would stall.) Returns the
     step of the pending release (the host's next_reneighbor), -1: none. */
  long long run_set_up(long long step)
  {
    if (!raining()) return -1;
    if (release_step >= 0 || rows == 0) release_step = step + 1;
    last_release_step = std::min(last_release_step, step);
    return release_step;
  }

  /* at the end of a step: whether to release on the next one (then
     pending_release() is that step), to stop because the line is blocked,
     or to wait */
  template <class Tag>
  StepVerdict end_of_step(long long step, int nlocal, const Tag *tag, double **x, double **v,
                          MPI_Comm world)
  {
    if (!raining() || release_step > step) return keep_waiting;
    const RowState state = last_row_state(step, nlocal, tag, x, v, world);
    if (state == row_blocked) return stop_blocked;
    if (state == row_falling) return keep_waiting;
    release_step = step + 1;
    return release_next_step;
  }

  /* row_fallen when every grain of the last row still present is `fall`
     below the line (a grain lost through a boundary no longer counts).
     row_blocked when one of them has not fallen so far but no longer
     moves down: it rests on the pile or bounced off it, so the pile has
     grown up to the line; without this the release would wait for ever.
     (A grain in free fall always has v_y < 0 at the end of a step after
     its release.) One MPI_Allreduce of two doubles. */
  template <class Tag>
  RowState last_row_state(long long step, int nlocal, const Tag *tag, double **x, double **v,
                          MPI_Comm world) const
  {
    if (rows == 0) return row_fallen;
    // highest y of the row, and 1 if a grain above the threshold does not fall
    double local[2] = { -std::numeric_limits<double>::max(), 0.0 };
    const double threshold = settings.line_height - settings.fall;
    const bool moved = step > last_release_step;
    for (int i = 0; i < nlocal; ++i) {
      if (tag[i] < last_row_first_tag || tag[i] > last_row_last_tag) continue;
      local[0] = std::max(local[0], x[i][1]);
      if (moved && x[i][1] > threshold && v[i][1] >= 0.0) local[1] = 1.0;
    }
    double global[2];
    MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, world);
    if (global[1] > 0.0) return row_blocked;
    return global[0] <= threshold ? row_fallen : row_falling;
  }

  /* in the host's pre_exchange: on the step of the pending release, the
     stop rules, then the next row, drawn (the same on every rank) and
     checked against the grains already there and their periodic images
     (`shifts`, periodic_image_shifts). present() is the host's count of
     the fix group (collective), uniform() its generator. */
  template <class Present, class Tag, class Uniform>
  Release release(long long step, Present present, int nlocal, const Tag *tag, double **x,
                  const double *radius, const std::vector<Shift> &shifts, Uniform uniform,
                  MPI_Comm world)
  {
    Release result;
    if (release_step != step) return result;
    release_step = -1;
    if (!raining()) return result;
    result.present = present();
    result.reason = stop_rule_before_release(result.present);
    if (result.reason != still_raining) {
      result.outcome = Release::stopped;
      return result;
    }
    long long largest_local = 0, largest = 0;
    for (int i = 0; i < nlocal; ++i)
      largest_local = std::max(largest_local, static_cast<long long>(tag[i]));
    MPI_Allreduce(&largest_local, &largest, 1, MPI_LONG_LONG, MPI_MAX, world);
    result.row = draw_row(largest, uniform);
    if (result.row.empty()) {
      result.outcome = Release::does_not_fit;
    } else if (row_overlaps_grains(result.row, nlocal, x, radius, shifts, world)) {
      result.outcome = Release::stopped;
      result.reason = line_blocked;
      result.row.clear();
    } else {
      result.outcome = Release::row_drawn;
    }
    return result;
  }

  /* before a release, given the grains of the fix group present now:
     records the sample and says whether a stop rule holds (still_raining
     if not) */
  StopReason stop_rule_before_release(int present)
  {
    present_at_release.push_back(present);
    while (present_at_release.size() > 2*static_cast<std::size_t>(settings.window))
      present_at_release.erase(present_at_release.begin());
    if (relative_growth() <= settings.tolerance) return stationary;
    if (settings.max_rows > 0 && rows >= settings.max_rows) return max_rows_reached;
    if (settings.max_grains > 0 && inserted + grains_per_row > settings.max_grains)
      return max_grains_reached;
    return still_raining;
  }

  /* the stop criterion: with n_k the grains present (in the fix group)
     just before release k, the mean of n over the last `window` releases
     exceeds the mean over the `window` releases before by at most
     `tolerance` times the newer mean. (While the rain runs at a constant
     rate, the grains in the air are a constant number of rows, so n is
     stationary when the number in the pile is.) */
  double relative_growth() const
  {
    const std::size_t n = present_at_release.size();
    const int window = settings.window;
    if (n < 2*static_cast<std::size_t>(window)) return std::numeric_limits<double>::infinity();
    double older = 0.0, newer = 0.0;
    for (int k = 0; k < window; ++k) {
      older += present_at_release[n - 2*window + k];
      newer += present_at_release[n - window + k];
    }
    if (!(newer > 0.0)) return std::numeric_limits<double>::infinity();
    return (newer - older)/newer;
  }

  /* the next row: diameters uniform in d(1 -+ p), then the gaps
     (rain_row.h); the same numbers on every rank. Tags continue after the
     largest tag in use (over all ranks) and never go back, so that a grain
     lost through a boundary never lends its tag to a new one. Empty when
     the grains do not fit on the line. */
  template <class Uniform>
  std::vector<Disc> draw_row(long long largest_tag_in_use, Uniform uniform)
  {
    next_tag = std::max(next_tag, largest_tag_in_use + 1);
    std::vector<double> diameters(grains_per_row), cuts(grains_per_row);
    for (int k = 0; k < grains_per_row; ++k)
      diameters[k] = settings.mean_diameter*(1.0 + settings.polydispersity*(2.0*uniform() - 1.0));
    for (int k = 0; k < grains_per_row; ++k) cuts[k] = uniform();
    const std::vector<double> centres =
      rain_row_centres(diameters, settings.line_lo, settings.line_hi, cuts);
    std::vector<Disc> row;
    if (centres.size() != diameters.size()) return row;
    row.resize(grains_per_row);
    for (int k = 0; k < grains_per_row; ++k) {
      row[k].tag = next_tag++;
      row[k].x = centres[k];
      row[k].diameter = diameters[k];
    }
    return row;
  }

  // the row has been created at `step`
  void released(const std::vector<Disc> &row, long long step)
  {
    rows += 1;
    inserted += static_cast<int>(row.size());
    last_row_first_tag = row.front().tag;
    last_row_last_tag = row.back().tag;
    last_release_step = step;
  }

  /* whether a grain of the row would overlap a grain already there (any
     group) or a periodic image of one (`shifts`): in a box periodic in x
     a row that reaches one side has the grains just across the other side
     as neighbours. Only grains or images whose centre is within a largest
     diameter of the line can overlap, and those are gathered on every
     rank. */
  bool row_overlaps_grains(const std::vector<Disc> &row, int nlocal, double **x,
                           const double *radius, const std::vector<Shift> &shifts,
                           MPI_Comm world) const
  {
    const double reach = settings.largest_diameter();
    std::vector<double> local;
    for (int i = 0; i < nlocal; ++i) {
      // the grain itself (n = -1), then its images
      for (int n = -1; n < static_cast<int>(shifts.size()); ++n) {
        const double centre_x = x[i][0] + (n < 0 ? 0.0 : shifts[n].d[0]);
        const double centre_y = x[i][1] + (n < 0 ? 0.0 : shifts[n].d[1]);
        const double margin = reach + radius[i];
        if (std::fabs(centre_y - settings.line_height) > margin ||
            centre_x < settings.line_lo - margin || centre_x > settings.line_hi + margin)
          continue;
        local.push_back(centre_x);
        local.push_back(centre_y);
        local.push_back(radius[i]);
      }
    }
    const std::vector<double> near = allgather(local, world);
    for (std::size_t k = 0; k + 2 < near.size(); k += 3)
      for (std::size_t n = 0; n < row.size(); ++n) {
        const double dx = row[n].x - near[k], dy = settings.line_height - near[k+1];
        const double contact = 0.5*row[n].diameter + near[k+2];
        if (dx*dx + dy*dy < contact*contact) return true;
      }
    return false;
  }

  // the rain stops for good; returns the line the hosts print
  std::string stop(StopReason reason, const std::string &fix_id, long long step, int present)
  {
    stop_reason = reason;
    release_step = -1;
    static const char *why[] = { "", "the number of grains present is stationary",
                                 "max_grains reached", "max_rows reached",
                                 "the pile has reached the release line" };
    std::ostringstream line;
    line << "fix insert/rain2d " << fix_id << ": release stopped at step " << step
         << ": " << why[reason] << "; " << rows << " rows, " << inserted
         << " grains inserted, " << present << " present\n";
    return line.str();
  }

  /* 0 grains inserted, 1 rows released, 2 stop reason (0 while raining;
     1 stationary, 2 max_grains, 3 max_rows, 4 line blocked), 3 grains
     present at the last release, 4 relative growth between the last two
     windows (-1 before two windows of releases) */
  double output(int index) const
  {
    switch (index) {
      case 0: return inserted;
      case 1: return rows;
      case 2: return stop_reason;
      case 3: return present_at_release.empty() ? 0.0 : present_at_release.back();
      case 4: {
        const double growth = relative_growth();
        return std::isfinite(growth) ? growth : -1.0;
      }
    }
    return 0.0;
  }

  /* restart data: the length of the list, the random state, the tag
     counter, rows and grains inserted, the stop reason, the last row's
     tags, the pending and the last release step (10 values), then the
     samples of n */
  std::vector<double> restart_list(int random_state) const
  {
    std::vector<double> list;
    list.push_back(0.0);                 // the length of the list, set below
    list.push_back(random_state);
    list.push_back(static_cast<double>(next_tag));
    list.push_back(rows);
    list.push_back(inserted);
    list.push_back(stop_reason);
    list.push_back(static_cast<double>(last_row_first_tag));
    list.push_back(static_cast<double>(last_row_last_tag));
    list.push_back(static_cast<double>(release_step));
    list.push_back(static_cast<double>(last_release_step));
    list.insert(list.end(), present_at_release.begin(), present_at_release.end());
    list[0] = static_cast<double>(list.size());
    return list;
  }

  // reads restart_list() back; returns the random state
  int read_restart_list(const double *list)
  {
    const int count = static_cast<int>(list[0]);
    next_tag = static_cast<long long>(list[2]);
    rows = static_cast<int>(list[3]);
    inserted = static_cast<int>(list[4]);
    stop_reason = static_cast<StopReason>(static_cast<int>(list[5]));
    last_row_first_tag = static_cast<long long>(list[6]);
    last_row_last_tag = static_cast<long long>(list[7]);
    release_step = static_cast<long long>(list[8]);
    last_release_step = static_cast<long long>(list[9]);
    present_at_release.assign(list + restart_scalars, list + count);
    return static_cast<int>(list[1]);
  }

 private:
  static const int restart_scalars = 10;

  // kept across restarts
  long long next_tag;          // tags are drawn here, never reused
  int rows;                    // rows released
  int inserted;                // grains inserted
  StopReason stop_reason;
  long long last_row_first_tag, last_row_last_tag;
  long long release_step;      // step of the pending release, -1: none
  long long last_release_step;
  std::vector<double> present_at_release;   // grains present before each release (last 2 windows)
};

}  // namespace rain2d
}  // namespace silokit

#endif
