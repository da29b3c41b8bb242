/* -*- c++ -*- ----------------------------------------------------------
   sphcut - fix sph/jc-thermal: owns the per-atom SPH solid state and
   integrates it (velocity Verlet for x and v, Heun predictor-corrector
   for density, deviatoric stress, temperature and internal energy,
   radial return for Johnson-Cook plasticity).
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(sph/jc-thermal,FixSPHJCThermal);
// clang-format on
#else

#ifndef LMP_FIX_SPH_JC_THERMAL_H
#define LMP_FIX_SPH_JC_THERMAL_H

#include "fix.h"

#include <string>

namespace LAMMPS_NS {

class PairSPHJCThermal;

class FixSPHJCThermal : public Fix {
 public:
  // columns of the per-atom array (dump custom f_ID[k] uses k = column + 1)
  enum Column {
    RHO = 0, PRESS, SXX, SYY, SZZ, SXY, SXZ, SYZ, VM, EPS, EPSDOT, TEMP, ROLE, UINT,
    DTEMP,                                  // temperature rate of this step (all heat sources)
    NOUT,                                   // columns above are the documented output
    RHO_F = NOUT, SF, TEMP_F = SF + 6, VEST, // state the forces are computed from (predictor)
    DRHO = VEST + 3, DS, DU = DS + 6,       // rates of this step (pair adds)
    DRHO_O, DS_O, DTEMP_O = DS_O + 6, DU_O, // rates of the previous step
    XSPH, VEND = XSPH + 3,                  // XSPH velocity correction, v at end of last step
    NCOL = VEND + 3
  };
  enum Role { WORKPIECE = 0, TOOL = 1, CLAMPED = 2 };
  static constexpr int LAYOUT = 2;    // bump when the column layout changes (restart check)

  FixSPHJCThermal(class LAMMPS *, int, char **);
  ~FixSPHJCThermal() override;
  int setmask() override;
  void init() override;
  void setup_pre_force(int) override;
  void setup(int) override;
  void initial_integrate(int) override;
  void pre_force(int) override;
  void final_integrate() override;
  void end_of_step() override;
  void post_run() override;
  void reset_dt() override;
  double compute_vector(int) override;

  double memory_usage() override;
  void grow_arrays(int) override;
  void set_arrays(int i) override { initialize_atom(i); }
  void copy_arrays(int, int, int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

  // interface for the pair style and the heat / contact fixes
  double **state;             // per-atom state, NCOL columns (see Column)
  int toolbit, clampbit;      // group bits of the tool and clamped particles
  int role_of(int mask) const
  {
    return (mask & toolbit) ? TOOL : ((mask & clampbit) ? CLAMPED : WORKPIECE);
  }
  double dt_used() const { return dtv; }
  double cpu_time = 0.0;      // wall time of the integration on this rank (timing table)
  // for the other sphcut styles: the pair style and this fix, or an error that names `who`
  // (also when atoms of `groupbit`, group `gname`, lie outside the group of this fix)
  static FixSPHJCThermal *require(class LAMMPS *lmp, const std::string &who, int groupbit,
                                  const char *gname, PairSPHJCThermal **pair);

 protected:
  PairSPHJCThermal *pair;
  double dtv, dtf;
  double temp0;               // initial temperature (< 0: take Tref of the material)
  std::string temp_var;       // or an atom-style variable giving it
  int force_state_valid;      // force-state columns hold the last predictor (continued run)
  double cfl;                 // > 0: adaptive time step with this Courant number
  double dtmax, dtmin;
  double thermal_cfl;         // dt <= thermal_cfl rho cp h^2 / k with a heat fix
  int heat_active;            // a heat fix integrates conduction: apply the thermal limit
  double plastic_work;        // accumulated plastic work (energy units), this rank
  void initialize_atom(int);
  void predict(int i, const double *mass, const double *rmass, const int *type);
  double stable_dt();
  void apply_dt(double);
  double run_start;           // wall clock at the setup of the run
  void reset_timers();
};

}    // namespace LAMMPS_NS

#endif
#endif
