// pair sph/jc-thermal hourglass control (keyword hourglass, sphcut::hourglass_pair): an odd-even
// (zero-energy) velocity mode survives without it and is damped with it; a linear velocity field
// gets no force from it (patch test); its pair forces conserve linear and angular momentum; its
// work goes into the internal energy; newton on/off, restart, bad input, /kk refusal.
#include "sphcut_test.h"

#include "comm.h"
#include "domain.h"
#include "fix_sph_jc_thermal.h"
#include "pair.h"
#include "pair_sph_jc_thermal.h"

#include <cmath>
#include <string>
#include <vector>

using LAMMPS_NS::FixSPHJCThermal;
using LAMMPS_NS::PairSPHJCThermal;
using sphcut_test::Lammps;
using F = FixSPHJCThermal;

namespace {

const double DX = 1.0e-3, RHO = 7800.0;

FixSPHJCThermal *state_fix(Lammps &l)
{
  LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, "sph");
  return static_cast<FixSPHJCThermal *>(f);
}

// nx x ny particles of spacing DX, elastic steel without artificial viscosity, artificial stress
// or XSPH (nothing else damps or moves a mode); periodic: a laterally infinite lattice (with
// ghosts), else a free block
void lattice(Lammps &l, int nx, int ny, bool periodic, const std::string &pairstyle, const std::string &newton = "on")
{
  l.cmds({"units si", "dimension 2", std::string("boundary ") + (periodic ? "p p p" : "f f p"), "newton " + newton,
          "atom_style atomic", "atom_modify map array", "lattice sq " + std::to_string(DX)});
  if (periodic) {
    l.cmds({"region box block 0 " + std::to_string(nx) + " 0 " + std::to_string(ny) + " -0.5 0.5",
            "create_box 1 box", "create_atoms 1 box"});
  } else {
    l.cmds({"region box block -2 " + std::to_string(nx + 2) + " -2 " + std::to_string(ny + 2) + " -0.5 0.5",
            "create_box 1 box",
            "region blk block -0.01 " + std::to_string(nx - 0.99) + " -0.01 " + std::to_string(ny - 0.99) + " -0.5 0.5",
            "create_atoms 1 region blk"});
  }
  l.cmds({"mass 1 " + std::to_string(RHO * DX * DX), pairstyle,
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 alpha 0 beta 0 as_eps 0 xsph 0",
          "fix sph all sph/jc-thermal", "timestep 2e-8"});
}

// the odd-even (checkerboard) mode v_y = a (-1)^(i+j): every particle's neighbours are
// symmetric pairs with equal velocity differences, so L = 0, no density or stress rate, no force
void checkerboard(Lammps &l, double a)
{
  l.cmds({"variable vy atom " + std::to_string(a) + "*cos(PI*(x+y)/" + std::to_string(DX) + ")",
          "velocity all set 0.0 v_vy 0.0 units box"});
}

double kinetic(Lammps &l)
{
  double e = 0.0;
  auto *atom = l.lmp->atom;
  for (int i = 0; i < atom->nlocal; i++)
    e += 0.5 * atom->mass[atom->type[i]] * (atom->v[i][0] * atom->v[i][0] + atom->v[i][1] * atom->v[i][1]);
  return e;
}

double internal(Lammps &l)
{
  double e = 0.0;
  auto *atom = l.lmp->atom;
  auto *fix = state_fix(l);
  for (int i = 0; i < atom->nlocal; i++) e += atom->mass[atom->type[i]] * fix->state[i][F::UINT];
  return e;
}

// amplitude of the mode in the displacements: rms of y - y0, the lattice being at rest on average
double rms_dy(Lammps &l, const std::vector<double> &y0)
{
  auto *atom = l.lmp->atom;
  const double ly = l.lmp->domain->yprd;
  double s = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    double d = atom->x[i][1] - y0[atom->tag[i] - 1];
    d -= ly * std::round(d / ly);    // across the periodic boundary
    s += d * d;
  }
  return sqrt(s / atom->nlocal);
}

std::vector<double> y_by_tag(Lammps &l)
{
  auto *atom = l.lmp->atom;
  std::vector<double> y(atom->natoms);
  for (int i = 0; i < atom->nlocal; i++) y[atom->tag[i] - 1] = atom->x[i][1];
  return y;
}

}    // namespace

