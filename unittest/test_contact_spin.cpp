// fix contact/tri-penalty with a rotating tool (keyword spin, issue 55): a flat plate (top face
// z = 0) spinning about z, particles pressed on it.
//   Per contact (sphcut::contact_step, the step of the CPU and /kk fixes, with a recording sink):
//   the plate turned and carried, the sliding speed is |v_t + omega z x r| at each contact point,
//   the friction along it, the facet's force in the tool frame, the torque (r x f).z.
//   Analytic: particles at rest on the plate, each at distance r from the axis, slide at omega r
//   against the tool's surface; with Coulomb friction (friction coulomb, vreg 0) each gets the
//   friction mu F_N along the surface velocity omega z x r, the friction power is
//   sum mu F_N omega r, the torque about the axis sum mu F_N r and the spindle power torque *
//   omega (to round-off), at the start and after the tool turned a quarter (the plate, longer
//   than wide, then covers other particles: the query runs in the tool frame).
//   Heat: the friction heat booked (vector 6 + 7 + 14) equals the time integral of the friction
//   power step by step (eta 1), and fix heat/fmfs received it.
//   Pose: after N steps of constant rotation (and translation) the tool's vertices are the
//   analytic rotation of the initial ones about the moving axis point.
//   Invariance: a restart in the middle of the rotation continues bit for bit (one rank), 1 vs 2
//   ranks (mpirun -np 2), CPU vs -k on t 1 -sf kk (Kokkos OpenMP backend, SPHCUT_SPIN_KOKKOS).
//   Tool fields at a setup (tool_fields N): at step 0 the array's centroids are the tool's start
//   pose (they were zeros, CPU and /kk), a continued run and a read_restart read the row the last
//   interval closed with; CPU vs -sf kk.
//   Bad input: a zero axis, a NaN rate variable (named with the step), a non-z axis in 2D.
#include "sphcut_test.h"

#include "sphcut_contact_step.h"
#include "sphcut_stl.h"
#include "sphcut_tool_fields.h"
#include "update.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using sphcut_test::Lammps;

namespace {

const double RHO = 7800.0, DP = 1.0e-3, H = 1.3e-3, SFAC = 1.2;
const double RC = 0.5 * H / SFAC;
const double PI = 3.14159265358979323846;
const double MU = 0.3, W = 1000.0;    // friction coefficient, spin rate (rad/s)

using sphcut_test::num;
using sphcut_test::rank;

bool serial()
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  return nprocs == 1;
}

// the plate: x in [-3, 20] mm, y in [-3, 3] mm, z in [-5, 0] mm (top face z = 0)
void write_plate()
{
  if (rank() == 0) {
    const double lo[3] = {-3e-3, -3e-3, -5e-3}, hi[3] = {20e-3, 3e-3, 0.0};
    sphcut::write_stl_ascii("spinplate.stl", sphcut_test::box_triangles(lo, hi), "plate");
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

LAMMPS_NS::Fix *tool_fix(Lammps &l)
{
  return sphcut::fix_by_id(l.lmp->modify, "tool");
}

// a 3D box with one material (E 1e6, elastic); particles created by the caller
void box3d(Lammps &l)
{
  l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "region box block -0.03 0.03 -0.03 0.03 -0.01 0.02", "create_box 1 box"});
}

