// fix heat/fmfs + compute surface/lambda driven through LAMMPS: exactness of the FMFS
// Laplacian, convergence of transient conduction against an analytic solution, lumped
// convection and radiation, Dirichlet steady state, two materials in series, energy
// conservation, surface flags, bad input.  Every test asserts physics against an answer
// known in advance.  Pure conduction runs make all particles rigid (`tool all`) so that no
// mechanics is integrated.
#include "sphcut_test.h"

#include "compute.h"
#include "fix_sph_jc_thermal.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

using LAMMPS_NS::FixSPHJCThermal;
using sphcut_test::Lammps;
using F = FixSPHJCThermal;

namespace {

constexpr double SIGMA_SB = 5.670374419e-8;

std::string sfmt(const char *f, ...)
{
  char buf[1024];
  va_list ap;
  va_start(ap, f);
  vsnprintf(buf, sizeof(buf), f, ap);
  va_end(ap);
  return buf;
}

FixSPHJCThermal *state_fix(Lammps &l, const char *id = "sph")
{
  // the class lives in the plugin: check the style, then cast without RTTI
  LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, id);
  EXPECT_STREQ(f->style, "sph/jc-thermal");
  return static_cast<FixSPHJCThermal *>(f);
}

LAMMPS_NS::Compute *get_compute(Lammps &l, const char *id)
{
  LAMMPS_NS::Compute *c = sphcut::compute_by_id(l.lmp->modify, id);
  EXPECT_NE(c, nullptr);
  return c;
}

// 2D box [xlo,xhi] x [ylo,yhi] (box units) with a square lattice of spacing dx at the origin
void box2d(Lammps &l, const char *boundary, double dx, double xlo, double xhi, double ylo, double yhi,
           int ntypes = 1)
{
  l.cmds({"units si", "dimension 2", std::string("boundary ") + boundary, "atom_style atomic",
          "atom_modify map array", sfmt("lattice sq %.17g", dx),
          sfmt("region box block %.17g %.17g %.17g %.17g %.17g %.17g units box", xlo, xhi, ylo, yhi, -0.5 * dx,
              0.5 * dx),
          sfmt("create_box %d box", ntypes)});
}

int nregion = 0;

// lattice sites in [xlo,xhi] x [ylo,yhi] (inclusive), of type t, optionally into a new group
void atoms2d(Lammps &l, int t, double dx, double xlo, double xhi, double ylo, double yhi,
             const std::string &group = "")
{
  const double e = 0.01 * dx;
  const std::string r = "blk" + std::to_string(nregion++);
  l.cmds({sfmt("region %s block %.17g %.17g %.17g %.17g %.17g %.17g units box", r.c_str(), xlo - e, xhi + e,
              ylo - e, yhi + e, -0.5 * dx, 0.5 * dx),
          sfmt("create_atoms %d region %s", t, r.c_str())});
  if (!group.empty()) l.cmd("group " + group + " region " + r);
}

// group of the lattice sites already created in the given rectangle
void group2d(Lammps &l, const std::string &name, double dx, double xlo, double xhi, double ylo, double yhi)
{
  const double e = 0.01 * dx;
  const std::string r = "grp" + std::to_string(nregion++);
  l.cmds({sfmt("region %s block %.17g %.17g %.17g %.17g INF INF units box", r.c_str(), xlo - e, xhi + e, ylo - e,
              yhi + e),
          "group " + name + " region " + r});
}

std::string material(int t, double rho, double k, double cp)
{
  return sfmt("pair_coeff %d %d rho0 %.17g E 1 nu 0.3 hdx 1.5 k %.17g cp %.17g", t, t, rho, k, cp);
}

double mean_temp(Lammps &l)
{
  auto *fix = state_fix(l);
  double s = 0.0;
  const int n = l.lmp->atom->nlocal;
  for (int i = 0; i < n; i++) s += fix->state[i][F::TEMP];
  return s / n;
}

// least-squares slope of T over x for the particles with lattice column in [c0,c1]
double slope(Lammps &l, double dx, int c0, int c1)
{
  auto *fix = state_fix(l);
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double x = l.lmp->atom->x[i][0];
    const long c = lround(x / dx);
    if (c < c0 || c > c1) continue;
    const double T = fix->state[i][F::TEMP];
    sx += x;
    sy += T;
    sxx += x * x;
    sxy += x * T;
    n++;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}    // namespace

// ---------------------------------------------------------------------------
// 1. Laplacian of a quadratic field through LAMMPS (seed 003 sec. 5.1)

namespace {

// f = x^2 + y^2 on 21 x 21 particles in [-1,1]^2, cubic kernel, h = 1.5 dx, k = rho = cp = 1:
// DTEMP = rho cp dT/dt / (rho cp) = lap f
void laplacian_square(Lammps &l)
{
  box2d(l, "f f p", 0.1, -1.5, 1.5, -1.5, 1.5);
  atoms2d(l, 1, 0.1, -1.0, 1.0, -1.0, 1.0);
  l.cmds({"mass 1 0.01", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0), "variable T0 atom x*x+y*y",
          "fix sph all sph/jc-thermal tool all temp v_T0", "compute surf all surface/lambda"});
}

bool outer_square(const double *x)
{
  return fabs(fabs(x[0]) - 1.0) < 1e-9 || fabs(fabs(x[1]) - 1.0) < 1e-9;
}

}    // namespace

TEST(Laplacian, Quadratic2DFmfsExact)
{
  Lammps l;
  laplacian_square(l);
  // fmfs_lambda 0 forces FMFS at the boundary particles too (seed 003 sec. 5.1)
  l.cmds({"fix heat all heat/fmfs scheme fmfs fmfs_lambda 0 conservative no", "run 0"});
  auto *fix = state_fix(l);
  ASSERT_EQ(l.lmp->atom->nlocal, 441);
  double worst = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) worst = std::max(worst, fabs(fix->state[i][F::DTEMP] - 4.0));
  printf("[ laplacian ] FMFS 21x21, max |lap - 4| = %.3e\n", worst);
  EXPECT_LT(worst, 1e-10);
  EXPECT_DOUBLE_EQ(l.equal("f_heat[6]"), 1.0);    // every particle on FMFS
}

// by default (fmfs_lambda 0.75, the surface threshold of seed 003) the particles with a
// truncated support take Brookshaw even without a surface compute: the outer layer here
TEST(Laplacian, DefaultFmfsLambdaSwitchesOuterLayer)
{
  Lammps l;
  laplacian_square(l);
  l.cmds({"fix heat all heat/fmfs", "run 0"});
  EXPECT_NEAR(l.equal("f_heat[6]"), 361.0 / 441.0, 1e-12);
}

TEST(Laplacian, Quadratic2DBrookshaw)
{
  Lammps l;
  laplacian_square(l);
  l.cmds({"fix heat all heat/fmfs scheme brookshaw", "run 0"});
  auto *fix = state_fix(l);
  double centre = 0.0, lmin = 1e300, lmax = -1e300;
  int ncorner = 0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double *x = l.lmp->atom->x[i];
    const double d = fix->state[i][F::DTEMP];
    lmin = std::min(lmin, d);
    lmax = std::max(lmax, d);
    if (fabs(x[0]) < 1e-9 && fabs(x[1]) < 1e-9) centre = d;
    if (fabs(fabs(x[0]) - 1.0) < 1e-9 && fabs(fabs(x[1]) - 1.0) < 1e-9) {
      ncorner++;
      EXPECT_NEAR(d, -22.12, 0.01 * 22.12) << "corner " << x[0] << " " << x[1];
    }
  }
  printf("[ laplacian ] Brookshaw 21x21: centre %.6f, min %.6f, max %.6f (exact 4)\n", centre, lmin, lmax);
  EXPECT_EQ(ncorner, 4);
  EXPECT_NEAR(centre, 4.027, 0.001);
  EXPECT_DOUBLE_EQ(l.equal("f_heat[6]"), 0.0);
}

// with the surface compute exactly the outer layer (80 of 441) switches to Brookshaw:
// those particles carry the Brookshaw values, the 361 inner ones stay exact
TEST(Laplacian, SurfaceLayerUsesBrookshaw)
{
  Lammps l;
  laplacian_square(l);
  l.cmds({"fix heat all heat/fmfs scheme brookshaw", "run 0"});
  auto *fix = state_fix(l);
  std::map<long, double> brook;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) brook[l.lmp->atom->tag[i]] = fix->state[i][F::DTEMP];
  l.cmds({"unfix heat", "fix heat all heat/fmfs scheme fmfs surface surf conservative no", "run 0"});
  double **flag = get_compute(l, "surf")->array_atom;
  int nflag = 0, nouter = 0;
  double worst_in = 0.0, worst_out = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double *x = l.lmp->atom->x[i];
    const bool outer = outer_square(x);
    const double d = fix->state[i][F::DTEMP];
    nouter += outer;
    nflag += flag[i][1] > 0.5;
    EXPECT_EQ(flag[i][1] > 0.5, outer) << "at " << x[0] << " " << x[1];
    if (outer) worst_out = std::max(worst_out, fabs(d - brook[l.lmp->atom->tag[i]]));
    else worst_in = std::max(worst_in, fabs(d - 4.0));
  }
  const double frac = l.equal("f_heat[6]");
  printf("[ laplacian ] FMFS + surface: %d flagged (outer layer %d), FMFS fraction %.6f (361/441 = %.6f), "
         "inner max |lap - 4| %.2e, outer max |lap - Brookshaw| %.2e\n",
         nflag, nouter, frac, 361.0 / 441.0, worst_in, worst_out);
  EXPECT_EQ(nouter, 80);
  EXPECT_EQ(nflag, 80);
  EXPECT_NEAR(frac, 361.0 / 441.0, 1e-12);
  EXPECT_LT(worst_in, 1e-10);
  EXPECT_LT(worst_out, 1e-12);
}

