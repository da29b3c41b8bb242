/* ----------------------------------------------------------------------
   sphcut - fix heat/fmfs

   rho cp dT_i/dt = k_i lap T_i + Q_i        (seed 003 eq. 4)
   lap T_i: FMFS (eqs. 13-15, second-order consistent) for interior
   particles whose neighbours share their conductivity; Brookshaw with the
   harmonic mean of the conductivities (eq. 12, seed 000 eq. 6) for surface
   particles (compute surface/lambda), across material interfaces, where
   FMFS is singular, or everywhere with `scheme brookshaw`.
   Q_i: heat sources handed in through add_heat() (friction heat), minus
   convection h_c (T - T_inf) and radiation e sigma (T^4 - T_inf^4) through
   the surface area A_i = V_i^((d-1)/d) of surface particles (eq. 8).
   Plastic heat is added by fix sph/jc-thermal.  Dirichlet groups hold
   their temperature (eq. 7); the heat that takes is accounted.
------------------------------------------------------------------------- */

#include "fix_heat_fmfs.h"

#include "atom.h"
#include "comm.h"
#include "compute_surface_lambda.h"
#include "domain.h"
#include "error.h"
#include "fix_sph_jc_thermal.h"
#include "force.h"
#include "group.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "sphcut_model.h"
#include "update.h"

#include "sphcut_checks.h"
#include "sphcut_compat.h"
#include "sphcut_kernels.h"
#include "sphcut_thermal.h"
#include "sphcut_timer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;
using sphcut::Material;

using sphcut::STEFAN_BOLTZMANN_SI;
// largest thermal Courant number of a stable update (fix sph/jc-thermal thermal_cfl <= this;
// measured stability limit 0.15-0.17 with hdx 1.5, cubic kernel)
static constexpr double THERMAL_CFL_MAX = 0.15;

/* ----------------------------------------------------------------------
   fix ID group heat/fmfs [scheme fmfs|brookshaw] [surface CID]
       [convection h_c T_inf] [radiation emissivity T_inf] [backing GROUP h_b T_b] [dirichlet GROUP T] ...
------------------------------------------------------------------------- */

