#!/usr/bin/env python3
"""Fixes 6 to 9 of tools/build-deps.sh: LAMMPS 29Sep2021's Kokkos communication on several
ranks with an MPI that is not GPU-aware, packed on the device and staged through the host: the
forward communication of every step (fix 6), the exchange and the borders of every reneighbouring
(fix 7), only the messages of the fixes' and pairs' forward communication (fix 8), all of these
messages through page-locked host buffers (fix 9).

Usage: lammps-staged-comm.py FILE...   (LAMMPS' src/KOKKOS/kokkos.cpp and/or comm_kokkos.cpp,
patched in place, each by its name; a file already patched is left alone)

Without a GPU-aware MPI (Open MPI built without CUDA, as on the device machine) LAMMPS 29Sep2021
sends every Kokkos forward communication on several ranks through its classic host path: each step
the whole x array goes to the host and back, and each fix's and pair's columns too.  LAMMPS
4Jul2026 does the same (kokkos.cpp: gpu/aware off on several ranks sets every Kokkos communication
to its legacy host path), so it would need this too.  Here:

comm_kokkos.cpp  CommKokkos::forward_comm_device packs on the device, copies the n packed doubles
                 to the host half of the send buffer, MPI on host memory, and copies the received
                 doubles straight into x (as the GPU-aware path receives them; the general unpack,
                 AtomVecKokkos::unpack_comm_kokkos, reads its buffer with the border shape, not with
                 the (n/3, 3) shape the pack wrote: compiled with SPHCUT_FIX6_UNPACK_X it is used
                 instead, the negative control of the test test_migrate_np2_staged)
                 (fix 6).  CommKokkos::exchange_device and borders_device (fix 7) likewise: the
                 leaving atoms and the border atoms packed on the device, only the messages copied
                 to the host and back.  Without fix 7 LAMMPS exchanged on the host: every atom
                 array to the host and back at every reneighbouring.  A fix with per-atom data
                 that registers a grow or border callback still sends LAMMPS to its classic
                 exchange (fix sph/jc-thermal/kk with migrate device has none during a run).
                 forward_comm_fix_device and forward_comm_pair_device (fix 8) stage through the
                 host already, but by DualView::sync, which copies the whole buffer each way for
                 each message: the buffer is 1.5 times the largest message of any swap (the
                 ranks' own periodic images included) and of any fix so far.  Only the message's
                 doubles are copied now (SPHCUT_LAMMPS_CLASSIC_FORWARD=buffers: the whole buffers
                 as before, the baseline).  Fix 9: the staged messages of fixes 6-8 go through two
                 page-locked host buffers of the file's own (sphcut_stage; cudaMallocHost), not
                 the pageable host halves of LAMMPS' buffers, so that the copies run by DMA
                 (SPHCUT_LAMMPS_STAGE=pageable: the host halves, the baseline).  On a host backend
                 they are host memory, and the copies, empty before, are real there
kokkos.cpp       the device paths stay on for the forward communication of the positions, of pairs
                 and of fixes (the latter two already stage through the host when gpu/aware is off)
                 and for the exchange and borders.  SPHCUT_LAMMPS_CLASSIC_FORWARD in the environment
                 restores LAMMPS' own choice: "1" for all four, or a list of pos, pair, fix,
                 exchange (the baselines of bench/gpu/multigpu.sh; "buffers": fix 8's).
"""
import os
import sys

MARK = "sphcut fix 6"
MARK7 = "sphcut fix 7"
MARK8 = "sphcut fix 8"
MARK9 = "sphcut fix 9"