// 3D: f = (x+y+z)^2 on 11^3 particles in [-1,1]^3: lap f = 6
TEST(Laplacian, Quadratic3DFmfsExact)
{
  Lammps l;
  l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "lattice sc 0.2", "region box block -1.5 1.5 -1.5 1.5 -1.5 1.5 units box", "create_box 1 box",
          "region cube block -1.01 1.01 -1.01 1.01 -1.01 1.01 units box", "create_atoms 1 region cube",
          "mass 1 0.008", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          "variable T0 atom (x+y+z)^2", "fix sph all sph/jc-thermal tool all temp v_T0",
          "fix heat all heat/fmfs fmfs_lambda 0 conservative no", "run 0"});
  ASSERT_EQ(l.lmp->atom->nlocal, 1331);
  auto *fix = state_fix(l);
  double worst = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) worst = std::max(worst, fabs(fix->state[i][F::DTEMP] - 6.0));
  printf("[ laplacian ] FMFS 11^3, max |lap - 6| = %.3e\n", worst);
  EXPECT_LT(worst, 1e-9);
}

// ---------------------------------------------------------------------------
// 2. transient conduction: T = 1 + exp(-2 pi^2 t) sin(pi x) sin(pi y) on [0,1]^2, alpha = 1,
// T = 1 held on the outermost layer (Dirichlet group), t = 0.05, dt = 0.2 dx^2 at every
// resolution (time error O(dx^4)).  FMFS is second order; Brookshaw (inconsistent next to
// the boundary layer) about first order.

namespace {

struct Err {
  double max, rms;
};

Err sine_decay(int n, const char *scheme, double r = 0.2, int every = 1, const char *extra = "")
{
  Lammps l;
  const double dx = 1.0 / (n - 1), tend = 0.05;
  const long nsteps = lround(tend / (r * dx * dx));
  const double dt = tend / nsteps;
  box2d(l, "f f p", dx, -3 * dx, 1 + 3 * dx, -3 * dx, 1 + 3 * dx);
  atoms2d(l, 1, dx, 0.0, 1.0, 0.0, 1.0);
  group2d(l, "inner", dx, dx, 1 - dx, dx, 1 - dx);
  l.cmds({"group edge subtract all inner", sfmt("mass 1 %.17g", dx * dx), "pair_style sph/jc-thermal",
          material(1, 1.0, 1.0, 1.0), "variable T0 atom 1+sin(PI*x)*sin(PI*y)",
          "fix sph all sph/jc-thermal tool all temp v_T0",
          sfmt("fix heat all heat/fmfs scheme %s every %d dirichlet edge 1 %s", scheme, every, extra), sfmt("timestep %.17g", dt),
          sfmt("run %ld", nsteps)});
  auto *fix = state_fix(l);
  const double amp = exp(-2.0 * M_PI * M_PI * tend);
  Err e{0.0, 0.0};
  const int nl = l.lmp->atom->nlocal;
  for (int i = 0; i < nl; i++) {
    const double *x = l.lmp->atom->x[i];
    const double ex = 1.0 + amp * sin(M_PI * x[0]) * sin(M_PI * x[1]);
    const double d = fabs(fix->state[i][F::TEMP] - ex) / amp;
    e.max = std::max(e.max, d);
    e.rms += d * d;
  }
  e.rms = sqrt(e.rms / nl);
  printf("[ conduction ] %-9s %s %2d x %2d, %4ld steps: max error %.4e, rms error %.4e (relative to amplitude)\n",
         scheme, extra, n, n, nsteps, e.max, e.rms);
  return e;
}

}    // namespace

// thermal sub-cycling: holding the conduction rate for N steps lags it by about N dt / 2, an
// error of order N dt / tau relative to the thermal time scale tau.  With a time step far below
// the thermal limit (dt = 0.001 dx^2 here; in the cutting example the mechanics sets dt about
// 1e-5 of the thermal scale) every 10 steps changes the error by little
TEST(Conduction, SubcyclingEvery10)
{
  const Err e1 = sine_decay(21, "fmfs", 0.001, 1, "conservative no");
  const Err e10 = sine_decay(21, "fmfs", 0.001, 10, "conservative no");
  printf("[ conduction ] every 1: max error %.4e, every 10: %.4e\n", e1.max, e10.max);
  EXPECT_LT(e1.max, 1.0e-2);
  EXPECT_LT(fabs(e10.max - e1.max), 0.05 * e1.max);
}

TEST(Conduction, SineDecayConvergence)
{
  const int res[3] = {11, 21, 41};
  Err ef[3], eb[3];
  for (int r = 0; r < 3; r++) ef[r] = sine_decay(res[r], "fmfs", 0.2, 1, "conservative no");
  for (int r = 0; r < 3; r++) eb[r] = sine_decay(res[r], "brookshaw");
  const double of1 = log2(ef[0].max / ef[1].max), of2 = log2(ef[1].max / ef[2].max);
  const double ob1 = log2(eb[0].max / eb[1].max), ob2 = log2(eb[1].max / eb[2].max);
  printf("[ conduction ] order (max error) 11->21, 21->41: FMFS %.3f %.3f, Brookshaw %.3f %.3f\n", of1, of2, ob1,
         ob2);
  printf("[ conduction ] order (rms error) 11->21, 21->41: FMFS %.3f %.3f, Brookshaw %.3f %.3f\n",
         log2(ef[0].rms / ef[1].rms), log2(ef[1].rms / ef[2].rms), log2(eb[0].rms / eb[1].rms),
         log2(eb[1].rms / eb[2].rms));
  EXPECT_GE(of1, 1.8);
  EXPECT_GE(of2, 1.8);
  EXPECT_LT(ef[2].max, 3e-3);
  for (int r = 0; r < 3; r++) EXPECT_TRUE(std::isfinite(eb[r].max) && eb[r].max < 1.0);
  // the default conservative form (pairs exchange with the mean weight): second order in the
  // interior (rms), about first order in the max norm next to the boundary, where the two
  // particles' FMFS weights differ (measured max 3.4e-2, 1.1e-2, 5.0e-3; rms order 1.86, 1.79)
  Err ec[3];
  for (int r = 0; r < 3; r++) ec[r] = sine_decay(res[r], "fmfs");
  const double oc1 = log2(ec[0].rms / ec[1].rms), oc2 = log2(ec[1].rms / ec[2].rms);
  printf("[ conduction ] conservative FMFS: order (rms error) %.3f %.3f, (max error) %.3f %.3f\n", oc1, oc2,
         log2(ec[0].max / ec[1].max), log2(ec[1].max / ec[2].max));
  EXPECT_GE(oc1, 1.7);
  EXPECT_GE(oc2, 1.7);
  EXPECT_LT(ec[2].max, 1.5e-2);
  EXPECT_LT(ec[2].max, 0.5 * eb[2].max);    // still far better than Brookshaw
}

// adaptive time step (fix sph/jc-thermal cfl) with a heat fix: for rigid particles only the
// thermal limit dt = thermal_cfl rho cp h^2 / k applies (h = 1.5 dx = 0.15, rho cp / k = 2);
// without a heat fix there is no limit and the timestep command's value stays.
// (Measured stability limit of the explicit update, hdx 1.5, cubic kernel: thermal_cfl
// ~0.16-0.17 in 2D and 3D, ~0.15 for FMFS in 3D; the lagged-predictor Heun update is stable
// for dt |lambda| < 1 only, half the interval of forward Euler.  0.14 is checked here.)
TEST(Conduction, ThermalTimeStepLimit)
{
  for (const char *tcfl : {"", " thermal_cfl 0.14"}) {
    Lammps l;
    box2d(l, "f f p", 0.1, -1.5, 1.5, -1.5, 1.5);
    atoms2d(l, 1, 0.1, -1.0, 1.0, -1.0, 1.0);
    l.cmds({"mass 1 0.02", "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 2 E 1 nu 0.3 hdx 1.5 k 4 cp 2",
            "variable T0 atom 300+100*(x<0)", std::string("fix sph all sph/jc-thermal tool all temp v_T0 cfl 0.5") + tcfl,
            "fix heat all heat/fmfs scheme brookshaw", "timestep 1", "run 0"});
    const double f = *tcfl ? 0.14 : 0.1;
    const double expect = f * 2.0 * 2.0 * 0.15 * 0.15 / 4.0;
    EXPECT_NEAR(l.equal("f_sph[1]"), expect, 1e-12 * expect);
    l.cmd("run 100");
    auto *fix = state_fix(l);
    double lo = 1e300, hi = -1e300;
    for (int i = 0; i < l.lmp->atom->nlocal; i++) {
      lo = std::min(lo, fix->state[i][F::TEMP]);
      hi = std::max(hi, fix->state[i][F::TEMP]);
    }
    printf("[ conduction ] cfl 0.5%s: dt %.6g (expected %.6g), T after 100 steps in [%.3f, %.3f]\n", tcfl,
           l.equal("f_sph[1]"), expect, lo, hi);
    EXPECT_NEAR(l.equal("f_sph[1]"), expect, 1e-12 * expect);
    EXPECT_GE(lo, 300.0 - 1e-9);    // stable: the maximum principle holds
    EXPECT_LE(hi, 400.0 + 1e-9);
  }
  Lammps l;
  box2d(l, "f f p", 0.1, -1.5, 1.5, -1.5, 1.5);
  atoms2d(l, 1, 0.1, -1.0, 1.0, -1.0, 1.0);
  l.cmds({"mass 1 0.02", "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 2 E 1 nu 0.3 hdx 1.5 k 4 cp 2",
          "fix sph all sph/jc-thermal tool all cfl 0.5", "timestep 1e-3", "run 0"});
  EXPECT_EQ(l.equal("f_sph[1]"), 1e-3);
}