FixHeatFMFS::FixHeatFMFS(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), scheme(FMFS), every(1), conservative(1), fwts(nullptr), nmax_fwts(0), held_conv(0.0), held_rad(0.0), fmfs_lambda(0.75), id_surface(nullptr), surface(nullptr), hconv(0.0), tconv(0.0),
    emiss(0.0), trad(0.0), backbit(0), hback(0.0), tback(0.0), q_conv(0.0), q_rad(0.0), q_dirichlet(0.0), q_sources(0.0), n_fmfs(0),
    n_brookshaw(0), n_fallback(0), p_conv_prev(0.0), p_rad_prev(0.0), list(nullptr), fix(nullptr), model(nullptr),
    fuse_surface(false)
{
  int iarg = 3;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    auto need = [&](int n) {
      if (iarg + n >= narg) error->all(FLERR, "Fix heat/fmfs: keyword {} needs {} value(s)", kw, n);
    };
    if (kw == "scheme") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "fmfs") scheme = FMFS;
      else if (v == "brookshaw") scheme = BROOKSHAW;
      else error->all(FLERR, "Fix heat/fmfs: unknown scheme {} (fmfs, brookshaw)", v);
      iarg += 2;
    } else if (kw == "every") {
      need(1);
      every = sphcut::parse_int(lmp, "Fix heat/fmfs", kw, arg[iarg + 1]);
      iarg += 2;
    } else if (kw == "conservative") {
      need(1);
      const std::string v = arg[iarg + 1];
      if (v == "yes") conservative = 1;
      else if (v == "no") conservative = 0;
      else error->all(FLERR, "Fix heat/fmfs: conservative must be yes or no, got {}", v);
      iarg += 2;
    } else if (kw == "fmfs_lambda") {
      need(1);
      fmfs_lambda = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (fmfs_lambda < 0.0 || fmfs_lambda > 1.0)
        error->all(FLERR, "Fix heat/fmfs: fmfs_lambda must be in [0,1], got {}", fmfs_lambda);
      iarg += 2;
    } else if (kw == "surface") {
      need(1);
      delete[] id_surface;
      id_surface = utils::strdup(arg[iarg + 1]);
      iarg += 2;
    } else if (kw == "convection") {
      need(2);
      hconv = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      tconv = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      if (hconv < 0.0) error->all(FLERR, "Fix heat/fmfs: convection coefficient must be >= 0, got {}", hconv);
      if (tconv < 0.0) error->all(FLERR, "Fix heat/fmfs: convection T_inf must be >= 0, got {}", tconv);
      iarg += 3;
    } else if (kw == "radiation") {
      need(2);
      emiss = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      trad = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      if (emiss < 0.0 || emiss > 1.0) error->all(FLERR, "Fix heat/fmfs: emissivity must be in [0,1], got {}", emiss);
      if (trad < 0.0) error->all(FLERR, "Fix heat/fmfs: radiation T_inf must be >= 0, got {}", trad);
      iarg += 3;
    } else if (kw == "backing") {
      need(3);
      const int ig = group->find(arg[iarg + 1]);
      if (ig < 0) error->all(FLERR, "Fix heat/fmfs: backing group {} does not exist", arg[iarg + 1]);
      backbit = group->bitmask[ig];
      hback = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      tback = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
      if (hback < 0.0) error->all(FLERR, "Fix heat/fmfs: backing coefficient must be >= 0, got {}", hback);
      if (tback < 0.0) error->all(FLERR, "Fix heat/fmfs: backing temperature must be >= 0, got {}", tback);
      iarg += 4;
    } else if (kw == "dirichlet") {
      need(2);
      const int ig = group->find(arg[iarg + 1]);
      if (ig < 0) error->all(FLERR, "Fix heat/fmfs: dirichlet group {} does not exist", arg[iarg + 1]);
      const double t = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
      if (t < 0.0) error->all(FLERR, "Fix heat/fmfs: dirichlet temperature must be >= 0, got {}", t);
      dir_bits.push_back(group->bitmask[ig]);
      dir_temps.push_back(t);
      iarg += 3;
    } else {
      error->all(FLERR, "Fix heat/fmfs: unknown keyword {}", kw);
    }
  }
  if ((hconv > 0.0 || emiss > 0.0) && !id_surface)
    error->all(FLERR, "Fix heat/fmfs: convection and radiation need a surface compute (keyword surface)");

  vector_flag = 1;
  size_vector = 6;
  global_freq = 1;
  extvector = -1;
  extlist = new int[6]{1, 1, 1, 1, 1, 0};
  restart_global = 1;
  comm_forward = 1 + 3 * 3 + 3;
  // the rate held between evaluations lives in fix sph/jc-thermal's state (column HELD)
}

FixHeatFMFS::~FixHeatFMFS()
{
  delete[] id_surface;
  delete[] extlist;
  memory->destroy(fwts);
}

// (the Dirichlet temperatures after the predictor and after the corrector, with the heat through
// the clamp, and the held rate on ordinary steps are applied by fix sph/jc-thermal in its own
// passes: set_heat_rules in init)
int FixHeatFMFS::setmask()
{
  return POST_FORCE;
}

/* ---------------------------------------------------------------------- */

