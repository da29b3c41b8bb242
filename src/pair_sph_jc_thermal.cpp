/* ----------------------------------------------------------------------
   sphcut - pair_style sph/jc-thermal

   Per pair (seed 003 eqs. 10-11, seed 000 eqs. 2 and 4):
     drho_i/dt = -rho_i sum_j V_j (v_j - v_i) . grad_i W_ij
     dv_i/dt   =  sum_j m_j (sigma_i/rho_i^2 + sigma_j/rho_j^2 - Pi_ij I
                            + f_ij^n (R_i + R_j)) . grad_i W_ij
     L_i       =  [sum_j V_j (v_j - v_i) (x) grad_i W_ij] B_i^-1,
     B_i       =  sum_j V_j (x_j - x_i) (x) grad_i W_ij    (renormalisation)
     du_i/dt   =  1/2 sum_j m_j (v_j - v_i) . M_ij . grad_i W_ij  (M: the bracket above;
                  makes kinetic + internal energy conserved by the discrete scheme)
     xsph_i    =  sum_j m_j / rho_ij (v_j - v_i) W_ij
   then per particle ds_i/dt from the Jaumann rate.  With the keyword
   hourglass kappa, a second pass over the pairs adds the hourglass control
   of sphcut::hourglass_pair (needs L_i of both particles of a pair).  The velocities are the
   predicted ones of fix sph/jc-thermal (column VEST), the stress and
   density its predictor (RHO_F, SF), so forces are computed once a step.
   Rigid tool particles (role TOOL) take no part in the mechanics.
------------------------------------------------------------------------- */

#include "pair_sph_jc_thermal.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include "sphcut_checks.h"
#include "sphcut_compat.h"
#include "sphcut_kernels.h"
#include "sphcut_model.h"
#include "sphcut_pair.h"
#include "sphcut_solid.h"
#include "sphcut_timer.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using sphcut::Material;

static constexpr int NREVERSE = sphcut::NACC_REVERSE;
enum CommMode { COMM_ACC = 0, COMM_HG = 1 };

// a particle's packed row: what its neighbours read of it (sphcut_pair.h PackedRow, the /kk pair's
// layout; sphcut::pack_row, unpack_i, unpack_j), at full width
using sphcut::NPK;
using sphcut::PK_M;
using sphcut::PK_VOL;

/* ---------------------------------------------------------------------- */

PairSPHJCThermal::PairSPHJCThermal(LAMMPS *lmp) :
    Pair(lmp), fix(nullptr), nmax(0), pack(nullptr), acc(nullptr), lgrad(nullptr), hgacc(nullptr),
    comm_mode(COMM_ACC)
{
  restartinfo = 1;
  single_enable = 0;
  one_coeff = 0;
  comm_reverse = NREVERSE;
  comm_forward = 9;    // hourglass control: L of the ghosts
}

PairSPHJCThermal::~PairSPHJCThermal()
{
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
  free_scratch();
}

void PairSPHJCThermal::free_scratch()
{
  memory->destroy(pack);
  memory->destroy(acc);
  memory->destroy(lgrad);
  memory->destroy(hgacc);
}

/* ---------------------------------------------------------------------- */

void PairSPHJCThermal::allocate()
{
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  for (int i = 0; i <= n; i++)
    for (int j = 0; j <= n; j++) setflag[i][j] = 0;
  if (mdl.ntypes() != n) mdl.allocate(n);
}

void PairSPHJCThermal::grow_scratch(int n)
{
  if (n <= nmax) return;
  nmax = n;
  free_scratch();
  memory->create(pack, nmax, NPK, "pair:pack");
  memory->create(acc, nmax, sphcut::NACC, "pair:acc");
  if (mdl.hourglass_coefficient() > 0.0) {
    memory->create(lgrad, nmax, 9, "pair:lgrad");
    memory->create(hgacc, nmax, 4, "pair:hgacc");
  }
}

/* ----------------------------------------------------------------------
   pair_style and pair_coeff: parsed by the model (sphcut::Model::settings, coeff);
   setflag mirrors the pairs whose h or hdx pair_coeff gave
------------------------------------------------------------------------- */

void PairSPHJCThermal::settings(int narg, char **arg)
{
  mdl.settings(lmp, narg, arg);
}

void PairSPHJCThermal::coeff(int narg, char **arg)
{
  if (!allocated) allocate();
  mdl.coeff(lmp, narg, arg);
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = mdl.length_set(i, j) ? 1 : 0;
}

