/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the few LAMMPS API differences between the versions sphcut
   builds against.  SPHCUT_LAMMPS_VERSION (YYYYMMDD) comes from CMake.
     29Sep2021: comm->forward_comm_fix(fix), comm->reverse_comm_pair(pair), ...,
                neighbor->request() plus setting NeighRequest members
     >= 24Mar2022: comm->forward_comm(this), comm->reverse_comm(this) and
                neighbor->add_request(this, flags) (doc/src/Developer_updating.rst)
   Checked with -fsyntax-only against 4Feb2025 and 4Jul2026 (Debian sources) by the ctest
   test_compat_lammps (tools/compat-check.sh).
------------------------------------------------------------------------- */

#ifndef SPHCUT_COMPAT_H
#define SPHCUT_COMPAT_H

#ifndef SPHCUT_LAMMPS_VERSION
#define SPHCUT_LAMMPS_VERSION 20210929
#endif

#include "comm.h"
#include "neighbor.h"
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

}    // namespace sphcut

#endif
