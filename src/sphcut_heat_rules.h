/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the temperature rules of fix heat/fmfs (host and device) that
   an integrator applies in its own per-particle passes, so that the heat
   style needs no pass of its own on an ordinary step:
     Dirichlet groups  after the predictor (integrate_first_half) a particle of the style's group gb
                       in one of its n Dirichlet groups (bits) takes that group's temperature as its
                       predicted temperature (hold_predicted_temperature)
     held rate         the rate the style holds between its evaluations (column HELD: conduction and
                       surface losses) joins the temperature rate of the particles of its group where
                       the step first uses that rate, the corrector (add_held_rate, before
                       integrate_second_half).  The other heat sources (the contact's friction heat)
                       add to DTEMP before; with at most one of them per particle (one contact fix)
                       the sum is the same number as when the style added HELD first
     Dirichlet groups  after the corrector (right after integrate_second_half) a Dirichlet particle's
                       temperature goes back to its group's; the heat that takes, m cp (T_D - T), is
                       the heat through the clamp (hold_corrected_temperature, summed for the style's
                       budget).  With an adaptive step the /kk integrator also takes the style's
                       thermal dt limit over its group there (sphcut::thermal_dt_min, sphcut_thermal.h)
   Who applies them: the CPU fix sph/jc-thermal with the table the heat fix hands it
   (FixSPHJCThermal::set_heat_rules); under /kk the heat fix's own hooks in the integrator's fused
   kernels (KOKKOS/sphcut_heat_hooks_kokkos.h, through KOKKOS/sphcut_hooks_kokkos.h).
------------------------------------------------------------------------- */

#ifndef SPHCUT_HEAT_RULES_H
#define SPHCUT_HEAT_RULES_H

#include "sphcut_math.h"
#include "sphcut_state.h"

namespace sphcut {

// Dirichlet group of a particle: the first of the n group bits its mask holds (-1: none, or the
// particle is outside the style's group gb)
SPHCUT_INLINE int dirichlet_index(int mask, int gb, const int *bits, int n)
{
  if (!(mask & gb)) return -1;
  for (int k = 0; k < n; k++)
    if (mask & bits[k]) return k;
  return -1;
}

// after the predictor: a Dirichlet particle's predicted temperature (the one the force passes of
// the step read) is its group's temperature temps[k]
SPHCUT_INLINE void hold_predicted_temperature(int mask, int gb, const int *bits, const double *temps, int n, double *s)
{
  const int k = dirichlet_index(mask, gb, bits, n);
  if (k >= 0) s[StateLayout::TEMP_F] = temps[k];
}

// after the corrector: a Dirichlet particle's temperature back to its group's temperature temps[k];
// returns the heat this takes, mcp (T_D - T) with mcp = m cp of the particle (0: not a Dirichlet
// particle).  The corrector moved T by dt/2 (rate_old + rate_new), the same trapezoidal weights as
// the neighbours' exchange with the particle: the sum is the heat through the clamp
SPHCUT_INLINE double hold_corrected_temperature(int mask, int gb, const int *bits, const double *temps, int n,
                                                double mcp, double *s)
{
  const int k = dirichlet_index(mask, gb, bits, n);
  if (k < 0) return 0.0;
  const double q = mcp * (temps[k] - s[StateLayout::TEMP]);
  s[StateLayout::TEMP] = temps[k];
  return q;
}

// before the corrector: the held rate joins the temperature rate of the step
SPHCUT_INLINE void add_held_rate(double *s)
{
  s[StateLayout::DTEMP] += s[StateLayout::HELD];
}

}    // namespace sphcut

#endif
