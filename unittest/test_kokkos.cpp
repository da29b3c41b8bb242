// The /kk styles (pair sph/jc-thermal/kk, fix sph/jc-thermal/kk) against the CPU styles: the
// same plastic collision (2D and 3D, 100 steps, adaptive dt) with the Kokkos OpenMP backend in
// the neighbour-list configurations that matter (full list + newton off as on a GPU, half list
// + newton on as on CPU threads), per-atom state compared by atom ID; restarts across the two;
// and the clear errors.  Run on 1 and 2 MPI ranks (ctest: test_kokkos, test_kokkos_np2).
#include "sphcut_collision.h"

#include "fix_sph_jc_thermal_kokkos.h"
#include "pair_sph_jc_thermal_kokkos.h"

#include "atom.h"
#include "atom_masks.h"
#include "compute.h"
#include "fix.h"
#include "fix_external.h"
#include "input.h"
#include "modify.h"
#include "neighbor.h"
#include "timer.h"
#include "update.h"

#include <Kokkos_Core.hpp>

#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
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

// an environment switch of the /kk styles (doc/performance.md) set to value: LAMMPS under /kk,
// after cmds, stops at trigger (the command that runs the style's init) with an error naming the
// switch, the value and what is allowed; the switch is unset again
void expect_switch_refused(const char *name, const std::string &value, const std::vector<std::string> &cmds,
                           const std::string &trigger, const std::string &allowed = "0 or 1")
{
  setenv(name, value.c_str(), 1);
  {
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(cmds);
    EXPECT_TRUE(l.error_contains(trigger, std::string(name) + "=" + value + " is not " + allowed)) << name << "=" << value;
  }
  unsetenv(name);
}

}    // namespace

TEST(Kokkos, StylesAreTheKokkosOnes)
{
  Lammps l(MPI_COMM_WORLD, KK_FULL);
  l.cmds(collision("off"));
  EXPECT_STREQ(l.lmp->force->pair_style, "sph/jc-thermal/kk");
  // the fix goes by the CPU style's name (restart files match fixes by name): kokkosable tells
  LAMMPS_NS::Fix *fix = sphcut::fix_by_id(l.lmp->modify, "sph");
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

// the neighbour pass with a team of vector lanes per particle (package kokkos neigh/thread on, the
// default on a GPU for small systems): on a host backend one lane, the sums in the same order
// the lanes per particle of the pair's neighbour pass on a GPU (PairSPHJCThermalKokkos::gpu_lanes,
// as measured, bench/gpu/RESULTS.md "The 2D step"): 8 (2D) / 16 (3D) for small systems, halved
// while particles x lanes exceed 131,072, none above 65,536 particles; package kokkos neigh/thread
// on keeps at least 2, off none
TEST(Kokkos, PairLanesOnAGpu)
{
  using PK = LAMMPS_NS::PairSPHJCThermalKokkos<LMPDeviceType>;
  EXPECT_EQ(PK::gpu_lanes(1393, 2, false, false), 8);     // the quick cut
  EXPECT_EQ(PK::gpu_lanes(4882, 2, false, false), 8);     // 21 across
  EXPECT_EQ(PK::gpu_lanes(18271, 2, false, false), 4);    // 41 across: 4 lanes measured fastest
  EXPECT_EQ(PK::gpu_lanes(18271, 3, false, false), 4);
  EXPECT_EQ(PK::gpu_lanes(40000, 2, false, false), 2);
  EXPECT_EQ(PK::gpu_lanes(65536, 2, false, false), 2);
  EXPECT_EQ(PK::gpu_lanes(65537, 2, false, false), 0);    // one thread per particle
  EXPECT_EQ(PK::gpu_lanes(70567, 2, false, false), 0);    // 81 across: one thread measured fastest
  EXPECT_EQ(PK::gpu_lanes(4882, 3, false, false), 16);
  EXPECT_EQ(PK::gpu_lanes(1000000, 3, false, false), 0);
  EXPECT_EQ(PK::gpu_lanes(1000000, 3, true, true), 2);    // neigh/thread on
  EXPECT_EQ(PK::gpu_lanes(1393, 2, true, false), 0);      // neigh/thread off
}

TEST(Kokkos, TeamNeighbourPassMatchesCpu)
{
  std::vector<std::string> team = KK_FULL;
  for (const char *a : {"neigh/thread", "on"}) team.push_back(a);
  expect_same(run({}, "on", 2, 100), run(team, "off", 2, 100), "kk team 2D");
  expect_same(run({}, "on", 3, 100), run(team, "off", 3, 100), "kk team 3D");
}

// the one-thread pass with each list entry's index and row head loaded one entry ahead (the
// default on a GPU, SPHCUT_LOAD_AHEAD=1 here) against the pass without: the same sums in the
// same order (2D: the same bits, 3 runs of 3; in 3D this backend's list order varies from run to
// run, and with it the last bits: 1.2-1.9e-13 between two runs of one setting, 1.6-3.5e-13
// between the settings), and the CPU styles' results; anything but 0 or 1 is refused by name
TEST(Kokkos, PrefetchedNeighbourPassMatchesCpu)
{
  for (int dim : {2, 3}) {
    setenv("SPHCUT_LOAD_AHEAD", "1", 1);
    const Snapshot ahead = run(KK_FULL, "off", dim, 100);
    setenv("SPHCUT_LOAD_AHEAD", "0", 1);
    const Snapshot taken = run(KK_FULL, "off", dim, 100);
    unsetenv("SPHCUT_LOAD_AHEAD");
    expect_same(taken, ahead, dim == 2 ? "ahead 2D" : "ahead 3D", 1e-12);
    expect_same(run({}, "on", dim, 100), ahead, dim == 2 ? "kk ahead 2D" : "kk ahead 3D");
  }
  expect_switch_refused("SPHCUT_LOAD_AHEAD", "2", collision("off"), "run 0");
}

// the hourglass control (pair_style ... hourglass kappa) under /kk: full list (thread and team
// passes) against the CPU style, 2D and 3D; on 2 ranks the ghosts' L comes by forward
// communication on the device.  A half list is refused.
TEST(Kokkos, HourglassControlMatchesCpu)
{
  auto run_hg = [](const std::vector<std::string> &args, const std::string &newton, int dim) {
    Lammps l(MPI_COMM_WORLD, args);
    auto c = collision(newton, dim);
    for (auto &line : c)
      if (line == "pair_style sph/jc-thermal") line = "pair_style sph/jc-thermal hourglass 0.5";
    l.cmds(c);
    l.cmd("run 100");
    return take(l);
  };
  std::vector<std::string> team = KK_FULL;
  for (const char *a : {"neigh/thread", "on"}) team.push_back(a);
  for (int dim : {2, 3}) {
    const Snapshot cpu = run_hg({}, "on", dim);
    expect_same(cpu, run_hg(KK_FULL, "off", dim), dim == 2 ? "kk hourglass 2D" : "kk hourglass 3D");
    expect_same(cpu, run_hg(team, "off", dim), dim == 2 ? "kk team hourglass 2D" : "kk team hourglass 3D");
    // the control acts: without it the state differs by far more than the tolerance
    const Snapshot plain = run({}, "on", dim, 100);
    const int ncol = LAMMPS_NS::FixSPHJCThermal::NOUT, c = LAMMPS_NS::FixSPHJCThermal::SXX;
    double diff = 0.0, scale = 0.0;
    for (size_t i = 0; i < cpu.state.size() / ncol; i++) {
      diff = std::max(diff, fabs(cpu.state[i * ncol + c] - plain.state[i * ncol + c]));
      scale = std::max(scale, fabs(cpu.state[i * ncol + c]));
    }
    EXPECT_GT(diff, 1e-6 * scale) << "the hourglass control changes the stress";
  }
  Lammps l(MPI_COMM_WORLD, KK_HALF);
  auto c = collision("on");
  for (auto &line : c)
    if (line == "pair_style sph/jc-thermal") line = "pair_style sph/jc-thermal hourglass 0.5";
  l.cmds(c);
  EXPECT_TRUE(l.error_contains("run 0", "hourglass 0.5 needs the full neighbor list"));
}

// the pressure cutoff (pair_coeff ... pmin) under /kk: the collision with a pmin that the release
// waves reach, full and half list against the CPU style, 2D and 3D.  The cutoff acts: particles sit
// at pmin, and the state differs from the run without it by far more than the tolerance.
TEST(Kokkos, PressureCutoffMatchesCpu)
{
  const std::string pmin = "-3e8";
  auto run_pmin = [&](const std::vector<std::string> &args, const std::string &newton, int dim, const std::string &p) {
    Lammps l(MPI_COMM_WORLD, args);
    auto c = collision(newton, dim);
    for (auto &line : c)
      if (line.rfind("pair_coeff", 0) == 0 && !p.empty()) line += " pmin " + p;
    l.cmds(c);
    l.cmd("run 100");
    return take(l);
  };
  for (int dim : {2, 3}) {
    const Snapshot cpu = run_pmin({}, "on", dim, pmin);
    const int ncol = LAMMPS_NS::FixSPHJCThermal::NOUT, P = LAMMPS_NS::FixSPHJCThermal::PRESS;
    int atmin = 0;
    for (size_t i = 0; i < cpu.state.size() / ncol; i++)
      if (cpu.state[i * ncol + P] == std::stod(pmin)) atmin++;
    std::printf("[ pmin %dD  ] %d of %zu particles at pmin %s\n", dim, atmin, cpu.state.size() / ncol, pmin.c_str());
    EXPECT_GT(atmin, 0) << "the cutoff is reached";
    expect_same(cpu, run_pmin(KK_FULL, "off", dim, pmin), dim == 2 ? "kk pmin 2D" : "kk pmin 3D");
    expect_same(cpu, run_pmin(KK_HALF, "on", dim, pmin), dim == 2 ? "kk half pmin 2D" : "kk half pmin 3D");
    const Snapshot plain = run_pmin({}, "on", dim, "");
    double diff = 0.0, scale = 0.0;
    for (size_t i = 0; i < cpu.state.size() / ncol; i++) {
      diff = std::max(diff, fabs(cpu.state[i * ncol + P] - plain.state[i * ncol + P]));
      scale = std::max(scale, fabs(cpu.state[i * ncol + P]));
    }
    EXPECT_GT(diff, 1e-3 * scale) << "the cutoff changes the pressure";
    // spall release: the particles below the cutoff carry no stress (PRESS exactly 0), on the CPU
    // as under /kk
    const Snapshot rel = run_pmin({}, "on", dim, pmin + " spall release");
    int released = 0;
    for (size_t i = 0; i < rel.state.size() / ncol; i++)
      if (rel.state[i * ncol + P] == 0.0) released++;
    std::printf("[ release %dD ] %d of %zu particles released\n", dim, released, rel.state.size() / ncol);
    EXPECT_GT(released, 0) << "the release is reached";
    expect_same(rel, run_pmin(KK_FULL, "off", dim, pmin + " spall release"), dim == 2 ? "kk release 2D" : "kk release 3D");
  }
}

// the second flow-stress law (pair_coeff ... flow tanh, sphcut::flow_hardening) under /kk: the
// collision with the softening law, full and half list against the CPU style; the law acts (the
// state differs from the Johnson-Cook run by far more than the tolerance)
TEST(Kokkos, FlowTanhMatchesCpu)
{
  auto run_flow = [&](const std::vector<std::string> &args, const std::string &newton, const std::string &flow) {
    Lammps l(MPI_COMM_WORLD, args);
    auto c = collision(newton, 2);
    for (auto &line : c)
      if (line.rfind("pair_coeff", 0) == 0) line += " " + flow;
    l.cmds(c);
    l.cmd("run 100");
    return take(l);
  };
  const std::string tanh = "flow tanh a 2 b 5 c 2 d 1";
  const Snapshot cpu = run_flow({}, "on", tanh);
  expect_same(cpu, run_flow(KK_FULL, "off", tanh), "kk tanh");
  expect_same(cpu, run_flow(KK_HALF, "on", tanh), "kk half tanh");
  const Snapshot jc = run_flow({}, "on", "");
  const int ncol = LAMMPS_NS::FixSPHJCThermal::NOUT, VM = LAMMPS_NS::FixSPHJCThermal::VM;
  double diff = 0.0, scale = 0.0;
  for (size_t i = 0; i < cpu.state.size() / ncol; i++) {
    diff = std::max(diff, fabs(cpu.state[i * ncol + VM] - jc.state[i * ncol + VM]));
    scale = std::max(scale, fabs(jc.state[i * ncol + VM]));
  }
  std::printf("[ flow tanh ] von Mises differs from flow jc by up to %.3g of its maximum\n", diff / scale);
  EXPECT_GT(diff, 1e-2 * scale) << "the law changes the stress";
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

// a restart written by the CPU styles continues under /kk and the reverse, on each LAMMPS the way
// its write_restart leaves to a user (sphcut::restart_plain_styles in sphcut_compat.h; doc/build.md
// "Restart files between the CPU and /kk styles"):
//   CPU -> /kk, every version: -k on t N -sf kk (read_restart adds the suffix to the atom and pair
//     styles the file records: atomic/kk, sph/jc-thermal/kk)
//   /kk -> CPU, 29Sep2021: the file records atomic/kk and sph/jc-thermal/kk, which only a reader
//     with -k on can create (without it the plugin refuses, WithoutKokkosEnabled): the CPU styles
//     run with -k on but no -sf kk, run_style verlet/kk, and name the pair style again
//   /kk -> CPU, from 8Feb2023 (4Jul2026): the file records atomic and sph/jc-thermal: the plain lmp
//     reads it and goes on with the pair style and coefficients it records; -k on without -sf kk
//     stops there in LAMMPS (AtomKokkos::new_avec: the recorded atom style is the plain one)
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
    if (!cpu_first && sphcut::restart_plain_styles) {
      Lammps k(MPI_COMM_WORLD, cpu_styles_on_kokkos_atoms);
      EXPECT_TRUE(k.error_contains("read_restart kk.restart", "KOKKOS package requires a Kokkos-enabled atom_style"));
    }
    const bool plain_reader = !cpu_first && sphcut::restart_plain_styles;
    Lammps l(MPI_COMM_WORLD, cpu_first ? KK_FULL : plain_reader ? std::vector<std::string>{} : cpu_styles_on_kokkos_atoms);
    // newton pair as the reader wants it (read_restart keeps a newton pair off set before it and
    // warns); newton bond is the file's, unchangeable.  Under /kk (neigh full) no newton command:
    // 4Jul2026 checks each one against neigh full with newton bond included ("Must use 'newton
    // off' with KOKKOS package option 'neigh full'"), and the file of the CPU run has newton bond on
    l.cmd("read_restart kk.restart");
    if (!cpu_first) l.cmd("newton on off");
    EXPECT_EQ(l.lmp->force->newton_pair, cpu_first ? 0 : 1);
    EXPECT_STREQ(l.lmp->atom->atom_style, (cpu_first || !plain_reader) ? "atomic/kk" : "atomic");
    // 29Sep2021: the restart names the pair style it was written with (sph/jc-thermal/kk): the CPU
    // run names its own, with the material again (pair_style resets the coefficients)
    if (!cpu_first && !plain_reader) {
      EXPECT_STREQ(l.lmp->force->pair_style, "sph/jc-thermal/kk");
      for (auto &line : collision("on"))
        if (line.rfind("pair_", 0) == 0) l.cmd(line);
      l.cmd("run_style verlet/kk");    // -k on without -sf kk
    }
    l.cmds({"fix sph all sph/jc-thermal cfl 0.3", "run 50"});
    EXPECT_EQ(l.lmp->update->ntimestep, 100);
    EXPECT_STREQ(l.lmp->force->pair_style, cpu_first ? "sph/jc-thermal/kk" : "sph/jc-thermal");
    EXPECT_EQ(sphcut::fix_by_id(l.lmp->modify, "sph")->kokkosable, cpu_first ? 1 : 0);
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

// issue 50: the /kk styles and what -k on records, without -k on.  compute reduce/region/kk stops
// at its definition (it crashed at the run's setup, in AtomKokkos::sync).  A restart file that
// records the atom style atomic/kk, read without -k on, stops naming the atom style (LAMMPS 29Sep2021
// aborted in Kokkos: "Constructing View and initializing data with uninitialized execution space";
// 4Jul2026 stops with "Cannot use KOKKOS styles without enabling KOKKOS").  Which files record it
// (sphcut::restart_plain_styles): in 29Sep2021 every file written under -k on -sf kk; from 8Feb2023
// (4Jul2026) only one whose input named atomic/kk itself, and a file of a -sf kk run records atomic,
// read without -k on as a CPU run (RestartBetweenCpuAndKokkos compares its state)
TEST(Kokkos, WithoutKokkosEnabled)
{
  {
    Lammps l(MPI_COMM_WORLD, {});
    l.cmds(collision("off"));
    l.cmd("region rr block -1e-3 1e-3 0 2e-3 INF INF units box");
    EXPECT_TRUE(l.error_contains("compute r all reduce/region/kk rr ave f_sph[12]",
                                 "Compute reduce/region/kk needs the KOKKOS package enabled"));
  }
  const std::string refused = "Atom style atomic/kk needs the KOKKOS package enabled (";
  const std::string way = "): run with -k on t N, with -sf kk for the /kk styles";
  {
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(collision("off"));
    l.cmds({"run 10", "write_restart kk-written.restart"});
  }
  {
    Lammps l(MPI_COMM_WORLD, {});
    if (sphcut::restart_plain_styles) {
      l.cmds({"read_restart kk-written.restart", "newton on off", "fix sph all sph/jc-thermal cfl 0.3", "run 10"});
      EXPECT_STREQ(l.lmp->atom->atom_style, "atomic");
      EXPECT_STREQ(l.lmp->force->pair_style, "sph/jc-thermal");
      EXPECT_EQ(l.lmp->update->ntimestep, 20);
    } else {
      EXPECT_TRUE(l.error_contains("read_restart kk-written.restart",
                                   refused + "a restart file written with -k on records it" + way));
    }
  }
  // the input names atomic/kk (-k on, the CPU styles): the file records atomic/kk on every version
  {
    Lammps l(MPI_COMM_WORLD, {"-k", "on", "t", "1"});
    auto c = collision("off");
    for (auto &line : c)
      if (line == "atom_style atomic") line = "atom_style atomic/kk";
    l.cmds(c);
    l.cmds({"run_style verlet/kk", "run 10", "write_restart kk-named.restart"});
  }
  Lammps l(MPI_COMM_WORLD, {});
  EXPECT_TRUE(l.error_contains("read_restart kk-named.restart",
                               refused + (sphcut::restart_plain_styles
                                              ? "named in the input, or recorded in a restart file whose input named it"
                                              : "a restart file written with -k on records it") + way));
}

// the way doc/fix_sph_jc_thermal.rst gives to continue a /kk run's restart file with the CPU styles
// runs the cutting example (-var continue 1).  29Sep2021: -k on t 1 without -sf kk (the file records
// atomic/kk), for which the input sets run_style verlet/kk under -k on (LAMMPS stopped with "KOKKOS
// package requires run_style verlet/kk").  From 8Feb2023 (4Jul2026): the plain lmp (the file
// records atomic, sphcut::restart_plain_styles)
TEST(Kokkos, ExampleContinuesWithTheCpuStyles)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";
  auto run = [&](const std::vector<std::string> &args, int cont) {
    auto l = std::make_unique<Lammps>(MPI_COMM_WORLD, args);
    l->cmds({"variable ny index 11", "variable dumpevery index 0", "variable xstart index 0.6",
             "variable steps index 100", "variable continue index " + std::to_string(cont)});
    l->lmp->input->file(in.c_str());
    return l;
  };
  run({"-k", "on", "t", "1", "-sf", "kk"}, 0).reset();
  auto l = run(sphcut::restart_plain_styles ? std::vector<std::string>{} : std::vector<std::string>{"-k", "on", "t", "1"}, 1);
  EXPECT_EQ(l->lmp->update->ntimestep, 200);
  EXPECT_STREQ(l->lmp->atom->atom_style, sphcut::restart_plain_styles ? "atomic" : "atomic/kk");
  EXPECT_STREQ(l->lmp->force->pair_style, "sph/jc-thermal");
  EXPECT_EQ(sphcut::fix_by_id(l->lmp->modify, "sph")->kokkosable, 0);
  // the tool moved at the cutting speed through both parts (f_cut[8]: its displacement in x)
  const double v = 318.5 / 60.0, t = l->equal("time");
  EXPECT_GT(t, 0.0);
  EXPECT_NEAR(-l->equal("f_cut[8]"), v * t, 1e-9 * v * t);
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
    // a CPU thermal style beside the /kk mechanics would read a stale host state: refused
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(collision("off"));
    l.cmd("fix heat all heat/fmfs/kk");
    l.cmd("unfix heat");
    l.cmd("suffix off");
    l.cmd("fix heat all heat/fmfs");
    EXPECT_TRUE(l.error_contains("run 0", "is the CPU style; use its /kk variant"));
  }
  {
    // mu from a LAMMPS variable cannot be evaluated in a kernel
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(collision("off"));
    l.cmds({"variable T internal 300", "variable mu equal 0.3"});
    EXPECT_TRUE(l.error_contains("fix c all contact/tri-penalty insert rake 0 clearance 7 radius 0 rake_length 1e-3 "
                                 "flank_length 1e-3 mu v_mu tvar T",
                                 "cannot be evaluated on the device"));
  }
  {
    // per-atom values of the /kk fix between the steps it copies them to the host: LAMMPS refuses
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(collision("off"));
    l.cmds({"thermo 50", "compute t all reduce max f_sph[12]", "fix p all print 7 \"$(c_t)\" screen no"});
    EXPECT_TRUE(l.error_contains("run 20", "not computed at compatible time"));
  }
  {
    // between runs the host copy is current: write_dump (a dump of frequency 1) of the state works
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    l.cmds(collision("off"));
    l.cmds({"thermo 50", "run 20", "write_dump all custom kk-state.dump id f_sph[1] f_sph[12] modify sort id"});
    std::ifstream in("kk-state.dump");
    EXPECT_TRUE(in.good());
  }
}

