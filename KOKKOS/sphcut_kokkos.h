/* -*- c++ -*- ----------------------------------------------------------
   sphcut - helpers shared by the Kokkos (/kk) styles: device copies of
   small host tables, a timer that waits for the device, and the check
   that a /kk style runs with the KOKKOS package enabled.
------------------------------------------------------------------------- */

#ifndef SPHCUT_KOKKOS_H
#define SPHCUT_KOKKOS_H

#include "kokkos_type.h"
#include "lammps.h"
#include "error.h"
#include "integrate.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "atom_kokkos.h"
#include "neigh_list_kokkos.h"

#include <cstdint>
#include <cstdlib>
#include <mpi.h>
#include <string>
#include <type_traits>
#include <vector>

// The KOKKOS API of LAMMPS changed between the three versions the /kk styles compile against:
// 29Sep2021 (Kokkos 3.4, built and run), 4Feb2025 (Kokkos 4.5) and 4Jul2026 (Kokkos 5.2; both
// compile-checked only, tools/compat-check.sh).  One switch per change, each set from the first
// of these versions that has it (the versions in between were not checked):
//   SPHCUT_KK_SENDLIST_1D (4Feb2025, 4Jul2026): the forward communication's pack functions get
//     the send list of the swap (DAT::tdual_int_1d), not the 2D list (swap, i) and the swap
//   SPHCUT_KK_FORWARD_UNIFIED (4Jul2026): fixes pack and unpack through KokkosBase's
//     pack_/unpack_forward_comm_kokkos, as pairs do, not pack_/unpack_forward_comm_fix_kokkos
//   SPHCUT_KK_BUF_DOUBLE (4Jul2026): the communication buffer is a DAT::tdual_double_1d, not a
//     DAT::tdual_xfloat_1d (another type where the device layout is LayoutLeft, CUDA)
//   SPHCUT_KK_VIEW_TYPES_2026 (4Jul2026): atom views t_kkfloat_1d_3_lr (x), t_kkfloat_1d_3 (v),
//     t_kkacc_1d_3 (f), t_kkfloat_1d (masses) (double unless LAMMPS is built for single
//     precision), not t_x_array, t_v_array, t_f_array, t_float_1d
//   SPHCUT_REGION_EXTENT_MOVES (4Jul2026): Region::bbox_update(), called by prematch() of a
//     moving region, moves its extent_* with it (found when the /kk styles first ran against
//     4Jul2026, test_run_lammps_20260704: compute reduce/region/kk displaced a moved block twice)
//   neighbour requests: NeighRequest::set_kokkos_host/device and enable_full from 24Mar2022
//     (kokkos_list below), not its members set directly
#if SPHCUT_LAMMPS_VERSION >= 20250204
#define SPHCUT_KK_SENDLIST_1D 1
#endif
#if SPHCUT_LAMMPS_VERSION >= 20260704
#define SPHCUT_KK_FORWARD_UNIFIED 1
#define SPHCUT_KK_BUF_DOUBLE 1
#define SPHCUT_KK_VIEW_TYPES_2026 1
#define SPHCUT_REGION_EXTENT_MOVES 1
#endif

// A reducer's join(): Kokkos 3.4 calls it on volatile values; Kokkos 4 on plain ones, and 4.5
// refuses a reducer whose join takes only volatile ones (a static_assert).  Checked: Kokkos 3.4
// (built), 4.5 and 5.2 (compile check); the switch is at 4.0, where volatile joins were deprecated
#if KOKKOS_VERSION >= 40000
#define SPHCUT_KK_VOLATILE
#else
#define SPHCUT_KK_VOLATILE volatile
#endif

namespace sphcut {

#ifdef SPHCUT_KK_BUF_DOUBLE
typedef ::DAT::tdual_double_1d kk_buf;         // forward communication buffer
#else
typedef ::DAT::tdual_xfloat_1d kk_buf;
#endif
#ifdef SPHCUT_KK_SENDLIST_1D
typedef ::DAT::tdual_int_1d kk_sendlist;       // send list of one swap
#else
typedef ::DAT::tdual_int_2d kk_sendlist;       // (swap, i)
#endif

}    // namespace sphcut

