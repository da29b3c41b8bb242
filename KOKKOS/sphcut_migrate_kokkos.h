/* -*- c++ -*- ----------------------------------------------------------
   sphcut - the per-atom state rows of fix sph/jc-thermal/kk follow their
   atoms by tag on the device, on any number of ranks.

   Called after LAMMPS has exchanged, sorted and reneighboured the atoms
   (post_neighbor).  Rows [0, nold) of the state hold the atoms whose tags
   k_rowtag lists (the local atoms of the last call); afterwards rows
   [0, nlocal) hold the current local atoms in their order:
     1. a tag -> old row table; the old rows whose atom is still local are
        marked (one kernel each)
     2. several ranks: the old rows whose atom is no longer local (it left
        this rank, or was lost) are packed with their tags on the device,
        staged on the host and sent to all ranks (one MPI_Allgather of the
        counts, one MPI_Allgatherv of the rows: the rows of atoms that
        crossed a subdomain boundary since the last reneighbouring, few);
        the received rows enter the table for the tags this rank now owns
     3. each local atom takes its old row, a received row, or a new row
        (an atom created during the run), then the rows are copied back.
   Deciding what left after the exchange (not predicting it before) needs
   no copy of LAMMPS' exchange test: the box may be shrink-wrapped or
   rebalanced, atoms wrap through periodic sides and pass several ranks.
------------------------------------------------------------------------- */

#ifndef SPHCUT_MIGRATE_KOKKOS_H
#define SPHCUT_MIGRATE_KOKKOS_H

#include "kokkos_type.h"
#include "sphcut_kokkos.h"
#include "sphcut_solid.h"

#include "error.h"

#include <climits>
#include <mpi.h>
#include <vector>

