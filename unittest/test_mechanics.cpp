// pair sph/jc-thermal + fix sph/jc-thermal: patch tests, elastic wave speed, oscillating
// plate, and bad input.  Each test asserts physics against an analytic answer.
#include "sphcut_test.h"

#include "fix_sph_jc_thermal.h"
#include "force.h"
#include "pair.h"
#include "pair_sph_jc_thermal.h"
#include "update.h"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <sstream>

using LAMMPS_NS::FixSPHJCThermal;
using sphcut_test::Lammps;
using F = FixSPHJCThermal;

namespace {

FixSPHJCThermal *state_fix(Lammps &l, const char *id = "sph")
{
  // the class lives in the plugin: check the style, then cast without RTTI
  LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, id);
  EXPECT_EQ(std::string(f->style).rfind("sph/jc-thermal", 0), 0u) << f->style;    // or sph/jc-thermal/kk
  return static_cast<FixSPHJCThermal *>(f);
}

// 2D square block of nx x ny particles, spacing dx, centred at the origin, elastic material
void block2d(Lammps &l, int nx, int ny, double dx, const std::string &extra = "")
{
  const double rho = 7800.0;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "lattice sq " + std::to_string(dx),
          "region box block " + std::to_string(-nx) + " " + std::to_string(nx) + " " +
              std::to_string(-ny) + " " + std::to_string(ny) + " -0.5 0.5",
          "create_box 1 box",
          "region blk block " + std::to_string(-0.5 * (nx - 1) - 0.01) + " " +
              std::to_string(0.5 * (nx - 1) + 0.01) + " " + std::to_string(-0.5 * (ny - 1) - 0.01) + " " +
              std::to_string(0.5 * (ny - 1) + 0.01) + " -0.5 0.5",
          "create_atoms 1 region blk",
          "mass 1 " + std::to_string(rho * dx * dx),
          "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 alpha 1.0 beta 1.0 " + extra,
          "fix sph all sph/jc-thermal", "timestep 1e-9"});
}

}    // namespace

// rigid translation: no density or stress rate anywhere, and after 200 steps the state is unchanged
TEST(Patch, RigidTranslation2D)
{
  Lammps l;
  block2d(l, 12, 8, 1.0e-3);
  // atoms sorted at every reneighbouring: follow one atom by its id, not its index
  l.cmds({"atom_modify sort 1 0.0", "velocity all set 3.0 -2.0 0.0 units box", "run 0"});
  auto *fix = state_fix(l);
  const int n = l.lmp->atom->nlocal;
  for (int i = 0; i < n; i++) {
    EXPECT_EQ(fix->state[i][F::DRHO], 0.0);
    for (int k = 0; k < 6; k++) EXPECT_EQ(fix->state[i][F::DS + k], 0.0);
  }
  const int id = 1 + n / 2;
  const double x0[2] = {l.lmp->atom->x[l.lmp->atom->map(id)][0], l.lmp->atom->x[l.lmp->atom->map(id)][1]};
  l.cmd("run 200");
  const double t = 200 * 1e-9;
  for (int i = 0; i < n; i++) {
    EXPECT_NEAR(fix->state[i][F::RHO], 7800.0, 1e-9);
    EXPECT_NEAR(fix->state[i][F::VM], 0.0, 1e-6);
    EXPECT_NEAR(l.lmp->atom->v[i][0], 3.0, 1e-9);
  }
  const int i0 = l.lmp->atom->map(id);
  EXPECT_NEAR(l.lmp->atom->x[i0][0] - x0[0], 3.0 * t, 1e-12);
  EXPECT_NEAR(l.lmp->atom->x[i0][1] - x0[1], -2.0 * t, 1e-12);
}

// rigid rotation of a pre-stressed block: no strain rate (drho = 0, symmetric part of L = 0);
// the stress rate is exactly the Jaumann rotation W s - s W at every particle, surface included
// an atom created at rest between runs, after the first run made the force state valid: its
// force state (density, stress, temperature of the force evaluation) is set at the next setup
// like that of the others; before, an atom at rest kept the zero row (its velocity equalled the
// row's end-of-step velocity 0) and the setup's forces were not a number (density 0)
TEST(Patch, AtomCreatedAtRestBetweenRuns)
{
  Lammps l;
  block2d(l, 12, 8, 1.0e-3);
  l.cmds({"velocity all set 3.0 0.0 0.0 units box", "run 20"});
  // one spacing beside the block's last column (x 5.5 mm), within the kernel support
  l.cmds({"create_atoms 1 single 6.5e-3 0.5e-3 0.0 units box", "run 5"});
  auto *fix = state_fix(l);
  const int n = l.lmp->atom->nlocal;
  int bad = 0;
  for (int i = 0; i < n; i++) {
    for (int d = 0; d < 2; d++)
      if (!std::isfinite(l.lmp->atom->v[i][d]) || !std::isfinite(l.lmp->atom->f[i][d])) bad++;
    if (!std::isfinite(fix->state[i][F::RHO]) || fix->state[i][F::RHO] < 7000.0) bad++;
  }
  EXPECT_EQ(bad, 0);
}

