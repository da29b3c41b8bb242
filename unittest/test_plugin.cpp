// the plugin loads, registers its styles, and bad arguments give LAMMPS errors (not crashes)
#include "sphcut_test.h"

#include "force.h"
#include "variable.h"

using sphcut_test::Lammps;

TEST(Plugin, LoadsAndListsStyles)
{
  Lammps l;
  EXPECT_EQ(l.lmp->force->pair_map->count("sph/jc-thermal"), 1u);
  EXPECT_EQ(l.lmp->modify->fix_map->count("sph/jc-thermal"), 1u);
  int found = 0;
  char style[64], name[64];
  for (int i = 0; i < lammps_plugin_count(); i++) {
    lammps_plugin_name(i, style, name, 64);
    if (std::string(name) == "sph/jc-thermal") found++;
  }
  EXPECT_EQ(found, 2);    // pair and fix
}

TEST(Plugin, BadStyleArgumentIsALammpsError)
{
  Lammps l;
  l.cmds({"units si", "atom_style atomic", "region box block 0 1 0 1 0 1", "create_box 1 box"});
  EXPECT_TRUE(l.error_contains("pair_style sph/jc-thermal kernel gaussian", "unknown kernel gaussian"));
  EXPECT_TRUE(l.error_contains("pair_style sph/jc-thermal flavour x", "unknown pair_style keyword flavour"));
  EXPECT_TRUE(l.error_contains("fix 1 all sph/jc-thermal cfl 2.0", "cfl must be in (0,1], got 2"));
  EXPECT_TRUE(l.error_contains("fix 1 all sph/jc-thermal tool nogroup", "tool group nogroup does not exist"));
}
