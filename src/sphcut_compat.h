/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the few LAMMPS API differences between the versions sphcut
   builds against.  SPHCUT_LAMMPS_VERSION (YYYYMMDD) comes from CMake.
     29Sep2021: comm->forward_comm_fix(fix), comm->reverse_comm_pair(pair), ...,
                neighbor->request() plus setting NeighRequest members
     >= 24Mar2022: comm->forward_comm(this), comm->reverse_comm(this) and
                neighbor->add_request(this, flags) (doc/src/Developer_updating.rst)
   and Modify's lists of fixes and computes, read only through the functions below
   (test_modify_api fails on any other access in src/, KOKKOS/, tools/ and unittest/):
     29Sep2021: the arrays modify->fix[nfix], compute[ncompute], fmask[], find_fix(id)
     newer:     get_fix_list(), get_fix_by_id(), get_fix_by_style(), get_fix_mask(), ...
                (LAMMPS pull request 3001, Oct 2021); 4Jul2026 deprecates find_fix() and
                find_compute(), the 13Nov2026 feature release removes the arrays
   and the style names write_restart records (SPHCUT_RESTART_PLAIN_STYLES below):
     29Sep2021: as the run had them, atomic/kk and sph/jc-thermal/kk under -sf kk
     newer:     without the -sf suffix, atomic and sph/jc-thermal (LAMMPS pull request 3538)
   Checked with -fsyntax-only against 4Feb2025 and 4Jul2026 (Debian sources) by the ctest
   test_compat_lammps (tools/compat-check.sh).
------------------------------------------------------------------------- */

#ifndef SPHCUT_COMPAT_H
#define SPHCUT_COMPAT_H

#ifndef SPHCUT_LAMMPS_VERSION
#define SPHCUT_LAMMPS_VERSION 20210929
#endif

#include "comm.h"
#include "compute.h"
#include "fix.h"
#include "modify.h"
#include "neighbor.h"
#include "utils.h"

#include <string>
#include <vector>
#if SPHCUT_LAMMPS_VERSION < 20220324
#include "neigh_request.h"
#endif

