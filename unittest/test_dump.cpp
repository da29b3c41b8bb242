// command dump_sph: the SPH state under readable column names, values equal to the
// per-atom outputs they stand for, named errors for bad fields
#include "sphcut_test.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

using sphcut_test::Lammps;

namespace {

// 9 x 7 particles at spacing 1e-3, temperature 300 + 1000 x, one material
void block(Lammps &l, bool surface_compute, bool contact = false)
{
  l.cmds({"units si", "dimension 2", "boundary f f p", "atom_style atomic", "atom_modify map array",
          "lattice sq 1e-3", "region box block -2 12 -2 10 -0.5 0.5", "create_box 1 box",
          "region blk block -0.01 8.01 -0.01 6.01 -0.5 0.5", "create_atoms 1 region blk", "mass 1 4.43e-3",
          "pair_style sph/jc-thermal",
          "pair_coeff 1 1 rho0 4430 E 113.8e9 nu 0.35 A 862e6 B 331e6 n 0.35 k 7.3 cp 580 hdx 1.3",
          "variable T0 atom 300+1000*x", "fix sph all sph/jc-thermal temp v_T0"});
  if (surface_compute) l.cmd("compute surf all surface/lambda");
  if (contact)
    l.cmd("fix cut all contact/tri-penalty insert rake 0 clearance 7 radius 0 rake_length 3e-3 "
          "flank_length 2e-3 move 20e-3 4e-3 0 velocity 0 0 0 E 620e9");
}

// the header columns and the rows (by atom id) of a one-frame dump file
struct Frame {
  std::vector<std::string> cols;
  std::map<int, std::vector<double>> rows;
  int col(const std::string &name) const
  {
    for (size_t i = 0; i < cols.size(); i++)
      if (cols[i] == name) return (int) i;
    return -1;
  }
};

Frame read_dump(const std::string &file)
{
  Frame fr;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("ITEM: ATOMS", 0) == 0) break;
  std::istringstream hs(line.substr(11));
  for (std::string w; hs >> w;) fr.cols.push_back(w);
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::vector<double> v;
    for (double d; ls >> d;) v.push_back(d);
    if (v.size() == fr.cols.size()) fr.rows[(int) v[0]] = v;
  }
  return fr;
}

}    // namespace

TEST(DumpSPH, ReadableColumnsHoldTheState)
{
  Lammps l;
  block(l, true);
  l.cmds({"dump_sph d all 1 dump.sph id type x y density pressure vonmises plastic_strain temperature surface "
          "lambda f_sph[12] v_T0",
          "run 0"});
  const Frame fr = read_dump("dump.sph");
  const std::vector<std::string> want = {"id", "type", "x", "y", "density", "pressure", "vonmises",
                                         "plastic_strain", "temperature", "surface", "lambda", "f_sph[12]", "v_T0"};
  ASSERT_EQ(fr.cols, want);
  ASSERT_EQ(fr.rows.size(), 63u);
  int nsurf = 0;
  for (const auto &r : fr.rows) {
    const std::vector<double> &v = r.second;
    EXPECT_NEAR(v[fr.col("density")], 4430.0, 1e-9);
    EXPECT_NEAR(v[fr.col("pressure")], 0.0, 1e-3);
    EXPECT_EQ(v[fr.col("plastic_strain")], 0.0);
    // the named column is fix sph/jc-thermal column 12, the initial temperature
    EXPECT_EQ(v[fr.col("temperature")], v[fr.col("f_sph[12]")]);
    EXPECT_NEAR(v[fr.col("temperature")], 300.0 + 1000.0 * v[fr.col("x")], 1e-9);
    const bool edge = fabs(v[2]) < 1e-9 || fabs(v[2] - 8e-3) < 1e-9 || fabs(v[3]) < 1e-9 || fabs(v[3] - 6e-3) < 1e-9;
    EXPECT_EQ(v[fr.col("surface")], edge ? 1.0 : 0.0) << "atom " << r.first;
    // the flag is lambda below the threshold 0.75
    EXPECT_EQ(v[fr.col("surface")] > 0.5, v[fr.col("lambda")] < 0.75) << "atom " << r.first;
    nsurf += v[fr.col("surface")] > 0.5;
  }
  EXPECT_EQ(nsurf, 2 * 9 + 2 * 5);    // the outer layer of the 9 x 7 block
}

TEST(DumpSPH, ContactForceColumnsAndDumpModify)
{
  Lammps l;
  block(l, false, true);
  l.cmds({"dump_sph d all 1 dump.fc id fcontact_x fcontact_y", "dump_modify d sort id", "run 0"});
  const Frame fr = read_dump("dump.fc");
  ASSERT_EQ(fr.cols, (std::vector<std::string>{"id", "fcontact_x", "fcontact_y"}));
  EXPECT_EQ(fr.rows.size(), 63u);    // the tool is far away: no contact
  for (const auto &r : fr.rows) EXPECT_EQ(r.second[1], 0.0);
}

// the normal / friction / feature columns of the contact fix (4-6) under their names
TEST(DumpSPH, ContactDecompositionColumns)
{
  Lammps l;
  block(l, false, true);
  l.cmds({"dump_sph d all 1 dump.fn id fcontact_n fcontact_t contact_feature f_cut[6]", "dump_modify d sort id",
          "run 0"});
  const Frame fr = read_dump("dump.fn");
  ASSERT_EQ(fr.cols, (std::vector<std::string>{"id", "fcontact_n", "fcontact_t", "contact_feature", "f_cut[6]"}));
  EXPECT_EQ(fr.rows.size(), 63u);
  for (const auto &r : fr.rows) EXPECT_EQ(r.second[fr.col("contact_feature")], r.second[4]);
}

TEST(DumpSPH, BadFieldsAreNamedErrors)
{
  Lammps l;
  block(l, false);
  EXPECT_TRUE(l.error_contains("dump_sph d all 1 dump.x id surface",
                               "field surface needs a compute surface/lambda"));
  EXPECT_TRUE(l.error_contains("dump_sph d all 1 dump.x id fcontact_x",
                               "field fcontact_x needs a fix contact/tri-penalty"));
  EXPECT_TRUE(l.error_contains("dump_sph d all 1 dump.x id density density", "field density given twice"));
  EXPECT_TRUE(l.error_contains("dump_sph d all 1 dump.x", "Illegal dump_sph command"));
  // a name that is neither a sphcut field nor a dump custom field: the error of dump custom
  EXPECT_TRUE(l.error_contains("dump_sph d all 1 dump.x id densty", "densty"));
}
