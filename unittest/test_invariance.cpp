// Invariance of the SPH solid: the same positions and state within 1e-10 (relative to the
// body size / the state's scale) after 100 steps for newton on vs off, 1 vs N MPI ranks,
// and a restart in the middle.  Run under mpirun (ctest: test_invariance_np4).
#include "sphcut_test.h"

#include "domain.h"
#include "fix_sph_jc_thermal.h"
#include "update.h"

#include <cmath>
#include <cstdio>

using LAMMPS_NS::FixSPHJCThermal;
using sphcut_test::Lammps;
using F = FixSPHJCThermal;

namespace {

// two 2D Johnson-Cook blocks colliding at 2 x 150 m/s: plastic flow, heating, adaptive dt
std::vector<std::string> collision(const std::string &newton)
{
  return {"units si", "dimension 2", "boundary f f p", "newton " + newton, "atom_style atomic",
          "atom_modify map array", "lattice sq 2e-4", "region box block -30 30 -20 20 -0.5 0.5",
          "create_box 2 box", "region left block -16.01 -0.51 -6.01 6.01 -0.5 0.5",
          "region right block 0.49 12.01 -4.01 4.01 -0.5 0.5", "create_atoms 1 region left",
          "create_atoms 2 region right", "mass * $(7800*2e-4*2e-4)", "group left type 1",
          "group right type 2", "velocity left set 150 10 0 units box", "velocity right set -150 0 0 units box",
          "pair_style sph/jc-thermal",
          "pair_coeff * * rho0 7800 E 200e9 nu 0.3 hdx 1.3 A 350e6 B 275e6 n 0.36 C 0.022 m 1.0 "
          "Tref 300 Tmelt 1800 cp 477 chi 0.9",
          "fix sph all sph/jc-thermal cfl 0.3", "timestep 1e-9", "thermo 0"};
}

struct Snapshot {
  std::vector<double> x, state;
};

Snapshot take(Lammps &l)
{
  Snapshot s;
  const int natoms = static_cast<int>(l.lmp->atom->natoms);
  s.x.resize(3 * natoms);
  lammps_gather_atoms(l.lmp, (char *) "x", 1, 3, s.x.data());
  // state columns RHO, SXX..SYZ, EPS, TEMP gathered by atom ID
  const int ncol = F::NOUT;
  std::vector<double> mine((size_t) natoms * ncol, 0.0);
  auto *fix = static_cast<F *>(l.lmp->modify->fix[l.lmp->modify->find_fix("sph")]);
  for (int i = 0; i < l.lmp->atom->nlocal; i++)
    for (int k = 0; k < ncol; k++) mine[(size_t) (l.lmp->atom->tag[i] - 1) * ncol + k] = fix->state[i][k];
  s.state.resize(mine.size());
  MPI_Allreduce(mine.data(), s.state.data(), (int) mine.size(), MPI_DOUBLE, MPI_SUM, l.lmp->world);
  return s;
}

// max position difference relative to the body size, and max state difference relative
// to each column's largest magnitude
void expect_same(const Snapshot &a, const Snapshot &b, const char *what)
{
  ASSERT_EQ(a.x.size(), b.x.size());
  double dx = 0.0;
  for (size_t k = 0; k < a.x.size(); k++) dx = std::max(dx, fabs(a.x[k] - b.x[k]));
  const double size = 28 * 2e-4;
  const int ncol = F::NOUT;
  double ds = 0.0;
  for (int c : {F::RHO, F::SXX, F::SYY, F::SXY, F::EPS, F::TEMP}) {
    double scale = 0.0, diff = 0.0;
    for (size_t i = 0; i < a.state.size() / ncol; i++) {
      scale = std::max(scale, fabs(a.state[i * ncol + c]));
      diff = std::max(diff, fabs(a.state[i * ncol + c] - b.state[i * ncol + c]));
    }
    if (scale > 0.0) ds = std::max(ds, diff / scale);
  }
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0) std::printf("[ %-8s ] max |dx|/size %.3e, max state difference %.3e\n", what, dx / size, ds);
  EXPECT_LT(dx / size, 1e-10) << what;
  EXPECT_LT(ds, 1e-10) << what;
}

Snapshot run(MPI_Comm comm, const std::string &newton, int nsteps)
{
  Lammps l(comm);
  l.cmds(collision(newton));
  l.cmd("run " + std::to_string(nsteps));
  EXPECT_GT(l.equal("f_sph[6]"), 0.0);    // plastic flow happened
  return take(l);
}

}    // namespace

TEST(Invariance, NewtonOnOff)
{
  expect_same(run(MPI_COMM_WORLD, "on", 100), run(MPI_COMM_WORLD, "off", 100), "newton");
}

TEST(Invariance, RanksOneVsMany)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  if (nprocs == 1) GTEST_SKIP() << "needs mpirun -np > 1";
  expect_same(run(MPI_COMM_SELF, "on", 100), run(MPI_COMM_WORLD, "on", 100), "ranks");
}

TEST(Invariance, RestartThenContinue)
{
  const Snapshot ref = run(MPI_COMM_WORLD, "on", 100);
  {
    Lammps l;
    l.cmds(collision("on"));
    l.cmds({"run 50", "write_restart invariance.restart"});
  }
  Lammps l;
  l.cmds({"read_restart invariance.restart", "fix sph all sph/jc-thermal cfl 0.3", "run 50"});
  EXPECT_EQ(l.lmp->update->ntimestep, 100);
  expect_same(ref, take(l), "restart");
}