// The forward communication overrides on the device, declared and defined once for all versions:
//   int SPHCUT_KK_FIX_PACK_FORWARD(int n, SPHCUT_KK_SENDLIST(list, iswap), sphcut::kk_buf &buf,
//                                  int pbc_flag, int *pbc)   (a pair: pack_forward_comm_kokkos)
//   void SPHCUT_KK_FIX_UNPACK_FORWARD(int n, int first, sphcut::kk_buf &buf)
// where the body passes SPHCUT_KK_ISWAP(iswap) on to sphcut::pack_columns
#ifdef SPHCUT_KK_FORWARD_UNIFIED
#define SPHCUT_KK_FIX_PACK_FORWARD pack_forward_comm_kokkos
#define SPHCUT_KK_FIX_UNPACK_FORWARD unpack_forward_comm_kokkos
#else
#define SPHCUT_KK_FIX_PACK_FORWARD pack_forward_comm_fix_kokkos
#define SPHCUT_KK_FIX_UNPACK_FORWARD unpack_forward_comm_fix_kokkos
#endif
#ifdef SPHCUT_KK_SENDLIST_1D
#define SPHCUT_KK_SENDLIST(list, iswap) sphcut::kk_sendlist list
#define SPHCUT_KK_ISWAP(iswap) 0
#else
#define SPHCUT_KK_SENDLIST(list, iswap) sphcut::kk_sendlist list, int iswap
#define SPHCUT_KK_ISWAP(iswap) iswap
#endif

