/* ----------------------------------------------------------------------
   sphcut launcher: the LAMMPS main program, plus loading every plugin in
   the folders named by LAMMPS_PLUGIN_PATH (colon separated) before the
   input is read.  LAMMPS >= 4May2022 does the latter itself (in the LAMMPS
   constructor), so there this is just the plain main program; 29Sep2021
   does not, so `$LMP` from build/env.sh points here.
------------------------------------------------------------------------- */

// LAMMPS >= 15Jun2023 always throws exceptions and no longer has the define
#if defined(LAMMPS_EXCEPTIONS) || (SPHCUT_LAMMPS_VERSION >= 20230615)
#define SPHCUT_EXCEPTIONS
#endif

#include "accelerator_kokkos.h"
#include "input.h"
#include "lammps.h"
#include "lmppython.h"
#if defined(SPHCUT_EXCEPTIONS)
#include "exceptions.h"
#endif

#include <dirent.h>
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

#if SPHCUT_LAMMPS_VERSION < 20220504
static std::vector<std::string> plugins_in_path()
{
  std::vector<std::string> found;
  const char *env = getenv("LAMMPS_PLUGIN_PATH");
  if (!env) return found;
  std::string path(env);
  size_t start = 0;
  while (start <= path.size()) {
    size_t end = path.find(':', start);
    if (end == std::string::npos) end = path.size();
    std::string dir = path.substr(start, end - start);
    start = end + 1;
    if (dir.empty()) continue;
    DIR *d = opendir(dir.c_str());
    if (!d) continue;
    std::vector<std::string> here;
    while (struct dirent *e = readdir(d)) {
      std::string name(e->d_name);
      const std::string tail = "plugin.so";
      if (name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0)
        here.push_back(dir + "/" + name);
    }
    closedir(d);
    std::sort(here.begin(), here.end());
    found.insert(found.end(), here.begin(), here.end());
  }
  return found;
}
#endif

// -sf kk (-suffix kk, or a hybrid suffix with kk) without -k on: LAMMPS 29Sep2021 creates the /kk
// styles of its constructor (the atom and run styles) before it checks the switches, and aborts in
// Kokkos ("Constructing View and initializing data with uninitialized execution space").  The last
// -sf and the last -k count, as in LAMMPS
static bool kk_suffix_without_kokkos(int argc, char **argv)
{
  bool kk = false, on = false;
  for (int i = 1; i + 1 < argc; i++) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "-sf" || a == "-suffix")
      kk = v == "kk" || (v == "hybrid" && i + 3 < argc && (std::string(argv[i + 2]) == "kk" ||
                                                         std::string(argv[i + 3]) == "kk"));
    else if (a == "-k" || a == "-kokkos")
      on = v == "on";
  }
  return kk && !on;
}

static LAMMPS *lammps = nullptr;

static void run(int argc, char **argv, MPI_Comm comm)
{
  lammps = new LAMMPS(argc, argv, comm);
#if SPHCUT_LAMMPS_VERSION < 20220504
  for (const auto &p : plugins_in_path()) lammps->input->one(("plugin load " + p).c_str());
#endif
  lammps->input->file();
  delete lammps;
  lammps = nullptr;
}

#if defined(SPHCUT_EXCEPTIONS)
// error->one throws an abort exception after writing the message to the screen and log of its
// rank, buffered: MPI_Abort kills the process without flushing, so output to a file or pipe
// lost it.  Flush screen and log first; a rank without a screen (not rank 0, or -screen none)
// writes the message to stderr.
static void flush_before_abort(const char *msg)
{
  FILE *screen = lammps ? lammps->screen : nullptr;
  if (!screen && msg && *msg) fprintf(stderr, "%s", msg);
  fflush(nullptr);    // every open output stream: screen, log, stdout, stderr
}
#endif

#if defined(SPHCUT_EXCEPTIONS)
// communicator to abort: a public member in older LAMMPS, get_universe() in newer (4Feb2025)
template <class E> static auto abort_universe(const E &e, int) -> decltype(e.get_universe())
{
  return e.get_universe();
}
template <class E> static MPI_Comm abort_universe(const E &e, long) { return e.universe; }
#endif

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  MPI_Comm comm = MPI_COMM_WORLD;
  int rc = 0;
  if (kk_suffix_without_kokkos(argc, argv)) {
    int me;
    MPI_Comm_rank(comm, &me);
    if (me == 0)
      printf("ERROR: -sf kk selects the /kk styles, which need the KOKKOS package enabled: add -k on t N "
             "(N host threads) or -k on g N (N GPUs), or leave out -sf kk for the CPU styles\n");
    MPI_Finalize();
    return 1;
  }
#if defined(SPHCUT_EXCEPTIONS)
  try {
    run(argc, argv, comm);
  } catch (LAMMPSAbortException &ae) {
    flush_before_abort(ae.what());
    KokkosLMP::finalize();
    Python::finalize();
    MPI_Abort(abort_universe(ae, 0), 1);
  } catch (LAMMPSException &e) {
    rc = 1;
  }
#else
  run(argc, argv, comm);
#endif
  KokkosLMP::finalize();
  Python::finalize();
  MPI_Barrier(comm);
  MPI_Finalize();
  return rc;
}