/* ----------------------------------------------------------------------
   the thermal, surface and contact styles under /kk against the CPU styles, in the scenes of the
   examples: the 2D Ti6Al4V cut (11 across; the tool is in contact for the last ~1300 of 9000
   steps: penalty, friction with the stick limit, friction heat split between the workpiece and
   the tool particles, FMFS/Brookshaw conduction sub-cycled every 10 steps, surface losses,
   Dirichlet clamp) and the 3D cut with free sides (6 across, 3 layers; the triangulated
   insert; contact for the last ~1100 of 2500 steps).  Per-atom state by atom ID and the fixes'
   global vectors (tool force, work, dissipation, heat budgets) agree to round-off.
------------------------------------------------------------------------- */

namespace {

// rows of exactly ncols numbers (other lines: headers, comments, LAMMPS messages, are skipped)
std::vector<std::vector<double>> numeric_rows(const std::string &file, size_t ncols)
{
  std::ifstream in(file);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::vector<double> v;
    std::string tok;
    bool ok = true;
    while (ok && ls >> tok) {
      char *end = nullptr;
      const double d = strtod(tok.c_str(), &end);
      ok = end && *end == '\0' && end != tok.c_str();
      v.push_back(d);
    }
    if (ok && v.size() == ncols) rows.push_back(v);
  }
  return rows;
}

// largest difference of two decompositions (nfeat x 8 values from column first of a and b): the force
// components, sum F_N and sum |F_T| of a feature against that feature's sum F_N + sum |F_T|, the
// contact counts against max(count, 1)
double decomp_diff(const std::vector<double> &a, const std::vector<double> &b, size_t first, int nfeat = 4)
{
  double d = 0.0;
  for (int ft = 0; ft < nfeat; ft++) {
    const double *pa = &a[first + 8 * ft], *pb = &b[first + 8 * ft];
    const double scale = fabs(pa[5]) + fabs(pa[6]);
    for (int c = 0; c < 8; c++) {
      const double s = (c == 4 || c == 7) ? std::max(fabs(pa[c]), 1.0) : scale;
      if (s > 0.0) d = std::max(d, fabs(pa[c] - pb[c]) / s);
      else d = std::max(d, fabs(pb[c]) > 0.0 ? 1.0 : 0.0);
    }
  }
  return d;
}

struct CutRun {
  Snapshot snap;
  std::vector<double> cut, heat;
  std::vector<std::vector<double>> decomp;    // decomp.dat (-var decomp N): step, cut, 3 x 8 values
};

CutRun cut_run(const std::vector<std::string> &args, const std::string &example, const std::vector<std::string> &vars)
{
  Lammps l(MPI_COMM_WORLD, args);
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0) std::remove("decomp.dat");
  for (auto &v : vars) l.cmd("variable " + v);
  l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/" + example + "/in.cutting").c_str());
  CutRun r;
  MPI_Barrier(MPI_COMM_WORLD);    // fix print flushes each line
  r.decomp = numeric_rows("decomp.dat", 2 + 24);
  r.snap = take(l);
  // elements 1-15 and the decomposition by tool feature, 16-47
  for (int k = 1; k <= 47; k++) r.cut.push_back(l.equal("f_cut[" + std::to_string(k) + "]"));
  for (int k = 1; k <= 6; k++) r.heat.push_back(l.equal("f_heat[" + std::to_string(k) + "]"));
  return r;
}

// largest relative difference of the elements, each against its magnitude in a; the first
// nvec elements form a vector (the tool force) and are compared against its length (the z force
// of a plane cut vanishes to round-off)
double vector_diff(const std::vector<double> &a, const std::vector<double> &b, size_t nvec = 0)
{
  double len = 0.0, d = 0.0;
  for (size_t k = 0; k < nvec; k++) len += a[k] * a[k];
  len = sqrt(len);
  for (size_t k = 0; k < a.size(); k++) {
    const double scale = k < nvec ? len : fabs(a[k]);
    if (scale > 0.0) d = std::max(d, fabs(a[k] - b[k]) / scale);
    else d = std::max(d, fabs(b[k]) > 0.0 ? 1.0 : 0.0);
  }
  return d;
}

