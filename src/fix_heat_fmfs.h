/* -*- c++ -*- ----------------------------------------------------------
   sphcut - fix heat/fmfs: heat conduction of the SPH particles with the
   second-order FMFS Laplacian (seed 003 eqs. 13-15), Brookshaw at surface
   particles (eq. 12), harmonic-mean conductivity between materials (seed
   000 eq. 6), convection and radiation on free surfaces (eq. 8),
   Dirichlet temperatures (eq. 7).  The temperature itself is integrated
   by fix sph/jc-thermal: this fix adds to its temperature rate.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(heat/fmfs,FixHeatFMFS);
// clang-format on
#else

#ifndef LMP_FIX_HEAT_FMFS_H
#define LMP_FIX_HEAT_FMFS_H

#include "fix.h"
#include "sphcut_heat_rules.h"
#include "sphcut_thermal.h"
#include "sphcut_model.h"
#include "sphcut_timer.h"

#include <vector>

namespace LAMMPS_NS {

class FixSPHJCThermal;
class ComputeSurfaceLambda;

class FixHeatFMFS : public Fix, public sphcut::AttachedStyle {
 public:
  FixHeatFMFS(class LAMMPS *, int, char **);
  ~FixHeatFMFS() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void post_force(int) override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  double memory_usage() override;
  void restart(char *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

  // entry point for heat sources (fix contact/tri-penalty: friction heat):
  // add `power` (energy/time) to local atom i during post_force of this step
  void add_heat(int i, double power);
  // heat (energy) that a device path added to the particles itself, booked into element 4
  void book_sources(double energy) { q_sources += energy; }
  // cpu_time: wall time on this rank, without the surface compute
  std::string timing_name() const override { return std::string("fix heat/fmfs ") + id; }
  // thermal time step limit on this rank for thermal Courant number F, with the
  // sub-cycling interval (fix sph/jc-thermal stable_dt takes the minimum over ranks)
  double dt_limit(double, double F) const override;
  std::string starts_from_temperature() const override { return "Fix heat/fmfs"; }

 protected:
  enum { FMFS, BROOKSHAW };
  int scheme;
  int every;                    // conduction and losses evaluated every this many steps
  int conservative;             // 1: pairwise exchange with the mean FMFS/Brookshaw weight (default)
  double **fwts;                // per atom (local + ghost): scheme flag (1 FMFS) and FMFS weights
  int nmax_fwts;
  double held_conv, held_rad;   // loss rates of the last evaluation
  double fmfs_lambda;           // FMFS only where lambda (own support) >= this
  char *id_surface;
  ComputeSurfaceLambda *surface;
  double hconv, tconv;          // convection coefficient and ambient temperature
  double emiss, trad;           // emissivity and ambient temperature of radiation
  int backbit;                  // the backing's group (keyword backing; 0: none)
  double hback, tback;          // its heat transfer coefficient and temperature
  std::vector<int> dir_bits;        // the Dirichlet groups (keyword dirichlet) and their temperatures,
  std::vector<double> dir_temps;    // as the heat rules take them (sphcut::dirichlet_index)
  // energy budget (energy units, summed over this rank; reduced on output)
  double q_conv, q_rad, q_dirichlet, q_sources;
  bigint n_fmfs, n_brookshaw, n_fallback;    // counters of this rank
  double p_conv_prev, p_rad_prev;            // loss rates of the previous step
  class NeighList *list;
  FixSPHJCThermal *fix;
  const sphcut::Model *model;    // the model of pair sph/jc-thermal (sphcut::find_model)
  int dirichlet_of(int mask) const;
  // the temperature rules (sphcut_heat_rules.h) to the integrator, in init: CPU, the table of
  // FixSPHJCThermal::set_heat_rules; /kk, the fix's hooks in the integrator's kernels instead
  virtual void hand_over_rules();
  void check_timestep();
  template <int DIM> void conduction();
  template <int DIM> void conduction_conservative();
  template <int DIM> void scheme_pass();
  template <int DIM> void exchange_pass();
  sphcut::HeatLosses losses() const;    // convection and radiation as sphcut::heat_rate takes them
  // the surface compute's values are computed in this fix's first pass (this evaluation)
  bool fuse_surface;
  std::vector<sphcut::ThermalPair> tpair;    // [itype * (ntypes+1) + jtype]
  std::vector<double> hij;                   // smoothing length of a type pair, [itype * (ntypes+1) + jtype]
  std::vector<double> prow;                  // per atom (local + ghost): x, V = m/rho, T
  // the neighbours within the support of the particle being evaluated (see gather_support)
  std::vector<int> nb_j, nb_t;
  std::vector<double> nb_dx, nb_r2, nb_wfac, nb_ir2;
  void gather_rows();
  int gather_support(int i, bool half);
  template <class View> View support_view(int i, bool half);
  std::vector<double> rate_sum;              // pass 2: rho cp dT/dt of the local particles
  std::vector<char> listed;                  // pass 2: local particle has a neighbour list of its own
  virtual bool begin_evaluation();
};

}    // namespace LAMMPS_NS

#endif
#endif
