/* -*- c++ -*- ----------------------------------------------------------
   sphcut - compute surface/lambda/kk: the free-surface indicator lambda,
   flag and normal (sphcut_thermal.h surface_lambda, surface_normal) on the
   Kokkos device, from a full device neighbour list.  Per-atom results live
   in a DualView: fix heat/fmfs/kk reads the device view without a host copy
   (compute_device); LAMMPS consumers (dumps, variables) call
   compute_peratom, which also brings them to the host.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(surface/lambda/kk,ComputeSurfaceLambdaKokkos<LMPDeviceType>);
ComputeStyle(surface/lambda/kk/device,ComputeSurfaceLambdaKokkos<LMPDeviceType>);
ComputeStyle(surface/lambda/kk/host,ComputeSurfaceLambdaKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_COMPUTE_SURFACE_LAMBDA_KOKKOS_H
#define LMP_COMPUTE_SURFACE_LAMBDA_KOKKOS_H

#include "compute_surface_lambda.h"
#include "kokkos_type.h"

namespace LAMMPS_NS {

// what fix heat/fmfs/kk needs of the compute, whatever device type it was built for
class ComputeSurfaceLambdaKokkosBase : public ComputeSurfaceLambda {
 public:
  ComputeSurfaceLambdaKokkosBase(class LAMMPS *lmp, int narg, char **arg) : ComputeSurfaceLambda(lmp, narg, arg) {}
  DAT::tdual_double_2d k_out;    // NCOLS per atom; host view = array_atom
  // evaluate (or keep, see ComputeSurfaceLambda::compute_peratom) on the device only
  virtual void compute_device() = 0;
};

template <class DeviceType> class ComputeSurfaceLambdaKokkos : public ComputeSurfaceLambdaKokkosBase {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;
  ComputeSurfaceLambdaKokkos(class LAMMPS *, int, char **);
  ~ComputeSurfaceLambdaKokkos() override;
  void init() override;
  void compute_peratom() override;
  void compute_device() override;
  bool begin_step() override;

 public:    // (CUDA: a function that launches a device lambda must be public)
  Kokkos::View<sphcut::ThermalPair *, typename DeviceType::memory_space> d_tp;    // per type pair
  template <int DIM> void kernel();
};

}    // namespace LAMMPS_NS

#endif
#endif
