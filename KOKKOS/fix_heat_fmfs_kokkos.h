/* -*- c++ -*- ----------------------------------------------------------
   sphcut - fix heat/fmfs/kk: FMFS / Brookshaw conduction, convection and
   radiation on surface particles, Dirichlet groups and sub-cycling on the
   Kokkos device, with the arithmetic of the CPU fix (sphcut_thermal.h).
   It reads and writes the state of fix sph/jc-thermal/kk on the device
   (the rate held between evaluations is its column HELD) and the surface
   flags of compute surface/lambda/kk without a host copy.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(heat/fmfs/kk,FixHeatFMFSKokkos<LMPDeviceType>);
FixStyle(heat/fmfs/kk/device,FixHeatFMFSKokkos<LMPDeviceType>);
FixStyle(heat/fmfs/kk/host,FixHeatFMFSKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_FIX_HEAT_FMFS_KOKKOS_H
#define LMP_FIX_HEAT_FMFS_KOKKOS_H

#include "fix_heat_fmfs.h"
#include "kokkos_base.h"
#include "kokkos_type.h"
#include "sphcut_hooks_kokkos.h"
#include "sphcut_kokkos.h"
#include "sphcut_material.h"

namespace LAMMPS_NS {

class FixSPHJCThermalKokkosBase;
class ComputeSurfaceLambdaKokkosBase;
template <class DeviceType> struct HeatFMFSViews;

template <class DeviceType> class FixHeatFMFSKokkos : public FixHeatFMFS, public KokkosBase {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;
  FixHeatFMFSKokkos(class LAMMPS *, int, char **);
  ~FixHeatFMFSKokkos() override;
  void post_constructor() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void post_run() override;
  double dt_limit(double, double F) const override;
  int dt_limit_on_device() const override;
  int SPHCUT_KK_FIX_PACK_FORWARD(int, SPHCUT_KK_SENDLIST(, ), sphcut::kk_buf &, int, int *) override;
  void SPHCUT_KK_FIX_UNPACK_FORWARD(int, int, sphcut::kk_buf &) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  bool begin_evaluation() override;

 public:    // (CUDA: a function that launches a device lambda must be public)
  FixSPHJCThermalKokkosBase *fixkk;
  ComputeSurfaceLambdaKokkosBase *surfkk;
  Kokkos::View<sphcut::Material *, typename DeviceType::memory_space> d_mat;
  Kokkos::View<double *, typename DeviceType::memory_space> d_hij, d_h;
  Kokkos::View<sphcut::ThermalPair *, typename DeviceType::memory_space> d_tp;
  Kokkos::View<int *, typename DeviceType::memory_space> d_dirbit;
  Kokkos::View<double *, typename DeviceType::memory_space> d_dirtemp;
  sphcut::StagedColumns<DeviceType> stage_fwts;    // k_fwts's rows on the classic (host) forward communication
  DAT::tdual_double_2d k_fwts;    // (a pad,) scheme flag and FMFS weights, local + ghost
  typename AT::t_double_2d d_hrow;    // the heat rows (build_heat_rows), local + ghost
  void build_heat_rows();
  HeatFMFSViews<DeviceType> heat_views();    // what the heat kernels read
  template <int DIM> void conduction_kk();
  template <int DIM> void conduction_conservative_kk();
  template <int DIM, int EAGER>
  void scheme_pass_kk(const HeatFMFSViews<DeviceType> &, const typename AT::t_double_2d &surf);
  template <int DIM, int EAGER>
  void exchange_pass_kk(const HeatFMFSViews<DeviceType> &, const typename AT::t_double_2d &surf);
  void add_held();    // setup only (during the run this fix's hook in the integrator's corrector adds HELD)
  void set_dirichlet();    // setup only (during the run its hook after the integrator's first half sets TEMP_F)
  // this fix's hooks in the kernels of fix sph/jc-thermal/kk (sphcut_heat_hooks_kokkos.h), handed
  // over in init (sphcut::HookHost::set_hook): arm_hooks fills them for each pass of the integrator
  void hand_over_rules() override {}    // (init: the hooks, once fixkk is known)
  void arm_hooks(sphcut::IntegratorHooks<DeviceType> &h, const sphcut::HookCall &c);
  // the heat the Dirichlet groups took, summed on the device by the hook after the corrector into
  // k_qdir(0) (no host round trip per step; qdir_pending: added to since the last fetch), into
  // q_dirichlet when the host needs it (output, restart, end of run)
  DAT::tdual_double_1d k_qdir;
  int qdir_pending = 0;
  void fetch_dirichlet();
  // the thermal dt limit in this fix's slot (AttachedStyle::dt_slot) is written by the same hook's
  // final when the step is adaptive (the density the CPU fix's dt_limit sees at end_of_step):
  // slot_step, slot_F the step and thermal Courant number of the limit there (the hook's arm)
  bigint slot_step = -1;
  double slot_F = 0.0;
  // the loss rates of the last evaluation, the convective and radiative heat of the budget and the
  // scheme counters stay on the device during a run (d_loss): the passes' reductions write them in
  // their final, so that an evaluation makes no host round trip.  The host keeps the time the
  // current rates have acted for (loss_weight: the trapezoid's weight, FixHeatFMFS::post_force);
  // fetch_losses forms q_conv, q_rad, held_conv, held_rad and the counters from them when it needs
  // them (output, restart, end of run); push_losses hands the host's values over at the setup
  enum LossSlot { L_CONV = 0, L_RAD, L_QCONV, L_QRAD, L_NFMFS, L_NBROOK, L_NFALL, NLOSS };
  Kokkos::View<double *, typename DeviceType::memory_space> d_loss, d_red;    // (d_red: the reductions' result)
  Kokkos::View<double *, typename DeviceType::memory_space> d_wide_acc;    // their accumulator on the wide path
                                                                          // (shared: their inits are all zero)
  bool wide = false;    // the reductions on the wide path (sphcut::wide_choice, SPHCUT_WIDE_REDUCE; init)
  // the conservative passes load a neighbour's whole row before its support test (DeviceNeighbours'
  // EAGER): on a GPU (sphcut::load_ahead, SPHCUT_LOAD_AHEAD; init)
  bool eager = false;
  double loss_weight = 0.0;     // the time the current rates have acted for since the device's last sum
  double replaced_weight = 0.0;    // the weight the rates an evaluation replaces still take (its final)
  bigint count_base[3] = {0, 0, 0};    // n_fmfs, n_brookshaw, n_fallback at the last push
  double loss_host[NLOSS] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};    // d_loss as last copied
  int losses_stale = 0;    // an evaluation ran since (d_loss differs from loss_host)
  void push_losses();
  void fetch_losses();
};

}    // namespace LAMMPS_NS

#endif
#endif
