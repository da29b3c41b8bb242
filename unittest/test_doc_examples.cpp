// Every input example of the doc pages runs: the `.. code-block:: LAMMPS` blocks of the
// Examples section of each doc/*.rst are extracted and run, one block per LAMMPS instance,
// in a small 3D scene (SI units, a Ti6Al4V block of type 1 and a carbide layer of type 2,
// group clamp, region bottom, the files the examples read), then 2 steps.  So an example
// whose syntax rots (a renamed keyword, a column that moved) fails here.
//
// Conventions for the doc blocks: leading `plugin load`, `units` and `dimension` lines are
// the head of an input and run before the scene (the plugin is already loaded from the build,
// so `plugin load` is skipped); the scene defines pair_style sph/jc-thermal (unless the
// block does) and fix sph (which a block may redefine).  Per-atom variables of the examples
// are checked against the columns they name (the f_ID[k] vs F_ID[k] trap of issue 11).
#include "sphcut_test.h"

#include "fix.h"
#include "modify.h"
#include "sphcut_stl.h"

#include <dirent.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using sphcut_test::Lammps;
using sphcut_test::box_triangles;

namespace {

struct Block {
  std::string page;
  int line = 0;
  std::vector<std::string> lines;    // dedented, continuation lines (&) kept
};

std::string trim(const std::string &s)
{
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

bool is_underline(const std::string &s)
{
  const std::string t = trim(s);
  if (t.size() < 3 || t != s) return false;
  return t.find_first_not_of(t[0]) == std::string::npos && std::string("\"=-^~*#").find(t[0]) != std::string::npos;
}

std::vector<Block> doc_examples(const std::string &dir)
{
  std::vector<std::string> pages;
  if (DIR *d = opendir(dir.c_str())) {
    while (struct dirent *e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > 4 && n.compare(n.size() - 4, 4, ".rst") == 0) pages.push_back(n);
    }
    closedir(d);
  }
  std::sort(pages.begin(), pages.end());
  std::vector<Block> out;
  for (const auto &page : pages) {
    std::ifstream in(dir + "/" + page);
    std::vector<std::string> l;
    std::string s;
    while (std::getline(in, s)) l.push_back(s);
    std::string section;
    for (size_t k = 0; k < l.size(); k++) {
      if (k + 1 < l.size() && !trim(l[k]).empty() && l[k][0] != ' ' && is_underline(l[k + 1])) section = trim(l[k]);
      if (section != "Examples" || trim(l[k]) != ".. code-block:: LAMMPS") continue;
      Block b;
      b.page = page;
      b.line = (int) k + 1;
      size_t j = k + 1;
      for (; j < l.size(); j++) {
        if (!trim(l[j]).empty() && l[j][0] != ' ') break;
        b.lines.push_back(l[j].size() > 3 ? l[j].substr(3) : trim(l[j]));
      }
      while (!b.lines.empty() && trim(b.lines.back()).empty()) b.lines.pop_back();
      out.push_back(b);
      k = j - 1;
    }
  }
  return out;
}

using sphcut_test::num;

std::string first_word(const std::string &line)
{
  std::istringstream ss(line);
  std::string w;
  ss >> w;
  return w;
}

bool block_has(const Block &b, const std::string &start)
{
  for (const auto &s : b.lines)
    if (trim(s).compare(0, start.size(), start) == 0) return true;
  return false;
}

void write_scene_files()
{
  // plate.stl below the workpiece, insert.stl (in mm) beside it, a mu(T) table
  const double plo[3] = {-1.0e-3, -0.3e-3, -1.0e-3}, phi[3] = {1.0e-3, -0.1e-3, 1.0e-3};
  sphcut::write_stl_ascii("plate.stl", box_triangles(plo, phi), "plate");
  const double ilo[3] = {0.2, -0.8, -0.2}, ihi[3] = {0.6, -0.5, 0.2};
  sphcut::write_stl_binary("insert.stl", box_triangles(ilo, ihi));
  std::ofstream("mu_T.txt") << "# T mu\n300 0.4\n1000 0.25\n";
}

// the head lines of the block, the scene, the rest of the block, 2 steps
void run_block(Lammps &l, const Block &b)
{
  size_t k = 0;
  std::vector<std::string> head;
  for (; k < b.lines.size(); k++) {
    const std::string w = first_word(b.lines[k]);
    if (w.empty() || w[0] == '#') continue;
    if (w != "plugin" && w != "units" && w != "dimension") break;
    if (w != "plugin") head.push_back(b.lines[k]);
  }
  l.cmd("units si");    // the examples are in SI units; a head line may say so again
  l.cmds(head);
  // workpiece x in [-0.6, -0.2] mm, y in [0, 0.4] mm (clear of the tools of the examples),
  // carbide layer above it, spacing 0.1 mm
  const double dx = 1.0e-4;
  l.cmds({"atom_style atomic", "atom_modify map array", "lattice sc 1e-4",
          "region box block -12 12 -12 12 -6 6", "create_box 2 box",
          "region wp block -6.01 -1.99 -0.01 4.01 -2.01 2.01", "create_atoms 1 region wp",
          "region tp block -6.01 -1.99 4.99 5.01 -2.01 2.01", "create_atoms 2 region tp",
          "mass 1 " + num(4430.0 * dx * dx * dx), "mass 2 " + num(15000.0 * dx * dx * dx),
          "region bottom block INF INF INF 0.5 INF INF", "group clamp region bottom", "group work type 1",
          // a shear flow, so that the stress columns differ from atom to atom
          "variable vx0 atom 1.0e4*y", "velocity work set v_vx0 0 0 units box", "timestep 1e-9"});
  if (!block_has(b, "pair_style"))
    l.cmds({"pair_style sph/jc-thermal",
            "pair_coeff 1 1 rho0 4430 E 113.8e9 nu 0.35 cp 580 k 7.3 hdx 1.2",
            "pair_coeff 2 2 rho0 15000 E 6.0e11 nu 0.22 cp 292 k 88 hdx 1.2"});
  l.cmd("fix sph all sph/jc-thermal");
  if (b.page == "dump_sph.rst")    // its fields come from these two styles
    l.cmds({"compute surf all surface/lambda", "fix tool work contact/tri-penalty stl plate.stl"});
  // the rest of the block as one input file (continuation lines with &)
  std::ofstream out("block.in");
  for (size_t m = 0; m < b.lines.size(); m++) {
    const std::string w = first_word(b.lines[m]);
    if (m < k && w != "" && w[0] != '#') continue;    // head, run above
    out << b.lines[m] << "\n";
  }
  out.close();
  l.lmp->input->file("block.in");
  l.cmd("run 2");
}

}    // namespace