// thermal sub-cycling (fix heat/fmfs every N) holds the conduction rate for N steps: the update
// of a mode dT/dt = -lambda T is then stable for lambda dt < 2/(N + 1) (sphcut_thermal.h
// thermal_dt_limit), so the thermal limit of the adaptive dt shrinks by 2/(N + 1).  Same scene
// as above, every 10: the adaptive dt is 0.1 rho cp h^2/k 2/11 and the run stays within the
// initial range (without the factor the dt was 5.5x larger and the run blew up); a fixed
// timestep exactly at the refusal limit 0.15 rho cp h^2/k 2/11 runs stably; 1 % past it is refused.
TEST(Conduction, SubcyclingTimeStepLimit)
{
  const double base = 2.0 * 2.0 * 0.15 * 0.15 / 4.0;    // rho cp h^2 / k
  const double lim = 0.15 * base * 2.0 / 11.0;
  auto scene = [&](Lammps &l, const std::string &sph, const std::string &ts) {
    box2d(l, "f f p", 0.1, -1.5, 1.5, -1.5, 1.5);
    atoms2d(l, 1, 0.1, -1.0, 1.0, -1.0, 1.0);
    l.cmds({"mass 1 0.02", "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 2 E 1 nu 0.3 hdx 1.5 k 4 cp 2",
            "variable T0 atom 300+100*(x<0)", "fix sph all sph/jc-thermal tool all temp v_T0" + sph,
            "fix heat all heat/fmfs scheme brookshaw every 10", "timestep " + ts});
  };
  auto range = [&](Lammps &l, double &lo, double &hi) {
    auto *fix = state_fix(l);
    lo = 1e300, hi = -1e300;
    for (int i = 0; i < l.lmp->atom->nlocal; i++) {
      lo = std::min(lo, fix->state[i][F::TEMP]);
      hi = std::max(hi, fix->state[i][F::TEMP]);
    }
  };
  {
    Lammps l;
    scene(l, " cfl 0.5", "1");
    l.cmd("run 400");
    double lo, hi;
    range(l, lo, hi);
    const double expect = 0.1 * base * 2.0 / 11.0;
    printf("[ conduction ] every 10, cfl 0.5: dt %.6g (expected %.6g), T after 400 steps in [%.3f, %.3f]\n",
           l.equal("f_sph[1]"), expect, lo, hi);
    EXPECT_NEAR(l.equal("f_sph[1]"), expect, 1e-12 * expect);
    EXPECT_GE(lo, 300.0 - 1e-9);
    EXPECT_LE(hi, 400.0 + 1e-9);
  }
  {
    Lammps l;
    scene(l, "", sfmt("%.17g", lim));
    l.cmd("run 400");
    double lo, hi;
    range(l, lo, hi);
    printf("[ conduction ] every 10, fixed dt at the limit %.6g: T after 400 steps in [%.3f, %.3f]\n", lim, lo, hi);
    EXPECT_GE(lo, 299.0);    // stable (near the limit the update may overshoot slightly)
    EXPECT_LE(hi, 401.0);
  }
  {
    Lammps l;
    scene(l, "", sfmt("%.17g", 1.01 * lim));
    EXPECT_TRUE(l.error_contains("run 10", "exceeds the stable limit"));
  }
}

// ---------------------------------------------------------------------------
// 3. lumped convection and radiation of a thin strip
//
// The strip (20 x 4 particles, dx = 1 mm) is periodic in x and has free top and bottom
// surfaces: the surface compute flags exactly those two rows, 2 nx particles, each with the
// area A_i = V_i^((d-1)/d) = dx, so A = sum A_i = 2 Lx per unit thickness, exactly.  A block
// with corners would not give that: a corner particle is flagged once but borders two faces,
// so sum A_i underestimates the exposed area by about one dx per corner (in 3D edge and
// corner particles likewise), i.e. by ~1/n relative for n particles per side.  Hence the
// periodic strip.  Biot number h L/k = 0.02 (L = half thickness), so the strip is nearly
// isothermal and the loss rate is h A (T - T_inf) with the mean T (surface T lower by ~Bi/3).

namespace {

constexpr int SNX = 20, SNY = 4;
constexpr double SDX = 1e-3, SRHO = 1000.0, SCP = 1.0;

void strip(Lammps &l, double k, const std::string &scheme, const std::string &loss,
           const std::vector<std::string> &groups = {})
{
  box2d(l, "p f p", SDX, 0.0, SNX * SDX, -4 * SDX, (SNY + 3) * SDX);
  atoms2d(l, 1, SDX, 0.0, (SNX - 1) * SDX, 0.0, (SNY - 1) * SDX);
  l.cmds(groups);    // (groups the loss keywords name)
  l.cmds({sfmt("mass 1 %.17g", SRHO * SDX * SDX), "pair_style sph/jc-thermal", material(1, SRHO, k, SCP),
          "fix sph all sph/jc-thermal tool all temp 500", "compute surf all surface/lambda",
          "fix heat all heat/fmfs scheme " + scheme + " surface surf " + loss,
          sfmt("timestep %.17g", 0.1 * SRHO * SCP * (1.5 * SDX) * (1.5 * SDX) / k), "run 0"});
  double **s = get_compute(l, "surf")->array_atom;
  int nflag = 0, nwrong = 0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const long row = lround(l.lmp->atom->x[i][1] / SDX);
    const bool outer = row == 0 || row == SNY - 1;
    nflag += s[i][1] > 0.5;
    nwrong += (s[i][1] > 0.5) != outer;
  }
  EXPECT_EQ(nflag, 2 * SNX);
  EXPECT_EQ(nwrong, 0);
}

// rate of sum m cp T over windows vs the lumped prediction; returns the worst relative error
// of the rate and of the budget (fix heat element idx = heat lost vs drop of element 5)
void lumped_check(Lammps &l, const char *what, int idx, int nwin, int steps, double (*pred)(double),
                  double &worst_rate, double &worst_budget)
{
  const double dt = l.lmp->update->dt;
  double E0 = l.equal("f_heat[5]"), q0 = l.equal(sfmt("f_heat[%d]", idx)), T0 = mean_temp(l);
  worst_rate = worst_budget = 0.0;
  for (int w = 0; w < nwin; w++) {
    l.cmd(sfmt("run %d", steps));
    const double E1 = l.equal("f_heat[5]"), q1 = l.equal(sfmt("f_heat[%d]", idx)), T1 = mean_temp(l);
    const double rate = (E0 - E1) / (steps * dt);
    const double p = 0.5 * (pred(T0) + pred(T1));    // trapezoid over the window
    const double erate = rate / p - 1.0, ebud = ((E0 - E1) - (q1 - q0)) / (q1 - q0);
    printf("[ %s ] steps %4d-%4d: mean T %.3f -> %.3f, -dE/dt %.6g, lumped prediction %.6g (%+.3f %%), "
           "heat lost %.8g vs energy drop %.8g (%+.2e)\n",
           what, w * steps, (w + 1) * steps, T0, T1, rate, p, 100.0 * erate, q1 - q0, E0 - E1, ebud);
    worst_rate = std::max(worst_rate, fabs(erate));
    worst_budget = std::max(worst_budget, fabs(ebud));
    E0 = E1;
    q0 = q1;
    T0 = T1;
  }
}

constexpr double HC = 100.0, TINF = 300.0, EMISS = 0.9;
double conv_rate(double T) { return HC * 2.0 * SNX * SDX * (T - TINF); }
double rad_rate(double T) { return EMISS * SIGMA_SB * 2.0 * SNX * SDX * (pow(T, 4) - pow(TINF, 4)); }

}    // namespace

// scheme brookshaw conserves energy pairwise: the energy drop equals the heat lost to round-off
TEST(Convection, LumpedStripBrookshaw)
{
  Lammps l;
  strip(l, 10.0, "brookshaw", sfmt("convection %g %g", HC, TINF));
  double er, eb;
  lumped_check(l, "convection brookshaw", 1, 3, 150, conv_rate, er, eb);
  EXPECT_LT(er, 0.02);
  EXPECT_LT(eb, 1e-10);
}

TEST(Radiation, LumpedStripBrookshaw)
{
  Lammps l;
  strip(l, 2.0, "brookshaw", sfmt("radiation %g %g", EMISS, TINF));
  double er, eb;
  lumped_check(l, "radiation brookshaw", 2, 3, 200, rad_rate, er, eb);
  EXPECT_LT(er, 0.02);
  EXPECT_LT(eb, 1e-10);
}

