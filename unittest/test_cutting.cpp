// The flagship case (examples/cutting-2d-ti6al4v) at a coarse resolution and a short cut:
// runs without lost atoms or NaN, a chip starts to form, the forces are positive and in a
// broad band around the experiment, and the energy balance of the tool closes:
// work of the tool = kinetic + internal energy of the particles + contact dissipation.
#include "sphcut_test.h"

#include "library.h"
#include "update.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

using sphcut_test::Lammps;

// the restart tests' helpers: positions by atom ID over all ranks; rank 0 removes the periodic
// restart files of an earlier test (restart.a, restart.b), or puts restart.b where -var continue
// reads (restart.cutting; false when there is none)
std::vector<double> gathered_positions(Lammps &l)
{
  std::vector<double> x(3 * static_cast<size_t>(l.lmp->atom->natoms));
  lammps_gather_atoms(l.lmp, (char *) "x", 1, 3, x.data());
  return x;
}

void remove_periodic_restarts()
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0) {
    std::remove("restart.a");
    std::remove("restart.b");
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

bool continue_from_restart_b()
{
  int me, ok = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me == 0) {
    std::ifstream src("restart.b", std::ios::binary);
    ok = src.good();
    std::ofstream dst("restart.cutting", std::ios::binary);
    if (ok) dst << src.rdbuf();
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return ok;
}

// forces.dat's lines by step (a continued run appends: the last line of a step wins); rank 0 only
std::map<long, std::string> forces_rows()
{
  std::map<long, std::string> rows;
  std::ifstream in("forces.dat");
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') rows[std::stol(line)] = line;
  return rows;
}

// every line and column of forces.dat (step, time, cut, Fc, Ft, Tmax, Trake) against the uninterrupted
// run's (rank 0): the same text on one rank (rtol 0); on several, each column within rtol of its largest
// value in the reference
void expect_same_rows(const std::map<long, std::string> &ref, const std::map<long, std::string> &got, double rtol)
{
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  if (me != 0) return;
  auto values = [](const std::string &line) {
    std::istringstream ss(line);
    std::vector<double> v;
    for (double x; ss >> x;) v.push_back(x);
    return v;
  };
  std::vector<double> scale;
  for (const auto &r : ref) {
    const std::vector<double> v = values(r.second);
    scale.resize(std::max(scale.size(), v.size()), 0.0);
    for (size_t k = 0; k < v.size(); k++) scale[k] = std::max(scale[k], fabs(v[k]));
  }
  int differ = 0;
  std::string first;
  for (const auto &r : ref) {
    auto g = got.find(r.first);
    bool same = g != got.end();
    if (same && rtol == 0.0) same = g->second == r.second;
    if (same && rtol > 0.0) {
      const std::vector<double> a = values(r.second), b = values(g->second);
      same = a.size() == b.size();
      for (size_t k = 0; same && k < a.size(); k++) same = fabs(a[k] - b[k]) <= rtol * scale[k];
    }
    if (!same && differ++ == 0)
      first = "step " + std::to_string(r.first) + ": '" + r.second + "' / '" + (g != got.end() ? g->second : "none") + "'";
  }
  std::printf("[ restart  ] forces.dat: %d of %zu lines differ (every column)%s%s\n", differ, ref.size(),
              differ ? ", first at " : "", first.c_str());
  EXPECT_EQ(got.size(), ref.size());
  EXPECT_EQ(differ, 0) << first;
}

// spall: the example's pair_coeff spall (its default release, and cutoff); rn: the edge radius
// (-var rn); natoms: the particles the geometry creates; tol: the energy balance's tolerance, 3x
// the measured error; returns the energy balance (tool work - change of kinetic and internal
// energy - contact dissipation) / tool work
double quick_cut(const char *spall, const char *rn, int natoms, double tol)
{
  Lammps l;
  l.cmds({"variable ny index 11", "variable cut index 0.12e-3", "variable dumpevery index 0",
          std::string("variable spall index ") + spall, std::string("variable rn index ") + rn});
  l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting").c_str());
  auto *atom = l.lmp->atom;
  const double H = 0.3e-3, dx = H / 10;
  double ymax = -1.0, bad = 0.0;
  for (int i = 0; i < atom->nlocal; i++) {
    for (int k = 0; k < 2; k++)
      if (!std::isfinite(atom->x[i][k]) || !std::isfinite(atom->v[i][k])) bad = 1.0;
    if (atom->type[i] == 1) ymax = std::max(ymax, atom->x[i][1]);
  }
  EXPECT_EQ(bad, 0.0);
  // no lost atoms: the 11-across geometry creates natoms (workpiece, clamp, tool: 1393 with the
  // 2.8 um edge, 1409 with 28.7 um, whose insert reaches rn higher and further back); LAMMPS would
  // also stop with "Lost atoms" (thermo_modify lost error, the default)
  EXPECT_EQ(atom->natoms, natoms);
  const double lcut = l.equal("v_lcut"), fc = l.equal("v_Fc"), ft = l.equal("v_Ft");
  const double tmax = l.equal("v_Tmax");
  const double work = l.equal("f_cut[13]"), diss = l.equal("f_cut[15]");
  const double eint = l.equal("f_sph[2]"), ekin = l.equal("f_sph[3]");
  const double e0 = l.equal("v_e0");
  const double balance = (ekin + eint - e0 + diss - work) / work;
  std::printf("[ cutting  ] spall %s, rn %s, cut %.3f mm: Fc %.1f N/mm, Ft %.1f N/mm, Tmax %.0f K, chip top %.1f dx above the "
              "surface, energy: tool work %.6g J/m = (kin + int) change %.6g + contact %.6g (%+.2e)\n",
              spall, rn, lcut, fc, ft, tmax, (ymax - H) / dx, work, ekin + eint - e0, diss, balance);
  EXPECT_GT(lcut, 0.1);
  EXPECT_GT(ymax, H + 0.5 * dx);    // material pushed up the rake face: a chip starts
  EXPECT_GT(fc, 50.0);
  EXPECT_LT(fc, 400.0);
  EXPECT_GT(ft, 10.0);
  EXPECT_LT(ft, 300.0);
  EXPECT_GT(tmax, 350.0);           // plastic and friction heat
  EXPECT_LT(tmax, 1878.0);
  EXPECT_LT(fabs(balance), tol) << "spall " << spall << " rn " << rn;

  // heat budget (issue 11 item 3) over workpiece and tool particles (fix heat/fmfs acts on all):
  // sum m cp dT = plastic heat chi W_p + friction heat (workpiece and tool shares) + heat in
  // through the Dirichlet clamp - convection - radiation.  Conduction between workpiece and
  // tool is internal.  Artificial-viscosity work is not heat (item 4): it is not in the budget.
  const double dE = l.equal("f_heat[5]") - l.equal("v_eth0");
  const double qplast = 0.9 * l.equal("f_sph[4]"), qfric = l.equal("f_heat[4]");
  const double qconv = l.equal("f_heat[1]"), qrad = l.equal("f_heat[2]"), qdir = l.equal("f_heat[3]");
  const double qlost = l.equal("f_cut[14]");
  const double sources = qplast + qfric + qdir - qconv - qrad;
  const double hb = (dE - sources) / sources;
  std::printf("[ cutting  ] heat: sum m cp dT %.6g J/m = plastic %.6g + friction %.6g (workpiece %.4g, tool %.4g) "
              "+ Dirichlet %.4g - convection %.4g - radiation %.4g (%+.2e), friction heat unassigned %.3g\n",
              dE, qplast, qfric, l.equal("f_cut[6]"), l.equal("f_cut[7]"), qdir, qconv, qrad, hb, qlost);
  // the issue asks for 1 %; measured -3.5e-6 to -1.2e-5 (the friction heat is booked with the
  // rectangle rule, the temperature uses the trapezoid: first order in the step): with the 2.8 um
  // edge -1.2e-5 (release) and -6.8e-6 (cutoff), with the insert placed 2.8 um closer to the
  // workpiece (its tip, not its rake face, at xtip: before issue 51) -7.0e-6 and -3.5e-6, with the
  // 28.7 um edge -1.1e-5 (release); -1.1e-6 with seed 000's contact law and its 3x smaller step
  // in contact, onset 0 dtfac 0.15.  The per-particle FMFS/Brookshaw form (conservative no)
  // misses by +1.2e-3 here
  EXPECT_LT(fabs(hb), 3.5e-5) << "spall " << spall << " rn " << rn;
  EXPECT_EQ(qlost, 0.0);
  return balance;
}

// the energy balance's two figures a doc page cites, "<release> of the tool's work ... <cutoff>"
// (the first number in e-notation after the phrase); {0, 0} where the page has no such phrase
std::array<double, 2> doc_balance(const std::string &page)
{
  std::ifstream in(std::string(SPHCUT_SOURCE_DIR) + "/doc/" + page);
  std::string text, word;
  while (in >> word) text += word + " ";    // the lines of a paragraph joined
  const std::string phrase = " of the tool's work";
  const size_t at = text.find(phrase);
  if (at == std::string::npos) return {0.0, 0.0};
  const size_t start = text.rfind(' ', at - 1) + 1;
  const double release = std::atof(text.substr(start, at - start).c_str());
  std::istringstream after(text.substr(at + phrase.size(), 300));
  for (std::string w; after >> w;) {
    const size_t e = w.find_first_of("0123456789");
    if (e != std::string::npos && w.find("e-", e) != std::string::npos) return {release, std::atof(w.c_str() + e)};
  }
  return {release, 0.0};
}

// the quick cut (11 across, 0.12 mm), with the example's spall release and with spall cutoff.  Its
// energy balance is the figure that doc/fix_contact_tri_penalty.rst (Description, "Contact"),
// doc/pair_sph_jc_thermal.rst (spall) and doc/validation.md (Tests) cite: each page's two figures
// must be within 3x of what this test measures (and prints), so that they cannot drift.  Measured
// +5.15e-4 with release (the stress of a particle that crosses pmin switches off and on within one
// step, which the second-order integration sees as a jump) and +3.82e-5 with cutoff at the
// example's cfl 0.5 (4.4e-6 at cfl 0.3: the error grows about as dt^2-dt^3, doc/performance.md
// "The time step of the 2D cut")
TEST(Cutting, QuickTi6Al4V)
{
  // with seed 003's 2.8 um edge (-var rn 2.8e-6: the figures measured before the edge became an
  // input): release 5.2e-4, cutoff 3.8e-5
  quick_cut("release", "2.8e-6", 1393, 1.6e-3);
  quick_cut("cutoff", "2.8e-6", 1393, 1.2e-4);
  // the example's default, the measured 28.7 um edge: release 2.0e-4, cutoff 1.5e-5; the figures
  // the doc pages cite
  const double release = quick_cut("release", "28.7e-6", 1409, 6e-4);
  const double cutoff = quick_cut("cutoff", "28.7e-6", 1409, 4.5e-5);
  for (const char *page : {"fix_contact_tri_penalty.rst", "pair_sph_jc_thermal.rst", "validation.md"}) {
    const std::array<double, 2> doc = doc_balance(page);
    std::printf("[ cutting  ] doc/%s: energy balance %.2g (spall release), %.2g (cutoff)\n", page, doc[0], doc[1]);
    EXPECT_TRUE(doc[0] > fabs(release) / 3.0 && doc[0] < 3.0 * fabs(release))
        << "doc/" << page << " cites " << doc[0] << ", measured " << release << " (spall release)";
    EXPECT_TRUE(doc[1] > fabs(cutoff) / 3.0 && doc[1] < 3.0 * fabs(cutoff))
        << "doc/" << page << " cites " << doc[1] << ", measured " << cutoff << " (spall cutoff)";
  }
}

// a long cut split with restart files continues as one run: 9000 steps in one go against
// 8000 + write_restart + read_restart (-var continue 1) + 1000, with the tool in contact
// (it reaches the workpiece after about 7700 steps).  On one rank the continued run is the
// unsplit one bit for bit, in every line and column of forces.dat (the time too: fix sph/jc-thermal
// gives LAMMPS back the time as of its last change of dt, which LAMMPS folds at the end of a run).  On several ranks (ctest: test_cutting_restart_np2) it is not: the
// continued run reads the atoms in the restart file's order and balances the ranks anew at its
// start (the example's balance command), so each rank holds its atoms, ghosts and neighbours in
// another order than the unsplit run did, the sums over neighbours are added in another order,
// and round-off differences appear from the first step
// in contact (before it, at rest and stress-free, the order does not matter).  Measured on 2
// ranks at step 9000 (tool in contact from about step 7700), over the three splits: Fc up to
// 6.4e-14, Ft 2.5e-13 relative, tool work 1.2e-14, internal energy 1.7e-13, positions 1.2e-17 m
// (spacing 3e-5 m); with dtfac 1 up to 4.1e-13 (Ft) and 8e-18 m, with seed 000's contact 2.2e-13
// and 2.2e-18 m: the round-off grows chaotically, so the limits are 3x the largest seen.
TEST(Cutting, RestartContinuesTheCut)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";
  int nprocs;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  auto run = [&](int steps, int cont, int restartevery = 0) {
    auto l = std::make_unique<Lammps>();
    l->cmds({"variable ny index 11", "variable dumpevery index 0", "variable thermoevery index 1000",
             "variable steps index " + std::to_string(steps), "variable continue index " + std::to_string(cont),
             "variable restartevery index " + std::to_string(restartevery)});
    l->lmp->input->file(in.c_str());
    return l;
  };
  // the reference also writes restart.a / restart.b every 4000 steps (-var restartevery): the
  // one of step 8000 (restart.b) is the third split below
  int me;
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  remove_periodic_restarts();
  auto ref = run(9000, 0, 4000);
  const double fc = ref->equal("v_Fc"), ft = ref->equal("v_Ft"), work = ref->equal("f_cut[13]");
  const double eint = ref->equal("f_sph[2]"), time = ref->equal("time");
  const std::vector<double> xref = gathered_positions(*ref);
  ref.reset();
  const std::map<long, std::string> rows = forces_rows();
  // relative tolerance of the sums and absolute one of the positions [m]: bitwise on one rank,
  // about 3x the measured round-off on several (2 ranks, the example's cfl 0.5, the 2.8 um edge:
  // Fc / Ft 3.1e-13 / 5.3e-13 relative, positions 4.3e-17 m after 1000 steps in contact; 1.2e-17 m
  // at cfl 0.3; the 28.7 um edge, split at step 6000: Fc 1.7e-13, Ft 1.2e-12 of Fc, 7.3e-17 m)
  const double rtol = nprocs == 1 ? 0.0 : 3.5e-12, xtol = nprocs == 1 ? 0.0 : 2.2e-16;
  // split in contact (8000), and while the tool approaches (6000: the first step of the continued
  // run must not take the spring's limit the unsplit run did not take; it did, and the first
  // contact came 2 % off)
  for (int split : {6000, 8000, -8000}) {
    if (split > 0)
      run(split, 0).reset();
    else    // go on from the periodic restart file of step 8000
      ASSERT_TRUE(continue_from_restart_b()) << "restartevery 4000 wrote no restart.b";
    auto cont = run(9000 - std::abs(split), 1);
    EXPECT_EQ(cont->lmp->update->ntimestep, 9000);
    const double fc2 = cont->equal("v_Fc"), ft2 = cont->equal("v_Ft"), work2 = cont->equal("f_cut[13]");
    const double eint2 = cont->equal("f_sph[2]"), time2 = cont->equal("time");
    const std::vector<double> x = gathered_positions(*cont);
    ASSERT_EQ(x.size(), xref.size());
    double worst = 0.0;
    for (size_t k = 0; k < x.size(); k++) worst = std::max(worst, fabs(x[k] - xref[k]));
    if (me == 0) {
      std::printf("[ restart  ] %d rank(s), split at step %d%s\n", nprocs, std::abs(split),
                  split < 0 ? " (restart.b of restartevery)" : "");
      std::printf("[ restart  ] step 9000: Fc %.15g / %.15g N/mm (%.1e), Ft %.15g / %.15g (%.1e), tool work %.1e, "
                  "internal energy %.1e relative; largest position difference %.2e m (spacing 3e-5 m)\n",
                  fc, fc2, fabs(fc2 / fc - 1), ft, ft2, fabs(ft2 / ft - 1), fabs(work2 / work - 1),
                  fabs(eint2 / eint - 1), worst);
    }
    EXPECT_GT(fc, 20.0);    // in contact
    EXPECT_LE(fabs(fc2 - fc), rtol * fc);
    EXPECT_LE(fabs(ft2 - ft), rtol * fc);
    EXPECT_LE(fabs(work2 - work), rtol * work);
    EXPECT_LE(fabs(eint2 - eint), rtol * fabs(eint));
    EXPECT_LE(worst, xtol);
    // the elapsed time too (issue 50: after a restart 11-12 lines differed in its 15th digit)
    EXPECT_LE(fabs(time2 - time), rtol * time) << "time " << time2 << " / " << time;
    cont.reset();
    expect_same_rows(rows, forces_rows(), rtol);
  }
}

