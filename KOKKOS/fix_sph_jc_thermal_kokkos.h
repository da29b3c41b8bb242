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
#include "sphcut_hooks_kokkos.h"
#include "sphcut_kokkos.h"
#include "sphcut_material.h"
#include "sphcut_migrate_kokkos.h"

#include <utility>
#include <vector>

namespace LAMMPS_NS {

// what the other /kk styles need of the fix, whatever device type the fix was built for: the state
// on the device (sphcut::KokkosStateOwner::k_state, whose host view is FixSPHJCThermal::state), the
// hooks they hand to its kernels (sphcut::HookHost::set_hook, sphcut_hooks_kokkos.h) and their dt
// slots
class FixSPHJCThermalKokkosBase : public FixSPHJCThermal,
                                  public KokkosBase,
                                  public sphcut::KokkosStateOwner,
                                  public sphcut::HookHost {
 public:
  FixSPHJCThermalKokkosBase(class LAMMPS *lmp, int narg, char **arg) : FixSPHJCThermal(lmp, narg, arg) {}
  // what the host reads of a step, once, at end_of_step (the one host round trip of a step):
  // STEP_WORK the plastic work of the step and STEP_DT this rank's Courant limit, both from
  // final_integrate's reduction; from SLOT0 on one slot per attached style (its dt_slot, given at
  // attach), where the style's own kernel writes its dt limit on the device.  The fix takes the
  // minimum over its own limit and the slots whose style says they hold this step's limit
  // (AttachedStyle::dt_limit_on_device), knowing nothing of what a style computes.
  enum { STEP_WORK = 0, STEP_DT = 1, SLOT0 = 2 };
  DAT::tdual_double_1d k_dtlim;
  // a style's slot as a one-element device view (its kernel writes element 0; the caller syncs
  // k_dtlim to its device type before and marks it modified there after)
  template <class DT> typename ArrayTypes<DT>::t_double_1d dt_slot_view(const sphcut::AttachedStyle *st)
  {
    const int k = SLOT0 + st->dt_slot;
    return Kokkos::subview(k_dtlim.template view<DT>(), std::make_pair(k, k + 1));
  }
  // whether st's dt_slot is a slot of this fix's k_dtlim (it attached to this fix)
  bool holds_slot(const sphcut::AttachedStyle *st) const
  {
    return st->dt_slot >= 0 && st->dt_slot < (int) slot_owner.size() && slot_owner[st->dt_slot] == st;
  }
  double courant() const { return cfl; }
  double thermal_courant() const { return thermal_cfl; }
  // FixSPHJCThermal::attach, and a slot of k_dtlim for the style
  void attach(sphcut::AttachedStyle *style) override;

 protected:
  std::vector<const sphcut::AttachedStyle *> slot_owner;    // the style of each slot (never reused)
  double device_limits();    // this step's limits of the attached styles that hold them in their slots
  bool hook_owner_alive(const sphcut::AttachedStyle *owner) const override;
  void prune_attached() override;    // (and the hooks of the styles deleted since)
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
  void write_restart(FILE *) override;
  void fetch_work();    // the plastic work summed on the device into plastic_work
  // the output columns (RHO .. DTEMP: what dumps, f_ID[k] references and compute_vector read of
  // the state) of the local rows to the host, not the whole rows: on output and peratom_every
  // steps.  The DualView keeps the device as modified, so a host path that needs whole rows
  // (exchange, restart, sort) still copies them.  (Public: it launches a device lambda)
  void sync_outputs_host();

  // the first-half kernel on team-staged copies of the state rows (sphcut::stage_policy): on a GPU
  // from STAGE_MIN local particles (faster in 3D at a million particles and more, slower in 2D at
  // 18k and 70k: bench/gpu/RESULTS.md, "The first half on staged rows"); SPHCUT_STAGE_ROWS (init:
  // 0, 1, or 2 for staged in teams of 2 threads on a host backend; -1 when unset) overrides, for
  // the tests.  (The corrector on staged rows was slower: it runs in place.)
  static constexpr int STAGE_MIN = 500000;
  // the choice for n local particles: env the value of SPHCUT_STAGE_ROWS (-1: unset), host whether
  // the instance runs on a host backend
  static bool stage_choice(int n, bool host, int env) { return env >= 0 ? env >= 1 : !host && n >= STAGE_MIN; }

  void grow_arrays(int) override;
  void set_arrays(int) override;
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int SPHCUT_KK_FIX_PACK_FORWARD(int, SPHCUT_KK_SENDLIST(, ), sphcut::kk_buf &, int, int *) override;
  void SPHCUT_KK_FIX_UNPACK_FORWARD(int, int, sphcut::kk_buf &) override;

  double stable_dt() override;
  std::string timing_note() const override
  {
    return fence == 1 ? " (/kk, fence yes: device times)"
                      : " (/kk, fence no: host time per style, the device runs behind; fence yes for device times)";
  }
  void check_close_pairs() override;
  void report_runaway() override;

  // the state follows its atoms by tag on the device, on any number of ranks (no host
  // exchange, see .cpp; keyword migrate device)
  void setup_pre_exchange() override;
  void setup_post_neighbor() override;
  void post_neighbor() override;
  void remap_state();
  void report_migration();
  void *extract(const char *, int &) override;

 protected:
  // no other fix changes the atoms' data between initial_integrate's kernel and the forces
  // (init: others_keep_out; sphcut::HookCall::kept_to_force)
  int kept_to_force = 0;
  bool others_keep_out(bool before_only) const;
  // the forces zeroed in initial_integrate's kernel, after the half kick has read them, and in
  // pre_force's after a reneighbouring, instead of LAMMPS' own launch (Verlet's external_force_clear,
  // set from setup to post_run; init: force_clear_allowed)
  int clear_f = 0;
  int clear_f_active = 0;          // this run's setup set the integrator's flag (post_run restores it)
  int saved_force_clear = 0;       // the flag before
  int stage_rows = -1;    // the first-half kernel on staged rows (stage_choice): SPHCUT_STAGE_ROWS, -1 unset
  int host_team = 1;      // threads a staged team on a host backend (SPHCUT_STAGE_ROWS=2: 2)
  bool staged(int n) const
  {
    return stage_choice(n, ON_HOST, stage_rows) && sphcut::rows_contiguous(k_state.template view<DeviceType>());
  }
  static constexpr bool ON_HOST = sphcut::on_host_backend<DeviceType>();
  bool force_clear_allowed() const;
  template <class K> void integrator_views(K &k);    // (.cpp: FirstHalf, SecondHalf)
  // a step's corrector in the next step's first-half kernel (.cpp, defers_corrector): fuse (init:
  // fuse_allowed), the fixes whose end_of_step steps keep their corrector
  // (fuse_watch), the step asked last and its answer, the corrector left pending, its step and dt
  int fuse = 0;
  std::vector<const Fix *> fuse_watch;
  bigint defer_step = -1;
  bool defer_now = false;
  int corrector_pending = 0;
  bigint pending_step = -1;
  double pending_dt = 0.0, pending_dtf = 0.0;
  bool fuse_allowed();
  bool defers_corrector();
  void corrector(bool now);
  void settle_corrector();
  template <class K> void corrector_views(K &k, bool now);
  void corrector_done();
  sphcut::StagedColumns<DeviceType> stage_state;    // the force state's rows on the classic forward
                                                    // communication; the output columns (sync_outputs_host)
  bigint rates_zeroed_step = -1;    // step whose initial_integrate zeroed the rates (pre_force skips its kernel)
  int remap;                   // 1: state rows follow the atoms by tag during a run, 0: grow callback
  int nrows;                   // rows holding the state of the atoms labelled in k_rowtag
  DAT::tdual_tagint_1d k_rowtag;    // tag of the atom whose state each row holds
  tagint *rowtag;
  sphcut::RowMigration<DeviceType> mig;    // the remap's tables, buffers and counters
  void grow_on_device(int n);
  t_mat d_mat;                 // materials per type (device copy of the model's)
  t_h d_h;                     // smoothing length per type
  Kokkos::View<double *, typename DeviceType::memory_space> d_second;    // final_integrate's reduction (its final
                                                                         // writes the sums where they go)
  Kokkos::View<double *, typename DeviceType::memory_space> d_second_acc;    // its accumulator on the wide path
  bool wide = false;    // its reduction on the wide path (sphcut::wide_choice, SPHCUT_WIDE_REDUCE; init)
  void upload_tables();
  bigint outputs_step = -1;    // the step whose output columns were copied (-1: none since the setup)
  void sync_host_state() { k_state.sync_host(); }
  void modified_host_state() { k_state.modify_host(); }
};

}    // namespace LAMMPS_NS

#endif
#endif
