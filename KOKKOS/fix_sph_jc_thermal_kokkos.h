/* -*- c++ -*- ----------------------------------------------------------
   sphcut - fix sph/jc-thermal/kk: the SPH solid state and its time
   integration on the Kokkos device.  The per-particle arithmetic is that
   of the CPU fix (src/sphcut_solid.h); this class keeps the state in a
   DualView whose host view backs FixSPHJCThermal::state, so restart,
   exchange, dumps and f_ID outputs work as for the CPU style.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(sph/jc-thermal/kk,FixSPHJCThermalKokkos<LMPDeviceType>);
FixStyle(sph/jc-thermal/kk/device,FixSPHJCThermalKokkos<LMPDeviceType>);
FixStyle(sph/jc-thermal/kk/host,FixSPHJCThermalKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_FIX_SPH_JC_THERMAL_KOKKOS_H
#define LMP_FIX_SPH_JC_THERMAL_KOKKOS_H

#include "fix_sph_jc_thermal.h"
#include "kokkos_base.h"
#include "kokkos_type.h"
#include "sphcut_kokkos.h"
#include "sphcut_material.h"
#include "sphcut_migrate_kokkos.h"

namespace LAMMPS_NS {

// what the /kk pair needs of the fix, whatever device type the fix was built for
class FixSPHJCThermalKokkosBase : public FixSPHJCThermal, public KokkosBase {
 public:
  FixSPHJCThermalKokkosBase(class LAMMPS *lmp, int narg, char **arg) : FixSPHJCThermal(lmp, narg, arg) {}
  DAT::tdual_double_2d k_state;    // host view = FixSPHJCThermal::state
  // the thermal time step limit of fix heat/fmfs/kk (sphcut_thermal.h thermal_dt_limit over its
  // group), taken in the same reduction as the mechanical one: the heat fix registers its group
  // and sub-cycling interval at init and reads the result (no reduction of its own per step)
  int therm_bit = 0, therm_every = 1;
  double therm_dt = 1.0e300, therm_F = 0.0;
  bigint therm_step = -1;    // step of the last final_integrate that computed therm_dt
  // element 0: a dt limit an attached /kk style writes on the device each step
  // (AttachedStyle::dt_limit_on_device); the second-half reduction takes it into its minimum
  DAT::tdual_double_1d k_dtlim;
  double courant() const { return cfl; }
};

template <class DeviceType> class FixSPHJCThermalKokkos : public FixSPHJCThermalKokkosBase {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;
  typedef Kokkos::View<sphcut::Material *, typename DeviceType::memory_space> t_mat;
  typedef Kokkos::View<double *, typename DeviceType::memory_space> t_h;

  FixSPHJCThermalKokkos(class LAMMPS *, int, char **);
  ~FixSPHJCThermalKokkos() override;
  void post_constructor() override;
  int setmask() override;
  void init() override;
  void setup_pre_force(int) override;
  void setup(int) override;
  void initial_integrate(int) override;
  void pre_force(int) override;
  void final_integrate() override;
  void end_of_step() override;
  void post_run() override;
  double compute_vector(int) override;

  void grow_arrays(int) override;
  void set_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
#ifdef SPHCUT_KK_API_2026
  int pack_forward_comm_kokkos(int, DAT::tdual_int_1d, DAT::tdual_double_1d &, int, int *) override;
  void unpack_forward_comm_kokkos(int, int, DAT::tdual_double_1d &) override;
#else
  int pack_forward_comm_fix_kokkos(int, DAT::tdual_int_2d, int, DAT::tdual_xfloat_1d &, int, int *) override;
  void unpack_forward_comm_fix_kokkos(int, int, DAT::tdual_xfloat_1d &) override;
#endif

  double stable_dt() override;
  std::string timing_note() const override
  {
    return fence == 1 ? " (/kk, fence yes: device times)"
                      : " (/kk, fence no: host time per style, the device runs behind; fence yes for device times)";
  }
  void check_close_pairs() override;
  void report_runaway() override;
  int device_dt_limits();

  // the state follows its atoms by tag on the device, on any number of ranks (no host
  // exchange, see .cpp; keyword migrate device)
  void setup_pre_exchange() override;
  void setup_post_neighbor() override;
  void post_neighbor() override;
  void remap_state();
  void report_migration();
  void *extract(const char *, int &) override;

 protected:
  double dt_next;              // this rank's stable dt, from final_integrate's reduction
  int remap;                   // 1: state rows follow the atoms by tag during a run, 0: grow callback
  int nrows;                   // rows holding the state of the atoms labelled in k_rowtag
  DAT::tdual_tagint_1d k_rowtag;    // tag of the atom whose state each row holds
  tagint *rowtag;
  sphcut::RowMigration<DeviceType> mig;    // the remap's tables, buffers and counters
  void grow_on_device(int n);
  t_mat d_mat;                 // materials per type (device copy of the pair's)
  t_h d_h;                     // smoothing length per type
  void upload_tables();
  void sync_host_state() { k_state.sync_host(); }
  void modified_host_state() { k_state.modify_host(); }
};

}    // namespace LAMMPS_NS

#endif
#endif