void FixHeatFMFS::init()
{
  fix = FixSPHJCThermal::require(lmp, "Fix heat/fmfs", groupbit, group->names[igroup], &model);
  fix->attach(this);
  hand_over_rules();
  // Dirichlet temperatures are imposed after the temperature update of that fix
  if (sphcut::fix_index(modify, this) < sphcut::fix_index(modify, fix))
    error->all(FLERR, "Fix heat/fmfs must be defined after fix sph/jc-thermal");
  const int ninst = (int) sphcut::fixes_by_style(modify, "^heat/fmfs").size();
  if (ninst > 1) error->all(FLERR, "Fix heat/fmfs: only one instance is allowed, found {}", ninst);
  surface = nullptr;
  if (id_surface) {
    Compute *c = sphcut::compute_by_id(modify, id_surface);
    if (!c) error->all(FLERR, "Fix heat/fmfs: surface compute {} does not exist", id_surface);
    if (!utils::strmatch(c->style, "^surface/lambda"))
      error->all(FLERR, "Fix heat/fmfs: compute {} is not of style surface/lambda", id_surface);
    surface = dynamic_cast<ComputeSurfaceLambda *>(c);
  }
  const Material *mat = model->materials();
  for (int t = 1; t <= atom->ntypes; t++)
    if (mat[t].defined && mat[t].kappa > 0.0 && mat[t].cp <= 0.0)
      error->all(FLERR, "Fix heat/fmfs: atom type {} conducts (k > 0) but has no cp", t);
  if (emiss > 0.0 && strcmp(update->unit_style, "si") != 0)
    error->all(FLERR, "Fix heat/fmfs: radiation uses the SI Stefan-Boltzmann constant; use units si");
  sphcut::request_full_list(neighbor, this, instance_me, true, false);
  const int nt = atom->ntypes + 1;
  tpair.assign((size_t) nt * nt, sphcut::ThermalPair{});
  hij.assign((size_t) nt * nt, 0.0);
  for (int it = 1; it < nt; it++)
    for (int jt = 1; jt < nt; jt++) {
      hij[(size_t) it * nt + jt] = model->smoothing_length(it, jt);
      tpair[(size_t) it * nt + jt] = sphcut::thermal_pair(model->kernel(), domain->dimension,
                                                          model->smoothing_length(it, jt), mat[it].kappa, mat[jt].kappa);
    }
}

void FixHeatFMFS::init_list(int, NeighList *ptr)
{
  list = ptr;
}

/* the integrator adds the held rate (HELD) of this group to the temperature rate before its
   corrector, sets the predicted temperature of the Dirichlet groups after its predictor and their
   temperature after its corrector, the heat that takes into q_dirichlet (sphcut_heat_rules.h; the
   /kk variant hands hooks instead: FixHeatFMFSKokkos::hand_over_rules) */
void FixHeatFMFS::hand_over_rules()
{
  fix->set_heat_rules(this, groupbit, dir_bits, dir_temps, every, &q_dirichlet);
}

int FixHeatFMFS::dirichlet_of(int mask) const
{
  return sphcut::dirichlet_index(mask, groupbit, dir_bits.data(), (int) dir_bits.size());
}

/* ---------------------------------------------------------------------- */

double FixHeatFMFS::dt_limit(double, double F) const
{
  using F_ = FixSPHJCThermal;
  if (!fix || !model) return 1.0e300;
  const Material *mat = model->materials();
  double dt = 1.0e300;
  for (int i = 0; i < atom->nlocal; i++) {
    const int it = atom->type[i];
    sphcut::thermal_dt_min(atom->mask[i], groupbit, fix->state[i][F_::RHO], mat[it].cp, mat[it].kappa,
                           model->smoothing_length(it), F, every, dt);
  }
  return dt;
}

// refuse a time step the (sub-cycled) temperature update cannot integrate stably; the
// adaptive dt of fix sph/jc-thermal (defined before this fix, so set by now) stays below
void FixHeatFMFS::check_timestep()
{
  double lim = 1.0e300, dtlim = dt_limit(0.0, THERMAL_CFL_MAX);
  MPI_Allreduce(&dtlim, &lim, 1, MPI_DOUBLE, MPI_MIN, world);
  if (update->dt > lim * (1.0 + 1.0e-12))
    error->all(FLERR, "Fix heat/fmfs: timestep {} with every {} exceeds the stable limit {} "
               "(0.15 rho cp h^2/k 2/(every+1)): reduce timestep or every, or use fix sph/jc-thermal cfl",
               update->dt, every, lim);
}

