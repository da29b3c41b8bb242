// material physics of sphcut_material.h and the small linear algebra of sphcut_math.h:
// Johnson-Cook flow stress, radial return, Jaumann rate, EOS, artificial
// viscosity and stress, eigen decomposition and inverse
#include "sphcut_material.h"
#include "sphcut_pair.h"
#include "sphcut_solid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace sphcut;

namespace {

// Ti6Al4V (Johnson-Cook parameters of the cutting benchmarks)
Material ti64()
{
  Material mat = {};
  mat.defined = 1;
  mat.rho0 = 4430.0;
  mat.E = 113.8e9;
  mat.nu = 0.35;
  mat.plastic = 1;
  mat.A = 862.0e6;
  mat.B = 331.0e6;
  mat.C = 0.01;
  mat.n = 0.35;
  mat.m = 0.8;
  mat.epsdot0 = 1.0;
  mat.Tref = 300.0;
  mat.Tmelt = 1878.0;
  mat.cp = 580.0;
  material_derive(mat);
  return mat;
}

// Johnson-Cook written out independently of the header
double jc_reference(double eps, double epsdot, double T)
{
  const double hard = 862.0e6 + 331.0e6 * pow(eps, 0.35);
  const double rate = 1.0 + 0.01 * log(epsdot / 1.0);
  const double thermal = 1.0 - pow((T - 300.0) / (1878.0 - 300.0), 0.8);
  return hard * rate * thermal;
}

// full 3x3 (row major) from Voigt and back
void to_full(const double *v, double *t)
{
  t[0] = v[XX]; t[1] = v[XY]; t[2] = v[XZ];
  t[3] = v[XY]; t[4] = v[YY]; t[5] = v[YZ];
  t[6] = v[XZ]; t[7] = v[YZ]; t[8] = v[ZZ];
}

void mul3(const double *a, const double *b, double *c)
{
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      c[3 * i + j] = 0.0;
      for (int k = 0; k < 3; k++) c[3 * i + j] += a[3 * i + k] * b[3 * k + j];
    }
}

// random traceless symmetric tensor with von Mises equivalent q
void random_deviator(std::mt19937 &gen, double q, double *s)
{
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 6; k++) s[k] = u(gen);
  deviator(s);
  const double vm = von_mises(s);
  for (int k = 0; k < 6; k++) s[k] *= q / vm;
}

// one radial return of a random trial deviator `over` times the yield stress at eps (the
// material's law at the lowest rate): the trial and returned stress, q_trial, deps, sigy, y0
struct TrialReturn {
  double s[6], s0[6], q0, deps, sigy, y0;
};

TrialReturn trial_return(const Material &mat, std::mt19937 &gen, double eps, double T, double dt, double over,
                         double guess = 0.0)
{
  TrialReturn r;
  r.y0 = flow_stress(mat, eps, 0.0, T);
  random_deviator(gen, over * r.y0, r.s);
  for (int k = 0; k < 6; k++) r.s0[k] = r.s[k];
  r.q0 = von_mises(r.s0);
  r.deps = radial_return(mat, r.s, eps, T, dt, &r.sigy, guess);
  return r;
}

}    // namespace

/* ---------------------------------------------------------------------- */

// shear and bulk modulus and wave speeds from E, nu
// q (columns: eigenvectors) orthonormal and q diag(lam) q^T = sf (full 3x3) to 1e-12
static void expect_eigen_decomposition(const double *q, const double *lam, const double *sf, int trial)
{
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      double qtq = 0.0, rec = 0.0;
      for (int k = 0; k < 3; k++) {
        qtq += q[3 * k + a] * q[3 * k + b];
        rec += q[3 * a + k] * lam[k] * q[3 * b + k];
      }
      EXPECT_NEAR(qtq, a == b ? 1.0 : 0.0, 1.0e-12) << "trial " << trial;
      EXPECT_NEAR(rec, sf[3 * a + b], 1.0e-12) << "trial " << trial;
    }
}

TEST(Material, DerivedElasticConstants)
{
  const Material mat = ti64();
  EXPECT_NEAR(mat.G, 113.8e9 / 2.7, 1.0e-14 * mat.G);
  EXPECT_NEAR(mat.K, 113.8e9 / 0.9, 1.0e-14 * mat.K);
  EXPECT_NEAR(mat.c0, sqrt(113.8e9 / 0.9 / 4430.0), 1.0e-9);
  EXPECT_NEAR(mat.cl * mat.cl * mat.rho0, mat.K + 4.0 / 3.0 * mat.G, 1.0e-3);
}

// EOS: zero at reference state, bulk modulus as rho dp/drho at rho0 (both
// branches of Mie-Grueneisen), and thermal pressure gamma0 rho0 cp (T - Tref)
TEST(Material, EquationOfState)
{
  Material mat = ti64();
  mat.eos = EOS_LINEAR;
  EXPECT_EQ(eos_pressure(mat, mat.rho0, 900.0), 0.0);
  EXPECT_NEAR(eos_pressure(mat, 1.01 * mat.rho0, 300.0), 0.01 * mat.K, 1.0e-6 * mat.K);
  mat.eos = EOS_MIE_GRUNEISEN;
  mat.gamma0 = 1.23;
  mat.s_hug = 1.09;
  EXPECT_NEAR(eos_pressure(mat, mat.rho0, mat.Tref), 0.0, 1.0e-6);
  const double dr = 1.0e-6 * mat.rho0;
  const double p0 = eos_pressure(mat, mat.rho0, mat.Tref);
  const double up = (eos_pressure(mat, mat.rho0 + dr, mat.Tref) - p0) / dr;
  const double dn = (p0 - eos_pressure(mat, mat.rho0 - dr, mat.Tref)) / dr;
  EXPECT_NEAR(up * mat.rho0, mat.K, 1.0e-4 * mat.K);
  EXPECT_NEAR(dn * mat.rho0, mat.K, 1.0e-4 * mat.K);
  EXPECT_NEAR(eos_pressure(mat, mat.rho0, 500.0), 1.23 * 4430.0 * 580.0 * 200.0, 1.0e-3);
  // compression stiffens (s_hug > 1): p(+mu) > -p(-mu)
  EXPECT_GT(eos_pressure(mat, 1.1 * mat.rho0, mat.Tref),
            -eos_pressure(mat, 0.9 * mat.rho0, mat.Tref));
}