// the 3D example continued from its restart file (-var continue 1) gives the cut of the unsplit
// run: the 3D cut with free sides at 6 across and 3 layers (1,398 particles), the tool 0.6
// spacings off, in contact from about step 100; split at step 1000 of 1500, from the file the
// first part writes at its end (with restartevery) and from the periodic restart file of step 1000.
// Every run writes restart files every 500 steps (-var restartevery 500): LAMMPS rebuilds the neighbour
// lists at each step that writes one, which orders the sums differently (without it in the first
// part: 8e-14 in Fc after the split on one rank, 2.7e-14 on two).  With the same schedule the
// continued cut is bitwise the unsplit one, on one rank and on two (test_cutting_restart_np2)
TEST(Cutting, RestartContinuesThe3DCut)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-3d-ti6al4v/in.cutting";
  int nprocs, me;
  MPI_Comm_size(MPI_COMM_WORLD, &nprocs);
  MPI_Comm_rank(MPI_COMM_WORLD, &me);
  auto run = [&](int steps, int cont, int restartevery = 0) {
    auto l = std::make_unique<Lammps>();
    l->cmds({"variable ny index 6", "variable nz index 3", "variable sides index free", "variable xstart index 0.6",
             "variable thermoevery index 500", "variable printevery index 100", "variable dumpevery index 0",
             "variable steps index " + std::to_string(steps), "variable continue index " + std::to_string(cont),
             "variable restartevery index " + std::to_string(restartevery)});
    l->lmp->input->file(in.c_str());
    return l;
  };
  remove_periodic_restarts();
  auto ref = run(1500, 0, 500);
  const double fc = ref->equal("v_Fc"), ft = ref->equal("v_Ft"), tmax = ref->equal("v_Tmax");
  const double time = ref->equal("time");
  const std::vector<double> xref = gathered_positions(*ref);
  ref.reset();
  const std::map<long, std::string> rows = forces_rows();
  const double rtol = 0.0, xtol = 0.0;
  for (int split : {1000, -1000}) {
    if (split > 0)
      run(split, 0, 500).reset();
    else    // restart.b: step 1000 (restart.a: 500, then 1500)
      ASSERT_TRUE(continue_from_restart_b()) << "restartevery 500 wrote no restart.b";
    auto cont = run(1500 - std::abs(split), 1, 500);
    EXPECT_EQ(cont->lmp->update->ntimestep, 1500);
    const double fc2 = cont->equal("v_Fc"), ft2 = cont->equal("v_Ft"), tmax2 = cont->equal("v_Tmax");
    const double time2 = cont->equal("time");
    const std::vector<double> x = gathered_positions(*cont);
    ASSERT_EQ(x.size(), xref.size());
    double worst = 0.0;
    for (size_t k = 0; k < x.size(); k++) worst = std::max(worst, fabs(x[k] - xref[k]));
    if (me == 0)
      std::printf("[ restart  ] 3D, %d rank(s), split at step 1000%s: Fc %.15g / %.15g (%.1e), Ft %.15g / %.15g "
                  "(%.1e), Tmax %.1e relative; largest position difference %.2e m (spacing 6e-5 m)\n",
                  nprocs, split < 0 ? " (restart.b of restartevery)" : "", fc, fc2, fabs(fc2 / fc - 1), ft, ft2,
                  fabs(ft2 / ft - 1), fabs(tmax2 / tmax - 1), worst);
    EXPECT_GT(fc, 20.0);    // in contact
    EXPECT_LE(fabs(fc2 - fc), rtol * fc);
    EXPECT_LE(fabs(ft2 - ft), rtol * fc);
    EXPECT_LE(fabs(tmax2 - tmax), rtol * tmax);
    EXPECT_LE(worst, xtol);
    EXPECT_EQ(time2, time);
    cont.reset();
    expect_same_rows(rows, forces_rows(), rtol);
  }
}

