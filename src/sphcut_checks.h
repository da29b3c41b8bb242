/* -*- c++ -*- ----------------------------------------------------------
   sphcut - checks of the input that would otherwise fail silently (host
   only): integer keyword values (no wrap-around), particle masses, and
   particles that start (nearly) on top of each other.  Called by the
   styles when they parse their arguments or at the setup of a run;
   errors and warnings name the cause.
------------------------------------------------------------------------- */

#ifndef SPHCUT_CHECKS_H
#define SPHCUT_CHECKS_H

#include "lmptype.h"

#include <climits>
#include <string>

namespace LAMMPS_NS {
class LAMMPS;
class NeighList;
}    // namespace LAMMPS_NS

namespace sphcut {
class Model;

// the value of an integer keyword, `text` the word as given: every sphcut style parses its
// integer keywords here.  The whole word must be a decimal integer (an optional sign, digits)
// within [lo, hi]; LAMMPS 29Sep2021's utils::inumeric converts with atoi, so `every 10000000000`
// wrapped to 1410065408.  error->all "<who>: <keyword> must be an integer, got <text>",
// "... must be >= <lo>, got <text>" or "... must be <= <hi>, got <text> (out of range)".
int parse_int(LAMMPS_NS::LAMMPS *lmp, const std::string &who, const std::string &keyword, const char *text,
              int lo = 1, int hi = INT_MAX);

// every particle has a mass > 0: per-type masses set (mass command) when there is no
// per-atom mass, else every per-atom mass (rmass) > 0 and finite.  error->all naming
// the type or the first offending atom and the count; `who` starts the message.
void check_masses(LAMMPS_NS::LAMMPS *lmp, const char *who);

// pairs of particles closer than frac times their mean spacing (the pair style's
// Model::spacing, from mass and rho0), counted once over all ranks, from the pair style's
// neighbour list; a warning with the count and the closest distance when there are any.
// Returns the count (the same on every rank).
LAMMPS_NS::bigint warn_close_pairs(LAMMPS_NS::LAMMPS *lmp, LAMMPS_NS::NeighList *list, const Model &model,
                                   double frac = 0.5);

// the reduction and warning of warn_close_pairs, for drivers that count on their own (the /kk
// fix counts on the device): count and rmin of this rank (rmin in spacings)
LAMMPS_NS::bigint report_close_pairs(LAMMPS_NS::LAMMPS *lmp, double count, double rmin, double frac);

}    // namespace sphcut

#endif
