/* ----------------------------------------------------------------------
   sphcut - fix sph/jc-thermal

   Time integration of the updated-Lagrangian SPH solid (seed 003 eqs. 1-3,
   10-11; seed 000 eqs. 1-4):
     positions/velocities: velocity Verlet (kick-drift-kick), the drift
       with the XSPH-corrected velocity (Monaghan 1989);
     density, deviatoric stress, temperature, internal energy: Heun
       predictor-corrector, y* = y^n + dt f^n (predictor, used to compute
       the forces of the step), y^{n+1} = y^n + dt/2 (f^n + f^{n+1});
     Johnson-Cook plasticity: radial return after predictor and corrector;
       plastic work heats the particle (chi, seed 003 eq. 5).
   Both schemes are second order in dt.
------------------------------------------------------------------------- */

#include "fix_sph_jc_thermal.h"

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "pair.h"
#include "update.h"
#include "variable.h"

#include "sphcut_checks.h"
#include "sphcut_compat.h"
#include "sphcut_heat_rules.h"
#include "sphcut_solid.h"
#include "sphcut_timer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using namespace FixConst;
using sphcut::Material;

/* ---------------------------------------------------------------------- */

FixSPHJCThermal::FixSPHJCThermal(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), model(nullptr)
{
  if (narg < 3) error->all(FLERR, "Illegal fix sph/jc-thermal command: missing arguments");

  state = nullptr;
  solidbit = groupbit;
  toolbit = clampbit = 0;
  temp0 = -1.0;
  cfl = 0.0;
  vmax = -1.0;
  tmax = -1.0;
  dtmax = 0.0;
  dtmin = 0.0;
  thermal_cfl = 0.1;
  plastic_work = 0.0;
  force_state_valid = 0;

  int iarg = 3;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Fix sph/jc-thermal: keyword {} needs a value", kw);
    const char *val = arg[iarg + 1];
    if (kw == "tool" || kw == "clamp") {
      const int ig = group->find(val);
      if (ig < 0) error->all(FLERR, "Fix sph/jc-thermal: {} group {} does not exist", kw, val);
      if (kw == "tool") toolbit = group->bitmask[ig];
      else clampbit = group->bitmask[ig];
    } else if (kw == "temp") {
      if (utils::strmatch(val, "^v_")) {
        temp_var = val + 2;
      } else {
        temp0 = utils::numeric(FLERR, val, false, lmp);
        if (temp0 < 0.0) error->all(FLERR, "Fix sph/jc-thermal: temp must be >= 0, got {}", temp0);
      }
    } else if (kw == "cfl") {
      cfl = utils::numeric(FLERR, val, false, lmp);
      if (cfl <= 0.0 || cfl > 1.0) error->all(FLERR, "Fix sph/jc-thermal: cfl must be in (0,1], got {}", cfl);
    } else if (kw == "vmax" || kw == "tmax") {
      // a runaway limit: a positive number, none (0) or the material's own (-1: sound / melt)
      const char *own = kw == "vmax" ? "sound" : "melt";
      double lim;
      if (strcmp(val, "none") == 0) lim = 0.0;
      else if (strcmp(val, own) == 0) lim = -1.0;
      else {
        lim = utils::is_double(val) ? utils::numeric(FLERR, val, false, lmp) : -1.0;
        if (lim <= 0.0) error->all(FLERR, "Fix sph/jc-thermal: {} must be > 0, {} or none, got {}", kw, own, val);
      }
      (kw == "vmax" ? vmax : tmax) = lim;
    } else if (kw == "dtmax") {
      dtmax = utils::numeric(FLERR, val, false, lmp);
      if (dtmax <= 0.0) error->all(FLERR, "Fix sph/jc-thermal: dtmax must be > 0, got {}", dtmax);
    } else if (kw == "dtmin") {
      dtmin = utils::numeric(FLERR, val, false, lmp);
      if (dtmin <= 0.0) error->all(FLERR, "Fix sph/jc-thermal: dtmin must be > 0, got {}", dtmin);
    } else if (kw == "thermal_cfl") {
      thermal_cfl = utils::numeric(FLERR, val, false, lmp);
      // the Heun predictor-corrector of the temperature is stable to about 0.15-0.17 (measured)
      if (thermal_cfl <= 0.0 || thermal_cfl > 0.15)
        error->all(FLERR, "Fix sph/jc-thermal: thermal_cfl must be in (0,0.15], got {}", thermal_cfl);
    } else if (kw == "fence") {
      if (strcmp(val, "yes") == 0) fence = 1;
      else if (strcmp(val, "no") == 0) fence = 0;
      else error->all(FLERR, "Fix sph/jc-thermal: fence must be yes or no, got {}", val);
    } else if (kw == "migrate") {
      if (strcmp(val, "device") == 0) migrate_device = 1;
      else if (strcmp(val, "host") == 0) migrate_device = 0;
      else error->all(FLERR, "Fix sph/jc-thermal: migrate must be device or host, got {}", val);
    } else if (kw == "peratom_every") {
      peratom_every = sphcut::parse_int(lmp, "Fix sph/jc-thermal", kw, val);
    } else if (kw == "dtevery") {
      dtevery = sphcut::parse_int(lmp, "Fix sph/jc-thermal", kw, val);
    } else {
      error->all(FLERR, "Fix sph/jc-thermal: unknown keyword {}", kw);
    }
    iarg += 2;
  }
  if (!temp_var.empty() && temp0 >= 0.0)
    error->all(FLERR, "Fix sph/jc-thermal: temp given twice (a value and a variable)");
  if (toolbit && (toolbit == clampbit))
    error->all(FLERR, "Fix sph/jc-thermal: tool and clamp must be different groups");
  if (cfl == 0.0 && (dtmax > 0.0 || dtmin > 0.0))
    error->all(FLERR, "Fix sph/jc-thermal: dtmax and dtmin need the adaptive time step (keyword cfl)");
  if (cfl == 0.0 && dtevery > 1)
    error->all(FLERR, "Fix sph/jc-thermal: dtevery {} needs the adaptive time step (keyword cfl)", dtevery);
  if (dtmin > 0.0 && dtmax > 0.0 && dtmin > dtmax)
    error->all(FLERR, "Fix sph/jc-thermal: dtmin {} is larger than dtmax {}", dtmin, dtmax);

  time_integrate = 1;
  create_attribute = 1;
  vector_flag = 1;
  size_vector = 6;
  global_freq = 1;
  extvector = -1;
  extlist = new int[6]{0, 1, 1, 1, 0, 0};    // energies are extensive
  peratom_flag = 1;
  // all columns: LAMMPS variables index per-atom arrays with this stride (columns past NOUT are internal)
  size_peratom_cols = NCOL;
  // the per-atom array is valid every step on the CPU; peratom_every declares a coarser interval
  // (the /kk fix copies the state to the host only then, and LAMMPS refuses consumers at other steps)
  peratom_freq = peratom_every > 0 ? peratom_every : 1;
  restart_global = 1;
  restart_peratom = 1;
  comm_forward = NFORWARD;
  if (cfl > 0.0) nevery = 1;

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nlocal; i++) initialize_atom(i);

  dtv = update->dt;
  dtf = 0.5 * update->dt * force->ftm2v;
}

