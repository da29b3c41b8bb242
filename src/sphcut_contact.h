/* -*- c++ -*- ----------------------------------------------------------
   sphcut - node-to-surface penalty contact of SPH particles with a rigid
   triangulated tool (seed 000, sec. 3, eqs. 7-17): closest point,
   contact normal, penalty + friction force and the bin query of the
   tool triangles.  Host and device (SPHCUT_INLINE), no heap, no
   exceptions.  The host-only pieces (STL I/O, the bin build, the cutting
   insert) are in sphcut_stl.h.

   Elements: a triangle is 9 doubles (a, b, c), a 2D segment 6 doubles
   (a, b; z ignored, the segment lies in the x-y plane).  The outward
   normal of a triangle follows the right-hand rule, n = (b-a)x(c-a)/|..|
   (eq. 7, STL winding); that of a segment a->b is (b-a) x e_z =
   (dy, -dx)/|..|, i.e. a closed 2D outline traversed counter-clockwise
   has outward normals (a triangle extruded from a->b along +z has the
   same normal).

   Typical use for particle i and a rigid tool that only translates by
   disp (its mesh and bins stay in the tool frame):
     xt = x_i - disp
     n = tri_bin_query(bins, xt, rcut, cand, ncand)
     if n > ncand: grow cand to n entries and query again (n is an upper bound)
     pick the candidate with the smallest |xt - q| (on a tie the FACE hit)
     d = tri_bin_contact_normal(bins, e, xt, q, region, two_sided, nrm)
         (contact_normal with the feature's pseudo-normal: the side of an
         edge or vertex hit is right at sharp features too)
     penalty_contact(in, out)         (in.n = nrm, in.d = d, in.q = q + disp)
------------------------------------------------------------------------- */

#ifndef SPHCUT_CONTACT_H
#define SPHCUT_CONTACT_H

#include "sphcut_kernels.h"
#include "sphcut_math.h"

namespace sphcut {

// feature of a triangle (segment) holding the closest point; for a
// segment FACE is its interior and VERT_A / VERT_B its end points
enum ContactRegion {
  FACE = 0,
  EDGE_AB = 1,
  EDGE_BC = 2,
  EDGE_CA = 3,
  VERT_A = 4,
  VERT_B = 5,
  VERT_C = 6
};

/* ----------------------------------------------------------------------
   3-vector helpers
------------------------------------------------------------------------- */

SPHCUT_INLINE double dot3(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

SPHCUT_INLINE void cross3(const double *a, const double *b, double *c)
{
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

SPHCUT_INLINE void sub3(const double *a, const double *b, double *c)
{
  c[0] = a[0] - b[0];
  c[1] = a[1] - b[1];
  c[2] = a[2] - b[2];
}

SPHCUT_INLINE double len3(const double *a)
{
  return sqrt(dot3(a, a));
}

// c = a + s b
SPHCUT_INLINE void axpy3(const double *a, double s, const double *b, double *c)
{
  c[0] = a[0] + s * b[0];
  c[1] = a[1] + s * b[1];
  c[2] = a[2] + s * b[2];
}

/* ----------------------------------------------------------------------
   closest point q on segment ab to p (any dimension; a 2D tool uses z = 0).
   region: FACE (interior), VERT_A or VERT_B.  Returns |p - q|^2.
------------------------------------------------------------------------- */

SPHCUT_INLINE double closest_point_segment(const double *p, const double *a, const double *b,
                                           double *q, int &region)
{
  double ab[3], ap[3];
  sub3(b, a, ab);
  sub3(p, a, ap);
  const double t = dot3(ap, ab);
  const double l2 = dot3(ab, ab);
  if (t <= 0.0 || l2 <= 0.0) {
    region = VERT_A;
    for (int k = 0; k < 3; k++) q[k] = a[k];
  } else if (t >= l2) {
    region = VERT_B;
    for (int k = 0; k < 3; k++) q[k] = b[k];
  } else {
    region = FACE;
    axpy3(a, t / l2, ab, q);
  }
  double pq[3];
  sub3(p, q, pq);
  return dot3(pq, pq);
}

/* ----------------------------------------------------------------------
   closest point q on triangle abc to p, after Ericson, Real-Time Collision
   Detection, 5.1.5: classify p by the Voronoi regions of the vertices,
   then of the edges, else project onto the face.  This widens seed 000
   eq. 8 (face hits only) to edges and vertices, so particles at the
   rounded cutting edge and at corners are caught.  Returns |p - q|^2.
   A degenerate (zero area) triangle falls back to its three edges.
------------------------------------------------------------------------- */

SPHCUT_INLINE double closest_point_triangle(const double *p, const double *a, const double *b,
                                            const double *c, double *q, int &region)
{
  double ab[3], ac[3], ap[3], bp[3], cp[3];
  sub3(b, a, ab);
  sub3(c, a, ac);
  sub3(p, a, ap);
  sub3(p, b, bp);
  sub3(p, c, cp);

  const double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
  const double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
  const double d5 = dot3(ab, cp), d6 = dot3(ac, cp);

  // barycentric-like edge tests (Ericson's va, vb, vc)
  const double vc = d1 * d4 - d3 * d2;
  const double vb = d5 * d2 - d1 * d6;
  const double va = d3 * d6 - d5 * d4;
  const double sum = va + vb + vc;    // = |ab x ac|^2 > 0 unless degenerate

  if (!(sum > 0.0)) {
    // degenerate: best of the three edges, reported as edge/vertex of abc
    double qe[3], best = -1.0;
    const double *e0[3] = {a, b, c}, *e1[3] = {b, c, a};
    const int ereg[3] = {EDGE_AB, EDGE_BC, EDGE_CA};
    const int v0[3] = {VERT_A, VERT_B, VERT_C}, v1[3] = {VERT_B, VERT_C, VERT_A};
    for (int e = 0; e < 3; e++) {
      int r;
      const double dd = closest_point_segment(p, e0[e], e1[e], qe, r);
      if (best < 0.0 || dd < best) {
        best = dd;
        for (int k = 0; k < 3; k++) q[k] = qe[k];
        region = r == FACE ? ereg[e] : (r == VERT_A ? v0[e] : v1[e]);
      }
    }
    return best;
  }

  if (d1 <= 0.0 && d2 <= 0.0) {
    region = VERT_A;
    for (int k = 0; k < 3; k++) q[k] = a[k];
  } else if (d3 >= 0.0 && d4 <= d3) {
    region = VERT_B;
    for (int k = 0; k < 3; k++) q[k] = b[k];
  } else if (d6 >= 0.0 && d5 <= d6) {
    region = VERT_C;
    for (int k = 0; k < 3; k++) q[k] = c[k];
  } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    region = EDGE_AB;
    axpy3(a, d1 / (d1 - d3), ab, q);
  } else if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    region = EDGE_BC;
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    double bc[3];
    sub3(c, b, bc);
    axpy3(b, w, bc, q);
  } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    region = EDGE_CA;
    axpy3(a, d2 / (d2 - d6), ac, q);
  } else {
    region = FACE;
    const double v = vb / sum, w = vc / sum;
    for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k] + w * ac[k];
  }
  double pq[3];
  sub3(p, q, pq);
  return dot3(pq, pq);
}

