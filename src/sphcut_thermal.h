/* -*- c++ -*- ----------------------------------------------------------
   sphcut - thermal arithmetic of seed 003 (host and device): the
   second-order FMFS Laplacian of Fatehi & Manzari (seed 003 eqs. 13-15),
   the Brookshaw Laplacian (seed 003 eq. 12) with the harmonic-mean
   heat-flux form of seed 000 eq. 6, and the free-surface indicator of
   Marrone et al. (2010) (seed 003 sec. 4.2).

   Header only, no heap, no exceptions, fixed-size arrays: every function
   is SPHCUT_INLINE so the same code runs in the CPU styles and on device.

   Conventions
     FMFS / surface:  r = x_j - x_i, e = r/|r|, g = grad_i W_ij,
                      V = V_j = m_j/rho_j, dT = T_j - T_i
     Brookshaw:       dx = x_i - x_j (as in sphcut_pair.h), g = grad_i W_ij
   Inputs r, dx, g are double[3]; only the first DIM components are read.

   FMFS, derivation (exact for quadratic T; verified by unittest/test_fmfs):
   per particle accumulate (all sums over neighbours j, times V_j)
     B_ab    = sum r_a g_b                  A = B^-1   (seed 003 eq. 14)
     gT_b    = sum dT g_b
     T3_abc  = sum e_a e_b g_c
     Q3_abc  = sum r_a r_b g_c
     P4_abcd = sum r_a e_b e_c g_d          (fully symmetric in a,b,c)
     S1_cd   = sum 2 dT/|r| e_c g_d
   With T_j - T_i = r.D + 1/2 r.H.r (D = grad T, H = Hessian, exact for a
   quadratic field):
     gT = B^T D + 1/2 H:Q3   =>  grad~ = A^T gT = D + 1/2 A^T (H:Q3)
     S1_cd = 2 D_e T3_ecd + H_ab P4_abcd
     S_cd  = S1_cd - 2 grad~_e T3_ecd = H_ab M_abcd,
     M_abcd = P4_abcd - Q3_abf A_fe T3_ecd
   (for radial kernels B and A are symmetric and A_fe = A_ef).  The
   symmetric G with sum_cd G_cd M_abcd = delta_ab for every symmetric pair
   (ab) gives  G:S = H_ab delta_ab = tr H = lap T.  M is symmetric in (ab)
   and only the symmetric part of G matters, so the unknowns are the
   DIM(DIM+1)/2 entries G_cd, c <= d: a 3x3 (2D) or 6x6 (3D) system.
   This is seed 003 eq. 15 with the sign of its r_ij = x_i - x_j absorbed.

   Internal packing (dimension independent, "colex" order):
     pair   (a <= b)      -> a + b(b+1)/2                 (NS = DIM(DIM+1)/2)
     triple (a <= b <= c) -> a + b(b+1)/2 + c(c+1)(c+2)/6 (NT = DIM(DIM+1)(DIM+2)/6)
   Storage: 2D 32 doubles, 3D 90 doubles.
------------------------------------------------------------------------- */

#ifndef SPHCUT_THERMAL_H
#define SPHCUT_THERMAL_H

#include "sphcut_kernels.h"
#include "sphcut_math.h"

namespace sphcut {

// ---------------------------------------------------------------------------
// small dense linear algebra (N <= 6), partial pivoting, no allocation

// packed index of the symmetric pair (a,b) and of the symmetric triple (a,b,c)
SPHCUT_INLINE int sym_pair_index(int a, int b)
{
  if (a > b) { const int t = a; a = b; b = t; }
  return a + b * (b + 1) / 2;
}

SPHCUT_INLINE int sym_triple_index(int a, int b, int c)
{
  if (a > b) { const int t = a; a = b; b = t; }
  if (b > c) { const int t = b; b = c; c = t; }
  if (a > b) { const int t = a; a = b; b = t; }
  return a + b * (b + 1) / 2 + c * (c + 1) * (c + 2) / 6;
}

// max(m, |x|) with fmax's rule for a NaN x (m is kept), without the libm call fmax is
// without -ffast-math
SPHCUT_INLINE double max_abs(double m, double x)
{
  const double ax = fabs(x);
  return ax > m ? ax : m;
}

// solve a x = b in place (x returned in b); a is destroyed.  Returns false
// when a pivot falls below tol * max|a_ij| (singular or ill-conditioned).
template <int N>
SPHCUT_INLINE bool dense_solve(double (&a)[N][N], double (&b)[N], double tol)
{
  double scale = 0.0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) scale = max_abs(scale, a[i][j]);
  if (!(scale > 0.0)) return false;    // also catches NaN
  const double pmin = tol * scale;
  for (int k = 0; k < N; k++) {
    int p = k;
    double pmax = fabs(a[k][k]);
    for (int i = k + 1; i < N; i++)
      if (fabs(a[i][k]) > pmax) { pmax = fabs(a[i][k]); p = i; }
    if (!(pmax > pmin)) return false;
    if (p != k) {
      for (int j = 0; j < N; j++) { const double t = a[k][j]; a[k][j] = a[p][j]; a[p][j] = t; }
      const double t = b[k]; b[k] = b[p]; b[p] = t;
    }
    const double inv = 1.0 / a[k][k];
    for (int i = k + 1; i < N; i++) {
      const double f = a[i][k] * inv;
      if (f == 0.0) continue;
      for (int j = k + 1; j < N; j++) a[i][j] -= f * a[k][j];
      b[i] -= f * b[k];
    }
  }
  for (int k = N - 1; k >= 0; k--) {
    double s = b[k];
    for (int j = k + 1; j < N; j++) s -= a[k][j] * b[j];
    b[k] = s / a[k][k];
  }
  return true;
}

// inverse of a small dense matrix by Gauss-Jordan with partial pivoting;
// false (and inv = identity) when singular/ill-conditioned as above
template <int N>
SPHCUT_INLINE bool dense_inverse(const double (&a)[N][N], double (&inv)[N][N], double tol)
{
  double m[N][N];
  double scale = 0.0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      m[i][j] = a[i][j];
      inv[i][j] = i == j ? 1.0 : 0.0;
      scale = max_abs(scale, a[i][j]);
    }
  if (!(scale > 0.0)) return false;
  const double pmin = tol * scale;
  for (int k = 0; k < N; k++) {
    int p = k;
    double pmax = fabs(m[k][k]);
    for (int i = k + 1; i < N; i++)
      if (fabs(m[i][k]) > pmax) { pmax = fabs(m[i][k]); p = i; }
    if (!(pmax > pmin)) {
      for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) inv[i][j] = i == j ? 1.0 : 0.0;
      return false;
    }
    if (p != k)
      for (int j = 0; j < N; j++) {
        double t = m[k][j]; m[k][j] = m[p][j]; m[p][j] = t;
        t = inv[k][j]; inv[k][j] = inv[p][j]; inv[p][j] = t;
      }
    const double d = 1.0 / m[k][k];
    for (int j = 0; j < N; j++) { m[k][j] *= d; inv[k][j] *= d; }
    for (int i = 0; i < N; i++) {
      if (i == k) continue;
      const double f = m[i][k];
      if (f == 0.0) continue;
      for (int j = 0; j < N; j++) { m[i][j] -= f * m[k][j]; inv[i][j] -= f * inv[k][j]; }
    }
  }
  return true;
}