void material(Lammps &l)
{
  l.cmds({"mass 1 " + num(RHO * DP * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3 cp 477 k 0.01", "fix sph all sph/jc-thermal"});
}

// particles (x, y) at height z, 3 mm apart (beyond each other's kernel support 2h = 2.6 mm: no
// pair forces, each rests where it is): row A along x (y = 0), row B along y (x = 0)
const double ROW[4] = {4e-3, 7e-3, 10e-3, 13e-3};

void sparse_particles(Lammps &l, double z)
{
  for (double r : ROW) l.cmd("create_atoms 1 single " + num(r) + " 0 " + num(z) + " units box");
  for (double r : ROW) l.cmd("create_atoms 1 single 0 " + num(r) + " " + num(z) + " units box");
}

struct Sums {
  int n = 0;
  double fn = 0.0, fric = 0.0, torque = 0.0, fx = 0.0, fy = 0.0;
};

// each particle of one row in contact, its force against the analytic Coulomb friction along
// the tool's surface velocity omega z x r (r = (x, y), tangent t = z x r/|r|); the others free
Sums check_row(Lammps &l, int first_tag, bool along_x, bool in_contact, const char *what)
{
  Sums s;
  LAMMPS_NS::Fix *f = tool_fix(l);
  for (int k = 0; k < 4; k++) {
    const int i = l.lmp->atom->map(first_tag + k);
    const double *fo = f->array_atom[i];
    if (!in_contact) {
      EXPECT_EQ(fo[3], 0.0) << what << " particle " << first_tag + k;
      continue;
    }
    const double fn = fo[3], r = ROW[k];
    const double t[2] = {along_x ? 0.0 : -1.0, along_x ? 1.0 : 0.0};    // z x r/|r|
    EXPECT_GT(fn, 0.0) << what;
    EXPECT_NEAR(fo[0], MU * fn * t[0], 1e-12 * fn) << what << " particle " << first_tag + k;
    EXPECT_NEAR(fo[1], MU * fn * t[1], 1e-12 * fn) << what << " particle " << first_tag + k;
    EXPECT_NEAR(fo[2], fn, 1e-12 * fn) << what;
    EXPECT_NEAR(fo[4], MU * fn, 1e-12 * fn) << what;
    s.n++;
    s.fn += fn;
    s.fric += MU * fn * W * r;    // |F_T| times the sliding speed omega r
    s.torque += MU * fn * r;
    s.fx += MU * fn * t[0];
    s.fy += MU * fn * t[1];
  }
  return s;
}

void expect_sums(Lammps &l, const Sums &s, const char *what)
{
  std::printf("[ %-8s ] %d contacts, sum F_N %.6e N, friction power %.9e W (analytic %.9e), torque %.9e N m "
              "(analytic %.9e), spindle power %.9e W\n",
              what, s.n, s.fn, l.equal("f_tool[4]"), s.fric, l.equal("f_tool[53]"), s.torque, l.equal("f_tool[54]"));
  EXPECT_EQ(l.equal("f_tool[5]"), s.n) << what;
  EXPECT_NEAR(l.equal("f_tool[4]"), s.fric, 1e-12 * s.fric) << what;
  EXPECT_NEAR(l.equal("f_tool[53]"), s.torque, 1e-12 * s.torque) << what;
  EXPECT_NEAR(l.equal("f_tool[54]"), s.torque * W, 1e-12 * s.torque * W) << what;
  // the force on the tool: minus the particles'
  EXPECT_NEAR(l.equal("f_tool[1]"), -s.fx, 1e-12 * s.fn) << what;
  EXPECT_NEAR(l.equal("f_tool[2]"), -s.fy, 1e-12 * s.fn) << what;
  EXPECT_NEAR(l.equal("f_tool[3]"), -s.fn, 1e-12 * s.fn) << what;
}

}    // namespace

/* ----------------------------------------------------------------------
   one contact, through sphcut::contact_step (the CPU and /kk fixes' step) with a sink that keeps
   what the step hands out: the plate turned by 0.7 rad about z through the axis point, carried
   by a displacement; a particle at rest above a point X of the top face (tool frame).  Its
   sliding speed (the facet sums' FS_VS / FS_N) is omega r, r the distance of the contact point
   from the axis; the friction is mu F_N along z x r; the facet's force sums are -R^T f (tool
   frame); the torque sum is mu F_N r
------------------------------------------------------------------------- */

namespace {

struct StepSink {
  double xs[3], vs[3] = {0.0, 0.0, 0.0}, fs[3] = {0.0, 0.0, 0.0};
  std::vector<double> st = std::vector<double>(sphcut::StateLayout::NCOL, 0.0), out = std::vector<double>(6, 0.0);
  double sums[sphcut::NCS] = {};
  double fc[sphcut::NFS] = {};
  int nfacet = 0;
  double v(int k) const { return vs[k]; }
  double x(int k) const { return xs[k]; }
  double f(int k) const { return fs[k]; }
  double h() const { return H; }
  double spacing() const { return DP; }
  double E() const { return 1e6; }
  double mass() const { return RHO * DP * DP * DP; }
  double *state() { return st.data(); }
  double *output() { return out.data(); }
  void add(int c, double val) { sums[c] += val; }
  void add_force(int k, double val) { fs[k] += val; }
  void dt_crit(double) {}
  void record(int, const double *, double) {}
  void facet(int, const double *c)
  {
    nfacet++;
    for (int j = 0; j < sphcut::NFS; j++) fc[j] += c[j];
  }
  void heat_particle(double, double, double) {}
  bool heat_tool(double) { return false; }
};

}    // namespace

TEST(Spin, ContactStepSlidingSpeedPerContact)
{
  const double lo[3] = {-3e-3, -3e-3, -5e-3}, hi[3] = {20e-3, 3e-3, 0.0};
  const std::vector<double> elem = sphcut_test::box_triangles(lo, hi);
  sphcut::TriBins bins;
  sphcut::tri_bin_build(elem, 3, sphcut::support_radius(H), bins);
  const std::vector<int> feature(elem.size() / 9, 3);
  const std::vector<double> inv_area(elem.size() / 9, 1.0);
  sphcut::ContactStep cs;
  cs.tool = bins.view();
  cs.feature = feature.data();
  cs.base.dim = 3;
  cs.base.sfac = SFAC;
  cs.base.onset = 0.2;
  cs.base.dfac = 0.1;
  cs.base.vtool[0] = 0.3;    // the tool also translates: v_t + omega z x r
  cs.base.friction.mu0 = MU;    // Coulomb friction (the law's defaults) with a constant mu
  cs.dt = 1e-6;
  cs.fields = 1;
  cs.inv_area = inv_area.data();
  const double disp[3] = {1e-3, -2e-3, 0.0}, p0[3] = {2e-3, 0.5e-3, 0.0}, th = 0.7;
  for (int k = 0; k < 3; k++) {
    cs.disp[k] = disp[k];
    cs.rot.p0[k] = p0[k];
  }
  cs.rot.on = 1;
  cs.rot.omega = W;
  sphcut::rotation_matrix(cs.rot.axis, th, cs.rot.R);
  const double c = cos(th), s = sin(th);
  for (double X : {0.0, 4e-3, 11e-3, 18e-3}) {
    for (double Y : {-2e-3, 1.5e-3}) {
      StepSink sk;
      // the particle above the tool-frame point (X, Y, 0.9 RC)
      const double a[3] = {X - p0[0], Y - p0[1]};
      const double arm[3] = {c * a[0] - s * a[1], s * a[0] + c * a[1], 0.0};    // R (X_c - p0)
      sk.xs[0] = p0[0] + disp[0] + arm[0];
      sk.xs[1] = p0[1] + disp[1] + arm[1];
      sk.xs[2] = 0.9 * RC;
      sphcut::contact_step(cs, true, sk);
      const double r = sqrt(arm[0] * arm[0] + arm[1] * arm[1]);
      // the surface velocity at the contact point, its sliding speed against the particle at rest
      const double vsurf[2] = {0.3 - W * arm[1], W * arm[0]};
      const double vsl = sqrt(vsurf[0] * vsurf[0] + vsurf[1] * vsurf[1]);
      const double fn = sk.out[3];
      ASSERT_GT(fn, 0.0);
      ASSERT_EQ(sk.nfacet, 1);
      EXPECT_NEAR(sk.fc[sphcut::FS_VS] / sk.fc[sphcut::FS_N], vsl, 1e-12 * vsl) << X << " " << Y;
      for (int k = 0; k < 2; k++) EXPECT_NEAR(sk.fs[k], MU * fn * vsurf[k] / vsl, 1e-12 * fn) << X << " " << Y;
      EXPECT_NEAR(sk.fs[2], fn, 1e-12 * fn);
      // the facet's force (times dt) in the tool frame: -R^T f
      const double ft[2] = {c * sk.fs[0] + s * sk.fs[1], -s * sk.fs[0] + c * sk.fs[1]};
      for (int k = 0; k < 2; k++) EXPECT_NEAR(sk.fc[sphcut::FS_FX + k], -ft[k] * cs.dt, 1e-12 * fn * cs.dt);
      // torque about the axis: (arm x f) . z; friction power |F_T| times the sliding speed
      EXPECT_NEAR(sk.sums[sphcut::CS_TORQUE], arm[0] * sk.fs[1] - arm[1] * sk.fs[0], 1e-12 * fn * r);
      EXPECT_NEAR(sk.sums[sphcut::CS_FRIC], MU * fn * vsl, 1e-12 * fn * vsl);
      // the tool's work rate: F . v_surface
      EXPECT_NEAR(sk.sums[sphcut::CS_WORK], sk.fs[0] * vsurf[0] + sk.fs[1] * vsurf[1], 1e-12 * fn * vsl);
    }
  }
}

/* ----------------------------------------------------------------------
   the analytic sliding: at the start (row A on the plate, row B beside it), and after the
   plate turned a quarter about z (row B on it, row A beside it).  In between the particles are
   lifted 10 mm (out of reach) and put back, at rest.
------------------------------------------------------------------------- */

TEST(Spin, SlidingFrictionTorqueAndPower)
{
  if (!serial()) GTEST_SKIP() << "one rank (reads the particles' output by tag)";
  write_plate();
  Lammps l;
  box3d(l);
  const double z0 = 0.9 * RC;    // penetration 0.1 RC
  sparse_particles(l, z0);
  material(l);
  const int N = 100;
  const double dt = 0.5 * PI / (W * N);    // N steps turn the plate a quarter
  l.cmds({"timestep " + num(dt),
          "fix tool all contact/tri-penalty stl spinplate.stl spin 0 0 1 0 0 0 " + num(W) +
              " mu " + num(MU) + " friction coulomb vreg 0",
          "run 0"});
  expect_sums(l, check_row(l, 1, true, true, "start A"), "start");
  check_row(l, 5, false, false, "start B");
  l.cmds({"displace_atoms all move 0 0 0.01 units box", "run " + std::to_string(N),
          "displace_atoms all move 0 0 -0.01 units box", "run 0"});
  EXPECT_NEAR(l.equal("f_tool[5]"), 4.0, 0.0);
  expect_sums(l, check_row(l, 5, false, true, "quarter B"), "quarter");
  check_row(l, 1, true, false, "quarter A");
  // the lifted particles stayed at rest (nothing touched them)
  for (int tag = 1; tag <= 8; tag++)
    for (int k = 0; k < 3; k++) EXPECT_EQ(l.lmp->atom->v[l.lmp->atom->map(tag)][k], 0.0);
}

/* ----------------------------------------------------------------------
   a block (4 x 3 x 2 particles, 1 mm apart) pressed on the spinning plate by gravity, sliding:
   the friction heat booked equals the friction work, step by step
------------------------------------------------------------------------- */

namespace {

std::vector<std::string> block_scene(const std::string &rate = num(W), const std::string &extra = "")
{
  return {"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "region box block -0.03 0.03 -0.03 0.03 -0.01 0.02", "create_box 1 box", "lattice sc 1e-3 origin 0 0 " + num(0.95 * RC / DP),
          "region blk block 3.5 7.5 -1.5 1.5 0.2 1.8 units lattice",
          "create_atoms 1 region blk", "mass 1 " + num(RHO * DP * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3 cp 477 k 0.01", "timestep 2e-6", "thermo 0"};
}

std::vector<std::string> block_fixes(const std::string &rate = num(W), const std::string &extra = "")
{
  return {"fix sph all sph/jc-thermal", "fix heat all heat/fmfs", "fix g all gravity 1000 vector 0 0 -1",
          "fix tool all contact/tri-penalty stl spinplate.stl spin 0 0 1 0 0 0 " + rate + " velocity 0.5 0 0 mu " +
              num(MU) + " dfac 0.5 eta 1 split 1 heat heat" + extra};
}

}    // namespace

TEST(Spin, FrictionHeatEqualsFrictionWork)
{
  write_plate();
  Lammps l;
  l.cmds(block_scene());
  l.cmds(block_fixes());
  l.cmd("run 0");
  ASSERT_EQ(l.lmp->atom->natoms, 24);
  const double dt = 2e-6;
  double work = 0.0;
  for (int s = 0; s < 100; s++) {
    l.cmd("run 1 pre no post no");
    work += l.equal("f_tool[4]") * dt;    // the friction power of the step times its length
  }
  const double q = l.equal("f_tool[6]") + l.equal("f_tool[7]") + l.equal("f_tool[14]");
  std::printf("[ heat     ] friction work %.9e J, heat booked %.9e J (%+.2e), contacts %g, torque %.4e N m\n", work,
              q, (q - work) / work, l.equal("f_tool[5]"), l.equal("f_tool[53]"));
  EXPECT_GT(l.equal("f_tool[5]"), 0.0);
  EXPECT_GT(work, 0.0);
  EXPECT_NEAR(q, work, 1e-12 * work);
  EXPECT_NEAR(l.equal("f_heat[4]"), l.equal("f_tool[6]"), 1e-9 * q);    // heat/fmfs took the workpiece's share
  EXPECT_GT(l.equal("f_tool[53]"), 0.0);    // the plate drags the block along (torque +z on it)
}

/* ----------------------------------------------------------------------
   the pose: N steps of rotation at a constant rate and translation give the analytic rotation
   of the vertices about the moving axis point (no particle near the tool)
------------------------------------------------------------------------- */

TEST(Spin, PoseAfterConstantRotation)
{
  if (!serial()) GTEST_SKIP() << "one rank (reads the tool file rank 0 writes)";
  write_plate();
  Lammps l;
  box3d(l);
  l.cmd("create_atoms 1 single 0 0 0.015 units box");
  material(l);
  const double a[3] = {1.0, 2.0, 2.0}, p[3] = {1e-3, -2e-3, 0.5e-3}, v[3] = {0.3, -0.2, 0.1};
  const double w = 2000.0, dt = 1e-6;
  const int N = 20000;
  l.cmds({"timestep " + num(dt), "fix tool all contact/tri-penalty stl spinplate.stl spin 1 2 2 " + num(p[0]) + " " +
                                     num(p[1]) + " " + num(p[2]) + " " + num(w) + " velocity " + num(v[0]) + " " +
                                     num(v[1]) + " " + num(v[2]) + " write " + std::to_string(N) + " pose_*.stl",
          "run 0"});
  // the tool as the fix writes it (write: %.17g, exact) at step 0 and N
  sphcut::StlTransform none;
  const std::vector<double> e0 = sphcut::read_stl("pose_0.stl", none);
  l.cmd("run " + std::to_string(N) + " pre no post no");
  const std::vector<double> e1 = sphcut::read_stl("pose_" + std::to_string(N) + ".stl", none);
  ASSERT_EQ(e0.size(), e1.size());
  ASSERT_EQ(e0.size(), 12u * 9u);
  const double th = w * N * dt, n = 3.0, u[3] = {a[0] / n, a[1] / n, a[2] / n};
  const double c = cos(th), s = sin(th);
  double err = 0.0;
  for (size_t k = 0; k < e0.size(); k += 3) {
    double y[3], r[3], cr[3];
    for (int d = 0; d < 3; d++) y[d] = e0[k + d] - p[d];
    const double ud = u[0] * y[0] + u[1] * y[1] + u[2] * y[2];
    cr[0] = u[1] * y[2] - u[2] * y[1];
    cr[1] = u[2] * y[0] - u[0] * y[2];
    cr[2] = u[0] * y[1] - u[1] * y[0];
    for (int d = 0; d < 3; d++) {
      r[d] = p[d] + v[d] * N * dt + y[d] * c + cr[d] * s + u[d] * ud * (1.0 - c);
      err = std::max(err, fabs(e1[k + d] - r[d]));
    }
  }
  std::printf("[ pose     ] %d steps, angle %.6f rad: max vertex error %.3e m (tool 23 mm)\n", N, th, err);
  // the angle is the sum of the steps' dt omega: its round-off, N eps at most, times the tool's size
  EXPECT_LT(err, N * 2.2e-16 * 0.023);
  // the displacement (vector 8-10) and the rate: v N dt
  for (int d = 0; d < 3; d++) EXPECT_NEAR(l.equal("f_tool[" + std::to_string(8 + d) + "]"), v[d] * N * dt, 1e-15);
}

/* ----------------------------------------------------------------------
   invariance of the sliding block: restart, ranks, Kokkos
------------------------------------------------------------------------- */

namespace {

struct Snapshot {
  std::vector<double> x, v, ftool;
};

std::vector<double> gather(Lammps &l, const char *name)
{
  std::vector<double> a(3 * static_cast<size_t>(l.lmp->atom->natoms));
  lammps_gather_atoms(l.lmp, (char *) name, 1, 3, a.data());
  return a;
}

// the atoms by their lattice site at the start (x0): create_atoms numbers them by the domain
// decomposition
Snapshot take(Lammps &l, const std::vector<double> &x0)
{
  Snapshot s;
  const int natoms = (int) l.lmp->atom->natoms;
  std::vector<int> idx(natoms);
  for (int i = 0; i < natoms; i++) idx[i] = i;
  auto site = [&](int i) {
    return std::array<long, 3>{std::lround(x0[3 * i] / 1e-4), std::lround(x0[3 * i + 1] / 1e-4),
                               std::lround(x0[3 * i + 2] / 1e-4)};
  };
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return site(a) < site(b); });
  const std::vector<double> x = gather(l, "x"), v = gather(l, "v");
  for (int i : idx)
    for (int k = 0; k < 3; k++) {
      s.x.push_back(x[3 * i + k]);
      s.v.push_back(v[3 * i + k]);
    }
  for (int k = 1; k <= 54; k++) s.ftool.push_back(l.equal("f_tool[" + std::to_string(k) + "]"));
  return s;
}

// bitwise (tol 0) or within tol relative to the largest magnitude of each quantity
void expect_same(const Snapshot &a, const Snapshot &b, double tol, const char *what)
{
  auto cmp = [&](const std::vector<double> &p, const std::vector<double> &q, const char *name) {
    ASSERT_EQ(p.size(), q.size());
    double scale = 0.0, d = 0.0;
    for (size_t k = 0; k < p.size(); k++) {
      scale = std::max(scale, fabs(p[k]));
      d = std::max(d, fabs(p[k] - q[k]));
    }
    if (rank() == 0) std::printf("[ %-8s ] %-5s max diff %.3e (scale %.3e)\n", what, name, d, scale);
    if (tol == 0.0) EXPECT_EQ(d, 0.0) << what << " " << name;
    else EXPECT_LE(d, tol * scale) << what << " " << name;
  };
  cmp(a.x, b.x, "x");
  cmp(a.v, b.v, "v");
  for (size_t k = 0; k < a.ftool.size(); k++) {
    const double scale = std::max(fabs(a.ftool[k]), 1e-300);
    if (tol == 0.0) EXPECT_EQ(a.ftool[k], b.ftool[k]) << what << " f_tool[" << k + 1 << "]";
    else if (k != 11) EXPECT_LE(fabs(a.ftool[k] - b.ftool[k]), tol * scale + 1e-300) << what << " f_tool[" << k + 1 << "]";
  }
  EXPECT_GT(a.ftool[4], 0.0) << what;     // in contact
  EXPECT_GT(a.ftool[52], 0.0) << what;    // a torque
}

// a spindle ramp: the rate grows linearly with the step (an equal-style variable; of step, not
// time: LAMMPS's time, atime + (step - atimestep) dt, rounds differently once a run has ended)
const std::string RAMP = "v_wr";

Snapshot block_run(MPI_Comm comm, int nsteps, const std::vector<std::string> &switches = {},
                   const std::string &rate = RAMP)
{
  write_plate();
  Lammps l(comm, switches);
  l.cmds(block_scene());
  l.cmd("variable wr equal " + num(W) + "*(0.5+step/200)");
  l.cmds(block_fixes(rate));
  const std::vector<double> x0 = gather(l, "x");
  EXPECT_EQ(tool_fix(l)->kokkosable, switches.empty() ? 0 : 1);    // the /kk fix with -sf kk
  l.cmd("run " + std::to_string(nsteps));
  return take(l, x0);
}

}    // namespace

void restart_case(const std::string &rate, const char *what)
{
  const Snapshot ref = block_run(MPI_COMM_WORLD, 120, {}, rate);
  std::vector<double> x0;
  {
    Lammps l;
    l.cmds(block_scene());
    l.cmd("variable wr equal " + num(W) + "*(0.5+step/200)");
    l.cmds(block_fixes(rate));
    x0 = gather(l, "x");
    l.cmds({"run 60", "write_restart spin.restart"});
  }
  Lammps l;
  l.cmds({"read_restart spin.restart", "thermo 0", "variable wr equal " + num(W) + "*(0.5+step/200)"});
  l.cmds(block_fixes(rate));
  l.cmd("run 60");
  EXPECT_EQ(l.lmp->update->ntimestep, 120);
  expect_same(ref, take(l, x0), 0.0, what);
}

TEST(Spin, RestartMidRotationBitForBit)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  if (nprocs > 1) GTEST_SKIP() << "one rank (bit for bit)";
  restart_case(num(W), "restart");
  restart_case(RAMP, "ramp rst");
}

TEST(Spin, RanksOneVsTwo)
{
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  if (nprocs == 1) GTEST_SKIP() << "needs mpirun -np > 1";
  const Snapshot one = block_run(MPI_COMM_SELF, 120);
  const Snapshot many = block_run(MPI_COMM_WORLD, 120);
  expect_same(one, many, 1e-10, "ranks");
}

#ifdef SPHCUT_SPIN_KOKKOS
TEST(Spin, CpuVsKokkos)
{
  const Snapshot cpu = block_run(MPI_COMM_WORLD, 120);
  const Snapshot kk = block_run(MPI_COMM_WORLD, 120, {"-k", "on", "t", "1", "-sf", "kk"});
  expect_same(cpu, kk, 1e-10, "kokkos");
}
#endif

/* ----------------------------------------------------------------------
   the tool fields' array at a run's setup (tool_fields N, read there by fix print, thermo or a
   variable): at step 0 no interval has closed, yet the centroid columns (13-15) give the facets
   of the tool's pose of that step (the examples' spindle angle is read from them; the array held
   zeros there, on the CPU and under /kk), the averages 0.  A continued run at a multiple of N
   (run after run, and after read_restart) reads at its setup the row the last step closed with,
   bit for bit; the centroids at step 20 are the analytic turn and carry of the step-0 ones.
   CPU and -sf kk (Kokkos OpenMP, 2 threads, full list, newton off) give the same rows
------------------------------------------------------------------------- */

namespace {

using Rows = std::vector<std::vector<double>>;

Rows tool_array(Lammps &l)
{
  Rows a;
  const int nrow = tool_fix(l)->size_array_rows;
  for (int i = 1; i <= nrow; i++) {
    a.emplace_back();
    for (int j = 1; j <= sphcut::ToolFields::NCOL; j++)
      a.back().push_back(l.equal("f_tool[" + std::to_string(i) + "][" + std::to_string(j) + "]"));
  }
  return a;
}

struct SetupRows {
  Rows step0, step20, again20, restart20;
};

const std::string FIELDS = " tool_fields 10";

SetupRows setup_rows(const std::vector<std::string> &switches, const char *restart_file)
{
  SetupRows r;
  {
    Lammps l(MPI_COMM_WORLD, switches);
    l.cmds(block_scene());
    l.cmds(block_fixes(num(W), FIELDS));
    EXPECT_EQ(tool_fix(l)->kokkosable, switches.empty() ? 0 : 1);    // the /kk fix with -sf kk
    l.cmd("run 0");
    r.step0 = tool_array(l);
    l.cmd("run 20");
    r.step20 = tool_array(l);
    l.cmds({"run 0", "write_restart " + std::string(restart_file)});
    r.again20 = tool_array(l);
  }
  Lammps l(MPI_COMM_WORLD, switches);
  l.cmds({"read_restart " + std::string(restart_file), "thermo 0"});
  l.cmds(block_fixes(num(W), FIELDS));
  l.cmd("run 0");
  EXPECT_EQ(l.lmp->update->ntimestep, 20);
  r.restart20 = tool_array(l);
  return r;
}

// the largest difference over the columns [c0, c1) of all rows
double rows_diff(const Rows &a, const Rows &b, int c0 = 0, int c1 = sphcut::ToolFields::NCOL)
{
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); i++)
    for (int c = c0; c < c1; c++) d = std::max(d, fabs(a[i][c] - b[i][c]));
  return d;
}

