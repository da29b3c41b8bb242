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
#include "fix_sph_jc_thermal.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include "sphcut_checks.h"
#include "sphcut_compat.h"
#include "sphcut_kernels.h"
#include "sphcut_pair.h"
#include "sphcut_timer.h"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;
using sphcut::Material;

static constexpr int NREVERSE = sphcut::NACC_REVERSE;
enum CommMode { COMM_ACC = 0, COMM_HG = 1 };

// a particle's packed row: what its neighbours read of it (position, predicted velocity, density,
// mass (0: not in the SPH solid, skipped), volume m/rho, sigma/rho^2, artificial stress and
// whether it is nonzero), one contiguous row instead of pieces of x, the state row, mask, type,
// mass and the stresses
enum Pack { PK_X = 0, PK_V = 3, PK_RHO = 6, PK_M = 7, PK_VOL = 8, PK_HASR = 9, PK_A = 10, PK_R = 16, NPK = 22 };
static constexpr double UNSET = -1.0e300;
// the material record of restart files written before the pressure cutoff pmin (its last field)
static constexpr int MATSIZE_NO_PMIN = (int) offsetof(Material, pmin);
static_assert(offsetof(Material, pmin) + sizeof(double) == sizeof(Material),
              "pmin must stay the last field of Material (restart files of older versions)");

/* ---------------------------------------------------------------------- */

PairSPHJCThermal::PairSPHJCThermal(LAMMPS *lmp) :
    Pair(lmp), mat(nullptr), hlen(nullptr), hdx(nullptr), wdp(nullptr), dp(nullptr), tpair(nullptr),
    fix(nullptr), nmax(0), pack(nullptr), acc(nullptr), lgrad(nullptr), hgacc(nullptr), comm_mode(COMM_ACC),
    restart_matsize((int) sizeof(Material))
{
  restartinfo = 1;
  single_enable = 0;
  one_coeff = 0;
  comm_reverse = NREVERSE;
  comm_forward = 9;    // hourglass control: L of the ghosts
  kernel_kind = sphcut::KERNEL_CUBIC;
  correction = 1;
  hourglass = 0.0;
}

PairSPHJCThermal::~PairSPHJCThermal()
{
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(hlen);
    memory->destroy(hdx);
    memory->destroy(wdp);
    memory->destroy(dp);
    memory->destroy(tpair);
    delete[] mat;
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
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(hlen, n + 1, n + 1, "pair:h");
  memory->create(hdx, n + 1, n + 1, "pair:hdx");
  memory->create(wdp, n + 1, n + 1, "pair:wdp");
  memory->create(dp, n + 1, "pair:dp");
  memory->create(tpair, n + 1, n + 1, "pair:tpair");
  mat = new Material[n + 1];
  memset(mat, 0, (n + 1) * sizeof(Material));
  for (int i = 0; i <= n; i++) {
    dp[i] = 0.0;
    for (int j = 0; j <= n; j++) {
      setflag[i][j] = 0;
      hlen[i][j] = 0.0;
      hdx[i][j] = 0.0;
      wdp[i][j] = 0.0;
    }
  }
}

void PairSPHJCThermal::grow_scratch(int n)
{
  if (n <= nmax) return;
  nmax = n;
  free_scratch();
  memory->create(pack, nmax, NPK, "pair:pack");
  memory->create(acc, nmax, sphcut::NACC, "pair:acc");
  if (hourglass > 0.0) {
    memory->create(lgrad, nmax, 9, "pair:lgrad");
    memory->create(hgacc, nmax, 4, "pair:hgacc");
  }
}

/* ----------------------------------------------------------------------
   pair_style sph/jc-thermal [kernel cubic|wendland|hyperbolic] [correction yes|no]
                             [hourglass kappa]
------------------------------------------------------------------------- */

