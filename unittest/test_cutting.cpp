// The flagship case (examples/cutting-2d-ti6al4v) at a coarse resolution and a short cut:
// runs without lost atoms or NaN, a chip starts to form, the forces are positive and in a
// broad band around the experiment, and the energy balance of the tool closes:
// work of the tool = kinetic + internal energy of the particles + contact dissipation.
#include "sphcut_test.h"

#include "update.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>

using sphcut_test::Lammps;

TEST(Cutting, QuickTi6Al4V)
{
  Lammps l;
  l.cmds({"variable ny index 11", "variable cut index 0.12e-3", "variable dumpevery index 0"});
  l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting").c_str());
  auto *atom = l.lmp->atom;
  const double H = 0.3e-3, dx = H / 10;
  double ymax = -1.0, bad = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < 2; k++)
      if (!std::isfinite(atom->x[i][k]) || !std::isfinite(atom->v[i][k])) bad = 1.0;
    if (atom->type[i] == 1) ymax = std::max(ymax, atom->x[i][1]);
  }
  EXPECT_EQ(bad, 0.0);
  // no lost atoms: the 11-across geometry creates 1393 (workpiece, clamp, tool); LAMMPS would
  // also stop with "Lost atoms" (thermo_modify lost error, the default)
  EXPECT_EQ(atom->natoms, 1393);
  const double lcut = l.equal("v_lcut"), fc = l.equal("v_Fc"), ft = l.equal("v_Ft");
  const double tmax = l.equal("v_Tmax");
  const double work = l.equal("f_cut[13]"), diss = l.equal("f_cut[15]");
  const double eint = l.equal("f_sph[2]"), ekin = l.equal("f_sph[3]");
  const double e0 = l.equal("v_e0");
  const double balance = (ekin + eint - e0 + diss - work) / work;
  std::printf("[ cutting  ] cut %.3f mm: Fc %.1f N/mm, Ft %.1f N/mm, Tmax %.0f K, chip top %.1f dx above the "
              "surface, energy: tool work %.6g J/m = (kin + int) change %.6g + contact %.6g (%+.2e)\n",
              lcut, fc, ft, tmax, (ymax - H) / dx, work, ekin + eint - e0, diss, balance);
  EXPECT_GT(lcut, 0.1);
  EXPECT_GT(ymax, H + 0.5 * dx);    // material pushed up the rake face: a chip starts
  EXPECT_GT(fc, 50.0);
  EXPECT_LT(fc, 400.0);
  EXPECT_GT(ft, 10.0);
  EXPECT_LT(ft, 300.0);
  EXPECT_GT(tmax, 350.0);           // plastic and friction heat
  EXPECT_LT(tmax, 1878.0);
  EXPECT_LT(fabs(balance), 1.5e-5);    // measured 4.4e-6

  // heat budget (issue 11 item 3) over workpiece and tool particles (fix heat/fmfs acts on all):
  // sum m cp dT = plastic heat chi W_p + friction heat (workpiece and tool shares) + heat in
  // through the Dirichlet clamp - convection - radiation.  Conduction between workpiece and
  // tool is internal.  Artificial-viscosity work is not heat (item 4): it is not in the budget.
  const double dE = l.equal("f_heat[5]") - l.equal("v_eth0");
  const double qplast = 0.9 * l.equal("f_sph[4]"), qfric = l.equal("f_heat[4]");
  const double qconv = l.equal("f_heat[1]"), qrad = l.equal("f_heat[2]"), qdir = l.equal("f_heat[3]");
  const double qlost = l.equal("f_cut[14]");
  const double sources = qplast + qfric + qdir - qconv - qrad;
  const double hb = (dE - sources) / sources;
  std::printf("[ cutting  ] heat: sum m cp dT %.6g J/m = plastic %.6g + friction %.6g (workpiece %.4g, tool %.4g) "
              "+ Dirichlet %.4g - convection %.4g - radiation %.4g (%+.2e), friction heat unassigned %.3g\n",
              dE, qplast, qfric, l.equal("f_cut[6]"), l.equal("f_cut[7]"), qdir, qconv, qrad, hb, qlost);
  // the issue asks for 1 %; measured -1.1e-6 (the friction heat is booked with the rectangle
  // rule, the temperature uses the trapezoid); the per-particle FMFS/Brookshaw form
  // (conservative no) misses by +1.2e-3 here
  EXPECT_LT(fabs(hb), 3e-6);
  EXPECT_EQ(qlost, 0.0);
}

