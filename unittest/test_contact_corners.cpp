// Sharp tool corners (issue 23): the side of a particle at an edge or vertex of the tool
// whose angle is below 90 degrees, and the tool files that used to be accepted although every
// particle near them would be taken as inside (facets turned inward, a degenerating scale).
//
// The reference is computed here, independently of sphcut_contact.h: the distance by brute
// force over all facets (projection onto the facet's plane, else its three edges), the side
// by the generalized winding number (the solid angles of the facets seen from the point,
// van Oosterom and Strackee; in 2D the angles of the segments), the normal (p - q)/|p - q|
// turned out of the tool.  Geometries: a tall tetrahedron (apex and base vertices and its
// side edges sharp), a 30-degree wedge (a prism, its apex edge along z; in 2D its section
// with z = 0) and the generated 2D insert with a sharp edge (rake 0, clearance 7: 83
// degrees).
//
// Two levels: the host functions (tool_signed_distance, tool_surface over the bins) on dense
// grids, and the fix on a grid of particles after `run 0`: with sfac 0.25 the contact radius
// is 2h, the search radius, so every particle the search finds is in contact and its normal
// force k (rc - d) gives the signed distance d, its direction the normal (mu 0, at rest).  The
// fix-level tests run on the CPU (test_contact_corners) and with -k on t 2 -sf kk
// (test_contact_corners_kk).  Then a block dropped on the tetrahedron's apex, and the errors.
#include "sphcut_test.h"

#include "sphcut_stl.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

using sphcut_test::Lammps;

