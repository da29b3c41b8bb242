// The device's own timeline of a run, without synchronising anything: a CUPTI activity tracer
// that the CUDA driver loads at its initialisation (CUDA_INJECTION64_PATH), for machines without
// Nsight Systems.  kp_timer.cpp times each kernel between fences or CUDA events, which adds a
// synchronisation or an event per launch; this records what the GPU and the host did as they ran:
// every kernel, copy and memset on the device clock, every CUDA runtime call and every host wait
// (synchronisation) on the host, in one clock domain.
// At the end of the run it summarises a window of steps (CUPTI_TRACE_OUT, default stderr):
//   the window: from the CUPTI_TRACE_FROM-th (default 500) launch of a kernel whose short name
//   contains CUPTI_TRACE_MARK (default "initial_integrate": one launch a step) to the
//   CUPTI_TRACE_FROM + CUPTI_TRACE_STEPS-th (default 1000 steps later)
//   per step: wall span, device busy time (the union of its kernels, copies and memsets), idle
//   time and the idle gaps by length, each kernel's time and launches, copies, each runtime call's
//   host time, and the host's time in synchronisations.
// Kernel names are shortened to the Kokkos functor's enclosing function (e.g.
// PairSPHJCThermalKokkos::neigh_pass) or the demangled name's head.
// Build (device machine; bench/gpu/cutting.sh trace does it):
//   g++ -O2 -shared -fPIC -o libcupti_trace.so bench/gpu/cupti_trace.cpp -I$CUDA/include
//       -I$CUDA/extras/CUPTI/include -L$CUDA/extras/CUPTI/lib64 -lcupti -Wl,-rpath,$CUDA/extras/CUPTI/lib64
// Use:  CUDA_INJECTION64_PATH=$PWD/libcupti_trace.so lmp -k on g 1 -sf kk ...
#include <cupti.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cxxabi.h>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace {

struct Span {
  uint64_t start, end;
  int kind;           // 0 kernel, 1 copy, 2 memset, 3 runtime call, 4 synchronisation
  std::string name;
};
std::vector<Span> spans;
std::mutex lock;
// small buffers, so that CUPTI hands them over while the run goes on (about 6 KB of records a step):
// what the exit's flush may miss (the CUDA runtime may have torn the context down) is only the
// run's end, after the window
const size_t BUF = 1u << 20;

void check(CUptiResult r, const char *what)
{
  if (r == CUPTI_SUCCESS) return;
  const char *s = nullptr;
  cuptiGetResultString(r, &s);
  std::fprintf(stderr, "cupti_trace: %s failed: %s\n", what, s ? s : "?");
}

// Kokkos functors' kernels carry the enclosing function in their mangled name: keep
// "Class::method" of the first "...Kokkos<...>::method" there, else the demangled head
std::string short_name(const char *mangled)
{
  int st = 0;
  char *d = abi::__cxa_demangle(mangled, nullptr, nullptr, &st);
  std::string s = st == 0 && d ? d : mangled;
  std::free(d);
  const std::string tags[] = {"LAMMPS_NS::", "sphcut::"};
  for (const std::string &tag : tags) {
    size_t p = s.find(tag);
    while (p != std::string::npos) {
      size_t q = p + tag.size(), e = q;
      while (e < s.size() && (std::isalnum((unsigned char) s[e]) || s[e] == '_')) e++;
      std::string cls = s.substr(q, e - q);
      if (e < s.size() && s[e] == '<') {    // skip the template arguments
        int depth = 0;
        for (; e < s.size(); e++) {
          if (s[e] == '<') depth++;
          if (s[e] == '>' && --depth == 0) { e++; break; }
        }
      }
      if (s.compare(e, 2, "::") == 0) {
        size_t m = e + 2, me = m;
        while (me < s.size() && (std::isalnum((unsigned char) s[me]) || s[me] == '_')) me++;
        if (me > m) return cls + "::" + s.substr(m, me - m);
      }
      p = s.find(tag, q);
    }
  }
  // no method: the LAMMPS names in it (a functor and its tag, e.g. NeighborKokkos
  // TagNeighborCheckDistance), else the name without Kokkos' launch wrappers
  std::string names;
  for (size_t p = s.find("LAMMPS_NS::"); p != std::string::npos && names.size() < 80;
       p = s.find("LAMMPS_NS::", p + 1)) {
    size_t q = p + 11, e = q;
    while (e < s.size() && (std::isalnum((unsigned char) s[e]) || s[e] == '_')) e++;
    const std::string id = s.substr(q, e - q);
    if (names.find(id) == std::string::npos) names += (names.empty() ? "" : " ") + id;
  }
  if (!names.empty()) return names;
  for (const char *w : {"void ", "Kokkos::Impl::cuda_parallel_launch_local_memory<",
                        "Kokkos::Impl::cuda_parallel_launch_constant_memory<", "Kokkos::Impl::"})
    if (s.compare(0, std::strlen(w), w) == 0) s = s.substr(std::strlen(w));
  return s.substr(0, 80);
}