/* ---------------------------------------------------------------------- */

void PairSPHJCThermal::init_style()
{
  fix = nullptr;
  for (auto *f : sphcut::fixes_by_style(modify, "^sph/jc-thermal")) fix = dynamic_cast<sphcut::StateOwner *>(f);
  if (!fix) error->all(FLERR, "Pair sph/jc-thermal requires fix sph/jc-thermal");
  fix->attach(this);
  const double hourglass = mdl.hourglass_coefficient();
  if (hourglass > 0.0 && !mdl.renormalised())
    error->all(FLERR, "Pair sph/jc-thermal: hourglass {} needs correction yes (the linear-field prediction "
               "uses the renormalised velocity gradient)", hourglass);
  // scratch arrays of the hourglass control: allocated with the others
  if (hourglass > 0.0 && !lgrad) {
    nmax = 0;
    free_scratch();
  }
  // the scheme applies no unit conversion factors: only self-consistent unit styles
  const std::string units = update->unit_style;
  if (units != "si" && units != "cgs" && units != "micro" && units != "nano" && units != "lj")
    error->all(FLERR, "Pair sph/jc-thermal needs a self-consistent unit style (si, cgs, micro, nano, lj), got {}",
               units);
  // bonds and special lists would silently remove SPH neighbours from the list
  if (atom->molecular != 0)
    error->all(FLERR, "Pair sph/jc-thermal requires an atomic (non-molecular) atom style, got {}",
               atom->atom_style);

  // every particle has a mass > 0 (else NaN forces, or a misleading error about the spacing)
  sphcut::check_masses(lmp, "Pair sph/jc-thermal");
  mdl.set_spacing(lmp);    // particle spacing per type, from the masses
  neighbor->request(this, instance_me);
}

/* ---------------------------------------------------------------------- */

double PairSPHJCThermal::init_one(int i, int j)
{
  return mdl.mix(lmp, i, j);
}

/* ---------------------------------------------------------------------- */

void PairSPHJCThermal::compute(int eflag, int vflag)
{
  sphcut::ScopedTimer timer(cpu_time);
  ev_init(eflag, vflag);

  const int *type = atom->type;
  const int *mask = atom->mask;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  double **x = atom->x;
  double **f = atom->f;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int newton_pair = force->newton_pair;
  const int dim = domain->dimension;
  const int groupbit = fix->solidbit, toolbit = fix->toolbit, clampbit = fix->clampbit;
  double **st = fix->state;
  using F = sphcut::StateLayout;
  const Material *mat = mdl.materials();
  const int correction = mdl.renormalised();
  const double hourglass = mdl.hourglass_coefficient();

  grow_scratch(atom->nmax);

  // per particle (local + ghost): its packed row, with the Cauchy and artificial stress of the
  // force state; mass 0 marks particles outside the SPH solid (not in the group, tool)
  const int any_as = mdl.any_artificial_stress();
  const int nacc = newton_pair ? nall : nlocal;
  for (int i = 0; i < nall; i++) {
    if (i < nacc)
      for (int k = 0; k < sphcut::NACC; k++) acc[i][k] = 0.0;
    double *p = pack[i];
    if (!(mask[i] & groupbit) || sphcut::role_from_mask(mask[i], toolbit, clampbit) == F::TOOL) {
      sphcut::pack_outside(x[i], type[i], p);
      continue;
    }
    sphcut::pack_row(mat[type[i]], dim, any_as, x[i], type[i], st[i], rmass ? rmass[i] : mass[type[i]], p);
  }

  if (dim == 2) {
    if (newton_pair) pair_loop<2, 1>(any_as);
    else pair_loop<2, 0>(any_as);
  } else {
    if (newton_pair) pair_loop<3, 1>(any_as);
    else pair_loop<3, 0>(any_as);
  }

  // the force sums into atom->f (ghosts' through LAMMPS' reverse communication of f)
  for (int i = 0; i < nacc; i++)
    for (int a = 0; a < 3; a++) f[i][a] += acc[i][sphcut::ACC_F + a];
  if (newton_pair) sphcut::reverse_comm(comm, this);

  // hourglass control: a second pass over the pairs with L of both particles
  if (hourglass > 0.0) hourglass_forces();

  // per particle: density rate, velocity gradient, Jaumann stress rate
  for (int i = 0; i < nlocal; i++) {
    if (pack[i][PK_M] == 0.0) continue;
    double *s = st[i];
    double drho, ds[6], du;
    sphcut::particle_rates(mat[type[i]], dim, correction, acc[i], &s[F::SF], s[F::RHO_F], drho, ds, du);
    s[F::DRHO] += drho;
    for (int k = 0; k < 6; k++) s[F::DS + k] += ds[k];
    s[F::DU] += du;
    if (hourglass > 0.0) s[F::DU] += hgacc[i][3];
    for (int a = 0; a < 3; a++) s[F::XSPH + a] = acc[i][sphcut::ACC_XS + a];
  }

  if (vflag_fdotr) virial_fdotr_compute();
}