namespace {

const double PI = 3.14159265358979323846;
const double RHO = 7800.0, DP = 1.0e-3, H = 1.3e-3;    // hdx 1.3
typedef std::array<double, 3> Vec;

using sphcut_test::num;

Vec sub(const Vec &a, const Vec &b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec &a, const Vec &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec &a, const Vec &b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec &a) { return sqrt(dot(a, a)); }
Vec vert(const std::vector<double> &e, size_t k) { return {e[3 * k], e[3 * k + 1], e[3 * k + 2]}; }

// closest point on segment ab
Vec seg_closest(const Vec &p, const Vec &a, const Vec &b)
{
  const Vec ab = sub(b, a);
  double t = dot(sub(p, a), ab) / dot(ab, ab);
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  return {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
}

// the reference: distance, closest point and side of p against the closed mesh (nvert 3) or
// outline (nvert 2, z ignored)
struct Ref {
  double dist, wind;
  Vec q;
  bool inside() const { return wind > 0.5; }
  double d() const { return inside() ? -dist : dist; }
};

Ref reference(const std::vector<double> &elem, int nvert, Vec p)
{
  Ref r{1.0e300, 0.0, {0.0, 0.0, 0.0}};
  if (nvert == 2) p[2] = 0.0;
  const size_t ne = elem.size() / (3 * nvert);
  for (size_t e = 0; e < ne; e++) {
    const Vec a = vert(elem, nvert * e), b = vert(elem, nvert * e + 1);
    std::vector<Vec> cand;
    if (nvert == 2) {
      cand.push_back(seg_closest(p, a, b));
      const Vec u = sub(a, p), w = sub(b, p);
      r.wind += atan2(u[0] * w[1] - u[1] * w[0], u[0] * w[0] + u[1] * w[1]) / (2.0 * PI);
    } else {
      const Vec c = vert(elem, 3 * e + 2);
      const Vec n = cross(sub(b, a), sub(c, a));
      const double s = dot(sub(p, a), n) / dot(n, n);
      const Vec pp = {p[0] - s * n[0], p[1] - s * n[1], p[2] - s * n[2]};    // projection onto the plane
      // inside the facet: on the inner side of its three edges
      if (dot(cross(sub(b, a), sub(pp, a)), n) >= 0.0 && dot(cross(sub(c, b), sub(pp, b)), n) >= 0.0 &&
          dot(cross(sub(a, c), sub(pp, c)), n) >= 0.0)
        cand.push_back(pp);
      cand.push_back(seg_closest(p, a, b));
      cand.push_back(seg_closest(p, b, c));
      cand.push_back(seg_closest(p, c, a));
      const Vec u = sub(a, p), v = sub(b, p), w = sub(c, p);
      const double lu = norm(u), lv = norm(v), lw = norm(w);
      const double den = lu * lv * lw + dot(u, v) * lw + dot(u, w) * lv + dot(v, w) * lu;
      r.wind += 2.0 * atan2(dot(u, cross(v, w)), den) / (4.0 * PI);
    }
    for (const Vec &q : cand) {
      const double d = norm(sub(p, q));
      if (d < r.dist) {
        r.dist = d;
        r.q = q;
      }
    }
  }
  return r;
}

// the unit normal out of the tool at the closest point
Vec ref_normal(const Ref &r, Vec p, int nvert)
{
  if (nvert == 2) p[2] = 0.0;
  const Vec pq = sub(p, r.q);
  const double s = (r.inside() ? -1.0 : 1.0) / norm(pq);
  return {s * pq[0], s * pq[1], s * pq[2]};
}

// the geometries, closed with outward normals (each facet oriented away from the centroid of
// the convex solid: independent of the winding the code expects)
std::vector<double> convex_facets(const std::vector<Vec> &faces)
{
  Vec c = {0.0, 0.0, 0.0};
  for (const Vec &v : faces)
    for (int k = 0; k < 3; k++) c[k] += v[k] / faces.size();
  std::vector<double> tri;
  for (size_t f = 0; f < faces.size(); f += 3) {
    Vec a = faces[f], b = faces[f + 1], d = faces[f + 2];
    const Vec m = {(a[0] + b[0] + d[0]) / 3, (a[1] + b[1] + d[1]) / 3, (a[2] + b[2] + d[2]) / 3};
    if (dot(cross(sub(b, a), sub(d, a)), sub(m, c)) < 0.0) std::swap(b, d);
    for (const Vec &v : {a, b, d}) tri.insert(tri.end(), v.begin(), v.end());
  }
  return tri;
}

// tetrahedron, apex at `apex` pointing up (+y), base an equilateral triangle of circumradius R
// a height ht below: the apex's facet angles are 19 degrees, its side edges 63 degrees
std::vector<double> tetrahedron(const Vec &apex, double R, double ht)
{
  Vec b[3];
  for (int k = 0; k < 3; k++) {
    const double th = 2.0 * PI * k / 3.0 + 0.3;
    b[k] = {apex[0] + R * cos(th), apex[1] - ht, apex[2] + R * sin(th)};
  }
  return convex_facets({apex, b[0], b[1], apex, b[1], b[2], apex, b[2], b[0], b[0], b[1], b[2]});
}

// wedge of opening angle `deg` (apex edge along z through (0, 0), pointing up, length L),
// extruded over z in [-W, W]
std::vector<double> wedge(double deg, double L, double W)
{
  const double s = L * tan(0.5 * deg * PI / 180.0);
  const Vec a0 = {0, 0, -W}, a1 = {0, 0, W}, l0 = {-s, -L, -W}, l1 = {-s, -L, W}, r0 = {s, -L, -W}, r1 = {s, -L, W};
  return convex_facets({a0, l0, l1, a0, l1, a1, a0, r0, r1, a0, r1, a1, l0, r0, r1, l0, r1, l1,
                        a0, l0, r0, a1, l1, r1});
}

// the generated 2D insert with a sharp edge at the origin (as fix contact/tri-penalty insert)
std::vector<double> sharp_insert_2d()
{
  sphcut::InsertParams ip;
  ip.rake_angle = 0.0;
  ip.clearance_angle = 7.0;
  ip.edge_radius = 0.0;
  ip.rake_length = 5e-3;
  ip.flank_length = 5e-3;
  return sphcut::make_cutting_insert(ip, 2);
}

// grid of points around x0: n per direction (1 in z for 2D), spacing step, slightly off the
// lattice of the geometry (no point on a face or on a Voronoi boundary by construction)
std::vector<Vec> grid(const Vec &x0, int n, double step, int dim)
{
  std::vector<Vec> pts;
  const double off = 0.5 * (n - 1);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      for (int k = 0; k < (dim == 3 ? n : 1); k++)
        pts.push_back({x0[0] + (i - off) * step + 0.0123 * step, x0[1] + (j - off) * step + 0.0371 * step,
                       dim == 3 ? x0[2] + (k - off) * step + 0.0219 * step : 0.0});
  return pts;
}

struct Case {
  const char *what;
  std::vector<double> elem;
  int nvert;
  Vec at;    // the feature
};

std::vector<Case> cases()
{
  const Vec apex = {0.0, 0.0, 0.0};
  const std::vector<double> tet = tetrahedron(apex, 2e-3, 6e-3);
  const Vec base0 = vert(tet, 1);                                   // a base vertex
  const Vec side = {0.5 * base0[0], 0.5 * base0[1], 0.5 * base0[2]};    // middle of a side edge
  return {{"tetrahedron apex", tet, 3, apex},
          {"tetrahedron base vertex", tet, 3, base0},
          {"tetrahedron side edge", tet, 3, side},
          {"30-degree wedge edge", wedge(30.0, 6e-3, 5e-3), 3, {0.0, 0.0, 1e-3}},
          {"2D insert, sharp edge (83 deg)", sharp_insert_2d(), 2, {0.0, 0.0, 0.0}}};
}

}    // namespace

#ifndef SPHCUT_TEST_KOKKOS
/* ----------------------------------------------------------------------
   host level: tool_signed_distance and tool_surface (the contact's search within 2h) against
   the reference on grids around each sharp feature
------------------------------------------------------------------------- */

TEST(SharpCorners, SignedDistanceMatchesWindingNumber)
{
  for (const Case &c : cases()) {
    sphcut::TriBins bins;
    sphcut::tri_bin_build(c.elem, c.nvert, 2.0 * H, bins);
    const sphcut::TriBinView g = bins.view();
    int nchecked = 0, nwrong = 0, nsurf = 0;
    double worst = 0.0, worstn = 0.0;
    const std::vector<Vec> pts = grid(c.at, c.nvert == 3 ? 15 : 41, 0.2 * H, c.nvert == 3 ? 3 : 2);
    for (const Vec &p : pts) {
      const Ref r = reference(c.elem, c.nvert, p);
      if (r.dist < 1e-6 * H) continue;
      nchecked++;
      const double d = sphcut::tool_signed_distance(bins, p.data(), 2.0 * H);
      if ((d < 0.0) != r.inside()) nwrong++;
      if (d != HUGE_VAL) worst = std::max(worst, fabs(d - r.d()));    // HUGE_VAL: outside the bins' box
      if (r.dist < 1.9 * H) {
        double ds, n[3], q[3];
        int region;
        ASSERT_GE(sphcut::tool_surface(g, p.data(), H, ds, n, q, region), 0);
        const Vec nr = ref_normal(r, p, c.nvert);
        worst = std::max(worst, fabs(ds - r.d()));
        worstn = std::max(worstn, norm(sub({n[0], n[1], n[2]}, nr)));
        nsurf++;
      }
    }
    std::printf("[ corners  ] %-30s: %4d points (%4d within 2h), %d on the wrong side, max |d - d_ref| %.2e h, "
                "max |n - n_ref| %.2e\n",
                c.what, nchecked, nsurf, nwrong, worst / H, worstn);
    EXPECT_GT(nsurf, 100) << c.what;
    EXPECT_EQ(nwrong, 0) << c.what;
    EXPECT_LT(worst, 5e-15 * H) << c.what;    // measured 1.0e-15 h
    EXPECT_LT(worstn, 3e-12) << c.what;       // measured 6.0e-13 (points near the surface)
  }
}

/* ----------------------------------------------------------------------
   the pseudo-normals themselves: a box corner (3 faces, each at 90 degrees: (1 1 1)/sqrt 3
   whatever the triangulation), its edges (the bisector), an open sheet (its border keeps the
   face normal), the 2D insert's tip (the bisector of its two segment normals)
------------------------------------------------------------------------- */

TEST(SharpCorners, PseudoNormals)
{
  const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {1.0, 2.0, 3.0};
  const std::vector<double> box = sphcut_test::box_triangles(lo, hi);
  const std::vector<double> pn = sphcut::pseudo_normals(box, 3);
  ASSERT_EQ(pn.size(), 2 * box.size());
  const double r3 = 1.0 / sqrt(3.0), r2 = 1.0 / sqrt(2.0);
  double worst = 0.0;
  for (size_t e = 0; e < box.size() / 9; e++)
    for (int m = 0; m < 3; m++) {
      // vertex m: the corner's diagonal, outward
      const Vec v = vert(box, 3 * e + m);
      const Vec want = {(v[0] > 0.5 ? r3 : -r3), (v[1] > 1.0 ? r3 : -r3), (v[2] > 1.5 ? r3 : -r3)};
      worst = std::max(worst, norm(sub(vert(pn, 6 * e + 3 + m), want)));
      // edge m: on a box edge (two coordinates at a bound) the bisector, else (a face diagonal)
      // the face normal
      const Vec w = vert(box, 3 * e + (m + 1) % 3);
      Vec we = {0.0, 0.0, 0.0};
      int nb = 0;
      for (int k = 0; k < 3; k++)
        if (v[k] == w[k]) {
          we[k] = v[k] == lo[k] ? -1.0 : 1.0;
          nb++;
        }
      for (int k = 0; k < 3; k++) we[k] *= nb == 2 ? r2 : 1.0;
      worst = std::max(worst, norm(sub(vert(pn, 6 * e + m), we)));
    }
  EXPECT_LT(worst, 1e-15);
  // the top face alone (an open sheet): every feature keeps the face normal (0 0 1)
  const std::vector<double> sheet(box.begin() + 18, box.begin() + 36);
  const std::vector<double> ps = sphcut::pseudo_normals(sheet, 3);
  for (size_t k = 0; k < ps.size() / 3; k++) EXPECT_EQ(vert(ps, k), (Vec{0.0, 0.0, 1.0})) << k;
  // 2D insert tip (segment 0 ends there, segment 1 starts there): (n_rake + n_flank)/|..|
  const std::vector<double> seg = sharp_insert_2d();
  const std::vector<double> p2 = sphcut::pseudo_normals(seg, 2);
  const double a = 7.0 * PI / 180.0;
  const Vec sum = {-1.0 + sin(a), -cos(a), 0.0};
  const Vec tip = {sum[0] / norm(sum), sum[1] / norm(sum), 0.0};
  EXPECT_LT(norm(sub(vert(p2, 1), tip)), 1e-15);    // segment 0, vertex B
  EXPECT_LT(norm(sub(vert(p2, 2), tip)), 1e-15);    // segment 1, vertex A
}

/* ----------------------------------------------------------------------
   the 2D section of a rotated STL solid: the segments of neighbouring facets meet at equal
   points (each end is the start of exactly one other segment), so the vertex pseudo-normals
   are found; the outline is counter-clockwise (positive area)
------------------------------------------------------------------------- */

TEST(SharpCorners, SectionSegmentsMeet)
{
  std::vector<double> w = wedge(30.0, 6e-3, 5e-3);
  sphcut::StlTransform tf;
  const double axis[3] = {0.3, 1.0, 0.2};
  tf.set_axis_angle(axis, 17.0);
  for (size_t k = 0; k < w.size(); k += 3) {
    double y[3];
    tf.apply(&w[k], y);
    for (int c = 0; c < 3; c++) w[k + c] = y[c];
  }
  const std::vector<double> seg = sphcut::stl_section_z0("wedge.stl", w);
  const size_t ns = seg.size() / 6;
  EXPECT_GE(ns, 3u);
  double area = 0.0;
  for (size_t i = 0; i < ns; i++) {
    int starts = 0;
    for (size_t j = 0; j < ns; j++)
      if (seg[6 * j] == seg[6 * i + 3] && seg[6 * j + 1] == seg[6 * i + 4]) starts++;
    EXPECT_EQ(starts, 1) << "segment " << i;
    area += 0.5 * (seg[6 * i] * seg[6 * i + 4] - seg[6 * i + 1] * seg[6 * i + 3]);
  }
  EXPECT_GT(area, 0.0);
}

// library level: the volume check and the degenerate facet after a scale
TEST(SharpCorners, InwardAndDegenerateMeshesAtTheLibrary)
{
  const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {1.0, 2.0, 3.0};
  std::vector<double> box = sphcut_test::box_triangles(lo, hi), inward = box;
  for (size_t f = 0; f < inward.size(); f += 9)
    for (int k = 0; k < 3; k++) std::swap(inward[f + 3 + k], inward[f + 6 + k]);
  EXPECT_NEAR(sphcut::mesh_volume(box), 6.0, 1e-14);
  EXPECT_NEAR(sphcut::mesh_volume(inward), -6.0, 1e-14);
  EXPECT_TRUE(sphcut::mesh_closure(inward).closed());
  EXPECT_NO_THROW(sphcut::require_closed_mesh("box.stl", box));
  try {
    sphcut::require_closed_mesh("inward.stl", inward);
    ADD_FAILURE() << "a mesh turned inward passed";
  } catch (std::runtime_error &e) {
    EXPECT_EQ(std::string(e.what()), "STL file 'inward.stl': the closed mesh encloses a negative volume (-6): its "
                                     "facet normals point inward (reverse the vertex order of every facet)");
  }
  // two coincident facets of opposite winding: closed, no volume
  std::vector<double> fin(box.begin(), box.begin() + 9);
  fin.insert(fin.end(), {box[0], box[1], box[2], box[6], box[7], box[8], box[3], box[4], box[5]});
  EXPECT_THROW(sphcut::require_closed_mesh("fin.stl", fin), std::runtime_error);
  sphcut::write_stl_ascii("unit_box.stl", box);
  sphcut::StlTransform tf;
  tf.scale = 1e-30;
  tf.shift[0] = 1e-3;
  try {
    sphcut::read_stl("unit_box.stl", tf);
    ADD_FAILURE() << "scale 1e-30 with a shift passed";
  } catch (std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("STL file 'unit_box.stl': facet 0 is degenerate (zero area) after scale 1e-30"),
              std::string::npos)
        << e.what();
  }
  tf.scale = 1e-3;    // mm to m: fine
  EXPECT_EQ(sphcut::read_stl("unit_box.stl", tf).size(), box.size());
  EXPECT_NEAR(sphcut::bounding_diagonal(box), sqrt(14.0), 1e-15);
}
#endif

