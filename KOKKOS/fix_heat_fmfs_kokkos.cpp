/* ----------------------------------------------------------------------
   sphcut - fix heat/fmfs/kk

   One evaluation on the device (every N steps, as the CPU fix):
     conservative (default)  kernel 1: per particle the scheme (FMFS or
                             Brookshaw) and the FMFS pair weights; device
                             forward communication of the weights; kernel 2:
                             the pairwise exchange and the surface losses
                             into the held rate (state column HELD)
     conservative no         one kernel: the FMFS or Brookshaw Laplacian
   Every step one kernel adds the held rate to the temperature rate DTEMP.
   Dirichlet groups: one kernel after the predictor, one reduction after
   the corrector (the heat through the clamp).  The few global sums (loss
   rates, scheme counters, clamp heat) come back by parallel_reduce.
------------------------------------------------------------------------- */

#include "fix_heat_fmfs_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "comm.h"
#include "compute_surface_lambda_kokkos.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_jc_thermal_kokkos.h"
#include "neigh_list_kokkos.h"
#include "neighbor.h"
#include "sphcut_model.h"
#include "update.h"

#include "sphcut_compat.h"
#include "sphcut_kernels.h"
#include "sphcut_kokkos.h"
#include "sphcut_thermal.h"

#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
constexpr int NW = 1 + 3 * 3 + 3;    // scheme flag, Gf (3x3), z (3)
}    // namespace

namespace {
// the Dirichlet groups back to their temperature after the corrector, and the heat that took
// (FixHeatFMFS::final_integrate); final adds this step's sum to the accumulator on the device
template <class DeviceType> struct DirichletEnergy {
  typedef DeviceType device_type;
  typedef double value_type;
  typedef ArrayTypes<DeviceType> AT;
  typedef typename DeviceType::memory_space mem;
  typename AT::t_double_2d st;
  typename AT::t_int_1d_const mask, type;
  typename sphcut::AtomTypes<DeviceType>::scalar_const rmass, mass;
  Kokkos::View<const sphcut::Material *, mem> mat;
  Kokkos::View<const int *, mem> db;
  Kokkos::View<const double *, mem> dtemp;
  Kokkos::View<double *, mem> acc;
  int gb, nd, use_rmass;
  KOKKOS_INLINE_FUNCTION void operator()(const int i, double &sum) const
  {
    const int k = sphcut::dirichlet_index(mask(i), gb, &db(0), nd);
    if (k < 0) return;
    const int t = type(i);
    const double m = use_rmass ? rmass(i) : mass(t);
    sum += m * mat(t).cp * (dtemp(k) - st(i, FixSPHJCThermal::TEMP));
    st(i, FixSPHJCThermal::TEMP) = dtemp(k);
  }
  KOKKOS_INLINE_FUNCTION void final(double &sum) const { acc(0) += sum; }
};
}    // namespace

template <class DeviceType>
FixHeatFMFSKokkos<DeviceType>::FixHeatFMFSKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixHeatFMFS(sphcut::require_kokkos(lmp, "Fix heat/fmfs/kk"), narg, arg), fixkk(nullptr), surfkk(nullptr)
{
  kokkosable = 1;
  forward_comm_device = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK;
  datamask_modify = EMPTY_MASK;
}

template <class DeviceType> FixHeatFMFSKokkos<DeviceType>::~FixHeatFMFSKokkos() {}

