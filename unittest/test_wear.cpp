// fix contact/tri-penalty tool fields (tool_fields N, wear usui K alpha): per tool facet the
// normal and shear stress, sliding speed, temperature, contacts, Usui wear rate and depth.
// A 19 x 4 elastic block (2D, dp 1 mm) sliding at 1 m/s over a plate whose top face is cut
// into facets [-20, -9.5], [-9.5, 0], [0, 9.5], [9.5, 20] mm (the 2D section of an extruded
// STL splits each side quad at its diagonal: [-20, -14.75], [-14.75, -9.5], ... too): the block
// covers the middle two exactly, its particle at x = 0 sits on their shared vertex.  After one
// step every bottom particle has the same penetration, sliding speed and temperature, so the
// facet values equal the formulas to round-off: sigma_n = k delta / dp, tau = mu sigma_n,
// dW/dt = K sigma_n v_s exp(-alpha/T).  Then: a 3D contact at an edge shared by two triangles
// (the facet sums equal the tool force), the accumulated depth, output (VTK cell data, fix
// ave/time of the per-facet array), restart bit for bit, 1 vs 2 MPI ranks, CPU vs -sf kk, and
// bad input.  Run on 1 and 2 ranks (ctest test_wear, test_wear_np2).
#include "sphcut_test.h"

#include "comm.h"
#include "input.h"
#include "sphcut_stl.h"
#include "update.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using sphcut_test::Lammps;
using sphcut_test::prism;