def patch_kokkos(k):
    for what, old in (("pos", "if (forward_comm_classic == 0 && forward_comm_on_host == 0) {\n"
                              "      forward_comm_classic = 1;"),
                      ("pair", "if (forward_pair_comm_classic == 0) {\n      forward_pair_comm_classic = 1;"),
                      ("fix", "if (forward_fix_comm_classic == 0) {\n      forward_fix_comm_classic = 1;"),
                      ("exchange", "if (exchange_comm_classic == 0 && exchange_comm_on_host == 0) {\n"
                                   "      exchange_comm_classic = 1;")):
        if k.count(old) != 1:
            sys.exit("fix 6: kokkos.cpp: '%s' not found once" % old.split("\n")[0])
        mark = MARK7 if what == "exchange" else MARK
        k = k.replace(old, old.replace("if (", "if (sphcut_classic(\"%s\") /* %s */ && " % (what, mark), 1), 1)
    old = "  if ((!gpu_aware_flag && nmpi > 1) || pair_only_flag) {\n"
    if k.count(old) != 1:
        sys.exit("fix 6: kokkos.cpp: the gpu/aware off block not found once")
    k = k.replace(old, """  const char *sphcut_cf = getenv("SPHCUT_LAMMPS_CLASSIC_FORWARD");
  auto sphcut_classic = [&](const char *what) {
    return pair_only_flag || (sphcut_cf && (strstr(sphcut_cf, what) || strcmp(sphcut_cf, "1") == 0));
  };
""" + old, 1)
    return k.replace("#include", "#include <cstdlib>  // %s\n#include <cstring>\n#include" % MARK, 1)


# the host and device views of a staged message (fixes 6-8), in a block of 8 spaces' indent
MSG_TYPES = """typedef Kokkos::View<double *, LMPHostType::memory_space, Kokkos::MemoryUnmanaged> HostMsg;
        typedef Kokkos::View<double *, typename DeviceType::memory_space, Kokkos::MemoryUnmanaged> DevMsg;"""

STAGED = """      if (sendproc[iswap] != me && !lmp->kokkos->gpu_aware_flag) {
        // sphcut fix 6: MPI without GPU support: pack on the device, stage the message
        // through the host (only the doubles sent and received; fix 9's stage buffers)
        """ + MSG_TYPES + """
        const int nrecv = size_forward_recv[iswap];
        double *const hrecv = sphcut_stage(1,nrecv,k_buf_recv.h_view.data());    // fix 9
        if (nrecv)
          MPI_Irecv(hrecv,nrecv,MPI_DOUBLE,recvproc[iswap],0,world,&request);
        if (ghost_velocity)
          n = avec->pack_comm_vel_kokkos(sendnum[iswap],k_sendlist,iswap,
                                         k_buf_send,pbc_flag[iswap],pbc[iswap]);
        else
          n = avec->pack_comm_kokkos(sendnum[iswap],k_sendlist,iswap,
                                     k_buf_send,pbc_flag[iswap],pbc[iswap]);
        DeviceType().fence();
        if (n) {
          double *const hsend = sphcut_stage(0,n,k_buf_send.h_view.data());
          Kokkos::deep_copy(HostMsg(hsend,n),DevMsg(k_buf_send.view<DeviceType>().data(),n));
          MPI_Send(hsend,n,MPI_DOUBLE,sendproc[iswap],0,world);
        }
        if (nrecv) MPI_Wait(&request,MPI_STATUS_IGNORE);
#ifndef SPHCUT_FIX6_UNPACK_X
        if (comm_x_only) {
#else
        if (false) {
#endif
          // the positions straight into x, as the GPU-aware path receives them
          if (nrecv) {
            Kokkos::deep_copy(DevMsg(atomKK->k_x.view<DeviceType>().data() +
                                     firstrecv[iswap]*atomKK->k_x.view<DeviceType>().extent(1),nrecv),
                              HostMsg(hrecv,nrecv));
            atomKK->modified(ExecutionSpaceFromDevice<DeviceType>::space,X_MASK);
          }
        } else {
          if (nrecv)
            Kokkos::deep_copy(DevMsg(k_buf_recv.view<DeviceType>().data(),nrecv),HostMsg(hrecv,nrecv));
          if (ghost_velocity) avec->unpack_comm_vel_kokkos(recvnum[iswap],firstrecv[iswap],k_buf_recv);
          else avec->unpack_comm_kokkos(recvnum[iswap],firstrecv[iswap],k_buf_recv);
        }
        DeviceType().fence();
      } else if (sendproc[iswap] != me) {
        if (comm_x_only) {
"""


