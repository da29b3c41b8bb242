/* ----------------------------------------------------------------------
   sphcut - setup-time input checks (see sphcut_checks.h)
------------------------------------------------------------------------- */

#include "sphcut_checks.h"
#include "sphcut_model.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

using namespace LAMMPS_NS;

namespace sphcut {

int parse_int(LAMMPS *lmp, const std::string &who, const std::string &keyword, const char *text, int lo, int hi)
{
  const std::string word = text ? text : "";
  // a sign and digits only: strtoll alone would take leading blanks, "0x10" and "12abc" (as 12)
  const size_t digits = word.find_first_not_of("+-") == 1 ? 1 : 0;
  if (word.empty() || digits >= word.size() || word.find_first_not_of("0123456789", digits) != std::string::npos)
    lmp->error->all(FLERR, "{}: {} must be an integer, got {}", who, keyword, word);
  errno = 0;
  const long long v = std::strtoll(word.c_str(), nullptr, 10);
  const bool overflow = errno == ERANGE;    // beyond long long: v is LLONG_MIN or LLONG_MAX
  if (v < lo) lmp->error->all(FLERR, "{}: {} must be >= {}, got {}", who, keyword, lo, word);
  if (overflow || v > hi) lmp->error->all(FLERR, "{}: {} must be <= {}, got {} (out of range)", who, keyword, hi, word);
  return (int) v;
}

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

bigint warn_close_pairs(LAMMPS *lmp, NeighList *list, const Model &model, double frac)
{
  Atom *atom = lmp->atom;
  double count = 0.0, rmin = 1.0e300;
  if (list && list->ilist && list->numneigh && list->firstneigh) {
    double **x = atom->x;
    const int *type = atom->type;
    const int nlocal = atom->nlocal;
    // half list: a local-ghost pair is listed on both ranks without newton
    const double wghost = lmp->force->newton_pair ? 1.0 : 0.5;
    for (int ii = 0; ii < list->inum; ii++) {
      const int i = list->ilist[ii];
      const int *jl = list->firstneigh[i];
      for (int jj = 0; jj < list->numneigh[i]; jj++) {
        const int j = jl[jj] & NEIGHMASK;
        const double dp = 0.5 * (model.spacing(type[i]) + model.spacing(type[j]));
        if (!(dp > 0.0)) continue;
        const double dx = x[i][0] - x[j][0], dy = x[i][1] - x[j][1], dz = x[i][2] - x[j][2];
        const double r = sqrt(dx * dx + dy * dy + dz * dz) / dp;
        if (r >= frac) continue;
        count += j < nlocal ? 1.0 : wghost;
        rmin = std::min(rmin, r);
      }
    }
  }
  return report_close_pairs(lmp, count, rmin, frac);
}

bigint report_close_pairs(LAMMPS *lmp, double count, double rmin, double frac)
{
  double gcount = 0.0, grmin = 0.0;
  MPI_Allreduce(&count, &gcount, 1, MPI_DOUBLE, MPI_SUM, lmp->world);
  MPI_Allreduce(&rmin, &grmin, 1, MPI_DOUBLE, MPI_MIN, lmp->world);
  const bigint n = (bigint) std::llround(gcount);
  if (n > 0 && lmp->comm->me == 0)
    lmp->error->warning(FLERR, "{} pair(s) of particles closer than {} spacing, the closest {:.3g} spacing apart: "
                        "they move as one (duplicate atoms? check create_atoms and read_data)", n, frac, grmin);
  return n;
}

}    // namespace sphcut
