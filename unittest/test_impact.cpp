// Plastic impact: the copper Taylor bar of examples/taylor-bar at a coarse resolution runs
// stably (no lost atoms, no NaN), conserves kinetic + internal energy, and ends near the
// published final length (21.4 mm; broad band at this resolution).
#include "sphcut_test.h"

#include <cmath>
#include <cstdio>

using sphcut_test::Lammps;

TEST(Impact, TaylorBarCoarse)
{
  Lammps l;
  l.cmds({"variable dx index 0.81e-3"});
  l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/taylor-bar/in.taylor").c_str());
  const double natoms = l.lmp->atom->natoms;
  const double length = l.equal("v_length");
  const double radius = l.equal("v_radius");
  const double e0 = l.equal("v_e0");
  const double e1 = l.equal("v_etot");
  const double epsmax = l.equal("f_sph[6]");
  std::printf("[ taylor   ] %g atoms: final length %.3f mm, mushroom radius %.3f mm, max plastic strain %.3f, "
              "energy error %.2e\n", natoms, length, radius, epsmax, (e1 - e0) / e0);
  EXPECT_EQ(l.lmp->atom->natoms, 4160);    // 2 bars x 52 per layer x 40 layers, none lost
  EXPECT_TRUE(std::isfinite(length) && std::isfinite(e1));
  EXPECT_GT(length, 20.5);
  EXPECT_LT(length, 24.0);
  EXPECT_GT(radius, 5.0);
  EXPECT_GT(epsmax, 1.0);
  EXPECT_LT(fabs(e1 - e0) / e0, 0.01);
}
