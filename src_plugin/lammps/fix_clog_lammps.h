/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix clog for LAMMPS (a plugin style, loaded with `plugin load
   silokit_lammps.so`): detects that the flow through the outlet has
   stopped, finds the clogging arch (core/arch_walk.h), writes the records
   of doc/silo2d_records.md, then stops the run as LAMMPS' fix halt does,
   or breaks the arch through fix reinject and waits for the next clog: the
   LIGGGHTS fix of the same name, with the same keywords (but `contacts`),
   outputs and records. The keywords, the stop criterion, the gathering,
   the walk and the records are core/clog_logic.h, shared with the
   LIGGGHTS fix; the contacts come from pair_style granular/jiang.
   Documentation: doc/fix_clog_lammps.md.
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_FIX_CLOG_H
#define SILOKIT_LAMMPS_FIX_CLOG_H

#include "fix.h"
#include "clog_logic.h"
#include "silokit_clock.h"

namespace LAMMPS_NS {

class FixClog : public Fix {
 public:
  FixClog(class LAMMPS *, int, char **);
  ~FixClog() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void end_of_step() override;
  void post_run() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

 private:
  silokit::clog::Settings settings;   // the keywords
  class FixReinject *reinject;
  class PairGranularJiang *pair;       // gives the contacts at a clog
  // the silo's axes (x horizontal, vertical y or z), the groups, gravity
  silokit::clog::Scene scene;

  // the attempts and counts (core/clog_logic.h) and our own clock (LAMMPS
  // 20220106 keeps no time in restart files); kept across restarts
  silokit::clog::Attempts attempts;
  silokit::StepClock clock;

  bool restored;                       // state read from a restart file: append to the records
  bool halted;                         // this fix ended the current run (fix halt's timeout)
  silokit::clog::Records records;

  double simulated_time() const;
  void open_records();
  silokit::clog::Atoms<tagint> local_atoms() const;
  void halt_run(const char *why);
};

}    // namespace LAMMPS_NS

#endif
