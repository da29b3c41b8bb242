/* sphcut unit tests: a LAMMPS instance driven through its C++ library API */

#ifndef SPHCUT_TEST_H
#define SPHCUT_TEST_H

#include "atom.h"
#include "force.h"
#include "input.h"
#include "lammps.h"
#include "library.h"
#include "modify.h"
#include "fix.h"
#include "variable.h"
#include "exceptions.h"

#include "sphcut_compat.h"    // sphcut::fix_by_id(), compute_by_id(): Modify's lists in every LAMMPS version

#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <string>
#include <vector>

namespace sphcut_test {

// a number as an input's text, every digit of the double kept
inline std::string num(double x)
{
  char buf[40];
  snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

// this process's rank in MPI_COMM_WORLD
inline int rank()
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  return me;
}

// command-line switches of every instance: none, or (a test program compiled with
// SPHCUT_TEST_KOKKOS) the /kk styles on the Kokkos OpenMP backend
inline std::vector<std::string> default_switches()
{
#ifdef SPHCUT_TEST_KOKKOS
  return {"-k", "on", "t", "2", "-sf", "kk"};
#else
  return {};
#endif
}

// the plugin the tests load: the one built with them, or $SPHCUT_TEST_PLUGIN (e.g. an older
// build, to check that a new test fails without the fix it guards)
inline std::string plugin_path()
{
  const char *env = getenv("SPHCUT_TEST_PLUGIN");
  return env && *env ? env : SPHCUT_PLUGIN_PATH;
}

// one LAMMPS instance with the sphcut plugin loaded; output silenced unless SPHCUT_TEST_VERBOSE
class Lammps {
 public:
  explicit Lammps(MPI_Comm comm = MPI_COMM_WORLD, std::vector<std::string> extra = default_switches())
  {
    std::vector<std::string> args = {"sphcut_test", "-log", "none", "-nocite"};
    if (!getenv("SPHCUT_TEST_VERBOSE")) { args.push_back("-screen"); args.push_back("none"); }
    for (auto &e : extra) args.push_back(e);
    std::vector<char *> argv;
    for (auto &a : args) argv.push_back(const_cast<char *>(a.c_str()));
    lmp = new LAMMPS_NS::LAMMPS((int) argv.size(), argv.data(), comm);
    cmd(std::string("plugin load ") + plugin_path());
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

// closed box [lo, hi] as 12 triangles with outward normals (right-hand rule), for STL tools
inline std::vector<double> box_triangles(const double *lo, const double *hi)
{
  double v[8][3];
  for (int k = 0; k < 8; k++) {
    v[k][0] = (k == 1 || k == 2 || k == 5 || k == 6) ? hi[0] : lo[0];
    v[k][1] = (k == 2 || k == 3 || k == 6 || k == 7) ? hi[1] : lo[1];
    v[k][2] = k >= 4 ? hi[2] : lo[2];
  }
  // quads counter-clockwise seen from outside: -z, +z, -y, +y, +x, -x
  const int quad[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<double> tri;
  for (auto &q : quad)
    for (int t = 0; t < 2; t++) {
      const int c[3] = {q[0], q[1 + t], q[2 + t]};
      for (int k : c)
        for (int a = 0; a < 3; a++) tri.push_back(v[k][a]);
    }
  return tri;
}

// closed prism for STL tools: polygon (x, y) counter-clockwise, extruded over z in [z0, z1]; end caps
// fanned from the polygon's first vertex
inline std::vector<double> prism(const std::vector<double> &poly, double z0, double z1)
{
  const int n = (int) poly.size() / 2;
  std::vector<double> tri;
  auto put = [&](double x, double y, double z) { tri.insert(tri.end(), {x, y, z}); };
  for (int k = 1; k + 1 < n; k++) {
    put(poly[0], poly[1], z1), put(poly[2 * k], poly[2 * k + 1], z1), put(poly[2 * k + 2], poly[2 * k + 3], z1);
    put(poly[0], poly[1], z0), put(poly[2 * k + 2], poly[2 * k + 3], z0), put(poly[2 * k], poly[2 * k + 1], z0);
  }
  for (int k = 0; k < n; k++) {
    const double *a = &poly[2 * k], *b = &poly[2 * ((k + 1) % n)];
    put(a[0], a[1], z0), put(b[0], b[1], z0), put(b[0], b[1], z1);
    put(a[0], a[1], z0), put(b[0], b[1], z1), put(a[0], a[1], z1);
  }
  return tri;
}

}    // namespace sphcut_test

#endif
