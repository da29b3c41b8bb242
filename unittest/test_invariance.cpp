// Invariance of the SPH solid: the same positions and state within 1e-10 (relative to the
// body size / the state's scale) after 100 steps for newton on vs off, 1 vs N MPI ranks,
// and a restart in the middle.  Run under mpirun (ctest: test_invariance_np4).
#include "sphcut_collision.h"

#include "domain.h"
#include "fix_sph_jc_thermal.h"
#include "update.h"

#include <cmath>
#include <cstdio>

using LAMMPS_NS::FixSPHJCThermal;
using sphcut_test::Lammps;

namespace {

using sphcut_test::collision;
using sphcut_test::expect_same;
using sphcut_test::Snapshot;
using sphcut_test::take;

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
