/* ----------------------------------------------------------------------
   sphcut - fix contact/tri-penalty

   For each particle of the group (not rigid tool particles): the closest
   element of the tool (bin query, seed 000 sec. 3 with one sphere per
   triangle), the signed distance d and outward normal n (faces, edges
   and vertices: sphcut_contact.h), the penetration delta = 0.5 h/SFAC - d
   (eq. 9), the penalty force (k delta + D delta_dot) n (eqs. 10-12) and
   Coulomb friction (eqs. 13-15) with mu(T).  The tool only translates;
   its mesh stays in its own frame and particles are queried at x - disp.
   Friction heat eta |F_t| |v_t| goes partly to the particle, partly to
   tool SPH particles near it (seed 000's fourth list) or a lumped tool.
------------------------------------------------------------------------- */

#include "fix_contact_tri_penalty.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_heat_fmfs.h"
#include "fix_sph_jc_thermal.h"
#include "force.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "sphcut_model.h"
#include "update.h"
#include "variable.h"

#include "sphcut_checks.h"
#include "sphcut_compat.h"
#include "sphcut_contact.h"
#include "sphcut_kernels.h"
#include "sphcut_timer.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

using namespace LAMMPS_NS;
using namespace FixConst;
using sphcut::Material;

/* ---------------------------------------------------------------------- */

FixContactTriPenalty::FixContactTriPenalty(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), nvert(3), etool(0.0), pfac(1.0), dfac(0.1), sfac(1.2), vreg_set(0), mu_ivar(-1),
    mu_itvar(-1), eta(1.0), split(1.0), split_auto(0),
    toolbit(0), heat(nullptr), tool_cp(0.0), tool_temp(0.0), write_every(0), fric_power(0.0),
    work_rate(0.0), q_work(0.0), q_tool(0.0), q_tool_lost(0.0), q_work_tool(0.0), maxpen(0.0),
    ncontact(0), tool_work(0.0), diss_rate(0.0), contact_diss(0.0), dt_last(0.0), dt_crit(1.0e300), fcontact(nullptr), nmax_out(0), qbuf(nullptr), nmax_buf(0),
    list(nullptr), fix(nullptr), model(nullptr)
{
  for (int k = 0; k < 3; k++) disp[k] = vtool[k] = vconst[k] = ftool[k] = 0.0;
  friction.kind = sphcut::FrictionLaw::STATIC;    // the default: friction static, mu 0
  for (int f = 0; f < NFEAT; f++)
    for (int c = 0; c < NDECOMP; c++) decomp[f][c] = 0.0;
  ToolSpec spec;
  parse_keywords(narg, arg, spec);
  check_keywords(spec);
  load_geometry(spec);
  declare_outputs();
  // the per-atom data that must follow the atoms (last contact force, the velocity it used)
  // lives in fix sph/jc-thermal's state (columns FCONT, VCONT); fcontact is the output copy
  grow_output();
  fields_setup();
}

/* ----------------------------------------------------------------------
   the keywords, in groups: tool (geometry, motion, output), contact (stiffness, damping,
   friction), heat; then the tool fields' (fix_contact_tri_penalty_fields.cpp).  Each group's
   parser returns the number of arguments it used, 0 when the keyword is not one of its own.
------------------------------------------------------------------------- */

void FixContactTriPenalty::parse_keywords(int narg, char **arg, ToolSpec &spec)
{
  int iarg = 3;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    int nused = parse_tool_keyword(kw, iarg, narg, arg, spec);
    if (!nused) nused = parse_contact_keyword(kw, iarg, narg, arg);
    if (!nused) nused = parse_heat_keyword(kw, iarg, narg, arg);
    if (!nused) nused = fields_parse(kw, iarg, narg, arg);
    if (!nused) error->all(FLERR, "Fix contact/tri-penalty: unknown keyword {}", kw);
    iarg += nused;
  }
}

// keyword kw at arg[iarg] needs n values
void FixContactTriPenalty::need_values(int iarg, int narg, int n, const std::string &kw) const
{
  if (iarg + n >= narg) error->all(FLERR, "Fix contact/tri-penalty: keyword {} needs {} value(s)", kw, n);
}

double FixContactTriPenalty::number(const char *s) const
{
  return utils::numeric(FLERR, s, false, lmp);
}