void FixHeatFMFS::setup(int vflag)
{
  check_timestep();
  // Dirichlet particles start at their temperature
  using F = FixSPHJCThermal;
  for (int i = 0; i < atom->nlocal; i++) {
    const int k = dirichlet_of(atom->mask[i]);
    if (k < 0) continue;
    double *s = fix->state[i];
    s[F::TEMP] = s[F::TEMP_F] = dir_temps[k];
  }
  sphcut::forward_comm(comm, fix);
  // the rate of the Dirichlet particles is kept (not zeroed): the first corrector needs it
  // as the old rate for the trapezoidal heat through the clamp (element 3)
  post_force(vflag);
}

/* ----------------------------------------------------------------------
   conduction and surface losses: add to the temperature rate of the step
------------------------------------------------------------------------- */

void FixHeatFMFS::post_force(int)
{
  // thermal sub-cycling: the conduction and loss rates change on the thermal time scale,
  // far longer than the mechanical time step, so they may be evaluated every N steps
  const int eval = every == 1 || update->setupflag || update->ntimestep % every == 0;
  if (eval) begin_evaluation();
  sphcut::ScopedTimer timer(cpu_time);
  if (eval) {
    if (conservative) {
      if (domain->dimension == 2) conduction_conservative<2>();
      else conduction_conservative<3>();
    } else {
      if (domain->dimension == 2) conduction<2>();
      else conduction<3>();
    }
  }
  // the held rate joins the temperature rate: at the setup here, during the run in fix
  // sph/jc-thermal's corrector (sphcut::add_held_rate, set_heat_rules)
  if (update->setupflag) {
    double **st = fix->state;
    for (int i = 0; i < atom->nlocal; i++)
      if (atom->mask[i] & groupbit) sphcut::add_held_rate(st[i]);
  }
  // losses over the step with the trapezoidal weights of the temperature update
  if (!update->setupflag) {
    q_conv += 0.5 * update->dt * (p_conv_prev + held_conv);
    q_rad += 0.5 * update->dt * (p_rad_prev + held_rad);
  }
  p_conv_prev = held_conv;
  p_rad_prev = held_rad;
}

// an evaluation step: the surface flags of this step.  The conservative form computes them
// itself in its first pass where the compute sees the same neighbours (fuse_surface: one walk
// over the neighbours for lambda, the normal and the FMFS moments, the kernel evaluated once);
// otherwise the compute runs on its own.  Returns fuse_surface.
bool FixHeatFMFS::begin_evaluation()
{
  fuse_surface = false;
  if (!surface || surface->invoked_peratom == update->ntimestep) return false;    // none, or current
  if (conservative && surface->fusable(groupbit)) fuse_surface = surface->begin_step();
  else surface->compute_peratom();
  return fuse_surface;
}

namespace {
// the listed neighbours of one particle as sphcut::conduction_particle reads them
struct ListedNeighbours {
  const int *jlist;
  int n;
  const int *mask, *type;
  int groupbit;
  double *const *x;
  double *const *st;
  const double *rmass, *mass;
  const Material *mat;
  const double *hrow;    // the smoothing lengths of i's type with each type
  int size() const { return n; }
  int index(int k) const
  {
    const int j = jlist[k] & NEIGHMASK;
    return mask[j] & groupbit ? j : -1;
  }
  void pos(int j, double *xj) const
  {
    for (int a = 0; a < 3; a++) xj[a] = x[j][a];
  }
  double h(int j) const { return hrow[type[j]]; }
  double temp(int j) const { return st[j][FixSPHJCThermal::TEMP_F]; }
  double volume(int j) const { return (rmass ? rmass[j] : mass[type[j]]) / st[j][FixSPHJCThermal::RHO_F]; }
  double kappa(int j) const { return mat[type[j]].kappa; }
};
}    // namespace