// Without hourglass control the checkerboard mode is a zero-energy mode: it keeps its kinetic
// energy (measured: 1 - 4.7e-6, the displaced lattice stores a little elastic energy) and its
// displacement grows linearly with time (rms = a t: 2.000e-6, 4.000e-6 m after 100, 200 steps).
// With hourglass 0.5 (damping time about h / (kappa c) = 0.45 us, 22 steps) its kinetic energy
// is 1.8e-9 of the start after 200 steps and the displacement stops at 3.95e-7 m (grows by
// 2.6e-9 m from step 100 to 200, 0.13 % of the growth without); kinetic + internal energy
// holds to 6e-4 (the control's work goes into u; first-order time integration error).
TEST(Hourglass, CheckerboardModeGrowsWithoutDampedWith)
{
  const double a = 1.0;
  double ke_ratio[2], dy_100[2], dy_200[2], energy_err[2];
  for (int hg = 0; hg < 2; hg++) {
    Lammps l;
    lattice(l, 16, 16, true, std::string("pair_style sph/jc-thermal") + (hg ? " hourglass 0.5" : ""));
    checkerboard(l, a);
    l.cmd("run 0");
    const double ke0 = kinetic(l), e0 = ke0 + internal(l);
    const auto y0 = y_by_tag(l);
    l.cmd("run 100");
    dy_100[hg] = rms_dy(l, y0);
    l.cmd("run 100");
    dy_200[hg] = rms_dy(l, y0);
    ke_ratio[hg] = kinetic(l) / ke0;
    energy_err[hg] = (kinetic(l) + internal(l) - e0) / e0;
  }
  const double t100 = 100 * 2e-8;
  // without: the mode keeps its energy and its displacement grows as a t
  EXPECT_NEAR(ke_ratio[0], 1.0, 1.5e-5);
  EXPECT_NEAR(dy_100[0], a * t100, 1e-3 * a * t100);
  EXPECT_NEAR(dy_200[0], 2.0 * a * t100, 1e-3 * a * t100);
  // with: damped, the displacement saturates
  EXPECT_LT(ke_ratio[1], 6e-9);
  EXPECT_LT(dy_200[1] - dy_100[1], 0.004 * (dy_200[0] - dy_100[0]));
  EXPECT_LT(dy_200[1], 0.3 * dy_200[0]);
  // kinetic + internal energy: the mode's energy has gone into u
  EXPECT_LT(fabs(energy_err[0]), 1e-12);
  EXPECT_LT(fabs(energy_err[1]), 2e-3);
  printf("[ measured ] KE ratio without %.3g, with %.3g; rms dy (100, 200 steps) without %.4g %.4g, with %.4g %.4g;"
         " energy error without %.2g, with %.2g\n",
         ke_ratio[0], ke_ratio[1], dy_100[0], dy_200[0], dy_100[1], dy_200[1], energy_err[0], energy_err[1]);
}

// patch test: a linear velocity field (translation, stretching, shear, rotation) in a free block,
// surface included, gets exactly the forces and energy rates of the run without the control
TEST(Hourglass, LinearFieldUnchanged)
{
  std::vector<std::vector<double>> f[2], du[2];
  for (int hg = 0; hg < 2; hg++) {
    Lammps l;
    lattice(l, 12, 8, false, std::string("pair_style sph/jc-thermal") + (hg ? " hourglass 1.0" : ""));
    l.cmds({"pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3",    // with artificial viscosity and stress
            // compressive in every direction (D negative definite): the viscosity acts on every pair
            "variable vx atom 2.0-300*x-150*y", "variable vy atom -1.0+400*x-200*y",
            "velocity all set v_vx v_vy 0.0 units box", "run 0"});
    auto *atom = l.lmp->atom;
    auto *fix = state_fix(l);
    f[hg].assign(atom->natoms, {0.0, 0.0});
    du[hg].assign(atom->natoms, {0.0});
    for (int i = 0; i < atom->nlocal; i++) {
      f[hg][atom->tag[i] - 1] = {atom->f[i][0], atom->f[i][1]};
      du[hg][atom->tag[i] - 1] = {fix->state[i][F::DU]};
    }
  }
  double fmax = 0.0, dfmax = 0.0, dumax = 0.0, ddumax = 0.0;
  for (size_t k = 0; k < f[0].size(); k++) {
    for (int a = 0; a < 2; a++) {
      fmax = std::max(fmax, fabs(f[0][k][a]));
      dfmax = std::max(dfmax, fabs(f[1][k][a] - f[0][k][a]));
    }
    dumax = std::max(dumax, fabs(du[0][k][0]));
    ddumax = std::max(ddumax, fabs(du[1][k][0] - du[0][k][0]));
  }
  ASSERT_GT(fmax, 0.0);
  EXPECT_LT(dfmax, 1e-9 * fmax);    // measured: round-off
  EXPECT_LT(ddumax, 1e-9 * dumax);
  printf("[ measured ] linear field: max |f| %.3g, max change by the control %.3g; du %.3g, change %.3g\n", fmax,
         dfmax, dumax, ddumax);
}

