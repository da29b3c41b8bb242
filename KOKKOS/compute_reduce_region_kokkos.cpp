/* ----------------------------------------------------------------------
   sphcut - compute reduce/region/kk (see the header).  The device path:
   the region's displacement from its prematch() on the host, then one
   reduction over the local particles per value (the group, the block, the
   value), the ranks' results combined as LAMMPS' compute reduce does.
------------------------------------------------------------------------- */

#include "compute_reduce_region_kokkos.h"

#include "arg_info.h"
#include "atom_kokkos.h"
#include "atom_masks.h"
#include "domain.h"
#include "fix_sph_jc_thermal_kokkos.h"
#include "modify.h"
#include "region.h"
#include "region_block.h"
#include "update.h"
#include "utils.h"

#include "sphcut_compat.h"
#include "sphcut_kokkos.h"

using namespace LAMMPS_NS;

namespace {

// the particles of the group inside the block (lo, hi after the region's displacement d): the
// sum, minimum or maximum of column col of vals (its square for sumsq, avesq) and their count
template <class DeviceType, class Values> struct RegionReduce {
  typedef DeviceType device_type;
  struct value_type {
    double v, n;
  };
  typename sphcut::AtomTypes<DeviceType>::x_const x;
  typename ArrayTypes<DeviceType>::t_int_1d_const mask;
  Values vals;
  int col, groupbit, mode;
  double lo[3], hi[3], d[3];

  KOKKOS_INLINE_FUNCTION void init(value_type &a) const
  {
    a.v = mode == ComputeReduce::MINN ? 1.0e20 : (mode == ComputeReduce::MAXX ? -1.0e20 : 0.0);
    a.n = 0.0;
  }
  // q into the running value v by the mode: the minimum, the maximum or the sum
  KOKKOS_INLINE_FUNCTION void fold(volatile double &v, const double q) const
  {
    if (mode == ComputeReduce::MINN) {
      if (q < v) v = q;
    } else if (mode == ComputeReduce::MAXX) {
      if (q > v) v = q;
    } else
      v += q;
  }
  KOKKOS_INLINE_FUNCTION void join(SPHCUT_KK_VOLATILE value_type &a, const SPHCUT_KK_VOLATILE value_type &b) const
  {
    fold(a.v, b.v);
    a.n += b.n;
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type &a) const
  {
    if (!(mask(i) & groupbit)) return;
    for (int k = 0; k < 3; k++) {
      const double xk = x(i, k) - d[k];
      if (!(xk >= lo[k] && xk <= hi[k])) return;    // RegBlock::inside
    }
    double q = vals(i, col);
    if (mode == ComputeReduce::SUMSQ || mode == ComputeReduce::AVESQ) q *= q;
    fold(a.v, q);
    a.n += 1.0;
  }
};

// what LAMMPS' compute reduce holds of input m and its region: arrays of its own in LAMMPS
// 29Sep2021, a vector of inputs and the region itself in the LAMMPS versions since 2023 (the
// versions between are not checked)
#if SPHCUT_LAMMPS_VERSION >= 20230208
#define SPHCUT_REDUCE_WHICH(m) values[m].which
#define SPHCUT_REDUCE_ARGINDEX(m) values[m].argindex
#define SPHCUT_REDUCE_PERATOM(m) (input_mode == PERATOM)
#define SPHCUT_REDUCE_FIX(m) values[m].val.f
#define SPHCUT_REDUCE_REGION region
#else
#define SPHCUT_REDUCE_WHICH(m) which[m]
#define SPHCUT_REDUCE_ARGINDEX(m) argindex[m]
#define SPHCUT_REDUCE_PERATOM(m) (flavor[m] == PERATOM)
#define SPHCUT_REDUCE_FIX(m) sphcut::fix_by_index(modify, value2index[m])
#define SPHCUT_REDUCE_REGION domain->regions[iregion]
#endif

// the arguments with the style LAMMPS' compute reduce knows (its constructor refuses any other
// name: reduce/region/kk given by name, not by -sf kk, which passes the base name)
std::vector<char *> base_args(int narg, char **arg)
{
  static char name[] = "reduce/region";
  std::vector<char *> a(arg, arg + narg);
  if (narg > 2) a[2] = name;
  return a;
}

}    // namespace

template <class DeviceType>
ComputeReduceRegionKokkos<DeviceType>::ComputeReduceRegionKokkos(LAMMPS *lmp, int narg, char **arg) :
    ComputeReduceRegion(sphcut::require_kokkos(lmp, "Compute reduce/region/kk"), narg, base_args(narg, arg).data())
{
  delete[] style;
  style = utils::strdup(arg[2]);
  kokkosable = 1;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = X_MASK | V_MASK | F_MASK | MASK_MASK;
  datamask_modify = EMPTY_MASK;
}

