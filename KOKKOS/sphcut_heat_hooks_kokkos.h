/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the hooks of fix heat/fmfs/kk in the fused kernels of fix
   sph/jc-thermal/kk (sphcut_hooks_kokkos.h): its temperature rules
   (sphcut_heat_rules.h) and its thermal dt limit, applied to each particle
   in the integrator's own passes, so that the heat fix runs no kernel of its
   own on a step without an evaluation:
     after the first half   the Dirichlet groups' predicted temperature
                            (HeatPredictHook)
     before the corrector   the held rate HELD into the temperature rate
     after the corrector    the Dirichlet groups back to their temperature,
                            the heat that takes summed, and with an adaptive
                            step the thermal dt limit over the group
                            (HeatCorrectorHook: two values of the
                            corrector's reduction, whose final writes them
                            into the heat fix's own accumulator and its own
                            dt slot)
   The heat fix fills them (FixHeatFMFSKokkos::arm_hooks) each time the
   integrator builds one of its kernels.
------------------------------------------------------------------------- */

#ifndef SPHCUT_HEAT_HOOKS_KOKKOS_H
#define SPHCUT_HEAT_HOOKS_KOKKOS_H

#include "kokkos_type.h"
#include "sphcut_heat_rules.h"
#include "sphcut_kokkos.h"
#include "sphcut_material.h"
#include "sphcut_thermal.h"

#include <string>
#include <vector>

namespace sphcut {

// the Dirichlet table of the heat rules (group bits, temperatures; sphcut::dirichlet_index) on the
// device, one element more than given, so that the views are never empty
template <class DeviceType>
void dirichlet_to_device(std::vector<int> bits, std::vector<double> temps, const std::string &name,
                         Kokkos::View<int *, typename DeviceType::memory_space> &d_bits,
                         Kokkos::View<double *, typename DeviceType::memory_space> &d_temps)
{
  bits.push_back(0);
  temps.push_back(0.0);
  d_bits = to_device<int, DeviceType>(bits.data(), (int) bits.size(), (name + ":dirbit").c_str());
  d_temps = to_device<double, DeviceType>(temps.data(), (int) temps.size(), (name + ":dirtemp").c_str());
}

// the heat fix's rules as both hooks read them: its group and its nd Dirichlet groups (dbit, dtemp)
template <class DeviceType> struct HeatRulesView {
  typedef typename DeviceType::memory_space mem;
  int gb = 0, nd = 0;
  Kokkos::View<const int *, mem> dbit;
  Kokkos::View<const double *, mem> dtemp;
};

// after the first half: a Dirichlet particle's predicted temperature (TEMP_F) is its group's
template <class DeviceType> struct HeatPredictHook {
  int active = 0;           // 0: no Dirichlet group (the integrator skips it)
  HeatRulesView<DeviceType> rules;
  KOKKOS_INLINE_FUNCTION void operator()(const int mask, double *s) const
  {
    hold_predicted_temperature(mask, rules.gb, &rules.dbit(0), &rules.dtemp(0), rules.nd, s);
  }
};

// before and after the corrector: the held rate, the Dirichlet groups and the thermal dt limit.
// Its NVALUES values of the corrector's reduction: QDIR the Dirichlet heat (a sum), DT_LIM the
// thermal limit (a minimum)
template <class DeviceType> struct HeatCorrectorHook {
  typedef typename DeviceType::memory_space mem;
  enum { QDIR = 0, DT_LIM = 1, NVALUES = 2 };
  int active = 0;                  // 0: no heat fix (the integrator skips it)
  HeatRulesView<DeviceType> rules;    // (rules.gb: the group whose held rate joins)
  int want_lim = 0, every = 1;     // the thermal limit this step (thermal Courant number F, sub-cycling)
  double F = 0.0;
  Kokkos::View<const double *, mem> h;    // smoothing length per type
  typename ArrayTypes<DeviceType>::t_double_1d qacc;    // the heat fix's accumulator of the Dirichlet heat
  typename ArrayTypes<DeviceType>::t_double_1d slot;    // the heat fix's dt slot (want_lim)
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int k) { return k == DT_LIM; }
  KOKKOS_INLINE_FUNCTION void before_corrector(const int mask, double *s) const
  {
    if (mask & rules.gb) add_held_rate(s);
  }
  // particle of mask and type, mass m, material mt, right after its corrector; r: the hook's values
  KOKKOS_INLINE_FUNCTION void after_corrector(const int mask, const int type, const double m, const Material &mt,
                                              double *s, double *r) const
  {
    const HeatRulesView<DeviceType> &d = rules;
    if (d.nd) r[QDIR] += hold_corrected_temperature(mask, d.gb, &d.dbit(0), &d.dtemp(0), d.nd, m * mt.cp, s);
    if (want_lim && (mask & d.gb))
      thermal_dt_min(mask, d.gb, s[StateLayout::RHO], mt.cp, mt.kappa, h(type), F, every, r[DT_LIM]);
  }
  KOKKOS_INLINE_FUNCTION void final(const double *r) const
  {
    if (rules.nd) qacc(0) += r[QDIR];
    if (want_lim) slot(0) = r[DT_LIM];
  }
};

}    // namespace sphcut

#endif