// restart files match fixes by ID and style: the /kk fix goes by the CPU style's name (as the
// mechanics fix does), so the energy budget continues under either
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("heat/fmfs");
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::init()
{
  FixHeatFMFS::init();
  sphcut::kokkos_full_list<DeviceType>(neighbor);
  fixkk = dynamic_cast<FixSPHJCThermalKokkosBase *>(fix);
  if (!fixkk) error->all(FLERR, "Fix heat/fmfs/kk requires fix sph/jc-thermal/kk (run with -sf kk)");
  fixkk->therm_bit = groupbit;    // the thermal dt limit in fix sph/jc-thermal/kk's reduction
  fixkk->therm_every = every;
  fixkk->therm_step = -1;
  surfkk = nullptr;
  if (surface) {
    surfkk = dynamic_cast<ComputeSurfaceLambdaKokkosBase *>(surface);
    if (!surfkk)
      error->all(FLERR, "Fix heat/fmfs/kk: surface compute {} is not compute surface/lambda/kk (run with -sf kk)",
                 id_surface);
  }
  const int n = atom->ntypes + 1;
  d_mat = sphcut::to_device<sphcut::Material, DeviceType>(model->materials(), n, "heat/fmfs:mat");
  std::vector<double> hij((size_t) n * n, 0.0), h(n, 0.0);
  for (int i = 1; i < n; i++) {
    h[i] = model->smoothing_length(i);
    for (int j = 1; j < n; j++) hij[(size_t) i * n + j] = model->smoothing_length(i, j);
  }
  d_hij = sphcut::to_device<double, DeviceType>(hij.data(), n * n, "heat/fmfs:hij");
  d_h = sphcut::to_device<double, DeviceType>(h.data(), n, "heat/fmfs:h");
  d_tp = sphcut::to_device<sphcut::ThermalPair, DeviceType>(tpair.data(), (int) tpair.size(), "heat/fmfs:tp");
  const int nd = (int) dirichlet.size();
  std::vector<int> db(nd + 1, 0);
  std::vector<double> dtemp(nd + 1, 0.0);
  for (int k = 0; k < nd; k++) {
    db[k] = dirichlet[k].groupbit;
    dtemp[k] = dirichlet[k].temp;
  }
  d_dirbit = sphcut::to_device<int, DeviceType>(db.data(), nd + 1, "heat/fmfs:dirbit");
  d_dirtemp = sphcut::to_device<double, DeviceType>(dtemp.data(), nd + 1, "heat/fmfs:dirtemp");
}

/* thermal time step limit of this rank (a reduction on the device; taken by fix sph/jc-thermal
   every step with the other attached styles' limits) */
