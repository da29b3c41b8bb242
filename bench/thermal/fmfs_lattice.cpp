// bench/thermal: the operator of the conservative exchange of fix heat/fmfs on a frozen lattice
// (sphcut_thermal.h heat_scheme and exchange_sides, as fix heat/fmfs calls them: one material,
// k = rho cp = 1, dx = 1, insulated, surface compute threshold 0.75, fmfs_lambda 0.75, cubic
// kernel).  Prints the pair statistics (negative conductances c_ij, c_ij over Brookshaw's) and
// writes the symmetric operator S (dT/dt = S T) for operator_eig.py.
//   g++ -O2 -std=c++17 -Isrc bench/thermal/fmfs_lattice.cpp -o fmfs_lattice
//   ./fmfs_lattice dim n hdx jitter seed pairdist mode out.bin
//   python3 bench/thermal/operator_eig.py out.bin hdx
// n particles per side; jitter: each component displaced by jitter U(-1,1) (mt19937_64, 53 bits:
// the sequence of test_thermal Insulated.JitteredLatticeBounded); AFF="a b c d": 2D affine map of
// the lattice first; pairdist > 0: one extra particle at that distance from the central one;
// mode 0: the conductance_mean of the pair (before the fallback), 1: conductance_pair (now),
// 2: negative c_ij clipped at 0, 3: Brookshaw everywhere.  VERB=1 lists the negative pairs.
#include "sphcut_thermal.h"
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>
using namespace sphcut;

// every other particle of the set as the neighbours of particle i (O(N^2): a few hundred
// particles), the view sphcut::heat_scheme reads
struct AllPairs {
  static constexpr bool TWO_WALKS = false;
  const std::vector<double> &x;
  const ThermalPair &tp;
  int i;
  double V;
  int size() const { return (int) x.size() / 3; }
  bool pair(int k, HeatPair &p) const
  {
    double r2;
    p.j = k;
    p.tp = &tp;
    return thermal_support(tp, KERNEL_CUBIC, &x[3 * i], &x[3 * k], p.dx, r2, p.wfac, p.ir2);
  }
  double volume(int) const { return V; }
};