/* ----------------------------------------------------------------------
   through the fix: a grid of particles around each sharp feature after run 0, sfac 0.25
   (contact radius 2h): force k (2h - d) along the outward normal, d and n as the reference
------------------------------------------------------------------------- */

TEST(SharpCorners, ContactForceOnAGridAsTheReference)
{
  const double E = 1.0e6, RC = 2.0 * H;
  int icase = 0;
  for (const Case &c : cases()) {
    const int dim = c.nvert == 3 ? 3 : 2;
    const std::string file = "corner" + std::to_string(icase++) + ".stl";
    std::string tool;
    if (dim == 3) {
      sphcut::write_stl_ascii(file, c.elem);    // exact (binary STL is float32)
      tool = "stl " + file;
    } else {
      tool = "insert rake 0 clearance 7 radius 0 rake_length 5e-3 flank_length 5e-3";
    }
    const std::vector<Vec> pts = grid(c.at, dim == 3 ? 9 : 17, 0.4 * H, dim);
    Lammps l;
    l.cmds({"units si", "dimension " + std::to_string(dim), dim == 2 ? "boundary f f p" : "boundary f f f",
            "atom_style atomic", "atom_modify map array",
            std::string("region box block -0.02 0.02 -0.02 0.02 ") + (dim == 2 ? "-0.5e-3 0.5e-3" : "-0.02 0.02"),
            "create_box 1 box"});
    for (const Vec &p : pts)
      l.cmd("create_atoms 1 single " + num(p[0]) + " " + num(p[1]) + " " + num(p[2]) + " units box");
    l.cmds({"mass 1 " + num(dim == 2 ? RHO * DP * DP : RHO * DP * DP * DP), "pair_style sph/jc-thermal",
            "pair_coeff 1 1 rho0 7800 E " + num(E) + " nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal",
            "timestep 1e-7", "fix tool all contact/tri-penalty " + tool + " sfac 0.25 dfac 0 mu 0 onset 0", "run 0"});    // linear spring (onset 0): d = rc - F_N/k
    const double k = dim == 2 ? E : E * DP;
    LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, "tool");
#ifdef SPHCUT_TEST_KOKKOS
    EXPECT_EQ(f->kokkosable, 1);    // the /kk fix (it goes by the CPU style's name)
#endif
    int nchecked = 0, nwrong = 0, ninto = 0;
    double worst = 0.0, worstn = 0.0;
    for (size_t a = 0; a < pts.size(); a++) {
      const Ref r = reference(c.elem, c.nvert, pts[a]);
      if (r.dist > 1.9 * H || r.dist < 1e-6 * H) continue;    // beyond the search, or on the surface
      const double *fc = f->array_atom[l.lmp->atom->map((int) a + 1)];
      const double fl = sqrt(fc[0] * fc[0] + fc[1] * fc[1] + fc[2] * fc[2]);
      nchecked++;
      if (!(fl > 0.0)) {
        nwrong++;
        continue;
      }
      const double d = RC - fc[3] / k;
      const Vec nr = ref_normal(r, pts[a], c.nvert);
      const Vec n = {fc[0] / fl, fc[1] / fl, fc[2] / fl};
      if ((d < 0.0) != r.inside()) nwrong++;
      if (!r.inside() && dot(sub(r.q, pts[a]), {fc[0], fc[1], fc[2]}) > 0.0) ninto++;    // pulled into the tool
      worst = std::max(worst, fabs(d - r.d()));
      worstn = std::max(worstn, norm(sub(n, nr)));
    }
    std::printf("[ corners  ] fix, %-30s: %4d particles within 2h, %d on the wrong side, %d pulled into the tool, "
                "max |d - d_ref| %.2e h, max |n - n_ref| %.2e\n",
                c.what, nchecked, nwrong, ninto, worst / H, worstn);
    EXPECT_GT(nchecked, 50) << c.what;
    EXPECT_EQ(nwrong, 0) << c.what;
    EXPECT_EQ(ninto, 0) << c.what;
    EXPECT_LT(worst, 5e-14 * H) << c.what;    // measured 1.24e-14 h (d = rc - F_N/k)
    EXPECT_LT(worstn, 3e-12) << c.what;       // measured 5.8e-13
  }
}

