/* ----------------------------------------------------------------------
   sphcut - tool fields per facet (see sphcut_tool_fields.h)
------------------------------------------------------------------------- */

#include "sphcut_tool_fields.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace sphcut {

void ToolFields::build(const std::vector<double> &elem, int nv, const std::vector<int> &feat)
{
  nvert = nv;
  const int stride = 3 * nvert;
  nfacet = (int) (elem.size() / stride);
  area.assign(nfacet, 0.0);
  inv_area.assign(nfacet, 0.0);
  feature.assign(nfacet, 4);
  // vertex ids by coordinates equal to 1e-10 of the tool's size (2D segments: z ignored; the 2D
  // section of an STL tool computes a vertex shared by two segments from two triangles)
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t k = 0; k < elem.size(); k++) {
    lo[k % 3] = std::min(lo[k % 3], elem[k]);
    hi[k % 3] = std::max(hi[k % 3], elem[k]);
  }
  double size = 0.0;
  for (int k = 0; k < 3; k++) size = std::max(size, hi[k] - lo[k]);
  const double tol = size > 0.0 ? 1.0e-10 * size : 1.0;
  std::map<std::array<long long, 3>, int> ids;
  std::vector<int> vid((size_t) nfacet * nvert);
  for (int e = 0; e < nfacet; e++) {
    const double *v = elem.data() + (size_t) stride * e;
    double n[3];
    area[e] = nvert == 3 ? 0.5 * triangle_normal(v, v + 3, v + 6, n) : segment_normal(v, v + 3, n);
    inv_area[e] = area[e] > 0.0 ? 1.0 / area[e] : 0.0;
    if (e < (int) feat.size()) feature[e] = feat[e] + 1;
    for (int m = 0; m < nvert; m++) {
      const std::array<long long, 3> key = {std::llround(v[3 * m] / tol), std::llround(v[3 * m + 1] / tol),
                                            nvert == 3 ? std::llround(v[3 * m + 2] / tol) : 0LL};
      auto it = ids.emplace(key, (int) ids.size()).first;
      vid[(size_t) e * nvert + m] = it->second;
    }
  }
  // the elements at each vertex and at each (undirected) edge
  std::vector<std::vector<int>> at_vertex(ids.size());
  std::map<std::pair<int, int>, std::vector<int>> at_edge;
  auto edge_key = [](int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); };
  for (int e = 0; e < nfacet; e++) {
    const int *w = &vid[(size_t) e * nvert];
    for (int m = 0; m < nvert; m++) at_vertex[w[m]].push_back(e);
    if (nvert == 3)
      for (int m = 0; m < 3; m++) at_edge[edge_key(w[m], w[(m + 1) % 3])].push_back(e);
  }
  // CSR over (element, region - 1): regions EDGE_AB, EDGE_BC, EDGE_CA, VERT_A, VERT_B, VERT_C
  share_start.assign((size_t) 6 * nfacet + 1, 0);
  share_elem.clear();
  for (int e = 0; e < nfacet; e++) {
    const int *w = &vid[(size_t) e * nvert];
    for (int r = EDGE_AB; r <= VERT_C; r++) {
      const std::vector<int> *list = nullptr;
      if (r <= EDGE_CA && nvert == 3) list = &at_edge[edge_key(w[r - EDGE_AB], w[(r - EDGE_AB + 1) % 3])];
      else if (r >= VERT_A && r - VERT_A < nvert) list = &at_vertex[w[r - VERT_A]];
      if (list) share_elem.insert(share_elem.end(), list->begin(), list->end());
      share_start[(size_t) 6 * e + r] = (int) share_elem.size();
    }
  }
  acc.assign((size_t) nfacet * NFS, 0.0);
  depth.assign(nfacet, 0.0);
  out.assign((size_t) nfacet * NCOL, 0.0);
  for (int e = 0; e < nfacet; e++) {
    out[(size_t) e * NCOL + C_AREA] = area[e];
    out[(size_t) e * NCOL + C_FEAT] = feature[e];
  }
  time = 0.0;
}

FacetShare ToolFields::share() const
{
  FacetShare s;
  s.start = share_start.data();
  s.elem = share_elem.data();
  return s;
}

