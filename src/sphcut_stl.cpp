/* ----------------------------------------------------------------------
   sphcut - host utilities for rigid tool geometry: STL I/O, VTK output,
   cutting insert generator, contact bin build (see sphcut_stl.h)
------------------------------------------------------------------------- */

#include "sphcut_stl.h"
#include "sphcut_contact_step.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <sys/stat.h>

namespace sphcut {

namespace {

const double DEG = 3.14159265358979323846 / 180.0;

std::string fail_prefix(const std::string &file)
{
  return "STL file '" + file + "': ";
}

[[noreturn]] void fail(const std::string &file, const std::string &what)
{
  throw std::runtime_error(fail_prefix(file) + what);
}

std::string fmt3(const double *v)
{
  char buf[96];
  snprintf(buf, sizeof(buf), "(%g %g %g)", v[0], v[1], v[2]);
  return buf;
}

bool iequal(const std::string &a, const char *b)
{
  const size_t n = strlen(b);
  if (a.size() != n) return false;
  for (size_t i = 0; i < n; i++)
    if (tolower((unsigned char) a[i]) != b[i]) return false;
  return true;
}

// whitespace tokenizer of an ASCII STL with line numbers
struct Tokens {
  const std::string &s;
  size_t pos = 0;
  int line = 1;
  explicit Tokens(const std::string &str) : s(str) {}
  bool next(std::string &tok, int &tline)
  {
    while (pos < s.size() && isspace((unsigned char) s[pos])) {
      if (s[pos] == '\n') line++;
      pos++;
    }
    if (pos >= s.size()) return false;
    const size_t b = pos;
    while (pos < s.size() && !isspace((unsigned char) s[pos])) pos++;
    tok = s.substr(b, pos - b);
    tline = line;
    return true;
  }
  void skip_line()
  {
    while (pos < s.size() && s[pos] != '\n') pos++;
  }
};

std::string fmtg(double x)
{
  char buf[40];
  snprintf(buf, sizeof(buf), "%g", x);
  return buf;
}

// a facet (9 doubles) of zero area: twice its area at most 1e-12 of its longest edge squared,
// or that edge at most 1e-9 of its largest coordinate (below the resolution of the coordinates)
bool facet_degenerate(const double *v)
{
  double u[3], w[3], c[3];
  sub3(v + 3, v, u);
  sub3(v + 6, v, w);
  cross3(u, w, c);
  double lmax2 = 0.0, cmax = 0.0;
  for (int e = 0; e < 3; e++) {
    double d[3];
    sub3(v + 3 * ((e + 1) % 3), v + 3 * e, d);
    lmax2 = std::max(lmax2, dot3(d, d));
  }
  for (int k = 0; k < 9; k++) cmax = std::max(cmax, std::fabs(v[k]));
  return !(len3(c) > 1.0e-12 * lmax2) || !(lmax2 > 1.0e-18 * cmax * cmax);
}

// 9 vertex coordinates + stored normal of one facet, checked and placed
void add_facet(const std::string &file, size_t index, const double *nrm, const double *v,
               const StlTransform &tf, std::vector<double> &tri)
{
  if (facet_degenerate(v)) fail(file, "facet " + std::to_string(index) + " is degenerate (zero area)");
  double c[3], u[3], w[3];
  sub3(v + 3, v, u);
  sub3(v + 6, v, w);
  cross3(u, w, c);
  const double ln = len3(nrm);
  if (ln > 0.0 && dot3(nrm, c) < 0.0)
    fail(file, "facet " + std::to_string(index) + ": stored normal " + fmt3(nrm) +
             " disagrees with its vertex winding (right-hand rule gives the opposite side)");
  double y[9];
  for (int k = 0; k < 3; k++) tf.apply(v + 3 * k, y + 3 * k);
  for (int k = 0; k < 9; k++)
    if (!std::isfinite(y[k]))
      fail(file, "facet " + std::to_string(index) + " has a non-finite vertex after scale " + fmtg(tf.scale));
  // a scale that shrinks the facets below the resolution of their coordinates (scale 1e-30 with
  // a shift) makes them degenerate: every particle near the tool would see the same distance
  if (facet_degenerate(y))
    fail(file, "facet " + std::to_string(index) + " is degenerate (zero area) after scale " + fmtg(tf.scale) +
             " (its vertices " + fmt3(y) + " " + fmt3(y + 3) + " " + fmt3(y + 6) + ")");
  tri.insert(tri.end(), y, y + 9);
}

uint32_t get_u32(const unsigned char *p)
{
  return (uint32_t) p[0] | ((uint32_t) p[1] << 8) | ((uint32_t) p[2] << 16) | ((uint32_t) p[3] << 24);
}

double get_f32(const unsigned char *p)
{
  const uint32_t u = get_u32(p);
  float f;
  memcpy(&f, &u, 4);
  return (double) f;
}

void put_u32(unsigned char *p, uint32_t u)
{
  for (int k = 0; k < 4; k++) p[k] = (unsigned char) ((u >> (8 * k)) & 0xff);
}

void put_f32(unsigned char *p, double x)
{
  const float f = (float) x;
  uint32_t u;
  memcpy(&u, &f, 4);
  put_u32(p, u);
}

std::vector<double> read_binary(const std::string &file, const std::string &data,
                                const StlTransform &tf)
{
  const size_t size = data.size();
  if (size < 84)
    fail(file, "truncated binary STL (" + std::to_string(size) + " bytes, the header alone needs 84)");
  const unsigned char *p = (const unsigned char *) data.data();
  const uint32_t nf = get_u32(p + 80);
  if (nf == 0) fail(file, "no facets (binary STL with a facet count of 0)");
  const size_t expect = 84 + 50 * (size_t) nf;
  if (size != expect)
    fail(file, "truncated or malformed binary STL: header says " + std::to_string(nf) +
             " facets (" + std::to_string(expect) + " bytes) but the file has " +
             std::to_string(size) + " bytes");
  std::vector<double> tri;
  tri.reserve(9 * (size_t) nf);
  for (uint32_t f = 0; f < nf; f++) {
    const unsigned char *r = p + 84 + 50 * (size_t) f;
    double nrm[3], v[9];
    for (int k = 0; k < 3; k++) nrm[k] = get_f32(r + 4 * k);
    for (int k = 0; k < 9; k++) v[k] = get_f32(r + 12 + 4 * k);
    for (int k = 0; k < 9; k++)
      if (!std::isfinite(v[k])) fail(file, "facet " + std::to_string(f) + " has a non-finite vertex");
    if (!(std::isfinite(nrm[0]) && std::isfinite(nrm[1]) && std::isfinite(nrm[2])))
      nrm[0] = nrm[1] = nrm[2] = 0.0;
    add_facet(file, f, nrm, v, tf, tri);
  }
  return tri;
}

std::vector<double> read_ascii(const std::string &file, const std::string &data,
                               const StlTransform &tf)
{
  Tokens t(data);
  std::string tok;
  int line = 0;
  auto bad = [&](const std::string &what) {
    fail(file, "line " + std::to_string(line) + ": " + what);
  };
  auto expect = [&](const char *kw) {
    if (!t.next(tok, line)) {
      line = t.line;
      bad(std::string("unexpected end of file, expected '") + kw + "'");
    }
    if (!iequal(tok, kw)) bad(std::string("expected '") + kw + "', got '" + tok + "'");
  };
  auto number = [&](const char *what) {
    if (!t.next(tok, line)) {
      line = t.line;
      bad(std::string("unexpected end of file, expected a number (") + what + ")");
    }
    char *end = nullptr;
    errno = 0;
    const double x = strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(x) || errno == ERANGE)
      bad(std::string("expected a number (") + what + "), got '" + tok + "'");
    return x;
  };

