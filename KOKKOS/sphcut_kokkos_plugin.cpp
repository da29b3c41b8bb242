/* ----------------------------------------------------------------------
   sphcut - registration of the Kokkos (/kk) styles.  Compiled only when
   the LAMMPS that sphcut builds against has the KOKKOS package; called
   from lammpsplugin_init() in src/sphcut_plugin.cpp.  Each /kk style is
   registered as name/kk, name/kk/device and name/kk/host.
------------------------------------------------------------------------- */

#include "lammpsplugin.h"

void sphcut_register_kokkos(lammpsplugin_regfunc, void *, void *)
{
  // no /kk style exists yet: the Kokkos port of the physics is its own issue
}