// ---------------------------------------------------------------------------
// FMFS Laplacian (Fatehi & Manzari; seed 003 eqs. 13-15)

// relative pivot tolerance below which B or the G system counts as singular
#define SPHCUT_FMFS_TOL 1.0e-10

template <int DIM> struct FmfsAccum {
  static constexpr int NS = DIM * (DIM + 1) / 2;              // symmetric pairs
  static constexpr int NT = DIM * (DIM + 1) * (DIM + 2) / 6;  // symmetric triples
  double B[DIM][DIM];     // sum r_a g_b V
  double gT[DIM];         // sum dT g V
  double gs[DIM];         // sum g V (surface normal)
  double T3[NS][DIM];     // sum e_a e_b g_c V          [pair(a,b)][c]
  double Q3[NS][DIM];     // sum r_a r_b g_c V          [pair(a,b)][c]
  double P4[NT][DIM];     // sum |r| e_a e_b e_c g_d V  [triple(a,b,c)][d]
  double S1[DIM][DIM];    // sum 2 dT/|r| e_c g_d V
};

template <int DIM>
SPHCUT_INLINE void fmfs_zero(FmfsAccum<DIM> &acc)
{
  for (int a = 0; a < DIM; a++) {
    acc.gT[a] = acc.gs[a] = 0.0;
    for (int b = 0; b < DIM; b++) acc.B[a][b] = acc.S1[a][b] = 0.0;
  }
  for (int p = 0; p < FmfsAccum<DIM>::NS; p++)
    for (int c = 0; c < DIM; c++) acc.T3[p][c] = acc.Q3[p][c] = 0.0;
  for (int t = 0; t < FmfsAccum<DIM>::NT; t++)
    for (int d = 0; d < DIM; d++) acc.P4[t][d] = 0.0;
}

// add neighbour j: r = x_j - x_i, g = grad_i W_ij, V = m_j/rho_j, dT = T_j - T_i
template <int DIM>
SPHCUT_INLINE void fmfs_add(FmfsAccum<DIM> &acc, const double *r, const double *g, double V,
                            double dT)
{
  double r2 = 0.0;
  for (int a = 0; a < DIM; a++) r2 += r[a] * r[a];
  if (!(r2 > 0.0)) return;    // coincident particle carries no information
  const double rn = sqrt(r2), irn = 1.0 / rn;
  double e[DIM], gv[DIM];
  for (int a = 0; a < DIM; a++) {
    e[a] = r[a] * irn;
    gv[a] = g[a] * V;
  }
  const double s1 = 2.0 * dT * irn;
  for (int a = 0; a < DIM; a++) {
    acc.gT[a] += dT * gv[a];
    acc.gs[a] += gv[a];
    for (int b = 0; b < DIM; b++) {
      acc.B[a][b] += r[a] * gv[b];
      acc.S1[a][b] += s1 * e[a] * gv[b];
    }
  }
  int p = 0, t = 0;
  for (int c = 0; c < DIM; c++)
    for (int b = 0; b <= c; b++) {
      // pair (b,c), index b + c(c+1)/2 == p
      const double ee = e[b] * e[c];
      for (int d = 0; d < DIM; d++) {
        acc.T3[p][d] += ee * gv[d];
        acc.Q3[p][d] += r2 * ee * gv[d];
      }
      p++;
      for (int a = 0; a <= b; a++) {
        // triple (a,b,c), index a + b(b+1)/2 + c(c+1)(c+2)/6 == t
        const double eee = rn * e[a] * ee;
        for (int d = 0; d < DIM; d++) acc.P4[t][d] += eee * gv[d];
        t++;
      }
    }
}

// consistent gradient grad T = A^T gT, A = B^-1 (exact for linear T).
// Returns false (grad = 0) when B is singular.
template <int DIM>
SPHCUT_INLINE bool fmfs_gradient(const FmfsAccum<DIM> &acc, double *grad, double tol = SPHCUT_FMFS_TOL)
{
  double A[DIM][DIM];
  const bool ok = dense_inverse<DIM>(acc.B, A, tol);
  for (int f = 0; f < DIM; f++) {
    double s = 0.0;
    if (ok)
      for (int c = 0; c < DIM; c++) s += A[c][f] * acc.gT[c];
    grad[f] = s;
  }
  return ok;
}

// the second-order system of FMFS shared by fmfs_laplacian and fmfs_weights: with A = B^-1,
// W_ab,e = Q3_abf A_fe and K_(ab),(cd) = M_abcd + M_abdc (c < d) or M_abcc (c == d),
// M_abcd = P4_abcd - W_ab,e T3_ecd, solve K G = delta for the packed symmetric G; false
// where K is singular
template <int DIM>
SPHCUT_INLINE bool fmfs_system(const FmfsAccum<DIM> &acc, const double (&A)[DIM][DIM],
                               double (&G)[FmfsAccum<DIM>::NS], double tol)
{
  constexpr int NS = FmfsAccum<DIM>::NS;
  // W_ab,e = Q3_abf A_fe
  double W[NS][DIM];
  for (int p = 0; p < NS; p++)
    for (int e = 0; e < DIM; e++) {
      double s = 0.0;
      for (int f = 0; f < DIM; f++) s += acc.Q3[p][f] * A[f][e];
      W[p][e] = s;
    }

  // the packed indices of the loops below, once per call (the loops are too long to be
  // unrolled completely, so the index functions would run, with their compare and swap, per
  // entry): tri[p][c] = triple(a, b, c) of pair p = (a, b), pe[e][c] = pair(e, c)
  int tri[NS][DIM], pe[DIM][DIM];
  for (int b = 0; b < DIM; b++)
    for (int a = 0; a <= b; a++)
      for (int c = 0; c < DIM; c++) tri[sym_pair_index(a, b)][c] = sym_triple_index(a, b, c);
  for (int e = 0; e < DIM; e++)
    for (int c = 0; c < DIM; c++) pe[e][c] = sym_pair_index(e, c);

  // K_(ab),(cd) = M_abcd + M_abdc (c < d) or M_abcc (c == d),
  // M_abcd = P4_abcd - W_ab,e T3_ecd;  rhs delta_ab
  double K[NS][NS];
  for (int b = 0; b < DIM; b++)
    for (int a = 0; a <= b; a++) {
      const int p = sym_pair_index(a, b);
      G[p] = a == b ? 1.0 : 0.0;
      for (int d = 0; d < DIM; d++)
        for (int c = 0; c <= d; c++) {
          const int q = sym_pair_index(c, d);
          double m = acc.P4[tri[p][c]][d];
          for (int e = 0; e < DIM; e++) m -= W[p][e] * acc.T3[pe[e][c]][d];
          if (c != d) {
            m += acc.P4[tri[p][d]][c];
            for (int e = 0; e < DIM; e++) m -= W[p][e] * acc.T3[pe[e][d]][c];
          }
          K[p][q] = m;
        }
    }

  return dense_solve<NS>(K, G, tol);
}

