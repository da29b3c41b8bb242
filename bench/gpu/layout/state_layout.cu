// The state row's layout against the integrator's access (bench/gpu/cutting.sh layout): a kernel
// with the first-half kernel's access pattern of fix sph/jc-thermal/kk (per particle: x, v, f;
// 30 of the 63 state columns read, 28 written; a 24-double packed row for the pair written) over
// N particles, its state rows stored
//   aos63   one 504-byte row a particle (the fix's layout), one thread a particle
//   aos64   rows padded to 512 bytes
//   soa     a column a particle index apart (column-major)
//   aosoa   blocks of 32 particles, a column of the block contiguous
//   staged  the 504-byte rows, each warp's 32 rows loaded into shared memory with coalesced
//           loads, the particle's work on its shared row, the rows stored back coalesced
// Prints ms a call (the mean of REPS after a warm-up) and the bytes a particle touches over
// that time.  Run: state_layout N REPS (bench/gpu/cutting.sh layout builds it with
// nvcc -O3 -arch=sm_90 -std=c++17 --extended-lambda)
#include <cstdio>
#include <cstdlib>
#include <cuda_runtime.h>

#define CK(x) do { cudaError_t e = (x); if (e != cudaSuccess) { printf("%s: %s\n", #x, cudaGetErrorString(e)); exit(1); } } while (0)

constexpr int NC = 63;      // state columns
constexpr int NP = 24;      // packed row
struct Aos { int st; __device__ size_t operator()(int i, int c) const { return (size_t) i * st + c; } };
struct Soa { int n; __device__ size_t operator()(int i, int c) const { return (size_t) c * n + i; } };
struct Aosoa { __device__ size_t operator()(int i, int c) const { return ((size_t) (i >> 5) * NC + c) * 32 + (i & 31); } };

// the per-particle work on a row reached through idx (columns as in sphcut_state.h)
template <class S>
__device__ inline void work(S s, const double *xi, double *vi, const double *fi, double dt, double *pk)
{
  for (int k = 0; k < 9; k++) s(35 + k) = s(26 + k);                 // old rates = rates
  double q = 0.0;
  for (int d = 0; d < 3; d++) {
    s(22 + d) = vi[d] + dt * fi[d];                                   // VEST
    vi[d] += 0.5 * dt * fi[d] + 1e-3 * s(44 + d);                     // XSPH read
  }
  s(15) = s(0) + dt * s(35);                                          // RHO_F
  for (int k = 0; k < 6; k++) { s(16 + k) = s(2 + k) + dt * s(36 + k); q += s(16 + k) * s(16 + k); }
  s(21) = s(11) + dt * s(42) + 1e-9 * (s(9) + s(10));                 // TEMP_F (EPS, EPSDOT read)
  q = sqrt(q);
  if (q > 1e300) for (int k = 0; k < 6; k++) s(16 + k) *= 0.5;
  for (int k = 0; k < 9; k++) s(26 + k) = 0.0;                        // rates zeroed
  // the packed row, from what was just written
  for (int d = 0; d < 3; d++) { pk[d] = xi[d]; pk[3 + d] = s(22 + d); }
  pk[6] = s(15); pk[7] = 1.0 / s(15);
  for (int k = 0; k < 6; k++) pk[8 + k] = s(16 + k) / (s(15) * s(15));
  for (int k = 14; k < NP; k++) pk[k] = s(21) * k;
}

template <class I>
__global__ void plain(int n, I idx, double *st, double *x, double *v, double *f, double *pk, double dt)
{
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  double xi[3], vi[3], fi[3];
  for (int d = 0; d < 3; d++) { xi[d] = x[3 * i + d]; vi[d] = v[3 * i + d]; fi[d] = f[3 * i + d]; }
  for (int d = 0; d < 3; d++) xi[d] += dt * vi[d];
  work([&](int c) -> double & { return st[idx(i, c)]; }, xi, vi, fi, dt, pk + (size_t) NP * i);
  for (int d = 0; d < 3; d++) { x[3 * i + d] = xi[d]; v[3 * i + d] = vi[d]; f[3 * i + d] = 0.0; }
}

