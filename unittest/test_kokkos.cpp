// The /kk styles (pair sph/jc-thermal/kk, fix sph/jc-thermal/kk) against the CPU styles: the
// same plastic collision (2D and 3D, 100 steps, adaptive dt) with the Kokkos OpenMP backend in
// the neighbour-list configurations that matter (full list + newton off as on a GPU, half list
// + newton on as on CPU threads), per-atom state compared by atom ID; restarts across the two;
// and the clear errors.  Run on 1 and 2 MPI ranks (ctest: test_kokkos, test_kokkos_np2).
#include "sphcut_collision.h"

#include "update.h"

#include <fstream>
#include <sstream>

using namespace sphcut_test;

namespace {

const std::vector<std::string> KK_FULL = {"-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "neigh", "full",
                                          "newton", "off"};
const std::vector<std::string> KK_HALF = {"-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "neigh", "half",
                                          "newton", "on"};

Snapshot run(const std::vector<std::string> &args, const std::string &newton, int dim, int nsteps,
             double *plastic = nullptr)
{
  Lammps l(MPI_COMM_WORLD, args);
  l.cmds(collision(newton, dim));
  l.cmd("run " + std::to_string(nsteps));
  if (plastic) *plastic = l.equal("f_sph[6]");
  return take(l);
}

}    // namespace

TEST(Kokkos, StylesAreTheKokkosOnes)
{
  Lammps l(MPI_COMM_WORLD, KK_FULL);
  l.cmds(collision("off"));
  EXPECT_STREQ(l.lmp->force->pair_style, "sph/jc-thermal/kk");
  // the fix goes by the CPU style's name (restart files match fixes by name): kokkosable tells
  LAMMPS_NS::Fix *fix = l.lmp->modify->fix[l.lmp->modify->find_fix("sph")];
  EXPECT_STREQ(fix->style, "sph/jc-thermal");
  EXPECT_EQ(fix->kokkosable, 1);
}

TEST(Kokkos, FullListNewtonOffMatchesCpu2D)
{
  double eps = 0.0;
  const Snapshot cpu = run({}, "on", 2, 100);
  const Snapshot kk = run(KK_FULL, "off", 2, 100, &eps);
  EXPECT_GT(eps, 0.3);    // the collision is plastic
  expect_same(cpu, kk, "kk full");
}

TEST(Kokkos, HalfListNewtonOnMatchesCpu2D)
{
  expect_same(run({}, "on", 2, 100), run(KK_HALF, "on", 2, 100), "kk half");
}

TEST(Kokkos, FullListMatchesCpu3D)
{
  double eps = 0.0;
  const Snapshot cpu = run({}, "on", 3, 100);
  const Snapshot kk = run(KK_FULL, "off", 3, 100, &eps);
  EXPECT_GT(eps, 0.1);
  expect_same(cpu, kk, "kk 3D");
}

TEST(Kokkos, HalfListMatchesCpu3D)
{
  expect_same(run({}, "on", 3, 100), run(KK_HALF, "on", 3, 100), "kk half3D");
}

// a restart written by the CPU styles continues under /kk and the reverse.  A restart written
// under -k on records the atom style atomic/kk, which LAMMPS 29Sep2021 can only read with -k on
// (without it, it crashes in AtomVecAtomicKokkos): the CPU styles then run with -k on but no -sf kk,
// and name the pair style again.
TEST(Kokkos, RestartBetweenCpuAndKokkos)
{
  const Snapshot ref = run({}, "on", 2, 100);
  const std::vector<std::string> cpu_styles_on_kokkos_atoms = {"-k", "on", "t", "1"};
  for (int cpu_first = 0; cpu_first < 2; cpu_first++) {
    {
      Lammps l(MPI_COMM_WORLD, cpu_first ? std::vector<std::string>{} : KK_FULL);
      l.cmds(collision(cpu_first ? "on" : "off"));
      l.cmds({"run 50", "write_restart kk.restart"});
    }
    Lammps l(MPI_COMM_WORLD, cpu_first ? KK_FULL : cpu_styles_on_kokkos_atoms);
    // newton pair as the reader wants it; newton bond cannot change after a restart
    l.cmds({"read_restart kk.restart", std::string("newton ") + (cpu_first ? "off on" : "on off")});
    // the restart names the pair style it was written with (sph/jc-thermal/kk): the CPU run names
    // its own, with the material again (pair_style resets the coefficients)
    if (!cpu_first) {
      for (auto &line : collision("on"))
        if (line.rfind("pair_", 0) == 0) l.cmd(line);
      l.cmd("run_style verlet/kk");    // -k on without -sf kk
    }
    l.cmds({"fix sph all sph/jc-thermal cfl 0.3", "run 50"});
    EXPECT_EQ(l.lmp->update->ntimestep, 100);
    EXPECT_STREQ(l.lmp->force->pair_style, cpu_first ? "sph/jc-thermal/kk" : "sph/jc-thermal");
    expect_same(ref, take(l), cpu_first ? "cpu->kk" : "kk->cpu");
  }
}

// the state follows its atoms when LAMMPS reorders them: sorting every 10 steps during the run,
// delete_atoms between runs (on one rank the /kk fix remaps the rows by tag on the device, on
// several ranks the grow callback moves them)
TEST(Kokkos, StateFollowsAtomsThroughSortAndDelete)
{
  Snapshot snap[2];
  for (int k = 0; k < 2; k++) {
    Lammps l(MPI_COMM_WORLD, k ? KK_FULL : std::vector<std::string>{});
    auto c = collision(k ? "off" : "on");
    c.insert(c.begin() + 6, "atom_modify sort 10 4e-4");
    l.cmds(c);
    l.cmds({"run 50", "region cut block -30 -8 -20 20 -1 1", "delete_atoms region cut", "run 50"});
    snap[k] = take(l);
  }
  expect_same(snap[0], snap[1], "sort+del");
}