// pressure cutoff (pair_coeff keyword pmin): p = max(p_EOS, pmin) for both EOS, in tension and
// with the thermal pressure of Mie-Grueneisen; the EOS itself (bit for bit) above pmin and without
// a cutoff (pmin = 0); pmin exactly below it, however far the material expands
TEST(Material, PressureCutoff)
{
  for (int eos : {EOS_LINEAR, EOS_MIE_GRUNEISEN}) {
    Material mat = ti64();
    mat.eos = eos;
    if (eos == EOS_MIE_GRUNEISEN) {
      mat.gamma0 = 1.23;
      mat.s_hug = 1.09;
    }
    Material cut = mat;
    cut.pmin = -4.0e9;
    // p_EOS = -4 GPa at rho = rho0 (1 - 4e9/K) (linear; Mie-Grueneisen at T = Tref too)
    const double rho_c = mat.rho0 * (1.0 - 4.0e9 / mat.K);
    int nbelow = 0, nabove = 0;
    for (double T : {300.0, 900.0}) {
      for (int k = 0; k <= 60; k++) {
        const double rho = mat.rho0 * (1.10 - 0.005 * k);    // 10 % compression .. 20 % expansion
        const double p = eos_pressure_uncut(mat, rho, T);
        // hand-written EOS: the linear one, or Mie-Grueneisen's tension branch
        if (eos == EOS_LINEAR) EXPECT_EQ(p, mat.c0 * mat.c0 * (rho - mat.rho0));
        else if (rho < mat.rho0)
          EXPECT_NEAR(p, mat.K * (rho / mat.rho0 - 1.0) + 1.23 * mat.rho0 * mat.cp * (T - 300.0), 1e-6 * mat.K);
        EXPECT_EQ(eos_pressure(mat, rho, T), p) << "no cutoff: the EOS, bit for bit";
        const double pc = eos_pressure(cut, rho, T);
        if (p >= -4.0e9) {
          EXPECT_EQ(pc, p) << "above pmin: the EOS, rho " << rho << " T " << T;
          nabove++;
        } else {
          EXPECT_EQ(pc, -4.0e9) << "below pmin: pmin, rho " << rho << " T " << T;
          nbelow++;
        }
      }
    }
    EXPECT_GT(nbelow, 10);
    EXPECT_GT(nabove, 10);
    // the cutoff density of the linear EOS (and of Mie-Grueneisen at Tref): just above it the EOS,
    // just below pmin
    EXPECT_GT(eos_pressure(cut, rho_c * (1.0 + 1e-9), 300.0), -4.0e9);
    EXPECT_EQ(eos_pressure(cut, rho_c * (1.0 - 1e-9), 300.0), -4.0e9);
    EXPECT_EQ(eos_pressure(cut, 0.5 * mat.rho0, 300.0), -4.0e9);
    // compression untouched; a NaN is not hidden
    EXPECT_EQ(eos_pressure(cut, 1.05 * mat.rho0, 300.0), eos_pressure_uncut(mat, 1.05 * mat.rho0, 300.0));
    EXPECT_TRUE(std::isnan(eos_pressure(cut, std::nan(""), 300.0)));
  }
}

// spall release (pair_coeff ... pmin P spall release): below the cutoff the pressure is 0 instead
// of pmin and the particle carries no stress at all in the forces (A = sigma/rho^2 and the
// artificial stress R zero, whatever its deviatoric stress); above the cutoff, and with spall
// cutoff, what the cutoff alone gives, bit for bit
TEST(Material, SpallRelease)
{
  Material cut = ti64();
  cut.pmin = -4.0e9;
  Material rel = cut;
  rel.spall = SPALL_RELEASE;
  const double sdev[6] = {3.0e8, -1.0e8, -2.0e8, 5.0e7, 0.0, 0.0};
  int nreleased = 0, nheld = 0;
  for (int k = 0; k <= 40; k++) {
    const double rho = cut.rho0 * (1.05 - 0.005 * k);    // 5 % compression .. 15 % expansion
    const double p = eos_pressure_uncut(cut, rho, 300.0);
    double Ac[6], Rc[6], Ar[6], Rr[6];
    particle_stress(cut, 3, 1, rho, 300.0, sdev, Ac, Rc);
    particle_stress(rel, 3, 1, rho, 300.0, sdev, Ar, Rr);
    EXPECT_EQ(spall_released(rel, p), p < -4.0e9);
    EXPECT_FALSE(spall_released(cut, p)) << "spall cutoff releases nothing";
    if (p < -4.0e9) {
      EXPECT_EQ(eos_pressure(rel, rho, 300.0), 0.0);
      EXPECT_EQ(eos_pressure(cut, rho, 300.0), -4.0e9);
      for (int c = 0; c < 6; c++) {
        EXPECT_EQ(Ar[c], 0.0) << "released: no stress, rho " << rho;
        EXPECT_EQ(Rr[c], 0.0) << "released: no artificial stress, rho " << rho;
      }
      EXPECT_NE(Ac[0], 0.0) << "the cutoff alone keeps pmin and the deviator";
      nreleased++;
    } else {
      EXPECT_EQ(eos_pressure(rel, rho, 300.0), p);
      for (int c = 0; c < 6; c++) {
        EXPECT_EQ(Ar[c], Ac[c]) << "above pmin as with the cutoff, rho " << rho;
        EXPECT_EQ(Rr[c], Rc[c]) << "above pmin as with the cutoff, rho " << rho;
      }
      nheld++;
    }
  }
  EXPECT_GT(nreleased, 5);
  EXPECT_GT(nheld, 5);
  // without a cutoff nothing is released, whatever the tension
  Material none = rel;
  none.pmin = 0.0;
  EXPECT_FALSE(spall_released(none, -1.0e12));
  EXPECT_EQ(pressure_cutoff(none, -1.0e12), -1.0e12);
}