/* ----------------------------------------------------------------------
   face normal, eq. 7: n = (b-a)x(c-a)/|..|; returns twice the area
------------------------------------------------------------------------- */

SPHCUT_INLINE double triangle_normal(const double *a, const double *b, const double *c, double *n)
{
  double u[3], v[3];
  sub3(b, a, u);
  sub3(c, a, v);
  cross3(u, v, n);
  const double l = len3(n);
  if (l > 0.0)
    for (int k = 0; k < 3; k++) n[k] /= l;
  return l;
}

// outward normal of a 2D segment a->b: (dy, -dx)/|..|, z = 0; returns the length
SPHCUT_INLINE double segment_normal(const double *a, const double *b, double *n)
{
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double l = sqrt(dx * dx + dy * dy);
  n[0] = l > 0.0 ? dy / l : 0.0;
  n[1] = l > 0.0 ? -dx / l : 0.0;
  n[2] = 0.0;
  return l;
}

/* ----------------------------------------------------------------------
   contact normal n (unit, out of the tool) and signed distance d of p to
   the closest point q found above, given the element's face normal nf and
   ps, the pseudo-normal of the feature that holds q (nullptr: nf).
     FACE hit: n = nf (eq. 7), d = nf.(p - q) (seed eq. 9 without |.|).
     EDGE / VERTEX hit: n = (p - q)/|p - q|, d = |p - q|, i.e. n points
       from the feature to the particle (rounded edge, corners).
   closed solid (two_sided = 0, default for tools read from STL): d < 0
     means the particle is behind the face, i.e. inside the tool; an
     edge/vertex hit with (p - q).ps < 0 is inside too: d = -|p - q| and
     n = (q - p)/|p - q|, so n still points out of the tool.  With ps the
     angle-weighted pseudo-normal of the feature (Baerentzen and Aanaes
     2005: an edge the sum of its two face normals, a vertex the sum of its
     face normals weighted by the face angles there; tri_bin_build) this
     sign is right at every edge and vertex of a closed mesh whatever its
     angle, provided q is the globally closest point (pick the smallest
     |p - q|, a FACE hit on ties).  The face normal of one element (ps =
     nf) is right only where the feature's angles are not sharp: outside a
     30-degree edge, for example, (p - q).nf < 0 for a particle outside.
   zero-thickness sheet (two_sided = 1, seed's plate elements, eq. 9 with
     |.|): n is flipped to the particle's side and d = |p - q| >= 0 (ps is
     not used).
   p == q on an edge/vertex: n = nf (flipped for two_sided), d = 0.
------------------------------------------------------------------------- */

SPHCUT_INLINE double contact_normal_from(const double *p, const double *q, const double *nf,
                                         const double *ps, int region, int two_sided, double *n)
{
  double pq[3];
  sub3(p, q, pq);
  if (region == FACE) {
    const double s = dot3(pq, nf);
    const double sg = (two_sided && s < 0.0) ? -1.0 : 1.0;
    for (int k = 0; k < 3; k++) n[k] = sg * nf[k];
    return sg * s;
  }
  const double l = len3(pq);
  if (!(l > 0.0)) {
    for (int k = 0; k < 3; k++) n[k] = nf[k];
    return 0.0;
  }
  const double s = dot3(pq, ps ? ps : nf);
  const double sg = (!two_sided && s < 0.0) ? -1.0 : 1.0;
  for (int k = 0; k < 3; k++) n[k] = sg * pq[k] / l;
  return sg * l;
}

/* the pseudo-normal of feature `region` of an element from its block pn of pseudo-normals
   (TriBinView::pnorm: a triangle 6 vectors, edges AB BC CA then vertices A B C; a segment 2,
   vertices A B); nullptr for a FACE hit or when pn is nullptr */
SPHCUT_INLINE const double *feature_pseudo_normal(const double *pn, int nvert, int region)
{
  if (!pn || region == FACE) return nullptr;
  if (nvert == 3) return pn + 3 * (region - EDGE_AB);
  return pn + (region == VERT_B ? 3 : 0);
}

// triangle abc; pn: its 6 pseudo-normals (nullptr: the face normal decides the side)
SPHCUT_INLINE double contact_normal(const double *p, const double *a, const double *b,
                                    const double *c, const double *q, int region, int two_sided,
                                    double *n, const double *pn = nullptr)
{
  double nf[3];
  triangle_normal(a, b, c, nf);
  return contact_normal_from(p, q, nf, feature_pseudo_normal(pn, 3, region), region, two_sided, n);
}

// 2D segment ab (x-y plane); pn: its 2 vertex pseudo-normals (nullptr: the segment normal)
SPHCUT_INLINE double contact_normal_segment(const double *p, const double *a, const double *b,
                                            const double *q, int region, int two_sided, double *n,
                                            const double *pn = nullptr)
{
  double nf[3];
  segment_normal(a, b, nf);
  return contact_normal_from(p, q, nf, feature_pseudo_normal(pn, 2, region), region, two_sided, n);
}