void expect_same_cut(const CutRun &cpu, const CutRun &kk, const char *what, size_t nheat = 6)
{
  expect_same(cpu.snap, kk.snap, what);
  const double dc = vector_diff(cpu.cut, kk.cut, 3);
  const double dh = vector_diff(std::vector<double>(cpu.heat.begin(), cpu.heat.begin() + nheat),
                                std::vector<double>(kk.heat.begin(), kk.heat.begin() + nheat));
  std::printf("[ %-8s ] contact vector %.3e, heat vector %.3e (tool force %.6g N, %g particles in contact)\n", what, dc,
              dh, cpu.cut[0], cpu.cut[4]);
  EXPECT_GT(cpu.cut[4], 2.0);    // the tool is in contact
  EXPECT_GT(cpu.cut[5], 0.0);    // friction heat went into the workpiece
  EXPECT_GT(cpu.cut[6], 0.0);    // and into the tool particles
  EXPECT_LT(dc, 1e-10) << what;
  EXPECT_LT(dh, 1e-10) << what;
}

}    // namespace

// with the decomposition by tool feature written every 7 steps (-var decomp 7: fix print of
// f_cut[16..39] on steps that are mostly neither thermo nor per-atom output steps)
// cfl 0.3 (the example's default is 0.5): the 9000 steps and the 1e-10 were set at 0.3; at 0.5 the
// same steps reach further into the chaotic cut, where the round-off of the sums' order grows
// (measured 1.7e-10, with friction memory 4.5e-10)
TEST(KokkosThermal, Cut2DMatchesCpu)
{
  const std::vector<std::string> vars = {"ny index 11", "cut index 0.12e-3", "dumpevery index 0",
                                         "steps index 9000", "thermoevery index 1000", "cfl index 0.3", "decomp index 7"};
  const CutRun cpu = cut_run({}, "cutting-2d-ti6al4v", vars);
  const CutRun kk = cut_run(KK_FULL, "cutting-2d-ti6al4v", vars);
  expect_same_cut(cpu, kk, "cut 2D");
  ASSERT_EQ(cpu.decomp.size(), 2 + 9000u / 7);    // step 0 (run 0 and the setup of the run), 7, ..., 8995
  ASSERT_EQ(kk.decomp.size(), cpu.decomp.size());
  double d = 0.0, slip = 0.0;
  int ncont = 0;
  for (size_t r = 0; r < cpu.decomp.size(); r++) {
    ASSERT_EQ(kk.decomp[r][0], cpu.decomp[r][0]);
    d = std::max(d, decomp_diff(cpu.decomp[r], kk.decomp[r], 2, 3));
    ncont += cpu.decomp[r][2 + 4] > 0.0;
    slip = std::max(slip, cpu.decomp[r][2 + 7]);
  }
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0)
    std::printf("[ cut 2D   ] decomposition every 7 steps /kk vs CPU %.3e (%d lines with rake contacts, up to %g "
                "at the Coulomb limit)\n", d, ncont, slip);
  EXPECT_GT(ncont, 100);    // the rake face is in contact for the last ~1300 steps
  EXPECT_LT(d, 1e-10);
}

TEST(KokkosThermal, Cut2DFrictionMemoryMatchesCpu)
{
  const std::vector<std::string> vars = {"ny index 11", "cut index 0.12e-3", "dumpevery index 0",
                                         "steps index 9000", "thermoevery index 1000", "cfl index 0.3", "friction index memory"};
  const CutRun cpu = cut_run({}, "cutting-2d-ti6al4v", vars);
  const CutRun kk = cut_run(KK_FULL, "cutting-2d-ti6al4v", vars);
  expect_same_cut(cpu, kk, "memory");
  EXPECT_GT(cpu.cut[15 + 4], 0.0);    // rake-face contacts in the decomposition
}

TEST(KokkosThermal, Cut3DFreeSidesMatchesCpu)
{
  const std::vector<std::string> vars = {"ny index 6", "nz index 3", "sides index free", "steps index 2500",
                                         "xstart index 1", "thermoevery index 500"};
  const CutRun cpu = cut_run({}, "cutting-3d-ti6al4v", vars);
  const CutRun kk = cut_run(KK_FULL, "cutting-3d-ti6al4v", vars);
  expect_same_cut(cpu, kk, "cut 3D");
}

namespace {
// two steel blocks of different conductivity (40 and 15 W/mK), the upper one at 900 K, touching:
// fix heat/fmfs with opts, its surface losses and a Dirichlet layer at the bottom, 300 steps; the
// state, and the heat fix's vector into e (6 values)
Snapshot two_material_block(const std::vector<std::string> &args, const std::string &opts, double *e)
{
  const bool kk = !args.empty();
  Lammps l(MPI_COMM_WORLD, args);
  l.cmds({"units si", "dimension 3", "boundary f f f", std::string("newton ") + (kk ? "off" : "on"),
          "atom_style atomic", "atom_modify map array", "lattice sc 2e-4",
          "region box block -2 10 -2 10 -2 10", "create_box 2 box", "region a block -0.01 7.01 -0.01 7.01 -0.01 3.01",
          "region b block -0.01 7.01 -0.01 7.01 3.99 6.01", "create_atoms 1 region a", "create_atoms 2 region b",
          "mass * $(7800*2e-4*2e-4*2e-4)", "region bot block INF INF INF INF INF 0.5", "group bot region bot",
          "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 cp 477 k 40",
          "pair_coeff 2 2 rho0 7800 E 200e9 nu 0.3 hdx 1.3 cp 477 k 15",
          "variable t0 atom 300+600*(type==2)", "fix sph all sph/jc-thermal temp v_t0 cfl 0.3",
          "compute surf all surface/lambda",
          "fix heat all heat/fmfs surface surf convection 1e5 300 radiation 0.8 300 dirichlet bot 300 " + opts,
          "thermo 0", "run 300"});
  for (int c = 0; c < 6; c++) e[c] = l.equal("f_heat[" + std::to_string(c + 1) + "]");
  return take(l);
}

// the largest difference of the temperature rise (T - 300 K) of two states, relative to the
// largest rise
double rise_diff(const Snapshot &a, const Snapshot &b)
{
  using F = LAMMPS_NS::FixSPHJCThermal;
  double scale = 0.0, diff = 0.0;
  for (size_t i = 0; i < a.state.size() / F::NOUT; i++) {
    scale = std::max(scale, fabs(a.state[i * F::NOUT + F::TEMP] - 300.0));
    diff = std::max(diff, fabs(a.state[i * F::NOUT + F::TEMP] - b.state[i * F::NOUT + F::TEMP]));
  }
  return diff / scale;
}
}    // namespace

// the options the cuts do not use: the per-particle (non-conservative) form every step, a
// material interface (FMFS -> Brookshaw), radiation and convection on the surface, a Dirichlet
// group, scheme brookshaw; a hot block on a cooler substrate of another conductivity, 300 steps
TEST(KokkosThermal, HeatOptionsMatchCpu)
{
  for (const std::string opts : {"conservative no", "scheme brookshaw", "every 3"}) {
    Snapshot s[2];
    double e[2][6];
    for (int k = 0; k < 2; k++) s[k] = two_material_block(k ? KK_FULL : std::vector<std::string>{}, opts, e[k]);
    expect_same(s[0], s[1], opts.c_str());
    const double dh = vector_diff(std::vector<double>(e[0], e[0] + 6), std::vector<double>(e[1], e[1] + 6));
    std::printf("[ %-8s ] heat vector %.3e (convection %.4g J, radiation %.4g J, Dirichlet %.4g J)\n",
                opts.c_str(), dh, e[0][0], e[0][1], e[0][2]);
    EXPECT_GT(e[0][0], 0.0);
    EXPECT_GT(e[0][1], 0.0);
    EXPECT_LT(dh, 1e-10) << opts;
  }
}

namespace {
// kernel launches by name outside the setup (Kokkos Tools callbacks in this process)
std::map<std::string, int> launches;
LAMMPS_NS::LAMMPS *counted = nullptr;
long max_builds = 0;    // neighbour list builds in the steps of the run (ncalls at its end)
void count_launch(const char *name, const uint32_t, uint64_t *id)
{
  *id = 0;
  if (counted && !counted->update->setupflag) {
    launches[name]++;
    // in a run's steps: ncalls is set by the neighbour init, which comes after the fixes' init
    // (their views' initialization launches, setupflag 0 too, would read it unset)
    if (counted->update->whichflag && std::string(name).rfind("sphcut:", 0) == 0)
      max_builds = std::max(max_builds, (long) counted->neighbor->ncalls);
  }
}
void no_end(uint64_t) {}
std::map<std::string, int> scans;    // parallel_scan launches by name (setups: "setup " + name)
int sums_fills = 0;                  // fills of the contact fix's sums (deep_copy of a scalar)
void count_scan(const char *name, const uint32_t, uint64_t *id)
{
  *id = 0;
  if (!counted) return;
  scans[(counted->update->setupflag ? "setup " : "") + std::string(name)]++;
}
void count_copy(Kokkos::Tools::SpaceHandle, const char *dst, const void *, Kokkos::Tools::SpaceHandle,
                const char *src, const void *, uint64_t)
{
  if (std::string(dst) == "contact:sums" && std::string(src) == "Scalar") sums_fills++;
}

// counts the launches, scans and copies of lmp (the callbacks above) while it lives
struct CountLaunches {
  explicit CountLaunches(LAMMPS_NS::LAMMPS *lmp)
  {
    counted = lmp;
    set(true);
  }
  ~CountLaunches()
  {
    set(false);
    counted = nullptr;
  }
  static void set(bool on)
  {
    using namespace Kokkos::Tools::Experimental;
    set_begin_parallel_for_callback(on ? count_launch : nullptr);
    set_begin_parallel_reduce_callback(on ? count_launch : nullptr);
    set_begin_parallel_scan_callback(on ? count_scan : nullptr);
    set_end_parallel_for_callback(on ? no_end : nullptr);
    set_end_parallel_reduce_callback(on ? no_end : nullptr);
    set_end_parallel_scan_callback(on ? no_end : nullptr);
    set_begin_deep_copy_callback(on ? count_copy : nullptr);
  }
};

const std::string CUT2D = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";

// the 2D example at 11 across under /kk with its launches counted (the counters above reset
// first): the tool xstart spacings from the workpiece, steps steps, a line of forces.dat (and the
// per-atom outputs) every 10 steps, the environment switch env=value set for the run (env
// nullptr: none) and the example's variables vars ("name index value")
std::unique_ptr<Lammps> counted_cut(const std::string &xstart, int steps, const char *env, const char *value,
                                    const std::vector<std::string> &vars = {})
{
  if (env) setenv(env, value, 1);
  auto l = std::make_unique<Lammps>(MPI_COMM_WORLD, KK_FULL);
  for (auto &v : {"xstart index " + xstart, "steps index " + std::to_string(steps), std::string("ny index 11"),
                  std::string("dumpevery index 0"), std::string("thermoevery index 100"),
                  std::string("printevery index 10")})
    l->cmd("variable " + v);
  for (auto &v : vars) l->cmd("variable " + v);
  launches.clear();
  scans.clear();
  sums_fills = 0;
  max_builds = 0;
  {
    CountLaunches count(l->lmp);
    l->lmp->input->file(CUT2D.c_str());
  }
  if (env) unsetenv(env);
  return l;
}

// the cut's Fc, Ft and internal energy at the end of a run
struct CutEnd {
  double fc, ft, eint;
};
CutEnd cut_end(Lammps &l)
{
  return {l.equal("v_Fc"), l.equal("v_Ft"), l.equal("f_sph[2]")};
}

// two runs of one cut (two paths of the code) give the same cut (equal to the bit on one thread; on 2
// threads two runs of one input may differ by 1e-10 in Fc: the contact's records and heat sums
// are atomics)
void expect_same_cut_end(const CutEnd &a, const CutEnd &b)
{
  EXPECT_NEAR(a.fc, b.fc, 3e-10 * fabs(b.fc));
  EXPECT_NEAR(a.ft, b.ft, 3e-10 * fabs(b.ft));
  EXPECT_NEAR(a.eint, b.eint, 3e-10 * fabs(b.eint));
}

// a steel block of 6^3 particles heated from its bottom layer (fix heat/fmfs dirichlet bot 900),
// adaptive dt, run for nsteps
std::vector<std::string> heated_block(int nsteps)
{
  return {"units si", "dimension 3", "boundary f f f", "newton off", "atom_style atomic", "atom_modify map array",
          "lattice sc 2e-4", "region box block -2 8 -2 8 -2 8", "create_box 1 box",
          "region a block -0.01 5.01 -0.01 5.01 -0.01 5.01", "create_atoms 1 region a",
          "mass * $(7800*2e-4*2e-4*2e-4)", "region bot block INF INF INF INF INF 0.5", "group bot region bot",
          "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 cp 477 k 40",
          "fix sph all sph/jc-thermal temp 300 cfl 0.3", "fix heat all heat/fmfs every 5 dirichlet bot 900",
          "thermo 0", "run " + std::to_string(nsteps)};
}

// the heated block after 50 steps with the environment switch env=value: its step and the heat
// through its Dirichlet layer
struct BlockEnd {
  double dt, qdir;
};
BlockEnd heated_block_under(const char *env, const char *value)
{
  setenv(env, value, 1);
  Lammps l(MPI_COMM_WORLD, KK_FULL);
  l.cmds(heated_block(50));
  unsetenv(env);
  return {l.equal("dt"), l.equal("f_heat[3]")};
}

// the number of particles fix contact/tri-penalty/kk id evaluated last (its extract "near")
const int *contact_near(Lammps &l, const char *id)
{
  int dim = -1;
  LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, id);
  return f ? static_cast<const int *>(f->extract("near", dim)) : nullptr;
}
}    // namespace