/* ---------------------------------------------------------------------- */

FixSPHJCThermal::~FixSPHJCThermal()
{
  if (grow_callback) atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(state);
  delete[] extlist;
}

/* ---------------------------------------------------------------------- */

int FixSPHJCThermal::setmask()
{
  int mask = 0;
  mask |= INITIAL_INTEGRATE;
  mask |= PRE_FORCE;
  mask |= FINAL_INTEGRATE;
  if (cfl > 0.0) mask |= END_OF_STEP;
  return mask;
}

/* ----------------------------------------------------------------------
   new atom: zero state; density and temperature are taken from the
   material (sentinel -1) at the next setup
------------------------------------------------------------------------- */

void FixSPHJCThermal::initialize_atom(int i)
{
  sphcut::initial_row(state[i], temp0);
}

/* ---------------------------------------------------------------------- */

void FixSPHJCThermal::init()
{
  model = &sphcut::require_model(lmp, "Fix sph/jc-thermal");
  if (!atom->rmass_flag && !atom->mass_setflag)
    error->all(FLERR, "Fix sph/jc-thermal: per-type masses are not set (use the mass command)");
  int count = 0;
  for (auto *f : sphcut::fix_list(modify))
    if (f->time_integrate && f != this) {
      if (group->bitmask[f->igroup] & groupbit) count++;
    }
  if (count && comm->me == 0)
    error->warning(FLERR, "Fix sph/jc-thermal: another time integration fix acts on its group");
  const int ninst = (int) sphcut::fixes_by_style(modify, "^sph/jc-thermal").size();
  if (ninst > 1) error->all(FLERR, "Fix sph/jc-thermal: only one instance is allowed, found {}", ninst);
  reset_dt();
}

