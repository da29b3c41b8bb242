/* -*- c++ -*- ----------------------------------------------------------
   sphcut - compute reduce/region/kk: LAMMPS' compute reduce/region with
   the reduction on the Kokkos device where the device holds what it reads,
   so that an output of it (a line of fix print every few steps) copies no
   per-atom data to the host.  The device path takes: a block region
   (interior, no open faces, moving by variables but not rotating), the
   modes sum, sumsq, min, max, ave, avesq without replace, and the values
   x, v, f and the per-atom columns of fix sph/jc-thermal/kk (its state
   array, f_ID[k]).  Any other input runs LAMMPS' own compute on the host,
   with the atom data synchronised to the host first: `-sf kk` picks this
   style for every compute reduce/region, so it must give LAMMPS' values
   for every input.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(reduce/region/kk,ComputeReduceRegionKokkos<LMPDeviceType>);
ComputeStyle(reduce/region/kk/device,ComputeReduceRegionKokkos<LMPDeviceType>);
ComputeStyle(reduce/region/kk/host,ComputeReduceRegionKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_COMPUTE_REDUCE_REGION_KOKKOS_H
#define LMP_COMPUTE_REDUCE_REGION_KOKKOS_H

#include "compute_reduce_region.h"
#include "kokkos_type.h"

#include <vector>

namespace LAMMPS_NS {

template <class DeviceType> class ComputeReduceRegionKokkos : public ComputeReduceRegion {
 public:
  typedef DeviceType device_type;
  ComputeReduceRegionKokkos(class LAMMPS *, int, char **);
  void init() override;
  double compute_scalar() override;
  void compute_vector() override;

  // where value m is read on the device: an atom vector (x, v, f) or a column of the fix's state
  enum Source { ATOM_X, ATOM_V, ATOM_F, FIX_STATE };
  struct DeviceValue {
    int source, column;
    class FixSPHJCThermalKokkosBase *fix;
  };
  // the device path's reduction of value m on this rank: the sum (or minimum, maximum) of the
  // group's particles in the region, and how many there are
  void reduce_device(int m, double &value, double &count);

 private:
  bool device_path = false;
  std::vector<DeviceValue> dvalues;
  double reduce_all(int m);
};

}    // namespace LAMMPS_NS

#endif
#endif
