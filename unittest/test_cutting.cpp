// The flagship case (examples/cutting-2d-ti6al4v) at a coarse resolution and a short cut:
// runs without lost atoms or NaN, a chip starts to form, the forces are positive and in a
// broad band around the experiment, and the energy balance of the tool closes:
// work of the tool = kinetic + internal energy of the particles + contact dissipation.
#include "sphcut_test.h"

#include <cmath>
#include <cstdio>

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
  const double lcut = l.equal("v_lcut"), fc = l.equal("v_Fc"), ft = l.equal("v_Ft");
  const double tmax = l.equal("v_Tmax");
  const double work = l.equal("f_cut[13]"), diss = l.equal("f_cut[15]");
  const double eint = l.equal("f_sph[2]"), ekin = l.equal("f_sph[3]");
  const double e0 = l.equal("v_e0");
  const double balance = (ekin + eint - e0 + diss - work) / work;
  std::printf("[ cutting  ] cut %.3f mm: Fc %.1f N/mm, Ft %.1f N/mm, Tmax %.0f K, chip top %.1f dx above the "
              "surface, energy: tool work %.4g J/m = (kin + int) change %.4g + contact %.4g (%+.2f %%)\n",
              lcut, fc, ft, tmax, (ymax - H) / dx, work, ekin + eint - e0, diss, 100 * balance);
  EXPECT_GT(lcut, 0.1);
  EXPECT_GT(ymax, H + 0.5 * dx);    // material pushed up the rake face: a chip starts
  EXPECT_GT(fc, 50.0);
  EXPECT_LT(fc, 400.0);
  EXPECT_GT(ft, 10.0);
  EXPECT_LT(ft, 300.0);
  EXPECT_GT(tmax, 350.0);           // plastic and friction heat
  EXPECT_LT(tmax, 1878.0);
  EXPECT_LT(fabs(balance), 0.05);
}
