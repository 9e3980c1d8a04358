/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix insert/rain2d: rain deposition of polydisperse discs in 2D
   (Magalhaes et al. 2014): rows of grains released at rest on a horizontal
   line, the next row when the previous one has fallen a given distance,
   until the number of grains present is stationary.
   Documentation: doc/fix_insert_rain2d.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(insert/rain2d,FixInsertRain2d)

#else

#ifndef LMP_FIX_INSERT_RAIN2D_H
#define LMP_FIX_INSERT_RAIN2D_H

#include "fix.h"
#include <memory>
#include <vector>

namespace LAMMPS_NS {

class RanPark;

class FixInsertRain2d : public Fix {
 public:
  FixInsertRain2d(class LAMMPS *, int, char **);
  ~FixInsertRain2d();
  int setmask();
  void init();
  void setup(int);
  void end_of_step();
  void pre_exchange();
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);
  // LIGGGHTS checks that the atom types in use start at 1: the grains this
  // fix will create count as in use before they exist
  int min_type() { return grain_type; }
  int max_type() { return grain_type; }
  // pair gran sizes its neighbor cutoff from the largest radius present at
  // init and the one insertion fixes announce: grains raining later must
  // be counted, or their contacts are found only after deep overlap
  double max_rad(int type);
  double min_rad(int type);

  // why the release stopped (output 3 > 0); the values are part of the doc
  enum StopReason { still_raining = 0, stationary = 1, max_grains_reached = 2,
                    max_rows_reached = 3, line_blocked = 4 };

 private:
  struct Disc { int tag; double x, diameter; };

  // settings
  int grain_type;
  double mean_diameter;
  double polydispersity;       // diameters uniform in mean*(1 -+ polydispersity)
  double density;              // mass = pi r^2 density (LIGGGHTS' 2D mass)
  double line_lo, line_hi;     // the row spans [line_lo, line_hi] along x ...
  double line_height;          // ... with the centres at y = line_height
  double fill;                 // sum of diameters / row length
  double fall;                 // a row is released when the previous one has fallen this much
  int window;                  // stationarity: rows per averaging window
  double tolerance;            // stationarity: allowed relative growth between windows
  int max_grains;              // 0: no limit
  int max_rows;                // 0: no limit

  // state, kept across restarts
  std::unique_ptr<RanPark> random;
  int next_tag;                // tags are drawn here, never reused
  int rows;                    // rows released
  int inserted;                // grains inserted
  StopReason stop_reason;
  int last_row_first_tag, last_row_last_tag;
  bigint release_step;         // step of the pending release, -1: none
  bigint last_release_step;
  std::vector<double> present_at_release;   // grains present before each release (last 2 windows)

  int grains_per_row;

  void parse_arguments(int narg, char **arg);
  enum RowState { row_falling, row_fallen, row_blocked };
  RowState last_row_state() const;
  int grains_present() const;
  double relative_growth() const;
  std::vector<Disc> draw_row();
  bool row_overlaps_grains(const std::vector<Disc> &row) const;
  void create_owned_grains(const std::vector<Disc> &row);
  void stop(StopReason reason, int present);
};

}

#endif
#endif
