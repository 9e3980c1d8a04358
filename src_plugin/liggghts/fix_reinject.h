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
#include "silokit_clock.h"
#include "silokit_record.h"
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <set>
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
  int vertical_axis() const { return axis; }

 private:
  struct Sphere { double x[3]; double radius; };
  struct Leaver { int tag; double radius; double mass; bool left_through_exit; };

  int axis;                    // 0, 1, 2: the vertical axis (gravity along -axis)
  double exit_coordinate;      // a grain whose centre is below this has left
  std::string region_id;
  class Region *region;        // where grains re-enter
  std::unique_ptr<RanPark> random;
  int max_attempts;
  double rate_window;          // time over which the flow rate is averaged
  std::string file_name;       // of the record, empty without 'file'
  silokit::RecordFile record;  // one line per check with exits (rank 0)
  bool restored;               // state read from a restart file: append to the record
  std::set<int> requested;     // tags to re-enter without being counted

  // counts, kept across restarts
  double grains_out;
  double mass_out;
  double avalanche;
  // LIGGGHTS 3.8 restarts its time at 0 after read_restart
  // (doc/liggghts_quirks.md): the fix keeps the time of the whole run
  silokit::RestartClock clock;

  // (time, grains_out, mass_out) at recent checks, for the flow rate
  struct Sample { double time, grains, mass; };
  std::deque<Sample> samples;

  double simulated_time() const;
  bool is_leaver(int i) const;
  bool is_requested(int i) const;
  int count_local_leavers() const;
  std::vector<Leaver> gather_leavers() const;
  std::vector<Sphere> gather_spheres_near_region(double margin) const;
  bool find_free_spot(double radius, const std::vector<Sphere> &occupied, double *spot);
  void move_local_grains(const std::map<int, Sphere> &spots);
  void open_record_file();
  void record_sample();
  double rate(bool of_mass) const;
  void parse_arguments(int narg, char **arg);
};

}

#endif
#endif