void ToolFields::close_interval(MPI_Comm world, const std::vector<double> &cur_elem)
{
  std::vector<double> g(acc.size(), 0.0);
  MPI_Allreduce(acc.data(), g.data(), (int) acc.size(), MPI_DOUBLE, MPI_SUM, world);
  const double rt = time > 0.0 ? 1.0 / time : 0.0;
  for (int k = 0; k < NGLOB; k++) glob[k] = 0.0;
  for (int e = 0; e < nfacet; e++) {
    const double *s = &g[(size_t) e * NFS];
    double *o = &out[(size_t) e * NCOL];
    depth[e] += s[FS_WEAR];    // the time integral of the rate over the interval
    o[C_SN] = s[FS_FN] * rt * inv_area[e];
    o[C_TAU] = s[FS_FT] * rt * inv_area[e];
    o[C_VS] = s[FS_N] > 0.0 ? s[FS_VS] / s[FS_N] : 0.0;
    o[C_T] = s[FS_N] > 0.0 ? s[FS_T] / s[FS_N] : 0.0;
    o[C_N] = s[FS_N] * rt;
    o[C_WEAR] = s[FS_WEAR] * rt;
    o[C_DEPTH] = depth[e];
    for (int k = 0; k < 3; k++) o[C_FX + k] = s[FS_FX + k] * rt;
    o[C_AREA] = area[e];
    o[C_FEAT] = feature[e];
    glob[G_WEAR_RATE] += o[C_WEAR] * area[e];
    glob[G_FN] += s[FS_FN] * rt;
    glob[G_FT] += s[FS_FT] * rt;
    glob[G_WEAR_VOL] += depth[e] * area[e];
    glob[G_DEPTH_MAX] = std::max(glob[G_DEPTH_MAX], depth[e]);
  }
  set_pose(cur_elem);
  std::fill(acc.begin(), acc.end(), 0.0);
  time = 0.0;
}

void ToolFields::set_pose(const std::vector<double> &cur_elem)
{
  const int stride = 3 * nvert;
  for (int e = 0; e < nfacet; e++) {
    double *o = &out[(size_t) e * NCOL];
    const double *v = cur_elem.data() + (size_t) stride * e;
    for (int k = 0; k < 3; k++) {
      double c = 0.0;
      for (int m = 0; m < nvert; m++) c += v[3 * m + k];
      o[C_CX + k] = c / nvert;
    }
  }
}

const char *ToolFields::column_name(int c)
{
  static const char *names[NCOL] = {"normal_stress", "shear_stress", "sliding_velocity", "temperature",
                                    "contacts", "wear_rate", "wear_depth", "force_x", "force_y", "force_z",
                                    "area", "feature", "centroid_x", "centroid_y", "centroid_z"};
  return c >= 0 && c < NCOL ? names[c] : "";
}

std::vector<std::string> ToolFields::vtk_names() const
{
  std::vector<std::string> names;
  if (every)
    for (int c = 0; c < NCOL; c++) names.push_back(column_name(c));
  return names;
}

std::vector<double> ToolFields::restart_data(MPI_Comm world) const
{
  std::vector<double> g(acc.size(), 0.0);
  MPI_Allreduce(acc.data(), g.data(), (int) acc.size(), MPI_DOUBLE, MPI_SUM, world);
  std::vector<double> b;
  b.reserve(restart_size(nfacet));
  b.push_back(nfacet);
  b.push_back(time);
  b.insert(b.end(), depth.begin(), depth.end());
  b.insert(b.end(), g.begin(), g.end());
  b.insert(b.end(), out.begin(), out.end());
  b.insert(b.end(), glob, glob + NGLOB);
  return b;
}

bool ToolFields::read_restart(const double *buf, bool me0)
{
  if ((int) buf[0] != nfacet) return false;
  time = buf[1];
  const double *p = buf + 2;
  std::copy(p, p + nfacet, depth.begin());
  p += nfacet;
  for (size_t k = 0; k < acc.size(); k++) acc[k] = me0 ? p[k] : 0.0;
  p += acc.size();
  std::copy(p, p + out.size(), out.begin());
  p += out.size();
  std::copy(p, p + NGLOB, glob);
  return true;
}

}    // namespace sphcut
