/* -*- c++ -*- ----------------------------------------------------------
   sphcut - material and per-pair physics of the solid SPH scheme
   (host and device).  Equation numbers ("seed 003", "seed 000" in the
   comments of sphcut): seed 003 = Afrasiabi, Klippel, Roethlin, Wegener,
   "Smoothed particle hydrodynamics simulation of orthogonal cutting with
   enhanced thermal modeling", Appl. Sci. 11 (2021) 1020,
   doi:10.3390/app11031020; seed 000 = Fraser, St-Georges, Kiss, Chiricota,
   "Hybrid thermo-mechanical contact algorithm for 3D SPH-FEM multi-physics
   simulations", PARTICLES 2015, Barcelona (references of doc/theory.md).
------------------------------------------------------------------------- */

#ifndef SPHCUT_MATERIAL_H
#define SPHCUT_MATERIAL_H

#include "sphcut_math.h"

namespace sphcut {

enum EosKind { EOS_LINEAR = 0, EOS_MIE_GRUNEISEN = 1 };
// flow-stress law (pair_coeff keyword flow): a new law is a value here, a branch of
// flow_hardening below and its keywords in sphcut::Model (the material table)
enum FlowKind { FLOW_JC = 0, FLOW_TANH = 1 };
// what a particle below the pressure cutoff carries (pair_coeff keyword spall, with pmin):
// cutoff: the pressure pmin and its deviatoric stress (LS-DYNA's spall type 1); release: no
// stress at all while its EOS pressure is below pmin, the material separated there (pressure
// and deviatoric stress zero, no plastic flow, and it expands no further: spall_density)
enum SpallKind { SPALL_CUTOFF = 0, SPALL_RELEASE = 1 };

// Plain-old-data material record, one per atom type (copyable to the device).
struct Material {
  int defined;        // set by pair_coeff
  // elasticity and EOS
  double rho0, E, nu;
  double G, K, c0;    // derived: shear, bulk modulus, bulk sound speed sqrt(K/rho0)
  double cl;          // derived: longitudinal wave speed sqrt((K + 4G/3)/rho0)
  int eos;
  double gamma0, s_hug;   // Mie-Grueneisen: Grueneisen gamma and Hugoniot slope s
  // Johnson-Cook, eq. (9) of seed 003
  int plastic;        // 0: elastic only
  double A, B, C, n, m, epsdot0, Tref, Tmelt;
  // thermal
  double cp, chi, kappa;  // heat capacity, Taylor-Quinney fraction, conductivity
  // stabilisation
  double av_alpha, av_beta;   // Monaghan artificial viscosity
  double as_eps, as_n;        // Gray-Monaghan artificial stress
  double xsph;                // XSPH epsilon
  // tensile failure (pair_coeff keyword pmin): the pressure is cut off at pmin < 0 (spall, as the
  // pressure cutoff PC of LS-DYNA *MAT_JOHNSON_COOK, spall type 1); 0: no cutoff
  double pmin;
  int spall;          // SpallKind: what a particle below pmin carries
  // flow-stress law (keyword flow, FlowKind) and the parameters of the modified Johnson-Cook
  // law with strain softening (flow tanh, Calamaz et al. 2008): a, b, c, d
  int flow;
  double tanh_a, tanh_b, tanh_c, tanh_d;
  // Restart files store the record field by field, by name (sphcut::Model, the material table):
  // the fields may be reordered or extended freely.  Only the fields up to pmin must keep their
  // layout, that of the raw record of older files (sphcut::LegacyMaterial, sphcut_model.cpp).
};

SPHCUT_INLINE void material_derive(Material &mat)
{
  mat.G = mat.E / (2.0 * (1.0 + mat.nu));
  mat.K = mat.E / (3.0 * (1.0 - 2.0 * mat.nu));
  mat.c0 = sqrt(mat.K / mat.rho0);
  mat.cl = sqrt((mat.K + 4.0 * mat.G / 3.0) / mat.rho0);
}

/* ---- equation of state: pressure (positive in compression) ----------
   linear: p = c0^2 (rho - rho0)
   Mie-Grueneisen (Hugoniot reference, mu = rho/rho0 - 1, e = cp (T - Tref)):
     mu > 0: p = rho0 c0^2 mu (1 + (1 - gamma0/2) mu) / (1 - (s-1) mu)^2 + gamma0 rho0 e
     mu < 0: p = rho0 c0^2 mu + gamma0 rho0 e
   eos_pressure_uncut is the EOS alone; eos_pressure, what every caller uses (the pair's
   force state, the fix's PRESS column), adds the tension cutoff.                     */
SPHCUT_INLINE double eos_pressure_uncut(const Material &mat, double rho, double T)
{
  if (mat.eos == EOS_MIE_GRUNEISEN) {
    const double mu = rho / mat.rho0 - 1.0;
    const double e = mat.cp * (T - mat.Tref);
    const double rc2 = mat.rho0 * mat.c0 * mat.c0;
    if (mu > 0.0) {
      const double den = 1.0 - (mat.s_hug - 1.0) * mu;
      return rc2 * mu * (1.0 + (1.0 - 0.5 * mat.gamma0) * mu) / (den * den) +
          mat.gamma0 * mat.rho0 * e;
    }
    return rc2 * mu + mat.gamma0 * mat.rho0 * e;
  }
  return mat.c0 * mat.c0 * (rho - mat.rho0);
}

/* pressure cutoff (spall limit, keyword pmin < 0; LS-DYNA *MAT_JOHNSON_COOK PC, spall type 1):
   p = max(p_EOS, pmin).  Below the cutoff the pressure stays at pmin however far the particle
   expands (no bulk stiffness in tension there: dp/drho = 0), and it follows the EOS again once
   the EOS comes back above pmin; the deviatoric stress is not touched.  With spall release the
   pressure below the cutoff is 0 instead, and particle_stress drops the deviatoric stress too
   (spall_released).  Without a cutoff (pmin = 0) p_EOS unchanged.  The sound speeds (c0, c_l:
   time step, artificial viscosity) stay those of the EOS.  A NaN stays NaN (the comparison is
   false).                                                                                  */
SPHCUT_INLINE bool spall_released(const Material &mat, double p_eos)
{
  return mat.spall == SPALL_RELEASE && mat.pmin < 0.0 && p_eos < mat.pmin;
}

SPHCUT_INLINE double pressure_cutoff(const Material &mat, double p)
{
  if (mat.pmin < 0.0 && p < mat.pmin) return mat.spall == SPALL_RELEASE ? 0.0 : mat.pmin;
  return p;
}

/* spall release: the density of a particle after an update from rho_old to rho_new at the
   temperature T.  A particle already released by the spall (the EOS pressure of rho_old below
   pmin) that would expand further keeps rho_old: the material separated there, and what opens is
   the gap between the particles, not the material (its density would otherwise fall without
   bound, to a fifth of the reference density at the free surface of a shear band, and give that
   particle five times its volume in its neighbours' sums).  The step that takes a particle below
   pmin is kept (it releases the particle), and so is compression (rho_new >= rho_old): a
   released particle that is pushed back carries its stress again once its EOS pressure has come
   back above pmin.  Without spall release rho_new.                                             */
SPHCUT_INLINE double spall_density(const Material &mat, double rho_old, double rho_new, double T)
{
  // (the kind first: without spall release no EOS evaluation on this path)
  if (mat.spall == SPALL_RELEASE && rho_new < rho_old && spall_released(mat, eos_pressure_uncut(mat, rho_old, T)))
    return rho_old;
  return rho_new;
}

SPHCUT_INLINE double eos_pressure(const Material &mat, double rho, double T)
{
  return pressure_cutoff(mat, eos_pressure_uncut(mat, rho, T));
}

/* ---- Johnson-Cook flow stress, seed 003 eq. (9) ---------------------
   sigma_y = (A + B eps^n) (1 + C ln(max(epsdot/epsdot0, 1))) (1 - T*^m),
   T* = (T - Tref)/(Tmelt - Tref) clamped to [0,1].                    */

// x^p for x > 0; p = 1 (a common m, and n of linear hardening) without the pow call
// (pow(x, 1) is x exactly, so the result is the same to the bit)
SPHCUT_INLINE double pow_exp(double x, double p)
{
  return p == 1.0 ? x : pow(x, p);
}

SPHCUT_INLINE double jc_thermal_factor(const Material &mat, double T)
{
  double ts = (T - mat.Tref) / (mat.Tmelt - mat.Tref);
  if (ts <= 0.0) return 1.0;
  if (ts >= 1.0) return 0.0;
  return 1.0 - pow_exp(ts, mat.m);
}

SPHCUT_INLINE double jc_rate_factor(const Material &mat, double epsdot)
{
  const double r = epsdot / mat.epsdot0;
  return r > 1.0 ? 1.0 + mat.C * log(r) : 1.0;
}

SPHCUT_INLINE double jc_hardening(const Material &mat, double eps)
{
  return mat.A + (eps > 0.0 ? mat.B * pow_exp(eps, mat.n) : 0.0);
}

SPHCUT_INLINE double jc_flow_stress(const Material &mat, double eps, double epsdot, double T)
{
  return jc_hardening(mat, eps) * jc_rate_factor(mat, epsdot) * jc_thermal_factor(mat, T);
}

/* ---- modified Johnson-Cook with strain softening ("TANH", Calamaz, Coupard & Girot 2008,
   Int. J. Mach. Tools Manuf. 48, 275; used for Ti6Al4V chip segmentation):
     sigma_y = [A + B eps^n exp(-eps^a)] [1 + C ln(epsdot*)] [1 - T*^m]
               [D + (1 - D) tanh(1 / (eps + S)^c)],   D = 1 - (T/Tmelt)^d,  S = (T/Tmelt)^b
   (T and Tmelt absolute).  The rate and thermal factors are those of Johnson-Cook; the strain
   factor h(eps, T) = [A + B eps^n exp(-eps^a)] [D + (1 - D) tanh((eps + S)^-c)] replaces
   A + B eps^n.  For D = 1 (T << Tmelt with d large) and eps^a -> 0 it is Johnson-Cook.  */
SPHCUT_INLINE double tanh_softening_factor(const Material &mat, double eps, double T, double *slope)
{
  const double tt = T > 0.0 ? T / mat.Tmelt : 0.0;
  const double D = 1.0 - pow(tt, mat.tanh_d);
  const double S = pow(tt, mat.tanh_b);
  const double es = eps + S;
  if (!(es > 0.0)) {    // eps = 0 at T = 0: tanh(inf) = 1
    *slope = 0.0;
    return 1.0;
  }
  const double u = pow(es, -mat.tanh_c);
  const double th = tanh(u);
  const double sech2 = 1.0 - th * th;
  // d/deps; sech^2 = 0 where tanh is 1 in double precision (u may then be inf: no 0 * inf)
  *slope = sech2 > 0.0 ? -(1.0 - D) * sech2 * mat.tanh_c * u / es : 0.0;
  return D + (1.0 - D) * th;
}

/* ---- the strain factor of the selected law and its slope d/deps (for the Newton iteration
   of the radial return): sigma_y = flow_hardening(eps, T) * jc_rate_factor * jc_thermal_factor.
   Johnson-Cook: A + B eps^n, slope B n eps^(n-1) (huge at eps -> 0 for n < 1: capped at 1e30).
   A new law: a FlowKind value, a branch here (value and slope) and its keywords.  */
SPHCUT_INLINE double flow_hardening(const Material &mat, double eps, double T, double *slope)
{
  const double en = eps > 0.0 ? pow_exp(eps, mat.n) : 0.0;    // one pow for the value and its slope
  if (mat.flow == FLOW_TANH) {
    const double ea = eps > 0.0 ? pow(eps, mat.tanh_a) : 0.0;
    const double soft = exp(-ea);
    const double hard = mat.A + mat.B * en * soft;
    // d/deps [B eps^n exp(-eps^a)] = B eps^n exp(-eps^a) (n - a eps^a) / eps
    double dhard = eps > 0.0 ? mat.B * en * soft * (mat.n - mat.tanh_a * ea) / eps : 0.0;
    if (!(fabs(dhard) < 1.0e30)) dhard = dhard < 0.0 ? -1.0e30 : 1.0e30;
    double dg;
    const double g = tanh_softening_factor(mat, eps, T, &dg);
    *slope = dhard * g + hard * dg;
    return hard * g;
  }
  const double hard = mat.A + mat.B * en;    // jc_hardening(mat, eps)
  double dh = eps > 0.0 ? mat.B * mat.n * en / eps : 0.0;    // B n e^(n-1)
  if (!(dh < 1.0e30)) dh = 1.0e30;
  *slope = dh;
  return hard;
}

// the flow stress of the material's law (Johnson-Cook: jc_flow_stress)
SPHCUT_INLINE double flow_stress(const Material &mat, double eps, double epsdot, double T)
{
  double slope;
  return flow_hardening(mat, eps, T, &slope) * jc_rate_factor(mat, epsdot) * jc_thermal_factor(mat, T);
}

/* ---- radial return ----------------------------------------------------
   s: trial deviatoric stress (Voigt, modified in place).  Solves
     f(d) = q_trial - 3 G d - sigma_y(eps + d, d/dt, T) = 0
   for the plastic strain increment d >= 0 by a safeguarded Newton
   iteration, then scales s onto the yield surface.  Returns d; *sigy
   receives the flow stress at the returned state.  d_guess > 0 (e.g. the
   increment of the last step, rescaled to this dt) starts the iteration
   there instead of at the perfectly plastic, rate-independent guess.
   sigma_y is that of the material's law (flow_hardening: the strain factor and
   its slope, exact for every law).  Johnson-Cook: f is decreasing and, in x = ln d,
   concave (-3G e^x, the hardening and the rate factor all bend it down), so a Newton
   step in x from the right of the root (f < 0) stays right of it: where the Newton
   step in d leaves the bracket (the usual case just after first yield, where the
   hardening slope n B eps^(n-1) is steep), the step in x, d exp(-f/(d f')),
   replaces the bisection, which took 10 and more halvings there.  A softening law
   (flow tanh) need not keep f concave: every step is kept inside the bracket [lo, hi]
   (f(lo) > 0 >= f(hi)) and bisects where neither Newton step lands in it, so the
   iteration converges for any law with a continuous sigma_y.  The
   iteration ends when |f| <= 1e-12 q, when the bracket is narrower than
   1e-14 of its upper end, or when the Newton step is below 1e-6 of d: by quadratic convergence the error left after that step is
   of the order of 1e-12 d (times the relative curvature of f, below 1 on
   the usual increments), within the tolerance on f.                      */
SPHCUT_INLINE double radial_return(const Material &mat, double *s, double eps, double T, double dt,
                                   double *sigy, double d_guess = 0.0)
{
  const double q = von_mises(s);
  const double ft = jc_thermal_factor(mat, T);
  // Johnson-Cook: below A ft, below yield whatever the hardening (B >= 0): no pow needed unless
  // sigy is asked for (a softening law may yield below A ft)
  if (!mat.plastic || (!sigy && mat.flow == FLOW_JC && mat.B >= 0.0 && q <= mat.A * ft)) {
    if (sigy) *sigy = jc_hardening(mat, eps) * ft;
    return 0.0;
  }
  double slope;
  double y0 = flow_hardening(mat, eps, T, &slope) * ft;    // rate factor >= 1: the yield stress at this eps
  if (q <= y0) {
    if (sigy) *sigy = y0;    // = flow_stress(mat, eps, 0, T), the same products
    return 0.0;
  }
  const double G3 = 3.0 * mat.G;
  double lo = 0.0, hi = q / G3;    // f(lo) > 0, f(hi) = -sigma_y <= 0
  double d = (q - y0) / G3;        // perfectly plastic, rate-independent guess: f(d) <= 0 (Johnson-Cook)
  if (d_guess > 0.0 && d_guess < hi) d = d_guess;
  for (int it = 0; it < 50; it++) {
    double dh;
    const double hard = flow_hardening(mat, eps + d, T, &dh);
    const double rate = jc_rate_factor(mat, d / dt);
    const double y = hard * rate * ft;
    const double f = q - G3 * d - y;
    if (f > 0.0) lo = d; else hi = d;
    if (fabs(f) <= 1.0e-12 * q) break;
    const double dr = (d / dt > mat.epsdot0 && d > 0.0) ? mat.C / d : 0.0;
    const double df = -G3 - ft * (dh * rate + hard * dr);
    double dn = d - f / df;
    if (!(dn > lo && dn < hi) && d > 0.0) dn = d * exp(-f / (d * df));    // Newton step in ln d
    if (!(dn > lo && dn < hi)) dn = 0.5 * (lo + hi);
    if (fabs(dn - d) <= 1.0e-6 * d || hi - lo <= 1.0e-14 * hi) { d = dn; break; }
    d = dn;
  }
  const double qn = q - G3 * d;
  const double scale = qn > 0.0 ? qn / q : 0.0;
  for (int k = 0; k < 6; k++) s[k] *= scale;
  if (sigy) *sigy = qn > 0.0 ? qn : 0.0;
  return d;
}

/* ---- Jaumann rate of the deviatoric stress -----------------------------
   L: velocity gradient (row major, L_ab = dv_a/dx_b); s: deviatoric stress.
   ds = 2G (D - tr(D)/3 I) + W s - s W,  D = sym(L), W = skew(L).
   In 2D (plane strain) L has only the x-y block; D_zz = 0 still feeds
   the deviator, so s_zz evolves as -2G tr(D)/3.  Returns tr(D).        */
SPHCUT_INLINE double jaumann_rate(const Material &mat, const double *L, const double *s, double *ds)
{
  double D[6];
  D[XX] = L[0];
  D[YY] = L[4];
  D[ZZ] = L[8];
  D[XY] = 0.5 * (L[1] + L[3]);
  D[XZ] = 0.5 * (L[2] + L[6]);
  D[YZ] = 0.5 * (L[5] + L[7]);
  const double trd = D[XX] + D[YY] + D[ZZ];
  deviator(D);
  // spin W_ab = (L_ab - L_ba)/2
  const double wxy = 0.5 * (L[1] - L[3]);
  const double wxz = 0.5 * (L[2] - L[6]);
  const double wyz = 0.5 * (L[5] - L[7]);
  // (W s - s W) = W s + (W s)^T for symmetric s and antisymmetric W
  // W = [[0, wxy, wxz], [-wxy, 0, wyz], [-wxz, -wyz, 0]]
  const double S[3][3] = {{s[XX], s[XY], s[XZ]}, {s[XY], s[YY], s[YZ]}, {s[XZ], s[YZ], s[ZZ]}};
  const double W[3][3] = {{0.0, wxy, wxz}, {-wxy, 0.0, wyz}, {-wxz, -wyz, 0.0}};
  double WS[3][3];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) WS[a][b] = W[a][0] * S[0][b] + W[a][1] * S[1][b] + W[a][2] * S[2][b];
  const double g2 = 2.0 * mat.G;
  ds[XX] = g2 * D[XX] + 2.0 * WS[0][0];
  ds[YY] = g2 * D[YY] + 2.0 * WS[1][1];
  ds[ZZ] = g2 * D[ZZ] + 2.0 * WS[2][2];
  ds[XY] = g2 * D[XY] + WS[0][1] + WS[1][0];
  ds[XZ] = g2 * D[XZ] + WS[0][2] + WS[2][0];
  ds[YZ] = g2 * D[YZ] + WS[1][2] + WS[2][1];
  return trd;
}