// second-order Laplacian lap = G:S.  Returns false (lap = 0) when B or the
// G system is singular/ill-conditioned: the caller falls back to Brookshaw.
template <int DIM>
SPHCUT_INLINE bool fmfs_laplacian(const FmfsAccum<DIM> &acc, double &lap, double tol = SPHCUT_FMFS_TOL)
{
  constexpr int NS = FmfsAccum<DIM>::NS;
  lap = 0.0;
  double A[DIM][DIM];
  if (!dense_inverse<DIM>(acc.B, A, tol)) return false;

  // first-order gradient grad~ = A^T gT
  double grad[DIM];
  for (int f = 0; f < DIM; f++) {
    double s = 0.0;
    for (int c = 0; c < DIM; c++) s += A[c][f] * acc.gT[c];
    grad[f] = s;
  }

  // S_cd = S1_cd - 2 grad~_e T3_ecd
  double S[DIM][DIM];
  for (int c = 0; c < DIM; c++)
    for (int d = 0; d < DIM; d++) {
      double s = acc.S1[c][d];
      for (int e = 0; e < DIM; e++) s -= 2.0 * grad[e] * acc.T3[sym_pair_index(e, c)][d];
      S[c][d] = s;
    }

  double G[NS];
  if (!fmfs_system<DIM>(acc, A, G, tol)) return false;
  double Ssym[NS];
  for (int d = 0; d < DIM; d++)
    for (int c = 0; c <= d; c++) Ssym[sym_pair_index(c, d)] = c == d ? S[c][c] : S[c][d] + S[d][c];
  double l = 0.0;
  for (int q = 0; q < NS; q++) l += G[q] * Ssym[q];
  if (!(fabs(l) < 1.0e300)) return false;    // NaN / overflow guard
  lap = l;
  return true;
}

// FMFS as pair weights.  lap T_i = G:S is linear in the differences T_j - T_i:
//   lap T_i = sum_j V_j w_ij (T_j - T_i),
//   w_ij = 2/|r| e.Gf.g + z.g,   z_c = -2 sum_e A_ce Y_e,   Y_e = sum_cd Gf_cd T3_(ec)d
// (Gf the full symmetric G; r, e, g of neighbour j as in fmfs_add).  fmfs_weights
// stores Gf (DIM x DIM, row-major) and z in wts[0 .. DIM*DIM + DIM - 1]; returns false
// where fmfs_laplacian would (singular B or G system).  The pair weights let the
// conservative form of fix heat/fmfs exchange heat pairwise with the mean weight
// (w_ij + w_ji)/2 (see conductance_mean, conductance_pair): equal to FMFS wherever the two
// particles' weights agree (interior of a regular arrangement: exactly).
template <int DIM>
SPHCUT_INLINE bool fmfs_weights(const FmfsAccum<DIM> &acc, double *wts, double tol = SPHCUT_FMFS_TOL)
{
  constexpr int NS = FmfsAccum<DIM>::NS;
  for (int k = 0; k < DIM * DIM + DIM; k++) wts[k] = 0.0;
  double A[DIM][DIM], rhs[NS];
  if (!dense_inverse<DIM>(acc.B, A, tol)) return false;
  if (!fmfs_system<DIM>(acc, A, rhs, tol)) return false;
  double Gf[DIM][DIM];
  for (int c = 0; c < DIM; c++)
    for (int d = 0; d < DIM; d++) Gf[c][d] = rhs[sym_pair_index(c, d)];
  double Y[DIM];
  for (int e = 0; e < DIM; e++) {
    double s = 0.0;
    for (int c = 0; c < DIM; c++)
      for (int d = 0; d < DIM; d++) s += Gf[c][d] * acc.T3[sym_pair_index(e, c)][d];
    Y[e] = s;
  }
  for (int c = 0; c < DIM; c++) {
    double s = 0.0;
    for (int e = 0; e < DIM; e++) s += A[c][e] * Y[e];
    wts[DIM * DIM + c] = -2.0 * s;
    for (int d = 0; d < DIM; d++) wts[DIM * c + d] = Gf[c][d];
  }
  for (int k = 0; k < DIM * DIM + DIM; k++)
    if (!(fabs(wts[k]) < 1.0e300)) return false;
  return true;
}

// heat lost by a free-surface particle of volume vol at temperature T (2D: per unit
// thickness), with the area A = vol^((d-1)/d): convection qc = hconv (T - tconv) A and
// radiation qr = emiss_sigma (T^4 - trad^4) A (emiss_sigma: emissivity times Stefan-Boltzmann)
SPHCUT_INLINE void surface_losses(int dim, double vol, double T, double hconv, double tconv, double emiss_sigma,
                                  double trad, double &qc, double &qr)
{
  const double area = dim == 2 ? sqrt(vol) : pow(vol, 2.0 / 3.0);
  qc = hconv * (T - tconv) * area;
  qr = emiss_sigma * (T * T * T * T - trad * trad * trad * trad) * area;
}

// w_ij of neighbour j from the stored weights of particle i: r = x_j - x_i, g = grad_i W_ij
template <int DIM>
SPHCUT_INLINE double fmfs_pair_weight(const double *wts, const double *r, const double *g)
{
  double r2 = 0.0;
  for (int a = 0; a < DIM; a++) r2 += r[a] * r[a];
  if (!(r2 > 0.0)) return 0.0;
  const double irn = 1.0 / sqrt(r2);
  double egg = 0.0, zg = 0.0;
  for (int c = 0; c < DIM; c++) {
    double gc = 0.0;
    for (int d = 0; d < DIM; d++) gc += wts[DIM * c + d] * g[d];
    egg += r[c] * irn * gc;
    zg += wts[DIM * DIM + c] * g[c];
  }
  return 2.0 * irn * egg + zg;
}

// conservative FMFS / Brookshaw exchange of the pair i-j (default of fix heat/fmfs):
//   rho_i cp_i dT_i/dt = sum_j V_j c_ij (T_j - T_i),   c_ij = (s_ij + s_ji)/2 = c_ji,
// s_ij = k_i w_ij (i on FMFS, w_ij from its weights) or 2 kbar (-wfac) (i on Brookshaw,
// kbar the harmonic mean, seed 000 eq. 6), s_ji likewise from j's side (r -> -r, g -> -g).
// The pair moves V_i V_j c_ij (T_j - T_i) from j to i and the same from i to j: sum m cp T
// is conserved exactly, at the FMFS/Brookshaw seam too.
SPHCUT_INLINE double conductance_mean(double s_ij, double s_ji)
{
  return 0.5 * (s_ij + s_ji);
}

