// fix contact/tri-penalty (seed 000 sec. 3) driven through LAMMPS: a particle resting on a
// tool plane (penetration m g / k, eq. 10), Coulomb sliding (deceleration mu g), normal impact
// (restitution of the spring-dashpot, max penetration), edge and vertex hits (normal along
// x - q), a rigid plate pushing an elastic strip (F = M A strain), friction heat and its
// split between workpiece and tool particles, STL and input errors.  Each test asserts
// physics against an analytic answer.  The MPI and restart invariance is test_contact_mpi.
//
// Common scene: SI units, rho 7800 kg/m^3, spacing dp = 1 mm (2D mass rho dp^2 per unit
// thickness, 3D rho dp^3), hdx 1.3: h = 1.3 mm, contact radius rc = 0.5 h/SFAC = 0.5417 mm.
// Stiffness as implemented (sphcut_contact.h penalty_stiffness): E* = E (rigid tool, E
// keyword absent) or E E_t/(E + E_t); 2D k = PFAC E* (forces per unit thickness), 3D
// k = PFAC E* dp.  Both give the same m/k = rho dp^2/(PFAC E*).  The analytic tests of eq. 12's
// linear spring-dashpot use seed 000's law (onset 0); the default smooth onset has its own
// (Rest.SmoothOnsetPenetration, Impact.SmoothOnsetRebound).
#include "sphcut_test.h"

#include "domain.h"
#include "sphcut_stl.h"
#include "update.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

using sphcut_test::Lammps;
using sphcut_test::box_triangles;
using sphcut_test::prism;

namespace {

const double RHO = 7800.0, DP = 1.0e-3, H = 1.3e-3, SFAC = 1.2;
const double RC = 0.5 * H / SFAC;    // contact radius, seed 000 eq. 9
const double PI = 3.14159265358979323846;

using sphcut_test::num;

void write_box(const std::string &file, std::vector<double> lo, std::vector<double> hi, bool binary = false)
{
  const std::vector<double> tri = box_triangles(lo.data(), hi.data());
  if (binary) sphcut::write_stl_binary(file, tri);
  else sphcut::write_stl_ascii(file, tri, "box");
}

// the tool plate used by most tests: top face y = 0, |x|, |z| <= 20 mm
void write_plate(const std::string &file = "plate.stl")
{
  write_box(file, {-0.02, -0.005, -0.02}, {0.02, 0.0, 0.02});
}

using sphcut_test::rank;

// one particle of an elastic material (E Pa, no plasticity) at x, in 2D or 3D
void one_particle(Lammps &l, int dim, const double *x, double E = 1.0e6, const std::string &extra = "")
{
  const double mass = dim == 2 ? RHO * DP * DP : RHO * DP * DP * DP;
  l.cmds({"units si", "dimension " + std::to_string(dim), dim == 2 ? "boundary f f p" : "boundary f f f",
          "atom_style atomic", "atom_modify map array",
          std::string("region box block -0.02 0.02 -0.02 0.02 ") + (dim == 2 ? "-0.5e-3 0.5e-3" : "-0.02 0.02"),
          "create_box 1 box",
          "create_atoms 1 single " + num(x[0]) + " " + num(x[1]) + " " + num(dim == 2 ? 0.0 : x[2]) + " units box",
          "mass 1 " + num(mass), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E " + num(E) + " nu 0.3 hdx 1.3 " + extra, "fix sph all sph/jc-thermal",
          "timestep 5e-6"});
}

double *fcontact(Lammps &l, int tag, const char *id = "tool")
{
  LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, id);
  return f->array_atom[l.lmp->atom->map(tag)];
}

double *pos(Lammps &l, int tag) { return l.lmp->atom->x[l.lmp->atom->map(tag)]; }
double *vel(Lammps &l, int tag) { return l.lmp->atom->v[l.lmp->atom->map(tag)]; }

// largest |v_x| of atom 1 sampled after each of `nrun` further runs of `nstep` steps
double max_vx_over(Lammps &l, int nrun, int nstep)
{
  double vmax = 0.0;
  for (int k = 0; k < nrun; k++) {
    l.cmd("run " + std::to_string(nstep) + " pre no post no");
    vmax = std::max(vmax, fabs(vel(l, 1)[0]));
  }
  return vmax;
}

}    // namespace

/* ----------------------------------------------------------------------
   resting particle: k delta = m g, delta = m g / k with k from eq. 10 as implemented.
   2D: k = PFAC E*, m = rho dp^2; 3D: k = PFAC E* dp, m = rho dp^3.  dfac 0.5 settles it.
------------------------------------------------------------------------- */

TEST(Rest, ParticleOnPlanePenetration)
{
  write_plate();
  struct Case {
    int dim;
    double pfac, etool;    // etool 0: rigid tool, E* = E
  };
  const double E = 1.0e6, g = 1000.0;
  for (const Case &c : {Case{2, 1.0, 0.0}, Case{2, 0.5, 1.0e6}, Case{3, 1.0, 0.0}, Case{3, 2.0, 3.0e6}}) {
    Lammps l;
    const double x0[3] = {0.0, RC, 0.0};
    one_particle(l, c.dim, x0, E);
    const double estar = c.etool > 0.0 ? E * c.etool / (E + c.etool) : E;
    const double k = c.dim == 2 ? c.pfac * estar : c.pfac * estar * DP;
    const double m = c.dim == 2 ? RHO * DP * DP : RHO * DP * DP * DP;
    l.cmds({"fix g all gravity " + num(g) + " vector 0 -1 0",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 pfac " + num(c.pfac) +
                (c.etool > 0.0 ? " E " + num(c.etool) : ""),
            "run 3000"});
    const double delta = RC - pos(l, 1)[1], est = m * g / k;
    std::printf("[ rest     ] %dD pfac %g E_tool %g: penetration %.6e m, m g/k %.6e m (%+.2e), contact force %.6g N\n",
                c.dim, c.pfac, c.etool, delta, est, (delta - est) / est, -l.equal("f_tool[2]"));
    EXPECT_NEAR(delta, est, 0.01 * est);
    EXPECT_NEAR(-l.equal("f_tool[2]"), m * g, 1e-6 * m * g);    // the tool carries the weight
    EXPECT_NEAR(fcontact(l, 1)[1], m * g, 1e-6 * m * g);       // per-atom contact force
    EXPECT_EQ(l.equal("f_tool[5]"), 1.0);
    EXPECT_NEAR(l.equal("f_tool[12]"), est / RC, 0.01 * est / RC);
  }
}

/* ----------------------------------------------------------------------
   the smooth onset (fix contact/tri-penalty onset r, d0 = r rc): at rest under m g the
   penetration is sqrt(2 d0 m g/k) while that is below d0 (the ramp carries the weight), else
   m g/k + d0/2.  g is chosen for each regime.
------------------------------------------------------------------------- */

namespace {

// static penetration under a load F of a spring of stiffness k with the smooth onset over d0
// (penalty_normal_force, dfac irrelevant at rest), given F/k
double static_penetration(double f_over_k, double d0)
{
  const double ramp = sqrt(2.0 * d0 * f_over_k);
  return d0 > 0.0 && ramp < d0 ? ramp : f_over_k + 0.5 * d0;
}

}    // namespace

TEST(Rest, SmoothOnsetPenetration)
{
  write_plate();
  const double E = 1.0e6, m = RHO * DP * DP, k = E;    // 2D, rigid tool, pfac 1
  struct Case {
    double onset, g;
  };
  for (const Case &c : {Case{0.2, 100.0}, Case{0.2, 20000.0}, Case{0.5, 300.0}}) {
    Lammps l;
    const double x0[3] = {0.0, RC, 0.0};
    one_particle(l, 2, x0, E);
    l.cmds({"fix g all gravity " + num(c.g) + " vector 0 -1 0",
            "fix tool all contact/tri-penalty stl plate.stl dfac 0.5 onset " + num(c.onset), "run 6000"});
    const double d0 = c.onset * RC, est = static_penetration(m * c.g / k, d0);
    const double delta = RC - pos(l, 1)[1];
    std::printf("[ rest     ] onset %g, g %g: penetration %.6e m, expected %.6e m (%s, %+.2e)\n", c.onset, c.g, delta,
                est, est < d0 ? "on the ramp" : "past it", (delta - est) / est);
    EXPECT_NEAR(delta, est, 1e-3 * est);
    EXPECT_NEAR(-l.equal("f_tool[2]"), m * c.g, 1e-6 * m * c.g);
  }
}

/* ----------------------------------------------------------------------
   sliding particle at normal equilibrium (y = rc - m g/k): Coulomb friction F_T = mu m g
   decelerates it at mu g (above vreg); mu 0 leaves the tangential velocity alone.
   3D: sliding along (0.6, 0, 0.8): the friction opposes the sliding direction.
------------------------------------------------------------------------- */