// spall release in the integration of one particle (sphcut_solid.h, spall_density): a particle
// expanded below pmin keeps its density and carries no deviatoric stress, no plastic flow, no
// plastic heat, while the same steps with spall cutoff expand it on and heat it; pushed back
// (a positive density rate) it is compressed again and above pmin carries its stress again
TEST(Material, SpallReleaseIntegration)
{
  Material cut = ti64();
  cut.pmin = -4.0e9;
  cut.chi = 0.9;
  Material rel = cut;
  rel.spall = SPALL_RELEASE;
  using SL = StateLayout;
  const double dt = 1.0e-9, m = 1.0e-12;
  // the density at which the EOS gives pmin (linear in rho at 300 K for both EOS kinds below rho0)
  double lo = 0.5 * cut.rho0, hi = cut.rho0;
  for (int it = 0; it < 200; it++) {
    const double mid = 0.5 * (lo + hi);
    (eos_pressure_uncut(cut, mid, 300.0) < cut.pmin ? lo : hi) = mid;
  }
  const double rho_pmin = hi;
  auto start = [&](double *s) {
    for (int k = 0; k < SL::NCOL; k++) s[k] = 0.0;
    s[SL::RHO] = 1.001 * rho_pmin;    // just above the cutoff
    s[SL::TEMP] = 300.0;
    s[SL::EPS] = 0.1;
    const double dev[6] = {5.0e8, -2.5e8, -2.5e8, 2.0e8, 0.0, 0.0};    // von Mises 0.83 GPa, below yield
    for (int k = 0; k < 6; k++) s[SL::SXX + k] = dev[k];
    // expanding at 1 % per 10 steps and sheared (the rates of the last step and of this one)
    s[SL::DRHO_O] = s[SL::DRHO] = -1.0e-3 * rho_pmin / dt;
    s[SL::DS_O] = s[SL::DS] = 5.0e16;    // to the yield surface in a few steps
    s[SL::DS_O + 1] = s[SL::DS + 1] = -5.0e16;
  };
  double sr[SL::NCOL], sc[SL::NCOL];
  start(sr);
  start(sc);
  const double f[3] = {0.0, 0.0, 0.0};
  double v[3] = {0.0, 0.0, 0.0}, x[3] = {0.0, 0.0, 0.0};
  double work_rel = 0.0, work_cut = 0.0;
  for (int n = 0; n < 40; n++) {
    for (double *s : {sr, sc}) {
      const Material &mt = s == sr ? rel : cut;
      const double drho = s[SL::DRHO], ds0 = s[SL::DS], ds1 = s[SL::DS + 1];
      integrate_first_half(mt, SL::WORKPIECE, dt, 0.0, x, v, f, s);
      s[SL::DRHO] = drho;    // the pair's rates of this step: the same expansion and shear
      s[SL::DS] = ds0;
      s[SL::DS + 1] = ds1;
      const double w = integrate_second_half(mt, SL::WORKPIECE, dt, 0.0, m, v, f, s);
      (s == sr ? work_rel : work_cut) += w;
    }
  }
  EXPECT_LT(eos_pressure_uncut(cut, sc[SL::RHO], sc[SL::TEMP]), cut.pmin) << "the cutoff run went below pmin";
  EXPECT_LT(sc[SL::RHO], 0.97 * rho_pmin) << "with the cutoff the particle expands on";
  EXPECT_GT(sr[SL::RHO], 0.998 * rho_pmin) << "released: no expansion beyond one step below the cutoff";
  EXPECT_TRUE(spall_released(rel, eos_pressure_uncut(rel, sr[SL::RHO], sr[SL::TEMP])));
  EXPECT_LE(sr[SL::RHO_F], sr[SL::RHO] * (1.0 + 1e-12)) << "the force state's density held too";
  EXPECT_GE(sr[SL::RHO_F], sr[SL::RHO] * (1.0 - 1e-12));
  for (int k = 0; k < 6; k++) EXPECT_EQ(sr[SL::SXX + k], 0.0) << "released: no deviatoric stress";
  EXPECT_NE(sc[SL::SXX], 0.0);
  EXPECT_EQ(sr[SL::EPSDOT], 0.0) << "released: no plastic flow";
  EXPECT_GT(work_cut, 0.0) << "the cutoff run flows plastically";
  EXPECT_EQ(work_rel, 0.0) << "released (after its first step) before it yields: no plastic work";
  EXPECT_LT(sr[SL::TEMP], sc[SL::TEMP]);
  // pushed back: compressed again, and above pmin it carries its deviatoric stress again
  sr[SL::DRHO_O] = sr[SL::DRHO] = 1.0e-3 * rho_pmin / dt;
  const double rho_before = sr[SL::RHO];
  for (int n = 0; n < 5; n++) {
    integrate_first_half(rel, SL::WORKPIECE, dt, 0.0, x, v, f, sr);
    sr[SL::DRHO] = 1.0e-3 * rho_pmin / dt;
    sr[SL::DS] = 1.0e16;
    integrate_second_half(rel, SL::WORKPIECE, dt, 0.0, m, v, f, sr);
  }
  EXPECT_NEAR(sr[SL::RHO], rho_before * 1.005, 1e-3 * rho_before) << "compression as without the release";
  EXPECT_FALSE(spall_released(rel, eos_pressure_uncut(rel, sr[SL::RHO], sr[SL::TEMP])));
  EXPECT_NE(sr[SL::SXX], 0.0) << "recompressed above pmin: stress again";
  // spall_density leaves everything else alone
  EXPECT_EQ(spall_density(cut, 4000.0, 3000.0, 300.0), 3000.0) << "cutoff: expansion as it is";
  EXPECT_EQ(spall_density(rel, 3000.0, 4000.0, 300.0), 4000.0) << "release: compression as it is";
  EXPECT_EQ(spall_density(rel, 4430.0, 4429.0, 300.0), 4429.0) << "release above pmin: as it is";
  EXPECT_EQ(spall_density(rel, 4300.0, 3000.0, 300.0), 3000.0) << "release: the step below pmin is kept";
  EXPECT_EQ(spall_density(rel, 3000.0, 2900.0, 300.0), 3000.0) << "release below pmin: held";
}

// total stress = deviator - p I
TEST(Material, CauchyStress)
{
  const double s[6] = {1.0, -3.0, 2.0, 0.5, -0.25, 0.125};
  double sig[6];
  cauchy_stress(s, 7.0, sig);
  const double expect[6] = {-6.0, -10.0, -5.0, 0.5, -0.25, 0.125};
  for (int k = 0; k < 6; k++) EXPECT_DOUBLE_EQ(sig[k], expect[k]);
}

/* ---- Johnson-Cook ---------------------------------------------------- */

// flow stress equals (A + B eps^n)(1 + C ln(epsdot/epsdot0))(1 - T*^m)
TEST(JohnsonCook, FlowStressMatchesFormula)
{
  const Material mat = ti64();
  for (double eps : {0.01, 0.1, 0.5, 2.0})
    for (double epsdot : {2.0, 1.0e3, 1.0e6})
      for (double T : {350.0, 600.0, 1200.0, 1800.0}) {
        const double ref = jc_reference(eps, epsdot, T);
        EXPECT_NEAR(jc_flow_stress(mat, eps, epsdot, T), ref, 1.0e-12 * ref)
            << "eps " << eps << " epsdot " << epsdot << " T " << T;
      }
  // one value by hand: eps 0.2, epsdot 1e4, T 600
  const double hand = (862.0e6 + 331.0e6 * pow(0.2, 0.35)) * (1.0 + 0.01 * log(1.0e4)) *
      (1.0 - pow(300.0 / 1578.0, 0.8));
  EXPECT_NEAR(jc_flow_stress(mat, 0.2, 1.0e4, 600.0), hand, 1.0e-6);
  EXPECT_NEAR(hand, 843.2135e6, 1.0e2);    // worked value, Python: 843213478.25 Pa
}

// no rate hardening at or below the reference rate, no thermal softening at
// or below Tref, zero strength at and above the melting point, A at eps = 0
TEST(JohnsonCook, Limits)
{
  const Material mat = ti64();
  EXPECT_EQ(jc_rate_factor(mat, 0.0), 1.0);
  EXPECT_EQ(jc_rate_factor(mat, 0.5), 1.0);
  EXPECT_EQ(jc_rate_factor(mat, 1.0), 1.0);
  EXPECT_NEAR(jc_rate_factor(mat, 1.0e5), 1.0 + 0.01 * log(1.0e5), 1.0e-15);
  EXPECT_EQ(jc_thermal_factor(mat, 200.0), 1.0);
  EXPECT_EQ(jc_thermal_factor(mat, 300.0), 1.0);
  EXPECT_EQ(jc_thermal_factor(mat, 1878.0), 0.0);
  EXPECT_EQ(jc_thermal_factor(mat, 2500.0), 0.0);
  EXPECT_GT(jc_thermal_factor(mat, 1877.0), 0.0);
  EXPECT_EQ(jc_hardening(mat, 0.0), 862.0e6);
  EXPECT_EQ(jc_flow_stress(mat, 0.0, 0.1, 250.0), 862.0e6);
  EXPECT_EQ(jc_flow_stress(mat, 0.3, 1.0e4, 1900.0), 0.0);
  // monotonic: hardening with strain and rate, softening with temperature
  EXPECT_GT(jc_flow_stress(mat, 0.3, 10.0, 600.0), jc_flow_stress(mat, 0.2, 10.0, 600.0));
  EXPECT_GT(jc_flow_stress(mat, 0.3, 100.0, 600.0), jc_flow_stress(mat, 0.3, 10.0, 600.0));
  EXPECT_LT(jc_flow_stress(mat, 0.3, 10.0, 700.0), jc_flow_stress(mat, 0.3, 10.0, 600.0));
}