  std::vector<double> tri;
  size_t nfacet = 0;
  expect("solid");
  t.skip_line();    // solid name
  while (true) {
    if (!t.next(tok, line)) break;    // tolerate a missing endsolid after whole facets
    if (iequal(tok, "endsolid")) {
      t.skip_line();
      if (!t.next(tok, line)) break;
      if (!iequal(tok, "solid")) bad("expected 'solid' or end of file, got '" + tok + "'");
      t.skip_line();
      continue;
    }
    if (!iequal(tok, "facet")) bad("expected 'facet' or 'endsolid', got '" + tok + "'");
    double nrm[3], v[9];
    expect("normal");
    for (int k = 0; k < 3; k++) nrm[k] = number("normal");
    expect("outer");
    expect("loop");
    for (int m = 0; m < 3; m++) {
      expect("vertex");
      for (int k = 0; k < 3; k++) v[3 * m + k] = number("vertex");
    }
    expect("endloop");
    expect("endfacet");
    add_facet(file, nfacet++, nrm, v, tf, tri);
  }
  if (nfacet == 0) fail(file, "no facets");
  return tri;
}

void check_elem(const std::vector<double> &e, int nvert, const char *who)
{
  if (nvert != 2 && nvert != 3)
    throw std::invalid_argument(std::string(who) + ": nvert must be 2 or 3");
  if (e.size() % (size_t) (3 * nvert))
    throw std::invalid_argument(std::string(who) + ": element array size is not a multiple of " +
                                std::to_string(3 * nvert));
}

// weld: an id per vertex reference (3 doubles each) of the element array, equal for equal
// coordinates (sort the references)
std::vector<long> weld_vertices(const std::vector<double> &pts)
{
  const size_t nv = pts.size() / 3;
  std::vector<size_t> order(nv);
  for (size_t k = 0; k < nv; k++) order[k] = k;
  auto less = [&](size_t a, size_t b) {
    return std::lexicographical_compare(&pts[3 * a], &pts[3 * a + 3], &pts[3 * b], &pts[3 * b + 3]);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<long> id(nv);
  long next = -1;
  for (size_t k = 0; k < nv; k++) {
    if (k == 0 || less(order[k - 1], order[k])) next++;
    id[order[k]] = next;
  }
  return id;
}

std::ofstream open_out(const std::string &file, bool binary)
{
  std::ofstream out(file, binary ? std::ios::binary : std::ios::out);
  if (!out) throw std::runtime_error("cannot write '" + file + "': " + strerror(errno));
  return out;
}

}    // namespace

/* ---------------------------------------------------------------------- */

void StlTransform::set_axis_angle(const double *axis, double angle_deg)
{
  const double l = len3(axis);
  if (!(l > 0.0)) throw std::invalid_argument("STL rotation: zero rotation axis");
  const double u[3] = {axis[0] / l, axis[1] / l, axis[2] / l};
  rotation_matrix(u, angle_deg * DEG, rot);    // Rodrigues, the rotating tool's (sphcut_contact_step.h)
}

void StlTransform::set_euler_zyx(double az_deg, double ay_deg, double ax_deg)
{
  const double cz = cos(az_deg * DEG), sz = sin(az_deg * DEG);
  const double cy = cos(ay_deg * DEG), sy = sin(ay_deg * DEG);
  const double cx = cos(ax_deg * DEG), sx = sin(ax_deg * DEG);
  const double rz[9] = {cz, -sz, 0.0, sz, cz, 0.0, 0.0, 0.0, 1.0};
  const double ry[9] = {cy, 0.0, sy, 0.0, 1.0, 0.0, -sy, 0.0, cy};
  const double rx[9] = {1.0, 0.0, 0.0, 0.0, cx, -sx, 0.0, sx, cx};
  double t[9];
  mat_mul(rz, ry, t);
  mat_mul(t, rx, rot);
}

void StlTransform::apply(const double *x, double *y) const
{
  for (int a = 0; a < 3; a++)
    y[a] = scale * (rot[3 * a] * x[0] + rot[3 * a + 1] * x[1] + rot[3 * a + 2] * x[2]) + shift[a];
}

bool is_directory(const std::string &path)
{
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

/* ---------------------------------------------------------------------- */

std::vector<double> read_stl(const std::string &file, const StlTransform &tf)
{
  if (!(tf.scale > 0.0) || !std::isfinite(tf.scale))
    fail(file, "scale must be positive (got " + std::to_string(tf.scale) + ")");
  if (is_directory(file)) fail(file, "is a directory, not a file");
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, std::string("cannot open (") + strerror(errno) + ")");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) fail(file, "read error");
  const std::string data = ss.str();
  if (data.empty()) fail(file, "empty file (no facets)");