/* ----------------------------------------------------------------------
   penalty stiffness, eq. 10: k = PFAC E_i E_j dp/(E_i + E_j); E_j <= 0
   means a rigid tool: k = PFAC E_i dp.
   3D: force/length [N/m] (a particle column of cross section dp^2 and
   length dp: k = E* dp^2/dp).
   2D: LAMMPS 2D masses are per unit thickness (rho dx^2), so the force is
   per unit thickness too: the column has cross section dp x 1, k = E* (1 dp)/dp
   = PFAC E* [N/m per m of thickness]; dp drops out.
------------------------------------------------------------------------- */

SPHCUT_INLINE double penalty_stiffness(double E_i, double E_j, double dp, double pfac, int dim)
{
  const double estar = E_j > 0.0 ? E_i * E_j / (E_i + E_j) : E_i;
  return dim == 2 ? pfac * estar : pfac * estar * dp;
}

/* ----------------------------------------------------------------------
   damping coefficient D = DFAC 2 sqrt(k mu_red), mu_red = m_i m_j/(m_i + m_j)
   (m_j <= 0: rigid tool, mu_red = m_i), so DFAC = 1 is critical damping
   of the linear spring-dashpot.
   Deviation from seed eq. 11, D = DFAC (m_i + m_j) sqrt(k/mu_red): that
   has the right units but equals 2 sqrt(k mu_red) only when
   (m_i + m_j)^2 = 2 m_i m_j (never; equal masses give 2x critical) and
   diverges for a rigid tool (m_j -> infinity).
------------------------------------------------------------------------- */

SPHCUT_INLINE double penalty_damping(double k, double m_i, double m_j, double dfac)
{
  const double mred = m_j > 0.0 ? m_i * m_j / (m_i + m_j) : m_i;
  return dfac * 2.0 * sqrt(k * mred);
}

/* ----------------------------------------------------------------------
   time step limit of the penalty spring (per particle in or near contact):
     omega = sqrt(k/m) (rigid tool: the particle mass; eq. 10 stiffness),
     dt_crit = 2 (sqrt(1 + z^2) - z)/omega, z = DFAC (z <= 1)
   is the stability limit of velocity Verlet for the damped linear spring
   (undamped: omega dt < 2).  Stable is not enough: the spring switches on
   and off with the penetration (its stiffness jumps at delta = 0), and
   velocity Verlet then does not conserve the energy of a bounce.  Measured
   (test_contact Impact.BlockOnFaceAndEdgeConservesEnergy, 6^3 elastic
   block at 10 m/s, cfl 0.3, dfac 0, mu 0), energy gain face / edge against
   frac = dt/dt_crit / cfl (fix contact/tri-penalty dtfac):
     0.5: 0.32 / 0.086 %,  0.25: 0.099 / 0.028 %,  0.15: 0.026 / 0.009 %,
     0.1: 0.0094 / 0.0026 %  (about frac^2.5; limit applied within 2h of the tool).
   That is seed 000's law (onset 0).  The smooth onset (penalty_normal_force, onset > 0) has a
   continuous stiffness and removes that growth: +0.0041 / +0.0055 % at the Courant step (onset
   0.2; test_contact Impact.OnsetStudy), so the step need not be cut for the energy; the default
   dtfac 0.5 (omega dt <= 0.3 at cfl 0.3, undamped) is chosen from the 2D cut at 41 across: Fc
   within 2.1 % of a run at half the step, Ft 10 % apart with no trend in the step (38.7-42.7 N/mm)
   (bench/gpu/RESULTS.md, doc/fix_contact_tri_penalty.rst).  The caller passes frac = dtfac cfl; seed 000's law as before is onset 0
   dtfac 0.15.
------------------------------------------------------------------------- */

SPHCUT_INLINE double penalty_dt_limit(double k, double m, double dfac, double frac)
{
  if (!(k > 0.0) || !(m > 0.0)) return 1.0e300;
  const double omega = sqrt(k / m);
  const double z = dfac < 1.0 ? dfac : 1.0;
  return frac * 2.0 * (sqrt(1.0 + z * z) - z) / omega;
}

// the stability limit of the penalty spring of one particle (Young's modulus E, spacing dp, mass
// m) against a tool of modulus E_tool (eq. 10 stiffness, penalty_dt_limit with frac 1)
SPHCUT_INLINE double contact_spring_dt(double E, double E_tool, double dp, double pfac, double dfac, double m,
                                       int dim)
{
  return penalty_dt_limit(penalty_stiffness(E, E_tool, dp, pfac, dim), m, dfac, 1.0);
}

/* ----------------------------------------------------------------------
   normal force of the penalty spring-dashpot at penetration delta > 0 and rate delta_dot,
   eq. 12: F_N = k delta + D delta_dot (onset d0 = 0, the seed's law), or, with a smooth onset
   over d0 > 0 (fix contact/tri-penalty onset), a spring whose stiffness ramps linearly from 0 to
   k over the first d0 of penetration and a dashpot ramped alike:
     F_N = k delta^2/(2 d0) + (delta/d0) D delta_dot     delta <  d0
         = k (delta - d0/2) + D delta_dot                delta >= d0
   The force and its potential are then continuous in delta and so is the stiffness: velocity
   Verlet integrates a contact that switches on within a step without the energy gain of the
   stiffness jump (see penalty_dt_limit), and the step need not be cut to keep it small.  The
   price: d0/2 more penetration under the same load; the stiffness is never above k, so the
   stability limit is the seed law's.
------------------------------------------------------------------------- */

SPHCUT_INLINE double penalty_normal_force(double k, double damp, double delta, double delta_dot, double d0)
{
  if (d0 > 0.0 && delta < d0) return (0.5 * k * delta + damp * delta_dot) * delta / d0;
  return k * (d0 > 0.0 ? delta - 0.5 * d0 : delta) + damp * delta_dot;
}

/* friction coefficient from a table mu(T) (n points, T ascending), clamped at the ends */
SPHCUT_INLINE double mu_table(const double *t, const double *mu, int n, double temp)
{
  if (temp <= t[0]) return mu[0];
  if (temp >= t[n - 1]) return mu[n - 1];
  int k = 1;
  while (t[k] < temp) k++;
  const double s = (temp - t[k - 1]) / (t[k] - t[k - 1]);
  return mu[k - 1] + s * (mu[k] - mu[k - 1]);
}

