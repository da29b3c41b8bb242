/* -*- c++ -*- ----------------------------------------------------------
   sphcut - per-style wall-clock timers: every sphcut style adds the time
   of its work to its own cpu_time; fix sph/jc-thermal prints the table at
   the end of each run, so a user sees what each piece of physics costs.
------------------------------------------------------------------------- */

#ifndef SPHCUT_TIMER_H
#define SPHCUT_TIMER_H

#include <mpi.h>

#include <string>

namespace sphcut {

class ScopedTimer {
 public:
  explicit ScopedTimer(double &acc) : acc_(acc), t0_(MPI_Wtime()) {}
  ~ScopedTimer() { acc_ += MPI_Wtime() - t0_; }
  ScopedTimer(const ScopedTimer &) = delete;
  ScopedTimer &operator=(const ScopedTimer &) = delete;

 private:
  double &acc_;
  double t0_;
};

// a sphcut style with a row in the timing table: it attaches itself to fix sph/jc-thermal
// in its init (FixSPHJCThermal::attach) and adds the wall time of its work to cpu_time
class TimedStyle {
 public:
  virtual ~TimedStyle() = default;
  virtual std::string timing_name() const = 0;
  double cpu_time = 0.0;
};

}    // namespace sphcut

#endif
