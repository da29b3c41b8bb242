// A Kokkos Tools library (KOKKOS_PROFILE_LIBRARY) that times every kernel and deep copy of a
// CUDA run on its own: the device is synchronised before and after each one, so a kernel's
// time is its launch plus its execution, without overlap.  At the end it prints one row per
// kernel name (calls, total, mean) to the file KP_TIMER_OUT (default stderr), largest first.
// KP_TIMER_SYNC=0 counts the calls only (no synchronisation: the run's timing is undisturbed).
// Build (device machine):  g++ -O2 -shared -fPIC -o libkp_timer.so kp_timer.cpp
//                            -I$CUDA/include -L$CUDA/lib64 -lcudart
// Use:  KOKKOS_PROFILE_LIBRARY=$PWD/libkp_timer.so lmp -k on g 1 -sf kk ...
#include <cuda_runtime_api.h>
#include <cxxabi.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace {
struct Stat {
  long calls = 0;
  double seconds = 0.0;
};
struct Open {
  std::string name;
  double t0;
};
std::map<std::string, Stat> stats;
std::vector<Open> open_kernels;
bool sync = true;
double t_init = 0.0;
Open copy_open;

double now()
{
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

void device_sync()
{
  if (sync) cudaDeviceSynchronize();
}

std::string pretty(const char *name, const char *kind)
{
  int status = 0;
  char *d = abi::__cxa_demangle(name, nullptr, nullptr, &status);
  std::string s = status == 0 && d ? d : name;
  free(d);
  // lambdas are named after their enclosing function: keep the function, drop the templates
  std::string out;
  int depth = 0;
  for (char c : s) {
    if (c == '<') depth++;
    if (depth == 0) out += c;
    if (c == '>' && depth > 0) depth--;
  }
  if (out.size() > 110) out = out.substr(0, 110);
  return std::string(kind) + " " + out;
}

void begin(const char *name, const char *kind, uint64_t *kid)
{
  device_sync();
  open_kernels.push_back({pretty(name, kind), now()});
  *kid = open_kernels.size() - 1;
}

void end(uint64_t)
{
  device_sync();
  Open o = open_kernels.back();
  open_kernels.pop_back();
  Stat &s = stats[o.name];
  s.calls++;
  s.seconds += now() - o.t0;
}
}    // namespace

extern "C" {
struct SpaceHandle {
  char name[64];
};

void kokkosp_init_library(const int, const uint64_t, const uint32_t, void *)
{
  const char *e = getenv("KP_TIMER_SYNC");
  sync = !(e && strcmp(e, "0") == 0);
  t_init = now();
}

void kokkosp_begin_parallel_for(const char *n, uint32_t, uint64_t *k) { begin(n, "for", k); }
void kokkosp_begin_parallel_reduce(const char *n, uint32_t, uint64_t *k) { begin(n, "reduce", k); }
void kokkosp_begin_parallel_scan(const char *n, uint32_t, uint64_t *k) { begin(n, "scan", k); }
void kokkosp_end_parallel_for(uint64_t k) { end(k); }
void kokkosp_end_parallel_reduce(uint64_t k) { end(k); }
void kokkosp_end_parallel_scan(uint64_t k) { end(k); }

void kokkosp_begin_deep_copy(SpaceHandle dst, const char *dname, const void *, SpaceHandle src,
                             const char *sname, const void *, uint64_t size)
{
  device_sync();
  char buf[200];
  snprintf(buf, sizeof(buf), "copy %s <- %s %s%s", dst.name, src.name, dname, size > 0 ? "" : " (empty)");
  copy_open = {buf, now()};
}

void kokkosp_end_deep_copy()
{
  device_sync();
  Stat &s = stats[copy_open.name];
  s.calls++;
  s.seconds += now() - copy_open.t0;
}

void kokkosp_finalize_library()
{
  std::vector<std::pair<std::string, Stat>> rows(stats.begin(), stats.end());
  std::sort(rows.begin(), rows.end(), [](auto &a, auto &b) { return a.second.seconds > b.second.seconds; });
  const char *path = getenv("KP_TIMER_OUT");
  FILE *f = path ? fopen(path, "w") : stderr;
  if (!f) f = stderr;
  double total = 0.0;
  long calls = 0;
  for (auto &r : rows) {
    total += r.second.seconds;
    calls += r.second.calls;
  }
  fprintf(f, "# kp_timer: %s, %ld calls, %.3f s in kernels and copies, %.3f s since init\n",
          sync ? "synchronised" : "counting only", calls, total, now() - t_init);
  fprintf(f, "# %10s %12s %10s  name\n", "calls", "total_s", "mean_us");
  for (auto &r : rows)
    fprintf(f, "  %10ld %12.4f %10.2f  %s\n", r.second.calls, r.second.seconds,
            r.second.calls ? 1e6 * r.second.seconds / r.second.calls : 0.0, r.first.c_str());
  if (f != stderr) fclose(f);
}
}
