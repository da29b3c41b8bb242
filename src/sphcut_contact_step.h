/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the step of fix contact/tri-penalty for one particle (host and
   device), written once for both drivers: FixContactTriPenalty::post_force
   (CPU) and the reduction kernel of fix contact/tri-penalty/kk.

   A driver fills a ContactStep with what is the same for every particle
   of an evaluation (the tool's bins, its motion, the contact parameters,
   the heat routing), then calls contact_step for each local particle with
   a sink: a small struct of the driver for particle i (as LocalAdd and
   AtomicAdd of sphcut_pair.h), through which the step reads what it needs
   of the particle when it needs it and hands out what it produces.

   sink.                     reads (gathered when needed: a particle far
                             from the tool reads only v, its state row
                             and, if it may touch the tool, x and h)
     v(k) x(k) f(k)          velocity, position, force so far (pair, body)
     h() spacing() E()       smoothing length, particle spacing (<= 0:
                             h/sfac), Young's modulus of its type
     mass()                  (read when the tool is within 2h)
     state() output()        its row of the SPH state (StateLayout) and of
                             the per-atom output (force 3, F_N, |F_T|,
                             feature + 1)
                             writes
     add(c, val)             to the sum c of the evaluation (ContactSum)
     add_force(k, val)       the contact force onto the particle's force
     dt_crit(d)              the penalty spring's stability limit d of a
                             particle in or near contact (keep the minimum)
     record(feat, rec, pen)  a contact: the record of its decomposition
                             (contact_record), the tool feature of its
                             element, the penetration / contact radius
     facet(f, c)             tool fields: facet f's sums c[NFS], times dt
                             (facet_scatter; steps only, not at a setup)
     heat_particle(q, m, acc)  friction heat power q into the particle (mass m);
                             acc: the time it acts for (dt, 0 at a setup)
     heat_tool(q)            the tool's share q to the tool SPH particles
                             around the particle: true if some took it
------------------------------------------------------------------------- */

#ifndef SPHCUT_CONTACT_STEP_H
#define SPHCUT_CONTACT_STEP_H

#include "sphcut_contact.h"
#include "sphcut_kernels.h"
#include "sphcut_state.h"