// stl FILE, insert ..., scale, move, rotate, velocity, write
int FixContactTriPenalty::parse_tool_keyword(const std::string &kw, int iarg, int narg, char **arg, ToolSpec &spec)
{
  if (kw == "stl") {
    need_values(iarg, narg, 1, kw);
    spec.kind = "stl";
    spec.args = {arg[iarg + 1]};
    return 2;
  }
  if (kw == "insert") {
    // insert rake G clearance A radius R rake_length L flank_length F [width W] [segments N] [face_segments M]
    //        [land VB]
    spec.kind = "insert";
    spec.args.clear();
    int i = iarg + 1;
    while (i + 1 < narg) {
      const std::string k = arg[i];
      if (k != "rake" && k != "clearance" && k != "radius" && k != "rake_length" && k != "flank_length" &&
          k != "width" && k != "segments" && k != "face_segments" && k != "land")
        break;
      if (k == "segments" || k == "face_segments")
        sphcut::parse_int(lmp, "Fix contact/tri-penalty", "insert " + k, arg[i + 1]);
      else number(arg[i + 1]);    // a LAMMPS error here if the value is not a number
      spec.args.push_back(k);
      spec.args.push_back(arg[i + 1]);
      i += 2;
    }
    return i - iarg;
  }
  if (kw == "scale") {
    need_values(iarg, narg, 1, kw);
    spec.tf.scale = number(arg[iarg + 1]);
    if (spec.tf.scale <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: scale must be > 0, got {}", spec.tf.scale);
    spec.has_transform = 1;
    return 2;
  }
  if (kw == "move") {
    need_values(iarg, narg, 3, kw);
    for (int k = 0; k < 3; k++) spec.tf.shift[k] = number(arg[iarg + 1 + k]);
    return 4;
  }
  if (kw == "rotate") {
    need_values(iarg, narg, 4, kw);
    const double axis[3] = {number(arg[iarg + 2]), number(arg[iarg + 3]), number(arg[iarg + 4])};
    if (axis[0] == 0.0 && axis[1] == 0.0 && axis[2] == 0.0)
      error->all(FLERR, "Fix contact/tri-penalty: rotate axis must not be zero");
    spec.tf.set_axis_angle(axis, number(arg[iarg + 1]));
    spec.has_transform = 1;
    return 5;
  }
  if (kw == "velocity") {
    need_values(iarg, narg, 3, kw);
    for (int k = 0; k < 3; k++) {
      const std::string v = arg[iarg + 1 + k];
      if (utils::strmatch(v, "^v_")) vvar[k] = v.substr(2);
      else vconst[k] = number(arg[iarg + 1 + k]);
      // utils::numeric takes 1e999 as inf
      if (!std::isfinite(vconst[k]))
        error->all(FLERR, "Fix contact/tri-penalty: velocity {} is not a finite number", v);
    }
    return 4;
  }
  if (kw == "spin") return parse_spin(iarg, narg, arg);
  if (kw == "write") {
    need_values(iarg, narg, 2, kw);
    write_every = sphcut::parse_int(lmp, "Fix contact/tri-penalty", "write interval", arg[iarg + 1]);
    write_file = arg[iarg + 2];
    if (!utils::strmatch(write_file, "\\.vtk$") && !utils::strmatch(write_file, "\\.stl$"))
      error->all(FLERR, "Fix contact/tri-penalty: write file {} must end in .vtk or .stl", write_file);
    return 3;
  }
  return 0;
}

// spin AX AY AZ PX PY PZ RATE: the tool turns about the axis (AX AY AZ) through the point (PX PY PZ) of
// the tool frame (it moves with the tool's translation) at RATE rad/time (a number or v_name)
int FixContactTriPenalty::parse_spin(int iarg, int narg, char **arg)
{
  need_values(iarg, narg, 7, "spin");
  double a[3];
  for (int k = 0; k < 3; k++) {
    a[k] = number(arg[iarg + 1 + k]);
    spin_point[k] = number(arg[iarg + 4 + k]);
  }
  const double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  if (!(len > 0.0) || !std::isfinite(len))
    error->all(FLERR, "Fix contact/tri-penalty: spin axis {} {} {} must be a nonzero finite vector", arg[iarg + 1],
               arg[iarg + 2], arg[iarg + 3]);
  for (int k = 0; k < 3; k++) {
    spin_axis[k] = a[k] / len;
    if (!std::isfinite(spin_point[k]))
      error->all(FLERR, "Fix contact/tri-penalty: spin point {} is not a finite number", arg[iarg + 4 + k]);
  }
  if (domain->dimension == 2 && (a[0] != 0.0 || a[1] != 0.0))
    error->all(FLERR, "Fix contact/tri-penalty: spin axis {} {} {}: a 2D tool turns about z only (spin 0 0 1 ...)",
               arg[iarg + 1], arg[iarg + 2], arg[iarg + 3]);
  const std::string r = arg[iarg + 7];
  if (utils::strmatch(r, "^v_")) {
    spin_var = r.substr(2);
  } else {
    spin_var.clear();
    spin_const = number(arg[iarg + 7]);
    if (!std::isfinite(spin_const))
      error->all(FLERR, "Fix contact/tri-penalty: spin rate {} is not a finite number", r);
  }
  spin = 1;
  return 8;
}

// the pose of the tool's rotation at the current angle theta (off without spin)
sphcut::ToolRotation FixContactTriPenalty::rotation() const
{
  sphcut::ToolRotation r;
  if (!spin) return r;
  r.on = 1;
  for (int k = 0; k < 3; k++) {
    r.axis[k] = spin_axis[k];
    r.p0[k] = spin_point[k];
  }
  if (domain->dimension == 2) r.p0[2] = 0.0;
  r.omega = omega_step_set ? omega_step : omega;
  sphcut::rotation_matrix(r.axis, theta, r.R);
  return r;
}

// E, pfac, dfac, sfac, vreg, eta, dtfac, onset, stick, friction, tfac, mu
int FixContactTriPenalty::parse_contact_keyword(const std::string &kw, int iarg, int narg, char **arg)
{
  if (kw == "E") {
    need_values(iarg, narg, 1, kw);
    etool = number(arg[iarg + 1]);
    if (etool <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: E must be > 0, got {}", etool);
    return 2;
  }
  if (kw == "pfac" || kw == "dfac" || kw == "sfac" || kw == "vreg" || kw == "eta") {
    need_values(iarg, narg, 1, kw);
    const double v = number(arg[iarg + 1]);
    if (kw == "pfac") pfac = v;
    else if (kw == "dfac") dfac = v;
    else if (kw == "sfac") sfac = v;
    else if (kw == "vreg") {
      friction.v_reg = v;
      vreg_set = 1;
    } else eta = v;
    if ((kw == "pfac" || kw == "sfac") && v <= 0.0)
      error->all(FLERR, "Fix contact/tri-penalty: {} must be > 0, got {}", kw, v);
    if ((kw == "dfac" || kw == "vreg") && v < 0.0)
      error->all(FLERR, "Fix contact/tri-penalty: {} must be >= 0, got {}", kw, v);
    if (kw == "eta" && (v < 0.0 || v > 1.0))
      error->all(FLERR, "Fix contact/tri-penalty: eta must be in [0,1], got {}", v);
    return 2;
  }
  if (kw == "dtfac") {
    need_values(iarg, narg, 1, kw);
    dtfac = number(arg[iarg + 1]);
    if (!(dtfac > 0.0 && dtfac <= 1.0)) error->all(FLERR, "Fix contact/tri-penalty: dtfac must be in (0,1], got {}", arg[iarg + 1]);
    return 2;
  }
  if (kw == "onset") {
    need_values(iarg, narg, 1, kw);
    onset = number(arg[iarg + 1]);
    if (!(onset >= 0.0 && onset < 1.0))
      error->all(FLERR, "Fix contact/tri-penalty: onset must be in [0,1), got {}", arg[iarg + 1]);
    return 2;
  }
  if (kw == "stick") {
    need_values(iarg, narg, 1, kw);
    const std::string v = arg[iarg + 1];
    if (v != "yes" && v != "no") error->all(FLERR, "Fix contact/tri-penalty: stick must be yes or no, got {}", v);
    // (with friction memory an error in check_keywords, which names stick)
    if (!friction.memory()) friction.kind = v == "yes" ? sphcut::FrictionLaw::STATIC : sphcut::FrictionLaw::COULOMB;
    stick_given = 1;
    return 2;
  }
  if (kw == "friction") {
    need_values(iarg, narg, 1, kw);
    const std::string v = arg[iarg + 1];
    if (v == "static") friction.kind = sphcut::FrictionLaw::STATIC;
    else if (v == "coulomb") friction.kind = sphcut::FrictionLaw::COULOMB;
    else if (v == "memory") friction.kind = sphcut::FrictionLaw::MEMORY;
    else error->all(FLERR, "Fix contact/tri-penalty: friction must be static, coulomb or memory, got {}", v);
    friction_given = 1;
    return 2;
  }
  if (kw == "tfac") {
    need_values(iarg, narg, 1, kw);
    const double tfac = number(arg[iarg + 1]);
    if (tfac <= 0.0 || tfac > 1.0) error->all(FLERR, "Fix contact/tri-penalty: tfac must be in (0,1], got {}", tfac);
    friction.tfac = tfac;
    tfac_given = 1;
    return 2;
  }
  if (kw == "mu") {
    need_values(iarg, narg, 1, kw);
    const std::string v = arg[iarg + 1];
    if (v == "table") {
      need_values(iarg, narg, 2, kw);
      read_mu_table(arg[iarg + 2]);
      friction.mu_kind = sphcut::FrictionLaw::MU_TABLE;
      friction.nmu = (int) mu_t.size();
      friction.mu_t = mu_t.data();
      friction.mu_v = mu_v.data();
      return 3;
    }
    if (utils::strmatch(v, "^v_")) {
      // mu v_name tvar NAME: equal-style variable of the internal variable NAME (the temperature)
      if (iarg + 3 >= narg || std::string(arg[iarg + 2]) != "tvar")
        error->all(FLERR, "Fix contact/tri-penalty: mu v_{} needs 'tvar NAME' (an internal variable)", v.substr(2));
      mu_var = v.substr(2);
      mu_tvar = arg[iarg + 3];
      friction.mu_kind = sphcut::FrictionLaw::MU_HOST;
      friction.host_mu = &FixContactTriPenalty::mu_variable;
      friction.host_ctx = this;
      return 4;
    }
    const double mu0 = number(arg[iarg + 1]);
    if (mu0 < 0.0) error->all(FLERR, "Fix contact/tri-penalty: mu must be >= 0, got {}", mu0);
    friction.mu_kind = sphcut::FrictionLaw::MU_CONST;
    friction.mu0 = mu0;
    return 2;
  }
  return 0;
}

// mu table FILE: lines "T mu" (# comments), T increasing
void FixContactTriPenalty::read_mu_table(const std::string &file)
{
  if (sphcut::is_directory(file))
    error->all(FLERR, "Fix contact/tri-penalty: mu table {} is a directory, not a file", file);
  std::ifstream in(file);
  if (!in) error->all(FLERR, "Fix contact/tri-penalty: cannot open mu table {}", file);
  std::string line;
  while (std::getline(in, line)) {
    const auto p = line.find('#');
    if (p != std::string::npos) line.erase(p);
    std::istringstream ss(line);
    double t, m;
    if (!(ss >> t)) continue;
    if (!(ss >> m)) error->all(FLERR, "Fix contact/tri-penalty: mu table {}: line '{}' needs T mu", file, line);
    if (!mu_t.empty() && t <= mu_t.back())
      error->all(FLERR, "Fix contact/tri-penalty: mu table {}: temperatures must increase", file);
    if (m < 0.0) error->all(FLERR, "Fix contact/tri-penalty: mu table {}: negative mu {}", file, m);
    mu_t.push_back(t);
    mu_v.push_back(m);
  }
  if (mu_t.empty()) error->all(FLERR, "Fix contact/tri-penalty: mu table {} is empty", file);
}

// heat ID, split S|auto, tool_particles GROUP, tool_cp C T0
int FixContactTriPenalty::parse_heat_keyword(const std::string &kw, int iarg, int narg, char **arg)
{
  if (kw == "heat") {
    need_values(iarg, narg, 1, kw);
    id_heat = arg[iarg + 1];
    return 2;
  }
  if (kw == "split") {
    need_values(iarg, narg, 1, kw);
    split_given = 1;
    if (std::string(arg[iarg + 1]) == "auto") split_auto = 1;
    else {
      split = number(arg[iarg + 1]);
      if (split < 0.0 || split > 1.0) error->all(FLERR, "Fix contact/tri-penalty: split must be in [0,1] or auto, got {}", split);
    }
    return 2;
  }
  if (kw == "tool_particles") {
    need_values(iarg, narg, 1, kw);
    const int ig = group->find(arg[iarg + 1]);
    if (ig < 0) error->all(FLERR, "Fix contact/tri-penalty: tool_particles group {} does not exist", arg[iarg + 1]);
    tool_group = arg[iarg + 1];
    toolbit = group->bitmask[ig];
    return 2;
  }
  if (kw == "tool_cp") {
    need_values(iarg, narg, 2, kw);
    tool_cp = number(arg[iarg + 1]);
    tool_temp = number(arg[iarg + 2]);
    if (tool_cp <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: tool_cp must be > 0, got {}", tool_cp);
    return 3;
  }
  return 0;
}

// the keywords that exclude or need one another; the element kind (segments in 2D)
void FixContactTriPenalty::check_keywords(const ToolSpec &spec)
{
  if (spec.kind.empty()) error->all(FLERR, "Fix contact/tri-penalty: no tool geometry (keyword stl or insert)");
  const bool fmemory = friction.memory();
  if (fmemory && stick_given)
    error->all(FLERR, "Fix contact/tri-penalty: stick applies to friction static/coulomb, not to friction memory");
  if (stick_given && friction_given)
    error->all(FLERR, "Fix contact/tri-penalty: give friction or stick, not both (stick yes = friction static, "
               "stick no = friction coulomb)");
  if (fmemory && vreg_set)
    error->all(FLERR, "Fix contact/tri-penalty: vreg applies to friction static/coulomb, not to friction memory");
  if (!fmemory && tfac_given)
    error->all(FLERR, "Fix contact/tri-penalty: tfac applies to friction memory only");
  if (spec.kind == "insert" && spec.has_transform)
    error->all(FLERR, "Fix contact/tri-penalty: scale and rotate apply to stl tools only (use move)");
  if (!split_given && toolbit) split_auto = 1;
  if (split_auto && !toolbit)
    error->all(FLERR, "Fix contact/tri-penalty: split auto needs tool_particles (their conductivity)");
  if (spin && toolbit)
    error->all(FLERR, "Fix contact/tri-penalty: spin with tool_particles is not supported (the rigid tool "
               "particles translate only); give the tool's heat to tool_cp or leave it unassigned");

  nvert = domain->dimension == 2 ? 2 : 3;
  if (write_every && nvert == 2 && utils::strmatch(write_file, "\\.stl$"))
    error->all(FLERR, "Fix contact/tri-penalty: write file {}: a 2D tool (segments) can only be written as .vtk",
               write_file);
}

/* ----------------------------------------------------------------------
   the tool's elements (tool frame) and the feature of each: rank 0 reads the STL file or builds
   the insert, every rank gets a copy
------------------------------------------------------------------------- */

void FixContactTriPenalty::load_geometry(const ToolSpec &spec)
{
  std::string msg;
  if (comm->me == 0) {
    try {
      if (spec.kind == "stl") {
        std::vector<double> tri = sphcut::read_stl(spec.args[0], spec.tf);
        sphcut::require_closed_mesh(spec.args[0], tri);    // a tool is a solid: no open sheets
        stl_scale = spec.tf.scale;
        // 2D: the section of the solid with the plane z = 0, as segments (outward normal kept)
        elem = nvert == 3 ? tri : sphcut::stl_section_z0(spec.args[0], tri);
      } else {
        build_insert(spec);
      }
    } catch (std::exception &e) {
      msg = e.what();
    }
  }
  int len = (int) msg.size();
  MPI_Bcast(&len, 1, MPI_INT, 0, world);
  if (len) {
    msg.resize(len);
    MPI_Bcast(&msg[0], len, MPI_CHAR, 0, world);
    error->all(FLERR, "Fix contact/tri-penalty: {}", msg);
  }
  long n = (long) elem.size();
  MPI_Bcast(&n, 1, MPI_LONG, 0, world);
  elem.resize(n);
  MPI_Bcast(elem.data(), (int) n, MPI_DOUBLE, 0, world);
  // feature of each element (only the insert has tags: an STL tool is all FEAT_OTHER)
  const long nel = n / (nvert == 3 ? 9 : 6);
  if ((long) elem_feature.size() != nel) elem_feature.assign(nel, FEAT_OTHER);
  MPI_Bcast(elem_feature.data(), (int) nel, MPI_INT, 0, world);
}

// the generated cutting insert (keyword insert), moved by move; its elements' features
void FixContactTriPenalty::build_insert(const ToolSpec &spec)
{
  sphcut::InsertParams ip;
  const std::vector<std::string> &a = spec.args;
  for (size_t k = 0; k + 1 < a.size(); k += 2) {
    const double v = std::stod(a[k + 1]);
    if (a[k] == "rake") ip.rake_angle = v;
    else if (a[k] == "clearance") ip.clearance_angle = v;
    else if (a[k] == "radius") ip.edge_radius = v;
    else if (a[k] == "rake_length") ip.rake_length = v;
    else if (a[k] == "flank_length") ip.flank_length = v;
    else if (a[k] == "width") ip.width = v;
    else if (a[k] == "segments") ip.arc_segments = (int) v;
    else if (a[k] == "face_segments") ip.face_segments = (int) v;
    else if (a[k] == "land") ip.land = v;
  }
  std::vector<int> tags;
  elem = sphcut::make_cutting_insert(ip, domain->dimension, &tags);
  for (int t : tags)
    elem_feature.push_back(t == sphcut::INSERT_RAKE ? FEAT_RAKE
                           : t == sphcut::INSERT_EDGE ? FEAT_EDGE
                           : t == sphcut::INSERT_FLANK ? FEAT_FLANK : FEAT_OTHER);
  for (size_t k = 0; k < elem.size(); k += 3)
    for (int c = 0; c < 3; c++) elem[k + c] += (c < 2 || nvert == 3) ? spec.tf.shift[c] : 0.0;
}

// what the fix offers LAMMPS: global vector, per-atom array, restart, reverse communication
void FixContactTriPenalty::declare_outputs()
{
  vector_flag = 1;
  size_vector = NVEC;
  global_freq = 1;
  extvector = 0;
  peratom_flag = 1;
  size_peratom_cols = 6;
  peratom_freq = 1;
  restart_global = 1;
  comm_reverse = 1;
  nevery = 1;
  dynamic_group_allow = 0;
}

FixContactTriPenalty::~FixContactTriPenalty()
{
  memory->destroy(fcontact);
  memory->destroy(qbuf);
}

int FixContactTriPenalty::setmask()
{
  return INITIAL_INTEGRATE | POST_FORCE | END_OF_STEP;
}

/* ---------------------------------------------------------------------- */

double FixContactTriPenalty::contact_radius_max() const
{
  double hmax = 0.0;
  for (int t = 1; t <= atom->ntypes; t++)
    if (model->materials()[t].defined) hmax = std::max(hmax, model->smoothing_length(t));
  return hmax;
}

void FixContactTriPenalty::init()
{
  // one contact fix: the per-atom contact columns of fix sph/jc-thermal (force, feature, friction
  // memory) and the contact's time step limit exist once, a second fix would overwrite them
  for (auto *f : sphcut::fixes_by_style(modify, "^contact/tri-penalty"))
    if (f != this)
      error->all(FLERR, "Fix contact/tri-penalty: only one contact/tri-penalty fix is supported, found {} and {} "
                 "(the per-atom contact state and the contact's time step limit exist once; put several tools "
                 "in one STL file)", id, f->id);
  fix = FixSPHJCThermal::require(lmp, "Fix contact/tri-penalty", groupbit, group->names[igroup], &model);
  fix->attach(this);
  heat = nullptr;
  if (!id_heat.empty()) {
    Fix *h = sphcut::fix_by_id(modify, id_heat);
    if (!h) error->all(FLERR, "Fix contact/tri-penalty: heat fix {} does not exist", id_heat);
    if (!utils::strmatch(h->style, "^heat/fmfs"))
      error->all(FLERR, "Fix contact/tri-penalty: fix {} is not of style heat/fmfs", id_heat);
    heat = dynamic_cast<FixHeatFMFS *>(h);
  }
  for (int k = 0; k < 3; k++)
    if (!vvar[k].empty()) {
      const int iv = input->variable->find(vvar[k].c_str());
      if (iv < 0) error->all(FLERR, "Fix contact/tri-penalty: velocity variable {} does not exist", vvar[k]);
      if (!input->variable->equalstyle(iv))
        error->all(FLERR, "Fix contact/tri-penalty: velocity variable {} is not equal-style", vvar[k]);
    }
  if (!spin_var.empty()) {
    const int iv = input->variable->find(spin_var.c_str());
    if (iv < 0) error->all(FLERR, "Fix contact/tri-penalty: spin rate variable {} does not exist", spin_var);
    if (!input->variable->equalstyle(iv))
      error->all(FLERR, "Fix contact/tri-penalty: spin rate variable {} is not equal-style", spin_var);
  }
  if (friction.host_only()) {    // mu v_name tvar NAME: the variables of mu_variable
    mu_ivar = input->variable->find(mu_var.c_str());
    mu_itvar = input->variable->find(mu_tvar.c_str());
    if (mu_ivar < 0 || !input->variable->equalstyle(mu_ivar))
      error->all(FLERR, "Fix contact/tri-penalty: mu variable {} does not exist or is not equal-style", mu_var);
    if (mu_itvar < 0 || !input->variable->internalstyle(mu_itvar))
      error->all(FLERR, "Fix contact/tri-penalty: tvar {} must be an internal-style variable", mu_tvar);
  }
  if (split_auto) split = effusivity_split();
  // the bins: elements within the largest query radius, in the tool frame
  const double rsearch = sphcut::support_radius(contact_radius_max());
  sphcut::tri_bin_build(elem, nvert, rsearch, bins);
  // a tool far below the search radius is a point to the search: the distances of a particle
  // to its elements tie, and the side is lost (e.g. scale 1e-30, issue 23)
  const double extent = sphcut::bounding_diagonal(elem);
  if (!(extent > 1.0e-6 * rsearch))
    error->all(FLERR, "Fix contact/tri-penalty: the tool is degenerate at scale {}: it spans {}, below 1e-6 of the "
               "contact search radius 2h = {}", stl_scale, extent, rsearch);
  if (toolbit) sphcut::request_full_list(neighbor, this, instance_me, true, false);
  update_tool_velocity();
  dt_crit = initial_spring_limit();
  if (!vreg_set) {
    const double s = sqrt(vtool[0] * vtool[0] + vtool[1] * vtool[1] + vtool[2] * vtool[2]);
    friction.v_reg = 0.01 * s;    // 1 % of the tool speed (fixed tool: 0, Coulomb above the floor of post_force)
  }
}

// the share of the friction heat that goes into the workpiece by thermal effusivity sqrt(k rho cp)
// of workpiece and tool (seed 000 sec. 4; keyword split auto)
double FixContactTriPenalty::effusivity_split() const
{
  int ttool = 0, twork = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (atom->mask[i] & toolbit) ttool = atom->type[i];
    else if (atom->mask[i] & groupbit) twork = atom->type[i];
  }
  int g[2], l[2] = {ttool, twork};
  MPI_Allreduce(l, g, 2, MPI_INT, MPI_MAX, world);
  if (!g[0] || !g[1]) error->all(FLERR, "Fix contact/tri-penalty: split auto needs tool and workpiece particles");
  const Material &mt = model->materials()[g[0]], &mw = model->materials()[g[1]];
  const double et = sqrt(mt.kappa * mt.rho0 * mt.cp), ew = sqrt(mw.kappa * mw.rho0 * mw.cp);
  if (et + ew <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: split auto needs k and cp of tool and workpiece");
  return ew / (ew + et);
}

double FixContactTriPenalty::initial_spring_limit() const
{
  // the spring's time step limit before the first force evaluation (fix sph/jc-thermal sets
  // the first dt of a run in its setup, before this fix's): the particles in or about to be in
  // contact, by the test post_force applies (sphcut::near_contact), so that a run continued
  // from a restart file takes the step the unsplit run took (a wider band here, all particles
  // within 2h of the tool, gave the first step of a run continued while the tool approached
  // the workpiece the spring's limit: the time and the first contact shifted)
  double lim = 1.0e300;
  const sphcut::TriBinView view = bins.view();
  const sphcut::ToolRotation rot = rotation();
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit) || (atom->mask[i] & toolbit) || fix->role_of(atom->mask[i]) == FixSPHJCThermal::TOOL) continue;
    const int it = atom->type[i];
    const double h = model->smoothing_length(it);
    const double *xi = atom->x[i];
    double xt[3];
    sphcut::tool_frame_point(disp, rot, xi, nvert == 2 ? 2 : 3, xt);
    double d, n[3], q[3];
    int region;
    if (sphcut::tool_surface(view, xt, h, d, n, q, region) < 0) continue;    // no facet within 2h
    // (a rotating tool: its surface velocity at the particle)
    double vs[3] = {vtool[0], vtool[1], vtool[2]};
    if (rot.on) {
      double r[3];
      for (int k = 0; k < 3; k++) r[k] = xi[k] - disp[k] - rot.p0[k];
      if (nvert == 2) r[2] = 0.0;
      sphcut::tool_surface_velocity(vtool, rot, r, vs);
    }
    if (sphcut::near_contact(d, h, sfac, atom->v[i], vs, domain->dimension, update->dt))
      lim = std::min(lim, spring_dt_crit(i));
  }
  return lim;
}