/* ----------------------------------------------------------------------
   the friction law of fix contact/tri-penalty (its keywords friction, stick, vreg, tfac, mu):
   the force law with its parameters, and the coefficient mu(T) at the particle's temperature.
     kind     STATIC   Coulomb friction capped at the force that stops the trial sliding within
                       the step: static friction up to mu F_N (friction static, the fix's default)
              COULOMB  Coulomb friction against the sliding velocity (friction coulomb)
              MEMORY   elastic predictor and return to the Coulomb cone (friction memory)
              (force(): the formulas are in penalty_contact's comment)
     mu(T)    MU_CONST mu0
              MU_TABLE the nmu points (mu_t, mu_v) that the driver points at (host or device
                       copies), linear in between, clamped at the ends (mu_table)
              MU_HOST  host_mu(host_ctx, T): a function of the host driver (fix contact/tri-penalty
                       evaluates its equal-style variable mu v_name); never on a device (there
                       mu0; the /kk fix refuses it: host_only())
   A plain struct of values and pointers, copied to the device with the driver's parameters
   (ContactIn::friction); a driver fills it once and changes only the table pointers.  A new law
   is a kind here with its branch in force(), and its keyword in the fix.
------------------------------------------------------------------------- */

struct ContactIn;
struct ContactOut;

struct FrictionLaw {
  enum Kind { COULOMB = 0, STATIC, MEMORY };
  enum MuKind { MU_CONST = 0, MU_TABLE, MU_HOST };
  int kind = COULOMB;
  double v_reg = 0.0;    // STATIC, COULOMB: linear regularisation below this sliding speed (<= 0: none)
  double tfac = 0.1;     // MEMORY: alpha of the predictor, tangential stiffness alpha m/dt^2
  int mu_kind = MU_CONST;
  double mu0 = 0.0;
  int nmu = 0;
  const double *mu_t = nullptr, *mu_v = nullptr;
  double (*host_mu)(void *, double) = nullptr;
  void *host_ctx = nullptr;

  // the law keeps each particle's friction force from step to step (the FMEM state columns)
  SPHCUT_INLINE bool memory() const { return kind == MEMORY; }
  // mu(T) needs the host (a device cannot evaluate it)
  SPHCUT_INLINE bool host_only() const { return mu_kind == MU_HOST; }
  SPHCUT_INLINE double mu(double temp) const
  {
    if (mu_kind == MU_TABLE) return mu_table(mu_t, mu_v, nmu, temp);
#if !defined(__CUDA_ARCH__) && !defined(__HIP_DEVICE_COMPILE__)
    if (mu_kind == MU_HOST) return host_mu(host_ctx, temp);
#endif
    return mu0;
  }
  // the friction force of a contact with normal force fn and tangential relative velocity vt:
  // out.ft, out.slip, out.fric_power (in.mu, in.dt, in.mass, in.n, in.f_other, in.ft_old)
  SPHCUT_INLINE void force(const ContactIn &in, double fn, const double *vt, ContactOut &out) const;
  SPHCUT_INLINE void sliding_force(const ContactIn &in, double fn, const double *vt, ContactOut &out) const;
  SPHCUT_INLINE void memory_force(const ContactIn &in, double fn, const double *vt, ContactOut &out) const;
};

/* ----------------------------------------------------------------------
   one particle - tool contact pair
------------------------------------------------------------------------- */

struct ContactIn {
  double x[3] = {0.0, 0.0, 0.0};        // particle position (diagnostics only: d, n carry the geometry)
  double v[3] = {0.0, 0.0, 0.0};        // particle velocity
  double mass = 0.0;                    // particle mass (2D: per unit thickness)
  double h = 0.0;                       // smoothing length
  double vtool[3] = {0.0, 0.0, 0.0};    // tool velocity at q
  double q[3] = {0.0, 0.0, 0.0};        // contact point (diagnostics only)
  double n[3] = {0.0, 0.0, 0.0};        // unit normal out of the tool (contact_normal)
  double d = 0.0;                       // signed distance p - q (< 0: inside the tool)
  double E_particle = 0.0;              // Young's modulus of the workpiece
  double E_tool = 0.0;                  // Young's modulus of the tool (<= 0: rigid)
  double m_tool = 0.0;                  // tool mass (<= 0: rigid)
  double dp = 0.0;                      // particle spacing
  int dim = 3;                          // 2: forces per unit thickness (eq. 10 note)
  double pfac = 1.0;                    // penalty factor, eq. 10
  double dfac = 0.0;                    // fraction of critical damping (penalty_damping)
  double sfac = 1.2;                    // h = SFAC dp, eq. 9
  double onset = 0.0;                   // > 0: the spring ramps in over this fraction of the contact radius
  double f_other[3] = {0.0, 0.0, 0.0};  // the other forces on the particle (pair, body) this step
  FrictionLaw friction;                 // the friction law (the same for every particle)
  double mu = 0.0;                      // its coefficient at the particle's temperature, friction.mu(T), eq. 13
  double dt = 0.0;                      // the time step the friction is based on (FrictionLaw)
  double ft_old[3] = {0.0, 0.0, 0.0};   // friction force of the particle's last step (friction memory; 0: new contact)
};

struct ContactOut {
  int active;           // 1 if delta > 0
  double f[3];          // total contact force on the particle, eq. 16 (tool gets -f)
  double fn;            // normal force (n component), eq. 12; < 0 only while leaving
  double ft[3];         // tangential (friction) force, eq. 13
  double delta;         // penetration, eq. 9 (also when inactive)
  double delta_dot;     // penetration rate -n.(v - vtool)
  double vslide;        // sliding speed |v_rel,t|, eq. 14
  double fric_power;    // friction heat source: max(0, -F_T . v_rel,t); memory law: mu F_N times the slip rate
  double k, damp;       // stiffness and damping coefficient used
  int slip;             // 1 if the friction is at the Coulomb limit mu F_N (diagnostics)
};