/* ---- artificial viscosity (Monaghan 1992), Pi_ij of seed 003 eq. (11) --
   vr = (v_i - v_j).(x_i - x_j); Pi >= 0 for approaching pairs.  It enters
   the momentum bracket with a minus sign (repulsive).                   */
SPHCUT_INLINE double artificial_viscosity(double alpha, double beta, double vr, double r2, double h,
                                          double cbar, double rhobar)
{
  if (vr >= 0.0) return 0.0;
  const double mu = h * vr / (r2 + 0.01 * h * h);
  return (-alpha * cbar * mu + beta * mu * mu) / rhobar;
}

// true when no principal value of a symmetric tensor (Voigt) is negative: s is positive
// semidefinite (its principal minors are >= 0)
SPHCUT_INLINE bool no_negative_eigenvalue(const double *s)
{
  const double a = s[XX], b = s[YY], c = s[ZZ], d = s[XY], e = s[XZ], f = s[YZ];
  if (a < 0.0 || b < 0.0 || c < 0.0) return false;
  if (a * b - d * d < 0.0 || a * c - e * e < 0.0 || b * c - f * f < 0.0) return false;
  return a * (b * c - f * f) - d * (d * c - f * e) + e * (d * f - b * e) >= 0.0;
}

/* ---- artificial stress (Gray, Monaghan & Swift 2001), Lambda of eq. (11) --
   per particle: R = sum over principal directions with tensile principal
   stress sigma_p > 0 of  -eps sigma_p / rho^2  (rotated back).
   pair term: f^n (R_i + R_j), f = W(r)/W(dp).                           */
