/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the packed rows of pair sph/jc-thermal/kk: what a particle's
   neighbours read of it (sphcut::PackedRow, sphcut_pair.h), packed on the
   device by the pair's stress pass and, for the local particles, by the
   pair's hook in the first-half kernel of fix sph/jc-thermal/kk.
------------------------------------------------------------------------- */

#ifndef SPHCUT_ROW_PACKER_KOKKOS_H
#define SPHCUT_ROW_PACKER_KOKKOS_H

#include "kokkos_type.h"
#include "sphcut_kokkos.h"
#include "sphcut_material.h"
#include "sphcut_pair.h"
#include "sphcut_solid.h"

namespace sphcut {

// the packed row of particle i (sphcut::pack_row; pack_outside for a particle that is not in the SPH
// solid) from the atom views and the state: the body of the pair's stress pass, which the pair also
// hands to fix sph/jc-thermal/kk as its hook after the first half (sphcut_hooks_kokkos.h), so that
// the local particles' rows are packed in the integrator's first-half kernel right after it has
// moved them (PairSPHJCThermalKokkos::hook_packer)
template <class DeviceType> struct RowPacker {
  typename ArrayTypes<DeviceType>::t_double_2d pk;
  Kokkos::View<Material *, typename DeviceType::memory_space> mt;
  AtomViews<DeviceType> av;
  int gb = 0, tb = 0, cb = 0, dim = 3, any_as = 0, use_rmass = 0;
  int active = 0;    // (hook_packer: 0 when the pair packs every row itself this step)
  KOKKOS_INLINE_FUNCTION void operator()(const int i) const { (*this)(i, &av.st(i, 0)); }
  // the same from particle i's state row s (a copy of it: the integrator's staged kernel)
  KOKKOS_INLINE_FUNCTION void operator()(const int i, const double *s) const
  {
    const double xi[3] = {av.x(i, 0), av.x(i, 1), av.x(i, 2)};
    if (!(av.mask(i) & gb) || role_from_mask(av.mask(i), tb, cb) == StateLayout::TOOL) {
      pack_outside(xi, av.type(i), &pk(i, 0));    // not in the SPH solid: its neighbours skip it
      return;
    }
    pack_row(mt(av.type(i)), dim, any_as, xi, av.type(i), s, use_rmass ? av.rmass(i) : av.mass(av.type(i)), &pk(i, 0));
  }
};

}    // namespace sphcut

#endif