/* ----------------------------------------------------------------------
   penalty force, eqs. 9-17:
     delta = 0.5 h/SFAC - d                                  (eq. 9)
     active if delta > 0.  The seed also requires the pair to approach
       (delta_dot > 0); that filter only concerns pairs not yet in
       contact, which get no force here anyway, so a penetrated pair
       keeps its spring force while it separates (elastic rebound).
     delta_dot = -n.(v_i - v_tool), the penetration rate
     F_N = (k delta + D delta_dot) n                         (eq. 12)
       the damping opposes the motion: seed eq. 12 writes -D delta_dot
       with delta_dot the rate of the distance d; both are the same force.
       Not clipped at 0: while a penetrated particle moves out the damping
       term may pull briefly, as in eq. 12; this makes DFAC = 1 exactly
       critical (no rebound) and DFAC < 1 rebound with the linear
       oscillator's restitution exp(-pi z/sqrt(1-z^2)), z = DFAC.  The
       force vanishes with the penetration, so there is no static adhesion.
     v_t = v_rel - (v_rel.n) n, t = v_t/|v_t|                (eqs. 14-15)
   the friction force F_T (in.friction.force(), FrictionLaw), static limit and Coulomb
   (friction.kind STATIC, COULOMB):
     F_T = -min(mu |F_N| min(1, |w|/v_reg), m |w|/dt) w/|w|     (eq. 13)
       w = v_t + dt/m f_other,t (STATIC), else w = v_t: the
       sliding velocity the particle would have after the step without
       friction (velocity Verlet: v^(n+3/2) = v^(n+1/2) + dt/m F^(n+1)),
       f_other the other forces on the particle (its SPH neighbours).
       Friction opposes that trial sliding and is capped at the stick
       force m |w|/dt that stops it within the step: a particle held
       by its neighbours against the tool sticks (static friction up to
       mu F_N), a sliding one gets full Coulomb friction, and friction
       never reverses the sliding in a step (no chattering); COULOMB:
       without that cap.  Linear regularisation below v_reg (v_reg <= 0:
       plain Coulomb).
   friction with memory (friction.kind MEMORY; LS-DYNA, the IWF GPU code):
     f_o = f_old - (f_old.n) n       (last step's friction force, projected to the tangent plane)
     f* = f_o - alpha m v_t/dt       (elastic predictor: a tangential spring of stiffness
                                      alpha m/dt^2 stretched by the step's sliding v_t dt)
     F_T = f*                        if |f*| <= mu F_N (stick)
         = mu F_N f* / |f*|          otherwise (slip: return to the Coulomb cone)
     F_T = 0 while F_N <= 0; the caller keeps F_T as the particle's f_old of the next step
     and resets it to 0 when the contact ends.  Friction heat: the friction force times the
     slip rate (|f*| - mu F_N) dt/(alpha m), i.e. mu F_N |v_t| in steady sliding and 0 while
     the tangential spring only stretches (stick).  v_reg is not used.
   f = F_N + F_T                                             (eqs. 16-17)
------------------------------------------------------------------------- */

// the static-limit and the Coulomb law
SPHCUT_INLINE void FrictionLaw::sliding_force(const ContactIn &in, double fn, const double *vt, ContactOut &out) const
{
  const double dts = kind == STATIC ? in.dt : 0.0;    // > 0: the stick limit over this step
  // trial sliding velocity w over the step without friction
  double w[3] = {vt[0], vt[1], vt[2]};
  if (dts > 0.0) {
    const double fon = dot3(in.f_other, in.n);
    for (int k = 0; k < 3; k++) w[k] += dts / in.mass * (in.f_other[k] - fon * in.n[k]);
  }
  const double ws = len3(w);
  if (in.mu > 0.0 && fn > 0.0 && ws > 0.0) {    // no friction without compression
    const double ramp = (v_reg > 0.0 && ws < v_reg) ? ws / v_reg : 1.0;
    double ftmag = in.mu * fn * ramp;
    out.slip = ramp == 1.0;
    if (dts > 0.0) {
      const double fstick = in.mass * ws / dts;
      if (ftmag > fstick) {
        ftmag = fstick;
        out.slip = 0;
      }
    }
    for (int k = 0; k < 3; k++) out.ft[k] = -ftmag * w[k] / ws;
    // power of the friction force against the sliding (> 0: dissipated into heat)
    const double p = -dot3(out.ft, vt);
    out.fric_power = p > 0.0 ? p : 0.0;
  }
}

// the memory law: elastic predictor, return to the Coulomb cone
SPHCUT_INLINE void FrictionLaw::memory_force(const ContactIn &in, double fn, const double *vt, ContactOut &out) const
{
  if (!(in.mu > 0.0) || !(fn > 0.0) || !(in.dt > 0.0) || !(in.mass > 0.0)) return;    // out.ft = 0
  const double fon = dot3(in.ft_old, in.n);
  const double kdt = tfac * in.mass / in.dt;    // stiffness alpha m/dt^2 times dt
  double ts[3];
  for (int k = 0; k < 3; k++) ts[k] = in.ft_old[k] - fon * in.n[k] - kdt * vt[k];
  const double tsl = len3(ts), fmax = in.mu * fn;
  if (tsl > fmax) {
    for (int k = 0; k < 3; k++) out.ft[k] = fmax * ts[k] / tsl;
    out.slip = 1;
    out.fric_power = fmax * (tsl - fmax) / kdt;
  } else {
    for (int k = 0; k < 3; k++) out.ft[k] = ts[k];
  }
}

SPHCUT_INLINE void FrictionLaw::force(const ContactIn &in, double fn, const double *vt, ContactOut &out) const
{
  if (kind == MEMORY) memory_force(in, fn, vt, out);
  else sliding_force(in, fn, vt, out);
}

