/* ----------------------------------------------------------------------
   sphcut - the model (sphcut_model.h): parsing of pair_style / pair_coeff,
   mixing of the type pairs, restart records field by field.
------------------------------------------------------------------------- */

#include "sphcut_model.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "pair.h"
#include "utils.h"

#include <cmath>
#include <cstddef>
#include <cstring>

using namespace LAMMPS_NS;

namespace sphcut {

static constexpr double UNSET = MODEL_UNSET;

/* ----------------------------------------------------------------------
   the material tables: pair_coeff keyword = restart field name, default
   (UNSET: mandatory, or optional without a default: see check_material).
   A new parameter is one row here; restart files without it read its default.
------------------------------------------------------------------------- */

const std::vector<MaterialField> &material_fields()
{
  static const std::vector<MaterialField> fields = {
      {"rho0", &Material::rho0, UNSET},      {"E", &Material::E, UNSET},
      {"nu", &Material::nu, UNSET},          {"A", &Material::A, UNSET},
      {"B", &Material::B, 0.0},              {"C", &Material::C, 0.0},
      {"n", &Material::n, 1.0},              {"m", &Material::m, 1.0},
      {"epsdot0", &Material::epsdot0, 1.0},  {"Tref", &Material::Tref, 300.0},
      {"Tmelt", &Material::Tmelt, 1.0e30},   // no thermal softening
      {"cp", &Material::cp, 0.0},            {"chi", &Material::chi, 0.9},
      {"k", &Material::kappa, 0.0},          {"alpha", &Material::av_alpha, 1.0},
      {"beta", &Material::av_beta, 1.0},     {"as_eps", &Material::as_eps, 0.3},
      {"as_n", &Material::as_n, 4.0},        {"xsph", &Material::xsph, 0.5},
      {"gamma0", &Material::gamma0, 0.0},    {"s", &Material::s_hug, 0.0},
      {"pmin", &Material::pmin, 0.0},        // no pressure cutoff
      // flow tanh (Calamaz et al. 2008): mandatory with it, 0 otherwise
      {"a", &Material::tanh_a, 0.0},         {"b", &Material::tanh_b, 0.0},
      {"c", &Material::tanh_c, 0.0},         {"d", &Material::tanh_d, 0.0},
  };
  return fields;
}

const std::vector<MaterialFlag> &material_flags()
{
  static const std::vector<MaterialFlag> flags = {
      {"defined", &Material::defined, 0},
      {"eos", &Material::eos, EOS_LINEAR},
      {"plastic", &Material::plastic, 0},
      {"flow", &Material::flow, FLOW_JC},
      {"spall", &Material::spall, SPALL_CUTOFF},
  };
  return flags;
}

static const MaterialField *find_field(const std::string &name)
{
  for (const auto &f : material_fields())
    if (name == f.name) return &f;
  return nullptr;
}

/* ---------------------------------------------------------------------- */

void Model::allocate(int ntypes)
{
  nt = ntypes;
  const size_t n1 = ntypes + 1, n2 = n1 * n1;
  mat.assign(n1, Material{});
  for (auto &m : mat) {
    for (const auto &f : material_flags()) m.*(f.value) = 0;
    for (const auto &f : material_fields()) m.*(f.value) = 0.0;
    m.G = m.K = m.c0 = m.cl = 0.0;
  }
  hlen.assign(n2, 0.0);
  hdx.assign(n2, 0.0);
  hset.assign(n2, 0);
  wdp.assign(n2, 0.0);
  tpair.assign(n2, TypePair{});
  dp.assign(n1, 0.0);
}

/* ----------------------------------------------------------------------
   pair_style sph/jc-thermal [kernel cubic|wendland|hyperbolic] [correction yes|no]
                             [hourglass kappa]
------------------------------------------------------------------------- */

void Model::settings(LAMMPS *lmp, int narg, char **arg)
{
  Error *error = lmp->error;
  hourglass = 0.0;    // a repeated pair_style without the keyword switches it off
  int iarg = 0;
  while (iarg < narg) {
    const std::string kw = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair sph/jc-thermal: keyword {} needs a value", kw);
    const std::string val = arg[iarg + 1];
    if (kw == "kernel") {
      if (val == "cubic") kernel_kind = KERNEL_CUBIC;
      else if (val == "wendland") kernel_kind = KERNEL_WENDLAND;
      else if (val == "hyperbolic") kernel_kind = KERNEL_HYPERBOLIC;
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

void Model::coeff(LAMMPS *lmp, int narg, char **arg)
{
  if (narg < 4) lmp->error->all(FLERR, "Pair sph/jc-thermal: pair_coeff needs I J and keyword/value pairs");
  int nmat = 0;
  double h = 0.0, hx = 0.0;
  Material m = parse_material(lmp, narg, arg, nmat, h, hx);
  if (nmat) check_material(lmp, m, arg[0], arg[1]);
  store(lmp, arg, m, nmat, h, hx);
}

// the keywords of one pair_coeff line: the material's values (those not given UNSET, nmat: how
// many material keywords), h and hdx (0: not given)
Material Model::parse_material(LAMMPS *lmp, int narg, char **arg, int &nmat, double &h, double &hx) const
{
  Error *error = lmp->error;
  Material m = {};
  for (const auto &f : material_fields()) m.*(f.value) = UNSET;
  m.eos = EOS_LINEAR;
  m.flow = FLOW_JC;
  m.pmin = 0.0;    // no pressure cutoff
  m.spall = SPALL_CUTOFF;
  nmat = 0;
  for (int iarg = 2; iarg < narg; iarg += 2) {
    const std::string kw = arg[iarg];
    if (iarg + 1 >= narg) error->all(FLERR, "Pair sph/jc-thermal: pair_coeff keyword {} needs a value", kw);
    const char *val = arg[iarg + 1];
    const std::string v = val;
    if (kw == "h") {
      h = utils::numeric(FLERR, val, false, lmp);
      if (h <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: h must be > 0, got {}", h);
      continue;
    } else if (kw == "hdx") {
      hx = utils::numeric(FLERR, val, false, lmp);
      if (hx <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: hdx must be > 0, got {}", hx);
      continue;
    } else if (kw == "eos") {
      if (v == "linear") m.eos = EOS_LINEAR;
      else if (v == "mie-gruneisen") m.eos = EOS_MIE_GRUNEISEN;
      else error->all(FLERR, "Pair sph/jc-thermal: unknown eos {} (linear, mie-gruneisen)", v);
    } else if (kw == "flow") {
      if (v == "jc") m.flow = FLOW_JC;
      else if (v == "tanh") m.flow = FLOW_TANH;
      else error->all(FLERR, "Pair sph/jc-thermal: unknown flow {} (jc, tanh)", v);
    } else if (kw == "spall") {
      if (v == "cutoff") m.spall = SPALL_CUTOFF;
      else if (v == "release") m.spall = SPALL_RELEASE;
      else error->all(FLERR, "Pair sph/jc-thermal: unknown spall {} (cutoff, release)", v);
    } else if (kw == "pmin") {
      // tension cutoff of the pressure: a negative pressure, or none (the default)
      if (v == "none") m.pmin = 0.0;
      else {
        if (!utils::is_double(v))
          error->all(FLERR, "Pair sph/jc-thermal: pmin must be a negative pressure or none, got {}", v);
        m.pmin = utils::numeric(FLERR, val, false, lmp);
        if (!(m.pmin < 0.0))
          error->all(FLERR, "Pair sph/jc-thermal: pmin must be < 0 (a tensile pressure) or none, got {}", v);
      }
    } else {
      const MaterialField *f = find_field(kw);
      if (!f) error->all(FLERR, "Pair sph/jc-thermal: unknown pair_coeff keyword {}", kw);
      m.*(f->value) = utils::numeric(FLERR, val, false, lmp);
    }
    nmat++;
  }
  return m;
}

// the mandatory values and ranges of a material; then the defaults and the derived constants
void Model::check_material(LAMMPS *lmp, Material &m, const char *iarg, const char *jarg) const
{
  Error *error = lmp->error;
  for (const char *name : {"rho0", "E", "nu"})
    if (m.*(find_field(name)->value) == UNSET)
      error->all(FLERR, "Pair sph/jc-thermal: material value {} is missing in pair_coeff {} {}", name, iarg, jarg);
  if (m.rho0 <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: rho0 must be > 0, got {}", m.rho0);
  if (m.E <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: E must be > 0, got {}", m.E);
  if (m.nu <= -1.0 || m.nu >= 0.5) error->all(FLERR, "Pair sph/jc-thermal: nu must be in (-1,0.5), got {}", m.nu);
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
    for (const char *name : {"B", "C", "n", "m", "epsdot0"})
      if (m.*(find_field(name)->value) != UNSET)
        error->all(FLERR, "Pair sph/jc-thermal: Johnson-Cook value {} given without A", name);
    if (m.flow != FLOW_JC) error->all(FLERR, "Pair sph/jc-thermal: flow tanh needs the Johnson-Cook values (A ...)");
  }
  // the flow law's own parameters: all of them with flow tanh, none without
  for (const char *name : {"a", "b", "c", "d"}) {
    const double v = m.*(find_field(name)->value);
    if (m.flow == FLOW_TANH && v == UNSET)
      error->all(FLERR, "Pair sph/jc-thermal: flow tanh needs {} (a, b, c, d)", name);
    if (m.flow == FLOW_TANH && !(v > 0.0)) error->all(FLERR, "Pair sph/jc-thermal: {} must be > 0, got {}", name, v);
    if (m.flow != FLOW_TANH && v != UNSET)
      error->all(FLERR, "Pair sph/jc-thermal: {} is a parameter of flow tanh (add flow tanh)", name);
  }
  if (m.flow == FLOW_TANH && m.Tmelt == UNSET)
    error->all(FLERR, "Pair sph/jc-thermal: flow tanh needs Tmelt (its softening depends on T/Tmelt)");
  if (m.spall == SPALL_RELEASE && !(m.pmin < 0.0))
    error->all(FLERR, "Pair sph/jc-thermal: spall release needs a pressure cutoff (pmin < 0) in pair_coeff {} {}",
               iarg, jarg);
  if (m.eos == EOS_MIE_GRUNEISEN && (m.gamma0 == UNSET || m.s_hug == UNSET))
    error->all(FLERR, "Pair sph/jc-thermal: eos mie-gruneisen needs gamma0 and s");
  if (m.eos != EOS_MIE_GRUNEISEN && (m.gamma0 != UNSET || m.s_hug != UNSET))
    error->all(FLERR, "Pair sph/jc-thermal: gamma0 and s are Mie-Grueneisen values (add eos mie-gruneisen)");
  if (m.eos == EOS_MIE_GRUNEISEN && m.gamma0 > 0.0 && (m.cp == UNSET || m.cp <= 0.0))
    error->all(FLERR, "Pair sph/jc-thermal: eos mie-gruneisen with gamma0 > 0 needs cp (thermal pressure)");
  if (m.C != UNSET && m.C < 0.0) error->all(FLERR, "Pair sph/jc-thermal: C must be >= 0, got {}", m.C);
  if (m.m != UNSET && m.m <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: m must be > 0, got {}", m.m);
  if (m.Tref != UNSET && m.Tref < 0.0) error->all(FLERR, "Pair sph/jc-thermal: Tref must be >= 0, got {}", m.Tref);
  if (m.as_n != UNSET && m.as_n <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: as_n must be > 0, got {}", m.as_n);
  // defaults
  for (const auto &f : material_fields())
    if (m.*(f.value) == UNSET) m.*(f.value) = f.fallback;
  if (m.epsdot0 <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: epsdot0 must be > 0, got {}", m.epsdot0);
  if (m.Tmelt <= m.Tref) error->all(FLERR, "Pair sph/jc-thermal: Tmelt {} must be above Tref {}", m.Tmelt, m.Tref);
  if (m.cp < 0.0) error->all(FLERR, "Pair sph/jc-thermal: cp must be >= 0, got {}", m.cp);
  if (m.chi < 0.0 || m.chi > 1.0) error->all(FLERR, "Pair sph/jc-thermal: chi must be in [0,1], got {}", m.chi);
  if (m.kappa < 0.0) error->all(FLERR, "Pair sph/jc-thermal: k must be >= 0, got {}", m.kappa);
  if (m.plastic && m.chi > 0.0 && m.cp == 0.0)
    error->all(FLERR, "Pair sph/jc-thermal: cp is missing (needed for plastic heating with chi > 0; "
               "set chi 0 for an isothermal run)");
  if (m.av_alpha < 0.0 || m.av_beta < 0.0) error->all(FLERR, "Pair sph/jc-thermal: alpha and beta must be >= 0");
  if (m.as_eps < 0.0) error->all(FLERR, "Pair sph/jc-thermal: as_eps must be >= 0, got {}", m.as_eps);
  if (m.xsph < 0.0 || m.xsph > 1.0) error->all(FLERR, "Pair sph/jc-thermal: xsph must be in [0,1], got {}", m.xsph);
  material_derive(m);
  m.defined = 1;
}

// the material to the like types t in I and J, h / hdx to every pair (I,J)
void Model::store(LAMMPS *lmp, char **arg, const Material &m, int nmat, double h, double hx)
{
  Error *error = lmp->error;
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, nt, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, nt, jlo, jhi, error);
  if (h > 0.0 && hx > 0.0) error->all(FLERR, "Pair sph/jc-thermal: give either h or hdx, not both");
  int nlike = 0;
  for (int t = std::max(ilo, jlo); t <= std::min(ihi, jhi); t++) {
    if (nmat) mat[t] = m;
    nlike++;
  }
  if (nmat && nlike == 0)
    error->all(FLERR, "Pair sph/jc-thermal: material keywords need pair_coeff I I (or * *), got {} {}", arg[0],
               arg[1]);
  if (h > 0.0 || hx > 0.0) {
    // pair_coeff 2 1 sets the pair (1,2)
    for (int i = ilo; i <= ihi; i++)
      for (int j = jlo; j <= jhi; j++) {
        const int a = std::min(i, j), b = std::max(i, j);
        hlen[idx(a, b)] = h;
        hdx[idx(a, b)] = hx;
        hset[idx(a, b)] = 1;
      }
  } else if (!nmat) {
    error->all(FLERR, "Pair sph/jc-thermal: pair_coeff {} {} sets nothing", arg[0], arg[1]);
  }
}

/* ----------------------------------------------------------------------
   init: particle spacing per type, (m / rho0)^(1/d), mass from mass or mean rmass
------------------------------------------------------------------------- */

void Model::set_spacing(LAMMPS *lmp)
{
  Atom *atom = lmp->atom;
  dim = lmp->domain->dimension;
  std::vector<double> msum(nt + 1, 0.0), cnt(nt + 1, 0.0), gsum(nt + 1), gcnt(nt + 1);
  for (int i = 0; i < atom->nlocal; i++) {
    msum[atom->type[i]] += atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]];
    cnt[atom->type[i]] += 1.0;
  }
  MPI_Allreduce(msum.data(), gsum.data(), nt + 1, MPI_DOUBLE, MPI_SUM, lmp->world);
  MPI_Allreduce(cnt.data(), gcnt.data(), nt + 1, MPI_DOUBLE, MPI_SUM, lmp->world);
  for (int t = 1; t <= nt; t++) {
    dp[t] = 0.0;
    if (mat[t].defined && gcnt[t] > 0.0) dp[t] = pow(gsum[t] / gcnt[t] / mat[t].rho0, 1.0 / dim);
  }
}

/* ----------------------------------------------------------------------
   init_one: the smoothing length of a type pair (given, from hdx, or the mean of
   the like pairs'), W(dp) and the TypePair constants; returns the cutoff 2h
------------------------------------------------------------------------- */

double Model::mix(LAMMPS *lmp, int i, int j)
{
  Error *error = lmp->error;
  if (!mat[i].defined)
    error->all(FLERR, "Pair sph/jc-thermal: no material for atom type {} (pair_coeff {} {} rho0 ...)", i, i, i);
  if (!mat[j].defined)
    error->all(FLERR, "Pair sph/jc-thermal: no material for atom type {} (pair_coeff {} {} rho0 ...)", j, j, j);
  const int ij = idx(i, j), ji = idx(j, i);
  double dpij = 0.5 * (dp[i] + dp[j]);
  if (!hset[ij]) {
    // mix: mean of the like-type smoothing lengths
    if (!hset[idx(i, i)] || !hset[idx(j, j)])
      error->all(FLERR, "Pair sph/jc-thermal: smoothing length (h or hdx) not set for types {} {}", i, j);
    const double hi = hdx[idx(i, i)] > 0.0 ? hdx[idx(i, i)] * dp[i] : hlen[idx(i, i)];
    const double hj = hdx[idx(j, j)] > 0.0 ? hdx[idx(j, j)] * dp[j] : hlen[idx(j, j)];
    hlen[ij] = 0.5 * (hi + hj);
    hdx[ij] = 0.0;
  } else if (hdx[ij] > 0.0) {
    if (dpij <= 0.0)
      error->all(FLERR, "Pair sph/jc-thermal: hdx needs atoms of types {} {} to derive the spacing", i, j);
    hlen[ij] = hdx[ij] * dpij;
  }
  if (hlen[ij] <= 0.0) error->all(FLERR, "Pair sph/jc-thermal: smoothing length of types {} {} is not positive", i, j);
  hlen[ji] = hlen[ij];
  hdx[ji] = hdx[ij];
  if (dpij <= 0.0) dpij = hlen[ij] / 1.2;
  wdp[ij] = wdp[ji] = kernel_w(kernel_kind, dim, dpij, hlen[ij]);
  tpair[ij] = tpair[ji] = mix_type_pair(mat[i], mat[j], hlen[ij], wdp[ij], kernel_kind, dim);
  return sphcut::support_radius(hlen[ij]);
}

/* ----------------------------------------------------------------------
   restart files.  Format 2 (this version): the settings start with RESTART_TAG and the
   version, then kernel, correction, hourglass; per type the material as (name, value)
   pairs (int count; per field: int length, the name's characters, double value), then
   per type pair j >= i the flag h/hdx given and, if so, h and hdx.  A field this version
   does not know is refused (the file needs a newer sphcut); one it misses takes its
   default (a parameter added after the file was written).
   Format 1 (sphcut before this change): the settings start with the size in bytes of the
   raw material record, negative when the hourglass coefficient follows (older files: positive,
   hourglass 0); the record is the memory image of LegacyMaterial, of its full size or
   ending before pmin (files written before the pressure cutoff: no cutoff).
------------------------------------------------------------------------- */

namespace {
// the raw material record of format 1, field for field (frozen: do not edit)
struct LegacyMaterial {
  int defined;
  double rho0, E, nu;
  double G, K, c0;
  double cl;
  int eos;
  double gamma0, s_hug;
  int plastic;
  double A, B, C, n, m, epsdot0, Tref, Tmelt;
  double cp, chi, kappa;
  double av_alpha, av_beta;
  double as_eps, as_n;
  double xsph;
  double pmin;
};
constexpr int LEGACY_SIZE = (int) sizeof(LegacyMaterial);
constexpr int LEGACY_SIZE_NO_PMIN = (int) offsetof(LegacyMaterial, pmin);

Material from_legacy(const LegacyMaterial &o)
{
  Material m = {};
  for (const auto &f : material_fields()) m.*(f.value) = f.fallback == UNSET ? 0.0 : f.fallback;
  m.defined = o.defined;
  m.rho0 = o.rho0, m.E = o.E, m.nu = o.nu;
  m.eos = o.eos, m.gamma0 = o.gamma0, m.s_hug = o.s_hug;
  m.plastic = o.plastic;
  m.A = o.A, m.B = o.B, m.C = o.C, m.n = o.n, m.m = o.m, m.epsdot0 = o.epsdot0, m.Tref = o.Tref, m.Tmelt = o.Tmelt;
  m.cp = o.cp, m.chi = o.chi, m.kappa = o.kappa;
  m.av_alpha = o.av_alpha, m.av_beta = o.av_beta, m.as_eps = o.as_eps, m.as_n = o.as_n, m.xsph = o.xsph;
  m.pmin = o.pmin;
  m.flow = FLOW_JC;
  if (m.defined) material_derive(m);
  return m;
}

void write_field(FILE *fp, const char *name, double value)
{
  const int len = (int) strlen(name);
  fwrite(&len, sizeof(int), 1, fp);
  fwrite(name, 1, len, fp);
  fwrite(&value, sizeof(double), 1, fp);
}
}    // namespace

void Model::write_settings(FILE *fp) const
{
  const int tag = RESTART_TAG, version = RESTART_VERSION;
  fwrite(&tag, sizeof(int), 1, fp);
  fwrite(&version, sizeof(int), 1, fp);
  fwrite(&kernel_kind, sizeof(int), 1, fp);
  fwrite(&correction, sizeof(int), 1, fp);
  fwrite(&hourglass, sizeof(double), 1, fp);
}

void Model::write_restart(FILE *fp) const
{
  write_settings(fp);
  const int count = (int) (material_flags().size() + material_fields().size());
  for (int i = 1; i <= nt; i++) {
    fwrite(&count, sizeof(int), 1, fp);
    for (const auto &f : material_flags()) write_field(fp, f.name, mat[i].*(f.value));
    for (const auto &f : material_fields()) write_field(fp, f.name, mat[i].*(f.value));
    for (int j = i; j <= nt; j++) {
      const int flag = hset[idx(i, j)];
      fwrite(&flag, sizeof(int), 1, fp);
      if (flag) {
        fwrite(&hlen[idx(i, j)], sizeof(double), 1, fp);
        fwrite(&hdx[idx(i, j)], sizeof(double), 1, fp);
      }
    }
  }
}

// rank 0 reads, every rank returns the legacy record size (0: format 2) and the version
int Model::read_settings(LAMMPS *lmp, FILE *fp, int &version)
{
  Error *error = lmp->error;
  int first = 0;
  version = 1;
  if (lmp->comm->me == 0) {
    utils::sfread(FLERR, &first, sizeof(int), 1, fp, nullptr, error);
    if (first == RESTART_TAG) utils::sfread(FLERR, &version, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &kernel_kind, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &correction, sizeof(int), 1, fp, nullptr, error);
    hourglass = 0.0;
    if (first == RESTART_TAG || first < 0) utils::sfread(FLERR, &hourglass, sizeof(double), 1, fp, nullptr, error);
  }
  MPI_Bcast(&first, 1, MPI_INT, 0, lmp->world);
  MPI_Bcast(&version, 1, MPI_INT, 0, lmp->world);
  MPI_Bcast(&kernel_kind, 1, MPI_INT, 0, lmp->world);
  MPI_Bcast(&correction, 1, MPI_INT, 0, lmp->world);
  MPI_Bcast(&hourglass, 1, MPI_DOUBLE, 0, lmp->world);
  if (first == RESTART_TAG) {
    if (version < 2 || version > RESTART_VERSION)
      error->all(FLERR, "Pair sph/jc-thermal: restart file written by another sphcut version "
                 "(model restart format {}, this version reads formats 1 to {})", version, RESTART_VERSION);
    return 0;
  }
  const int size = first < 0 ? -first : first;
  if (size != LEGACY_SIZE && size != LEGACY_SIZE_NO_PMIN)
    error->all(FLERR, "Pair sph/jc-thermal: restart file written by another sphcut version "
               "(material record {} bytes, format 1 has {} or {})", size, LEGACY_SIZE, LEGACY_SIZE_NO_PMIN);
  return size;
}

// one material (rank 0 reads, broadcast to all)
void Model::read_material(LAMMPS *lmp, FILE *fp, int version, int legacy_size, Material &m)
{
  Error *error = lmp->error;
  std::string unknown;
  if (lmp->comm->me == 0) {
    if (legacy_size) {
      // an older file's shorter record leaves the fields after it (pmin) at 0: no cutoff
      LegacyMaterial o;
      memset(&o, 0, sizeof(o));
      utils::sfread(FLERR, &o, legacy_size, 1, fp, nullptr, error);
      m = from_legacy(o);
    } else {
      m = Material{};
      for (const auto &f : material_flags()) m.*(f.value) = f.fallback;
      for (const auto &f : material_fields()) m.*(f.value) = f.fallback == UNSET ? 0.0 : f.fallback;
      int count = 0;
      utils::sfread(FLERR, &count, sizeof(int), 1, fp, nullptr, error);
      for (int k = 0; k < count; k++) {
        int len = 0;
        utils::sfread(FLERR, &len, sizeof(int), 1, fp, nullptr, error);
        if (len <= 0 || len > 64)
          error->one(FLERR, "Pair sph/jc-thermal: restart file damaged (material field name of {} characters)", len);
        std::string name(len, ' ');
        double value = 0.0;
        utils::sfread(FLERR, &name[0], 1, len, fp, nullptr, error);
        utils::sfread(FLERR, &value, sizeof(double), 1, fp, nullptr, error);
        bool known = false;
        for (const auto &f : material_flags())
          if (name == f.name) {
            m.*(f.value) = (int) value;
            known = true;
          }
        if (const MaterialField *f = find_field(name)) {
          m.*(f->value) = value;
          known = true;
        }
        if (!known && unknown.empty()) unknown = name;
      }
      if (m.defined) material_derive(m);
    }
  }
  int nunknown = (int) unknown.size();
  MPI_Bcast(&nunknown, 1, MPI_INT, 0, lmp->world);
  if (nunknown) {
    unknown.resize(nunknown);
    MPI_Bcast(&unknown[0], nunknown, MPI_CHAR, 0, lmp->world);
    error->all(FLERR, "Pair sph/jc-thermal: restart file written by a newer sphcut: material parameter {} "
               "(format {}) is unknown to this version", unknown, version);
  }
  MPI_Bcast(&m, sizeof(Material), MPI_BYTE, 0, lmp->world);
}

void Model::read_restart(LAMMPS *lmp, FILE *fp)
{
  int version = 1;
  const int legacy_size = read_settings(lmp, fp, version);
  allocate(lmp->atom->ntypes);
  const int me = lmp->comm->me;
  for (int i = 1; i <= nt; i++) {
    read_material(lmp, fp, version, legacy_size, mat[i]);
    for (int j = i; j <= nt; j++) {
      int &flag = hset[idx(i, j)];
      if (me == 0) utils::sfread(FLERR, &flag, sizeof(int), 1, fp, nullptr, lmp->error);
      MPI_Bcast(&flag, 1, MPI_INT, 0, lmp->world);
      if (flag) {
        if (me == 0) {
          utils::sfread(FLERR, &hlen[idx(i, j)], sizeof(double), 1, fp, nullptr, lmp->error);
          utils::sfread(FLERR, &hdx[idx(i, j)], sizeof(double), 1, fp, nullptr, lmp->error);
        }
        MPI_Bcast(&hlen[idx(i, j)], 1, MPI_DOUBLE, 0, lmp->world);
        MPI_Bcast(&hdx[idx(i, j)], 1, MPI_DOUBLE, 0, lmp->world);
      }
    }
  }
}

/* ---------------------------------------------------------------------- */

const Model *find_model(LAMMPS *lmp)
{
  auto *owner = dynamic_cast<ModelOwner *>(lmp->force->pair_match("^sph/jc-thermal", 0));
  return owner ? &owner->model() : nullptr;
}

const Model &require_model(LAMMPS *lmp, const std::string &who)
{
  const Model *model = find_model(lmp);
  if (!model) lmp->error->all(FLERR, "{} requires pair_style sph/jc-thermal", who);
  return *model;
}

}    // namespace sphcut
