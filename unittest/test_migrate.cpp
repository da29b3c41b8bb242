// fix sph/jc-thermal/kk on several ranks: during a run the state rows of the atoms that change
// rank move on the device (keyword migrate device, the default; KOKKOS/sphcut_migrate_kokkos.h).
// The 2D cut and the 3D cut with free sides, in contact; on 2 ranks a rank boundary is then put
// just ahead of the tool's leading column of particles (balance x), so that tool particles cross
// it during the next 1000 steps.  The 2-rank /kk run equals the 1-rank /kk run, the 2-rank CPU
// run and the 2-rank /kk run with migrate host (per-atom state by atom ID, 1e-10), and rows did
// move between the ranks; a restart written on 2 ranks after such a run continues on 1 rank as
// the 2-rank run goes on.  Run on 2 ranks (ctest: test_migrate_np2); the 1-rank runs run on rank 0.
#include "sphcut_collision.h"

#include "comm_kokkos.h"
#include "domain.h"
#include "input.h"
#include "update.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

using namespace sphcut_test;

namespace {

// comm device: LAMMPS' Kokkos communication on the device as on a GPU with GPU-aware MPI (the default
// of a host backend is the classic host path, which the fix's migration must not need either)
const std::vector<std::string> KK = {"-k", "on",  "t",    "1",   "-sf",    "kk",   "-pk", "kokkos",
                                     "neigh", "full", "newton", "off", "comm", "device"};

struct CutRun {
  Snapshot start;             // before the last run (atom IDs differ between rank counts: create_atoms)
  Snapshot snap;
  std::vector<double> cut;    // f_cut[1..15]
  long long migrated = 0;     // rows moved between the ranks in the last run (all ranks)
  int classic = -1;           // 1: LAMMPS exchanged atoms on the host (classic path), 0: on the device
  double toolx = 0.0;         // tool tip x before the last run
};

long long migrated_rows(Lammps &l)
{
  auto *fix = sphcut::fix_by_id(l.lmp->modify, "sph");
  int dim = 0;
  long long mine = 0, all = 0;
  if (void *p = fix->extract("migrated_rows", dim)) mine = *static_cast<LAMMPS_NS::bigint *>(p);
  MPI_Allreduce(&mine, &all, 1, MPI_LONG_LONG, MPI_SUM, l.lmp->world);
  return all;
}

// the example (with `fixkw` appended to its fix sph/jc-thermal: a copy in the working directory)
// on `comm` for its `steps`; the tool is in contact by then
std::unique_ptr<Lammps> cut(MPI_Comm comm, const std::vector<std::string> &args, const std::string &example,
                            const std::vector<std::string> &vars, const std::string &fixkw = "")
{
  std::string in = std::string(SPHCUT_SOURCE_DIR) + "/examples/" + example + "/in.cutting";
  if (!fixkw.empty()) {
    int me;
    MPI_Comm_rank(comm, &me);
    const std::string copy = "in.migrate." + example;
    if (me == 0) {
      std::ifstream src(in);
      std::stringstream text;
      text << src.rdbuf();
      std::string s = text.str();
      const std::string fixline = "fix          sph all sph/jc-thermal ";
      const size_t at = s.find(fixline);
      EXPECT_NE(at, std::string::npos);
      s.insert(at + fixline.size(), fixkw + " ");
      std::ofstream(copy) << s;
    }
    MPI_Barrier(comm);
    in = copy;
  }
  auto l = std::make_unique<Lammps>(comm, args);
  l->cmd("processors * 1 1");    // the ranks side by side along the cut
  for (auto &v : vars) l->cmd("variable " + v);
  l->lmp->input->file(in.c_str());
  return l;
}

// then on several ranks the rank boundary just ahead of the tool's leading particle column, and
// `more` steps
CutRun go_on(Lammps &l, int more)
{
  CutRun r;
  if (sphcut::fix_by_id(l.lmp->modify, "lb")) l.cmd("unfix lb");    // the 2D example's load balancing
  int np;
  MPI_Comm_size(l.lmp->world, &np);
  r.start = take(l);
  r.toolx = l.equal("v_xtip") + l.equal("f_cut[8]");    // start + displacement
  if (np > 1) {
    const double dx = l.equal("v_dx");
    auto *d = l.lmp->domain;
    // the tool particles lie on the lattice from one spacing behind the tool tip (half a spacing
    // inside the rake face): their leading column crosses the boundary after 0.05 spacings
    const double xb = r.toolx + 0.95 * dx;
    char line[128];
    std::snprintf(line, sizeof(line), "balance 1.0 x %.12f", (xb - d->boxlo[0]) / (d->boxhi[0] - d->boxlo[0]));
    l.cmd(line);
  }
  l.cmd("run " + std::to_string(more));
  r.snap = take(l);
  for (int k = 1; k <= 15; k++) r.cut.push_back(l.equal("f_cut[" + std::to_string(k) + "]"));
  r.migrated = migrated_rows(l);
  if (auto *ck = dynamic_cast<LAMMPS_NS::CommKokkos *>(l.lmp->comm)) r.classic = ck->exchange_comm_classic ? 1 : 0;
  return r;
}

// largest relative difference of the contact's global vector (the tool force against its length)
double cut_diff(const std::vector<double> &a, const std::vector<double> &b)
{
  const double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
  double d = 0.0;
  for (size_t k = 0; k < a.size(); k++) {
    const double s = k < 3 ? len : fabs(a[k]);
    if (s > 0.0) d = std::max(d, fabs(a[k] - b[k]) / s);
  }
  return d;
}

// rank(): sphcut_test::rank

// rank 0 alone
MPI_Comm solo()
{
  MPI_Comm c;
  MPI_Comm_split(MPI_COMM_WORLD, rank() == 0 ? 0 : MPI_UNDEFINED, 0, &c);
  return c;
}

// `b` in the atom IDs of `a`: each atom of a is the atom of b nearest to it before the last run
// (positions equal to round-off there); the runs of one rank count share their IDs
Snapshot in_ids_of(const CutRun &a, const CutRun &b)
{
  using F = LAMMPS_NS::FixSPHJCThermal;
  const size_t n = a.start.x.size() / 3, ncol = F::NOUT;
  Snapshot s = b.snap;
  double worst = 0.0;
  for (size_t i = 0; i < n; i++) {
    size_t best = 0;
    double dmin = 1e300;
    for (size_t j = 0; j < n; j++) {
      double d = 0.0;
      for (int k = 0; k < 3; k++) d += pow(a.start.x[3 * i + k] - b.start.x[3 * j + k], 2);
      if (d < dmin) {
        dmin = d;
        best = j;
      }
    }
    worst = std::max(worst, sqrt(dmin));
    for (int k = 0; k < 3; k++) s.x[3 * i + k] = b.snap.x[3 * best + k];
    for (size_t k = 0; k < ncol; k++) s.state[i * ncol + k] = b.snap.state[best * ncol + k];
  }
  EXPECT_LT(worst / a.start.size, 1e-10) << "atoms matched by their positions";
  return s;
}

void compare(const CutRun &ref, const CutRun &other, const char *what, bool by_position = false)
{
  if (by_position) expect_same(ref.snap, in_ids_of(ref, other), what);
  else expect_same(ref.snap, other.snap, what);
  const double d = cut_diff(ref.cut, other.cut);
  if (rank() == 0) std::printf("[ %-8s ] contact vector %.3e\n", what, d);
  EXPECT_LT(d, 1e-10) << what;
}

void check_cut(const std::string &example, const std::vector<std::string> &vars, int more)
{
  int np;
  MPI_Comm_size(MPI_COMM_WORLD, &np);
  ASSERT_EQ(np, 2) << "run on 2 ranks";
  auto l = cut(MPI_COMM_WORLD, KK, example, vars);
  const CutRun kk2 = go_on(*l, more);
  l.reset();
  l = cut(MPI_COMM_WORLD, {}, example, vars);
  const CutRun cpu2 = go_on(*l, more);
  l.reset();
  l = cut(MPI_COMM_WORLD, KK, example, vars, "migrate host");
  const CutRun host2 = go_on(*l, more);
  l.reset();
  if (rank() == 0)
    std::printf("[ %-8s ] tool at x %.6g, %g particles in contact; %lld state rows moved between the ranks in "
                "%d steps (migrate host: %lld)\n", example.c_str(), kk2.toolx, kk2.cut[4], kk2.migrated, more,
                host2.migrated);
  EXPECT_GT(kk2.cut[4], 2.0);      // the tool is in contact
  EXPECT_GT(kk2.migrated, 0);      // rows did move on the device
  EXPECT_EQ(host2.migrated, 0);    // the classic path moved them
  EXPECT_EQ(kk2.classic, 0);       // LAMMPS exchanged, sorted and built the ghosts on the device
  EXPECT_EQ(host2.classic, 1);     // and on the host for migrate host
  compare(cpu2, kk2, "kk2-cpu2");
  compare(host2, kk2, "kk2-host");
  MPI_Comm one = solo();
  if (one != MPI_COMM_NULL) {
    l = cut(one, KK, example, vars);
    const CutRun kk1 = go_on(*l, more);
    l.reset();
    EXPECT_EQ(kk1.migrated, 0);
    ASSERT_EQ(kk1.start.x.size(), kk2.start.x.size());
    compare(kk2, kk1, "kk2-kk1", true);
    MPI_Comm_free(&one);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

const std::vector<std::string> CUT2D = {"ny index 11", "xstart index 1", "steps index 1500", "dumpevery index 0",
                                        "thermoevery index 500", "cut index 1e-3"};
const std::vector<std::string> CUT3D = {"ny index 6", "nz index 3", "sides index free", "xstart index 1",
                                        "steps index 1500", "thermoevery index 500", "cut index 1e-3"};

}    // namespace

TEST(Migrate, Cut2DAcrossRanks)
{
  check_cut("cutting-2d-ti6al4v", CUT2D, 1000);
}

TEST(Migrate, Cut3DToolCrossesRankBoundary)
{
  check_cut("cutting-3d-ti6al4v", CUT3D, 1000);
}

// written on 2 ranks after rows moved on the device, continued on 1 rank (the example's continue
// mode reads restart.cutting) as far as the 2-rank run goes on
TEST(Migrate, RestartOnTwoContinuesOnOne)
{
  auto l = cut(MPI_COMM_WORLD, KK, "cutting-2d-ti6al4v", CUT2D);
  const CutRun first = go_on(*l, 1000);
  EXPECT_GT(first.migrated, 0);
  l->cmd("write_restart restart.cutting");
  l->cmd("run 500");
  const Snapshot two = take(*l);
  const LAMMPS_NS::bigint step = l->lmp->update->ntimestep;
  l.reset();
  MPI_Comm one = solo();
  if (one != MPI_COMM_NULL) {
    std::vector<std::string> vars = CUT2D;
    vars.push_back("continue index 1");
    vars[2] = "steps index 500";
    l = cut(one, KK, "cutting-2d-ti6al4v", vars);
    EXPECT_EQ(l->lmp->update->ntimestep, step);
    expect_same(two, take(*l), "restart 2->1");
    l.reset();
    MPI_Comm_free(&one);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

// the collision of two blocks across the rank boundary (x = 0), /kk against the CPU styles on 2
// ranks: atoms deleted and created between runs (the rows follow by index there), sorting every
// 10 steps, and a small block created between the runs above the others that flies across the
// rank boundary and out of the box through the fixed side during the next run (the rows of its
// lost atoms are sent, nobody takes them)
TEST(Migrate, AtomsCreatedDeletedAndLost)
{
  Snapshot snap[2];
  long long moved[2] = {0, 0};
  LAMMPS_NS::bigint natoms[2] = {0, 0}, before = 0;
  for (int k = 0; k < 2; k++) {
    Lammps l(MPI_COMM_WORLD, k ? KK : std::vector<std::string>{});
    auto c = collision(k ? "off" : "on");
    c.insert(c.begin() + 6, "atom_modify sort 10 4e-4");
    c.insert(c.begin(), "processors * 1 1");
    l.cmds(c);
    l.cmds({"run 50", "region cut block -30 -12 -20 20 -1 1", "delete_atoms region cut",
            "region fly block 3.5 6.5 13.5 16.5 -0.5 0.5", "create_atoms 1 region fly", "group fly region fly",
            "velocity fly set -2000 0 0 units box",
            "thermo_modify lost ignore"});
    before = l.lmp->atom->natoms;
    l.cmd("run 400");
    snap[k] = take(l);
    natoms[k] = l.lmp->atom->natoms;
    if (k) moved[k] = migrated_rows(l);
  }
  if (rank() == 0)
    std::printf("[ lost     ] %lld atoms after delete/create, %lld after the run; %lld state rows moved between "
                "the ranks\n", (long long) before, (long long) natoms[1], moved[1]);
  EXPECT_EQ(natoms[0], natoms[1]);
  EXPECT_LT(before, 316);           // atoms were deleted (net of the 9 created)
  EXPECT_LT(natoms[1], before);     // and lost during the run
  EXPECT_GT(moved[1], 0);
  expect_same(snap[0], snap[1], "lost");
}

// the keyword: device or host, nothing else (the CPU style accepts and ignores it)
TEST(Migrate, Keyword)
{
  for (int k = 0; k < 2; k++) {
    Lammps l(MPI_COMM_WORLD, k ? KK : std::vector<std::string>{});
    auto c = collision(k ? "off" : "on");
    c.pop_back();
    c.pop_back();
    c.pop_back();    // the fix, timestep, thermo
    l.cmds(c);
    EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal migrate gpu", "migrate must be device or host, got gpu"));
    EXPECT_TRUE(l.error_contains("fix sph all sph/jc-thermal migrate", "keyword migrate needs a value"));
    l.cmd("fix sph all sph/jc-thermal migrate host");
    if (k) {
      int dim = 0;
      auto *fix = sphcut::fix_by_id(l.lmp->modify, "sph");
      ASSERT_NE(fix->extract("migrate_device", dim), nullptr);
      EXPECT_EQ(*static_cast<int *>(fix->extract("migrate_device", dim)), 0);
    }
  }
}
