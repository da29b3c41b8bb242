/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the model: what every sphcut style reads about the solid (host
   only).  One object holds the materials per atom type, the smoothing
   length per type pair, the particle spacing per type, the kernel, the
   velocity-gradient correction, the hourglass coefficient and the
   dimension.  It parses the pair_coeff keywords, mixes the type pairs and
   writes / reads itself to / from restart files, field by field.

   Owner: pair_style sph/jc-thermal (its pair_style and pair_coeff lines
   define the model; PairSPHJCThermal implements ModelOwner).  Every other
   style (fix sph/jc-thermal, heat/fmfs, contact/tri-penalty, compute
   surface/lambda, their /kk variants) reads it through sphcut::find_model
   / require_model, never through the pair's class: the pair and the fixes
   do not include each other's headers.

   A new material parameter: a Material field (sphcut_material.h) and a row
   of material_fields() (sphcut_model.cpp): the keyword, its default, and
   its restart record come from that row; files written before it read the
   default.  A new flow-stress law: a FlowKind value and a branch of
   sphcut::flow_hardening (sphcut_material.h), its keywords here.
------------------------------------------------------------------------- */

#ifndef SPHCUT_MODEL_H
#define SPHCUT_MODEL_H

#include "pointers.h"
#include "sphcut_pair.h"

#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

namespace sphcut {

// one named parameter of a material: the pair_coeff keyword and the restart field name
struct MaterialField {
  const char *name;
  double Material::*value;
  double fallback;    // default when pair_coeff (or an older restart file) does not give it; UNSET: none
};
// integer fields of a material (selectors and flags), written to restart files as numbers
struct MaterialFlag {
  const char *name;
  int Material::*value;
  int fallback;
};
constexpr double MODEL_UNSET = -1.0e300;
// the tables: every double / int field of Material that is not derived (G, K, c0, cl)
const std::vector<MaterialField> &material_fields();
const std::vector<MaterialFlag> &material_flags();

class Model {
 public:
  // ---- read by every sphcut style
  const Material *materials() const { return mat.data(); }
  const Material &material(int t) const { return mat[t]; }
  double smoothing_length(int t) const { return hlen[idx(t, t)]; }
  double smoothing_length(int i, int j) const { return hlen[idx(i, j)]; }
  double spacing(int t) const { return dp[t]; }    // (m / rho0)^(1/d), set in set_spacing
  const TypePair &type_pair(int i, int j) const { return tpair[idx(i, j)]; }
  const TypePair *type_pair_row(int i) const { return &tpair[idx(i, 0)]; }
  int kernel() const { return kernel_kind; }
  int renormalised() const { return correction; }
  double hourglass_coefficient() const { return hourglass; }
  int dimension() const { return dim; }
  int ntypes() const { return nt; }
  // some defined material has an artificial stress (the pair's rows then carry R: pack_width)
  bool any_artificial_stress() const
  {
    for (int t = 1; t <= nt; t++)
      if (mat[t].defined && mat[t].as_eps > 0.0) return true;
    return false;
  }

  // ---- the owner (pair style): parse, mix, store, restart
  void allocate(int ntypes);
  bool allocated() const { return nt > 0; }
  void settings(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);     // pair_style keywords
  // pair_coeff I J keyword value ...: the material of the like types, h / hdx of the pairs
  void coeff(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg);
  bool length_set(int i, int j) const { return hset[idx(i, j)] != 0; }
  void set_spacing(LAMMPS_NS::LAMMPS *lmp);    // init: dp per type from the masses, the dimension
  double mix(LAMMPS_NS::LAMMPS *lmp, int i, int j);    // init_one: h, W(dp), TypePair; returns the cutoff
  void write_restart(FILE *fp) const;     // settings, then the materials and lengths
  void read_restart(LAMMPS_NS::LAMMPS *lmp, FILE *fp);
  void write_settings(FILE *fp) const;   // the pair_style settings alone (Pair::write_restart_settings)
  // reads the settings (rank 0, broadcast): returns the raw record size of a format-1 file, 0 for
  // format 2; version: the format
  int read_settings(LAMMPS_NS::LAMMPS *lmp, FILE *fp, int &version);
  static constexpr int RESTART_TAG = 0x73706375;    // first int of the settings: field-by-field format
  static constexpr int RESTART_VERSION = 2;         // 1: the raw record of older files (read, see .cpp)

 private:
  int nt = 0;
  int kernel_kind = KERNEL_CUBIC;
  int correction = 1;       // 1: renormalised velocity gradient (exact for linear fields)
  double hourglass = 0.0;   // hourglass control coefficient kappa (0: off; sphcut::hourglass_pair)
  int dim = 3;
  std::vector<Material> mat;      // per type, 1..ntypes
  std::vector<double> hlen;       // smoothing length per type pair
  std::vector<double> hdx;        // h given as a multiple of the particle spacing (0: not used)
  std::vector<int> hset;          // h or hdx given by pair_coeff for this pair
  std::vector<double> wdp;        // W(dp) per type pair (artificial stress reference)
  std::vector<double> dp;         // particle spacing per type, from mass and rho0
  std::vector<TypePair> tpair;    // constants of each type pair (sphcut::mix_type_pair)
  int idx(int i, int j) const { return i * (nt + 1) + j; }

  Material parse_material(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, int &nmat, double &h, double &hx) const;
  void check_material(LAMMPS_NS::LAMMPS *lmp, Material &m, const char *iarg, const char *jarg) const;
  void store(LAMMPS_NS::LAMMPS *lmp, char **arg, const Material &m, int nmat, double h, double hx);
  void read_material(LAMMPS_NS::LAMMPS *lmp, FILE *fp, int version, int legacy_size, Material &m);
};

// implemented by the style that owns the model (pair sph/jc-thermal)
class ModelOwner {
 public:
  // the exception specification of LAMMPS' Pointers::~Pointers() (see sphcut::AttachedStyle)
  virtual ~ModelOwner() noexcept(std::is_nothrow_destructible<LAMMPS_NS::Pointers>::value) {}
  virtual const Model &model() const = 0;
};

// the model of pair_style sph/jc-thermal (or /kk), nullptr without it
const Model *find_model(LAMMPS_NS::LAMMPS *lmp);
// the same, or error->all "<who> requires pair_style sph/jc-thermal"
const Model &require_model(LAMMPS_NS::LAMMPS *lmp, const std::string &who);

}    // namespace sphcut

#endif