// stability limit of the penalty spring of local particle i (sphcut_contact.h contact_spring_dt)
double FixContactTriPenalty::spring_dt_crit(int i) const
{
  const int it = atom->type[i];
  const double h = model->smoothing_length(it);
  const double m = atom->rmass ? atom->rmass[i] : atom->mass[it];
  const double dp = model->spacing(it) > 0.0 ? model->spacing(it) : h / sfac;
  return sphcut::contact_spring_dt(model->materials()[it].E, etool, dp, pfac, dfac, m, domain->dimension);
}

void FixContactTriPenalty::init_list(int, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   tool velocity for the coming step; rigid tool particles get it too.  A
   variable's value is checked at every evaluation: a NaN or infinite
   velocity would move the tool (and its bins' query point) to NaN, and the
   closest-element search crashed on it
------------------------------------------------------------------------- */

void FixContactTriPenalty::compute_tool_velocity()
{
  for (int k = 0; k < 3; k++) {
    if (vvar[k].empty()) vtool[k] = vconst[k];
    else {
      vtool[k] = input->variable->compute_equal(input->variable->find(vvar[k].c_str()));
      // an equal-style variable has the same value on every rank
      if (!std::isfinite(vtool[k]))
        error->all(FLERR, "Fix contact/tri-penalty: velocity variable {} ({} component) is {} at step {}: the tool "
                   "velocity must be a finite number", vvar[k], "xyz"[k],
                   std::isnan(vtool[k]) ? std::string("not a number (NaN)") : fmt::format("{}", vtool[k]),
                   update->ntimestep);
    }
  }
  if (domain->dimension == 2) vtool[2] = 0.0;
  if (!spin) return;
  if (spin_var.empty()) omega = spin_const;
  else {
    omega = input->variable->compute_equal(input->variable->find(spin_var.c_str()));
    if (!std::isfinite(omega))
      error->all(FLERR, "Fix contact/tri-penalty: spin rate variable {} is {} at step {}: the rate must be a finite "
                 "number", spin_var, std::isnan(omega) ? std::string("not a number (NaN)") : fmt::format("{}", omega),
                 update->ntimestep);
  }
}

void FixContactTriPenalty::update_tool_velocity()
{
  compute_tool_velocity();
  if (!toolbit) return;
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & toolbit)
      for (int k = 0; k < 3; k++) atom->v[i][k] = vtool[k];
}

void FixContactTriPenalty::setup(int vflag)
{
  update_tool_velocity();
  if (!inside_checked) {
    warn_inside();
    // a fix defined anew (not read from a restart) starts without a contact history, whatever
    // an earlier contact fix left in the state
    if (!restored) clear_history();
  }
  fields_at_setup();    // before inside_checked: a fix's first setup
  inside_checked = 1;
  post_force(vflag);
  if (write_every) write_geometry();
}

void FixContactTriPenalty::clear_history()
{
  using F = FixSPHJCThermal;
  for (int i = 0; i < atom->nlocal; i++)
    for (int k = F::FCONT; k < F::FMEM + 6; k++) fix->state[i][k] = 0.0;
}

/* ----------------------------------------------------------------------
   particles of the group that start inside the tool or on its surface
   (first setup): a warning with their count; the penalty force throws them
   out at high speed.  A particle on the surface (distance 0, or within
   round-off of it: 1e-9 h) has the full contact radius as penetration, as
   one just inside: a block placed on a tool face gained 59 J in 20 steps.
   A fix defined anew (not from a restart) also warns of particles outside
   the tool but within the contact radius 0.5 h/sfac: the tool starts in
   contact, pushed from the first step (an impulsive start: in the 2D
   example at 41 across, the tool 0.6 or 0.7 spacings away, 14 such
   particles, and with spall release one thrown off at 712 m/s).
------------------------------------------------------------------------- */

void FixContactTriPenalty::warn_inside()
{
  using F = FixSPHJCThermal;
  double **x = atom->x;
  const int *mask = atom->mask;
  // inside or on the surface, on the surface, outside within the contact radius
  double n[3] = {0.0, 0.0, 0.0}, dmin = 0.0;
  const sphcut::TriBinView view = bins.view();
  const sphcut::ToolRotation rot = rotation();
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit) || (mask[i] & toolbit) || fix->role_of(mask[i]) == F::TOOL) continue;
    double xt[3];
    sphcut::tool_frame_point(disp, rot, x[i], domain->dimension, xt);
    const double h = model->smoothing_length(atom->type[i]);
    const double d = sphcut::tool_signed_distance(bins, xt, sphcut::support_radius(h));
    if (d <= 1.0e-9 * h) {
      n[0] += 1.0;
      if (d >= -1.0e-9 * h) n[1] += 1.0;
      dmin = std::min(dmin, d);
    } else {
      // outside: the distance as the contact takes it (the nearest facet within 2h)
      double ds, nrm[3], q[3];
      int region;
      if (sphcut::tool_surface(view, xt, h, ds, nrm, q, region) >= 0 && ds < 0.5 * h / sfac) n[2] += 1.0;
    }
  }
  double gn[3] = {0.0, 0.0, 0.0}, gdmin = 0.0;
  MPI_Allreduce(n, gn, 3, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&dmin, &gdmin, 1, MPI_DOUBLE, MPI_MIN, world);
  if (gn[0] > 0.0 && comm->me == 0)
    error->warning(FLERR, "Fix contact/tri-penalty: {:.0f} particle(s) start inside the tool or on its surface "
                   "({:.0f} on it{}); the contact throws them out at high speed", gn[0], gn[1],
                   gn[0] > gn[1] ? fmt::format(", the deepest {:.4g} below it", -gdmin) : std::string());
  if (gn[2] > 0.0 && !restored && comm->me == 0)
    error->warning(FLERR, "Fix contact/tri-penalty: {:.0f} particle(s) start within the contact radius 0.5 h/sfac "
                   "of the tool: it pushes them from the first step (an impulsive start; with pair_coeff ... "
                   "spall release one can be thrown off and fly on); start the tool farther away", gn[2]);
}