TEST(Patch, RigidRotationJaumannOnly2D)
{
  Lammps l;
  block2d(l, 12, 8, 1.0e-3);
  const double omega = 50.0, s0 = 1.0e8, sxy = 2.0e7;
  l.cmds({"variable vx atom -" + std::to_string(omega) + "*y", "variable vy atom " + std::to_string(omega) + "*x",
          "velocity all set v_vx v_vy 0.0 units box", "run 0 post no"});
  auto *fix = state_fix(l);
  const int n = l.lmp->atom->nlocal;
  // set a deviatoric stress sxx = s0, syy = -s0, sxy, recompute the rates from it
  for (int i = 0; i < n; i++) {
    double *s = fix->state[i];
    s[F::SXX] = s[F::SF] = s0;
    s[F::SYY] = s[F::SF + 1] = -s0;
    s[F::SXY] = s[F::SF + 3] = sxy;
  }
  l.cmd("run 0 post no");
  // W = [[0, -omega], [omega, 0]] (L_xy = dvx/dy = -omega): (W s - s W)
  const double dxx = -2.0 * omega * sxy;    // (Ws - sW)_xx = 2 W_xy s_xy
  const double dyy = 2.0 * omega * sxy;
  const double dxy = omega * (s0 - (-s0));    // W_yx s_xx - s_yy W_yx ... = omega (sxx - syy)
  for (int i = 0; i < n; i++) {
    const double *s = fix->state[i];
    EXPECT_NEAR(s[F::DRHO], 0.0, 1e-9 * 7800.0 * omega);
    EXPECT_NEAR(s[F::DS + 0], dxx, 1e-8 * s0 * omega);
    EXPECT_NEAR(s[F::DS + 1], dyy, 1e-8 * s0 * omega);
    EXPECT_NEAR(s[F::DS + 2], 0.0, 1e-8 * s0 * omega);
    EXPECT_NEAR(s[F::DS + 3], dxy, 1e-8 * s0 * omega);
  }
}

// without the renormalisation the surface particles see a spurious strain rate: the
// correction is what makes the patch test pass (guards against dropping it by accident)
TEST(Patch, RotationWithoutCorrectionIsWrongAtSurface)
{
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "lattice sq 1e-3", "region box block -12 12 -8 8 -0.5 0.5", "create_box 1 box",
          "region blk block -5.51 5.51 -3.51 3.51 -0.5 0.5", "create_atoms 1 region blk",
          "mass 1 0.0078", "pair_style sph/jc-thermal correction no",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal",
          "timestep 1e-9", "variable vx atom -50*y", "variable vy atom 50*x", "velocity all set v_vx v_vy 0.0 units box",
          "run 0"});
  auto *fix = state_fix(l);
  double maxds = 0.0;
  for (int i = 0; i < l.lmp->atom->nlocal; i++) maxds = std::max(maxds, fabs(fix->state[i][F::DS + 3]));
  EXPECT_GT(maxds, 1.0e6);    // 2 G D_xy with D_xy = O(omega) at the corners
}

// longitudinal (P) wave in a laterally periodic strip: c = sqrt((K + 4G/3)/rho) within 0.75 %
// (3x the measured +0.24 %)
TEST(Elastic, LongitudinalWaveSpeed2D)
{
  Lammps l;
  const int nx = 40, ny = 4;
  const double dx = 1.0e-3, E = 200e9, nu = 0.3, rho = 7800.0;
  const double K = E / (3 * (1 - 2 * nu)), G = E / (2 * (1 + nu));
  const double c = sqrt((K + 4 * G / 3) / rho);
  const double lx = nx * dx;
  l.cmds({"units si", "dimension 2", "boundary p p p", "atom_style atomic", "atom_modify map array",
          "lattice sq " + std::to_string(dx), "region box block 0 40 0 4 -0.5 0.5", "create_box 1 box",
          "create_atoms 1 box", "mass 1 " + std::to_string(rho * dx * dx), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 alpha 0.0 beta 0.0 as_eps 0.0 xsph 0.0",
          "fix sph all sph/jc-thermal cfl 0.2",
          "variable vx atom 0.01*cos(2*PI*x/" + std::to_string(lx) + ")", "velocity all set v_vx 0 0 units box",
          "run 0"});
  // standing wave v = A cos(kx) cos(wt): the velocity at x = 0 crosses zero at T/4 and 3T/4
  const int id = 1;    // atom at x = 0
  double tprev = 0.0, vprev = 0.01, cross[2] = {0, 0};
  int nc = 0;
  const double tend = 1.2 * lx / c;
  while (nc < 2 && l.lmp->update->atime + 1e-30 < tend) {
    l.cmd("run 5 pre no post no");
    const double t = l.lmp->update->atime + (l.lmp->update->ntimestep - l.lmp->update->atimestep) * l.lmp->update->dt;
    const double v = l.lmp->atom->v[l.lmp->atom->map(id)][0];
    if (v * vprev < 0.0) cross[nc++] = tprev + (t - tprev) * vprev / (vprev - v);
    tprev = t;
    vprev = v;
  }
  ASSERT_EQ(nc, 2);
  const double period = 2.0 * (cross[1] - cross[0]);
  const double csph = lx / period;
  std::printf("[ wave     ] c_sph = %.2f m/s, theory %.2f m/s (%+.3f %%)\n", csph, c, 100 * (csph - c) / c);
  EXPECT_NEAR(csph, c, 0.0075 * c);    // measured +0.24 %
}

