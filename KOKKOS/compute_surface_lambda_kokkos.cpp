/* ----------------------------------------------------------------------
   sphcut - compute surface/lambda/kk: one kernel over the local particles
   and their full device neighbour list, the arithmetic of the CPU compute
   (sphcut_thermal.h).  Recomputed under the same rules as the CPU style
   (every N steps and after each reneighbouring).
------------------------------------------------------------------------- */

#include "compute_surface_lambda_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_jc_thermal_kokkos.h"
#include "memory_kokkos.h"
#include "neigh_list_kokkos.h"
#include "neighbor.h"
#include "sphcut_model.h"
#include "update.h"

#include "sphcut_kernels.h"
#include "sphcut_kokkos.h"
#include "sphcut_thermal.h"

#include <vector>

using namespace LAMMPS_NS;

template <class DeviceType>
ComputeSurfaceLambdaKokkos<DeviceType>::ComputeSurfaceLambdaKokkos(LAMMPS *lmp, int narg, char **arg) :
    ComputeSurfaceLambdaKokkosBase(sphcut::require_kokkos(lmp, "Compute surface/lambda/kk"), narg, arg)
{
  kokkosable = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK;
  datamask_modify = EMPTY_MASK;
}

template <class DeviceType> ComputeSurfaceLambdaKokkos<DeviceType>::~ComputeSurfaceLambdaKokkos()
{
  if (copymode) return;
  memoryKK->destroy_kokkos(k_out, out);
  out = nullptr;    // the base destructor must not free it
}

template <class DeviceType> void ComputeSurfaceLambdaKokkos<DeviceType>::init()
{
  ComputeSurfaceLambda::init();
  sphcut::kokkos_full_list<DeviceType>(neighbor);
  if (!dynamic_cast<FixSPHJCThermalKokkosBase *>(fix))
    error->all(FLERR, "Compute surface/lambda/kk requires fix sph/jc-thermal/kk (run with -sf kk)");
  d_tp = sphcut::to_device<sphcut::ThermalPair, DeviceType>(tpair.data(), (int) tpair.size(), "surface/lambda:tp");
}

// LAMMPS consumers (dumps, variables, fix ave/atom) read the host array
template <class DeviceType> void ComputeSurfaceLambdaKokkos<DeviceType>::compute_peratom()
{
  compute_device();
  k_out.sync_host();
}

template <class DeviceType> void ComputeSurfaceLambdaKokkos<DeviceType>::compute_device()
{
  sphcut::FencedTimer timer(cpu_time);
  if (!begin_step()) return;
  if (domain->dimension == 2) kernel<2>();
  else kernel<3>();
}

// ComputeSurfaceLambda::begin_step with the output a DualView
template <class DeviceType> bool ComputeSurfaceLambdaKokkos<DeviceType>::begin_step()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    k_out.template sync<DeviceType>();
    k_out.template modify<DeviceType>();
    memoryKK->grow_kokkos(k_out, out, nmax, NCOLS, "surface/lambda:out");
    array_atom = out;
    last_step = -1;
  }
  return recompute_due();
}

template <class DeviceType> template <int DIM> void ComputeSurfaceLambdaKokkos<DeviceType>::kernel()
{
  atomKK->sync(execution_space, datamask_read);
  auto *fixkk = dynamic_cast<FixSPHJCThermalKokkosBase *>(fix);
  fixkk->k_state.template sync<DeviceType>();
  k_out.template sync<DeviceType>();
  const auto av = sphcut::atom_views<DeviceType>(atomKK, fixkk->k_state, list);
  auto o = k_out.template view<DeviceType>();
  auto tp = d_tp;
  const int nt = atom->ntypes + 1, kern = model->kernel(), gb = groupbit, hides = tool_hides;
  const int tb = fix->toolbit, cb = fix->clampbit, use_rmass = atom->rmass_flag;
  const double thr = threshold;
  using F = FixSPHJCThermal;
  if (list->inum != atom->nlocal) Kokkos::deep_copy(o, 0.0);

  Kokkos::parallel_for("sphcut:surface:kernel",
      sphcut::range<DeviceType>(0, list->inum), KOKKOS_LAMBDA(const int ii) {
        const int i = av.ilist(ii);
        for (int k = 0; k < NCOLS; k++) o(i, k) = 0.0;
        if (!(av.mask(i) & gb)) return;
        const int itool = sphcut::role_from_mask(av.mask(i), tb, cb) == F::TOOL;
        const double xi[3] = {av.x(i, 0), av.x(i, 1), av.x(i, 2)};
        const int itn = av.type(i) * nt;
        sphcut::SupportMoments<DIM> m;
        sphcut::support_zero<DIM>(m, false);
        for (int jj = 0; jj < av.numneigh(i); jj++) {
          const int j = av.neighbors(i, jj) & NEIGHMASK;
          if (!(av.mask(j) & gb)) continue;
          if (!hides && (sphcut::role_from_mask(av.mask(j), tb, cb) == F::TOOL) != itool) continue;
          const double xj[3] = {av.x(j, 0), av.x(j, 1), av.x(j, 2)};
          double r[3], r2, wfac, ir2;    // r = x_j - x_i
          if (!sphcut::thermal_support(tp(itn + av.type(j)), kern, xj, xi, r, r2, wfac, ir2)) continue;
          const double vj = (use_rmass ? av.rmass(j) : av.mass(av.type(j))) / av.st(j, F::RHO_F);
          sphcut::support_add_surface<DIM>(m, r, -wfac * vj);
        }
        double n[3];
        const double lam = sphcut::support_surface<DIM>(m, thr, n);
        o(i, LAMBDA) = lam;
        o(i, FLAG) = lam < thr ? 1.0 : 0.0;
        for (int a = 0; a < DIM; a++) o(i, NX + a) = n[a];
      });
  k_out.template modify<DeviceType>();
}

namespace LAMMPS_NS {
template class ComputeSurfaceLambdaKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class ComputeSurfaceLambdaKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