/* ----------------------------------------------------------------------
   the elapsed time of a run split in two equals that of one run, to the bit.  LAMMPS computes it
   as update->atime + (ntimestep - atimestep) dt and folds the steps since atimestep into atime
   when dt changes (apply_dt) and at the end of every run (Verlet::cleanup): a run split by a
   restart file or into two run commands then adds the steps of one dt in two groups, which
   rounds differently.  The fix keeps the time as of the last change of dt (the anchor), writes
   it to the restart file and gives it back to LAMMPS at the setup of each run (between runs
   LAMMPS' own folded time stands: Integrate::init expects it); a time that LAMMPS holds
   otherwise (a timestep or reset_timestep command between runs, another fix changing dt) is
   taken as the anchor instead.
------------------------------------------------------------------------- */

void FixSPHJCThermal::sync_time()
{
  const double now = update->atime + (update->ntimestep - update->atimestep) * update->dt;
  if (anchored && update->dt == dt_anchor && update->ntimestep >= step_anchor) {
    const double own = time_anchor + (update->ntimestep - step_anchor) * dt_anchor;
    if (fabs(own - now) <= 1.0e-10 * std::max(fabs(now), update->dt)) {
      update->atime = time_anchor;
      update->atimestep = step_anchor;
      return;
    }
  }
  time_anchor = update->atime;
  step_anchor = update->atimestep;
  dt_anchor = update->dt;
  anchored = true;
}

/* ---------------------------------------------------------------------- */

FixSPHJCThermal *FixSPHJCThermal::require(LAMMPS *lmp, const std::string &who, int groupbit,
                                          const char *gname, const sphcut::Model **model)
{
  *model = &sphcut::require_model(lmp, who);
  FixSPHJCThermal *fix = nullptr;
  for (auto *f : sphcut::fixes_by_style(lmp->modify, "^sph/jc-thermal")) fix = dynamic_cast<FixSPHJCThermal *>(f);
  if (!fix) lmp->error->all(FLERR, "{} requires fix sph/jc-thermal", who);
  // every particle of the caller's group needs the SPH state
  int bad = 0, gbad = 0;
  for (int i = 0; i < lmp->atom->nlocal; i++)
    if ((lmp->atom->mask[i] & groupbit) && !(lmp->atom->mask[i] & fix->groupbit)) bad = 1;
  MPI_Allreduce(&bad, &gbad, 1, MPI_INT, MPI_MAX, lmp->world);
  if (gbad) lmp->error->all(FLERR, "{}: group {} has atoms outside the group of fix sph/jc-thermal", who, gname);
  return fix;
}

/* ---------------------------------------------------------------------- */

void FixSPHJCThermal::reset_dt()
{
  dtv = update->dt;
  dtf = 0.5 * update->dt * force->ftm2v;
}

/* ----------------------------------------------------------------------
   before the setup force computation: complete the state of new atoms,
   and unless this continues a run (restart, or a second run command with
   unchanged velocities) compute the forces from the current state
------------------------------------------------------------------------- */

void FixSPHJCThermal::setup_pre_force(int vflag)
{
  setup_state();
  pre_force(vflag);
}

void FixSPHJCThermal::setup_state()
{
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const int *type = atom->type;
  double **v = atom->v;
  const Material *mat = model->materials();
  int nfresh = 0;

  // initial temperature from an atom-style variable, for atoms that have none yet
  if (!temp_var.empty()) {
    const int ivar = input->variable->find(temp_var.c_str());
    if (ivar < 0) error->all(FLERR, "Fix sph/jc-thermal: temp variable {} does not exist", temp_var);
    if (!input->variable->atomstyle(ivar))
      error->all(FLERR, "Fix sph/jc-thermal: temp variable {} is not atom-style", temp_var);
    std::vector<double> t0(nlocal);
    input->variable->compute_atom(ivar, igroup, t0.data(), 1, 0);
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit) || state[i][TEMP] >= 0.0) continue;
      if (t0[i] < 0.0) error->one(FLERR, "Fix sph/jc-thermal: temp variable {} is negative: {}", temp_var, t0[i]);
      if (!std::isfinite(t0[i]))
        error->one(FLERR, "Fix sph/jc-thermal: temp variable {} is not a finite number for atom {}: {}", temp_var,
                   atom->tag[i], t0[i]);
      state[i][TEMP] = t0[i];
    }
  }
  std::vector<bigint> ntref(atom->ntypes + 1, 0);    // particles given their material's Tref, by type
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *s = state[i];
    const Material &mt = mat[type[i]];
    // an atom created since the last run (initial_row: density -1) has no force state yet
    const bool created = s[RHO] <= 0.0;
    if (created) s[RHO] = mt.rho0;
    if (s[TEMP] < 0.0) {
      s[TEMP] = mt.Tref;
      ntref[type[i]]++;
    }
    s[ROLE] = role_of(mask[i]);
    s[PRESS] = sphcut::eos_pressure(mt, s[RHO], s[TEMP]);
    s[VM] = sphcut::von_mises(&s[SXX]);
    int fresh = !force_state_valid || created;
    for (int d = 0; d < 3; d++)
      if (v[i][d] != s[VEND + d]) fresh = 1;
    if (fresh) {
      nfresh++;
      s[RHO_F] = s[RHO];
      for (int k = 0; k < 6; k++) s[SF + k] = s[SXX + k];
      s[TEMP_F] = s[TEMP];
      for (int d = 0; d < 3; d++) s[VEST + d] = s[ROLE] == CLAMPED ? 0.0 : v[i][d];
    }
  }
  force_state_valid = 1;
  report_default_temperature(ntref);
}