// the particle - tool pair: eqs. 9-17 as described above penalty_contact's comment
SPHCUT_INLINE void penalty_contact(const ContactIn &in, ContactOut &out)
{
  out.active = out.slip = 0;
  out.fn = out.vslide = out.fric_power = 0.0;
  for (int k = 0; k < 3; k++) out.f[k] = out.ft[k] = 0.0;

  double vrel[3];
  sub3(in.v, in.vtool, vrel);
  const double vn = dot3(vrel, in.n);
  const double rc = 0.5 * in.h / in.sfac;    // contact radius, eq. 9
  out.delta = rc - in.d;
  out.delta_dot = -vn;
  out.k = penalty_stiffness(in.E_particle, in.E_tool, in.dp, in.pfac, in.dim);
  out.damp = penalty_damping(out.k, in.mass, in.m_tool, in.dfac);
  if (!(out.delta > 0.0)) return;
  out.active = 1;

  // not clipped: while the particle leaves (delta_dot < 0) the damping may pull (eq. 12 as
  // written), so DFAC = 1 is exactly critical: no rebound.  Friction takes max(F_N, 0).
  const double fn = penalty_normal_force(out.k, out.damp, out.delta, out.delta_dot, in.onset * rc);
  out.fn = fn;

  double vt[3];
  axpy3(vrel, -vn, in.n, vt);
  const double vs = len3(vt);
  out.vslide = vs;
  in.friction.force(in, fn, vt, out);
  for (int k = 0; k < 3; k++) out.f[k] = fn * in.n[k] + out.ft[k];
}

/* ----------------------------------------------------------------------
   uniform bin grid over the tool elements, in the tool's own frame (the
   tool only translates: query with x - displacement).  Flat CSR arrays,
   so a Kokkos port copies them into Views and points a TriBinView at the
   device copies.  Built on the host by tri_bin_build() (sphcut_stl.h):
   element e is listed in every bin whose box it may touch (its bounding
   box and plane overlap the bin box), its bounding sphere (seed 000: one
   sphere per triangle) is the cheap prefilter of the query.
------------------------------------------------------------------------- */

struct TriBinView {
  int nvert;               // 3: triangles (9 doubles), 2: 2D segments (6 doubles)
  int nelem;
  const double *elem;      // element vertices, tool frame
  const double *sphere;    // 4 per element: centre, radius
  double lo[3];            // grid origin
  double size;             // bin edge length
  int n[3];                // bins per direction (n[2] = 1 for segments)
  const int *start;        // n[0] n[1] n[2] + 1 offsets into index
  const int *index;        // element ids, bin by bin (bin = (iz n[1] + iy) n[0] + ix)
  const double *pnorm = nullptr;    // per element its feature pseudo-normals (tri_bin_pnorm_stride
                                    // doubles, see feature_pseudo_normal), or nullptr: face normals
  double halo = 0.0;       // each bin lists every element within halo of its box (tri_bin_build:
                           // the bin size), so that a query of radius <= halo reads one bin
};

// doubles of pseudo-normals per element: a triangle 3 edges + 3 vertices, a segment 2 vertices
SPHCUT_INLINE int tri_bin_pnorm_stride(int nvert)
{
  return nvert == 3 ? 18 : 6;
}

/* the signed distance and outward normal of p (tool frame) against element e of the bins, for
   its closest point q in feature region (contact_normal with the feature's pseudo-normal) */
SPHCUT_INLINE double tri_bin_contact_normal(const TriBinView &g, int e, const double *p, const double *q,
                                            int region, int two_sided, double *n)
{
  const double *v = g.elem + (g.nvert == 3 ? 9 : 6) * e;
  const double *pn = g.pnorm ? g.pnorm + tri_bin_pnorm_stride(g.nvert) * e : nullptr;
  return g.nvert == 3 ? contact_normal(p, v, v + 3, v + 6, q, region, two_sided, n, pn)
                      : contact_normal_segment(p, v, v + 3, q, region, two_sided, n, pn);
}

/* closest point of element e to p (triangle or segment); returns |p - q|^2 */

SPHCUT_INLINE double tri_bin_closest(const TriBinView &g, int e, const double *p, double *q,
                                     int &region)
{
  const double *v = g.elem + (g.nvert == 3 ? 9 : 6) * e;
  if (g.nvert == 3) return closest_point_triangle(p, v, v + 3, v + 6, q, region);
  double pp[3] = {p[0], p[1], 0.0};
  return closest_point_segment(pp, v, v + 3, q, region);
}

/* the bins a query of radius around x covers (ilo..ihi per direction; z a single bin for 2D
   segments); false when the sphere misses the grid */
SPHCUT_INLINE bool tri_bin_range(const TriBinView &g, const double *x, double radius, int *ilo, int *ihi)
{
  const int nd = g.nvert == 3 ? 3 : 2;
  const double pad = 1.0e-9 * g.size;
  ilo[2] = ihi[2] = 0;
  for (int k = 0; k < nd; k++) {
    const double flo = floor((x[k] - radius - pad - g.lo[k]) / g.size);
    const double fhi = floor((x[k] + radius + pad - g.lo[k]) / g.size);
    if (fhi < 0.0 || flo > g.n[k] - 1.0) return false;
    ilo[k] = flo < 0.0 ? 0 : (int) flo;
    ihi[k] = fhi > g.n[k] - 1.0 ? g.n[k] - 1 : (int) fhi;
  }
  return true;
}

/* every element listed in the bins around x whose closest point lies within distance radius
   (tool frame; segments: the distance in the x-y plane), bin by bin: visit(e, d2, q, region),
   d2 = |x - q|^2.  The embedded sphere of each element is the cheap prefilter (seed 000).  A
   query of radius <= g.halo reads the one bin holding x, whose list holds every element within
   halo of the bin (each element once, in the order of their ids; the 2D contact kernel
   on a GPU took as long as with the bins walked: bench/gpu/RESULTS.md); a larger one the bins the
   radius covers, where an element listed in several bins is visited once per bin. */