void PairSPHJCThermal::settings(int narg, char **arg)
{
  hourglass = 0.0;    // a repeated pair_style without the keyword switches it off
  int iarg = 0;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair sph/jc-thermal: keyword {} needs a value", kw);
    const std::string val = arg[iarg + 1];
    if (kw == "kernel") {
      if (val == "cubic") kernel_kind = sphcut::KERNEL_CUBIC;
      else if (val == "wendland") kernel_kind = sphcut::KERNEL_WENDLAND;
      else if (val == "hyperbolic") kernel_kind = sphcut::KERNEL_HYPERBOLIC;
      else error->all(FLERR, "Pair sph/jc-thermal: unknown kernel {} (cubic, wendland, hyperbolic)", val);
    } else if (kw == "correction") {
      if (val == "yes") correction = 1;
      else if (val == "no") correction = 0;
      else error->all(FLERR, "Pair sph/jc-thermal: correction must be yes or no, got {}", val);
    } else if (kw == "hourglass") {
      hourglass = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (hourglass < 0.0 || hourglass > 10.0)
        error->all(FLERR, "Pair sph/jc-thermal: hourglass must be in [0,10], got {}", hourglass);
    } else {
      error->all(FLERR, "Pair sph/jc-thermal: unknown pair_style keyword {}", kw);
    }
    iarg += 2;
  }
}

/* ----------------------------------------------------------------------
   pair_coeff I J keyword value ...
   material keywords set the material of the types t with t in I and J;
   h / hdx set the smoothing length of every pair (I,J)
------------------------------------------------------------------------- */