/* ----------------------------------------------------------------------
   the 2D section of an STL solid at a sharp edge: the 30-degree wedge cut by z = 0, as given
   and tilted (17 degrees about (0.3, 1, 0.2): the crossing points are rounded, and the segments
   of neighbouring facets must still meet for their vertex pseudo-normal to be found).  The
   reference: the section computed here (distance) and the winding number of the 3D mesh (side).
------------------------------------------------------------------------- */

TEST(SharpCorners, SectionOfAnStlWedgeIn2D)
{
  const double E = 1.0e6, RC = 2.0 * H;
  for (double tilt : {0.0, 17.0}) {
    std::vector<double> w3 = wedge(30.0, 6e-3, 5e-3);
    sphcut::StlTransform tf;
    const double axis[3] = {0.3, 1.0, 0.2};
    tf.set_axis_angle(axis, tilt);
    for (size_t k = 0; k < w3.size(); k += 3) {
      double y[3];
      tf.apply(&w3[k], y);
      for (int c = 0; c < 3; c++) w3[k + c] = y[c];
    }
    sphcut::write_stl_ascii("wedge2d.stl", w3);
    std::vector<double> section;    // unoriented segments where the facets cross z = 0
    for (size_t f = 0; f < w3.size(); f += 9) {
      int np = 0;
      for (int e = 0; e < 3; e++) {
        const Vec a = vert(w3, f / 3 + e), b = vert(w3, f / 3 + (e + 1) % 3);
        if ((a[2] < 0.0) == (b[2] < 0.0)) continue;
        const double t = a[2] / (a[2] - b[2]);
        section.insert(section.end(), {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 0.0});
        np++;
      }
      if (np == 1) section.resize(section.size() - 3);
    }
    const std::vector<Vec> pts = grid({0.0, 0.0, 0.0}, 17, 0.4 * H, 2);
    Lammps l;
    l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
            "region box block -0.02 0.02 -0.02 0.02 -0.5e-3 0.5e-3", "create_box 1 box"});
    for (const Vec &p : pts) l.cmd("create_atoms 1 single " + num(p[0]) + " " + num(p[1]) + " 0 units box");
    l.cmds({"mass 1 " + num(RHO * DP * DP), "pair_style sph/jc-thermal",
            "pair_coeff 1 1 rho0 7800 E " + num(E) + " nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal",
            "timestep 1e-7", "fix tool all contact/tri-penalty stl wedge2d.stl sfac 0.25 dfac 0 mu 0 onset 0", "run 0"});
    LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, "tool");
    int nchecked = 0, nwrong = 0;
    double worst = 0.0, worstn = 0.0;
    for (size_t a = 0; a < pts.size(); a++) {
      Ref r = reference(section, 2, pts[a]);
      r.wind = reference(w3, 3, pts[a]).wind;
      if (r.dist > 1.9 * H || r.dist < 1e-6 * H) continue;
      const double *fc = f->array_atom[l.lmp->atom->map((int) a + 1)];
      const double fl = sqrt(fc[0] * fc[0] + fc[1] * fc[1]);
      nchecked++;
      const double d = RC - fc[3] / E;
      if (!(fl > 0.0) || (d < 0.0) != r.inside()) {
        nwrong++;
        continue;
      }
      worst = std::max(worst, fabs(d - r.d()));
      worstn = std::max(worstn, norm(sub({fc[0] / fl, fc[1] / fl, 0.0}, ref_normal(r, pts[a], 2))));
    }
    std::printf("[ corners  ] fix, 2D section of the STL wedge, tilt %2g deg: %d particles within 2h, %d on the wrong "
                "side, max |d - d_ref| %.2e h, max |n - n_ref| %.2e\n",
                tilt, nchecked, nwrong, worst / H, worstn);
    EXPECT_GT(nchecked, 50);
    EXPECT_EQ(nwrong, 0);
    EXPECT_LT(worst, 5e-14 * H);    // measured 3.0e-15 h
    EXPECT_LT(worstn, 3e-12);
  }
}

