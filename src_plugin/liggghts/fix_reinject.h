/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix reinject: grains that fall below the outlet re-enter at the top of
   the silo at a free spot, at rest, and are counted (flow rate, avalanche
   size). Documentation: doc/fix_reinject.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(reinject,FixReinject)

#else

#ifndef LMP_FIX_REINJECT_H
#define LMP_FIX_REINJECT_H

#include "fix.h"
#include "reinject_logic.h"
#include "silokit_clock.h"
#include "silokit_record.h"
#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class RanPark;

class FixReinject : public Fix {
 public:
  FixReinject(class LAMMPS *, int, char **);
  ~FixReinject();
  int setmask();
  void init();
  void setup(int);
  void end_of_step();
  void pre_exchange();
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);

  // for fix clog: closes the current avalanche, returns its size (grains)
  int close_avalanche();
  // for fix clog: the grains with these tags re-enter at the top on the
  // next step, like grains that left, but are not counted as out. Every
  // rank must pass the same tags.
  void request_reinjection(const std::vector<int> &tags);
  int vertical_axis() const { return settings.axis; }

 private:
  silokit::reinject::Settings settings;   // the keywords
  class Region *region;        // where grains re-enter
  std::unique_ptr<RanPark> random;
  silokit::RecordFile record;  // one line per step with re-entries (rank 0)
  bool restored;               // state read from a restart file: append to the record

  // counts, tags to re-enter for fix clog, flow-rate samples
  // (core/reinject_logic.h); kept across restarts
  silokit::reinject::State state;
  // LIGGGHTS 3.8 restarts its time at 0 after read_restart
  // (doc/liggghts_quirks.md): the fix keeps the time of the whole run
  silokit::RestartClock clock;

  double simulated_time() const;
  bool is_leaver(int i) const;
  void send_to_owners();
  void open_record_file();
};

}

#endif
#endif