TEST(Sliding, ParticleDecelerationMuG)
{
  write_plate();
  const double E = 1.0e6, g = 1000.0;
  struct Case {
    int dim;
    double mu;
    std::string extra;
  };
  for (const Case &c : {Case{2, 0.3, ""}, Case{2, 0.3, " vreg 0.05"}, Case{2, 0.0, ""}, Case{3, 0.2, ""},
                        Case{3, 0.0, ""}}) {
    Lammps l;
    const double m = c.dim == 2 ? RHO * DP * DP : RHO * DP * DP * DP;
    const double k = c.dim == 2 ? E : E * DP;
    const double x0[3] = {0.0, RC - m * g / k, 0.0};
    one_particle(l, c.dim, x0, E);
    const double dir[3] = {c.dim == 2 ? 1.0 : 0.6, 0.0, c.dim == 2 ? 0.0 : 0.8};
    const double v0 = 1.0;
    l.cmds({"velocity all set " + num(v0 * dir[0]) + " 0 " + num(v0 * dir[2]) + " units box",
            "fix g all gravity " + num(g) + " vector 0 -1 0",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 mu " + num(c.mu) + c.extra, "run 500"});
    const double t = 500 * 5e-6;
    const double *v = vel(l, 1);
    const double vt = v[0] * dir[0] + v[2] * dir[2];
    const double across = v[2] * dir[0] - v[0] * dir[2];
    const double decel = (v0 - vt) / t;
    std::printf("[ sliding  ] %dD mu %g%s: deceleration %.8g m/s^2, mu g %.8g, v_y %.2e, off-track v %.2e\n", c.dim,
                c.mu, c.extra.c_str(), decel, c.mu * g, v[1], across);
    if (c.mu > 0.0) {
      EXPECT_GT(vt, 0.1);    // still sliding, above vreg
      EXPECT_NEAR(decel, c.mu * g, 0.005 * c.mu * g);
      EXPECT_NEAR(l.equal("f_tool[4]"), c.mu * m * g * vt, 0.01 * c.mu * m * g * vt);    // friction power
    } else {
      EXPECT_NEAR(vt, v0, 1e-10);
      EXPECT_EQ(l.equal("f_tool[4]"), 0.0);
    }
    EXPECT_NEAR(across, 0.0, 1e-12);
    EXPECT_NEAR(v[1], 0.0, 1e-9);    // the normal force stays m g
  }
}

// below vreg the friction is viscous, mu m g |v_t|/vreg: v decays as exp(-mu g t/vreg).
// A fixed tool (vreg 0: Coulomb) stops the particle and holds it: the stability floor
// vreg >= mu F_N dt/m keeps the friction from flipping sign every step (chatter +- mu g dt)
TEST(Sliding, RegularisedFrictionAndStop)
{
  write_plate();
  const double E = 1.0e6, g = 1000.0, m = RHO * DP * DP, mu = 0.3;
  for (double vreg : {1.0, 0.0}) {
    Lammps l;
    const double x0[3] = {0.0, RC - m * g / E, 0.0};
    one_particle(l, 2, x0, E);
    l.cmds({"velocity all set 0.5 0 0 units box", "fix g all gravity " + num(g) + " vector 0 -1 0",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 mu " + num(mu) + " vreg " + num(vreg)});
    if (vreg > 0.0) {
      l.cmd("run 500");
      const double t = 500 * 5e-6, v = vel(l, 1)[0], expect = 0.5 * exp(-mu * g * t / vreg);
      std::printf("[ sliding  ] vreg %g: v %.6f m/s, 0.5 exp(-mu g t/vreg) %.6f (%+.2e)\n", vreg, v, expect,
                  (v - expect) / expect);
      EXPECT_NEAR(v, expect, 0.01 * expect);
    } else {
      l.cmd("run 1000");    // Coulomb stop after 0.5/(mu g) = 1.67 ms = 333 steps
      const double v = vel(l, 1)[0];
      const double vmax = max_vx_over(l, 20, 5);
      std::printf("[ sliding  ] vreg 0 (Coulomb): stopped, v %.2e m/s, max |v| over 100 more steps %.2e m/s "
                  "(chatter would be mu g dt = %.1e)\n", v, vmax, mu * g * 5e-6);
      EXPECT_LT(vmax, 1e-9);
      EXPECT_NEAR(l.equal("f_tool[2]"), -m * g, 1e-6 * m * g);
    }
  }
}

// static friction: a resting particle pushed along the plate by another force f (fix addforce,
// in the particle's force before the contact fix) sticks while f < mu m g, the friction
// balancing f exactly; above it slides at (f - mu m g)/m.  With stick no (plain Coulomb, a
// fixed tool: vreg 0) the friction only sees the velocity and chatters around v = 0.
TEST(Sliding, StaticFrictionHoldsBelowMuN)
{
  write_plate();
  const double E = 1.0e6, g = 1000.0, m = RHO * DP * DP, mu = 0.3, dt = 5e-6;
  struct Case {
    double ratio;    // f / (mu m g)
    const char *stick;
  };
  for (const Case &c : {Case{0.5, "yes"}, Case{1.5, "yes"}, Case{0.5, "no"}}) {
    Lammps l;
    const double x0[3] = {0.0, RC - m * g / E, 0.0};
    one_particle(l, 2, x0, E);
    const double f = c.ratio * mu * m * g;
    l.cmds({"fix g all gravity " + num(g) + " vector 0 -1 0", "fix push all addforce " + num(f) + " 0 0",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 mu " + num(mu) + " stick " + c.stick,
            "run 400"});
    const double v = vel(l, 1)[0];
    const double vmax = max_vx_over(l, 20, 1);
    std::printf("[ static   ] f = %.1f mu m g, stick %s: v %.3e m/s, max |v| over 20 steps %.3e, tool force x %.6g "
                "(f %.6g)\n", c.ratio, c.stick, v, vmax, l.equal("f_tool[1]"), f);
    if (c.ratio < 1.0 && std::string(c.stick) == "yes") {
      EXPECT_LT(vmax, 1e-12);                                   // held
      EXPECT_NEAR(l.equal("f_tool[1]"), f, 1e-9 * f);          // friction = f
    } else if (c.ratio > 1.0) {
      const double a = (f - mu * m * g) / m, t = 420 * dt;
      EXPECT_NEAR(vel(l, 1)[0], a * t, 0.01 * a * t);           // sliding at (f - mu m g)/m
    } else {
      EXPECT_GT(vmax, 0.1 * mu * g * dt);                       // Coulomb chatter
      EXPECT_LT(vmax, 2.0 * (mu * g + f / m) * dt);
    }
  }
}

// mu(T) at the particle temperature (Tref 300 K): table 200 K 0.1 .. 400 K 0.4 gives 0.25,
// the variable 0.001 T gives 0.3, and the deceleration follows
TEST(Sliding, MuOfTemperature)
{
  write_plate();
  std::ofstream("mu.txt") << "# T mu\n200 0.1   # cold\n\n400 0.4\n";
  const double E = 1.0e6, g = 1000.0, m = RHO * DP * DP;
  struct Case {
    std::string mu;
    double expect;
  };
  for (const Case &c : {Case{"table mu.txt", 0.25}, Case{"v_mu tvar T", 0.3}}) {
    Lammps l;
    const double x0[3] = {0.0, RC - m * g / E, 0.0};
    one_particle(l, 2, x0, E);
    l.cmds({"variable T internal 0", "variable mu equal 0.001*v_T", "velocity all set 1 0 0 units box",
            "fix g all gravity " + num(g) + " vector 0 -1 0",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 mu " + c.mu, "run 500"});
    const double decel = (1.0 - vel(l, 1)[0]) / (500 * 5e-6);
    std::printf("[ sliding  ] mu %-12s at 300 K: deceleration %.8g m/s^2, expected %.8g\n", c.mu.c_str(), decel,
                c.expect * g);
    EXPECT_NEAR(decel, c.expect * g, 1e-6 * c.expect * g);
  }
  Lammps l;
  const double x0[3] = {0.0, 0.005, 0.0};
  one_particle(l, 2, x0);
  std::ofstream("mu_bad.txt") << "300 0.2\n250 0.3\n";
  EXPECT_TRUE(l.error_contains("fix tool all contact/tri-penalty stl plate.stl mu table mu_bad.txt",
                               "mu table mu_bad.txt: temperatures must increase"));
  mkdir("mu_folder", 0755);
  EXPECT_TRUE(l.error_contains("fix tool all contact/tri-penalty stl plate.stl mu table mu_folder",
                               "mu table mu_folder is a directory, not a file"));
  EXPECT_TRUE(l.error_contains("fix tool all contact/tri-penalty stl plate.stl mu v_mu", "needs 'tvar NAME'"));
}

namespace {

// a 19 x 4 block settles on the plate, then slides: first frictionless (the centre-of-mass
// velocity is unchanged), then with mu 0.3.  The friction on the block is mu sum F_N, and
// sum F_N - M g = M dv_y,cm/dt, so dv_x,cm = -mu (g t + dv_y,cm) exactly; after settling
// the vertical motion is small and the deceleration is mu g within 0.5 %.  friction: the
// friction law keywords of the sliding phase (the default static-limit law, or memory).
void block_deceleration(const std::string &friction, double tol_exact)
{
  write_plate();
  const double g = 1000.0, E = 1.0e7, mu = 0.3;
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "lattice sq 1e-3", "region box block -25 25 -5 10 -0.5 0.5", "create_box 1 box",
          "region blk block -9.51 9.51 -0.01 3.01 -0.5 0.5", "create_atoms 1 region blk",
          "displace_atoms all move 0 " + num(RC - 4 * RHO * DP * DP * g / E) + " 0 units box",
          "mass 1 " + num(RHO * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E " + num(E) + " nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal",
          "fix g all gravity " + num(g) + " vector 0 -1 0", "timestep 5e-6",
          "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 1", "run 6000"});
  ASSERT_EQ(l.lmp->atom->natoms, 76);    // 19 x 4
  const double M = 76 * RHO * DP * DP;
  EXPECT_NEAR(-l.equal("f_tool[2]"), M * g, 0.02 * M * g);
  EXPECT_EQ(l.equal("f_tool[5]"), 19.0);    // the bottom row is in contact
  l.cmds({"velocity all set 1.0 NULL NULL sum yes units box", "run 200"});
  const double vx_free = l.equal("vcm(all,x)");
  l.cmds({"unfix tool", "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 1 mu " + num(mu) + friction});
  const double vx0 = l.equal("vcm(all,x)"), vy0 = l.equal("vcm(all,y)");
  l.cmd("run 500");
  const double t = 500 * 5e-6;
  const double vx1 = l.equal("vcm(all,x)"), vy1 = l.equal("vcm(all,y)");
  const double decel = (vx0 - vx1) / t, exact = mu * (g + (vy1 - vy0) / t);
  std::printf("[ sliding  ] block%s: frictionless dv_x %.2e; mu %g: deceleration %.6g m/s^2, mu g %.6g (%+.3f %%), "
              "mu (g + dv_y/t) %.6g (%+.2e)\n",
              friction.c_str(), vx_free - 1.0, mu, decel, mu * g, 100 * (decel - mu * g) / (mu * g), exact,
              (decel - exact) / (mu * g));
  EXPECT_NEAR(vx_free, 1.0, 1e-10);
  EXPECT_NEAR(decel, mu * g, 0.005 * mu * g);
  EXPECT_NEAR(decel, exact, tol_exact * mu * g);
  // every bottom particle slides at the Coulomb limit: sum |F_T| = mu sum F_N (other = STL)
  EXPECT_EQ(l.equal("f_tool[44]"), 19.0);
  EXPECT_EQ(l.equal("f_tool[47]"), 19.0);
  EXPECT_NEAR(l.equal("f_tool[46]"), mu * l.equal("f_tool[45]"), 1e-9 * l.equal("f_tool[46]"));
}

}    // namespace

TEST(Sliding, BlockDecelerationMuG)
{
  block_deceleration("", 1e-6);
}

/* ----------------------------------------------------------------------
   friction with memory (friction memory: elastic predictor f* = f_old - alpha m v_t/dt,
   returned to the cone |F_T| <= mu F_N, f_old carried per particle).
------------------------------------------------------------------------- */

// the sliding block of BlockDecelerationMuG with the memory law: it reaches the Coulomb
// limit at once (alpha m v/dt >> mu F_N) and decelerates at mu g
TEST(FrictionMemory, BlockDecelerationMuG)
{
  block_deceleration(" friction memory", 1e-6);
}

// one particle at normal equilibrium pushed along the plate by f (fix addforce, ramped up over
// 300 steps, 15 periods of the tangential spring k_t = alpha m/dt^2): below mu m g the spring
// holds it where it carries f (x = f/k_t), with no friction heat; above mu m g it slides at
// (f - mu m g)/m with the friction mu m g and the heat mu m g v.  (A load applied at once
// would overshoot the undamped spring to 2 f and slip above mu m g/2.)
TEST(FrictionMemory, StickSlipThreshold)
{
  write_plate();
  const double E = 1.0e6, g = 1000.0, m = RHO * DP * DP, mu = 0.3, dt = 5e-6, alpha = 0.1;
  const double kt = alpha * m / (dt * dt);
  for (double ratio : {0.5, 0.95, 1.05, 1.5}) {
    Lammps l;
    const double x0[3] = {0.0, RC - m * g / E, 0.0};
    one_particle(l, 2, x0, E);
    const double f = ratio * mu * m * g;
    l.cmds({"variable fx equal " + num(f) + "*((step<300)*step/300+(step>=300))", "fix g all gravity " + num(g) + " vector 0 -1 0",
            "fix push all addforce v_fx 0 0",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 mu " + num(mu) + " friction memory tfac " +
                num(alpha),
            "run 400"});
    double xmin = 1e300, xmax = -1e300;
    const double v0 = vel(l, 1)[0];
    for (int k = 0; k < 200; k++) {
      l.cmd("run 1 pre no post no");
      xmin = std::min(xmin, pos(l, 1)[0]);
      xmax = std::max(xmax, pos(l, 1)[0]);
    }
    const double v = vel(l, 1)[0], acc = (v - v0) / (200 * dt);
    std::printf("[ memory   ] f = %.2f mu m g: x in [%.4e, %.4e] m (f/k_t %.4e), acceleration %.5g m/s^2 "
                "((f - mu m g)/m %.5g), tool force x %.6g (f %.6g, mu m g %.6g), friction power %.4g, sliding %g\n",
                ratio, xmin, xmax, f / kt, acc, (f - mu * m * g) / m, l.equal("f_tool[1]"), f, mu * m * g,
                l.equal("f_tool[4]"), l.equal("f_tool[47]"));
    if (ratio < 1.0) {
      // held where the spring carries f (measured: within 1.1 %, the force within 0.04 %)
      EXPECT_NEAR(xmin, f / kt, 0.03 * f / kt);
      EXPECT_NEAR(xmax, f / kt, 0.03 * f / kt);
      EXPECT_NEAR(l.equal("f_tool[1]"), f, 0.0015 * f);
      EXPECT_EQ(l.equal("f_tool[4]"), 0.0);        // no slip, no heat
      EXPECT_EQ(l.equal("f_tool[47]"), 0.0);
    } else {
      const double a = (f - mu * m * g) / m;
      EXPECT_NEAR(acc, a, 1e-6 * a);               // sliding at (f - mu m g)/m
      EXPECT_NEAR(l.equal("f_tool[1]"), mu * m * g, 1e-9 * mu * m * g);
      EXPECT_NEAR(l.equal("f_tool[4]"), mu * m * g * v, 0.01 * mu * m * g * v);
      EXPECT_EQ(l.equal("f_tool[47]"), 1.0);
    }
  }
}

// the state resets when the contact ends: a particle sliding on the plate with the memory
// law, lifted off and put back at rest, starts from f_old = 0 (no friction at rest)
TEST(FrictionMemory, ResetWhenContactEnds)
{
  write_plate();
  const double E = 1.0e6, g = 1000.0, m = RHO * DP * DP, mu = 0.3;
  Lammps l;
  const double x0[3] = {0.0, RC - m * g / E, 0.0};
  one_particle(l, 2, x0, E);
  l.cmds({"velocity all set 0.5 0 0 units box", "fix g all gravity " + num(g) + " vector 0 -1 0",
          "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac 0.5 mu " + num(mu) + " friction memory", "run 50"});
  EXPECT_NEAR(l.equal("f_tool[1]"), mu * m * g, 1e-3 * mu * m * g);    // sliding: mu F_N
  EXPECT_NEAR(fcontact(l, 1)[4], mu * m * g, 1e-3 * mu * m * g);      // per-atom |F_T|
  EXPECT_EQ(fcontact(l, 1)[5], 4.0);                                  // feature: other (STL)
  l.cmds({"set atom 1 y 0.002", "velocity all set 0 0 0 units box", "run 1"});    // out of contact
  EXPECT_EQ(l.equal("f_tool[5]"), 0.0);
  EXPECT_EQ(fcontact(l, 1)[5], 0.0);
  l.cmds({"unfix g", "set atom 1 y " + num(x0[1]), "velocity all set 0 0 0 units box", "run 1"});
  EXPECT_EQ(l.equal("f_tool[5]"), 1.0);
  EXPECT_EQ(l.equal("f_tool[1]"), 0.0);    // no memory of the earlier sliding
}

// the decomposition by tool feature (vector 16-47, per-atom columns 4-6): particles pressed
// on the rake face, the edge and the flank of a 2D insert; each feature sums its own contacts,
// and the features add up to the total force on the tool
TEST(FrictionMemory, DecompositionByFeature)
{
  const double r = 1e-3, d = RC - 2e-5, c45 = sqrt(0.5), a = 7.0 * PI / 180.0, sa = sin(a), ca = cos(a);
  const double fx = r * sa, fy = r - r * ca;
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "region box block -0.02 0.02 -0.02 0.02 -0.5e-3 0.5e-3", "create_box 1 box",
          // edge radius r about (0, r) (tip at the origin): rake face x = -r above y = r, the
          // flank from (r sin a, r - r cos a) along (cos a, sin a); each particle 20 um inside
          // its contact radius, the edge one on the arc's bisector
          "create_atoms 1 single " + num(-r - d) + " 0.005 0 units box",
          "create_atoms 1 single " + num(-c45 * (r + d)) + " " + num(r - c45 * (r + d)) + " 0 units box",
          "create_atoms 1 single " + num(fx + 3e-3 * ca + d * sa) + " " + num(fy + 3e-3 * sa - d * ca) + " 0 units box",
          "mass 1 " + num(RHO * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal", "timestep 5e-6",
          "velocity all set 0.1 -0.1 0 units box",
          "fix tool all contact/tri-penalty insert rake 0 clearance 7 radius 1e-3 rake_length 0.01 "
          "flank_length 0.01 segments 8 mu 0.3",
          "run 1"});
  double sum[2] = {0.0, 0.0};
  for (int feat = 0; feat < 4; feat++) {
    const int b = 16 + 8 * feat;
    const double n = l.equal("f_tool[" + std::to_string(b + 4) + "]");
    std::printf("[ decomp   ] feature %d: %g contacts, normal (%.4g, %.4g), friction (%.4g, %.4g), sum F_N %.4g, "
                "sum |F_T| %.4g, at the limit %g\n",
                feat, n, l.equal("f_tool[" + std::to_string(b) + "]"), l.equal("f_tool[" + std::to_string(b + 1) + "]"),
                l.equal("f_tool[" + std::to_string(b + 2) + "]"), l.equal("f_tool[" + std::to_string(b + 3) + "]"),
                l.equal("f_tool[" + std::to_string(b + 5) + "]"), l.equal("f_tool[" + std::to_string(b + 6) + "]"),
                l.equal("f_tool[" + std::to_string(b + 7) + "]"));
    EXPECT_EQ(n, feat < 3 ? 1.0 : 0.0) << feat;
    for (int k = 0; k < 2; k++)
      sum[k] += l.equal("f_tool[" + std::to_string(b + k) + "]") + l.equal("f_tool[" + std::to_string(b + 2 + k) + "]");
  }
  for (int k = 0; k < 2; k++) EXPECT_NEAR(sum[k], l.equal("f_tool[" + std::to_string(k + 1) + "]"), 1e-12 * fabs(sum[k]) + 1e-300);
  for (int tag = 1; tag <= 3; tag++) EXPECT_EQ(fcontact(l, tag)[5], (double) tag) << tag;    // rake, edge, flank
  EXPECT_GT(l.equal("f_tool[16]"), 0.0);    // the rake face is pushed in +x
  EXPECT_GT(l.equal("f_tool[33]"), 0.0);    // the flank is pushed up (+y) by the particle below it
}

/* ----------------------------------------------------------------------
   energy of elastic impacts (issue 11 item 1): a 6 x 6 x 6 steel block (E 200 GPa, dp 1 mm,
   elastic, default artificial viscosity and XSPH) hits a tool at 10 m/s with dfac 0 and mu 0,
   so the contact must not change kinetic + internal energy (the artificial viscosity work
   stays in the internal energy).  Face: the top face of a plate, at 45 degrees incidence.
   Edge: the apex edge of a 90 degree wedge (binary STL), falling straight down, 45 degrees to
   both wedge faces.  Adaptive dt, cfl 0.3 (the cutting example's).  Measured: +0.030 % (face),
   +0.006 % (edge), the same with xsph 0.  Before the spring's time step limit and without XSPH
   in contact (issue 11): +2.2 % / +6.3 % (xsph 0: +0.52 % / +0.12 %, the spring at omega dt =
   0.34); with the limit but XSPH in contact +1.7 % / +5.9 %.  Bound: the 0.05 %.
------------------------------------------------------------------------- */

namespace {

struct ImpactEnergy {
  double gain, vmax, steps;
};

// block of 6^3 particles (lattice 0..5 mm) moving at v, tool from `stl`; runs until the block has
// left the tool again.  Returns the relative change of kinetic + internal energy.
ImpactEnergy block_impact(const std::string &stl, double vx, double vy, const std::string &pair_extra = "",
                          const std::string &fix_extra = "")
{
  Lammps l;
  l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "lattice sc 1e-3", "region box block -15 20 -15 20 -15 20", "create_box 1 box",
          "region blk block -0.01 5.01 -0.01 5.01 -0.01 5.01", "create_atoms 1 region blk",
          "mass 1 " + num(RHO * DP * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3 " + pair_extra,
          "fix sph all sph/jc-thermal cfl 0.3", "timestep 1e-8",
          "velocity all set " + num(vx) + " " + num(vy) + " 0 units box",
          "fix tool all contact/tri-penalty stl " + stl + " dfac 0 mu 0 " + fix_extra, "thermo_modify lost error",
          "variable e equal f_sph[2]+f_sph[3]", "run 0"});
  EXPECT_EQ(l.lmp->atom->natoms, 216);
  const double e0 = l.equal("v_e");
  int touched = 0, steps = 0;
  double pmax = 0.0;
  for (int k = 0; k < 1000; k++) {
    l.cmd("run 10 pre no post no");
    steps += 10;
    const double nc = l.equal("f_tool[5]");
    pmax = std::max(pmax, l.equal("f_tool[12]"));
    if (nc > 0) touched = 1;
    else if (touched) break;
  }
  EXPECT_EQ(touched, 1);
  EXPECT_EQ(l.equal("f_tool[5]"), 0.0);    // left the tool
  const double e1 = l.equal("v_e");
  return {(e1 - e0) / e0, pmax, (double) steps};
}

}    // namespace

TEST(Impact, BlockOnFaceAndEdgeConservesEnergy)
{
  const double v = 10.0, c = v / sqrt(2.0);
  // plate: top face y = -0.8 mm (block bottom row at y = 0: gap 0.8 mm - rc = 0.26 mm)
  write_box("plate-energy.stl", {-0.02, -0.01, -0.02}, {0.03, -0.8e-3, 0.03});
  // wedge: apex edge along z at x = 2.2 mm, y = -0.8 mm, faces at 45 degrees
  const double ax = 2.2e-3, ay = -0.8e-3, w = 8e-3;
  if (rank() == 0) sphcut::write_stl_binary("wedge.stl", prism({ax, ay, ax - w, ay - w, ax + w, ay - w}, -0.01, 0.015));
  MPI_Barrier(MPI_COMM_WORLD);
  struct Case {
    const char *what, *stl;
    double vx, vy;
    const char *pair;
  };
  // the default contact (smooth onset 0.2, dtfac 0.5): measured +0.0031 / +0.0047 % (face /
  // edge; xsph 0 alike; +0.0041 / +0.0055 % at the Courant step, dtfac 1); seed 000's law with the
  // step cut to 0.15 of its limit: +0.030 / +0.007 %; seed 000's law at the Courant step (dtfac 1,
  // onset 0): +0.47 / +0.12 % (Impact.OnsetStudy)
  struct Law {
    const char *what, *fix;
    double gain;
  };
  for (const Law &law : {Law{"default", "", 2e-4}, Law{"onset 0 dtfac 0.15", "onset 0 dtfac 0.15", 5e-4}})
    for (const Case &k : {Case{"face 45 deg", "plate-energy.stl", c, -c, ""}, Case{"edge", "wedge.stl", 0.0, -v, ""},
                          Case{"face 45 deg, xsph 0", "plate-energy.stl", c, -c, "xsph 0"},
                          Case{"edge, xsph 0", "wedge.stl", 0.0, -v, "xsph 0"}}) {
      const ImpactEnergy r = block_impact(k.stl, k.vx, k.vy, k.pair, law.fix);
      std::printf("[ impact   ] block on %s, contact %s: energy change %+.4f %%, max penetration / rc %.3f, %g steps\n",
                  k.what, law.what, 100.0 * r.gain, r.vmax, r.steps);
      EXPECT_LT(r.gain, law.gain);    // issue 11: gain <= 0.05 %
      EXPECT_GT(r.gain, -5e-3);       // and no large loss either (dfac 0, mu 0)
    }
  // the seed law at the Courant step gains ten times more: what the smooth onset removes
  const ImpactEnergy seed = block_impact("plate-energy.stl", c, -c, "", "onset 0 dtfac 1");
  std::printf("[ impact   ] block on face 45 deg, onset 0 dtfac 1: energy change %+.4f %%\n", 100.0 * seed.gain);
  EXPECT_GT(seed.gain, 1e-3);
}

// the energy of the block bounce against the contact's time step (dtfac) and the spring's
// onset: a study, run with SPHCUT_STUDY=1 (prints a table)
TEST(Impact, OnsetStudy)
{
  if (!getenv("SPHCUT_STUDY")) GTEST_SKIP() << "SPHCUT_STUDY=1 runs the study";
  const double v = 10.0, c = v / sqrt(2.0);
  write_box("plate-energy.stl", {-0.02, -0.01, -0.02}, {0.03, -0.8e-3, 0.03});
  const double ax = 2.2e-3, ay = -0.8e-3, w = 8e-3;
  if (rank() == 0) sphcut::write_stl_binary("wedge.stl", prism({ax, ay, ax - w, ay - w, ax + w, ay - w}, -0.01, 0.015));
  MPI_Barrier(MPI_COMM_WORLD);
  for (const char *onset : {"0", "0.1", "0.2", "0.4"})
    for (const char *dtfac : {"0.15", "0.5", "1"}) {
      const std::string fx = std::string("onset ") + onset + " dtfac " + dtfac;
      const ImpactEnergy a = block_impact("plate-energy.stl", c, -c, "", fx);
      const ImpactEnergy b = block_impact("wedge.stl", 0.0, -v, "", fx);
      std::printf("[ study    ] onset %4s dtfac %4s: face %+.4f %% (pen %.3f, %g steps), edge %+.4f %% (pen %.3f, %g steps)\n",
                  onset, dtfac, 100 * a.gain, a.vmax, a.steps, 100 * b.gain, b.vmax, b.steps);
    }
}

/* ----------------------------------------------------------------------
   normal impact at v0 = 3 m/s (no gravity): the spring-dashpot of eq. 12 as implemented has
   the linear oscillator's restitution e = exp(-pi z / sqrt(1 - z^2)), z = dfac: 1 for
   dfac 0, no rebound for dfac 1 (critical).  Max penetration (dfac 0) v0 sqrt(m/k) = 0.49 rc:
   the particle centre stays outside the tool surface (ratio < 1, element 12).
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   the smooth onset's bounce (dfac 0, v0 = 3 m/s, as ParticleRestitutionAndPenetration): elastic
   (rebound ratio 1) and the deepest penetration where the spring's energy equals 1/2 m v0^2:
     U(delta) = k delta^3/(6 d0)                               delta <  d0
              = k d0^2/6 + k ((delta^2 - d0^2)/2 - d0 (delta - d0)/2)   delta >= d0
------------------------------------------------------------------------- */

TEST(Impact, SmoothOnsetRebound)
{
  write_plate();
  const double E = 1.0e6, v0 = 3.0, m = RHO * DP * DP, k = E;
  for (double onset : {0.2, 0.5}) {
    Lammps l;
    const double x0[3] = {0.0, RC + 1.0e-4, 0.0};
    one_particle(l, 2, x0, E);
    l.cmds({"timestep 2e-6", "velocity all set 0 " + num(-v0) + " 0 units box",
            "fix tool all contact/tri-penalty stl plate.stl dfac 0 onset " + num(onset),
            "fix pen all vector 1 f_tool[12]", "run 1000"});
    const double d0 = onset * RC, e = 0.5 * m * v0 * v0;
    // U(delta) = e solved past the ramp: k/2 delta^2 - k d0/2 delta + k d0^2/6 - e = 0 (checked >= d0)
    double dmax = 0.5 * (d0 + sqrt(d0 * d0 - 4.0 * (d0 * d0 / 3.0 - 2.0 * e / k)));
    if (dmax < d0) dmax = cbrt(6.0 * d0 * e / k);
    const double ratio = vel(l, 1)[1] / v0, pmax = l.equal("max(f_pen)");
    std::printf("[ impact   ] onset %g: rebound ratio %.6f, max penetration / rc %.4f, expected %.4f\n", onset, ratio,
                pmax, dmax / RC);
    EXPECT_NEAR(ratio, 1.0, 2e-3);
    EXPECT_NEAR(pmax, dmax / RC, 0.02 * dmax / RC);
    EXPECT_LT(pmax, 1.0);
  }
}

TEST(Impact, ParticleRestitutionAndPenetration)
{
  write_plate();
  const double E = 1.0e6, v0 = 3.0;
  struct Case {
    int dim;
    double dfac;
  };
  for (const Case &c : {Case{2, 0.0}, Case{3, 0.0}, Case{2, 0.3}, Case{2, 1.0}}) {
    Lammps l;
    const double x0[3] = {0.0, RC + 1.0e-4, 0.0};
    one_particle(l, c.dim, x0, E);
    l.cmds({"timestep 2e-6", "velocity all set 0 " + num(-v0) + " 0 units box",
            "fix tool all contact/tri-penalty stl plate.stl onset 0 dfac " + num(c.dfac), "fix pen all vector 1 f_tool[12]",
            "fix nc all vector 1 f_tool[5]", "run 1000"});
    const double m = c.dim == 2 ? RHO * DP * DP : RHO * DP * DP * DP;
    const double k = c.dim == 2 ? E : E * DP;
    const double pmax = l.equal("max(f_pen)");
    const double vy = vel(l, 1)[1];
    const double z = c.dfac;
    std::printf("[ impact   ] %dD dfac %g: rebound ratio %.6f, max penetration / rc %.4f, in contact at the end %g\n",
                c.dim, c.dfac, vy / v0, pmax, l.equal("f_tool[5]"));
    EXPECT_LT(pmax, 1.0);    // never deeper than 0.5 h/SFAC: the centre stays outside the tool
    EXPECT_GT(pmax, 0.1);
    if (z < 1.0) {
      const double e = exp(-PI * z / sqrt(1.0 - z * z));
      EXPECT_NEAR(vy / v0, e, 0.02 * e);
      EXPECT_EQ(l.equal("f_tool[5]"), 0.0);    // separated
      if (z == 0.0) EXPECT_NEAR(pmax, v0 * sqrt(m / k) / RC, 0.02 * v0 * sqrt(m / k) / RC);
    } else {
      // critically damped: creeps back towards delta = 0 without leaving the surface
      EXPECT_LT(fabs(vy), 1e-4 * v0);
      EXPECT_EQ(l.equal("min(f_nc)"), 0.0);    // before the impact
      EXPECT_EQ(l.equal("f_tool[5]"), 1.0);    // never separated: no rebound
    }
    EXPECT_NEAR(vel(l, 1)[0], 0.0, 1e-12);
  }
}

/* ----------------------------------------------------------------------
   edge and vertex hits on a box tool: the contact normal of an edge/vertex hit is
   (x - q)/|x - q| (sphcut_contact.h), not a face normal.  A particle approaching the edge
   x = y = 0 (3D, along z) or the vertex (0, 0, 0) along a ray gets a contact force along
   that ray at every step of the contact and leaves back along it at its impact speed.
------------------------------------------------------------------------- */

TEST(EdgeVertex, PushedOutAlongFeatureNormal)
{
  // tool: x, y <= 0 (and z <= 0 for the corner case)
  write_box("edge.stl", {-0.01, -0.01, -0.01}, {0.0, 0.0, 0.01});
  write_box("corner.stl", {-0.01, -0.01, -0.01}, {0.0, 0.0, 0.0});
  struct Case {
    int dim;
    const char *file;
    double dir[3];    // ray from the feature to the particle
    const char *what;
  };
  for (const Case &c : {Case{3, "edge.stl", {1.0, 1.0, 0.0}, "3D edge, diagonal"},
                        Case{3, "edge.stl", {1.0, 0.45, 0.0}, "3D edge, off-diagonal"},
                        Case{3, "corner.stl", {1.0, 1.0, 1.0}, "3D vertex, diagonal"},
                        Case{3, "corner.stl", {0.5, 1.0, 0.8}, "3D vertex, off-diagonal"},
                        Case{2, "edge.stl", {1.0, 0.6, 0.0}, "2D corner of the section"}}) {
    double n[3];
    const double ln = sqrt(c.dir[0] * c.dir[0] + c.dir[1] * c.dir[1] + c.dir[2] * c.dir[2]);
    for (int a = 0; a < 3; a++) n[a] = c.dir[a] / ln;
    // the feature: the edge (q = (0, 0, z)) or the vertex (q = 0)
    const bool vertex = std::string(c.file) == "corner.stl" || c.dim == 2;
    Lammps l;
    const double d0 = RC + 2.0e-4, v0 = 2.0;
    const double zoff = vertex ? 0.0 : 1.0e-3;    // an edge hit away from z = 0
    const double x0[3] = {d0 * n[0], d0 * n[1], d0 * n[2] + zoff};
    one_particle(l, c.dim, x0, 1.0e6);
    l.cmds({"timestep 2e-6",
            "velocity all set " + num(-v0 * n[0]) + " " + num(-v0 * n[1]) + " " + num(-v0 * n[2]) + " units box",
            std::string("fix tool all contact/tri-penalty dfac 0 stl ") + c.file});
    double worst = 0.0, fmax = 0.0;
    int ncontact = 0;
    for (int s = 0; s < 60; s++) {
      l.cmd("run 5 pre no post no");
      const double *x = pos(l, 1), *f = fcontact(l, 1);
      const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      if (fl == 0.0) continue;
      ncontact++;
      double r[3] = {x[0], x[1], vertex ? x[2] : 0.0};    // x - q
      const double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
      double cr = 0.0;    // |f/|f| x r/|r||
      const double cx = f[1] * r[2] - f[2] * r[1], cy = f[2] * r[0] - f[0] * r[2], cz = f[0] * r[1] - f[1] * r[0];
      cr = sqrt(cx * cx + cy * cy + cz * cz) / (fl * rl);
      worst = std::max(worst, cr);
      fmax = std::max(fmax, fl);
      EXPECT_GT(f[0] * r[0] + f[1] * r[1] + f[2] * r[2], 0.0);    // pushed out, not in
    }
    const double *v = vel(l, 1);
    const double vout = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    double vperp = 0.0;
    for (int a = 0; a < 3; a++) vperp += (v[a] - vout * n[a]) * (v[a] - vout * n[a]);
    vperp = sqrt(vperp);
    std::printf("[ feature  ] %-26s: %2d samples in contact, max |f x (x-q)|/(|f||x-q|) %.2e, "
                "rebound along the ray %.5f v0, across %.1e\n",
                c.what, ncontact, worst, vout / v0, vperp / v0);
    EXPECT_GT(ncontact, 3);
    EXPECT_LT(worst, 1e-10);
    EXPECT_NEAR(vout, v0, 0.02 * v0);
    EXPECT_LT(vperp, 1e-10 * v0);
    EXPECT_EQ(l.equal("f_tool[5]"), 0.0);
  }
}

/* ----------------------------------------------------------------------
   STL errors reach the user as LAMMPS errors naming the file and the problem
------------------------------------------------------------------------- */

TEST(StlErrors, ThroughTheFix)
{
  {
    std::ofstream("malformed.stl") << "solid bad\n facet normal 0 0 1\n  outer lop\n";
    std::ofstream("empty.stl");
    // one facet in the z = 0 plane, counter-clockwise seen from +z, stored normal -z
    std::ofstream("flipped.stl") << "solid flipped\n facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n"
                                    "   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid flipped\n";
    write_box("above.stl", {-0.01, -0.01, 0.001}, {0.01, 0.0, 0.002});    // misses z = 0
    // an open sheet: the top face of the plate alone (particles behind it were thrown out)
    const std::vector<double> plate = box_triangles(std::vector<double>{-0.02, -0.005, -0.02}.data(),
                                                    std::vector<double>{0.02, 0.0, 0.02}.data());
    sphcut::write_stl_binary("sheet.stl", std::vector<double>(plate.begin() + 9 * 6, plate.begin() + 9 * 8));
    std::vector<double> tri = box_triangles(std::vector<double>{-0.01, -0.01, -0.01}.data(),
                                            std::vector<double>{0.01, 0.0, 0.01}.data());
    sphcut::write_stl_binary("truncated.stl", tri);
    std::string data;
    {
      std::ifstream in("truncated.stl", std::ios::binary);
      data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::ofstream("truncated.stl", std::ios::binary).write(data.data(), (std::streamsize) data.size() - 20);
    mkdir("folder.stl", 0755);    // a directory under a file's name (refused as "empty file" before)
  }
  for (int dim : {3, 2}) {
    Lammps l;
    const double x0[3] = {0.0, 0.005, 0.0};
    one_particle(l, dim, x0);
    const std::string fix = "fix tool all contact/tri-penalty stl ";
    EXPECT_TRUE(l.error_contains(fix + "malformed.stl", "STL file 'malformed.stl': line 3: expected 'loop', got 'lop'"));
    EXPECT_TRUE(l.error_contains(fix + "empty.stl", "STL file 'empty.stl': empty file"));
    EXPECT_TRUE(l.error_contains(fix + "nosuch.stl", "STL file 'nosuch.stl': cannot open"));
    EXPECT_TRUE(l.error_contains(fix + "folder.stl", "STL file 'folder.stl': is a directory, not a file"));
    EXPECT_TRUE(l.error_contains(fix + "flipped.stl", "facet 0: stored normal (0 0 -1) disagrees with its vertex winding"));
    EXPECT_TRUE(l.error_contains(fix + "truncated.stl", "STL file 'truncated.stl'"));
    EXPECT_TRUE(l.error_contains(fix + "sheet.stl", "STL file 'sheet.stl': the mesh is not closed: 4 edge(s) "
                                                    "belong to one facet only"));
    if (dim == 2)
      EXPECT_TRUE(l.error_contains(fix + "above.stl", "no facet crosses the plane z = 0 (2D section is empty)"));
    else
      l.cmd(fix + "above.stl");    // fine in 3D
  }
}

// particles that start inside the tool: a warning at the first setup with their count and
// the deepest one (also deeper than the contact search radius 2h); none for particles outside
TEST(StlErrors, WarnsAboutParticlesStartingInside)
{
  write_box("thick.stl", {-0.02, -0.015, -0.02}, {0.02, 0.0, 0.02});    // the tool: y in [-15, 0] mm
  auto log_of = [](Lammps &l) {
    fflush(l.lmp->logfile);
    std::ifstream in("inside.log");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  for (int dim : {3, 2}) {
    SCOPED_TRACE("dim " + std::to_string(dim));
    {
      Lammps l(MPI_COMM_WORLD, {"-log", "inside.log"});
      const double x0[3] = {0.0, 0.005, 0.0};
      one_particle(l, dim, x0);
      l.cmds({"fix tool all contact/tri-penalty stl thick.stl", "run 0"});
      EXPECT_EQ(log_of(l).find("inside the tool"), std::string::npos);
      EXPECT_EQ(log_of(l).find("within the contact radius"), std::string::npos) << "5 mm away: no warning";
    }
    Lammps l(MPI_COMM_WORLD, {"-log", "inside.log"});
    const double x0[3] = {0.0, 0.005, 0.0};
    one_particle(l, dim, x0);
    // 0.3 mm and 7 mm deep (h = 1.3 mm), and one 0.3 mm outside
    l.cmds({"create_atoms 1 single 0.005 -0.3e-3 0 units box", "create_atoms 1 single -0.005 -7e-3 0 units box",
            "create_atoms 1 single 0.01 0.3e-3 0 units box", "fix tool all contact/tri-penalty stl thick.stl", "run 0"});
    const std::string log = log_of(l);
    EXPECT_NE(log.find("WARNING: Fix contact/tri-penalty: 2 particle(s) start inside the tool or on its surface "
                       "(0 on it, the deepest 0.007 below it)"),
              std::string::npos)
        << log;
    // the one 0.3 mm outside lies within the contact radius 0.5 h/sfac = 0.54 mm: an impulsive start
    EXPECT_NE(log.find("WARNING: Fix contact/tri-penalty: 1 particle(s) start within the contact radius 0.5 h/sfac "
                       "of the tool"),
              std::string::npos)
        << log;
    l.cmd("run 0");    // once, at the first setup
    EXPECT_EQ(log_of(l).find("inside the tool", log.find("inside the tool") + 20), std::string::npos);
    EXPECT_EQ(log_of(l).find("within the contact radius", log.find("within the contact radius") + 20),
              std::string::npos);
  }
}

/* ----------------------------------------------------------------------
   a finely meshed tool: a UV sphere of radius 15 mm with 200 x 256 facets (101,888, a
   binary STL), so that a few hundred facets lie within 2h = 2.6 mm of a particle at its
   surface (slivers near the poles).  Eight particles launched radially at it (equator, mid
   latitudes, near and at a pole) must bounce back as from a smooth sphere: never closer than
   the contact radius minus the spring's maximum penetration, the contact force along the
   radius (the facet normals deviate from it by < 0.012 rad), rebound speed v0.
------------------------------------------------------------------------- */

namespace {

std::vector<double> uv_sphere(double R, int nlat, int nlon)
{
  auto vert = [&](int i, int j, double *v) {    // ring i (0: north pole, nlat: south pole), meridian j
    const double th = PI * i / nlat, ph = 2.0 * PI * (j % nlon) / nlon;
    v[0] = (i == 0 || i == nlat) ? 0.0 : R * sin(th) * cos(ph);
    v[1] = (i == 0 || i == nlat) ? 0.0 : R * sin(th) * sin(ph);
    v[2] = R * cos(th);
  };
  std::vector<double> tri;
  auto add = [&](const double *a, const double *b, const double *c) {
    double n[3];
    sphcut::triangle_normal(a, b, c, n);
    const double m[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
    const bool out = n[0] * m[0] + n[1] * m[1] + n[2] * m[2] > 0.0;
    for (const double *v : {a, out ? b : c, out ? c : b}) tri.insert(tri.end(), v, v + 3);
  };
  for (int i = 0; i < nlat; i++)
    for (int j = 0; j < nlon; j++) {
      double a[3], b[3], c[3], d[3];
      vert(i, j, a);
      vert(i, j + 1, b);
      vert(i + 1, j, c);
      vert(i + 1, j + 1, d);
      if (i > 0) add(a, b, d);
      if (i < nlat - 1) add(a, d, c);
    }
  return tri;
}

}    // namespace

TEST(FineMesh, SphereOf100kFacets)
{
  const double R = 0.015;
  const std::vector<double> tri = uv_sphere(R, 200, 256);
  ASSERT_EQ(tri.size() / 9, 101888u);
  sphcut::write_stl_binary("sphere.stl", tri);
  // facets within 2h of a point at the surface, at the equator and near the pole
  sphcut::TriBins bins;
  sphcut::tri_bin_build(tri, 3, 2.0 * H, bins);
  std::vector<int> cand(200000);
  const double xe[3] = {R + RC, 0.0, 0.0}, xp[3] = {1e-4, 1e-4, R + RC};
  const int ne = sphcut::tri_bin_query(bins.view(), xe, 2.0 * H, cand.data(), (int) cand.size());
  const int np = sphcut::tri_bin_query(bins.view(), xp, 2.0 * H, cand.data(), (int) cand.size());
  std::printf("[ fine     ] %zu facets; within 2h of a surface particle: %d at the equator, %d at a pole\n",
              tri.size() / 9, ne, np);
  EXPECT_GT(ne, 200);

  const double dirs[8][3] = {{1, 0, 0},  {0, 1, 0},      {-1, -1, 0},   {1, 1, 1},
                             {0.3, -0.5, 0.81}, {0.05, 0.02, 1}, {0, 0, -1}, {-0.7, 0.2, -0.68}};
  const double d0 = RC + 2.0e-4, v0 = 2.0;
  Lammps l;
  double x0[3];
  std::vector<std::array<double, 3>> n(8);
  for (int k = 0; k < 8; k++) {
    const double ln = sqrt(dirs[k][0] * dirs[k][0] + dirs[k][1] * dirs[k][1] + dirs[k][2] * dirs[k][2]);
    for (int a = 0; a < 3; a++) n[k][a] = dirs[k][a] / ln;
  }
  for (int a = 0; a < 3; a++) x0[a] = (R + d0) * n[0][a];
  one_particle(l, 3, x0);
  for (int k = 1; k < 8; k++)
    l.cmd("create_atoms 1 single " + num((R + d0) * n[k][0]) + " " + num((R + d0) * n[k][1]) + " " +
          num((R + d0) * n[k][2]) + " units box");
  l.cmd("timestep 2e-6");
  for (int k = 0; k < 8; k++) {
    const int i = l.lmp->atom->map(k + 1);
    for (int a = 0; a < 3; a++) l.lmp->atom->v[i][a] = -v0 * n[k][a];
  }
  l.cmd("fix tool all contact/tri-penalty dfac 0 onset 0 stl sphere.stl");    // seed 000's law: max penetration below
  const double k_spring = 1.0e6 * DP, m = RHO * DP * DP * DP;
  const double dmin_allowed = RC - 1.2 * v0 * sqrt(m / k_spring);    // max penetration v0 sqrt(m/k)
  std::vector<double> dmin(8, 1.0), worst(8, 0.0);
  std::vector<int> ncontact(8, 0);
  for (int s = 0; s < 60; s++) {
    l.cmd("run 5 pre no post no");
    for (int k = 0; k < 8; k++) {
      const double *x = pos(l, k + 1), *f = fcontact(l, k + 1);
      const double r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
      dmin[k] = std::min(dmin[k], r - R);
      const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      if (fl == 0.0) continue;
      ncontact[k]++;
      const double cx = f[1] * x[2] - f[2] * x[1], cy = f[2] * x[0] - f[0] * x[2], cz = f[0] * x[1] - f[1] * x[0];
      worst[k] = std::max(worst[k], sqrt(cx * cx + cy * cy + cz * cz) / (fl * r));
      EXPECT_GT(f[0] * x[0] + f[1] * x[1] + f[2] * x[2], 0.0) << "particle " << k << " pulled in";
    }
  }
  for (int k = 0; k < 8; k++) {
    const double *x = pos(l, k + 1), *v = vel(l, k + 1);
    const double r = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    const double vout = (v[0] * x[0] + v[1] * x[1] + v[2] * x[2]) / r;
    std::printf("[ fine     ] particle %d: closest %.4f mm to the sphere (allowed > %.4f), %2d samples in contact, "
                "force off the radius %.1e rad, rebound %.4f v0\n",
                k, 1e3 * dmin[k], 1e3 * dmin_allowed, ncontact[k], worst[k], vout / v0);
    EXPECT_GT(dmin[k], dmin_allowed) << "particle " << k;
    EXPECT_GT(ncontact[k], 3) << "particle " << k;
    EXPECT_LT(worst[k], 0.02) << "particle " << k;
    EXPECT_NEAR(vout, v0, 0.03 * v0) << "particle " << k;
  }
}

/* ----------------------------------------------------------------------
   moving tool: a rigid plate pushes a 2D elastic strip (40 x 4 particles, y periodic,
   the far 3 rows clamped) at 0.2 m/s.  Periodic in y and plane strain (LAMMPS 2D) the strip
   is laterally confined, eps_yy = eps_zz = 0: uniaxial strain, sigma_xx = M eps_xx with the
   constrained (P-wave) modulus M = E (1 - nu)/((1 + nu)(1 - 2 nu)), uniform along the
   strip and without end effects at the clamp.  E/(1 - nu^2) would be plane strain with free
   lateral faces, E plane stress: neither applies here.  Strain = front-row displacement /
   distance front row - first clamped row; F is fitted through the origin over the second
   half of the push (the elastic waves, 30 transits, average out).  The contact penetration
   under load is that of the default smooth onset (static_penetration) under F / ny, k = PFAC E.
------------------------------------------------------------------------- */

TEST(MovingTool, PlatePushesConfinedStrip)
{
  const int nx = 40, ny = 4;
  const double E = 200e9, nu = 0.3, V = 0.2;
  const double M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
  const double height = ny * DP, L0 = (nx - 3) * DP;
  write_box("push.stl", {-0.01, -0.01, -0.001}, {-RC, 0.02, 0.001});
  Lammps l;
  l.cmds({"units si", "dimension 2", "boundary f p p", "atom_style atomic", "atom_modify map array",
          "lattice sq 1e-3", "region box block -20 50 0 " + std::to_string(ny) + " -0.5 0.5", "create_box 1 box",
          "region blk block -0.01 " + num(nx - 0.99) + " 0 " + std::to_string(ny) + " -0.5 0.5",
          "create_atoms 1 region blk", "mass 1 " + num(RHO * DP * DP),
          "region cl block " + num(nx - 3.01) + " INF INF INF INF INF", "group clamp region cl",
          "region fr block INF 0.01 INF INF INF INF", "group front region fr", "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal clamp clamp cfl 0.3",
          "fix tool all contact/tri-penalty stl push.stl velocity " + num(V) + " 0 0 dfac 0.5",
          "variable uf equal xcm(front,x)", "run 0"});
  ASSERT_EQ(l.lmp->atom->natoms, nx * ny);
  double sfe = 0.0, see = 0.0, worst_pen = 0.0;
  double F = 0.0, eps = 0.0;
  for (int s = 1; s <= 20; s++) {
    // about 280 steps of the Courant limit (the default contact's limit, dtfac 0.5, is 0.7 of it)
    l.cmd("run 400 pre no post no");
    F = -l.equal("f_tool[1]");
    const double uf = l.equal("v_uf");
    eps = uf / L0;
    if (s > 10) {
      sfe += F * eps;
      see += eps * eps;
    }
    // the plate is ahead of the front row by the contact penetration under F / ny (k = E)
    const double pen = l.equal("f_tool[8]") - uf, pen_est = static_penetration(F / (ny * E), 0.2 * RC);
    if (s > 10) worst_pen = std::max(worst_pen, fabs(pen - pen_est) / pen_est);
  }
  const double Mfit = sfe / see / height;
  const double transits = l.lmp->update->atime * sqrt(M / RHO) / L0;
  std::printf("[ push     ] strain %.3e, F %.5g N/m, M H eps %.5g N/m; fitted modulus %.4g GPa, "
              "M %.4g GPa (%+.2f %%), %.0f wave transits; penetration vs static_penetration %.2f %%\n",
              eps, F, M * height * eps, Mfit / 1e9, M / 1e9, 100 * (Mfit - M) / M, transits, 100 * worst_pen);
  EXPECT_GT(transits, 20.0);
  EXPECT_GT(eps, 1.0e-3);
  EXPECT_NEAR(Mfit, M, 0.03 * M);
  EXPECT_LT(worst_pen, 0.02);
  EXPECT_EQ(l.equal("f_tool[5]"), ny);    // only the front row touches the plate
  EXPECT_NEAR(l.equal("f_tool[8]"), V * l.lmp->update->atime, 1e-12);
}

/* ----------------------------------------------------------------------
   friction heat: a particle slides on the plate with mu 0.3, eta 1.  The friction work is
   the kinetic energy it loses (the normal motion is at equilibrium, gravity does no work);
   the heat budget (elements 6 + 7), the time integral of the friction power (element 4)
   and the temperature rise sum m cp dT all equal it within 1 %.
   Split auto with tool particles: the tool takes e_t/(e_t + e_w), e = sqrt(k rho cp)
   (k 0.04 vs 0.01 W/m/K: 2/3; with the tool density a quarter: 1/2), spread with kernel weights over tool particles within 2h
   of the particle; the conductivities are small so conduction moves < 1e-5 of the heat.
------------------------------------------------------------------------- */

namespace {

void heat_scene(Lammps &l, bool tool_particles, const std::string &contact_extra,
                const std::string &tool_coeff = "rho0 7800 E 1e6 nu 0.3 h 1.3e-3 cp 477 k 0.04")
{
  const double g = 1000.0, E = 1.0e6;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "region box block -0.02 0.02 -0.02 0.02 -0.5e-3 0.5e-3", "create_box 2 box",
          "create_atoms 1 single 0 " + num(RC - RHO * DP * DP * g / E) + " 0 units box",
          "mass * " + num(RHO * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3 cp 477 k 0.01",
          "pair_coeff 2 2 " + tool_coeff});
  if (tool_particles) {
    // two rows of rigid tool particles under the plate surface, x in [-10, 10] mm
    l.cmds({"lattice sq 1e-3", "region tl block -10.01 10.01 -2.01 -0.99 -0.5 0.5",
            "create_atoms 2 region tl", "group toolp type 2",
            "fix sph all sph/jc-thermal tool toolp"});
  } else {
    l.cmd("fix sph all sph/jc-thermal");
  }
  l.cmds({"group work type 1", "fix heat all heat/fmfs", "fix g work gravity " + num(g) + " vector 0 -1 0",
          "timestep 5e-6", "velocity work set 1 0 0 units box",
          "fix tool all contact/tri-penalty stl plate.stl dfac 0.5 mu 0.3 eta 1 heat heat " + contact_extra,
          "fix pw all vector 1 f_tool[4]", "run 0"});
}

// sum m cp T over the particles of one type (serial test: all atoms are local)
double heat_content(Lammps &l, int type)
{
  auto *atom = l.lmp->atom;
  auto *sph = sphcut::fix_by_id(l.lmp->modify, "sph");
  double e = 0.0;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->type[i] == type) e += atom->mass[type] * 477.0 * sph->array_atom[i][11];    // column TEMP
  return e;
}

}    // namespace

TEST(FrictionHeat, BudgetEqualsFrictionWork)
{
  write_plate();
  Lammps l;
  heat_scene(l, false, "split 1");
  const double m = RHO * DP * DP;
  const double e0 = heat_content(l, 1);
  const double v0 = vel(l, 1)[0];
  l.cmd("run 500");
  const double v1 = vel(l, 1)[0];
  const double work = 0.5 * m * (v0 * v0 - v1 * v1);
  const double q = l.equal("f_tool[6]") + l.equal("f_tool[7]");
  const double integral = l.equal("trap(f_pw)") * 5e-6;    // trapezoidal rule over steps 0..500
  const double de = heat_content(l, 1) - e0;
  std::printf("[ heat     ] friction work (kinetic energy lost) %.6e J/m, heat budget %.6e (%+.2e), "
              "int P dt %.6e (%+.2e), sum m cp dT %.6e (%+.2e)\n",
              work, q, (q - work) / work, integral, (integral - work) / work, de, (de - work) / work);
  EXPECT_GT(v1, 0.1);
  EXPECT_NEAR(q, integral, 0.01 * integral);
  EXPECT_NEAR(q, work, 0.01 * work);
  EXPECT_NEAR(de, work, 0.01 * work);
  EXPECT_NEAR(l.equal("f_heat[4]"), q, 1e-9 * q);    // heat/fmfs counted the same source
  EXPECT_EQ(l.equal("f_tool[14]"), 0.0);
}

TEST(FrictionHeat, SplitAutoToToolParticles)
{
  // the tool share, worked out by hand: two semi-infinite bodies heated at their contact
  // take the heat in the ratio of their effusivities e = sqrt(k rho cp) (seed 000 sec. 4).
  // A: k 0.04 vs 0.01 W/m/K, same rho and cp: e_t = 2 e_w, tool share 2/3.
  // B: k 0.04 vs 0.01 and tool rho0 a quarter: e_t = e_w, share 1/2 (a split by conductivity
  //    alone would give 0.8, one by diffusivity 0.94).
  struct Case {
    std::string tool_coeff;
    double share;
  };
  for (const Case &c : {Case{"rho0 7800 E 1e6 nu 0.3 h 1.3e-3 cp 477 k 0.04", 2.0 / 3.0},
                        Case{"rho0 1950 E 1e6 nu 0.3 h 1.3e-3 cp 477 k 0.04", 0.5}}) {
    SCOPED_TRACE(c.tool_coeff);
    write_plate();
    Lammps l;
    heat_scene(l, true, "tool_particles toolp", c.tool_coeff);    // split auto is the default with tool_particles
    const double m = RHO * DP * DP;
    const double ew0 = heat_content(l, 1), et0 = heat_content(l, 2);
    const double v0 = vel(l, 1)[0];
    l.cmd("run 500");
    const double v1 = vel(l, 1)[0];
    const double work = 0.5 * m * (v0 * v0 - v1 * v1);
    const double qw = l.equal("f_tool[6]"), qt = l.equal("f_tool[7]");
    const double dew = heat_content(l, 1) - ew0, det = heat_content(l, 2) - et0;
    // tool particles out of reach (2h) of the particle's path (x in [0, 1.6] mm) get no friction heat
    double far = 0.0, near = 0.0;
    auto *atom = l.lmp->atom;
    auto *sph = sphcut::fix_by_id(l.lmp->modify, "sph");
    for (int i = 0; i < atom->nlocal; i++) {
      if (atom->type[i] != 2) continue;
      const double dT = sph->array_atom[i][11] - 300.0;
      if (atom->x[i][0] < -2.0 * H - 1e-9 || atom->x[i][0] > 2.0e-3 + 2.0 * H) far = std::max(far, fabs(dT));
      else near = std::max(near, dT);
    }
    std::printf("[ heat     ] split auto: tool share %.6f (expected %.6f), workpiece dE %.6e vs %.6e, "
                "tool dE %.6e vs %.6e, friction work %.6e; far tool particles dT %.1e K, near %.2e K\n",
                qt / (qw + qt), c.share, dew, qw, det, qt, work, far, near);
    EXPECT_NEAR(qt / (qw + qt), c.share, 1e-12);
    EXPECT_NEAR(qw + qt, work, 0.01 * work);
    EXPECT_NEAR(dew, qw, 0.01 * qw);
    EXPECT_NEAR(det, qt, 0.01 * qt);
    EXPECT_GT(near, 0.0);
    EXPECT_LT(far, 1e-5 * near);    // conduction only (k = 0.04 W/m/K)
    EXPECT_EQ(l.equal("f_tool[14]"), 0.0);
  }
}

// the tool share of the friction heat goes to every tool particle within reach (2 h_ij),
// however many: a fine tool-particle lattice (0.05 mm) puts several hundred there
// (the buffer used to stop at 256); tool conductivity 0, so only friction heats the tool
TEST(FrictionHeat, EveryToolParticleInReach)
{
  write_plate();
  Lammps l;
  const double g = 1000.0, E = 1.0e6, dpt = 5.0e-5;
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "region box block -0.02 0.02 -0.02 0.02 -0.5e-3 0.5e-3", "create_box 2 box",
          "create_atoms 1 single 0 " + num(RC - RHO * DP * DP * g / E) + " 0 units box",
          "mass 1 " + num(RHO * DP * DP), "mass 2 " + num(RHO * dpt * dpt), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3 cp 477 k 0.01",
          "pair_coeff 2 2 rho0 7800 E 1e6 nu 0.3 hdx 1.3 cp 477 k 0",
          "lattice sq " + num(dpt), "region tl block -60.01 60.01 -20.01 -0.99 -0.5 0.5", "create_atoms 2 region tl",
          "group toolp type 2", "group work type 1", "fix sph all sph/jc-thermal tool toolp",
          "fix heat all heat/fmfs", "fix g work gravity " + num(g) + " vector 0 -1 0", "timestep 5e-6",
          "velocity work set 1 0 0 units box",
          "fix tool all contact/tri-penalty stl plate.stl dfac 0.5 mu 0.3 eta 1 heat heat tool_particles toolp split 0.5",
          "run 0"});
  auto *atom = l.lmp->atom;
  auto *sph = sphcut::fix_by_id(l.lmp->modify, "sph");
  std::vector<double> t0(atom->natoms + 1);
  for (int i = 0; i < atom->nlocal; i++) t0[atom->tag[i]] = sph->array_atom[i][11];
  l.cmd("run 1");
  const double reach = 2.0 * 0.5 * (1.3 * DP + 1.3 * dpt);    // 2 h_ij, h = hdx x spacing
  const double *xw = pos(l, 1);
  int inside = 0, cold = 0, hot_outside = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (atom->type[i] != 2) continue;
    const double r = sqrt(sphcut::sq(atom->x[i][0] - xw[0]) + sphcut::sq(atom->x[i][1] - xw[1]));
    const double dT = sph->array_atom[i][11] - t0[atom->tag[i]];
    if (r < reach - 1.0e-5) {    // the particle moved 5 um in the step
      inside++;
      cold += !(dT > 0.0);
    } else if (r > reach + 1.0e-5) {
      hot_outside += dT != 0.0;
    }
  }
  std::printf("[ heat     ] %d tool particles within 2h_ij of the sliding particle, %d got no friction heat, "
              "%d outside got some; tool heat %.4e J/m\n",
              inside, cold, hot_outside, l.equal("f_tool[7]"));
  EXPECT_GT(inside, 256);
  EXPECT_GT(l.equal("f_tool[7]"), 0.0);
  EXPECT_EQ(cold, 0);
  EXPECT_EQ(hot_outside, 0);
}

// heat accounting without tool particles: split 0.4 with a lumped tool (tool_cp C T0): the
// tool share 0.6 q raises the tool temperature (element 11) by 0.6 q / C; without a heat fix
// the workpiece share is not assigned (element 14), with neither the whole heat is
TEST(FrictionHeat, LumpedToolAndUnassigned)
{
  write_plate();
  const double m = RHO * DP * DP, C = 0.01;
  struct Case {
    bool heatfix;
    std::string extra;
  };
  for (const Case &c : {Case{true, "split 0.4 tool_cp 0.01 300"}, Case{false, "split 0.4 tool_cp 0.01 300"},
                        Case{false, ""}}) {
    Lammps l;
    heat_scene(l, false, c.extra);
    if (!c.heatfix) l.cmds({"unfix tool", "unfix heat",
                            "fix tool all contact/tri-penalty stl plate.stl dfac 0.5 mu 0.3 eta 1 " + c.extra});
    const double e0 = heat_content(l, 1);
    const double v0 = vel(l, 1)[0];
    l.cmd("run 500");
    const double v1 = vel(l, 1)[0];
    const double work = 0.5 * m * (v0 * v0 - v1 * v1);
    const double qw = l.equal("f_tool[6]"), qt = l.equal("f_tool[7]"), lost = l.equal("f_tool[14]");
    const double ttool = l.equal("f_tool[11]"), de = heat_content(l, 1) - e0;
    std::printf("[ heat     ] %s %-27s: workpiece %.5e (dE %.5e), tool %.5e (T %.6f K), not assigned %.5e, "
                "friction work %.5e J/m\n",
                c.heatfix ? "heat/fmfs" : "no heat  ", c.extra.c_str(), qw, de, qt, ttool, lost, work);
    EXPECT_NEAR(qw + qt + lost, work, 0.01 * work);
    if (c.extra.empty()) {
      EXPECT_EQ(qw + qt, 0.0);
      EXPECT_EQ(ttool, 0.0);
    } else {
      EXPECT_NEAR(qt, 0.6 * (qw + qt + lost), 1e-12 * work);
      EXPECT_NEAR(ttool, 300.0 + qt / C, 1e-9 * 300.0);
      if (c.heatfix) {
        EXPECT_EQ(lost, 0.0);
        EXPECT_NEAR(de, qw, 0.01 * qw);
      } else {
        EXPECT_EQ(qw, 0.0);
        EXPECT_NEAR(lost, 0.4 / 0.6 * qt, 1e-12 * work);
        EXPECT_EQ(de, 0.0);
      }
    }
  }
}

/* ----------------------------------------------------------------------
   tool output and the insert generator through the fix
------------------------------------------------------------------------- */

// write N FILE: the current (moved) geometry; 3D STL read back = the plate + displacement
TEST(Output, WriteMovedToolGeometry)
{
  write_plate();
  Lammps l;
  const double x0[3] = {0.0, 0.005, 0.0};
  one_particle(l, 3, x0);
  l.cmds({"fix tool all contact/tri-penalty stl plate.stl velocity 1 -2 0.5 write 10 tool_*.stl", "run 20"});
  const std::vector<double> tri = sphcut::read_stl("tool_20.stl");
  const std::vector<double> ref = sphcut::read_stl("plate.stl");
  ASSERT_EQ(tri.size(), ref.size());
  const double t = 20 * 5e-6, d[3] = {1.0 * t, -2.0 * t, 0.5 * t};
  double err = 0.0;
  for (size_t k = 0; k < tri.size(); k++) err = std::max(err, fabs(tri[k] - ref[k] - d[k % 3]));
  EXPECT_LT(err, 1e-15);
  EXPECT_NEAR(l.equal("f_tool[8]"), d[0], 1e-18);
  EXPECT_NEAR(l.equal("f_tool[9]"), d[1], 1e-18);
  EXPECT_NEAR(l.equal("f_tool[10]"), d[2], 1e-18);
  std::ifstream in("tool_0.stl");
  EXPECT_TRUE(in.good());    // written at the setup too
}

// insert generator (sphcut_stl.h convention): the rake face faces -x, tilted by the rake
// angle: outward normal (-cos g, sin g).  A particle thrown at the rake face 1 mm above the
// (sharp) tip is pushed back along that normal, in 2D (section) and 3D (extruded insert).
TEST(Insert, RakeFaceNormal)
{
  const double gam = 8.0 * PI / 180.0;
  const double nr[3] = {-cos(gam), sin(gam), 0.0}, up[3] = {sin(gam), cos(gam), 0.0};
  for (int dim : {2, 3}) {
    Lammps l;
    const double s = 1.0e-3, d0 = RC + 2.0e-4, v0 = 2.0;
    const double x0[3] = {s * up[0] + d0 * nr[0], s * up[1] + d0 * nr[1], 0.0};
    one_particle(l, dim, x0);
    l.cmds({"timestep 2e-6", "velocity all set " + num(-v0 * nr[0]) + " " + num(-v0 * nr[1]) + " 0 units box",
            std::string("fix tool all contact/tri-penalty insert rake 8 clearance 6 radius 0 rake_length 3e-3 "
                        "flank_length 3e-3") + (dim == 3 ? " width 4e-3" : "") + " dfac 0 write 1000 insert.vtk"});
    double worst = 0.0;
    int ncontact = 0;
    for (int k = 0; k < 60; k++) {
      l.cmd("run 5 pre no post no");
      const double *f = fcontact(l, 1);
      const double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
      if (fl == 0.0) continue;
      ncontact++;
      for (int a = 0; a < 3; a++) worst = std::max(worst, fabs(f[a] / fl - nr[a]));
    }
    const double *v = vel(l, 1);
    const double vout = v[0] * nr[0] + v[1] * nr[1];
    std::printf("[ insert   ] %dD rake face hit: %d samples in contact, max |f/|f| - n_rake| %.2e, rebound %.5f v0\n", dim,
                ncontact, worst, vout / v0);
    EXPECT_GT(ncontact, 3);
    EXPECT_LT(worst, 1e-12);
    EXPECT_NEAR(vout, v0, 0.02 * v0);
  }
}

/* ----------------------------------------------------------------------
   bad input
------------------------------------------------------------------------- */

TEST(BadInput, ContactFix)
{
  write_plate();
  Lammps l;
  const double x0[3] = {0.0, 0.005, 0.0};
  one_particle(l, 2, x0);
  const std::string fix = "fix tool all contact/tri-penalty ";
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl colour red", "unknown keyword colour"));
  EXPECT_TRUE(l.error_contains(fix + "mu 0.3", "no tool geometry (keyword stl or insert)"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl mu -1", "mu must be >= 0, got -1"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl write 10 tool.txt", "write file tool.txt must end in .vtk or .stl"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl write 10 tool.stl",
                               "write file tool.stl: a 2D tool (segments) can only be written as .vtk"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl eta 2", "eta must be in [0,1], got 2"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl stick maybe", "stick must be yes or no, got maybe"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl pfac 0", "pfac must be > 0, got 0"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl split auto", "split auto needs tool_particles"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl scale 2 insert rake 5 clearance 7 radius 0 rake_length 1e-3 "
                                     "flank_length 1e-3",
                               "scale and rotate apply to stl tools only"));
  EXPECT_TRUE(l.error_contains(fix + "stl", "keyword stl needs 1 value(s)"));
  EXPECT_TRUE(l.error_contains(fix + "insert rake 5 clearance x radius 0 rake_length 1e-3 flank_length 1e-3",
                               "Expected floating point parameter instead of 'x'"));
  EXPECT_TRUE(l.error_contains(fix + "insert rake 50 clearance 45 radius 0 rake_length 1e-3 flank_length 1e-3",
                               "wedge angle 90 - alpha - gamma must be positive"));
  EXPECT_TRUE(l.error_contains(fix + "insert rake 0 clearance 7 radius 0 rake_length 1e-3 flank_length 1e-3 land -2e-05",
                               "cutting insert: land must be >= 0 and finite, got -2e-05"));
  // the friction law keywords
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction sticky", "friction must be static, coulomb or memory, got sticky"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction memory tfac 0", "tfac must be in (0,1], got 0"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction memory tfac 2", "tfac must be in (0,1], got 2"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl tfac 0.2", "tfac applies to friction memory only"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction memory stick yes", "stick applies to friction static/coulomb"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction memory vreg 0.1", "vreg applies to friction static/coulomb"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction static stick no", "give friction or stick, not both"));
  EXPECT_TRUE(l.error_contains(fix + "stl plate.stl friction", "keyword friction needs 1 value(s)"));
  // checked at init
  l.cmds({fix + "stl plate.stl velocity v_vx 0 0"});
  EXPECT_TRUE(l.error_contains("run 0", "velocity variable vx does not exist"));
  l.cmds({"unfix tool", "fix g all gravity 1 vector 0 -1 0", fix + "stl plate.stl heat g"});
  EXPECT_TRUE(l.error_contains("run 0", "fix g is not of style heat/fmfs"));
  l.cmds({"unfix tool", fix + "stl plate.stl heat nofix"});
  EXPECT_TRUE(l.error_contains("run 0", "heat fix nofix does not exist"));
  l.cmds({"unfix tool", "variable vx atom x", fix + "stl plate.stl velocity v_vx 0 0"});
  EXPECT_TRUE(l.error_contains("run 0", "velocity variable vx is not equal-style"));
  l.cmds({"unfix tool", fix + "stl plate.stl mu v_m tvar T"});
  EXPECT_TRUE(l.error_contains("run 0", "mu variable m does not exist or is not equal-style"));
}
