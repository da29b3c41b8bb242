/* -*- c++ -*- ----------------------------------------------------------
   sphcut - time integration of one SPH solid particle (host and device):
   what fix sph/jc-thermal and fix sph/jc-thermal/kk do per particle, on a
   state row laid out as sphcut::StateLayout (seed 003 eqs. 1-3, 5, 9-11).
     first half  (initial_integrate): keep the rates of the last step, kick
       v by dt/2 f/m, drift x with the XSPH-corrected velocity (Monaghan
       1989), predictor y* = y^n + dt f^n of rho, s, T, radial return;
     rates       (pre_force): zeroed, then the pair and the heat sources add;
     second half (final_integrate): kick, corrector y^{n+1} = y^n + dt/2
       (f^n + f^{n+1}) of rho, s, u, T, radial return, plastic heat chi W_p
       (a particle released by the spall: no expansion, s = 0, no plastic flow);
     time step   the stable dt of the particle (mechanics, conduction).
   Rigid tool particles move with their prescribed velocity and carry only
   a temperature; clamped particles stay at rest but keep their stress.
------------------------------------------------------------------------- */

#ifndef SPHCUT_SOLID_H
#define SPHCUT_SOLID_H

#include "sphcut_material.h"
#include "sphcut_state.h"

namespace sphcut {

using SL = StateLayout;

// role of a particle from its group mask (tool first, then clamped)
SPHCUT_INLINE int role_from_mask(int mask, int toolbit, int clampbit)
{
  return (mask & toolbit) ? SL::TOOL : ((mask & clampbit) ? SL::CLAMPED : SL::WORKPIECE);
}

// the row of a new particle: zero; density and temperature are taken from the material
// (sentinel -1) at the next setup unless temp0 >= 0 gives the temperature
SPHCUT_INLINE void initial_row(double *s, double temp0)
{
  for (int k = 0; k < SL::NCOL; k++) s[k] = 0.0;
  s[SL::RHO] = -1.0;
  s[SL::TEMP] = temp0;
}

// predictor of the material state: the force state of this step
SPHCUT_INLINE void predict_state(const Material &mt, double dt, double *s)
{
  s[SL::TEMP_F] = s[SL::TEMP] + dt * s[SL::DTEMP_O];
  s[SL::RHO_F] = spall_density(mt, s[SL::RHO], s[SL::RHO] + dt * s[SL::DRHO_O], s[SL::TEMP_F]);
  for (int k = 0; k < 6; k++) s[SL::SF + k] = s[SL::SXX + k] + dt * s[SL::DS_O + k];
  radial_return(mt, &s[SL::SF], s[SL::EPS], s[SL::TEMP_F], dt, nullptr, s[SL::EPSDOT] * dt);
}

/* initial_integrate of one particle: x, v are the particle's rows, f its
   force, dtfm = dt/2 ftm2v / m, eps_xsph the XSPH factor of its material  */
SPHCUT_INLINE void integrate_first_half(const Material &mt, int role, double dt, double dtfm,
                                        double *x, double *v, const double *f, double *s)
{
  s[SL::DRHO_O] = s[SL::DRHO];
  for (int k = 0; k < 6; k++) s[SL::DS_O + k] = s[SL::DS + k];
  s[SL::DTEMP_O] = s[SL::DTEMP];
  s[SL::DU_O] = s[SL::DU];
  if (role == SL::TOOL) {
    for (int d = 0; d < 3; d++) {
      x[d] += dt * v[d];
      s[SL::VEST + d] = v[d];
    }
    s[SL::TEMP_F] = s[SL::TEMP] + dt * s[SL::DTEMP_O];
    return;
  }
  if (role == SL::CLAMPED) {
    for (int d = 0; d < 3; d++) v[d] = s[SL::VEST + d] = 0.0;
  } else {
    for (int d = 0; d < 3; d++) {
      s[SL::VEST + d] = v[d] + 2.0 * dtfm * f[d];    // velocity estimate at the end of the step
      v[d] += dtfm * f[d];
      x[d] += dt * (v[d] + mt.xsph * s[SL::XSPH + d]);
    }
  }
  predict_state(mt, dt, s);
}

// clear the rates of this step (pre_force)
SPHCUT_INLINE void zero_rates(double *s)
{
  s[SL::DRHO] = 0.0;
  for (int k = 0; k < 6; k++) s[SL::DS + k] = 0.0;
  s[SL::DTEMP] = 0.0;
  s[SL::DU] = 0.0;
}

/* final_integrate of one particle; m its mass.  Returns the plastic work of
   the step (energy units), which has already heated the particle.        */
SPHCUT_INLINE double integrate_second_half(const Material &mt, int role, double dt, double dtfm,
                                           double m, double *v, const double *f, double *s)
{
  const double hdt = 0.5 * dt;
  double work = 0.0;
  s[SL::TEMP] += hdt * (s[SL::DTEMP_O] + s[SL::DTEMP]);
  if (role != SL::TOOL) {
    if (role == SL::WORKPIECE)
      for (int d = 0; d < 3; d++) v[d] += dtfm * f[d];
    s[SL::RHO] = spall_density(mt, s[SL::RHO], s[SL::RHO] + hdt * (s[SL::DRHO_O] + s[SL::DRHO]), s[SL::TEMP]);
    for (int k = 0; k < 6; k++) s[SL::SXX + k] += hdt * (s[SL::DS_O + k] + s[SL::DS + k]);
    s[SL::UINT] += hdt * (s[SL::DU_O] + s[SL::DU]);
    double sigy = 0.0, deps = 0.0;
    if (spall_released(mt, eos_pressure_uncut(mt, s[SL::RHO], s[SL::TEMP])))
      for (int k = 0; k < 6; k++) s[SL::SXX + k] = 0.0;    // separated: no deviatoric stress, no plastic flow
    else
      deps = radial_return(mt, &s[SL::SXX], s[SL::EPS], s[SL::TEMP], dt, &sigy, s[SL::EPSDOT] * dt);
    s[SL::EPS] += deps;
    s[SL::EPSDOT] = deps / dt;
    if (deps > 0.0) {
      const double wp = sigy * deps / s[SL::RHO];    // plastic work per unit mass
      work = m * wp;
      if (mt.cp > 0.0) s[SL::TEMP] += mt.chi * wp / mt.cp;
    }
    s[SL::PRESS] = eos_pressure(mt, s[SL::RHO], s[SL::TEMP]);
    s[SL::VM] = von_mises(&s[SL::SXX]);
  }
  for (int d = 0; d < 3; d++) s[SL::VEND + d] = v[d];
  return work;
}

/* the speed above which a particle has run away (fix sph/jc-thermal keyword vmax): vmax < 0 (the
   default) its material's longitudinal sound speed c_l, 0 no limit, > 0 that speed */
SPHCUT_INLINE double runaway_speed(const Material &mt, double vmax)
{
  return vmax < 0.0 ? mt.cl : vmax;
}

/* the temperature above which a particle's temperature solution has run away (fix sph/jc-thermal
   keyword tmax): tmax > 0 that temperature, 0 no limit, < 0 (the default) twice its material's
   Johnson-Cook melting temperature Tmelt (no limit where none is given).  The flow stress
   vanishes at Tmelt; 2 Tmelt (3756 K for Ti6Al4V) lies above the boiling points of the
   engineering alloys, which only an unstable temperature solution reaches. */
SPHCUT_INLINE double runaway_temperature(const Material &mt, double tmax)
{
  if (tmax >= 0.0) return tmax;
  return mt.Tmelt > mt.Tref && mt.Tmelt < 1.0e29 ? 2.0 * mt.Tmelt : 0.0;
}

/* stable time step of one particle (adaptive dt, keyword cfl), mechanics:
     dt = cfl h / (c_l + |v|)        (not for tool particles)
   the conduction and contact limits come from fix heat/fmfs and fix contact/tri-penalty.
   A particle faster than runaway_speed, or hotter than runaway_temperature (tool particles too),
   or with a velocity or temperature that is not a number (NaN; also where the limit is switched
   off with none, or the material has no Tmelt), gives -1, which no step can be: the step's minimum carries the checks for free, and the fix stops
   the run naming the particle (FixSPHJCThermal::report_runaway) instead of letting it fly off
   and fail later somewhere else ("Domain too large for neighbor bins"), or heat up without
   bound unnoticed. */
SPHCUT_INLINE double particle_dt(const Material &mt, int role, double h, const double *v, double T, double cfl,
                                 double vmax, double tmax)
{
  const double tlim = runaway_temperature(mt, tmax);
  if (T != T || (tlim > 0.0 && !(T <= tlim))) return -1.0;
  if (role == SL::TOOL) return 1.0e300;
  const double vv = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const double lim = runaway_speed(mt, vmax);
  if (vv != vv || (lim > 0.0 && !(vv <= lim))) return -1.0;
  return cfl * h / (mt.cl + vv);
}

}    // namespace sphcut

#endif
