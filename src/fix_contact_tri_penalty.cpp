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
    Fix(lmp, narg, arg), nvert(3), etool(0.0), pfac(1.0), dfac(0.1), sfac(1.2), vreg(0.0), vreg_set(0),
    mustyle(MU_CONST), mu0(0.0), mu_ivar(-1), mu_itvar(-1), eta(1.0), split(1.0), split_auto(0),
    toolbit(0), heat(nullptr), tool_cp(0.0), tool_temp(0.0), write_every(0), fric_power(0.0),
    work_rate(0.0), q_work(0.0), q_tool(0.0), q_tool_lost(0.0), q_work_tool(0.0), maxpen(0.0),
    ncontact(0), tool_work(0.0), diss_rate(0.0), contact_diss(0.0), dt_last(0.0), dt_crit(1.0e300), fcontact(nullptr), nmax_out(0), qbuf(nullptr), nmax_buf(0),
    list(nullptr), fix(nullptr), model(nullptr)
{
  for (int k = 0; k < 3; k++) disp[k] = vtool[k] = vconst[k] = ftool[k] = 0.0;
  for (int f = 0; f < NFEAT; f++)
    for (int c = 0; c < NDECOMP; c++) decomp[f][c] = 0.0;
  std::string geom;
  std::vector<std::string> gargs;
  sphcut::StlTransform tf;
  int has_transform = 0;
  int split_given = 0;

  int iarg = 3;
  auto need = [&](int n, const std::string &kw) {
    if (iarg + n >= narg) error->all(FLERR, "Fix contact/tri-penalty: keyword {} needs {} value(s)", kw, n);
  };
  auto num = [&](int k) { return utils::numeric(FLERR, arg[iarg + k], false, lmp); };
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    if (kw == "stl") {
      need(1, kw);
      geom = "stl";
      gargs = {arg[iarg + 1]};
      iarg += 2;
    } else if (kw == "insert") {
      // insert rake G clearance A radius R rake_length L flank_length F [width W] [segments N] [face_segments M]
      geom = "insert";
      gargs.clear();
      iarg++;
      while (iarg + 1 < narg) {
        const std::string k = arg[iarg];
        if (k != "rake" && k != "clearance" && k != "radius" && k != "rake_length" &&
            k != "flank_length" && k != "width" && k != "segments" && k != "face_segments")
          break;
        if (k == "segments" || k == "face_segments")
          sphcut::parse_int(lmp, "Fix contact/tri-penalty", "insert " + k, arg[iarg + 1]);
        else num(1);    // a LAMMPS error here if the value is not a number
        gargs.push_back(k);
        gargs.push_back(arg[iarg + 1]);
        iarg += 2;
      }
    } else if (kw == "scale") {
      need(1, kw);
      tf.scale = num(1);
      if (tf.scale <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: scale must be > 0, got {}", tf.scale);
      has_transform = 1;
      iarg += 2;
    } else if (kw == "move") {
      need(3, kw);
      for (int k = 0; k < 3; k++) tf.shift[k] = num(k + 1);
      iarg += 4;
    } else if (kw == "rotate") {
      need(4, kw);
      const double axis[3] = {num(2), num(3), num(4)};
      if (axis[0] == 0.0 && axis[1] == 0.0 && axis[2] == 0.0)
        error->all(FLERR, "Fix contact/tri-penalty: rotate axis must not be zero");
      tf.set_axis_angle(axis, num(1));
      has_transform = 1;
      iarg += 5;
    } else if (kw == "velocity") {
      need(3, kw);
      for (int k = 0; k < 3; k++) {
        const std::string v = arg[iarg + 1 + k];
        if (utils::strmatch(v, "^v_")) vvar[k] = v.substr(2);
        else vconst[k] = num(k + 1);
        // utils::numeric takes 1e999 as inf
        if (!std::isfinite(vconst[k]))
          error->all(FLERR, "Fix contact/tri-penalty: velocity {} is not a finite number", v);
      }
      iarg += 4;
    } else if (kw == "E") {
      need(1, kw);
      etool = num(1);
      if (etool <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: E must be > 0, got {}", etool);
      iarg += 2;
    } else if (kw == "pfac" || kw == "dfac" || kw == "sfac" || kw == "vreg" || kw == "eta") {
      need(1, kw);
      const double v = num(1);
      if (kw == "pfac") pfac = v;
      else if (kw == "dfac") dfac = v;
      else if (kw == "sfac") sfac = v;
      else if (kw == "vreg") {
        vreg = v;
        vreg_set = 1;
      } else eta = v;
      if ((kw == "pfac" || kw == "sfac") && v <= 0.0)
        error->all(FLERR, "Fix contact/tri-penalty: {} must be > 0, got {}", kw, v);
      if ((kw == "dfac" || kw == "vreg") && v < 0.0)
        error->all(FLERR, "Fix contact/tri-penalty: {} must be >= 0, got {}", kw, v);
      if (kw == "eta" && (v < 0.0 || v > 1.0))
        error->all(FLERR, "Fix contact/tri-penalty: eta must be in [0,1], got {}", v);
      iarg += 2;
    } else if (kw == "dtfac") {
      need(1, kw);
      dtfac = num(1);
      if (!(dtfac > 0.0 && dtfac <= 1.0)) error->all(FLERR, "Fix contact/tri-penalty: dtfac must be in (0,1], got {}", arg[iarg + 1]);
      iarg += 2;
    } else if (kw == "onset") {
      need(1, kw);
      onset = num(1);
      if (!(onset >= 0.0 && onset < 1.0))
        error->all(FLERR, "Fix contact/tri-penalty: onset must be in [0,1), got {}", arg[iarg + 1]);
      iarg += 2;
    } else if (kw == "stick") {
      need(1, kw);
      const std::string v = arg[iarg + 1];
      if (v == "yes") stick = 1;
      else if (v == "no") stick = 0;
      else error->all(FLERR, "Fix contact/tri-penalty: stick must be yes or no, got {}", v);
      stick_given = 1;
      iarg += 2;
    } else if (kw == "friction") {
      need(1, kw);
      const std::string v = arg[iarg + 1];
      if (v == "static") stick = 1;
      else if (v == "coulomb") stick = 0;
      else if (v == "memory") fmemory = 1;
      else error->all(FLERR, "Fix contact/tri-penalty: friction must be static, coulomb or memory, got {}", v);
      if (v != "memory") fmemory = 0;
      friction_given = 1;
      iarg += 2;
    } else if (kw == "tfac") {
      need(1, kw);
      tfac = num(1);
      if (tfac <= 0.0 || tfac > 1.0) error->all(FLERR, "Fix contact/tri-penalty: tfac must be in (0,1], got {}", tfac);
      tfac_given = 1;
      iarg += 2;
    } else if (kw == "mu") {
      need(1, kw);
      const std::string v = arg[iarg + 1];
      if (v == "table") {
        need(2, kw);
        mustyle = MU_TABLE;
        std::ifstream in(arg[iarg + 2]);
        if (!in) error->all(FLERR, "Fix contact/tri-penalty: cannot open mu table {}", arg[iarg + 2]);
        std::string line;
        while (std::getline(in, line)) {
          const auto p = line.find('#');
          if (p != std::string::npos) line.erase(p);
          std::istringstream ss(line);
          double t, m;
          if (!(ss >> t)) continue;
          if (!(ss >> m)) error->all(FLERR, "Fix contact/tri-penalty: mu table {}: line '{}' needs T mu", arg[iarg + 2], line);
          if (!mu_t.empty() && t <= mu_t.back())
            error->all(FLERR, "Fix contact/tri-penalty: mu table {}: temperatures must increase", arg[iarg + 2]);
          if (m < 0.0) error->all(FLERR, "Fix contact/tri-penalty: mu table {}: negative mu {}", arg[iarg + 2], m);
          mu_t.push_back(t);
          mu_v.push_back(m);
        }
        if (mu_t.empty()) error->all(FLERR, "Fix contact/tri-penalty: mu table {} is empty", arg[iarg + 2]);
        iarg += 3;
      } else if (utils::strmatch(v, "^v_")) {
        // mu v_name tvar NAME: equal-style variable of the internal variable NAME (the temperature)
        if (iarg + 3 >= narg || std::string(arg[iarg + 2]) != "tvar")
          error->all(FLERR, "Fix contact/tri-penalty: mu v_{} needs 'tvar NAME' (an internal variable)", v.substr(2));
        mustyle = MU_VARIABLE;
        mu_var = v.substr(2);
        mu_tvar = arg[iarg + 3];
        iarg += 4;
      } else {
        mustyle = MU_CONST;
        mu0 = num(1);
        if (mu0 < 0.0) error->all(FLERR, "Fix contact/tri-penalty: mu must be >= 0, got {}", mu0);
        iarg += 2;
      }
    } else if (kw == "heat") {
      need(1, kw);
      id_heat = arg[iarg + 1];
      iarg += 2;
    } else if (kw == "split") {
      need(1, kw);
      split_given = 1;
      if (std::string(arg[iarg + 1]) == "auto") split_auto = 1;
      else {
        split = num(1);
        if (split < 0.0 || split > 1.0) error->all(FLERR, "Fix contact/tri-penalty: split must be in [0,1] or auto, got {}", split);
      }
      iarg += 2;
    } else if (kw == "tool_particles") {
      need(1, kw);
      const int ig = group->find(arg[iarg + 1]);
      if (ig < 0) error->all(FLERR, "Fix contact/tri-penalty: tool_particles group {} does not exist", arg[iarg + 1]);
      tool_group = arg[iarg + 1];
      toolbit = group->bitmask[ig];
      iarg += 2;
    } else if (kw == "tool_cp") {
      need(2, kw);
      tool_cp = num(1);
      tool_temp = num(2);
      if (tool_cp <= 0.0) error->all(FLERR, "Fix contact/tri-penalty: tool_cp must be > 0, got {}", tool_cp);
      iarg += 3;
    } else if (kw == "write") {
      need(2, kw);
      write_every = sphcut::parse_int(lmp, "Fix contact/tri-penalty", "write interval", arg[iarg + 1]);
      write_file = arg[iarg + 2];
      if (!utils::strmatch(write_file, "\\.vtk$") && !utils::strmatch(write_file, "\\.stl$"))
        error->all(FLERR, "Fix contact/tri-penalty: write file {} must end in .vtk or .stl", write_file);
      iarg += 3;
    } else if (const int nused = fields_parse(kw, iarg, narg, arg)) {
      iarg += nused;
    } else {
      error->all(FLERR, "Fix contact/tri-penalty: unknown keyword {}", kw);
    }
  }
  if (geom.empty()) error->all(FLERR, "Fix contact/tri-penalty: no tool geometry (keyword stl or insert)");
  if (fmemory && stick_given)
    error->all(FLERR, "Fix contact/tri-penalty: stick applies to friction static/coulomb, not to friction memory");
  if (stick_given && friction_given)
    error->all(FLERR, "Fix contact/tri-penalty: give friction or stick, not both (stick yes = friction static, "
               "stick no = friction coulomb)");
  if (fmemory && vreg_set)
    error->all(FLERR, "Fix contact/tri-penalty: vreg applies to friction static/coulomb, not to friction memory");
  if (!fmemory && tfac_given)
    error->all(FLERR, "Fix contact/tri-penalty: tfac applies to friction memory only");
  if (geom == "insert" && has_transform)
    error->all(FLERR, "Fix contact/tri-penalty: scale and rotate apply to stl tools only (use move)");
  if (!split_given && toolbit) split_auto = 1;
  if (split_auto && !toolbit)
    error->all(FLERR, "Fix contact/tri-penalty: split auto needs tool_particles (their conductivity)");

  nvert = domain->dimension == 2 ? 2 : 3;
  if (write_every && nvert == 2 && utils::strmatch(write_file, "\\.stl$"))
    error->all(FLERR, "Fix contact/tri-penalty: write file {}: a 2D tool (segments) can only be written as .vtk",
               write_file);
  // rank 0 reads or builds the geometry, all ranks get a copy
  std::string msg;
  if (comm->me == 0) {
    try {
      if (geom == "stl") {
        std::vector<double> tri = sphcut::read_stl(gargs[0], tf);
        sphcut::require_closed_mesh(gargs[0], tri);    // a tool is a solid: no open sheets
        stl_scale = tf.scale;
        // 2D: the section of the solid with the plane z = 0, as segments (outward normal kept)
        elem = nvert == 3 ? tri : sphcut::stl_section_z0(gargs[0], tri);
      } else {
        sphcut::InsertParams ip;
        for (size_t k = 0; k + 1 < gargs.size(); k += 2) {
          const double v = std::stod(gargs[k + 1]);
          if (gargs[k] == "rake") ip.rake_angle = v;
          else if (gargs[k] == "clearance") ip.clearance_angle = v;
          else if (gargs[k] == "radius") ip.edge_radius = v;
          else if (gargs[k] == "rake_length") ip.rake_length = v;
          else if (gargs[k] == "flank_length") ip.flank_length = v;
          else if (gargs[k] == "width") ip.width = v;
          else if (gargs[k] == "segments") ip.arc_segments = (int) v;
          else if (gargs[k] == "face_segments") ip.face_segments = (int) v;
        }
        std::vector<int> tags;
        elem = sphcut::make_cutting_insert(ip, domain->dimension, &tags);
        for (int t : tags)
          elem_feature.push_back(t == sphcut::INSERT_RAKE ? FEAT_RAKE
                                 : t == sphcut::INSERT_EDGE ? FEAT_EDGE
                                 : t == sphcut::INSERT_FLANK ? FEAT_FLANK : FEAT_OTHER);
        for (size_t k = 0; k < elem.size(); k += 3)
          for (int c = 0; c < 3; c++) elem[k + c] += (c < 2 || nvert == 3) ? tf.shift[c] : 0.0;
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

  vector_flag = 1;
  size_vector = 15 + NFEAT * NDECOMP;
  global_freq = 1;
  extvector = 0;
  peratom_flag = 1;
  size_peratom_cols = 6;
  peratom_freq = 1;
  restart_global = 1;
  comm_reverse = 1;
  nevery = 1;
  dynamic_group_allow = 0;

  // the per-atom data that must follow the atoms (last contact force, the velocity it used)
  // lives in fix sph/jc-thermal's state (columns FCONT, VCONT); fcontact is the output copy
  grow_output();
  fields_setup();
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
  for (int k = 0; k < modify->nfix; k++)
    if (modify->fix[k] != this && utils::strmatch(modify->fix[k]->style, "^contact/tri-penalty"))
      error->all(FLERR, "Fix contact/tri-penalty: only one contact/tri-penalty fix is supported, found {} and {} "
                 "(the per-atom contact state and the contact's time step limit exist once; put several tools "
                 "in one STL file)", id, modify->fix[k]->id);
  fix = FixSPHJCThermal::require(lmp, "Fix contact/tri-penalty", groupbit, group->names[igroup], &model);
  fix->attach(this);
  heat = nullptr;
  if (!id_heat.empty()) {
    const int ih = modify->find_fix(id_heat);
    if (ih < 0) error->all(FLERR, "Fix contact/tri-penalty: heat fix {} does not exist", id_heat);
    if (!utils::strmatch(modify->fix[ih]->style, "^heat/fmfs"))
      error->all(FLERR, "Fix contact/tri-penalty: fix {} is not of style heat/fmfs", id_heat);
    heat = dynamic_cast<FixHeatFMFS *>(modify->fix[ih]);
  }
  for (int k = 0; k < 3; k++)
    if (!vvar[k].empty()) {
      const int iv = input->variable->find(vvar[k].c_str());
      if (iv < 0) error->all(FLERR, "Fix contact/tri-penalty: velocity variable {} does not exist", vvar[k]);
      if (!input->variable->equalstyle(iv))
        error->all(FLERR, "Fix contact/tri-penalty: velocity variable {} is not equal-style", vvar[k]);
    }
  if (mustyle == MU_VARIABLE) {
    mu_ivar = input->variable->find(mu_var.c_str());
    mu_itvar = input->variable->find(mu_tvar.c_str());
    if (mu_ivar < 0 || !input->variable->equalstyle(mu_ivar))
      error->all(FLERR, "Fix contact/tri-penalty: mu variable {} does not exist or is not equal-style", mu_var);
    if (mu_itvar < 0 || !input->variable->internalstyle(mu_itvar))
      error->all(FLERR, "Fix contact/tri-penalty: tvar {} must be an internal-style variable", mu_tvar);
  }
  if (split_auto) {
    // split by thermal effusivity sqrt(k rho cp) of workpiece and tool (seed 000 sec. 4)
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
    split = ew / (ew + et);
  }
  // the bins: elements within the largest query radius, in the tool frame
  const double hmax = contact_radius_max();
  sphcut::tri_bin_build(elem, nvert, 2.0 * hmax, bins);
  // a tool far below the search radius is a point to the search: the distances of a particle
  // to its elements tie, and the side is lost (e.g. scale 1e-30, issue 23)
  const double extent = sphcut::bounding_diagonal(elem);
  if (!(extent > 1.0e-6 * 2.0 * hmax))
    error->all(FLERR, "Fix contact/tri-penalty: the tool is degenerate at scale {}: it spans {}, below 1e-6 of the "
               "contact search radius 2h = {}", stl_scale, extent, 2.0 * hmax);
  if (toolbit) sphcut::request_full_list(neighbor, this, instance_me, true, false);
  update_tool_velocity();
  // the spring's time step limit before the first force evaluation (fix sph/jc-thermal sets
  // the first dt of a run in its setup, before this fix's): the particles in or about to be in
  // contact, by the test post_force applies (sphcut::near_contact), so that a run continued
  // from a restart file takes the step the unsplit run took (a wider band here, all particles
  // within 2h of the tool, gave the first step of a run continued while the tool approached
  // the workpiece the spring's limit: the time and the first contact shifted)
  dt_crit = 1.0e300;
  {
    const sphcut::TriBinView view = bins.view();
    for (int i = 0; i < atom->nlocal; i++) {
      if (!(atom->mask[i] & groupbit) || (atom->mask[i] & toolbit) || fix->role_of(atom->mask[i]) == FixSPHJCThermal::TOOL) continue;
      const int it = atom->type[i];
      const double h = model->smoothing_length(it);
      const double *xi = atom->x[i];
      const double xt[3] = {xi[0] - disp[0], xi[1] - disp[1], nvert == 2 ? 0.0 : xi[2] - disp[2]};
      double d, n[3], q[3];
      int region;
      if (sphcut::tool_surface(view, xt, h, d, n, q, region) < 0) continue;    // no facet within 2h
      if (sphcut::near_contact(d, h, sfac, atom->v[i], vtool, domain->dimension, update->dt))
        dt_crit = std::min(dt_crit, spring_dt_crit(i));
    }
  }
  if (!vreg_set) {
    const double s = sqrt(vtool[0] * vtool[0] + vtool[1] * vtool[1] + vtool[2] * vtool[2]);
    vreg = 0.01 * s;    // 1 % of the tool speed (fixed tool: 0, Coulomb above the floor of post_force)
  }
}

// stability limit of the penalty spring of local particle i (sphcut_contact.h penalty_dt_limit)
double FixContactTriPenalty::spring_dt_crit(int i) const
{
  const int it = atom->type[i];
  const double h = model->smoothing_length(it);
  const double m = atom->rmass ? atom->rmass[i] : atom->mass[it];
  const double dp = model->spacing(it) > 0.0 ? model->spacing(it) : h / sfac;
  const double k = sphcut::penalty_stiffness(model->materials()[it].E, etool, dp, pfac, domain->dimension);
  return sphcut::penalty_dt_limit(k, m, dfac, 1.0);
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
------------------------------------------------------------------------- */

void FixContactTriPenalty::warn_inside()
{
  using F = FixSPHJCThermal;
  double **x = atom->x;
  const int *mask = atom->mask;
  std::vector<int> scratch;
  double n[2] = {0.0, 0.0}, dmin = 0.0;    // inside or on the surface, on the surface
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit) || (mask[i] & toolbit) || fix->role_of(mask[i]) == F::TOOL) continue;
    const double xt[3] = {x[i][0] - disp[0], x[i][1] - disp[1], domain->dimension == 2 ? 0.0 : x[i][2] - disp[2]};
    const double h = model->smoothing_length(atom->type[i]);
    const double d = sphcut::tool_signed_distance(bins, xt, 2.0 * h, scratch);
    if (d <= 1.0e-9 * h) {
      n[0] += 1.0;
      if (d >= -1.0e-9 * h) n[1] += 1.0;
      dmin = std::min(dmin, d);
    }
  }
  double gn[2] = {0.0, 0.0}, gdmin = 0.0;
  MPI_Allreduce(n, gn, 2, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&dmin, &gdmin, 1, MPI_DOUBLE, MPI_MIN, world);
  if (gn[0] > 0.0 && comm->me == 0)
    error->warning(FLERR, "Fix contact/tri-penalty: {:.0f} particle(s) start inside the tool or on its surface "
                   "({:.0f} on it{}); the contact throws them out at high speed", gn[0], gn[1],
                   gn[0] > gn[1] ? fmt::format(", the deepest {:.4g} below it", -gdmin) : std::string());
}

void FixContactTriPenalty::initial_integrate(int)
{
  for (int k = 0; k < 3; k++) disp[k] += update->dt * vtool[k];
}

/* ---------------------------------------------------------------------- */

double FixContactTriPenalty::friction_coefficient(double temp)
{
  if (mustyle == MU_CONST) return mu0;
  if (mustyle == MU_TABLE) return sphcut::mu_table(mu_t.data(), mu_v.data(), (int) mu_t.size(), temp);
  input->variable->internal_set(mu_itvar, temp);
  const double m = input->variable->compute_equal(mu_ivar);
  if (m != m) error->one(FLERR, "Fix contact/tri-penalty: mu variable {} is not a number (NaN) at {} = {}", mu_var, mu_tvar, temp);
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
  in.v_reg = vreg;
  // friction opposes the sliding the particle would have after the step (its pair forces
  // included) and never exceeds the force that stops it: static friction up to mu F_N
  in.dt_stick = stick ? dt_force : 0.0;
  if (fmemory) {
    in.friction_memory = 1;
    in.tfac = tfac;
    in.dt = dt_force;
    in.dt_stick = 0.0;
  }
  return in;
}

void FixContactTriPenalty::post_force(int)
{
  sphcut::ScopedTimer timer(cpu_time);
  using F = FixSPHJCThermal;
  double **x = atom->x;
  double **f = atom->f;
  const int *mask = atom->mask;
  const int *type = atom->type;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  double **st = fix->state;
  const Material *mat = model->materials();
  const sphcut::TriBinView view = bins.view();
  const int dim = domain->dimension;
  const double dt = update->dt;
  // the time step the friction floor is based on: this step's, or at the setup of a continued
  // run the one of the last step (the adaptive dt has moved on since), so that forces repeat
  if (!update->setupflag || dt_last <= 0.0) dt_last = dt;
  const double dt_force = dt_last;

  if (toolbit) {
    if (nall > nmax_buf) {
      nmax_buf = atom->nmax;
      memory->destroy(qbuf);
      memory->create(qbuf, nmax_buf, "contact:qbuf");
    }
    for (int i = 0; i < nall; i++) qbuf[i] = 0.0;
  }
  grow_output();
  for (int k = 0; k < 3; k++) ftool[k] = 0.0;
  fric_power = work_rate = diss_rate = maxpen = 0.0;
  ncontact = 0;
  dt_crit = 1.0e300;
  for (int ft = 0; ft < NFEAT; ft++)
    for (int c = 0; c < NDECOMP; c++) decomp[ft][c] = 0.0;
  double q_lumped = 0.0;    // heat into the lumped tool (tool_cp) on this rank, this step
  fields_step();

  // energy over the step with the weights of velocity Verlet: the particle gains
  // dt/2 (F^n + F^(n+1)).v^(n+1/2), v^(n+1/2) the velocity that drifts it this step.
  // First the F^n half, with the contact forces of the previous step.
  double w_old = 0.0, d_old = 0.0;
  for (int i = 0; i < nlocal; i++)
    for (int k = 0; k < dim; k++) {
      w_old += st[i][F::FCONT + k] * vtool[k];
      d_old += st[i][F::FCONT + k] * (vtool[k] - atom->v[i][k]);
    }

  const sphcut::ContactIn params = contact_params(dt_force);
  for (int i = 0; i < nlocal; i++) {
    double *fc = &st[i][F::FCONT], *vc = &st[i][F::VCONT], *fm = &st[i][F::FMEM];
    fc[0] = fc[1] = fc[2] = 0.0;
    for (int k = 0; k < 6; k++) fcontact[i][k] = 0.0;
    if (!update->setupflag) {
      for (int k = 0; k < 3; k++) vc[k] = atom->v[i][k];
      vc[3] = 1.0;
    }
    // friction memory: a step takes the last step's friction force as f_old, remembers it
    // as its input and zeroes the state (set again below if the particle is in contact)
    if (fmemory && !update->setupflag) sphcut::memory_friction_step(fm);
    if (!(mask[i] & groupbit) || (mask[i] & toolbit) || fix->role_of(mask[i]) == F::TOOL) continue;
    const int it = type[i];
    const double h = model->smoothing_length(it);
    const double xt[3] = {x[i][0] - disp[0], x[i][1] - disp[1], dim == 2 ? 0.0 : x[i][2] - disp[2]};
    sphcut::ContactIn in = params;
    double qs[3];
    int region;
    const int best = sphcut::tool_surface(view, xt, h, in.d, in.n, qs, region);
    if (best < 0) continue;
    const double mi = rmass ? rmass[i] : mass[it];
    const double dpi = model->spacing(it) > 0.0 ? model->spacing(it) : h / sfac;
    if (sphcut::near_contact(in.d, h, sfac, atom->v[i], vtool, dim, dt)) dt_crit = std::min(dt_crit, spring_dt_crit(i));
    if (0.5 * h / sfac - in.d <= 0.0) continue;
    // the velocity that moves the particle this step, v^(n+1/2); at the setup of a continued
    // run (restart, or a second run with unchanged velocities) the one of the last step
    const double *vuse = atom->v[i];
    const bool repeat = update->setupflag && vc[3] > 0.0 && atom->v[i][0] == st[i][F::VEND] &&
        atom->v[i][1] == st[i][F::VEND + 1] && atom->v[i][2] == st[i][F::VEND + 2];
    if (repeat) vuse = vc;
    // f_old of the memory law: at a step its input set above; a setup evaluation that repeats
    // the last step (a continued run) uses that step's input if the particle had friction then,
    // else the current state (zero after a contact ended)
    if (fmemory) sphcut::memory_friction_input(fm, !update->setupflag, repeat, in.ft_old);
    for (int k = 0; k < 3; k++) {
      in.x[k] = x[i][k];
      in.v[k] = vuse[k];
      in.q[k] = qs[k] + disp[k];
      in.f_other[k] = k < dim ? f[i][k] : 0.0;
    }
    in.mass = mi;
    in.h = h;
    in.E_particle = mat[it].E;
    in.dp = dpi;
    in.mu = friction_coefficient(st[i][F::TEMP_F]);
    sphcut::ContactOut out;
    sphcut::penalty_contact(in, out);
    if (!out.active) continue;
    ncontact++;
    if (fmemory && !update->setupflag)
      for (int k = 0; k < 3; k++) fm[k] = out.ft[k];
    // decomposition by the tool feature of the closest element (forces on the tool)
    {
      const int feat = elem_feature[best];
      const double ftm = sphcut::decompose_contact(out, in.n, decomp[feat]);
      fcontact[i][3] = out.fn;
      fcontact[i][4] = ftm;
      fcontact[i][5] = feat + 1;
    }
    fields_contact(best, region, out, st[i][F::TEMP_F]);
    maxpen = std::max(maxpen, out.delta / (0.5 * h / sfac));
    // no XSPH drift along the contact normal (sphcut::contact_drift)
    sphcut::contact_drift(&st[i][F::XSPH], in.n);
    for (int k = 0; k < dim; k++) {
      f[i][k] += out.f[k];
      fc[k] = out.f[k];
      fcontact[i][k] = out.f[k];
      ftool[k] -= out.f[k];
      work_rate += out.f[k] * vtool[k];
      // friction + dashpot (+ spring) power
      diss_rate += out.f[k] * (vtool[k] - atom->v[i][k]);
    }
    fric_power += out.fric_power;

    // friction heat (eq. 6 of seed 003): particle share and tool share
    // (without a heat fix the workpiece share is not assigned: element 14)
    const double q = eta * out.fric_power;
    if (q <= 0.0) continue;
    const double acc = update->setupflag ? 0.0 : dt;    // setup: rates only, no time passes
    const double qw = split * q;
    if (qw > 0.0) {
      if (heat) {
        heat->add_heat(i, qw);
        q_work += qw * acc;
      } else {
        q_tool_lost += qw * acc;
      }
    }
    const double qt = q - qw;
    if (qt <= 0.0) continue;
    if (toolbit && list && heat) {
      // tool SPH particles near the contact (seed 000: NeibContTherm), kernel weighted
      double wsum = 0.0;
      const int *jl = list->firstneigh[i];    // the list holds every local atom, indexed by i
      const int jn = list->numneigh[i];
      heat_w.clear();
      heat_j.clear();
      for (int jj = 0; jj < jn; jj++) {
        const int j = jl[jj] & NEIGHMASK;
        if (!(mask[j] & toolbit)) continue;
        double r2 = 0.0;
        for (int k = 0; k < 3; k++) r2 += (x[i][k] - x[j][k]) * (x[i][k] - x[j][k]);
        const double hij = model->smoothing_length(it, type[j]);
        if (r2 >= 4.0 * hij * hij) continue;
        const double w = sphcut::kernel_w(model->kernel(), dim, sqrt(r2), hij);
        heat_w.push_back(w);
        heat_j.push_back(j);
        wsum += w;
      }
      if (wsum > 0.0) {
        for (size_t k = 0; k < heat_j.size(); k++) qbuf[heat_j[k]] += qt * heat_w[k] / wsum;
        q_tool += qt * acc;
        continue;
      }
    }
    if (tool_cp > 0.0) {
      q_lumped += qt * acc;    // summed over the ranks below
      q_tool += qt * acc;
    } else {
      q_tool_lost += qt * acc;
    }
  }

  if (tool_cp > 0.0) {
    // the lumped tool is one body: every rank adds the heat of all ranks
    double qsum = 0.0;
    MPI_Allreduce(&q_lumped, &qsum, 1, MPI_DOUBLE, MPI_SUM, world);
    tool_temp += qsum / tool_cp;
  }
  if (toolbit && heat) {
    sphcut::reverse_comm(comm, this);
    for (int i = 0; i < nlocal; i++)
      if ((mask[i] & toolbit) && qbuf[i] > 0.0) heat->add_heat(i, qbuf[i]);
  }
  if (!update->setupflag) {
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
  for (size_t k = 0; k < out.size(); k += 3)
    for (int c = 0; c < 3; c++) out[k + c] += (nvert == 3 || c < 2) ? disp[c] : 0.0;
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
   sum F_N; sum |F_T|; contacts at the Coulomb limit |F_T| = mu F_N
------------------------------------------------------------------------- */

double FixContactTriPenalty::compute_vector(int n)
{
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
  // version 2: a NaN tag, the version, the 10 values of version 1 (no tag), the tool fields
  std::vector<double> list = {std::nan(""), 2.0, disp[0], disp[1], disp[2], tool_temp, tot[0], tot[1], tot[2],
                              tot[3], tot[4], dt_last};
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
  const bool v2 = std::isnan(list[0]);
  if (v2) list += 2;
  for (int k = 0; k < 3; k++) disp[k] = list[k];
  tool_temp = list[3];
  const int me0 = comm->me == 0;
  q_work = me0 ? list[4] : 0.0;
  q_tool = me0 ? list[5] : 0.0;
  q_tool_lost = me0 ? list[6] : 0.0;
  tool_work = me0 ? list[7] : 0.0;
  contact_diss = me0 ? list[8] : 0.0;
  dt_last = list[9];
  if (v2) fields_restart(list + 10);
}

double FixContactTriPenalty::memory_usage()
{
  return (double) nmax_out * 6 * sizeof(double) + elem.size() * sizeof(double);
}
