/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   fix reinject for LAMMPS (a plugin style, loaded with `plugin load
   silokit_lammps.so`): grains that fall below the outlet re-enter at the
   top of the silo at a free spot, at rest, and are counted (flow rate,
   avalanche size), as the LIGGGHTS fix of the same name does, with the
   same keywords, outputs and record file. The placement, counts, flow
   rate, record lines and restart data are core/reinject_logic.h, shared
   with the LIGGGHTS fix. Spheres only.
   Documentation: doc/fix_reinject_lammps.md.
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_FIX_REINJECT_H
#define SILOKIT_LAMMPS_FIX_REINJECT_H

#include "fix.h"
#include "reinject_logic.h"
#include "silokit_clock.h"
#include "silokit_record.h"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixReinject : public Fix {
 public:
  FixReinject(class LAMMPS *, int, char **);
  ~FixReinject() override;
  int setmask() override;
  void init() override;
  void end_of_step() override;
  void pre_exchange() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;

  // for fix clog: closes the current avalanche, returns its size (grains)
  int close_avalanche();
  // for fix clog: the grains with these tags re-enter at the top on the
  // next step, like grains that left, but are not counted as out. Every
  // rank must pass the same tags.
  void request_reinjection(const std::vector<int> &tags);
  int vertical_axis() const { return settings.axis; }

  // the simulated time of the whole simulation, across restarts
  double simulated_time() const;

 private:
  silokit::reinject::Settings settings;   // the keywords
  class Region *region;        // where grains re-enter
  std::unique_ptr<class RanPark> random;
  silokit::RecordFile record;  // one line per step with re-entries (rank 0)
  bool restored;               // state read from a restart file: append to the record

  // counts, tags to re-enter for fix clog, flow-rate samples
  // (core/reinject_logic.h); kept across restarts
  silokit::reinject::State state;
  // our own clock (LAMMPS 20220106 keeps no time in restart files)
  silokit::StepClock clock;

  bool is_leaver(int i) const;
  void send_to_owners(const std::map<int, silokit::reinject::Sphere> &spots);
  void open_record_file();
};

}    // namespace LAMMPS_NS

#endif
