// building blocks of fix contact/tri-penalty (seed 000 sec. 3): closest
// point on triangles/segments, contact normals, penalty + friction force,
// STL/VTK I/O, the cutting insert generator and the contact bins
#include "sphcut_contact.h"
#include "sphcut_stl.h"
#include "sphcut_test.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace sphcut;

namespace {

const double PI = 3.14159265358979323846;

double dist3(const double *a, const double *b)
{
  return sqrt(sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2]));
}

// barycentric coordinates (u, v, w) of q in abc (least squares in the plane)
void barycentric(const double *q, const double *a, const double *b, const double *c, double *bc)
{
  double v0[3], v1[3], v2[3];
  sub3(b, a, v0);
  sub3(c, a, v1);
  sub3(q, a, v2);
  const double d00 = dot3(v0, v0), d01 = dot3(v0, v1), d11 = dot3(v1, v1);
  const double d20 = dot3(v2, v0), d21 = dot3(v2, v1);
  const double den = d00 * d11 - d01 * d01;
  bc[1] = (d11 * d20 - d01 * d21) / den;
  bc[2] = (d00 * d21 - d01 * d20) / den;
  bc[0] = 1.0 - bc[1] - bc[2];
}

// independent exact distance: plane projection if inside (seed eq. 8
// inside-outside test), else the best of the three clamped edges
double reference_distance(const double *p, const double *a, const double *b, const double *c)
{
  double n[3];
  triangle_normal(a, b, c, n);
  double ap[3];
  sub3(p, a, ap);
  const double h = dot3(ap, n);
  double pr[3];
  axpy3(p, -h, n, pr);
  const double *v[4] = {a, b, c, a};
  bool inside = true;
  for (int e = 0; e < 3; e++) {
    double ed[3], rq[3], cr[3];
    sub3(v[e + 1], v[e], ed);
    sub3(pr, v[e], rq);
    cross3(ed, rq, cr);
    if (dot3(cr, n) < 0.0) inside = false;
  }
  if (inside) return fabs(h);
  double best = 1e300;
  for (int e = 0; e < 3; e++) {
    double ed[3], rq[3], q[3];
    sub3(v[e + 1], v[e], ed);
    sub3(p, v[e], rq);
    double t = dot3(rq, ed) / dot3(ed, ed);
    t = std::min(1.0, std::max(0.0, t));
    axpy3(v[e], t, ed, q);
    best = std::min(best, dist3(p, q));
  }
  return best;
}

void random_triangle(std::mt19937 &rng, double *t)
{
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double n[3];
  do {
    for (int k = 0; k < 9; k++) t[k] = u(rng);
  } while (triangle_normal(t, t + 3, t + 6, n) < 0.2);    // no slivers
}

std::string read_text(const std::string &file)
{
  std::ifstream in(file, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_text(const std::string &file, const std::string &text)
{
  std::ofstream out(file, std::ios::binary);
  out << text;
}

// error message of read_stl(file), "" when none
std::string stl_error(const std::string &file)
{
  try {
    read_stl(file);
  } catch (std::runtime_error &e) {
    return e.what();
  }
  return "";
}

// contact of a particle with the plane n.x = 0 of a rigid tool moving with vtool
ContactOut plane_contact(ContactIn in, const double *x, const double *v, const double *n)
{
  for (int k = 0; k < 3; k++) {
    in.x[k] = x[k];
    in.v[k] = v[k];
    in.n[k] = n[k];
  }
  in.d = dot3(x, n);
  for (int k = 0; k < 3; k++) in.q[k] = x[k] - in.d * n[k];
  ContactOut out;
  penalty_contact(in, out);
  return out;
}

ContactIn steel_particle()
{
  ContactIn in;
  in.mass = 7.8e-9;    // (0.1 mm)^3 of steel
  in.dp = 1.0e-4;
  in.h = 1.2e-4;
  in.sfac = 1.2;
  in.E_particle = 200e9;
  in.E_tool = 0.0;    // rigid
  in.pfac = 1.0;
  return in;
}

// velocity Verlet of one particle against the plane n.x = 0 (force evaluated
// with the half-step velocity), until it has left the contact; returns the
// final velocity along n; delta_min/max track the penetration history
double bounce(const ContactIn &in, const double *n, double v0, const double *g, double tmax,
              double &dmax, bool &left, bool &monotone)
{
  const double rp = 0.5 * in.h / in.sfac;
  double x[3], v[3];
  for (int k = 0; k < 3; k++) {
    x[k] = rp * n[k];    // touching
    v[k] = -v0 * n[k];
  }
  const double k = penalty_stiffness(in.E_particle, in.E_tool, in.dp, in.pfac, in.dim);
  const double dt = 2.0e-4 * sqrt(in.mass / k);
  ContactOut out = plane_contact(in, x, v, n);
  double a[3];
  for (int c = 0; c < 3; c++) a[c] = out.f[c] / in.mass + g[c];
  dmax = 0.0;
  left = false;
  monotone = true;
  double dprev = 0.0;
  for (double t = 0.0; t < tmax; t += dt) {
    double vh[3];
    for (int c = 0; c < 3; c++) {
      vh[c] = v[c] + 0.5 * dt * a[c];
      x[c] += dt * vh[c];
    }
    out = plane_contact(in, x, vh, n);
    for (int c = 0; c < 3; c++) {
      a[c] = out.f[c] / in.mass + g[c];
      v[c] = vh[c] + 0.5 * dt * a[c];
    }
    dmax = std::max(dmax, out.delta);
    if (out.delta < dprev - 1e-6 * dmax) monotone = false;
    dprev = out.delta;
    if (out.delta < 0.0 && dot3(v, n) > 0.0) {
      left = true;
      break;
    }
  }
  return dot3(v, n);
}

// undirected / directed edge bookkeeping of a triangle mesh
typedef std::array<double, 3> P3;
typedef std::pair<P3, P3> Edge;

P3 vtx(const std::vector<double> &t, size_t f, int m)
{
  return P3{{t[9 * f + 3 * m], t[9 * f + 3 * m + 1], t[9 * f + 3 * m + 2]}};
}

}    // namespace

/* ----------------------------------------------------------------------
   closest point on a triangle
------------------------------------------------------------------------- */

TEST(ClosestPoint, TriangleMatchesBruteForce)
{
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int NS = 150;    // samples per edge of the brute-force grid
  int hits[7] = {0, 0, 0, 0, 0, 0, 0};
  double t[9];
  for (int ip = 0; ip < 1000; ip++) {
    if (ip % 50 == 0) random_triangle(rng, t);
    const double *a = t, *b = t + 3, *c = t + 6;
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = 2.0 * u(rng);
    double q[3];
    int region = -1;
    const double d2 = closest_point_triangle(p, a, b, c, q, region);
    ASSERT_GE(region, FACE);
    ASSERT_LE(region, VERT_C);
    hits[region]++;
    const double d = sqrt(d2);
    EXPECT_NEAR(d, dist3(p, q), 1e-14);

    // q lies on the triangle
    double bc[3];
    barycentric(q, a, b, c, bc);
    for (int k = 0; k < 3; k++) EXPECT_GE(bc[k], -1e-12) << "point " << ip;

    // brute force: dense barycentric sampling of the triangle
    double dmin = 1e300, lmax = 0.0;
    for (int e = 0; e < 3; e++) lmax = std::max(lmax, dist3(t + 3 * e, t + 3 * ((e + 1) % 3)));
    for (int i = 0; i <= NS; i++)
      for (int j = 0; i + j <= NS; j++) {
        double s[3];
        for (int k = 0; k < 3; k++)
          s[k] = a[k] + (double) i / NS * (b[k] - a[k]) + (double) j / NS * (c[k] - a[k]);
        dmin = std::min(dmin, dist3(p, s));
      }
    EXPECT_LE(d, dmin + 1e-12) << "point " << ip;
    EXPECT_LE(dmin - d, lmax / NS) << "point " << ip;

    // independent exact distance
    EXPECT_NEAR(d, reference_distance(p, a, b, c), 1e-12) << "point " << ip;

    // the feature holds q: vertices exactly, edges by (p-q) perpendicular to the edge
    const double *vv[3] = {a, b, c};
    if (region >= VERT_A) {
      for (int k = 0; k < 3; k++) EXPECT_EQ(q[k], vv[region - VERT_A][k]);
    } else if (region >= EDGE_AB) {
      const int e = region - EDGE_AB;
      const double *e0 = vv[e], *e1 = vv[(e + 1) % 3];
      double ed[3], pq[3];
      sub3(e1, e0, ed);
      sub3(p, q, pq);
      EXPECT_NEAR(dot3(ed, pq), 0.0, 1e-12);
      EXPECT_NEAR(bc[(e + 2) % 3], 0.0, 1e-12);    // opposite vertex weight
    } else {
      double n[3], pq[3], cr[3];
      triangle_normal(a, b, c, n);
      sub3(p, q, pq);
      cross3(n, pq, cr);
      EXPECT_NEAR(len3(cr), 0.0, 1e-12);    // p - q along the face normal
    }
  }
  const char *names[7] = {"FACE", "EDGE_AB", "EDGE_BC", "EDGE_CA", "VERT_A", "VERT_B", "VERT_C"};
  for (int r = 0; r < 7; r++) EXPECT_GT(hits[r], 0) << names[r] << " never hit";
}

TEST(ClosestPoint, DegenerateTriangle)
{
  const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {2, 0, 0};    // collinear
  const double p[3] = {1.5, 1.0, 0.0};
  double q[3];
  int region;
  const double d2 = closest_point_triangle(p, a, b, c, q, region);
  EXPECT_NEAR(d2, 1.0, 1e-15);
  EXPECT_NEAR(q[0], 1.5, 1e-15);
  EXPECT_TRUE(region == EDGE_BC || region == EDGE_CA);
}

TEST(ClosestPoint, SegmentMatchesBruteForce)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int hits[3] = {0, 0, 0};
  double a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  for (int ip = 0; ip < 1000; ip++) {
    if (ip % 50 == 0) {
      do {
        for (int k = 0; k < 2; k++) {
          a[k] = u(rng);
          b[k] = u(rng);
        }
      } while (dist3(a, b) < 0.2);
    }
    const double p[3] = {2.0 * u(rng), 2.0 * u(rng), 0.0};
    double q[3];
    int region = -1;
    const double d = sqrt(closest_point_segment(p, a, b, q, region));
    ASSERT_TRUE(region == FACE || region == VERT_A || region == VERT_B);
    hits[region == FACE ? 0 : region - VERT_A + 1]++;
    const int NS = 4000;
    double dmin = 1e300;
    for (int i = 0; i <= NS; i++) {
      double s[3];
      axpy3(a, (double) i / NS, b, s);
      axpy3(s, -(double) i / NS, a, s);
      dmin = std::min(dmin, dist3(p, s));
    }
    EXPECT_LE(d, dmin + 1e-12);
    EXPECT_LE(dmin - d, dist3(a, b) / NS);
    if (region == VERT_A) {
      for (int k = 0; k < 3; k++) EXPECT_EQ(q[k], a[k]);
    }
    if (region == VERT_B) {
      for (int k = 0; k < 3; k++) EXPECT_EQ(q[k], b[k]);
    }

    // contact normal: FACE -> (dy, -dx) side-signed; ends -> from q to p
    double n[3];
    const double ds = contact_normal_segment(p, a, b, q, region, 1, n);
    EXPECT_NEAR(ds, d, 1e-12);
    EXPECT_NEAR(len3(n), 1.0, 1e-12);
    EXPECT_EQ(n[2], 0.0);
    for (int k = 0; k < 3; k++) EXPECT_NEAR(q[k] + ds * n[k], p[k], 1e-12);
    double nf[3];
    segment_normal(a, b, nf);
    EXPECT_NEAR(nf[0], (b[1] - a[1]) / dist3(a, b), 1e-14);
    EXPECT_NEAR(nf[1], -(b[0] - a[0]) / dist3(a, b), 1e-14);
    if (region == FACE) {
      const double dc = contact_normal_segment(p, a, b, q, region, 0, n);
      double pq[3];
      sub3(p, q, pq);
      EXPECT_NEAR(dc, dot3(pq, nf), 1e-12);    // signed: < 0 on the inner side
      for (int k = 0; k < 3; k++) EXPECT_EQ(n[k], nf[k]);
    }
  }
  EXPECT_GT(hits[0], 0);
  EXPECT_GT(hits[1], 0);
  EXPECT_GT(hits[2], 0);
}