void FixContactTriPenalty::initial_integrate(int)
{
  for (int k = 0; k < 3; k++) disp[k] += update->dt * vtool[k];
  // the angle about the fixed axis (in the tool frame): exact for a constant rate, no drift
  theta += update->dt * omega;
  omega_step = omega;
  omega_step_set = spin;
}

/* ---------------------------------------------------------------------- */

// the friction law's mu(T) of mu v_name tvar NAME (sphcut::FrictionLaw::MU_HOST, host only): the
// equal-style variable at the internal variable NAME = temp, clipped at 0
double FixContactTriPenalty::mu_variable(void *self, double temp)
{
  auto *fx = static_cast<FixContactTriPenalty *>(self);
  fx->input->variable->internal_set(fx->mu_itvar, temp);
  const double m = fx->input->variable->compute_equal(fx->mu_ivar);
  if (m != m)
    fx->error->one(FLERR, "Fix contact/tri-penalty: mu variable {} is not a number (NaN) at {} = {}", fx->mu_var,
                   fx->mu_tvar, temp);
  return m > 0.0 ? m : 0.0;
}

/* ----------------------------------------------------------------------
   the fields of sphcut::ContactIn that are the same for every particle of a step (the CPU and
   /kk drivers start each particle's input from it): tool stiffness and motion, contact
   parameters and the friction law, dt_force the time step the friction is based on
------------------------------------------------------------------------- */