template <class DeviceType> double FixHeatFMFSKokkos<DeviceType>::dt_limit(double, double Fc) const
{
  if (!fixkk || d_mat.extent(0) == 0) return 1.0e300;
  // computed by fix sph/jc-thermal/kk after this step's corrector (its final_integrate)
  if (fixkk->therm_step == update->ntimestep && fixkk->therm_F == Fc) return fixkk->therm_dt;
  fixkk->k_state.template sync<DeviceType>();
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto mat = d_mat;
  auto h = d_h;
  const int gb = groupbit, ev = every;
  double dt = 1.0e300;
  Kokkos::parallel_reduce("sphcut:heat:dt_limit",
      sphcut::range<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &m) {
        if (!(mask(i) & gb)) return;
        const int t = type(i);
        const double d = sphcut::thermal_dt_limit(st(i, FixSPHJCThermal::RHO), mat(t).cp, mat(t).kappa, h(t), Fc, ev);
        if (d < m) m = d;
      },
      Kokkos::Min<double>(dt));
  return dt;
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::setup(int vflag)
{
  check_timestep();
  if (!dirichlet.empty()) {
    set_dirichlet(true);    // Dirichlet particles start at their temperature
    sphcut::forward_comm(comm, fix);
  }
  post_force(vflag);
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::post_force(int)
{
  const int eval = every == 1 || update->setupflag || update->ntimestep % every == 0;
  if (eval) begin_evaluation();
  sphcut::FencedTimer timer(cpu_time);
  atomKK->sync(execution_space, datamask_read);
  fixkk->k_state.template sync<DeviceType>();
  if (eval) {
    if (conservative) {
      if (domain->dimension == 2) conduction_conservative_kk<2>();
      else conduction_conservative_kk<3>();
    } else {
      if (domain->dimension == 2) conduction_kk<2>();
      else conduction_kk<3>();
    }
  }
  add_held();
  if (!update->setupflag) {
    q_conv += 0.5 * update->dt * (p_conv_prev + held_conv);
    q_rad += 0.5 * update->dt * (p_rad_prev + held_rad);
  }
  p_conv_prev = held_conv;
  p_rad_prev = held_rad;
}

// FixHeatFMFS::begin_evaluation with the compute's values on the device
template <class DeviceType> bool FixHeatFMFSKokkos<DeviceType>::begin_evaluation()
{
  fuse_surface = false;
  if (!surfkk || surfkk->invoked_peratom == update->ntimestep) return false;
  if (conservative && surfkk->fusable(groupbit)) fuse_surface = surfkk->begin_step();
  else surfkk->compute_device();
  return fuse_surface;
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::add_held()
{
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  const int gb = groupbit;
  Kokkos::parallel_for("sphcut:heat:add_held",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
        if (mask(i) & gb) st(i, FixSPHJCThermal::DTEMP) += st(i, FixSPHJCThermal::HELD);
      });
  fixkk->k_state.template modify<DeviceType>();
}

/* the non-conservative form: FMFS Laplacian or Brookshaw per particle (FixHeatFMFS::conduction) */
template <class DeviceType> template <int DIM> void FixHeatFMFSKokkos<DeviceType>::conduction_kk()
{
  using F = FixSPHJCThermal;
  const auto av = sphcut::atom_views<DeviceType>(atomKK, fixkk->k_state, list);
  typename AT::t_double_2d surf;
  if (surfkk) surf = surfkk->k_out.template view<DeviceType>();
  auto mat = d_mat;
  auto hij = d_hij;
  const int nt = atom->ntypes + 1, kern = model->kernel(), gb = groupbit, use_rmass = atom->rmass_flag;
  const int has_surf = surfkk != nullptr, fmfs = scheme == FMFS;
  const double flam = fmfs_lambda, hc = hconv, tc = tconv, es = emiss * sphcut::STEFAN_BOLTZMANN_SI, tr = trad;
  const int losses = hconv > 0.0 || emiss > 0.0;
  double pc = 0.0, pr = 0.0, nf = 0.0, nb = 0.0, nfb = 0.0;

  Kokkos::parallel_for("sphcut:heat:zero_held_pp",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) { av.st(i, F::HELD) = 0.0; });
  Kokkos::parallel_reduce("sphcut:heat:per_particle",
      sphcut::range<DeviceType>(0, list->inum),
      KOKKOS_LAMBDA(const int ii, double &p_conv, double &p_rad, double &c_fmfs, double &c_brook, double &c_fall) {
        const int i = av.ilist(ii);
        if (!(av.mask(i) & gb)) return;
        const int itype = av.type(i);
        const sphcut::Material &mi = mat(itype);
        if (mi.cp <= 0.0) return;
        const double Ti = av.st(i, F::TEMP_F), rhoi = av.st(i, F::RHO_F);
        const double massi = use_rmass ? av.rmass(i) : av.mass(itype);
        const int is_surf = has_surf ? surf(i, ComputeSurfaceLambda::FLAG) > 0.5 : 0;
        int use_fmfs = fmfs && !is_surf && mi.kappa > 0.0;
        double brook = 0.0;
        sphcut::FmfsAccum<DIM> acc;
        if (use_fmfs) sphcut::fmfs_zero<DIM>(acc);
        const double xi[3] = {av.x(i, 0), av.x(i, 1), av.x(i, 2)};
        for (int jj = 0; jj < av.numneigh(i); jj++) {
          const int j = av.neighbors(i, jj) & NEIGHMASK;
          if (!(av.mask(j) & gb)) continue;
          const int jtype = av.type(j);
          const double h = hij(itype * nt + jtype);
          const double xj[3] = {av.x(j, 0), av.x(j, 1), av.x(j, 2)};
          double dx[3], r2;
          if (!sphcut::in_support(xi, xj, h, dx, r2)) continue;
          double w, wfac;
          sphcut::kernel_w_gradfac(kern, DIM, sqrt(r2), h, w, wfac);
          const double Tj = av.st(j, F::TEMP_F);
          const double vj = (use_rmass ? av.rmass(j) : av.mass(jtype)) / av.st(j, F::RHO_F);
          const double kj = mat(jtype).kappa;
          brook += vj * sphcut::brookshaw_pair_radial(Ti, Tj, mi.kappa, kj, wfac);
          if (use_fmfs) {
            if (kj != mi.kappa) {
              use_fmfs = 0;
              continue;
            }
            const double r[3] = {-dx[0], -dx[1], -dx[2]};
            const double g[3] = {wfac * dx[0], wfac * dx[1], wfac * dx[2]};
            sphcut::fmfs_add<DIM>(acc, r, g, vj, Tj - Ti);
          }
        }
        double rate, lap;
        if (use_fmfs && sphcut::surface_lambda<DIM>(acc.B) < flam) use_fmfs = 0;
        if (use_fmfs && sphcut::fmfs_laplacian<DIM>(acc, lap)) {
          rate = mi.kappa * lap;
          c_fmfs += 1.0;
        } else {
          if (use_fmfs) c_fall += 1.0;
          rate = brook;
          c_brook += 1.0;
        }
        double dT = rate / (rhoi * mi.cp);
        if (is_surf && losses) {
          double qc, qr;
          sphcut::surface_losses(DIM, massi / rhoi, Ti, hc, tc, es, tr, qc, qr);
          p_conv += qc;
          p_rad += qr;
          dT -= (qc + qr) / (massi * mi.cp);
        }
        av.st(i, F::HELD) = dT;
      },
      pc, pr, nf, nb, nfb);
  fixkk->k_state.template modify<DeviceType>();
  held_conv = pc;
  held_rad = pr;
  n_fmfs += (bigint) nf;
  n_brookshaw += (bigint) nb;
  n_fallback += (bigint) nfb;
}

