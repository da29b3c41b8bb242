/* ----------------------------------------------------------------------
   sphcut - command dump_sph (see dump_sph.h and doc/dump_sph.rst)

     dump_sph ID group-ID N file field1 field2 ...

   creates `dump ID group-ID custom N file ...` with every sphcut field
   name replaced by the per-atom output it stands for (f_ID[k] of fix
   sph/jc-thermal, c_ID[k] of compute surface/lambda, f_ID[k] of fix
   contact/tri-penalty) and every other field passed through; then gives
   the columns of the header line the sphcut names.  The dump is an
   ordinary dump custom afterwards (dump_modify, undump, write_dump).
   Plugins cannot add dump styles to LAMMPS (29Sep2021 to 2026), hence a
   command.
------------------------------------------------------------------------- */

#include "dump_sph.h"

#include "comm.h"
#include "compute.h"
#include "compute_surface_lambda.h"
#include "dump_custom.h"
#include "error.h"
#include "fix.h"
#include "fix_sph_jc_thermal.h"
#include "input.h"
#include "modify.h"
#include "output.h"
#include "utils.h"

#include "sphcut_checks.h"
#include "sphcut_compat.h"

#include <cstring>
#include <map>

using namespace LAMMPS_NS;

const std::vector<DumpSPH::Field> &DumpSPH::fields()
{
  // the documented per-atom columns of fix sph/jc-thermal, compute surface/lambda and fix
  // contact/tri-penalty (1-based, as in f_ID[k]), taken from the styles' own enums
  using F = FixSPHJCThermal;
  using S = ComputeSurfaceLambda;
  static const std::vector<Field> f = {
      {"density", 0, F::RHO + 1},          {"pressure", 0, F::PRESS + 1},
      {"sxx", 0, F::SXX + 1},              {"syy", 0, F::SYY + 1},
      {"szz", 0, F::SZZ + 1},              {"sxy", 0, F::SXY + 1},
      {"sxz", 0, F::SXZ + 1},              {"syz", 0, F::SYZ + 1},
      {"vonmises", 0, F::VM + 1},          {"plastic_strain", 0, F::EPS + 1},
      {"plastic_strain_rate", 0, F::EPSDOT + 1}, {"temperature", 0, F::TEMP + 1},
      {"role", 0, F::ROLE + 1},            {"internal_energy", 0, F::UINT + 1},
      {"temperature_rate", 0, F::DTEMP + 1},
      {"lambda", 1, S::LAMBDA + 1},        {"surface", 1, S::FLAG + 1},
      {"surface_nx", 1, S::NX + 1},        {"surface_ny", 1, S::NY + 1},
      {"surface_nz", 1, S::NZ + 1},
      {"fcontact_x", 2, 1},                {"fcontact_y", 2, 2},
      {"fcontact_z", 2, 3},                {"fcontact_n", 2, 4},
      {"fcontact_t", 2, 5},                {"contact_feature", 2, 6}};
  return f;
}

namespace {

// the per-atom attributes of dump custom (29Sep2021; typelabel from 2023), and the prefixes of
// its computes, fixes, variables and custom properties (c_ID, f_ID[2], v_name, d_name, i2_name[1])
const char *const CUSTOM_ATTRIBUTES[] = {
    "id", "mol", "proc", "procp1", "type", "element", "typelabel", "mass", "x", "y", "z", "xs", "ys", "zs", "xu",
    "yu", "zu", "xsu", "ysu", "zsu", "ix", "iy", "iz", "vx", "vy", "vz", "fx", "fy", "fz", "q", "mux", "muy", "muz",
    "mu", "radius", "diameter", "omegax", "omegay", "omegaz", "angmomx", "angmomy", "angmomz", "tqx", "tqy", "tqz"};
const char *const CUSTOM_PREFIXES[] = {"c_", "f_", "v_", "d_", "i_", "d2_", "i2_"};

bool custom_field(const std::string &name)
{
  for (const char *a : CUSTOM_ATTRIBUTES)
    if (name == a) return true;
  for (const char *p : CUSTOM_PREFIXES)
    if (name.size() > strlen(p) && name.compare(0, strlen(p), p) == 0) return true;
  return false;
}

// 29Sep2021 has no dump_modify colname: set the header text of the columns directly
// (pointer to a protected member through a derived class: standard C++)
struct ColumnsAccess : public DumpCustom {
  static char *&columns_of(DumpCustom *d) { return d->*(&ColumnsAccess::columns); }
};

}    // namespace