// scheme fmfs: the heat the surface particles lose follows h A (T - T_inf)
TEST(Convection, LumpedStripFmfsSurfaceLoss)
{
  Lammps l;
  strip(l, 10.0, "fmfs", sfmt("convection %g %g", HC, TINF));
  const double dt = l.lmp->update->dt;
  const double q0 = l.equal("f_heat[1]"), T0 = mean_temp(l);
  l.cmd("run 150");
  const double q1 = l.equal("f_heat[1]"), T1 = mean_temp(l);
  const double p = 0.5 * (conv_rate(T0) + conv_rate(T1)) * 150 * dt;
  printf("[ convection fmfs ] heat lost %.6g, h A (T - T_inf) dt %.6g (%+.3f %%)\n", q1 - q0, p,
         100.0 * ((q1 - q0) / p - 1.0));
  EXPECT_NEAR((q1 - q0) / p, 1.0, 0.02);
}

// fmfs_lambda 0.95: particles near the surface (truncated support) use Brookshaw too
TEST(Convection, LumpedStripFmfsBufferEnergyBalance)
{
  Lammps l;
  strip(l, 10.0, "fmfs", sfmt("convection %g %g fmfs_lambda 0.95", HC, TINF));
  double er, eb;
  lumped_check(l, "convection fmfs buffer", 1, 3, 150, conv_rate, er, eb);
  EXPECT_LT(er, 0.02);
  EXPECT_LT(eb, 1e-10);
}

// keyword backing: the strip's bottom row (group bottom, SNX particles of area dx) loses
// h_b (T - T_b) dx each to a body in contact, and nothing else leaves (no surface losses):
// -dE/dt = h_b Lx (T - T_b) with the mean T (Bi = h_b L / k = 0.008: the bottom row is cooler
// than the mean by about Bi/2 of T - T_b), and the heat lost, booked in element 1, equals the
// energy drop to round-off.  The same under fix heat/fmfs/kk on host threads, to round-off of the CPU's.
namespace {
constexpr double HB = 100.0, TB = 300.0;
double back_rate(double T) { return HB * SNX * SDX * (T - TB); }
double backing_strip(const std::vector<std::string> &sw, double &er, double &eb)
{
  Lammps l(MPI_COMM_WORLD, sw);
  strip(l, 50.0, "brookshaw", sfmt("backing bottom %g %g", HB, TB),
        {sfmt("region bot block INF INF INF %.17g INF INF units box", 0.5 * SDX), "group bottom region bot"});
  EXPECT_EQ(l.equal("count(bottom)"), SNX);
  lumped_check(l, "backing brookshaw", 1, 3, 150, back_rate, er, eb);
  return mean_temp(l);
}
}    // namespace

TEST(Backing, LumpedStripBottomRow)
{
  double er, eb;
  const double T = backing_strip(sphcut_test::default_switches(), er, eb);
  EXPECT_LT(er, 0.0065);    // measured -0.21 %
  EXPECT_LT(eb, 1e-10);
  EXPECT_LT(T, 500.0);
#ifdef SPHCUT_TEST_HAVE_KOKKOS
  double erk, ebk;
  const double Tk = backing_strip({"-k", "on", "t", "2", "-sf", "kk"}, erk, ebk);
  printf("[ backing ] mean T after 450 steps: CPU %.15g, /kk %.15g\n", T, Tk);
  EXPECT_NEAR(Tk, T, 1e-12 * T);
  EXPECT_LT(ebk, 1e-10);
#endif
}

// the energy balance at the FMFS/Brookshaw seam (issue 11 item 3).  The default conservative
// form exchanges heat pairwise (mean of the two particles' weights): the energy drop equals the
// heat lost to round-off (measured 2e-14), and the loss rate follows h A (T - T_inf) (-0.52 %).
// Per particle (conservative no, the form of seed 003) the FMFS interior delivers the full flux
// k dT/dn towards the surface, the Brookshaw surface particles (truncated support) take up
// only part of it, and the energy falls faster than the heat lost: +15 % on this strip (+18 to
// +21 % on strips of 6, 12 and 24 rows).  Before the conservative default this test failed.
TEST(Convection, LumpedStripFmfsEnergyBalance)
{
  {
    Lammps l;
    strip(l, 10.0, "fmfs", sfmt("convection %g %g", HC, TINF));
    double er, eb;
    lumped_check(l, "convection fmfs", 1, 3, 150, conv_rate, er, eb);
    EXPECT_LT(er, 0.015);
    EXPECT_LT(eb, 1e-10);
  }
  Lammps l;
  strip(l, 10.0, "fmfs", sfmt("convection %g %g conservative no", HC, TINF));
  double er, eb;
  lumped_check(l, "convection fmfs per particle", 1, 1, 150, conv_rate, er, eb);
  EXPECT_GT(eb, 0.1);
}

// ---------------------------------------------------------------------------
// 4. Dirichlet: bar of 21 particles between T = 400 and T = 300 layers, periodic in y,
// from T = 300: the steady state is linear.  FMFS is exact for it; Brookshaw (truncated
// support next to the Dirichlet layers) settles slightly off (printed, loosely bounded).

namespace {

constexpr double BDX = 0.05;
constexpr int BN = 21, BNY = 8;

void bar(Lammps &l, int ntypes = 1)
{
  box2d(l, "f p p", BDX, -3 * BDX, (BN + 2) * BDX, 0.0, BNY * BDX, ntypes);
}

void bar_dirichlet(Lammps &l, const char *scheme, long nsteps, double &worst, const std::string &extra = "")
{
  bar(l);
  atoms2d(l, 1, BDX, 0.0, (BN - 1) * BDX, 0.0, (BNY - 1) * BDX);
  group2d(l, "hot", BDX, 0.0, 0.0, 0.0, (BNY - 1) * BDX);
  group2d(l, "cold", BDX, (BN - 1) * BDX, (BN - 1) * BDX, 0.0, (BNY - 1) * BDX);
  l.cmds({sfmt("mass 1 %.17g", BDX * BDX), "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          "fix sph all sph/jc-thermal tool all temp 300", "compute surf all surface/lambda",
          sfmt("fix heat all heat/fmfs scheme %s surface surf dirichlet hot 400 dirichlet cold 300 %s", scheme,
               extra.c_str()),
          sfmt("timestep %.17g", 0.2 * BDX * BDX), sfmt("run %ld", nsteps)});
  auto *fix = state_fix(l);
  const double L = (BN - 1) * BDX;
  worst = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double ex = 400.0 - 100.0 * l.lmp->atom->x[i][0] / L;
    worst = std::max(worst, fabs(fix->state[i][F::TEMP] - ex) / ex);
  }
}

}    // namespace

TEST(Dirichlet, SteadyLinearProfile)
{
  double wf, wb;
  {
    Lammps l;
    bar_dirichlet(l, "fmfs", 3000, wf);
  }
  {
    Lammps l;
    bar_dirichlet(l, "brookshaw", 3000, wb);
  }
  printf("[ dirichlet ] steady bar, max relative deviation from the linear profile: FMFS %.3e, Brookshaw %.3e\n",
         wf, wb);
  EXPECT_LT(wf, 1e-3);
  EXPECT_LT(wb, 1e-2);
}

// heat through the Dirichlet groups (fix heat element 3) is the energy the clamps put in:
// with the conservative Brookshaw scheme it equals the change of sum m cp T to round-off.
// With convection on the flagged surface (here the two clamped end layers, the bar being
// periodic in y) the budget is dE = element 3 - element 1.
TEST(Dirichlet, ClampHeatEqualsEnergyChange)
{
  for (const char *loss : {"", "convection 5 300"}) {
    Lammps l;
    double w;
    bar_dirichlet(l, "brookshaw", 0, w, loss);
    const double E0 = l.equal("f_heat[5]");
    l.cmd("run 300");
    const double E1 = l.equal("f_heat[5]"), qd = l.equal("f_heat[3]"), qc = l.equal("f_heat[1]");
    printf("[ dirichlet ] %s: 300 steps from T = 300: energy change %.10g, heat through the clamps %.10g, "
           "lost by convection %.6g, budget error %+.2e\n",
           *loss ? loss : "no losses", E1 - E0, qd, qc, (qd - qc - (E1 - E0)) / (E1 - E0));
    EXPECT_GT(E1 - E0, 1.0);
    if (*loss) EXPECT_GT(qc, 0.01 * (E1 - E0));
    else EXPECT_EQ(qc, 0.0);
    EXPECT_NEAR(qd - qc, E1 - E0, 1e-10 * (E1 - E0));
  }
}