// bad input: each a LAMMPS error with a message naming the problem
TEST(BadInput, PairAndFix)
{
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "lattice sq 1e-3",
          "region box block 0 4 0 4 -0.5 0.5", "create_box 1 box", "create_atoms 1 box", "mass 1 0.0078",
          "pair_style sph/jc-thermal"});
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 colour red",
                               "unknown pair_coeff keyword colour"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 nu 0.3 h 1e-3", "material value E is missing"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h -1e-3", "h must be > 0, got -0.001"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.6 h 1e-3", "nu must be in (-1,0.5), got 0.6"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 A 1e8 n 0.3",
                               "Johnson-Cook value B is missing"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 A 1e8 B 1e8 n 0.3",
                               "cp is missing"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 eos ideal", "unknown eos ideal"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 abc E 200e9 nu 0.3 h 1e-3", "abc"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 A 1e8 B 1e8 n 0.3 C -0.1 chi 0",
                               "C must be >= 0, got -0.1"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 gamma0 2.0",
                               "gamma0 and s are Mie-Grueneisen values"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 pmin 4e9",
                               "pmin must be < 0 (a tensile pressure) or none, got 4e9"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 pmin 0",
                               "pmin must be < 0 (a tensile pressure) or none, got 0"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 pmin -4GPa",
                               "pmin must be a negative pressure or none, got -4GPa"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 pmin", "keyword pmin needs a value"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 pmin -4e9 spall free",
                               "unknown spall free (cutoff, release)"));
  EXPECT_TRUE(l.error_contains("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1e-3 spall release",
                               "spall release needs a pressure cutoff (pmin < 0) in pair_coeff 1 1"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal dtmax 1e-9", "dtmax and dtmin need the adaptive time step"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal dtevery 10", "dtevery 10 needs the adaptive time step"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal cfl 0.3 dtevery 0", "dtevery must be >= 1, got 0"));
  l.cmd("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1.3e-3");
  EXPECT_TRUE(l.error_contains("run 0", "requires fix sph/jc-thermal"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal temp -5", "temp must be >= 0, got -5"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal cfl", "keyword cfl needs a value"));
}

/* pressure cutoff (pair_coeff keyword pmin): a block at uniform density rho, without deviatoric
   or artificial stress (as_eps 0), carries the uniform stress -p I.  Stretched 2 % (p_EOS =
   -0.02 K = -3.33 GPa) with pmin -1 GPa, the PRESS column is pmin and every force (the surface
   particles' traction; f is linear in a uniform p) is that of p_EOS scaled by pmin/p_EOS;
   stretched 0.3 % (p_EOS = -0.5 GPa, above pmin) the state and forces are those without pmin,
   bit for bit.  Under /kk (test_mechanics_kk) the same. */
TEST(PressureCutoff, StretchedBlock)
{
  const double rho0 = 7800.0, K = 200e9 / (3 * (1 - 2 * 0.3));
  struct Result {
    std::vector<double> press, fx, fy;
  };
  auto stretched = [&](const std::string &pmin, double strain) {
    Lammps l;
    block2d(l, 12, 8, 1.0e-3, "as_eps 0.0" + (pmin.empty() ? std::string() : " pmin " + pmin));
    l.cmd("run 0 post no");
    auto *fix = state_fix(l);
    auto *atom = l.lmp->atom;
    for (int i = 0; i < atom->nlocal; i++) fix->state[i][F::RHO] = fix->state[i][F::RHO_F] = rho0 * (1.0 - strain);
    l.cmd("run 0 post no");
    Result r;
    r.press.resize(atom->natoms);
    r.fx.resize(atom->natoms);
    r.fy.resize(atom->natoms);
    for (int i = 0; i < atom->nlocal; i++) {
      const int t = atom->tag[i] - 1;
      r.press[t] = fix->state[i][F::PRESS];
      r.fx[t] = atom->f[i][0];
      r.fy[t] = atom->f[i][1];
    }
    return r;
  };
  const double p_eos = -0.02 * K;
  const Result none = stretched("", 0.02), cut = stretched("-1e9", 0.02);
  ASSERT_EQ(none.press.size(), 77u);    // 11 x 7
  double fmax = 0.0;
  for (size_t t = 0; t < none.fx.size(); t++) fmax = std::max(fmax, std::hypot(none.fx[t], none.fy[t]));
  ASSERT_GT(fmax, 0.0);
  for (size_t t = 0; t < none.press.size(); t++) {
    EXPECT_NEAR(none.press[t], p_eos, 1e-9 * K);
    EXPECT_EQ(cut.press[t], -1.0e9) << "atom " << t + 1;
    EXPECT_NEAR(cut.fx[t], none.fx[t] * (-1.0e9 / p_eos), 1e-12 * fmax) << "atom " << t + 1;
    EXPECT_NEAR(cut.fy[t], none.fy[t] * (-1.0e9 / p_eos), 1e-12 * fmax) << "atom " << t + 1;
  }
  // above pmin: the EOS
  // (forces to round-off: under /kk with threads the sums' order varies between runs)
  const Result none3 = stretched("", 0.003), cut3 = stretched("-1e9", 0.003);
  double fmax3 = 0.0;
  for (size_t t = 0; t < none3.fx.size(); t++) fmax3 = std::max(fmax3, std::hypot(none3.fx[t], none3.fy[t]));
  for (size_t t = 0; t < none3.press.size(); t++) {
    EXPECT_NEAR(none3.press[t], -0.003 * K, 1e-9 * K);
    EXPECT_EQ(cut3.press[t], none3.press[t]);
    EXPECT_NEAR(cut3.fx[t], none3.fx[t], 1e-12 * fmax3) << "atom " << t + 1;
    EXPECT_NEAR(cut3.fy[t], none3.fy[t], 1e-12 * fmax3) << "atom " << t + 1;
  }
}

// pmin and spall travel with the restart file, per type; pair_coeff without them (or with pmin none)
// sets no cutoff and spall cutoff
TEST(PressureCutoff, Restart)
{
  {
    Lammps l;
    block2d(l, 6, 4, 1.0e-3, "pmin -2.5e9 spall release");
    l.cmds({"run 0 post no", "write_restart pmin.restart"});
  }
  Lammps l;
  l.cmds({"read_restart pmin.restart", "fix sph all sph/jc-thermal", "run 0 post no"});
  auto *pair = static_cast<LAMMPS_NS::PairSPHJCThermal *>(l.lmp->force->pair);
  EXPECT_EQ(pair->model().materials()[1].pmin, -2.5e9);
  EXPECT_EQ(pair->model().materials()[1].spall, sphcut::SPALL_RELEASE);
  EXPECT_EQ(pair->model().materials()[1].rho0, 7800.0);
  l.cmd("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 pmin none");
  EXPECT_EQ(pair->model().materials()[1].pmin, 0.0);
  EXPECT_EQ(pair->model().materials()[1].spall, sphcut::SPALL_CUTOFF);
  l.cmd("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 pmin -3e9");
  EXPECT_EQ(pair->model().materials()[1].pmin, -3e9);
  l.cmd("pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3");
  EXPECT_EQ(pair->model().materials()[1].pmin, 0.0);
}

/* a restart file of a version before pmin (its material record ends before pmin, the last field)
   reads as no cutoff; a record of any other size is refused.  The pair's restart section is
   written here by hand in the older layout and read with PairSPHJCThermal::read_restart. */
TEST(PressureCutoff, OlderRestartReadsAsNoCutoff)
{
  auto write_old = [](const char *name, int matsize) {
    sphcut::Material m = {};
    m.defined = 1;
    m.rho0 = 4430.0;
    m.E = 113.8e9;
    m.nu = 0.342;
    m.xsph = 0.5;
    m.pmin = -7.0e9;    // not in the older record: must not be read
    FILE *fp = fopen(name, "wb");
    const int neg = -matsize, kernel = 0, corr = 1, setflag = 1;
    const double hourglass = 0.1, h = 1.3e-5, hdx = 1.3;
    fwrite(&neg, sizeof(int), 1, fp);
    fwrite(&kernel, sizeof(int), 1, fp);
    fwrite(&corr, sizeof(int), 1, fp);
    fwrite(&hourglass, sizeof(double), 1, fp);
    fwrite(&m, matsize, 1, fp);
    fwrite(&setflag, sizeof(int), 1, fp);
    fwrite(&h, sizeof(double), 1, fp);
    fwrite(&hdx, sizeof(double), 1, fp);
    fclose(fp);
  };
  const int oldsize = (int) offsetof(sphcut::Material, pmin);
  write_old("pmin-old.restart", oldsize);
  FILE *fp = nullptr;
  {
    Lammps l;
    l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "region box block 0 1 0 1 -0.5 0.5",
            "create_box 1 box", "pair_style sph/jc-thermal"});
    auto *pair = static_cast<LAMMPS_NS::PairSPHJCThermal *>(l.lmp->force->pair);
    fp = fopen("pmin-old.restart", "rb");
    pair->read_restart(fp);
    fclose(fp);
    const sphcut::Material &m = pair->model().materials()[1];
    EXPECT_EQ(m.rho0, 4430.0);
    EXPECT_EQ(m.nu, 0.342);
    EXPECT_EQ(m.xsph, 0.5);
    EXPECT_EQ(m.pmin, 0.0) << "older file: no cutoff";
    EXPECT_EQ(pair->model().hourglass_coefficient(), 0.1);
    EXPECT_EQ(pair->model().smoothing_length(1, 1), 1.3e-5);
  }
  // a record neither of this version nor of the one before
  Lammps l2;
  l2.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "region box block 0 1 0 1 -0.5 0.5",
           "create_box 1 box", "pair_style sph/jc-thermal"});
  write_old("pmin-bad.restart", oldsize - 8);
  fp = fopen("pmin-bad.restart", "rb");
  bool refused = false;
  try {
    static_cast<LAMMPS_NS::PairSPHJCThermal *>(l2.lmp->force->pair)->read_restart(fp);
  } catch (LAMMPS_NS::LAMMPSException &e) {
    refused = std::string(e.what()).find("restart file written by another sphcut version") != std::string::npos;
  }
  fclose(fp);
  EXPECT_TRUE(refused);
}

