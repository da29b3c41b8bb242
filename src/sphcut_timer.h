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
// table), and may limit the adaptive time step: it reports its own limit, the fix takes the
// minimum over the styles, its own Courant limit and the ranks without knowing what each style
// computes.  On the host through dt_limit; under /kk through its slot (dt_slot) of the fix's
// device view of limits, which the style's own kernel writes, so that no style costs a host
// round trip of its own per step.
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
  // stable dt of this style's physics on this rank, for the Courant numbers of fix
  // sph/jc-thermal (1e300: no limit)
  virtual double dt_limit(double /*cfl*/, double /*thermal_cfl*/) const { return 1.0e300; }
  // 1: the slot dt_slot holds this style's limit of the current step (already scaled by the
  // Courant numbers, written by the style's own kernel on the device: /kk, see
  // FixSPHJCThermalKokkosBase::k_dtlim), and dt_limit returns 1e300 meanwhile; 0: dt_limit
  // gives the limit.  Asked each time the fix takes the minimum, so a style may switch (the
  // heat fix's slot holds the limit after its final_integrate, not at the setup of a run).
  virtual int dt_limit_on_device() const { return 0; }
  // this style's slot in the /kk fix's device view of limits, given by the fix at attach (-1: none)
  int dt_slot = -1;
  // a style whose physics starts from the particles' temperatures (heat conduction) gives its
  // name for the message that particles without an initial temperature start at their
  // material's Tref (fix sph/jc-thermal, no keyword temp); empty: the style does not care
  virtual std::string starts_from_temperature() const { return ""; }
  // whether this style's end_of_step (if it has one) may read or change the particles' data
  // (positions, velocities, the state) or evaluate user variables: fix sph/jc-thermal/kk then
  // finishes its corrector at each such step instead of leaving it to the next step's first half
  virtual bool end_of_step_reads_particles() const { return true; }
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
