/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the hooks of fix sph/jc-thermal/kk's fused kernels: per-particle
   device work of other /kk styles that the integrator runs inside its own
   passes over the particles (no kernel of theirs, no pass of their own over
   the state rows), without knowing what it does.

   Kokkos device code cannot call virtual functions, so a hook is a small
   device-copyable functor of its style (defined in the style's own header)
   held by value in a slot of the aggregate below, which the integrator's
   kernels carry and call at fixed points:
     after_first_half(i, mask, s)   after particle i's kick, drift, predictor
                                    and the rates zeroed, on its state row s
                                    (every local particle)
     before_corrector(i, mask, s)   before particle i's corrector (every local
                                    particle).  Where the corrector waits for
                                    the next step's first half (one kernel for
                                    both), a hook that reads other particles'
                                    data must read none that kernel writes:
                                    the tool-heat gather reads the contact
                                    particles' positions from the contact
                                    fix's qtw rows, not x
     after_corrector(i, mask, type, m, mt, s, r)
                                    right after the corrector of a particle of
                                    the integrator's group (mass m, material
                                    mt); r: the hooks' values of the
                                    corrector's reduction (NVALUES, is_min),
                                    whose final hands them to the hooks'
                                    final (their own views: an accumulator, a
                                    dt slot), on the device
   The slots and who fills them:
     HOOK_HEAT       fix heat/fmfs/kk: its temperature rules and thermal dt
                     limit (sphcut_heat_hooks_kokkos.h)
     HOOK_TOOL_HEAT  fix contact/tri-penalty/kk: the tool particles' share of
                     the friction heat (ToolHeatGather, sphcut_tool_heat_kokkos.h)
     HOOK_ROWS       pair sph/jc-thermal/kk: the local particles' packed rows
                     (RowPacker, sphcut_row_packer_kokkos.h)
   A style takes its slot through sphcut::HookHost::set_hook (the integrator
   derives from HookHost) in its init, with an arm callback on the host: each
   time the integrator builds one of its kernels it calls every arm with the
   pass (HookCall), and the arm fills its style's slot for that pass or leaves
   it inactive (the hooks' arguments, the style's own views, the step it ran:
   the style knows from that when its hook ran).
------------------------------------------------------------------------- */

#ifndef SPHCUT_HOOKS_KOKKOS_H
#define SPHCUT_HOOKS_KOKKOS_H

#include "lmptype.h"
#include "pointers.h"
#include "sphcut_heat_hooks_kokkos.h"
#include "sphcut_row_packer_kokkos.h"
#include "sphcut_timer.h"
#include "sphcut_tool_heat_kokkos.h"

#include <functional>
#include <type_traits>
#include <typeinfo>
#include <vector>

namespace sphcut {

enum HookSlot { HOOK_HEAT = 0, HOOK_TOOL_HEAT, HOOK_ROWS, NHOOK_SLOTS };

// the hooks of the first-half kernel, in the order it calls them
template <class DeviceType> struct FirstHalfHooks {
  HeatPredictHook<DeviceType> heat;
  RowPacker<DeviceType> rows;
  KOKKOS_INLINE_FUNCTION void after_first_half(const int i, const int mask, double *s) const
  {
    if (heat.active) heat(mask, s);
    if (rows.active) rows(i, s);
  }
};

// the hooks of the corrector's kernel, in the order it calls them, and their values of its reduction
template <class DeviceType> struct CorrectorHooks {
  ToolHeatGather<DeviceType> tool_heat;
  HeatCorrectorHook<DeviceType> heat;
  enum { NVALUES = HeatCorrectorHook<DeviceType>::NVALUES };
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int k) { return HeatCorrectorHook<DeviceType>::is_min(k); }
  KOKKOS_INLINE_FUNCTION void before_corrector(const int i, const int mask, double *s) const
  {
    if (tool_heat.active) tool_heat(i, s);
    if (heat.active) heat.before_corrector(mask, s);
  }
  KOKKOS_INLINE_FUNCTION void after_corrector(const int, const int mask, const int type, const double m,
                                              const Material &mt, double *s, double *r) const
  {
    if (heat.active) heat.after_corrector(mask, type, m, mt, s, r);
  }
  KOKKOS_INLINE_FUNCTION void final(const double *r) const
  {
    if (heat.active) heat.final(r);
  }
};

template <class DeviceType> struct IntegratorHooks {
  FirstHalfHooks<DeviceType> first_half;
  CorrectorHooks<DeviceType> corrector;
};

// what the integrator tells the arms when it builds a kernel
struct HookCall {
  enum Pass { FIRST_HALF, CORRECTOR };
  Pass pass;
  LAMMPS_NS::bigint step;    // the step whose pass it is (a corrector left pending: the step before)
  int want_dt;               // the corrector of a step whose dt limits the host reads (adaptive dt)
  int kept_to_force;         // first half: no other fix changes the atoms' data between this pass and
                             // the forces of the step (a packed row stays valid)
};

template <class DeviceType> using HookArm = std::function<void(IntegratorHooks<DeviceType> &, const HookCall &)>;

// the integrator's side: the slots' owners and arms, host only
class HookHost {
 public:
  // the exception specification of LAMMPS' Pointers::~Pointers(), as sphcut::AttachedStyle's
  virtual ~HookHost() noexcept(std::is_nothrow_destructible<LAMMPS_NS::Pointers>::value) {}
  // owner's hook in slot (arm: see the header); called again in each init, the last arm stays.
  // False (nothing set) where the integrator's kernels run on another device type, or another
  // style that still exists holds the slot: the style then does its work in a kernel of its own
  template <class DeviceType> bool set_hook(const AttachedStyle *owner, HookSlot slot, HookArm<DeviceType> arm)
  {
    if (!hook_type || *hook_type != typeid(IntegratorHooks<DeviceType>)) return false;
    Entry &e = entries[slot];
    if (e.owner && e.owner != owner && hook_owner_alive(e.owner)) return false;
    e.owner = owner;
    e.arm = [arm](void *h, const HookCall &c) { arm(*static_cast<IntegratorHooks<DeviceType> *>(h), c); };
    return true;
  }

 protected:
  const std::type_info *hook_type = nullptr;    // IntegratorHooks of the integrator's device type
  virtual bool hook_owner_alive(const AttachedStyle *owner) const = 0;
  // the hooks of a pass: every slot's arm called
  template <class DeviceType> IntegratorHooks<DeviceType> arm_hooks(const HookCall &c) const
  {
    IntegratorHooks<DeviceType> h;
    for (const Entry &e : entries)
      if (e.owner) e.arm(&h, c);
    return h;
  }
  // the slots of styles that no longer exist (deleted between runs) freed
  void prune_hooks(const std::vector<AttachedStyle *> &live)
  {
    for (Entry &e : entries) {
      bool found = false;
      for (auto *st : live) found = found || st == e.owner;
      if (!found) e = Entry();
    }
  }

 private:
  struct Entry {
    const AttachedStyle *owner = nullptr;
    std::function<void(void *, const HookCall &)> arm;
  };
  Entry entries[NHOOK_SLOTS];
};

}    // namespace sphcut

#endif