// the conservative form's passes with each neighbour's heat row (and in the exchange its scheme
// flag; its FMFS weights after the test) loaded before its support test (SPHCUT_LOAD_AHEAD=1, the
// default on a GPU) against the loads where they are read (0, the default on host threads): the
// same values in the same sums.  The two-material block (FMFS inside each block, Brookshaw across
// the interface and at the surface) to the bit, and the 2D cut in contact (the contact's atomic
// sums: 1e-10); anything but 0 or 1 is refused by name
TEST(KokkosThermal, HeatRowsLoadedEagerlyMatch)
{
  double e[2][6];
  Snapshot s[2];
  for (int k = 0; k < 2; k++) {
    setenv("SPHCUT_LOAD_AHEAD", k ? "0" : "1", 1);
    s[k] = two_material_block(KK_FULL, "", e[k]);
    unsetenv("SPHCUT_LOAD_AHEAD");
  }
  std::printf("[ eager    ] block: rise %.3e, heat vector %.3e (FMFS fraction %.3f)\n", rise_diff(s[0], s[1]),
              vector_diff(std::vector<double>(e[0], e[0] + 6), std::vector<double>(e[1], e[1] + 6)), e[0][5]);
  expect_same(s[0], s[1], "eager block", 1e-15);
  EXPECT_EQ(rise_diff(s[0], s[1]), 0.0);
  for (int c = 0; c < 6; c++) EXPECT_EQ(e[0][c], e[1][c]) << "f_heat[" << c + 1 << "]";
  EXPECT_GT(e[0][5], 0.05);    // FMFS weights in use (8 %: a small block, mostly surface), not Brookshaw alone
  EXPECT_LT(e[0][5], 1.0);    // and Brookshaw at the interface and the surface

  Snapshot c[2];
  CutEnd end[2];
  double fmfs = 0.0;
  for (int k = 0; k < 2; k++) {
    auto l = counted_cut("0.6", 300, "SPHCUT_LOAD_AHEAD", k ? "0" : "1");
    c[k] = take(*l);
    end[k] = cut_end(*l);
    fmfs = l->equal("f_heat[6]");
  }
  std::printf("[ eager    ] 2D cut: rise %.3e (FMFS fraction %.3f)\n", rise_diff(c[0], c[1]), fmfs);
  expect_same(c[0], c[1], "eager cut");
  EXPECT_LT(rise_diff(c[0], c[1]), 1e-10);
  expect_same_cut_end(end[0], end[1]);
  EXPECT_GT(fmfs, 0.3);

  auto block = heated_block(0);
  block.pop_back();    // (its run)
  expect_switch_refused("SPHCUT_LOAD_AHEAD", "2", block, "run 0");
}

// an ordinary step of the heat fix launches no kernel of its own under /kk: the held rate joins
// the temperature rate in fix sph/jc-thermal/kk's corrector, the Dirichlet particles' predicted
// temperature is set in its first-half kernel and their temperature after the corrector in its
// corrector's reduction, which also sums the heat that takes (the heat rules, set_heat_rules);
// the heat fix launches only its evaluation every 5 steps.  With an adaptive step (cfl) the
// corrector's reduction writes the heat fix's thermal dt limit into its slot (no heat:dt_limit)
TEST(KokkosThermal, OrdinaryStepLaunchesNoHeatKernel)
{
  Lammps l(MPI_COMM_WORLD, KK_FULL);
  l.cmds(heated_block(0));
  launches.clear();
  {
    CountLaunches count(l.lmp);
    l.cmd("run 20");
  }
  int heat = 0;
  for (auto &n : launches)
    if (n.first.rfind("sphcut:heat:", 0) == 0) {
      std::printf("[ launches ] %-32s %3d in 20 steps\n", n.first.c_str(), n.second);
      heat += n.second;
      EXPECT_LE(n.second, 4) << n.first;    // a heat kernel at most once per evaluation, none on other steps
    }
  EXPECT_EQ(launches["sphcut:sph:initial_integrate"], 20);    // the counting works
  EXPECT_EQ(launches["sphcut:sph:final_integrate"], 20);
  EXPECT_EQ(launches["sphcut:heat:weights"], 4);              // the evaluations (steps 5, 10, 15, 20)
  EXPECT_EQ(launches["sphcut:heat:final_integrate"], 0);      // the Dirichlet heat: in the corrector's
  EXPECT_EQ(launches["sphcut:heat:dt_limit"], 0);             // reduction, and the thermal limit
  EXPECT_EQ(launches["sphcut:heat:add_held"], 0);
  EXPECT_EQ(launches["sphcut:heat:set_dirichlet"], 0);
  EXPECT_EQ(launches["sphcut:heat:zero_weights"], 0);    // cleared in the passes that set them
  EXPECT_EQ(launches["sphcut:heat:zero_surface"], 0);    // (the list holds every local particle)
  EXPECT_EQ(launches["sphcut:heat:zero_held"], 0);
  EXPECT_GT(l.equal("f_heat[3]"), 0.0);    // heat entered through the hot Dirichlet layer
}

