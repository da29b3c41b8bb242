// A Kokkos Tools library (KOKKOS_PROFILE_LIBRARY) that counts the kernel launches (parallel_for,
// parallel_reduce, parallel_scan) and deep copies of a run by name, for any backend: no CUDA,
// nothing synchronised (kp_timer.cpp, which times them, needs the CUDA runtime).  At the end it
// writes one row per name (calls, kind, name) to KP_COUNT_OUT (default stderr), most calls first,
// then the totals.  Kernels per step: the difference of two runs that differ only in their step
// count, divided by the difference of the steps.
// Build (host):  g++ -O2 -shared -fPIC -o libkp_count.so bench/gpu/kp_count.cpp
// Use:  KOKKOS_PROFILE_LIBRARY=$PWD/libkp_count.so lmp -k on t 2 -sf kk ...
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {
std::map<std::pair<std::string, std::string>, long> counts;    // (kind, name) -> calls
long total[4] = {0, 0, 0, 0};                                   // for, reduce, scan, copy
const char *kinds[4] = {"for", "reduce", "scan", "copy"};

void count(int kind, const char *name)
{
  counts[{kinds[kind], name ? name : "?"}]++;
  total[kind]++;
}
}    // namespace

extern "C" {
// no fence around the callbacks (Kokkos 3.3 on fences the device around every callback of a tool
// that does not declare otherwise): the counted run keeps its own timing
struct Kokkos_Tools_ToolSettings {
  bool requires_global_fencing;
  bool padding[255];
};
void kokkosp_request_tool_settings(const uint32_t, Kokkos_Tools_ToolSettings *settings)
{
  settings->requires_global_fencing = false;
}

void kokkosp_init_library(const int, const uint64_t, const uint32_t, void *) {}

void kokkosp_begin_parallel_for(const char *name, const uint32_t, uint64_t *kid)
{
  count(0, name);
  *kid = 0;
}
void kokkosp_end_parallel_for(const uint64_t) {}
void kokkosp_begin_parallel_reduce(const char *name, const uint32_t, uint64_t *kid)
{
  count(1, name);
  *kid = 0;
}
void kokkosp_end_parallel_reduce(const uint64_t) {}
void kokkosp_begin_parallel_scan(const char *name, const uint32_t, uint64_t *kid)
{
  count(2, name);
  *kid = 0;
}
void kokkosp_end_parallel_scan(const uint64_t) {}

struct SpaceHandle {
  char name[64];
};
void kokkosp_begin_deep_copy(SpaceHandle, const char *dst, const void *, SpaceHandle, const char *src,
                             const void *, uint64_t)
{
  const std::string n = std::string(dst ? dst : "?") + " <- " + (src ? src : "?");
  count(3, n.c_str());
}
void kokkosp_end_deep_copy() {}

void kokkosp_finalize_library()
{
  FILE *fp = stderr;
  const char *out = getenv("KP_COUNT_OUT");
  if (out && *out) fp = fopen(out, "w");
  if (!fp) fp = stderr;
  std::vector<std::pair<long, std::pair<std::string, std::string>>> rows;
  for (auto &c : counts) rows.push_back({c.second, c.first});
  std::sort(rows.begin(), rows.end(), [](const auto &a, const auto &b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  for (auto &r : rows) fprintf(fp, "%10ld %-6s %s\n", r.first, r.second.first.c_str(), r.second.second.c_str());
  fprintf(fp, "# total: %ld for, %ld reduce, %ld scan (%ld kernels), %ld deep copies\n", total[0], total[1],
          total[2], total[0] + total[1] + total[2], total[3]);
  if (fp != stderr) fclose(fp);
}
}