// fix heat/fmfs hands fix sph/jc-thermal its rules, which that fix applies in its own passes (the
// held rate added before the corrector, the Dirichlet groups' predicted temperature); deleted, the
// heat fix takes its rules with it: a further run without any heat source leaves every
// temperature as it was (were the rules kept, the held rate would still heat and cool the bar)
TEST(Dirichlet, RulesLeaveWithTheHeatFix)
{
  std::vector<std::vector<std::string>> switches = {{}};
#ifdef SPHCUT_TEST_HAVE_KOKKOS
  switches.push_back({"-k", "on", "t", "2", "-sf", "kk"});
#endif
  for (const auto &sw : switches) {
    Lammps l(MPI_COMM_WORLD, sw);
    double w;
    bar_dirichlet(l, "brookshaw", 50, w);
    auto temps = [&l](double *held) {
      auto *fix = state_fix(l);
      std::map<LAMMPS_NS::tagint, double> t;
      for (int i = 0; i < l.lmp->atom->nlocal; i++) {
        t[l.lmp->atom->tag[i]] = fix->state[i][F::TEMP];
        if (held) *held = std::max(*held, fabs(fix->state[i][F::HELD]));
      }
      return t;
    };
    double held = 0.0;
    const auto before = temps(&held);
    l.cmds({"unfix heat", "run 20"});
    const auto after = temps(nullptr);
    double change = 0.0;
    for (const auto &t : before) change = std::max(change, fabs(after.at(t.first) - t.second));
    printf("[ dirichlet ] %s: held rate up to %.4g K/s, 20 steps without the heat fix change T by %.3g K\n",
           sw.empty() ? "CPU" : "/kk", held, change);
    EXPECT_GT(held, 1.0);
    EXPECT_EQ(change, 0.0);
  }
}

// ---------------------------------------------------------------------------
// 5. two materials in series: k1 = 7.3 (Ti6Al4V) on columns 0-9, k2 = 88 (tool) on 10-20,
// Dirichlet 400 / 300 at the ends, periodic in y.  cp = k (rho = 1) so both have alpha = 1:
// the steady state does not depend on cp, and the transient is fast.  The interface lies
// half way between columns 9 and 10: L1 = 9.5 dx, L2 = 10.5 dx, q = dT / (L1/k1 + L2/k2).

namespace {

constexpr double K1 = 7.3, K2 = 88.0;

void two_blocks(Lammps &l, const char *scheme, bool dirichlet)
{
  bar(l, 2);
  atoms2d(l, 1, BDX, 0.0, 9 * BDX, 0.0, (BNY - 1) * BDX);
  atoms2d(l, 2, BDX, 10 * BDX, (BN - 1) * BDX, 0.0, (BNY - 1) * BDX);
  group2d(l, "hot", BDX, 0.0, 0.0, 0.0, (BNY - 1) * BDX);
  group2d(l, "cold", BDX, (BN - 1) * BDX, (BN - 1) * BDX, 0.0, (BNY - 1) * BDX);
  l.cmds({sfmt("mass * %.17g", BDX * BDX), "pair_style sph/jc-thermal", material(1, 1.0, K1, K1),
          material(2, 1.0, K2, K2), "pair_coeff 1 2 hdx 1.5", "variable T0 atom 300+700*(type==1)",
          "fix sph all sph/jc-thermal tool all temp v_T0",
          sfmt("fix heat all heat/fmfs scheme %s%s", scheme, dirichlet ? " dirichlet hot 400 dirichlet cold 300" : ""),
          sfmt("timestep %.17g", 0.2 * BDX * BDX)});
}

double series_flux(const char *scheme)
{
  Lammps l;
  two_blocks(l, scheme, true);
  l.cmd("run 2500");
  // interior columns, two away from the Dirichlet ends and from the interface
  const double q1 = -K1 * slope(l, BDX, 2, 7), q2 = -K2 * slope(l, BDX, 12, 18);
  const double q = 100.0 / (9.5 * BDX / K1 + 10.5 * BDX / K2);
  printf("[ two materials ] %-9s steady flux from the slopes: block 1 %.2f, block 2 %.2f, series resistance %.2f "
         "(%+.2f %%, %+.2f %%)\n",
         scheme, q1, q2, q, 100.0 * (q1 / q - 1.0), 100.0 * (q2 / q - 1.0));
  EXPECT_NEAR(q1 / q, 1.0, 0.05);
  EXPECT_NEAR(q2 / q, 1.0, 0.05);
  EXPECT_NEAR(q1 / q2, 1.0, 0.01);    // steady: the same flux through both blocks
  return q1;
}

}    // namespace

TEST(TwoMaterials, SeriesFluxFmfs)
{
  series_flux("fmfs");
}

TEST(TwoMaterials, SeriesFluxBrookshaw)
{
  series_flux("brookshaw");
}

// no Dirichlet, no losses, T discontinuous (1000 | 300): Brookshaw with the harmonic-mean
// conductivity moves energy pairwise, sum m cp T (element 5) is conserved to round-off
TEST(TwoMaterials, EnergyConservedBrookshaw)
{
  Lammps l;
  two_blocks(l, "brookshaw", false);
  l.cmd("run 0");
  const double E0 = l.equal("f_heat[5]");
  auto *fix = state_fix(l);
  double tmax0 = -1e300;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) tmax0 = std::max(tmax0, fix->state[i][F::TEMP]);
  l.cmd("run 200");
  const double E1 = l.equal("f_heat[5]");
  double tmax1 = -1e300;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) tmax1 = std::max(tmax1, fix->state[i][F::TEMP]);
  printf("[ two materials ] brookshaw, 200 steps: sum m cp T %.15g -> %.15g (relative change %.2e), "
         "max T %.1f -> %.1f\n",
         E0, E1, (E1 - E0) / E0, tmax0, tmax1);
  EXPECT_LT(tmax1, tmax0 - 50.0);    // heat did flow
  EXPECT_NEAR(E1, E0, 1e-10 * E0);
}

// insulated free block (no losses), T discontinuous: with the surface compute the flagged
// layer (Brookshaw, a zero-flux condition) closes the FMFS interior.  The temperature obeys
// the maximum principle and relaxes to the mean; sum m cp T is not conserved exactly (FMFS is
// not conservative) but drifts little.  (Without the surface compute FMFS has no boundary
// condition at a free surface and this run diverges exponentially, at any time step.)
TEST(Insulated, FmfsWithSurfaceBounded)
{
  Lammps l;
  const double dx = BDX;
  box2d(l, "f f p", dx, -3 * dx, 23 * dx, -3 * dx, 11 * dx);
  atoms2d(l, 1, dx, 0.0, 20 * dx, 0.0, 7 * dx);
  l.cmds({sfmt("mass 1 %.17g", dx * dx), "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          sfmt("variable T0 atom 300+700*(x<%.17g)", 9.5 * dx), "fix sph all sph/jc-thermal tool all temp v_T0",
          "compute surf all surface/lambda", "fix heat all heat/fmfs surface surf",
          sfmt("timestep %.17g", 0.2 * dx * dx), "run 0"});
  const double E0 = l.equal("f_heat[5]");
  double tmin = 1e300, tmax = -1e300;
  for (int k = 0; k < 10; k++) {
    l.cmd("run 100");
    auto *fix = state_fix(l);
    for (int i = 0; i < l.lmp->atom->nlocal; i++) {
      tmin = std::min(tmin, fix->state[i][F::TEMP]);
      tmax = std::max(tmax, fix->state[i][F::TEMP]);
    }
  }
  const double E1 = l.equal("f_heat[5]");
  auto *fix = state_fix(l);
  double lo = 1e300, hi = -1e300;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    lo = std::min(lo, fix->state[i][F::TEMP]);
    hi = std::max(hi, fix->state[i][F::TEMP]);
  }
  printf("[ insulated ] FMFS + surface, 1000 steps: T within [%.3f, %.3f] throughout, final spread %.3f, "
         "sum m cp T relative drift %+.3e\n",
         tmin, tmax, hi - lo, (E1 - E0) / E0);
  EXPECT_GE(tmin, 300.0 - 1e-9);
  EXPECT_LE(tmax, 1000.0 + 1e-9);
  EXPECT_LT(hi - lo, 100.0);    // relaxing towards the mean
  EXPECT_LT(fabs(E1 - E0), 1e-3 * E0);
}

namespace {

struct Bounds {
  double lo0, hi0;      // initial temperature range
  double lo, hi;        // lowest at the end, highest over the run (f_sph[5] every `steps` steps)
  double growth;        // d ln(max T - mean T) / dt over the second half of the run
};

// a frozen n x n lattice (dx = 1, k = rho = cp = 1, h = hdx) with each particle displaced by
// jit U(-1,1) in x and y (U from mt19937_64 with 53 bits, the same sequence on every
// platform), T0 = 300 + 10 x, insulated, FMFS with the surface compute as in the cutting
// example (sw: command-line switches); one run of nchunk * steps steps with time step dt (one run: a negative temperature,
// which anti-diffusion produces, would be reset by the setup of the next)
Bounds jittered_lattice(int n, double hdx, double jit, unsigned seed, double dt, int nchunk, int steps,
                        const std::vector<std::string> &sw = sphcut_test::default_switches())
{
  Lammps l(MPI_COMM_WORLD, sw);
  box2d(l, "f f p", 1.0, -3.0, n + 2.0, -3.0, n + 2.0);
  std::mt19937_64 rng(seed);
  auto u = [&rng]() { return 2.0 * ldexp((double) (rng() >> 11), -53) - 1.0; };
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      const double x = i + jit * u(), y = j + jit * u();
      l.cmd(sfmt("create_atoms 1 single %.17g %.17g 0 units box", x, y));
    }
  const std::string file = "jittered_tmax.txt";
  l.cmds({"mass 1 1", "pair_style sph/jc-thermal",
          sfmt("pair_coeff 1 1 rho0 1 E 1 nu 0.3 hdx %.17g k 1 cp 1", hdx), "variable T0 atom 300+10*x",
          "fix sph all sph/jc-thermal tool all temp v_T0", "compute surf all surface/lambda",
          "fix heat all heat/fmfs surface surf", sfmt("timestep %.17g", dt), "run 0"});
  auto *fix = state_fix(l);
  const int nl = l.lmp->atom->nlocal;
  Bounds b{1e300, -1e300, 1e300, -1e300, 0.0};
  for (int i = 0; i < nl; i++) {
    b.lo0 = std::min(b.lo0, fix->state[i][F::TEMP]);
    b.hi0 = std::max(b.hi0, fix->state[i][F::TEMP]);
  }
  const double mean = l.equal("f_heat[5]") / nl;    // m cp = 1: conserved
  l.cmds({"variable tmx equal f_sph[5]",
          sfmt("fix pr all print %d \"${tmx}\" file %s screen no", steps, file.c_str()),
          sfmt("run %d", nchunk * steps), "unfix pr"});
  std::vector<double> tmax;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') tmax.push_back(std::stod(line));
  EXPECT_EQ((int) tmax.size(), nchunk + 1);
  for (double t : tmax) b.hi = std::max(b.hi, t);
  for (int i = 0; i < nl; i++) b.lo = std::min(b.lo, fix->state[i][F::TEMP]);
  const int k1 = nchunk / 2, k2 = (int) tmax.size() - 1;
  b.growth = log((tmax[k2] - mean) / (tmax[k1] - mean)) / ((k2 - k1) * steps * dt);
  return b;
}

}    // namespace