sphcut::HeatLosses FixHeatFMFS::losses() const
{
  return {hconv, tconv, emiss * STEFAN_BOLTZMANN_SI, trad, hconv > 0.0 || emiss > 0.0, hback > 0.0 ? backbit : 0, hback, tback};
}

// per particle (conservative no): the physics is sphcut::conduction_particle and heat_rate
template <int DIM> void FixHeatFMFS::conduction()
{
  const int *mask = atom->mask;
  const int *type = atom->type;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  double **st = fix->state;
  const Material *mat = model->materials();
  const int kernel = model->kernel(), nt = atom->ntypes + 1;
  const sphcut::HeatLosses hl = losses();
  using F = FixSPHJCThermal;
  double p_conv = 0.0, p_rad = 0.0;
  for (int i = 0; i < atom->nlocal; i++) st[i][F::HELD] = 0.0;
  ListedNeighbours nb{nullptr, 0, mask, type, groupbit, atom->x, st, rmass, mass, mat, nullptr};

  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const int itype = type[i];
    const Material &mi = mat[itype];
    if (mi.cp <= 0.0) continue;
    const double Ti = st[i][F::TEMP_F];
    const int surf = surface ? surface->is_surface(i) : 0;
    nb.jlist = list->firstneigh[i];
    nb.n = list->numneigh[i];
    nb.hrow = &hij[(size_t) itype * nt];
    double rate;    // rho cp dT/dt
    const int s = sphcut::conduction_particle<DIM>(nb, kernel, atom->x[i], Ti, mi.kappa,
                                                   scheme == FMFS && !surf && mi.kappa > 0.0, fmfs_lambda, rate);
    sphcut::heat_count(s, n_fmfs, n_brookshaw, n_fallback);
    st[i][F::HELD] = sphcut::heat_rate(DIM, hl, surf, mask[i], rate, st[i][F::RHO_F], rmass ? rmass[i] : mass[itype], mi.cp,
                                       Ti, p_conv, p_rad);
  }
  held_conv = p_conv;
  held_rad = p_rad;
}

/* ----------------------------------------------------------------------
   conservative form (default): per particle the scheme (FMFS or Brookshaw, the
   same choice as conduction()) and, for FMFS, its pair weights; then the pairs
   exchange heat with the mean of the two particles' weights (sphcut_thermal.h
   conductance_mean), so sum m cp T changes only by sources, losses and Dirichlet
------------------------------------------------------------------------- */

// position, volume and predicted temperature of every particle of the group (local and ghost)
// in one row of prow, so the neighbour loops read one short row per neighbour
void FixHeatFMFS::gather_rows()
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int *type = atom->type;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  double **st = fix->state;
  using F = FixSPHJCThermal;
  const int nall = atom->nlocal + atom->nghost;
  if (prow.size() < (size_t) 5 * nall) prow.resize((size_t) 5 * atom->nmax);
  for (int i = 0; i < nall; i++) {
    if (!(mask[i] & groupbit)) continue;
    double *p = &prow[(size_t) 5 * i];
    p[0] = x[i][0];
    p[1] = x[i][1];
    p[2] = x[i][2];
    p[3] = (rmass ? rmass[i] : mass[type[i]]) / st[i][F::RHO_F];
    p[4] = st[i][F::TEMP_F];
  }
}