/* ---- modified Johnson-Cook with strain softening (flow tanh, Calamaz et al. 2008) ---- */

// Ti6Al4V above with the softening parameters of Calamaz et al. (a 2, b 5, c 2, d 1)
static Material ti64_tanh()
{
  Material mat = ti64();
  mat.flow = FLOW_TANH;
  mat.tanh_a = 2.0;
  mat.tanh_b = 5.0;
  mat.tanh_c = 2.0;
  mat.tanh_d = 1.0;
  return mat;
}

// the TANH law written out independently of the header:
// [A + B eps^n exp(-eps^a)] [1 + C ln(epsdot)] [1 - T*^m] [D + (1 - D) tanh(1/(eps + S)^c)],
// D = 1 - (T/Tmelt)^d, S = (T/Tmelt)^b
static double tanh_reference(double eps, double epsdot, double T, double a = 2.0, double b = 5.0, double c = 2.0,
                             double d = 1.0)
{
  const double hard = 862.0e6 + 331.0e6 * pow(eps, 0.35) / exp(pow(eps, a));
  const double rate = epsdot > 1.0 ? 1.0 + 0.01 * log(epsdot) : 1.0;
  const double ts = (T - 300.0) / (1878.0 - 300.0);
  const double thermal = ts <= 0.0 ? 1.0 : 1.0 - pow(ts, 0.8);
  const double D = 1.0 - pow(T / 1878.0, d), S = pow(T / 1878.0, b);
  return hard * rate * thermal * (D + (1.0 - D) * tanh(1.0 / pow(eps + S, c)));
}

TEST(FlowTanh, StressMatchesHandComputedValues)
{
  const Material mat = ti64_tanh();
  // worked values (mpmath, 30 digits)
  EXPECT_NEAR(flow_stress(mat, 0.5, 1.0e4, 600.0), 854092249.28891978621, 1.0e-12 * 854092249.29);
  EXPECT_NEAR(flow_stress(mat, 1.5, 1.0e5, 900.0), 387441300.69192132772, 1.0e-12 * 387441300.69);
  EXPECT_NEAR(flow_stress(mat, 0.05, 10.0, 1200.0), 361952733.61865684046, 1.0e-12 * 361952733.62);
  for (double eps : {0.0, 0.01, 0.3, 1.0, 3.0})
    for (double epsdot : {0.5, 1.0e3, 1.0e6})
      for (double T : {300.0, 700.0, 1500.0}) {
        const double ref = tanh_reference(eps, epsdot, T);
        EXPECT_NEAR(flow_stress(mat, eps, epsdot, T), ref, 1.0e-12 * ref)
            << "eps " << eps << " epsdot " << epsdot << " T " << T;
      }
  // softening: beyond the peak the stress falls with strain, and more so when hot
  EXPECT_LT(flow_stress(mat, 2.0, 1.0e3, 700.0), flow_stress(mat, 0.5, 1.0e3, 700.0));
  EXPECT_LT(flow_stress(mat, 1.0, 1.0e3, 1200.0) / jc_flow_stress(mat, 1.0, 1.0e3, 1200.0),
            flow_stress(mat, 1.0, 1.0e3, 600.0) / jc_flow_stress(mat, 1.0, 1.0e3, 600.0));
  // flow jc (the default): flow_stress is jc_flow_stress, to the bit
  const Material jc = ti64();
  for (double eps : {0.0, 0.2, 1.5})
    EXPECT_EQ(flow_stress(jc, eps, 1.0e4, 600.0), jc_flow_stress(jc, eps, 1.0e4, 600.0));
}

// softening off: d large makes D = 1 (no temperature-dependent softening), a large makes
// eps^a vanish for eps < 1 (no strain softening of the hardening term): Johnson-Cook
TEST(FlowTanh, LimitIsJohnsonCook)
{
  Material mat = ti64_tanh();
  mat.tanh_a = 1.0e3;
  mat.tanh_d = 1.0e3;
  const Material jc = ti64();
  for (double eps : {0.0, 0.05, 0.3, 0.7})
    for (double T : {300.0, 600.0, 900.0}) {
      const double ref = jc_flow_stress(jc, eps, 1.0e4, T);
      EXPECT_NEAR(flow_stress(mat, eps, 1.0e4, T), ref, 1.0e-15 * ref) << "eps " << eps << " T " << T;
    }
  // and the softening acts when it is on: 20 % and more below Johnson-Cook at eps 1.5, 900 K
  EXPECT_LT(flow_stress(ti64_tanh(), 1.5, 1.0e4, 900.0), 0.8 * jc_flow_stress(jc, 1.5, 1.0e4, 900.0));
}

// the slope that the radial return's Newton iteration uses is the derivative of the strain factor
TEST(FlowTanh, SlopeIsTheDerivative)
{
  for (const Material &mat : {ti64(), ti64_tanh()})
    for (double eps : {0.01, 0.2, 0.8, 1.5, 3.0})
      for (double T : {300.0, 900.0, 1500.0}) {
        double slope, sp, sm;
        flow_hardening(mat, eps, T, &slope);
        const double h = 1.0e-6 * eps;
        const double fd = (flow_hardening(mat, eps + h, T, &sp) - flow_hardening(mat, eps - h, T, &sm)) / (2.0 * h);
        EXPECT_NEAR(slope, fd, 1.0e-6 * (fabs(fd) + 1.0e6)) << "flow " << mat.flow << " eps " << eps << " T " << T;
      }
  // first yield of a cold particle: (eps + S)^-c overflows, tanh is 1, the slope finite (0)
  double slope = -1.0;
  const double h0 = flow_hardening(ti64_tanh(), 0.0, 1.0e-37, &slope);    // S = 4e-202
  EXPECT_EQ(h0, 862.0e6);
  EXPECT_EQ(slope, 0.0);
}