// Jittered frozen lattices (0.4-0.5 dx): the FMFS weights of a strongly disordered support can
// give a pair i-j of the conservative exchange a conductance of the anti-diffusive sign (these
// two arrangements: 11 of 3623 and 10 of 4786 pairs, down to -47 and -40 times Brookshaw's, all
// around one particle next to the top surface, lambda 0.83 and 0.76, whose second-order system
// is ill-conditioned).  Without the Brookshaw fallback for such pairs (sphcut::conductance_pair)
// the semi-discrete operator has a growing mode, largest eigenvalue 1.95 and 0.27 k/(rho cp h^2)
// (1.154 and 0.121 here): the temperature leaves its initial range and grows exponentially at
// that rate, measured 1.155 at dt and dt/2 alike and 0.121 (the operator, not the explicit
// step).  With it the exchange is a graph Laplacian with nonnegative weights and the
// temperature stays within its initial range (maximum principle; measured: max T never above
// its initial value, the minimum rising, max T - mean T decaying at 0.03 and 0.02).
TEST(Insulated, JitteredLatticeBounded)
{
  struct Case {
    double hdx, jit;
    unsigned seed;
    double dt;
    int nchunk, steps;
  };
  const Case cases[] = {{1.3, 0.4, 7, 0.01, 10, 100}, {1.3, 0.4, 7, 0.005, 10, 200}, {1.5, 0.5, 7, 0.02, 10, 500}};
  for (const Case &c : cases) {
    const Bounds b = jittered_lattice(20, c.hdx, c.jit, c.seed, c.dt, c.nchunk, c.steps);
    printf("[ insulated ] jittered lattice hdx %.1f jit %.1f seed %u dt %.3g, t = %.0f: T0 in [%.3f, %.3f], "
           "max T over the run %.6g, min T at the end %.6g, growth rate of max T - mean T %+.4f\n",
           c.hdx, c.jit, c.seed, c.dt, c.nchunk * c.steps * c.dt, b.lo0, b.hi0, b.hi, b.lo, b.growth);
    EXPECT_GE(b.lo, b.lo0 - 1e-6 * b.hi0);
    EXPECT_LE(b.hi, b.hi0 + 1e-6 * b.hi0);
    EXPECT_LT(b.growth, 0.0);    // relaxing towards the mean
  }
}

#ifdef SPHCUT_TEST_HAVE_KOKKOS
// the same under fix heat/fmfs/kk (Kokkos OpenMP backend): the exchange calls the same
// sphcut::conductance_pair, so the run stays bounded and agrees with the CPU style
TEST(Insulated, JitteredLatticeBoundedKokkos)
{
  const Bounds cpu = jittered_lattice(20, 1.3, 0.4, 7, 0.01, 10, 100);
  const Bounds kk = jittered_lattice(20, 1.3, 0.4, 7, 0.01, 10, 100, {"-k", "on", "t", "2", "-sf", "kk"});
  printf("[ insulated ] jittered lattice under /kk: max T %.9g, min T at the end %.9g (CPU %.9g, %.9g), growth "
         "%+.6f (CPU %+.6f)\n",
         kk.hi, kk.lo, cpu.hi, cpu.lo, kk.growth, cpu.growth);
  EXPECT_LE(kk.hi, kk.hi0 + 1e-6 * kk.hi0);
  EXPECT_GE(kk.lo, kk.lo0 - 1e-6 * kk.hi0);
  EXPECT_NEAR(kk.lo, cpu.lo, 1e-9 * cpu.hi);
  EXPECT_NEAR(kk.growth, cpu.growth, 1e-6);
}
#endif

// fix heat/fmfs computes the surface compute's lambda, flag and normal in its own first pass
// where the compute sees the same neighbours (same group, tool yes); with `tool no` (no tool
// particles here: the same neighbours) the compute runs on its own.  A deforming, cooling
// block (compressed, plastic heating, convection) gives the same temperatures, surface values
// and energy budget both ways.
TEST(Surface, FusedWithHeatFixMatchesStandalone)
{
  std::vector<double> T[2], lam[2], nrm[2];
  double e[2][6];
  for (int k = 0; k < 2; k++) {
    Lammps l;
    l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
            "lattice sc 1e-4", "region box block -4 12 -4 12 -4 12", "create_box 1 box",
            "region blk block -0.01 8.01 -0.01 8.01 -0.01 8.01", "create_atoms 1 region blk",
            "mass 1 $(7800*1e-12)", "variable vz atom -5e4*(z-4e-4)", "velocity all set 0 0 v_vz units box",
            "pair_style sph/jc-thermal",
            "pair_coeff * * rho0 7800 E 200e9 nu 0.3 hdx 1.3 A 350e6 B 275e6 n 0.36 C 0.022 m 1.0 "
            "Tref 300 Tmelt 1800 cp 477 chi 0.9 k 50",
            "variable t0 atom 300+400*(x<4e-4)", "fix sph all sph/jc-thermal temp v_t0",
            std::string("compute surf all surface/lambda") + (k ? " tool no" : ""),
            "fix heat all heat/fmfs surface surf convection 1e6 300", "timestep 5e-9", "run 60"});
    auto *fix = state_fix(l);
    double **s = get_compute(l, "surf")->array_atom;
    const int n = l.lmp->atom->nlocal;
    T[k].assign(n + 1, 0.0);
    lam[k].assign(n + 1, 0.0);
    nrm[k].assign(3 * (n + 1), 0.0);
    for (int i = 0; i < n; i++) {    // by tag (the runs sort alike, but do not rely on it)
      const int t = (int) l.lmp->atom->tag[i];
      T[k][t] = fix->state[i][F::TEMP];
      lam[k][t] = s[i][0];
      for (int a = 0; a < 3; a++) nrm[k][3 * t + a] = s[i][2 + a];
    }
    for (int c = 0; c < 6; c++) e[k][c] = l.equal("f_heat[" + std::to_string(c + 1) + "]");
  }
  double dT = 0.0, dl = 0.0, dn = 0.0, tmax = 0.0;
  for (size_t t = 1; t < T[0].size(); t++) {
    dT = std::max(dT, fabs(T[0][t] - T[1][t]));
    tmax = std::max(tmax, T[0][t]);
    dl = std::max(dl, fabs(lam[0][t] - lam[1][t]));
    for (int a = 0; a < 3; a++) dn = std::max(dn, fabs(nrm[0][3 * t + a] - nrm[1][3 * t + a]));
  }
  printf("[ surface ] fused / standalone compute: |dT| %.3e K (T up to %.2f K), |d lambda| %.3e, |d n| %.3e, "
         "convection %.6g / %.6g J\n", dT, tmax, dl, dn, e[0][0], e[1][0]);
  EXPECT_EQ(T[0].size(), (size_t) 730);
  EXPECT_GT(tmax, 650.0);       // the hot half, still hot
  EXPECT_GT(e[0][0], 0.0);      // convection through the flagged surface
  // the same arithmetic both ways (sphcut_thermal.h): equal to the bit here; round-off bounds
  EXPECT_LT(dT, 1e-12);
  EXPECT_LT(dl, 1e-15);
  EXPECT_LT(dn, 1e-15);
  for (int c = 0; c < 5; c++) EXPECT_NEAR(e[0][c], e[1][c], 1e-14 * (fabs(e[0][c]) + 1e-30)) << c;
}

// ---------------------------------------------------------------------------
// 6. surface flags

