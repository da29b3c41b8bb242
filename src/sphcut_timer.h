/* -*- c++ -*- ----------------------------------------------------------
   sphcut - per-style wall-clock timers: every sphcut style adds the time
   of its work to its own cpu_time; fix sph/jc-thermal prints the table at
   the end of each run, so a user sees what each piece of physics costs.
------------------------------------------------------------------------- */

#ifndef SPHCUT_TIMER_H
#define SPHCUT_TIMER_H

#include "pointers.h"

#include <mpi.h>

#include <string>
#include <type_traits>

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

// a sphcut style attached to fix sph/jc-thermal: it attaches itself in its init
// (FixSPHJCThermal::attach), adds the wall time of its work to cpu_time (a row of the timing
// table), and may limit the adaptive time step (dt_limit: this rank's limit, the fix takes the
// minimum over the styles and ranks)
class AttachedStyle {
 public:
  // the same exception specification as LAMMPS' Pointers::~Pointers(), which the styles' other
  // base (Fix, Pair, Compute) derives from: implicit noexcept up to LAMMPS 29Sep2021, declared
  // noexcept(false) in newer versions (4Feb2025, 4Jul2026: errors may be thrown from
  // destructors).  Were the two bases to differ, the implicit specification of a style's
  // destructor would be looser than that of the base destructor it overrides, a compile error
  // (tools/compat-check.sh compiles the sources against those versions' headers).
  // Taken from the type, not a version number, so it follows LAMMPS wherever it changes.
  virtual ~AttachedStyle() noexcept(std::is_nothrow_destructible<LAMMPS_NS::Pointers>::value) {}
  virtual std::string timing_name() const = 0;
  // stable dt of this style's physics for the Courant numbers of fix sph/jc-thermal
  virtual double dt_limit(double /*cfl*/, double /*thermal_cfl*/) const { return 1.0e300; }
  // 1: the style writes its limit (already scaled by the Courant numbers) into the device view
  // FixSPHJCThermalKokkosBase::k_dtlim each step instead (/kk, no host round trip), and
  // dt_limit returns 1e300
  virtual int dt_limit_on_device() const { return 0; }
  double cpu_time = 0.0;
};

// the owner of the per-atom state (fix sph/jc-thermal) as the pair style sees it: the state
// rows (sphcut::StateLayout columns), the groups that give a particle its role, and the timing
// table to attach to.  The pair style reaches the fix through this, not through the fix's class
// (the model, which the pair owns, is read the other way: sphcut::find_model, sphcut_model.h).
class StateOwner {
 public:
  // the exception specification of LAMMPS' Pointers::~Pointers(), as AttachedStyle's
  virtual ~StateOwner() noexcept(std::is_nothrow_destructible<LAMMPS_NS::Pointers>::value) {}
  virtual void attach(AttachedStyle *style) = 0;
  double **state = nullptr;    // per-atom state, one row per atom (local and ghost)
  int solidbit = 0;            // group bit of the SPH solid (the fix's group)
  int toolbit = 0, clampbit = 0;    // group bits of the tool and clamped particles
};

}    // namespace sphcut

#endif