# fix 7: the messages of exchange_device (the leaving atoms, along each dimension to one or both
# neighbours) and of borders_device (the border atoms of a swap)
EXCHANGE_OLD = """        MPI_Irecv(k_buf_recv.view<DeviceType>().data(),nrecv1,
                  MPI_DOUBLE,procneigh[dim][1],0,
                  world,&request);
        MPI_Send(k_buf_send.view<DeviceType>().data(),nsend,
                 MPI_DOUBLE,procneigh[dim][0],0,world);
        MPI_Wait(&request,MPI_STATUS_IGNORE);

        if (procgrid[dim] > 2) {
          MPI_Irecv(k_buf_recv.view<DeviceType>().data()+nrecv1,
                    nrecv2,MPI_DOUBLE,procneigh[dim][0],0,
                    world,&request);
          MPI_Send(k_buf_send.view<DeviceType>().data(),nsend,
                   MPI_DOUBLE,procneigh[dim][1],0,world);
          MPI_Wait(&request,MPI_STATUS_IGNORE);
        }
"""

EXCHANGE_NEW = """        // sphcut fix 7: MPI without GPU support: the messages staged through the host (only
        // the doubles sent and received; fix 9's stage buffers)
        const bool staged = !lmp->kokkos->gpu_aware_flag;
        """ + MSG_TYPES + """
        double *sbuf = staged ? sphcut_stage(0,nsend,k_buf_send.h_view.data()) : k_buf_send.view<DeviceType>().data();
        double *rbuf = staged ? sphcut_stage(1,nrecv,k_buf_recv.h_view.data()) : k_buf_recv.view<DeviceType>().data();
        if (staged && nsend)
          Kokkos::deep_copy(HostMsg(sbuf,nsend),DevMsg(k_buf_send.view<DeviceType>().data(),nsend));
        MPI_Irecv(rbuf,nrecv1,
                  MPI_DOUBLE,procneigh[dim][1],0,
                  world,&request);
        MPI_Send(sbuf,nsend,
                 MPI_DOUBLE,procneigh[dim][0],0,world);
        MPI_Wait(&request,MPI_STATUS_IGNORE);

        if (procgrid[dim] > 2) {
          MPI_Irecv(rbuf+nrecv1,
                    nrecv2,MPI_DOUBLE,procneigh[dim][0],0,
                    world,&request);
          MPI_Send(sbuf,nsend,
                   MPI_DOUBLE,procneigh[dim][1],0,world);
          MPI_Wait(&request,MPI_STATUS_IGNORE);
        }
        if (staged && nrecv)
          Kokkos::deep_copy(DevMsg(k_buf_recv.view<DeviceType>().data(),nrecv),HostMsg(rbuf,nrecv));
"""

BORDERS_OLD = """        if (nrecv) MPI_Irecv(k_buf_recv.view<DeviceType>().data(),
                             nrecv*size_border,MPI_DOUBLE,
                             recvproc[iswap],0,world,&request);
        if (n) MPI_Send(k_buf_send.view<DeviceType>().data(),n,
                        MPI_DOUBLE,sendproc[iswap],0,world);
        if (nrecv) MPI_Wait(&request,MPI_STATUS_IGNORE);
"""

BORDERS_NEW = """        // sphcut fix 7: MPI without GPU support: the messages staged through the host
        const bool staged = !lmp->kokkos->gpu_aware_flag;
        """ + MSG_TYPES + """
        double *sbuf = staged ? sphcut_stage(0,n,k_buf_send.h_view.data()) : k_buf_send.view<DeviceType>().data();
        double *rbuf = staged ? sphcut_stage(1,nrecv*size_border,k_buf_recv.h_view.data())
                              : k_buf_recv.view<DeviceType>().data();
        if (staged && n)
          Kokkos::deep_copy(HostMsg(sbuf,n),DevMsg(k_buf_send.view<DeviceType>().data(),n));
        if (nrecv) MPI_Irecv(rbuf,nrecv*size_border,MPI_DOUBLE,
                             recvproc[iswap],0,world,&request);
        if (n) MPI_Send(sbuf,n,MPI_DOUBLE,sendproc[iswap],0,world);
        if (nrecv) MPI_Wait(&request,MPI_STATUS_IGNORE);
        if (staged && nrecv)
          Kokkos::deep_copy(DevMsg(k_buf_recv.view<DeviceType>().data(),nrecv*size_border),
                            HostMsg(rbuf,nrecv*size_border));
"""