// the launches of fix contact/tri-penalty/kk in the 2D cut with thermal tool particles: per
// ordinary step the contact reduction and, with the tool beside the workpiece (xstart 0.6), the
// tool particles' heat gather, which fix sph/jc-thermal/kk's corrector kernel applies (that of the
// step, or the next step's first-half kernel where the corrector joins it: no kernel of the
// contact fix's own); none while the tool is away (xstart 3, the first 100 steps).  The
// cross neighbours they walk are built at each setup and once per build of the neighbour lists
// in the steps (ncalls counts these, not the setup's); the accumulators that an output step's
// fetch read are zeroed by the next contact reduction, not by a fill (peratom_every 10)
TEST(KokkosThermal, ContactLaunchesPerOrdinaryStep)
{
  for (const int near : {1, 0}) {
    {
      const int steps = near ? 600 : 100;
      const auto l = counted_cut(near ? "0.6" : "3", steps, nullptr, nullptr);
      const std::string what = near ? "tool near" : "tool away";
      for (auto &n : launches)
        if (n.first.rfind("sphcut:contact:", 0) == 0)
          std::printf("[ launches ] %s: %-34s %3d in %d steps\n", what.c_str(), n.first.c_str(), n.second, steps);
      std::printf("[ launches ] %s: sphcut:contact:cross_build %d in the steps for %ld list builds, %d in the 2 "
                  "setups; %d fills of the sums\n", what.c_str(), scans["sphcut:contact:cross_build"], max_builds,
                  scans["setup sphcut:contact:cross_build"], sums_fills);
      EXPECT_EQ(launches["sphcut:contact:post_force"], steps) << what;    // the counting works
      // (on several ranks: on those with tool particles beside the workpiece)
      int gather = launches["sphcut:contact:tool_heat_gather"], gmax = 0;
      MPI_Allreduce(&gather, &gmax, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
      EXPECT_TRUE(gather == 0 || gather == steps) << what;
      EXPECT_EQ(gmax, 0) << what;
      EXPECT_EQ(scans["sphcut:contact:cross_build"], max_builds) << what;
      EXPECT_EQ(scans["setup sphcut:contact:cross_build"], 2) << what;    // run 0 and the run
      EXPECT_EQ(sums_fills, 0) << what;
      if (near) {
        EXPECT_GT(max_builds, 0);                // the lists were built during the run
        EXPECT_GT(l->equal("f_cut[7]"), 0.0);    // friction heat went into the tool particles
        EXPECT_GT(l->equal("f_heat[4]"), 0.0);
      }
    }
  }
}

// the pair's rows of the local particles are packed in fix sph/jc-thermal/kk's first-half kernel:
// in the 2D cut on one rank (no ghost atoms) the pair's stress pass runs only at the steps where
// the lists were rebuilt (the atoms may have moved in the arrays); on several it packs the ghosts
// every step
TEST(KokkosThermal, PairRowsPackedInTheFirstHalf)
{
  const int steps = 600;
  const auto l = counted_cut("0.6", steps, nullptr, nullptr);
  const int packs = launches["sphcut:pair:stress_pass"];
  const long builds = max_builds;
  const CutEnd end = cut_end(*l);
  std::printf("[ prepack  ] %d stress passes in %d steps (%ld list builds); Fc %.15g, Ft %.15g\n", packs, steps, builds,
              end.fc, end.ft);
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  EXPECT_GT(builds, 0);
  if (nprocs == 1) EXPECT_EQ(packs, (int) builds);    // only where the lists were rebuilt
  else EXPECT_EQ(packs, steps);                        // the ghosts every step
  EXPECT_GT(end.fc, 20.0);    // in contact
}

// where the first-half kernel works on staged rows by default (FixSPHJCThermalKokkos::stage_choice:
// on a GPU from 500,000 local particles: bench/gpu/RESULTS.md, "The first half on staged rows");
// SPHCUT_STAGE_ROWS overrides (2: staged, in teams of 2 threads on a host backend)
TEST(KokkosThermal, StagedRowsChoice)
{
  using FK = LAMMPS_NS::FixSPHJCThermalKokkos<LMPDeviceType>;
  EXPECT_FALSE(FK::stage_choice(18272, false, -1));
  EXPECT_FALSE(FK::stage_choice(70570, false, -1));
  EXPECT_TRUE(FK::stage_choice(1009750, false, -1));    // the 1 M-particle 3D cut with free sides
  EXPECT_TRUE(FK::stage_choice(4239104, false, -1));
  EXPECT_FALSE(FK::stage_choice(4239104, true, -1));    // host threads
  EXPECT_TRUE(FK::stage_choice(1384, true, 1));         // forced
  EXPECT_TRUE(FK::stage_choice(1384, true, 2));
  EXPECT_FALSE(FK::stage_choice(4239104, false, 0));
}

// fix sph/jc-thermal/kk's first-half kernel on team-staged copies of the state rows (the default on
// a GPU from 500,000 particles; SPHCUT_STAGE_ROWS=1 here, on this host backend one thread a team):
// the 2D cut in contact (the heat rules, the pair's rows packed in the first half) and the 3D
// collision give the state of the kernel in place, particle by particle, and so do the step's sums
// (dt, plastic work, the heat through a Dirichlet layer); anything but 0, 1 or 2 is refused by name
TEST(KokkosThermal, StagedRowsMatchInPlace)
{
  const int steps = 600;
  CutEnd end[2];
  Snapshot snap[2];
  double sums[2][3];    // dt, the plastic work, the Dirichlet heat
  for (const int staged : {1, 0}) {
    const auto l = counted_cut("0.6", steps, "SPHCUT_STAGE_ROWS", staged ? "1" : "0");
    // the kernel taken (alone or with the step before's corrector)
    EXPECT_EQ(launches["sphcut:sph:initial_integrate_staged"] + launches["sphcut:sph:correct_then_first_half_staged"],
              staged ? steps : 0);
    EXPECT_EQ(launches["sphcut:sph:initial_integrate"] + launches["sphcut:sph:correct_then_first_half"],
              staged ? 0 : steps);
    EXPECT_GT(launches[staged ? "sphcut:sph:correct_then_first_half_staged" : "sphcut:sph:correct_then_first_half"], 0);
    end[staged] = cut_end(*l);
    snap[staged] = take(*l);
    sums[staged][0] = l->equal("f_sph[1]");
    sums[staged][1] = l->equal("f_sph[4]");
    sums[staged][2] = l->equal("f_heat[3]");
    std::printf("[ staged   ] SPHCUT_STAGE_ROWS=%d: Fc %.15g, Ft %.15g, internal energy %.15g; dt %.15g, plastic "
                "work %.15g, Dirichlet heat %.15g\n", staged, end[staged].fc, end[staged].ft, end[staged].eint,
                sums[staged][0], sums[staged][1], sums[staged][2]);
  }
  EXPECT_GT(end[1].fc, 20.0);    // in contact
  expect_same_cut_end(end[1], end[0]);
  expect_same(snap[0], snap[1], "staged cut");
  EXPECT_EQ(sums[1][0], sums[0][0]);    // a minimum: the same in any order
  EXPECT_GT(sums[0][1], 0.0);
  EXPECT_NEAR(sums[1][1], sums[0][1], 1e-12 * sums[0][1]);
  // the Dirichlet heat (a block heated from its bottom layer; the cut's clamp has not warmed yet)
  double qdir[2];
  for (const int staged : {1, 0}) qdir[staged] = heated_block_under("SPHCUT_STAGE_ROWS", staged ? "1" : "0").qdir;
  std::printf("[ staged   ] Dirichlet heat of the heated block: %.15g / %.15g J\n", qdir[1], qdir[0]);
  EXPECT_GT(qdir[0], 0.0);
  EXPECT_NEAR(qdir[1], qdir[0], 1e-12 * qdir[0]);
  setenv("SPHCUT_STAGE_ROWS", "1", 1);
  const Snapshot staged3 = run(KK_FULL, "off", 3, 100);
  unsetenv("SPHCUT_STAGE_ROWS");
  expect_same(run({}, "on", 3, 100), staged3, "kk staged 3D");
  expect_switch_refused("SPHCUT_STAGE_ROWS", "3", collision("off"), "run 0", "0, 1 or 2");
}

namespace {
// the heated block (heated_block) with the adaptive step recomputed every dtevery steps and thermo
// output every 100 (without any, fix sph/jc-thermal's per-atom values are current every step)
std::vector<std::string> heated_block_every(int nsteps, int dtevery)
{
  auto c = heated_block(nsteps);
  for (auto &line : c) {
    if (line.rfind("fix sph ", 0) == 0) line += " dtevery " + std::to_string(dtevery);
    if (line == "thermo 0") line = "thermo 100";
  }
  return c;
}

// fix external's callback: no force (its array is not zeroed by LAMMPS), and LAMMPS' timeout
// forced at the step given (the run ends after it)
LAMMPS_NS::bigint timeout_step = -1;
void force_timeout_at(void *ptr, LAMMPS_NS::bigint step, int nlocal, LAMMPS_NS::tagint *, double **, double **fext)
{
  for (int i = 0; i < nlocal; i++)
    for (int d = 0; d < 3; d++) fext[i][d] = 0.0;
  if (step == timeout_step) static_cast<LAMMPS_NS::LAMMPS *>(ptr)->timer->force_timeout();
}

// the heated block after nsteps steps, its corrector fused where it may be (fuse 1) or never (0: a
// fix print every step keeps each step's corrector), or (stop > 0) a run of nsteps that a timeout
// ends after step stop; more: commands before the run
Snapshot heated_block_run(int fuse, int nsteps, int stop, double *qdir, const std::vector<std::string> &more = {})
{
  Lammps l(MPI_COMM_WORLD, KK_FULL);
  l.cmds(heated_block_every(0, 5));
  l.cmds(more);
  if (!fuse) l.cmd("fix nofuse all print 1 \"x\" screen no");
  if (stop > 0) {
    l.cmd("fix ext all external pf/callback 1 1");
    auto *fe = static_cast<LAMMPS_NS::FixExternal *>(sphcut::fix_by_id(l.lmp->modify, "ext"));
    fe->set_callback(force_timeout_at, l.lmp);
    timeout_step = stop;
  }
  launches.clear();
  {
    CountLaunches count(l.lmp);
    l.cmd("run " + std::to_string(nsteps));
  }
  timeout_step = -1;
  if (stop > 0) EXPECT_EQ(l.lmp->update->ntimestep, stop);    // the timeout ended the run there
  *qdir = l.equal("f_heat[3]");
  return take(l);
}
}    // namespace

// fix sph/jc-thermal/kk leaves a step's corrector to the next step's first-half kernel
// (CorrectThenFirstHalf: one launch and one pass over the state rows fewer) where nothing reads v
// or the state in between: not at a dt step (dtevery), an output step, a step of another fix's
// end_of_step (here fix print every 10 and fix halt every 100), nor the run's last.  The 2D cut in
// contact (the heat rules, the pair's rows packed in the first half, the tool-heat gather of the
// step before), in place and on staged rows, gives the state of the two kernels,
// and so do the step's sums; a run that a timeout ends after a deferred step finishes its
// corrector (post_run); the heated block fused gives the state of the block whose every step keeps
// its corrector (a fix print every step)
TEST(KokkosThermal, CorrectorJoinsTheNextFirstHalf)
{
  const int steps = 600;
  // the steps deferred: neither a multiple of dtevery (4) nor of 10 (fix print; thermo and fix
  // halt every 100), nor the last
  int deferred = 0;
  for (int s = 1; s < steps; s++) deferred += s % 4 != 0 && s % 10 != 0;
  CutEnd end[3];
  Snapshot snap[3];
  double sums[3][2];    // dt, the plastic work
  // fused in place, fused staged (teams of 1 and of 2 threads: their sums joined by the team
  // reduction, as a GPU's teams of 32)
  for (const int run : {0, 1, 2}) {
    const auto l = counted_cut("0.6", steps, run ? "SPHCUT_STAGE_ROWS" : nullptr, run == 2 ? "2" : "1",
                               {"dtevery index 4"});
    const int fused = launches["sphcut:sph:correct_then_first_half"],
              staged = launches["sphcut:sph:correct_then_first_half_staged"];
    std::printf("[ fused    ] %s: %d + %d fused, %d first halves, %d correctors, %d gather kernels of the "
                "contact fix in %d steps\n",
                run == 0 ? "in place" : run == 1 ? "staged" : "staged, teams of 2",
                fused, staged,
                launches["sphcut:sph:initial_integrate"] + launches["sphcut:sph:initial_integrate_staged"],
                launches["sphcut:sph:final_integrate"], launches["sphcut:contact:tool_heat_gather"], steps);
    EXPECT_EQ(fused, run == 0 ? deferred : 0);
    EXPECT_EQ(staged, run != 0 ? deferred : 0);
    EXPECT_EQ(launches["sphcut:sph:initial_integrate"] + launches["sphcut:sph:initial_integrate_staged"], steps - deferred);
    EXPECT_EQ(launches["sphcut:sph:final_integrate"], steps - deferred);
    EXPECT_EQ(launches["sphcut:contact:tool_heat_gather"], 0);    // in the integrator's kernels
    end[run] = cut_end(*l);
    snap[run] = take(*l);
    sums[run][0] = l->equal("f_sph[1]");
    sums[run][1] = l->equal("f_sph[4]");
    EXPECT_GT(l->equal("f_cut[7]"), 0.0);    // friction heat went into the tool particles
  }
  EXPECT_GT(end[0].fc, 20.0);    // in contact
  EXPECT_GT(sums[0][1], 0.0);
  // staged against in place (to round-off: on 2 threads two runs of the cut may differ by about
  // 2e-12 in the state, the contact's sums being atomics; the heated block below has none, and is
  // compared to 1e-13)
  for (const int run : {1, 2}) {
    expect_same_cut_end(end[run], end[0]);
    expect_same(snap[run], snap[0], run == 1 ? "fused staged" : "fused staged, teams of 2", 1e-11);
    EXPECT_EQ(sums[run][0], sums[0][0]);
    EXPECT_NEAR(sums[run][1], sums[0][1], 1e-12 * sums[0][1]);
  }
  // the heated block (the held rate and the Dirichlet layer, dtevery 5): 60 steps, and a run of
  // 500 that a timeout ends after step 37 (deferred) against 37 steps with the two kernels
  double q[4];
  const Snapshot a = heated_block_run(1, 60, 0, &q[0]);
  EXPECT_EQ(launches["sphcut:sph:correct_then_first_half"], 48);    // after steps 1-59 but the multiples of 5
  const Snapshot b = heated_block_run(0, 60, 0, &q[1]);
  EXPECT_EQ(launches["sphcut:sph:correct_then_first_half"], 0);    // a fix print every step
  double qs = 0.0;    // staged, teams of 2 threads
  setenv("SPHCUT_STAGE_ROWS", "2", 1);
  const Snapshot s2 = heated_block_run(1, 60, 0, &qs);
  unsetenv("SPHCUT_STAGE_ROWS");
  EXPECT_EQ(launches["sphcut:sph:correct_then_first_half_staged"], 48);
  expect_same(s2, b, "fused block staged, teams of 2", 1e-13);
  EXPECT_NEAR(qs, q[1], 1e-12 * q[1]);
  const Snapshot c = heated_block_run(1, 500, 37, &q[2]);
  EXPECT_EQ(launches["sphcut:sph:correct_then_first_half"], 29);    // after steps 1-36 but 5 ... 35
  const Snapshot d = heated_block_run(0, 37, 0, &q[3]);
  std::printf("[ fused    ] Dirichlet heat of the heated block: %.15g / %.15g J (60 steps), %.15g / %.15g (37)\n",
              q[0], q[1], q[2], q[3]);
  expect_same(a, b, "fused block", 1e-13);
  expect_same(c, d, "fused block ended by a timeout", 1e-13);
  EXPECT_GT(q[1], 0.0);
  EXPECT_NEAR(q[0], q[1], 1e-12 * q[1]);
  EXPECT_NEAR(q[2], q[3], 1e-12 * q[3]);
  // a fix print every 3 steps of an atom's velocity (read on the host, no fix sph/jc-thermal output
  // that would finish the corrector itself): its steps keep their corrector too
  const std::vector<std::string> print = {"variable vz equal vz[100]", "fix pr all print 3 \"${vz}\" screen no"};
  const Snapshot e = heated_block_run(1, 60, 0, &q[0], print);
  EXPECT_EQ(launches["sphcut:sph:correct_then_first_half"], 32);    // after steps 1-59 but those of 3 or 5
  expect_same(e, b, "fused block printed every 3 steps", 1e-13);
}

// the reductions over the particles (fix sph/jc-thermal/kk's corrector, fix heat/fmfs/kk's two
// passes, fix contact/tri-penalty/kk's kernel) on the wide path of sphcut::reduce (one thread per
// particle, the warps' values joined by atomics, the last to join runs the final: a GPU's default)
// against Kokkos' range reductions: the same cut and state, the same step (a minimum: any order),
// the plastic work and the heat fix's sums (convection and radiation, the scheme counters) to
// round-off; one kernel a reduction.  The corrector's thermal dt limit (a second
// minimum) through the heated block's adaptive step
TEST(KokkosThermal, WideReductionsMatchKokkos)
{
  const int steps = 600;
  CutEnd end[2];
  Snapshot snap[2];
  double sums[2][2];    // dt, the plastic work
  double heat[2][6];    // fix heat/fmfs's vector
  for (const int wide : {1, 0}) {
    const auto l = counted_cut("0.6", steps, "SPHCUT_WIDE_REDUCE", wide ? "1" : "0");
    // one kernel a reduction (the last warp runs its final); the accumulator set up once (the
    // corrector's in the first step, the others' in the setup, which is not counted).  The
    // contact kernel of a rank with no particle near the tool (2 ranks) is its final alone
    // (the correctors in the next step's first-half kernel but at the dt and print steps)
    EXPECT_EQ(launches["sphcut:sph:final_integrate"] + launches["sphcut:sph:correct_then_first_half"], steps);
    EXPECT_EQ(launches["sphcut:sph:final_integrate:acc_init"] + launches["sphcut:sph:correct_then_first_half:acc_init"],
              wide);
    EXPECT_GT(launches["sphcut:heat:exchange"], steps / 20);    // (every 10 steps)
    EXPECT_GE(launches["sphcut:contact:post_force"] + launches["sphcut:contact:post_force:final"], steps);
    if (!wide) EXPECT_EQ(launches["sphcut:contact:post_force:final"], 0);
    for (const char *k : {"sphcut:sph:final_integrate", "sphcut:heat:weights", "sphcut:heat:exchange"})
      EXPECT_EQ(launches[std::string(k) + ":final"], 0) << k;
    end[wide] = cut_end(*l);
    snap[wide] = take(*l);
    sums[wide][0] = l->equal("f_sph[1]");
    sums[wide][1] = l->equal("f_sph[4]");
    for (int k = 0; k < 6; k++) heat[wide][k] = l->equal("f_heat[" + std::to_string(k + 1) + "]");
    std::printf("[ wide     ] SPHCUT_WIDE_REDUCE=%d: Fc %.15g, Ft %.15g; dt %.15g, plastic work %.15g; heat fix "
                "%.15g %.15g %.15g %.15g %.15g %.15g\n", wide, end[wide].fc, end[wide].ft, sums[wide][0],
                sums[wide][1], heat[wide][0], heat[wide][1], heat[wide][2], heat[wide][3], heat[wide][4],
                heat[wide][5]);
  }
  EXPECT_GT(end[1].fc, 20.0);    // in contact
  expect_same_cut_end(end[1], end[0]);
  expect_same(snap[0], snap[1], "wide reductions");
  EXPECT_EQ(sums[1][0], sums[0][0]);
  EXPECT_GT(sums[0][1], 0.0);
  EXPECT_NEAR(sums[1][1], sums[0][1], 1e-12 * sums[0][1]);
  for (int k = 0; k < 6; k++) EXPECT_NEAR(heat[1][k], heat[0][k], 1e-12 * fabs(heat[0][k])) << "f_heat[" << k + 1 << "]";
  EXPECT_GT(fabs(heat[0][1]), 0.0);    // the convective heat: summed
  // the heated block's adaptive step (its thermal limit reduced in the corrector)
  double dt[2], qdir[2];
  for (const int wide : {1, 0}) {
    const BlockEnd b = heated_block_under("SPHCUT_WIDE_REDUCE", wide ? "1" : "0");
    dt[wide] = b.dt;
    qdir[wide] = b.qdir;
  }
  std::printf("[ wide     ] heated block: dt %.15g / %.15g s, Dirichlet heat %.15g / %.15g J\n", dt[1], dt[0],
              qdir[1], qdir[0]);
  EXPECT_EQ(dt[1], dt[0]);
  EXPECT_GT(qdir[0], 0.0);
  EXPECT_NEAR(qdir[1], qdir[0], 1e-12 * qdir[0]);
  auto block = heated_block(0);
  block.pop_back();    // (its run)
  expect_switch_refused("SPHCUT_WIDE_REDUCE", "yes", block, "run 0");
}

// a reduction of two values for sphcut::wide_reduce: the sum of i + 1 and the minimum of 1000 - i;
// final copies them into out and counts itself in out(2)
struct TwoValues {
  Kokkos::View<double *, LMPDeviceType> out;
  KOKKOS_INLINE_FUNCTION static constexpr bool is_min(int k) { return k == 1; }
  KOKKOS_INLINE_FUNCTION void init(double *r) const
  {
    r[0] = 0.0;
    r[1] = 1.0e300;
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, double *r) const
  {
    r[0] += i + 1.0;
    if (1000.0 - i < r[1]) r[1] = 1000.0 - i;
  }
  KOKKOS_INLINE_FUNCTION void final(double *r) const
  {
    out(0) = r[0];
    out(1) = r[1];
    out(2) += 1.0;
  }
};

// sphcut::wide_reduce on the host backend (each index's values by atomics, the last to join runs
// final): the sum and the minimum over 0, 1, 37 and 1000 indices through one accumulator, final
// once a call (with no index from a kernel of its own), the accumulator reset between calls
TEST(KokkosThermal, WideReduceSumsAndMinima)
{
  Lammps l(MPI_COMM_WORLD, KK_FULL);    // (Kokkos initialised)
  Kokkos::View<double *, LMPDeviceType> out("out", 3);
  Kokkos::View<double *, LMPDeviceType::memory_space> acc;
  const TwoValues f{out};
  double finals = 0.0;
  for (const int n : {0, 1, 37, 1000, 37}) {
    sphcut::wide_reduce<LMPDeviceType, 2>("test:wide", n, f, acc);
    Kokkos::fence();
    finals += 1.0;
    EXPECT_EQ(out(0), 0.5 * n * (n + 1.0)) << n;
    EXPECT_EQ(out(1), n > 0 ? 1001.0 - n : 1.0e300) << n;
    EXPECT_EQ(out(2), finals) << n;
    EXPECT_EQ(acc(0), 0.0);        // reset to init
    EXPECT_EQ(acc(1), 1.0e300);
    EXPECT_EQ(acc(2), 0.0);        // the count
  }
}

// sphcut::wide_choice: the wide path on a GPU, Kokkos' reduction on a host backend, the
// environment's choice on either
TEST(KokkosThermal, WideReductionChoice)
{
  EXPECT_TRUE(sphcut::wide_choice(false, -1));
  EXPECT_FALSE(sphcut::wide_choice(true, -1));
  EXPECT_TRUE(sphcut::wide_choice(true, 1));
  EXPECT_FALSE(sphcut::wide_choice(false, 0));
}

// LAMMPS' launch of its force clear (the Zero functor) outside the setups
int zero_launches()
{
  int n = 0;
  for (auto &k : launches)
    if (k.first.find("Zero") != std::string::npos && k.first.find("MemsetZero") == std::string::npos) n += k.second;
  return n;
}

// with newton off fix sph/jc-thermal/kk zeroes the forces in its first-half kernel, after the half
// kick has read them, and after each reneighbouring in pre_force (the exchange and the sort move
// atoms into rows the kernel did not zero): LAMMPS' own force clear is not launched in the steps,
// also when the cut goes on with the lists rebuilt at every step and the atoms sorted every 10.
// After each run the integrator clears them again (its flag restored)
TEST(KokkosThermal, ForcesClearedInTheFirstHalf)
{
  const int steps = 600;
  const auto l = counted_cut("0.6", steps, nullptr, nullptr);
  const int zeros = zero_launches();
  const CutEnd end = cut_end(*l);
  EXPECT_EQ(sphcut::IntegrateForceClear::flag(l->lmp->update->integrate), 0);    // restored at post_run
  l->cmd("atom_modify sort 10 0.0");
  l->cmd("neigh_modify every 1 delay 0 check no");
  l->cmd("run 100");
  const CutEnd end2 = cut_end(*l);
  std::printf("[ f clear  ] %d force clears in %d steps; Fc %.15g, Ft %.15g; after 100 steps sorted every 10: Fc "
              "%.15g, Ft %.15g\n", zeros, steps, end.fc, end.ft, end2.fc, end2.ft);
  EXPECT_EQ(zeros, 0);
  EXPECT_EQ(sphcut::IntegrateForceClear::flag(l->lmp->update->integrate), 0);
  EXPECT_GT(end.fc, 20.0);    // in contact
  EXPECT_GT(end2.fc, 20.0);
}

// fix heat/fmfs/kk keeps its loss rates, the convective and radiative heat and the scheme counters
// on the device during a run (its reductions' final writes them; the host forms the budget when it
// is read, from the time the current rates have acted for): the 2D cut run as 300 + 300 steps
// (the budget read between the runs, handed back at the second setup) gives the budget of one run
// of 600 steps; both are those of the CPU styles (the sums are formed in another order).
// Tolerances 2e-12, about 3x the largest difference measured (runs of test_kokkos, which start
// Kokkos with 2 threads): split / whole 0 on 29Sep2021 + Kokkos 3.4.01 (5 runs, the same bits each
// time), 0 to 7e-13 on 4Jul2026 + Kokkos 5.2.2 (0, 2.9e-14, 4.5e-14, 4.6e-13, 7e-13; 4.2e-13 on 2 ranks: the runs are
// not bit-reproducible there, two of them with one input give two budgets); whole / CPU 8.8e-14 on
// 29Sep2021, 2.4e-13 to 7.0e-13 on 4Jul2026
TEST(KokkosThermal, HeatBudgetAcrossRuns)
{
  auto budget = [](const std::vector<std::string> &args, int first, int second) {
    Lammps l(MPI_COMM_WORLD, args);
    // (xstart 0.5: the rake face half a spacing off, in contact from the start, as xstart 0.6 was
    // before the edge radius became an input and the insert's face lay 2.8 um nearer)
    for (auto &v : {std::string("ny index 11"), std::string("xstart index 0.5"), std::string("dumpevery index 0"),
                    std::string("printevery index 10"), "steps index " + std::to_string(first)})
      l.cmd("variable " + v);
    l.lmp->input->file(CUT2D.c_str());
    std::vector<double> b;
    if (second > 0) {
      b.push_back(l.equal("f_heat[1]"));    // read between the runs
      l.cmd("run " + std::to_string(second));
    }
    for (int k : {1, 2, 6}) b.push_back(l.equal("f_heat[" + std::to_string(k) + "]"));
    return b;
  };
  // t 1 takes effect only where this case starts Kokkos (run alone, --gtest_filter): a process keeps
  // the thread count Kokkos was first initialised with (LAMMPS cannot initialise it again; 29Sep2021
  // warns, 4Jul2026 does not), 2 in test_kokkos, whose first case uses KK_FULL.  On 2 threads the
  // contact's heat sums are atomics in an order that may change from run to run, and the cut's last
  // bits with it: seen on 4Jul2026 + Kokkos 5.2.2, not in the runs on 29Sep2021 + Kokkos 3.4.01
  std::vector<std::string> kk1(KK_FULL);
  kk1[3] = "1";
  const auto split = budget(kk1, 300, 300), whole = budget(kk1, 600, 0), cpu = budget({}, 600, 0);
  std::printf("[ budget   ] convection %.15g / %.15g / CPU %.15g J, radiation %.15g / %.15g / %.15g J, FMFS %.6f\n",
              split[1], whole[0], cpu[0], split[2], whole[1], cpu[1], whole[2]);
  double dsplit = 0.0, dcpu = 0.0;
  for (int k = 0; k < 3; k++) {
    dsplit = std::max(dsplit, fabs(split[k + 1] - whole[k]) / fabs(whole[k]));
    dcpu = std::max(dcpu, fabs(whole[k] - cpu[k]) / fabs(cpu[k]));
  }
  std::printf("[ budget   ] relative difference split / whole %.3e, whole / CPU %.3e (LAMMPS %d, %d Kokkos threads)\n",
              dsplit, dcpu, SPHCUT_LAMMPS_VERSION, (int) Kokkos::DefaultExecutionSpace().concurrency());
  EXPECT_GT(split[0], 0.0);
  EXPECT_GT(split[1], 2.0 * split[0]);    // the second run added to the first's
  // (on one thread, the case run alone, equal to the printed digits on 1 and 2 ranks)
  const double rtol = 2e-12;
  for (int k = 0; k < 3; k++) {
    EXPECT_NEAR(split[k + 1], whole[k], rtol * fabs(whole[k])) << k;
    EXPECT_NEAR(whole[k], cpu[k], rtol * fabs(cpu[k])) << k;
  }
}

// output steps under /kk: fix sph/jc-thermal/kk copies the output columns of the state to the
// host (the dumps' and f_ID[k]'s, which the example's rake temperature reads every printevery
// steps), and fix print and fix halt no longer declare every atom array modified on the host (a
// copy of all of them to the device after each of their steps).  The cut's forces.dat (the
// rake temperature, Tmax) has a line every printevery steps, heated in contact
TEST(KokkosThermal, OutputStepsCopyTheOutputColumns)
{
  const int steps = 600;
  std::vector<std::string> lines;
  const auto l = counted_cut("0.6", steps, nullptr, nullptr);
  for (const char *id : {"series", "stop"}) {
    const auto *f = sphcut::fix_by_id(l->lmp->modify, id);
    ASSERT_NE(f, nullptr) << id;
    // the masks' own type: unsigned int to 4Feb2025, uint64_t in 4Jul2026
    using mask_t = decltype(f->datamask_read);
    EXPECT_EQ(f->datamask_modify, (mask_t) EMPTY_MASK) << id;
    EXPECT_EQ(f->datamask_read, (mask_t) ALL_MASK) << id;
  }
  const double tmax = l->equal("f_sph[5]");
  std::ifstream in("forces.dat");
  for (std::string s; std::getline(in, s);) lines.push_back(s);
  std::printf("[ output   ] forces.dat, %zu lines; Tmax %.15g K\n", lines.size(), tmax);
  EXPECT_GT(lines.size(), (size_t) steps / 10);    // a line every printevery (10) steps
  EXPECT_GT(tmax, 310.0);    // in contact: heated (338 K, from 300)
}

// The examples' line of forces.dat under -sf kk reads nothing per atom on the host: compute
// reduce/region/kk reduces the rake temperature on the device, fix sph/jc-thermal/kk its global
// vector.  The 2D cut writes the line every 10 steps while the fix's per-atom array reaches the
// host only every 100 (its default, the thermo interval: the example gives no peratom_every), at
// which LAMMPS' host compute would stop the run ("not computed at compatible time"); the lines
// and the global vector as on the CPU.  Then, in the state after the run, each mode and source of
// the device path, a moving region, a group and a region it leaves to LAMMPS' compute against
// LAMMPS' compute reduce/region (reduce/region/kk/host: the device path on the host backend)
TEST(KokkosThermal, OutputsReducedOnTheDevice)
{
  const std::vector<std::string> vars = {"ny index 11", "xstart index 0.6", "steps index 600", "dumpevery index 0",
                                         "thermoevery index 100", "printevery index 10"};
  std::vector<std::vector<double>> rows[2];
  double glob[2][4];
  for (const int kk : {0, 1}) {
    Lammps l(MPI_COMM_WORLD, kk ? KK_FULL : std::vector<std::string>{});
    for (auto &v : vars) l.cmd("variable " + v);
    l.lmp->input->file(CUT2D.c_str());
    MPI_Barrier(MPI_COMM_WORLD);    // (fix print flushes each line)
    rows[kk] = numeric_rows("forces.dat", 7);
    const auto *trake = sphcut::compute_by_id(l.lmp->modify, "Trake");
    ASSERT_NE(trake, nullptr);
    EXPECT_STREQ(trake->style, kk ? "reduce/region/kk" : "reduce/region");
    for (int k = 0; k < 4; k++) glob[kk][k] = l.equal("f_sph[" + std::to_string(k < 2 ? k + 2 : k + 3) + "]");
    if (!kk) continue;
    const auto *sph = sphcut::fix_by_id(l.lmp->modify, "sph");
    ASSERT_NE(sph, nullptr);
    EXPECT_EQ(sph->peratom_freq, 100);
    // the same state: the device path (and its fall-back) against LAMMPS' compute on the host
    l.cmds({"region ball sphere $(v_xtip) $(v_ytip) 0 $(8*v_dx) units box",
            "region all block INF INF INF INF INF INF units box", "variable shift equal 4.5*v_dx",
            "region moved block 0 $(3*v_dx) 0 $(3*v_dx) INF INF units box move v_shift v_shift NULL"});
    const std::vector<std::string> cases = {
        "work REGION rakeframe ave f_sph[12] x vy", "work REGION rakeframe max f_sph[12] vx f_sph[13]",
        "work REGION rakeframe min fy f_sph[12]", "work REGION rakeframe sumsq vx fx",
        "work REGION rakeframe avesq f_sph[12]", "tool REGION all sum f_sph[12] y",
        "work REGION moved ave x y", "work REGION ball ave f_sph[12] x"};
    std::string thermo = "thermo_style custom step";
    for (size_t c = 0; c < cases.size(); c++)
      for (const char *v : {"kk", "ref"}) {
        std::string def = cases[c];
        def.replace(def.find("REGION"), 6, std::string(v) == std::string("kk") ? "reduce/region/kk/host" : "reduce/region");
        l.cmds({std::string("suffix ") + (def.find("/kk") != std::string::npos ? "on" : "off"),    // (-sf kk)
                "compute " + std::string(v) + std::to_string(c) + " " + def});
        thermo += " c_" + std::string(v) + std::to_string(c) + (c == 4 ? "" : "[1]");    // (4: one value, a scalar)
      }
    l.cmds({"suffix on", thermo, "run 0"});
    EXPECT_STREQ(sphcut::compute_by_id(l.lmp->modify, "ref0")->style, "reduce/region");
    for (size_t c = 0; c < cases.size(); c++) {
      const int nv = c == 4 ? 1 : 2;
      for (int m = 1; m <= nv; m++) {
        const std::string idx = std::to_string(c) + (nv > 1 ? "[" + std::to_string(m) + "]" : "");
        const double ref = l.equal("c_ref" + idx), dev = l.equal("c_kk" + idx);
        EXPECT_NEAR(dev, ref, 1e-12 * std::max(fabs(ref), 1e-30)) << cases[c] << " value " << m;
        if (m == 1) EXPECT_NE(ref, 0.0) << cases[c];    // particles in the region
      }
    }
  }
  ASSERT_GT(rows[1].size(), 600u / 10);    // a line every 10 steps
  ASSERT_EQ(rows[0].size(), rows[1].size());
  double d = 0.0;
  for (size_t r = 0; r < rows[0].size(); r++)
    for (int c = 5; c < 7; c++) d = std::max(d, fabs(rows[1][r][c] - rows[0][r][c]) / rows[0][r][c]);
  std::printf("[ outputs  ] Tmax, Trake every 10 steps /kk vs CPU %.2e; Trake %.1f K at the end\n", d, rows[0].back()[6]);
  EXPECT_GT(rows[0].back()[6], 310.0);    // in contact: the rake frame heated (from 300 K)
  EXPECT_LT(d, 1e-10);
  for (int k = 0; k < 4; k++) EXPECT_NEAR(glob[1][k], glob[0][k], 1e-10 * fabs(glob[0][k])) << "f_sph element " << k;
}

// fix sph/jc-thermal/kk's per-atom array is valid on the host every gcd(thermo interval, dump
// intervals) steps by default: each dump step is an output step, at which the fix copies it.  The
// 2D example with a dump every 100 steps and thermo every 500 runs (LAMMPS checks the dump's
// interval against peratom_freq: the thermo interval alone stopped it), and the dump's last frame
// holds the temperatures of its step (their maximum: Tmax, reduced on the device)
TEST(KokkosThermal, PerAtomIntervalFollowsTheDumps)
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  for (const int dump : {0, 100}) {
    Lammps l(MPI_COMM_WORLD, KK_FULL);
    // (xstart 0.5: in contact from the start, HeatBudgetAcrossRuns)
    for (const std::string v : {"ny index 11", "xstart index 0.5", "steps index 300", "thermoevery index 500",
                                "printevery index 100"})
      l.cmd("variable " + v);
    l.cmd("variable dumpevery index " + std::to_string(dump));
    if (me == 0) std::remove("dump.cutting");
    ASSERT_NO_THROW(l.lmp->input->file(CUT2D.c_str())) << "dump every " << dump;
    const auto *sph = sphcut::fix_by_id(l.lmp->modify, "sph");
    ASSERT_NE(sph, nullptr);
    EXPECT_EQ(sph->peratom_freq, dump ? 100 : 500);
    if (!dump) continue;
    const double tmax = l.equal("f_sph[5]");
    MPI_Barrier(MPI_COMM_WORLD);
    // the last frame's temperature column
    std::ifstream in("dump.cutting");
    int col = -1, last_step = -1;
    double fmax = 0.0;
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("ITEM: TIMESTEP", 0) == 0) {
        std::getline(in, line);
        last_step = std::stoi(line);
        fmax = 0.0;
      } else if (line.rfind("ITEM: ATOMS", 0) == 0) {
        std::istringstream h(line.substr(12));
        int k = 0;
        for (std::string name; h >> name; k++)
          if (name == "temperature") col = k;
      } else if (col >= 0 && !line.empty() && line.rfind("ITEM:", 0) != 0) {
        std::istringstream r(line);
        std::string tok;
        for (int k = 0; k <= col && r >> tok; k++)
          if (k == col) fmax = std::max(fmax, std::stod(tok));
      }
    }
    ASSERT_GE(col, 0);
    EXPECT_EQ(last_step, 300);
    EXPECT_GT(tmax, 301.0);    // in contact: heated
    EXPECT_NEAR(fmax, tmax, 1e-5 * tmax);
  }
}