void DumpSPH::command(int narg, char **arg)
{
  if (narg < 5) error->all(FLERR, "Illegal dump_sph command: dump_sph ID group-ID N file field ...");
  sphcut::parse_int(lmp, "dump_sph", "N (the output interval)", arg[2]);    // dump custom would wrap it

  // the first style providing each source, found by name
  const char *srcstyle[3] = {"sph/jc-thermal", "surface/lambda", "contact/tri-penalty"};
  std::string srcid[3];
  int srcn[3] = {0, 0, 0};
  for (auto *f : sphcut::fix_list(modify)) {
    if (utils::strmatch(f->style, "^sph/jc-thermal") && !srcn[0]++) srcid[0] = f->id;
    if (utils::strmatch(f->style, "^contact/tri-penalty") && !srcn[2]++) srcid[2] = f->id;
  }
  for (auto *c : sphcut::compute_list(modify))
    if (utils::strmatch(c->style, "^surface/lambda") && !srcn[1]++) srcid[1] = c->id;

  std::vector<std::string> words = {arg[0], arg[1], "custom", arg[2], arg[3]};
  std::vector<std::pair<int, std::string>> rename;    // column (1-based) -> sphcut name
  std::map<std::string, int> seen;
  for (int iarg = 4; iarg < narg; iarg++) {
    const std::string name = arg[iarg];
    if (seen[name]++) error->all(FLERR, "dump_sph: field {} given twice", name);
    const Field *fd = nullptr;
    for (const Field &f : fields())
      if (name == f.name) fd = &f;
    if (!fd) {
      // any dump custom field: id, type, x, vx, c_ID, f_ID[2], v_name, ... (dump custom checks
      // that they exist); anything else would be reported by dump custom under its own name
      if (!custom_field(name)) {
        std::string sph, custom;
        for (const Field &f : fields()) sph += std::string(sph.empty() ? "" : " ") + f.name;
        for (const char *a : CUSTOM_ATTRIBUTES) custom += std::string(custom.empty() ? "" : " ") + a;
        error->all(FLERR, "dump_sph: unknown field {}; sphcut fields: {}; dump custom fields: {}, c_ID, c_ID[N], "
                   "f_ID, f_ID[N], v_name, d_name, i_name", name, sph, custom);
      }
      words.push_back(name);
      continue;
    }
    if (!srcn[fd->source])
      error->all(FLERR, "dump_sph: field {} needs a {} {} (define it before dump_sph)", name,
                 fd->source == 1 ? "compute" : "fix", srcstyle[fd->source]);
    if (srcn[fd->source] > 1 && comm->me == 0)
      error->warning(FLERR, "dump_sph: field {} taken from the first {} {}, {}", name,
                     fd->source == 1 ? "compute" : "fix", srcstyle[fd->source], srcid[fd->source]);
    words.push_back(fmt::format("{}_{}[{}]", fd->source == 1 ? "c" : "f", srcid[fd->source], fd->column));
    rename.emplace_back((int) words.size() - 5, name);
  }

  std::vector<char *> argv;
  for (std::string &w : words) argv.push_back(&w[0]);
  output->add_dump((int) argv.size(), argv.data());
  if (rename.empty()) return;

#if SPHCUT_LAMMPS_VERSION >= 20220504
  // newer LAMMPS rebuilds the header in init_style from dump_modify colname
  std::string cmd = fmt::format("dump_modify {}", arg[0]);
  for (const auto &r : rename) cmd += fmt::format(" colname {} {}", r.first, r.second);
  input->one(cmd);
#else
  auto *dump = static_cast<DumpCustom *>(output->dump[output->ndump - 1]);
  std::vector<std::string> cols = utils::split_words(ColumnsAccess::columns_of(dump));
  for (const auto &r : rename) cols[r.first - 1] = r.second;
  std::string joined;
  for (const std::string &c : cols) joined += (joined.empty() ? "" : " ") + c;
  char *&columns = ColumnsAccess::columns_of(dump);
  delete[] columns;
  columns = utils::strdup(joined);
#endif
}