namespace {

const double RHO = 7800.0, DP = 1.0e-3, H = 1.3e-3, SFAC = 1.2, RC = 0.5 * H / SFAC;
const double E = 1.0e7, MU = 0.3, KUSUI = 7.8e-9, ALPHA = 2500.0, T0 = 900.0, DT = 5e-6;
// per-facet columns (f_ID[facet][column], 0-based here; sphcut::ToolFields)
enum { SN = 0, TAU, VS, TEMP, NC, WEAR, DEPTH, FX, FY, FZ, AREA, FEAT, CX, CY, CZ, NCOL };

using sphcut_test::num;

using sphcut_test::rank;

// the plate: top face y = 0 with vertices at x = +-9.5 mm (2D tests), or a plain box (3D)
void write_tools()
{
  if (rank() == 0) {
    sphcut::write_stl_ascii("split.stl", prism({-0.02, -0.005, 0.02, -0.005, 0.02, 0.0, 0.0095, 0.0, -0.0095, 0.0,
                                                 -0.02, 0.0},
                                               -0.02, 0.02), "split");
    const double lo[3] = {-0.02, -0.005, -0.02}, hi[3] = {0.02, 0.0, 0.02};
    sphcut::write_stl_ascii("box.stl", sphcut_test::box_triangles(lo, hi), "box");
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// the sliding block: 19 x 4 particles (x = -9 .. 9 mm), the bottom row delta0 inside the contact
// radius, velocity (vx, 0), temperature T0, heat conduction (fix heat/fmfs), the spring of seed 000
// (onset 0: F_N = k delta, no ramp); contact keywords extra
std::vector<std::string> block(const std::string &extra, double vx = 1.0, double delta0 = 2e-5)
{
  write_tools();
  return {"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "lattice sq 1e-3", "region box block -25 25 -6 10 -0.5 0.5", "create_box 1 box",
          "region blk block -9.51 9.51 -0.01 3.01 -0.5 0.5", "create_atoms 1 region blk",
          "displace_atoms all move 0 " + num(RC - delta0) + " 0 units box", "mass 1 " + num(RHO * DP * DP),
          "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 7800 E " + num(E) + " nu 0.3 hdx 1.3 cp 477 k 50",
          "fix sph all sph/jc-thermal temp " + num(T0), "fix heat all heat/fmfs", "timestep " + num(DT),
          "velocity all set " + num(vx) + " 0 0 units box",
          "fix tool all contact/tri-penalty stl split.stl dfac 0 onset 0 mu " + num(MU) + " heat heat " + extra,
          "thermo 0"};
}

LAMMPS_NS::Fix *fix_of(Lammps &l, const char *id = "tool")
{
  return sphcut::fix_by_id(l.lmp->modify, id);
}

// the per-facet array (every rank holds it)
std::vector<std::vector<double>> facets(Lammps &l)
{
  LAMMPS_NS::Fix *f = fix_of(l);
  std::vector<std::vector<double>> a(f->size_array_rows, std::vector<double>(NCOL));
  for (int i = 0; i < f->size_array_rows; i++)
    for (int j = 0; j < NCOL; j++) a[i][j] = f->compute_array(i, j);
  return a;
}

// the facet of the plate's top face (y = 0) whose centroid is at x (within 1 um)
int top_facet(const std::vector<std::vector<double>> &a, double x)
{
  for (size_t i = 0; i < a.size(); i++)
    if (fabs(a[i][CY]) < 1e-12 && fabs(a[i][CX] - x) < 1e-6) return (int) i;
  return -1;
}

double rel(double a, double b)
{
  return a == b ? 0.0 : fabs(a - b) / std::max(fabs(a), fabs(b));
}

}    // namespace

/* ----------------------------------------------------------------------
   the formulas after one step (tool_fields 1): all bottom particles alike, so each facet's
   values are those of one contact times its share
------------------------------------------------------------------------- */

TEST(ToolFields, SlidingBlockFormula)
{
  Lammps l;
  l.cmds(block("eta 0 tool_fields 1 wear usui " + num(KUSUI) + " " + num(ALPHA)));
  l.cmd("run 1");
  const auto a = facets(l);
  const int left = top_facet(a, -0.00475), right = top_facet(a, 0.00475);
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  EXPECT_EQ(a.size(), 12u);    // bottom 2, sides 2 + 2, top 6 (each quad split at its diagonal)
  // the bottom row from the atoms: penetration, F_N = k delta (k = E, 2D, rigid tool, dfac 0),
  // the sliding velocity v^(n+1/2) = v - dt/2 f/m the contact used
  const LAMMPS_NS::Atom *atom = l.lmp->atom;
  LAMMPS_NS::Fix *tool = fix_of(l);
  const double m = RHO * DP * DP;
  double fn_min = 1e300, fn_max = 0.0, vs = 0.0, fn_sum[2] = {0.0, 0.0};
  int nbottom = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (tool->array_atom[i][5] == 0.0) continue;
    const double fn = tool->array_atom[i][3];
    EXPECT_LT(rel(fn, E * (RC - atom->x[i][1])), 1e-10);    // the known force k delta
    fn_min = std::min(fn_min, fn);
    fn_max = std::max(fn_max, fn);
    vs = atom->v[i][0] - 0.5 * DT * atom->f[i][0] / m;
    fn_sum[atom->x[i][0] < 0.0 ? 0 : 1] += fn;    // (the particle from x = 0 has moved to 5 um)
    nbottom++;
  }
  int ntot = 0;
  MPI_Allreduce(&nbottom, &ntot, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  ASSERT_EQ(ntot, 19);
  if (l.lmp->comm->nprocs == 1) {
    EXPECT_LT(rel(fn_min, fn_max), 1e-12);    // every bottom particle alike
    EXPECT_LT(rel(a[left][SN], fn_sum[0] / 0.0095), 1e-12);
    EXPECT_LT(rel(a[right][SN], fn_sum[1] / 0.0095), 1e-12);
    EXPECT_LT(rel(a[left][VS], vs), 1e-12);
    std::printf("[ formula  ] F_N %.10g N/m per particle, sigma_n %.10g Pa (F_N/dp %.10g), tau %.10g, v_s %.10g "
                "m/s, T %.6g K, dW/dt %.6e m/s\n", fn_max, a[left][SN], fn_max / DP, a[left][TAU], a[left][VS],
                a[left][TEMP], a[left][WEAR]);
  }
  // the contact stress: the facet of length L holds the particles over it, 9 and 10 here (each
  // carries dp of the face): F_N/dp within the discretisation error dp/L of a facet, exactly
  // on the two together (the block covers them)
  EXPECT_LT(rel(0.5 * (a[left][SN] + a[right][SN]), fn_max / DP), 1e-12);
  EXPECT_LT(rel(a[left][NC], 9.0), 1e-12);
  EXPECT_LT(rel(a[right][NC], 10.0), 1e-12);
  for (int f : {left, right}) {
    EXPECT_LT(fabs(a[f][SN] * DP / fn_max - 1.0), DP / 0.0095);
    EXPECT_LT(rel(a[f][TAU], MU * a[f][SN]), 1e-12);    // sliding: at the Coulomb limit
    EXPECT_LT(rel(a[f][TEMP], T0), 1e-12);
    EXPECT_LT(rel(a[f][WEAR], KUSUI * a[f][SN] * a[f][VS] * exp(-ALPHA / a[f][TEMP])), 1e-10);
    EXPECT_LT(rel(a[f][DEPTH], a[f][WEAR] * DT), 1e-12);
    EXPECT_LT(rel(a[f][AREA], 0.0095), 1e-12);
    EXPECT_EQ(a[f][FEAT], 4.0);    // an STL tool: other
  }
  // the facet sums equal the tool force and the decomposition's sums (other: 40-47)
  double fsum[3] = {0.0, 0.0, 0.0}, nsum = 0.0, wear_vol = 0.0;
  for (auto &r : a) {
    for (int k = 0; k < 3; k++) fsum[k] += r[FX + k];
    nsum += r[NC];
    wear_vol += r[WEAR] * r[AREA];
    if (&r != &a[left] && &r != &a[right]) EXPECT_EQ(r[NC], 0.0);
  }
  EXPECT_LT(rel(nsum, 19.0), 1e-12);
  EXPECT_LT(rel(fsum[0], l.equal("f_tool[1]")), 1e-12);
  EXPECT_LT(rel(fsum[1], l.equal("f_tool[2]")), 1e-12);
  EXPECT_LT(rel(l.equal("f_tool[48]"), wear_vol), 1e-12);
  EXPECT_LT(rel(l.equal("f_tool[49]"), l.equal("f_tool[45]")), 1e-12);    // sum F_N
  EXPECT_LT(rel(l.equal("f_tool[50]"), l.equal("f_tool[46]")), 1e-12);    // sum |F_T|
  EXPECT_GT(l.equal("f_tool[48]"), 0.0);
}

// the depth is the time integral of the rate: with tool_fields 1 the sum of rate dt over the
// steps; a longer interval gives the same depth (the interval's integral) and the rate's mean
TEST(ToolFields, DepthIsTheIntegralOfTheRate)
{
  const std::string wear = " wear usui " + num(KUSUI) + " " + num(ALPHA);
  double sum = 0.0, mean = 0.0, depth1 = 0.0;
  int f = -1;
  {
    Lammps l;
    l.cmds(block("tool_fields 1" + wear));
    for (int k = 0; k < 10; k++) {
      l.cmd("run 1 pre no post no");
      const auto a = facets(l);
      f = top_facet(a, -0.00475);
      sum += a[f][WEAR] * DT;
      mean += a[f][WEAR] / 10;
    }
    depth1 = facets(l)[f][DEPTH];
    EXPECT_LT(rel(depth1, sum), 1e-12);
    EXPECT_GT(facets(l)[f][TEMP], T0);    // friction heat (eta 1) warms the contact layer
  }
  Lammps l;
  l.cmds(block("tool_fields 5" + wear));
  l.cmd("run 10");
  const auto a = facets(l);
  std::printf("[ depth    ] after 10 steps: %.6e m (sum of rate dt %.6e), mean rate %.6e m/s (tool_fields 5: "
              "%.6e over the last 5 steps)\n", a[f][DEPTH], sum, mean, a[f][WEAR]);
  EXPECT_LT(rel(a[f][DEPTH], depth1), 1e-10);
  EXPECT_GT(l.equal("f_tool[51]"), 0.0);    // the wear volume
  EXPECT_LT(rel(l.equal("f_tool[52]"), std::max(a[f][DEPTH], a[top_facet(a, 0.00475)][DEPTH])), 1e-12);
}

/* ----------------------------------------------------------------------
   a 3D contact at an edge shared by two triangles (the plate's top face and its side x = 20 mm):
   split 1/2 : 1/2, the facet sums equal the tool force
------------------------------------------------------------------------- */

TEST(ToolFields, EdgeSharedByTwoFacets)
{
  write_tools();
  Lammps l;
  const double a0 = 0.3 * RC;
  l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "region box block -0.03 0.03 -0.03 0.03 -0.03 0.03", "create_box 1 box",
          "create_atoms 1 single " + num(0.02 + a0) + " " + num(a0) + " 0.001 units box",
          "mass 1 " + num(RHO * DP * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e7 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal", "timestep 5e-6",
          "velocity all set -0.5 -0.5 0.3 units box",
          "fix tool all contact/tri-penalty stl box.stl mu 0.3 tool_fields 1", "run 1"});
  const auto a = facets(l);
  ASSERT_EQ(a.size(), 12u);
  int nshared = 0;
  double fsum[3] = {0.0, 0.0, 0.0};
  for (auto &r : a) {
    if (r[NC] > 0.0) {
      nshared++;
      EXPECT_LT(rel(r[NC], 0.5), 1e-12);
    }
    for (int k = 0; k < 3; k++) fsum[k] += r[FX + k];
  }
  EXPECT_EQ(nshared, 2);
  const double f[3] = {l.equal("f_tool[1]"), l.equal("f_tool[2]"), l.equal("f_tool[3]")};
  const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  std::printf("[ edge     ] tool force (%.6g, %.6g, %.6g) N, facet sums (%.6g, %.6g, %.6g)\n", f[0], f[1], f[2], fsum[0],
              fsum[1], fsum[2]);
  EXPECT_GT(fl, 0.0);
  for (int k = 0; k < 3; k++) EXPECT_LE(fabs(fsum[k] - f[k]), 1e-14 * fl) << k;
}

// 2D: a particle pressed on the vertex x = 0 shared by the segments [-9.5, 0] and [0, 9.5] mm of
// the plate's top face (at rest: it stays on the vertex): half on each, the sums the tool force
TEST(ToolFields, VertexSharedByTwoSegments)
{
  write_tools();
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "region box block -0.02 0.02 -0.02 0.02 -0.5e-3 0.5e-3", "create_box 1 box",
          "create_atoms 1 single 0 " + num(RC - 2e-5) + " 0 units box", "mass 1 " + num(RHO * DP * DP),
          "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 7800 E 1e7 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal",
          "timestep 5e-6", "fix tool all contact/tri-penalty stl split.stl mu 0.3 tool_fields 1", "run 1"});
  const auto a = facets(l);
  const int left = top_facet(a, -0.00475), right = top_facet(a, 0.00475);
  ASSERT_GE(left, 0);
  ASSERT_GE(right, 0);
  EXPECT_LT(rel(a[left][NC], 0.5), 1e-12);
  EXPECT_LT(rel(a[right][NC], 0.5), 1e-12);
  const double fy = l.equal("f_tool[2]");
  EXPECT_LT(fy, 0.0);    // pressed down
  EXPECT_LT(rel(a[left][FY] + a[right][FY], fy), 1e-14);
  EXPECT_LT(rel(a[left][SN], -0.5 * fy / 0.0095), 1e-12);
}