/* the conservative form (FixHeatFMFS::conduction_conservative): one thread per particle walks
   its neighbours once for the surface indicator (fused: into the compute's values) and the FMFS
   moments, the same sums in the same order as the CPU fix */
template <class DeviceType> template <int DIM> void FixHeatFMFSKokkos<DeviceType>::conduction_conservative_kk()
{
  using F = FixSPHJCThermal;
  using CS = ComputeSurfaceLambda;
  if ((int) k_fwts.extent(0) < atom->nmax) k_fwts = DAT::tdual_double_2d("heat/fmfs:fwts", atom->nmax, NW);
  k_fwts.template sync<DeviceType>();
  const auto av = sphcut::atom_views<DeviceType>(atomKK, fixkk->k_state, list);
  auto fw = k_fwts.template view<DeviceType>();
  typename AT::t_double_2d surf;
  if (surfkk) {
    surfkk->k_out.template sync<DeviceType>();
    surf = surfkk->k_out.template view<DeviceType>();
  }
  auto mat = d_mat;
  auto tp = d_tp;
  const int nt = atom->ntypes + 1, kern = model->kernel(), gb = groupbit, use_rmass = atom->rmass_flag;
  const int has_surf = surfkk != nullptr, fmfs = scheme == FMFS, fuse = fuse_surface;
  const double flam = fmfs_lambda, hc = hconv, tc = tconv, es = emiss * sphcut::STEFAN_BOLTZMANN_SI, tr = trad;
  const double thr = surfkk ? surfkk->threshold : 0.0;
  const int losses = hconv > 0.0 || emiss > 0.0;
  const int nall = atom->nlocal + atom->nghost;

  // 1. the surface indicator, the scheme of each particle and its FMFS pair weights
  double nf = 0.0, nb = 0.0, nfb = 0.0;
  Kokkos::parallel_for("sphcut:heat:zero_weights",
      sphcut::range<DeviceType>(0, nall), KOKKOS_LAMBDA(const int i) { fw(i, 0) = 0.0; });
  if (fuse)
    Kokkos::parallel_for(
        "sphcut:heat:zero_surface", sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
          for (int k = 0; k < CS::NCOLS; k++) surf(i, k) = 0.0;
        });
  Kokkos::parallel_reduce("sphcut:heat:weights",
      sphcut::range<DeviceType>(0, list->inum),
      KOKKOS_LAMBDA(const int ii, double &c_fmfs, double &c_brook, double &c_fall) {
        const int i = av.ilist(ii);
        if (!(av.mask(i) & gb)) return;
        const int itype = av.type(i);
        const sphcut::Material &mi = mat(itype);
        const int conducts = mi.cp > 0.0;
        const int was_surf = !fuse && has_surf && surf(i, CS::FLAG) > 0.5;
        int cand = conducts && fmfs && mi.kappa > 0.0 && !was_surf;
        if (!fuse && !cand) {
          if (conducts) c_brook += 1.0;
          return;
        }
        const int itn = itype * nt;
        const double xi[3] = {av.x(i, 0), av.x(i, 1), av.x(i, 2)};
        sphcut::SupportMoments<DIM> m;
        sphcut::support_zero<DIM>(m, cand);
        for (int jj = 0; jj < av.numneigh(i); jj++) {
          const int j = av.neighbors(i, jj) & NEIGHMASK;
          if (!(av.mask(j) & gb)) continue;
          const sphcut::ThermalPair &tij = tp(itn + av.type(j));
          const double xj[3] = {av.x(j, 0), av.x(j, 1), av.x(j, 2)};
          double dx[3], r2, wfac, ir2;
          if (!sphcut::thermal_support(tij, kern, xi, xj, dx, r2, wfac, ir2)) continue;
          const double r[3] = {-dx[0], -dx[1], -dx[2]};    // x_j - x_i
          const double s = -wfac * ((use_rmass ? av.rmass(j) : av.mass(av.type(j))) / av.st(j, F::RHO_F));
          sphcut::support_add_surface<DIM>(m, r, s);
          if (cand) {
            if (tij.same_kappa) sphcut::support_add_fmfs<DIM>(m, r, s, ir2);
            else cand = 0;    // material interface: Brookshaw
          }
        }
        double lam = 0.0;
        if (fuse) {
          double n[3];
          lam = sphcut::support_surface<DIM>(m, thr, n);
          surf(i, CS::LAMBDA) = lam;
          surf(i, CS::FLAG) = lam < thr ? 1.0 : 0.0;
          for (int a = 0; a < DIM; a++) surf(i, CS::NX + a) = n[a];
          if (lam < thr) cand = 0;
        } else if (cand) {
          double B[DIM][DIM];
          sphcut::support_matrix<DIM>(m, B);
          lam = sphcut::surface_lambda<DIM>(B);
        }
        if (!conducts) return;
        int ok = 0;
        if (cand && lam >= flam) {
          sphcut::FmfsAccum<DIM> acc;
          sphcut::support_to_fmfs<DIM>(m, acc);
          double wts[NW - 1];
          if (sphcut::fmfs_weights<DIM>(acc, wts)) {
            for (int k = 0; k < NW - 1; k++) fw(i, 1 + k) = wts[k];
            ok = 1;
          } else c_fall += 1.0;
        }
        fw(i, 0) = ok ? 1.0 : 0.0;
        if (ok) c_fmfs += 1.0;
        else c_brook += 1.0;
      },
      nf, nb, nfb);
  k_fwts.template modify<DeviceType>();
  if (fuse) surfkk->k_out.template modify<DeviceType>();
  n_fmfs += (bigint) nf;
  n_brookshaw += (bigint) nb;
  n_fallback += (bigint) nfb;
  sphcut::forward_comm(comm, this);
  k_fwts.template sync<DeviceType>();

  // 2. the pairwise exchange with the mean weight, and the surface losses
  double pc = 0.0, pr = 0.0;
  Kokkos::parallel_for("sphcut:heat:zero_held",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) { av.st(i, F::HELD) = 0.0; });
  Kokkos::parallel_reduce("sphcut:heat:exchange",
      sphcut::range<DeviceType>(0, list->inum),
      KOKKOS_LAMBDA(const int ii, double &p_conv, double &p_rad) {
        const int i = av.ilist(ii);
        if (!(av.mask(i) & gb)) return;
        const int itype = av.type(i);
        const sphcut::Material &mi = mat(itype);
        if (mi.cp <= 0.0) return;
        const double Ti = av.st(i, F::TEMP_F), rhoi = av.st(i, F::RHO_F);
        const double massi = use_rmass ? av.rmass(i) : av.mass(itype);
        const int fi = fw(i, 0) > 0.0;
        const int itn = itype * nt;
        const double xi[3] = {av.x(i, 0), av.x(i, 1), av.x(i, 2)};
        double rate = 0.0;
        for (int jj = 0; jj < av.numneigh(i); jj++) {
          const int j = av.neighbors(i, jj) & NEIGHMASK;
          if (!(av.mask(j) & gb)) continue;
          const int jtype = av.type(j);
          const sphcut::ThermalPair &tij = tp(itn + jtype);
          const double xj[3] = {av.x(j, 0), av.x(j, 1), av.x(j, 2)};
          double dx[3], r2, wfac, ir2;
          if (!sphcut::thermal_support(tij, kern, xi, xj, dx, r2, wfac, ir2)) continue;
          const double mdx[3] = {-dx[0], -dx[1], -dx[2]};
          const double ai = fi ? mi.kappa * sphcut::fmfs_pair_weight_radial<DIM>(&fw(i, 1), dx, ir2) : tij.brook;
          const double aj =
              fw(j, 0) > 0.0 ? mat(jtype).kappa * sphcut::fmfs_pair_weight_radial<DIM>(&fw(j, 1), mdx, ir2) : tij.brook;
          const double vj = (use_rmass ? av.rmass(j) : av.mass(jtype)) / av.st(j, F::RHO_F);
          rate += vj * wfac * sphcut::conductance_pair(ai, aj, tij.brook) * (av.st(j, F::TEMP_F) - Ti);
        }
        double dT = rate / (rhoi * mi.cp);
        const int is_surf = has_surf ? surf(i, CS::FLAG) > 0.5 : 0;
        if (is_surf && losses) {
          double qc, qr;
          sphcut::surface_losses(DIM, massi / rhoi, Ti, hc, tc, es, tr, qc, qr);
          p_conv += qc;
          p_rad += qr;
          dT -= (qc + qr) / (massi * mi.cp);
        }
        av.st(i, F::HELD) = dT;
      },
      pc, pr);
  fixkk->k_state.template modify<DeviceType>();
  held_conv = pc;
  held_rad = pr;
}