// the largest difference of a column relative to the column's largest magnitude, over all columns
double rows_rel(const Rows &a, const Rows &b)
{
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (int c = 0; c < sphcut::ToolFields::NCOL; c++) {
    double scale = 0.0, d = 0.0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); i++) {
      scale = std::max(scale, fabs(a[i][c]));
      d = std::max(d, fabs(a[i][c] - b[i][c]));
    }
    if (d > 0.0) worst = std::max(worst, scale > 0.0 ? d / scale : 1.0);
  }
  return worst;
}

// e: the plate's elements as in its STL file
void expect_setup_rows(const SetupRows &r, const std::vector<double> &e, const char *what)
{
  using TF = sphcut::ToolFields;
  ASSERT_EQ(r.step0.size(), e.size() / 9);
  ASSERT_EQ(r.step0.size(), 12u);
  // block_fixes: spin about z through the origin at W, carried at 0.5 m/s along x; 20 steps of 2e-6 s
  const double th = W * 20 * 2e-6, c = cos(th), s = sin(th), dx = 0.5 * 20 * 2e-6;
  double e0 = 0.0, e20 = 0.0, avg0 = 0.0, n20 = 0.0;
  for (size_t f = 0; f < r.step0.size(); f++) {
    double cen[3];
    for (int k = 0; k < 3; k++) cen[k] = (e[9 * f + k] + e[9 * f + 3 + k] + e[9 * f + 6 + k]) / 3.0;
    const double turned[3] = {c * cen[0] - s * cen[1] + dx, s * cen[0] + c * cen[1], cen[2]};
    for (int k = 0; k < 3; k++) {
      e0 = std::max(e0, fabs(r.step0[f][TF::C_CX + k] - cen[k]));
      e20 = std::max(e20, fabs(r.step20[f][TF::C_CX + k] - turned[k]));
    }
    for (int col = TF::C_SN; col <= TF::C_FZ; col++) avg0 = std::max(avg0, fabs(r.step0[f][col]));
    EXPECT_EQ(r.step0[f][TF::C_AREA], r.step20[f][TF::C_AREA]) << what;
    n20 += r.step20[f][TF::C_N];
  }
  if (rank() == 0)
    std::printf("[ %-8s ] step 0: centroids vs the STL's %.2e m, averages %.1e; step 20 (%.3f rad, %.0f contacts): vs "
                "the analytic turn %.2e m; continued run %.1e, after read_restart %.1e\n",
                what, e0, avg0, th, n20, e20, rows_diff(r.again20, r.step20), rows_diff(r.restart20, r.step20));
  EXPECT_LE(e0, 1e-17) << what;      // theta 0, no displacement: the STL's facets (the bug: zeros)
  EXPECT_EQ(avg0, 0.0) << what;      // no interval has closed
  EXPECT_LT(e20, 1e-15) << what;     // the angle's and the rotation's round-off (the plate is 23 mm)
  EXPECT_GT(n20, 0.0) << what;       // the block is in contact in the interval 10-20
  EXPECT_EQ(rows_diff(r.again20, r.step20), 0.0) << what;
  EXPECT_EQ(rows_diff(r.restart20, r.step20), 0.0) << what;
}

}    // namespace

