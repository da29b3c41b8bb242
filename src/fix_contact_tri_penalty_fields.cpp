/* ----------------------------------------------------------------------
   sphcut - fix contact/tri-penalty: tool fields per facet (keywords
   tool_fields N, wear usui K alpha).  Member functions of
   FixContactTriPenalty kept apart from the contact itself: the keywords,
   the interval's time, the end of an averaging interval
   (sphcut::ToolFields), the global vector elements 48-52, the per-facet
   array and the restart block.  Each contact's share of the facets is
   booked by sphcut::contact_step (facet_scatter, the same for the CPU and
   /kk drivers).
------------------------------------------------------------------------- */

#include "fix_contact_tri_penalty.h"

#include "sphcut_checks.h"

#include "comm.h"
#include "error.h"
#include "update.h"

using namespace LAMMPS_NS;

/* the keywords tool_fields N and wear usui K alpha: the number of arguments used, 0 if kw is not one of them */

int FixContactTriPenalty::fields_parse(const std::string &kw, int iarg, int narg, char **arg)
{
  if (kw == "tool_fields") {
    if (iarg + 1 >= narg) error->all(FLERR, "Fix contact/tri-penalty: keyword tool_fields needs 1 value(s)");
    fields.every = sphcut::parse_int(lmp, "Fix contact/tri-penalty", "tool_fields interval", arg[iarg + 1]);
    return 2;
  }
  if (kw == "wear") {
    if (iarg + 3 >= narg) error->all(FLERR, "Fix contact/tri-penalty: keyword wear needs 3 value(s) (usui K alpha)");
    if (std::string(arg[iarg + 1]) != "usui")
      error->all(FLERR, "Fix contact/tri-penalty: wear model must be usui, got {}", arg[iarg + 1]);
    fields.K = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
    fields.alpha = utils::numeric(FLERR, arg[iarg + 3], false, lmp);
    if (fields.K < 0.0) error->all(FLERR, "Fix contact/tri-penalty: wear usui K must be >= 0, got {}", fields.K);
    if (fields.alpha < 0.0)
      error->all(FLERR, "Fix contact/tri-penalty: wear usui alpha must be >= 0, got {}", fields.alpha);
    fields.wear = 1;
    return 4;
  }
  return 0;
}

/* after the geometry is loaded (constructor): the facets, the array, the vector's length */

void FixContactTriPenalty::fields_setup()
{
  size_vector = NVEC;    // the tool fields' sums, then the spin's (fix_contact_tri_penalty.h)
  if (fields.wear && !fields.every)
    error->all(FLERR, "Fix contact/tri-penalty: wear usui needs tool_fields N (the averaging interval)");
  if (fields.wear && id_heat.empty())
    error->all(FLERR, "Fix contact/tri-penalty: wear usui needs the interface temperature: give heat ID "
               "(a fix heat/fmfs)");
  if (!fields.every) return;
  fields.build(elem, nvert, elem_feature);
  array_flag = 1;
  size_array_rows = fields.nfacet;
  size_array_cols = sphcut::ToolFields::NCOL;
  extarray = 0;
}

// a step's contact evaluation adds its dt to the running interval
void FixContactTriPenalty::fields_step()
{
  if (fields.every && !update->setupflag) fields.time += update->dt;
}

// the end of an interval (steps that are multiples of N): averages, depth, global sums
void FixContactTriPenalty::fields_end_of_step()
{
  if (fields.every && update->ntimestep % fields.every == 0) fields.close_interval(world, current_elements());
}

/* a run's setup: the array where it is read at the setup step (fix print, thermo, variables).
   At steps that are multiples of N (step 0 included) the centroids of the tool's pose of this
   step, as the interval closed there would give them: at step 0 no interval has closed and out
   held the constructor's zeros (a spinning tool's angle read from a centroid came out wrong
   at step 0); a continued run at a multiple of N gets the values its last step closed with (the
   same arithmetic of the same pose, unchanged).  A fix defined anew at another step gets the
   pose too (no interval of it has closed).  The averages, the running sums and the interval's
   time are left alone; a restored fix between intervals keeps the restart file's array (a split
   run reads as the unsplit one) */

void FixContactTriPenalty::fields_at_setup()
{
  if (!fields.every) return;
  if (update->ntimestep % fields.every == 0 || (!inside_checked && !restored)) fields.set_pose(current_elements());
}

double FixContactTriPenalty::compute_array(int i, int j)
{
  return fields.out[(size_t) i * sphcut::ToolFields::NCOL + j];
}

/* restart: a flag (1: tool fields follow) and ToolFields::restart_data; collective */

void FixContactTriPenalty::fields_write_restart(std::vector<double> &list)
{
  list.push_back(fields.every ? 1.0 : 0.0);
  if (!fields.every) return;
  const std::vector<double> b = fields.restart_data(world);
  list.insert(list.end(), b.begin(), b.end());
}

void FixContactTriPenalty::fields_restart(const double *buf)
{
  if (buf[0] == 0.0 || !fields.every) return;    // none stored, or none wanted now
  if (!fields.read_restart(buf + 1, comm->me == 0))
    error->all(FLERR, "Fix contact/tri-penalty: the restart file holds tool fields of {} facets, the tool has {}",
               (int) buf[1], fields.nfacet);
}