// the neighbours of local particle i within the support (of the group) into the nb_ buffers:
// index, type, x_i - x_j, r^2, then their kernel factors wfac and 1/r^2.  All the pairs'
// scalars first and the sums after (in the callers), so that the processor overlaps the pairs'
// sqrt and division instead of waiting for each before the sums.  With half, a local j with a
// smaller index and a list of its own (listed) is left out: i is in j's (full) list, so the
// symmetric pair term is computed once, by j.  Returns the count.
int FixHeatFMFS::gather_support(int i, bool half)
{
  const int *mask = atom->mask;
  const int *type = atom->type;
  const int kernel = model->kernel(), nt = atom->ntypes + 1;
  const sphcut::ThermalPair *tpi = tpair.data() + type[i] * nt;
  const double *pk = prow.data();
  const double *xi = pk + 5 * i;
  const int *jlist = list->firstneigh[i];
  const int jnum = list->numneigh[i];
  if ((int) nb_j.size() < jnum) {
    nb_j.resize(jnum);
    nb_t.resize(jnum);
    nb_dx.resize(3 * (size_t) jnum);
    nb_r2.resize(jnum);
    nb_wfac.resize(jnum);
    nb_ir2.resize(jnum);
  }
  int n = 0;
  for (int jj = 0; jj < jnum; jj++) {
    const int j = jlist[jj] & NEIGHMASK;
    if (!(mask[j] & groupbit) || (half && j < i && listed[j])) continue;
    const int jt = type[j];
    double r2;
    if (!sphcut::thermal_in_support(tpi[jt], xi, pk + 5 * j, &nb_dx[3 * n], r2)) continue;
    nb_j[n] = j;
    nb_t[n] = jt;
    nb_r2[n] = r2;
    n++;
  }
  for (int k = 0; k < n; k++) sphcut::thermal_kernel(tpi[nb_t[k]], kernel, nb_r2[k], nb_wfac[k], nb_ir2[k]);
  return n;
}

namespace {
// the neighbours of one particle gathered by gather_support, as the passes of the conservative
// form (sphcut::heat_scheme, heat_exchange) read them: gathered, so cheap to walk twice
struct GatheredSupport {
  static constexpr bool TWO_WALKS = true;
  int n;
  const int *j, *t;                      // index and type
  const double *dx, *wfac, *ir2;         // x_i - x_j (3 each), the kernel factor, 1/r^2
  const sphcut::ThermalPair *tpi;        // the row of i's type
  const double *prow;                    // x, V, T per particle
  double *const *fwts;                   // scheme flag and FMFS weights per particle
  const Material *mat;
  const int *type;
  int size() const { return n; }
  bool pair(int k, sphcut::HeatPair &p) const
  {
    p.j = j[k];
    p.tp = tpi + t[k];
    for (int a = 0; a < 3; a++) p.dx[a] = dx[3 * k + a];
    p.wfac = wfac[k];
    p.ir2 = ir2[k];
    return true;
  }
  double volume(int jj) const { return prow[5 * jj + 3]; }
  double temp(int jj) const { return prow[5 * jj + 4]; }
  template <int DIM> bool weights(int jj, double *w) const { return sphcut::row_weights<DIM>(fwts[jj], w); }
  double kappa(int jj) const { return mat[type[jj]].kappa; }
};
}    // namespace

// the neighbours of particle i within the support (gather_support(i, half)) as a view
template <class View> View FixHeatFMFS::support_view(int i, bool half)
{
  const int n = gather_support(i, half);
  return View{n, nb_j.data(), nb_t.data(), nb_dx.data(), nb_wfac.data(), nb_ir2.data(),
              tpair.data() + atom->type[i] * (atom->ntypes + 1), prow.data(), fwts, model->materials(), atom->type};
}

template <int DIM> void FixHeatFMFS::conduction_conservative()
{
  if (atom->nmax > nmax_fwts) {
    nmax_fwts = atom->nmax;
    memory->destroy(fwts);
    memory->create(fwts, nmax_fwts, 1 + 3 * 3 + 3, "heat/fmfs:fwts");
  }
  gather_rows();
  const int nall = atom->nlocal + atom->nghost;
  for (int i = 0; i < nall; i++) fwts[i][0] = 0.0;
  scheme_pass<DIM>();
  sphcut::forward_comm(comm, this);
  exchange_pass<DIM>();
}