/* a restart file written by main 863d4de (format 1: the raw material record; its input is
   unittest/data/main-863d4de.in) reads with every value (two materials, one plastic with pmin,
   one Mie-Grueneisen; h of the mixed pair; hourglass) and continues as main continued the same
   run in one process (values printed there with %.17g). */
TEST(RestartFormat, FileOfMainReads)
{
  Lammps l;
#ifdef SPHCUT_TEST_KOKKOS
  l.cmd("package kokkos neigh full newton off");    // the hourglass control of /kk needs the full list
#endif
  l.cmd(std::string("read_restart ") + SPHCUT_SOURCE_DIR + "/unittest/data/main-863d4de.restart");
  l.cmd("fix sph all sph/jc-thermal temp 320");
  auto *pair = static_cast<LAMMPS_NS::PairSPHJCThermal *>(l.lmp->force->pair);
  const sphcut::Material &m1 = pair->model().materials()[1], &m2 = pair->model().materials()[2];
  EXPECT_EQ(m1.A, 862e6);
  EXPECT_EQ(m1.n, 0.34);
  EXPECT_EQ(m1.Tmelt, 1878.0);
  EXPECT_EQ(m1.kappa, 7.0);
  EXPECT_EQ(m1.pmin, -5e9);
  EXPECT_EQ(m1.flow, sphcut::FLOW_JC);
  EXPECT_EQ(m1.plastic, 1);
  EXPECT_EQ(m2.plastic, 0);
  EXPECT_EQ(m2.eos, sphcut::EOS_MIE_GRUNEISEN);
  EXPECT_EQ(m2.gamma0, 1.23);
  EXPECT_EQ(m2.pmin, 0.0);
  EXPECT_EQ(pair->model().hourglass_coefficient(), 0.1);
  l.cmds({"variable x5 equal x[5]", "variable y5 equal y[5]", "variable x17 equal x[17]",
          "variable vy17 equal vy[17]", "variable eps17 equal f_sph[17][10]", "variable t17 equal f_sph[17][12]",
          "variable p5 equal f_sph[5][2]", "thermo 10", "run 20"});
  EXPECT_NEAR(pair->model().smoothing_length(1, 2), 1.4e-4, 1e-20);
  const std::vector<std::pair<std::string, double>> ref = {
      {"v_x5", 9.6280835847073406e-05},    {"v_y5", -0.000207177163227193},  {"v_x17", -9.6334140016671803e-05},
      {"v_vy17", 3.1775873439857101},      {"v_eps17", 0.034000865145451503}, {"v_t17", 332.296413292046},
      {"v_p5", 1026044670.34173}};
  for (const auto &r : ref) EXPECT_NEAR(l.equal(r.first), r.second, 1e-10 * fabs(r.second)) << r.first;
  std::printf("[ main file ] x5 %.3e rel, eps17 %.3e rel, p5 %.3e rel\n",
              fabs(l.equal("v_x5") / ref[0].second - 1.0), fabs(l.equal("v_eps17") / ref[4].second - 1.0),
              fabs(l.equal("v_p5") / ref[6].second - 1.0));
}