template <class Visit>
SPHCUT_INLINE void tri_bin_visit(const TriBinView &g, const double *x, double radius, Visit &&visit)
{
  if (g.nelem <= 0 || g.n[0] <= 0) return;
  const double xx[3] = {x[0], x[1], g.nvert == 3 ? x[2] : 0.0};
  const double r2 = radius * radius;
  auto visit_bin = [&](int bin) {
    for (int m = g.start[bin]; m < g.start[bin + 1]; m++) {
      const int e = g.index[m];
      const double *s = g.sphere + 4 * e;
      const double dc2 = sq(xx[0] - s[0]) + sq(xx[1] - s[1]) + sq(xx[2] - s[2]);
      if (dc2 > sq(radius + s[3])) continue;
      double q[3];
      int region;
      const double d2 = tri_bin_closest(g, e, xx, q, region);
      if (d2 <= r2) visit(e, d2, q, region);
    }
  };
  if (radius <= g.halo) {
    int ib[3] = {0, 0, 0};
    for (int k = 0; k < (g.nvert == 3 ? 3 : 2); k++) {
      const double f = floor((x[k] - g.lo[k]) / g.size);
      if (!(f >= 0.0 && f < g.n[k])) return;    // beyond the grid: farther than halo from every element
      ib[k] = (int) f;
    }
    visit_bin((ib[2] * g.n[1] + ib[1]) * g.n[0] + ib[0]);
    return;
  }
  int ilo[3], ihi[3];
  if (!tri_bin_range(g, x, radius, ilo, ihi)) return;
  for (int iz = ilo[2]; iz <= ihi[2]; iz++)
    for (int iy = ilo[1]; iy <= ihi[1]; iy++)
      for (int ix = ilo[0]; ix <= ihi[0]; ix++) visit_bin((iz * g.n[1] + iy) * g.n[0] + ix);
}

/* ----------------------------------------------------------------------
   all elements within distance radius of x (tool frame; segments: the
   distance in the x-y plane).  Ids go to out[0..maxout-1] without
   duplicates, in no particular order; returns how many were found (more
   than maxout means out is incomplete: enlarge it).
------------------------------------------------------------------------- */

SPHCUT_INLINE int tri_bin_query(const TriBinView &g, const double *x, double radius, int *out,
                                int maxout)
{
  int count = 0;
  tri_bin_visit(g, x, radius, [&](int e, double, const double *, int) {
    const int nstored = count < maxout ? count : maxout;
    for (int j = 0; j < nstored; j++)
      if (out[j] == e) return;
    // an overflowed list cannot be deduplicated: count stays an upper bound
    if (count < maxout) out[count] = e;
    count++;
  });
  return count;
}

/* ----------------------------------------------------------------------
   the nearest element to x (tool frame) among those within distance
   radius: its id (-1: none), closest point q and feature region.  Ties
   (within 1e-12 relative) go to a face over an edge or vertex, so the
   normal of a particle over a face interior is the face normal.  No
   candidate buffer (the device path cannot grow one); an element visited
   again in another bin cannot change the choice.
------------------------------------------------------------------------- */

SPHCUT_INLINE int tri_bin_nearest(const TriBinView &g, const double *x, double radius, double *q,
                                  int &region)
{
  region = 0;
  int best = -1;
  double bestd2 = 1.0e300;
  tri_bin_visit(g, x, radius, [&](int e, double d2, const double *qe, int reg) {
    if (d2 < bestd2 * (1.0 - 1.0e-12) || (d2 <= bestd2 * (1.0 + 1.0e-12) && reg == FACE && region != FACE)) {
      best = e;
      bestd2 = d2;
      region = reg;
      for (int k = 0; k < 3; k++) q[k] = qe[k];
    }
  });
  return best;
}

/* ----------------------------------------------------------------------
   the tool surface seen by a particle at xt (tool frame): nearest element
   within the kernel support 2h (support_radius: particles deeper than the
   contact radius still find the surface), signed distance d (< 0 inside),
   outward unit normal n, point q (tool frame), and the feature (FACE,
   EDGE_*, VERT_*) of that element holding q.  Returns the element, -1 when
   none lies within 2h.
------------------------------------------------------------------------- */

SPHCUT_INLINE int tool_surface(const TriBinView &g, const double *xt, double h, double &d, double *n,
                               double *q, int &region)
{
  const int e = tri_bin_nearest(g, xt, support_radius(h), q, region);
  if (e < 0) return -1;
  d = tri_bin_contact_normal(g, e, xt, q, region, 0, n);
  return e;
}

/* the XSPH drift of a particle in contact (Monaghan's smoothed velocity, s[XSPH], with which
   fix sph/jc-thermal moves it): the spring does work with the velocity v that the kinetic
   energy sees, so the particle must not drift along the contact normal n (it would move into
   or out of the spring without that work: energy from nothing).  Along the face the drift
   stays: it keeps the particles of the contact layer from passing through one another.  (With
   all of the drift removed, two particles stuck on the rake face of the 41-across cut came
   within 0.12 spacings of each other and flew apart at 600 m/s.)                               */
SPHCUT_INLINE void contact_drift(double *xsph, const double *n)
{
  const double dn = xsph[0] * n[0] + xsph[1] * n[1] + xsph[2] * n[2];
  for (int k = 0; k < 3; k++) xsph[k] -= dn * n[k];
}

/* the decomposition by tool feature (fix contact/tri-penalty vector 16-47), in two parts so that
   the sums can be formed later from stored contacts (fix contact/tri-penalty/kk forms them only
   when they are read):
   contact_record keeps what the decomposition needs of one contact, rec[DREC_*]: the normal force
   on the tool x y, the friction force on the tool x y, F_N, |F_T|, 1 at the Coulomb limit;
   decompose_record adds a record to the feature's sums dc: dc[0..1] normal force on the tool x y,
   dc[2..3] friction force on the tool x y, dc[4] contacts, dc[5] sum F_N, dc[6] sum |F_T|,
   dc[7] contacts at the Coulomb limit */
enum { DREC_NX = 0, DREC_NY, DREC_TX, DREC_TY, DREC_FN, DREC_FT, DREC_SLIP, NDREC };

SPHCUT_INLINE void contact_record(const ContactOut &out, const double *n, double *rec)
{
  for (int k = 0; k < 2; k++) {
    rec[DREC_NX + k] = -out.fn * n[k];
    rec[DREC_TX + k] = -out.ft[k];
  }
  rec[DREC_FN] = out.fn;
  rec[DREC_FT] = len3(out.ft);
  rec[DREC_SLIP] = out.slip;
}

SPHCUT_INLINE void decompose_record(const double *rec, double *dc)
{
  for (int k = 0; k < 2; k++) {
    dc[k] += rec[DREC_NX + k];
    dc[2 + k] += rec[DREC_TX + k];
  }
  dc[4] += 1.0;
  dc[5] += rec[DREC_FN];
  dc[6] += rec[DREC_FT];
  dc[7] += rec[DREC_SLIP];
}