// 1. one walk over the neighbours of each particle: the surface indicator (fused: into the
// compute's values) and the FMFS moments, then the scheme and the FMFS pair weights
template <int DIM> void FixHeatFMFS::scheme_pass()
{
  const int *mask = atom->mask;
  const int *type = atom->type;
  const Material *mat = model->materials();
  using CS = ComputeSurfaceLambda;
  const bool fuse = fuse_surface;
  double **so = fuse ? surface->values() : nullptr;
  const double thr = surface ? surface->threshold : 0.0;
  if (fuse)
    for (int i = 0; i < atom->nlocal; i++)
      for (int k = 0; k < CS::NCOLS; k++) so[i][k] = 0.0;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const Material &mi = mat[type[i]];
    const int conducts = mi.cp > 0.0;
    // FMFS candidate: with the fused compute the surface flag and lambda come after the walk
    const int cand = conducts && scheme == FMFS && mi.kappa > 0.0 && !(!fuse && surface && surface->is_surface(i));
    sphcut::HeatSurface sv;
    // (without the fused compute a particle that cannot take FMFS needs no walk)
    const int s = sphcut::heat_scheme<DIM>(fuse || cand ? support_view<GatheredSupport>(i, false) : GatheredSupport{},
                                           conducts, cand, fuse, thr, fmfs_lambda, sv, &fwts[i][1]);
    if (fuse) {
      so[i][CS::LAMBDA] = sv.lambda;
      so[i][CS::FLAG] = sv.flag;
      for (int a = 0; a < DIM; a++) so[i][CS::NX + a] = sv.n[a];
    }
    if (s == sphcut::HEAT_FMFS) fwts[i][0] = 1.0;
    sphcut::heat_count(s, n_fmfs, n_brookshaw, n_fallback);
  }
}

// 2. the pairwise exchange (sphcut::heat_exchange): the conductance c_ij is symmetric, so a pair
// of two local particles is computed once and moves heat both ways; then the temperature rates
// and the surface losses
template <int DIM> void FixHeatFMFS::exchange_pass()
{
  const int *mask = atom->mask;
  const int *type = atom->type;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  double **st = fix->state;
  const Material *mat = model->materials();
  const double *pk = prow.data();
  const sphcut::HeatLosses hl = losses();
  using F = FixSPHJCThermal;
  const int nlocal = atom->nlocal;
  if (rate_sum.size() < (size_t) nlocal) rate_sum.resize(atom->nmax);
  double *rate = rate_sum.data();    // rho cp dT/dt
  for (int i = 0; i < nlocal; i++) rate[i] = 0.0;
  // (neigh_modify include may leave particles without a list of their own: their pairs are
  // computed from the other side in full)
  listed.assign(nlocal, 0);
  for (int ii = 0; ii < list->inum; ii++)
    if (mask[list->ilist[ii]] & groupbit) listed[list->ilist[ii]] = 1;
  auto to_j = [rate, nlocal](int j, double v) {
    if (j < nlocal) rate[j] += v;
  };
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    rate[i] += sphcut::heat_exchange<DIM>(support_view<GatheredSupport>(i, true), mat[type[i]].kappa, pk[5 * i + 4],
                                          pk[5 * i + 3], fwts[i], to_j);
  }

  double p_conv = 0.0, p_rad = 0.0;
  for (int i = 0; i < nlocal; i++) st[i][F::HELD] = 0.0;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const Material &mi = mat[type[i]];
    if (mi.cp <= 0.0) continue;
    const int surf = surface ? surface->is_surface(i) : 0;
    st[i][F::HELD] = sphcut::heat_rate(DIM, hl, surf, mask[i], rate[i], st[i][F::RHO_F], rmass ? rmass[i] : mass[type[i]], mi.cp,
                                       pk[5 * i + 4], p_conv, p_rad);
  }
  held_conv = p_conv;
  held_rad = p_rad;
}

int FixHeatFMFS::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++)
    for (int k = 0; k < comm_forward; k++) buf[m++] = fwts[list_[ii]][k];
  return m;
}