void CUPTIAPI requested(uint8_t **buffer, size_t *size, size_t *max_records)
{
  *buffer = static_cast<uint8_t *>(std::aligned_alloc(8, BUF));
  *size = BUF;
  *max_records = 0;
}

void CUPTIAPI completed(CUcontext, uint32_t, uint8_t *buffer, size_t, size_t valid)
{
  std::vector<Span> got;
  CUpti_Activity *rec = nullptr;
  while (cuptiActivityGetNextRecord(buffer, valid, &rec) == CUPTI_SUCCESS) {
    switch (rec->kind) {
      case CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL:
      case CUPTI_ACTIVITY_KIND_KERNEL: {
        auto *k = reinterpret_cast<CUpti_ActivityKernel10 *>(rec);
        got.push_back({k->start, k->end, 0, short_name(k->name)});
        break;
      }
      case CUPTI_ACTIVITY_KIND_MEMCPY: {
        auto *m = reinterpret_cast<CUpti_ActivityMemcpy6 *>(rec);
        const int c = (int) m->copyKind;    // CUpti_ActivityMemcpyKind: 1 host to device, 2 device to host, ...
        got.push_back({m->start, m->end, 1, c == 1 ? "copy to device" : c == 2 ? "copy to host" : "copy kind " + std::to_string(c)});
        break;
      }
      case CUPTI_ACTIVITY_KIND_MEMSET: {
        auto *m = reinterpret_cast<CUpti_ActivityMemset4 *>(rec);
        got.push_back({m->start, m->end, 2, "memset"});
        break;
      }
      case CUPTI_ACTIVITY_KIND_RUNTIME: {
        auto *a = reinterpret_cast<CUpti_ActivityAPI *>(rec);
        const char *n = nullptr;
        cuptiGetCallbackName(CUPTI_CB_DOMAIN_RUNTIME_API, a->cbid, &n);
        got.push_back({a->start, a->end, 3, n ? n : "runtime " + std::to_string(a->cbid)});
        break;
      }
      case CUPTI_ACTIVITY_KIND_SYNCHRONIZATION: {
        auto *s = reinterpret_cast<CUpti_ActivitySynchronization2 *>(rec);
        const char *types[] = {"sync", "event synchronize", "stream wait event", "stream synchronize",
                               "context synchronize"};
        const int t = (int) s->type;
        got.push_back({s->start, s->end, 4, t >= 0 && t <= 4 ? types[t] : "sync"});
        break;
      }
      default: break;
    }
  }
  size_t dropped = 0;
  cuptiActivityGetNumDroppedRecords(nullptr, 0, &dropped);
  if (dropped) std::fprintf(stderr, "cupti_trace: %zu records dropped\n", dropped);
  std::free(buffer);
  std::lock_guard<std::mutex> g(lock);
  spans.insert(spans.end(), got.begin(), got.end());
}

long env_long(const char *name, long def)
{
  const char *e = std::getenv(name);
  return e && *e ? std::atol(e) : def;
}

bool summarised = false;