namespace sphcut {

// the rigid rotation of the tool (fix contact/tri-penalty keyword spin): the tool frame turned
// by the angle theta about the unit axis a through the point p0 of the tool frame, which the
// translation disp carries to p0 + disp.  A point X of the tool frame is at
//   x = p0 + disp + R (X - p0)            (R: Rodrigues' matrix of a and theta, row-major)
// and a particle at x is at X = p0 + R^T (x - disp - p0) in the tool frame.  The surface of the
// tool moves with v = vtool + omega a x (x - p0 - disp).  on = 0: no rotation (R the identity,
// never applied: a translating tool's contact is computed as before, to the bit)
struct ToolRotation {
  int on = 0;
  double R[9] = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  double axis[3] = {0.0, 0.0, 1.0};    // unit axis a
  double p0[3] = {0.0, 0.0, 0.0};      // a point of the axis, tool frame
  double omega = 0.0;                  // rate (rad/time) about a, right-handed
};

// Rodrigues: R = cos(t) I + sin(t) [a]x + (1 - cos(t)) a a^T, a a unit vector (row-major)
SPHCUT_INLINE void rotation_matrix(const double *a, double t, double *R)
{
  const double c = cos(t), s = sin(t), C = 1.0 - c;
  R[0] = c + C * a[0] * a[0];
  R[1] = C * a[0] * a[1] - s * a[2];
  R[2] = C * a[0] * a[2] + s * a[1];
  R[3] = C * a[1] * a[0] + s * a[2];
  R[4] = c + C * a[1] * a[1];
  R[5] = C * a[1] * a[2] - s * a[0];
  R[6] = C * a[2] * a[0] - s * a[1];
  R[7] = C * a[2] * a[1] + s * a[0];
  R[8] = c + C * a[2] * a[2];
}

// out = R in (tool frame to simulation frame), out = R^T in (back)
SPHCUT_INLINE void rotate_fwd(const double *R, const double *in, double *out)
{
  for (int r = 0; r < 3; r++) out[r] = R[3 * r] * in[0] + R[3 * r + 1] * in[1] + R[3 * r + 2] * in[2];
}
SPHCUT_INLINE void rotate_back(const double *R, const double *in, double *out)
{
  for (int c = 0; c < 3; c++) out[c] = R[c] * in[0] + R[3 + c] * in[1] + R[6 + c] * in[2];
}

// the tool-frame position xt of a point x of the simulation frame (2D: z = 0)
SPHCUT_INLINE void tool_frame_point(const double *disp, const ToolRotation &rot, const double *x, int dim,
                                    double *xt)
{
  if (!rot.on) {
    for (int k = 0; k < 3; k++) xt[k] = x[k] - disp[k];
  } else {
    double y[3], r[3];
    for (int k = 0; k < 3; k++) y[k] = x[k] - disp[k] - rot.p0[k];
    if (dim == 2) y[2] = 0.0;
    rotate_back(rot.R, y, r);
    for (int k = 0; k < 3; k++) xt[k] = rot.p0[k] + r[k];
  }
  if (dim == 2) xt[2] = 0.0;
}

// the velocity of the tool's surface at r = x - (p0 + disp) (the arm from the axis point, simulation frame)
SPHCUT_INLINE void tool_surface_velocity(const double *vtool, const ToolRotation &rot, const double *r, double *vs)
{
  double w[3], c[3];
  for (int k = 0; k < 3; k++) w[k] = rot.omega * rot.axis[k];
  cross3(w, r, c);
  for (int k = 0; k < 3; k++) vs[k] = vtool[k] + c[k];
}

// what is the same for every particle of one contact evaluation
struct ContactStep {
  TriBinView tool;                  // the tool's bins, tool frame (host or device copies)
  const int *feature = nullptr;     // tool feature of each element (fix contact/tri-penalty FEAT_*)
  ContactIn base;                   // the ContactIn fields common to all particles (vtool, dim, E_tool,
                                    // factors, the friction law and its dt: FixContactTriPenalty::contact_params)
  double disp[3] = {0.0, 0.0, 0.0};    // tool displacement: the particles are queried at x - disp
  ToolRotation rot;                 // and, when rot.on, turned back into the tool frame (tool_frame_point)
  double dt = 0.0;                  // this step's time step (dt band, tool fields, heat booked)
  int setup = 0;                    // a setup evaluation: forces only, no time passes
  double eta = 1.0;                 // fraction of the friction power that becomes heat
  double split = 1.0;               // the workpiece's share of that heat
  int has_heat = 0;                 // a heat fix takes heat into the particles
  int tool_particles = 0;           // tool SPH particles take the tool's share (sink.heat_tool)
  int lumped = 0;                   // else a lumped tool (tool_cp) does, else it is lost
  int fields = 0;                   // tool fields per facet (sink.facet)
  FacetShare share;                 // the facets sharing each edge / vertex
  const double *inv_area = nullptr;    // 1/area of each facet
  double wear_K = 0.0, wear_alpha = 0.0;    // Usui wear
};

// the sums of an evaluation (sink.add): the force on the tool; the rates F.v_tool (work of the
// tool) and F.(v_tool - v) (dissipation) of the previous step's contact force and of this one's
// (velocity Verlet weights the step's energy by both halves); the friction power; the friction
// heat booked (energy: power times dt) into the workpiece, lost (no heat fix, no tool to take
// it), into a lumped tool, into the tool (lumped or particles)
enum ContactSum {
  CS_FX = 0, CS_FY, CS_FZ, CS_WORK, CS_DISS, CS_FRIC, CS_QWORK, CS_QLOST, CS_QLUMP, CS_QTOOL,
  CS_WORK_OLD, CS_DISS_OLD, CS_TORQUE, NCS
};
// CS_TORQUE: a . sum (x_c - p) x f, the torque of the contact forces f on the particles about the tool's
// axis (x_c the contact point, p the axis point): what the spindle supplies; 0 without rotation

// the kernel weight with which a tool particle at distance^2 r2 takes a share of the tool's
// friction heat of a contact particle (pair smoothing length h); 0 beyond the kernel support
SPHCUT_INLINE double tool_heat_weight(int kernel, int dim, double r2, double h)
{
  return r2 < support_radius_sq(h) ? kernel_w(kernel, dim, sqrt(r2), h) : 0.0;
}

// the friction heat of a contact with friction power fric_power (particle mass m): the
// workpiece's share to the particle, the tool's to the tool particles, a lumped tool or lost
template <class Sink>
SPHCUT_INLINE void contact_heat(const ContactStep &cs, double fric_power, double m, Sink &sink)
{
  // friction heat (eq. 6 of seed 003): particle share and tool share
  // (without a heat fix the workpiece share is not assigned: vector element 14)
  const double q = cs.eta * fric_power;
  if (q <= 0.0) return;
  const double acc = cs.setup ? 0.0 : cs.dt;    // setup: rates only, no time passes
  const double qw = cs.split * q;
  if (qw > 0.0) {
    if (cs.has_heat) {
      sink.heat_particle(qw, m, acc);
      sink.add(CS_QWORK, qw * acc);
    } else {
      sink.add(CS_QLOST, qw * acc);
    }
  }
  const double qt = q - qw;
  if (qt <= 0.0) return;
  // tool SPH particles near the contact (seed 000: NeibContTherm), kernel weighted
  if (cs.tool_particles && cs.has_heat && sink.heat_tool(qt)) {
    sink.add(CS_QTOOL, qt * acc);
    return;
  }
  if (cs.lumped) {
    sink.add(CS_QLUMP, qt * acc);    // summed over the ranks by the driver
    sink.add(CS_QTOOL, qt * acc);
  } else {
    sink.add(CS_QLOST, qt * acc);
  }
}

/* ----------------------------------------------------------------------
   one particle's contact evaluation.  Every local particle: the energy
   rates of its last contact force, its contact columns and output reset
   and the friction memory's step.  A candidate (in the fix's group, not a
   tool particle): the nearest tool element within 2h (tool_surface); one
   that finds it keeps the velocity of this step, takes the spring's dt
   limit if it is in or near contact, and inside the contact radius the
   penalty contact (penalty_contact) with its force, record, tool fields,
   XSPH drift and friction heat.  For a particle that had no contact force
   and finds no element this changes nothing (what lets fix
   contact/tri-penalty/kk skip the particles far from the tool).
------------------------------------------------------------------------- */

template <class Sink>
SPHCUT_INLINE void contact_step(const ContactStep &cs, bool candidate, Sink &sink)
{
  using SL = StateLayout;
  const ContactIn &b = cs.base;
  const int dim = b.dim;
  double *s = sink.state();
  double *fc = s + SL::FCONT, *vc = s + SL::VCONT, *fm = s + SL::FMEM;
  double *fo = sink.output();
  // (the particle's position and velocity are read where they are used: on a GPU, values kept
  // across the tool search cost registers)
  // energy over the step with the weights of velocity Verlet: the particle gains
  // dt/2 (F^n + F^(n+1)).v^(n+1/2), v^(n+1/2) the velocity that drifts it this step.
  // The F^n half, with the contact force of the previous step (particles that had one).
  if (fc[0] != 0.0 || fc[1] != 0.0 || fc[2] != 0.0) {
    // a rotating tool: its surface velocity at the particle (the contact point of the last step
    // is not kept; the two differ by omega d n x a, d < 0.5 h/sfac)
    double vt0[3] = {b.vtool[0], b.vtool[1], b.vtool[2]};
    if (cs.rot.on) {
      const double r[3] = {sink.x(0) - cs.disp[0] - cs.rot.p0[0], sink.x(1) - cs.disp[1] - cs.rot.p0[1],
                           dim == 2 ? 0.0 : sink.x(2) - cs.disp[2] - cs.rot.p0[2]};
      tool_surface_velocity(b.vtool, cs.rot, r, vt0);
    }
    for (int k = 0; k < dim; k++) {
      sink.add(CS_WORK_OLD, fc[k] * vt0[k]);
      sink.add(CS_DISS_OLD, fc[k] * (vt0[k] - sink.v(k)));
    }
  }
  fc[0] = fc[1] = fc[2] = 0.0;
  for (int k = 0; k < 6; k++) fo[k] = 0.0;
  // friction memory: a step takes the last step's friction force as f_old, remembers it
  // as its input and zeroes the state (set again below if the particle is in contact)
  if (b.friction.memory() && !cs.setup) memory_friction_step(fm);
  if (!candidate) return;

  const double h = sink.h();
  double xt[3];
  if (!cs.rot.on) {
    xt[0] = sink.x(0) - cs.disp[0];
    xt[1] = sink.x(1) - cs.disp[1];
    xt[2] = dim == 2 ? 0.0 : sink.x(2) - cs.disp[2];
  } else {
    const double xs[3] = {sink.x(0), sink.x(1), sink.x(2)};
    tool_frame_point(cs.disp, cs.rot, xs, dim, xt);
  }
  ContactIn in = b;
  double q[3];
  int region;
  const int best = tool_surface(cs.tool, xt, h, in.d, in.n, q, region);
  if (best < 0) return;
  // a rotating tool: the query ran in the tool frame (the bins as built); the normal and the
  // contact point back in the simulation frame, where the contact law runs with the surface
  // velocity there (the law is isotropic: the same as running it in the tool frame on the turned
  // particle velocity and forces and turning its force back)
  double arm[3] = {0.0, 0.0, 0.0};    // contact point minus axis point, simulation frame
  if (cs.rot.on) {
    double nt[3], qt[3];
    for (int k = 0; k < 3; k++) {
      nt[k] = in.n[k];
      qt[k] = q[k] - cs.rot.p0[k];
    }
    if (dim == 2) qt[2] = 0.0;
    rotate_fwd(cs.rot.R, nt, in.n);
    rotate_fwd(cs.rot.R, qt, arm);
    tool_surface_velocity(b.vtool, cs.rot, arm, in.vtool);
    if (dim == 2) in.n[2] = in.vtool[2] = 0.0;
  }
  // the velocity of this step, for a continued run's setup (repeat, below) of a particle in
  // contact: kept by the particles that find the tool within 2h (a particle in contact at a
  // setup found it the step before), so that the others touch no contact column on a step
  // without contact force (fix contact/tri-penalty/kk evaluates only the particles near the tool)
  if (!cs.setup) {
    for (int k = 0; k < 3; k++) vc[k] = sink.v(k);
    vc[3] = 1.0;
  }
  const double v[3] = {sink.v(0), sink.v(1), sink.v(2)};
  const double m = sink.mass();
  const double sp = sink.spacing();
  const double dp = sp > 0.0 ? sp : h / b.sfac;
  const double E = sink.E();
  if (near_contact(in.d, h, b.sfac, v, in.vtool, dim, cs.dt))
    sink.dt_crit(contact_spring_dt(E, b.E_tool, dp, b.pfac, b.dfac, m, dim));
  const double rc = 0.5 * h / b.sfac;    // contact radius, eq. 9
  if (rc - in.d <= 0.0) return;

  // the velocity that moves the particle this step, v^(n+1/2); at the setup of a continued
  // run (restart, or a second run with unchanged velocities) the one of the last step
  const bool repeat =
      cs.setup && vc[3] > 0.0 && v[0] == s[SL::VEND] && v[1] == s[SL::VEND + 1] && v[2] == s[SL::VEND + 2];
  double vuse[3] = {v[0], v[1], v[2]};    // (an array, not a pointer to v or vc: v stays in registers)
  if (repeat)
    for (int k = 0; k < 3; k++) vuse[k] = vc[k];
  // f_old of the memory law: at a step its input set above; a setup evaluation that repeats
  // the last step (a continued run) uses that step's input if the particle had friction then,
  // else the current state (zero after a contact ended)
  if (b.friction.memory()) memory_friction_input(fm, !cs.setup, repeat, in.ft_old);
  for (int k = 0; k < 3; k++) {
    in.x[k] = sink.x(k);
    in.v[k] = vuse[k];
    in.q[k] = cs.rot.on ? cs.rot.p0[k] + cs.disp[k] + arm[k] : q[k] + cs.disp[k];
    in.f_other[k] = k < dim ? sink.f(k) : 0.0;
  }
  in.mass = m;
  in.h = h;
  in.E_particle = E;
  in.dp = dp;
  in.mu = b.friction.mu(s[SL::TEMP_F]);
  ContactOut out;
  penalty_contact(in, out);
  if (!out.active) return;
  if (b.friction.memory() && !cs.setup)
    for (int k = 0; k < 3; k++) fm[k] = out.ft[k];

  // the decomposition by the tool feature of the nearest element (forces on the tool)
  const int feat = cs.feature[best];
  double rec[NDREC];
  contact_record(out, in.n, rec);
  sink.record(feat, rec, out.delta / rc);
  fo[3] = out.fn;
  fo[4] = rec[DREC_FT];
  fo[5] = feat + 1;
  // tool fields: the facets sharing the feature that holds the closest point, weighted by dt
  // (a rotating tool: the force on each facet in the tool frame)
  if (cs.fields && !cs.setup) {
    if (!cs.rot.on) {
      facet_scatter(cs.share, cs.inv_area, best, region, out, s[SL::TEMP_F], cs.wear_K, cs.wear_alpha, cs.dt,
                    [&](int f, const double *c) { sink.facet(f, c); });
    } else {
      ContactOut ot = out;
      rotate_back(cs.rot.R, out.f, ot.f);
      facet_scatter(cs.share, cs.inv_area, best, region, ot, s[SL::TEMP_F], cs.wear_K, cs.wear_alpha, cs.dt,
                    [&](int f, const double *c) { sink.facet(f, c); });
    }
  }
  // no XSPH drift along the contact normal (contact_drift)
  contact_drift(s + SL::XSPH, in.n);
  for (int k = 0; k < dim; k++) {
    sink.add_force(k, out.f[k]);
    fc[k] = out.f[k];
    fo[k] = out.f[k];
    sink.add(CS_FX + k, -out.f[k]);
    sink.add(CS_WORK, out.f[k] * in.vtool[k]);
    // friction + dashpot (+ spring) power
    sink.add(CS_DISS, out.f[k] * (in.vtool[k] - sink.v(k)));
  }
  if (cs.rot.on) {
    double tq[3];
    cross3(arm, out.f, tq);
    sink.add(CS_TORQUE, dot3(tq, cs.rot.axis));
  }
  sink.add(CS_FRIC, out.fric_power);
  contact_heat(cs, out.fric_power, m, sink);
}

}    // namespace sphcut

#endif