void PairSPHJCThermal::coeff(int narg, char **arg)
{
  if (narg < 4) error->all(FLERR, "Pair sph/jc-thermal: pair_coeff needs I J and keyword/value pairs");
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  // values not given stay UNSET so that defaults and mandatory checks can be applied
  Material m;
  double *fields[] = {&m.rho0, &m.E, &m.nu, &m.A, &m.B, &m.C, &m.n, &m.m, &m.epsdot0,
                      &m.Tref, &m.Tmelt, &m.cp, &m.chi, &m.kappa, &m.av_alpha, &m.av_beta,
                      &m.as_eps, &m.as_n, &m.xsph, &m.gamma0, &m.s_hug};
  const char *names[] = {"rho0", "E", "nu", "A", "B", "C", "n", "m", "epsdot0", "Tref", "Tmelt",
                         "cp", "chi", "k", "alpha", "beta", "as_eps", "as_n", "xsph", "gamma0", "s"};
  const int nfields = sizeof(names) / sizeof(names[0]);
  for (int k = 0; k < nfields; k++) *fields[k] = UNSET;
  m.eos = sphcut::EOS_LINEAR;
  m.pmin = 0.0;    // no pressure cutoff
  double h = 0.0, hx = 0.0;
  int nmat = 0;

  int iarg = 2;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair sph/jc-thermal: pair_coeff keyword {} needs a value", kw);
    const char *val = arg[iarg + 1];
    if (kw == "h") {
      h = utils::numeric(FLERR, val, false, lmp);
      if (h <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: h must be > 0, got {}", h);
    } else if (kw == "hdx") {
      hx = utils::numeric(FLERR, val, false, lmp);
      if (hx <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: hdx must be > 0, got {}", hx);
    } else if (kw == "eos") {
      const std::string e = val;
      if (e == "linear") m.eos = sphcut::EOS_LINEAR;
      else if (e == "mie-gruneisen") m.eos = sphcut::EOS_MIE_GRUNEISEN;
      else error->all(FLERR, "Pair sph/jc-thermal: unknown eos {} (linear, mie-gruneisen)", e);
      nmat++;
    } else if (kw == "pmin") {
      // tension cutoff of the pressure: a negative pressure, or none (the default)
      const std::string v = val;
      if (v == "none") m.pmin = 0.0;
      else {
        if (!utils::is_double(v))
          error->all(FLERR, "Pair sph/jc-thermal: pmin must be a negative pressure or none, got {}", v);
        m.pmin = utils::numeric(FLERR, val, false, lmp);
        if (!(m.pmin < 0.0))
          error->all(FLERR, "Pair sph/jc-thermal: pmin must be < 0 (a tensile pressure) or none, got {}", v);
      }
      nmat++;
    } else {
      int k = 0;
      while (k < nfields && kw != names[k]) k++;
      if (k == nfields) error->all(FLERR, "Pair sph/jc-thermal: unknown pair_coeff keyword {}", kw);
      *fields[k] = utils::numeric(FLERR, val, false, lmp);
      nmat++;
    }
    iarg += 2;
  }

  if (nmat) {
    // mandatory values
    const char *mandatory[] = {"rho0", "E", "nu"};
    for (int k = 0; k < 3; k++)
      if (*fields[k] == UNSET)
        error->all(FLERR, "Pair sph/jc-thermal: material value {} is missing in pair_coeff {} {}",
                   mandatory[k], arg[0], arg[1]);
    if (m.rho0 <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: rho0 must be > 0, got {}", m.rho0);
    if (m.E <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: E must be > 0, got {}", m.E);
    if (m.nu <= -1.0 || m.nu >= 0.5)
      error->all(FLERR, "Pair sph/jc-thermal: nu must be in (-1,0.5), got {}", m.nu);
    m.plastic = m.A != UNSET;
    if (m.plastic) {
      if (m.B == UNSET) error->all(FLERR, "Pair sph/jc-thermal: Johnson-Cook value B is missing (A is given)");
      if (m.n == UNSET) error->all(FLERR, "Pair sph/jc-thermal: Johnson-Cook value n is missing (A is given)");
      if (m.A <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: A must be > 0, got {}", m.A);
      if (m.B < 0.0) error->all(FLERR, "Pair sph/jc-thermal: B must be >= 0, got {}", m.B);
      if (m.n <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: n must be > 0, got {}", m.n);
      if (m.m != UNSET && (m.Tmelt == UNSET || m.Tref == UNSET))
        error->all(FLERR, "Pair sph/jc-thermal: Johnson-Cook m needs Tref and Tmelt");
    } else {
      const char *jc[] = {"B", "C", "n", "m", "epsdot0"};
      double *jcv[] = {&m.B, &m.C, &m.n, &m.m, &m.epsdot0};
      for (int k = 0; k < 5; k++)
        if (*jcv[k] != UNSET)
          error->all(FLERR, "Pair sph/jc-thermal: Johnson-Cook value {} given without A", jc[k]);
    }
    if (m.eos == sphcut::EOS_MIE_GRUNEISEN && (m.gamma0 == UNSET || m.s_hug == UNSET))
      error->all(FLERR, "Pair sph/jc-thermal: eos mie-gruneisen needs gamma0 and s");
    if (m.eos != sphcut::EOS_MIE_GRUNEISEN && (m.gamma0 != UNSET || m.s_hug != UNSET))
      error->all(FLERR, "Pair sph/jc-thermal: gamma0 and s are Mie-Grueneisen values (add eos mie-gruneisen)");
    if (m.eos == sphcut::EOS_MIE_GRUNEISEN && m.gamma0 > 0.0 && (m.cp == UNSET || m.cp <= 0.0))
      error->all(FLERR, "Pair sph/jc-thermal: eos mie-gruneisen with gamma0 > 0 needs cp (thermal pressure)");
    if (m.C != UNSET && m.C < 0.0) error->all(FLERR, "Pair sph/jc-thermal: C must be >= 0, got {}", m.C);
    if (m.m != UNSET && m.m <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: m must be > 0, got {}", m.m);
    if (m.Tref != UNSET && m.Tref < 0.0) error->all(FLERR, "Pair sph/jc-thermal: Tref must be >= 0, got {}", m.Tref);
    if (m.as_n != UNSET && m.as_n <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: as_n must be > 0, got {}", m.as_n);
    // defaults
    auto def = [](double &v, double d) { if (v == UNSET) v = d; };
    def(m.B, 0.0);
    def(m.C, 0.0);
    def(m.n, 1.0);
    def(m.m, 1.0);
    def(m.epsdot0, 1.0);
    def(m.Tref, 300.0);
    def(m.Tmelt, 1.0e30);    // no thermal softening
    def(m.cp, 0.0);
    def(m.chi, 0.9);
    def(m.kappa, 0.0);
    def(m.av_alpha, 1.0);
    def(m.av_beta, 1.0);
    def(m.as_eps, 0.3);
    def(m.as_n, 4.0);
    def(m.xsph, 0.5);
    def(m.gamma0, 0.0);
    def(m.s_hug, 0.0);
    if (m.epsdot0 <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: epsdot0 must be > 0, got {}", m.epsdot0);
    if (m.Tmelt <= m.Tref)
      error->all(FLERR, "Pair sph/jc-thermal: Tmelt {} must be above Tref {}", m.Tmelt, m.Tref);
    if (m.cp < 0.0) error->all(FLERR, "Pair sph/jc-thermal: cp must be >= 0, got {}", m.cp);
    if (m.chi < 0.0 || m.chi > 1.0) error->all(FLERR, "Pair sph/jc-thermal: chi must be in [0,1], got {}", m.chi);
    if (m.kappa < 0.0) error->all(FLERR, "Pair sph/jc-thermal: k must be >= 0, got {}", m.kappa);
    if (m.plastic && m.chi > 0.0 && m.cp == 0.0)
      error->all(FLERR, "Pair sph/jc-thermal: cp is missing (needed for plastic heating with chi > 0; "
                 "set chi 0 for an isothermal run)");
    if (m.av_alpha < 0.0 || m.av_beta < 0.0)
      error->all(FLERR, "Pair sph/jc-thermal: alpha and beta must be >= 0");
    if (m.as_eps < 0.0) error->all(FLERR, "Pair sph/jc-thermal: as_eps must be >= 0, got {}", m.as_eps);
    if (m.xsph < 0.0 || m.xsph > 1.0)
      error->all(FLERR, "Pair sph/jc-thermal: xsph must be in [0,1], got {}", m.xsph);
    sphcut::material_derive(m);
    m.defined = 1;
  }
  if (h > 0.0 && hx > 0.0) error->all(FLERR, "Pair sph/jc-thermal: give either h or hdx, not both");

  // material: the types t that lie in both ranges (the like pairs t,t)
  int nlike = 0;
  for (int t = std::max(ilo, jlo); t <= std::min(ihi, jhi); t++) {
    if (nmat) mat[t] = m;
    nlike++;
  }
  if (nmat && nlike == 0)
    error->all(FLERR, "Pair sph/jc-thermal: material keywords need pair_coeff I I (or * *), got {} {}",
               arg[0], arg[1]);
  if (h > 0.0 || hx > 0.0) {
    // pair_coeff 2 1 sets the pair (1,2)
    for (int i = ilo; i <= ihi; i++)
      for (int j = jlo; j <= jhi; j++) {
        const int a = std::min(i, j), b = std::max(i, j);
        hlen[a][b] = h;
        hdx[a][b] = hx;
        setflag[a][b] = 1;
      }
  } else if (!nmat) {
    error->all(FLERR, "Pair sph/jc-thermal: pair_coeff {} {} sets nothing", arg[0], arg[1]);
  }
}

/* ---------------------------------------------------------------------- */

void PairSPHJCThermal::init_style()
{
  fix = nullptr;
  for (int i = 0; i < modify->nfix; i++)
    if (utils::strmatch(modify->fix[i]->style, "^sph/jc-thermal"))
      fix = dynamic_cast<FixSPHJCThermal *>(modify->fix[i]);
  if (!fix) error->all(FLERR, "Pair sph/jc-thermal requires fix sph/jc-thermal");
  fix->attach(this);
  if (hourglass > 0.0 && !correction)
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

  // particle spacing per type: (m / rho0)^(1/d), mass from mass or mean rmass
  const int n = atom->ntypes;
  const int dim = domain->dimension;
  std::vector<double> msum(n + 1, 0.0), cnt(n + 1, 0.0), gsum(n + 1), gcnt(n + 1);
  for (int i = 0; i < atom->nlocal; i++) {
    msum[atom->type[i]] += atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    cnt[atom->type[i]] += 1.0;
  }
  MPI_Allreduce(msum.data(), gsum.data(), n + 1, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(cnt.data(), gcnt.data(), n + 1, MPI_DOUBLE, MPI_SUM, world);
  for (int t = 1; t <= n; t++) {
    dp[t] = 0.0;
    if (mat[t].defined && gcnt[t] > 0.0) dp[t] = pow(gsum[t] / gcnt[t] / mat[t].rho0, 1.0 / dim);
  }
  neighbor->request(this, instance_me);
}

/* ---------------------------------------------------------------------- */

double PairSPHJCThermal::init_one(int i, int j)
{
  if (!mat[i].defined) error->all(FLERR, "Pair sph/jc-thermal: no material for atom type {} (pair_coeff {} {} rho0 ...)", i, i, i);
  if (!mat[j].defined) error->all(FLERR, "Pair sph/jc-thermal: no material for atom type {} (pair_coeff {} {} rho0 ...)", j, j, j);
  double dpij = 0.5 * (dp[i] + dp[j]);
  if (!setflag[i][j]) {
    // mix: mean of the like-type smoothing lengths
    if (!setflag[i][i] || !setflag[j][j])
      error->all(FLERR, "Pair sph/jc-thermal: smoothing length (h or hdx) not set for types {} {}", i, j);
    const double hi = hdx[i][i] > 0.0 ? hdx[i][i] * dp[i] : hlen[i][i];
    const double hj = hdx[j][j] > 0.0 ? hdx[j][j] * dp[j] : hlen[j][j];
    hlen[i][j] = 0.5 * (hi + hj);
    hdx[i][j] = 0.0;
  } else if (hdx[i][j] > 0.0) {
    if (dpij <= 0.0)
      error->all(FLERR, "Pair sph/jc-thermal: hdx needs atoms of types {} {} to derive the spacing", i, j);
    hlen[i][j] = hdx[i][j] * dpij;
  }
  if (hlen[i][j] <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: smoothing length of types {} {} is not positive", i, j);
  hlen[j][i] = hlen[i][j];
  hdx[j][i] = hdx[i][j];
  if (dpij <= 0.0) dpij = hlen[i][j] / 1.2;
  wdp[i][j] = wdp[j][i] = sphcut::kernel_w(kernel_kind, domain->dimension, dpij, hlen[i][j]);
  tpair[i][j] = tpair[j][i] = sphcut::mix_type_pair(mat[i], mat[j], hlen[i][j], wdp[i][j], kernel_kind, domain->dimension);
  return sphcut::support_radius(hlen[i][j]);
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
  const int groupbit = fix->groupbit;
  double **st = fix->state;
  using F = FixSPHJCThermal;

  grow_scratch(atom->nmax);

  // per particle (local + ghost): its packed row, with the Cauchy and artificial stress of the
  // force state; mass 0 marks particles outside the SPH solid (not in the group, tool)
  int any_as = 0;
  for (int t = 1; t <= atom->ntypes; t++)
    if (mat[t].defined && mat[t].as_eps > 0.0) any_as = 1;
  const int nacc = newton_pair ? nall : nlocal;
  for (int i = 0; i < nall; i++) {
    if (i < nacc)
      for (int k = 0; k < sphcut::NACC; k++) acc[i][k] = 0.0;
    double *p = pack[i];
    for (int a = 0; a < 3; a++) p[PK_X + a] = x[i][a];
    if (!(mask[i] & groupbit) || fix->role_of(mask[i]) == F::TOOL) {
      p[PK_M] = 0.0;
      continue;
    }
    const double *s = st[i];
    const double m = rmass ? rmass[i] : mass[type[i]];
    for (int a = 0; a < 3; a++) p[PK_V + a] = s[F::VEST + a];
    p[PK_RHO] = s[F::RHO_F];
    p[PK_M] = m;
    p[PK_VOL] = m / s[F::RHO_F];
    sphcut::particle_stress(mat[type[i]], dim, any_as, s[F::RHO_F], s[F::TEMP_F], &s[F::SF], &p[PK_A], &p[PK_R]);
    p[PK_HASR] = 0.0;
    if (any_as)
      for (int k = 0; k < 6; k++)
        if (p[PK_R + k] != 0.0) p[PK_HASR] = 1.0;
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
    const sphcut::TypePair *tpi = tpair[type[i]];
    const double vi = pi[PK_VOL];
    const double xi[3] = {pi[PK_X], pi[PK_X + 1], pi[PK_X + 2]};
    const double veli[3] = {pi[PK_V], pi[PK_V + 1], pi[PK_V + 2]};
    const bool ri = any_as && pi[PK_HASR] != 0.0;
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    if ((int) nbr_j.size() < jnum) {
      nbr_j.resize(jnum);
      nbr_s.resize(jnum);
    }

    // the inputs of pair i-j from the packed rows; false beyond the cutoff, or when j is not
    // in the SPH solid
    sphcut::PairIn in;
    in.rho_i = pi[PK_RHO];
    in.A_i = &pi[PK_A];
    auto gather = [&](int j, const double *pj) {
      const sphcut::TypePair &tp = tpi[type[j]];
      for (int a = 0; a < 3; a++) in.dx[a] = xi[a] - pj[PK_X + a];
      in.r2 = in.dx[0] * in.dx[0] + in.dx[1] * in.dx[1] + in.dx[2] * in.dx[2];
      if (in.r2 >= tp.cutsq || in.r2 == 0.0 || pj[PK_M] == 0.0) return false;
      for (int a = 0; a < 3; a++) in.dv[a] = pj[PK_V + a] - veli[a];
      sphcut::set_type_pair(tp, in);
      in.rho_j = pj[PK_RHO];
      in.A_j = &pj[PK_A];
      // the artificial stress term of a pair whose two tensors are zero (compression) adds
      // exactly nothing: skipped
      in.R_i = (ri || (any_as && pj[PK_HASR] != 0.0)) ? &pi[PK_R] : nullptr;
      in.R_j = &pj[PK_R];
      return true;
    };

    // first pass: the pairs within the cutoff and their scalars (the long chains of sqrt,
    // divisions and kernel, which the processor overlaps from pair to pair in a short loop)
    int npair = 0;
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      if (!gather(j, pk[j])) continue;
      sphcut::pair_scalars<DIM>(kernel_kind, in, nbr_s[npair]);
      nbr_j[npair++] = j;
    }

    // second pass: the bracket and the sums, i's kept local, j's in its row
    double acci[sphcut::NACC];
    for (int k = 0; k < sphcut::NACC; k++) acci[k] = 0.0;
    for (int n = 0; n < npair; n++) {
      const int j = nbr_j[n];
      const double *pj = pk[j];
      gather(j, pj);
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
    sphcut::particle_velocity_gradient(dim, correction, acc[i], lgrad[i]);
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
    const sphcut::TypePair *tpi = tpair[type[i]];
    const int *jlist = firstneigh[i];
    const int jnum = numneigh[i];
    sphcut::PairIn in;
    in.rho_i = pi[PK_RHO];
    double hi[4] = {0.0, 0.0, 0.0, 0.0};
    for (int jj = 0; jj < jnum; jj++) {
      const int j = jlist[jj] & NEIGHMASK;
      const double *pj = pk[j];
      const sphcut::TypePair &tp = tpi[type[j]];
      for (int a = 0; a < 3; a++) in.dx[a] = pi[PK_X + a] - pj[PK_X + a];
      in.r2 = in.dx[0] * in.dx[0] + in.dx[1] * in.dx[1] + in.dx[2] * in.dx[2];
      if (in.r2 >= tp.cutsq || in.r2 == 0.0 || pj[PK_M] == 0.0) continue;
      for (int a = 0; a < 3; a++) in.dv[a] = pj[PK_V + a] - pi[PK_V + a];
      sphcut::set_type_pair(tp, in);
      in.rho_j = pj[PK_RHO];
      double w, wfac;
      sphcut::kernel_w_gradfac_pre(kernel_kind, sqrt(in.r2), in.inv_h, in.wnorm, w, wfac);
      double Mg[3], work;
      sphcut::hourglass_pair<DIM>(hourglass, in, wfac, lgrad[i], lgrad[j], Mg, work);
      const double mj = pj[PK_M], mm = mi * mj;
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
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    fwrite(&mat[i], sizeof(Material), 1, fp);
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) {
        fwrite(&hlen[i][j], sizeof(double), 1, fp);
        fwrite(&hdx[i][j], sizeof(double), 1, fp);
      }
    }
  }
}

void PairSPHJCThermal::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    // an older file's shorter record leaves the fields after it (pmin) at 0 (allocate): no cutoff
    if (me == 0) utils::sfread(FLERR, &mat[i], restart_matsize, 1, fp, nullptr, error);
    MPI_Bcast(&mat[i], sizeof(Material), MPI_BYTE, 0, world);
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) {
          utils::sfread(FLERR, &hlen[i][j], sizeof(double), 1, fp, nullptr, error);
          utils::sfread(FLERR, &hdx[i][j], sizeof(double), 1, fp, nullptr, error);
        }
        MPI_Bcast(&hlen[i][j], 1, MPI_DOUBLE, 0, world);
        MPI_Bcast(&hdx[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
  }
}

void PairSPHJCThermal::write_restart_settings(FILE *fp)
{
  // a negative record size marks the settings with the hourglass coefficient (files written
  // before it have the positive size and no coefficient: read as hourglass 0).  The record
  // size itself tells the material layout: sizeof(Material), or MATSIZE_NO_PMIN for files
  // written before the pressure cutoff (read as no cutoff)
  const int matsize = -(int) sizeof(Material);
  fwrite(&matsize, sizeof(int), 1, fp);
  fwrite(&kernel_kind, sizeof(int), 1, fp);
  fwrite(&correction, sizeof(int), 1, fp);
  fwrite(&hourglass, sizeof(double), 1, fp);
}

void PairSPHJCThermal::read_restart_settings(FILE *fp)
{
  int matsize = 0;
  if (comm->me == 0) {
    utils::sfread(FLERR, &matsize, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &kernel_kind, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &correction, sizeof(int), 1, fp, nullptr, error);
    hourglass = 0.0;
    if (matsize < 0) {
      utils::sfread(FLERR, &hourglass, sizeof(double), 1, fp, nullptr, error);
      matsize = -matsize;
    }
  }
  MPI_Bcast(&matsize, 1, MPI_INT, 0, world);
  if (matsize != (int) sizeof(Material) && matsize != MATSIZE_NO_PMIN)
    error->all(FLERR, "Pair sph/jc-thermal: restart file written by another sphcut version "
               "(material record {} bytes, this version {})", matsize, (int) sizeof(Material));
  restart_matsize = matsize;
  MPI_Bcast(&kernel_kind, 1, MPI_INT, 0, world);
  MPI_Bcast(&correction, 1, MPI_INT, 0, world);
  MPI_Bcast(&hourglass, 1, MPI_DOUBLE, 0, world);
}

double PairSPHJCThermal::memory_usage()
{
  return (double) nmax * (NPK + sphcut::NACC + (hourglass > 0.0 ? 13 : 0)) * sizeof(double);
}
