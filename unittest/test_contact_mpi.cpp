// fix contact/tri-penalty invariance: a cutting-like case (a rigid box tool with rigid tool
// particles moving at 200 m/s into a Johnson-Cook block with friction mu 0.3, friction heat
// split between workpiece and tool particles, heat conduction) gives the same tool force
// vector, positions and temperatures within 1e-10 (relative) after 100 steps for 1 vs N
// MPI ranks, newton on vs off, and a restart in the middle (tool displacement and heat
// budgets restored).  Run under mpirun (ctest: test_contact_mpi_np4).
#include "sphcut_test.h"

#include "sphcut_stl.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

using sphcut_test::Lammps;

namespace {

const int TEMP_COL = 11;    // FixSPHJCThermal::TEMP

// tool box: front face x = rc (touching the block's right face x = 0), bottom y = -0.8 mm
void write_tool()
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);    // one writer also when every rank runs its own copy
  if (me == 0) {
    const double rc = 0.5 * 1.3 * 2e-4 / 1.2;
    const double lo[3] = {rc, -8e-4, -1e-3}, hi[3] = {3e-3, 3e-3, 1e-3};
    const std::vector<double> tri = sphcut_test::box_triangles(lo, hi);
    sphcut::write_stl_binary("cut.stl", tri);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

std::vector<std::string> setup(const std::string &newton)
{
  return {"units si", "dimension 2", "boundary f f p", "newton " + newton, "atom_style atomic",
          "atom_modify map array", "lattice sq 2e-4", "region box block -40 20 -20 20 -0.5 0.5",
          "create_box 2 box", "region work block -30.01 0.01 -12.01 0.01 -0.5 0.5", "create_atoms 1 region work",
          "region tl block 0.99 8.01 -3.49 8.01 -0.5 0.5", "create_atoms 2 region tl",
          "mass * " + std::to_string(7800 * 2e-4 * 2e-4), "group work type 1", "group toolp type 2",
          "region cl block INF INF INF -10.5 INF INF", "group clamp region cl", "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 A 350e6 B 275e6 n 0.36 C 0.022 m 1.0 "
          "Tref 300 Tmelt 1800 cp 477 chi 0.9 k 50",
          "pair_coeff 2 2 rho0 15000 E 600e9 nu 0.22 hdx 1.3 cp 200 k 80", "timestep 1e-9", "thermo 0"};
}

// heat: "particles" = split auto to the tool particles; "lumped" = split 0.4, the tool share
// into the lumped tool temperature (element 11, one value summed over all ranks)
// friction: extra friction keywords of the contact fix (e.g. the memory law)
std::vector<std::string> fixes(const std::string &heat = "particles", const std::string &friction = "")
{
  return {"fix sph all sph/jc-thermal cfl 0.3 tool toolp clamp clamp", "fix heat all heat/fmfs",
          "fix tool work contact/tri-penalty stl cut.stl velocity -200 0 0 mu 0.3 heat heat " +
              std::string(heat == "particles" ? "tool_particles toolp" : "split 0.4 tool_cp 1e-3 300") + friction};
}

struct Snapshot {
  std::vector<double> x, temp, ftool;
};

// atom IDs depend on the domain decomposition of create_atoms: order the atoms by their
// lattice site at the start (x0, a gathered copy of the initial positions by ID)
std::vector<int> site_order(const std::vector<double> &x0)
{
  const int n = (int) x0.size() / 3;
  std::vector<int> idx(n);
  for (int i = 0; i < n; i++) idx[i] = i;
  auto site = [&](int i, int a) { return std::lround(x0[3 * i + a] / 1e-4); };    // half spacing
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return site(a, 0) != site(b, 0) ? site(a, 0) < site(b, 0) : site(a, 1) < site(b, 1);
  });
  return idx;
}

std::vector<double> gather_x(Lammps &l)
{
  std::vector<double> x(3 * static_cast<size_t>(l.lmp->atom->natoms));
  lammps_gather_atoms(l.lmp, (char *) "x", 1, 3, x.data());
  return x;
}