// a long cut split with restart files continues as one run: 9000 steps in one go against
// 8000 + write_restart + read_restart (-var continue 1) + 1000, with the tool in contact
// (it reaches the workpiece after about 7700 steps).  Equal to round-off: the continued run
// re-sorts and re-neighbours, which changes the summation order.
TEST(Cutting, RestartContinuesTheCut)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";
  auto run = [&](int steps, int cont, int restartevery = 0) {
    auto l = std::make_unique<Lammps>();
    l->cmds({"variable ny index 11", "variable dumpevery index 0", "variable thermoevery index 1000",
             "variable steps index " + std::to_string(steps), "variable continue index " + std::to_string(cont),
             "variable restartevery index " + std::to_string(restartevery)});
    l->lmp->input->file(in.c_str());
    return l;
  };
  // the reference also writes restart.a / restart.b every 4000 steps (-var restartevery): the
  // one of step 8000 (restart.b) is the third split below
  std::remove("restart.a");
  std::remove("restart.b");
  auto ref = run(9000, 0, 4000);
  const double fc = ref->equal("v_Fc"), ft = ref->equal("v_Ft"), work = ref->equal("f_cut[13]");
  const double eint = ref->equal("f_sph[2]");
  std::map<int, std::array<double, 2>> xref;
  for (int i = 0; i < ref->lmp->atom->nlocal; i++)
    xref[ref->lmp->atom->tag[i]] = {ref->lmp->atom->x[i][0], ref->lmp->atom->x[i][1]};
  ref.reset();
  // split in contact (8000), and while the tool approaches (6000: the first step of the continued
  // run must not take the spring's limit the unsplit run did not take; it did, and the first
  // contact came 2 % off)
  for (int split : {6000, 8000, -8000}) {
    if (split > 0) {
      run(split, 0).reset();
    } else {    // go on from the periodic restart file of step 8000
      std::ifstream src("restart.b", std::ios::binary);
      ASSERT_TRUE(src.good()) << "restartevery 4000 wrote no restart.b";
      std::ofstream dst("restart.cutting", std::ios::binary);
      dst << src.rdbuf();
    }
    auto cont = run(9000 - std::abs(split), 1);
    std::printf("[ restart  ] split at step %d%s\n", std::abs(split), split < 0 ? " (restart.b of restartevery)" : "");
    EXPECT_EQ(cont->lmp->update->ntimestep, 9000);
    std::printf("[ restart  ] step 9000: Fc %.10g / %.10g N/mm, Ft %.10g / %.10g, tool work %.10g / %.10g\n", fc,
                cont->equal("v_Fc"), ft, cont->equal("v_Ft"), work, cont->equal("f_cut[13]"));
    EXPECT_GT(fc, 20.0);    // in contact
    EXPECT_NEAR(cont->equal("v_Fc"), fc, 1e-8 * fc);
    EXPECT_NEAR(cont->equal("v_Ft"), ft, 1e-8 * fc);
    EXPECT_NEAR(cont->equal("f_cut[13]"), work, 1e-8 * work);
    EXPECT_NEAR(cont->equal("f_sph[2]"), eint, 1e-8 * fabs(eint));
    double worst = 0.0;
    auto *atom = cont->lmp->atom;
    ASSERT_EQ((size_t) atom->nlocal, xref.size());
    for (int i = 0; i < atom->nlocal; i++) {
      const auto &x = xref.at(atom->tag[i]);
      worst = std::max({worst, fabs(atom->x[i][0] - x[0]), fabs(atom->x[i][1] - x[1])});
    }
    std::printf("[ restart  ] largest position difference %.2e m (spacing 3e-5 m)\n", worst);
    EXPECT_LT(worst, 1e-14);
  }
}

// -var balance rcb (recursive bisection, comm_style tiled: 1.02x the mean load on the busiest of
// 16 ranks at 81 across, against 1.41x with shift) runs the input's path and gives the cut of
// the default shift (one rank here; on 16 oversubscribed ranks the forces after 20 steps agreed
// to 1e-12, doc/performance.md)
TEST(Cutting, BalanceRcbEqualsShift)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";
  auto run = [&](const std::string &lb) {
    auto l = std::make_unique<Lammps>();
    l->cmds({"variable ny index 11", "variable dumpevery index 0", "variable xstart index 0.6",
             "variable steps index 3000", "variable balance index " + lb});
    l->lmp->input->file(in.c_str());
    return std::array<double, 2>{l->equal("v_Fc"), l->equal("v_Ft")};
  };
  const auto shift = run("shift"), rcb = run("rcb");
  std::printf("[ balance  ] after 3000 steps in contact: Fc %.10g / %.10g, Ft %.10g / %.10g\n", shift[0], rcb[0],
              shift[1], rcb[1]);
  EXPECT_GT(shift[0], 20.0);    // in contact
  EXPECT_NEAR(rcb[0], shift[0], 1e-9 * shift[0]);
  EXPECT_NEAR(rcb[1], shift[1], 1e-9 * shift[0]);
}