// the radial return with the softening law: the consistency condition holds at the returned
// state, also where the law softens (eps beyond the peak, hot)
TEST(FlowTanh, RadialReturnConverges)
{
  const Material mat = ti64_tanh();
  std::mt19937 gen(21);
  for (double dt : {1.0e-9, 1.0e-6})
    for (double eps : {0.0, 0.05, 0.8, 2.0})
      for (double T : {300.0, 900.0, 1500.0})
        for (double over : {1.0001, 1.05, 1.5, 3.0}) {
          const TrialReturn r = trial_return(mat, gen, eps, T, dt, over, over > 1.4 ? 1.0e-3 : 0.0);
          const double q0 = r.q0, deps = r.deps, sigy = r.sigy;
          ASSERT_GT(deps, 0.0);
          const double sy = flow_stress(mat, eps + deps, deps / dt, T);
          EXPECT_NEAR(q0 - 3.0 * mat.G * deps, sy, 1.0e-9 * sy)
              << "dt " << dt << " eps " << eps << " T " << T << " over " << over;
          EXPECT_NEAR(von_mises(r.s), sy, 1.0e-9 * sy);
          EXPECT_NEAR(sigy, sy, 1.0e-9 * sy);
        }
  // below the (softened) yield stress: elastic, and the yield stress reported is the law's
  double s[6], sigy;
  random_deviator(gen, 0.99 * flow_stress(mat, 2.0, 0.0, 900.0), s);
  EXPECT_EQ(radial_return(mat, s, 2.0, 900.0, 1.0e-9, &sigy), 0.0);
  EXPECT_DOUBLE_EQ(sigy, flow_stress(mat, 2.0, 0.0, 900.0));
  // ... which lies below A (1 - T*^m): the Johnson-Cook shortcut must not apply to it
  EXPECT_LT(flow_stress(mat, 2.0, 0.0, 900.0), 862.0e6 * jc_thermal_factor(mat, 900.0));
  random_deviator(gen, 0.5 * (flow_stress(mat, 2.0, 0.0, 900.0) + 862.0e6 * jc_thermal_factor(mat, 900.0)), s);
  EXPECT_GT(radial_return(mat, s, 2.0, 900.0, 1.0e-9, nullptr), 0.0);
}

/* ---- radial return --------------------------------------------------- */

// elastic trial state (von Mises below yield): stress unchanged, no plastic strain
TEST(RadialReturn, ElasticTrialUnchanged)
{
  const Material mat = ti64();
  std::mt19937 gen(11);
  double s[6], s0[6], sigy = -1.0;
  random_deviator(gen, 0.9 * 862.0e6, s);
  for (int k = 0; k < 6; k++) s0[k] = s[k];
  EXPECT_EQ(radial_return(mat, s, 0.0, 300.0, 1.0e-9, &sigy), 0.0);
  for (int k = 0; k < 6; k++) EXPECT_EQ(s[k], s0[k]);
  EXPECT_DOUBLE_EQ(sigy, 862.0e6);
  // an elastic-only material never yields
  Material el = mat;
  el.plastic = 0;
  random_deviator(gen, 5.0 * 862.0e6, s);
  for (int k = 0; k < 6; k++) s0[k] = s[k];
  EXPECT_EQ(radial_return(el, s, 0.0, 300.0, 1.0e-9, nullptr), 0.0);
  for (int k = 0; k < 6; k++) EXPECT_EQ(s[k], s0[k]);
}

// perfect plasticity (B = C = 0): return onto q = A (1 - T*^m) along the
// trial direction, deps = (q_trial - sigma_y)/(3G)
TEST(RadialReturn, PerfectlyPlastic)
{
  Material mat = ti64();
  mat.B = 0.0;
  mat.C = 0.0;
  std::mt19937 gen(12);
  for (double T : {300.0, 800.0})
    for (double over : {1.001, 1.5, 4.0}) {
      const double sy = 862.0e6 * jc_thermal_factor(mat, T);
      double s[6], s0[6], sigy;
      random_deviator(gen, over * sy, s);
      for (int k = 0; k < 6; k++) s0[k] = s[k];
      const double q0 = von_mises(s0);
      const double deps = radial_return(mat, s, 0.1, T, 1.0e-9, &sigy);
      EXPECT_NEAR(von_mises(s), sy, 1.0e-10 * sy) << "T " << T << " over " << over;
      EXPECT_NEAR(sigy, sy, 1.0e-10 * sy);
      EXPECT_NEAR(deps, (q0 - sy) / (3.0 * mat.G), 1.0e-10 * deps);
      // radial: s_new = (sy / q0) s_trial component by component
      for (int k = 0; k < 6; k++) EXPECT_NEAR(s[k], s0[k] * sy / q0, 1.0e-10 * sy);
    }
}

// hardening + rate: the return solves q_trial - 3G deps = sigma_y(eps + deps, deps/dt, T)
TEST(RadialReturn, HardeningAndRateConsistency)
{
  const Material mat = ti64();
  const double dt = 1.0e-9;
  std::mt19937 gen(13);
  for (double eps : {0.0, 0.05, 0.8})
    for (double T : {300.0, 700.0})
      for (double over : {1.0001, 1.05, 1.5, 3.0}) {
        const TrialReturn r = trial_return(mat, gen, eps, T, dt, over);    // flow jc: jc_flow_stress
        const double *s = r.s, *s0 = r.s0, q0 = r.q0, deps = r.deps, sigy = r.sigy, y0 = r.y0;
        ASSERT_GT(deps, 0.0);
        const double sy = jc_flow_stress(mat, eps + deps, deps / dt, T);
        EXPECT_NEAR(q0 - 3.0 * mat.G * deps, sy, 1.0e-9 * sy)
            << "eps " << eps << " T " << T << " over " << over;
        EXPECT_NEAR(von_mises(s), sy, 1.0e-9 * sy);
        EXPECT_NEAR(sigy, sy, 1.0e-9 * sy);
        // strain and rate hardening put the returned state above the initial yield stress
        EXPECT_GT(sy, y0);
        for (int k = 0; k < 6; k++) EXPECT_NEAR(s[k] * q0, s0[k] * von_mises(s), 1.0e-9 * sy * q0);
      }
}

// the starting guess (the last step's increment in the fix) changes the path, not the
// answer: just after first yield (eps 0 or tiny, where the hardening slope is steep), on
// the usual increments and far from the root on either side, the return satisfies the
// consistency condition and agrees with the unguessed return to the solver's tolerance;
// m = 1 and n = 1 (no pow) give the flow stress of the general formula
TEST(RadialReturn, GuessChangesPathNotAnswer)
{
  Material mat = ti64();
  const double dt = 5.0e-9;
  std::mt19937 gen(16);
  for (double n : {mat.n, 1.0})
    for (double m : {mat.m, 1.0})
      for (double eps : {0.0, 1.0e-8, 0.01, 0.5})
        for (double over : {1.0001, 1.01, 1.3, 2.0})
          for (double g : {1.0e-12, 0.5, 0.99, 1.0, 1.01, 3.0, 1.0e3}) {
            mat.n = n;
            mat.m = m;
            const double T = 600.0;
            double s[6], s0[6], sigy, sigy0;
            const double y0 = jc_flow_stress(mat, eps, 0.0, T);
            random_deviator(gen, over * y0, s0);
            for (int k = 0; k < 6; k++) s[k] = s0[k];
            const double q0 = von_mises(s0);
            const double ref = radial_return(mat, s, eps, T, dt, &sigy0);
            ASSERT_GT(ref, 0.0);
            for (int k = 0; k < 6; k++) s[k] = s0[k];
            const double deps = radial_return(mat, s, eps, T, dt, &sigy, g * ref);
            const double sy = jc_flow_stress(mat, eps + deps, deps / dt, T);
            EXPECT_NEAR(q0 - 3.0 * mat.G * deps, sy, 1.0e-11 * q0)
                << "n " << n << " m " << m << " eps " << eps << " over " << over << " guess " << g;
            EXPECT_NEAR(deps, ref, 1.0e-11 * q0 / (3.0 * mat.G));
            EXPECT_NEAR(sigy, sigy0, 1.0e-11 * q0);
            const double ts = (T - mat.Tref) / (mat.Tmelt - mat.Tref);
            EXPECT_NEAR(jc_thermal_factor(mat, T), 1.0 - std::pow(ts, m), 1.0e-15);
          }
}