// fix contact/tri-penalty/kk evaluates only the particles near the tool (near_build: the
// candidates within twice the neighbour skin of the tool's bin grid): in the 2D cut in contact
// a few percent of the particles, more than are in contact
TEST(KokkosThermal, ContactEvaluatesTheParticlesNearTheTool)
{
  const int steps = 600;
  const auto l = counted_cut("0.6", steps, nullptr, nullptr);
  const CutEnd end = cut_end(*l);
  const double ncont = l->equal("f_cut[5]");
  const int *p = contact_near(*l, "cut");
  ASSERT_NE(p, nullptr);
  const int nnear = *p, nlocal = l->lmp->atom->nlocal;
  std::printf("[ near     ] Fc %.15g, Ft %.15g, %g in contact, %d of %d local particles evaluated\n", end.fc, end.ft,
              ncont, nnear, nlocal);
  EXPECT_GT(ncont, 2.0);    // in contact
  int counts[2] = {nnear, nlocal}, sums[2];
  MPI_Allreduce(counts, sums, 2, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_GT(sums[0], (int) ncont);    // (over the ranks)
  EXPECT_LT(sums[0], sums[1] / 4);
}

// the 2D example under /kk with its defaults (printevery 0: every 100 steps; neighevery 0: every 10)
// and -var steps 30: the run goes to step 100, a multiple of printevery, with a note (its last
// step's output reads per-atom values computed every printevery steps: 30 had ended in LAMMPS'
// "not computed at compatible time" error)
TEST(KokkosThermal, ExampleStepsRoundedToTheOutputInterval)
{
  Lammps l(MPI_COMM_WORLD, KK_FULL);
  for (auto &v : {"xstart index 3", "steps index 30", "ny index 11", "dumpevery index 0"})
    l.cmd(std::string("variable ") + v);
  l.lmp->input->file(CUT2D.c_str());
  EXPECT_EQ(l.lmp->update->ntimestep, 100);
  EXPECT_EQ(l.equal("v_printevery"), 100.0);
  EXPECT_EQ(l.lmp->neighbor->every, 10);
}

// the 3D example's spatial sort (-var sortevery, default auto): LAMMPS' 1000 steps on the CPU,
// never under /kk (LAMMPS 29Sep2021 sorts on the host: every atom array and the state rows to the
// host and back), and a value given is taken as it is
TEST(KokkosThermal, Example3DSortsOnlyOnTheCpu)
{
  const std::string cut3d = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-3d-ti6al4v/in.cutting";
  for (const int kk : {0, 1})
    for (const char *sort : {"", "500"}) {
      Lammps l(MPI_COMM_WORLD, kk ? KK_FULL : std::vector<std::string>{});
      for (const std::string v : {"ny index 6", "nz index 3", "steps index 10", "dumpevery index 0"})
        l.cmd("variable " + v);
      if (*sort) l.cmd(std::string("variable sortevery index ") + sort);
      l.lmp->input->file(cut3d.c_str());
      EXPECT_EQ(l.lmp->atom->sortfreq, *sort ? 500 : (kk ? 0 : 1000)) << (kk ? "/kk" : "CPU") << " sortevery '" << sort << "'";
    }
}

// the cut split by a restart across the styles: 8000 steps with the CPU styles, write_restart,
// the last 1000 under /kk (the tool is in contact: the contact history, the held conduction
// rate and the fixes' budgets come from the file), against 9000 steps in one CPU run
TEST(KokkosThermal, CutRestartedFromCpuUnderKokkos)
{
  const std::vector<std::string> base = {"ny index 11", "cut index 0.12e-3", "dumpevery index 0",
                                         "thermoevery index 1000"};
  auto with = [&](std::vector<std::string> extra) {
    auto v = base;
    v.insert(v.end(), extra.begin(), extra.end());
    return v;
  };
  const CutRun ref = cut_run({}, "cutting-2d-ti6al4v", with({"steps index 9000"}));
  cut_run({}, "cutting-2d-ti6al4v", with({"steps index 8000"}));
  const CutRun cont = cut_run(KK_FULL, "cutting-2d-ti6al4v", with({"steps index 1000", "continue index 1"}));
  // heat element 6 (fraction of FMFS evaluations) counts since the fix was defined: not compared
  expect_same_cut(ref, cont, "cpu->kk", 5);
}

/* ----------------------------------------------------------------------
   the decomposition by tool feature (f_cut[16..47]), the contact count and the deepest
   penetration (f_cut[5], f_cut[12]): /kk forms them from the contacts' records only when they are
   read; they must be the ones of the last contact evaluation on any step a consumer reads them.  The 2D cut, 11 across, the tool starting 0.6 spacings from the workpiece (the rake face
   in contact from step ~100); after 1500 steps a second run of 200 steps reads it on the thermo
   steps (every 7, also through a variable), with fix ave/time every 5 steps (mostly steps
   without output or per-atom transfer to the host), at the setup, after the run and after a
   run 0, as with the CPU style.  (13 across, with the tool tip on a row of particles, the CPU
   and /kk runs part at ~1e-6 before this change too: not used.)
------------------------------------------------------------------------- */

TEST(KokkosThermal, DecompositionOnAnyStepAsOnTheCpu)
{
  const std::vector<std::string> vars = {"ny index 11", "xstart index 0.6", "dumpevery index 0", "steps index 1500",
                                         "thermoevery index 1000"};
  std::string fcut = " f_cut[5] f_cut[12]";
  for (int k = 16; k <= 47; k++) fcut += " f_cut[" + std::to_string(k) + "]";
  std::vector<double> after[2], again[2];
  for (int k = 0; k < 2; k++) {
    const std::string name = k ? "kk" : "cpu";
    Lammps l(MPI_COMM_WORLD, k ? KK_FULL : std::vector<std::string>{});
    for (auto &v : vars) l.cmd("variable " + v);
    l.lmp->input->file(CUT2D.c_str());
    l.cmds({"variable dn equal f_cut[21]+f_cut[29]+f_cut[37]+f_cut[45]",
            "thermo_style custom step v_dn" + fcut, "thermo_modify format float %.17g", "thermo 7",
            "fix dec all ave/time 5 1 5" + fcut + " file decomp." + name + " format ' %.17g'",
            "log thermo." + name, "run 200", "log none"});
    for (int c = 16; c <= 47; c++) after[k].push_back(l.equal("f_cut[" + std::to_string(c) + "]"));
    // a setup evaluation after the run (run 0) and the read after it
    l.cmd("run 0");
    for (int c = 16; c <= 47; c++) again[k].push_back(l.equal("f_cut[" + std::to_string(c) + "]"));
    after[k].push_back(l.equal("f_cut[5]"));
    after[k].push_back(l.equal("f_cut[12]"));
  }
  MPI_Barrier(MPI_COMM_WORLD);
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  const auto tc = numeric_rows("thermo.cpu", 36), tk = numeric_rows("thermo.kk", 36);
  const auto ac = numeric_rows("decomp.cpu", 35), ak = numeric_rows("decomp.kk", 35);
  ASSERT_EQ(tc.size(), 30u);    // steps 1500 (setup), 1505, ..., 1694 and 1700 (the last step)
  ASSERT_EQ(tk.size(), tc.size());
  ASSERT_EQ(ac.size(), 41u);    // steps 1500 (setup), 1505, ..., 1700
  ASSERT_EQ(ak.size(), ac.size());
  // a value against its magnitude (0 must stay 0)
  auto rel = [](double a, double b) { return a != 0.0 ? fabs(b - a) / fabs(a) : fabs(b); };
  double dt = 0.0, dn = 0.0, da = 0.0, dp = 0.0;
  for (size_t r = 0; r < tc.size(); r++) {
    ASSERT_EQ(tk[r][0], tc[r][0]);
    dt = std::max(dt, decomp_diff(tc[r], tk[r], 4));
    dn = std::max(dn, rel(tc[r][1], tk[r][1]));
    EXPECT_EQ(tk[r][2], tc[r][2]) << "contacts, step " << tc[r][0];
    dp = std::max(dp, rel(tc[r][3], tk[r][3]));
  }
  for (size_t r = 0; r < ac.size(); r++) {
    ASSERT_EQ(ak[r][0], ac[r][0]);
    da = std::max(da, decomp_diff(ac[r], ak[r], 3));
    EXPECT_EQ(ak[r][1], ac[r][1]) << "contacts, step " << ac[r][0];
    dp = std::max(dp, rel(ac[r][2], ak[r][2]));
  }
  const double de = std::max(decomp_diff(after[0], after[1], 0), decomp_diff(again[0], again[1], 0));
  EXPECT_EQ(after[1][32], after[0][32]);    // contacts after the run 0
  dp = std::max(dp, rel(after[0][33], after[1][33]));
  if (me == 0)
    std::printf("[ decomp   ] /kk vs CPU: thermo every 7 %.3e (variable %.3e), ave/time every 5 %.3e, after the "
                "run and run 0 %.3e, deepest penetration %.3e; rake contacts at the end %g (%g at the Coulomb "
                "limit)\n", dt, dn, da, de, dp, after[0][4], after[0][7]);
  EXPECT_GT(after[0][4], 2.0);                // the rake face is in contact
  EXPECT_GT(after[0][7], 0.0);                // some at the Coulomb limit
  EXPECT_GT(ac[ac.size() / 2][3 + 5], 0.0);   // half way too (sum F_N on the rake face)
  EXPECT_GT(after[0][33], 0.0);               // a penetration
  EXPECT_LT(dt, 1e-10);
  EXPECT_LT(dn, 1e-10);
  EXPECT_LT(da, 1e-10);
  EXPECT_LT(de, 1e-10);
  EXPECT_LT(dp, 1e-10);
}

/* ----------------------------------------------------------------------
   each attached style's dt limit is honoured, through its own slot under /kk (AttachedStyle
   dt_limit, dt_slot): a 4 x 3 steel block (2D, 1 mm spacing) moving at 1 m/s onto a plate, with
   an adaptive step (cfl 0.3, Courant ~6.7e-8 s), a conductivity that makes the thermal limit of
   fix heat/fmfs bind before the contact (~3.1e-8 s) and a penalty factor that makes the spring's
   limit of fix contact/tri-penalty bind below it near the plate (~1.7e-8 s).  Every step: the
   next dt <= the thermal limit of the densities after the corrector (computed here), equal to it
   on the steps before the contact, and below it by more than 10 % on the steps the spring binds.
   Ignoring the heat fix's slot gives the Courant step (~2x the thermal limit), ignoring the
   contact fix's gives no spring-bound step.  With and without a Dirichlet group (the heat fix's
   limit rides on its Dirichlet reduction or has one of its own) and sub-cycling (every 2);
   CPU and /kk take the same steps.
------------------------------------------------------------------------- */

namespace {

// num(): sphcut_test::num

// the plate: the box y in [-5, 0] mm (x, z in [-20, 20] mm) as dtplate.stl (rank 0 writes it)
void write_plate_stl()
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0) {
    const double lo[3] = {-0.02, -0.005, -0.02}, hi[3] = {0.02, 0.0, 0.02};
    const std::vector<double> tri = box_triangles(lo, hi);
    FILE *fp = fopen("dtplate.stl", "w");
    fprintf(fp, "solid plate\n");
    for (size_t t = 0; t < tri.size(); t += 9) {
      fprintf(fp, "facet normal 0 0 0\nouter loop\n");
      for (int k = 0; k < 3; k++)
        fprintf(fp, "vertex %.17g %.17g %.17g\n", tri[t + 3 * k], tri[t + 3 * k + 1], tri[t + 3 * k + 2]);
      fprintf(fp, "endloop\nendfacet\n");
    }
    fprintf(fp, "endsolid plate\n");
    fclose(fp);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// the 4 x 3 steel block of the plate scenes (2D, 1 mm spacing, mass 7.8e-3 each), its lower row
// 0.03 mm above the contact distance 0.5 h / sfac (h 1.3 mm, sfac 1.2) from the plate's top y = 0
const double BLOCK_Y0 = 0.5 * 1.3e-3 / 1.2 + 0.03e-3;
std::vector<std::string> block_cmds()
{
  const double y0 = BLOCK_Y0;
  return {"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "region box block -0.02 0.02 -0.02 0.02 -0.5e-3 0.5e-3 units box", "create_box 1 box",
          "lattice sq 1e-3 origin 0 " + num(y0 / 1.0e-3) + " 0",
          "region blk block -0.1e-3 3.1e-3 " + num(y0 - 0.1e-3) + " " + num(y0 + 2.1e-3) + " -0.5e-3 0.5e-3 units box",
          "create_atoms 1 region blk", "mass 1 7.8e-3", "pair_style sph/jc-thermal"};
}

// rows: step, the dt of the next step, the least density of the heat fix's group after the step;
// sphargs: more keywords of fix sph/jc-thermal
std::vector<std::vector<double>> dt_limit_run(const std::vector<std::string> &args, const std::string &heatargs,
                                              const std::string &sphargs = "", const std::string &vy = "-1")
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  write_plate_stl();
  if (me == 0) std::remove("dtlim.dat");
  MPI_Barrier(MPI_COMM_WORLD);
  Lammps l(MPI_COMM_WORLD, args);
  const double y0 = BLOCK_Y0;
  l.cmds(block_cmds());
  l.cmds({"region topr block INF INF " + num(y0 + 1.9e-3) + " INF INF INF units box",
          "group top region topr", "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 cp 477 k 2e7",
          "fix sph all sph/jc-thermal cfl 0.3 peratom_every 1 " + sphargs, "fix heat all heat/fmfs " + heatargs,
          "fix tool all contact/tri-penalty stl dtplate.stl pfac 10 dfac 0.1 dtfac 0.5",
          "velocity all set 0 " + vy + " 0 units box", "timestep 1e-8", "compute rho all reduce min f_sph[1]",
          "variable dt equal f_sph[1]", "variable rho equal c_rho",
          "fix out all print 1 \"$(step) $(v_dt:%.17g) $(v_rho:%.17g)\" file dtlim.dat screen no", "run 1500"});
  MPI_Barrier(MPI_COMM_WORLD);
  return numeric_rows("dtlim.dat", 3);
}

}    // namespace