// the pair's conductance over wfac as the exchange uses it: conductance_mean, unless that has
// the anti-diffusive sign, then Brookshaw's (brook = -2 kbar, ThermalPair::brook).  The FMFS
// weights of a strongly disordered support (jittered lattice, 0.4-0.5 dx) can give a pair a
// conductance of the wrong sign, up to -47 times Brookshaw's: heat then flows from cold to
// hot, and a few such pairs give the semi-discrete operator a growing mode (rate up to
// 2 k/(rho cp h^2) measured, independent of dt).  With every c_ij of the diffusive sign the
// exchange is a weighted graph Laplacian, negative semidefinite for any arrangement (maximum
// principle of the semi-discrete system).  Symmetric in i, j (brook is), so sum m cp T stays
// conserved exactly.  wfac <= 0 for all kernels, so c_ij = wfac * this is >= 0 when this has
// the sign of brook (<= 0); a regular lattice has no such pair (unchanged there).
SPHCUT_INLINE double conductance_pair(double s_ij, double s_ji, double brook)
{
  const double c = conductance_mean(s_ij, s_ji);
  return c * brook >= 0.0 ? c : brook;
}

// ---------------------------------------------------------------------------
// Brookshaw Laplacian (seed 003 eq. 12) and heat flux (seed 000 eq. 6)

// harmonic mean 2 ki kj / (ki + kj) (0 when both vanish)
SPHCUT_INLINE double harmonic_mean(double ki, double kj)
{
  const double s = ki + kj;
  return s != 0.0 ? 2.0 * ki * kj / s : 0.0;
}

// per-pair Brookshaw Laplacian term: lap T_i = sum_j V_j brookshaw_term,
//   brookshaw_term = 2 (T_i - T_j) (dx . g) / |dx|^2,  dx = x_i - x_j, g = grad_i W_ij
// (dx . g < 0 for the usual kernels, so T = x^2 gives +2 in the interior)
template <int DIM>
SPHCUT_INLINE double brookshaw_term(double Ti, double Tj, const double *dx, const double *g)
{
  double r2 = 0.0, dg = 0.0;
  for (int a = 0; a < DIM; a++) {
    r2 += dx[a] * dx[a];
    dg += dx[a] * g[a];
  }
  return r2 > 0.0 ? 2.0 * (Ti - Tj) * dg / r2 : 0.0;
}

// per-pair heat-flux term of seed 000 eq. 6 (Jubelgas, harmonic-mean conductivity):
//   p_ij = 4 ki kj / (ki + kj) (T_i - T_j) (dx . g) / |dx|^2
// so that rho_i cp_i dT_i/dt = sum_j V_j p_ij  (= div(k grad T)).
// p_ij = -p_ji exactly (dx, g and T_i - T_j all flip), hence with newton
//   rho_i cp_i dT_i/dt += V_j p_ij,   rho_j cp_j dT_j/dt -= V_i p_ij
// conserves sum_i m_i cp_i T_i exactly (the pair moves V_i V_j p_ij of energy).
template <int DIM>
SPHCUT_INLINE double brookshaw_pair(double Ti, double Tj, double ki, double kj, const double *dx,
                                    const double *g)
{
  return harmonic_mean(ki, kj) * brookshaw_term<DIM>(Ti, Tj, dx, g);
}

// same for radial kernels given wfac of kernel_w_gradfac (g = wfac dx, so
// (dx . g)/|dx|^2 = wfac): p_ij = 4 ki kj/(ki + kj) (T_i - T_j) wfac
SPHCUT_INLINE double brookshaw_pair_radial(double Ti, double Tj, double ki, double kj, double wfac)
{
  return 2.0 * harmonic_mean(ki, kj) * (Ti - Tj) * wfac;
}

// ---------------------------------------------------------------------------
// thermal time step limit of one particle (explicit conduction):
//   dt <= F rho cp h^2 / k * 2/(N + 1)
// F the thermal Courant number (fix sph/jc-thermal thermal_cfl), N the sub-cycling
// interval of fix heat/fmfs (keyword every).  The temperature update (Heun with the
// rate of the previous step as predictor, the conduction rate held for N steps) of a
// mode dT/dt = -lambda T is stable for lambda dt < 2/(N + 1) (N = 1: lambda dt < 1;
// derived for the scalar mode and checked by iterating the update): holding the
// rate stretches the lag to N steps, so the stable dt shrinks by 2/(N + 1), not 1/N.
// k <= 0 or cp <= 0: no limit (1e300).
SPHCUT_INLINE double thermal_dt_limit(double rho, double cp, double kappa, double h, double F, int every)
{
  if (!(kappa > 0.0) || !(cp > 0.0)) return 1.0e300;
  return F * rho * cp * h * h / kappa * 2.0 / (every + 1.0);
}

// the thermal limit's loop over a heat style's group gb, one particle: its limit (density rho, cp,
// kappa of its material, smoothing length h) joined into the minimum m when its mask holds gb.
// The one body of that loop: fix heat/fmfs's dt_limit (CPU), its /kk reduction, and its hook in the
// corrector of fix sph/jc-thermal/kk (sphcut::HeatCorrectorHook)
SPHCUT_INLINE void thermal_dt_min(int mask, int gb, double rho, double cp, double kappa, double h, double F,
                                  int every, double &m)
{
  if (!(mask & gb)) return;
  const double d = thermal_dt_limit(rho, cp, kappa, h, F, every);
  if (d < m) m = d;
}

// Stefan-Boltzmann constant in SI units (radiation of fix heat/fmfs needs units si)
constexpr double STEFAN_BOLTZMANN_SI = 5.670374419e-8;

// (the Dirichlet group of a particle, dirichlet_index, is in sphcut_heat_rules.h: the integrator
// applies the Dirichlet temperatures in its predictor and after its corrector)

// ---------------------------------------------------------------------------
// free-surface indicator (Marrone et al. 2010; seed 003 sec. 4.2)

// lambda = minimum eigenvalue of the symmetric part of B = sum r (x) g V
// (~1 inside a full kernel support, smaller at the surface; seed 003 uses
// lambda <= 0.75 to mark surface particles).  Marrone's lambda is the
// minimum eigenvalue of L^-1 with L the renormalisation matrix, i.e. of B
// itself (not of A = B^-1 as seed 003's wording suggests).
template <int DIM>
SPHCUT_INLINE double surface_lambda(const double (&B)[DIM][DIM])
{
  if (DIM == 2) {
    const double bxy = 0.5 * (B[0][1] + B[1][0]);
    const double m = 0.5 * (B[0][0] + B[1][1]);
    const double d = 0.5 * (B[0][0] - B[1][1]);
    return m - sqrt(d * d + bxy * bxy);
  }
  double s[6], lam[3];
  s[XX] = B[0][0];
  s[YY] = B[1 % DIM][1 % DIM];
  s[ZZ] = B[2 % DIM][2 % DIM];
  s[XY] = 0.5 * (B[0][1 % DIM] + B[1 % DIM][0]);
  s[XZ] = 0.5 * (B[0][2 % DIM] + B[2 % DIM][0]);
  s[YZ] = 0.5 * (B[1 % DIM][2 % DIM] + B[2 % DIM][1 % DIM]);
  sym_eigenvalues(s, lam);
  return fmin(lam[0], fmin(lam[1], lam[2]));
}

template <int DIM>
SPHCUT_INLINE double surface_lambda(const FmfsAccum<DIM> &acc)
{
  return surface_lambda<DIM>(acc.B);
}