/* ----------------------------------------------------------------------
   output: the tool geometry's VTK cell arrays, the per-facet array through fix ave/time
------------------------------------------------------------------------- */

TEST(ToolFields, VtkCellDataAndAveTime)
{
  Lammps l;
  l.cmds(block("tool_fields 5 wear usui " + num(KUSUI) + " " + num(ALPHA) + " write 5 tool_*.vtk"));
  l.cmds({"fix facets all ave/time 5 1 5 f_tool[1] f_tool[6] f_tool[12] mode vector file facets.dat", "run 10"});
  const auto a = facets(l);
  MPI_Barrier(MPI_COMM_WORLD);
  std::ifstream in("tool_10.vtk");
  ASSERT_TRUE(in.good());
  std::string line;
  std::vector<double> wear;
  bool in_wear = false;
  int nscalars = 0;
  while (std::getline(in, line)) {
    if (line.rfind("SCALARS", 0) == 0) {
      nscalars++;
      in_wear = line == "SCALARS wear_rate double 1";
      std::getline(in, line);    // LOOKUP_TABLE
      continue;
    }
    if (in_wear) wear.push_back(std::stod(line));
  }
  EXPECT_EQ(nscalars, NCOL);
  ASSERT_EQ(wear.size(), a.size());
  for (size_t i = 0; i < a.size(); i++) EXPECT_EQ(wear[i], a[i][WEAR]);
  // fix ave/time mode vector: one row per facet
  std::ifstream fa("facets.dat");
  int rows = 0;
  double sn_left = -1.0;
  const int left = top_facet(a, -0.00475);
  while (std::getline(fa, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::vector<double> v;
    for (double x; ls >> x;) v.push_back(x);
    if (v.size() == 4) {
      rows++;
      if ((int) v[0] == left + 1) sn_left = v[1];
    }
  }
  EXPECT_EQ(rows, 3 * (int) a.size());    // steps 0 (zeros), 5 and 10
  EXPECT_LT(rel(sn_left, a[left][SN]), 1e-6);
}

/* ----------------------------------------------------------------------
   restart: the accumulated wear and the running interval's sums are in the file; a run split by
   write_restart / read_restart gives the uninterrupted run's fields (one rank: bit for bit)
------------------------------------------------------------------------- */

TEST(ToolFields, RestartContinuesWear)
{
  const std::string kw = "tool_fields 7 wear usui " + num(KUSUI) + " " + num(ALPHA);
  std::vector<std::vector<double>> ref, mid;
  {
    Lammps l;
    l.cmds(block(kw));
    l.cmd("run 30");
    ref = facets(l);
  }
  {
    Lammps l;
    l.cmds(block(kw));
    l.cmds({"run 17", "write_restart wear.restart"});    // in the middle of the interval 15-21
    mid = facets(l);
  }
  Lammps l;
  l.cmds({"read_restart wear.restart", "fix sph all sph/jc-thermal temp " + num(T0), "fix heat all heat/fmfs",
          "fix tool all contact/tri-penalty stl split.stl dfac 0 onset 0 mu " + num(MU) + " heat heat " + kw, "thermo 0"});
  const auto back = facets(l);
  for (size_t i = 0; i < mid.size(); i++)
    for (int c = 0; c < NCOL; c++) EXPECT_EQ(back[i][c], mid[i][c]) << i << " " << c;
  l.cmd("run 13");
  const auto cont = facets(l);
  double worst = 0.0;
  int nbit = 0;
  for (size_t i = 0; i < ref.size(); i++)
    for (int c = 0; c < NCOL; c++) {
      worst = std::max(worst, rel(ref[i][c], cont[i][c]));
      nbit += ref[i][c] == cont[i][c];
    }
  if (rank() == 0)
    std::printf("[ restart  ] %d ranks: %d of %zu values bit for bit, largest difference %.2e (depth %.6e m)\n",
                l.lmp->comm->nprocs, nbit, ref.size() * NCOL, worst, ref[top_facet(ref, -0.00475)][DEPTH]);
  EXPECT_GT(ref[top_facet(ref, -0.00475)][DEPTH], 0.0);
  if (l.lmp->comm->nprocs == 1) EXPECT_EQ(worst, 0.0);
  else EXPECT_LT(worst, 1e-10);
}

/* ----------------------------------------------------------------------
   1 vs 2 MPI ranks: the facets' sums are reduced over the ranks
------------------------------------------------------------------------- */

TEST(ToolFields, RanksOneVsTwo)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  if (nprocs == 1) GTEST_SKIP() << "needs mpirun -np > 1";
  const std::string kw = "tool_fields 10 wear usui " + num(KUSUI) + " " + num(ALPHA);
  std::vector<std::vector<double>> a[2];
  for (int k = 0; k < 2; k++) {
    Lammps l(k ? MPI_COMM_WORLD : MPI_COMM_SELF);
    l.cmds(block(kw));
    l.cmd("run 40");
    a[k] = facets(l);
  }
  double worst = 0.0;
  for (size_t i = 0; i < a[0].size(); i++)
    for (int c = 0; c < NCOL; c++) worst = std::max(worst, rel(a[0][i][c], a[1][i][c]));
  if (rank() == 0) std::printf("[ ranks    ] 1 vs %d ranks: largest difference %.2e\n", nprocs, worst);
  EXPECT_GT(a[0][top_facet(a[0], 0.00475)][WEAR], 0.0);
  EXPECT_LT(worst, 1e-10);
}

