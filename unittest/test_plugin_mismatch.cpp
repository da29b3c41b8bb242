// a plugin built for another LAMMPS version registers nothing and says which versions and how to
// rebuild (issue 52).  SPHCUT_MISMATCH_PLUGIN_PATH: the same plugin built with
// SPHCUT_BUILT_FOR_LAMMPS="1 Jan 2000".  Each case runs in a process of its own (ctest, filters),
// so that the two plugins, which define the same symbols, are never loaded together.
#include "sphcut_test.h"

#include "compute.h"
#include "input.h"
#include "library.h"
#include "version.h"

#include <fstream>
#include <sstream>

namespace {

struct Loaded {
  std::string log;
  int nplugins;
  bool pair, fix, compute, command;
};

// a LAMMPS instance logging to `logname` loads `plugin`; what was registered and what was logged
Loaded load(const std::string &plugin, const std::string &logname)
{
  std::vector<std::string> args = {"sphcut_test", "-log", logname, "-screen", "none", "-nocite"};
  std::vector<char *> argv;
  for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
  auto *lmp = new LAMMPS_NS::LAMMPS((int) argv.size(), argv.data(), MPI_COMM_WORLD);
  lmp->input->one("plugin load " + plugin);
  Loaded r;
  r.nplugins = lammps_plugin_count();
  r.pair = lmp->force->pair_map->count("sph/jc-thermal") > 0;
  r.fix = lmp->modify->fix_map->count("sph/jc-thermal") + lmp->modify->fix_map->count("heat/fmfs") +
          lmp->modify->fix_map->count("contact/tri-penalty") > 0;
  r.compute = lmp->modify->compute_map->count("surface/lambda") > 0;
  r.command = lmp->input->command_map->count("dump_sph") > 0;
  if (r.pair) {
    delete lmp;
  } else {
    // using a style then is LAMMPS' own error, not a crash
    lmp->input->one("units si");
    lmp->input->one("region box block 0 1 0 1 0 1");
    lmp->input->one("create_box 1 box");
    EXPECT_THROW(lmp->input->one("pair_style sph/jc-thermal"), LAMMPS_NS::LAMMPSException);
    delete lmp;
  }
  std::ifstream in(logname);
  std::stringstream ss;
  ss << in.rdbuf();
  r.log = ss.str();
  return r;
}

}    // namespace

TEST(PluginMismatch, RegistersNothingAndNamesBothVersions)
{
  const Loaded r = load(SPHCUT_MISMATCH_PLUGIN_PATH, "log.mismatch");
  EXPECT_EQ(r.nplugins, 0);
  EXPECT_FALSE(r.pair);
  EXPECT_FALSE(r.fix);
  EXPECT_FALSE(r.compute);
  EXPECT_FALSE(r.command);
  const std::string running = LAMMPS_VERSION;    // this LAMMPS (the test links the one it is built against)
  EXPECT_NE(r.log.find("WARNING: sphcut " SPHCUT_TEST_VERSION " was built for LAMMPS 1 Jan 2000 but this is LAMMPS " +
                       running + ": no sphcut style is loaded"),
            std::string::npos)
      << r.log;
  EXPECT_NE(r.log.find("Rebuild sphcut against this LAMMPS"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("cmake -S " SPHCUT_SOURCE_DIR " -B build-"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("-DLAMMPS_SOURCE_DIR=<this LAMMPS>/src -DLAMMPS_ROOT=<its install prefix>"), std::string::npos)
      << r.log;
  EXPECT_NE(r.log.find("ERROR: Unrecognized pair style 'sph/jc-thermal'"), std::string::npos) << r.log;
}

TEST(PluginMatch, RegistersEverythingWithoutWarning)
{
  const Loaded r = load(SPHCUT_PLUGIN_PATH, "log.match");
  EXPECT_GT(r.nplugins, 0);
  EXPECT_TRUE(r.pair);
  EXPECT_TRUE(r.fix);
  EXPECT_TRUE(r.compute);
  EXPECT_TRUE(r.command);
  EXPECT_EQ(r.log.find("WARNING"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("Loading plugin: sphcut"), std::string::npos) << r.log;
}