/* ----------------------------------------------------------------------
   a block of 6^3 elastic particles dropped at 10 m/s on the apex of the tetrahedron (dfac 0,
   mu 0): it must not run away (issue 23: vmax at step 6); energy bounded
------------------------------------------------------------------------- */

TEST(SharpCorners, BlockDroppedOnTetrahedronApex)
{
  sphcut::write_stl_binary("tet.stl", tetrahedron({2.2e-3, -0.8e-3, 2.7e-3}, 4e-3, 8e-3));
  Lammps l;
  l.cmds({"units si", "dimension 3", "boundary f f f", "atom_style atomic", "atom_modify map array",
          "lattice sc 1e-3", "region box block -15 20 -15 20 -15 20", "create_box 1 box",
          "region blk block -0.01 5.01 -0.01 5.01 -0.01 5.01", "create_atoms 1 region blk",
          "mass 1 " + num(RHO * DP * DP * DP), "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 hdx 1.3", "fix sph all sph/jc-thermal cfl 0.3",
          "timestep 1e-8", "velocity all set 0 -10 0 units box", "fix tool all contact/tri-penalty stl tet.stl dfac 0 mu 0",
          "thermo_modify lost error", "variable e equal f_sph[2]+f_sph[3]", "run 0"});
  const double e0 = l.equal("v_e");
  int touched = 0, steps = 0;
  double pmax = 0.0, emax = e0;
  std::string err;
  try {
    for (int k = 0; k < 300; k++) {
      l.cmd("run 10 pre no post no");
      steps += 10;
      pmax = std::max(pmax, l.equal("f_tool[12]"));
      emax = std::max(emax, l.equal("v_e"));
      if (l.equal("f_tool[5]") > 0) touched = 1;
      else if (touched) break;
    }
  } catch (LAMMPS_NS::LAMMPSException &e) {
    err = e.what();
  }
  const double e1 = l.equal("v_e");
  std::printf("[ corners  ] block on the tetrahedron's apex: %d steps, energy change %+.4f %% (max %+.4f %%), "
              "max penetration / rc %.3f%s%s\n",
              steps, 100.0 * (e1 - e0) / e0, 100.0 * (emax - e0) / e0, pmax, err.empty() ? "" : ", error: ",
              err.c_str());
  EXPECT_EQ(err, "");
  EXPECT_EQ(touched, 1);
  EXPECT_LT((emax - e0) / e0, 5e-5);    // measured +1.2e-5 (main: vmax exceeded at step 5)
  EXPECT_LT(pmax, 1.0);                 // no particle centre crosses the surface (measured 0.011)
}

