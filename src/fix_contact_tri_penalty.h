/* -*- c++ -*- ----------------------------------------------------------
   sphcut - fix contact/tri-penalty: node-to-surface penalty contact of
   SPH particles with a rigid triangulated tool (seed 000 sec. 3): STL or
   generated cutting insert, prescribed translation, Coulomb friction
   mu(T), friction heat split between workpiece and tool.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(contact/tri-penalty,FixContactTriPenalty);
// clang-format on
#else

#ifndef LMP_FIX_CONTACT_TRI_PENALTY_H
#define LMP_FIX_CONTACT_TRI_PENALTY_H

#include "fix.h"
#include "sphcut_contact_step.h"
#include "sphcut_stl.h"
#include "sphcut_model.h"
#include "sphcut_timer.h"
#include "sphcut_tool_fields.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixSPHJCThermal;
class FixHeatFMFS;

class FixContactTriPenalty : public Fix, public sphcut::AttachedStyle {
 public:
  // tool features of the force decomposition (global vector elements 16-47)
  enum { FEAT_RAKE, FEAT_EDGE, FEAT_FLANK, FEAT_OTHER, NFEAT };
  enum { NDECOMP = 8 };
  FixContactTriPenalty(class LAMMPS *, int, char **);
  ~FixContactTriPenalty() override;
  int setmask() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void setup(int) override;
  void initial_integrate(int) override;
  void post_force(int) override;
  void end_of_step() override;
  double compute_vector(int) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  double memory_usage() override;
  double compute_array(int, int) override;

  // the current tool geometry in the simulation frame (for output and tests)
  std::vector<double> current_elements() const;
  int element_vertices() const { return nvert; }
  std::string timing_name() const override { return std::string("fix contact/tri-penalty ") + id; }
  // its end_of_step sets the tool particles' velocity and evaluates the velocity variables; with a
  // constant velocity it reads only its own sums (tool fields, outputs, the geometry file)
  bool end_of_step_reads_particles() const override
  {
    return !vvar[0].empty() || !vvar[1].empty() || !vvar[2].empty() || !spin_var.empty();
  }
  // time step limit of the penalty spring on this rank (fix sph/jc-thermal stable_dt takes the
  // minimum over the ranks): dtfac cfl times the stability limit of the particles in or about to be in contact
  double dt_limit(double cfl, double) const override { return dt_crit < 1.0e300 ? dtfac * cfl * dt_crit : 1.0e300; }

 protected:
  // geometry, in the tool frame; the tool translates by disp
  std::vector<double> elem;
  int nvert;                      // 3 triangles, 2 segments (2D)
  sphcut::TriBins bins;
  double stl_scale = 1.0;         // the scale of an stl tool (named by the degenerate-element error)
  double disp[3], vtool[3];
  std::string vvar[3];            // equal-style variables of the tool velocity (empty: constant)
  double vconst[3];
  // rigid rotation (keyword spin AX AY AZ PX PY PZ RATE): the unit axis, its point in the tool frame,
  // the rate (a number, or an equal-style variable: spin_var), the angle turned so far (the pose is
  // Rodrigues' matrix of the angle: no drift of the axis) and this step's torque sum (CS_TORQUE)
  int spin = 0;
  double spin_axis[3] = {0.0, 0.0, 1.0}, spin_point[3] = {0.0, 0.0, 0.0};
  double spin_const = 0.0, omega = 0.0, theta = 0.0, torque = 0.0;
  // the rate that turned the tool in its last step (the contact's surface velocity: at the setup of
  // a continued run as at that step's end, so that the run continues bit for bit with a ramp)
  double omega_step = 0.0;
  int omega_step_set = 0;
  std::string spin_var;
  int parse_spin(int iarg, int narg, char **arg);
  sphcut::ToolRotation rotation() const;    // the pose of the current angle (step_params)
  // contact parameters
  double etool, pfac, dfac, sfac;
  // the friction law (sphcut::FrictionLaw: static limit, Coulomb or memory; mu constant, a table
  // mu(T) or an equal-style variable of an internal T), set by the keywords; vreg by init() unless given
  sphcut::FrictionLaw friction;
  int vreg_set;
  int stick_given = 0, tfac_given = 0, friction_given = 0, split_given = 0;
  std::vector<double> mu_t, mu_v;    // the table mu(T) that friction points at
  std::string mu_var, mu_tvar;       // mu v_name tvar NAME: the law's host function (mu_variable)
  int mu_ivar, mu_itvar;
  static double mu_variable(void *fix, double temp);
  // heat
  double eta, split;
  int split_auto;
  std::string id_heat, tool_group;
  int toolbit;
  FixHeatFMFS *heat;
  double tool_cp;                 // lumped tool heat capacity (energy/K, 0: none)
  double tool_temp;
  // output
  int write_every;
  std::string write_file;
  // accumulators of this rank
  double ftool[3], fric_power, work_rate, q_work, q_tool, q_tool_lost, q_work_tool, maxpen;
  int ncontact;
  double tool_work;               // work done by the tool on the particles (cumulative)
  double diss_rate;               // contact dissipation rate sum F.(v_tool - v) of this step
  double contact_diss;            // dissipated at the contact (friction, dashpot), cumulative
  double dt_last;                 // time step of the last contact evaluation
  double dtfac = 0.5;             // fraction (times cfl) of the spring's stability limit
  double onset = 0.2;             // smooth onset of the spring over this fraction of the contact radius
  double dt_crit;                 // min stability limit of the spring, particles in or near contact (this rank)
  double **fcontact;              // per-atom output of this step: contact force (3), F_N, |F_T|, feature
  int nmax_out;
  void grow_output();
  // decomposition by tool feature (rake, edge, flank, other), this step and rank:
  // normal force on the tool x y, friction force on the tool x y, contacts, sum F_N,
  // sum |F_T|, contacts at the Coulomb limit
  double decomp[NFEAT][NDECOMP];
  std::vector<int> elem_feature;  // per element: FEAT_* (insert tags; STL tools: FEAT_OTHER)
  double *qbuf;                   // tool heat to reverse communicate
  int nmax_buf;
  class NeighList *list;
  FixSPHJCThermal *fix;
  const sphcut::Model *model;    // the model of pair sph/jc-thermal (sphcut::find_model)

  // the constructor's pieces: the keywords (by group, each returns the arguments it used, 0:
  // not its keyword), their consistency, the tool's elements, the outputs offered
  struct ToolSpec {
    std::string kind;                 // stl or insert
    std::vector<std::string> args;    // the file, or the insert's keyword value pairs
    sphcut::StlTransform tf;          // scale, move, rotate
    int has_transform = 0;
  };
  void parse_keywords(int narg, char **arg, ToolSpec &spec);
  int parse_tool_keyword(const std::string &kw, int iarg, int narg, char **arg, ToolSpec &spec);
  int parse_contact_keyword(const std::string &kw, int iarg, int narg, char **arg);
  int parse_heat_keyword(const std::string &kw, int iarg, int narg, char **arg);
  void read_mu_table(const std::string &file);
  void need_values(int iarg, int narg, int n, const std::string &kw) const;
  double number(const char *s) const;
  void check_keywords(const ToolSpec &spec);
  void load_geometry(const ToolSpec &spec);
  void build_insert(const ToolSpec &spec);
  void declare_outputs();
  void compute_tool_velocity();    // vtool from the constants / variables
  void update_tool_velocity();     // and the rigid tool particles' velocity (host)
  void write_geometry();
  double contact_radius_max() const;
  std::vector<double> heat_w;     // tool particles near one contact and their kernel weights
  std::vector<int> heat_j;
  int inside_checked = 0;         // particles inside the tool looked for (first setup)
  int restored = 0;               // global state read from a restart file
  void clear_history();
  sphcut::ContactIn contact_params(double dt_force) const;
  sphcut::ContactStep step_params(double dt_force) const;    // sphcut_contact_step.h (host copies)
  // post_force's pieces: the sums cleared, the particles (sphcut::contact_step through HostSink),
  // the tool's heat and the step's energy integrals
  struct HostSink;
  void clear_step_sums();
  void finish_step(double w_old, double d_old, double q_lumped);
  void warn_inside();
  double spring_dt_crit(int i) const;
  double effusivity_split() const;        // split auto: the workpiece's share of the friction heat
  double initial_spring_limit() const;    // the spring's dt limit before the first force evaluation

  // tool fields per facet (tool_fields N, wear usui K alpha): loads, temperature and Usui wear,
  // averaged over N steps (sphcut_tool_fields.h; the per-contact arithmetic in sphcut_contact.h)
 public:
  enum { NVEC_BASE = 15 + NFEAT * NDECOMP };    // vector elements before the tool fields' global sums
  // after them (1-based 53, 54): the torque about the spin axis, the spindle power torque * rate
  enum { NVEC_SPIN = NVEC_BASE + sphcut::ToolFields::NGLOB, NVEC = NVEC_SPIN + 2 };
  sphcut::ToolFields fields;
 protected:
  int fields_parse(const std::string &kw, int iarg, int narg, char **arg);    // values used, 0: not ours
  void fields_setup();                          // after the geometry: facets, vector and array sizes
  void fields_step();                           // post_force of a step (not a setup): the interval's time
  virtual void fields_end_of_step();            // the interval's end: averages (the /kk fix fetches first)
  void fields_at_setup();                       // a run's setup: the array's pose columns at this step
  // the tool's fingerprint in restart files: element values, the vertices' bounding box (lo, hi)
  enum { NFINGER = 7 };
  void tool_fingerprint(double *fp) const;
  void check_fingerprint(const double *saved) const;
  void fields_write_restart(std::vector<double> &list);
  void fields_restart(const double *buf);
};

}    // namespace LAMMPS_NS

#endif
#endif
