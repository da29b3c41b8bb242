// A Kokkos Tools library (KOKKOS_PROFILE_LIBRARY) that times every kernel and deep copy of a
// CUDA run on its own: the device is synchronised before and after each one, so a kernel's
// time is its launch plus its execution, without overlap.  At the end it prints one row per
// kernel name (calls, total, mean) to the file KP_TIMER_OUT (default stderr), largest first.
// KP_TIMER_SYNC=0 counts the calls only (no synchronisation: the run's timing is undisturbed).
// KP_TIMER_SYNC=events: no synchronisation either; a CUDA event is recorded on the default stream
// before and after each kernel and copy (calls KP_TIMER_SKIP to KP_TIMER_SKIP + KP_TIMER_CALLS,
// defaults 3000 and 30000), and at the end the device's own clock gives each kernel's execution
// time and the time the device sat idle before it (waiting for the host to launch it): the
// timeline of the run without a profiler.  Rows: calls, device time, mean; then the idle time.
// Build (device machine):  g++ -O2 -shared -fPIC -o libkp_timer.so kp_timer.cpp
//                            -I$CUDA/include -L$CUDA/lib64 -lcudart
// Use:  KOKKOS_PROFILE_LIBRARY=$PWD/libkp_timer.so lmp -k on g 1 -sf kk ...
// Launch counts without a GPU (the OpenMP build, -k on t N): the same build against the CUDA
// toolkit's headers and libcudart, run with KP_TIMER_SYNC=0 (that mode makes no CUDA call); the
// calls of two runs of N and 2N steps subtract to the launches of N ordinary steps.
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
bool events = false;
long skip_calls = 3000, max_calls = 30000, seen_calls = 0;
struct Mark {
  int name;
  cudaEvent_t a, b;
};
std::vector<Mark> marks;
std::vector<std::string> names;
std::map<std::string, int> name_index;
std::vector<cudaEvent_t> pool;
std::vector<int> open_marks;

cudaEvent_t take_event()
{
  if (pool.empty()) {
    cudaEvent_t e;
    cudaEventCreate(&e);
    return e;
  }
  cudaEvent_t e = pool.back();
  pool.pop_back();
  return e;
}

// events mode: a mark opens before a kernel or copy (-1: outside the window)
int open_mark(const std::string &name)
{
  seen_calls++;
  if (seen_calls <= skip_calls || (long) marks.size() >= max_calls) return -1;
  auto it = name_index.find(name);
  int k;
  if (it == name_index.end()) {
    k = names.size();
    names.push_back(name);
    name_index[name] = k;
  } else
    k = it->second;
  Mark m{k, take_event(), take_event()};
  cudaEventRecord(m.a, 0);
  marks.push_back(m);
  return (int) marks.size() - 1;
}

void close_mark(int m)
{
  if (m >= 0) cudaEventRecord(marks[m].b, 0);
}
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

std::string pretty_uncached(const char *name, const char *kind);

// demangled names cached (events mode keeps the host's time per launch small)
std::string pretty(const char *name, const char *kind)
{
  static std::map<std::pair<std::string, std::string>, std::string> cache;
  auto key = std::make_pair(std::string(name), std::string(kind));
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  return cache[key] = pretty_uncached(name, kind);
}

std::string pretty_uncached(const char *name, const char *kind)
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
  if (events) {
    open_marks.push_back(open_mark(pretty(name, kind)));
    *kid = 0;
    return;
  }
  device_sync();
  open_kernels.push_back({pretty(name, kind), now()});
  *kid = open_kernels.size() - 1;
}

void end(uint64_t)
{
  if (events) {
    close_mark(open_marks.back());
    open_marks.pop_back();
    return;
  }
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
  sync = !(e && (strcmp(e, "0") == 0 || strcmp(e, "events") == 0));
  events = e && strcmp(e, "events") == 0;
  if (const char *v = getenv("KP_TIMER_SKIP")) skip_calls = atol(v);
  if (const char *v = getenv("KP_TIMER_CALLS")) max_calls = atol(v);
  if (events) {
    pool.resize(2 * max_calls);
    for (auto &ev : pool) cudaEventCreate(&ev);
    marks.reserve(max_calls);
  }
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
  char buf[200];
  snprintf(buf, sizeof(buf), "copy %s <- %s %s%s", dst.name, src.name, dname, size > 0 ? "" : " (empty)");
  if (events) {
    open_marks.push_back(open_mark(buf));
    return;
  }
  device_sync();
  copy_open = {buf, now()};
}

void kokkosp_end_deep_copy()
{
  if (events) {
    close_mark(open_marks.back());
    open_marks.pop_back();
    return;
  }
  device_sync();
  Stat &s = stats[copy_open.name];
  s.calls++;
  s.seconds += now() - copy_open.t0;
}

// events mode: device time per name and the device's idle time between the marks
void report_events(FILE *f)
{
  cudaDeviceSynchronize();
  std::vector<double> busy(names.size(), 0.0), idle(names.size(), 0.0);
  std::vector<long> calls(names.size(), 0);
  double total_busy = 0.0, total_idle = 0.0, span = 0.0;
  for (size_t i = 0; i < marks.size(); i++) {
    float ms = 0.0f, gap = 0.0f;
    cudaEventElapsedTime(&ms, marks[i].a, marks[i].b);
    if (i > 0) cudaEventElapsedTime(&gap, marks[i - 1].b, marks[i].a);
    busy[marks[i].name] += 1e-3 * ms;
    idle[marks[i].name] += 1e-3 * (gap > 0.0f ? gap : 0.0f);
    calls[marks[i].name]++;
    total_busy += 1e-3 * ms;
    total_idle += 1e-3 * (gap > 0.0f ? gap : 0.0f);
  }
  if (!marks.empty()) {
    float ms = 0.0f;
    cudaEventElapsedTime(&ms, marks.front().a, marks.back().b);
    span = 1e-3 * ms;
  }
  fprintf(f, "# kp_timer events: %zu marks (calls %ld to %ld), device span %.4f s, kernels and copies %.4f s "
          "(%.1f %%), idle before them %.4f s\n", marks.size(), skip_calls + 1, skip_calls + (long) marks.size(),
          span, total_busy, span > 0 ? 100.0 * total_busy / span : 0.0, total_idle);
  fprintf(f, "# %10s %12s %10s %12s  name (device time, idle before)\n", "calls", "device_s", "mean_us", "idle_s");
  std::vector<size_t> order(names.size());
  for (size_t k = 0; k < order.size(); k++) order[k] = k;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return busy[a] + idle[a] > busy[b] + idle[b]; });
  for (size_t k : order)
    fprintf(f, "  %10ld %12.4f %10.2f %12.4f  %s\n", calls[k], busy[k], calls[k] ? 1e6 * busy[k] / calls[k] : 0.0,
            idle[k], names[k].c_str());
}

void kokkosp_finalize_library()
{
  std::vector<std::pair<std::string, Stat>> rows(stats.begin(), stats.end());
  std::sort(rows.begin(), rows.end(), [](auto &a, auto &b) { return a.second.seconds > b.second.seconds; });
  const char *path = getenv("KP_TIMER_OUT");
  FILE *f = path ? fopen(path, "w") : stderr;
  if (!f) f = stderr;
  if (events) {
    report_events(f);
    if (f != stderr) fclose(f);
    return;
  }
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