// thermal softening: the same trial state flows more at a higher temperature
TEST(RadialReturn, ThermalSofteningIncreasesPlasticStrain)
{
  const Material mat = ti64();
  std::mt19937 gen(14);
  double s0[6], s[6];
  random_deviator(gen, 1.2e9, s0);
  double prev = -1.0;
  for (double T : {300.0, 600.0, 900.0, 1500.0}) {
    for (int k = 0; k < 6; k++) s[k] = s0[k];
    const double deps = radial_return(mat, s, 0.1, T, 1.0e-9, nullptr);
    EXPECT_GT(deps, prev) << "T " << T;
    prev = deps;
  }
}

// a deviatoric trial stays deviatoric (the return is a scaling)
TEST(RadialReturn, DeviatorStaysTraceless)
{
  const Material mat = ti64();
  std::mt19937 gen(15);
  for (int trial = 0; trial < 20; trial++) {
    double s[6];
    random_deviator(gen, 1.0e9 + 1.0e8 * trial, s);
    radial_return(mat, s, 0.05 * trial, 300.0 + 40.0 * trial, 1.0e-9, nullptr);
    EXPECT_NEAR(s[XX] + s[YY] + s[ZZ], 0.0, 1.0e-12 * von_mises(s));
  }
}

/* ---- Jaumann rate ----------------------------------------------------- */

// pure spin: ds = W s - s W (no 2G D part), s:ds = 0 (invariants preserved),
// and zero stress stays zero
TEST(Jaumann, PureSpin)
{
  const Material mat = ti64();
  std::mt19937 gen(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 5; trial++) {
    double L[9] = {0.0, u(gen), u(gen), 0.0, 0.0, u(gen), 0.0, 0.0, 0.0};
    L[3] = -L[1];
    L[6] = -L[2];
    L[7] = -L[5];
    for (double &l : L) l *= 1.0e5;
    double s[6], ds[6], sf[9], ws[9], sw[9];
    random_deviator(gen, 5.0e8, s);
    EXPECT_EQ(jaumann_rate(mat, L, s, ds), 0.0);
    to_full(s, sf);
    mul3(L, sf, ws);    // W = L for antisymmetric L
    mul3(sf, L, sw);
    const int ia[6] = {0, 4, 8, 1, 2, 5};
    const double scale = 5.0e8 * 1.0e5;
    for (int k = 0; k < 6; k++) EXPECT_NEAR(ds[k], ws[ia[k]] - sw[ia[k]], 1.0e-12 * scale) << k;
    EXPECT_NEAR(s[XX] * ds[XX] + s[YY] * ds[YY] + s[ZZ] * ds[ZZ] +
                    2.0 * (s[XY] * ds[XY] + s[XZ] * ds[XZ] + s[YZ] * ds[YZ]),
                0.0, 1.0e-12 * 5.0e8 * scale);
    const double zero[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    jaumann_rate(mat, L, zero, ds);
    for (int k = 0; k < 6; k++) EXPECT_EQ(ds[k], 0.0);
  }
}

// sign convention: a body spinning about z at omega (v = omega x r) carries
// a uniaxial x stress k diag(2,-1,-1) with it, so d s_xy/dt = 3 k omega
TEST(Jaumann, RigidRotationCarriesStress)
{
  const Material mat = ti64();
  const double omega = 2.0e4, k = 1.0e8;
  const double L[9] = {0.0, -omega, 0.0, omega, 0.0, 0.0, 0.0, 0.0, 0.0};
  const double s[6] = {2.0 * k, -k, -k, 0.0, 0.0, 0.0};
  double ds[6];
  jaumann_rate(mat, L, s, ds);
  EXPECT_NEAR(ds[XY], 3.0 * k * omega, 1.0e-12 * k * omega);
  for (int c : {XX, YY, ZZ, XZ, YZ}) EXPECT_NEAR(ds[c], 0.0, 1.0e-12 * k * omega);
}

// symmetric L (no spin): ds = 2G dev(D), traceless, returns tr(D)
TEST(Jaumann, PureStrainRate)
{
  const Material mat = ti64();
  const double L[9] = {3.0e3, 1.0e3, -2.0e3, 1.0e3, -1.0e3, 0.5e3, -2.0e3, 0.5e3, 4.0e3};
  const double trd = 6.0e3;
  const double m = trd / 3.0;
  const double dev[6] = {3.0e3 - m, -1.0e3 - m, 4.0e3 - m, 1.0e3, -2.0e3, 0.5e3};
  const double zero[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  double ds[6];
  EXPECT_DOUBLE_EQ(jaumann_rate(mat, L, zero, ds), trd);
  const double scale = 2.0 * mat.G * 4.0e3;
  for (int k = 0; k < 6; k++) EXPECT_NEAR(ds[k], 2.0 * mat.G * dev[k], 1.0e-14 * scale) << k;
  EXPECT_NEAR(ds[XX] + ds[YY] + ds[ZZ], 0.0, 1.0e-14 * scale);
  // with a pre-stress and no spin the rate is still 2G dev(D)
  const double s[6] = {1.0e8, -2.0e8, 1.0e8, 3.0e7, -1.0e7, 2.0e7};
  double ds2[6];
  jaumann_rate(mat, L, s, ds2);
  for (int k = 0; k < 6; k++) EXPECT_NEAR(ds2[k], ds[k], 1.0e-14 * scale) << k;
  // pure dilatation produces no deviatoric stress rate
  const double Ld[9] = {2.0e3, 0.0, 0.0, 0.0, 2.0e3, 0.0, 0.0, 0.0, 2.0e3};
  EXPECT_DOUBLE_EQ(jaumann_rate(mat, Ld, zero, ds), 6.0e3);
  for (int k = 0; k < 6; k++) EXPECT_NEAR(ds[k], 0.0, 1.0e-14 * scale) << k;
}

// plane strain: in-plane dilatation L = diag(a,a,0) drives s_zz at -2G (2a/3)
TEST(Jaumann, PlaneStrainDilatation)
{
  const Material mat = ti64();
  const double a = 1.0e4;
  const double L[9] = {a, 0.0, 0.0, 0.0, a, 0.0, 0.0, 0.0, 0.0};
  const double zero[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  double ds[6];
  EXPECT_DOUBLE_EQ(jaumann_rate(mat, L, zero, ds), 2.0 * a);
  const double tol = 1.0e-14 * mat.G * a;
  EXPECT_NEAR(ds[ZZ], -2.0 * mat.G * 2.0 * a / 3.0, tol);
  EXPECT_NEAR(ds[XX], 2.0 * mat.G * a / 3.0, tol);
  EXPECT_NEAR(ds[YY], 2.0 * mat.G * a / 3.0, tol);
  for (int c : {XY, XZ, YZ}) EXPECT_EQ(ds[c], 0.0);
}

/* ---- linear algebra --------------------------------------------------- */

// Jacobi eigen decomposition: Q orthonormal, Q diag(lam) Q^T = S, and the
// eigenvalues of a matrix built from known ones are recovered
TEST(Math, SymEigenReconstructs)
{
  std::mt19937 gen(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; trial++) {
    double s[6], lam[3], q[9];
    for (int k = 0; k < 6; k++) s[k] = u(gen);
    if (trial == 1) s[XY] = s[XZ] = s[YZ] = 0.0;                          // already diagonal
    if (trial == 2) { s[XX] = s[YY] = s[ZZ] = 0.5; s[XY] = s[XZ] = s[YZ] = 0.25; }    // degenerate
    double sf[9];
    sym_eigen(s, lam, q);
    to_full(s, sf);
    expect_eigen_decomposition(q, lam, sf, trial);
  }
  // known spectrum {3, -1, 0.5} in a rotated frame
  const double c = cos(0.7), sn = sin(0.7), c2 = cos(-1.1), s2 = sin(-1.1);
  const double rz[9] = {c, -sn, 0.0, sn, c, 0.0, 0.0, 0.0, 1.0};
  const double rx[9] = {1.0, 0.0, 0.0, 0.0, c2, -s2, 0.0, s2, c2};
  double r[9], rd[9], full[9];
  mul3(rz, rx, r);
  const double ev[3] = {3.0, -1.0, 0.5};
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) rd[3 * a + b] = r[3 * a + b] * ev[b];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      full[3 * a + b] = 0.0;
      for (int k = 0; k < 3; k++) full[3 * a + b] += rd[3 * a + k] * r[3 * b + k];
    }
  const double s[6] = {full[0], full[4], full[8], full[1], full[2], full[5]};
  double lam[3], q[9];
  sym_eigen(s, lam, q);
  double sorted[3] = {lam[0], lam[1], lam[2]};
  std::sort(sorted, sorted + 3);
  EXPECT_NEAR(sorted[0], -1.0, 1.0e-12);
  EXPECT_NEAR(sorted[1], 0.5, 1.0e-12);
  EXPECT_NEAR(sorted[2], 3.0, 1.0e-12);
}

// closed-form x-y eigen decomposition: reconstructs the in-plane block,
// lam[2] = s_zz, third eigenvector e_z, lam[0] >= lam[1]
TEST(Math, SymEigen2dReconstructs)
{
  std::mt19937 gen(32);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; trial++) {
    double s[6] = {u(gen), u(gen), u(gen), u(gen), 0.0, 0.0};
    if (trial == 1) s[XY] = 0.0;
    if (trial == 2) { s[XX] = s[YY] = 0.3; s[XY] = 0.0; }
    if (trial == 3) { s[XX] = s[YY] = 0.3; }
    double lam[3], q[9], sf[9];
    sym_eigen_2d(s, lam, q);
    to_full(s, sf);
    EXPECT_GE(lam[0], lam[1]);
    EXPECT_EQ(lam[2], s[ZZ]);
    expect_eigen_decomposition(q, lam, sf, trial);
    EXPECT_EQ(q[2], 0.0);
    EXPECT_EQ(q[5], 0.0);
    EXPECT_EQ(q[8], 1.0);
  }
}

