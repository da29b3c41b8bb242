/* -*- c++ -*- ----------------------------------------------------------
   sphcut - pair_style sph/jc-thermal/kk: the SPH solid's pair passes on
   the Kokkos device.  The per-pair and per-particle arithmetic is that of
   the CPU style (src/sphcut_pair.h); this class gathers and scatters.
     FULL list (GPU default, newton off): one kernel, each thread sums the
       neighbours of its particle in registers and writes its force and
       rates: no atomics, no reverse communication of the sums;
     HALF / HALFTHREAD list (CPU threads, newton on or off): atomic sums
       into a per-atom table, reverse communication of the sums (host),
       then a kernel for the rates.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(sph/jc-thermal/kk,PairSPHJCThermalKokkos<LMPDeviceType>);
PairStyle(sph/jc-thermal/kk/device,PairSPHJCThermalKokkos<LMPDeviceType>);
PairStyle(sph/jc-thermal/kk/host,PairSPHJCThermalKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_PAIR_SPH_JC_THERMAL_KOKKOS_H
#define LMP_PAIR_SPH_JC_THERMAL_KOKKOS_H

#include "kokkos_base.h"
#include "kokkos_type.h"
#include "sphcut_hooks_kokkos.h"
#include "sphcut_kokkos.h"
#include "sphcut_pair.h"
#include "sphcut_row_packer_kokkos.h"
#include "sphcut_solid.h"
#include "pair_sph_jc_thermal.h"

namespace LAMMPS_NS {

template <class DeviceType> class PairSPHJCThermalKokkos : public PairSPHJCThermal, public KokkosBase {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;
  typedef Kokkos::View<sphcut::Material *, typename DeviceType::memory_space> t_mat;
  typedef Kokkos::View<sphcut::TypePair *, typename DeviceType::memory_space> t_tpair;

  PairSPHJCThermalKokkos(class LAMMPS *);
  ~PairSPHJCThermalKokkos() override;
  void compute(int, int) override;
  void init_style() override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  // the hourglass control's L of the ghosts: forward communication on the host (the classic
  // path LAMMPS takes here) or on the device
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_forward_comm_kokkos(int, SPHCUT_KK_SENDLIST(, ), sphcut::kk_buf &, int, int *) override;
  void unpack_forward_comm_kokkos(int, int, sphcut::kk_buf &) override;
  double memory_usage() override;

  // the passes (public: they launch device lambdas); stress_pass packs the rows first .. nall - 1
  void stress_pass(int first, int nall, int any_as);
  sphcut::RowPacker<DeviceType> row_packer(int any_as);
  // the local particles' rows are packed by this pair's hook after the first half in the kernel of
  // fix sph/jc-thermal/kk (sphcut_hooks_kokkos.h, HOOK_ROWS; arm_hook): the packer (active 0 when
  // the rows cannot be packed there: setup, no rows yet, or their width or number would change),
  // and the step it was armed for (prepacked_step); compute packs only the ghosts then, unless the
  // lists were rebuilt in between (the atoms reordered) or it reallocated the rows.
  sphcut::RowPacker<DeviceType> hook_packer();
  void arm_hook(sphcut::IntegratorHooks<DeviceType> &h, const sphcut::HookCall &c);
  bool rows_fit(int pk_cols) const;
  template <int DIM, int HALF, int NEWTON, int PF = 0> void neigh_pass(int inum, int any_as);
  template <int DIM> void neigh_pass_team(int inum, int any_as, int lanes);
  template <int DIM> void hourglass_pass(int inum);
  // the team path (neigh_pass_team): at most TEAM_LANES_2D / _3D lanes per particle, halved
  // while particles x lanes exceed TEAM_FILL (the threads that fill a GPU of about a hundred
  // multiprocessors); threads per team
  enum { TEAM_FILL = 131072, TEAM_LANES_2D = 8, TEAM_LANES_3D = 16, TEAM_THREADS = 128 };
  // the one-thread-per-particle pass of the full list (neigh_pass, where team_lanes gives 0) is
  // compiled with launch bounds: at most 128 threads a block, NEIGH_MINB blocks on a
  // multiprocessor (at most 168 registers a thread in 3D; no spill, 20 bytes with the one-ahead
  // loads below; bench/gpu/RESULTS.md, "Launch bounds"); the half-list passes without.
  // On a GPU it loads each list entry's index and row head one entry ahead (PF: their latency
  // overlaps the entry before; sphcut::unpack_j_head / unpack_j_rest; bench/gpu/RESULTS.md, "The
  // pair's list entries loaded one ahead"); on a host backend each entry when it is taken
  // (sphcut::load_ahead; SPHCUT_LOAD_AHEAD=1 takes the GPU's loop there, for the tests).
  // (The team pass, one entry ahead per lane, gained nothing: it loads each entry when taken.)
  enum { NEIGH_MINB = 3 };
  // whether this instance runs on a host backend (one lane in the team pass, no one-ahead loads)
  static constexpr bool ON_HOST = sphcut::on_host_backend<DeviceType>();
  int team_lanes(int inum) const;
  // the choice on a GPU (team_lanes): set / on from package kokkos neigh/thread; 0 = one thread
  // per particle
  static int gpu_lanes(int inum, int dim, bool set, bool on)
  {
    if (set && !on) return 0;
    int lanes = dim == 2 ? TEAM_LANES_2D : TEAM_LANES_3D;
    while (lanes > 2 && (double) inum * lanes > TEAM_FILL) lanes /= 2;
    if (!set && (double) inum * lanes > TEAM_FILL) return 0;
    return lanes;
  }
  struct NeighViews {
    typename sphcut::AtomTypes<DeviceType>::f f;
    typename AT::t_int_1d_const type;
    typename AT::t_double_2d st, pk;
    t_mat mt;
    t_tpair tpt;
    typename AT::t_neighbors_2d neighbors;
    typename AT::t_int_1d numneigh, ilist;
    typename AT::t_double_2d lg;    // hourglass control: L per particle (row major, 9); empty without
  };
  NeighViews neigh_views();
  void rates_pass(int nlocal);

 protected:
  int neighflag;
  int nmax_kk;
  sphcut::KokkosStateOwner *statekk;    // the state on the device (fix sph/jc-thermal/kk)
  int tables_ready;
  int prefetch;     // PF of neigh_pass (init_style: sphcut::load_ahead)
  bigint prepacked_step = -1;    // the step whose local rows the hook packed (arm_hook)
  t_mat d_mat;
  t_tpair d_tpair;                              // (ntypes+1)^2, row major
  typename AT::t_double_2d d_pack;              // what neighbours read of a particle (Pack): local + ghost
  DAT::tdual_double_2d k_acc;                   // neighbour sums (half lists only)
  sphcut::StagedColumns<DeviceType> stage_lgrad;    // k_lgrad's rows on the classic forward communication
  DAT::tdual_double_2d k_lgrad;                 // hourglass control: L, local + ghost (full lists only)
  void upload_tables();
};

}    // namespace LAMMPS_NS

#endif
#endif
