/* -*- c++ -*- ----------------------------------------------------------
   sphcut - layout of the per-atom SPH state that fix sph/jc-thermal owns
   (one row of NCOL doubles per atom, migrating with it and written to
   restart files).  The columns are grouped by who writes them; every
   sphcut style reads and writes its columns by these names, never by
   number.  dump custom f_ID[k] uses k = column + 1 (output columns only).

   group           columns                         written by
   output          RHO .. DTEMP                    fix sph/jc-thermal (integration);
                                                   DTEMP: every heat source adds to it (the
                                                   held rate HELD: the fix, before its corrector)
   force state     RHO_F, SF(6), TEMP_F, VEST(3)   fix sph/jc-thermal predictor; sent to
                                                   the ghosts before the forces (NFORWARD)
   rates           DRHO, DS(6), DU                 zeroed by the fix, added by the pair
   old rates       DRHO_O, DS_O(6), DTEMP_O, DU_O  fix (copy at the start of a step)
   XSPH, VEND      XSPH(3), VEND(3)                pair (XSPH sum), fix (v at step end)
   attached        HELD, FCONT(3), VCONT(4), FMEM(6)  fix heat/fmfs (conduction rate held between
                                                   evaluations), fix contact/tri-penalty (last
                                                   contact force; velocity it used, valid flag;
                                                   friction memory state)
   The attached styles keep their per-atom data here, not in arrays of their own, so that it
   migrates, sorts, restarts and (under /kk on one rank) follows the atoms on the device with
   the rest of the state.
------------------------------------------------------------------------- */

#ifndef SPHCUT_STATE_H
#define SPHCUT_STATE_H

namespace sphcut {

struct StateLayout {
  enum Column {
    // output (documented in doc/fix_sph_jc_thermal.rst)
    RHO = 0, PRESS, SXX, SYY, SZZ, SXY, SXZ, SYZ, VM, EPS, EPSDOT, TEMP, ROLE, UINT,
    DTEMP,                                  // temperature rate of this step (all heat sources; HELD joins
                                            // it at the corrector, sphcut::add_held_rate)
    NOUT,                                   // columns above are the documented output
    // force state: the predictor the forces of a step are computed from
    RHO_F = NOUT, SF, TEMP_F = SF + 6, VEST,
    // rates of this step (the pair adds), and of the previous step
    DRHO = VEST + 3, DS, DU = DS + 6,
    DRHO_O, DS_O, DTEMP_O = DS_O + 6, DU_O,
    XSPH, VEND = XSPH + 3,                  // XSPH velocity correction, v at end of last step
    // per-atom data of the attached styles
    HELD = VEND + 3,                        // fix heat/fmfs: temperature rate held between evaluations
                                            // (fix sph/jc-thermal adds it to DTEMP: set_heat_rules)
    FCONT,                                  // fix contact/tri-penalty: contact force of the last step (3)
    VCONT = FCONT + 3,                      // velocity the contact used last step (3), valid flag (1)
    FMEM = VCONT + 4,                       // friction memory: friction force of the last step (3),
                                            // the f_old that step started from (3)
    NCOL = FMEM + 6
  };
  enum Role { WORKPIECE = 0, TOOL = 1, CLAMPED = 2 };
  // the force state is contiguous: RHO_F .. VEST+2 travel to the ghosts
  static constexpr int FORWARD_FIRST = RHO_F;
  static constexpr int NFORWARD = 1 + 6 + 1 + 3;
  static constexpr int LAYOUT = 4;          // bump when the column layout changes (restart check)
};

static_assert(StateLayout::RHO_F + StateLayout::NFORWARD == StateLayout::DRHO,
              "the force state columns must be contiguous and end before the rates");

}    // namespace sphcut

#endif