  // binary if the size matches the binary header's facet count
  if (data.size() >= 84) {
    const uint32_t nf = get_u32((const unsigned char *) data.data() + 80);
    if (data.size() == 84 + 50 * (size_t) nf) return read_binary(file, data, tf);
  }
  // ASCII: starts with "solid" (after blanks) and is text
  size_t b = 0;
  while (b < data.size() && isspace((unsigned char) data[b])) b++;
  bool ascii = data.size() - b >= 5 && iequal(data.substr(b, 5), "solid");
  const size_t nscan = std::min(data.size(), (size_t) 4096);
  for (size_t i = 0; ascii && i < nscan; i++) {
    const unsigned char ch = (unsigned char) data[i];
    if (ch == 0 || (ch < 32 && !isspace(ch))) ascii = false;
  }
  if (ascii) return read_ascii(file, data, tf);
  return read_binary(file, data, tf);
}

MeshClosure mesh_closure(const std::vector<double> &tri)
{
  check_elem(tri, 3, "mesh_closure");
  MeshClosure out;
  const size_t nv = tri.size() / 3;
  const std::vector<long> id = weld_vertices(tri);
  // directed edges as (low id, high id, +1 if low -> high else -1), sorted
  struct Edge {
    long a, b;
    int dir;
    size_t ref;    // vertex reference of its start, for the message
  };
  std::vector<Edge> edges;
  edges.reserve(nv);
  for (size_t f = 0; f < nv / 3; f++)
    for (int e = 0; e < 3; e++) {
      const size_t r0 = 3 * f + e, r1 = 3 * f + (e + 1) % 3;
      const long i = id[r0], j = id[r1];
      if (i == j) continue;
      edges.push_back(i < j ? Edge{i, j, 1, r0} : Edge{j, i, -1, r1});
    }
  std::sort(edges.begin(), edges.end(),
            [](const Edge &p, const Edge &q) { return p.a < q.a || (p.a == q.a && p.b < q.b); });
  for (size_t k = 0; k < edges.size();) {
    size_t m = k;
    int uses = 0, balance = 0;
    for (; m < edges.size() && edges[m].a == edges[k].a && edges[m].b == edges[k].b; m++) {
      uses++;
      balance += edges[m].dir;
    }
    if (uses == 1 || balance != 0) {
      const bool first = out.open_edges == 0 && out.inconsistent_edges == 0;
      if (uses == 1) out.open_edges++;
      else out.inconsistent_edges++;
      if (first) {
        // the edge's two end points: the start reference and the next vertex of its facet
        const size_t r = edges[k].ref, f = r / 3, rn = 3 * f + (r % 3 + 1) % 3;
        for (int c = 0; c < 3; c++) {
          out.edge[c] = tri[3 * r + c];
          out.edge[3 + c] = tri[3 * rn + c];
        }
      }
    }
    k = m;
  }
  return out;
}

double mesh_volume(const std::vector<double> &tri)
{
  check_elem(tri, 3, "mesh_volume");
  if (tri.empty()) return 0.0;
  const double *o = tri.data();    // about the first vertex: no cancellation far from the origin
  double vol = 0.0;
  for (size_t f = 0; f < tri.size() / 9; f++) {
    const double *v = tri.data() + 9 * f;
    double a[3], b[3], c[3], bc[3];
    sub3(v, o, a);
    sub3(v + 3, o, b);
    sub3(v + 6, o, c);
    cross3(b, c, bc);
    vol += dot3(a, bc);
  }
  return vol / 6.0;
}