/* ----------------------------------------------------------------------
   the neighbour loop: per pair arithmetic in sphcut::pair_terms, here only
   the gathering of inputs from the packed rows and the accumulation (i in
   a local row, added once; j, with newton or when local, in its row)
------------------------------------------------------------------------- */

template <int DIM, int NEWTON> void PairSPHJCThermal::pair_loop(int any_as)
{
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const double *const *pk = pack;

  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double *pi = pk[i];
    const double mi = pi[PK_M];
    if (mi == 0.0) continue;    // not in the SPH solid
    const sphcut::TypePair *tpi = mdl.type_pair_row(type[i]);
    const double vi = pi[PK_VOL];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    if ((int) nbr_j.size() < jnum) {
      nbr_j.resize(jnum);
      nbr_s.resize(jnum);
    }

    // the inputs of pair i-j from the packed rows; false beyond the cutoff, or when j is not
    // in the SPH solid
    sphcut::PairIn in{};    // (zeroed: GCC cannot see that the second pass gathers only pairs the first accepted)
    double xi[3], veli[3];
    sphcut::unpack_i(pi, any_as, xi, veli, in);
    auto gather = [&](const double *pj) {
      double mj, Vj;
      return sphcut::unpack_j(pj, tpi, xi, veli, in, mj, Vj);
    };

    // first pass: the pairs within the cutoff and their scalars (the long chains of sqrt,
    // divisions and kernel, which the processor overlaps from pair to pair in a short loop)
    int npair = 0;
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!gather(pk[j])) continue;
      sphcut::pair_scalars<DIM>(mdl.kernel(), in, nbr_s[npair]);
      nbr_j[npair++] = j;
    }

    // second pass: the bracket and the sums, i's kept local, j's in its row
    double acci[sphcut::NACC];
    for (int k = 0; k < sphcut::NACC; k++) acci[k] = 0.0;
    for (int n = 0; n < npair; n++) {
      const int j = nbr_j[n];
      const double *pj = pk[j];
      gather(pj);
      sphcut::PairOut out;
      sphcut::pair_finish<DIM>(in, nbr_s[n], out);
      const double mj = pj[PK_M], mm = mi * mj;
      sphcut::pair_accumulate<DIM>(in, out, mm, mj, pj[PK_VOL], 1.0, [&acci](int k, double val) { acci[k] += val; });
      if (NEWTON || j < nlocal) {
        double *accj = acc[j];
        sphcut::pair_accumulate<DIM>(in, out, mm, mi, vi, -1.0, [accj](int k, double val) { accj[k] += val; });
      }
    }
    double *acc_i = acc[i];
    for (int k = 0; k < sphcut::NACC; k++) acc_i[k] += acci[k];
  }
}

/* ----------------------------------------------------------------------
   hourglass control (keyword hourglass, sphcut::hourglass_pair): L of the
   local particles from their summed rows, L of the ghosts by forward
   communication, then the pairs again: force into atom->f (ghosts' through
   LAMMPS' reverse communication of f), du into hgacc (ghosts' by reverse
   communication), added to the rate of u with the others
------------------------------------------------------------------------- */

void PairSPHJCThermal::hourglass_forces()
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const int newton_pair = force->newton_pair;
  const int dim = domain->dimension;
  for (int i = 0; i < nlocal; i++) {
    if (pack[i][PK_M] == 0.0) {
      for (int k = 0; k < 9; k++) lgrad[i][k] = 0.0;
      continue;
    }
    sphcut::particle_velocity_gradient(dim, mdl.renormalised(), acc[i], lgrad[i]);
  }
  comm_mode = COMM_HG;
  sphcut::forward_comm(comm, this);
  const int nacc = newton_pair ? nall : nlocal;
  for (int i = 0; i < nacc; i++)
    for (int k = 0; k < 4; k++) hgacc[i][k] = 0.0;
  if (dim == 2) {
    if (newton_pair) hourglass_loop<2, 1>();
    else hourglass_loop<2, 0>();
  } else {
    if (newton_pair) hourglass_loop<3, 1>();
    else hourglass_loop<3, 0>();
  }
  double **f = atom->f;
  for (int i = 0; i < nacc; i++)
    for (int a = 0; a < 3; a++) f[i][a] += hgacc[i][a];
  if (newton_pair) sphcut::reverse_comm(comm, this);
  comm_mode = COMM_ACC;
}

