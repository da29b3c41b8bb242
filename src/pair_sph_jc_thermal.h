/* -*- c++ -*- ----------------------------------------------------------
   sphcut - pair_style sph/jc-thermal: updated-Lagrangian SPH for
   elasto-plastic solids with Johnson-Cook plasticity.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(sph/jc-thermal,PairSPHJCThermal);
// clang-format on
#else

#ifndef LMP_PAIR_SPH_JC_THERMAL_H
#define LMP_PAIR_SPH_JC_THERMAL_H

#include "pair.h"
#include "sphcut_model.h"
#include "sphcut_timer.h"

#include <vector>

namespace LAMMPS_NS {

// owns the model (sphcut::Model: materials, smoothing lengths, kernel), which its pair_style
// and pair_coeff lines define; reads the per-atom state of fix sph/jc-thermal (sphcut::StateOwner)
class PairSPHJCThermal : public Pair, public sphcut::AttachedStyle, public sphcut::ModelOwner {
 public:
  PairSPHJCThermal(class LAMMPS *);
  ~PairSPHJCThermal() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  double memory_usage() override;

  // the model, for the other sphcut styles (they find it with sphcut::find_model)
  const sphcut::Model &model() const override { return mdl; }
  std::string timing_name() const override { return "pair sph/jc-thermal"; }

 protected:
  sphcut::Model mdl;
  sphcut::StateOwner *fix;

  int nmax;                       // scratch arrays, local + ghost
  double **pack;                  // per particle: what its neighbours read (packed row, see the .cpp)
  double **acc;                   // neighbour sums (sphcut::PairAcc layout; ACC_F is added to atom->f)
  double **lgrad;                 // hourglass control: velocity gradient L per particle (row major, 9)
  double **hgacc;                 // hourglass control: force (3) and du (1) per particle
  int comm_mode;                  // what pack/unpack_*_comm move: COMM_ACC (the sums), COMM_HG (L / du)
  std::vector<int> nbr_j;         // the pairs of one particle within the cutoff, and their scalars
  std::vector<sphcut::PairScalars> nbr_s;

  void allocate();
  template <int DIM, int NEWTON> void pair_loop(int any_as);
  template <int DIM, int NEWTON> void hourglass_loop();
  void hourglass_forces();
  void grow_scratch(int);
  void free_scratch();
};

}    // namespace LAMMPS_NS

#endif
#endif
