/* ----------------------------------------------------------------------
   sphcut - compute surface/lambda

   B_i = sum_j V_j (x_j - x_i) (x) grad_i W_ij (the inverse of the
   renormalisation matrix A of seed 003 eq. 14); lambda_i = minimum
   eigenvalue of its symmetric part: ~1 inside, -> 0 at the surface.
   A particle is a surface particle when lambda < threshold (0.75).
   The outward normal is -A^T sum_j V_j grad_i W_ij, normalised.
------------------------------------------------------------------------- */

#include "compute_surface_lambda.h"

#include "atom.h"
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

using namespace LAMMPS_NS;

/* ----------------------------------------------------------------------
   compute ID group surface/lambda [threshold L] [tool yes|no] [every N]
------------------------------------------------------------------------- */

ComputeSurfaceLambda::ComputeSurfaceLambda(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), threshold(0.75), every(1), tool_hides(1), last_step(-1), last_neigh(-1),
    nmax(0), out(nullptr), list(nullptr), fix(nullptr), model(nullptr)
{
  int iarg = 3;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Compute surface/lambda: keyword {} needs a value", kw);
    const std::string val = arg[iarg + 1];
    if (kw == "threshold") {
      threshold = utils::numeric(FLERR, val.c_str(), false, lmp);
      if (threshold <= 0.0 || threshold >= 1.0)
        error->all(FLERR, "Compute surface/lambda: threshold must be in (0,1), got {}", threshold);
    } else if (kw == "tool") {
      if (val == "yes") tool_hides = 1;
      else if (val == "no") tool_hides = 0;
      else error->all(FLERR, "Compute surface/lambda: tool must be yes or no, got {}", val);
    } else if (kw == "every") {
      every = sphcut::parse_int(lmp, "Compute surface/lambda", kw, val.c_str());
    } else {
      error->all(FLERR, "Compute surface/lambda: unknown keyword {}", kw);
    }
    iarg += 2;
  }
  peratom_flag = 1;
  size_peratom_cols = NCOLS;
}

ComputeSurfaceLambda::~ComputeSurfaceLambda()
{
  memory->destroy(out);
}

void ComputeSurfaceLambda::init()
{
  fix = FixSPHJCThermal::require(lmp, "Compute surface/lambda", groupbit, group->names[igroup], &model);
  fix->attach(this);
  // perpetual full list: the flags are needed every step by fix heat/fmfs
  sphcut::request_full_list(neighbor, this, instance_me, false, false);
  const int nt = atom->ntypes + 1;
  tpair.assign((size_t) nt * nt, sphcut::ThermalPair{});
  for (int it = 1; it < nt; it++)
    for (int jt = 1; jt < nt; jt++)
      tpair[(size_t) it * nt + jt] =
          sphcut::thermal_pair(model->kernel(), domain->dimension, model->smoothing_length(it, jt), 0.0, 0.0);
}

void ComputeSurfaceLambda::init_list(int, NeighList *ptr)
{
  list = ptr;
}

/* ----------------------------------------------------------------------
   values are kept between invocations only while the atom order is the
   same (no reneighboring since), fewer than `every` steps have passed, and
   outside the setup of a run
------------------------------------------------------------------------- */

void ComputeSurfaceLambda::compute_peratom()
{
  sphcut::ScopedTimer timer(cpu_time);
  if (!begin_step()) return;
  if (domain->dimension == 2) compute_dim<2>();
  else compute_dim<3>();
}

bool ComputeSurfaceLambda::begin_step()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    nmax = atom->nmax;
    memory->destroy(out);
    memory->create(out, nmax, NCOLS, "surface/lambda:out");
    array_atom = out;
    last_step = -1;
  }
  return recompute_due();
}

// whether the values must be computed now (and, if so, the step and list build they are for):
// the setup of a run always recomputes, as it rebuilds the lists (and may re-sort the atoms) at
// the time step the previous run ended on, so lastcall alone cannot tell
bool ComputeSurfaceLambda::recompute_due()
{
  if (last_step >= 0 && !update->setupflag && neighbor->lastcall <= last_neigh &&
      update->ntimestep - last_step < every)
    return false;
  last_step = update->ntimestep;
  last_neigh = neighbor->lastcall;
  return true;
}

template <int DIM> void ComputeSurfaceLambda::compute_dim()
{
  double **x = atom->x;
  const int *mask = atom->mask;
  const int *type = atom->type;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  double **st = fix->state;
  const int kernel = model->kernel(), nt = atom->ntypes + 1;
  const sphcut::ThermalPair *tp = tpair.data();
  using F = FixSPHJCThermal;

  for (int i = 0; i < atom->nlocal; i++)
    for (int k = 0; k < NCOLS; k++) out[i][k] = 0.0;

  sphcut::SupportMoments<DIM> m;
  for (int ii = 0; ii < list->inum; ii++) {
    const int i = list->ilist[ii];
    if (!(mask[i] & groupbit)) continue;
    const int itool = fix->role_of(mask[i]) == F::TOOL;
    const sphcut::ThermalPair *tpi = tp + type[i] * nt;
    sphcut::support_zero<DIM>(m, false);
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!(mask[j] & groupbit)) continue;
      if (!tool_hides && (fix->role_of(mask[j]) == F::TOOL) != itool) continue;
      double r[3], r2, wfac, ir2;    // r = x_j - x_i
      if (!sphcut::thermal_support(tpi[type[j]], kernel, x[j], x[i], r, r2, wfac, ir2)) continue;
      const double vj = (rmass ? rmass[j] : mass[type[j]]) / st[j][F::RHO_F];
      sphcut::support_add_surface<DIM>(m, r, -wfac * vj);
    }
    double n[3];
    const double lam = sphcut::support_surface<DIM>(m, threshold, n);
    out[i][LAMBDA] = lam;
    out[i][FLAG] = lam < threshold ? 1.0 : 0.0;
    for (int a = 0; a < DIM; a++) out[i][NX + a] = n[a];
  }
}

double ComputeSurfaceLambda::memory_usage()
{
  return (double) nmax * NCOLS * sizeof(double);
}