# fix 8: forward_comm_fix_device and forward_comm_pair_device (X = fix, pair) without GPU-aware MPI
# copy the message alone to the host and back, not the whole DualView buffer
FWD_SEND_OLD = """      } else {
        k_buf_send_X.modify<DeviceType>();
        k_buf_send_X.sync<LMPHostType>();
        buf_send_X = k_buf_send_X.h_view.data();
        buf_recv_X = k_buf_recv_X.h_view.data();
      }
"""
FWD_SEND_NEW = """      } else if (sphcut_whole_buffers()) {
        k_buf_send_X.modify<DeviceType>();
        k_buf_send_X.sync<LMPHostType>();
        buf_send_X = k_buf_send_X.h_view.data();
        buf_recv_X = k_buf_recv_X.h_view.data();
      } else {
        // sphcut fix 8: the n doubles of the message to the host, not the whole buffer
        """ + MSG_TYPES + """
        buf_send_X = sphcut_stage(0,n,k_buf_send_X.h_view.data());    // fix 9
        buf_recv_X = sphcut_stage(1,nsize*recvnum[iswap],k_buf_recv_X.h_view.data());
        if (n)
          Kokkos::deep_copy(HostMsg(buf_send_X,n),DevMsg(k_buf_send_X.view<DeviceType>().data(),n));
      }
"""
FWD_RECV_OLD = """      if (!lmp->kokkos->gpu_aware_flag) {
        k_buf_recv_X.modify<LMPHostType>();
        k_buf_recv_X.sync<DeviceType>();
      }
"""
FWD_RECV_NEW = """      if (!lmp->kokkos->gpu_aware_flag && sphcut_whole_buffers()) {
        k_buf_recv_X.modify<LMPHostType>();
        k_buf_recv_X.sync<DeviceType>();
      } else if (!lmp->kokkos->gpu_aware_flag && recvnum[iswap]) {
        // sphcut fix 8: the received message alone back to the device
        """ + MSG_TYPES + """
        Kokkos::deep_copy(DevMsg(k_buf_recv_X.view<DeviceType>().data(),nsize*recvnum[iswap]),
                          HostMsg(buf_recv_X,nsize*recvnum[iswap]));
      }
"""
WHOLE_FN = """
// sphcut fix 8: SPHCUT_LAMMPS_CLASSIC_FORWARD=buffers: the fixes' and pairs' forward messages staged
// by DualView::sync of their whole buffers, as LAMMPS 29Sep2021 does (the baseline)
static bool sphcut_whole_buffers()
{
  static const int whole = [] {
    const char *e = getenv("SPHCUT_LAMMPS_CLASSIC_FORWARD");
    return e && strstr(e, "buffers") ? 1 : 0;
  }();
  return whole;
}
"""