/* ---------------------------------------------------------------------- */

#ifdef SPHCUT_KK_API_2026
template <class DeviceType>
int FixHeatFMFSKokkos<DeviceType>::pack_forward_comm_kokkos(int n, DAT::tdual_int_1d k_sendlist,
                                                            DAT::tdual_double_1d &k_buf, int, int *)
{
  return sphcut::pack_columns<DeviceType>(k_fwts, 0, NW, n, k_sendlist, 0, k_buf);
}

template <class DeviceType>
void FixHeatFMFSKokkos<DeviceType>::unpack_forward_comm_kokkos(int n, int first, DAT::tdual_double_1d &k_buf)
{
  sphcut::unpack_columns<DeviceType>(k_fwts, 0, NW, n, first, k_buf);
}
#else
template <class DeviceType>
int FixHeatFMFSKokkos<DeviceType>::pack_forward_comm_fix_kokkos(int n, DAT::tdual_int_2d k_sendlist, int iswap,
                                                                 DAT::tdual_xfloat_1d &k_buf, int, int *)
{
  return sphcut::pack_columns<DeviceType>(k_fwts, 0, NW, n, k_sendlist, iswap, k_buf);
}

template <class DeviceType>
void FixHeatFMFSKokkos<DeviceType>::unpack_forward_comm_fix_kokkos(int n, int first, DAT::tdual_xfloat_1d &k_buf)
{
  sphcut::unpack_columns<DeviceType>(k_fwts, 0, NW, n, first, k_buf);
}
#endif