// outward surface normal n = -normalize(A^T gs), A = B^-1, gs = sum_j g V_j.
// Returns false (n = 0) when B is singular or A^T gs vanishes (full support).
template <int DIM>
SPHCUT_INLINE bool surface_normal(const double (&B)[DIM][DIM], const double *gs, double *n,
                                  double tol = SPHCUT_FMFS_TOL)
{
  double A[DIM][DIM];
  const bool ok = dense_inverse<DIM>(B, A, tol);
  double v[DIM], n2 = 0.0;
  for (int f = 0; f < DIM; f++) {
    double s = 0.0;
    for (int c = 0; c < DIM; c++) s += A[c][f] * gs[c];
    v[f] = s;
    n2 += s * s;
  }
  if (!ok || !(n2 > 0.0)) {
    for (int f = 0; f < DIM; f++) n[f] = 0.0;
    return false;
  }
  const double inv = -1.0 / sqrt(n2);
  for (int f = 0; f < DIM; f++) n[f] = v[f] * inv;
  return true;
}

template <int DIM>
SPHCUT_INLINE bool surface_normal(const FmfsAccum<DIM> &acc, double *n, double tol = SPHCUT_FMFS_TOL)
{
  return surface_normal<DIM>(acc.B, acc.gs, n, tol);
}

// ---------------------------------------------------------------------------
// the fused neighbour pass of fix heat/fmfs and compute surface/lambda (radial kernels)
//
// With a radial kernel g = grad_i W_ij = wfac (x_i - x_j) = -wfac r, so every moment of
// FmfsAccum is a sum of monomials of r with the one pair scalar s = -wfac V_j (>= 0):
//   B_ab   = sum s r_a r_b            gs_a    = sum s r_a
//   Q3_abc = sum s r_a r_b r_c        T3_abc  = sum s r_a r_b r_c / r^2
//   P4_abcd = sum s r_a r_b r_c r_d / r^2
// all fully symmetric: 6 + 3 + 10 + 10 + 15 = 44 moments in 3D (FmfsAccum: 90), of which 9
// follow from the others (sum_c T3_acc = gs_a, sum_c P4_abcc = B_ab): 35 sums per pair, no
// sqrt and no division per pair beyond the kernel's.  One walk over the neighbours gives the
// surface indicator (B, gs) and the FMFS moments; support_to_fmfs expands them into
// FmfsAccum for fmfs_weights (equal to fmfs_add's sums up to round-off).

// constants of an (itype, jtype) pair for the thermal passes
struct ThermalPair {
  double cutsq;    // (2h)^2, the support
  double inv_h;    // 1/h
  double wnorm;    // sigma_d / h^d
  double brook;    // Brookshaw's conductance over wfac: -2 kbar, kbar = harmonic_mean(ki, kj)
  int same_kappa;  // 1: ki == kj (FMFS may span the pair; otherwise a material interface)
};

SPHCUT_INLINE ThermalPair thermal_pair(int kind, int dim, double h, double ki, double kj)
{
  ThermalPair tp;
  tp.cutsq = support_radius_sq(h);
  tp.inv_h = 1.0 / h;
  tp.wnorm = kernel_sigma(kind, dim) / (dim == 2 ? h * h : h * h * h);
  tp.brook = -2.0 * harmonic_mean(ki, kj);
  tp.same_kappa = ki == kj;
  return tp;
}

// the pair within the support: dx = x_i - x_j, r2 = |dx|^2; false beyond the support or for
// coincident particles (in_support's rule)
SPHCUT_INLINE bool thermal_in_support(const ThermalPair &tp, const double *xi, const double *xj, double *dx,
                                      double &r2)
{
  r2 = 0.0;
  for (int a = 0; a < 3; a++) {
    dx[a] = xi[a] - xj[a];
    r2 += dx[a] * dx[a];
  }
  return r2 < tp.cutsq && r2 != 0.0;
}

// the kernel of a pair within the support: grad_i W_ij = wfac dx, and ir2 = 1/r2 (one sqrt, one
// division)
SPHCUT_INLINE void thermal_kernel(const ThermalPair &tp, int kind, double r2, double &wfac, double &ir2)
{
  const double r = sqrt(r2), ir = 1.0 / r;
  double f, df;
  kernel_shape(kind, r * tp.inv_h, f, df);
  wfac = tp.wnorm * df * tp.inv_h * ir;
  ir2 = ir * ir;
}

// both: the pair's dx, r2, wfac, ir2; false beyond the support
SPHCUT_INLINE bool thermal_support(const ThermalPair &tp, int kind, const double *xi, const double *xj,
                                   double *dx, double &r2, double &wfac, double &ir2)
{
  if (!thermal_in_support(tp, xi, xj, dx, r2)) return false;
  thermal_kernel(tp, kind, r2, wfac, ir2);
  return true;
}

template <int DIM> struct SupportMoments {
  static constexpr int NS = DIM * (DIM + 1) / 2;                            // symmetric pairs
  static constexpr int NT = DIM * (DIM + 1) * (DIM + 2) / 6;                // triples
  static constexpr int NQ = DIM * (DIM + 1) * (DIM + 2) * (DIM + 3) / 24;   // quadruples
  double B[NS];     // sum s r_a r_b             [pair(a,b)]
  double gs[DIM];   // sum s r_a
  double Q3[NT];    // sum s r_a r_b r_c         [triple(a,b,c)]
  double T3[NT];    // sum s r_a r_b r_c / r^2
  double P4[NQ];    // sum s r_a r_b r_c r_d / r^2  [quad(a,b,c,d)]
};

// packed index of the symmetric quadruple (a <= b <= c <= d), colex as the others
SPHCUT_INLINE int sym_quad_index(int a, int b, int c, int d)
{
  int v[4] = {a, b, c, d};
  for (int i = 1; i < 4; i++)
    for (int k = i; k > 0 && v[k - 1] > v[k]; k--) {
      const int t = v[k]; v[k] = v[k - 1]; v[k - 1] = t;
    }
  return v[0] + v[1] * (v[1] + 1) / 2 + v[2] * (v[2] + 1) * (v[2] + 2) / 6 +
      v[3] * (v[3] + 1) * (v[3] + 2) * (v[3] + 3) / 24;
}

// sym_quad_index(a, b, c, d) of a sorted triple a <= b <= c: d inserted, three comparisons
SPHCUT_INLINE int sym_quad_index_sorted3(int a, int b, int c, int d)
{
  int v0 = a, v1 = b, v2 = c, v3 = d;
  if (d < c) {
    v3 = c;
    if (d < b) {
      v2 = b;
      if (d < a) {
        v1 = a;
        v0 = d;
      } else {
        v1 = d;
      }
    } else {
      v2 = d;
    }
  }
  return v0 + v1 * (v1 + 1) / 2 + v2 * (v2 + 1) * (v2 + 2) / 6 + v3 * (v3 + 1) * (v3 + 2) * (v3 + 3) / 24;
}

