/* ----------------------------------------------------------------------
   sphcut - fix sph/jc-thermal/kk

   One step on the device (doc/design.md):
     initial_integrate  one kernel: keep the old rates, kick, drift,
                        predictor, radial return (sphcut_solid.h)
     pre_force          one kernel zeroing the rates, then the force state
                        to the ghosts by device forward communication
     final_integrate    one reduction: corrector, radial return, plastic
                        heat, and the sums the host needs (plastic work,
                        the next stable dt)
     end_of_step        the new dt (one MPI_Allreduce); the state to the
                        host only on output steps
   Host copies of the state otherwise happen only where LAMMPS needs it on
   the host: exchange and sorting at reneighbouring, restart, setup.
------------------------------------------------------------------------- */

#include "fix_sph_jc_thermal_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "comm.h"
#include "compute.h"
#include "error.h"
#include "force.h"
#include "memory_kokkos.h"
#include "modify.h"
#include "output.h"
#include "pair_sph_jc_thermal.h"
#include "update.h"

#include "sphcut_compat.h"
#include "sphcut_kokkos.h"
#include "sphcut_solid.h"

#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {

/* second half of the step with the two sums the host needs: the plastic
   work of the step and this rank's stable dt (computed from the final v
   and rho, as the CPU fix does at end_of_step)                          */
template <class DeviceType> struct SecondHalf {
  typedef DeviceType device_type;
  typedef double value_type[];
  const unsigned value_count = 2;
  typedef ArrayTypes<DeviceType> AT;
  typename AT::t_v_array v;
  typename AT::t_f_array_const f;
  typename AT::t_int_1d_const mask, type;
  typename AT::t_float_1d_const rmass, mass;
  typename AT::t_double_2d state;
  Kokkos::View<const sphcut::Material *, typename DeviceType::memory_space> mat;
  Kokkos::View<const double *, typename DeviceType::memory_space> h;
  int groupbit, toolbit, clampbit, use_rmass, want_dt, heat_active;
  double dt, dtf, cfl, thermal_cfl;

  KOKKOS_INLINE_FUNCTION void init(value_type r) const
  {
    r[0] = 0.0;
    r[1] = 1.0e300;
  }
  KOKKOS_INLINE_FUNCTION void join(volatile value_type dst, const volatile value_type src) const
  {
    dst[0] += src[0];
    if (src[1] < dst[1]) dst[1] = src[1];
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type r) const
  {
    if (!(mask(i) & groupbit)) return;
    const int t = type(i);
    const int role = sphcut::role_from_mask(mask(i), toolbit, clampbit);
    const double m = use_rmass ? rmass(i) : mass(t);
    double vi[3] = {v(i, 0), v(i, 1), v(i, 2)};
    const double fi[3] = {f(i, 0), f(i, 1), f(i, 2)};
    double *s = &state(i, 0);
    r[0] += sphcut::integrate_second_half(mat(t), role, dt, dtf / m, m, vi, fi, s);
    for (int d = 0; d < 3; d++) v(i, d) = vi[d];
    if (want_dt) {
      const double d = sphcut::particle_dt(mat(t), role, h(t), vi, s[sphcut::StateLayout::RHO], cfl,
                                           heat_active, thermal_cfl);
      if (d < r[1]) r[1] = d;
    }
  }
};

}    // namespace

/* ---------------------------------------------------------------------- */

template <class DeviceType>
FixSPHJCThermalKokkos<DeviceType>::FixSPHJCThermalKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixSPHJCThermalKokkosBase(sphcut::require_kokkos(lmp, "Fix sph/jc-thermal/kk"), narg, arg), dt_next(1.0e300)
{
  kokkosable = 1;
  forward_comm_device = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | V_MASK | F_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK;
  datamask_modify = X_MASK | V_MASK;

  // the base class allocated a host array: replace it by the DualView's host view
  memory->destroy(state);
  state = nullptr;
  grow_arrays(atom->nmax);
  for (int i = 0; i < atom->nlocal; i++) initialize_atom(i);
  k_state.modify_host();
}