/* ----------------------------------------------------------------------
   contact normals
------------------------------------------------------------------------- */

TEST(ContactNormal, FaceEdgeVertex)
{
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double t[9];
  int nedge = 0, nface = 0;
  for (int ip = 0; ip < 2000; ip++) {
    if (ip % 100 == 0) random_triangle(rng, t);
    const double *a = t, *b = t + 3, *c = t + 6;
    double nf[3];
    triangle_normal(a, b, c, nf);
    const double p[3] = {2.0 * u(rng), 2.0 * u(rng), 2.0 * u(rng)};
    double q[3], n[3], pq[3];
    int region;
    const double dist = sqrt(closest_point_triangle(p, a, b, c, q, region));
    sub3(p, q, pq);
    const double side = dot3(pq, nf);

    // two-sided sheet: n from the surface to the particle, d = |p - q|
    double d = contact_normal(p, a, b, c, q, region, 1, n);
    EXPECT_NEAR(d, dist, 1e-12);
    EXPECT_NEAR(len3(n), 1.0, 1e-12);
    for (int k = 0; k < 3; k++) EXPECT_NEAR(q[k] + d * n[k], p[k], 1e-12);

    // closed solid
    d = contact_normal(p, a, b, c, q, region, 0, n);
    if (region == FACE) {
      nface++;
      EXPECT_NEAR(d, side, 1e-12);    // signed, eq. 9 without |.|
      for (int k = 0; k < 3; k++) EXPECT_EQ(n[k], nf[k]);    // eq. 7, even when behind
    } else {
      nedge++;
      if (side >= 0.0) {
        // from the feature to the particle
        EXPECT_NEAR(d, dist, 1e-12);
        for (int k = 0; k < 3; k++) EXPECT_NEAR(n[k], pq[k] / dist, 1e-12);
      } else {
        // behind the plane: inside, n still out of the tool (towards q)
        EXPECT_NEAR(d, -dist, 1e-12);
        for (int k = 0; k < 3; k++) EXPECT_NEAR(n[k], -pq[k] / dist, 1e-12);
      }
    }
  }
  EXPECT_GT(nface, 0);
  EXPECT_GT(nedge, 0);

  // eq. 7 orientation: counter-clockwise in x-y -> +z
  const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
  double n[3];
  EXPECT_NEAR(triangle_normal(a, b, c, n), 1.0, 1e-15);
  EXPECT_EQ(n[2], 1.0);
  // point below the face: closed solid -> negative distance, outward normal kept
  const double p[3] = {0.2, 0.2, -0.1};
  double q[3];
  int region;
  closest_point_triangle(p, a, b, c, q, region);
  EXPECT_EQ(region, FACE);
  EXPECT_NEAR(contact_normal(p, a, b, c, q, region, 0, n), -0.1, 1e-15);
  EXPECT_EQ(n[2], 1.0);
  EXPECT_NEAR(contact_normal(p, a, b, c, q, region, 1, n), 0.1, 1e-15);
  EXPECT_EQ(n[2], -1.0);
  // the particle exactly on the edge: face normal, d = 0
  const double pe[3] = {0.5, 0.0, 0.0};
  closest_point_triangle(pe, a, b, c, q, region);
  EXPECT_NEAR(contact_normal(pe, a, b, c, q, region, 0, n), 0.0, 1e-15);
  EXPECT_NEAR(n[2], 1.0, 1e-15);
}

