/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the per-pair arithmetic of pair sph/jc-thermal (host and
   device), seed 003 eqs. 10-11.  The drivers (CPU pair, Kokkos pair)
   only gather inputs and scatter the outputs.
------------------------------------------------------------------------- */

#ifndef SPHCUT_PAIR_H
#define SPHCUT_PAIR_H

#include "sphcut_kernels.h"
#include "sphcut_material.h"

// the per-pair functions are inlined into the neighbour loops whatever the compiler's size
// heuristics (GCC -O3 called pair_terms out of line in the CPU pair's loop: 15 % slower, measured);
// host compilers only
#if defined(__GNUC__) && !defined(__CUDACC__)
#define SPHCUT_PAIR_INLINE SPHCUT_INLINE __attribute__((always_inline))
#else
#define SPHCUT_PAIR_INLINE SPHCUT_INLINE
#endif

namespace sphcut {

// inputs of one pair i-j (force state of fix sph/jc-thermal)
struct PairIn {
  double dx[3];               // x_i - x_j
  double r2;
  double dv[3];               // v_j - v_i (predicted velocities)
  double h, inv_h, wnorm;     // smoothing length, 1/h, kernel normalisation sigma_d/h^d
  double inv_wdp;             // 1/W(particle spacing)
  double rho_i, rho_j;
  const double *A_i, *A_j;    // Cauchy stress over rho^2, sigma/rho^2 (Voigt; particle_stress)
  const double *R_i, *R_j;    // artificial stress tensors (nullptr: none)
  double as_n;                // artificial stress exponent
  double alpha, beta, cbar;   // artificial viscosity
};

// outputs: everything the drivers accumulate
struct PairOut {
  double w;                   // W_ij
  double g[3];                // grad_i W_ij
  double Mg[3];               // M_ij . grad_i W_ij (force on i = m_i m_j Mg)
  double dvg;                 // (v_j - v_i) . grad_i W_ij
  double work;                // (v_j - v_i) . M_ij . grad_i W_ij
  double w_rho;               // W_ij / rho_ij, rho_ij = (rho_i + rho_j)/2 (XSPH; one division for both sides)
};

SPHCUT_INLINE double int_pow(double x, double n)
{
  // the usual artificial stress exponents are small integers
  if (n == 4.0) { const double x2 = x * x; return x2 * x2; }
  if (n == 2.0) return x * x;
  if (n == 3.0) return x * x * x;
  return pow(x, n);
}

template <int DIM>
SPHCUT_PAIR_INLINE void pair_terms(int kernel, const PairIn &in, PairOut &out)
{
  const double r = sqrt(in.r2);
  double wfac;
  kernel_w_gradfac_pre(kernel, r, in.inv_h, in.wnorm, out.w, wfac);
  for (int a = 0; a < 3; a++) out.g[a] = a < DIM ? wfac * in.dx[a] : 0.0;

  // bracket M_ij = sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I + f^n (R_i + R_j)
  double M[6];
  for (int k = 0; k < 6; k++) M[k] = in.A_i[k] + in.A_j[k];
  double vr = 0.0;    // (v_i - v_j).(x_i - x_j)
  for (int a = 0; a < DIM; a++) vr -= in.dv[a] * in.dx[a];
  const double pi_ij = artificial_viscosity(in.alpha, in.beta, vr, in.r2, in.h, in.cbar,
                                            0.5 * (in.rho_i + in.rho_j));
  M[XX] -= pi_ij;
  M[YY] -= pi_ij;
  M[ZZ] -= pi_ij;
  if (in.R_i) {
    const double fn = int_pow(out.w * in.inv_wdp, in.as_n);
    for (int k = 0; k < 6; k++) M[k] += fn * (in.R_i[k] + in.R_j[k]);
  }
  sym_apply(M, out.g, out.Mg);
  out.w_rho = out.w / (0.5 * (in.rho_i + in.rho_j));
  out.dvg = 0.0;
  out.work = 0.0;
  for (int a = 0; a < DIM; a++) {
    out.dvg += in.dv[a] * out.g[a];
    out.work += in.dv[a] * out.Mg[a];
  }
}

/* ---- constants of a type pair (mixing rules) --------------------------
   h and W(dp) come from the pair style's settings; the stabilisation
   parameters of a pair are the means of the two materials'.             */
struct TypePair {
  double h, cutsq, wdp;       // smoothing length, (2h)^2, W(mean particle spacing)
  double inv_h, wnorm, inv_wdp;    // 1/h, kernel normalisation sigma_d/h^d, 1/W(dp)
  double as_n;                // artificial stress exponent
  double alpha, beta, cbar;   // artificial viscosity, mean bulk sound speed
};

SPHCUT_INLINE TypePair mix_type_pair(const Material &mi, const Material &mj, double h, double wdp, int kernel,
                                     int dim)
{
  TypePair tp;
  tp.h = h;
  tp.cutsq = 4.0 * h * h;
  tp.wdp = wdp;
  tp.inv_h = 1.0 / h;
  tp.wnorm = kernel_sigma(kernel, dim) / (dim == 2 ? h * h : h * h * h);
  tp.inv_wdp = wdp > 0.0 ? 1.0 / wdp : 0.0;
  tp.as_n = 0.5 * (mi.as_n + mj.as_n);
  tp.alpha = 0.5 * (mi.av_alpha + mj.av_alpha);
  tp.beta = 0.5 * (mi.av_beta + mj.av_beta);
  tp.cbar = 0.5 * (mi.c0 + mj.c0);
  return tp;
}

SPHCUT_INLINE void set_type_pair(const TypePair &tp, PairIn &in)
{
  in.h = tp.h;
  in.inv_h = tp.inv_h;
  in.wnorm = tp.wnorm;
  in.inv_wdp = tp.inv_wdp;
  in.as_n = tp.as_n;
  in.alpha = tp.alpha;
  in.beta = tp.beta;
  in.cbar = tp.cbar;
}

/* ---- the sums a particle gathers from its neighbours --------------------
   index layout of one particle's accumulator row (ACC_F: the force, which
   the drivers keep in atom->f; the rest travel in reverse communication)   */
enum PairAcc {
  ACC_F = 0,                  // m_i m_j M_ij grad_i W_ij (3)
  ACC_DRHO = 3,               // sum_j V_j (v_j - v_i) . grad_i W_ij
  ACC_DU,                     // 1/2 sum_j m_j (v_j - v_i) . M_ij grad_i W_ij
  ACC_XS,                     // sum_j m_j / rho_ij (v_j - v_i) W_ij (3)
  ACC_L = ACC_XS + 3,         // sum_j V_j (v_j - v_i) (x) grad_i W_ij (9, row major)
  ACC_B = ACC_L + 9,          // -sum_j V_j (x_i - x_j) (x) grad_i W_ij (9): renormalisation
  NACC = ACC_B + 9,
  ACC_FIRST_REVERSE = ACC_DRHO,
  NACC_REVERSE = NACC - ACC_DRHO
};

/* add the contribution of pair i-j to one of the two particles through
   add(index, value): side = +1 for i (m_o, V_o: mass and volume of j),
   side = -1 for j (m_o, V_o of i).  Force and XSPH are antisymmetric, the
   others symmetric (grad_j W_ij = -grad_i W_ij, v_i - v_j = -(v_j - v_i)). */
template <int DIM, class Add>
SPHCUT_PAIR_INLINE void pair_accumulate(const PairIn &in, const PairOut &out, double mm, double m_o,
                                        double V_o, double side, Add &&add)
{
  const double xsfac = m_o * out.w_rho;
  for (int a = 0; a < DIM; a++) add(ACC_F + a, side * mm * out.Mg[a]);
  add(ACC_DRHO, V_o * out.dvg);
  add(ACC_DU, 0.5 * m_o * out.work);
  for (int a = 0; a < DIM; a++) {
    add(ACC_XS + a, side * xsfac * in.dv[a]);
    for (int b = 0; b < DIM; b++) {
      add(ACC_L + 3 * a + b, V_o * in.dv[a] * out.g[b]);
      add(ACC_B + 3 * a + b, -V_o * in.dx[a] * out.g[b]);
    }
  }
}

/* ---- per particle, after the neighbour sums: the rates -----------------
   L = (sum V_j dv (x) grad W) B^-1 (renormalised, exact for linear velocity
   fields) or the plain sum; then the Jaumann rate of the force-state stress
   sf.  Results: drho = -rho_f sum V_j dv.gradW, ds (Voigt), du.          */
SPHCUT_INLINE void particle_rates(const Material &mt, int dim, int correction, const double *acc,
                                  const double *sf, double rho_f, double &drho, double *ds, double &du)
{
  double L[9];
  if (correction) {
    double b[9], binv[9];
    for (int k = 0; k < 9; k++) b[k] = acc[ACC_B + k];
    if (dim == 2) {
      b[2] = b[5] = b[6] = b[7] = 0.0;
      b[8] = 1.0;
    }
    mat_inverse(b, binv, dim);
    mat_mul(&acc[ACC_L], binv, L);
  } else {
    for (int k = 0; k < 9; k++) L[k] = acc[ACC_L + k];
  }
  if (dim == 2) L[2] = L[5] = L[6] = L[7] = L[8] = 0.0;
  jaumann_rate(mt, L, sf, ds);
  drho = -rho_f * acc[ACC_DRHO];
  du = acc[ACC_DU];
}

// an upper bound of the largest eigenvalue of a symmetric tensor (Voigt; Gershgorin's discs)
SPHCUT_INLINE double max_eigen_bound(const double *s)
{
  const double bx = s[XX] + fabs(s[XY]) + fabs(s[XZ]);
  const double by = s[YY] + fabs(s[XY]) + fabs(s[YZ]);
  const double bz = s[ZZ] + fabs(s[XZ]) + fabs(s[YZ]);
  const double b = bx > by ? bx : by;
  return b > bz ? b : bz;
}

// per particle of the force state (local and ghost), what its pairs need: A = sigma/rho^2
// (the particle's share of the momentum bracket) and the artificial stress R.  R is zero
// unless a principal stress is tensile: a stress whose Gershgorin bound is <= 0 (the usual
// state under compression) skips the eigen-decomposition.
SPHCUT_INLINE void particle_stress(const Material &mt, int dim, int with_as, double rho_f, double temp_f,
                                   const double *sf, double *A, double *R)
{
  double sig[6];
  cauchy_stress(sf, eos_pressure(mt, rho_f, temp_f), sig);
  const double ir2 = 1.0 / (rho_f * rho_f);
  for (int k = 0; k < 6; k++) A[k] = sig[k] * ir2;
  if (!with_as) return;
  if (mt.as_eps > 0.0 && max_eigen_bound(sig) > 0.0) artificial_stress(mt.as_eps, sig, rho_f, dim, R);
  else for (int k = 0; k < 6; k++) R[k] = 0.0;
}

}    // namespace sphcut

#endif