void summarise()
{
  if (summarised) return;
  summarised = true;
  if (cuptiActivityFlushAll(CUPTI_ACTIVITY_FLAG_FLUSH_FORCED) != CUPTI_SUCCESS)
    std::fprintf(stderr, "cupti_trace: the last records could not be flushed\n");
  std::lock_guard<std::mutex> g(lock);
  const char *out = std::getenv("CUPTI_TRACE_OUT");
  FILE *f = out && *out ? std::fopen(out, "w") : stderr;
  if (!f) f = stderr;
  const char *me = std::getenv("CUPTI_TRACE_MARK");
  const std::string mark = me && *me ? me : "initial_integrate";
  const long from = env_long("CUPTI_TRACE_FROM", 500), steps = env_long("CUPTI_TRACE_STEPS", 1000);
  std::sort(spans.begin(), spans.end(), [](const Span &a, const Span &b) { return a.start < b.start; });
  std::vector<uint64_t> marks;
  for (const Span &s : spans)
    if (s.kind == 0 && s.name.find(mark) != std::string::npos) marks.push_back(s.start);
  if ((long) marks.size() <= from + 1) {
    std::fprintf(f, "cupti_trace: %zu launches of a kernel named *%s*: no window of steps after the %ld-th\n",
                 marks.size(), mark.c_str(), from);
    // what was recorded: records of each kind, the most launched kernels
    long nkind[5] = {0, 0, 0, 0, 0};
    std::map<std::string, long> launches;
    for (const Span &s : spans) {
      nkind[s.kind]++;
      if (s.kind == 0) launches[s.name]++;
    }
    std::fprintf(f, "  records: %ld kernels, %ld copies, %ld memsets, %ld runtime calls, %ld synchronisations\n",
                 nkind[0], nkind[1], nkind[2], nkind[3], nkind[4]);
    std::vector<std::pair<long, std::string>> top;
    for (const auto &e : launches) top.push_back({e.second, e.first});
    std::sort(top.rbegin(), top.rend());
    for (size_t k = 0; k < top.size() && k < 12; k++) std::fprintf(f, "  %8ld  %s\n", top[k].first, top[k].second.c_str());
    if (f != stderr) std::fclose(f);
    return;
  }
  const long n = std::min<long>(steps, (long) marks.size() - 1 - from);
  const uint64_t t0 = marks[from], t1 = marks[from + n];
  const double ps = 1e-3 / n;    // ns in the window -> us a step
  std::map<std::string, std::pair<double, long>> dev, host;
  std::vector<std::pair<uint64_t, uint64_t>> busy;
  double sync = 0.0;
  for (const Span &s : spans) {
    if (s.start < t0 || s.start >= t1) continue;
    const double d = (double) (s.end - s.start);
    if (s.kind <= 2) {
      auto &e = dev[(s.kind == 0 ? "" : "[") + s.name + (s.kind == 0 ? "" : "]")];
      e.first += d;
      e.second++;
      busy.push_back({s.start, std::min(s.end, t1)});
    } else {
      auto &e = host[s.kind == 4 ? "[" + s.name + "]" : s.name];
      e.first += d;
      e.second++;
      if (s.kind == 4) sync += d;
    }
  }
  // the device's busy time: the union of its intervals; its idle gaps by length
  std::sort(busy.begin(), busy.end());
  double on = 0.0;
  uint64_t cur_s = 0, cur_e = 0;
  std::vector<double> gaps;
  uint64_t last_end = t0;
  for (const auto &b : busy) {
    if (b.first > cur_e) {
      if (cur_e > cur_s) on += (double) (cur_e - cur_s);
      if (b.first > last_end) gaps.push_back((double) (b.first - last_end));
      cur_s = b.first;
      cur_e = b.second;
    } else if (b.second > cur_e) {
      cur_e = b.second;
    }
    last_end = std::max(last_end, cur_e);
  }
  if (cur_e > cur_s) on += (double) (cur_e - cur_s);
  if (t1 > last_end) gaps.push_back((double) (t1 - last_end));
  const double span = (double) (t1 - t0);
  std::fprintf(f, "cupti_trace: %ld steps (launches %ld to %ld of *%s*)\n", n, from, from + n, mark.c_str());
  std::fprintf(f, "  per step: span %.1f us, device busy %.1f us (%.0f %%), idle %.1f us; host in synchronisations %.1f us\n",
               span * ps, on * ps, 100.0 * on / span, (span - on) * ps, sync * ps);
  const double edges[] = {1e3, 2e3, 5e3, 1e4, 2e4, 5e4, 1e99};
  const char *labels[] = {"<1", "1-2", "2-5", "5-10", "10-20", "20-50", ">50"};
  std::fprintf(f, "  device idle gaps [us]: count a step / idle us a step:");
  for (int b = 0; b < 7; b++) {
    double c = 0.0, t = 0.0;
    for (double x : gaps)
      if (x < edges[b] && (b == 0 || x >= edges[b - 1])) c += 1.0, t += x;
    std::fprintf(f, "  %s: %.2f / %.1f", labels[b], c / n, t * ps);
  }
  std::fprintf(f, "\n");
  auto table = [&](const std::map<std::string, std::pair<double, long>> &m, const char *what, size_t rows) {
    std::vector<std::pair<std::string, std::pair<double, long>>> v(m.begin(), m.end());
    std::sort(v.begin(), v.end(), [](const auto &a, const auto &b) { return a.second.first > b.second.first; });
    for (size_t k = 0; k < v.size() && k < rows; k++)
      std::fprintf(f, "  %s %8.2f us/step %6.2f calls/step %8.2f us/call  %s\n", what, v[k].second.first * ps,
                   (double) v[k].second.second / n, v[k].second.first * 1e-3 / v[k].second.second, v[k].first.c_str());
  };
  table(dev, "device", 40);
  table(host, "host  ", 20);
  // one step as it ran (the window's middle step): each device activity and host wait with its start
  // after the step's first launch and its length, and the device's idle gap before it
  const uint64_t a = marks[from + n / 2], b = marks[from + n / 2 + 1];
  std::fprintf(f, "  one step (launch %ld of *%s*), us: start, length, idle before (device)\n", from + n / 2,
               mark.c_str());
  uint64_t dev_end = a;
  for (const Span &s : spans) {
    if (s.start < a || s.start >= b || s.kind == 3) continue;
    const double gap = s.kind <= 2 && s.start > dev_end ? (double) (s.start - dev_end) * 1e-3 : 0.0;
    std::fprintf(f, "    %8.1f %8.1f %6.1f  %s%s\n", (double) (s.start - a) * 1e-3, (double) (s.end - s.start) * 1e-3,
                 gap, s.kind <= 2 ? "" : "host wait: ", s.name.c_str());
    if (s.kind <= 2) dev_end = std::max(dev_end, s.end);
  }
  if (f != stderr) std::fclose(f);
}

}    // namespace