namespace sphcut {

// the overloaded comm->forward_comm(Fix *) etc. replaced the *_fix/_pair names in 24Mar2022
#if SPHCUT_LAMMPS_VERSION >= 20220324
template <class T> inline void forward_comm(LAMMPS_NS::Comm *comm, T *obj) { comm->forward_comm(obj); }
template <class T> inline void reverse_comm(LAMMPS_NS::Comm *comm, T *obj) { comm->reverse_comm(obj); }
#else
inline void forward_comm(LAMMPS_NS::Comm *comm, LAMMPS_NS::Fix *obj) { comm->forward_comm_fix(obj); }
inline void reverse_comm(LAMMPS_NS::Comm *comm, LAMMPS_NS::Fix *obj) { comm->reverse_comm_fix(obj); }
inline void forward_comm(LAMMPS_NS::Comm *comm, LAMMPS_NS::Pair *obj) { comm->forward_comm_pair(obj); }
inline void reverse_comm(LAMMPS_NS::Comm *comm, LAMMPS_NS::Pair *obj) { comm->reverse_comm_pair(obj); }
inline void forward_comm(LAMMPS_NS::Comm *comm, LAMMPS_NS::Compute *obj) { comm->forward_comm_compute(obj); }
#endif

// request a full neighbour list for a fix or compute (perpetual, or occasional = built on demand)
template <class T> inline void request_full_list(LAMMPS_NS::Neighbor *neighbor, T *obj, int instance,
                                                 bool is_fix, bool occasional)
{
#if SPHCUT_LAMMPS_VERSION >= 20220324
  (void) instance;
  (void) is_fix;
  neighbor->add_request(obj, LAMMPS_NS::NeighConst::REQ_FULL |
                        (occasional ? LAMMPS_NS::NeighConst::REQ_OCCASIONAL : 0));
#else
  const int irequest = neighbor->request(obj, instance);
  LAMMPS_NS::NeighRequest *rq = neighbor->requests[irequest];
  rq->pair = 0;
  rq->fix = is_fix ? 1 : 0;
  rq->compute = is_fix ? 0 : 1;
  rq->half = 0;
  rq->full = 1;
  rq->occasional = occasional ? 1 : 0;
#endif
}

// Modify's fixes and computes.  The accessors came with LAMMPS pull request 3001 (Oct 2021,
// after 29Sep2021); the switch is at the version of the other switches above, which is safe
// since the arrays of the fallback exist in every LAMMPS before 13Nov2026
#if SPHCUT_LAMMPS_VERSION >= 20220324
#define SPHCUT_MODIFY_ACCESSORS 1
#endif

#ifndef SPHCUT_MODIFY_ACCESSORS
// 29Sep2021: a view of one of Modify's arrays, iterated and indexed like the vectors of newer LAMMPS
template <class T> class ModifyArray {
 public:
  ModifyArray(T **first, int n) : first_(first), n_(n) {}
  T **begin() const { return first_; }
  T **end() const { return first_ + n_; }
  std::size_t size() const { return (std::size_t) n_; }
  T *operator[](std::size_t i) const { return first_[i]; }

 private:
  T **first_;
  int n_;
};
#endif

// the fixes (computes) in the order they were defined, the order of Modify's callbacks.  Newer
// LAMMPS rebuilds the vector it returns at each get_*_list() call: a copy, so that a loop over it
// stays valid whatever the loop body calls
#ifdef SPHCUT_MODIFY_ACCESSORS
inline std::vector<LAMMPS_NS::Fix *> fix_list(LAMMPS_NS::Modify *modify)
{
  return modify->get_fix_list();
}

inline std::vector<LAMMPS_NS::Compute *> compute_list(LAMMPS_NS::Modify *modify)
{
  return modify->get_compute_list();
}
#else
inline ModifyArray<LAMMPS_NS::Fix> fix_list(LAMMPS_NS::Modify *modify)
{
  return {modify->fix, modify->nfix};
}

inline ModifyArray<LAMMPS_NS::Compute> compute_list(LAMMPS_NS::Modify *modify)
{
  return {modify->compute, modify->ncompute};
}
#endif

// the fix (compute) with this ID, nullptr if there is none
inline LAMMPS_NS::Fix *fix_by_id(LAMMPS_NS::Modify *modify, const std::string &id)
{
#ifdef SPHCUT_MODIFY_ACCESSORS
  return modify->get_fix_by_id(id);
#else
  const int i = modify->find_fix(id);
  return i < 0 ? nullptr : modify->fix[i];
#endif
}

inline LAMMPS_NS::Compute *compute_by_id(LAMMPS_NS::Modify *modify, const std::string &id)
{
#ifdef SPHCUT_MODIFY_ACCESSORS
  return modify->get_compute_by_id(id);
#else
  const int i = modify->find_compute(id);
  return i < 0 ? nullptr : modify->compute[i];
#endif
}

// the fixes (computes) whose style matches the regular expression (utils::strmatch), in order
inline std::vector<LAMMPS_NS::Fix *> fixes_by_style(LAMMPS_NS::Modify *modify, const std::string &style)
{
#ifdef SPHCUT_MODIFY_ACCESSORS
  return modify->get_fix_by_style(style);
#else
  std::vector<LAMMPS_NS::Fix *> found;
  for (int i = 0; i < modify->nfix; i++)
    if (LAMMPS_NS::utils::strmatch(modify->fix[i]->style, style)) found.push_back(modify->fix[i]);
  return found;
#endif
}

inline std::vector<LAMMPS_NS::Compute *> computes_by_style(LAMMPS_NS::Modify *modify, const std::string &style)
{
#ifdef SPHCUT_MODIFY_ACCESSORS
  return modify->get_compute_by_style(style);
#else
  std::vector<LAMMPS_NS::Compute *> found;
  for (int i = 0; i < modify->ncompute; i++)
    if (LAMMPS_NS::utils::strmatch(modify->compute[i]->style, style)) found.push_back(modify->compute[i]);
  return found;
#endif
}

// the fix at position i of fix_list(), for the indices LAMMPS hands out (compute reduce's
// value2index in 29Sep2021), nullptr out of range
inline LAMMPS_NS::Fix *fix_by_index(LAMMPS_NS::Modify *modify, int i)
{
#ifdef SPHCUT_MODIFY_ACCESSORS
  return modify->get_fix_by_index(i);
#else
  return (i >= 0 && i < modify->nfix) ? modify->fix[i] : nullptr;
#endif
}

// the position of a fix in fix_list() (what Atom's callback lists hold), -1 if absent
inline int fix_index(LAMMPS_NS::Modify *modify, const LAMMPS_NS::Fix *fix)
{
  const auto fixes = fix_list(modify);
  for (std::size_t i = 0; i < fixes.size(); i++)
    if (fixes[i] == fix) return (int) i;
  return -1;
}

// the callbacks (FixConst mask) Modify calls the fix at, 0 if it is not defined.  get_fix_mask()
// is in 4Feb2025 (checked), not among pull request 3001's accessors; before 4Feb2025 the fallback reads fmask[]
inline int fix_mask(LAMMPS_NS::Modify *modify, LAMMPS_NS::Fix *fix)
{
#if SPHCUT_LAMMPS_VERSION >= 20250204
  return modify->get_fix_mask(fix);
#else
  for (int i = 0; i < modify->nfix; i++)
    if (modify->fix[i] == fix) return modify->fmask[i];
  return 0;
#endif
}

// The style names in a restart file.  29Sep2021's write_restart records atom->atom_style and
// force->pair_style as they are: a run under -k on -sf kk records atomic/kk and sph/jc-thermal/kk,
// which only a reader with -k on can create (without it the plugin refuses the atom style,
// sphcut_plugin.cpp).  LAMMPS pull request 3538 ("Remove suffix from style names when writing
// restart files", Dec 2022: in every release from 8Feb2023; read in 4Jul2026's write_restart.cpp,
// utils::strip_style_suffix) records them without the -sf suffix, atomic and sph/jc-thermal: such a
// file is read without -k on as the CPU styles, and with -sf kk as the /kk ones (read_restart
// applies the suffix), but not under -k on without -sf kk (AtomKokkos::new_avec: "KOKKOS package
// requires a Kokkos-enabled atom_style"); a /kk atom style is recorded only where the input named
// it (atom_style atomic/kk).  The switch is at 8Feb2023; between the two only 4Feb2025 is built here
#if SPHCUT_LAMMPS_VERSION >= 20230208
#define SPHCUT_RESTART_PLAIN_STYLES 1
constexpr bool restart_plain_styles = true;
#else
constexpr bool restart_plain_styles = false;
#endif

}    // namespace sphcut

#endif