// zero the surface part (B, gs) and, with fmfs, the FMFS part (Q3, T3, P4)
template <int DIM> SPHCUT_INLINE void support_zero(SupportMoments<DIM> &m, bool fmfs)
{
  for (int p = 0; p < SupportMoments<DIM>::NS; p++) m.B[p] = 0.0;
  for (int a = 0; a < DIM; a++) m.gs[a] = 0.0;
  if (!fmfs) return;
  for (int t = 0; t < SupportMoments<DIM>::NT; t++) m.Q3[t] = m.T3[t] = 0.0;
  for (int q = 0; q < SupportMoments<DIM>::NQ; q++) m.P4[q] = 0.0;
}

// the surface part of neighbour j: r = x_j - x_i, s = -wfac V_j
template <int DIM> SPHCUT_INLINE void support_add_surface(SupportMoments<DIM> &m, const double *r, double s)
{
  int p = 0;
  for (int b = 0; b < DIM; b++) {
    const double sr = s * r[b];
    m.gs[b] += sr;
    for (int a = 0; a <= b; a++) m.B[p++] += sr * r[a];
  }
}

// the FMFS part of neighbour j (r, s as above, ir2 = 1/|r|^2).  The moments with two last
// indices equal to the last axis z (T3_azz: the last DIM triples; P4_abzz: the last NS
// quadruples) are left out: support_to_fmfs takes them from the trace identities
//   sum_c T3_acc = gs_a,   sum_c P4_abcc = B_ab     (r_x^2 + r_y^2 + r_z^2 = r^2)
// (3 + 6 of the 35 FMFS sums per pair in 3D, 2 + 3 of 14 in 2D)
template <int DIM>
SPHCUT_INLINE void support_add_fmfs(SupportMoments<DIM> &m, const double *r, double s, double ir2)
{
  using SM = SupportMoments<DIM>;
  double m2[SM::NS], m3[SM::NT];
  int p = 0;
  for (int b = 0; b < DIM; b++)
    for (int a = 0; a <= b; a++) m2[p++] = r[a] * r[b];
  int t = 0;
  for (int c = 0; c < DIM; c++)
    for (int b = 0; b <= c; b++)
      for (int a = 0; a <= b; a++) m3[t++] = r[a] * m2[b + c * (c + 1) / 2];
  const double u = s * ir2;
  for (int k = 0; k < SM::NT; k++) m.Q3[k] += s * m3[k];
  for (int k = 0; k < SM::NT - DIM; k++) m.T3[k] += u * m3[k];
  int q = 0;
  for (int d = 0; d < DIM; d++)
    for (int c = 0; c <= d; c++) {
      if (c == DIM - 1) break;    // d = c = z: the last NS quadruples
      for (int b = 0; b <= c; b++) {
        const double ub = u * r[d] * r[c] * r[b];
        for (int a = 0; a <= b; a++) m.P4[q++] += ub * r[a];
      }
    }
}

// the FMFS moments as FmfsAccum (gT = S1 = 0: the weights need no temperatures)
template <int DIM> SPHCUT_INLINE void support_to_fmfs(const SupportMoments<DIM> &m, FmfsAccum<DIM> &acc)
{
  using SM = SupportMoments<DIM>;
  // the moments support_add_fmfs leaves out, from the trace identities: T3_azz = gs_a -
  // sum_(c<z) T3_acc, P4_abzz = B_ab - sum_(c<z) P4_abcc (in the order of the packed index, so
  // that P4_zzzz finds the P4_cczz it needs)
  double T3[SM::NT], P4[SM::NQ];
  for (int k = 0; k < SM::NT - DIM; k++) T3[k] = m.T3[k];
  for (int k = 0; k < SM::NQ - SM::NS; k++) P4[k] = m.P4[k];
  for (int a = 0; a < DIM; a++) {
    double v = m.gs[a];
    for (int c = 0; c < DIM - 1; c++) v -= T3[sym_triple_index(a, c, c)];
    T3[SM::NT - DIM + a] = v;
  }
  for (int b = 0; b < DIM; b++)
    for (int a = 0; a <= b; a++) {
      const int p = sym_pair_index(a, b);
      double v = m.B[p];
      for (int c = 0; c < DIM - 1; c++) v -= P4[sym_quad_index(a, b, c, c)];
      P4[SM::NQ - SM::NS + p] = v;
    }
  for (int a = 0; a < DIM; a++) {
    acc.gT[a] = 0.0;
    acc.gs[a] = m.gs[a];
    for (int b = 0; b < DIM; b++) {
      acc.B[a][b] = m.B[sym_pair_index(a, b)];
      acc.S1[a][b] = 0.0;
    }
  }
  for (int b = 0; b < DIM; b++)
    for (int a = 0; a <= b; a++) {
      const int p = sym_pair_index(a, b);
      for (int c = 0; c < DIM; c++) {
        const int t = sym_triple_index(a, b, c);
        acc.T3[p][c] = T3[t];
        acc.Q3[p][c] = m.Q3[t];
      }
    }
  int t = 0;    // = sym_triple_index(a, b, c): colex order
  for (int c = 0; c < DIM; c++)
    for (int b = 0; b <= c; b++)
      for (int a = 0; a <= b; a++, t++)
        for (int d = 0; d < DIM; d++) acc.P4[t][d] = P4[sym_quad_index_sorted3(a, b, c, d)];
}

// B of the moments as a full matrix (for surface_lambda, surface_normal, dense_inverse)
template <int DIM> SPHCUT_INLINE void support_matrix(const SupportMoments<DIM> &m, double (&B)[DIM][DIM])
{
  for (int a = 0; a < DIM; a++)
    for (int b = 0; b < DIM; b++) B[a][b] = m.B[sym_pair_index(a, b)];
}

// the surface indicator of the moments: lambda, and with lambda < threshold the normal
// (n = 0 otherwise); returns lambda
template <int DIM>
SPHCUT_INLINE double support_surface(const SupportMoments<DIM> &m, double threshold, double *n)
{
  double B[DIM][DIM];
  support_matrix<DIM>(m, B);
  const double lam = surface_lambda<DIM>(B);
  for (int a = 0; a < DIM; a++) n[a] = 0.0;
  if (lam < threshold) surface_normal<DIM>(B, m.gs, n);
  return lam;
}

// one side's FMFS weight over wfac for the radial kernel: w_self,other = wfac *
// fmfs_pair_weight_radial(wts_self, d, ir2), d = x_self - x_other, ir2 = 1/|d|^2;
// = fmfs_pair_weight (r = -d, g = wfac d) without its sqrt and division:
//   2/|r| e.Gf.g + z.g = wfac (z.d - 2 d.Gf.d / |d|^2)
template <int DIM> SPHCUT_INLINE double fmfs_pair_weight_radial(const double *wts, const double *d, double ir2)
{
  double q = 0.0, zd = 0.0;
  for (int c = 0; c < DIM; c++) {
    double gc = 0.0;
    for (int e = 0; e < DIM; e++) gc += wts[DIM * c + e] * d[e];
    q += d[c] * gc;
    zd += wts[DIM * DIM + c] * d[c];
  }
  return zd - 2.0 * q * ir2;
}