/* a contact's share of the decomposition (the two above at once); returns |F_T| */
SPHCUT_INLINE double decompose_contact(const ContactOut &out, const double *n, double *dc)
{
  double rec[NDREC];
  contact_record(out, n, rec);
  decompose_record(rec, dc);
  return rec[DREC_FT];
}

/* the per-particle state of friction with memory, fm[0..2] the friction force of the particle's
   last step, fm[3..5] the f_old that step started from.  At the start of a step's evaluation
   (not a setup) the last friction force becomes this step's input and the state is zeroed (set
   again if the particle is in contact, so it resets when contact ends). */
SPHCUT_INLINE void memory_friction_step(double *fm)
{
  for (int k = 0; k < 3; k++) {
    fm[3 + k] = fm[k];
    fm[k] = 0.0;
  }
}

/* f_old of this evaluation: at a step its input (memory_friction_step); a setup evaluation that
   repeats the last step (a continued run) uses that step's input if the particle had friction
   then, else the current state (zero after a contact ended) */
SPHCUT_INLINE void memory_friction_input(const double *fm, bool step, bool repeat, double *ft_in)
{
  const bool had = fm[0] != 0.0 || fm[1] != 0.0 || fm[2] != 0.0;
  const int c0 = step || (repeat && had) ? 3 : 0;
  for (int k = 0; k < 3; k++) ft_in[k] = fm[c0 + k];
}

/* the penalty spring limits the time step of a particle in contact or about to be: within 10
   steps at its speed relative to the tool, |v - vtool| (dim components; the next step may be
   ~3x longer), plus h/100 */
SPHCUT_INLINE bool near_contact(double d, double h, double sfac, const double *v, const double *vtool, int dim,
                                double dt)
{
  double vr2 = 0.0;
  for (int k = 0; k < dim; k++) vr2 += (v[k] - vtool[k]) * (v[k] - vtool[k]);
  return d < 0.5 * h / sfac + 10.0 * sqrt(vr2) * dt + 0.01 * h;
}

/* ----------------------------------------------------------------------
   tool fields per facet (fix contact/tri-penalty tool_fields, wear usui):
   the contact of particle i with the tool is booked on the facet (triangle,
   2D segment) that holds its closest point q.  A contact whose q lies on an
   edge or a vertex (region != FACE) is split equally among the facets that
   share that edge or vertex (FacetShare, built on the host from exactly equal
   vertex coordinates); the weights of one contact add up to 1, so the facet
   sums of any force equal the tool's total force to round-off.
   Per contact and facet f with weight w (facet_contact_sums), c[FS_*]:
     FS_FN   w F_N                      (normal force on the tool, signed)
     FS_FT   w |F_T|                    (friction force)
     FS_VS   w v_s                      (sliding speed |v_rel,t|, weighted sum)
     FS_T    w T                        (the particle's temperature, weighted sum)
     FS_N    w                          (contacts)
     FS_WEAR Usui rate of the contact's share of the facet's normal stress:
               K sigma v_s exp(-alpha/T), sigma = max(w F_N, 0)/A_f
               (usui_rate; 0 when T <= 0)
     FS_FX.. -w f                       (force on the tool x, y, z)
   Summed over the contacts of a facet FS_WEAR is K sigma_n v_s exp(-alpha/T)
   when the contacts share v_s and T (a block sliding on a face), and the sum of
   the contacts' local rates otherwise.  The drivers weight each step's sums with
   dt (time averages over the interval).
------------------------------------------------------------------------- */

enum { FS_FN = 0, FS_FT, FS_VS, FS_T, FS_N, FS_WEAR, FS_FX, FS_FY, FS_FZ, NFS };

// the facets sharing each edge / vertex: element e, region r (EDGE_AB .. VERT_C; 2D segments
// VERT_A, VERT_B) lists elem[start[6 e + r - 1] .. start[6 e + r] - 1] (e itself included)
struct FacetShare {
  const int *start = nullptr;
  const int *elem = nullptr;
};

// Usui's wear rate dW/dt = K sigma_n v_s exp(-alpha/T) (Usui, Shirakashi, Kitagawa 1984):
// K (1/pressure), alpha (temperature), T absolute; no wear under tension or at T <= 0
SPHCUT_INLINE double usui_rate(double K, double alpha, double sigma_n, double vs, double temp)
{
  if (!(sigma_n > 0.0) || !(temp > 0.0)) return 0.0;
  return K * sigma_n * vs * exp(-alpha / temp);
}

// one contact's share w of facet f (inv_area = 1/A_f), as described above
SPHCUT_INLINE void facet_contact_sums(const ContactOut &out, double w, double temp, double inv_area, double K,
                                      double alpha, double *c)
{
  const double fn = w * out.fn;
  c[FS_FN] = fn;
  c[FS_FT] = w * len3(out.ft);
  c[FS_VS] = w * out.vslide;
  c[FS_T] = w * temp;
  c[FS_N] = w;
  c[FS_WEAR] = usui_rate(K, alpha, fn * inv_area, out.vslide, temp);
  for (int k = 0; k < 3; k++) c[FS_FX + k] = -w * out.f[k];
}

// the contact on element e (closest point in region) over the facets sharing the feature:
// add(f, c) with c[NFS] the sums of facet f, each multiplied by wt (the time step)
template <class Add>
SPHCUT_INLINE void facet_scatter(const FacetShare &s, const double *inv_area, int e, int region,
                                 const ContactOut &out, double temp, double K, double alpha, double wt, Add &&add)
{
  int b = 0, n = 0;
  if (region != FACE && s.start) {
    b = s.start[6 * e + region - 1];
    n = s.start[6 * e + region] - b;
  }
  const double w = n > 0 ? 1.0 / n : 1.0;
  for (int k = 0; k < (n > 0 ? n : 1); k++) {
    const int f = n > 0 ? s.elem[b + k] : e;
    double c[NFS];
    facet_contact_sums(out, w, temp, inv_area[f], K, alpha, c);
    for (int j = 0; j < NFS; j++) c[j] *= wt;
    add(f, c);
  }
}

}    // namespace sphcut

#endif