template <int DIM, int NEWTON> void PairSPHJCThermal::hourglass_loop()
{
  const int *type = atom->type;
  const int nlocal = atom->nlocal;
  const double *const *pk = pack;
  const int inum = list->inum;
  const int *ilist = list->ilist;
  const int *numneigh = list->numneigh;
  int **firstneigh = list->firstneigh;

  for (int ii = 0; ii < inum; ii++) {
    const int i = ilist[ii];
    const double *pi = pk[i];
    const double mi = pi[PK_M];
    if (mi == 0.0) continue;
    const sphcut::TypePair *tpi = mdl.type_pair_row(type[i]);
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    sphcut::PairIn in;
    double xi[3], veli[3];
    sphcut::unpack_i(pi, 0, xi, veli, in);
    double hi[4] = {0.0, 0.0, 0.0, 0.0};
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      double mj, Vj;
      if (!sphcut::unpack_j(pk[j], tpi, xi, veli, in, mj, Vj)) continue;
      double w, wfac;
      sphcut::kernel_w_gradfac_pre(mdl.kernel(), sqrt(in.r2), in.inv_h, in.wnorm, w, wfac);
      double Mg[3], work;
      sphcut::hourglass_pair<DIM>(mdl.hourglass_coefficient(), in, wfac, lgrad[i], lgrad[j], Mg, work);
      const double mm = mi * mj;
      for (int a = 0; a < DIM; a++) hi[a] += mm * Mg[a];
      hi[3] += mj * 0.5 * work;
      if (NEWTON || j < nlocal) {
        for (int a = 0; a < DIM; a++) hgacc[j][a] -= mm * Mg[a];
        hgacc[j][3] += mi * 0.5 * work;
      }
    }
    for (int k = 0; k < 4; k++) hgacc[i][k] += hi[k];
  }
}

/* ---------------------------------------------------------------------- */

int PairSPHJCThermal::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  if (comm_mode == COMM_HG) {
    for (int i = first; i < first + n; i++) buf[m++] = hgacc[i][3];
    return m;
  }
  for (int i = first; i < first + n; i++)
    for (int k = sphcut::ACC_FIRST_REVERSE; k < sphcut::NACC; k++) buf[m++] = acc[i][k];
  return m;
}

void PairSPHJCThermal::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  if (comm_mode == COMM_HG) {
    for (int ii = 0; ii < n; ii++) hgacc[list[ii]][3] += buf[m++];
    return;
  }
  for (int ii = 0; ii < n; ii++) {
    const int i = list[ii];
    for (int k = sphcut::ACC_FIRST_REVERSE; k < sphcut::NACC; k++) acc[i][k] += buf[m++];
  }
}

// forward communication: only the hourglass control's L (COMM_HG)
int PairSPHJCThermal::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  int m = 0;
  for (int ii = 0; ii < n; ii++)
    for (int k = 0; k < 9; k++) buf[m++] = lgrad[list[ii]][k];
  return m;
}

void PairSPHJCThermal::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < 9; k++) lgrad[i][k] = buf[m++];
}

/* ---------------------------------------------------------------------- */

void PairSPHJCThermal::write_restart(FILE *fp)
{
  mdl.write_restart(fp);    // field by field, with a format version (sphcut::Model)
}

void PairSPHJCThermal::read_restart(FILE *fp)
{
  allocate();
  mdl.read_restart(lmp, fp);    // this format and the raw record of older files
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) setflag[i][j] = mdl.length_set(i, j) ? 1 : 0;
}

void PairSPHJCThermal::write_restart_settings(FILE *fp)
{
  mdl.write_settings(fp);
}

void PairSPHJCThermal::read_restart_settings(FILE *fp)
{
  int version;
  mdl.read_settings(lmp, fp, version);
}

double PairSPHJCThermal::memory_usage()
{
  return (double) nmax * (NPK + sphcut::NACC + (mdl.hourglass_coefficient() > 0.0 ? 13 : 0)) * sizeof(double);
}