# fix 9: the host side of every staged message (fixes 6-8) in page-locked memory of its own
STAGE_FN = """
// sphcut fix 9: the staged messages of fixes 6-8 pass through page-locked host buffers of their own
// (CUDA: cudaMallocHost; the copies to and from the device then run by DMA at the link's rate,
// where from pageable memory the driver copies through bounce buffers of its own).  which: 0 the
// message sent, 1 the one received; n doubles, kept until the next call with the same which.
// SPHCUT_LAMMPS_STAGE=pageable: the host halves of LAMMPS' buffers (fallback), as fixes 6-8 alone,
// the baseline.  On a host backend the buffers are host memory (the copies real, as on a GPU)
#ifdef KOKKOS_ENABLE_CUDA
typedef Kokkos::CudaHostPinnedSpace SphcutStageSpace;
#else
typedef Kokkos::HostSpace SphcutStageSpace;
#endif
static double *sphcut_stage_buf[2] = {nullptr, nullptr};
static size_t sphcut_stage_cap[2] = {0, 0};
static double *sphcut_stage(int which, size_t n, double *fallback)
{
  static const bool pageable = [] {
    const char *e = getenv("SPHCUT_LAMMPS_STAGE");
    return e && strcmp(e, "pageable") == 0;
  }();
  if (pageable) return fallback;
  if (n > sphcut_stage_cap[which]) {
    if (!sphcut_stage_buf[0] && !sphcut_stage_buf[1])
      Kokkos::push_finalize_hook([] {
        for (int k = 0; k < 2; k++) {
          if (sphcut_stage_buf[k]) Kokkos::kokkos_free<SphcutStageSpace>(sphcut_stage_buf[k]);
          sphcut_stage_buf[k] = nullptr;
          sphcut_stage_cap[k] = 0;
        }
      });
    if (sphcut_stage_buf[which]) Kokkos::kokkos_free<SphcutStageSpace>(sphcut_stage_buf[which]);
    sphcut_stage_cap[which] = n + n / 2 + 1024;
    sphcut_stage_buf[which] = static_cast<double *>(
        Kokkos::kokkos_malloc<SphcutStageSpace>("sphcut:stage", sphcut_stage_cap[which] * sizeof(double)));
  }
  return sphcut_stage_buf[which];
}
"""


def patch_comm(c):
    if MARK9 not in c:
        anchor = "using namespace LAMMPS_NS;\n"
        if c.count(anchor) != 1:
            sys.exit("fix 9: comm_kokkos.cpp: no 'using namespace LAMMPS_NS;' line")
        c = c.replace(anchor, anchor + STAGE_FN, 1)
        c = c.replace("#include", "#include <cstdlib>  // sphcut fix 9\n#include <cstring>\n#include", 1)
    if MARK not in c:
        old = "      if (sendproc[iswap] != me) {\n        if (comm_x_only) {\n"
        if c.count(old) != 1:
            sys.exit("fix 6: comm_kokkos.cpp: forward_comm_device's swap loop not found once")
        c = c.replace(old, STAGED, 1)
    if MARK7 not in c:
        for what, old, new in (("exchange_device", EXCHANGE_OLD, EXCHANGE_NEW),
                               ("borders_device", BORDERS_OLD, BORDERS_NEW)):
            if c.count(old) != 1:
                sys.exit("fix 7: comm_kokkos.cpp: %s's messages not found once" % what)
            c = c.replace(old, new, 1)
    if MARK8 not in c:
        for x in ("fix", "pair"):
            for old, new in ((FWD_SEND_OLD, FWD_SEND_NEW), (FWD_RECV_OLD, FWD_RECV_NEW)):
                old, new = old.replace("_X", "_" + x), new.replace("_X", "_" + x)
                if c.count(old) != 1:
                    sys.exit("fix 8: comm_kokkos.cpp: forward_comm_%s_device's staging not found once" % x)
                c = c.replace(old, new, 1)
        anchor = "using namespace LAMMPS_NS;\n"
        if c.count(anchor) != 1:
            sys.exit("fix 8: comm_kokkos.cpp: no 'using namespace LAMMPS_NS;' line")
        c = c.replace(anchor, anchor + WHOLE_FN, 1)    # (getenv, strstr: included with fix 9's function)
    return c


def main(paths):
    if not paths:
        sys.exit(__doc__)
    for p in paths:
        name = os.path.basename(p)
        with open(p) as f:
            s = f.read()
        if name == "kokkos.cpp":
            if MARK in s:
                continue
            s = patch_kokkos(s)
        elif name == "comm_kokkos.cpp":
            if MARK in s and MARK7 in s and MARK8 in s and MARK9 in s:
                continue
            s = patch_comm(s)
        else:
            sys.exit("fixes 6-9: do not know how to patch %s" % p)
        with open(p, "w") as f:
            f.write(s)


if __name__ == "__main__":
    main(sys.argv[1:])
