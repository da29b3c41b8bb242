/* ----------------------------------------------------------------------
   sphcut - pair_style sph/jc-thermal/kk (see the header for the passes)
------------------------------------------------------------------------- */

#include "pair_sph_jc_thermal_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "kokkos.h"
#include "memory_kokkos.h"
#include "neigh_list_kokkos.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair_kokkos.h"
#include "update.h"

#include "sphcut_compat.h"
#include "sphcut_hooks_kokkos.h"
#include "sphcut_kokkos.h"
#include "sphcut_pair.h"

using namespace LAMMPS_NS;
using sphcut::StateLayout;
using sphcut::PK_M;

namespace {

/* what a particle's neighbours read of it: one packed row (sphcut_pair.h PackedRow: 128 bytes, 4
   memory sectors, without artificial stress) built in the stress pass (sphcut::pack_row), read by
   the neighbour passes (sphcut::unpack_i, unpack_j) in 16-byte pairs.  The pair kernel's cost is
   the irregular loads of its neighbours' data (Nsight Compute: L1-bound, not DRAM- or
   FLOP-bound); one contiguous row instead of pieces of x, the 49-column state row, mask, type,
   mass, sigma and R cuts the sectors and load instructions each neighbour costs.  The device row
   has no host extension (sphcut::pack_width columns).                                           */

// particle i's side of its pairs, from its packed row; R_i with artificial stress
template <class PK>
KOKKOS_INLINE_FUNCTION void gather_i(const PK &pk, int i, int any_as, double *xi, double *vi, sphcut::PairIn &in)
{
  sphcut::unpack_i(&pk(i, 0), any_as, xi, vi, in);
}

// the inputs of pair i-j (tprow: i's type pairs); false when j is beyond the cutoff or not in the
// SPH solid; mj, Vj: mass and volume of j
template <class PK>
KOKKOS_INLINE_FUNCTION bool gather_j(const PK &pk, const sphcut::TypePair *tprow, int j, const double *xi,
                                     const double *vi, sphcut::PairIn &in, double &mj, double &Vj)
{
  return sphcut::unpack_j(&pk(j, 0), tprow, xi, vi, in, mj, Vj);
}

// the rates of particle i from its neighbour sums, into its state row
template <class ST>
KOKKOS_INLINE_FUNCTION void store_rates(const sphcut::Material &mt, int dim, int corr, const double *acc, const ST &st,
                                        int i)
{
  using SL = sphcut::StateLayout;
  double drho, ds[6], du;
  sphcut::particle_rates(mt, dim, corr, acc, &st(i, SL::SF), st(i, SL::RHO_F), drho, ds, du);
  st(i, SL::DRHO) += drho;
  for (int k = 0; k < 6; k++) st(i, SL::DS + k) += ds[k];
  st(i, SL::DU) += du;
  for (int a = 0; a < 3; a++) st(i, SL::XSPH + a) = acc[sphcut::ACC_XS + a];
}

// sums of one particle kept in registers
struct LocalAdd {
  double *acc;
  KOKKOS_INLINE_FUNCTION void operator()(int k, double val) const { acc[k] += val; }
};

// a particle's sums into its force, its rates and (hourglass control) its velocity gradient L
template <class NV>
KOKKOS_INLINE_FUNCTION void store_sums(const NV &nv, const sphcut::Material &mt, int dim, int corr, int hg,
                                       const double *acc, int i)
{
  for (int a = 0; a < 3; a++) nv.f(i, a) += acc[sphcut::ACC_F + a];
  store_rates(mt, dim, corr, acc, nv.st, i);
  if (hg) sphcut::particle_velocity_gradient(dim, corr, acc, &nv.lg(i, 0));
}

// the sums of one particle as one value, for the reduction over the vector lanes that share its
// neighbours (team path: Kokkos sums it with +=, starting from the default-constructed zero)
struct PairSums {
  double v[sphcut::NACC];
  KOKKOS_INLINE_FUNCTION PairSums()
  {
    for (int k = 0; k < sphcut::NACC; k++) v[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION PairSums &operator+=(const PairSums &o)
  {
    for (int k = 0; k < sphcut::NACC; k++) v[k] += o.v[k];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile PairSums &o) volatile
  {
    for (int k = 0; k < sphcut::NACC; k++) v[k] += o.v[k];
  }
};

// sums of another particle: atomics into the per-atom table and the force
template <class DeviceType> struct AtomicAdd {
  typename ArrayTypes<DeviceType>::t_double_2d acc;
  typename sphcut::AtomTypes<DeviceType>::f f;
  int j;
  KOKKOS_INLINE_FUNCTION void operator()(int k, double val) const
  {
    if (k < 3) Kokkos::atomic_add(&f(j, k), val);
    else Kokkos::atomic_add(&acc(j, k), val);
  }
};

}    // namespace

/* ---------------------------------------------------------------------- */

template <class DeviceType>
PairSPHJCThermalKokkos<DeviceType>::PairSPHJCThermalKokkos(LAMMPS *lmp) :
    PairSPHJCThermal(sphcut::require_kokkos(lmp, "Pair sph/jc-thermal/kk")), neighflag(FULL), nmax_kk(0),
    statekk(nullptr), tables_ready(0), prefetch(1)
{
  kokkosable = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | F_MASK | TYPE_MASK | MASK_MASK | RMASS_MASK;
  datamask_modify = F_MASK;
}

template <class DeviceType> PairSPHJCThermalKokkos<DeviceType>::~PairSPHJCThermalKokkos()
{
  if (!copymode) {
    memoryKK->destroy_kokkos(k_acc);
    memoryKK->destroy_kokkos(k_lgrad);
  }
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void PairSPHJCThermalKokkos<DeviceType>::init_style()
{
  PairSPHJCThermal::init_style();
  statekk = dynamic_cast<sphcut::KokkosStateOwner *>(fix);
  if (!statekk)
    error->all(FLERR, "Pair sph/jc-thermal/kk requires fix sph/jc-thermal/kk (run with -sf kk)");
  // the local rows packed by this pair's hook in the integrator's first-half kernel (where the
  // integrator runs on this device type: else the stress pass packs every row)
  prepacked_step = -1;
  if (auto *host = dynamic_cast<sphcut::HookHost *>(fix)) {
    const sphcut::HookArm<DeviceType> arm = [this](sphcut::IntegratorHooks<DeviceType> &h,
                                                   const sphcut::HookCall &c) { arm_hook(h, c); };
    host->set_hook<DeviceType>(this, sphcut::HOOK_ROWS, arm);
  }
  prefetch = sphcut::load_ahead<DeviceType>(lmp, "Pair sph/jc-thermal/kk");
  // fix property/atom rmass keeps the per-atom mass on the host only in this LAMMPS version
  if (atom->rmass_flag && atomKK->k_rmass.view_host().data() != atom->rmass)
    error->all(FLERR, "Pair sph/jc-thermal/kk: the per-atom mass (rmass) has no Kokkos device copy "
               "(fix property/atom rmass); use per-type masses (mass command) or atom_style sphere");
  neighflag = lmp->kokkos->neighflag;
  if (neighflag != FULL && neighflag != HALF && neighflag != HALFTHREAD)
    error->all(FLERR, "Pair sph/jc-thermal/kk: neighbor list kind {} not supported (full, half, half/thread)",
               neighflag);
  sphcut::kokkos_list<DeviceType>(neighbor, neighflag == FULL);
  if (mdl.hourglass_coefficient() > 0.0 && neighflag != FULL)
    error->all(FLERR, "Pair sph/jc-thermal/kk: hourglass {} needs the full neighbor list (package kokkos neigh full)",
               mdl.hourglass_coefficient());
  tables_ready = 0;    // init_one runs after this: the tables go to the device at the first compute
}

template <class DeviceType> void PairSPHJCThermalKokkos<DeviceType>::upload_tables()
{
  const int n = atom->ntypes + 1;
  d_mat = sphcut::to_device<sphcut::Material, DeviceType>(mdl.materials(), n, "pair:mat");
  std::vector<sphcut::TypePair> tp((size_t) n * n);
  for (int i = 1; i < n; i++)
    for (int j = 1; j < n; j++) tp[(size_t) i * n + j] = mdl.type_pair(i, j);
  d_tpair = sphcut::to_device<sphcut::TypePair, DeviceType>(tp.data(), n * n, "pair:tpair");
  tables_ready = 1;
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void PairSPHJCThermalKokkos<DeviceType>::compute(int eflag, int vflag)
{
  sphcut::FencedTimer timer(cpu_time);
  if (neighflag == FULL) no_virial_fdotr_compute = 1;
  ev_init(eflag, vflag, 0);
  atomKK->sync(execution_space, datamask_read);
  atomKK->modified(execution_space, F_MASK);
  if (!tables_ready) upload_tables();

  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int dim = domain->dimension;
  const int any_as = mdl.any_artificial_stress();
  const int pk_cols = sphcut::pack_width(any_as);
  // the local rows packed by the hook this step (arm_hook) stand unless the lists were rebuilt
  // since (the atoms may have moved in the arrays) or the rows are reallocated
  int first = prepacked_step == update->ntimestep && !update->setupflag && neighbor->ago != 0 ? atom->nlocal : 0;
  prepacked_step = -1;
  if (!rows_fit(pk_cols)) {
    d_pack = typename AT::t_double_2d("pair:pack", atom->nmax, pk_cols);
    sphcut::require_aligned16(lmp, d_pack.data(), "Pair sph/jc-thermal/kk: the packed rows");
    first = 0;
  }
  if (atom->nmax > nmax_kk) {
    nmax_kk = atom->nmax;
    if (neighflag != FULL) {
      memoryKK->destroy_kokkos(k_acc);
      k_acc = DAT::tdual_double_2d("pair:acc", nmax_kk, sphcut::NACC);
    }
  }
  if (mdl.hourglass_coefficient() > 0.0 && (int) k_lgrad.extent(0) < nmax_kk) {
    memoryKK->destroy_kokkos(k_lgrad);
    k_lgrad = DAT::tdual_double_2d("pair:lgrad", nmax_kk, 9);
  }
  statekk->k_state.template sync<DeviceType>();
  stress_pass(first, nall, any_as);
  const int inum = list->inum;
  if (neighflag == FULL) {
    const int lanes = team_lanes(inum);
    if (lanes > 0) {
      if (dim == 2) neigh_pass_team<2>(inum, any_as, lanes);
      else neigh_pass_team<3>(inum, any_as, lanes);
    } else {
      if (prefetch) {
        if (dim == 2) neigh_pass<2, 0, 0, 1>(inum, any_as);
        else neigh_pass<3, 0, 0, 1>(inum, any_as);
      } else {
        if (dim == 2) neigh_pass<2, 0, 0>(inum, any_as);
        else neigh_pass<3, 0, 0>(inum, any_as);
      }
    }
    if (mdl.hourglass_coefficient() > 0.0) {
      // the hourglass control (sphcut::hourglass_pair): L of the local particles from the
      // neighbour pass, of the ghosts by forward communication, then the pairs again
      k_lgrad.template modify<DeviceType>();
      if (atom->nghost > 0) {
        sphcut::forward_comm(comm, this);
        k_lgrad.template sync<DeviceType>();
      }
      if (dim == 2) hourglass_pass<2>(inum);
      else hourglass_pass<3>(inum);
    }
  } else {
    const int newton = force->newton_pair;
    // clear the sums (ghosts too with newton: they come back by reverse communication)
    k_acc.template sync<DeviceType>();
    auto acc = k_acc.template view<DeviceType>();
    Kokkos::parallel_for("sphcut:pair:zero_sums",
        sphcut::range<DeviceType>(0, newton ? nall : nlocal), KOKKOS_LAMBDA(const int i) {
          for (int k = 0; k < sphcut::NACC; k++) acc(i, k) = 0.0;
        });
    if (dim == 2) {
      if (newton) neigh_pass<2, 1, 1>(inum, any_as);
      else neigh_pass<2, 1, 0>(inum, any_as);
    } else {
      if (newton) neigh_pass<3, 1, 1>(inum, any_as);
      else neigh_pass<3, 1, 0>(inum, any_as);
    }
    k_acc.template modify<DeviceType>();
    if (newton) {
      sphcut::reverse_comm(comm, this);    // host path in this LAMMPS version
      k_acc.template sync<DeviceType>();
    }
    rates_pass(nlocal);
  }
  statekk->k_state.template modify<DeviceType>();

  if (vflag_fdotr) {
    // half lists only (fdotr is not valid for a full list)
    EV_FLOAT ev;
    Kokkos::parallel_reduce("sphcut:pair:virial", nall, PairVirialFDotRCompute<DeviceType>(atomKK->k_x.view<DeviceType>(),
                                                                      atomKK->k_f.view<DeviceType>(), 0), ev);
    for (int k = 0; k < 6; k++) virial[k] = ev.v[k];
    vflag_fdotr = 0;
  }
}

/* ----------------------------------------------------------------------
   Cauchy and artificial stress of the force state, local and ghost
------------------------------------------------------------------------- */

// what packs a row (the stress pass's body) with this step's views
template <class DeviceType> sphcut::RowPacker<DeviceType> PairSPHJCThermalKokkos<DeviceType>::row_packer(int any_as)
{
  sphcut::RowPacker<DeviceType> p;
  p.pk = d_pack;
  p.mt = d_mat;
  p.av = sphcut::atom_views<DeviceType>(atomKK, statekk->k_state);
  p.gb = fix->solidbit;
  p.tb = fix->toolbit;
  p.cb = fix->clampbit;
  p.dim = domain->dimension;
  p.any_as = any_as;
  p.use_rmass = atom->rmass_flag;
  return p;
}

template <class DeviceType> void PairSPHJCThermalKokkos<DeviceType>::stress_pass(int first, int nall, int any_as)
{
  if (first >= nall) return;    // (no ghosts, the local rows packed by the fix)
  const sphcut::RowPacker<DeviceType> p = row_packer(any_as);
  Kokkos::parallel_for("sphcut:pair:stress_pass", sphcut::range<DeviceType>(first, nall),
                       KOKKOS_LAMBDA(const int i) { p(i); });
}

// the packer of the hook after the first half (active 0 where this compute would reallocate the rows
// or has none yet)
template <class DeviceType> sphcut::RowPacker<DeviceType> PairSPHJCThermalKokkos<DeviceType>::hook_packer()
{
  const int any_as = mdl.any_artificial_stress();
  sphcut::RowPacker<DeviceType> p = row_packer(any_as);
  p.active = tables_ready && !update->setupflag && rows_fit(sphcut::pack_width(any_as));
  return p;
}

// this pair's hook for a pass of the integrator: after the first half, where nothing changes what
// the rows hold before the forces (kept_to_force), the local rows packed; the step remembered
template <class DeviceType>
void PairSPHJCThermalKokkos<DeviceType>::arm_hook(sphcut::IntegratorHooks<DeviceType> &h, const sphcut::HookCall &c)
{
  if (c.pass != sphcut::HookCall::FIRST_HALF || !c.kept_to_force) return;
  h.first_half.rows = hook_packer();
  if (h.first_half.rows.active) prepacked_step = c.step;
}

// whether the packed rows hold every atom at this width (compute reallocates them where not)
template <class DeviceType> bool PairSPHJCThermalKokkos<DeviceType>::rows_fit(int pk_cols) const
{
  return atom->nmax <= nmax_kk && (int) d_pack.extent(0) >= atom->nmax && (int) d_pack.extent(1) == pk_cols;
}

/* ----------------------------------------------------------------------
   the neighbour pass.  Full list (HALF = 0): every pair is seen from both
   particles; each thread sums its particle's pairs in registers and writes
   its force and rates, no atomics.  Half list (HALF = 1): each pair once,
   j's share by atomics (j < nlocal, or any j with newton), the sums of i
   added atomically at the end; the rates follow in rates_pass.  The
   full-list pass runs with launch bounds (NEIGH_MINB), the half-list ones
   without; PF: list entries loaded one ahead (the header).
------------------------------------------------------------------------- */

template <class DeviceType>
template <int DIM, int HALF, int NEWTON, int PF>
void PairSPHJCThermalKokkos<DeviceType>::neigh_pass(int inum, int any_as)
{
  constexpr int MINB = HALF ? 0 : NEIGH_MINB;
  const NeighViews nv = neigh_views();
  auto accv = k_acc.template view<DeviceType>();
  const int kind = mdl.kernel(), corr = mdl.renormalised(), ntp = atom->ntypes + 1;
  const int nlocal = atom->nlocal;
  const int hg = !HALF && mdl.hourglass_coefficient() > 0.0;

  Kokkos::parallel_for("sphcut:pair:neigh_pass",
      sphcut::range<DeviceType, MINB>(0, inum), KOKKOS_LAMBDA(const int ii) {
        const int i = nv.ilist(ii);
        const double mi = nv.pk(i, PK_M);
        if (mi == 0.0) return;    // not in the SPH solid
        const int itype = nv.type(i);
        double acc[sphcut::NACC];
        for (int k = 0; k < sphcut::NACC; k++) acc[k] = 0.0;
        sphcut::PairIn in;
        sphcut::PairOut out;
        double xi[3], vi[3], mj, Vj;
        gather_i(nv.pk, i, any_as, xi, vi, in);
        const double Vi = nv.pk(i, sphcut::PK_VOL);
        const sphcut::TypePair *tprow = &nv.tpt(itype * ntp);
        const int jnum = nv.numneigh(i);
        // PF: the next entry's index and row head are loaded before this entry's rest and its
        // pair's work, so that their latency overlaps them (a chain of dependent loads per entry
        // otherwise: index, head, rest)
        int jn = 0;
        double xn[3] = {0.0, 0.0, 0.0}, tn = 0.0;
        if (PF && jnum > 0) {
          jn = nv.neighbors(i, 0) & NEIGHMASK;
          sphcut::unpack_j_head(&nv.pk(jn, 0), xn, tn);
        }
        for (int jj = 0; jj < jnum; jj++) {
          int j;
          bool inside;
          if (PF) {
            j = jn;
            const double xj[3] = {xn[0], xn[1], xn[2]}, tj = tn;
            if (jj + 1 < jnum) {
              jn = nv.neighbors(i, jj + 1) & NEIGHMASK;
              sphcut::unpack_j_head(&nv.pk(jn, 0), xn, tn);
            }
            inside = sphcut::unpack_j_rest(&nv.pk(j, 0), xj, tj, tprow, xi, vi, in, mj, Vj);
          } else {
            j = nv.neighbors(i, jj) & NEIGHMASK;
            inside = gather_j(nv.pk, tprow, j, xi, vi, in, mj, Vj);
          }
          if (!inside) continue;
          sphcut::pair_terms<DIM>(kind, in, out);
          sphcut::pair_accumulate<DIM>(in, out, mi * mj, mj, Vj, 1.0, LocalAdd{acc});
          if (HALF && (NEWTON || j < nlocal))
            sphcut::pair_accumulate<DIM>(in, out, mi * mj, mi, Vi, -1.0, AtomicAdd<DeviceType>{accv, nv.f, j});
        }
        if (HALF) {
          AtomicAdd<DeviceType> to_i{accv, nv.f, i};
          for (int k = 0; k < sphcut::NACC; k++)
            if (acc[k] != 0.0) to_i(k, acc[k]);
        } else {
          store_sums(nv, nv.mt(itype), DIM, corr, hg, acc, i);
        }
      });
}

// what the neighbour passes read and write
template <class DeviceType>
typename PairSPHJCThermalKokkos<DeviceType>::NeighViews PairSPHJCThermalKokkos<DeviceType>::neigh_views()
{
  auto *kl = static_cast<NeighListKokkos<DeviceType> *>(list);
  return {atomKK->k_f.view<DeviceType>(), atomKK->k_type.view<DeviceType>(),
          statekk->k_state.template view<DeviceType>(), d_pack, d_mat, d_tpair,
          kl->d_neighbors, kl->d_numneigh, kl->d_ilist, k_lgrad.template view<DeviceType>()};
}

/* ----------------------------------------------------------------------
   how many vector lanes share a particle's neighbours in the neighbour
   pass, as in LAMMPS's own Kokkos pair styles: 0 for one thread per
   particle (neigh_pass), else the lanes of a team (neigh_pass_team).  Few
   particles leave most of a GPU idle and a step lasts as long as one
   thread's chain over its neighbours: lanes shorten the chain, and their
   sums cost shuffles.  So on a GPU by default the most lanes (8 in 2D, 16
   in 3D) for which particles x lanes stay within TEAM_FILL threads, down
   to 2; one thread per particle above TEAM_FILL / 2 particles.  package
   kokkos neigh/thread off: one thread per particle; on: at least 2 lanes.
   On a host backend the team path has one lane (the CPU's order of the
   sums).  TEAM_FILL and the lanes were measured (bench/gpu/RESULTS.md,
   "The 2D step").  The choice itself: gpu_lanes.
------------------------------------------------------------------------- */

template <class DeviceType> int PairSPHJCThermalKokkos<DeviceType>::team_lanes(int inum) const
{
  const bool set = lmp->kokkos->neigh_thread_set, on = lmp->kokkos->neigh_thread;
  if (ON_HOST) return set && on ? 1 : 0;
  return gpu_lanes(inum, domain->dimension, set, on);
}

/* the full-list pass with a team per TEAM_THREADS / lanes particles, the
   given lanes per particle (team_lanes; one on a host backend: the same
   order of the sums as neigh_pass); the lanes' sums are added by
   shuffles, one lane writes */
template <class DeviceType>
template <int DIM>
void PairSPHJCThermalKokkos<DeviceType>::neigh_pass_team(int inum, int any_as, int lanes)
{
  const NeighViews nv = neigh_views();
  const int kind = mdl.kernel(), corr = mdl.renormalised(), ntp = atom->ntypes + 1;
  const int hg = mdl.hourglass_coefficient() > 0.0;
  if (ON_HOST) lanes = 1;
  const int per_team = ON_HOST ? 1 : TEAM_THREADS / lanes;
  typedef Kokkos::TeamPolicy<DeviceType> policy_t;

  Kokkos::parallel_for(
      "sphcut:pair:neigh_pass_team", policy_t((inum + per_team - 1) / per_team, per_team, lanes),
      KOKKOS_LAMBDA(const typename policy_t::member_type &team) {
        const int ii = team.league_rank() * team.team_size() + team.team_rank();
        if (ii >= inum) return;    // all lanes of this particle alike
        const int i = nv.ilist(ii);
        const double mi = nv.pk(i, PK_M);
        if (mi == 0.0) return;    // not in the SPH solid
        const int itype = nv.type(i);
        sphcut::PairIn in_i;
        double xi[3], vi[3];
        gather_i(nv.pk, i, any_as, xi, vi, in_i);
        const sphcut::TypePair *tprow = &nv.tpt(itype * ntp);
        PairSums sums;
        Kokkos::parallel_reduce(
            Kokkos::ThreadVectorRange(team, nv.numneigh(i)),
            [&](const int jj, PairSums &s) {
              const int j = nv.neighbors(i, jj) & NEIGHMASK;
              sphcut::PairIn in = in_i;
              double mj, Vj;
              if (!gather_j(nv.pk, tprow, j, xi, vi, in, mj, Vj)) return;
              sphcut::PairOut out;
              sphcut::pair_terms<DIM>(kind, in, out);
              sphcut::pair_accumulate<DIM>(in, out, mi * mj, mj, Vj, 1.0, LocalAdd{s.v});
            },
            sums);
        Kokkos::single(Kokkos::PerThread(team), [&]() { store_sums(nv, nv.mt(itype), DIM, corr, hg, sums.v, i); });
      });
}

/* the hourglass control (keyword hourglass, sphcut::hourglass_pair; the CPU style's
   hourglass_loop): a second pass over the full list with L of both particles; each particle
   sums its own share (the pair's force is antisymmetric, its work symmetric), into its force
   and its rate of u after the other rates, as on the CPU                                   */
template <class DeviceType>
template <int DIM>
void PairSPHJCThermalKokkos<DeviceType>::hourglass_pass(int inum)
{
  const NeighViews nv = neigh_views();
  const int kind = mdl.kernel(), ntp = atom->ntypes + 1;
  const double kappa = mdl.hourglass_coefficient();
  using SL = StateLayout;
  Kokkos::parallel_for("sphcut:pair:hourglass_pass",
      sphcut::range<DeviceType>(0, inum), KOKKOS_LAMBDA(const int ii) {
        const int i = nv.ilist(ii);
        const double mi = nv.pk(i, PK_M);
        if (mi == 0.0) return;    // not in the SPH solid
        const int itype = nv.type(i);
        sphcut::PairIn in;
        double xi[3], vi[3], mj, Vj;
        gather_i(nv.pk, i, 0, xi, vi, in);
        const sphcut::TypePair *tprow = &nv.tpt(itype * ntp);
        double hi[4] = {0.0, 0.0, 0.0, 0.0};
        const int jnum = nv.numneigh(i);
        for (int jj = 0; jj < jnum; jj++) {
          const int j = nv.neighbors(i, jj) & NEIGHMASK;
          if (!gather_j(nv.pk, tprow, j, xi, vi, in, mj, Vj)) continue;
          double w, wfac, Mg[3], work;
          sphcut::kernel_w_gradfac_pre(kind, sqrt(in.r2), in.inv_h, in.wnorm, w, wfac);
          sphcut::hourglass_pair<DIM>(kappa, in, wfac, &nv.lg(i, 0), &nv.lg(j, 0), Mg, work);
          for (int a = 0; a < DIM; a++) hi[a] += mi * mj * Mg[a];
          hi[3] += mj * 0.5 * work;
        }
        for (int a = 0; a < DIM; a++) nv.f(i, a) += hi[a];
        nv.st(i, SL::DU) += hi[3];
      });
}

// the classic (host) forward communication of L: only the listed rows travel (sphcut::StagedColumns)
template <class DeviceType>
int PairSPHJCThermalKokkos<DeviceType>::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  return stage_lgrad.pack(k_lgrad, 0, 9, n, list, buf);
}

template <class DeviceType> void PairSPHJCThermalKokkos<DeviceType>::unpack_forward_comm(int n, int first, double *buf)
{
  stage_lgrad.unpack(k_lgrad, 0, 9, n, first, buf);
}

template <class DeviceType>
int PairSPHJCThermalKokkos<DeviceType>::pack_forward_comm_kokkos(int n, SPHCUT_KK_SENDLIST(k_sendlist, iswap),
    sphcut::kk_buf &k_buf, int, int *)
{
  return sphcut::pack_columns<DeviceType>(k_lgrad, 0, 9, n, k_sendlist, SPHCUT_KK_ISWAP(iswap), k_buf);
}

template <class DeviceType>
void PairSPHJCThermalKokkos<DeviceType>::unpack_forward_comm_kokkos(int n, int first, sphcut::kk_buf &k_buf)
{
  sphcut::unpack_columns<DeviceType>(k_lgrad, 0, 9, n, first, k_buf);
}

// per particle after the half-list sums: the rates
template <class DeviceType> void PairSPHJCThermalKokkos<DeviceType>::rates_pass(int nlocal)
{
  auto type = atomKK->k_type.view<DeviceType>();
  auto st = statekk->k_state.template view<DeviceType>();
  auto pk = d_pack;
  auto accv = k_acc.template view<DeviceType>();
  auto mt = d_mat;
  const int corr = mdl.renormalised(), dim = domain->dimension;
  Kokkos::parallel_for("sphcut:pair:rates_pass",
      sphcut::range<DeviceType>(0, nlocal), KOKKOS_LAMBDA(const int i) {
        if (pk(i, PK_M) == 0.0) return;    // not in the SPH solid (stress pass)
        store_rates(mt(type(i)), dim, corr, &accv(i, 0), st, i);
      });
}

/* ---------------------------------------------------------------------- */

template <class DeviceType>
int PairSPHJCThermalKokkos<DeviceType>::pack_reverse_comm(int n, int first, double *buf)
{
  k_acc.sync_host();
  auto h = k_acc.view_host();
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = sphcut::ACC_FIRST_REVERSE; k < sphcut::NACC; k++) buf[m++] = h(i, k);
  return m;
}

template <class DeviceType>
void PairSPHJCThermalKokkos<DeviceType>::unpack_reverse_comm(int n, int *list, double *buf)
{
  k_acc.sync_host();
  auto h = k_acc.view_host();
  int m = 0;
  for (int ii = 0; ii < n; ii++)
    for (int k = sphcut::ACC_FIRST_REVERSE; k < sphcut::NACC; k++) h(list[ii], k) += buf[m++];
  k_acc.modify_host();
}

template <class DeviceType> double PairSPHJCThermalKokkos<DeviceType>::memory_usage()
{
  const int nhg = mdl.hourglass_coefficient() > 0.0 ? 9 : 0;
  return (double) nmax_kk * ((int) d_pack.extent(1) + (neighflag == FULL ? 0 : sphcut::NACC) + nhg) * sizeof(double);
}

namespace LAMMPS_NS {
template class PairSPHJCThermalKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class PairSPHJCThermalKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