sphcut::ContactIn FixContactTriPenalty::contact_params(double dt_force) const
{
  sphcut::ContactIn in;
  for (int k = 0; k < 3; k++) in.vtool[k] = vtool[k];
  in.E_tool = etool;
  in.m_tool = 0.0;
  in.dim = domain->dimension;
  in.pfac = pfac;
  in.dfac = dfac;
  in.sfac = sfac;
  in.onset = onset;
  in.friction = friction;
  in.dt = dt_force;
  return in;
}

/* ----------------------------------------------------------------------
   what is the same for every particle of a contact evaluation (sphcut_contact_step.h), with
   the host's copies of the tool and its facet tables (the /kk fix points them at its device
   copies); dt_force the time step the friction is based on
------------------------------------------------------------------------- */

sphcut::ContactStep FixContactTriPenalty::step_params(double dt_force) const
{
  sphcut::ContactStep cs;
  cs.tool = bins.view();
  cs.feature = elem_feature.data();
  cs.base = contact_params(dt_force);
  for (int k = 0; k < 3; k++) cs.disp[k] = disp[k];
  cs.rot = rotation();
  cs.dt = update->dt;
  cs.setup = update->setupflag;
  cs.eta = eta;
  cs.split = split;
  cs.has_heat = heat != nullptr;
  cs.tool_particles = toolbit && list;
  cs.lumped = tool_cp > 0.0;
  cs.fields = fields.every;
  cs.share = fields.share();
  cs.inv_area = fields.inv_area.data();
  cs.wear_K = fields.K;
  cs.wear_alpha = fields.alpha;
  return cs;
}

