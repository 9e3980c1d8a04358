/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

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

// LAMMPS 20220106 does not store the simulated time in restart files
// either: after read_restart its time reads 0 at the restart's step
// (doc/lammps_host.md, section 5.4). A LAMMPS fix that keeps times holds a
// StepClock: the time base_time at step base_step, then dt per step. It
// writes the three to its restart data and reads them back, so that a
// continued run computes each time with the same operations as the
// uninterrupted one; when dt changes between runs (the timestep command)
// the clock goes on from the time reached with the old one.
class StepClock {
 public:
  StepClock() : base_time(0.0), base_step(0), step_dt(0.0) {}

  void start(double time, long long step, double dt)
  {
    base_time = time;
    base_step = step;
    step_dt = dt;
  }

  double time(long long step) const { return base_time + (step - base_step)*step_dt; }

  // a run with time step dt is set up at `step`
  void use_time_step(long long step, double dt)
  {
    if (dt != step_dt) start(time(step), step, dt);
  }

  // three values for restart data
  void write(double *values) const
  {
    values[0] = base_time;
    values[1] = static_cast<double>(base_step);
    values[2] = step_dt;
  }
  void read(const double *values)
  {
    start(values[0], static_cast<long long>(values[1]), values[2]);
  }

 private:
  double base_time;
  long long base_step;
  double step_dt;
};

}  // namespace silokit

#endif