/* the field-by-field record: every parameter of the flow tanh law (and the others) survives the
   restart; a record without a field reads its default (a parameter added after the file was
   written); a field or a format this version does not know is refused, naming it. The records
   are written here by hand in format 2 and read with PairSPHJCThermal::read_restart. */
TEST(RestartFormat, FieldByField)
{
  {
    Lammps l;
    block2d(l, 6, 4, 1.0e-3, "A 350e6 B 275e6 n 0.36 Tref 300 Tmelt 1800 cp 477 flow tanh a 2 b 5 c 2 d 1");
    l.cmds({"run 0 post no", "write_restart tanh.restart"});
  }
  {
    Lammps l;
    l.cmds({"read_restart tanh.restart", "fix sph all sph/jc-thermal", "run 0 post no"});
    const sphcut::Material &m = static_cast<LAMMPS_NS::PairSPHJCThermal *>(l.lmp->force->pair)->model().materials()[1];
    EXPECT_EQ(m.flow, sphcut::FLOW_TANH);
    EXPECT_EQ(m.tanh_a, 2.0);
    EXPECT_EQ(m.tanh_b, 5.0);
    EXPECT_EQ(m.tanh_c, 2.0);
    EXPECT_EQ(m.tanh_d, 1.0);
    EXPECT_EQ(m.A, 350e6);
    EXPECT_EQ(m.Tmelt, 1800.0);
    EXPECT_EQ(m.cp, 477.0);
    EXPECT_EQ(m.xsph, 0.5);
    EXPECT_DOUBLE_EQ(m.G, 200e9 / 2.6);    // derived again
  }
  // format 2 by hand: tag, version, kernel, correction, hourglass; per type (count, (length, name,
  // value)...), setflag, h, hdx
  auto write_v2 = [](const char *name, int version, const std::vector<std::pair<std::string, double>> &fields) {
    FILE *fp = fopen(name, "wb");
    const int tag = 0x73706375, kernel = 0, corr = 1, setflag = 1, count = (int) fields.size();
    const double hourglass = 0.0, h = 1.3e-5, hdx = 0.0;
    fwrite(&tag, sizeof(int), 1, fp);
    fwrite(&version, sizeof(int), 1, fp);
    fwrite(&kernel, sizeof(int), 1, fp);
    fwrite(&corr, sizeof(int), 1, fp);
    fwrite(&hourglass, sizeof(double), 1, fp);
    fwrite(&count, sizeof(int), 1, fp);
    for (const auto &f : fields) {
      const int len = (int) f.first.size();
      fwrite(&len, sizeof(int), 1, fp);
      fwrite(f.first.data(), 1, len, fp);
      fwrite(&f.second, sizeof(double), 1, fp);
    }
    fwrite(&setflag, sizeof(int), 1, fp);
    fwrite(&h, sizeof(double), 1, fp);
    fwrite(&hdx, sizeof(double), 1, fp);
    fclose(fp);
  };
  auto read_with = [](const char *name, std::string *err) {
    Lammps l;
    l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "region box block 0 1 0 1 -0.5 0.5",
            "create_box 1 box", "pair_style sph/jc-thermal"});
    auto *pair = static_cast<LAMMPS_NS::PairSPHJCThermal *>(l.lmp->force->pair);
    FILE *fp = fopen(name, "rb");
    sphcut::Material m = {};
    try {
      pair->read_restart(fp);
      m = pair->model().materials()[1];
    } catch (LAMMPS_NS::LAMMPSException &e) {
      *err = e.what();
    }
    fclose(fp);
    return m;
  };
  const std::vector<std::pair<std::string, double>> few = {{"defined", 1}, {"rho0", 4430}, {"E", 113.8e9},
                                                           {"nu", 0.342}, {"chi", 0.0}};
  std::string err;
  write_v2("few.restart", 2, few);
  const sphcut::Material m = read_with("few.restart", &err);
  EXPECT_EQ(err, "");
  EXPECT_EQ(m.rho0, 4430.0);
  EXPECT_EQ(m.chi, 0.0);
  EXPECT_EQ(m.xsph, 0.5) << "missing field: its pair_coeff default";
  EXPECT_EQ(m.Tref, 300.0);
  EXPECT_EQ(m.flow, sphcut::FLOW_JC);
  EXPECT_EQ(m.pmin, 0.0);
  EXPECT_DOUBLE_EQ(m.K, 113.8e9 / (3.0 * (1.0 - 2.0 * 0.342)));
  auto unknown = few;
  unknown.push_back({"zeta", 1.0});
  write_v2("unknown.restart", 2, unknown);
  read_with("unknown.restart", &err);
  EXPECT_NE(err.find("material parameter zeta (format 2) is unknown to this version"), std::string::npos) << err;
  err.clear();
  write_v2("future.restart", 3, few);
  read_with("future.restart", &err);
  EXPECT_NE(err.find("restart file written by another sphcut version (model restart format 3"), std::string::npos)
      << err;
}

// a missing mass command, or per-atom masses left at 0 (fix property/atom rmass without
// set mass): an error naming the cause, not a misleading one (spacing) or NaN forces
TEST(BadInput, MissingOrZeroMass)
{
  const std::vector<std::string> scene = {"units si", "dimension 2", "boundary f f p", "atom_style atomic",
                                          "lattice sq 1e-3", "region box block 0 4 0 4 -0.5 0.5",
                                          "create_box 1 box", "create_atoms 1 box"};
  const std::string coeff = "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3";
  {
    Lammps l;
    l.cmds(scene);
    l.cmds({"pair_style sph/jc-thermal", coeff, "fix sph all sph/jc-thermal"});
    EXPECT_TRUE(l.error_contains("run 0", "Pair sph/jc-thermal: mass of atom type 1 is not set (use the mass command)"));
  }
  {
    Lammps l;
    l.cmds(scene);
    l.cmds({"fix pm all property/atom rmass", "pair_style sph/jc-thermal", coeff, "fix sph all sph/jc-thermal"});
    EXPECT_TRUE(l.error_contains("run 0", "16 atom(s) have a per-atom mass (rmass) <= 0 or not finite, e.g. atom 1 "
                                          "with mass 0"));
    // some set, the others still 0: the count and the first of them
    l.cmd("set atom 1*12 mass 0.0078");
    EXPECT_TRUE(l.error_contains("run 0", "4 atom(s) have a per-atom mass (rmass) <= 0 or not finite, e.g. atom 13"));
    l.cmd("set atom 13*16 mass 0.0078");
#ifdef SPHCUT_TEST_KOKKOS
    // /kk: fix property/atom keeps rmass on the host only (LAMMPS 29Sep2021): refused, by name
    EXPECT_TRUE(l.error_contains("run 0", "the per-atom mass (rmass) has no Kokkos device copy"));
    return;
#endif
    l.cmd("run 0");
    EXPECT_NEAR(l.lmp->force->pair->cutforce, 2.0 * 1.3e-3, 1e-12);    // spacing from rmass: 1 mm
  }
}

