// bench/thermal: the operator of the conservative exchange of fix heat/fmfs on frozen particles
// read from a file ("x y type" per line, e.g. from write_dump of a cutting restart), with the
// materials of examples/cutting-2d-ti6al4v (1: Ti6Al4V k 7.3, 2: tool k 88), V = dx^2, cubic
// kernel, surface threshold 0.75 (tool yes).  Prints the pair statistics over all particles
// and writes S (in units of the workpiece's k/(rho cp h^2)) for the particles in the window.
//   g++ -O2 -std=c++17 -Isrc bench/thermal/fmfs_chip.cpp -o fmfs_chip
//   ./fmfs_chip file dx hdx mode xlo xhi ylo yhi out.bin     (mode as fmfs_lattice)
//   python3 bench/thermal/operator_eig.py out.bin 1
#include "sphcut_thermal.h"
#include <cstdio>
#include <cstdlib>
#include <vector>
#include <algorithm>
#include <cmath>
using namespace sphcut;
constexpr int DIM = 2;

// the cell-list neighbours of particle i, the view sphcut::heat_scheme reads
struct CellNeighbours {
  static constexpr bool TWO_WALKS = false;
  const std::vector<int> &nb;
  const std::vector<double> &x;
  const std::vector<int> &ty;
  const ThermalPair (&tp)[3][3];
  int i;
  double V;
  int size() const { return (int) nb.size(); }
  bool pair(int k, HeatPair &p) const
  {
    double r2;
    p.j = nb[k];
    p.tp = &tp[ty[i]][ty[p.j]];
    return thermal_support(*p.tp, KERNEL_CUBIC, &x[3 * i], &x[3 * p.j], p.dx, r2, p.wfac, p.ir2);
  }
  double volume(int) const { return V; }
};

