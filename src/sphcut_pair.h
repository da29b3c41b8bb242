/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the per-pair arithmetic of pair sph/jc-thermal (host and
   device), seed 003 eqs. 10-11.  The drivers (CPU pair, Kokkos pair)
   only gather inputs and scatter the outputs.
------------------------------------------------------------------------- */

#ifndef SPHCUT_PAIR_H
#define SPHCUT_PAIR_H

#include "sphcut_kernels.h"
#include "sphcut_material.h"
#include "sphcut_state.h"

// the per-pair functions are inlined into the neighbour loops (sphcut_math.h SPHCUT_LOOP_INLINE)
#define SPHCUT_PAIR_INLINE SPHCUT_LOOP_INLINE

namespace sphcut {

// inputs of one pair i-j (force state of fix sph/jc-thermal)
struct PairIn {
  double dx[3];               // x_i - x_j
  double r2;
  double dv[3];               // v_j - v_i (predicted velocities)
  double h, inv_h, wnorm;     // smoothing length, 1/h, kernel normalisation sigma_d/h^d
  double inv_wdp;             // 1/W(particle spacing)
  double rho_i, rho_j;
  double A_i[6], A_j[6];      // Cauchy stress over rho^2, sigma/rho^2 (Voigt; particle_stress)
  const double *R_i, *R_j;    // artificial stress tensors (R_i nullptr: no artificial stress term)
  const double *R_own;        // i's artificial stress (nullptr: none in the run; unpack_i)
  bool r_own;                 // i's R is nonzero
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

/* pair_terms in two halves.  pair_scalars: what depends on the distance
   and the velocities only, the long chain of dependent operations (sqrt,
   divisions, kernel); pair_finish: the bracket and its products.  A CPU
   loop can run the first half over all neighbours of a particle, then the
   second (short bodies the processor overlaps from pair to pair).        */
struct PairScalars {
  double w, wfac;             // W_ij and grad_i W_ij = wfac (x_i - x_j)
  double pi;                  // artificial viscosity Pi_ij
  double fn;                  // artificial stress factor f^n (0 when in.R_i is nullptr)
  double w_rho;               // W_ij / rho_ij
};

template <int DIM>
SPHCUT_PAIR_INLINE void pair_scalars(int kernel, const PairIn &in, PairScalars &ps)
{
  const double r = sqrt(in.r2);
  kernel_w_gradfac_pre(kernel, r, in.inv_h, in.wnorm, ps.w, ps.wfac);
  double vr = 0.0;    // (v_i - v_j).(x_i - x_j)
  for (int a = 0; a < DIM; a++) vr -= in.dv[a] * in.dx[a];
  ps.pi = artificial_viscosity(in.alpha, in.beta, vr, in.r2, in.h, in.cbar, 0.5 * (in.rho_i + in.rho_j));
  ps.fn = in.R_i ? int_pow(ps.w * in.inv_wdp, in.as_n) : 0.0;
  ps.w_rho = ps.w / (0.5 * (in.rho_i + in.rho_j));
}

template <int DIM>
SPHCUT_PAIR_INLINE void pair_finish(const PairIn &in, const PairScalars &ps, PairOut &out)
{
  out.w = ps.w;
  out.w_rho = ps.w_rho;
  for (int a = 0; a < 3; a++) out.g[a] = a < DIM ? ps.wfac * in.dx[a] : 0.0;
  // bracket M_ij = sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I + f^n (R_i + R_j)
  double M[6];
  for (int k = 0; k < 6; k++) M[k] = in.A_i[k] + in.A_j[k];
  M[XX] -= ps.pi;
  M[YY] -= ps.pi;
  M[ZZ] -= ps.pi;
  if (in.R_i)
    for (int k = 0; k < 6; k += 2) {
      double ri0, ri1, rj0, rj1;
      load2(in.R_i + k, ri0, ri1);
      load2(in.R_j + k, rj0, rj1);
      M[k] += ps.fn * (ri0 + rj0);
      M[k + 1] += ps.fn * (ri1 + rj1);
    }
  sym_apply(M, out.g, out.Mg);
  out.dvg = 0.0;
  out.work = 0.0;
  for (int a = 0; a < DIM; a++) {
    out.dvg += in.dv[a] * out.g[a];
    out.work += in.dv[a] * out.Mg[a];
  }
}

template <int DIM>
SPHCUT_PAIR_INLINE void pair_terms(int kernel, const PairIn &in, PairOut &out)
{
  PairScalars ps;
  pair_scalars<DIM>(kernel, in, ps);
  pair_finish<DIM>(in, ps, out);
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
  tp.cutsq = support_radius_sq(h);
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
  ACC_B = ACC_L + 9,          // -sum_j V_j (x_i - x_j) (x) grad_i W_ij (9): renormalisation, symmetric:
                              // the upper triangle is summed, the entries below the diagonal stay 0
  NACC = ACC_B + 9,
  ACC_FIRST_REVERSE = ACC_DRHO,
  NACC_REVERSE = NACC - ACC_DRHO
};

/* add the contribution of pair i-j to one of the two particles through
   add(index, value): side = +1 for i (m_o, V_o: mass and volume of j),
   side = -1 for j (m_o, V_o of i).  Force and XSPH are antisymmetric, the
   others symmetric (grad_j W_ij = -grad_i W_ij, v_i - v_j = -(v_j - v_i)).
   The products of the pair (dv_a g_b, ...) are written apart from the
   weights so that a driver adding both sides computes them once; B is
   symmetric (g is parallel to dx): only its upper triangle (a <= b) is
   summed, particle_rates mirrors it.                                      */
template <int DIM, class Add>
SPHCUT_PAIR_INLINE void pair_accumulate(const PairIn &in, const PairOut &out, double mm, double m_o,
                                        double V_o, double side, Add &&add)
{
  const double fs = side * mm, xs = side * m_o;
  for (int a = 0; a < DIM; a++) add(ACC_F + a, fs * out.Mg[a]);
  add(ACC_DRHO, V_o * out.dvg);
  add(ACC_DU, m_o * (0.5 * out.work));
  for (int a = 0; a < DIM; a++) {
    add(ACC_XS + a, xs * (out.w_rho * in.dv[a]));
    for (int b = 0; b < DIM; b++) {
      add(ACC_L + 3 * a + b, V_o * (in.dv[a] * out.g[b]));
      if (b >= a) add(ACC_B + 3 * a + b, -V_o * (in.dx[a] * out.g[b]));
    }
  }
}

/* ---- per particle, after the neighbour sums: the rates -----------------
   L = (sum V_j dv (x) grad W) B^-1 (renormalised, exact for linear velocity
   fields) or the plain sum (particle_velocity_gradient, row major, 2d: z row
   and column 0); then the Jaumann rate of the force-state stress sf.
   Results: drho = -rho_f sum V_j dv.gradW, ds (Voigt), du.               */
SPHCUT_INLINE void particle_velocity_gradient(int dim, int correction, const double *acc, double *L)
{
  if (correction) {
    double b[9], binv[9];
    for (int a = 0; a < 3; a++)
      for (int c = 0; c < 3; c++) b[3 * a + c] = a <= c ? acc[ACC_B + 3 * a + c] : acc[ACC_B + 3 * c + a];
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
}

SPHCUT_INLINE void particle_rates(const Material &mt, int dim, int correction, const double *acc,
                                  const double *sf, double rho_f, double &drho, double *ds, double &du)
{
  double L[9];
  particle_velocity_gradient(dim, correction, acc, L);
  jaumann_rate(mt, L, sf, ds);
  drho = -rho_f * acc[ACC_DRHO];
  du = acc[ACC_DU];
}

/* ---- hourglass control (pair_style keyword hourglass, default off) -----
   The part of a pair's velocity difference that the velocity gradients of
   its two particles do not predict,
     e_ij = (v_j - v_i) - 1/2 (L_i + L_j) (x_j - x_i),
   is zero for a linear velocity field (L exact: correction yes) and O(1)
   for the odd-even (zero-energy) modes that L does not see.  Its component
   along the pair is damped like the artificial viscosity damps v_ij:
     Pi^hg_ij = kappa cbar h (e_ij . x_ij) / ((r_ij^2 + 0.01 h^2) rho_ij),
   entering the bracket M_ij as -Pi^hg I (for either sign of e.x; Pi of the
   artificial viscosity acts on approaching pairs only).  The pair force is
   central and antisymmetric (linear and angular momentum conserved); its
   work goes into u like that of the bracket (du_i += 1/2 m_j dv.Mg), so
   kinetic + internal energy is conserved.  An updated-Lagrangian, velocity
   form of the hourglass control of Ganzenmueller (Comput. Methods Appl.
   Mech. Engrg. 286 (2015) 87-106), which works on the positions of total-
   Lagrangian SPH.  Needs L of both particles: a second pass over the pairs
   after the first has been summed.                                         */
template <int DIM>
SPHCUT_PAIR_INLINE double hourglass_error_dx(const double *dx, const double *dv, const double *L_i,
                                             const double *L_j)
{
  // x_j - x_i = -dx: e = dv + 1/2 (L_i + L_j) dx
  double edx = 0.0;
  for (int a = 0; a < DIM; a++) {
    double e = dv[a];
    for (int b = 0; b < DIM; b++) e += 0.5 * (L_i[3 * a + b] + L_j[3 * a + b]) * dx[b];
    edx += e * dx[a];
  }
  return edx;
}

/* the hourglass term of pair i-j: Mg (force on i = m_i m_j Mg) and its work
   dv.Mg; wfac from pair_scalars (grad_i W = wfac dx), rho_bar = (rho_i +
   rho_j)/2                                                                 */
template <int DIM>
SPHCUT_PAIR_INLINE void hourglass_pair(double kappa, const PairIn &in, double wfac, const double *L_i,
                                       const double *L_j, double *Mg, double &work)
{
  const double edx = hourglass_error_dx<DIM>(in.dx, in.dv, L_i, L_j);
  const double rho_bar = 0.5 * (in.rho_i + in.rho_j);
  const double pi = kappa * in.cbar * in.h * edx / ((in.r2 + 0.01 * in.h * in.h) * rho_bar);
  work = 0.0;
  for (int a = 0; a < 3; a++) {
    Mg[a] = a < DIM ? -pi * wfac * in.dx[a] : 0.0;
    if (a < DIM) work += in.dv[a] * Mg[a];
  }
}

// true when no principal value of a symmetric tensor (Voigt) is positive: -s is positive
// semidefinite (its principal minors are >= 0)
SPHCUT_INLINE bool no_positive_eigenvalue(const double *s)
{
  const double a = -s[XX], b = -s[YY], c = -s[ZZ], d = -s[XY], e = -s[XZ], f = -s[YZ];
  if (a < 0.0 || b < 0.0 || c < 0.0) return false;
  if (a * b - d * d < 0.0 || a * c - e * e < 0.0 || b * c - f * f < 0.0) return false;
  return a * (b * c - f * f) - d * (d * c - f * e) + e * (d * f - b * e) >= 0.0;
}

// per particle of the force state (local and ghost), what its pairs need: A = sigma/rho^2
// (the particle's share of the momentum bracket) and the artificial stress R.  R is zero
// unless a principal stress is tensile: a stress without one (the usual state under
// compression) skips the eigen-decomposition.  A particle released by the spall (pmin with
// spall release, below the cutoff) carries neither.
SPHCUT_INLINE void particle_stress(const Material &mt, int dim, int with_as, double rho_f, double temp_f,
                                   const double *sf, double *A, double *R)
{
  const double p_eos = eos_pressure_uncut(mt, rho_f, temp_f);
  if (spall_released(mt, p_eos)) {
    // separated (spall release): no stress, so no artificial stress either (R written only
    // with_as: a row without artificial stress has no room for it)
    for (int k = 0; k < 6; k++) A[k] = 0.0;
    if (with_as)
      for (int k = 0; k < 6; k++) R[k] = 0.0;
    return;
  }
  double sig[6];
  cauchy_stress(sf, pressure_cutoff(mt, p_eos), sig);
  const double ir2 = 1.0 / (rho_f * rho_f);
  for (int k = 0; k < 6; k++) A[k] = sig[k] * ir2;
  if (!with_as) return;
  if (mt.as_eps > 0.0 && !no_positive_eigenvalue(sig)) artificial_stress(mt.as_eps, sig, rho_f, dim, R);
  else for (int k = 0; k < 6; k++) R[k] = 0.0;
}

/* ---- a particle's packed row: what its neighbours read of it -------------
   One contiguous row per particle (local and ghost), built once per force
   evaluation, instead of pieces of x, the state row, mask, type, mass, sigma
   and R: position, type (negative when the particle's artificial stress
   is nonzero), mass (0: not in the SPH solid, skipped: only its position
   and type are packed), volume m/rho, predicted velocity, density,
   sigma/rho^2 and the artificial stress.  The neighbour loads are what the
   pair kernel's time goes to on a GPU (L1-bound: the cost of an irregular
   load is per instruction and per sector), so the row is read in 16-byte
   pairs (load2: one 128-bit load each on a GPU), in the order the pair
   needs them: position and type (the cutoff of the type pair), then mass
   and volume (a particle outside the solid stops there), then the rest.
   A row without artificial stress is NPK_NOAS = 16 doubles (128 bytes, 4
   sectors of 32 bytes), with it NPK = 24 (R and padding); a pair loads R
   only where one of its two particles has a nonzero R (the sign of the
   type: under compression R is zero, and a term of two zero tensors adds
   exactly nothing).                                                        */
enum PackedRow : int {
  PK_X = 0,       // position (3)
  PK_TYPE = 3,    // atom type (a double: read with the position, for the type pair's cutoff);
                  // -type when the artificial stress R is nonzero
  PK_M = 4,       // mass; 0: not in the SPH solid (outside the group, or a tool particle)
  PK_VOL = 5,     // volume m/rho
  PK_V = 6,       // predicted velocity (3, state VEST)
  PK_RHO = 9,     // density of the force state (RHO_F)
  PK_A = 10,      // sigma/rho^2 (6, Voigt; particle_stress)
  NPK_NOAS = 16,  // the row's width without artificial stress
  PK_R = 16,      // artificial stress (6; only in rows of width NPK, when some material has one)
  NPK = 24        // the row's width with artificial stress (16-byte multiple: load2 alignment)
};

// rows and the slots read in pairs start at even slots (16-byte aligned: load2)
static_assert(NPK % 2 == 0 && NPK_NOAS % 2 == 0 && PK_M % 2 == 0 && PK_V % 2 == 0 && PK_A % 2 == 0 && PK_R % 2 == 0,
              "packed rows not in 16-byte pairs");

// the width of a row (its stride): with or without room for the artificial stress
SPHCUT_INLINE int pack_width(int with_as) { return with_as ? NPK : NPK_NOAS; }

// the packed row of a particle outside the SPH solid: its position and type, mass 0
SPHCUT_INLINE void pack_outside(const double *x, int type, double *row)
{
  for (int a = 0; a < 3; a++) row[PK_X + a] = x[a];
  row[PK_TYPE] = type;
  row[PK_M] = 0.0;
  row[PK_VOL] = 0.0;
}

// the packed row of a particle of the SPH solid from its position, type, its state row s (the
// force state of fix sph/jc-thermal: RHO_F, SF, TEMP_F, VEST), its mass and material
SPHCUT_INLINE void pack_row(const Material &mt, int dim, int with_as, const double *x, int type, const double *s,
                            double m, double *row)
{
  using SL = StateLayout;
  for (int a = 0; a < 3; a++) {
    row[PK_X + a] = x[a];
    row[PK_V + a] = s[SL::VEST + a];
  }
  row[PK_RHO] = s[SL::RHO_F];
  row[PK_M] = m;
  row[PK_VOL] = m / s[SL::RHO_F];
  // R in registers, then into the row: the type's sign from them, not read back from the row
  double R[6];
  particle_stress(mt, dim, with_as, s[SL::RHO_F], s[SL::TEMP_F], &s[SL::SF], &row[PK_A], R);
  bool r_nonzero = false;
  if (with_as)
    for (int k = 0; k < 6; k++) {
      row[PK_R + k] = R[k];
      if (R[k] != 0.0) r_nonzero = true;
    }
  row[PK_TYPE] = r_nonzero ? -type : type;
}

// the type of a packed row
SPHCUT_INLINE int row_type(double t) { return (int) (t < 0.0 ? -t : t); }

// particle i's side of its pairs from its row: position, velocity, density and sigma/rho^2, and
// with_as (some material has an artificial stress) its R for unpack_j
SPHCUT_INLINE void unpack_i(const double *pi, int with_as, double *xi, double *vi, PairIn &in)
{
  double t;
  load2(pi + PK_X, xi[0], xi[1]);
  load2(pi + PK_X + 2, xi[2], t);
  in.R_own = with_as ? pi + PK_R : nullptr;
  in.r_own = with_as && t < 0.0;
  load2(pi + PK_V, vi[0], vi[1]);
  load2(pi + PK_V + 2, vi[2], in.rho_i);
  for (int k = 0; k < 6; k += 2) load2(pi + PK_A + k, in.A_i[k], in.A_i[k + 1]);
}

// the head of j's row: its position and its type (as stored: negative with artificial stress),
// what the cutoff test reads of every list entry
SPHCUT_INLINE void unpack_j_head(const double *pj, double *xj, double &tj)
{
  load2(pj + PK_X, xj[0], xj[1]);
  load2(pj + PK_X + 2, xj[2], tj);
}

// the inputs of pair i-j from j's row pj, whose head (unpack_j_head) is xj, tj, and the row tprow
// of i's type pairs (tprow[type of j]): false when j is beyond the cutoff (or on top of i), or not
// in the SPH solid (mj 0; loaded only within the cutoff); mj and Vj the mass and volume of j.  The
// artificial stress term: in.R_i and R_j point to the two tensors where one of them is nonzero,
// else in.R_i is nullptr (pair_terms skips the term and loads neither).  (A GPU pass may load the
// next entry's head before this one's rest: its latency then overlaps this pair's work.)
SPHCUT_INLINE bool unpack_j_rest(const double *pj, const double *xj, double tj, const TypePair *tprow,
                                 const double *xi, const double *vi, PairIn &in, double &mj, double &Vj)
{
  for (int a = 0; a < 3; a++) in.dx[a] = xi[a] - xj[a];
  in.r2 = in.dx[0] * in.dx[0] + in.dx[1] * in.dx[1] + in.dx[2] * in.dx[2];
  const TypePair &tp = tprow[row_type(tj)];
  if (in.r2 >= tp.cutsq || in.r2 == 0.0) return false;
  load2(pj + PK_M, mj, Vj);
  if (mj == 0.0) return false;
  double vj[3];
  load2(pj + PK_V, vj[0], vj[1]);
  load2(pj + PK_V + 2, vj[2], in.rho_j);
  for (int a = 0; a < 3; a++) in.dv[a] = vj[a] - vi[a];
  set_type_pair(tp, in);
  for (int k = 0; k < 6; k += 2) load2(pj + PK_A + k, in.A_j[k], in.A_j[k + 1]);
  in.R_i = in.R_own && (in.r_own || tj < 0.0) ? in.R_own : nullptr;
  in.R_j = pj + PK_R;
  return true;
}

// the inputs of pair i-j from j's row: unpack_j_head, then unpack_j_rest
SPHCUT_INLINE bool unpack_j(const double *pj, const TypePair *tprow, const double *xi, const double *vi, PairIn &in,
                            double &mj, double &Vj)
{
  double xj[3], tj;
  unpack_j_head(pj, xj, tj);
  return unpack_j_rest(pj, xj, tj, tprow, xi, vi, in, mj, Vj);
}

}    // namespace sphcut

#endif