// -var length: the workpiece's length; 0 sizes it to the cut, max(1.5 cut, cut + 0.5 mm) (the
// paper cuts 2/3 of its 3 mm workpiece so that the clamped far end does not reach the chip): the
// particles of the workpiece reach round(L/dx) spacings, in 2D and in 3D; the default stays the
// paper's 3 mm whatever the cut.  (A length not longer than the cut stops the input:
// test_example_length_error.)
TEST(Cutting, WorkpieceSizedToTheCut)
{
  struct Case {
    const char *example, *cut, *length;
    double L;
  };
  const Case cases[] = {{"cutting-2d-ti6al4v", "0.12e-3", "0", 0.62e-3},
                        {"cutting-2d-ti6al4v", "1.0e-3", "0", 1.5e-3},
                        {"cutting-2d-ti6al4v", "2.0e-3", "0", 3.0e-3},
                        {"cutting-2d-ti6al4v", "0.12e-3", "", 3.0e-3},
                        {"cutting-3d-ti6al4v", "0.5e-3", "0", 1.0e-3},
                        {"cutting-3d-ti6al4v", "0.5e-3", "1.2e-3", 1.2e-3}};
  const double H = 0.3e-3;
  for (const Case &c : cases) {
    const bool d3 = std::string(c.example).find("3d") != std::string::npos;
    const int ny = d3 ? 6 : 11;
    Lammps l;
    std::vector<std::string> v = {"variable ny index " + std::to_string(ny), "variable nz index 3",
                                  "variable sides index free", std::string("variable cut index ") + c.cut,
                                  "variable dumpevery index 0", "variable steps index 1"};
    if (*c.length) v.push_back(std::string("variable length index ") + c.length);
    l.cmds(v);
    l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/" + c.example + "/in.cutting").c_str());
    const double dx = H / (ny - 1);
    auto *atom = l.lmp->atom;
    double xmax = -1.0, all = 0.0;
    for (int i = 0; i < atom->nlocal; i++)
      if (atom->type[i] == 1) xmax = std::max(xmax, atom->x[i][0]);
    MPI_Allreduce(&xmax, &all, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    std::printf("[ length   ] %s, cut %s, length %s: L %.4g mm, the workpiece to x = %.4g mm (%.0f spacings)\n",
                c.example, c.cut, *c.length ? c.length : "(default)", 1e3 * l.equal("v_L"), 1e3 * all, all / dx);
    EXPECT_NEAR(l.equal("v_L"), c.L, 1e-12) << c.example << " cut " << c.cut;
    // (the particles sit on the lattice at most a step of the tool's approach from their start)
    EXPECT_NEAR(all, std::round(c.L / dx) * dx, 0.05 * dx) << c.example << " cut " << c.cut;
  }
}

// a continued run must rebuild the tool of the run that wrote the restart file: fix
// contact/tri-penalty keeps the tool's fingerprint there (its elements and their bounding box) and
// stops a continued run whose input builds another tool.  With -var length 0 the workpiece, and
// so the insert's start, follow the cut: continuing with a longer cut would move the tool by 0.18
// mm against the workpiece of the file.  The same input continues (the restart tests above).
TEST(Cutting, ContinueRefusesAnotherTool)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";
  auto run = [&](const char *cut, int cont) {
    auto l = std::make_unique<Lammps>();
    l->cmds({"variable ny index 11", std::string("variable cut index ") + cut, "variable length index 0",
             "variable dumpevery index 0", "variable steps index 100", "variable continue index " + std::to_string(cont)});
    return l;
  };
  {
    auto l = run("0.12e-3", 0);
    l->lmp->input->file(in.c_str());
  }
  {
    auto l = run("0.3e-3", 1);
    std::string what;
    try {
      l->lmp->input->file(in.c_str());
    } catch (LAMMPS_NS::LAMMPSException &e) {
      what = e.what();
    }
    EXPECT_NE(what.find("the tool differs from the one in the restart file"), std::string::npos) << "error: '" << what << "'";
  }
  auto l = run("0.12e-3", 1);
  l->lmp->input->file(in.c_str());
  EXPECT_EQ(l->lmp->update->ntimestep, 200);
}