/* ----------------------------------------------------------------------
   the CPU driver's sink of sphcut::contact_step for local particle i: reads the atom arrays,
   the model and the state; writes this rank's sums (the fix's members; the previous contact
   force's rates and the lumped tool's heat here), the force, the heat fix's temperature rates
   and the tool particles' heat buffer (qbuf, reverse communicated)
------------------------------------------------------------------------- */

struct FixContactTriPenalty::HostSink {
  FixContactTriPenalty *fx;
  double **xa, **va, **fa, **st, **out;
  const double *rmass, *tmass;    // per-atom and per-type masses
  const int *mask, *type;
  const Material *mat;
  int dim;
  int i = 0, it = 0;                  // the particle and its type
  double w_old = 0.0, d_old = 0.0;    // the F^n half of the step's energy (CS_WORK_OLD, CS_DISS_OLD)
  double q_lumped = 0.0;              // heat into the lumped tool (tool_cp) on this rank, this step

  explicit HostSink(FixContactTriPenalty *f) :
      fx(f), xa(f->atom->x), va(f->atom->v), fa(f->atom->f), st(f->fix->state), out(f->fcontact),
      rmass(f->atom->rmass), tmass(f->atom->mass), mask(f->atom->mask), type(f->atom->type),
      mat(f->model->materials()), dim(f->domain->dimension)
  {
  }
  double v(int k) const { return va[i][k]; }
  double x(int k) const { return xa[i][k]; }
  double f(int k) const { return fa[i][k]; }
  double h() const { return fx->model->smoothing_length(it); }
  double spacing() const { return fx->model->spacing(it); }
  double E() const { return mat[it].E; }
  double mass() const { return rmass ? rmass[i] : tmass[it]; }
  double *state() const { return st[i]; }
  double *output() const { return out[i]; }
  void add(int c, double val)
  {
    switch (c) {
      case sphcut::CS_FX:
      case sphcut::CS_FY:
      case sphcut::CS_FZ: fx->ftool[c - sphcut::CS_FX] += val; break;
      case sphcut::CS_WORK: fx->work_rate += val; break;
      case sphcut::CS_DISS: fx->diss_rate += val; break;
      case sphcut::CS_FRIC: fx->fric_power += val; break;
      case sphcut::CS_QWORK: fx->q_work += val; break;
      case sphcut::CS_QLOST: fx->q_tool_lost += val; break;
      case sphcut::CS_QLUMP: q_lumped += val; break;
      case sphcut::CS_QTOOL: fx->q_tool += val; break;
      case sphcut::CS_WORK_OLD: w_old += val; break;
      case sphcut::CS_DISS_OLD: d_old += val; break;
      case sphcut::CS_TORQUE: fx->torque += val; break;
    }
  }
  void add_force(int k, double val) { fa[i][k] += val; }
  void dt_crit(double d) { fx->dt_crit = std::min(fx->dt_crit, d); }
  void record(int feat, const double *rec, double pen)
  {
    fx->ncontact++;
    sphcut::decompose_record(rec, fx->decomp[feat]);
    fx->maxpen = std::max(fx->maxpen, pen);
  }
  void facet(int fct, const double *c) { fx->fields.add(fct, c); }
  void heat_particle(double q, double, double) { fx->heat->add_heat(i, q); }
  bool heat_tool(double q);
};