// particles whose temperature was never set (no keyword temp) start at their material's Tref:
// with an attached style whose physics starts from these temperatures (fix heat/fmfs: its
// conduction), a one-line message in its name says so, with the temperature of each type (not
// silently: issue 23)
void FixSPHJCThermal::report_default_temperature(const std::vector<bigint> &ntref)
{
  prune_attached();    // (setup_pre_force: before setup prunes the styles deleted since the last run)
  std::string who;
  for (auto *st : timed)
    if (who.empty()) who = st->starts_from_temperature();
  if (who.empty()) return;
  std::vector<bigint> all(ntref.size(), 0);
  MPI_Allreduce(ntref.data(), all.data(), (int) ntref.size(), MPI_LMP_BIGINT, MPI_SUM, world);
  bigint n = 0;
  std::string types;
  for (size_t t = 1; t < all.size(); t++) {
    if (!all[t]) continue;
    n += all[t];
    types += fmt::format("{}type {}: {:.6g}", types.empty() ? "" : ", ", t, model->materials()[t].Tref);
  }
  if (n && comm->me == 0)
    utils::logmesg(lmp, "{}: no initial temperature given for {} particle(s) (fix sph/jc-thermal keyword "
                   "temp): they start at their material's Tref (pair_coeff, default 300), {}\n", who, n, types);
}

/* ----------------------------------------------------------------------
   after neighboring, before the forces: clear this step's rates and send
   the force state to the ghosts
------------------------------------------------------------------------- */

void FixSPHJCThermal::pre_force(int)
{
  sphcut::ScopedTimer timer(cpu_time);
  const int nlocal = atom->nlocal;
  for (int i = 0; i < nlocal; i++) sphcut::zero_rates(state[i]);
  sphcut::forward_comm(comm, this);
}

/* ----------------------------------------------------------------------
   first half of the step (sphcut_solid.h): kick, drift, predictor
------------------------------------------------------------------------- */

void FixSPHJCThermal::initial_integrate(int)
{
  sphcut::ScopedTimer timer(cpu_time);
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const Material *mat = model->materials();

  // an attached heat style's Dirichlet groups (set_heat_rules): their predicted temperature
  const HeatRules &hr = heat_rules;
  const int nd = (int) hr.bits.size();
  for (int i = 0; i < nlocal; i++) {
    if (mask[i] & groupbit) {
      const double dtfm = dtf / (rmass ? rmass[i] : mass[type[i]]);
      sphcut::integrate_first_half(mat[type[i]], role_of(mask[i]), dtv, dtfm, x[i], v[i], f[i], state[i]);
    }
    if (nd) sphcut::hold_predicted_temperature(mask[i], hr.gb, hr.bits.data(), hr.temps.data(), nd, state[i]);
  }
}

/* ---------------------------------------------------------------------- */

void FixSPHJCThermal::final_integrate()
{
  sphcut::ScopedTimer timer(cpu_time);
  double **v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const Material *mat = model->materials();

  // an attached heat style's rules (set_heat_rules): its held rate joins the temperature rate
  // first; after the corrector its Dirichlet particles go back to their temperature, the heat that
  // takes into the style's budget (its group lies inside this fix's: FixSPHJCThermal::require)
  const HeatRules &hr = heat_rules;
  const int nd = (int) hr.bits.size();
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    if (mask[i] & hr.gb) sphcut::add_held_rate(state[i]);
    const double m = rmass ? rmass[i] : mass[type[i]];
    plastic_work += sphcut::integrate_second_half(mat[type[i]], role_of(mask[i]), dtv, dtf / m, m,
                                                  v[i], f[i], state[i]);
    if (nd)    // (0 for the other particles: the sum is the same number)
      *hr.qdir += sphcut::hold_corrected_temperature(mask[i], hr.gb, hr.bits.data(), hr.temps.data(), nd,
                                                     m * mat[type[i]].cp, state[i]);
  }
}