// the rows of a one-frame dump file (sorted by id), all columns as numbers
std::vector<std::vector<double>> dump_rows(const std::string &file)
{
  std::ifstream in(file);
  std::string line;
  std::vector<std::vector<double>> rows;
  bool atoms = false;
  while (std::getline(in, line)) {
    if (line.rfind("ITEM: ATOMS", 0) == 0) {
      atoms = true;
      continue;
    }
    if (!atoms) continue;
    std::istringstream ls(line);
    std::vector<double> v;
    for (double d; ls >> d;) v.push_back(d);
    rows.push_back(v);
  }
  return rows;
}

// outputs during a /kk run read the state of that step: dump_sph frames in the middle of the
// run and at its end, and the fix's global values on the thermo steps, as with the CPU styles
TEST(Kokkos, DumpsAndThermoAsOnTheCpu)
{
  double thermo[2][3];
  for (int k = 0; k < 2; k++) {
    Lammps l(MPI_COMM_WORLD, k ? KK_FULL : std::vector<std::string>{});
    l.cmds(collision(k ? "off" : "on"));
    const std::string name = k ? "kk" : "cpu";
    l.cmds({"dump_sph d all 50 dump." + name + ".* id density vonmises plastic_strain temperature vx",
            "dump_modify d sort id format float %.17g",
            "variable wp equal f_sph[4]", "variable tmax equal f_sph[5]",
            "fix out all print 50 \"${wp} ${tmax}\" file thermo." + name + " screen no", "run 100"});
    std::ifstream in("thermo." + name);
    std::string line;
    std::vector<double> v;
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') {
        std::istringstream ls(line);
        double a, b;
        ls >> a >> b;
        v.push_back(a);
        v.push_back(b);
      }
    ASSERT_EQ(v.size(), 6u);    // steps 0, 50, 100
    thermo[k][0] = v[2];        // plastic work at step 50
    thermo[k][1] = v[3];        // max temperature at step 50
    thermo[k][2] = v[4];        // plastic work at step 100
  }
  for (int c = 0; c < 3; c++) EXPECT_NEAR(thermo[1][c], thermo[0][c], 1e-10 * fabs(thermo[0][c])) << c;
  EXPECT_GT(thermo[0][0], 0.0);
  for (const char *step : {"50", "100"}) {
    const auto a = dump_rows(std::string("dump.cpu.") + step), b = dump_rows(std::string("dump.kk.") + step);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GT(a.size(), 300u);
    double worst = 0.0;
    for (size_t c = 1; c < a[0].size(); c++) {
      double scale = 0.0, diff = 0.0;
      for (size_t r = 0; r < a.size(); r++) {
        scale = std::max(scale, fabs(a[r][c]));
        diff = std::max(diff, fabs(a[r][c] - b[r][c]));
      }
      if (scale > 0.0) worst = std::max(worst, diff / scale);
    }
    int me;
    MPI_Comm_rank(MPI_COMM_WORLD, &me);
    if (me == 0) std::printf("[ dumps    ] step %s: dump_sph /kk vs CPU, max relative difference %.3e\n", step, worst);
    EXPECT_LT(worst, 1e-10) << step;
  }
}

// energy: kinetic + internal energy of the elastic-plastic collision is conserved by the scheme
// (internal energy includes the plastic work), as for the CPU styles
TEST(Kokkos, EnergyBalanceAsOnTheCpu)
{
  double e[2][2];
  int k = 0;
  for (auto args : {std::vector<std::string>{}, KK_FULL}) {
    Lammps l(MPI_COMM_WORLD, args);
    l.cmds(collision(k ? "off" : "on"));
    l.cmd("run 0");
    e[k][0] = l.equal("f_sph[2]+f_sph[3]");
    l.cmd("run 200");
    e[k][1] = l.equal("f_sph[2]+f_sph[3]");
    k++;
  }
  const double drift_cpu = (e[0][1] - e[0][0]) / e[0][0], drift_kk = (e[1][1] - e[1][0]) / e[1][0];
  std::printf("[ energy   ] drift cpu %.3e, kk %.3e\n", drift_cpu, drift_kk);
  EXPECT_NEAR(drift_kk, drift_cpu, 1e-10);
}

TEST(Kokkos, ClearErrors)
{
  {
    // a /kk style without -k on
    Lammps l;
    l.cmds({"units si", "atom_style atomic", "region box block 0 1 0 1 0 1", "create_box 1 box"});
    EXPECT_TRUE(l.error_contains("pair_style sph/jc-thermal/kk", "needs the KOKKOS package enabled"));
    EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal/kk", "needs the KOKKOS package enabled"));
  }
  {
    // /kk fix with the CPU pair
    Lammps l(MPI_COMM_WORLD, {"-k", "on", "t", "1"});
    auto c = collision("off");
    for (auto &line : c) {
      if (line.rfind("fix sph", 0) == 0) line = "fix sph all sph/jc-thermal/kk cfl 0.3";
      if (line == "atom_style atomic") line = "atom_style atomic/kk";
    }
    l.cmds(c);
    EXPECT_TRUE(l.error_contains("run 0", "requires fix sph/jc-thermal/kk") ||
                l.error_contains("run 0", "requires pair_style sph/jc-thermal/kk"));
  }
  {
    // the thermal and contact styles have no /kk variant yet: refused, not silently wrong
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(collision("off"));
    l.cmd("fix heat all heat/fmfs");
    EXPECT_TRUE(l.error_contains("run 0", "has no /kk variant yet"));
  }
}