/* ----------------------------------------------------------------------
   penalty force
------------------------------------------------------------------------- */

TEST(Penalty, StiffnessAndDamping)
{
  // eq. 10 in 3D [N/m]; 2D per unit thickness: dp drops out
  EXPECT_DOUBLE_EQ(penalty_stiffness(200e9, 600e9, 1e-4, 0.5, 3), 0.5 * 150e9 * 1e-4);
  EXPECT_DOUBLE_EQ(penalty_stiffness(200e9, 600e9, 1e-4, 0.5, 2), 0.5 * 150e9);
  EXPECT_DOUBLE_EQ(penalty_stiffness(200e9, 0.0, 1e-4, 1.0, 3), 200e9 * 1e-4);    // rigid tool
  // critical damping 2 sqrt(k mu_red), rigid tool -> 2 sqrt(k m_i)
  EXPECT_DOUBLE_EQ(penalty_damping(4.0, 1.0, 0.0, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(penalty_damping(4.0, 2.0, 2.0, 0.5), 2.0);
}

TEST(Penalty, ActivationAndDashpot)
{
  ContactIn in = steel_particle();
  in.dfac = 1.0;
  const double n[3] = {0.0, 1.0, 0.0};
  const double rp = 0.5 * in.h / in.sfac;
  const double v0[3] = {0.0, 0.0, 0.0};
  // out of reach: no force
  double x[3] = {0.0, 1.01 * rp, 0.0};
  ContactOut out = plane_contact(in, x, v0, n);
  EXPECT_EQ(out.active, 0);
  EXPECT_EQ(out.fn, 0.0);
  EXPECT_LT(out.delta, 0.0);
  // penetrated, at rest: F = k delta n (eq. 9, 12)
  x[1] = 0.9 * rp;
  out = plane_contact(in, x, v0, n);
  EXPECT_EQ(out.active, 1);
  EXPECT_NEAR(out.delta, 0.1 * rp, 1e-12 * rp);
  EXPECT_NEAR(out.f[1], out.k * 0.1 * rp, 1e-9 * out.f[1]);
  EXPECT_EQ(out.f[0], 0.0);
  // inside the tool (d < 0): larger force
  x[1] = -0.5 * rp;
  EXPECT_NEAR(plane_contact(in, x, v0, n).delta, 1.5 * rp, 1e-12 * rp);
  // separating fast with damping: eq. 12 as written, the dashpot pulls while the particle
  // leaves (k delta - D |delta_dot|), and no friction acts without compression
  x[1] = 0.9 * rp;
  const double vout[3] = {0.0, 1000.0, 0.0};
  in.mu = 0.5;
  out = plane_contact(in, x, vout, n);
  in.mu = 0.0;
  EXPECT_EQ(out.active, 1);
  EXPECT_NEAR(out.fn, out.k * 0.1 * rp - out.damp * 1000.0, 1e-9 * fabs(out.fn));
  EXPECT_LT(out.fn, 0.0);
  EXPECT_EQ(out.ft[0], 0.0);
  // approaching: damping adds to the spring
  const double vin[3] = {0.0, -1.0, 0.0};
  out = plane_contact(in, x, vin, n);
  EXPECT_NEAR(out.fn, out.k * 0.1 * rp + out.damp * 1.0, 1e-9 * out.fn);
  EXPECT_NEAR(out.delta_dot, 1.0, 1e-15);
}

TEST(Penalty, StaticEquilibrium)
{
  // a particle resting on a tilted face under gravity settles at delta = m g_n / k
  ContactIn in = steel_particle();
  in.dfac = 1.0;
  double n[3] = {0.3, 1.0, -0.2};
  const double ln = len3(n);
  for (int k = 0; k < 3; k++) n[k] /= ln;
  const double gmag = 1.0e7;    // large so that m g / k is not tiny
  const double g[3] = {-gmag * n[0], -gmag * n[1], -gmag * n[2]};
  const double k = penalty_stiffness(in.E_particle, in.E_tool, in.dp, in.pfac, in.dim);
  const double expect = in.mass * gmag / k;
  double dmax;
  bool left, monotone;
  const double tmax = 40.0 * sqrt(in.mass / k);    // 40 / omega
  bounce(in, n, 0.0, g, tmax, dmax, left, monotone);
  EXPECT_FALSE(left);
  EXPECT_TRUE(monotone);    // critically damped from rest: no overshoot
  EXPECT_NEAR(dmax, expect, 1e-6 * expect);
  // exactly at equilibrium the contact force balances gravity
  const double rp = 0.5 * in.h / in.sfac;
  double x[3], v[3] = {0.0, 0.0, 0.0};
  for (int c = 0; c < 3; c++) x[c] = (rp - expect) * n[c];
  ContactOut out = plane_contact(in, x, v, n);
  for (int c = 0; c < 3; c++) EXPECT_NEAR(out.f[c] / in.mass + g[c], 0.0, 1e-8 * gmag);
}

TEST(Penalty, ElasticBounceConservesSpeed)
{
  ContactIn in = steel_particle();
  in.dfac = 0.0;
  double n[3] = {-0.5, 0.2, 1.0};
  const double ln = len3(n);
  for (int k = 0; k < 3; k++) n[k] /= ln;
  const double g[3] = {0.0, 0.0, 0.0};
  const double v0 = 50.0;
  const double k = penalty_stiffness(in.E_particle, in.E_tool, in.dp, in.pfac, in.dim);
  double dmax;
  bool left, monotone;
  const double vout = bounce(in, n, v0, g, 10.0 * sqrt(in.mass / k), dmax, left, monotone);
  ASSERT_TRUE(left);
  EXPECT_NEAR(vout, v0, 0.01 * v0);
  EXPECT_NEAR(dmax, v0 * sqrt(in.mass / k), 0.01 * v0 * sqrt(in.mass / k));    // energy balance
  // the same in 2D (per unit thickness)
  in.dim = 2;
  in.mass = 7.8e-5;
  const double vout2 = bounce(in, n, v0, g, 10.0 * sqrt(in.mass / in.E_particle), dmax, left, monotone);
  ASSERT_TRUE(left);
  EXPECT_NEAR(vout2, v0, 0.01 * v0);
}

TEST(Penalty, CriticalDamping)
{
  // eq. 11-12 as a linear spring-dashpot: DFAC = z is the damping ratio.
  // z < 1 rebounds with e = exp(-pi z / sqrt(1 - z^2)); z >= 1 does not rebound.
  ContactIn in = steel_particle();
  const double n[3] = {0.0, 0.0, 1.0}, g[3] = {0.0, 0.0, 0.0};
  const double v0 = 50.0;
  const double k = penalty_stiffness(in.E_particle, in.E_tool, in.dp, in.pfac, in.dim);
  double dmax;
  bool left, monotone;
  for (double z : {0.2, 0.5}) {
    in.dfac = z;
    const double e = bounce(in, n, v0, g, 100.0 * sqrt(in.mass / k), dmax, left, monotone) / v0;
    ASSERT_TRUE(left);
    EXPECT_NEAR(e, exp(-M_PI * z / sqrt(1.0 - z * z)), 0.01 * e);
  }
  for (double z : {1.0, 2.0}) {
    in.dfac = z;
    const double vend = bounce(in, n, v0, g, 100.0 * sqrt(in.mass / k), dmax, left, monotone);
    EXPECT_FALSE(left) << "DFAC " << z << " rebounds";
    EXPECT_LT(fabs(vend), 1.0e-3 * v0);
  }
  // dropped onto the tool from rest under gravity: it stays in contact, no oscillation
  in.dfac = 1.0;
  const double gz[3] = {0.0, 0.0, -1.0e7};
  bounce(in, n, 0.0, gz, 60.0 * sqrt(in.mass / k), dmax, left, monotone);
  EXPECT_FALSE(left);
  EXPECT_TRUE(monotone);
}

TEST(Penalty, Friction)
{
  ContactIn in = steel_particle();
  in.mu = 0.3;
  in.friction.v_reg = 0.5;    // (friction.kind COULOMB, the default of sphcut::ContactIn)
  in.dfac = 0.0;
  const double n[3] = {0.0, 1.0, 0.0};
  const double rp = 0.5 * in.h / in.sfac;
  const double x[3] = {0.0, 0.8 * rp, 0.0};
  const double vt[3] = {-2.0, 0.0, 0.0};    // tool moving in -x
  in.vtool[0] = vt[0];
  in.vtool[1] = vt[1];
  in.vtool[2] = vt[2];

  // sliding faster than v_reg: |F_T| = mu F_N, opposite to the sliding
  const double dirs[3][3] = {{1.0, 0.0, 0.0}, {0.6, 0.0, -0.8}, {-0.28, 0.0, 0.96}};
  for (const auto &dir : dirs) {
    for (double speed : {0.0, 0.1, 0.25, 0.5, 1.0, 10.0}) {
      double v[3];
      for (int c = 0; c < 3; c++) v[c] = vt[c] + speed * dir[c] + (c == 1 ? -0.3 : 0.0);
      const ContactOut out = plane_contact(in, x, v, n);
      ASSERT_EQ(out.active, 1);
      ASSERT_GT(out.fn, 0.0);
      EXPECT_NEAR(out.vslide, speed, 1e-12);
      const double ft = len3(out.ft);
      EXPECT_NEAR(dot3(out.ft, n), 0.0, 1e-12 * out.fn);    // tangential
      EXPECT_NEAR(out.fric_power, ft * speed, 1e-12 * out.fn);
      if (speed == 0.0) {
        EXPECT_EQ(ft, 0.0);    // no force without sliding
        continue;
      }
      EXPECT_NEAR(dot3(out.ft, dir), -ft, 1e-12 * out.fn);    // opposes sliding
      const double expect = in.mu * out.fn * std::min(1.0, speed / in.friction.v_reg);
      EXPECT_NEAR(ft, expect, 1e-12 * out.fn);
      for (int c = 0; c < 3; c++) EXPECT_NEAR(out.f[c], out.fn * n[c] + out.ft[c], 1e-12 * out.fn);
    }
  }
  // plain Coulomb without regularisation, and no friction out of contact
  in.friction.v_reg = 0.0;
  double v[3] = {vt[0] + 1e-6, 0.0, 0.0};
  ContactOut out = plane_contact(in, x, v, n);
  EXPECT_NEAR(len3(out.ft), in.mu * out.fn, 1e-12 * out.fn);
  const double xfar[3] = {0.0, 2.0 * rp, 0.0};
  out = plane_contact(in, xfar, v, n);
  EXPECT_EQ(len3(out.ft), 0.0);
  EXPECT_EQ(out.fric_power, 0.0);
}

// friction with memory (sphcut_contact.h FrictionLaw::memory_force): the elastic predictor
// f* = f_old,t - alpha m v_t/dt, returned to the cone |F_T| <= mu F_N
TEST(Penalty, FrictionMemory)
{
  ContactIn in = steel_particle();
  in.mu = 0.3;
  in.dfac = 0.0;
  in.friction.kind = FrictionLaw::MEMORY;
  in.friction.tfac = 0.1;
  in.dt = 1.0e-8;
  in.friction.v_reg = 0.5;    // not used by the memory law
  const double n[3] = {0.0, 1.0, 0.0};
  const double rp = 0.5 * in.h / in.sfac;
  const double x[3] = {0.0, 0.8 * rp, 0.0};
  const double kdt = in.friction.tfac * in.mass / in.dt;    // force per unit sliding speed of one step

  // a new contact (f_old = 0) sliding slowly: the predictor alone, no slip, no heat
  double v[3] = {1.0e-3, 0.0, 0.0};
  ContactOut out = plane_contact(in, x, v, n);
  ASSERT_EQ(out.active, 1);
  const double fmax = in.mu * out.fn;
  ASSERT_LT(kdt * v[0], fmax);
  EXPECT_NEAR(out.ft[0], -kdt * v[0], 1e-12 * fmax);
  EXPECT_EQ(out.ft[1], 0.0);
  EXPECT_EQ(out.slip, 0);
  EXPECT_EQ(out.fric_power, 0.0);

  // memory: at rest the old force stays (static friction), also when it is tilted out of
  // the tangent plane (projected), and in 3D any direction
  v[0] = 0.0;
  in.ft_old[0] = -0.5 * fmax;
  in.ft_old[1] = 0.2 * fmax;    // normal part: dropped
  in.ft_old[2] = 0.4 * fmax;
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(out.ft[0], -0.5 * fmax, 1e-12 * fmax);
  EXPECT_EQ(out.ft[1], 0.0);
  EXPECT_NEAR(out.ft[2], 0.4 * fmax, 1e-12 * fmax);
  EXPECT_EQ(out.slip, 0);

  // fast sliding: the force is mu F_N against the trial force, the heat mu F_N times the
  // slip rate; with f_old = mu F_N against steady sliding the heat is mu F_N |v_t|
  for (int k = 0; k < 3; k++) in.ft_old[k] = 0.0;
  in.ft_old[0] = -fmax;
  v[0] = 2.0;
  out = plane_contact(in, x, v, n);
  EXPECT_EQ(out.slip, 1);
  EXPECT_NEAR(len3(out.ft), fmax, 1e-12 * fmax);
  EXPECT_NEAR(out.ft[0], -fmax, 1e-12 * fmax);
  EXPECT_NEAR(out.fric_power, fmax * v[0], 1e-9 * fmax * v[0]);
  for (int c = 0; c < 3; c++) EXPECT_NEAR(out.f[c], out.fn * n[c] + out.ft[c], 1e-12 * out.fn);

  // reversal: the old force +mu F_N came from sliding in -x; going on in -x it stays at the
  // limit (slip), reversed the predictor first unloads it (stick, half of it left)
  in.ft_old[0] = fmax;
  v[0] = -0.5 * fmax / kdt;
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(out.ft[0], fmax, 1e-12 * fmax);
  EXPECT_EQ(out.slip, 1);
  EXPECT_NEAR(out.fric_power, fmax * 0.5 * fmax / kdt, 1e-9 * fmax * fmax / kdt);
  v[0] = 0.5 * fmax / kdt;
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(out.ft[0], 0.5 * fmax, 1e-12 * fmax);
  EXPECT_EQ(out.slip, 0);

  // no friction without compression or out of contact (the caller then resets f_old)
  const double xfar[3] = {0.0, 2.0 * rp, 0.0};
  out = plane_contact(in, xfar, v, n);
  EXPECT_EQ(len3(out.ft), 0.0);
  in.mu = 0.0;
  out = plane_contact(in, x, v, n);
  EXPECT_EQ(len3(out.ft), 0.0);
  EXPECT_EQ(out.fric_power, 0.0);
}

// the friction law's mu(T): a constant, a table (at its points, linear between them, the end
// values outside), and a function of the host driver (fix contact/tri-penalty's mu v_name)
TEST(FrictionLaw, MuOfTemperature)
{
  FrictionLaw law;
  law.mu0 = 0.4;
  EXPECT_EQ(law.mu(300.0), 0.4);
  EXPECT_EQ(law.mu(2000.0), 0.4);
  EXPECT_FALSE(law.host_only());
  const double t[3] = {300.0, 700.0, 1100.0}, m[3] = {0.5, 0.3, 0.2};
  law.mu_kind = FrictionLaw::MU_TABLE;
  law.nmu = 3;
  law.mu_t = t;
  law.mu_v = m;
  for (int k = 0; k < 3; k++) EXPECT_EQ(law.mu(t[k]), m[k]);
  EXPECT_NEAR(law.mu(500.0), 0.4, 1e-15);
  EXPECT_NEAR(law.mu(1000.0), 0.225, 1e-15);
  EXPECT_EQ(law.mu(20.0), 0.5);
  EXPECT_EQ(law.mu(5000.0), 0.2);
  EXPECT_FALSE(law.host_only());
  double calls = 0.0;
  law.mu_kind = FrictionLaw::MU_HOST;
  law.host_ctx = &calls;
  law.host_mu = [](void *c, double temp) {
    *static_cast<double *>(c) += 1.0;
    return 1e-3 * temp;
  };
  EXPECT_TRUE(law.host_only());
  EXPECT_EQ(law.mu(450.0), 0.45);
  EXPECT_EQ(calls, 1.0);
}

// the static limit (friction static) against plain Coulomb (friction coulomb): a particle pushed
// along the tool by its neighbours (f_other) sliding slowly: static friction takes the force that
// stops the trial sliding w = v_t + dt/m f_other,t within the step, Coulomb mu F_N against v_t
TEST(FrictionLaw, StaticLimitAgainstCoulomb)
{
  ContactIn in = steel_particle();
  in.mu = 0.3;
  in.dfac = 0.0;
  in.dt = 1.0e-8;
  const double n[3] = {0.0, 1.0, 0.0};
  const double rp = 0.5 * in.h / in.sfac;
  const double x[3] = {0.0, 0.8 * rp, 0.0};
  const double v[3] = {1.0e-3, 0.0, 0.0};
  in.f_other[1] = -5.0;    // normal part: not in w
  in.friction.kind = FrictionLaw::COULOMB;
  ContactOut out = plane_contact(in, x, v, n);
  ASSERT_EQ(out.active, 1);
  const double fmax = in.mu * out.fn;
  EXPECT_NEAR(out.ft[0], -fmax, 1e-12 * fmax);
  EXPECT_EQ(out.slip, 1);
  // static: w = v_t + dt/m f_other,t; held (f_other,t = 0): the stick force m |v_t|/dt < mu F_N
  in.friction.kind = FrictionLaw::STATIC;
  const double fstick = in.mass * v[0] / in.dt;
  ASSERT_LT(fstick, fmax);
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(out.ft[0], -fstick, 1e-12 * fmax);
  EXPECT_EQ(out.slip, 0);
  EXPECT_NEAR(out.fric_power, fstick * v[0], 1e-12 * fstick * v[0]);
  // pushed against the sliding by a force the friction can hold: w = 0, no friction force
  in.f_other[0] = -in.mass * v[0] / in.dt;
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(len3(out.ft), 0.0, 1e-12 * fmax);
  // pushed along it beyond mu F_N: sliding at the Coulomb limit against w
  in.f_other[0] = 10.0 * fmax;
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(out.ft[0], -fmax, 1e-12 * fmax);
  EXPECT_EQ(out.slip, 1);
  // without a step (dt 0) the static law is the Coulomb law
  in.dt = 0.0;
  out = plane_contact(in, x, v, n);
  EXPECT_NEAR(out.ft[0], -fmax, 1e-12 * fmax);
}

/* ----------------------------------------------------------------------
   STL / VTK
------------------------------------------------------------------------- */

TEST(Stl, AsciiBinaryRoundTrip)
{
  InsertParams ip;
  ip.rake_angle = 8.0;
  ip.clearance_angle = 6.0;
  ip.edge_radius = 0.02;
  ip.arc_segments = 6;
  std::vector<double> tri = make_cutting_insert(ip, 3);
  for (double &x : tri) x = (double) (float) x;    // binary STL is float32
  write_stl_ascii("insert_ascii.stl", tri, "insert");
  write_stl_binary("insert_binary.stl", tri, "solid insert (binary, CAD style header)");
  ASSERT_EQ(read_text("insert_binary.stl").compare(0, 5, "solid"), 0);
  const std::vector<double> ta = read_stl("insert_ascii.stl");
  const std::vector<double> tb = read_stl("insert_binary.stl");
  ASSERT_EQ(ta.size(), tri.size());
  ASSERT_EQ(tb.size(), tri.size());
  for (size_t i = 0; i < tri.size(); i++) {
    EXPECT_EQ(ta[i], tri[i]);
    EXPECT_EQ(tb[i], tri[i]);
  }

  // placement: x' = R (s x) + shift
  StlTransform tf;
  tf.scale = 1.0e-3;
  tf.shift[0] = 1.0;
  tf.shift[1] = -2.0;
  tf.shift[2] = 0.5;
  const double axis[3] = {1.0, 1.0, 1.0};
  tf.set_axis_angle(axis, 120.0);    // cyclic x -> y -> z -> x
  const std::vector<double> tt = read_stl("insert_binary.stl", tf);
  ASSERT_EQ(tt.size(), tri.size());
  for (size_t i = 0; i < tri.size() / 3; i++) {
    const double *x = &tri[3 * i];
    EXPECT_NEAR(tt[3 * i + 0], 1.0e-3 * x[2] + 1.0, 1e-13);
    EXPECT_NEAR(tt[3 * i + 1], 1.0e-3 * x[0] - 2.0, 1e-13);
    EXPECT_NEAR(tt[3 * i + 2], 1.0e-3 * x[1] + 0.5, 1e-13);
  }
  // Euler z, y, x: R = Rz Ry Rx (x axis first)
  StlTransform te;
  te.set_euler_zyx(90.0, 0.0, 90.0);
  double y[3];
  const double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0};
  te.apply(ey, y);    // Rx: y -> z, Rz: z stays
  EXPECT_NEAR(y[0], 0.0, 1e-15);
  EXPECT_NEAR(y[1], 0.0, 1e-15);
  EXPECT_NEAR(y[2], 1.0, 1e-15);
  te.apply(ex, y);    // Rx: x stays, Rz: x -> y
  EXPECT_NEAR(y[0], 0.0, 1e-15);
  EXPECT_NEAR(y[1], 1.0, 1e-15);
  EXPECT_NEAR(y[2], 0.0, 1e-15);
  StlTransform ta2;
  const double zaxis[3] = {0, 0, 2};
  ta2.set_axis_angle(zaxis, 37.0);
  te.set_euler_zyx(37.0, 0.0, 0.0);
  for (int k = 0; k < 9; k++) EXPECT_NEAR(ta2.rot[k], te.rot[k], 1e-15);
  // solid orientation survives a proper rotation: the volume is unchanged
  EXPECT_NEAR(mesh_volume(tt), 1e-9 * mesh_volume(tri), 1e-8 * 1e-9 * mesh_volume(tri));
}

TEST(Stl, Errors)
{
  const std::string facet =
      "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n      vertex 1 0 0\n"
      "      vertex 0 1 0\n    endloop\n  endfacet\n";
  struct Case {
    std::string file, content, what[2];
  };
  std::vector<Case> cases = {
      {"empty.stl", "", {"empty", ""}},
      {"nofacet.stl", "solid nothing\nendsolid nothing\n", {"no facets", ""}},
      {"badtoken.stl",
       "solid x\n" + facet + "  facet normal 0 0 1\n    outer loop\n      vertx 0 0 0\n",
       {"line 11", "vertx"}},
      {"badnumber.stl", "solid x\n  facet normal 0 0 1\n    outer loop\n      vertex 0 0 zero\n",
       {"line 4", "zero"}},
      {"cut.stl", "solid x\n" + facet + "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 0\n",
       {"end of file", "vertex"}},
      {"flipped.stl",
       "solid x\n" + facet +
           "  facet normal 0 0 1\n    outer loop\n      vertex 0 0 1\n      vertex 0 1 1\n"
           "      vertex 1 0 1\n    endloop\n  endfacet\nendsolid x\n",
       {"facet 1", "normal"}},
      {"degenerate.stl",
       "solid x\n  facet normal 0 0 0\n    outer loop\n      vertex 0 0 0\n      vertex 1 1 1\n"
       "      vertex 2 2 2\n    endloop\n  endfacet\n" + facet + "endsolid x\n",
       {"facet 0", "degenerate"}},
  };
  // binary: zero facets, truncated, flipped normal
  std::vector<double> one = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  write_stl_binary("one_binary.stl", one, "solid but binary");
  const std::string bin = read_text("one_binary.stl");
  ASSERT_EQ(bin.size(), 134u);
  std::string zero = bin.substr(0, 84);
  zero[80] = zero[81] = zero[82] = zero[83] = 0;
  cases.push_back({"zero_binary.stl", zero, {"no facets", ""}});
  cases.push_back({"trunc_binary.stl", bin.substr(0, 120), {"truncated", "134"}});
  std::string two = bin + bin.substr(84);    // 2 facets, header still says 1
  two[80] = 2;
  cases.push_back({"trunc2_binary.stl", two.substr(0, 150), {"truncated", "2 facets"}});
  std::string flip = bin;
  flip[84 + 11] = (char) 0xbf;    // normal z = -1.0f (0xbf800000)
  cases.push_back({"flip_binary.stl", flip, {"facet 0", "normal"}});

  for (const Case &c : cases) {
    write_text(c.file, c.content);
    const std::string msg = stl_error(c.file);
    EXPECT_NE(msg.find(c.file), std::string::npos) << c.file << ": '" << msg << "'";
    for (const std::string &w : c.what)
      EXPECT_NE(msg.find(w), std::string::npos) << c.file << ": '" << msg << "' lacks '" << w << "'";
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  const std::string missing = stl_error("no_such_file.stl");
  EXPECT_NE(missing.find("no_such_file.stl"), std::string::npos) << missing;
  EXPECT_NE(missing.find("cannot open"), std::string::npos) << missing;
  // a zero stored normal is accepted, and the valid binary reads
  write_text("zero_normal.stl", "solid x\n  facet normal 0 0 0\n    outer loop\n      vertex 0 0 0\n"
             "      vertex 1 0 0\n      vertex 0 1 0\n    endloop\n  endfacet\nendsolid x\n");
  EXPECT_EQ(read_stl("zero_normal.stl").size(), 9u);
  EXPECT_EQ(read_stl("one_binary.stl"), one);
  StlTransform bad;
  bad.scale = -1.0;
  EXPECT_THROW(read_stl("one_binary.stl", bad), std::runtime_error);
}

// a tool must be the closed surface of a solid: open sheets, holes and facets turned inside
// out are found (counts of the offending edges), the generated inserts are closed
TEST(Stl, ClosedMeshCheck)
{
  const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {1.0, 2.0, 3.0};
  const std::vector<double> box = sphcut_test::box_triangles(lo, hi);
  EXPECT_TRUE(mesh_closure(box).closed());
  const std::vector<double> sheet(box.begin(), box.begin() + 18);    // the two facets of one face
  MeshClosure c = mesh_closure(sheet);
  EXPECT_EQ(c.open_edges, 4);
  EXPECT_EQ(c.inconsistent_edges, 0);
  const std::vector<double> holed(box.begin() + 9, box.end());    // one facet missing
  c = mesh_closure(holed);
  EXPECT_EQ(c.open_edges, 3);
  EXPECT_EQ(c.inconsistent_edges, 0);
  std::vector<double> flipped = box;    // facet 0 turned inside out
  for (int k = 0; k < 3; k++) std::swap(flipped[3 + k], flipped[6 + k]);
  c = mesh_closure(flipped);
  EXPECT_EQ(c.open_edges, 0);
  EXPECT_EQ(c.inconsistent_edges, 3);
  std::vector<double> two = box;    // two solids touching along an edge: still closed
  const double lo2[3] = {1.0, 2.0, 0.0}, hi2[3] = {2.0, 3.0, 3.0};
  const std::vector<double> box2 = sphcut_test::box_triangles(lo2, hi2);
  two.insert(two.end(), box2.begin(), box2.end());
  EXPECT_TRUE(mesh_closure(two).closed());
  for (double r : {0.0, 0.02}) {
    InsertParams ip;
    ip.edge_radius = r;
    ip.rake_angle = 8.0;
    EXPECT_TRUE(mesh_closure(make_cutting_insert(ip, 3)).closed()) << "insert, edge radius " << r;
  }
  try {
    require_closed_mesh("sheet.stl", sheet);
    ADD_FAILURE() << "an open sheet passed";
  } catch (std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("STL file 'sheet.stl': the mesh is not closed: 4 edge(s) belong to one "
                                         "facet only, e.g. ("),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(require_closed_mesh("box.stl", box));
}

TEST(Stl, VtkWriter)
{
  InsertParams ip;
  ip.edge_radius = 0.01;
  const std::vector<double> tri = make_cutting_insert(ip, 3);
  write_vtk("insert.vtk", tri, 3);
  const std::string vtk = read_text("insert.vtk");
  const size_t nt = tri.size() / 9;
  EXPECT_EQ(vtk.compare(0, 26, "# vtk DataFile Version 3.0"), 0);
  EXPECT_NE(vtk.find("POINTS " + std::to_string(3 * nt) + " double"), std::string::npos);
  EXPECT_NE(vtk.find("DATASET UNSTRUCTURED_GRID"), std::string::npos);
  EXPECT_NE(vtk.find("CELLS " + std::to_string(nt) + " " + std::to_string(4 * nt)), std::string::npos);
  EXPECT_NE(vtk.find("CELL_TYPES " + std::to_string(nt) + "\n5\n"), std::string::npos);
  EXPECT_NE(vtk.find("CELL_DATA " + std::to_string(nt)), std::string::npos);
  const std::vector<double> seg = make_cutting_insert(ip, 2);
  write_vtk("insert2d.vtk", seg, 2);
  const size_t ns = seg.size() / 6;
  const std::string vtk2 = read_text("insert2d.vtk");
  EXPECT_NE(vtk2.find("CELLS " + std::to_string(ns) + " " + std::to_string(3 * ns)), std::string::npos);
  EXPECT_NE(vtk2.find("CELL_TYPES " + std::to_string(ns) + "\n3\n"), std::string::npos);
}

/* ----------------------------------------------------------------------
   cutting insert
------------------------------------------------------------------------- */

TEST(Insert, Geometry)
{
  struct P {
    double gamma, alpha, r;
    int nseg;
  };
  const P sets[] = {{0.0, 7.0, 0.02, 8}, {-6.0, 5.0, 0.05, 12}, {15.0, 10.0, 0.0, 4},
                    {20.0, 0.0, 0.01, 5}, {-30.0, 11.0, 0.003, 1}};
  for (const P &s : sets) {
    InsertParams ip;
    ip.rake_angle = s.gamma;
    ip.clearance_angle = s.alpha;
    ip.edge_radius = s.r;
    ip.arc_segments = s.nseg;
    ip.rake_length = 1.5;
    ip.flank_length = 0.8;
    ip.width = 0.4;
    std::vector<int> tags;
    const std::vector<double> tri = make_cutting_insert(ip, 3, &tags);
    const size_t nt = tri.size() / 9;
    ASSERT_EQ(tags.size(), nt);
    int nrake = 0, nflank = 0, nedge = 0;
    double ymin = 1e300;
    bool tip = false;
    for (size_t f = 0; f < nt; f++) {
      const double *v = &tri[9 * f];
      double n[3];
      ASSERT_GT(triangle_normal(v, v + 3, v + 6, n), 0.0);
      for (int m = 0; m < 3; m++) {
        ymin = std::min(ymin, v[3 * m + 1]);
        if (v[3 * m] == 0.0 && v[3 * m + 1] == 0.0) tip = true;
      }
      if (tags[f] == INSERT_RAKE) {
        nrake++;
        // rake face normal (-cos g, sin g): gamma from +y, positive away from the chip
        EXPECT_NEAR(atan2(n[1], -n[0]) * 180.0 / PI, s.gamma, 1e-12);
        EXPECT_NEAR(n[2], 0.0, 1e-15);
      } else if (tags[f] == INSERT_FLANK) {
        nflank++;
        EXPECT_NEAR(atan2(n[0], -n[1]) * 180.0 / PI, s.alpha, 1e-12);
        EXPECT_NEAR(n[2], 0.0, 1e-15);
      } else if (tags[f] == INSERT_EDGE) {
        nedge++;
        for (int m = 0; m < 3; m++)    // arc vertices on the circle about (0, r)
          EXPECT_NEAR(sqrt(sq(v[3 * m]) + sq(v[3 * m + 1] - s.r)), s.r, 1e-12 * s.r);
      }
    }
    EXPECT_EQ(nrake, 2);
    EXPECT_EQ(nflank, 2);
    EXPECT_EQ(nedge, s.r > 0.0 ? 2 * std::max(s.nseg, s.alpha > 0.0 ? 2 : 1) : 0);
    EXPECT_EQ(ymin, 0.0);    // the tip is the lowest point ...
    EXPECT_TRUE(tip);        // ... and at the origin

    // closed and consistently oriented: every directed edge once, with its reverse once
    std::map<Edge, int> directed;
    for (size_t f = 0; f < nt; f++)
      for (int m = 0; m < 3; m++) directed[Edge(vtx(tri, f, m), vtx(tri, f, (m + 1) % 3))]++;
    for (const auto &e : directed) {
      EXPECT_EQ(e.second, 1);
      auto rev = directed.find(Edge(e.first.second, e.first.first));
      ASSERT_NE(rev, directed.end()) << "open edge";
      EXPECT_EQ(rev->second, 1);
    }

    // 2D section: closed counter-clockwise loop with the same tags; the
    // 3D volume (outward normals) is its area times the width
    std::vector<int> tags2;
    const std::vector<double> seg = make_cutting_insert(ip, 2, &tags2);
    const size_t ns = seg.size() / 6;
    ASSERT_EQ(tags2.size(), ns);
    double area = 0.0;
    for (size_t e = 0; e < ns; e++) {
      const double *a = &seg[6 * e], *b = &seg[6 * e + 3];
      EXPECT_EQ(a[2], 0.0);
      const double *an = &seg[6 * ((e + 1) % ns)];
      for (int k = 0; k < 3; k++) EXPECT_EQ(b[k], an[k]);    // closed chain
      area += 0.5 * (a[0] * b[1] - a[1] * b[0]);
      double n[3];
      segment_normal(a, b, n);
      if (tags2[e] == INSERT_RAKE) {
        EXPECT_NEAR(atan2(n[1], -n[0]) * 180.0 / PI, s.gamma, 1e-12);
      }
      if (tags2[e] == INSERT_FLANK) {
        EXPECT_NEAR(atan2(n[0], -n[1]) * 180.0 / PI, s.alpha, 1e-12);
      }
    }
    EXPECT_GT(area, 0.0);
    EXPECT_NEAR(mesh_volume(tri), area * ip.width, 1e-12);

    // the STL reader's checks accept the generated mesh
    write_stl_ascii("insert_check.stl", tri);
    EXPECT_EQ(read_stl("insert_check.stl").size(), tri.size());
  }
  InsertParams bad;
  bad.rake_angle = 50.0;
  bad.clearance_angle = 45.0;
  EXPECT_THROW(make_cutting_insert(bad, 3), std::invalid_argument);
}

// a flank wear land: a flat of width land at the tip's height from the tip, tagged flank, then the
// flank at the clearance angle; the arc on the rake side only; closed 3D mesh of the section's area
TEST(Insert, FlankWearLand)
{
  for (double r : {28.7e-6, 0.0}) {
    InsertParams ip;
    ip.rake_angle = 0.0;
    ip.clearance_angle = 7.0;
    ip.edge_radius = r;
    ip.arc_segments = 8;
    ip.rake_length = 300e-6;
    ip.flank_length = 200e-6;
    ip.width = 100e-6;
    ip.land = 50e-6;
    std::vector<int> tags;
    const std::vector<double> seg = make_cutting_insert(ip, 2, &tags);
    const size_t ns = seg.size() / 6;
    ASSERT_EQ(tags.size(), ns);
    int nland = 0, nedge = 0, nflank = 0;
    double area = 0.0;
    for (size_t e = 0; e < ns; e++) {
      const double *a = &seg[6 * e], *b = &seg[6 * e + 3];
      EXPECT_GE(a[1], 0.0) << "no vertex below the tip";
      area += 0.5 * (a[0] * b[1] - a[1] * b[0]);
      if (tags[e] == INSERT_EDGE) nedge++;
      if (tags[e] == INSERT_FLANK) nflank++;
      if (a[0] == 0.0 && a[1] == 0.0) {    // the segment from the tip: the land
        nland++;
        EXPECT_EQ(tags[e], INSERT_FLANK);
        EXPECT_EQ(b[0], ip.land);
        EXPECT_EQ(b[1], 0.0);
        const double *c = &seg[6 * ((e + 1) % ns) + 3];    // the flank's end
        const double a7 = 7.0 * PI / 180.0;
        EXPECT_NEAR(c[0], ip.land + ip.flank_length * cos(a7), 1e-18);
        EXPECT_NEAR(c[1], ip.flank_length * sin(a7), 1e-18);
        EXPECT_EQ(tags[(e + 1) % ns], INSERT_FLANK);
      }
    }
    EXPECT_EQ(nland, 1) << "radius " << r;
    EXPECT_EQ(nedge, r > 0.0 ? ip.arc_segments : 0) << "the arc on the rake side only, radius " << r;
    EXPECT_EQ(nflank, 2);
    const std::vector<double> tri = make_cutting_insert(ip, 3);
    EXPECT_TRUE(mesh_closure(tri).closed()) << "radius " << r;
    EXPECT_NEAR(mesh_volume(tri), area * ip.width, 1e-12 * area * ip.width);
    // without the land: the flank from the arc at 270 + alpha degrees, no vertex on y = 0 but the tip
    ip.land = 0.0;
    const std::vector<double> seg0 = make_cutting_insert(ip, 2);
    int on0 = 0;
    for (size_t k = 0; k < seg0.size(); k += 6) on0 += seg0[k + 1] == 0.0;
    EXPECT_EQ(on0, 1) << "radius " << r;
  }
  InsertParams bad;
  bad.land = -1e-6;
  EXPECT_THROW(make_cutting_insert(bad, 2), std::invalid_argument);
  bad.land = INFINITY;
  EXPECT_THROW(make_cutting_insert(bad, 3), std::invalid_argument);
}

/* ----------------------------------------------------------------------
   contact bins
------------------------------------------------------------------------- */

namespace {

void check_bins(const std::vector<double> &elem, int nvert, double bin_size, unsigned seed,
                int &nonempty)
{
  TriBins bins;
  tri_bin_build(elem, nvert, bin_size, bins);
  const TriBinView g = bins.view();
  const int ne = (int) (elem.size() / (3 * nvert));
  ASSERT_EQ(g.nelem, ne);
  EXPECT_EQ(g.halo, g.size);    // each bin lists the elements within one bin size of it
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t i = 0; i < elem.size() / 3; i++)
    for (int k = 0; k < 3; k++) {
      lo[k] = std::min(lo[k], elem[3 * i + k]);
      hi[k] = std::max(hi[k], elem[3 * i + k]);
    }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int MAXC = 4096;
  std::vector<int> cand(MAXC);
  for (int ip = 0; ip < 2000; ip++) {
    double x[3];
    if (ip % 2) {    // anywhere around the tool
      for (int k = 0; k < 3; k++) {
        const double ext = hi[k] - lo[k];
        x[k] = lo[k] - 0.2 * ext + 1.4 * ext * u(rng);
      }
    } else {    // near a random element point
      const double *v = elem.data() + 3 * nvert * (int) (u(rng) * ne * 0.999999);
      const double w1 = u(rng), w2 = nvert == 3 ? u(rng) * (1.0 - w1) : 0.0;
      for (int k = 0; k < 3; k++)
        x[k] = v[k] + w1 * (v[3 + k] - v[k]) + (nvert == 3 ? w2 * (v[6 + k] - v[k]) : 0.0) +
            2.0 * bin_size * (u(rng) - 0.5);
    }
    if (nvert == 2) x[2] = 0.0;
    // radii up to the halo (one bin read), the halo itself (the contact's query) and beyond (the bins
    // the radius covers)
    const double radius = ip % 5 == 1 ? bins.halo : bin_size * (ip % 3 == 0 ? 2.5 : 0.6) * u(rng);
    const int nc = tri_bin_query(g, x, radius, cand.data(), MAXC);
    ASSERT_LE(nc, MAXC);
    std::vector<int> got(cand.begin(), cand.begin() + nc), want;
    for (int e = 0; e < ne; e++) {
      double q[3];
      int region;
      if (tri_bin_closest(g, e, x, q, region) <= radius * radius) want.push_back(e);
    }
    std::sort(got.begin(), got.end());
    ASSERT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << "duplicates";
    EXPECT_EQ(got, want) << "point " << ip;
    if (!want.empty()) nonempty++;
    if (want.size() >= 2) {    // overflow is reported
      int small[1];
      EXPECT_GT(tri_bin_query(g, x, radius, small, 1), 1);
    }
  }
}

}    // namespace

TEST(TriBin, QueryMatchesBruteForce)
{
  // the insert (long slivers on rake and flank) plus a random triangle soup
  InsertParams ip;
  ip.rake_angle = 6.0;
  ip.edge_radius = 0.02;
  ip.arc_segments = 10;
  ip.width = 0.5;
  std::vector<double> tri = make_cutting_insert(ip, 3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.5, 1.0);
  for (int t = 0; t < 300; t++) {
    const double c[3] = {u(rng), u(rng), 0.5 * u(rng)};
    for (int m = 0; m < 3; m++)
      for (int k = 0; k < 3; k++) tri.push_back(c[k] + 0.1 * u(rng));
  }
  int nonempty = 0;
  check_bins(tri, 3, 0.05, 11, nonempty);
  check_bins(tri, 3, 0.013, 12, nonempty);
  EXPECT_GT(nonempty, 500);
  // 2D segments
  nonempty = 0;
  ip.arc_segments = 16;
  std::vector<double> seg = make_cutting_insert(ip, 2);
  for (int t = 0; t < 200; t++) {
    const double c[2] = {u(rng), u(rng)};
    for (int m = 0; m < 2; m++) {
      seg.push_back(c[0] + 0.1 * u(rng));
      seg.push_back(c[1] + 0.1 * u(rng));
      seg.push_back(0.3);    // z ignored
    }
  }
  check_bins(seg, 2, 0.04, 13, nonempty);
  EXPECT_GT(nonempty, 500);
  // far away: nothing
  TriBins bins;
  tri_bin_build(tri, 3, 0.05, bins);
  const double far[3] = {100.0, 0.0, 0.0};
  int out[4];
  EXPECT_EQ(tri_bin_query(bins.view(), far, 1.0, out, 4), 0);
  // many bins requested: the bin size grows to respect max_bins
  tri_bin_build(tri, 3, 1e-5, bins, 1000);
  EXPECT_LE((long) bins.n[0] * bins.n[1] * bins.n[2], 1000);
}

// signed distance to a closed tool: the depth inside (also deeper than the first search
// radius), the distance outside within the tool's box, +inf beyond it; 2D outlines too
TEST(TriBin, SignedDistanceInsideAndOutside)
{
  const double lo1[3] = {0.0, 0.0, 0.0}, hi1[3] = {4.0, 10.0, 10.0};
  const double lo2[3] = {6.0, 0.0, 0.0}, hi2[3] = {10.0, 10.0, 10.0};
  std::vector<double> tri = sphcut_test::box_triangles(lo1, hi1);
  const std::vector<double> b2 = sphcut_test::box_triangles(lo2, hi2);
  tri.insert(tri.end(), b2.begin(), b2.end());
  TriBins bins;
  tri_bin_build(tri, 3, 0.5, bins);
  const double p1[3] = {2.0, 5.0, 5.0}, p2[3] = {3.7, 5.0, 5.0}, p3[3] = {5.0, 5.0, 5.0}, p4[3] = {5.0, 5.0, 11.0};
  EXPECT_NEAR(tool_signed_distance(bins, p1, 0.25), -2.0, 1e-12);    // 8 doublings of the radius
  EXPECT_NEAR(tool_signed_distance(bins, p2, 0.25), -0.3, 1e-12);
  EXPECT_NEAR(tool_signed_distance(bins, p3, 0.25), 1.0, 1e-12);     // in the gap
  EXPECT_EQ(tool_signed_distance(bins, p4, 0.25), HUGE_VAL);         // beyond the box
  // 2D: the generated insert's section (rake angle 0, sharp: rake face x = 0 from (0, 0) to
  // (0, 1), flank end (cos 7, sin 7) deg), a point inside near the rake face, one beyond the
  // back face (from (0, 1) to the flank end) but within the tool's box
  InsertParams ip;
  const std::vector<double> seg = make_cutting_insert(ip, 2);
  TriBins b2d;
  tri_bin_build(seg, 2, 0.1, b2d);
  const double in2[3] = {0.1, 0.5, 0.0}, out2[3] = {0.9, 0.9, 0.0};
  const double bx = cos(7.0 * PI / 180.0), by = sin(7.0 * PI / 180.0) - 1.0;    // back face direction
  const double dback = fabs(out2[0] * by - (out2[1] - 1.0) * bx) / sqrt(bx * bx + by * by);
  EXPECT_NEAR(tool_signed_distance(b2d, in2, 0.05), -0.1, 1e-12);
  EXPECT_NEAR(tool_signed_distance(b2d, out2, 0.05), dback, 1e-12);
}

// the XSPH drift of a particle in contact loses its component along the contact normal and
// keeps the part along the face (with the whole drift removed, the particles of the contact
// layer could pass through one another: doc/validation.md, the 41-across cut)
TEST(ContactDrift, NormalPartRemovedTangentialKept)
{
  const double c = 1.0 / sqrt(3.0);
  const double n[3] = {c, c, c};
  double xs[3] = {1.0, -2.0, 4.0};
  const double before[3] = {xs[0], xs[1], xs[2]};
  sphcut::contact_drift(xs, n);
  EXPECT_NEAR(xs[0] * n[0] + xs[1] * n[1] + xs[2] * n[2], 0.0, 1e-15);
  // the tangential part is unchanged: before - (before.n) n
  const double bn = (before[0] + before[1] + before[2]) * c;
  for (int k = 0; k < 3; k++) EXPECT_NEAR(xs[k], before[k] - bn * n[k], 1e-15);
  EXPECT_GT(fabs(xs[1]), 1.0);    // not zeroed
}