// A inv(A) = I in 3D and on the x-y block in 2D; singular input gives det 0 and I
TEST(Math, MatInverse)
{
  std::mt19937 gen(33);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; trial++) {
    double a[9], inv[9], prod[9];
    for (double &x : a) x = u(gen);
    for (int k = 0; k < 3; k++) a[4 * k] += 2.0;    // keep it well conditioned
    const double det = mat_inverse(a, inv, 3);
    const double det_ref = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
        a[2] * (a[3] * a[7] - a[4] * a[6]);
    EXPECT_NEAR(det, det_ref, 1.0e-12 * fabs(det_ref));
    mat_mul(a, inv, prod);
    for (int k = 0; k < 9; k++) EXPECT_NEAR(prod[k], k % 4 == 0 ? 1.0 : 0.0, 1.0e-12) << trial;
    mul3(inv, a, prod);
    for (int k = 0; k < 9; k++) EXPECT_NEAR(prod[k], k % 4 == 0 ? 1.0 : 0.0, 1.0e-12) << trial;
    // 2D: only the x-y block is inverted (z entries of a are ignored)
    const double det2 = mat_inverse(a, inv, 2);
    EXPECT_DOUBLE_EQ(det2, a[0] * a[4] - a[1] * a[3]);
    double a2[9] = {a[0], a[1], 0.0, a[3], a[4], 0.0, 0.0, 0.0, 1.0};
    mat_mul(a2, inv, prod);
    for (int k = 0; k < 9; k++) EXPECT_NEAR(prod[k], k % 4 == 0 ? 1.0 : 0.0, 1.0e-12) << trial;
    for (int k : {2, 5, 6, 7}) EXPECT_EQ(inv[k], 0.0);
  }
  // singular: rank-deficient (row 3 = row 1 + row 2; in 2D row 2 = 2 row 1)
  const double sing3[9] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 5.0, 7.0, 9.0};
  const double sing2[9] = {1.0, 2.0, 0.0, 2.0, 4.0, 0.0, 0.0, 0.0, 1.0};
  for (int dim = 2; dim <= 3; dim++) {
    double inv[9];
    EXPECT_EQ(mat_inverse(dim == 2 ? sing2 : sing3, inv, dim), 0.0);
    for (int k = 0; k < 9; k++) EXPECT_EQ(inv[k], k % 4 == 0 ? 1.0 : 0.0) << "dim " << dim;
  }
  // nearly singular (det / scale^dim ~ 1e-15, round-off level) is treated as singular too
  const double near3[9] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 5.0, 7.0, 9.0 + 1.0e-13};
  const double near2[9] = {1.0, 2.0, 0.0, 2.0, 4.0 + 1.0e-14, 0.0, 0.0, 0.0, 1.0};
  for (int dim = 2; dim <= 3; dim++) {
    double inv[9];
    EXPECT_EQ(mat_inverse(dim == 2 ? near2 : near3, inv, dim), 0.0) << "dim " << dim;
    for (int k = 0; k < 9; k++) EXPECT_EQ(inv[k], k % 4 == 0 ? 1.0 : 0.0) << "dim " << dim;
  }
  // a tiny but regular matrix is not treated as singular (the test is scale free)
  const double tiny[9] = {1.0e-9, 0.0, 0.0, 0.0, 2.0e-9, 0.0, 0.0, 0.0, 4.0e-9};
  double inv[9];
  EXPECT_NEAR(mat_inverse(tiny, inv, 3), 8.0e-27, 1.0e-40);
  EXPECT_NEAR(inv[8], 0.25e9, 1.0e-3);
}