SPHCUT_INLINE void artificial_stress(double eps, const double *sigma, double rho, int dim, double *R)
{
  if (dim == 3 && no_negative_eigenvalue(sigma)) {
    // every principal stress tensile (or zero): R = -eps sigma / rho^2 without the eigen-
    // decomposition (a third of the calls in a compressed block; equal up to round-off)
    for (int k = 0; k < 6; k++) R[k] = -eps * sigma[k] / (rho * rho);
    return;
  }
  double lam[3], q[9];
  if (dim == 2) sym_eigen_2d(sigma, lam, q);
  else sym_eigen(sigma, lam, q);
  double rp[3];
  for (int k = 0; k < 3; k++) rp[k] = lam[k] > 0.0 ? -eps * lam[k] / (rho * rho) : 0.0;
  // R = Q diag(rp) Q^T
  R[XX] = q[0] * q[0] * rp[0] + q[1] * q[1] * rp[1] + q[2] * q[2] * rp[2];
  R[YY] = q[3] * q[3] * rp[0] + q[4] * q[4] * rp[1] + q[5] * q[5] * rp[2];
  R[ZZ] = q[6] * q[6] * rp[0] + q[7] * q[7] * rp[1] + q[8] * q[8] * rp[2];
  R[XY] = q[0] * q[3] * rp[0] + q[1] * q[4] * rp[1] + q[2] * q[5] * rp[2];
  R[XZ] = q[0] * q[6] * rp[0] + q[1] * q[7] * rp[1] + q[2] * q[8] * rp[2];
  R[YZ] = q[3] * q[6] * rp[0] + q[4] * q[7] * rp[1] + q[5] * q[8] * rp[2];
  if (dim == 2) R[XZ] = R[YZ] = 0.0;
}

// total Cauchy stress sigma = s - p I (Voigt)
SPHCUT_INLINE void cauchy_stress(const double *s, double p, double *sigma)
{
  sigma[XX] = s[XX] - p;
  sigma[YY] = s[YY] - p;
  sigma[ZZ] = s[ZZ] - p;
  sigma[XY] = s[XY];
  sigma[XZ] = s[XZ];
  sigma[YZ] = s[YZ];
}

// y = M x for symmetric M (Voigt) and a 3-vector x
SPHCUT_INLINE void sym_apply(const double *M, const double *x, double *y)
{
  y[0] = M[XX] * x[0] + M[XY] * x[1] + M[XZ] * x[2];
  y[1] = M[XY] * x[0] + M[YY] * x[1] + M[YZ] * x[2];
  y[2] = M[XZ] * x[0] + M[YZ] * x[1] + M[ZZ] * x[2];
}

}    // namespace sphcut

#endif