TEST(Surface, SquareOuterLayer)
{
  Lammps l;
  laplacian_square(l);
  l.cmds({"compute s2 all surface/lambda threshold 0.5", "run 0"});
  auto *c = get_compute(l, "surf");
  c->compute_peratom();
  double **s = c->array_atom;
  int nflag = 0;
  double lam_outer = 0.0, lam_inner = 1e300, worst_n = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double *x = l.lmp->atom->x[i];
    const bool outer = outer_square(x);
    nflag += s[i][1] > 0.5;
    EXPECT_EQ(s[i][1] > 0.5, outer) << "at " << x[0] << " " << x[1];
    if (outer) lam_outer = std::max(lam_outer, s[i][0]);
    else lam_inner = std::min(lam_inner, s[i][0]);
    // face centre particles: outward normal along the axis
    if (outer && fabs(x[1]) < 1e-9) worst_n = std::max(worst_n, fabs(s[i][2] - (x[0] > 0 ? 1.0 : -1.0)));
    if (outer && fabs(x[0]) < 1e-9) worst_n = std::max(worst_n, fabs(s[i][3] - (x[1] > 0 ? 1.0 : -1.0)));
    if (!outer) EXPECT_EQ(s[i][2] * s[i][2] + s[i][3] * s[i][3], 0.0);    // no normal inside
  }
  printf("[ surface ] square: %d flagged, max lambda outer %.4f, min lambda inner %.4f\n", nflag, lam_outer,
         lam_inner);
  EXPECT_EQ(nflag, 80);
  EXPECT_LT(worst_n, 1e-12);
  // a lower threshold flags fewer particles (the corners have the smallest lambda)
  auto *c2 = get_compute(l, "s2");
  c2->compute_peratom();
  int n2 = 0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) n2 += c2->array_atom[i][1] > 0.5;
  EXPECT_LT(n2, 80);
  EXPECT_GE(n2, 4);
}

TEST(Surface, CubeOuterLayer)
{
  Lammps l;
  l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "lattice sc 0.2", "region box block -1.5 1.5 -1.5 1.5 -1.5 1.5 units box", "create_box 1 box",
          "region cube block -1.01 1.01 -1.01 1.01 -1.01 1.01 units box", "create_atoms 1 region cube",
          "mass 1 0.008", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          "fix sph all sph/jc-thermal tool all", "compute surf all surface/lambda", "run 0"});
  auto *c = get_compute(l, "surf");
  c->compute_peratom();
  int nflag = 0, nouter = 0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double *x = l.lmp->atom->x[i];
    bool outer = false;
    for (int a = 0; a < 3; a++) outer = outer || fabs(fabs(x[a]) - 1.0) < 1e-9;
    nouter += outer;
    nflag += c->array_atom[i][1] > 0.5;
    EXPECT_EQ(c->array_atom[i][1] > 0.5, outer) << "at " << x[0] << " " << x[1] << " " << x[2];
  }
  printf("[ surface ] cube 11^3: %d flagged, outer layer %d\n", nflag, nouter);
  EXPECT_EQ(nouter, 1331 - 729);
  EXPECT_EQ(nflag, nouter);
}

// disk of radius 1 cut from the dx = 0.1 lattice: every rim particle (a lattice neighbour
// outside the disk) is flagged, none deeper than 2 dx, and the normals point outwards
TEST(Surface, DiskRim)
{
  Lammps l;
  const double dx = 0.1;
  box2d(l, "f f p", dx, -1.5, 1.5, -1.5, 1.5);
  l.cmds({"region disk cylinder z 0 0 1.000001 -0.05 0.05 units box", "create_atoms 1 region disk",
          "mass 1 0.01", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          "fix sph all sph/jc-thermal tool all", "compute surf all surface/lambda", "run 0"});
  auto *c = get_compute(l, "surf");
  c->compute_peratom();
  int nrim = 0, rim_flagged = 0, deep_flagged = 0, nflag = 0;
  double min_ndot = 1.0, max_depth = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double *x = l.lmp->atom->x[i];
    const long a = lround(x[0] / dx), b = lround(x[1] / dx);
    auto out = [](long p, long q) { return p * p + q * q > 100; };
    const bool rim = out(a + 1, b) || out(a - 1, b) || out(a, b + 1) || out(a, b - 1);
    const double rad = sqrt(x[0] * x[0] + x[1] * x[1]), depth = 1.0 - rad;
    const bool flag = c->array_atom[i][1] > 0.5;
    nflag += flag;
    if (flag) max_depth = std::max(max_depth, depth);
    if (rim) {
      nrim++;
      rim_flagged += flag;
      min_ndot = std::min(min_ndot, (c->array_atom[i][2] * x[0] + c->array_atom[i][3] * x[1]) / rad);
    }
    if (depth > 2 * dx + 1e-9) deep_flagged += flag;
  }
  printf("[ surface ] disk: %d particles, %d rim, %d rim flagged, %d flagged, deepest flagged %.3f dx, "
         "min n.e_r on the rim %.4f\n",
         l.lmp->atom->nlocal, nrim, rim_flagged, nflag, max_depth / dx, min_ndot);
  EXPECT_GT(nrim, 50);
  EXPECT_EQ(rim_flagged, nrim);
  EXPECT_EQ(deep_flagged, 0);
  EXPECT_GT(min_ndot, 0.9);
}

// a 10 x 10 workpiece block touching a 10 x 10 tool block (gap dx): `tool yes` (default)
// counts tool particles as neighbours, so the contact face is no surface; `tool no` ignores
// them across the workpiece/tool boundary and flags both faces
TEST(Surface, ToolHidesContactFace)
{
  Lammps l;
  const double dx = 0.1;
  box2d(l, "f f p", dx, -0.5, 2.5, -0.5, 1.5);
  atoms2d(l, 1, dx, 0.0, 0.9, 0.0, 0.9);
  atoms2d(l, 1, dx, 1.0, 1.9, 0.0, 0.9, "tool");
  l.cmds({"mass 1 0.01", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          "fix sph all sph/jc-thermal tool tool", "compute sy all surface/lambda tool yes",
          "compute sn all surface/lambda tool no", "run 0"});
  auto *cy = get_compute(l, "sy"), *cn = get_compute(l, "sn");
  cy->compute_peratom();
  cn->compute_peratom();
  int nface = 0, face_yes = 0, face_no = 0, other_diff = 0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) {
    const double *x = l.lmp->atom->x[i];
    const long a = lround(x[0] / dx), b = lround(x[1] / dx);
    const bool fy = cy->array_atom[i][1] > 0.5, fn = cn->array_atom[i][1] > 0.5;
    if ((a == 9 || a == 10) && b > 0 && b < 9) {    // the two contact faces, without the corners
      nface++;
      face_yes += fy;
      face_no += fn;
    } else if (b > 2 && b < 7 && a > 2 && a < 17) {
      other_diff += fy != fn;    // well away from the outer surfaces: never flagged
    }
  }
  printf("[ surface ] contact faces (%d particles): flagged %d with tool yes, %d with tool no\n", nface, face_yes,
         face_no);
  EXPECT_EQ(nface, 16);
  EXPECT_EQ(face_yes, 0);
  EXPECT_EQ(face_no, nface);
  EXPECT_EQ(other_diff, 0);
}

namespace {

struct Snap {
  long step;
  std::vector<std::vector<double>> rows;    // id x y lam1 flag1 lam5 flag5
};

std::vector<Snap> read_dump(const std::string &file)
{
  std::vector<Snap> snaps;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM: TIMESTEP", 0) == 0) {
      snaps.emplace_back();
      std::getline(in, line);
      snaps.back().step = std::stol(line);
    } else if (line.rfind("ITEM: ATOMS", 0) == 0) {
      continue;
    } else if (!snaps.empty() && line.rfind("ITEM:", 0) != 0) {
      std::istringstream ss(line);
      std::vector<double> v;
      double d;
      while (ss >> d) v.push_back(d);
      if (v.size() == 7) snaps.back().rows.push_back(v);
    }
  }
  return snaps;
}

}    // namespace

// `every 5` keeps lambda between recomputes: two rigid blocks approaching each other (no
// reneighboring, big skin) change lambda on the facing faces every step; with every 5 the
// values at step s are those of step 5 floor(s/5)
TEST(Surface, EveryKeepsValuesBetweenRecomputes)
{
  Lammps l;
  const double dx = 0.1;
  box2d(l, "f f p", dx, -0.5, 3.0, -0.5, 1.5);
  atoms2d(l, 1, dx, 0.0, 0.9, 0.0, 0.9, "a");
  atoms2d(l, 1, dx, 1.3, 2.2, 0.0, 0.9, "b");
  l.cmds({"mass 1 0.01", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0), "neighbor 0.5 bin",
          "neigh_modify every 1 delay 0 check yes", "fix sph all sph/jc-thermal tool all",
          "velocity b set -1.0 0 0 units box", "timestep 0.01", "compute s1 all surface/lambda",
          "compute s5 all surface/lambda every 5",
          "dump d all custom 1 every_keep.dump id x y c_s1[1] c_s1[2] c_s5[1] c_s5[2]",
          "dump_modify d format float %.17g", "run 20"});
  EXPECT_EQ(l.lmp->neighbor->ncalls, 0);    // no reneighboring during the run
  l.cmd("undump d");
  auto snaps = read_dump("every_keep.dump");
  ASSERT_EQ(snaps.size(), 21u);
  std::map<long, std::map<long, double>> lam1;    // step -> id -> lambda (every 1)
  for (auto &s : snaps)
    for (auto &r : s.rows) lam1[s.step][lround(r[0])] = r[3];
  int nchanged = 0, nbad = 0;
  for (auto &s : snaps) {
    const long s0 = 5 * (s.step / 5);
    for (auto &r : s.rows) {
      const long id = lround(r[0]);
      if (r[5] != lam1[s0][id]) nbad++;
      if (r[3] != lam1[s0][id]) nchanged++;
    }
  }
  printf("[ surface ] every 5 vs every 1 over 20 steps: %d lambda values changed between recomputes, "
         "%d every-5 values differ from the last recompute\n",
         nchanged, nbad);
  EXPECT_GT(nchanged, 20);    // the test is sensitive: lambda does change between recomputes
  EXPECT_EQ(nbad, 0);
}