/* the device path when the region and every value allow it (the header); else LAMMPS' compute */
template <class DeviceType> void ComputeReduceRegionKokkos<DeviceType>::init()
{
  ComputeReduceRegion::init();
  device_path = false;
  dvalues.assign(nvalues, DeviceValue{0, 0, nullptr});
  Region *reg = SPHCUT_REDUCE_REGION;
  if (!dynamic_cast<RegBlock *>(reg) || !reg->interior || !reg->bboxflag || reg->openflag || reg->rotateflag ||
      reg->varshape)
    return;
  if (mode != SUM && mode != SUMSQ && mode != MINN && mode != MAXX && mode != AVE && mode != AVESQ) return;
  if (replace)
    for (int m = 0; m < nvalues; m++)
      if (replace[m] >= 0) return;
  for (int m = 0; m < nvalues; m++) {
    DeviceValue &dv = dvalues[m];
    const int which_m = SPHCUT_REDUCE_WHICH(m), argindex_m = SPHCUT_REDUCE_ARGINDEX(m);
    dv.column = argindex_m;
    if (which_m == ArgInfo::X) dv.source = ATOM_X;
    else if (which_m == ArgInfo::V) dv.source = ATOM_V;
    else if (which_m == ArgInfo::F) dv.source = ATOM_F;
    else if (which_m == ArgInfo::FIX && SPHCUT_REDUCE_PERATOM(m) && argindex_m > 0 &&
             (dv.fix = dynamic_cast<FixSPHJCThermalKokkosBase *>(SPHCUT_REDUCE_FIX(m)))) {
      dv.source = FIX_STATE;
      dv.column = argindex_m - 1;
    } else
      return;
  }
  device_path = true;
}

template <class DeviceType> void ComputeReduceRegionKokkos<DeviceType>::reduce_device(int m, double &value, double &count)
{
  const DeviceValue &dv = dvalues[m];
  Region *reg = SPHCUT_REDUCE_REGION;
  reg->prematch();
  atomKK->sync(execution_space, X_MASK | MASK_MASK | (dv.source == ATOM_V ? V_MASK : 0) | (dv.source == ATOM_F ? F_MASK : 0));
  // one reduction of column dv.column of vals over the group's particles in the block
  auto launch = [&](auto vals) {
    RegionReduce<DeviceType, decltype(vals)> k;
    k.x = atomKK->k_x.view<DeviceType>();
    k.mask = atomKK->k_mask.view<DeviceType>();
    k.vals = vals;
    k.col = dv.column;
    k.groupbit = groupbit;
    k.mode = mode;
    const double lo[3] = {reg->extent_xlo, reg->extent_ylo, reg->extent_zlo};
    const double hi[3] = {reg->extent_xhi, reg->extent_yhi, reg->extent_zhi};
#ifdef SPHCUT_REGION_EXTENT_MOVES
    const double d[3] = {0.0, 0.0, 0.0};    // the extent has moved with the region (Region::bbox_update)
#else
    const double d[3] = {reg->dx, reg->dy, reg->dz};
#endif
    for (int c = 0; c < 3; c++) {
      k.lo[c] = lo[c];
      k.hi[c] = hi[c];
      k.d[c] = reg->moveflag ? d[c] : 0.0;
    }
    typename decltype(k)::value_type r;
    Kokkos::parallel_reduce("sphcut:reduce_region", sphcut::range<DeviceType>(0, atom->nlocal), k, r);
    value = r.v;
    count = r.n;
  };
  typedef sphcut::AtomTypes<DeviceType> AT3;
  if (dv.source == FIX_STATE) {
    dv.fix->k_state.template sync<DeviceType>();
    launch(dv.fix->k_state.template view<DeviceType>());
  } else if (dv.source == ATOM_X)
    launch(typename AT3::x_const(atomKK->k_x.view<DeviceType>()));
  else if (dv.source == ATOM_V)
    launch(typename AT3::v_const(atomKK->k_v.view<DeviceType>()));
  else
    launch(typename AT3::f_const(atomKK->k_f.view<DeviceType>()));
}

// value m over all ranks, as ComputeReduce::compute_scalar / compute_vector combine compute_one's
template <class DeviceType> double ComputeReduceRegionKokkos<DeviceType>::reduce_all(int m)
{
  double one[2], all[2];
  reduce_device(m, one[0], one[1]);
  if (mode == MINN) MPI_Allreduce(one, all, 1, MPI_DOUBLE, MPI_MIN, world);
  else if (mode == MAXX) MPI_Allreduce(one, all, 1, MPI_DOUBLE, MPI_MAX, world);
  else MPI_Allreduce(one, all, 2, MPI_DOUBLE, MPI_SUM, world);
  if ((mode == AVE || mode == AVESQ) && all[1] > 0.0) all[0] /= all[1];
  return all[0];
}

template <class DeviceType> double ComputeReduceRegionKokkos<DeviceType>::compute_scalar()
{
  if (!device_path) {
    atomKK->sync(Host, ALL_MASK);
    return ComputeReduceRegion::compute_scalar();
  }
  invoked_scalar = update->ntimestep;
  scalar = reduce_all(0);
  return scalar;
}

template <class DeviceType> void ComputeReduceRegionKokkos<DeviceType>::compute_vector()
{
  if (!device_path) {
    atomKK->sync(Host, ALL_MASK);
    ComputeReduceRegion::compute_vector();
    return;
  }
  invoked_vector = update->ntimestep;
  for (int m = 0; m < nvalues; m++) vector[m] = reduce_all(m);
}

namespace LAMMPS_NS {
template class ComputeReduceRegionKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class ComputeReduceRegionKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