/* ----------------------------------------------------------------------
   tool files that would put particles on the wrong side: every facet turned inward (closed,
   consistent, negative volume) and a scale that makes the facets degenerate
------------------------------------------------------------------------- */

TEST(SharpCorners, InwardAndDegenerateToolsRefused)
{
  const double lo[3] = {-0.01, -0.01, -0.01}, hi[3] = {0.01, 0.0, 0.01};
  std::vector<double> box = sphcut_test::box_triangles(lo, hi), inward = box;
  for (size_t f = 0; f < inward.size(); f += 9)
    for (int k = 0; k < 3; k++) std::swap(inward[f + 3 + k], inward[f + 6 + k]);
  sphcut::write_stl_ascii("inward.stl", inward);
  sphcut::write_stl_binary("box.stl", box);
  for (int dim : {3, 2}) {
    Lammps l;
    l.cmds({"units si", "dimension " + std::to_string(dim), dim == 2 ? "boundary f f p" : "boundary f f f",
            "atom_style atomic", "atom_modify map array",
            std::string("region box block -0.02 0.02 -0.02 0.02 ") + (dim == 2 ? "-0.5e-3 0.5e-3" : "-0.02 0.02"),
            "create_box 1 box", "create_atoms 1 single 0 0.005 0 units box", "mass 1 1e-6",
            "pair_style sph/jc-thermal", "pair_coeff 1 1 rho0 7800 E 1e6 nu 0.3 hdx 1.3",
            "fix sph all sph/jc-thermal", "timestep 1e-7"});
    const std::string fix = "fix tool all contact/tri-penalty stl ";
    EXPECT_TRUE(l.error_contains(fix + "inward.stl", "STL file 'inward.stl': the closed mesh encloses a negative "
                                                     "volume (-4e-06): its facet normals point inward"));
    // the vertices collapse onto the shift: zero area after the scale
    EXPECT_TRUE(l.error_contains(fix + "box.stl scale 1e-30 move 0.001 0 0",
                                 "STL file 'box.stl': facet 0 is degenerate (zero area) after scale 1e-30"));
    // without a shift the facets keep their shape, but the tool is a point to the contact search
    l.cmd(fix + "box.stl scale 1e-30");
    EXPECT_TRUE(l.error_contains("run 0", "Fix contact/tri-penalty: the tool is degenerate at scale 1e-30: it spans "));
    EXPECT_TRUE(l.error_contains("run 0", ", below 1e-6 of the contact search radius 2h = "));
  }
}