namespace sphcut {

template <class DeviceType> class RowMigration {
 public:
  typedef LAMMPS_NS::bigint bigint;
  typedef LAMMPS_NS::tagint tagint;
  typedef ArrayTypes<DeviceType> AT;
  typedef Kokkos::View<double *, typename DeviceType::memory_space> t_buf;

  // totals since the counters were last cleared (this rank)
  bigint sent = 0;        // rows packed for the other ranks (atoms that left this rank or were lost)
  bigint received = 0;    // rows taken from other ranks
  bigint created = 0;     // rows started anew (atoms created during the run)
  bigint calls = 0;
  double seconds = 0.0;        // wall time in remap (host clock; the device copies fence)
  double mpi_seconds = 0.0;    // of which in the MPI calls (with the wait for the slowest rank)
  void clear()
  {
    sent = received = created = calls = 0;
    seconds = mpi_seconds = 0.0;
  }

  // the views are kept between calls (sized up only)
  typename AT::t_int_1d row_of;    // tag -> old row (>= 0), received row k (-2 - k), none (-1)
  typename AT::t_int_1d used;      // 1: the old row's atom is still local
  typename AT::t_double_2d tmp;    // the rows in the atoms' new order
  t_buf sendbuf, recvbuf;          // per row: tag, then the ncol state values

  /* returns the number of local rows now labelled (nlocal) */
  int remap(DAT::tdual_double_2d &k_state, DAT::tdual_tagint_1d &k_rowtag, int nold,
            typename AT::t_tagint_1d tag, int nlocal, int nmax, MPI_Comm world, double t0,
            LAMMPS_NS::Error *error)
  {
    const double wall0 = MPI_Wtime();
    int nprocs = 1, me = 0;
    MPI_Comm_size(world, &nprocs);
    MPI_Comm_rank(world, &me);
    k_state.template sync<DeviceType>();
    k_rowtag.template sync<DeviceType>();
    auto rt = k_rowtag.template view<DeviceType>();
    auto st = k_state.template view<DeviceType>();
    const int ncol = (int) st.extent(1), stride = ncol + 1;

    // largest tag among the labelled rows and the atoms: size of the tag -> row table
    tagint maxtag = 0;
    Kokkos::parallel_reduce("sphcut:migrate:maxtag", range<DeviceType>(0, nold > nlocal ? nold : nlocal),
        KOKKOS_LAMBDA(const int i, tagint &m) {
          if (i < nold && rt(i) > m) m = rt(i);
          if (i < nlocal && tag(i) > m) m = tag(i);
        },
        Kokkos::Max<tagint>(maxtag));
    if ((tagint) row_of.extent(0) <= maxtag)
      row_of = typename AT::t_int_1d("sphcut:migrate:row_of", (size_t) (maxtag + 1 + maxtag / 8));
    if ((int) tmp.extent(0) < nlocal || tmp.extent(1) != (size_t) ncol)
      tmp = typename AT::t_double_2d("sphcut:migrate:tmp", (size_t) (nmax > nlocal ? nmax : nlocal), (size_t) ncol);
    auto row = row_of;
    auto out = tmp;
    Kokkos::deep_copy(row, -1);
    Kokkos::parallel_for("sphcut:migrate:table", range<DeviceType>(0, nold), KOKKOS_LAMBDA(const int r) {
      if (rt(r) > 0) row(rt(r)) = r;
    });

    int nrecv_rows = 0;
    if (nprocs > 1) {
      // the old rows still local; the others are sent
      if ((int) used.extent(0) < nold)
        used = typename AT::t_int_1d("sphcut:migrate:used", (size_t) (nmax > nold ? nmax : nold));
      auto u = used;
      Kokkos::parallel_for("sphcut:migrate:clear", range<DeviceType>(0, nold), KOKKOS_LAMBDA(const int r) {
        u(r) = 0;
      });
      Kokkos::parallel_for("sphcut:migrate:mark", range<DeviceType>(0, nlocal), KOKKOS_LAMBDA(const int i) {
        const int r = row(tag(i));
        if (r >= 0) u(r) = 1;
      });
      int nsend = 0;
      Kokkos::parallel_reduce("sphcut:migrate:count", range<DeviceType>(0, nold),
          KOKKOS_LAMBDA(const int r, int &c) { c += !u(r) && rt(r) > 0; }, nsend);
      if ((bigint) sendbuf.extent(0) < (bigint) nsend * stride)
        sendbuf = t_buf(Kokkos::ViewAllocateWithoutInitializing("sphcut:migrate:send"),
                        (size_t) (nsend + nsend / 4 + 16) * stride);
      auto sb = sendbuf;
      Kokkos::parallel_scan("sphcut:migrate:pack", range<DeviceType>(0, nold),
          KOKKOS_LAMBDA(const int r, int &pos, const bool final) {
            if (u(r) || rt(r) <= 0) return;
            if (final) {
              double *p = &sb((size_t) pos * stride);
              p[0] = (double) rt(r);
              for (int k = 0; k < ncol; k++) p[1 + k] = st(r, k);
            }
            pos++;
          });

      // every rank receives every rank's rows (a first version: the rows are few; neighbour
      // ranks only would need the brick's 26 neighbours)
      std::vector<int> counts(nprocs), displs(nprocs + 1, 0);
      double t_mpi = MPI_Wtime();
      MPI_Allgather(&nsend, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
      mpi_seconds += MPI_Wtime() - t_mpi;
      bigint total = 0;
      for (int p = 0; p < nprocs; p++) total += counts[p];
      if ((bigint) total * stride > INT_MAX)
        error->all(FLERR, "Fix sph/jc-thermal/kk: {} state rows migrate at once, more than one MPI message "
                   "holds; use migrate host", total);
      for (int p = 0; p < nprocs; p++) {
        displs[p + 1] = displs[p] + counts[p] * stride;
        counts[p] *= stride;
      }
      sent += nsend;
      if (total > 0) {
        if ((bigint) recvbuf.extent(0) < total * stride)
          recvbuf = t_buf(Kokkos::ViewAllocateWithoutInitializing("sphcut:migrate:recv"),
                          (size_t) (total + total / 4 + 16) * stride);
        // host staging (a no-op where the device memory is host memory)
        auto hs = Kokkos::create_mirror_view(sendbuf);
        auto hr = Kokkos::create_mirror_view(recvbuf);
        if (nsend > 0)
          Kokkos::deep_copy(Kokkos::subview(hs, std::make_pair((size_t) 0, (size_t) nsend * stride)),
                            Kokkos::subview(sendbuf, std::make_pair((size_t) 0, (size_t) nsend * stride)));
        t_mpi = MPI_Wtime();
        MPI_Allgatherv(hs.data(), nsend * stride, MPI_DOUBLE, hr.data(), counts.data(), displs.data(), MPI_DOUBLE,
                       world);
        mpi_seconds += MPI_Wtime() - t_mpi;
        Kokkos::deep_copy(Kokkos::subview(recvbuf, std::make_pair((size_t) 0, (size_t) total * stride)),
                          Kokkos::subview(hr, std::make_pair((size_t) 0, (size_t) total * stride)));
        // the received rows enter the table for tags this rank may own (old rows first: an atom
        // still local keeps its own row)
        auto rb = recvbuf;
        const tagint mt = maxtag;
        const int own0 = displs[me] / stride, own1 = displs[me + 1] / stride;
        nrecv_rows = (int) total;
        Kokkos::parallel_for("sphcut:migrate:insert", range<DeviceType>(0, nrecv_rows), KOKKOS_LAMBDA(const int k) {
          if (k >= own0 && k < own1) return;
          const tagint t = (tagint) rb((size_t) k * stride);
          if (t > 0 && t <= mt && row(t) == -1) row(t) = -2 - k;
        });
      }
    }

    // each atom takes its old row, a received one, or a new one
    auto rb = recvbuf;
    int nrecv = 0, nnew = 0;
    Kokkos::parallel_reduce("sphcut:migrate:gather", range<DeviceType>(0, nlocal),
        KOKKOS_LAMBDA(const int i, int &cr, int &cn) {
          const int r = row(tag(i));
          if (r >= 0) {
            for (int k = 0; k < ncol; k++) out(i, k) = st(r, k);
          } else if (r <= -2) {
            const double *p = &rb((size_t) (-2 - r) * stride);
            for (int k = 0; k < ncol; k++) out(i, k) = p[1 + k];
            cr++;
          } else {
            initial_row(&out(i, 0), t0);    // an atom created since the last remap
            cn++;
          }
        },
        nrecv, nnew);
    Kokkos::parallel_for("sphcut:migrate:copy", range<DeviceType>(0, nlocal), KOKKOS_LAMBDA(const int i) {
      for (int k = 0; k < ncol; k++) st(i, k) = out(i, k);
      rt(i) = tag(i);
    });
    k_state.template modify<DeviceType>();
    k_rowtag.template modify<DeviceType>();
    received += nrecv;
    created += nnew;
    calls++;
    seconds += MPI_Wtime() - wall0;
    return nlocal;
  }
};

}    // namespace sphcut

#endif
