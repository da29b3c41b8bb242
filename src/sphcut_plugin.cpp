/* ----------------------------------------------------------------------
   sphcut - registration of all sphcut styles with LAMMPS (plugin load)
------------------------------------------------------------------------- */

#include "lammpsplugin.h"
#include "library.h"
#include "utils.h"
#include "version.h"

#include "atom.h"
#include "error.h"
#include "lammps.h"

#include "compute_surface_lambda.h"
#include "dump_sph.h"
#include "fix_contact_tri_penalty.h"
#include "fix_heat_fmfs.h"
#include "fix_sph_jc_thermal.h"
#include "pair_sph_jc_thermal.h"
#include "sphcut_compat.h"

#include <cstdio>
#include <string>
#include <utility>

using namespace LAMMPS_NS;

// the LAMMPS version (version.h's "D Mon YYYY") the plugin is compiled against; the tests build a
// second plugin that claims another one (test_plugin_mismatch)
#ifndef SPHCUT_BUILT_FOR_LAMMPS
#define SPHCUT_BUILT_FOR_LAMMPS LAMMPS_VERSION
#endif
#ifndef SPHCUT_SOURCE_DIR
#define SPHCUT_SOURCE_DIR "<sphcut>"
#endif

namespace {

template <class T> Pair *pair_creator(LAMMPS *lmp) { return new T(lmp); }
template <class T> Fix *fix_creator(LAMMPS *lmp, int argc, char **argv) { return new T(lmp, argc, argv); }
template <class T> Compute *compute_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new T(lmp, argc, argv);
}
template <class T> Command *command_creator(LAMMPS *lmp) { return new T(lmp); }

void add(lammpsplugin_regfunc reg, void *lmp, void *handle, const char *style, const char *name,
         const char *info, void *creator)
{
  lammpsplugin_t plugin;
  plugin.version = LAMMPS_VERSION;
  plugin.style = style;
  plugin.name = name;
  plugin.info = info;
  plugin.author = "sphcut developers";
  plugin.creator.v1 = (lammpsplugin_factory1 *) creator;
  plugin.handle = handle;
  (*reg)(&plugin, lmp);
}

// A /kk atom style without -k on: LAMMPS 29Sep2021 creates it and aborts in Kokkos, "Constructing
// View and initializing data with uninitialized execution space" (4Jul2026 stops with "Cannot use
// KOKKOS styles without enabling KOKKOS", which names neither the style nor the way on).  Without
// -k on, plugin load puts a creator that stops the input with what to do in place of each such
// style's (one creator per style, K, to name it).  Where it comes from differs
// (sphcut::restart_plain_styles, sphcut_compat.h): in 29Sep2021 every restart file written under
// -k on -sf kk records atomic/kk; from 8Feb2023 such a file records atomic, read here without a
// word, and atomic/kk comes only from an input that names it (or its restart file)
constexpr int NKK_ATOM = 64;
std::string kk_atom_style[NKK_ATOM];

template <int K> AtomVec *refuse_kk_atom_style(LAMMPS *lmp)
{
  lmp->error->all(FLERR, "Atom style {} needs the KOKKOS package enabled ({}): run with -k on t N, with -sf kk "
                  "for the /kk styles or with run_style verlet/kk for the CPU styles", kk_atom_style[K],
                  sphcut::restart_plain_styles
                      ? "named in the input, or recorded in a restart file whose input named it"
                      : "a restart file written with -k on records it");
  return nullptr;
}

template <int... K> void refuse_kk_atom_styles(LAMMPS *lmp, std::integer_sequence<int, K...>)
{
  const Atom::AtomVecCreator refuse[] = {&refuse_kk_atom_style<K>...};
  int n = 0;
  for (auto &style : *lmp->atom->avec_map)
    if (style.first.find("/kk") != std::string::npos && n < NKK_ATOM) {
      kk_atom_style[n] = style.first;
      style.second = refuse[n++];
    }
}