template <class DeviceType> FixSPHJCThermalKokkos<DeviceType>::~FixSPHJCThermalKokkos()
{
  memoryKK->destroy_kokkos(k_state, state);
  state = nullptr;    // the base destructor must not free it
}

/* LAMMPS 29Sep2021 matches the state in a restart file to a fix by ID and style name: the /kk fix
   goes by the name of the CPU style (as LAMMPS itself matches from 2022 on, suffix stripped), so a
   restart written by either continues under the other.  kokkosable tells the two apart.        */
template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("sph/jc-thermal");
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::setmask()
{
  // end_of_step every step: the new dt, and the host copy of the state before output
  return FixSPHJCThermal::setmask() | END_OF_STEP;
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::init()
{
  FixSPHJCThermal::init();
  if (!pair->kokkosable)
    error->all(FLERR, "Fix sph/jc-thermal/kk requires pair_style sph/jc-thermal/kk (run with -sf kk)");
  // the other sphcut styles read and write the state on the host: not yet on the device
  for (int i = 0; i < modify->nfix; i++) {
    const std::string st = modify->fix[i]->style;
    if (utils::strmatch(st, "^heat/fmfs") || utils::strmatch(st, "^contact/tri-penalty"))
      error->all(FLERR, "Fix sph/jc-thermal/kk: fix {} has no /kk variant yet; run this scene with "
                 "the CPU styles (without -sf kk)", st);
  }
  for (int i = 0; i < modify->ncompute; i++)
    if (utils::strmatch(modify->compute[i]->style, "^surface/lambda"))
      error->all(FLERR, "Fix sph/jc-thermal/kk: compute {} has no /kk variant yet; run this scene "
                 "with the CPU styles (without -sf kk)", modify->compute[i]->style);
  atomKK->k_mass.modify<LMPHostType>();
  atomKK->k_mass.sync<DeviceType>();
  upload_tables();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::upload_tables()
{
  const int n = atom->ntypes + 1;
  d_mat = sphcut::to_device<sphcut::Material, DeviceType>(pair->materials(), n, "sph/jc-thermal:mat");
  std::vector<double> h(n, 0.0);
  for (int t = 1; t < n; t++) h[t] = pair->smoothing_length(t);
  d_h = sphcut::to_device<double, DeviceType>(h.data(), n, "sph/jc-thermal:h");
}

/* ----------------------------------------------------------------------
   setup: the state of new atoms is completed on the host (it may need an
   atom-style variable), then the forces of the setup step on the device
------------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::setup_pre_force(int vflag)
{
  atomKK->sync(Host, V_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK);
  k_state.sync_host();
  setup_state();
  k_state.modify_host();
  pre_force(vflag);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::setup(int vflag)
{
  atomKK->sync(execution_space, datamask_read);
  FixSPHJCThermal::setup(vflag);    // timers, first stable dt (stable_dt below, on the device)
}

template <class DeviceType> double FixSPHJCThermalKokkos<DeviceType>::stable_dt()
{
  k_state.template sync<DeviceType>();
  auto v = atomKK->k_v.view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  auto mat = d_mat;
  auto h = d_h;
  const int gb = groupbit, tb = toolbit, cb = clampbit, heat = heat_active;
  const double c = cfl, tc = thermal_cfl;
  double dtloc = 1.0e300;
  Kokkos::parallel_reduce(
      Kokkos::RangePolicy<DeviceType>(0, atom->nlocal),
      KOKKOS_LAMBDA(const int i, double &m) {
        if (!(mask(i) & gb)) return;
        const double vi[3] = {v(i, 0), v(i, 1), v(i, 2)};
        const int t = type(i);
        const double d = sphcut::particle_dt(mat(t), sphcut::role_from_mask(mask(i), tb, cb), h(t), vi,
                                             st(i, sphcut::StateLayout::RHO), c, heat, tc);
        if (d < m) m = d;
      },
      Kokkos::Min<double>(dtloc));
  return finish_dt(dtloc);
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::initial_integrate(int)
{
  sphcut::FencedTimer timer(cpu_time);
  atomKK->sync(execution_space, datamask_read);
  k_state.template sync<DeviceType>();
  auto x = atomKK->k_x.view<DeviceType>();
  auto v = atomKK->k_v.view<DeviceType>();
  auto f = atomKK->k_f.view<DeviceType>();
  auto mask = atomKK->k_mask.view<DeviceType>();
  auto type = atomKK->k_type.view<DeviceType>();
  auto rmass = atomKK->k_rmass.view<DeviceType>();
  auto mass = atomKK->k_mass.view<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  auto mat = d_mat;
  const int gb = groupbit, tb = toolbit, cb = clampbit, use_rmass = atom->rmass_flag;
  const double dt = dtv, dtfh = dtf;
  Kokkos::parallel_for(
      Kokkos::RangePolicy<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) {
        if (!(mask(i) & gb)) return;
        const int t = type(i);
        const double m = use_rmass ? rmass(i) : mass(t);
        double xi[3] = {x(i, 0), x(i, 1), x(i, 2)};
        double vi[3] = {v(i, 0), v(i, 1), v(i, 2)};
        const double fi[3] = {f(i, 0), f(i, 1), f(i, 2)};
        sphcut::integrate_first_half(mat(t), sphcut::role_from_mask(mask(i), tb, cb), dt, dtfh / m, xi, vi,
                                     fi, &st(i, 0));
        for (int d = 0; d < 3; d++) {
          x(i, d) = xi[d];
          v(i, d) = vi[d];
        }
      });
  k_state.template modify<DeviceType>();
  atomKK->modified(execution_space, datamask_modify);
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::pre_force(int)
{
  sphcut::FencedTimer timer(cpu_time);
  k_state.template sync<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  Kokkos::parallel_for(
      Kokkos::RangePolicy<DeviceType>(0, atom->nlocal), KOKKOS_LAMBDA(const int i) { sphcut::zero_rates(&st(i, 0)); });
  k_state.template modify<DeviceType>();
  // the force state to the ghosts: on the device unless LAMMPS takes the classic path
  sphcut::forward_comm(comm, this);
}

template <class DeviceType>
int FixSPHJCThermalKokkos<DeviceType>::pack_forward_comm_fix_kokkos(int n, DAT::tdual_int_2d k_sendlist,
                                                                     int iswap, DAT::tdual_xfloat_1d &k_buf,
                                                                     int, int *)
{
  k_state.template sync<DeviceType>();
  auto list = k_sendlist.view<DeviceType>();
  auto buf = k_buf.view<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  Kokkos::parallel_for(
      Kokkos::RangePolicy<DeviceType>(0, n), KOKKOS_LAMBDA(const int ii) {
        const int j = list(iswap, ii);
        for (int k = 0; k < NFORWARD; k++) buf(ii * NFORWARD + k) = st(j, FORWARD_FIRST + k);
      });
  return n * NFORWARD;
}

template <class DeviceType>
void FixSPHJCThermalKokkos<DeviceType>::unpack_forward_comm_fix_kokkos(int n, int first, DAT::tdual_xfloat_1d &k_buf)
{
  k_state.template sync<DeviceType>();
  auto buf = k_buf.view<DeviceType>();
  auto st = k_state.template view<DeviceType>();
  Kokkos::parallel_for(
      Kokkos::RangePolicy<DeviceType>(0, n), KOKKOS_LAMBDA(const int ii) {
        for (int k = 0; k < NFORWARD; k++) st(first + ii, FORWARD_FIRST + k) = buf(ii * NFORWARD + k);
      });
  k_state.template modify<DeviceType>();
}

/* ---------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::final_integrate()
{
  sphcut::FencedTimer timer(cpu_time);
  atomKK->sync(execution_space, datamask_read);
  k_state.template sync<DeviceType>();
  SecondHalf<DeviceType> k;
  k.v = atomKK->k_v.view<DeviceType>();
  k.f = atomKK->k_f.view<DeviceType>();
  k.mask = atomKK->k_mask.view<DeviceType>();
  k.type = atomKK->k_type.view<DeviceType>();
  k.rmass = atomKK->k_rmass.view<DeviceType>();
  k.mass = atomKK->k_mass.view<DeviceType>();
  k.state = k_state.template view<DeviceType>();
  k.mat = d_mat;
  k.h = d_h;
  k.groupbit = groupbit;
  k.toolbit = toolbit;
  k.clampbit = clampbit;
  k.use_rmass = atom->rmass_flag;
  k.want_dt = cfl > 0.0;
  k.heat_active = heat_active;
  k.dt = dtv;
  k.dtf = dtf;
  k.cfl = cfl;
  k.thermal_cfl = thermal_cfl;
  double sums[2] = {0.0, 1.0e300};
  Kokkos::parallel_reduce(Kokkos::RangePolicy<DeviceType>(0, atom->nlocal), k, sums);
  plastic_work += sums[0];
  dt_next = sums[1];
  k_state.template modify<DeviceType>();
  atomKK->modified(execution_space, V_MASK);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::end_of_step()
{
  sphcut::FencedTimer timer(cpu_time);
  if (cfl > 0.0) apply_dt(finish_dt(dt_next));
  // dumps and f_ID outputs read the host array on output steps
  if (update->ntimestep == output->next) k_state.sync_host();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::post_run()
{
  k_state.sync_host();    // the state readable after the run (library interface, tests)
  FixSPHJCThermal::post_run();
}

template <class DeviceType> double FixSPHJCThermalKokkos<DeviceType>::compute_vector(int n)
{
  if (n > 0) {
    atomKK->sync(Host, V_MASK | MASK_MASK | TYPE_MASK | RMASS_MASK);
    k_state.sync_host();
  }
  return FixSPHJCThermal::compute_vector(n);
}

/* ----------------------------------------------------------------------
   host paths: grow, exchange, sort, restart, classic forward comm.  Each
   syncs the host view first and marks it modified when it writes.
------------------------------------------------------------------------- */

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::grow_arrays(int nmax)
{
  // Kokkos 3.4 DualView::resize leaves the host mirror unset unless the host is current
  k_state.sync_host();
  k_state.modify_host();
  memoryKK->grow_kokkos(k_state, state, nmax, NCOL, "sph/jc-thermal:state");
  k_state.modify_host();
  array_atom = state;
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::set_arrays(int i)
{
  k_state.sync_host();
  initialize_atom(i);
  k_state.modify_host();
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::copy_arrays(int i, int j, int delflag)
{
  k_state.sync_host();
  FixSPHJCThermal::copy_arrays(i, j, delflag);
  k_state.modify_host();
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::pack_exchange(int i, double *buf)
{
  k_state.sync_host();
  return FixSPHJCThermal::pack_exchange(i, buf);
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::unpack_exchange(int nlocal, double *buf)
{
  k_state.sync_host();
  const int n = FixSPHJCThermal::unpack_exchange(nlocal, buf);
  k_state.modify_host();
  return n;
}

template <class DeviceType> int FixSPHJCThermalKokkos<DeviceType>::pack_restart(int i, double *buf)
{
  k_state.sync_host();
  return FixSPHJCThermal::pack_restart(i, buf);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::unpack_restart(int nlocal, int nth)
{
  k_state.sync_host();
  FixSPHJCThermal::unpack_restart(nlocal, nth);
  k_state.modify_host();
}

template <class DeviceType>
int FixSPHJCThermalKokkos<DeviceType>::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  k_state.sync_host();
  return FixSPHJCThermal::pack_forward_comm(n, list, buf, pbc_flag, pbc);
}

template <class DeviceType> void FixSPHJCThermalKokkos<DeviceType>::unpack_forward_comm(int n, int first, double *buf)
{
  k_state.sync_host();
  FixSPHJCThermal::unpack_forward_comm(n, first, buf);
  k_state.modify_host();
}

namespace LAMMPS_NS {
template class FixSPHJCThermalKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixSPHJCThermalKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