// blocks of 128 threads: 4 warps, each stages its 32 rows (32 x 63 doubles, 16 KB)
__global__ void staged(int n, double *st, double *x, double *v, double *f, double *pk, double dt)
{
  extern __shared__ double sh[];
  const int lane = threadIdx.x & 31, w = threadIdx.x >> 5;
  double *rows = sh + w * 32 * NC;
  const int i0 = (blockIdx.x * blockDim.x) + w * 32;
  const int cnt = min(32, n - i0);
  if (cnt <= 0) return;
  const double *g = st + (size_t) i0 * NC;
  for (int k = lane; k < cnt * NC; k += 32) rows[k] = g[k];
  __syncwarp();
  const int i = i0 + lane;
  if (lane < cnt) {
    double xi[3], vi[3], fi[3];
    for (int d = 0; d < 3; d++) { xi[d] = x[3 * i + d]; vi[d] = v[3 * i + d]; fi[d] = f[3 * i + d]; }
    for (int d = 0; d < 3; d++) xi[d] += dt * vi[d];
    double *r = rows + lane * NC;
    work([&](int c) -> double & { return r[c]; }, xi, vi, fi, dt, pk + (size_t) NP * i);
    for (int d = 0; d < 3; d++) { x[3 * i + d] = xi[d]; v[3 * i + d] = vi[d]; f[3 * i + d] = 0.0; }
  }
  __syncwarp();
  double *gw = st + (size_t) i0 * NC;
  for (int k = lane; k < cnt * NC; k += 32) gw[k] = rows[k];
}

int main(int argc, char **argv)
{
  const int n = argc > 1 ? atoi(argv[1]) : 4239104;
  const int reps = argc > 2 ? atoi(argv[2]) : 20;
  double *st, *x, *v, *f, *pk;
  const size_t nst = (size_t) (n + 32) * 64;
  CK(cudaMalloc(&st, nst * 8)); CK(cudaMalloc(&x, (size_t) 3 * n * 8)); CK(cudaMalloc(&v, (size_t) 3 * n * 8));
  CK(cudaMalloc(&f, (size_t) 3 * n * 8)); CK(cudaMalloc(&pk, (size_t) NP * n * 8));
  CK(cudaMemset(st, 0, nst * 8)); CK(cudaMemset(x, 0, (size_t) 3 * n * 8)); CK(cudaMemset(v, 0, (size_t) 3 * n * 8));
  CK(cudaMemset(f, 0, (size_t) 3 * n * 8));
  cudaEvent_t a, b; CK(cudaEventCreate(&a)); CK(cudaEventCreate(&b));
  const double bytes = 8.0 * (9 + 9 + 30 + 28 + NP);    // x v f read, x v f written, columns, packed row
  auto run = [&](const char *name, auto launch) {
    launch(); CK(cudaDeviceSynchronize());
    CK(cudaEventRecord(a));
    for (int r = 0; r < reps; r++) launch();
    CK(cudaEventRecord(b)); CK(cudaEventSynchronize(b)); CK(cudaGetLastError());
    float ms; CK(cudaEventElapsedTime(&ms, a, b)); ms /= reps;
    printf("%-7s n %d: %.3f ms a call, %.2f TB/s of the %g bytes a particle touches\n", name, n, ms,
           bytes * n / (ms * 1e-3) / 1e12, bytes);
  };
  const int B = 128, G = (n + B - 1) / B;
  const double dt = 1e-9;
  run("aos63", [&] { plain<<<G, B>>>(n, Aos{63}, st, x, v, f, pk, dt); });
  run("aos64", [&] { plain<<<G, B>>>(n, Aos{64}, st, x, v, f, pk, dt); });
  run("soa", [&] { plain<<<G, B>>>(n, Soa{n}, st, x, v, f, pk, dt); });
  run("aosoa", [&] { plain<<<G, B>>>(n, Aosoa{}, st, x, v, f, pk, dt); });
  CK(cudaFuncSetAttribute(staged, cudaFuncAttributeMaxDynamicSharedMemorySize, 4 * 32 * NC * 8));
  run("staged", [&] { staged<<<G, B, 4 * 32 * NC * 8>>>(n, st, x, v, f, pk, dt); });
  return 0;
}
