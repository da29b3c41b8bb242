/* -*- c++ -*- ----------------------------------------------------------
   sphcut - fix contact/tri-penalty/kk: the penalty contact with the
   triangulated tool on the Kokkos device.  The tool mesh and its bins are
   copied to the device at init; one kernel per step finds each particle's
   nearest tool element and applies the contact of sphcut_contact.h
   (penalty, damping, friction with the stick limit, mu(T) tables, friction
   heat); the tool's share of the friction heat reaches the tool particles
   by a gather (no atomics, no reverse communication).  The global sums
   (tool force, powers, heat, the spring's dt limit) come back in one
   reduction; the decomposition by tool feature (vector 16-47) and the
   deepest penetration are formed from per-contact records only when they
   are read.  mu from a LAMMPS variable cannot run in a kernel: refused.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(contact/tri-penalty/kk,FixContactTriPenaltyKokkos<LMPDeviceType>);
FixStyle(contact/tri-penalty/kk/device,FixContactTriPenaltyKokkos<LMPDeviceType>);
FixStyle(contact/tri-penalty/kk/host,FixContactTriPenaltyKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_FIX_CONTACT_TRI_PENALTY_KOKKOS_H
#define LMP_FIX_CONTACT_TRI_PENALTY_KOKKOS_H

#include "fix_contact_tri_penalty.h"
#include "kokkos_base.h"
#include "kokkos_type.h"
#include "sphcut_kokkos.h"
#include "sphcut_contact.h"
#include "sphcut_hooks_kokkos.h"
#include "sphcut_material.h"
#include "sphcut_solid.h"

#include <string>

namespace LAMMPS_NS {

class FixSPHJCThermalKokkosBase;

// the mask bits that sort particles for the contact's kernels: the fix's group, its tool particles
// (tool_particles), fix sph/jc-thermal's tool and clamp roles, the heat fix's group (0: none)
struct ContactMaskBits {
  int group, tool, fixtool, fixclamp, heat;
  // a particle the contact acts on: in the group, not a tool particle (tool_particles group, or
  // the role TOOL of fix sph/jc-thermal)
  KOKKOS_INLINE_FUNCTION bool candidate(int m) const
  {
    return (m & group) && !(m & tool) && sphcut::role_from_mask(m, fixtool, fixclamp) != sphcut::StateLayout::TOOL;
  }
};

template <class DeviceType> class FixContactTriPenaltyKokkos : public FixContactTriPenalty, public KokkosBase {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;
  FixContactTriPenaltyKokkos(class LAMMPS *, int, char **);
  ~FixContactTriPenaltyKokkos() override;
  void post_constructor() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  void end_of_step() override;
  void post_run() override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  double dt_limit(double, double) const override { return 1.0e300; }    // in its slot (dt_slot), on the device
  int dt_limit_on_device() const override { return 1; }
  int SPHCUT_KK_FIX_PACK_FORWARD(int, SPHCUT_KK_SENDLIST(, ), sphcut::kk_buf &, int, int *) override;
  void SPHCUT_KK_FIX_UNPACK_FORWARD(int, int, sphcut::kk_buf &) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  // "near": the number of particles the contact kernel evaluated last (int, dim 0; -1 before any)
  void *extract(const char *name, int &dim) override
  {
    dim = 0;
    return std::string(name) == "near" ? (void *) &nnear : nullptr;
  }

 public:    // (CUDA: a function that launches a device lambda must be public)
  typedef typename DeviceType::memory_space mem;
  FixSPHJCThermalKokkosBase *fixkk;
  // the tool-heat gather as this fix's hook before the corrector of fix sph/jc-thermal/kk
  // (sphcut::HookHost::set_hook, HOOK_TOOL_HEAT; false: on another device type, or another contact
  // fix holds the hook): tool_heat_gather keeps the gather of a step (gather, gather_step) for the
  // hook's arm (arm_hook), which hands it to the corrector's kernel of that step
  bool hooked = false;
  sphcut::ToolHeatGather<DeviceType> gather;
  bigint gather_step = -1;
  void arm_hook(sphcut::IntegratorHooks<DeviceType> &h, const sphcut::HookCall &c);
  // the particles the contact kernel evaluates (near_build): the local contact candidates within
  // a slack (twice the neighbour skin) of the tool's bin grid (tool frame), which holds every point
  // within the search radius 2h of the tool; built at each setup and reneighbouring and when the
  // tool has moved half the slack since.  The others have no contact state to clear (a particle
  // in contact stays in the list until it is farther than the slack from the grid) and find no
  // element: the kernel skips them
  bool wide = false;    // its kernel on the wide path (sphcut::wide_choice, SPHCUT_WIDE_REDUCE; init)
  Kokkos::View<double *, typename DeviceType::memory_space> d_wide_acc;    // the wide path's accumulator
  Kokkos::View<int *, mem> d_near;
  int nnear = -1;                                // particles in d_near (-1: build it)
  double near_disp[3] = {0.0, 0.0, 0.0};         // the tool's displacement at the build
  double near_theta = 0.0, near_arm = 0.0;       // its angle (spin) then, the farthest box corner from the axis
  bigint near_calls = -1;                        // neighbor->ncalls at the build
  int near_nlocal = -1;
  void near_build(const sphcut::ContactStep &step);
  Kokkos::View<double *, mem> d_elem, d_sphere, d_pnorm;    // d_pnorm: feature pseudo-normals
  Kokkos::View<int *, mem> d_start, d_index;
  sphcut::TriBinView d_view;                      // points at the device copies
  Kokkos::View<sphcut::Material *, mem> d_mat;
  Kokkos::View<double *, mem> d_h, d_dp, d_hij;  // per type (h, spacing), per type pair (h)
  Kokkos::View<double *, mem> d_mut, d_muv;      // mu(T) table
  sphcut::StagedColumns<DeviceType> stage_qtw;    // k_qtw's rows on the classic (host) forward communication
  DAT::tdual_double_2d k_qtw;    // tool heat per kernel weight of each contact particle, then its position (4
                                 // columns; the heat alone goes to the ghosts)
  DAT::tdual_double_2d k_fout;                   // per-atom output (host view = fcontact)
  Kokkos::View<int *, mem> d_feature;            // tool feature of each element
  void upload();
  Kokkos::View<double *, mem> d_sums;            // the contact kernel's sums and accumulators (.cpp)
  typename Kokkos::View<double *, mem>::host_mirror_type h_sums;
  int stale = 0;                                 // d_sums holds what the host copies lack
  void fetch();
  // a record per contact of the last evaluation: sphcut::contact_record, the tool feature, the
  // penetration relative to the contact radius (the .cpp's kernels)
  enum { REC_FEAT = sphcut::NDREC, REC_PEN, NREC };
  Kokkos::View<double *[NREC], mem> d_rec;
  int rec_cur = 0;                               // the record counter of the next evaluation (0, 1)
  int records_stale = 0;                         // decomp, maxpen lack the last evaluation's records
  void record_sums();                            // decomp, maxpen from the records (when read)
  double vtool_dev[3] = {0.0, 0.0, 0.0};         // tool velocity the tool particles were last given
  void tool_velocity_device();
  void tool_heat_gather();                       // adds the tool's heat to its particles and to d_sums
  // the cross neighbours (built at each reneighbouring, cross_build): for a local tool particle
  // its listed neighbours that are not tool particles, for a contact candidate its listed tool
  // neighbours, in the order of the neighbour list (d_xnb from d_xoff(i) to d_xoff(i + 1));
  // d_xtool: the local tool particles of the heat fix's group that have some (the gather's range)
  Kokkos::View<int *, mem> d_xoff, d_xnb, d_xtool;
  int nxtool = 0;
  bigint xcalls = -1;                            // neighbor->ncalls at the last build (-1: build)
  int xnlocal = -1;
  void cross_build();
  ContactMaskBits mask_bits() const;
  int reset_accum = 0;                           // fetch() read the accumulators: the next kernel zeroes them
  // tool fields per facet: the contact kernel adds each contact's share to d_facc (atomics, the
  // running interval's sums of this rank); the host copy (fields.acc) is made at the interval's
  // end, at restarts and at the end of a run only
  Kokkos::View<int *, mem> d_share_start, d_share_elem;
  Kokkos::View<double *, mem> d_inv_area, d_facc;
  void fields_upload();
  void fields_fetch();
  void fields_end_of_step() override;
};

}    // namespace LAMMPS_NS

#endif
#endif