/* ----------------------------------------------------------------------
   stable time step (adaptive dt with keyword cfl):
     dt = cfl * min_i h_i / (c_l,i + |v_i|)       (mechanics, this fix)
     dt <= each attached style's own limit, its dt_limit(cfl, thermal_cfl)
           (the conduction of fix heat/fmfs, the penalty spring of fix
           contact/tri-penalty: each knows its physics, this fix only takes
           the minimum)
------------------------------------------------------------------------- */

double FixSPHJCThermal::stable_dt()
{
  double **v = atom->v;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;
  const Material *mat = model->materials();
  double dtloc = 1.0e300;
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const int it = type[i];
    dtloc = std::min(dtloc, sphcut::particle_dt(mat[it], role_of(mask[i]), model->smoothing_length(it), v[i],
                                                    state[i][TEMP], cfl, vmax, tmax));
  }
  return finish_dt(dtloc);
}

// this rank's mechanical limit -> the step: the stiff parts owned by the attached styles (the
// contact spring, conduction with its sub-cycling), the minimum over the ranks, dtmin/dtmax
double FixSPHJCThermal::finish_dt(double dtloc)
{
  for (auto *st : timed) dtloc = std::min(dtloc, st->dt_limit(cfl, thermal_cfl));
  double dtnew;
  MPI_Allreduce(&dtloc, &dtnew, 1, MPI_DOUBLE, MPI_MIN, world);
  if (dtnew < 0.0) report_runaway();
  if (dtmax > 0.0) dtnew = std::min(dtnew, dtmax);
  if (dtmin > 0.0) dtnew = std::max(dtnew, dtmin);
  return dtnew;
}

// for an error message: the particle of the group (tool particles only with with_tool) with
// the largest score above floor over all ranks; score(i, vals) gives particle i's score and its
// two values to report; info gets its tag, x, y, z and those values on every rank.  Returns the
// largest score (floor if no particle has more).
double FixSPHJCThermal::worst_particle(const std::function<double(int, double *)> &score, double floor,
                                       double *info, bool with_tool)
{
  struct {
    double score;
    int rank;
  } loc = {floor, comm->me}, glob;
  for (int k = 0; k < 6; k++) info[k] = 0.0;
  double vals[2];
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit) || (!with_tool && role_of(atom->mask[i]) == TOOL)) continue;
    const double sc = score(i, vals);
    if (sc <= loc.score) continue;
    loc.score = sc;
    info[0] = atom->tag[i];
    for (int k = 0; k < 3; k++) info[1 + k] = atom->x[i][k];
    info[4] = vals[0];
    info[5] = vals[1];
  }
  MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  MPI_Bcast(info, 6, MPI_DOUBLE, glob.rank, world);
  return glob.score;
}

// a particle faster than vmax (sphcut::particle_dt gave -1): stop the run and name the fastest
// one against its limit (host arrays; the /kk fix copies them there first)
void FixSPHJCThermal::report_runaway()
{
  double **v = atom->v;
  const Material *mat = model->materials();
  double info[6];    // tag, x, y, z, speed, limit
  const double worst = worst_particle(
      [&](int i, double *vals) {
        const double vv = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
        const double lim = sphcut::runaway_speed(mat[atom->type[i]], vmax);
        if (vv == vv && (!(lim > 0.0) || vv <= lim)) return -1.0;
        vals[0] = vv;
        vals[1] = lim;
        return vv == vv ? vv / lim : 1.0e300;    // a speed that is not a number first
      },
      -1.0, info);
  if (worst < 0.0) {
    report_temperature();
    report_density();
  }
  if (std::isnan(info[4]))
    error->all(FLERR,
               "Fix sph/jc-thermal: particle {} at ({:.6g}, {:.6g}, {:.6g}) has a velocity that is not a number "
               "(NaN), at step {}: the solution has become unstable (see the fix's doc page, keyword vmax)",
               (bigint) info[0], info[1], info[2], info[3], update->ntimestep);
  error->all(FLERR,
             "Fix sph/jc-thermal: particle {} at ({:.6g}, {:.6g}, {:.6g}) moves at {:.4g}, faster than vmax {:.4g} "
             "(default: its material's sound speed), at step {}: the solution has become unstable "
             "(see the fix's doc page, keyword vmax)",
             (bigint) info[0], info[1], info[2], info[3], info[4], info[5], update->ntimestep);
}