// the tool SPH particles within the kernel support of particle i share q by kernel weight
bool FixContactTriPenalty::HostSink::heat_tool(double q)
{
  const int *jl = fx->list->firstneigh[i];    // the list holds every local atom, indexed by i
  const int jn = fx->list->numneigh[i];
  std::vector<double> &hw = fx->heat_w;
  std::vector<int> &hj = fx->heat_j;
  hw.clear();
  hj.clear();
  double wsum = 0.0;
  for (int jj = 0; jj < jn; jj++) {
    const int j = jl[jj] & NEIGHMASK;
    if (!(mask[j] & fx->toolbit)) continue;
    double r2 = 0.0;
    for (int k = 0; k < 3; k++) r2 += (xa[i][k] - xa[j][k]) * (xa[i][k] - xa[j][k]);
    const double w =
        sphcut::tool_heat_weight(fx->model->kernel(), dim, r2, fx->model->smoothing_length(it, type[j]));
    if (!(w > 0.0)) continue;
    hw.push_back(w);
    hj.push_back(j);
    wsum += w;
  }
  if (!(wsum > 0.0)) return false;
  for (size_t k = 0; k < hj.size(); k++) fx->qbuf[hj[k]] += q * hw[k] / wsum;
  return true;
}

/* ----------------------------------------------------------------------
   the contact of this step (or setup): the sums cleared, each local particle's contact
   (sphcut::contact_step), then the heat of the tool and the step's energy integrals
------------------------------------------------------------------------- */

void FixContactTriPenalty::post_force(int)
{
  sphcut::ScopedTimer timer(cpu_time);
  // the time step the friction floor is based on: this step's, or at the setup of a continued
  // run the one of the last step (the adaptive dt has moved on since), so that forces repeat
  if (!update->setupflag || dt_last <= 0.0) dt_last = update->dt;
  clear_step_sums();
  dt_crit = 1.0e300;
  HostSink sink(this);
  const sphcut::ContactStep cs = step_params(dt_last);
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++) {
    sink.i = i;
    sink.it = atom->type[i];
    const bool candidate =
        (mask[i] & groupbit) && !(mask[i] & toolbit) && fix->role_of(mask[i]) != FixSPHJCThermal::TOOL;
    sphcut::contact_step(cs, candidate, sink);
  }
  finish_step(sink.w_old, sink.d_old, sink.q_lumped);
}

// the buffers of this evaluation sized, its sums and the tool particles' heat zeroed
void FixContactTriPenalty::clear_step_sums()
{
  if (toolbit) {
    const int nall = atom->nlocal + atom->nghost;
    if (nall > nmax_buf) {
      nmax_buf = atom->nmax;
      memory->destroy(qbuf);
      memory->create(qbuf, nmax_buf, "contact:qbuf");
    }
    for (int i = 0; i < nall; i++) qbuf[i] = 0.0;
  }
  grow_output();
  for (int k = 0; k < 3; k++) ftool[k] = 0.0;
  fric_power = work_rate = diss_rate = maxpen = torque = 0.0;
  ncontact = 0;
  for (int ft = 0; ft < NFEAT; ft++)
    for (int c = 0; c < NDECOMP; c++) decomp[ft][c] = 0.0;
  fields_step();
}

/* after the particles: the lumped tool's temperature (q_lumped: this rank's heat into it), the
   tool particles' heat (their ghosts' shares first), the work of the tool and the contact's
   dissipation over the step (w_old, d_old: the rates of the previous contact force) */
void FixContactTriPenalty::finish_step(double w_old, double d_old, double q_lumped)
{
  if (tool_cp > 0.0) {
    // the lumped tool is one body: every rank adds the heat of all ranks
    double qsum = 0.0;
    MPI_Allreduce(&q_lumped, &qsum, 1, MPI_DOUBLE, MPI_SUM, world);
    tool_temp += qsum / tool_cp;
  }
  if (toolbit && heat) {
    sphcut::reverse_comm(comm, this);
    for (int i = 0; i < atom->nlocal; i++)
      if ((atom->mask[i] & toolbit) && qbuf[i] > 0.0) heat->add_heat(i, qbuf[i]);
  }
  if (!update->setupflag) {
    const double dt = update->dt;
    tool_work += 0.5 * dt * (w_old + work_rate);
    contact_diss += 0.5 * dt * (d_old + diss_rate);
  }
}

/* ----------------------------------------------------------------------
   per-atom output (f_ID[1..6]): contact force, F_N, |F_T| and feature of this step, written by
   post_force (valid until the next reneighbouring, i.e. at every output of the step)
------------------------------------------------------------------------- */

void FixContactTriPenalty::grow_output()
{
  if (atom->nmax <= nmax_out) return;
  nmax_out = atom->nmax;
  memory->destroy(fcontact);
  memory->create(fcontact, nmax_out, 6, "contact:fcontact");
  for (int i = 0; i < nmax_out; i++)
    for (int k = 0; k < 6; k++) fcontact[i][k] = 0.0;
  array_atom = fcontact;
}

/* ---------------------------------------------------------------------- */

void FixContactTriPenalty::end_of_step()
{
  update_tool_velocity();
  fields_end_of_step();
  if (write_every && update->ntimestep % write_every == 0) write_geometry();
}

std::vector<double> FixContactTriPenalty::current_elements() const
{
  std::vector<double> out(elem);
  const sphcut::ToolRotation rot = rotation();
  for (size_t k = 0; k < out.size(); k += 3) {
    if (rot.on) {
      double y[3] = {out[k] - rot.p0[0], out[k + 1] - rot.p0[1], nvert == 3 ? out[k + 2] - rot.p0[2] : 0.0}, r[3];
      sphcut::rotate_fwd(rot.R, y, r);
      for (int c = 0; c < 3; c++) out[k + c] = (nvert == 3 || c < 2) ? rot.p0[c] + r[c] : out[k + c];
    }
    for (int c = 0; c < 3; c++) out[k + c] += (nvert == 3 || c < 2) ? disp[c] : 0.0;
  }
  return out;
}

void FixContactTriPenalty::write_geometry()
{
  if (comm->me != 0) return;
  std::string file = write_file;
  const auto star = file.find('*');
  if (star != std::string::npos) file.replace(star, 1, std::to_string(update->ntimestep));
  const std::vector<double> cur = current_elements();
  try {
    if (utils::strmatch(file, "\\.stl$") && nvert == 3) sphcut::write_stl_ascii(file, cur, id);
    else sphcut::write_vtk(file, cur, nvert, fields.vtk_names(), fields.out);
  } catch (std::exception &e) {
    error->one(FLERR, "Fix contact/tri-penalty: {}", e.what());
  }
}

