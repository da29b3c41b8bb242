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
#include "sphcut_model.h"
#include "sphcut_solid.h"
#include "sphcut_timer.h"

#include <functional>
#include <string>
#include <vector>

namespace LAMMPS_NS {

// the state columns (Column, Role, NCOL, NFORWARD, ...) are those of sphcut::StateLayout; the
// model (materials, smoothing lengths) is that of pair sph/jc-thermal, read through sphcut::Model
class FixSPHJCThermal : public Fix,
                        public sphcut::StateLayout,
                        public sphcut::AttachedStyle,
                        public sphcut::StateOwner {
 public:
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

  // interface for the pair style and the heat / contact fixes: state, toolbit, clampbit
  // (sphcut::StateOwner): the per-atom state, NCOL columns (see Column), the group bits of the
  // tool and clamped particles
  int role_of(int mask) const { return sphcut::role_from_mask(mask, toolbit, clampbit); }
  double dt_used() const { return dtv; }
  std::string timing_name() const override { return "fix sph/jc-thermal (integration)"; }
  // timing table: the styles that report their time (each attaches itself in its init)
  void attach(sphcut::AttachedStyle *style) override;
  // an attached heat style (fix heat/fmfs, in its init) hands over the temperature rules that this
  // fix applies for it in its own per-particle passes (sphcut_solid.h), so that the style runs no
  // pass of its own on an ordinary step: gb, its group, whose held rate (column HELD) joins the
  // temperature rate before the corrector; bits, temps: its Dirichlet groups, whose predicted temperature the predictor sets and whose temperature the corrector's loop
  // sets back after the corrector, adding the heat that takes to *qdir (the style's Dirichlet
  // budget; /kk: to a device accumulator instead, take_dirichlet_heat); every: the style's
  // sub-cycling (/kk: the corrector's reduction also writes the style's thermal dt limit over gb
  // into the style's dt slot).  One owner (the last to call); dropped when the owner is deleted
  // (prune_attached).
  virtual void set_heat_rules(const sphcut::AttachedStyle *owner, int gb, const std::vector<int> &bits,
                              const std::vector<double> &temps, int every, double *qdir);
  // for the other sphcut styles: the model (of the pair style) and this fix, or an error that
  // names `who` (also when atoms of `groupbit`, group `gname`, lie outside the group of this fix)
  static FixSPHJCThermal *require(class LAMMPS *lmp, const std::string &who, int groupbit,
                                  const char *gname, const sphcut::Model **model);

 protected:
  const sphcut::Model *model;
  double dtv, dtf;
  double temp0;               // initial temperature (< 0: take Tref of the material)
  std::string temp_var;       // or an atom-style variable giving it
  int force_state_valid;      // force-state columns hold the last predictor (continued run)
  double cfl;                 // > 0: adaptive time step with this Courant number
  int peratom_every = 0;      // > 0: the per-atom array is valid every this many steps (keyword)
  int dtevery = 1;            // the adaptive dt is recomputed every this many steps (keyword dtevery)
  bool dt_step() const;       // whether this step's end_of_step recomputes the adaptive dt
  int fence = -1;             // /kk: 1 per-style timers wait for the device (keyword fence), 0 not, -1 default
  int migrate_device = 1;     // /kk: 1 the state rows follow their atoms on the device (keyword migrate), 0 host
  // remark in the timing table's title (the /kk fix: what its times mean)
  virtual std::string timing_note() const { return ""; }
  double dtmax, dtmin;
  double thermal_cfl;         // dt <= thermal_cfl rho cp h^2 / k with a heat fix
  double plastic_work;        // accumulated plastic work (energy units), this rank
  // the elapsed time as of the last change of dt: time_anchor at step step_anchor, dt_anchor since
  // (sync_time); anchored: set (at the setup of a run, a change of dt or from a restart file)
  double time_anchor = 0.0, dt_anchor = 0.0;
  bigint step_anchor = 0;
  bool anchored = false;
  void sync_time();
  std::vector<sphcut::AttachedStyle *> timed;    // attached styles, this run
  struct HeatRules {                              // set_heat_rules
    const sphcut::AttachedStyle *owner = nullptr;
    int gb = 0;                  // the owner's group (0: no rules)
    std::vector<int> bits;
    std::vector<double> temps;
    int every = 1;               // the owner's sub-cycling (its thermal dt limit)
    double *qdir = nullptr;      // the owner's Dirichlet heat (CPU: the corrector's loop adds to it)
  } heat_rules;
  int grow_callback = 1;      // the state migrates through Atom's grow callback (/kk on one rank: no)
  void initialize_atom(int);
  void setup_state();         // host part of setup_pre_force: complete the state of new atoms
  void report_default_temperature(const std::vector<bigint> &ntref);    // particles at Tref (heat/fmfs)
  virtual double stable_dt(); // this step's stable dt (global min)
  virtual void check_close_pairs();    // warn about particles (nearly) on top of each other
  double vmax;                // runaway speed: < 0 the sound speed c_l (default), 0 none, > 0 this
  double tmax;                // runaway temperature: < 0 twice Tmelt (default), 0 none, > 0 this
  virtual void report_runaway();    // stop the run: a particle is faster than vmax
  void report_temperature();        // ... or hotter than tmax
  void report_density();            // ... or its density is no longer positive
  double worst_particle(const std::function<double(int, double *)> &score, double floor, double *info,
                        bool with_tool = false);
  double finish_dt(double dtloc);    // with the attached styles' limits, global min, dtmin/dtmax
  void apply_dt(double);
  double run_start;           // wall clock at the setup of the run
  void reset_timers();
  virtual void prune_attached();
  std::vector<sphcut::AttachedStyle *> live_styles() const;    // the sphcut styles that exist now
};

}    // namespace LAMMPS_NS

#endif
#endif