// no particle faster than vmax: a particle hotter than tmax (tool particles too) stops the run
// naming the hottest one against its limit; returns if there is none
void FixSPHJCThermal::report_temperature()
{
  const Material *mat = model->materials();
  double info[6];    // tag, x, y, z, temperature, limit
  const double worst = worst_particle(
      [&](int i, double *vals) {
        const double T = state[i][TEMP], lim = sphcut::runaway_temperature(mat[atom->type[i]], tmax);
        if (T == T && (!(lim > 0.0) || T <= lim)) return -1.0;
        vals[0] = T;
        vals[1] = lim;
        return T == T ? T / lim : 1.0e300;    // a temperature that is not a number first
      },
      -1.0, info, true);
  if (worst < 0.0) return;
  if (std::isnan(info[4]))
    error->all(FLERR,
               "Fix sph/jc-thermal: particle {} at ({:.6g}, {:.6g}, {:.6g}) has a temperature that is not a number "
               "(NaN), at step {}: the temperature solution has become unstable (see the fix's doc page, keyword "
               "tmax)", (bigint) info[0], info[1], info[2], info[3], update->ntimestep);
  error->all(FLERR,
             "Fix sph/jc-thermal: particle {} at ({:.6g}, {:.6g}, {:.6g}) has temperature {:.4g}, above tmax {:.4g} "
             "(default: twice its material's Tmelt), at step {}: the temperature solution has become unstable "
             "(see the fix's doc page, keyword tmax)",
             (bigint) info[0], info[1], info[2], info[3], info[4], info[5], update->ntimestep);
}

// no particle faster than vmax: the negative step came from a particle whose density is no longer
// positive (or not a number), through the conduction limit rho cp h^2 / k; name the one with the
// least density relative to its rho0
void FixSPHJCThermal::report_density()
{
  const Material *mat = model->materials();
  double info[6];    // tag, x, y, z, density, rho0
  worst_particle(
      [&](int i, double *vals) {
        const double rho = state[i][RHO], rho0 = mat[atom->type[i]].rho0;
        vals[0] = rho;
        vals[1] = rho0;
        return rho == rho ? -rho / rho0 : 1.0e300;    // -(rho / rho0): the largest is the least dense
      },
      -1.0e300, info);
  if (std::isnan(info[4]))
    error->all(FLERR,
               "Fix sph/jc-thermal: particle {} at ({:.6g}, {:.6g}, {:.6g}) has a density that is not a number "
               "(NaN; rho0 {:.4g}) at step {}: the solution has become unstable",
               (bigint) info[0], info[1], info[2], info[3], info[5], update->ntimestep);
  if (!(info[4] > 0.0))
    error->all(FLERR,
               "Fix sph/jc-thermal: particle {} at ({:.6g}, {:.6g}, {:.6g}) has density {:.4g} (rho0 {:.4g}) at "
               "step {}: the solution has become unstable (a particle torn apart in tension; see pair_coeff "
               "pmin)", (bigint) info[0], info[1], info[2], info[3], info[4], info[5], update->ntimestep);
  error->all(FLERR,
             "Fix sph/jc-thermal: the time step limit came back negative at step {}, with no particle faster "
             "than vmax and none with a density <= 0 (least dense: particle {}, {:.4g} of rho0 {:.4g})",
             update->ntimestep, (bigint) info[0], info[4], info[5]);
}

void FixSPHJCThermal::apply_dt(double dtnew)
{
  if (dtnew == update->dt || dtnew >= 1.0e300) return;
  update->update_time();
  update->dt = dtnew;
  time_anchor = update->atime;
  step_anchor = update->atimestep;
  dt_anchor = dtnew;
  anchored = true;
  update->dt_default = 0;
  if (force->pair) force->pair->reset_dt();
  for (auto *f : sphcut::fix_list(modify)) f->reset_dt();
}

// the adaptive dt is recomputed at the end of every dtevery-th step (and at every setup): between,
// the step stays as it was, and so do the runaway checks folded into its computation
bool FixSPHJCThermal::dt_step() const
{
  return dtevery == 1 || update->ntimestep % dtevery == 0;
}

void FixSPHJCThermal::end_of_step()
{
  sphcut::ScopedTimer timer(cpu_time);
  if (dt_step()) apply_dt(stable_dt());
}

// the first step of a run already uses the stable time step
void FixSPHJCThermal::setup(int)
{
  reset_timers();
  // particles on top of each other move as one: warn about the initial configuration
  if (update->ntimestep == 0) check_close_pairs();
  sync_time();
  if (cfl > 0.0) apply_dt(stable_dt());
}

/* ----------------------------------------------------------------------
   per-style timing table at the end of each run (max over the ranks):
   what each piece of physics cost, and what the scene saved by leaving
   a piece out
------------------------------------------------------------------------- */

void FixSPHJCThermal::check_close_pairs()
{
  sphcut::warn_close_pairs(lmp, force->pair_match("^sph/jc-thermal", 0)->list, *model);
}