/* ----------------------------------------------------------------------
   CPU vs -sf kk (Kokkos OpenMP, 2 threads): per facet, 2D and 3D, over two runs
------------------------------------------------------------------------- */

#ifdef SPHCUT_TEST_HAVE_KOKKOS
TEST(ToolFields, KokkosMatchesCpu)
{
  const std::vector<std::string> kk = {"-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "neigh", "full",
                                       "newton", "off"};
  const std::string kw = "tool_fields 10 wear usui " + num(KUSUI) + " " + num(ALPHA);
  // 3D: a 6 x 3 x 6 block resting on the box plate (gravity) and sliding diagonally over it (the
  // plate's top face is two triangles: contacts on the diagonal split between them)
  const std::vector<std::string> block3d = {
      "units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array", "lattice sc 1e-3",
      "region box block -25 25 -6 10 -25 25", "create_box 1 box", "region blk block -3.01 2.01 -0.01 2.01 -3.01 2.01",
      "create_atoms 1 region blk", "displace_atoms all move 0 " + num(RC - 3 * RHO * DP * DP * DP * 1000 / (E * DP)) + " 0 units box",
      "mass 1 " + num(RHO * DP * DP * DP), "pair_style sph/jc-thermal",
      "pair_coeff 1 1 rho0 7800 E " + num(E) + " nu 0.3 hdx 1.3 cp 477 k 50", "fix sph all sph/jc-thermal temp 900",
      "fix heat all heat/fmfs", "timestep 5e-6", "velocity all set 1 0 1 units box", "fix g all gravity 1000 vector 0 -1 0",
      "fix tool all contact/tri-penalty stl box.stl dfac 0 mu 0.3 heat heat " + kw, "thermo 0"};
  for (int dim : {2, 3}) {
    std::vector<std::vector<double>> a[2];
    double g[2][5];
    for (int k = 0; k < 2; k++) {
      Lammps l(MPI_COMM_WORLD, k ? kk : std::vector<std::string>{});
      write_tools();
      l.cmds(dim == 2 ? block(kw) : block3d);
      l.cmds({"run 25", "run 15"});    // two runs: the running sums stay on the device between them
      a[k] = facets(l);
      for (int c = 0; c < 5; c++) g[k][c] = l.equal("f_tool[" + std::to_string(48 + c) + "]");
    }
    double worst = 0.0, wear = 0.0;
    int nshared = 0;
    for (size_t i = 0; i < a[0].size(); i++) {
      for (int c = 0; c < NCOL; c++) worst = std::max(worst, rel(a[0][i][c], a[1][i][c]));
      wear = std::max(wear, a[0][i][WEAR]);
      nshared += a[0][i][NC] > 0.0;
    }
    for (int c = 0; c < 5; c++) worst = std::max(worst, rel(g[0][c], g[1][c]));
    if (rank() == 0)
      std::printf("[ kokkos   ] %dD: CPU vs -sf kk per facet: largest difference %.2e (%d facets in contact)\n", dim,
                  worst, nshared);
    EXPECT_GT(wear, 0.0);
    EXPECT_EQ(nshared, 2);    // 2D: the two middle segments; 3D: the two triangles of the top face
    EXPECT_LT(worst, 1e-10);
  }
}