int main(int argc, char **argv)
{
  FILE *f = fopen(argv[1], "r");
  const double dx = atof(argv[2]), hdx = atof(argv[3]);
  const int mode = atoi(argv[4]);
  const double wx0 = atof(argv[5]), wx1 = atof(argv[6]), wy0 = atof(argv[7]), wy1 = atof(argv[8]);
  std::vector<double> x;
  std::vector<int> ty;
  double a, b;
  int t;
  while (fscanf(f, "%lf %lf %d", &a, &b, &t) == 3) { x.push_back(a); x.push_back(b); x.push_back(0.0); ty.push_back(t); }
  const int N = ty.size();
  const double kap[3] = {0, 7.3, 88}, rcp[3] = {0, 4430 * 580.0, 14500 * 292.0};
  const double h = hdx * dx, V = dx * dx;
  ThermalPair tp[3][3];
  for (int i = 1; i < 3; i++)
    for (int j = 1; j < 3; j++) tp[i][j] = thermal_pair(KERNEL_CUBIC, DIM, h, kap[i], kap[j]);
  // cell list
  const double cs = support_radius(h);
  double xmin = 1e300, ymin = 1e300, xmax = -1e300, ymax = -1e300;
  for (int i = 0; i < N; i++) { xmin = std::min(xmin, x[3*i]); xmax = std::max(xmax, x[3*i]); ymin = std::min(ymin, x[3*i+1]); ymax = std::max(ymax, x[3*i+1]); }
  const int ncx = int((xmax - xmin) / cs) + 1, ncy = int((ymax - ymin) / cs) + 1;
  std::vector<std::vector<int>> cell(ncx * ncy);
  auto cid = [&](int i, int &cx, int &cy) { cx = int((x[3*i] - xmin) / cs); cy = int((x[3*i+1] - ymin) / cs); };
  for (int i = 0; i < N; i++) { int cx, cy; cid(i, cx, cy); cell[cx + ncx * cy].push_back(i); }
  std::vector<std::vector<int>> nb(N);
  for (int i = 0; i < N; i++) {
    int cx, cy; cid(i, cx, cy);
    for (int ox = -1; ox <= 1; ox++) for (int oy = -1; oy <= 1; oy++) {
      const int X = cx + ox, Y = cy + oy;
      if (X < 0 || Y < 0 || X >= ncx || Y >= ncy) continue;
      for (int j : cell[X + ncx * Y]) if (j != i) nb[i].push_back(j);
    }
  }
  const int NW = DIM * DIM + DIM;
  std::vector<double> wts(N * NW, 0.0);
  std::vector<int> fm(N, 0);
  int nf = 0, ns = 0;
  for (int i = 0; i < N; i++) {
    HeatSurface sv;
    const int s = heat_scheme<DIM>(CellNeighbours{nb[i], x, ty, tp, i, V}, 1, 1, 1, 0.75, 0.75, sv, &wts[i * NW]);
    if (sv.flag > 0.0) ns++;
    if (s == HEAT_FMFS) { fm[i] = 1; nf++; }
  }
  std::vector<int> win;
  std::vector<int> wix(N, -1);
  for (int i = 0; i < N; i++)
    if (x[3*i] >= wx0 && x[3*i] <= wx1 && x[3*i+1] >= wy0 && x[3*i+1] <= wy1) { wix[i] = win.size(); win.push_back(i); }
  const int M = win.size();
  std::vector<double> A((size_t) M * M, 0.0), diag(M, 0.0);
  long npair = 0, nneg = 0, nff = 0, nnegff = 0, nnegt[3] = {0,0,0};
  double minratio = 1e300, negsum = 0.0, possum = 0.0;
  double rowmax = 0.0;  // max_i sum_j |c_ij| V / (rho cp) * h^2 rho cp / k (normalized with the workpiece)
  const double rate1 = kap[1] / (rcp[1] * h * h);
  for (int i = 0; i < N; i++) {
    double rows = 0.0;
    for (int j : nb[i]) {
      double d[3], r2, wfac, ir2;
      const ThermalPair &T = tp[ty[i]][ty[j]];
      if (!thermal_support(T, KERNEL_CUBIC, &x[3 * i], &x[3 * j], d, r2, wfac, ir2)) continue;
      double ai, aj;
      exchange_sides<DIM>(T, d, ir2, fm[i], &wts[i * NW], kap[ty[i]], fm[j], &wts[j * NW], kap[ty[j]], ai, aj);
      double c = wfac * conductance_mean(ai, aj);
      const double cb = wfac * T.brook;
      if (i < j) {
        npair++;
        if (fm[i] && fm[j]) nff++;
        if (c < 0.0) { nneg++; nnegt[ty[i]]++; if (fm[i] && fm[j]) nnegff++; negsum += c; } else possum += c;
        if (cb > 0 && c / cb < minratio) minratio = c / cb;
      }
      if (mode == 1) c = wfac * conductance_pair(ai, aj, T.brook);
      if (mode == 2 && c < 0.0) c = 0.0;
      if (mode == 3) c = cb;
      rows += fabs(c) * V / rcp[ty[i]];
      if (wix[i] >= 0 && wix[j] >= 0) {
        A[(size_t) wix[i] * M + wix[j]] = V * V * c;
        diag[wix[i]] -= V * V * c;
      }
    }
    rowmax = std::max(rowmax, 2 * rows / rate1);
  }
  // symmetric S = M^-1/2 A M^-1/2, M = rho cp V; in units of the workpiece rate k/(rho cp h^2)
  for (int i = 0; i < M; i++) A[(size_t) i * M + i] = diag[i];
  for (int i = 0; i < M; i++)
    for (int j = 0; j < M; j++) A[(size_t) i * M + j] /= sqrt(rcp[ty[win[i]]] * V * rcp[ty[win[j]]] * V) * rate1;
  FILE *o = fopen(argv[9], "wb");
  fwrite(&M, sizeof(int), 1, o);
  fwrite(A.data(), sizeof(double), A.size(), o);
  for (int i : win) fwrite(&x[3 * i], sizeof(double), 3, o);
  fclose(o);
  printf("N %d fmfs %d surface %d pairs %ld ff %ld neg %ld (%.3f%%; type1 %ld type2 %ld) negff %ld minratio %.3f negsum/possum %.3e; Gershgorin 2 max rowsum (units k1/(rho cp h^2)_1) %.2f; window %d\n", N, nf, ns, npair, nff, nneg, 100.0 * nneg / npair, nnegt[1], nnegt[2], nnegff, minratio, negsum / possum, rowmax, M);
}