// momentum: with no stress, no viscosity and no artificial stress the control's pair forces are
// the only forces; for a random velocity field in a free block they sum to zero, and so do their
// torques (central pair forces)
TEST(Hourglass, ConservesLinearAndAngularMomentum)
{
  Lammps l;
  lattice(l, 12, 8, false, "pair_style sph/jc-thermal hourglass 1.0");
  l.cmds({"variable vx atom random(-1.0,1.0,4928459)", "variable vy atom random(-1.0,1.0,1234567)",
          "velocity all set v_vx v_vy 0.0 units box", "run 0"});
  auto *atom = l.lmp->atom;
  double fx = 0.0, fy = 0.0, tz = 0.0, fabs_sum = 0.0, tabs = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double *x = atom->x[i], *f = atom->f[i];
    fx += f[0];
    fy += f[1];
    tz += x[0] * f[1] - x[1] * f[0];
    fabs_sum += fabs(f[0]) + fabs(f[1]);
    tabs += fabs(x[0] * f[1]) + fabs(x[1] * f[0]);
  }
  ASSERT_GT(fabs_sum, 0.0);    // the random field has an odd-even part: the control acts
  EXPECT_LT(fabs(fx) + fabs(fy), 1e-12 * fabs_sum);
  EXPECT_LT(fabs(tz), 1e-12 * tabs);
  printf("[ measured ] sum |f| %.3g, |sum f| %.3g; sum |torque| %.3g, |sum torque| %.3g\n", fabs_sum,
         fabs(fx) + fabs(fy), tabs, fabs(tz));
}

// newton off (ghost pairs computed on both sides) gives the forces of newton on, in a periodic
// lattice (ghosts on one rank) with the mode plus a linear field
TEST(Hourglass, NewtonOffEqualsNewtonOn)
{
  std::vector<std::vector<double>> f[2];
  for (int nw = 0; nw < 2; nw++) {
    Lammps l;
    lattice(l, 10, 10, true, "pair_style sph/jc-thermal hourglass 0.5", nw ? "off" : "on");
    l.cmds({"variable vx atom 0.3*sin(2*PI*y/0.01)", "variable vy atom 1.0*cos(PI*(x+y)/" + std::to_string(DX) + ")",
            "velocity all set v_vx v_vy 0.0 units box", "run 0"});
    auto *atom = l.lmp->atom;
    f[nw].assign(atom->natoms, {0.0, 0.0});
    for (int i = 0; i < atom->nlocal; i++) f[nw][atom->tag[i] - 1] = {atom->f[i][0], atom->f[i][1]};
  }
  double fmax = 0.0, d = 0.0;
  for (size_t k = 0; k < f[0].size(); k++)
    for (int a = 0; a < 2; a++) {
      fmax = std::max(fmax, fabs(f[0][k][a]));
      d = std::max(d, fabs(f[1][k][a] - f[0][k][a]));
    }
  ASSERT_GT(fmax, 0.0);
  EXPECT_LT(d, 1e-10 * fmax);
}

// the coefficient travels with the restart file
TEST(Hourglass, Restart)
{
  {
    Lammps l;
    lattice(l, 6, 6, true, "pair_style sph/jc-thermal hourglass 0.25");
    l.cmds({"run 0", "write_restart hourglass.restart"});
  }
  Lammps l;
  l.cmds({"read_restart hourglass.restart", "fix sph all sph/jc-thermal", "run 0"});
  auto *pair = static_cast<PairSPHJCThermal *>(l.lmp->force->pair);
  EXPECT_EQ(pair->model().hourglass_coefficient(), 0.25);
  // a repeated pair_style without the keyword (LAMMPS keeps the instance) switches it off
  l.cmd("pair_style sph/jc-thermal");
  EXPECT_EQ(static_cast<PairSPHJCThermal *>(l.lmp->force->pair)->model().hourglass_coefficient(), 0.0);
}

// (one LAMMPS instance at a time: a second one loading the plugin replaces its styles)
TEST(Hourglass, BadInput)
{
  {
    Lammps l;
    l.cmds({"units si", "dimension 2", "boundary p p p", "atom_style atomic", "region box block 0 1 0 1 -0.5 0.5",
            "create_box 1 box"});
    EXPECT_TRUE(l.error_contains("pair_style sph/jc-thermal hourglass -0.1", "hourglass must be in [0,10], got -0.1"));
    EXPECT_TRUE(l.error_contains("pair_style sph/jc-thermal hourglass", "keyword hourglass needs a value"));
    EXPECT_TRUE(l.error_contains("pair_style sph/jc-thermal hourglass abc", "Expected floating point"));
  }
  Lammps l2;
  lattice(l2, 6, 6, true, "pair_style sph/jc-thermal hourglass 0.1 correction no");
  EXPECT_TRUE(l2.error_contains("run 0", "hourglass 0.1 needs correction yes"));
}

#ifdef SPHCUT_TEST_HAVE_KOKKOS
// under /kk the control needs the full neighbour list (test_kokkos HourglassControlMatchesCpu
// compares it with the CPU style); with a half list it is refused at the run's setup
TEST(Hourglass, KokkosNeedsTheFullList)
{
  Lammps l(MPI_COMM_WORLD, {"-k", "on", "t", "1", "-sf", "kk", "-pk", "kokkos", "neigh", "half", "newton", "on"});
  lattice(l, 6, 6, true, "pair_style sph/jc-thermal hourglass 0.1");
  EXPECT_TRUE(l.error_contains("run 0", "hourglass 0.1 needs the full neighbor list"));
}
#endif