namespace sphcut {

// the view types of the atom arrays the /kk kernels read and write
template <class DeviceType> struct AtomTypes {
  typedef ArrayTypes<DeviceType> AT;
#ifdef SPHCUT_KK_VIEW_TYPES_2026
  typedef typename AT::t_kkfloat_1d_3_lr x;
  typedef typename AT::t_kkfloat_1d_3_lr_const x_const;
  typedef typename AT::t_kkfloat_1d_3 v;
  typedef typename AT::t_kkfloat_1d_3_const v_const;
  typedef typename AT::t_kkacc_1d_3 f;
  typedef typename AT::t_kkacc_1d_3_const f_const;
  typedef typename AT::t_kkfloat_1d scalar;
  typedef typename AT::t_kkfloat_1d_const scalar_const;
#else
  typedef typename AT::t_x_array x;
  typedef typename AT::t_x_array_const x_const;
  typedef typename AT::t_v_array v;
  typedef typename AT::t_v_array_const v_const;
  typedef typename AT::t_f_array f;
  typedef typename AT::t_f_array_const f_const;
  typedef typename AT::t_float_1d scalar;
  typedef typename AT::t_float_1d_const scalar_const;
#endif
};

// device copy of a host array of plain structs (materials, type-pair constants)
template <class T, class DeviceType>
Kokkos::View<T *, typename DeviceType::memory_space> to_device(const T *host, int n, const char *name)
{
  Kokkos::View<T *, typename DeviceType::memory_space> d(std::string(name), (size_t) n);
  auto h = Kokkos::create_mirror_view(d);
  for (int i = 0; i < n; i++) h(i) = host[i];
  Kokkos::deep_copy(d, h);
  return d;
}

// the range policy of every sphcut kernel: HintLightWeight passes the functor (its Views and
// constants, often more than 512 bytes) as a kernel argument.  Without the hint Kokkos 3.4 puts
// functors over 512 bytes into constant memory, and each such launch waits for the previous one
// to finish (cudaEventSynchronize): the host cannot run ahead of the device, and the fixed cost
// of a step grows with the number of kernels (measured: bench/gpu/RESULTS.md).  MINB > 0: the
// kernel compiled with launch bounds, at most 128 threads a block and MINB blocks on a
// multiprocessor (a cap on its registers; Kokkos chooses the block size within them)
template <class DeviceType, int MINB = 0> inline auto range(int begin, int end)
{
  typedef typename std::conditional<MINB == 0, Kokkos::LaunchBounds<>, Kokkos::LaunchBounds<128, MINB>>::type
      bounds;
  return Kokkos::Experimental::require(Kokkos::RangePolicy<DeviceType, bounds>(begin, end),
                                       Kokkos::Experimental::WorkItemProperty::HintLightWeight);
}

// whether a style instance on DeviceType runs on a host backend (LAMMPS' host execution space:
// one lane, no one-ahead loads, no staged rows by default)
template <class DeviceType> constexpr bool on_host_backend()
{
  return std::is_same<typename DeviceType::execution_space, LMPHostType::execution_space>::value;
}

/* A reduction over many particles, one thread each.  Kokkos 3.4 launches a range reduction on
   CUDA in at most block_size blocks of block_size threads (Kokkos_Cuda_Parallel.hpp: "grid.x <=
   block.y", 256 x 256), each thread looping over n / 65,536 of the indices, and its tree's shared
   memory under the L1 preference leaves one block of 256 a multiprocessor (Nsight Compute,
   bench/gpu/RESULTS.md: low occupancy).  wide_reduce runs
   the same functor as a parallel_for of one thread per index instead: each warp joins its lanes'
   values by shuffles and its first lane joins them into the accumulator acc on the device by
   atomics (sums: add; minima: the integer minimum of their bits, which orders non-negative
   doubles as their values), then counts itself done in acc(N); the last to arrive (after a
   fence) runs the functor's final on acc and resets it, so no kernel of its own is launched for
   final.  The functor: init(double *), operator()(i, double *), final(double *) and a static
   is_min(k) for its N values; its minima must be non-negative (time-step limits); a final that
   reads what other threads wrote besides their values needs their operator() to fence after it
   (only the first lane of a warp fences before the count).  The minima are exact; the sums take
   the atomics' order (their round-off varies from run to run).  On a host backend each index
   joins its values by atomics (the tests' path).                                              */
template <class DeviceType, int N, class Functor> struct WideReduce {
  typedef DeviceType device_type;
  Functor f;
  Kokkos::View<double *, typename DeviceType::memory_space> acc;    // N values, then the count
  int end;
  KOKKOS_INLINE_FUNCTION void join_atomic(int k, double v) const
  {
    if (!Functor::is_min(k)) {
      Kokkos::atomic_add(&acc(k), v);
      return;
    }
#ifdef __CUDA_ARCH__
    if (v >= 0.0) {
      atomicMin(reinterpret_cast<unsigned long long *>(&acc(k)), (unsigned long long) __double_as_longlong(v));
      return;
    }
#endif
    Kokkos::atomic_fetch_min(&acc(k), v);
  }
  // acc set to the functor's init, the count to 0
  KOKKOS_INLINE_FUNCTION void reset() const
  {
    double v[N];
    f.init(v);
    for (int k = 0; k < N; k++) acc(k) = v[k];
    acc(N) = 0.0;
  }
  // the functor's final on acc, then the reset
  KOKKOS_INLINE_FUNCTION void finish() const
  {
    const volatile double *a = &acc(0);    // (the atomics' values, not a cached copy)
    double v[N];
    for (int k = 0; k < N; k++) v[k] = a[k];
    f.final(v);
    reset();
  }
  // the values r of one of units joins; the last finishes (the "threadfence reduction" of CUDA's
  // samples: every join's atomics are done before its count)
  KOKKOS_INLINE_FUNCTION void join(const double *r, int units) const
  {
    for (int k = 0; k < N; k++) join_atomic(k, r[k]);
    Kokkos::memory_fence();
    if (Kokkos::atomic_fetch_add(&acc(N), 1.0) + 1.0 != (double) units) return;
    Kokkos::memory_fence();
    finish();
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i) const
  {
    double r[N];
    f.init(r);
    f(i, r);
#ifdef __CUDA_ARCH__
    // Kokkos' range launch: blocks (1, size, 1), index i = threadIdx.y + size * blockIdx.x (+ a
    // multiple of size * gridDim.x): with size a multiple of 32 a warp holds 32 consecutive
    // indices, its lanes below nv valid
    if (blockDim.x == 1 && (blockDim.y & 31) == 0) {
      const int lane = threadIdx.y & 31, nv = end - (i - lane);
      const unsigned m = nv >= 32 ? 0xffffffffu : (1u << nv) - 1u;
      for (int off = 16; off > 0; off >>= 1)
        for (int k = 0; k < N; k++) {
          const double o = __shfl_down_sync(m, r[k], off);
          if (lane + off < nv) r[k] = Functor::is_min(k) ? (o < r[k] ? o : r[k]) : r[k] + o;
        }
      if (lane == 0) join(r, (end + 31) / 32);
      return;
    }
#endif
    join(r, end);
  }
};

// whether a reduction takes wide_reduce: on a GPU at every size (bench/gpu/RESULTS.md "The
// reductions over the particles"), never on a host backend; SPHCUT_WIDE_REDUCE (0 or 1,
// env_switch's -1 when unset) overrides, 1 on host backends too (the tests of the wide path)
inline bool wide_choice(bool host, int env)
{
  return env >= 0 ? env == 1 : !host;
}

// the WideReduce of functor f (N values) over 0 .. n - 1 through the accumulator acc (allocated
// and set to the functor's init here when it has fewer than N + 1 values; shared by functors of
// one init), for a kernel that joins its own values (a team kernel: WideReduce::join); and
// wide_reduce: that reduction as a kernel of one thread an index; with no index a kernel of one
// thread runs final
template <class DeviceType, int N, class Functor>
WideReduce<DeviceType, N, Functor> wide_reducer(const std::string &name, int n, const Functor &f,
                                                Kokkos::View<double *, typename DeviceType::memory_space> &acc)
{
  const bool fresh = (int) acc.extent(0) < N + 1;
  if (fresh) acc = Kokkos::View<double *, typename DeviceType::memory_space>(name + ":acc", N + 1);
  const WideReduce<DeviceType, N, Functor> w{f, acc, n};
  if (fresh) Kokkos::parallel_for(name + ":acc_init", range<DeviceType>(0, 1), KOKKOS_LAMBDA(const int) { w.reset(); });
  return w;
}

template <class DeviceType, int N, int MINB = 0, class Functor>
void wide_reduce(const std::string &name, int n, const Functor &f,
                 Kokkos::View<double *, typename DeviceType::memory_space> &acc)
{
  const auto w = wide_reducer<DeviceType, N>(name, n, f, acc);
  if (n > 0) {
    Kokkos::parallel_for(name, range<DeviceType, MINB>(0, n), w);
    return;
  }
  Kokkos::parallel_for(name + ":final", range<DeviceType>(0, 1), KOKKOS_LAMBDA(const int) { w.finish(); });
}

// the reduction of functor f (a Kokkos reduction functor of N values, with is_min) over 0 .. n - 1:
// Kokkos' own into result (a view of N on the device, as parallel_reduce writes it), or with
// wide, wide_reduce through acc
template <class DeviceType, int N, int MINB = 0, class Functor, class Result>
void reduce(const std::string &name, int n, const Functor &f, bool wide, const Result &result,
            Kokkos::View<double *, typename DeviceType::memory_space> &acc)
{
  if (wide)
    wide_reduce<DeviceType, N, MINB>(name, n, f, acc);
  else
    Kokkos::parallel_reduce(name, range<DeviceType, MINB>(0, n), f, result);
}

// the staged kernel of fix sph/jc-thermal/kk (initial_integrate): a team takes
// STAGE_ROWS consecutive particles, copies their state rows (contiguous in the LayoutRight view)
// into its scratch with loads of consecutive doubles across its threads, each thread integrates its
// particle on the scratch row, and the team stores the rows back the same way.  In place, each
// thread reads and writes its own 504-byte row: a warp's access of one column touches 32 rows
// 504 bytes apart.  On a host backend host_team threads a team (1; 2 in the tests of the team
// reductions, which a GPU's teams of 32 run)
constexpr int STAGE_ROWS = 32;
template <class DeviceType> inline auto stage_policy(int n, int ncol, int host_team = 1)
{
  auto p = Kokkos::Experimental::require(
      Kokkos::TeamPolicy<DeviceType>((n + STAGE_ROWS - 1) / STAGE_ROWS,
                                     on_host_backend<DeviceType>() ? host_team : STAGE_ROWS),
      Kokkos::Experimental::WorkItemProperty::HintLightWeight);
  p.set_scratch_size(0, Kokkos::PerTeam(STAGE_ROWS * ncol * sizeof(double)));
  return p;
}

// a team's rows in: the scratch holding rows first .. first + cnt - 1 (cnt = the team's particles)
template <class Member, class View>
KOKKOS_INLINE_FUNCTION double *stage_in(const Member &t, const View &st, int first, int cnt)
{
  const int ncol = (int) st.extent(1), n = cnt * ncol;
  double *sh = (double *) t.team_shmem().get_shmem(STAGE_ROWS * ncol * sizeof(double));
  const double *g = &st(first, 0);
  for (int k = t.team_rank(); k < n; k += t.team_size()) sh[k] = g[k];
  t.team_barrier();
  return sh;
}

// and out, after every thread of the team has finished its rows (all of them: storing only the
// values that changed costs an extra read of the rows)
template <class Member, class View>
KOKKOS_INLINE_FUNCTION void stage_out(const Member &t, const View &st, int first, int cnt, const double *sh)
{
  const int ncol = (int) st.extent(1), n = cnt * ncol;
  t.team_barrier();
  double *g = &st(first, 0);
  for (int k = t.team_rank(); k < n; k += t.team_size()) g[k] = sh[k];
}

// whether the rows of a state view are contiguous (what stage_in / stage_out assume)
template <class View> inline bool rows_contiguous(const View &st)
{
  return st.extent(0) < 2 || (st.stride(1) == 1 && st.stride(0) == st.extent(1));
}

// the integrator's flag that it leaves the force clear to someone else (Integrate's protected
// external_force_clear, which LAMMPS' OpenMP package sets from inside Verlet::init), reached
// through a member pointer named in a derived class: fix sph/jc-thermal/kk sets it from its setup
// to post_run (force_clear_allowed), the tests read it
struct IntegrateForceClear : LAMMPS_NS::Integrate {
  static int &flag(LAMMPS_NS::Integrate *in) { return in->*(&IntegrateForceClear::external_force_clear); }
};

// a switch of the environment, 0 .. hi (1 or 2): def when unset or empty, an error naming the
// variable and its value for anything else.  The switches (at most three) and what they do are
// listed in doc/performance.md, "Environment switches" (unittest/test_env_switches.sh checks that
// every name read here is there): each lets a CPU build's tests run a path a GPU takes by default
inline int env_switch(LAMMPS_NS::LAMMPS *lmp, const char *name, const char *who, int def, int hi = 1)
{
  const char *e = std::getenv(name);
  if (!e || !*e) return def;
  const std::string v(e);
  if (v.size() != 1 || v[0] < '0' || v[0] > '0' + hi)
    lmp->error->all(FLERR, "{}: {}={} is not {}", who, name, v, hi == 1 ? "0 or 1" : "0, 1 or 2");
  return v[0] - '0';
}

// a style's choice of the wide reductions (wide_choice) on its device type, SPHCUT_WIDE_REDUCE read
// for it (who: the style, for the error on a bad value)
template <class DeviceType> bool wide_choice(LAMMPS_NS::LAMMPS *lmp, const char *who)
{
  return wide_choice(on_host_backend<DeviceType>(), env_switch(lmp, "SPHCUT_WIDE_REDUCE", who, -1));
}

// whether a style's neighbour loops load ahead on its device type (the pair's list entries one
// entry ahead, the heat passes' neighbour rows before the support test; the same values in the
// same order either way): on a GPU, not on a host backend (there they cost time);
// SPHCUT_LOAD_AHEAD (0 or 1) overrides, 1 on host backends too (the tests of those loops)
template <class DeviceType> bool load_ahead(LAMMPS_NS::LAMMPS *lmp, const char *who)
{
  const int env = env_switch(lmp, "SPHCUT_LOAD_AHEAD", who, -1);
  return env >= 0 ? env == 1 : !on_host_backend<DeviceType>();
}

// forward communication of the per-atom columns col0 .. col0 + ncol - 1 of a DualView, on the
// device (pack_/unpack_forward_comm_fix_kokkos of the /kk fixes) and on the host (the classic
// path of CommKokkos)
template <class DeviceType>
int pack_columns(::DAT::tdual_double_2d &k, int col0, int ncol, int n, kk_sendlist k_sendlist,
                 int iswap, kk_buf &k_buf)
{
  k.template sync<DeviceType>();
  auto list = k_sendlist.view<DeviceType>();
  auto buf = k_buf.view<DeviceType>();
  auto v = k.template view<DeviceType>();
  Kokkos::parallel_for(
      "sphcut:pack_columns", range<DeviceType>(0, n), KOKKOS_LAMBDA(const int ii) {
#ifdef SPHCUT_KK_SENDLIST_1D
        const int j = list(ii);
#else
        const int j = list(iswap, ii);
#endif
        for (int c = 0; c < ncol; c++) buf(ii * ncol + c) = v(j, col0 + c);
      });
  return n * ncol;
}

template <class DeviceType>
void unpack_columns(::DAT::tdual_double_2d &k, int col0, int ncol, int n, int first, kk_buf &k_buf)
{
  k.template sync<DeviceType>();
  auto buf = k_buf.view<DeviceType>();
  auto v = k.template view<DeviceType>();
  Kokkos::parallel_for(
      "sphcut:unpack_columns", range<DeviceType>(0, n), KOKKOS_LAMBDA(const int ii) {
        for (int c = 0; c < ncol; c++) v(first + ii, col0 + c) = buf(ii * ncol + c);
      });
  k.template modify<DeviceType>();
}

// the classic (host) forward communication of columns col0 .. col0 + ncol - 1 of a DualView that
// lives on the device (and, pack_range, a copy of some columns of a range of rows to the host):
// only the listed rows travel, packed on the device into a staging buffer
// whose used part alone is copied to the host (unpack: the reverse), so the array stays current
// on the device (a host sync of the array would copy all of it both ways every step: with 4 M
// particles and 49 state columns 1.6 GB).  LAMMPS 29Sep2021 takes this path on several ranks
// without a CUDA-aware MPI.  One per communicated array, owned by the style.
template <class DeviceType> struct StagedColumns {
  typedef typename DeviceType::memory_space mem;
  Kokkos::View<int *, mem> list;
  Kokkos::View<double *, mem> buf;
  typename Kokkos::View<int *, mem>::host_mirror_type h_list;
  typename Kokkos::View<double *, mem>::host_mirror_type h_buf;

  void grow(int n, int nval)
  {
    if ((int) list.extent(0) < n) {
      list = Kokkos::View<int *, mem>(Kokkos::view_alloc(Kokkos::WithoutInitializing, "sphcut:stage_list"), n + n / 4 + 16);
      h_list = Kokkos::create_mirror_view(list);
    }
    if ((int) buf.extent(0) < nval) {
      buf = Kokkos::View<double *, mem>(Kokkos::view_alloc(Kokkos::WithoutInitializing, "sphcut:stage_buf"),
                                        nval + nval / 4 + 16);
      h_buf = Kokkos::create_mirror_view(buf);
    }
  }

  int pack(::DAT::tdual_double_2d &k, int col0, int ncol, int n, const int *rows, double *out)
  {
    k.template sync<DeviceType>();
    grow(n, n * ncol);
    for (int ii = 0; ii < n; ii++) h_list(ii) = rows[ii];
    const auto used_list = std::make_pair(0, n), used_buf = std::make_pair(0, n * ncol);
    Kokkos::deep_copy(Kokkos::subview(list, used_list), Kokkos::subview(h_list, used_list));
    auto l = list;
    auto b = buf;
    auto v = k.template view<DeviceType>();
    Kokkos::parallel_for(
        "sphcut:stage_pack", range<DeviceType>(0, n), KOKKOS_LAMBDA(const int ii) {
          for (int c = 0; c < ncol; c++) b(ii * ncol + c) = v(l(ii), col0 + c);
        });
    Kokkos::deep_copy(Kokkos::subview(h_buf, used_buf), Kokkos::subview(buf, used_buf));
    for (int m = 0; m < n * ncol; m++) out[m] = h_buf(m);
    return n * ncol;
  }

  // rows first .. first + n - 1 (no list): packed on the device, the used part copied into h_buf
  // (row ii's columns at h_buf(ii * ncol) ..)
  void pack_range(::DAT::tdual_double_2d &k, int col0, int ncol, int first, int n)
  {
    k.template sync<DeviceType>();
    grow(0, n * ncol);
    const auto used_buf = std::make_pair(0, n * ncol);
    auto b = buf;
    auto v = k.template view<DeviceType>();
    Kokkos::parallel_for(
        "sphcut:stage_pack_range", range<DeviceType>(0, n * ncol), KOKKOS_LAMBDA(const int m) {
          b(m) = v(first + m / ncol, col0 + m % ncol);
        });
    Kokkos::deep_copy(Kokkos::subview(h_buf, used_buf), Kokkos::subview(buf, used_buf));
  }

  void unpack(::DAT::tdual_double_2d &k, int col0, int ncol, int n, int first, const double *in)
  {
    k.template sync<DeviceType>();
    grow(0, n * ncol);
    for (int m = 0; m < n * ncol; m++) h_buf(m) = in[m];
    const auto used_buf = std::make_pair(0, n * ncol);
    Kokkos::deep_copy(Kokkos::subview(buf, used_buf), Kokkos::subview(h_buf, used_buf));
    auto b = buf;
    auto v = k.template view<DeviceType>();
    Kokkos::parallel_for(
        "sphcut:stage_unpack", range<DeviceType>(0, n), KOKKOS_LAMBDA(const int ii) {
          for (int c = 0; c < ncol; c++) v(first + ii, col0 + c) = b(ii * ncol + c);
        });
    k.template modify<DeviceType>();
  }
};

// whether the /kk styles' timers wait for the device (fix sph/jc-thermal keyword fence): a fence
// after every hook makes the timing table exact but stops the host from queueing the next
// kernels while the device works (measured: the 2D cut at 41 across, bench/gpu/RESULTS.md)
inline bool &fence_timers()
{
  static bool fence = false;
  return fence;
}

// wall time of a hook, with fence_timers() including the device work it launched (kernels are
// asynchronous); without, the host's time in the hook (launches and the reductions it waits for)
class FencedTimer {
 public:
  explicit FencedTimer(double &acc) : acc_(acc), t0_(MPI_Wtime()) {}
  ~FencedTimer()
  {
    if (fence_timers()) Kokkos::fence();
    acc_ += MPI_Wtime() - t0_;
  }
  FencedTimer(const FencedTimer &) = delete;
  FencedTimer &operator=(const FencedTimer &) = delete;