TEST(BadInput, UnitsWithConversionFactors)
{
  Lammps l;
  l.cmds({"units metal", "dimension 2", "boundary f f p", "atom_style atomic", "lattice sq 1.0",
          "region box block 0 4 0 4 -0.5 0.5", "create_box 1 box", "create_atoms 1 box", "mass 1 1.0",
          "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 1 E 1 nu 0.3 h 1.3", "fix sph all sph/jc-thermal"});
  EXPECT_TRUE(l.error_contains("run 0", "needs a self-consistent unit style (si, cgs, micro, nano, lj), got metal"));
}

TEST(BadInput, WrongAtomStyle)
{
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style bond", "lattice sq 1e-3",
          "region box block 0 4 0 4 -0.5 0.5", "create_box 1 box bond/types 1 extra/bond/per/atom 2",
          "create_atoms 1 box", "mass 1 0.0078", "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1.3e-3", "bond_style zero", "bond_coeff 1",
          "fix sph all sph/jc-thermal"});
  EXPECT_TRUE(l.error_contains("run 0", "requires an atomic (non-molecular) atom style, got bond"));
}

// oscillating plate (examples/oscillating-plate): first period within 5 % of beam theory,
// kinetic + internal energy drift < 5e-5 over 3 periods with low artificial viscosity (3x the
// measured 1.7e-5)
TEST(Elastic, OscillatingPlate)
{
  Lammps l;
  l.cmds({"variable periods index 3", "variable alpha index 0.1"});
  l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/oscillating-plate/in.plate").c_str());
  std::ifstream in("plate.dat");
  std::string line;
  std::vector<double> t, d, e;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double step, tt, dd, ek, ei, et;
    ss >> step >> tt >> dd >> ek >> ei >> et;
    t.push_back(tt);
    d.push_back(dd);
    e.push_back(et);
  }
  ASSERT_GT(t.size(), 100u);
  std::vector<double> z;
  for (size_t k = 1; k < d.size(); k++)
    if (d[k - 1] * d[k] < 0.0) z.push_back(t[k - 1] + (t[k] - t[k - 1]) * d[k - 1] / (d[k - 1] - d[k]));
  ASSERT_GE(z.size(), 5u);    // 3 periods: crossings at T/2, T, ..., 5T/2
  const double tfirst = 2.0 * (z[1] - z[0]);
  const double tbeam = l.equal("v_Tbeam");
  double drift = 0.0;
  for (double ee : e) drift = std::max(drift, fabs(ee - e[0]) / e[0]);
  std::printf("[ plate    ] period %.5f s, beam theory %.5f s (%+.2f %%), energy drift %.4f %%\n", tfirst,
              tbeam, 100 * (tfirst - tbeam) / tbeam, 100 * drift);
  EXPECT_NEAR(tfirst, tbeam, 0.05 * tbeam);
  EXPECT_LT(drift, 5.0e-5);    // measured 1.7e-5
}

// particles on top of each other (a duplicated create_atoms) move as one: a warning at the
// setup of a run from step 0 with the count of pairs closer than 0.5 spacing; a regular
// lattice gives none
TEST(Setup, WarnsAboutCoincidentParticles)
{
  auto log_of = [](Lammps &l) {
    fflush(l.lmp->logfile);
    std::ifstream in("close.log");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  {
    Lammps l(MPI_COMM_WORLD, {"-log", "close.log"});
    block2d(l, 12, 8, 1.0e-3);
    l.cmd("run 0");
    EXPECT_EQ(log_of(l).find("closer than"), std::string::npos) << "a regular lattice has no close pairs";
  }
  {
    Lammps l(MPI_COMM_WORLD, {"-log", "close.log"});
    block2d(l, 12, 8, 1.0e-3);
    // one atom exactly on a lattice site, one 0.01 spacing from another, one at 0.71 spacing (not counted)
    l.cmds({"create_atoms 1 single 0 0 0 units box", "create_atoms 1 single 1.01e-3 0 0 units box",
            "create_atoms 1 single 2.5e-3 1.5e-3 0 units box", "run 0"});
    const std::string log = log_of(l);
    EXPECT_NE(log.find("WARNING: 2 pair(s) of particles closer than 0.5 spacing, the closest 0 spacing apart"),
              std::string::npos) << log;
    // only for the initial configuration (runs from step 0), not for later runs
    auto count = [](const std::string &text) {
      int n = 0;
      for (size_t p = text.find("closer than"); p != std::string::npos; p = text.find("closer than", p + 1)) n++;
      return n;
    };
    l.cmd("run 1");
    const int n1 = count(log_of(l));
    l.cmd("run 0");
    EXPECT_EQ(count(log_of(l)), n1);
  }
}

// a particle faster than vmax (default: the sound speed c_l, 5875 m/s for this steel) stops the
// run with an error that names it, at the step it happens, instead of flying off until LAMMPS
// fails somewhere else; vmax sets the speed, vmax none switches the check off
TEST(Runaway, FasterThanVmaxStopsTheRunNamingTheParticle)
{
  auto scene = [](Lammps &l, const std::string &fixargs) {
    block2d(l, 8, 6, 1.0e-3);
    l.cmds({"unfix sph", "fix sph all sph/jc-thermal cfl 0.3 " + fixargs, "run 0"});
  };
  {
    Lammps l;
    scene(l, "");
    l.cmd("set atom 17 vx 7000.0");    // supersonic: 1.19 c_l
    EXPECT_TRUE(l.error_contains("run 5", "particle 17 at ("));
  }
  {
    Lammps l;
    scene(l, "");
    l.cmd("set atom 17 vx 7000.0");
    EXPECT_TRUE(l.error_contains("run 5", "moves at 7000, faster than vmax 5875"));
  }
  {
    Lammps l;
    scene(l, "vmax 100");
    l.cmd("set atom 9 vy -150.0");
    EXPECT_TRUE(l.error_contains("run 5", "particle 9 at (")) << "vmax 100";
  }
  {
    Lammps l;
    scene(l, "vmax 200");    // 150 m/s is allowed
    l.cmds({"set atom 9 vy -150.0", "run 5"});
    EXPECT_EQ(l.lmp->update->ntimestep, 5);
  }
  {
    Lammps l;
    scene(l, "vmax none");
    l.cmds({"set atom 17 vx 7000.0", "run 5"});
    EXPECT_EQ(l.lmp->update->ntimestep, 5);
  }
  Lammps l;
  block2d(l, 4, 4, 1.0e-3);
  l.cmd("unfix sph");
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal cfl 0.3 vmax -1", "vmax must be > 0, sound or none, got -1"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal cfl 0.3 vmax fast", "vmax must be > 0"));
}

