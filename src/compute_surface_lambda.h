/* -*- c++ -*- ----------------------------------------------------------
   sphcut - compute surface/lambda: free-surface flag of SPH particles from
   the minimum eigenvalue lambda of the renormalisation matrix (Marrone et
   al. 2010; seed 003 sec. 4.2 and eq. 14)
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(surface/lambda,ComputeSurfaceLambda);
// clang-format on
#else

#ifndef LMP_COMPUTE_SURFACE_LAMBDA_H
#define LMP_COMPUTE_SURFACE_LAMBDA_H

#include "compute.h"
#include "sphcut_thermal.h"
#include "sphcut_model.h"
#include "sphcut_timer.h"

#include <vector>

namespace LAMMPS_NS {

class FixSPHJCThermal;

class ComputeSurfaceLambda : public Compute, public sphcut::AttachedStyle {
 public:
  enum { LAMBDA = 0, FLAG, NX, NY, NZ, NCOLS };
  ComputeSurfaceLambda(class LAMMPS *, int, char **);
  ~ComputeSurfaceLambda() override;
  void init() override;
  void init_list(int, class NeighList *) override;
  void compute_peratom() override;
  double memory_usage() override;

  // for fix heat/fmfs: 1 if local atom i is a surface particle (valid after compute_peratom)
  int is_surface(int i) const { return out[i][FLAG] > 0.5; }
  double threshold;
  // fix heat/fmfs may compute lambda, flag and normal in its own neighbour pass (the same
  // sphcut_thermal.h arithmetic, bit for bit) when the compute sees the same neighbours:
  // the same group and tool particles counted as neighbours (tool yes)
  bool fusable(int fix_groupbit) const { return groupbit == fix_groupbit && tool_hides; }
  // start an invocation at this step (invoked_peratom, output grown); true when the values
  // must be computed now (the caller then fills them), false when they are kept
  virtual bool begin_step();
  double **values() { return out; }
  // the type-pair constants of the pass (support, kernel normalisation), [itype * (ntypes+1) + jtype]
  const sphcut::ThermalPair *type_pairs() const { return tpair.data(); }
  std::string timing_name() const override { return std::string("compute surface/lambda ") + id; }

 protected:
  int every;                  // recompute every this many steps (and after reneighboring)
  int tool_hides;             // 1: tool particles count as neighbours of the workpiece
  bigint last_step, last_neigh;
  int nmax;
  double **out;
  std::vector<sphcut::ThermalPair> tpair;
  class NeighList *list;
  FixSPHJCThermal *fix;
  const sphcut::Model *model;    // the model of pair sph/jc-thermal (sphcut::find_model)
  template <int DIM> void compute_dim();
  bool recompute_due();
};

}    // namespace LAMMPS_NS

#endif
#endif