const char *const MONTHS[12] = {"Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};

// "29 Sep 2021" -> 20210929 (what LAMMPS' utils::date2num gives its num_ver), 0 if unreadable
int date_number(const char *date)
{
  int day = 0, year = 0;
  char mon[4] = "";
  if (std::sscanf(date, "%d %3s %d", &day, mon, &year) != 3) return 0;
  for (int m = 0; m < 12; m++)
    if (std::string(mon) == MONTHS[m]) return year * 10000 + (m + 1) * 100 + day;
  return 0;
}

// 20260704 -> "4 Jul 2026"
std::string date_string(int num)
{
  const int m = (num / 100) % 100;
  if (m < 1 || m > 12) return std::to_string(num);
  return std::to_string(num % 100) + " " + MONTHS[m - 1] + " " + std::to_string(num / 10000);
}

}    // namespace

#ifdef SPHCUT_HAVE_KOKKOS
void sphcut_register_kokkos(lammpsplugin_regfunc reg, void *lmp, void *handle);
#endif

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  // a plugin compiled against another LAMMPS sees other class layouts (LAMMPS' plugin docs: "there
  // are no checks"): register nothing and say so.  Only LAMMPS' C library interface and
  // utils::logmesg(LAMMPS *, std::string) are called before the check, so no member of a LAMMPS
  // class is read with this build's layout.  A warning, as LAMMPS' own failed plugin loads are,
  // not an error: LAMMPS_PLUGIN_PATH loads every plugin there at start-up, wanted or not
  const int running = lammps_version(lmp);
  if (running != date_number(SPHCUT_BUILT_FOR_LAMMPS)) {
    if (lammps_extract_setting(lmp, "world_rank") == 0)
      utils::logmesg((LAMMPS *) lmp, std::string("WARNING: sphcut " SPHCUT_VERSION " was built for LAMMPS "
                     SPHCUT_BUILT_FOR_LAMMPS " but this is LAMMPS ") + date_string(running) +
                     ": no sphcut style is loaded. Rebuild sphcut against this LAMMPS (a shared library "
                     "with the PLUGIN package): cmake -S " SPHCUT_SOURCE_DIR " -B build-" +
                     std::to_string(running) + " -DLAMMPS_SOURCE_DIR=<this LAMMPS>/src "
                     "-DLAMMPS_ROOT=<its install prefix> && cmake --build build-" + std::to_string(running) +
                     ", then load that build's sphcutplugin.so\n");
    return;
  }
  auto reg = (lammpsplugin_regfunc) regfunc;
  auto *lammps = (LAMMPS *) lmp;
  if (!lammps->kokkos) refuse_kk_atom_styles(lammps, std::make_integer_sequence<int, NKK_ATOM>());
  add(reg, lmp, handle, "pair", "sph/jc-thermal",
      "sphcut " SPHCUT_VERSION ": updated-Lagrangian SPH solid, Johnson-Cook plasticity",
      (void *) &pair_creator<PairSPHJCThermal>);
  add(reg, lmp, handle, "fix", "sph/jc-thermal",
      "sphcut " SPHCUT_VERSION ": SPH solid state and time integration",
      (void *) &fix_creator<FixSPHJCThermal>);
  add(reg, lmp, handle, "fix", "heat/fmfs",
      "sphcut " SPHCUT_VERSION ": heat conduction, FMFS/Brookshaw Laplacian, surface losses, Dirichlet",
      (void *) &fix_creator<FixHeatFMFS>);
  add(reg, lmp, handle, "fix", "contact/tri-penalty",
      "sphcut " SPHCUT_VERSION ": penalty contact with a rigid triangulated tool, friction, friction heat",
      (void *) &fix_creator<FixContactTriPenalty>);
  add(reg, lmp, handle, "compute", "surface/lambda",
      "sphcut " SPHCUT_VERSION ": free-surface flag from the renormalisation matrix eigenvalue",
      (void *) &compute_creator<ComputeSurfaceLambda>);
  add(reg, lmp, handle, "command", "dump_sph",
      "sphcut " SPHCUT_VERSION ": dump custom of the SPH state under readable column names",
      (void *) &command_creator<DumpSPH>);
#ifdef SPHCUT_HAVE_KOKKOS
  sphcut_register_kokkos(reg, lmp, handle);
#endif
}