// -var balance rcb (recursive bisection, comm_style tiled: 1.02x the mean load on the busiest of
// 16 ranks at 81 across, against 1.41x with shift) runs the input's path and gives the cut of
// the default shift (one rank here; on 16 oversubscribed ranks the forces after 20 steps agreed
// to 1e-12, doc/performance.md)
TEST(Cutting, BalanceRcbEqualsShift)
{
  const std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting";
  auto run = [&](const std::string &lb) {
    auto l = std::make_unique<Lammps>();
    l->cmds({"variable ny index 11", "variable dumpevery index 0", "variable xstart index 0.6",
             "variable steps index 3000", "variable balance index " + lb});
    l->lmp->input->file(in.c_str());
    return std::array<double, 2>{l->equal("v_Fc"), l->equal("v_Ft")};
  };
  const auto shift = run("shift"), rcb = run("rcb");
  std::printf("[ balance  ] after 3000 steps in contact: Fc %.10g / %.10g, Ft %.10g / %.10g\n", shift[0], rcb[0],
              shift[1], rcb[1]);
  EXPECT_GT(shift[0], 20.0);    // in contact
  EXPECT_NEAR(rcb[0], shift[0], 1e-9 * shift[0]);
  EXPECT_NEAR(rcb[1], shift[1], 1e-9 * shift[0]);
}