Snapshot take(Lammps &l, const std::vector<double> &x0)
{
  Snapshot s;
  const int natoms = static_cast<int>(l.lmp->atom->natoms);
  const std::vector<double> x = gather_x(l);
  std::vector<double> mine(natoms, 0.0), temp(natoms);
  LAMMPS_NS::Fix *sph = sphcut::fix_by_id(l.lmp->modify, "sph");
  for (int i = 0; i < l.lmp->atom->nlocal; i++) mine[l.lmp->atom->tag[i] - 1] = sph->array_atom[i][TEMP_COL];
  MPI_Allreduce(mine.data(), temp.data(), natoms, MPI_DOUBLE, MPI_SUM, l.lmp->world);
  for (int i : site_order(x0)) {
    for (int a = 0; a < 3; a++) s.x.push_back(x[3 * i + a]);
    s.temp.push_back(temp[i]);
  }
  for (int k = 1; k <= 14; k++) s.ftool.push_back(l.equal("f_tool[" + std::to_string(k) + "]"));
  return s;
}

// max |dx| relative to the block size; max |dT| relative to the temperature rise; each tool
// vector element relative to its magnitude (element 12, the max penetration, starts at
// round-off level and is compared absolutely)
void expect_same(const Snapshot &a, const Snapshot &b, const char *what)
{
  ASSERT_EQ(a.x.size(), b.x.size());
  double dx = 0.0, dT = 0.0, rise = 0.0, df = 0.0;
  for (size_t k = 0; k < a.x.size(); k++) dx = std::max(dx, fabs(a.x[k] - b.x[k]));
  for (size_t k = 0; k < a.temp.size(); k++) {
    dT = std::max(dT, fabs(a.temp[k] - b.temp[k]));
    rise = std::max(rise, fabs(a.temp[k] - 300.0));
  }
  for (size_t k = 0; k < a.ftool.size(); k++) {
    const double scale = k == 11 ? 1.0 : std::max(fabs(a.ftool[k]), 1e-300);
    if (a.ftool[k] != b.ftool[k]) df = std::max(df, fabs(a.ftool[k] - b.ftool[k]) / scale);
  }
  const double size = 30 * 2e-4;
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0)
    std::printf("[ %-8s ] tool force (%.6g, %.6g) N/m, %g contacts, heat %.4g + %.4g J/m, max dT %.1f K: "
                "max |dx|/size %.2e, |dT|/rise %.2e, tool vector %.2e\n",
                what, a.ftool[0], a.ftool[1], a.ftool[4], a.ftool[5], a.ftool[6], rise, dx / size, dT / rise, df);
  EXPECT_LT(dx / size, 1e-10) << what;
  EXPECT_LT(dT / rise, 1e-10) << what;
  EXPECT_LT(df, 1e-10) << what;
  EXPECT_GT(a.ftool[0], 1e5) << what;    // the block resists the tool (+x force on it)
  EXPECT_GT(a.ftool[4], 0.0) << what;    // in contact
  EXPECT_GT(a.ftool[6], 0.0) << what;    // friction heat reached the tool (particles or lumped)
}

Snapshot run(MPI_Comm comm, const std::string &newton, int nsteps, const std::string &heat = "particles",
             const std::string &friction = "")
{
  write_tool();
  Lammps l(comm);
  l.cmds(setup(newton));
  l.cmds(fixes(heat, friction));
  const std::vector<double> x0 = gather_x(l);
  l.cmd("run " + std::to_string(nsteps));
  return take(l, x0);
}

}    // namespace

TEST(ContactInvariance, RanksOneVsMany)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  if (nprocs == 1) GTEST_SKIP() << "needs mpirun -np > 1";
  expect_same(run(MPI_COMM_SELF, "on", 100), run(MPI_COMM_WORLD, "on", 100), "ranks");
}