// a particle hotter than tmax (default: twice its material's Johnson-Cook Tmelt) stops the run
// with an error that names it, tool particles included, instead of heating up without bound
// unnoticed (a 2D cut on a GPU went on with one particle at 63,000 K); tmax sets the
// temperature, tmax none switches the check off, a material without Tmelt has no limit
TEST(Runaway, HotterThanTmaxStopsTheRunNamingTheParticle)
{
  auto scene = [](Lammps &l, double T17, const std::string &fixargs, const std::string &mat = "Tref 300 Tmelt 1800") {
    block2d(l, 8, 6, 1.0e-3, mat);
    l.cmds({"unfix sph", "group hot id 17", "variable T0 atom 300+" + std::to_string(T17 - 300.0) + "*(id==17)",
            "fix sph all sph/jc-thermal cfl 0.3 temp v_T0 " + fixargs});
  };
  {
    Lammps l;
    scene(l, 4000.0, "");
    EXPECT_TRUE(l.error_contains("run 5", "particle 17 at ("));
  }
  {
    Lammps l;
    scene(l, 4000.0, "");
    EXPECT_TRUE(l.error_contains("run 5", "has temperature 4000, above tmax 3600"));
  }
  {
    Lammps l;    // a rigid tool particle is checked too (the speed check leaves tool particles out)
    scene(l, 4000.0, "tool hot");
    EXPECT_TRUE(l.error_contains("run 5", "particle 17 at (")) << "tool particle";
  }
  {
    Lammps l;
    scene(l, 1500.0, "tmax 1000");
    EXPECT_TRUE(l.error_contains("run 5", "has temperature 1500, above tmax 1000")) << "tmax 1000";
  }
  {
    Lammps l;
    scene(l, 3500.0, "");    // below twice Tmelt: allowed
    l.cmd("run 5");
    EXPECT_EQ(l.lmp->update->ntimestep, 5);
  }
  for (const std::string args : {"tmax 5000", "tmax none"}) {
    Lammps l;
    scene(l, 4000.0, args);
    l.cmd("run 5");
    EXPECT_EQ(l.lmp->update->ntimestep, 5) << args;
  }
  {
    Lammps l;    // no Tmelt: no thermal softening, no limit
    scene(l, 1.0e5, "", "");
    l.cmd("run 5");
    EXPECT_EQ(l.lmp->update->ntimestep, 5) << "no Tmelt";
  }
  Lammps l;
  block2d(l, 4, 4, 1.0e-3);
  l.cmd("unfix sph");
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal cfl 0.3 tmax -1", "tmax must be > 0, melt or none, got -1"));
  EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal cfl 0.3 tmax hot", "tmax must be > 0, melt or none, got hot"));
}