void FixSPHJCThermal::attach(sphcut::AttachedStyle *style)
{
  if (std::find(timed.begin(), timed.end(), style) == timed.end()) timed.push_back(style);
}

void FixSPHJCThermal::set_heat_rules(const sphcut::AttachedStyle *owner, int gb,
                                     const std::vector<int> &bits, const std::vector<double> &temps, int every,
                                     double *qdir)
{
  if (!bits.empty() && !qdir) error->all(FLERR, "Fix sph/jc-thermal: Dirichlet groups without a heat budget");
  if (bits.size() != temps.size())
    error->all(FLERR, "Fix sph/jc-thermal: {} Dirichlet groups with {} temperatures", bits.size(), temps.size());
  heat_rules.owner = owner;
  heat_rules.gb = gb;
  heat_rules.bits = bits;
  heat_rules.temps = temps;
  heat_rules.every = every;
  heat_rules.qdir = qdir;
}

// the attached styles that still exist (a style may be deleted between runs; a run with
// `pre no` calls no init, so the list is kept from run to run and only pruned here)
std::vector<sphcut::AttachedStyle *> FixSPHJCThermal::live_styles() const
{
  std::vector<sphcut::AttachedStyle *> live;
  if (auto *p = dynamic_cast<sphcut::AttachedStyle *>(force->pair)) live.push_back(p);
  for (auto *fx : sphcut::fix_list(modify))
    if (auto *f = dynamic_cast<sphcut::AttachedStyle *>(fx)) live.push_back(f);
  for (auto *cx : sphcut::compute_list(modify))
    if (auto *c = dynamic_cast<sphcut::AttachedStyle *>(cx)) live.push_back(c);
  return live;
}

void FixSPHJCThermal::prune_attached()
{
  const std::vector<sphcut::AttachedStyle *> live = live_styles();
  std::vector<sphcut::AttachedStyle *> kept;
  for (auto *t : timed)
    if (std::find(live.begin(), live.end(), t) != live.end()) kept.push_back(t);
  timed.swap(kept);
  // the heat rules of a style deleted since
  if (heat_rules.owner && std::find(live.begin(), live.end(), heat_rules.owner) == live.end())
    set_heat_rules(nullptr, 0, {}, {}, 1, nullptr);
}

void FixSPHJCThermal::reset_timers()
{
  prune_attached();
  run_start = MPI_Wtime();
  cpu_time = 0.0;
  for (auto *t : timed) t->cpu_time = 0.0;
}

void FixSPHJCThermal::post_run()
{
  const std::vector<sphcut::AttachedStyle *> &attached = timed;
  if (update->nsteps <= 0) return;
  std::vector<std::string> names = {timing_name()};
  std::vector<double> t = {cpu_time};
  for (auto *ts : attached) {
    names.push_back(ts->timing_name());
    t.push_back(ts->cpu_time);
  }
  // the rest of this rank's run (neighbour lists, communication, output, other fixes)
  const double total_me = MPI_Wtime() - run_start;
  double styles = 0.0;
  for (double v : t) styles += v;
  t.push_back(total_me - styles);
  t.push_back(total_me);
  std::vector<double> tmax(t.size());
  MPI_Allreduce(t.data(), tmax.data(), (int) t.size(), MPI_DOUBLE, MPI_MAX, world);
  if (comm->me != 0) return;
  const double total = tmax.back() > 0.0 ? tmax.back() : 1.0;
  std::string msg = fmt::format("sphcut timing of this run (wall seconds, max over ranks; run {:.4g} s){}:\n", total,
                                timing_note());
  names.push_back("rest (neighbour lists, comm, output, ...)");
  for (size_t k = 0; k < names.size(); k++)
    msg += fmt::format("  {:<42s} {:10.4g} s {:6.1f} %\n", names[k], tmax[k], 100.0 * tmax[k] / total);
  utils::logmesg(lmp, msg);
}

/* ----------------------------------------------------------------------
   global vector: 1 dt, 2 internal energy sum m u, 3 kinetic energy of the
   non-tool particles, 4 plastic work, 5 max temperature, 6 max plastic strain
------------------------------------------------------------------------- */