void require_closed_mesh(const std::string &file, const std::vector<double> &tri)
{
  const MeshClosure c = mesh_closure(tri);
  if (c.closed()) {
    // closed and consistent, but the facets may all be turned inward (a negative volume): the
    // particles outside would be taken as inside (issue 23)
    const double diag = bounding_diagonal(tri);
    const double vol = mesh_volume(tri);
    if (vol < -1.0e-12 * diag * diag * diag)
      fail(file, "the closed mesh encloses a negative volume (" + fmtg(vol) +
                 "): its facet normals point inward (reverse the vertex order of every facet)");
    if (!(vol > 1.0e-12 * diag * diag * diag))
      fail(file, "the closed mesh encloses no volume (" + fmtg(vol) + ", bounding-box diagonal " + fmtg(diag) +
                 "): the tool must be the surface of a solid");
    return;
  }
  std::string what = "the mesh is not closed: ";
  if (c.open_edges)
    what += std::to_string(c.open_edges) + " edge(s) belong to one facet only";
  if (c.inconsistent_edges)
    what += std::string(c.open_edges ? ", " : "") + std::to_string(c.inconsistent_edges) +
            " edge(s) join facets of opposite winding (a facet turned inside out)";
  what += ", e.g. " + fmt3(c.edge) + "-" + fmt3(c.edge + 3) +
          "; the tool must be the closed surface of a solid (behind an open sheet particles are "
          "pushed through it)";
  fail(file, what);
}

