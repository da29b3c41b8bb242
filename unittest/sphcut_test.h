/* sphcut unit tests: a LAMMPS instance driven through its C++ library API */

#ifndef SPHCUT_TEST_H
#define SPHCUT_TEST_H

#include "atom.h"
#include "input.h"
#include "lammps.h"
#include "library.h"
#include "modify.h"
#include "fix.h"
#include "variable.h"
#include "exceptions.h"

#include <gtest/gtest.h>
#include <mpi.h>

#include <string>
#include <vector>

namespace sphcut_test {

// one LAMMPS instance with the sphcut plugin loaded; output silenced unless SPHCUT_TEST_VERBOSE
class Lammps {
 public:
  explicit Lammps(MPI_Comm comm = MPI_COMM_WORLD, std::vector<std::string> extra = {})
  {
    std::vector<std::string> args = {"sphcut_test", "-log", "none", "-nocite"};
    if (!getenv("SPHCUT_TEST_VERBOSE")) { args.push_back("-screen"); args.push_back("none"); }
    for (auto &e : extra) args.push_back(e);
    std::vector<char *> argv;
    for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
    lmp = new LAMMPS_NS::LAMMPS((int) argv.size(), argv.data(), comm);
    cmd(std::string("plugin load ") + SPHCUT_PLUGIN_PATH);
  }
  ~Lammps() { delete lmp; }
  void cmd(const std::string &line) { lmp->input->one(line); }
  void cmds(const std::vector<std::string> &lines) { for (auto &l : lines) cmd(l); }
  // expect a LAMMPS error whose message contains `what`
  ::testing::AssertionResult error_contains(const std::string &line, const std::string &what)
  {
    try {
      cmd(line);
    } catch (LAMMPS_NS::LAMMPSException &e) {
      if (std::string(e.what()).find(what) != std::string::npos) return ::testing::AssertionSuccess();
      return ::testing::AssertionFailure() << "error '" << e.what() << "' lacks '" << what << "'";
    }
    return ::testing::AssertionFailure() << "no error from '" << line << "'";
  }
  double equal(const std::string &expr) { return lmp->input->variable->compute_equal(expr); }
  LAMMPS_NS::LAMMPS *lmp;
};

}    // namespace sphcut_test

#endif