TEST(KokkosThermal, EachStyleReportsItsDtLimit)
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  const double h = 1.3 * sqrt(7.8e-3 / 7800.0), cp = 477.0, kappa = 2e7, F = 0.1;
  const std::vector<std::pair<std::string, int>> cases = {{"", 1}, {"every 2 dirichlet top 300", 2}};
  for (const auto &c : cases) {
    const auto cpu = dt_limit_run({}, c.first);
    const auto kk = dt_limit_run(KK_FULL, c.first);
    ASSERT_EQ(cpu.size(), 1501u);
    ASSERT_EQ(kk.size(), cpu.size());
    for (const auto *rows : {&cpu, &kk}) {
      const char *what = rows == &cpu ? "CPU" : "/kk";
      int nheat = 0, ncontact = 0;
      double worst = 0.0;
      for (const auto &r : *rows) {
        const double lim = F * r[2] * cp * h * h / kappa * 2.0 / (c.second + 1.0);
        worst = std::max(worst, r[1] / lim - 1.0);
        if (std::fabs(r[1] / lim - 1.0) < 1e-9) nheat++;
        if (r[1] < 0.9 * lim) ncontact++;
      }
      if (me == 0)
        std::printf("[ dt limit ] %s heat/fmfs %-26s: %d steps at the thermal limit, %d at the spring's, dt / "
                    "thermal limit - 1 at most %.2e\n", what, c.first.c_str(), nheat, ncontact, worst);
      EXPECT_LT(worst, 1e-9) << what << " " << c.first;    // the heat fix's limit honoured every step
      EXPECT_GT(nheat, 100) << what << " " << c.first;     // ... and binding before the contact
      EXPECT_GT(ncontact, 20) << what << " " << c.first;   // the contact fix's limit binding near the plate
    }
    double d = 0.0;
    for (size_t r = 0; r < cpu.size(); r++) {
      ASSERT_EQ(kk[r][0], cpu[r][0]);
      d = std::max(d, std::fabs(kk[r][1] - cpu[r][1]) / cpu[r][1]);
    }
    EXPECT_LT(d, 1e-10) << c.first;    // the same steps
  }
}

