/* ----------------------------------------------------------------------
   sphcut - registration of the Kokkos (/kk) styles.  Compiled only when
   the LAMMPS that sphcut builds against has the KOKKOS package; called
   from lammpsplugin_init() in src/sphcut_plugin.cpp.  Each /kk style is
   registered as name/kk and name/kk/device (the Kokkos device: the GPU in
   a CUDA build) and name/kk/host (the host threads); `-sf kk` picks
   name/kk.
------------------------------------------------------------------------- */

#include "lammpsplugin.h"
#include "version.h"

#include "compute_reduce_region_kokkos.h"
#include "compute_surface_lambda_kokkos.h"
#include "fix_contact_tri_penalty_kokkos.h"
#include "fix_heat_fmfs_kokkos.h"
#include "fix_sph_jc_thermal_kokkos.h"
#include "pair_sph_jc_thermal_kokkos.h"

#include <deque>
#include <string>

using namespace LAMMPS_NS;

namespace {

template <class T> Pair *pair_creator(LAMMPS *lmp) { return new T(lmp); }
template <class T> Fix *fix_creator(LAMMPS *lmp, int argc, char **argv) { return new T(lmp, argc, argv); }
template <class T> Compute *compute_creator(LAMMPS *lmp, int argc, char **argv) { return new T(lmp, argc, argv); }

// LAMMPS keeps the name pointer (plugin list, unload): the names live as long as the library
const char *keep(const std::string &name)
{
  static std::deque<std::string> names;
  names.push_back(name);
  return names.back().c_str();
}

void add(lammpsplugin_regfunc reg, void *lmp, void *handle, const char *style, const std::string &name,
         const char *info, void *creator)
{
  lammpsplugin_t plugin;
  plugin.version = LAMMPS_VERSION;
  plugin.style = style;
  plugin.name = keep(name);
  plugin.info = info;
  plugin.author = "sphcut developers";
  plugin.creator.v1 = (lammpsplugin_factory1 *) creator;
  plugin.handle = handle;
  (*reg)(&plugin, lmp);
}

// name/kk and name/kk/device on the device type, name/kk/host on the host type
void add_kk(lammpsplugin_regfunc reg, void *lmp, void *handle, const char *style, const std::string &name,
            const char *info, void *device_creator, void *host_creator)
{
  add(reg, lmp, handle, style, name + "/kk", info, device_creator);
  add(reg, lmp, handle, style, name + "/kk/device", info, device_creator);
  add(reg, lmp, handle, style, name + "/kk/host", info, host_creator);
}

}    // namespace

void sphcut_register_kokkos(lammpsplugin_regfunc reg, void *lmp, void *handle)
{
  add_kk(reg, lmp, handle, "pair", "sph/jc-thermal",
         "sphcut " SPHCUT_VERSION ": updated-Lagrangian SPH solid on the Kokkos device",
         (void *) &pair_creator<PairSPHJCThermalKokkos<LMPDeviceType>>,
         (void *) &pair_creator<PairSPHJCThermalKokkos<LMPHostType>>);
  add_kk(reg, lmp, handle, "fix", "sph/jc-thermal",
         "sphcut " SPHCUT_VERSION ": SPH solid state and time integration on the Kokkos device",
         (void *) &fix_creator<FixSPHJCThermalKokkos<LMPDeviceType>>,
         (void *) &fix_creator<FixSPHJCThermalKokkos<LMPHostType>>);
  add_kk(reg, lmp, handle, "fix", "heat/fmfs",
         "sphcut " SPHCUT_VERSION ": FMFS/Brookshaw heat conduction on the Kokkos device",
         (void *) &fix_creator<FixHeatFMFSKokkos<LMPDeviceType>>,
         (void *) &fix_creator<FixHeatFMFSKokkos<LMPHostType>>);
  add_kk(reg, lmp, handle, "fix", "contact/tri-penalty",
         "sphcut " SPHCUT_VERSION ": penalty contact with a triangulated tool on the Kokkos device",
         (void *) &fix_creator<FixContactTriPenaltyKokkos<LMPDeviceType>>,
         (void *) &fix_creator<FixContactTriPenaltyKokkos<LMPHostType>>);
  add_kk(reg, lmp, handle, "compute", "surface/lambda",
         "sphcut " SPHCUT_VERSION ": free-surface indicator on the Kokkos device",
         (void *) &compute_creator<ComputeSurfaceLambdaKokkos<LMPDeviceType>>,
         (void *) &compute_creator<ComputeSurfaceLambdaKokkos<LMPHostType>>);
  // a LAMMPS style whose outputs would otherwise read per-atom data on the host
  add_kk(reg, lmp, handle, "compute", "reduce/region",
         "sphcut " SPHCUT_VERSION ": compute reduce/region reduced on the Kokkos device (block regions)",
         (void *) &compute_creator<ComputeReduceRegionKokkos<LMPDeviceType>>,
         (void *) &compute_creator<ComputeReduceRegionKokkos<LMPHostType>>);
}
