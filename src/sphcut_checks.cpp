/* ----------------------------------------------------------------------
   sphcut - setup-time input checks (see sphcut_checks.h)
------------------------------------------------------------------------- */

#include "sphcut_checks.h"

#include "atom.h"
#include "comm.h"
#include "error.h"

#include <cmath>

using namespace LAMMPS_NS;

namespace sphcut {

void check_masses(LAMMPS *lmp, const char *who)
{
  Atom *atom = lmp->atom;
  if (!atom->rmass) {
    // LAMMPS checks the per-type masses only after the styles are initialised; the
    // spacing the pair style derives from them would be 0 (or NaN) before that
    for (int t = 1; t <= atom->ntypes; t++)
      if (!atom->mass || !atom->mass_setflag || !atom->mass_setflag[t])
        lmp->error->all(FLERR, "{}: mass of atom type {} is not set (use the mass command)", who, t);
    return;
  }
  // per-atom masses: a zero (e.g. fix property/atom rmass without set mass) gives NaN forces
  bigint nbad = 0;
  tagint first = 0;
  double mfirst = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double m = atom->rmass[i];
    if (m > 0.0 && std::isfinite(m)) continue;
    if (!nbad || atom->tag[i] < first) {
      first = atom->tag[i];
      mfirst = m;
    }
    nbad++;
  }
  bigint nall = 0;
  MPI_Allreduce(&nbad, &nall, 1, MPI_LMP_BIGINT, MPI_SUM, lmp->world);
  if (!nall) return;
  // the offending atom with the smallest id, and its mass (held by one rank)
  const tagint mine = nbad ? first : MAXTAGINT;
  tagint gfirst = 0;
  MPI_Allreduce(&mine, &gfirst, 1, MPI_LMP_TAGINT, MPI_MIN, lmp->world);
  const double m = mine == gfirst ? mfirst : 0.0;
  double gm = 0.0;
  MPI_Allreduce(&m, &gm, 1, MPI_DOUBLE, MPI_SUM, lmp->world);
  lmp->error->all(FLERR, "{}: {} atom(s) have a per-atom mass (rmass) <= 0 or not finite, e.g. atom {} with mass {} "
                  "(set it with the set command or in the data file)", who, nall, gfirst, gm);
}

}    // namespace sphcut