TEST(ContactInvariance, RanksOneVsManyLumpedTool)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  if (nprocs == 1) GTEST_SKIP() << "needs mpirun -np > 1";
  const Snapshot a = run(MPI_COMM_SELF, "on", 100, "lumped"), b = run(MPI_COMM_WORLD, "on", 100, "lumped");
  expect_same(a, b, "lumped");
  EXPECT_NEAR(a.ftool[10], 300.0 + a.ftool[6] / 1e-3, 1e-9 * a.ftool[10]);    // T = T0 + Q_tool / C
  EXPECT_NEAR(a.ftool[6], 0.6 / 0.4 * a.ftool[5], 1e-9 * a.ftool[6]);
}

TEST(ContactInvariance, NewtonOnOff)
{
  expect_same(run(MPI_COMM_WORLD, "on", 100), run(MPI_COMM_WORLD, "off", 100), "newton");
}

namespace {

int rank_of_world()
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  return me;
}

void restart_then_continue(const std::string &friction, const char *what)
{
  const Snapshot ref = run(MPI_COMM_WORLD, "on", 100, "particles", friction);
  write_tool();
  std::vector<double> x0;
  {
    Lammps l;
    l.cmds(setup("on"));
    l.cmds(fixes("particles", friction));
    x0 = gather_x(l);
    l.cmds({"run 50", "write_restart contact.restart"});
  }
  Lammps l;
  l.cmds({"read_restart contact.restart", "group work type 1", "group toolp type 2", "thermo 0"});
  l.cmds(fixes("particles", friction));
  l.cmd("run 50");
  EXPECT_EQ(l.lmp->update->ntimestep, 100);
  expect_same(ref, take(l, x0), what);
}

}    // namespace

TEST(ContactInvariance, RestartThenContinue)
{
  restart_then_continue("", "restart");
}

// friction with memory: the per-particle friction state migrates between the ranks and is
// carried through the restart file; a run split in two equals the unsplit one, and a second
// run command continues it as well
TEST(ContactInvariance, FrictionMemoryRanksAndRestart)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  const std::string mem = " friction memory";
  if (nprocs > 1) {
    // the parallel run is rebalanced after 50 steps: the cuts move to the particles, and
    // particles in contact (with friction state) change rank
    const Snapshot one = run(MPI_COMM_SELF, "on", 100, "particles", mem);
    write_tool();
    Lammps l;
    l.cmds(setup("on"));
    l.cmds(fixes("particles", mem));
    const std::vector<double> x0 = gather_x(l);
    l.cmd("run 50");
    LAMMPS_NS::Fix *tool = sphcut::fix_by_id(l.lmp->modify, "tool");
    std::vector<int> mine;
    for (int i = 0; i < l.lmp->atom->nlocal; i++)
      if (tool->array_atom[i][5] > 0.0 && tool->array_atom[i][4] > 0.0) mine.push_back(l.lmp->atom->tag[i]);
    l.cmd("balance 1.0 shift xy 10 1.0");
    int moved = 0, nmoved = 0, ncont = 0, nc = (int) mine.size();
    for (int tag : mine) {
      const int i = l.lmp->atom->map(tag);
      if (i < 0 || i >= l.lmp->atom->nlocal) moved++;
    }
    MPI_Allreduce(&moved, &nmoved, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    MPI_Allreduce(&nc, &ncont, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    l.cmd("run 50");
    if (rank_of_world() == 0)
      std::printf("[ memory   ] %d ranks: %d of %d particles with friction changed rank at the rebalance\n", nprocs,
                  nmoved, ncont);
    EXPECT_GT(ncont, 0);
    if (nprocs == 4) EXPECT_GT(nmoved, 0);    // the 2 x 2 grid: the y cut moves below the contact
    expect_same(one, take(l, x0), "memory ranks");
  }
  restart_then_continue(mem, "mem restart");
  const Snapshot ref = run(MPI_COMM_WORLD, "on", 100, "particles", mem);
  Lammps l;
  l.cmds(setup("on"));
  l.cmds(fixes("particles", mem));
  const std::vector<double> x0 = gather_x(l);
  l.cmds({"run 50", "run 50"});
  expect_same(ref, take(l, x0), "mem 2 runs");
}