double FixSPHJCThermal::compute_vector(int n)
{
  if (n == 0) return update->dt;
  const int nlocal = atom->nlocal;
  const int *mask = atom->mask;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  double **v = atom->v;
  double loc = 0.0, res = 0.0;
  if (n == 1 || n == 2) {
    for (int i = 0; i < nlocal; i++) {
      if (!(mask[i] & groupbit) || role_of(mask[i]) == TOOL) continue;
      const double m = rmass ? rmass[i] : mass[type[i]];
      if (n == 1) loc += m * state[i][UINT];
      else loc += 0.5 * m * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    }
    MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_SUM, world);
    return n == 2 ? res * force->mvv2e : res;
  }
  if (n == 3) {
    MPI_Allreduce(&plastic_work, &res, 1, MPI_DOUBLE, MPI_SUM, world);
    return res;
  }
  const int col = n == 4 ? TEMP : EPS;
  loc = -1.0e300;
  for (int i = 0; i < nlocal; i++)
    if (mask[i] & groupbit) loc = std::max(loc, state[i][col]);
  MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_MAX, world);
  return res;
}

/* ---------------------------------------------------------------------- */

double FixSPHJCThermal::memory_usage()
{
  return (double) atom->nmax * NCOL * sizeof(double);
}

void FixSPHJCThermal::grow_arrays(int nmax)
{
  memory->grow(state, nmax, NCOL, "sph/jc-thermal:state");
  array_atom = state;
}

void FixSPHJCThermal::copy_arrays(int i, int j, int)
{
  memcpy(state[j], state[i], NCOL * sizeof(double));
}

int FixSPHJCThermal::pack_exchange(int i, double *buf)
{
  memcpy(buf, state[i], NCOL * sizeof(double));
  return NCOL;
}

int FixSPHJCThermal::unpack_exchange(int nlocal, double *buf)
{
  memcpy(state[nlocal], buf, NCOL * sizeof(double));
  return NCOL;
}

int FixSPHJCThermal::pack_restart(int i, double *buf)
{
  buf[0] = NCOL + 1;
  memcpy(&buf[1], state[i], NCOL * sizeof(double));
  return NCOL + 1;
}

void FixSPHJCThermal::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  m++;
  memcpy(state[nlocal], &extra[nlocal][m], NCOL * sizeof(double));
}

int FixSPHJCThermal::size_restart(int)
{
  return NCOL + 1;
}

int FixSPHJCThermal::maxsize_restart()
{
  return NCOL + 1;
}

// the global record: its layout id, force_state_valid, the plastic work, the elapsed time and (where
// the id carries TIME_ANCHOR) the time anchor and its step (sync_time); files without it (sphcut
// before issue 50) end after the elapsed time
static constexpr int TIME_ANCHOR = 1000000;

void FixSPHJCThermal::write_restart(FILE *fp)
{
  double total = 0.0;
  MPI_Allreduce(&plastic_work, &total, 1, MPI_DOUBLE, MPI_SUM, world);
  if (comm->me == 0) {
    // the elapsed time too: LAMMPS 29Sep2021 restarts it at 0, which an adaptive dt cannot undo
    const double now = update->atime + (update->ntimestep - update->atimestep) * update->dt;
    const bool anchor = anchored && update->dt == dt_anchor;
    const double t0 = anchor ? time_anchor : now;
    const double s0 = (double) (anchor ? step_anchor : update->ntimestep);
    double list[6] = {(double) (NCOL + 1000 * LAYOUT + TIME_ANCHOR), (double) force_state_valid, total, now, t0, s0};
    int size = 6 * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 6, fp);
  }
}

void FixSPHJCThermal::restart(char *buf)
{
  const double *list = (const double *) buf;
  int id = static_cast<int>(list[0]);
  const bool has_anchor = id >= TIME_ANCHOR;
  if (has_anchor) id -= TIME_ANCHOR;
  if (id != NCOL + 1000 * LAYOUT)
    error->all(FLERR, "Fix sph/jc-thermal: restart file has state layout {}, this version {} "
               "(written by another sphcut version)", id, NCOL + 1000 * LAYOUT);
  force_state_valid = static_cast<int>(list[1]);
  plastic_work = comm->me == 0 ? list[2] : 0.0;
  time_anchor = has_anchor ? list[4] : list[3];
  step_anchor = has_anchor ? static_cast<bigint>(list[5]) : update->ntimestep;
  dt_anchor = update->dt;
  anchored = true;
  // LAMMPS' own time, folded to this step (the setup then takes the anchor)
  if (update->atime == 0.0 && update->atimestep == 0) {
    update->atime = list[3];
    update->atimestep = update->ntimestep;
  }
}

/* ---------------------------------------------------------------------- */

int FixSPHJCThermal::pack_forward_comm(int n, int *list, double *buf, int, int *)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++) {
    const double *s = state[list[ii]];
    for (int k = 0; k < NFORWARD; k++) buf[m++] = s[RHO_F + k];
  }
  return m;
}

void FixSPHJCThermal::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++) {
    double *s = state[i];
    for (int k = 0; k < NFORWARD; k++) s[RHO_F + k] = buf[m++];
  }
}