template <int DIM> int run(int n, double hdx, double jit, unsigned seed, double pd, int mode, const char *out)
{
  std::vector<double> x;
  std::mt19937_64 rng(seed);
  auto U = [](std::mt19937_64 &g) { return 2.0 * ((g() >> 11) * 0x1.0p-53) - 1.0; };
  const int nz = DIM == 3 ? n : 1;
  for (int k = 0; k < nz; k++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++) {
        double p[3] = {double(i), double(j), double(k)};
        if (getenv("AFF")) {    // 2D affine map x' = F x (row-major a b c d)
          double F[4];
          sscanf(getenv("AFF"), "%lf %lf %lf %lf", F, F + 1, F + 2, F + 3);
          const double px = F[0] * p[0] + F[1] * p[1], py = F[2] * p[0] + F[3] * p[1];
          p[0] = px;
          p[1] = py;
        }
        for (int a = 0; a < DIM; a++) p[a] += jit * U(rng);
        x.insert(x.end(), p, p + 3);
      }
  if (pd > 0.0) {
    const int c = (n / 2) + n * (n / 2) + (DIM == 3 ? n * n * (n / 2) : 0);
    double p[3] = {x[3 * c] + pd * 0.8, x[3 * c + 1] + pd * 0.6, x[3 * c + 2]};
    x.insert(x.end(), p, p + 3);
  }
  const int N = x.size() / 3;
  const double h = hdx, V = 1.0, kappa = 1.0, rhocp = 1.0;    // dx = 1: V = dx^DIM = 1
  ThermalPair tp = thermal_pair(KERNEL_CUBIC, DIM, h, kappa, kappa);
  std::vector<double> wts(N * (DIM * DIM + DIM), 0.0);
  std::vector<int> fm(N, 0), surf(N, 0);
  std::vector<double> lamv(N, 0.0);
  int nf = 0, ns = 0;
  for (int i = 0; i < N; i++) {
    HeatSurface sv;
    const int s = heat_scheme<DIM>(AllPairs{x, tp, i, V}, 1, 1, 1, 0.75, 0.75, sv, &wts[i * (DIM * DIM + DIM)]);
    lamv[i] = sv.lambda;
    if (sv.flag > 0.0) { surf[i] = 1; ns++; }
    if (s == HEAT_FMFS) { fm[i] = 1; nf++; }
  }
  std::vector<double> A((size_t) N * N, 0.0);
  long npair = 0, nneg = 0, nff = 0, nnegff = 0;
  double maxratio = -1e300, minratio = 1e300, negsum = 0.0, possum = 0.0;
  for (int i = 0; i < N; i++)
    for (int j = i + 1; j < N; j++) {
      double dx[3], r2, wfac, ir2;
      if (!thermal_support(tp, KERNEL_CUBIC, &x[3 * i], &x[3 * j], dx, r2, wfac, ir2)) continue;
      double ai, aj;
      exchange_sides<DIM>(tp, dx, ir2, fm[i], &wts[i * (DIM * DIM + DIM)], kappa, fm[j], &wts[j * (DIM * DIM + DIM)],
                          kappa, ai, aj);
      double c = wfac * conductance_mean(ai, aj);
      const double cb = wfac * tp.brook;
      npair++;
      if (fm[i] && fm[j]) nff++;
      if (cb > 0.0) {
        if (c < 0.0 && getenv("VERB")) printf("neg pair %d %d lam %.3f %.3f fm %d %d r %.3f ratio %.3f  ai/b %.3f aj/b %.3f\n", i, j, lamv[i], lamv[j], fm[i], fm[j], sqrt(r2), c / cb, ai / tp.brook, aj / tp.brook);
        if (c < 0.0) { nneg++; if (fm[i] && fm[j]) nnegff++; negsum += c; }
        else possum += c;
        if (c / cb < minratio) minratio = c / cb;
        if (c / cb > maxratio) maxratio = c / cb;
      }
      if (mode == 1) c = wfac * conductance_pair(ai, aj, tp.brook);
      if (mode == 2 && c < 0.0) c = 0.0;
      if (mode == 3) c = cb;
      A[(size_t) i * N + j] = A[(size_t) j * N + i] = V * V * c;
    }
  for (int i = 0; i < N; i++) {
    double s = 0.0;
    for (int j = 0; j < N; j++) s += A[(size_t) i * N + j];
    A[(size_t) i * N + i] = -s;
  }
  // dT/dt = M^-1 A T, M = rho cp V: symmetric S = A / (rho cp V)
  for (auto &a : A) a /= rhocp * V;
  FILE *f = fopen(out, "wb");
  fwrite(&N, sizeof(int), 1, f);
  fwrite(A.data(), sizeof(double), A.size(), f);
  fwrite(x.data(), sizeof(double), x.size(), f);
  fclose(f);
  printf("N %d fmfs %d surface %d pairs %ld ff %ld neg %ld (%.2f%%) negff %ld minratio %.3f negsum/possum %.3e maxratio %.3f\n", N,
         nf, ns, npair, nff, nneg, 100.0 * nneg / npair, nnegff, minratio, negsum / possum, maxratio);
  return 0;
}

int main(int argc, char **argv)
{
  const int dim = atoi(argv[1]), n = atoi(argv[2]);
  const double hdx = atof(argv[3]), jit = atof(argv[4]);
  const unsigned seed = atoi(argv[5]);
  const double pd = atof(argv[6]);
  const int mode = atoi(argv[7]);
  return dim == 2 ? run<2>(n, hdx, jit, seed, pd, mode, argv[8]) : run<3>(n, hdx, jit, seed, pd, mode, argv[8]);
}