// the classic (host) path of the forward communication
template <class DeviceType>
int FixHeatFMFSKokkos<DeviceType>::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  return sphcut::pack_columns_host(k_fwts, NW, n, list_, buf);
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::unpack_forward_comm(int n, int first, double *buf)
{
  sphcut::unpack_columns_host(k_fwts, NW, n, first, buf);
}

/* ----------------------------------------------------------------------
   Dirichlet groups (FixHeatFMFS::initial_integrate, final_integrate)
------------------------------------------------------------------------- */

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::initial_integrate(int)
{
  if (dirichlet.empty()) return;
  sphcut::FencedTimer timer(cpu_time);
  set_dirichlet(false);
}

// Dirichlet particles to their temperature: the predicted one (TEMP_F), with also_temp the
// temperature itself (setup)
template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::set_dirichlet(bool also_temp)
{
  atomKK->sync(execution_space, MASK_MASK);
  fixkk->k_state.template sync<DeviceType>();
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto db = d_dirbit;
  auto dtemp = d_dirtemp;
  const int gb = groupbit, nd = (int) dirichlet.size(), both = also_temp;
  Kokkos::parallel_for("sphcut:heat:set_dirichlet",
      sphcut::range<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
        const int k = sphcut::dirichlet_index(mask(i), gb, &db(0), nd);
        if (k < 0) return;
        st(i, FixSPHJCThermal::TEMP_F) = dtemp(k);
        if (both) st(i, FixSPHJCThermal::TEMP) = dtemp(k);
      });
  fixkk->k_state.template modify<DeviceType>();
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::final_integrate()
{
  if (dirichlet.empty()) return;
  sphcut::FencedTimer timer(cpu_time);
  atomKK->sync(execution_space, MASK_MASK | TYPE_MASK | RMASS_MASK);
  fixkk->k_state.template sync<DeviceType>();
  DirichletEnergy<DeviceType> k;
  k.st = fixkk->k_state.template view<DeviceType>();
  k.mask = atomKK->k_mask.view<DeviceType>();
  k.type = atomKK->k_type.view<DeviceType>();
  k.rmass = atomKK->k_rmass.view<DeviceType>();
  k.mass = atomKK->k_mass.view<DeviceType>();
  k.mat = d_mat;
  k.db = d_dirbit;
  k.dtemp = d_dirtemp;
  k.gb = groupbit;
  k.nd = (int) dirichlet.size();
  k.use_rmass = atom->rmass_flag;
  if (d_qdir.extent(0) != 2) d_qdir = Kokkos::View<double *, typename DeviceType::memory_space>("heat:qdir", 2);
  k.acc = d_qdir;
  // the sum goes to d_qdir(1) and is added to d_qdir(0) on the device (final): no host round trip
  Kokkos::parallel_reduce("sphcut:heat:final_integrate", sphcut::range<DeviceType>(0, atom->nlocal), k,
                          Kokkos::subview(d_qdir, 1));
  fixkk->k_state.template modify<DeviceType>();
  qdir_stale = 1;
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::fetch_dirichlet()
{
  if (!qdir_stale) return;
  qdir_stale = 0;
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d_qdir);
  q_dirichlet += h(0);
  Kokkos::deep_copy(Kokkos::subview(d_qdir, 0), 0.0);
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::write_restart(FILE *fp)
{
  fetch_dirichlet();
  FixHeatFMFS::write_restart(fp);
}

template <class DeviceType> void FixHeatFMFSKokkos<DeviceType>::post_run()
{
  fetch_dirichlet();
  FixHeatFMFS::post_run();
}

// element 5 (thermal energy) is summed on the device; the others are host scalars
template <class DeviceType> double FixHeatFMFSKokkos<DeviceType>::compute_vector(int n)
{
  fetch_dirichlet();
  if (n != 4 || !fixkk) return FixHeatFMFS::compute_vector(n);
  atomKK->sync(execution_space, MASK_MASK | TYPE_MASK | RMASS_MASK);
  fixkk->k_state.template sync<DeviceType>();
  auto st = fixkk->k_state.template view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto rmass = atomKK->k_rmass.view<DeviceType>();
  auto mass = atomKK->k_mass.view<DeviceType>();
  auto mat = d_mat;
  const int gb = groupbit, use_rmass = atom->rmass_flag;
  double loc = 0.0, res = 0.0;
  Kokkos::parallel_reduce("sphcut:heat:compute_vector",
      sphcut::range<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &sum) {
        if (!(mask(i) & gb)) return;
        const int t = type(i);
        sum += (use_rmass ? rmass(i) : mass(t)) * mat(t).cp * st(i, FixSPHJCThermal::TEMP);
      },
      loc);
  MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_SUM, world);
  return res;
}

namespace LAMMPS_NS {
template class FixHeatFMFSKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixHeatFMFSKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