TEST(Spin, ToolFieldsAtTheSetup)
{
  // the plate written once and read by every rank before the runs (a second write_plate while
  // another rank still reads the file would race)
  write_plate();
  sphcut::StlTransform none;
  const std::vector<double> plate = sphcut::read_stl("spinplate.stl", none);
  const SetupRows cpu = setup_rows({}, "spin_fields.restart");
  expect_setup_rows(cpu, plate, "cpu");
#ifdef SPHCUT_SPIN_KOKKOS
  const SetupRows kk = setup_rows({"-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "neigh", "full", "newton", "off"},
                                  "spin_fields_kk.restart");
  expect_setup_rows(kk, plate, "kokkos");
  // the step-0 rows alike; at step 20 and after read_restart the centroids bit for bit (host
  // arithmetic of the same pose), the averages (atomic sums on the device) to 1e-12
  const double d0 = rows_rel(cpu.step0, kk.step0), d20 = rows_rel(cpu.step20, kk.step20),
               dr = rows_rel(cpu.restart20, kk.restart20);
  if (rank() == 0)
    std::printf("[ kokkos   ] CPU vs -sf kk, largest difference relative to the column's scale: step 0 %.1e, "
                "step 20 %.2e (centroids %.1e m), after read_restart %.2e\n",
                d0, d20, rows_diff(cpu.step20, kk.step20, sphcut::ToolFields::C_CX), dr);
  EXPECT_LE(d0, 1e-12);
  EXPECT_LE(d20, 1e-12);
  EXPECT_LE(dr, 1e-12);
  EXPECT_EQ(rows_diff(cpu.step0, kk.step0, sphcut::ToolFields::C_CX), 0.0);
  EXPECT_EQ(rows_diff(cpu.step20, kk.step20, sphcut::ToolFields::C_CX), 0.0);
#endif
}

/* ----------------------------------------------------------------------
   bad input
------------------------------------------------------------------------- */

TEST(Spin, BadInput)
{
  write_plate();
  {
    Lammps l;
    box3d(l);
    l.cmd("create_atoms 1 single 0 0 0.015 units box");
    material(l);
    const std::string fix = "fix tool all contact/tri-penalty stl spinplate.stl ";
    EXPECT_TRUE(l.error_contains(fix + "spin 0 0 0 0 0 0 100", "spin axis 0 0 0 must be a nonzero finite vector"));
    EXPECT_TRUE(l.error_contains(fix + "spin 0 0 1 0 0 0", "keyword spin needs 7 value(s)"));
    EXPECT_TRUE(l.error_contains(fix + "spin 0 0 1 0 0 0 1e999", "spin rate 1e999 is not a finite number"));
    l.cmds({"variable bad equal 1e300*1e300-1e300*1e300", fix + "spin 0 0 1 0 0 0 v_bad"});
    EXPECT_TRUE(l.error_contains("run 0", "spin rate variable bad is not a number (NaN) at step 0"));
    l.cmds({"unfix tool", fix + "spin 0 0 1 0 0 0 v_nothere"});
    EXPECT_TRUE(l.error_contains("run 0", "spin rate variable nothere does not exist"));
    // the ramp turns to NaN at step 3: named with the step
    l.cmds({"unfix tool", "variable late equal 100+(step>=3)*1e300*1e300-(step>=3)*1e300*1e300",
            fix + "spin 0 0 1 0 0 0 v_late"});
    EXPECT_TRUE(l.error_contains("run 5", "spin rate variable late is not a number (NaN) at step 3"));
  }
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "region box block -0.03 0.03 -0.03 0.03 -0.5e-3 0.5e-3", "create_box 1 box",
          "create_atoms 1 single 0 0.01 0 units box", "mass 1 " + num(RHO * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal", "timestep 1e-6"});
  const std::string fix = "fix tool all contact/tri-penalty stl spinplate.stl ";
  EXPECT_TRUE(l.error_contains(fix + "spin 1 0 0 0 0 0 100", "spin axis 1 0 0: a 2D tool turns about z only"));
  EXPECT_TRUE(l.error_contains(fix + "spin 0 1 1 0 0 0 100", "spin axis 0 1 1: a 2D tool turns about z only"));
  l.cmds({fix + "spin 0 0 -1 0 0 0 100", "run 0"});    // about -z: accepted
}

/* ----------------------------------------------------------------------
   a restart file of the format before spin (version 3: no angle, written by the main branch before spin with
   unittest/data/contact-v3.in) still reads: the displacement and the budgets come back, the
   angle starts at 0, and a spinning tool continues from it
------------------------------------------------------------------------- */

TEST(Spin, ReadsVersion3RestartFile)
{
  if (!serial()) GTEST_SKIP() << "one rank";
  write_plate();
  Lammps l;
  l.cmds({std::string("read_restart ") + SPHCUT_SOURCE_DIR + "/unittest/data/contact-v3.restart", "thermo 0"});
  l.cmds(block_fixes(num(W)));
  l.cmd("run 0");
  // the values the writer printed (%.17g)
  EXPECT_EQ(l.equal("f_tool[8]"), 2.0000000000000005e-05);
  EXPECT_EQ(l.equal("f_tool[6]"), 2.6321303730026587e-07);
  EXPECT_EQ(l.equal("f_tool[13]"), 2.6359957158313288e-07);
  EXPECT_EQ(l.equal("f_tool[15]"), 2.8241688535621895e-07);
  EXPECT_GT(l.equal("f_tool[53]"), 0.0);    // turning from the start: the plate drags the block
  l.cmd("run 10");
  EXPECT_EQ(l.lmp->update->ntimestep, 30);
  EXPECT_GT(l.equal("f_tool[5]"), 0.0);
}