// the 2D cutting example with -var toolfields: many contacts on the rake face, the edge arc and
// the flank (vertex splits), friction heat and conduction (the temperature column), two intervals
TEST(ToolFields, KokkosCut2DMatchesCpu)
{
  const std::vector<std::string> kk = {"-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "neigh", "full",
                                       "newton", "off"};
  std::vector<std::vector<double>> a[2];
  for (int k = 0; k < 2; k++) {
    Lammps l(MPI_COMM_WORLD, k ? kk : std::vector<std::string>{});
    for (const char *v : {"ny index 11", "xstart index 0.6", "steps index 1000", "dumpevery index 0",
                          "thermoevery index 1000", "toolfields index 500"})
      l.cmd(std::string("variable ") + v);
    l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting").c_str());
    LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, "cut");
    a[k].assign(f->size_array_rows, std::vector<double>(NCOL));
    for (int i = 0; i < f->size_array_rows; i++)
      for (int j = 0; j < NCOL; j++) a[k][i][j] = f->compute_array(i, j);
  }
  // each column against its largest magnitude over the facets; the sliding speed against the
  // cutting speed and the wear rate against K sigma_max v_c exp(-alpha/T_max) (the chip sticks in
  // the first steps: v_s is round-off, 1e-16 m/s, on some facets)
  const double vc = 318.5 / 60.0;
  double scale[NCOL] = {0.0};
  for (auto &r : a[0])
    for (int c = 0; c < NCOL; c++) scale[c] = std::max(scale[c], fabs(r[c]));
  scale[VS] = std::max(scale[VS], vc);
  scale[WEAR] = std::max(scale[WEAR], 7.8e-15 * scale[SN] * vc * exp(-2500.0 / std::max(scale[TEMP], 1.0)));
  double worst = 0.0, contacts = 0.0;
  int nfacets = 0;
  for (size_t i = 0; i < a[0].size(); i++) {
    for (int c = 0; c < NCOL; c++)
      if (scale[c] > 0.0) worst = std::max(worst, fabs(a[0][i][c] - a[1][i][c]) / scale[c]);
    contacts += a[0][i][NC];
    nfacets += a[0][i][NC] > 0.0;
  }
  if (rank() == 0)
    std::printf("[ kokkos   ] 2D cut, 1000 steps: CPU vs -sf kk per facet: largest difference %.2e (%d facets, %.2f "
                "contacts)\n", worst, nfacets, contacts);
  EXPECT_GT(nfacets, 2);
  EXPECT_LT(worst, 1e-10);
}
#endif

