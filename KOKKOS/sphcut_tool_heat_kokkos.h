/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the tool's share of the friction heat on the device: the tool
   SPH particles of the heat group take it from the contact particles
   among their non-tool neighbours, kernel weighted (seed 000's
   NeibContTherm, seen from the tool particle; the CPU fix scatters it from
   the contact particle).  Fix contact/tri-penalty/kk fills one per step
   (its cross neighbours, the heat per kernel weight qtw of its contact
   kernel) and either runs it as a kernel of its own over its tool
   particles (a setup, or where it holds no hook) or hands it to fix
   sph/jc-thermal/kk as its hook before the corrector (HOOK_TOOL_HEAT,
   sphcut_hooks_kokkos.h), which the corrector's kernel applies to each
   particle before it integrates the temperature: one launch fewer a step.
------------------------------------------------------------------------- */

#ifndef SPHCUT_TOOL_HEAT_KOKKOS_H
#define SPHCUT_TOOL_HEAT_KOKKOS_H

#include "kokkos_type.h"
#include "sphcut_contact_step.h"
#include "sphcut_kokkos.h"
#include "sphcut_material.h"
#include "sphcut_thermal.h"

namespace sphcut {

template <class DeviceType> struct ToolHeatGather {
  typedef typename DeviceType::memory_space mem;
  int active = 0;                       // 0: nothing to gather (the integrator's hook point skips it)
  int tb = 0, hb = 0;                   // the tool particles' and the heat group's mask bits
  int kern = 0, dim = 3, ntp = 0, use_rmass = 0;
  double acc = 0.0;                     // the time the heat acts for (dt; 0 at a setup)
  int nlocal = 0;                       // the local particles (their positions: from qtw)
  AtomViews<DeviceType> av;             // x, mask, type, masses and the state (DTEMP)
  // heat per kernel weight of each contact particle (column 0) and, for a local one, its position
  // when the contact kernel set that (1-3): fix sph/jc-thermal/kk may gather in the kernel of the
  // next step's first half, where the local particles' x changes while the tool particles gather
  typename ArrayTypes<DeviceType>::t_double_2d qtw;
  Kokkos::View<const int *, mem> xoff, xnb;            // the cross neighbours (a tool particle's non-tool ones)
  Kokkos::View<const Material *, mem> mat;
  Kokkos::View<const double *, mem> hij;               // pair smoothing lengths, type by type
  Kokkos::View<double, mem> qsrc;                      // the heat booked into the particles (energy)

  // tool particle j (any other particle: nothing) takes its share into its temperature rate, on
  // its state row sj (the row in place: sj null; a staged copy in fix sph/jc-thermal/kk's kernel)
  KOKKOS_INLINE_FUNCTION void operator()(const int j, double *sj = nullptr) const
  {
    if (!(av.mask(j) & tb)) return;
    double p = 0.0;
    for (int c = xoff(j); c < xoff(j + 1); c++) {
      const int i = xnb(c);
      if (!(qtw(i, 0) > 0.0)) continue;
      double r2 = 0.0;
      for (int k = 0; k < 3; k++) {
        const double xi = i < nlocal ? qtw(i, 1 + k) : av.x(i, k);    // (a ghost's x stays)
        r2 += (xi - av.x(j, k)) * (xi - av.x(j, k));
      }
      const double w = tool_heat_weight(kern, dim, r2, hij(av.type(i) * ntp + av.type(j)));
      if (w > 0.0) p += qtw(i, 0) * w;
    }
    if (!(p > 0.0) || !(av.mask(j) & hb)) return;
    const double m = use_rmass ? av.rmass(j) : av.mass(av.type(j));
    if (!add_source_heat(sj ? sj[StateLayout::DTEMP] : av.st(j, StateLayout::DTEMP), p, m, mat(av.type(j)).cp)) return;
    if (acc > 0.0) Kokkos::atomic_add(&qsrc(), p * acc);
  }
};

}    // namespace sphcut

#endif