 private:
  double &acc_;
  double t0_;
};

// a /kk style needs `-k on` (LAMMPS 29Sep2021 does not check this for plugin styles); called in
// the constructor's initialiser list, before the base class registers anything that an error
// would have to undo
inline LAMMPS_NS::LAMMPS *require_kokkos(LAMMPS_NS::LAMMPS *lmp, const std::string &who)
{
  if (!lmp->kokkos)
    lmp->error->all(FLERR, "{} needs the KOKKOS package enabled: run with -k on ... -sf kk "
                    "(or use the style without /kk)", who);
  return lmp;
}

// the rows a neighbour pass reads in 16-byte pairs (sphcut::load2, load_weights) start 16-byte
// aligned: checked where such a view is allocated (their widths: static_asserts at the layouts)
inline void require_aligned16(LAMMPS_NS::LAMMPS *lmp, const void *data, const std::string &what)
{
  if (reinterpret_cast<std::uintptr_t>(data) % 16 != 0)
    lmp->error->one(FLERR, "{} are not 16-byte aligned", what);
}

// mark the neighbour request a style just made as a Kokkos list on DeviceType, so that the list
// is built on the device; full: a full list, else a half list
template <class DeviceType> void kokkos_list(LAMMPS_NS::Neighbor *neighbor, bool full)
{
  LAMMPS_NS::NeighRequest *rq = neighbor->requests[neighbor->nrequest - 1];
  const int host = std::is_same<DeviceType, ::LMPHostType>::value &&
      !std::is_same<DeviceType, ::LMPDeviceType>::value;
  const int device = std::is_same<DeviceType, ::LMPDeviceType>::value;
#if SPHCUT_LAMMPS_VERSION >= 20220324
  rq->set_kokkos_host(host);
  rq->set_kokkos_device(device);
  if (full) rq->enable_full();    // neighbor->add_request made a half list unless asked for full
#else
  rq->kokkos_host = host;
  rq->kokkos_device = device;
  rq->full = full ? 1 : 0;
  rq->half = full ? 0 : 1;
#endif
}

// the request made by sphcut::request_full_list as a full Kokkos list on DeviceType
template <class DeviceType> void kokkos_full_list(LAMMPS_NS::Neighbor *neighbor)
{
  kokkos_list<DeviceType>(neighbor, true);
}

// the owner of the per-atom state on the Kokkos device (fix sph/jc-thermal/kk) as the other /kk
// styles see it: the DualView of the state rows (StateLayout columns), whose host view backs
// sphcut::StateOwner::state.  The /kk pair reaches the state through this, not through the
// integrator's class (as the CPU pair reaches it through sphcut::StateOwner)
class KokkosStateOwner {
 public:
  // the exception specification of LAMMPS' Pointers::~Pointers(), as sphcut::AttachedStyle's
  virtual ~KokkosStateOwner() noexcept(std::is_nothrow_destructible<LAMMPS_NS::Pointers>::value) {}
  ::DAT::tdual_double_2d k_state;
};

// the views of the atoms, of the solid's state and of a Kokkos neighbour list that the /kk
// kernels read: gathered in one place (atom_views) instead of one local per view in each kernel
template <class DeviceType> struct AtomViews {
  typedef ArrayTypes<DeviceType> AT;
  typename AtomTypes<DeviceType>::x x;
  typename AT::t_int_1d mask, type;
  typename AtomTypes<DeviceType>::scalar rmass, mass;
  typename AT::t_double_2d st;
  typename AT::t_neighbors_2d neighbors;    // (empty without a list)
  typename AT::t_int_1d numneigh, ilist;
};

template <class DeviceType>
AtomViews<DeviceType> atom_views(LAMMPS_NS::AtomKokkos *atomKK, ::DAT::tdual_double_2d &k_state,
                                 LAMMPS_NS::NeighList *list = nullptr)
{
  AtomViews<DeviceType> v;
  v.x = atomKK->k_x.view<DeviceType>();
  v.mask = atomKK->k_mask.view<DeviceType>();
  v.type = atomKK->k_type.view<DeviceType>();
  v.rmass = atomKK->k_rmass.view<DeviceType>();
  v.mass = atomKK->k_mass.view<DeviceType>();
  v.st = k_state.template view<DeviceType>();
  if (list) {
    auto *kl = static_cast<LAMMPS_NS::NeighListKokkos<DeviceType> *>(list);
    v.neighbors = kl->d_neighbors;
    v.numneigh = kl->d_numneigh;
    v.ilist = kl->d_ilist;
  }
  return v;
}

}    // namespace sphcut

#endif
