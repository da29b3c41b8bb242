// The shared physics headers (src/sphcut_*.h) compile as CUDA device code: every entry point the
// /kk styles call, instantiated in one kernel with inputs read from memory (nothing folds away).
// A host-only construct in a header (std::, an allocation, a call of a host function: nvcc only
// warns about that, --Werror all-warnings makes it fail) fails this test.
// ctest runs it where nvcc exists (test_device_headers); no GPU is needed.
#include "sphcut_pair.h"
#include "sphcut_solid.h"
#include "sphcut_heat_rules.h"
#include "sphcut_thermal.h"
#include "sphcut_contact.h"
#include "sphcut_kernels.h"
using namespace sphcut;
struct Sink { double *a; __host__ __device__ void operator()(int k, double v) const { a[k] += v; } };
// a neighbour view of the heat functions (sphcut_thermal.h): one neighbour, read from memory
struct HeatView {
  static constexpr bool TWO_WALKS = false;
  const double *s;
  const ThermalPair *tp;
  __host__ __device__ int size() const { return 1; }
  __host__ __device__ int index(int) const { return 0; }
  __host__ __device__ void pos(int, double *xj) const { for (int a = 0; a < 3; a++) xj[a] = s[10 + a]; }
  __host__ __device__ double h(int) const { return s[17]; }
  __host__ __device__ bool pair(int, HeatPair &p) const
  {
    const double xi[3] = {s[13], s[14], s[15]}, xj[3] = {s[10], s[11], s[12]};
    double r2;
    p.j = 0;
    p.tp = tp;
    return thermal_support(*tp, 0, xi, xj, p.dx, r2, p.wfac, p.ir2);
  }
  __host__ __device__ double volume(int) const { return s[20]; }
  __host__ __device__ double temp(int) const { return s[21]; }
  template <int DIM> __host__ __device__ bool weights(int, double *w) const { return row_weights<DIM>(s + 23, w); }
  __host__ __device__ double kappa(int) const { return s[22]; }
};
__global__ void k(const Material *mat, double *s, double *acc, TriBinView g, double *out, const PairIn *pin, const ContactIn *cin)
{
  PairIn in = pin[0];
  PairOut po{};
  pair_terms<3>(0, in, po);
  pair_terms<2>(1, in, po);
  Sink sink{acc};
  pair_accumulate<3>(in, po, 1.0, 1.0, 1.0, 1.0, sink);
  pair_accumulate<2>(in, po, 1.0, 1.0, 1.0, -1.0, sink);
  double drho, ds[6], du, A[6], R[6];
  particle_rates(mat[0], 3, 1, acc, s, 1.0, drho, ds, du);
  particle_stress(mat[0], 3, 1, 1.0, 300.0, s, A, R);
  double x[3] = {s[1], s[2], s[3]}, v[3] = {s[4], s[5], s[6]}, f[3] = {s[7], s[8], s[9]};
  integrate_first_half(mat[0], 0, 1e-9, 1.0, x, v, f, s);
  out[0] = integrate_second_half(mat[0], 0, 1e-9, 1.0, 1.0, v, f, s);
  out[1] = particle_dt(mat[0], 0, 1e-4, v, s[20], 0.3, -1.0, -1.0);
  zero_rates(s);
  FmfsAccum<3> a3; fmfs_zero<3>(a3);
  double r[3] = {s[10], s[11], s[12]}, gg[3] = {s[13], s[14], s[15]}, wts[12], lap;
  fmfs_add<3>(a3, r, gg, 1.0, 1.0);
  out[2] = fmfs_weights<3>(a3, wts) + fmfs_laplacian<3>(a3, lap) + surface_lambda<3>(a3.B);
  FmfsAccum<2> a2; fmfs_zero<2>(a2); fmfs_add<2>(a2, r, gg, 1.0, 1.0);
  double tmin = 1e300;
  thermal_dt_min(1, 1, s[0], 1, 1, 1, 0.1, 1, tmin);
  out[3] = fmfs_weights<2>(a2, wts) + fmfs_pair_weight<3>(wts, r, gg) + thermal_dt_limit(1, 1, 1, 1, 0.1, 1) + tmin;
  double n[3], q[3], d, qc, qr;
  surface_normal<3>(a3.B, gg, n);
  // the fused pass of fix heat/fmfs and compute surface/lambda
  const ThermalPair tp = thermal_pair(s[16] > 0.0 ? 1 : 0, 3, s[17], s[18], s[19]);
  SupportMoments<3> m3; support_zero<3>(m3, true);
  double dx[3], r2, wfac, ir2;
  if (thermal_support(tp, 0, r, gg, dx, r2, wfac, ir2)) {
    support_add_surface<3>(m3, dx, -wfac);
    support_add_fmfs<3>(m3, dx, -wfac, ir2);
  }
  support_to_fmfs<3>(m3, a3);
  out[5] = support_surface<3>(m3, 0.75, n) + fmfs_pair_weight_radial<3>(wts, dx, ir2) + tp.same_kappa +
           conductance_pair(s[21], s[22], tp.brook);
  surface_losses(3, 1.0, 300.0, 1.0, 300.0, 1.0, 300.0, qc, qr);
  // fix heat/fmfs per particle over a view of its neighbours (the /kk fix's calls)
  const HeatView hv{s, &tp};
  HeatSurface hs;
  double rate, pc = 0.0, pr = 0.0, c[3] = {0.0, 0.0, 0.0};
  const int sch = heat_scheme<3>(hv, 1, 1, 1, 0.75, 0.75, hs, wts) + heat_scheme<2>(hv, 1, 1, 0, 0.75, 0.75, hs, wts) +
                  conduction_particle<3>(hv, 0, r, 300.0, 1.0, 1, 0.75, rate) +
                  conduction_particle<2>(hv, 1, r, 300.0, 1.0, 1, 0.75, rate);
  heat_count(sch, c[0], c[1], c[2]);
  out[6] = rate + hs.lambda + c[0] + heat_exchange<3>(hv, 1.0, 300.0, 0.0, s + 23, NoAdd{}) +
           heat_exchange<2>(hv, 1.0, 300.0, 1.0, s + 23, sink) +
           heat_rate(3, HeatLosses{1.0, 300.0, 1.0, 300.0, 1, 1, 2.0, 300.0}, 1, 1, 1.0, 1.0, 1.0, 1.0, 300.0, pc, pr) +
           support_radius_sq(s[17]);
  int region;
  int e = tool_surface(g, x, 1e-4, d, n, q, region);
  ContactIn ci = cin[0]; ContactOut co;
  ci.friction.kind = (e & 1) ? FrictionLaw::MEMORY : FrictionLaw::STATIC;
  ci.mu = ci.friction.mu(s[10]);
  memory_friction_input(s, true, false, ci.ft_old);
  memory_friction_step(s);
  penalty_contact(ci, co);
  out[4] = decompose_contact(co, n, acc) + mu_table(r, gg, 2, 300.0) + penalty_dt_limit(1, 1, 0.1, 1) +
           kernel_w(0, 3, 0.5, 1.0) + near_contact(d, 1, 1.2, v, v, 3, 1e-9) + dirichlet_index(1, 1, &e, 1);
  // the heat rules an integrator applies for fix heat/fmfs (sphcut_heat_rules.h)
  const double td = s[24];
  add_held_rate(s);
  hold_predicted_temperature(1, 1, &e, &td, 1, s);
  out[4] += hold_corrected_temperature(1, 1, &e, &td, 1, 2.0, s);
  // tool fields per facet
  FacetShare fs;
  fs.start = &e;
  fs.elem = &e;
  facet_scatter(fs, acc, e, region, co, s[11], s[12], s[13], 1e-9,
                [&](int f, const double *c) { out[6] += f * c[FS_WEAR] + c[FS_FN]; });
  out[7] = usui_rate(1e-15, 2500.0, s[14], s[15], s[16]);
}