// the tool's geometry follows -var rn, h, H, rake and clearance (issue 51): the insert of fix
// contact/tri-penalty (its tool-0.vtk, written at the setup) has its tip, the lowest point of the
// edge, at y = H - h and its rake face (extended down to the tip's height) at x = xtip, xstart
// spacings right of the workpiece, for any edge radius; its arc's vertices lie rn from the centre
// the input names (xcen, ycen).  The thermal tool particles lie inside the rounded insert, at least
// half a spacing d inside the rake face, the flank and the edge (within rn - d of the centre where
// the arc is the nearest surface), and follow the edge: one lies within d + 1.5 dx of it.  H
// (-var H 0) is max(3 h, h + 3 rn) or the height given, the spacing H / (ny - 1), the workpiece's
// top at H and its length (-var length 0) max(1.5 cut, cut + 5 h).  (A height not above h stops
// the input: test_example_height_error.)
TEST(Cutting, EdgeRadiusAndUncutChipThickness)
{
  struct Case {
    double rn, h, rake, clearance, H;    // H: the expected height
    int ny;
    const char *Hin = "0";               // -var H
  };
  const Case cases[] = {{28.7e-6, 0.1e-3, 0, 7, 0.3e-3, 11},      // the default
                        {28.7e-6, 0.1e-3, 0, 7, 0.3e-3, 41},      // the edge spans 3.8 spacings
                        {2.8e-6, 0.1e-3, 0, 7, 0.3e-3, 11},       // seed 003's Table 1
                        {28.7e-6, 0.05e-3, 0, 7, 0.15e-3, 11},    // H = 3 h
                        {28.7e-6, 0.02e-3, 0, 7, 0.1061e-3, 11},  // H = h + 3 rn
                        {28.7e-6, 0.1e-3, 10, 5, 0.3e-3, 41},     // other angles
                        {28.7e-6, 0.05e-3, 0, 7, 0.2e-3, 11, "0.2e-3"}};    // H given
  const double cut = 0.12e-3;
  for (const Case &c : cases) {
    const int ny = c.ny;
    char tag[160];
    std::snprintf(tag, sizeof(tag), "ny %d rn %g h %g rake %g clearance %g", ny, c.rn, c.h, c.rake, c.clearance);
    std::remove("tool-0.vtk");
    Lammps l;
    char rn[32], h[32], ga[32], al[32];
    std::snprintf(rn, sizeof(rn), "%.10g", c.rn);
    std::snprintf(h, sizeof(h), "%.10g", c.h);
    std::snprintf(ga, sizeof(ga), "%.10g", c.rake);
    std::snprintf(al, sizeof(al), "%.10g", c.clearance);
    l.cmds({"variable ny index " + std::to_string(ny), "variable cut index 0.12e-3", "variable length index 0",
            "variable dumpevery index 0", "variable steps index 1", std::string("variable rn index ") + rn,
            std::string("variable h index ") + h, std::string("variable rake index ") + ga,
            std::string("variable clearance index ") + al, std::string("variable H index ") + c.Hin});
    l.lmp->input->file((std::string(SPHCUT_SOURCE_DIR) + "/examples/cutting-2d-ti6al4v/in.cutting").c_str());
    const double H = l.equal("v_H"), dx = l.equal("v_dx"), d = 0.5 * dx;
    EXPECT_NEAR(H, c.H, 1e-12) << tag;
    EXPECT_NEAR(dx, c.H / (ny - 1), 1e-15) << tag;
    const double L = l.equal("v_L"), Lwant = std::max(1.5 * cut, cut + 5 * c.h);
    EXPECT_NEAR(L, Lwant, 1e-12) << tag;
    const double g = c.rake * M_PI / 180, a = c.clearance * M_PI / 180;
    const double ytip = H - c.h, xtip = l.equal("v_xtip"), disp = l.equal("f_cut[8]");
    // the rake face starts xstart (3) spacings right of x = L
    EXPECT_NEAR(xtip, L + 3 * dx, 1e-12) << tag;
    // the insert as the fix built it, at the setup (before the tool moved by disp)
    std::vector<double> v;
    {
      std::ifstream in("tool-0.vtk");
      ASSERT_TRUE(in.good()) << tag << ": no tool-0.vtk";
      std::string word;
      while (in >> word && word != "POINTS") {}
      size_t np = 0;
      in >> np >> word;
      v.resize(3 * np);
      for (double &x : v) in >> x;
      ASSERT_TRUE(in.good() && np > 4) << tag;
    }
    const size_t nv = v.size() / 3;
    size_t itip = 0;
    for (size_t k = 0; k < nv; k++)
      if (v[3 * k + 1] < v[3 * itip + 1]) itip = k;
    const double xc = l.equal("v_xcen"), yc = l.equal("v_ycen");
    EXPECT_NEAR(v[3 * itip + 1], ytip, 1e-12) << tag << ": the tip at H - h";
    EXPECT_NEAR(v[3 * itip], xc, 1e-12) << tag << ": the tip below the arc's centre";
    EXPECT_NEAR(yc, ytip + c.rn, 1e-12) << tag;
    // the first segment is the rake face (rake end, tangent point): on the line through (xtip, ytip)
    // with the outward normal (-cos g, sin g)
    for (int k = 0; k < 2; k++)
      EXPECT_NEAR(-(v[3 * k] - xtip) * cos(g) + (v[3 * k + 1] - ytip) * sin(g), 0.0, 1e-12) << tag << ": rake face";
    // the edge's vertices (the rake's tangent point to the flank's, the first and the last but one
    // vertex of the outline's arc part) lie rn from the centre; the arc has 8 segments
    int onarc = 0;
    for (size_t k = 0; k < nv; k++) onarc += fabs(std::hypot(v[3 * k] - xc, v[3 * k + 1] - yc) - c.rn) < 1e-12;
    EXPECT_GE(onarc, 9) << tag << ": vertices on the arc";
    // the tool particles (moved with the tool by disp)
    const double nr[2] = {-cos(g), sin(g)}, tr[2] = {sin(g), cos(g)};
    const double nf[2] = {sin(a), -cos(a)}, tf[2] = {cos(a), sin(a)};
    auto *atom = l.lmp->atom;
    int ntool = 0, outside = 0, near = 0;
    double worst = 1e30;
    for (int i = 0; i < atom->nlocal; i++) {
      if (atom->type[i] != 2) continue;
      ntool++;
      const double px = atom->x[i][0] - disp - xc, py = atom->x[i][1] - yc;
      // distances inside the rake face and the flank (both pass rn from the centre)
      const double drake = c.rn - (px * nr[0] + py * nr[1]), dflank = c.rn - (px * nf[0] + py * nf[1]);
      double dist = std::min(drake, dflank);
      if (px * tr[0] + py * tr[1] <= 0.0 && px * tf[0] + py * tf[1] <= 0.0)    // the arc is nearest
        dist = std::min(dist, c.rn - std::hypot(px, py));
      worst = std::min(worst, dist);
      if (dist < d * (1 - 1e-9)) outside++;
      if (dist < d + 1.5 * dx && px * tr[0] + py * tr[1] <= 0.0 && px * tf[0] + py * tf[1] <= 0.0) near++;
    }
    // the lattice sites the sharp wedge of before (half a spacing inside the rake face x = xtip and
    // the flank through (xtip, ytip)) held but the rounded insert does not: the particles above
    // must have left them out (where the edge is wider than the lattice)
    int sharp_only = 0;
    const double x0 = l.equal("v_xins") - xc;    // (0: the insert's tip below the centre)
    for (int i = -3; i <= 3; i++)
      for (int j = -3; j <= 3; j++) {
        const double sx = (std::round((xtip + disp) / dx) + i) * dx, sy = (std::round(ytip / dx) + j) * dx;
        const double px = sx - disp - xc, py = sy - yc;
        const bool sharp = (sx - disp) >= xtip + d && -(sx - disp - xtip) * nf[0] - (sy - ytip) * nf[1] >= d;
        if (!sharp || px * tr[0] + py * tr[1] > 0.0 || px * tf[0] + py * tf[1] > 0.0) continue;
        if (c.rn - std::hypot(px, py) < d) sharp_only++;
      }
    EXPECT_EQ(x0, 0.0) << tag;
    std::printf("[ tool     ] %s: H %.4g mm, dx %.3g um, %d tool particles, the closest %.3f dx inside the rake "
                "face, edge and flank, %d at most 1.5 dx deeper than d at the edge; %d lattice sites of the sharp "
                "wedge outside the edge\n", tag, H * 1e3, dx * 1e6, ntool, worst / dx, near, sharp_only);
    EXPECT_GT(ntool, 20) << tag;
    EXPECT_EQ(outside, 0) << tag << ": tool particles closer than half a spacing to the rounded insert's surface";
    if (c.rn > 1.5 * dx) EXPECT_GT(near, 0) << tag << ": no tool particle follows the edge";
    // the edge spans several lattice sites: the sharp wedge would have held particles outside it
    if (c.rn > 3 * dx) EXPECT_GT(sharp_only, 0) << tag << ": the sharp wedge's particles are inside the edge too";
    // the workpiece's top row at H, its last column at round(L/dx) dx
    double ytop = -1, xend = -1;
    for (int i = 0; i < atom->nlocal; i++)
      if (atom->type[i] == 1) ytop = std::max(ytop, atom->x[i][1]), xend = std::max(xend, atom->x[i][0]);
    EXPECT_NEAR(ytop, H, 1e-3 * dx) << tag;
    EXPECT_NEAR(xend, std::round(L / dx) * dx, 0.05 * dx) << tag;
  }
}