TEST(DocExamples, EveryExampleBlockRuns)
{
  write_scene_files();
  const std::vector<Block> blocks = doc_examples(std::string(SPHCUT_SOURCE_DIR) + "/doc");
  // every style page has examples (a page added without them, or a renamed section, fails)
  std::vector<std::string> pages;
  for (const auto &b : blocks) pages.push_back(b.page);
  for (const char *p : {"compute_surface_lambda.rst", "dump_sph.rst", "fix_contact_tri_penalty.rst",
                        "fix_heat_fmfs.rst", "fix_sph_jc_thermal.rst", "pair_sph_jc_thermal.rst"})
    EXPECT_NE(std::find(pages.begin(), pages.end(), p), pages.end()) << "no Examples code block in doc/" << p;
  int nvar = 0;
  for (const auto &b : blocks) {
    SCOPED_TRACE("doc/" + b.page + ":" + std::to_string(b.line));
    std::string text;
    for (const auto &s : b.lines) text += s + "\n";
    Lammps l;
    try {
      run_block(l, b);
    } catch (LAMMPS_NS::LAMMPSException &e) {
      ADD_FAILURE() << "the example fails: " << e.what() << "\n" << text;
      continue;
    }
    // per-atom variables of the example: `variable NAME atom F_ID[a]-F_ID[b]` must give the
    // difference of those per-atom columns, atom by atom
    for (const auto &s : b.lines) {
      std::istringstream ss(s);
      std::string cmd, name, style, expr;
      ss >> cmd >> name >> style >> expr;
      if (cmd != "variable" || style != "atom") continue;
      const int iv = l.lmp->input->variable->find(name.c_str());
      ASSERT_GE(iv, 0);
      const int nlocal = l.lmp->atom->nlocal;
      std::vector<double> val(nlocal);
      l.lmp->input->variable->compute_atom(iv, 0, val.data(), 1, 0);
      char fid[64];
      int ca = 0, cb = 0;
      if (sscanf(expr.c_str(), "%*[Ff]_%63[^[][%d]-%*[Ff]_%*[^[][%d]", fid, &ca, &cb) != 3) continue;
      LAMMPS_NS::Fix *f = sphcut::fix_by_id(l.lmp->modify, fid);
      double spread = 0.0, worst = 0.0;
      for (int i = 0; i < nlocal; i++) {
        const double want = f->array_atom[i][ca - 1] - f->array_atom[i][cb - 1];
        worst = std::max(worst, fabs(val[i] - want));
        spread = std::max(spread, fabs(want - (f->array_atom[0][ca - 1] - f->array_atom[0][cb - 1])));
      }
      EXPECT_GT(spread, 0.0) << "the scene should give different values per atom";
      EXPECT_LE(worst, 1e-9 * spread) << "variable " << name << " (" << expr << ") is not the per-atom "
                                      << "column difference";
      nvar++;
    }
  }
  std::printf("[ docs     ] %zu example blocks run, %d per-atom variables checked\n", blocks.size(), nvar);
  EXPECT_GE(nvar, 1);
}