// called by the CUDA driver at its initialisation (CUDA_INJECTION64_PATH)
extern "C" int InitializeInjection(void)
{
  static bool done = false;    // the driver may call it more than once (seen with CUDA 13)
  if (done) return 1;
  done = true;
  check(cuptiActivityRegisterCallbacks(requested, completed), "cuptiActivityRegisterCallbacks");
  check(cuptiActivityEnable(CUPTI_ACTIVITY_KIND_CONCURRENT_KERNEL), "enable kernels");
  check(cuptiActivityEnable(CUPTI_ACTIVITY_KIND_MEMCPY), "enable copies");
  check(cuptiActivityEnable(CUPTI_ACTIVITY_KIND_MEMSET), "enable memsets");
  check(cuptiActivityEnable(CUPTI_ACTIVITY_KIND_RUNTIME), "enable runtime calls");
  check(cuptiActivityEnable(CUPTI_ACTIVITY_KIND_SYNCHRONIZATION), "enable synchronisations");
  // and a flush by CUPTI's own thread every 200 ms besides the full buffers (a subscription to the
  // context's destruction is refused on the device machine: CUPTI_ERROR_MULTIPLE_SUBSCRIBERS_NOT_SUPPORTED)
  check(cuptiActivityFlushPeriod(200), "cuptiActivityFlushPeriod");
  std::atexit(summarise);
  return 1;
}
