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
// KP_TIMER_SYNC=host: no CUDA call at all; the host's clock inside each launch or copy (what a
// launch costs the host, or how long a copy to the host waits for the device) and before it
// (LAMMPS' own host work since the previous one), over the same window of calls: whether the
// step is bound by the host or by the device.  Rows: calls, host inside, mean, host before.
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
bool hostclock = false;
// host mode: the host's time inside and before each name
struct HostStat {
  long calls = 0;
  double inside = 0.0, before = 0.0;
};
std::map<std::string, HostStat> hstats;
double h_last_end = -1.0, h_first = -1.0, h_last = -1.0;
long h_seen = 0, h_kept = 0;
struct HostOpen {
  std::string name;
  double t0, before;
  bool kept;
};
std::vector<HostOpen> h_open;
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

void host_begin(const std::string &name)
{
  double t = now();
  h_seen++;
  bool kept = h_seen > skip_calls && h_kept < max_calls && h_open.empty();
  double before = h_last_end >= 0.0 ? t - h_last_end : 0.0;
  if (kept) {
    h_kept++;
    if (h_first < 0.0) h_first = t;
  }
  h_open.push_back({name, t, before, kept});
}

void host_end()
{
  double t = now();
  HostOpen o = h_open.back();
  h_open.pop_back();
  if (!h_open.empty()) return;    // nested (a copy inside a launch): counted in the outer one
  h_last_end = t;
  if (!o.kept) return;
  HostStat &s = hstats[o.name];
  s.calls++;
  s.inside += t - o.t0;
  s.before += o.before;
  h_last = t;
}

void begin(const char *name, const char *kind, uint64_t *kid)
{
  if (hostclock) {
    host_begin(pretty(name, kind));
    *kid = 0;
    return;
  }
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
  if (hostclock) {
    host_end();
    return;
  }
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

// Kokkos (3.3 on) fences the device around every callback of a tool that does not declare
// otherwise: the synchronised mode wants that, the others must not have it (each kernel would
// then wait for the one before and the host for each kernel: the step of the 2D cut at 41 across
// took 234-262 us under the events and host modes with the fences, against 171-176 without a tool)
struct Kokkos_Tools_ToolSettings {
  bool requires_global_fencing;
  bool padding[255];
};
// (Kokkos asks after kokkosp_init_library, which has read KP_TIMER_SYNC into sync)
void kokkosp_request_tool_settings(const uint32_t, Kokkos_Tools_ToolSettings *settings)
{
  settings->requires_global_fencing = sync;
}

void kokkosp_init_library(const int, const uint64_t, const uint32_t, void *)
{
  const char *e = getenv("KP_TIMER_SYNC");
  hostclock = e && strcmp(e, "host") == 0;
  sync = !(e && (strcmp(e, "0") == 0 || strcmp(e, "events") == 0 || hostclock));
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
  if (hostclock) {
    host_begin(buf);
    return;
  }
  if (events) {
    open_marks.push_back(open_mark(buf));
    return;
  }
  device_sync();
  copy_open = {buf, now()};
}

void kokkosp_end_deep_copy()
{
  if (hostclock) {
    host_end();
    return;
  }
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

// host mode: the host's time inside each name and before it
void report_host(FILE *f)
{
  std::vector<std::pair<std::string, HostStat>> rows(hstats.begin(), hstats.end());
  std::sort(rows.begin(), rows.end(),
            [](auto &a, auto &b) { return a.second.inside + a.second.before > b.second.inside + b.second.before; });
  double in = 0.0, bef = 0.0;
  for (auto &r : rows) {
    in += r.second.inside;
    bef += r.second.before;
  }
  const double span = h_last > h_first ? h_last - h_first : 0.0;
  fprintf(f, "# kp_timer host: %ld calls (from call %ld), host span %.4f s, inside launches and copies %.4f s "
          "(%.1f %%), before them %.4f s\n", h_kept, skip_calls + 1, span, in, span > 0 ? 100.0 * in / span : 0.0, bef);
  fprintf(f, "# %10s %12s %10s %12s %10s  name (host inside, host before)\n", "calls", "inside_s", "mean_us",
          "before_s", "mean_us");
  for (auto &r : rows)
    fprintf(f, "  %10ld %12.4f %10.2f %12.4f %10.2f  %s\n", r.second.calls, r.second.inside,
            r.second.calls ? 1e6 * r.second.inside / r.second.calls : 0.0, r.second.before,
            r.second.calls ? 1e6 * r.second.before / r.second.calls : 0.0, r.first.c_str());
}

void kokkosp_finalize_library()
{
  std::vector<std::pair<std::string, Stat>> rows(stats.begin(), stats.end());
  std::sort(rows.begin(), rows.end(), [](auto &a, auto &b) { return a.second.seconds > b.second.seconds; });
  const char *path = getenv("KP_TIMER_OUT");
  FILE *f = path ? fopen(path, "w") : stderr;
  if (!f) f = stderr;
  if (hostclock) {
    report_host(f);
    if (f != stderr) fclose(f);
    return;
  }
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