// von Mises of a uniaxial deviator k diag(2,-1,-1) is 3k, of pure shear tau is sqrt(3) tau
TEST(Math, VonMises)
{
  const double uni[6] = {2.0, -1.0, -1.0, 0.0, 0.0, 0.0};
  EXPECT_DOUBLE_EQ(von_mises(uni), 3.0);
  const double shear[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  EXPECT_DOUBLE_EQ(von_mises(shear), sqrt(3.0));
}

/* ---- stabilisation ----------------------------------------------------- */

// Monaghan viscosity: zero for separating pairs, positive for approaching,
// Pi = (-alpha cbar mu + beta mu^2)/rhobar with mu = h vr/(r^2 + 0.01 h^2)
TEST(Stabilisation, ArtificialViscosity)
{
  const double alpha = 1.0, beta = 2.0, h = 1.5e-4, cbar = 5000.0, rhobar = 4430.0;
  const double r2 = sq(1.2e-4);
  EXPECT_EQ(artificial_viscosity(alpha, beta, 0.0, r2, h, cbar, rhobar), 0.0);
  EXPECT_EQ(artificial_viscosity(alpha, beta, 1.0e-3, r2, h, cbar, rhobar), 0.0);
  for (double vr : {-1.0e-6, -1.0e-4, -1.0e-2}) {
    const double mu = h * vr / (r2 + 0.01 * h * h);
    const double ref = (-alpha * cbar * mu + beta * mu * mu) / rhobar;
    const double pi = artificial_viscosity(alpha, beta, vr, r2, h, cbar, rhobar);
    EXPECT_GT(pi, 0.0) << vr;
    EXPECT_NEAR(pi, ref, 1.0e-12 * ref) << vr;
  }
  // linear term alone scales with the approach speed
  const double p1 = artificial_viscosity(alpha, 0.0, -1.0e-4, r2, h, cbar, rhobar);
  const double p2 = artificial_viscosity(alpha, 0.0, -2.0e-4, r2, h, cbar, rhobar);
  EXPECT_NEAR(p2, 2.0 * p1, 1.0e-12 * p2);
}

// Gray-Monaghan artificial stress: acts only on tensile principal stresses,
// -eps sigma_p / rho^2 along the principal direction
TEST(Stabilisation, ArtificialStress)
{
  const double eps = 0.3, rho = 4430.0, sig0 = 4.0e8;
  const double a = -eps * sig0 / (rho * rho);
  double R[6];
  // fully compressive states give nothing
  const double comp[6] = {-3.0e8, -2.0e8, -1.0e8, 5.0e7, 2.0e7, -3.0e7};
  for (int dim = 2; dim <= 3; dim++) {
    artificial_stress(eps, comp, rho, dim, R);
    for (int k = 0; k < 6; k++) EXPECT_EQ(R[k], 0.0) << "dim " << dim << " " << k;
  }
  // uniaxial tension along x
  const double ux[6] = {sig0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int dim = 2; dim <= 3; dim++) {
    artificial_stress(eps, ux, rho, dim, R);
    EXPECT_NEAR(R[XX], a, 1.0e-12 * fabs(a)) << "dim " << dim;
    for (int k = 1; k < 6; k++)
      EXPECT_NEAR(R[k], 0.0, 1.0e-12 * fabs(a)) << "dim " << dim << " " << k;
  }
  // tension along x, compression along y: only x is corrected
  const double mixed[6] = {sig0, -2.0 * sig0, 0.0, 0.0, 0.0, 0.0};
  for (int dim = 2; dim <= 3; dim++) {
    artificial_stress(eps, mixed, rho, dim, R);
    EXPECT_NEAR(R[XX], a, 1.0e-12 * fabs(a)) << "dim " << dim;
    EXPECT_NEAR(R[YY], 0.0, 1.0e-12 * fabs(a)) << "dim " << dim;
  }
  // 2D: tension along the diagonal n = (1,1)/sqrt2 -> R = a n (x) n
  const double diag2[6] = {0.5 * sig0, 0.5 * sig0, 0.0, 0.5 * sig0, 0.0, 0.0};
  artificial_stress(eps, diag2, rho, 2, R);
  EXPECT_NEAR(R[XX], 0.5 * a, 1.0e-12 * fabs(a));
  EXPECT_NEAR(R[YY], 0.5 * a, 1.0e-12 * fabs(a));
  EXPECT_NEAR(R[XY], 0.5 * a, 1.0e-12 * fabs(a));
  for (int c : {ZZ, XZ, YZ}) EXPECT_NEAR(R[c], 0.0, 1.0e-12 * fabs(a));
  // 2D: tension along (cos t, sin t) plus compression across it
  const double t = 0.4, c = cos(t), s = sin(t);
  const double sg[6] = {sig0 * (c * c - s * s), sig0 * (s * s - c * c), 0.0, 2.0 * sig0 * c * s,
                        0.0, 0.0};
  artificial_stress(eps, sg, rho, 2, R);
  EXPECT_NEAR(R[XX], a * c * c, 1.0e-12 * fabs(a));
  EXPECT_NEAR(R[YY], a * s * s, 1.0e-12 * fabs(a));
  EXPECT_NEAR(R[XY], a * c * s, 1.0e-12 * fabs(a));
  // 3D: tension along (1,1,1)/sqrt3 -> every component a/3
  const double diag3[6] = {sig0 / 3.0, sig0 / 3.0, sig0 / 3.0, sig0 / 3.0, sig0 / 3.0, sig0 / 3.0};
  artificial_stress(eps, diag3, rho, 3, R);
  for (int k = 0; k < 6; k++) EXPECT_NEAR(R[k], a / 3.0, 1.0e-12 * fabs(a)) << k;
}

// every principal stress tensile (or zero): R = -eps sigma / rho^2, taken without the
// eigen-decomposition; the same as the sum over the principal directions up to round-off,
// and a state with one compressive principal stress still goes through the decomposition
TEST(Stabilisation, ArtificialStressAllTensile)
{
  const double eps = 0.3, rho = 7800.0;
  std::mt19937 gen(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; trial++) {
    // sigma = Q diag(l) Q^T with a random rotation (of a random symmetric matrix) and l >= 0,
    // one l = 0 in a quarter of the trials, and l[2] < 0 in every fourth
    double g[6], lg[3], q[9];
    for (int k = 0; k < 6; k++) g[k] = u(gen);
    sym_eigen(g, lg, q);
    double l[3] = {4.0e8 * (1.0 + u(gen)), 3.0e8 * (1.0 + u(gen)), 2.0e8 * (1.0 + u(gen))};
    if (trial % 4 == 1) l[1] = 0.0;
    if (trial % 4 == 3) l[2] = -l[2];
    double sig[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    const int ia[6] = {0, 1, 2, 0, 0, 1}, ib[6] = {0, 1, 2, 1, 2, 2};
    for (int k = 0; k < 6; k++)
      for (int m = 0; m < 3; m++) sig[k] += q[3 * ia[k] + m] * q[3 * ib[k] + m] * l[m];
    double R[6], ref[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    artificial_stress(eps, sig, rho, 3, R);
    for (int k = 0; k < 6; k++)
      for (int m = 0; m < 3; m++)
        if (l[m] > 0.0) ref[k] -= eps * q[3 * ia[k] + m] * q[3 * ib[k] + m] * l[m] / (rho * rho);
    for (int k = 0; k < 6; k++) EXPECT_NEAR(R[k], ref[k], 1.0e-13 * 8.0e8 * eps / (rho * rho)) << trial << " " << k;
  }
}
