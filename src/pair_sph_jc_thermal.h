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
#include "sphcut_pair.h"
#include "sphcut_timer.h"

#include <vector>

namespace LAMMPS_NS {

class FixSPHJCThermal;

class PairSPHJCThermal : public Pair, public sphcut::AttachedStyle {
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

  // interface for fix sph/jc-thermal and the other sphcut styles
  const sphcut::Material *materials() const { return mat; }
  double smoothing_length(int itype) const { return hlen[itype][itype]; }
  double smoothing_length(int itype, int jtype) const { return hlen[itype][jtype]; }
  const sphcut::TypePair &type_pair(int itype, int jtype) const { return tpair[itype][jtype]; }
  int renormalised() const { return correction; }
  double hourglass_coefficient() const { return hourglass; }
  int kernel() const { return kernel_kind; }
  double spacing(int itype) const { return dp[itype]; }    // (m/rho0)^(1/d), set in init_style
  FixSPHJCThermal *state_fix() const { return fix; }
  std::string timing_name() const override { return "pair sph/jc-thermal"; }

 protected:
  int kernel_kind;
  int correction;                 // 1: renormalised velocity gradient (exact for linear fields)
  double hourglass;               // hourglass control coefficient kappa (0: off; sphcut::hourglass_pair)
  sphcut::Material *mat;          // per type, 1..ntypes
  double **hlen;                  // smoothing length per type pair
  double **hdx;                   // h given as a multiple of the particle spacing (0: not used)
  double **wdp;                   // W(dp) per type pair (artificial stress reference)
  double *dp;                     // particle spacing per type, from mass and rho0
  sphcut::TypePair **tpair;       // constants of each type pair (sphcut::mix_type_pair)
  FixSPHJCThermal *fix;

  int nmax;                       // scratch arrays, local + ghost
  double **pack;                  // per particle: what its neighbours read (packed row, see the .cpp)
  double **acc;                   // neighbour sums (sphcut::PairAcc layout; ACC_F is added to atom->f)
  double **lgrad;                 // hourglass control: velocity gradient L per particle (row major, 9)
  double **hgacc;                 // hourglass control: force (3) and du (1) per particle
  int comm_mode;                  // what pack/unpack_*_comm move: COMM_ACC (the sums), COMM_HG (L / du)
  std::vector<int> nbr_j;         // the pairs of one particle within the cutoff, and their scalars
  std::vector<sphcut::PairScalars> nbr_s;
  int restart_matsize;            // bytes of a material record in the restart file being read

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