void FixHeatFMFS::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < comm_forward; k++) fwts[i][k] = buf[m++];
}

/* ---------------------------------------------------------------------- */

double FixHeatFMFS::memory_usage()
{
  return (double) nmax_fwts * (1 + 3 * 3 + 3) * sizeof(double) + (double) prow.capacity() * sizeof(double);
}

/* ----------------------------------------------------------------------
   heat source (energy/time) for local atom i, e.g. friction heat
------------------------------------------------------------------------- */

void FixHeatFMFS::add_heat(int i, double power)
{
  if (i >= atom->nlocal || !(atom->mask[i] & groupbit)) return;
  const Material &mt = model->materials()[atom->type[i]];
  const double m = atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
  if (!sphcut::add_source_heat(fix->state[i][FixSPHJCThermal::DTEMP], power, m, mt.cp)) return;
  // booked with the rectangle rule (the temperature uses the trapezoid: O(dt) difference per step)
  if (!update->setupflag) q_sources += power * update->dt;
}

/* ----------------------------------------------------------------------
   after the temperature update, Dirichlet particles go back to their
   temperature; the energy that takes is the heat through the clamp
   (element 3).  Fix sph/jc-thermal does it in its corrector's loop, right
   after each particle's corrector (sphcut::hold_corrected_temperature,
   set_heat_rules), adding the heat to q_dirichlet.  Their rate is kept
   (and their predicted temperature reset to T_D after the predictor), so
   the corrector moved them by dt/2 (old + new rate), the same trapezoidal
   weights as their neighbours' exchange with them: with a conservative
   scheme element 3 equals the energy change.
------------------------------------------------------------------------- */

/* ----------------------------------------------------------------------
   global vector: 1 heat lost by convection, 2 by radiation, 3 heat entering
   through Dirichlet groups, 4 heat added by sources, 5 thermal energy
   sum m cp T of the group, 6 fraction of particle evaluations on FMFS (since the fix was defined)
------------------------------------------------------------------------- */

double FixHeatFMFS::compute_vector(int n)
{
  double loc = 0.0, res = 0.0;
  if (n == 0) loc = q_conv;
  else if (n == 1) loc = q_rad;
  else if (n == 2) loc = q_dirichlet;
  else if (n == 3) loc = q_sources;
  else if (n == 4) {
    if (!fix || !model)
      error->all(FLERR, "Fix heat/fmfs: the thermal energy (element 5) is available from the first run (or run 0) on");
    const Material *mat = model->materials();
    for (int i = 0; i < atom->nlocal; i++) {
      if (!(atom->mask[i] & groupbit)) continue;
      const double m = atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
      loc += m * mat[atom->type[i]].cp * fix->state[i][FixSPHJCThermal::TEMP];
    }
  } else {
    double c[2] = {(double) n_fmfs, (double) (n_fmfs + n_brookshaw)}, g[2];
    MPI_Allreduce(c, g, 2, MPI_DOUBLE, MPI_SUM, world);
    return g[1] > 0.0 ? g[0] / g[1] : 0.0;
  }
  MPI_Allreduce(&loc, &res, 1, MPI_DOUBLE, MPI_SUM, world);
  return res;
}

void FixHeatFMFS::write_restart(FILE *fp)
{
  double loc[4] = {q_conv, q_rad, q_dirichlet, q_sources}, tot[4];
  MPI_Allreduce(loc, tot, 4, MPI_DOUBLE, MPI_SUM, world);
  if (comm->me == 0) {
    int size = 4 * sizeof(double);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(tot, sizeof(double), 4, fp);
  }
}

void FixHeatFMFS::restart(char *buf)
{
  const double *list = (const double *) buf;
  const int me0 = comm->me == 0;
  q_conv = me0 ? list[0] : 0.0;
  q_rad = me0 ? list[1] : 0.0;
  q_dirichlet = me0 ? list[2] : 0.0;
  q_sources = me0 ? list[3] : 0.0;
}