// `every 5` after reneighboring: a static and a moving block, atoms re-sorted at every
// neighbor list build (which reorders the local arrays); the kept flags must still belong to
// the right atoms
TEST(Surface, EveryAlignedAfterReneighboring)
{
  Lammps l;
  const double dx = 0.1;
  box2d(l, "f f p", dx, -0.5, 3.0, -0.5, 3.0);
  atoms2d(l, 1, dx, 0.0, 0.9, 0.0, 0.9, "a");
  atoms2d(l, 1, dx, 1.5, 2.4, 0.0, 0.9, "b");
  l.cmds({"mass 1 0.01", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0), "neighbor 0.02 bin",
          "neigh_modify every 1 delay 0 check yes", "atom_modify sort 1 0.05", "fix sph all sph/jc-thermal tool all",
          "velocity b set 0 1.0 0 units box", "timestep 0.007", "compute s1 all surface/lambda",
          "compute s5 all surface/lambda every 5",
          "dump d all custom 1 every_align.dump id x y c_s1[1] c_s1[2] c_s5[1] c_s5[2]",
          "dump_modify d format float %.17g"});
  std::vector<long> tags0(l.lmp->atom->tag, l.lmp->atom->tag + l.lmp->atom->nlocal);
  l.cmd("run 60");
  const long nbuild = l.lmp->neighbor->ncalls;
  std::vector<long> tags1(l.lmp->atom->tag, l.lmp->atom->tag + l.lmp->atom->nlocal);
  l.cmd("undump d");
  auto snaps = read_dump("every_align.dump");
  ASSERT_EQ(snaps.size(), 61u);
  int nbad = 0, nflag = 0;
  for (auto &s : snaps)
    for (auto &r : s.rows) {
      // outer layer of its block (block b moves in y only)
      const double x = r[1], y = r[2];
      const bool ina = x < 1.2;
      const double x0 = ina ? 0.0 : 1.5, y0 = ina ? 0.0 : 0.007 * s.step;
      const long a = lround((x - x0) / dx), b = lround((y - y0) / dx);
      const bool outer = a == 0 || a == 9 || b == 0 || b == 9;
      nflag += r[6] > 0.5;
      if ((r[6] > 0.5) != outer || (r[4] > 0.5) != outer || fabs(r[5] - r[3]) > 1e-9) nbad++;
    }
  printf("[ surface ] every 5 with %ld neighbor builds in 60 steps, atom order %s: %d mismatches\n", nbuild,
         tags0 == tags1 ? "unchanged" : "changed", nbad);
  EXPECT_GT(nbuild, 10);
  EXPECT_NE(tags0, tags1);    // the sort did reorder the atoms
  EXPECT_EQ(nflag, 61 * 72);
  EXPECT_EQ(nbad, 0);
}

// a second run starts at the time step the first ended on and rebuilds the neighbor lists in
// its setup; whatever changed in between (here displace_atoms brings block b into contact
// with block a) must show in the flags that fix heat/fmfs uses in that setup.  With
// reneighboring on the last step of the first run the compute used to keep its old values.
TEST(Surface, RecomputedInSetupOfNextRun)
{
  Lammps l;
  const double dx = 0.1;
  box2d(l, "f f p", dx, -0.5, 3.0, -0.5, 1.5);
  atoms2d(l, 1, dx, 0.0, 0.9, 0.0, 0.9, "a");
  atoms2d(l, 1, dx, 1.4, 2.3, 0.0, 0.9, "b");
  l.cmds({"mass 1 0.01", "pair_style sph/jc-thermal", material(1, 1.0, 1.0, 1.0),
          "neigh_modify every 1 delay 0 check no", "fix sph all sph/jc-thermal tool all",
          "compute surf all surface/lambda", "fix heat all heat/fmfs surface surf", "run 1"});
  auto count_face = [&](int &face, int &flagged) {
    double **s = get_compute(l, "surf")->array_atom;
    face = flagged = 0;
    for (int i = 0; i < l.lmp->atom->nlocal; i++) {
      const double *x = l.lmp->atom->x[i];
      const long b = lround(x[1] / dx);
      if (fabs(x[0] - 0.9) < 1e-9 && b > 0 && b < 9) {    // right face of block a, no corners
        face++;
        flagged += s[i][1] > 0.5;
      }
    }
  };
  int face, before, after;
  count_face(face, before);
  l.cmds({"displace_atoms b move -0.4 0 0 units box", "run 0"});
  count_face(face, after);
  printf("[ surface ] face of block a: %d of %d flagged apart, %d flagged in contact after the next setup\n",
         before, face, after);
  EXPECT_EQ(face, 8);
  EXPECT_EQ(before, 8);
  EXPECT_EQ(after, 0);
}

// ---------------------------------------------------------------------------
// 7. bad input

namespace {

void small_setup(Lammps &l, const std::string &coeff = "")
{
  box2d(l, "f f p", 0.1, -0.5, 1.5, -0.5, 1.5);
  atoms2d(l, 1, 0.1, 0.0, 0.5, 0.0, 0.5);
  l.cmds({"mass 1 0.01", "pair_style sph/jc-thermal",
          coeff.empty() ? material(1, 1.0, 1.0, 1.0) : coeff});
}

}    // namespace

TEST(BadInput, HeatFix)
{
  Lammps l;
  small_setup(l);
  l.cmds({"fix sph all sph/jc-thermal tool all", "compute surf all surface/lambda"});
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs colour red", "Fix heat/fmfs: unknown keyword colour"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs scheme sph", "unknown scheme sph (fmfs, brookshaw)"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs every 0", "every must be >= 1, got 0"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs convection 10 300",
                               "convection and radiation need a surface compute (keyword surface)"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs radiation 0.5 300",
                               "convection and radiation need a surface compute"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs surface surf radiation -0.1 300",
                               "emissivity must be in [0,1], got -0.1"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs surface surf convection -5 300",
                               "convection coefficient must be >= 0, got -5"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs dirichlet nogroup 300",
                               "dirichlet group nogroup does not exist"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs dirichlet all", "keyword dirichlet needs 2 value(s)"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs backing nogroup 100 300", "backing group nogroup does not exist"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs backing all 100", "keyword backing needs 3 value(s)"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs backing all -2 300", "backing coefficient must be >= 0, got -2"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs backing all 2 -300", "backing temperature must be >= 0, got -300"));
  EXPECT_TRUE(l.error_contains("fix heat all heat/fmfs dirichlet all -1", "dirichlet temperature must be >= 0"));
  l.cmd("fix heat all heat/fmfs surface nosuch");
  EXPECT_TRUE(l.error_contains("run 0", "surface compute nosuch does not exist"));
}

TEST(BadInput, HeatFixBeforeStateFix)
{
  Lammps l;
  small_setup(l);
  l.cmds({"fix heat all heat/fmfs", "fix sph all sph/jc-thermal tool all"});
  EXPECT_TRUE(l.error_contains("run 0", "Fix heat/fmfs must be defined after fix sph/jc-thermal"));
}

TEST(BadInput, ConductorWithoutCp)
{
  Lammps l;
  small_setup(l, "pair_coeff 1 1 rho0 1 E 1 nu 0.3 hdx 1.5 k 5");
  l.cmds({"fix sph all sph/jc-thermal tool all", "fix heat all heat/fmfs"});
  EXPECT_TRUE(l.error_contains("run 0", "Fix heat/fmfs: atom type 1 conducts (k > 0) but has no cp"));
}

TEST(BadInput, SurfaceCompute)
{
  Lammps l;
  small_setup(l);
  l.cmd("fix sph all sph/jc-thermal tool all");
  EXPECT_TRUE(l.error_contains("compute s all surface/lambda threshold 1.5",
                               "Compute surface/lambda: threshold must be in (0,1), got 1.5"));
  EXPECT_TRUE(l.error_contains("compute s all surface/lambda every 0",
                               "Compute surface/lambda: every must be >= 1, got 0"));
  EXPECT_TRUE(l.error_contains("compute s all surface/lambda tool maybe", "tool must be yes or no, got maybe"));
  EXPECT_TRUE(l.error_contains("compute s all surface/lambda every", "keyword every needs a value"));
  EXPECT_TRUE(l.error_contains("compute s all surface/lambda colour red", "unknown keyword colour"));
}

// the thermal energy (element 5) needs the state fix: asked for before the first run it is an
// error, not a crash
TEST(BadInput, HeatVectorBeforeFirstRun)
{
  Lammps l;
  small_setup(l);
  l.cmds({"fix sph all sph/jc-thermal tool all", "fix heat all heat/fmfs"});
  EXPECT_TRUE(l.error_contains("print \"$(f_heat[5])\"", "Fix heat/fmfs"));
}
