/* sphcut unit tests: the plastic collision of two Johnson-Cook blocks (2D or 3D) used by the
   invariance tests (newton, ranks, restart) and the CPU vs Kokkos comparison, and the per-atom
   snapshot (gathered by atom ID) they compare */

#ifndef SPHCUT_COLLISION_H
#define SPHCUT_COLLISION_H

#include "sphcut_test.h"

#include "fix_sph_jc_thermal.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace sphcut_test {

// two Johnson-Cook blocks colliding at 2 x 150 m/s: plastic flow, heating, adaptive dt.
// 2D: 316 particles; 3D: 2 x 6^3 + ... (a few hundred), spacing 0.2 mm
inline std::vector<std::string> collision(const std::string &newton, int dim = 2)
{
  std::vector<std::string> c = {"units si", "dimension " + std::to_string(dim),
                                dim == 2 ? "boundary f f p" : "boundary f f f", "newton " + newton,
                                "atom_style atomic", "atom_modify map array"};
  if (dim == 2) {
    c.insert(c.end(), {"lattice sq 2e-4", "region box block -30 30 -20 20 -0.5 0.5", "create_box 2 box",
                       "region left block -16.01 -0.51 -6.01 6.01 -0.5 0.5",
                       "region right block 0.49 12.01 -4.01 4.01 -0.5 0.5", "create_atoms 1 region left",
                       "create_atoms 2 region right", "mass * $(7800*2e-4*2e-4)"});
  } else {
    c.insert(c.end(), {"lattice sc 2e-4", "region box block -20 20 -12 12 -12 12", "create_box 2 box",
                       "region left block -8.01 -0.51 -3.01 3.01 -3.01 3.01",
                       "region right block 0.49 6.01 -2.01 2.01 -2.01 2.01", "create_atoms 1 region left",
                       "create_atoms 2 region right", "mass * $(7800*2e-4*2e-4*2e-4)"});
  }
  c.insert(c.end(), {"group left type 1", "group right type 2", "velocity left set 150 10 0 units box",
                     "velocity right set -150 0 0 units box", "pair_style sph/jc-thermal",
                     "pair_coeff * * rho0 7800 E 200e9 nu 0.3 hdx 1.3 A 350e6 B 275e6 n 0.36 C 0.022 m 1.0 "
                     "Tref 300 Tmelt 1800 cp 477 chi 0.9",
                     "fix sph all sph/jc-thermal cfl 0.3", "timestep 1e-9", "thermo 0"});
  return c;
}

struct Snapshot {
  std::vector<double> x, state;
  double size = 1.0;    // body size, the scale of position differences
};

inline Snapshot take(Lammps &l, const char *fixid = "sph")
{
  using F = LAMMPS_NS::FixSPHJCThermal;
  auto *atom = l.lmp->atom;
  Snapshot s;
  // by atom ID (IDs need not be contiguous: atoms may have been deleted)
  LAMMPS_NS::tagint mymax = 0, maxtag = 0;
  for (int i = 0; i < atom->nlocal; i++) mymax = std::max(mymax, atom->tag[i]);
  MPI_Allreduce(&mymax, &maxtag, 1, MPI_LMP_TAGINT, MPI_MAX, l.lmp->world);
  const int ncol = F::NOUT;    // state columns RHO .. DTEMP
  std::vector<double> x((size_t) 3 * maxtag, 0.0), st((size_t) maxtag * ncol, 0.0);
  auto *fix = static_cast<F *>(sphcut::fix_by_id(l.lmp->modify, fixid));
  for (int i = 0; i < atom->nlocal; i++) {
    const size_t t = atom->tag[i] - 1;
    for (int a = 0; a < 3; a++) x[3 * t + a] = atom->x[i][a];
    for (int k = 0; k < ncol; k++) st[t * ncol + k] = fix->state[i][k];
  }
  s.x.resize(x.size());
  s.state.resize(st.size());
  MPI_Allreduce(x.data(), s.x.data(), (int) x.size(), MPI_DOUBLE, MPI_SUM, l.lmp->world);
  MPI_Allreduce(st.data(), s.state.data(), (int) st.size(), MPI_DOUBLE, MPI_SUM, l.lmp->world);
  double lo = 1e300, hi = -1e300;
  for (size_t k = 0; k < s.x.size(); k += 3) {
    lo = std::min(lo, s.x[k]);
    hi = std::max(hi, s.x[k]);
  }
  s.size = hi - lo;
  return s;
}

// max position difference relative to the body size, and max state difference relative to each
// column's largest magnitude (density, stress, plastic strain, temperature, internal energy)
inline void expect_same(const Snapshot &a, const Snapshot &b, const char *what, double tol = 1e-10)
{
  using F = LAMMPS_NS::FixSPHJCThermal;
  ASSERT_EQ(a.x.size(), b.x.size());
  double dx = 0.0;
  for (size_t k = 0; k < a.x.size(); k++) dx = std::max(dx, fabs(a.x[k] - b.x[k]));
  const int ncol = F::NOUT;
  double ds = 0.0;
  for (int c : {F::RHO, F::SXX, F::SYY, F::SZZ, F::SXY, F::SXZ, F::SYZ, F::EPS, F::TEMP, F::UINT}) {
    double scale = 0.0, diff = 0.0;
    for (size_t i = 0; i < a.state.size() / ncol; i++) {
      scale = std::max(scale, fabs(a.state[i * ncol + c]));
      diff = std::max(diff, fabs(a.state[i * ncol + c] - b.state[i * ncol + c]));
    }
    if (scale > 0.0) ds = std::max(ds, diff / scale);
  }
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0) std::printf("[ %-8s ] max |dx|/size %.3e, max state difference %.3e\n", what, dx / a.size, ds);
  EXPECT_LT(dx / a.size, tol) << what;
  EXPECT_LT(ds, tol) << what;
}

}    // namespace sphcut_test

#endif