void write_stl_ascii(const std::string &file, const std::vector<double> &tri, const std::string &name)
{
  check_elem(tri, 3, "write_stl_ascii");
  std::ofstream out = open_out(file, false);
  char buf[256];
  out << "solid " << name << "\n";
  for (size_t f = 0; f < tri.size() / 9; f++) {
    const double *v = tri.data() + 9 * f;
    double n[3];
    if (!(triangle_normal(v, v + 3, v + 6, n) > 0.0)) n[0] = n[1] = n[2] = 0.0;
    snprintf(buf, sizeof(buf), "  facet normal %.17g %.17g %.17g\n", n[0], n[1], n[2]);
    out << buf << "    outer loop\n";
    for (int m = 0; m < 3; m++) {
      snprintf(buf, sizeof(buf), "      vertex %.17g %.17g %.17g\n", v[3 * m], v[3 * m + 1],
               v[3 * m + 2]);
      out << buf;
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid " << name << "\n";
  if (!out) throw std::runtime_error("cannot write '" + file + "'");
}

void write_stl_binary(const std::string &file, const std::vector<double> &tri, const std::string &header)
{
  check_elem(tri, 3, "write_stl_binary");
  const size_t nf = tri.size() / 9;
  std::vector<unsigned char> buf(84 + 50 * nf, 0);
  memcpy(buf.data(), header.data(), std::min(header.size(), (size_t) 80));
  put_u32(buf.data() + 80, (uint32_t) nf);
  for (size_t f = 0; f < nf; f++) {
    const double *v = tri.data() + 9 * f;
    unsigned char *r = buf.data() + 84 + 50 * f;
    double n[3];
    if (!(triangle_normal(v, v + 3, v + 6, n) > 0.0)) n[0] = n[1] = n[2] = 0.0;
    for (int k = 0; k < 3; k++) put_f32(r + 4 * k, n[k]);
    for (int k = 0; k < 9; k++) put_f32(r + 12 + 4 * k, v[k]);
  }
  std::ofstream out = open_out(file, true);
  out.write((const char *) buf.data(), (std::streamsize) buf.size());
  if (!out) throw std::runtime_error("cannot write '" + file + "'");
}

void write_vtk(const std::string &file, const std::vector<double> &elem, int nvert,
               const std::vector<std::string> &cell_names, const std::vector<double> &cell_values)
{
  check_elem(elem, nvert, "write_vtk");
  const size_t ne = elem.size() / (3 * nvert);
  std::ofstream out = open_out(file, false);
  char buf[256];
  out << "# vtk DataFile Version 3.0\nsphcut tool geometry\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << ne * nvert << " double\n";
  for (size_t i = 0; i < ne * nvert; i++) {
    snprintf(buf, sizeof(buf), "%.17g %.17g %.17g\n", elem[3 * i], elem[3 * i + 1], elem[3 * i + 2]);
    out << buf;
  }
  out << "CELLS " << ne << " " << ne * (nvert + 1) << "\n";
  for (size_t e = 0; e < ne; e++) {
    out << nvert;
    for (int m = 0; m < nvert; m++) out << " " << e * nvert + m;
    out << "\n";
  }
  // VTK cell types: 5 triangle, 3 line
  out << "CELL_TYPES " << ne << "\n";
  for (size_t e = 0; e < ne; e++) out << (nvert == 3 ? "5\n" : "3\n");
  out << "CELL_DATA " << ne << "\nVECTORS normal double\n";
  for (size_t e = 0; e < ne; e++) {
    const double *v = elem.data() + 3 * nvert * e;
    double n[3];
    if (nvert == 3) triangle_normal(v, v + 3, v + 6, n);
    else segment_normal(v, v + 3, n);
    snprintf(buf, sizeof(buf), "%.17g %.17g %.17g\n", n[0], n[1], n[2]);
    out << buf;
  }
  const size_t nc = cell_names.size();
  if (nc && cell_values.size() != ne * nc)
    throw std::invalid_argument("write_vtk: " + std::to_string(cell_values.size()) + " cell values for " +
                                std::to_string(ne) + " cells and " + std::to_string(nc) + " arrays");
  for (size_t c = 0; c < nc; c++) {
    out << "SCALARS " << cell_names[c] << " double 1\nLOOKUP_TABLE default\n";
    for (size_t e = 0; e < ne; e++) {
      snprintf(buf, sizeof(buf), "%.17g\n", cell_values[e * nc + c]);
      out << buf;
    }
  }
  if (!out) throw std::runtime_error("cannot write '" + file + "'");
}

/* ---------------------------------------------------------------------- */

std::vector<double> make_cutting_insert(const InsertParams &p, int dim, std::vector<int> *tags)
{
  const std::string who = "cutting insert: ";
  if (dim != 2 && dim != 3) throw std::invalid_argument(who + "dim must be 2 or 3");
  if (!(p.clearance_angle >= 0.0 && p.clearance_angle < 90.0))
    throw std::invalid_argument(who + "clearance angle must be in [0, 90) degrees");
  if (!(p.rake_angle > -90.0 && p.rake_angle + p.clearance_angle < 90.0))
    throw std::invalid_argument(who + "wedge angle 90 - alpha - gamma must be positive "
                                "(and gamma > -90 degrees)");
  if (!(p.edge_radius >= 0.0)) throw std::invalid_argument(who + "edge radius must be >= 0");
  if (!(p.rake_length > 0.0 && p.flank_length > 0.0))
    throw std::invalid_argument(who + "rake and flank lengths must be positive");
  if (dim == 3 && !(p.width > 0.0)) throw std::invalid_argument(who + "width must be positive");
  if (p.arc_segments < 1) throw std::invalid_argument(who + "arc_segments must be >= 1");
  if (p.face_segments < 1) throw std::invalid_argument(who + "face_segments must be >= 1");
  if (!(p.land >= 0.0) || std::isinf(p.land)) {
    char v[32];
    snprintf(v, sizeof(v), "%g", p.land);
    throw std::invalid_argument(who + "land must be >= 0 and finite, got " + v);
  }

  const double g = p.rake_angle * DEG, a = p.clearance_angle * DEG, r = p.edge_radius;
  const double nr[2] = {-cos(g), sin(g)};     // rake outward normal
  const double tr[2] = {sin(g), cos(g)};      // up the rake face
  const double nf[2] = {sin(a), -cos(a)};     // flank outward normal
  const double tf[2] = {cos(a), sin(a)};      // back along the flank

  // section outline, counter-clockwise: rake end, rake tangent point,
  // arc (normal angle 180-g .. 270 (tip) .. 270+a), flank tangent point, flank end
  std::vector<double> px, py;
  std::vector<int> ptag;    // tag of the outline edge starting at this vertex
  const double Tr[2] = {r * nr[0], r + r * nr[1]};
  const double Tf[2] = {r * nf[0], r + r * nf[1]};
  px.push_back(Tr[0] + p.rake_length * tr[0]);
  py.push_back(Tr[1] + p.rake_length * tr[1]);
  ptag.push_back(INSERT_RAKE);
  px.push_back(Tr[0]);
  py.push_back(Tr[1]);
  if (r > 0.0) {
    ptag.push_back(INSERT_EDGE);
    const double part1 = 90.0 + p.rake_angle, part2 = p.clearance_angle;
    const int nseg = p.arc_segments;
    int n2 = 0;
    if (part2 > 0.0 && p.land == 0.0) {
      n2 = (int) std::lround(nseg * part2 / (part1 + part2));
      n2 = std::max(1, std::min(n2, nseg - 1));
    }
    const int n1 = std::max(1, nseg - n2);
    const double th0 = (180.0 - p.rake_angle) * DEG;
    for (int k = 1; k <= n1; k++) {
      if (k == n1) {    // the tip, exactly at the origin
        px.push_back(0.0);
        py.push_back(0.0);
      } else {
        const double th = th0 + k * (part1 * DEG) / n1;
        px.push_back(r * cos(th));
        py.push_back(r + r * sin(th));
      }
      ptag.push_back(INSERT_EDGE);
    }
    for (int k = 1; k <= n2; k++) {
      if (k == n2) {
        px.push_back(Tf[0]);
        py.push_back(Tf[1]);
      } else {
        const double th = 1.5 * 3.14159265358979323846 + k * (part2 * DEG) / n2;
        px.push_back(r * cos(th));
        py.push_back(r + r * sin(th));
      }
      ptag.push_back(INSERT_EDGE);
    }
    ptag.back() = INSERT_FLANK;    // edge from the flank tangent point (with a land: from the tip)
  } else {
    ptag.push_back(INSERT_FLANK);
  }
  // a flank wear land: the arc's part behind the tip (r (1 - cos alpha) high) is worn away and the
  // flank starts after a flat of width land at the tip's height, tangent to the arc at the tip
  if (p.land > 0.0) {
    px.push_back(p.land);
    py.push_back(0.0);
    ptag.push_back(INSERT_FLANK);
  }
  px.push_back(px.back() + p.flank_length * tf[0]);
  py.push_back(py.back() + p.flank_length * tf[1]);
  ptag.push_back(INSERT_BACK);
  if (p.face_segments > 1) {
    // rake and flank faces split into face_segments equal parts (per-facet tool fields along them)
    std::vector<double> qx, qy;
    std::vector<int> qtag;
    const int n0 = (int) px.size();
    for (int i = 0; i < n0; i++) {
      qx.push_back(px[i]);
      qy.push_back(py[i]);
      qtag.push_back(ptag[i]);
      if (ptag[i] != INSERT_RAKE && ptag[i] != INSERT_FLANK) continue;
      const int j = (i + 1) % n0;
      for (int k = 1; k < p.face_segments; k++) {
        const double s = (double) k / p.face_segments;
        qx.push_back(px[i] + s * (px[j] - px[i]));
        qy.push_back(py[i] + s * (py[j] - py[i]));
        qtag.push_back(ptag[i]);
      }
    }
    px.swap(qx);
    py.swap(qy);
    ptag.swap(qtag);
  }
  const int nv = (int) px.size();

  std::vector<double> out;
  if (tags) tags->clear();
  if (dim == 2) {
    for (int i = 0; i < nv; i++) {
      const int j = (i + 1) % nv;
      const double s[6] = {px[i], py[i], 0.0, px[j], py[j], 0.0};
      out.insert(out.end(), s, s + 6);
      if (tags) tags->push_back(ptag[i]);
    }
    return out;
  }

  const double z0 = -0.5 * p.width, z1 = 0.5 * p.width;
  auto add = [&](const double *A, const double *B, const double *C, int tag) {
    out.insert(out.end(), A, A + 3);
    out.insert(out.end(), B, B + 3);
    out.insert(out.end(), C, C + 3);
    if (tags) tags->push_back(tag);
  };
  // side faces: outline edge i->j extruded along +z, normal (dy, -dx, 0)
  for (int i = 0; i < nv; i++) {
    const int j = (i + 1) % nv;
    const double a0[3] = {px[i], py[i], z0}, a1[3] = {px[i], py[i], z1};
    const double b0[3] = {px[j], py[j], z0}, b1[3] = {px[j], py[j], z1};
    add(a0, b0, b1, ptag[i]);
    add(a0, b1, a1, ptag[i]);
  }
  // end caps: fan around the vertex centroid (inside the convex section)
  double cx = 0.0, cy = 0.0;
  for (int i = 0; i < nv; i++) {
    cx += px[i] / nv;
    cy += py[i] / nv;
  }
  const double c0[3] = {cx, cy, z0}, c1[3] = {cx, cy, z1};
  for (int i = 0; i < nv; i++) {
    const int j = (i + 1) % nv;
    const double a0[3] = {px[i], py[i], z0}, a1[3] = {px[i], py[i], z1};
    const double b0[3] = {px[j], py[j], z0}, b1[3] = {px[j], py[j], z1};
    add(c1, a1, b1, INSERT_SIDE);    // +z
    add(c0, b0, a0, INSERT_SIDE);    // -z
  }
  return out;
}

/* ---------------------------------------------------------------------- */

std::vector<double> stl_section_z0(const std::string &file, const std::vector<double> &tri)
{
  check_elem(tri, 3, "stl_section_z0");
  std::vector<double> seg;
  for (size_t t = 0; t + 9 <= tri.size(); t += 9) {
    const double *v = &tri[t];
    double pts[2][3];
    int np = 0;
    for (int e = 0; e < 3 && np < 2; e++) {
      const double *a = v + 3 * e, *b = v + 3 * ((e + 1) % 3);
      if ((a[2] < 0.0) == (b[2] < 0.0)) continue;
      // from the end below the plane: the neighbouring facet, which runs the edge the other
      // way, gets the same point to the bit
      if (b[2] < 0.0) std::swap(a, b);
      const double s = b[2] == 0.0 ? 1.0 : a[2] / (a[2] - b[2]);
      for (int k = 0; k < 2; k++) pts[np][k] = s == 1.0 ? b[k] : a[k] + s * (b[k] - a[k]);
      pts[np][2] = 0.0;
      np++;
    }
    if (np < 2 || (pts[0][0] == pts[1][0] && pts[0][1] == pts[1][1])) continue;
    double nt[3];
    triangle_normal(v, v + 3, v + 6, nt);
    // segment a->b has outward normal (dy, -dx): order the points accordingly
    const double dxs = pts[1][0] - pts[0][0], dys = pts[1][1] - pts[0][1];
    const int flip = dys * nt[0] - dxs * nt[1] < 0.0;
    const double *p0 = flip ? pts[1] : pts[0], *p1 = flip ? pts[0] : pts[1];
    seg.insert(seg.end(), p0, p0 + 3);
    seg.insert(seg.end(), p1, p1 + 3);
  }
  if (seg.empty()) fail(file, "no facet crosses the plane z = 0 (2D section is empty)");
  return seg;
}

void bounding_box(const std::vector<double> &pts, double *lo, double *hi)
{
  for (int k = 0; k < 3; k++) lo[k] = hi[k] = pts.size() < 3 ? 0.0 : pts[k];
  for (size_t i = 0; i + 3 <= pts.size(); i += 3)
    for (int k = 0; k < 3; k++) {
      lo[k] = std::min(lo[k], pts[i + k]);
      hi[k] = std::max(hi[k], pts[i + k]);
    }
}

double box_diagonal(const double *lo, const double *hi)
{
  return sqrt(sq(hi[0] - lo[0]) + sq(hi[1] - lo[1]) + sq(hi[2] - lo[2]));
}

double bounding_diagonal(const std::vector<double> &pts)
{
  double lo[3], hi[3];
  bounding_box(pts, lo, hi);    // (all 0 if empty)
  return box_diagonal(lo, hi);
}

std::vector<double> pseudo_normals(const std::vector<double> &elem, int nvert)
{
  check_elem(elem, nvert, "pseudo_normals");
  const size_t stride = 3 * nvert, ne = elem.size() / stride;
  const int nf = tri_bin_pnorm_stride(nvert) / 3;    // features per element
  const std::vector<long> id = weld_vertices(elem);
  const size_t nid = id.empty() ? 0 : (size_t) *std::max_element(id.begin(), id.end()) + 1;
  // face normals; every feature starts with its element's (the fallback)
  std::vector<double> fn(3 * ne), pn(3 * nf * ne);
  for (size_t e = 0; e < ne; e++) {
    const double *v = elem.data() + stride * e;
    if (nvert == 3) triangle_normal(v, v + 3, v + 6, &fn[3 * e]);
    else segment_normal(v, v + 3, &fn[3 * e]);
    for (int f = 0; f < nf; f++)
      for (int k = 0; k < 3; k++) pn[3 * (nf * e + f) + k] = fn[3 * e + k];
  }
  // the sum at a feature replaces the fallback unless it vanishes (a fin)
  auto put = [&](double *dst, const double *sum) {
    const double l = len3(sum);
    if (l > 1.0e-12)
      for (int k = 0; k < 3; k++) dst[k] = sum[k] / l;
  };
  std::vector<double> vsum(3 * nid, 0.0);
  std::vector<char> vok(nid, 1);
  if (nvert == 2) {
    // a 2D vertex joins one segment that ends there (as its B) and one that starts there (A)
    std::vector<int> nin(nid, 0), nout(nid, 0);
    for (size_t e = 0; e < ne; e++) {
      nout[id[2 * e]]++;
      nin[id[2 * e + 1]]++;
      for (int m = 0; m < 2; m++)
        for (int k = 0; k < 3; k++) vsum[3 * id[2 * e + m] + k] += fn[3 * e + k];
    }
    for (size_t e = 0; e < ne; e++)
      for (int m = 0; m < 2; m++) {
        const long i = id[2 * e + m];
        if (nin[i] == 1 && nout[i] == 1) put(&pn[3 * (2 * e + m)], &vsum[3 * i]);
      }
    return pn;
  }
  // triangles: the angle-weighted vertex sums
  for (size_t e = 0; e < ne; e++) {
    const double *v = elem.data() + 9 * e;
    for (int m = 0; m < 3; m++) {
      double u[3], w[3];
      sub3(v + 3 * ((m + 1) % 3), v + 3 * m, u);
      sub3(v + 3 * ((m + 2) % 3), v + 3 * m, w);
      const double lu = len3(u), lw = len3(w);
      if (!(lu > 0.0 && lw > 0.0)) continue;
      const double ang = acos(std::max(-1.0, std::min(1.0, dot3(u, w) / (lu * lw))));
      for (int k = 0; k < 3; k++) vsum[3 * id[3 * e + m] + k] += ang * fn[3 * e + k];
    }
  }
  // edges: (low id, high id, direction, element, local edge), sorted; a manifold edge is used
  // twice, once in each direction
  struct Edge {
    long a, b;
    int dir;
    size_t e;
    int m;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * ne);
  for (size_t e = 0; e < ne; e++)
    for (int m = 0; m < 3; m++) {
      const long i = id[3 * e + m], j = id[3 * e + (m + 1) % 3];
      edges.push_back(i < j ? Edge{i, j, 1, e, m} : Edge{j, i, -1, e, m});
    }
  std::sort(edges.begin(), edges.end(),
            [](const Edge &p, const Edge &q) { return p.a < q.a || (p.a == q.a && p.b < q.b); });
  for (size_t k = 0; k < edges.size();) {
    size_t m = k;
    while (m < edges.size() && edges[m].a == edges[k].a && edges[m].b == edges[k].b) m++;
    const Edge &p = edges[k];
    if (m - k == 2 && p.a != p.b && p.dir + edges[k + 1].dir == 0) {
      double sum[3];
      for (int c = 0; c < 3; c++) sum[c] = fn[3 * p.e + c] + fn[3 * edges[k + 1].e + c];
      for (size_t r = k; r < m; r++) put(&pn[3 * (6 * edges[r].e + edges[r].m)], sum);
    } else {
      vok[p.a] = vok[p.b] = 0;    // a border or non-manifold edge: its ends keep face normals
    }
    k = m;
  }
  for (size_t e = 0; e < ne; e++)
    for (int m = 0; m < 3; m++) {
      const long i = id[3 * e + m];
      if (vok[i]) put(&pn[3 * (6 * e + 3 + m)], &vsum[3 * i]);
    }
  return pn;
}

/* ---------------------------------------------------------------------- */

TriBinView TriBins::view() const
{
  TriBinView v;
  v.nvert = nvert;
  v.nelem = (int) (elem.size() / (3 * nvert));
  v.elem = elem.data();
  v.sphere = sphere.data();
  for (int k = 0; k < 3; k++) {
    v.lo[k] = lo[k];
    v.n[k] = n[k];
  }
  v.size = size;
  v.start = start.data();
  v.index = index.data();
  v.pnorm = pnorm.empty() ? nullptr : pnorm.data();
  v.halo = halo;
  return v;
}

void tri_bin_build(const std::vector<double> &elem, int nvert, double bin_size, TriBins &bins,
                   long max_bins)
{
  check_elem(elem, nvert, "tri_bin_build");
  if (!(bin_size > 0.0)) throw std::invalid_argument("tri_bin_build: bin size must be positive");
  const int stride = 3 * nvert, nd = nvert == 3 ? 3 : 2;
  const size_t ne = elem.size() / stride;
  bins.nvert = nvert;
  bins.elem = elem;
  if (nvert == 2)
    for (size_t e = 0; e < ne; e++) bins.elem[stride * e + 2] = bins.elem[stride * e + 5] = 0.0;
  bins.pnorm = pseudo_normals(bins.elem, nvert);

  // embedded spheres: vertex centroid, radius enclosing all vertices
  bins.sphere.assign(4 * ne, 0.0);
  double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0};
  for (size_t e = 0; e < ne; e++) {
    const double *v = bins.elem.data() + stride * e;
    double *s = bins.sphere.data() + 4 * e;
    for (int m = 0; m < nvert; m++)
      for (int k = 0; k < 3; k++) s[k] += v[3 * m + k] / nvert;
    double r2 = 0.0;
    for (int m = 0; m < nvert; m++) {
      r2 = std::max(r2, sq(v[3 * m] - s[0]) + sq(v[3 * m + 1] - s[1]) + sq(v[3 * m + 2] - s[2]));
      for (int k = 0; k < 3; k++) {
        if ((e == 0 && m == 0) || v[3 * m + k] < lo[k]) lo[k] = v[3 * m + k];
        if ((e == 0 && m == 0) || v[3 * m + k] > hi[k]) hi[k] = v[3 * m + k];
      }
    }
    s[3] = sqrt(r2) * (1.0 + 1.0e-12);
  }

  // grid: the tool's box and one bin around it, enlarging the bins while there would be too many
  double size = bin_size;
  long nbin = 1;
  while (true) {
    nbin = 1;
    for (int k = 0; k < 3; k++) {
      bins.n[k] = k < nd ? std::max(1, (int) std::ceil((hi[k] - lo[k]) / size)) + 2 : 1;
      nbin *= bins.n[k];
    }
    if (ne == 0) bins.n[0] = bins.n[1] = bins.n[2] = nbin = 1;
    if (nbin <= max_bins) break;
    size *= 1.01 * std::pow((double) nbin / (double) max_bins, 1.0 / nd);
  }
  bins.size = size;
  bins.halo = ne > 0 ? size : 0.0;
  for (int k = 0; k < 3; k++) {
    bins.lo[k] = k < nd ? lo[k] - size : 0.0;
    bins.box_lo[k] = lo[k];
    bins.box_hi[k] = hi[k];
  }

  // element e goes into each bin whose box, grown by halo (and a pad), its bounding box overlaps
  // and its plane (line) crosses: every element within halo of the bin, and some farther (the
  // grown box is a cube, not a ball); two passes: count, then fill
  const double scale = std::max(std::fabs(lo[0]) + std::fabs(hi[0]),
                                std::max(std::fabs(lo[1]) + std::fabs(hi[1]), std::fabs(lo[2]) + std::fabs(hi[2])));
  const double pad = 1.0e-9 * size + 1.0e-13 * scale;
  const double grow = bins.halo + pad;
  bins.start.assign(nbin + 1, 0);
  for (int pass = 0; pass < 2; pass++) {
    std::vector<int> fill;
    if (pass == 1) {
      for (long b = 0; b < nbin; b++) bins.start[b + 1] += bins.start[b];
      bins.index.assign(bins.start[nbin], 0);
      fill.assign(bins.start.begin(), bins.start.end() - 1);
    }
    for (size_t e = 0; e < ne; e++) {
      const double *v = bins.elem.data() + stride * e;
      double nrm[3];
      if (nvert == 3) triangle_normal(v, v + 3, v + 6, nrm);
      else segment_normal(v, v + 3, nrm);
      int ilo[3] = {0, 0, 0}, ihi[3] = {0, 0, 0};
      for (int k = 0; k < nd; k++) {
        double emin = v[k], emax = v[k];
        for (int m = 1; m < nvert; m++) {
          emin = std::min(emin, v[3 * m + k]);
          emax = std::max(emax, v[3 * m + k]);
        }
        ilo[k] = std::max(0, (int) std::floor((emin - grow - bins.lo[k]) / size));
        ihi[k] = std::min(bins.n[k] - 1, (int) std::floor((emax + grow - bins.lo[k]) / size));
      }
      const double hw = 0.5 * size + grow;
      const double reach = hw * (std::fabs(nrm[0]) + std::fabs(nrm[1]) + std::fabs(nrm[2]));
      for (int iz = ilo[2]; iz <= ihi[2]; iz++)
        for (int iy = ilo[1]; iy <= ihi[1]; iy++)
          for (int ix = ilo[0]; ix <= ihi[0]; ix++) {
            const double c[3] = {bins.lo[0] + (ix + 0.5) * size, bins.lo[1] + (iy + 0.5) * size,
                                 nd == 3 ? bins.lo[2] + (iz + 0.5) * size : 0.0};
            double cv[3];
            sub3(c, v, cv);
            if (std::fabs(dot3(nrm, cv)) > reach) continue;
            const long b = ((long) iz * bins.n[1] + iy) * bins.n[0] + ix;
            if (pass == 0) bins.start[b + 1]++;
            else bins.index[fill[b]++] = (int) e;
          }
    }
  }
}

double tool_signed_distance(const TriBins &bins, const double *x, double r0)
{
  const TriBinView g = bins.view();
  if (g.nelem <= 0 || !(r0 > 0.0)) return HUGE_VAL;
  const int nd = g.nvert == 3 ? 3 : 2;
  double diag2 = 0.0;
  for (int k = 0; k < nd; k++) {
    if (x[k] < bins.box_lo[k] || x[k] > bins.box_hi[k]) return HUGE_VAL;    // outside the box of the tool
    diag2 += sq(bins.box_hi[k] - bins.box_lo[k]);
  }
  const double xx[3] = {x[0], x[1], nd == 3 ? x[2] : 0.0};
  for (double r = r0;; r *= 2.0) {
    // the closest element, a FACE hit on ties (as the contact picks it: tri_bin_nearest)
    double q[3];
    int region;
    const int best = tri_bin_nearest(g, x, r, q, region);
    if (best >= 0) {
      double n[3];
      return tri_bin_contact_normal(g, best, xx, q, region, 0, n);
    }
    if (r * r > 4.0 * diag2) return HUGE_VAL;
  }
}

}    // namespace sphcut
