/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the per-pair arithmetic of pair sph/jc-thermal (host and
   device), seed 003 eqs. 10-11.  The drivers (CPU pair, Kokkos pair)
   only gather inputs and scatter the outputs.
------------------------------------------------------------------------- */

#ifndef SPHCUT_PAIR_H
#define SPHCUT_PAIR_H

#include "sphcut_kernels.h"
#include "sphcut_material.h"

namespace sphcut {

// inputs of one pair i-j (force state of fix sph/jc-thermal)
struct PairIn {
  double dx[3];               // x_i - x_j
  double r2;
  double dv[3];               // v_j - v_i (predicted velocities)
  double h, wdp;              // smoothing length, W(particle spacing)
  double rho_i, rho_j;
  const double *sig_i, *sig_j;    // Cauchy stress (Voigt)
  const double *R_i, *R_j;        // artificial stress tensors (nullptr: none)
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
SPHCUT_INLINE void pair_terms(int kernel, const PairIn &in, PairOut &out)
{
  const double r = sqrt(in.r2);
  double wfac;
  kernel_w_gradfac(kernel, DIM, r, in.h, out.w, wfac);
  for (int a = 0; a < 3; a++) out.g[a] = a < DIM ? wfac * in.dx[a] : 0.0;

  // bracket M_ij = sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I + f^n (R_i + R_j)
  const double ri2 = 1.0 / (in.rho_i * in.rho_i);
  const double rj2 = 1.0 / (in.rho_j * in.rho_j);
  double M[6];
  for (int k = 0; k < 6; k++) M[k] = in.sig_i[k] * ri2 + in.sig_j[k] * rj2;
  double vr = 0.0;    // (v_i - v_j).(x_i - x_j)
  for (int a = 0; a < DIM; a++) vr -= in.dv[a] * in.dx[a];
  const double pi_ij = artificial_viscosity(in.alpha, in.beta, vr, in.r2, in.h, in.cbar,
                                            0.5 * (in.rho_i + in.rho_j));
  M[XX] -= pi_ij;
  M[YY] -= pi_ij;
  M[ZZ] -= pi_ij;
  if (in.R_i) {
    const double fn = int_pow(out.w / in.wdp, in.as_n);
    for (int k = 0; k < 6; k++) M[k] += fn * (in.R_i[k] + in.R_j[k]);
  }
  sym_apply(M, out.g, out.Mg);
  out.dvg = 0.0;
  out.work = 0.0;
  for (int a = 0; a < DIM; a++) {
    out.dvg += in.dv[a] * out.g[a];
    out.work += in.dv[a] * out.Mg[a];
  }
}

}    // namespace sphcut

#endif