/* ----------------------------------------------------------------------
   dtevery N: the adaptive dt is recomputed at the end of every N-th step only (on a GPU the
   step's host round trip then happens every N steps).  The scene of EachStyleReportsItsDtLimit
   at 100 m/s with dtevery 5: the printed dt (the next step's) changes only at multiples of 5, it
   does change (the densities, and with them the thermal limit, change every step), CPU and /kk take the same steps, and with
   dtevery 1 it changes at other steps too (so the test can fail).
------------------------------------------------------------------------- */

TEST(KokkosThermal, DtEveryHoldsTheStep)
{
  auto changes = [](const std::vector<std::vector<double>> &rows, int &off_grid) {
    int n = 0;
    off_grid = 0;
    for (size_t k = 1; k < rows.size(); k++)
      if (rows[k][1] != rows[k - 1][1]) {
        n++;
        if ((long) rows[k][0] % 5 != 0) off_grid++;
      }
    return n;
  };
  const std::string heat = "";
  // at 100 m/s the block's densities change every step, and so does the thermal limit
  const auto cpu = dt_limit_run({}, heat, "dtevery 5", "-100");
  const auto kk = dt_limit_run(KK_FULL, heat, "dtevery 5", "-100");
  const auto every1 = dt_limit_run({}, heat, "", "-100");
  int off_cpu, off_kk, off_1;
  const int n_cpu = changes(cpu, off_cpu), n_kk = changes(kk, off_kk), n_1 = changes(every1, off_1);
  std::printf("[ dtevery  ] dtevery 5: %d changes of dt (%d off the 5-step grid), /kk %d (%d); dtevery 1: %d (%d off "
              "the grid)\n", n_cpu, off_cpu, n_kk, off_kk, n_1, off_1);
  ASSERT_EQ(cpu.size(), kk.size());
  EXPECT_GT(n_cpu, 10);
  EXPECT_EQ(off_cpu, 0);
  EXPECT_EQ(off_kk, 0);
  EXPECT_GT(off_1, 10);
  double dmax = 0.0;
  for (size_t k = 0; k < cpu.size(); k++) dmax = std::max(dmax, std::fabs(cpu[k][1] / kk[k][1] - 1.0));
  EXPECT_LT(dmax, 1e-10);
}

// the list follows the tool when no atom moves: a 4 x 3 block at rest (2D, 1 mm spacing, the
// plate of EachStyleReportsItsDtLimit) and the plate coming up from 6 mm below at 10 m/s, no tool
// atoms and a skin of 0.2 mm, so that no neighbour list is rebuilt before the contact: the list
// of the setup is empty, the ones built as the tool moves (each half its slack) take the block in,
// and the impact (the tool's work, the dissipation, the block's velocity) is that of the CPU
// style, which evaluates every particle
TEST(KokkosThermal, ContactListFollowsTheTool)
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  write_plate_stl();
  double work[2], diss[2], vy[2];
  int nnear0 = -1;
  for (const int near : {1, 0}) {
    Lammps l(MPI_COMM_WORLD, near ? KK_FULL : std::vector<std::string>{});
    l.cmds(block_cmds());
    l.cmds({"pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3", "neighbor 0.2e-3 bin",
            "neigh_modify every 1 delay 0 check yes", "fix sph all sph/jc-thermal cfl 0.3",
            "fix tool all contact/tri-penalty stl dtplate.stl move 0 -6e-3 0 velocity 0 10 0 pfac 10 dfac 0.1",
            "variable vy equal vcm(all,y)", "thermo 0", "run 0"});
    if (near) {
      const int *p = contact_near(l, "tool");
      ASSERT_NE(p, nullptr);
      nnear0 = *p;
    }
    l.cmd("run 12000");
    work[near] = l.equal("f_tool[13]");
    diss[near] = l.equal("f_tool[15]");
    vy[near] = l.equal("v_vy");
  }
  if (me == 0)
    std::printf("[ near     ] plate at 10 m/s onto a block at rest (%d particles near it at the setup): tool work %.10g / "
                "%.10g J, dissipated %.10g / %.10g J, block velocity %.10g / %.10g m/s\n",
                nnear0, work[1], work[0], diss[1], diss[0], vy[1], vy[0]);
  EXPECT_EQ(nnear0, 0);        // the tool 6 mm away: nobody near at the setup
  EXPECT_GT(work[0], 0.0);     // the plate hit the block
  EXPECT_GT(vy[0], 1.0);       // and threw it up
  EXPECT_NEAR(work[1], work[0], 1e-10 * fabs(work[0]));
  EXPECT_NEAR(diss[1], diss[0], 1e-10 * fabs(diss[0]));
  EXPECT_NEAR(vy[1], vy[0], 1e-10 * fabs(vy[0]));
}