/* ----------------------------------------------------------------------
   global vector: 1-3 force on the tool, 4 friction power, 5 contacts,
   6 friction heat into the workpiece, 7 into the tool, 8-10 tool
   displacement, 11 lumped tool temperature, 12 max penetration relative
   to the contact radius, 13 work done by the tool, 14 friction heat not
   assigned (no heat fix / tool particle), 15 energy dissipated at the contact
   (friction and dashpot, sum F.(v_tool - v) integrated): work of the tool =
   kinetic + internal energy change of the particles + this;
   16-47 the decomposition by tool feature, 8 values each for rake (16-23),
   edge (24-31), flank (32-39), other (40-47: back face, STL tools): normal
   force on the tool x, y; friction force on the tool x, y; contacts;
   sum F_N; sum |F_T|; contacts at the Coulomb limit |F_T| = mu F_N;
   48-52 the tool fields' sums (fix_contact_tri_penalty_fields.cpp); 53 the
   torque of the contact forces on the particles about the spin axis, 54 the
   spindle power (53 times the rate; both 0 without spin)
------------------------------------------------------------------------- */

double FixContactTriPenalty::compute_vector(int n)
{
  if (n >= NVEC_SPIN) {
    double res = 0.0;
    MPI_Allreduce(&torque, &res, 1, MPI_DOUBLE, MPI_SUM, world);
    return n == NVEC_SPIN ? res : res * rotation().omega;
  }
  if (n >= NVEC_BASE) return fields.glob[n - NVEC_BASE];
  double loc = 0.0, res = 0.0;
  if (n <= 2) loc = ftool[n];
  else if (n == 3) loc = fric_power;
  else if (n == 4) loc = ncontact;
  else if (n == 5) loc = q_work;
  else if (n == 6) loc = q_tool;
  else if (n <= 9) return disp[n - 7];
  else if (n == 10) return tool_temp;
  else if (n == 11) {
    MPI_Allreduce(&maxpen, &res, 1, MPI_DOUBLE, MPI_MAX, world);
    return res;
  } else if (n == 12) loc = tool_work;
  else if (n == 13) loc = q_tool_lost;
  else if (n == 14) loc = contact_diss;
  else loc = decomp[(n - 15) / NDECOMP][(n - 15) % NDECOMP];
  MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_SUM, world);
  return res;
}

/* ---------------------------------------------------------------------- */

int FixContactTriPenalty::pack_reverse_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) buf[i] = qbuf[first + i];
  return n;
}

void FixContactTriPenalty::unpack_reverse_comm(int n, int *list, double *buf)
{
  for (int i = 0; i < n; i++) qbuf[list[i]] += buf[i];
}

void FixContactTriPenalty::write_restart(FILE *fp)
{
  double loc[5] = {q_work, q_tool, q_tool_lost, tool_work, contact_diss}, tot[5];
  MPI_Allreduce(loc, tot, 5, MPI_DOUBLE, MPI_SUM, world);
  // version 4: a NaN tag, the version, the 10 values of version 1 (no tag), the tool's fingerprint
  // (tool_fingerprint: restart() checks that the input gives the same tool), the angle the tool
  // has turned (spin) and the rate of its last step (NaN: none yet), the tool fields (version 3 had
  // neither, version 2 no fingerprint)
  std::vector<double> list = {std::nan(""), 4.0, disp[0], disp[1], disp[2], tool_temp, tot[0], tot[1], tot[2],
                              tot[3], tot[4], dt_last};
  double finger[NFINGER];
  tool_fingerprint(finger);
  list.insert(list.end(), finger, finger + NFINGER);
  list.push_back(theta);
  list.push_back(omega_step_set ? omega_step : std::nan(""));
  fields_write_restart(list);    // collective
  if (comm->me == 0) {
    int size = (int) (list.size() * sizeof(double));
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list.data(), sizeof(double), list.size(), fp);
  }
}

void FixContactTriPenalty::restart(char *buf)
{
  restored = 1;
  const double *list = (const double *) buf;
  const bool tagged = std::isnan(list[0]);
  const int version = tagged ? (int) list[1] : 1;
  if (tagged) list += 2;
  for (int k = 0; k < 3; k++) disp[k] = list[k];
  tool_temp = list[3];
  const int me0 = comm->me == 0;
  q_work = me0 ? list[4] : 0.0;
  q_tool = me0 ? list[5] : 0.0;
  q_tool_lost = me0 ? list[6] : 0.0;
  tool_work = me0 ? list[7] : 0.0;
  contact_diss = me0 ? list[8] : 0.0;
  dt_last = list[9];
  if (version >= 3) check_fingerprint(list + 10);
  if (version >= 4) {
    theta = list[10 + NFINGER];
    omega_step_set = !std::isnan(list[11 + NFINGER]);
    omega_step = omega_step_set ? list[11 + NFINGER] : 0.0;
  }
  if (version >= 2) fields_restart(list + 10 + (version >= 3 ? NFINGER : 0) + (version >= 4 ? 2 : 0));
}

// what restart files keep of the tool: its elements and the bounding box of their vertices in the
// tool frame (placed by the keywords, before the run's displacement)
void FixContactTriPenalty::tool_fingerprint(double *fp) const
{
  fp[0] = (double) elem.size();
  sphcut::bounding_box(elem, fp + 1, fp + 4);
}

// a continued run must build the tool that wrote the restart file: the displacement and the
// contact state in it are relative to that tool (in the cutting examples the insert is placed
// from the workpiece's length and the tool's start: another -var length, cut or xstart would put
// it elsewhere)
void FixContactTriPenalty::check_fingerprint(const double *saved) const
{
  double now[NFINGER];
  tool_fingerprint(now);
  const double size = sphcut::box_diagonal(now + 1, now + 4);
  bool same = saved[0] == now[0];
  for (int k = 1; k < NFINGER; k++) same = same && fabs(saved[k] - now[k]) <= 1.0e-9 * size;
  if (!same)
    error->all(FLERR, "Fix contact/tri-penalty {}: the tool differs from the one in the restart file (its "
               "vertices within x {:.6g} .. {:.6g}, y {:.6g} .. {:.6g}, z {:.6g} .. {:.6g}, {} coordinates there; "
               "x {:.6g} .. {:.6g}, y {:.6g} .. {:.6g}, z {:.6g} .. {:.6g}, {} here): the input shapes or places it "
               "differently (in the cutting examples: another -var length, cut or xstart than the run that wrote "
               "the file)", id, saved[1], saved[4], saved[2], saved[5], saved[3], saved[6], (long) saved[0], now[1],
               now[4], now[2], now[5], now[3], now[6], (long) now[0]);
}

double FixContactTriPenalty::memory_usage()
{
  return (double) nmax_out * 6 * sizeof(double) + elem.size() * sizeof(double);
}
