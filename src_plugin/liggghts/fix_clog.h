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
#include "silokit_clock.h"
#include "silokit_record.h"
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
  };

  // settings
  std::string reinject_id;
  class FixReinject *reinject;
  std::string base_group_id;
  int base_groupbit;
  double orifice_centre;       // horizontal (x) coordinate of the middle of the outlet
  double bottom;               // height of the silo bottom surface
  double quiet_time;           // no exit for this long, and ...
  double energy_ratio;         // ... Ec/Ep below this: the flow has stopped
  double max_time;             // an attempt longer than this is "no clog" (0: no limit)
  bool break_arches;           // action break (else stop)
  int arches_wanted;           // action break: done after this many arches
  std::string directory;
  std::string contacts_id;     // the compute pair/gran/local read at a clog
  bool own_contacts_compute;   // created by this fix (else the user's)
  class ComputePairGranLocal *contacts;
  int vertical;                // 1 (y) or 2 (z): gravity along -vertical
  int off_plane;               // the third axis
  double gravity;              // magnitude of the acceleration along -vertical

  // state, kept across restarts; times are those of `clock`
  int attempts;                // rows written to clogs.txt
  int arches_found;            // rows with status 1
  bool done;                   // the deck may stop
  double attempt_start;        // time the current attempt began
  double last_exit_time;       // time the exit count last changed
  double last_grains_out;
  // LIGGGHTS 3.8 restarts its time at 0 after read_restart
  // (doc/liggghts_quirks.md): the fix keeps the time of the whole run
  silokit::RestartClock clock;

  double last_ratio;           // Ec/Ep at the last check
  bool restored;               // state read from a restart file
  silokit::RecordFile clogs_file, arches_file, feet_file, contacts_file;

  double simulated_time() const;
  void parse_arguments(int narg, char **arg);
  void open_records();
  silokit::RecordFile open_record(const char *name, const char *header);
  double kinetic_to_potential_ratio() const;
  void end_attempt(double now);
  std::vector<GrainRecord> gather_grains() const;
  std::vector<ContactRecord> gather_contacts(const std::vector<GrainRecord> &grains);
  Outcome identify_arch(const std::vector<GrainRecord> &grains,
                        const std::vector<ContactRecord> &contacts) const;
  std::vector<int> grains_over_orifice(const std::vector<GrainRecord> &grains) const;
  void write_records(const Outcome &outcome, int avalanche,
                     const std::vector<GrainRecord> &grains,
                     const std::vector<ContactRecord> &contacts);
  void report(const Outcome &outcome, int avalanche);
};

}

#endif
#endif
