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
#include "rain2d_logic.h"
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
  int min_type() { return rain->settings.grain_type; }
  int max_type() { return rain->settings.grain_type; }
  // pair gran sizes its neighbor cutoff from the largest radius present at
  // init and the one insertion fixes announce: grains raining later must
  // be counted, or their contacts are found only after deep overlap
  double max_rad(int type);
  double min_rad(int type);

 private:
  // the keywords, schedule, stop rules, rows, outputs and restart data
  // (core/rain2d_logic.h, shared with the LAMMPS fix)
  std::unique_ptr<silokit::rain2d::Rain> rain;
  std::unique_ptr<RanPark> random;

  int grains_present() const;
  void create_owned_grains(const std::vector<silokit::rain2d::Disc> &row);
  void stop(silokit::rain2d::StopReason reason, int present);
};

}

#endif
#endif
