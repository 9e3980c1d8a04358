/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The simulated time of a whole simulation, across restarts, for the
   silokit fixes that keep or compare times.
------------------------------------------------------------------------- */

#ifndef SILOKIT_CLOCK_H
#define SILOKIT_CLOCK_H

namespace silokit {

// LIGGGHTS 3.8 does not store the simulated time in restart files: after
// read_restart its time reads step x dt until the first run, whose set-up
// (Integrate::init) starts it again at 0 (doc/liggghts_quirks.md).
//
// A fix that keeps times holds a RestartClock and
//  - writes time() to its restart data (Fix::write_restart),
//  - hands that value to restored() when it is defined again after
//    read_restart (Fix::restart),
//  - calls run_set_up() from Fix::setup, at the start of every run.
// time() is then the time of the whole simulation: LIGGGHTS' time plus the
// time reached when the restart file was written; between read_restart and
// the first run, that time alone (step x dt need not be the time the
// restored runs reached: the time step may have changed, or they may have
// started from a restart file themselves).
class RestartClock {
 public:
  RestartClock() : time_before_restart(0.0), restored_before_run(false) {}

  // the simulated time, given LIGGGHTS' (update->get_cur_time())
  double time(double liggghts_time) const
  {
    return restored_before_run ? time_before_restart : time_before_restart + liggghts_time;
  }

  // the time() written to the restart file that was read
  void restored(double time_reached)
  {
    time_before_restart = time_reached;
    restored_before_run = true;
  }

  // a run is being set up; the first after read_restart has set
  // LIGGGHTS' time to 0 in its Integrate::init
  void run_set_up() { restored_before_run = false; }

 private:
  double time_before_restart;  // time() written to the restart file read, 0 without one
  bool restored_before_run;    // restored, no run since: LIGGGHTS' time still reads step x dt
};

}  // namespace silokit

#endif