/* ---------------------------------------------------------------------- */

TEST(ToolFields, BadInput)
{
  write_tools();
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "region box block -0.02 0.02 -0.02 0.02 "
          "-0.5e-3 0.5e-3", "create_box 1 box", "create_atoms 1 single 0 0.005 0 units box", "mass 1 1",
          "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 7800 E 1e7 nu 0.3 hdx 1.3 cp 477 k 50",
          "fix sph all sph/jc-thermal", "fix heat all heat/fmfs"});
  const std::string fix = "fix tool all contact/tri-penalty stl split.stl heat heat ";
  EXPECT_TRUE(l.error_contains(fix + "tool_fields 0", "tool_fields interval must be >= 1, got 0"));
  EXPECT_TRUE(l.error_contains(fix + "tool_fields 2.5", "tool_fields interval must be an integer, got 2.5"));
  EXPECT_TRUE(l.error_contains(fix + "tool_fields", "keyword tool_fields needs 1 value(s)"));
  EXPECT_TRUE(l.error_contains(fix + "tool_fields 10 wear usui -1e-8 2500", "wear usui K must be >= 0, got -1e-08"));
  EXPECT_TRUE(l.error_contains(fix + "tool_fields 10 wear usui 1e-8 -5", "wear usui alpha must be >= 0, got -5"));
  EXPECT_TRUE(l.error_contains(fix + "tool_fields 10 wear archard 1e-8 5", "wear model must be usui, got archard"));
  EXPECT_TRUE(l.error_contains(fix + "tool_fields 10 wear usui 1e-8", "keyword wear needs 3 value(s)"));
  EXPECT_TRUE(l.error_contains(fix + "wear usui 1e-8 2500", "wear usui needs tool_fields N"));
  EXPECT_TRUE(l.error_contains("fix tool all contact/tri-penalty stl split.stl tool_fields 10 wear usui 1e-8 2500",
                               "wear usui needs the interface temperature: give heat ID"));
  EXPECT_TRUE(l.error_contains("fix tool all contact/tri-penalty insert rake 0 clearance 7 radius 0 rake_length 1e-3 "
                               "flank_length 1e-3 face_segments 0",
                               "insert face_segments must be >= 1, got 0"));
}