// ---------------------------------------------------------------------------
// fix heat/fmfs one particle at a time (host and device).  The drivers (FixHeatFMFS,
// FixHeatFMFSKokkos, bench/thermal) loop over the particles, gather what a particle's
// neighbours carry into a small view Nb of their own and store what these functions return;
// the neighbour loops and the arithmetic are here, once.  What a pair gives the other particle
// goes through an add-sink (as sphcut_pair.h): add(j, value); a driver that visits every pair
// from both sides passes NoAdd.

// the scheme a particle's evaluation took (the counters of fix heat/fmfs: a fallback counts as
// Brookshaw too)
enum HeatScheme { HEAT_NONE = -1, HEAT_BROOKSHAW = 0, HEAT_FMFS = 1, HEAT_FALLBACK = 2 };

// the counters of fix heat/fmfs for the scheme s a particle took
template <class T> SPHCUT_INLINE void heat_count(int s, T &n_fmfs, T &n_brookshaw, T &n_fallback)
{
  if (s == HEAT_FMFS) n_fmfs += 1;
  else if (s != HEAT_NONE) {
    n_brookshaw += 1;
    if (s == HEAT_FALLBACK) n_fallback += 1;
  }
}

// the sink of a driver that computes each pair from both sides
struct NoAdd {
  SPHCUT_INLINE void operator()(int, double) const {}
};

// the surface losses of fix heat/fmfs (keywords convection, radiation) and the loss of a group
// to a body in contact (keyword backing)
struct HeatLosses {
  double hconv, tconv;        // convection coefficient and ambient temperature
  double emiss_sigma, trad;   // emissivity times Stefan-Boltzmann, ambient temperature
  int on;                     // hconv > 0 or emissivity > 0
  int bbit;                   // group bit of the backing's particles (0: none)
  double hback, tback;        // heat transfer coefficient to the backing and its temperature
};

/* a heat source of the given power (energy/time, e.g. friction heat) into a particle's
   temperature rate dT/dt (mass m, heat capacity cp): false, and nothing added, for a material
   without heat capacity.  fix heat/fmfs add_heat and the contact's device kernel.            */
SPHCUT_INLINE bool add_source_heat(double &dtemp, double power, double m, double cp)
{
  if (cp <= 0.0) return false;
  dtemp += power / (m * cp);
  return true;
}

// the held temperature rate of a particle: rho cp dT/dt = rate over rho cp, less, on a free
// surface (surf) with losses, the heat it loses by convection and radiation (surface_losses of
// its volume m/rho), which are added to p_conv and p_rad; a particle of the backing's group (its
// mask holds hl.bbit) also loses hback (T - tback) A to the backing, added to p_conv
SPHCUT_INLINE double heat_rate(int dim, const HeatLosses &hl, int surf, int mask, double rate, double rho, double mass,
                               double cp, double T, double &p_conv, double &p_rad)
{
  double dT = rate / (rho * cp);
  if (surf && hl.on) {
    double qc, qr;
    surface_losses(dim, mass / rho, T, hl.hconv, hl.tconv, hl.emiss_sigma, hl.trad, qc, qr);
    p_conv += qc;
    p_rad += qr;
    dT -= (qc + qr) / (mass * cp);
  }
  if (mask & hl.bbit) {
    double qb, unused;
    surface_losses(dim, mass / rho, T, hl.hback, hl.tback, 0.0, 0.0, qb, unused);
    p_conv += qb;
    dT -= qb / (mass * cp);
  }
  return dT;
}

/* per particle (conservative no, the form of seed 003): rate = rho cp dT/dt of particle i
   (position xi, predicted temperature Ti, conductivity ki) by the FMFS Laplacian k_i lap T_i
   where try_fmfs (scheme fmfs, not on the surface, k_i > 0), one conductivity spans the
   support, lambda of the particle's own B >= fmfs_lambda and the system is regular; Brookshaw
   with the harmonic mean of the conductivities (seed 000 eq. 6) otherwise.  The view nb of the
   particle's listed neighbours:
     int size()                the count of listed neighbours
     int index(int k)          the k-th neighbour's index j, -1 where it is not of the group
     void pos(int j, double *) its position
     double h(int j)           the smoothing length of the pair i-j
     double temp(int j), volume(int j), kappa(int j): predicted T, m/rho and conductivity
   Returns HEAT_FMFS, HEAT_BROOKSHAW or HEAT_FALLBACK (FMFS singular: Brookshaw).            */
template <int DIM, class Nb>
SPHCUT_LOOP_INLINE int conduction_particle(const Nb &nb, int kernel, const double *xi, double Ti, double ki,
                                           int try_fmfs, double fmfs_lambda, double &rate)
{
  int use_fmfs = try_fmfs;
  double brook = 0.0;
  FmfsAccum<DIM> acc;
  if (use_fmfs) fmfs_zero<DIM>(acc);
  const int n = nb.size();
  for (int k = 0; k < n; k++) {
    const int j = nb.index(k);
    if (j < 0) continue;
    const double h = nb.h(j);
    double xj[3], dx[3], r2;
    nb.pos(j, xj);
    if (!in_support(xi, xj, h, dx, r2)) continue;
    double w, wfac;
    kernel_w_gradfac(kernel, DIM, sqrt(r2), h, w, wfac);
    const double Tj = nb.temp(j), vj = nb.volume(j), kj = nb.kappa(j);
    brook += vj * brookshaw_pair_radial(Ti, Tj, ki, kj, wfac);
    if (use_fmfs) {
      if (kj != ki) {
        use_fmfs = 0;    // material interface: heat flux form with the harmonic mean
        continue;
      }
      const double r[3] = {-dx[0], -dx[1], -dx[2]};
      const double g[3] = {wfac * dx[0], wfac * dx[1], wfac * dx[2]};
      fmfs_add<DIM>(acc, r, g, vj, Tj - Ti);
    }
  }
  double lap;
  if (use_fmfs && surface_lambda<DIM>(acc.B) < fmfs_lambda) use_fmfs = 0;
  if (use_fmfs && fmfs_laplacian<DIM>(acc, lap)) {
    rate = ki * lap;
    return HEAT_FMFS;
  }
  rate = brook;
  return use_fmfs ? HEAT_FALLBACK : HEAT_BROOKSHAW;
}

/* the conservative form (default): two passes over the pairs within the support.  Its view nb
   of one particle's neighbours:
     int size()                    the count of neighbours to visit
     bool pair(int k, HeatPair &)  the k-th: false where it is not of the group or outside the
                                   support; else j, its ThermalPair with i, dx = x_i - x_j,
                                   wfac (grad_i W_ij = wfac dx) and ir2 = 1/|dx|^2
     double volume(int j)          m/rho (predicted density)
   and, for the exchange,
     double temp(int j)            predicted temperature
     bool weights<DIM>(int j, double *w)  its scheme flag (true: FMFS) and, where set, its
                                   DIM*DIM + DIM FMFS weights (fmfs_weights) into w
     double kappa(int j)           its conductivity
   A view whose pairs are cheap to visit twice (gathered beforehand: the CPU fix) sets
   static constexpr bool TWO_WALKS = true: the FMFS moments are then summed in a second walk,
   only for a particle that turns out to take FMFS; otherwise (on the fly: /kk) in the one walk. */
struct HeatPair {
  int j;
  const ThermalPair *tp;
  double dx[3];
  double wfac, ir2;
};

