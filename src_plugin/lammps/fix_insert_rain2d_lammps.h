/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix insert/rain2d for LAMMPS (a plugin style, loaded with `plugin load
   silokit_lammps.so`): rain deposition of polydisperse discs in 2D
   (Magalhaes et al. 2014), rows of grains released at rest on a
   horizontal line, the next row when the previous one has fallen a given
   distance, until the number of grains present is stationary; the same
   keywords, defaults, outputs and restart data as the LIGGGHTS fix of the
   same name. The keywords, schedule, stop rules, rows, outputs and
   restart data are core/rain2d_logic.h, shared with the LIGGGHTS fix.
   Documentation: doc/fix_insert_rain2d_lammps.md.
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_FIX_INSERT_RAIN2D_H
#define SILOKIT_LAMMPS_FIX_INSERT_RAIN2D_H

#include "fix.h"
#include "rain2d_logic.h"

#include <memory>
#include <vector>

namespace LAMMPS_NS {

class FixInsertRain2d : public Fix {
 public:
  FixInsertRain2d(class LAMMPS *, int, char **);
  ~FixInsertRain2d() override;
  int setmask() override;
  void setup(int) override;
  void end_of_step() override;
  void pre_exchange() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  // "radius": the largest radius this fix will create for a type, as fix
  // pour announces it, so that pair granular/jiang sizes its cutoff for
  // grains that do not exist yet at run set-up
  void *extract(const char *, int &) override;

 private:
  std::unique_ptr<silokit::rain2d::Rain> rain;
  std::unique_ptr<class RanPark> random;
  double announced_radius;     // what extract("radius") points to

  int grains_present() const;
  void create_owned_grains(const std::vector<silokit::rain2d::Disc> &row);
  void stop(silokit::rain2d::StopReason reason, int present);
};

}    // namespace LAMMPS_NS

#endif
