/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix clog: detects that the flow through the outlet has stopped, finds
   the clogging arch (Hidalgo et al. 2013, section 3; src_plugin/core/arch_walk.h),
   writes the records of doc/silo2d_records.md, then raises a flag the deck
   stops on, or breaks the arch and waits for the next clog.
   Documentation: doc/fix_clog.md.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS

FixStyle(clog,FixClog)

#else

#ifndef LMP_FIX_CLOG_H
#define LMP_FIX_CLOG_H

#include "fix.h"
#include "clog_logic.h"
#include "silokit_clock.h"
#include <cstdio>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixClog : public Fix {
 public:
  FixClog(class LAMMPS *, int, char **);
  ~FixClog();
  int setmask();
  void post_create();
  void pre_delete(bool unfixflag);
  void init();
  void setup(int);
  void end_of_step();
  double compute_vector(int);
  void write_restart(FILE *);
  void restart(char *);

 private:
  // the keywords, the stop criterion, the records: core/clog_logic.h
  silokit::clog::Settings settings;
  class FixReinject *reinject;
  bool own_contacts_compute;   // created by this fix (else the user's)
  class ComputePairGranLocal *contacts;
  // the silo's axes (x horizontal, vertical y or z), the groups, gravity
  silokit::clog::Scene scene;

  // state, kept across restarts; times are those of `clock`
  silokit::clog::Attempts attempts;
  // LIGGGHTS 3.8 restarts its time at 0 after read_restart
  // (doc/liggghts_quirks.md): the fix keeps the time of the whole run
  silokit::RestartClock clock;

  bool restored;               // state read from a restart file
  silokit::clog::Records records;

  double simulated_time() const;
  void open_records();
  silokit::clog::Atoms<int> local_atoms() const;
  std::vector<silokit::ContactSample> local_contacts();
};

}

#endif
#endif