// roles: rigid tool particles move with their own velocity and exert/feel no mechanics;
// clamped particles keep their position while their neighbours move
TEST(Roles, ToolAndClamped)
{
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "lattice sq 1e-3", "region box block -10 20 -10 20 -0.5 0.5", "create_box 2 box",
          "region work block -0.01 8.01 -0.01 4.01 -0.5 0.5", "create_atoms 1 region work",
          "region tool block -0.01 8.01 4.99 6.01 -0.5 0.5", "create_atoms 2 region tool",
          "mass * 0.0078", "group tool type 2", "region cl block INF 0.5 INF INF INF INF",
          "group clamp region cl", "group work type 1",
          "pair_style sph/jc-thermal", "pair_coeff * * rho0 7800 E 200e9 nu 0.3 hdx 1.3",
          "fix sph all sph/jc-thermal tool tool clamp clamp", "timestep 2e-8",
          "velocity tool set 0.0 -20.0 0.0 units box", "velocity work set 5.0 0.0 0.0 units box",
          "run 0"});
  auto *fix = static_cast<FixSPHJCThermal *>(sphcut::fix_by_id(l.lmp->modify, "sph"));
  auto *atom = l.lmp->atom;
  // at rest relative to each other, the workpiece sees no force although the tool is within 2h
  for (int i = 0; i < atom->nlocal; i++) {
    if (atom->type[i] != 1) continue;
    EXPECT_EQ(atom->f[i][1], 0.0);
    EXPECT_EQ(fix->state[i][F::ROLE], (atom->x[i][0] < 0.5e-3) ? F::CLAMPED : F::WORKPIECE);
  }
  // kinetic energy (element 3): the workpiece particles at 5 m/s, the tool not counted
  int nwork = 0, nmoving = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    nwork += atom->type[i] == 1;
    nmoving += atom->type[i] == 1 && fix->state[i][F::ROLE] == F::WORKPIECE;
  }
  const double m = 0.0078, ek0 = 0.5 * m * 25.0 * nwork, ek_moving = 0.5 * m * 25.0 * nmoving;
  EXPECT_EQ(nwork, 45);
  EXPECT_EQ(nmoving, 40);
  EXPECT_NEAR(l.equal("f_sph[3]"), ek0, 1e-12 * ek0);
  std::vector<double> y0(atom->nlocal), x0(atom->nlocal);
  for (int i = 0; i < atom->nlocal; i++) {    // serial, 100 steps: no atom sorting
    y0[i] = atom->x[i][1];
    x0[i] = atom->x[i][0];
  }
  l.cmd("run 100");
  for (int i = 0; i < atom->nlocal; i++) {
    const int role = static_cast<int>(fix->state[i][F::ROLE]);
    if (role == F::TOOL) {
      EXPECT_NEAR(atom->v[i][1], -20.0, 1e-12);
      EXPECT_NEAR(atom->x[i][1] - y0[i], -20.0 * 100 * 2e-8, 1e-12);
      EXPECT_EQ(fix->state[i][F::VM], 0.0);
    } else if (role == F::CLAMPED) {
      EXPECT_EQ(atom->x[i][0], x0[i]);
      EXPECT_EQ(atom->v[i][0], 0.0);
    }
  }
  // the clamp takes the kinetic energy of the clamped particles in the first step and then
  // does no work: the rest becomes strain energy (internal energy, element 2) as the clamp
  // stops the block; kinetic + internal energy stays that of the moving particles (measured
  // 1.2e-4 relative after 100 steps)
  const double ek = l.equal("f_sph[3]"), ei = l.equal("f_sph[2]");
  double ek_sum = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->type[i] == 1) ek_sum += 0.5 * m * (atom->v[i][0] * atom->v[i][0] + atom->v[i][1] * atom->v[i][1]);
  std::printf("[ roles    ] after 100 steps: kinetic %.6g J/m, internal %.6g, sum %.6g vs %.6g (%+.2e)\n", ek, ei,
              ek + ei, ek_moving, (ek + ei - ek_moving) / ek_moving);
  EXPECT_NEAR(ek, ek_sum, 1e-12 * ek_moving);
  EXPECT_LT(ek, 0.1 * ek_moving);
  EXPECT_NEAR(ek + ei, ek_moving, 4e-4 * ek_moving);
  // the workpiece next to the clamp is strained (stress), the clamp held it
  double vmmax = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->type[i] == 1) vmmax = std::max(vmmax, fix->state[i][F::VM]);
  EXPECT_GT(vmmax, 1.0e6);
}

// artificial-viscosity work (issue 11 item 4): the modelling decision is that it stays in the
// internal energy u (the discrete du/dt of pair sph/jc-thermal includes Pi_ij, so kinetic +
// internal energy is conserved) and does not heat: the temperature changes only by plastic
// heat chi W_p, friction heat and conduction (seed 003 eq. 12: Q_plast + Q_fric).  An elastic
// block (cp 500, no conduction) compressed at 100 m/s at its faces, with strong artificial
// viscosity (alpha = beta = 1): kinetic + internal energy is conserved, no plastic work, and
// the temperature stays at 300 K exactly, although the viscosity did work (the same block
// without it keeps more kinetic energy).  Kinetic + internal energy rises by 0.81 % here,
// independent of the amplitude (and by 19 % without artificial viscosity, which this block
// does not survive cleanly): the velocity Verlet / Heun pair has a first-order energy error,
// du is evaluated with the predicted velocity v^n + dt a^n, the kinetic energy changes with
// v^(n+1/2), a mismatch dt^2/(2m) f^n.f^(n+1) per step; small for smooth motion (plate:
// 0.0017 %), large for this compression of the whole block at the Courant limit.
TEST(Energy, ArtificialViscosityWorkIsInternalNotHeat)
{
  double ekin_end[2];
  for (int av = 1; av >= 0; av--) {
    Lammps l;
    block2d(l, 10, 10, 1.0e-3, std::string("cp 500 xsph 0 ") + (av ? "" : "alpha 0 beta 0"));
    l.cmds({"unfix sph", "fix sph all sph/jc-thermal temp 300 cfl 0.3", "variable vx atom -2*x/0.0045",
            "variable vy atom -2*y/0.0045", "velocity all set v_vx v_vy 0 units box", "variable e equal f_sph[2]+f_sph[3]",
            "run 0"});
    const double e0 = l.equal("v_e");
    l.cmd("run 400");
    const double e1 = l.equal("v_e");
    auto *fix = state_fix(l);
    double tlo = 1e300, thi = -1e300;
    for (int i = 0; i < l.lmp->atom->nlocal; i++) {
      tlo = std::min(tlo, fix->state[i][F::TEMP]);
      thi = std::max(thi, fix->state[i][F::TEMP]);
    }
    ekin_end[av] = l.equal("f_sph[3]");
    std::printf("[ energy   ] alpha = beta = %d: kinetic + internal %.6g -> %.6g J/m (%+.2e), kinetic at the end %.4g, "
                "plastic work %g, T in [%.6f, %.6f]\n",
                av, e0, e1, (e1 - e0) / e0, ekin_end[av], l.equal("f_sph[4]"), tlo, thi);
    if (av) EXPECT_NEAR(e1, e0, 0.025 * e0);    // measured +0.81 % (see the note above)
    EXPECT_EQ(l.equal("f_sph[4]"), 0.0);
    EXPECT_EQ(tlo, 300.0);
    EXPECT_EQ(thi, 300.0);
  }
  EXPECT_LT(ekin_end[1], ekin_end[0]);    // the viscosity did work (into u)
}