// the surface indicator of a particle (compute surface/lambda's columns LAMBDA, FLAG, NX..NZ)
struct HeatSurface {
  double lambda, flag;
  double n[3];
};

/* first pass, one particle: the surface indicator and the scheme.  One walk over the neighbours
   sums the surface moments (with fuse into surf for compute surface/lambda: lambda, flag
   lambda < thr and the normal; a flagged particle takes Brookshaw) and the FMFS moments of a
   candidate (cand: conducts, scheme fmfs, k > 0, not flagged by the compute when not fused; a
   material interface in the support makes it Brookshaw).  With lambda >= fmfs_lambda the FMFS
   pair weights (DIM*DIM + DIM, fmfs_weights) go to wts.  surf is zero without fuse.  Returns HEAT_NONE for a particle that
   does not conduct (conducts = 0: the surface indicator only), else the scheme.             */
template <int DIM, class Nb>
SPHCUT_LOOP_INLINE int heat_scheme(const Nb &nb, int conducts, int cand, int fuse, double thr, double fmfs_lambda,
                                   HeatSurface &surf, double *wts)
{
  surf.lambda = surf.flag = surf.n[0] = surf.n[1] = surf.n[2] = 0.0;
  if (!fuse && !cand) return conducts ? HEAT_BROOKSHAW : HEAT_NONE;    // nothing to walk for
  SupportMoments<DIM> m;
  support_zero<DIM>(m, cand);
  const int n = nb.size();
  for (int k = 0; k < n; k++) {
    HeatPair p;
    if (!nb.pair(k, p)) continue;
    const double r[3] = {-p.dx[0], -p.dx[1], -p.dx[2]};    // x_j - x_i
    const double s = -p.wfac * nb.volume(p.j);
    support_add_surface<DIM>(m, r, s);
    if (cand) {
      if (!p.tp->same_kappa) cand = 0;    // material interface: Brookshaw
      else if (!Nb::TWO_WALKS) support_add_fmfs<DIM>(m, r, s, p.ir2);
    }
  }
  double lam = 0.0;
  if (fuse) {
    lam = support_surface<DIM>(m, thr, surf.n);
    surf.lambda = lam;
    surf.flag = lam < thr ? 1.0 : 0.0;
    if (lam < thr) cand = 0;
  } else if (cand) {
    double B[DIM][DIM];
    support_matrix<DIM>(m, B);
    lam = surface_lambda<DIM>(B);
  }
  if (!conducts) return HEAT_NONE;
  // FMFS only with a full enough kernel support (lambda >= fmfs_lambda)
  if (!cand || !(lam >= fmfs_lambda)) return HEAT_BROOKSHAW;
  if (Nb::TWO_WALKS)
    for (int k = 0; k < n; k++) {
      HeatPair p;
      if (!nb.pair(k, p)) continue;
      const double r[3] = {-p.dx[0], -p.dx[1], -p.dx[2]};
      support_add_fmfs<DIM>(m, r, -p.wfac * nb.volume(p.j), p.ir2);
    }
  FmfsAccum<DIM> acc;
  support_to_fmfs<DIM>(m, acc);
  return fmfs_weights<DIM>(acc, wts) ? HEAT_FMFS : HEAT_FALLBACK;
}

// one side's conductance over wfac of a pair: k w_self,other / wfac from the FMFS weights w of
// that side where it has them (fmfs), else Brookshaw's (tp.brook); d = x_self - x_other
template <int DIM>
SPHCUT_INLINE double side_conductance(const ThermalPair &tp, bool fmfs, const double *w, double k, const double *d,
                                      double ir2)
{
  return fmfs ? k * fmfs_pair_weight_radial<DIM>(w, d, ir2) : tp.brook;
}

// the two sides' conductances over wfac of the pair i-j (dx = x_i - x_j, ir2 = 1/|dx|^2):
// s_ij = k_i w_ij / wfac from the FMFS weights wi of particle i where it has them (fi), else
// Brookshaw's (tp.brook); s_ji likewise from j's side.  Flags, not pointers that may be null: a
// GPU keeps the weights' arrays in registers then, not in local memory
template <int DIM>
SPHCUT_INLINE void exchange_sides(const ThermalPair &tp, const double *dx, double ir2, bool fi, const double *wi,
                                  double ki, bool fj, const double *wj, double kj, double &s_ij, double &s_ji)
{
  const double mdx[3] = {-dx[0], -dx[1], -dx[2]};
  s_ij = side_conductance<DIM>(tp, fi, wi, ki, dx, ir2);
  s_ji = side_conductance<DIM>(tp, fj, wj, kj, mdx, ir2);
}

// the FMFS weights of a particle (DIM*DIM + DIM of them, an even count) into registers, in
// 16-byte pairs (load2: w must be 16-byte aligned where a GPU reads it)
template <int DIM> SPHCUT_INLINE void load_weights(const double *w, double *out)
{
  for (int k = 0; k < DIM * DIM + DIM; k += 2) load2(w + k, out[k], out[k + 1]);
}

// the weights<DIM> of a view whose particle rows hold the scheme flag and then the weights
// (16-byte aligned, as load_weights reads them): the flag, and the weights where it is set
template <int DIM> SPHCUT_INLINE bool row_weights(const double *row, double *w)
{
  if (!(row[0] > 0.0)) return false;
  load_weights<DIM>(row + 1, w);
  return true;
}

/* second pass, one particle i (conductivity ki, predicted temperature Ti, volume Vi, scheme
   flag and FMFS weights wi as a row of row_weights): the pairwise exchange with the
   conductance c_ij = wfac conductance_pair (the mean of the two sides, Brookshaw's where that
   is anti-diffusive).  Returns i's rho cp dT/dt from these pairs, sum_j V_j c_ij (T_j - T_i);
   what each pair gives j, -V_i c_ij (T_j - T_i), goes to add(j, value).                      */
template <int DIM, class Nb, class Add>
SPHCUT_LOOP_INLINE double heat_exchange(const Nb &nb, double ki, double Ti, double Vi, const double *wi, Add &&add)
{
  // i's weights once, in registers; j's as the view gives them (arrays, not pointers: a GPU
  // keeps them in registers)
  double fi[DIM * DIM + DIM], fj[DIM * DIM + DIM];
  const bool wfi = row_weights<DIM>(wi, fi);
  double ri = 0.0;
  const int n = nb.size();
  for (int k = 0; k < n; k++) {
    HeatPair p;
    if (!nb.pair(k, p)) continue;
    const bool wfj = nb.template weights<DIM>(p.j, fj);
    double s_ij, s_ji;
    exchange_sides<DIM>(*p.tp, p.dx, p.ir2, wfi, fi, ki, wfj, fj, wfj ? nb.kappa(p.j) : 0.0, s_ij, s_ji);
    const double c = p.wfac * conductance_pair(s_ij, s_ji, p.tp->brook), dT = nb.temp(p.j) - Ti;
    ri += nb.volume(p.j) * c * dT;
    add(p.j, -(Vi * c * dT));
  }
  return ri;
}

}    // namespace sphcut

#endif
