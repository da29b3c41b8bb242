#!/usr/bin/env python3
"""Fix 6 of tools/build-deps.sh: LAMMPS 29Sep2021's Kokkos forward communication on several ranks
with an MPI that is not GPU-aware, packed on the device and staged through the host.

Usage: lammps-staged-comm.py FILE...   (LAMMPS' src/KOKKOS/kokkos.cpp and/or comm_kokkos.cpp,
patched in place, each by its name; a file already patched is left alone)

Without a GPU-aware MPI (Open MPI built without CUDA, as on the device machine) LAMMPS 29Sep2021
sends every Kokkos forward communication on several ranks through its classic host path: each step
the whole x array goes to the host and back, and each fix's and pair's columns too.  Newer LAMMPS
packs on the device and moves only the message through the host.  Here:

comm_kokkos.cpp  CommKokkos::forward_comm_device packs on the device, copies the n packed doubles
                 to the host half of the send buffer, MPI on host memory, and copies the received
                 doubles straight into x (as the GPU-aware path receives them; the general unpack,
                 AtomVecKokkos::unpack_comm_kokkos, reads its buffer with the border shape, not with
                 the (n/3, 3) shape the pack wrote: compiled with SPHCUT_FIX6_UNPACK_X it is used
                 instead, the negative control of the test test_migrate_np2_staged)
kokkos.cpp       the device paths stay on for the forward communication of the positions, of pairs
                 and of fixes (the latter two already stage through the host when gpu/aware is off);
                 exchange and borders (at reneighbouring) stay classic.  SPHCUT_LAMMPS_CLASSIC_FORWARD
                 in the environment restores LAMMPS' own choice: "1" for all three, or a list of
                 pos, pair, fix (the baselines of bench/gpu/multigpu.sh).
"""
import os
import sys

MARK = "sphcut fix 6"


def patch_kokkos(k):
    for what, old in (("pos", "if (forward_comm_classic == 0 && forward_comm_on_host == 0) {\n"
                              "      forward_comm_classic = 1;"),
                      ("pair", "if (forward_pair_comm_classic == 0) {\n      forward_pair_comm_classic = 1;"),
                      ("fix", "if (forward_fix_comm_classic == 0) {\n      forward_fix_comm_classic = 1;")):
        if k.count(old) != 1:
            sys.exit("fix 6: kokkos.cpp: '%s' not found once" % old.split("\n")[0])
        k = k.replace(old, old.replace("if (", "if (sphcut_classic(\"%s\") /* %s */ && " % (what, MARK), 1), 1)
    old = "  if ((!gpu_aware_flag && nmpi > 1) || pair_only_flag) {\n"
    if k.count(old) != 1:
        sys.exit("fix 6: kokkos.cpp: the gpu/aware off block not found once")
    k = k.replace(old, """  const char *sphcut_cf = getenv("SPHCUT_LAMMPS_CLASSIC_FORWARD");
  auto sphcut_classic = [&](const char *what) {
    return pair_only_flag || (sphcut_cf && (strstr(sphcut_cf, what) || strcmp(sphcut_cf, "1") == 0));
  };
""" + old, 1)
    return k.replace("#include", "#include <cstdlib>  // %s\n#include <cstring>\n#include" % MARK, 1)


STAGED = """      if (sendproc[iswap] != me && !lmp->kokkos->gpu_aware_flag) {
        // sphcut fix 6: MPI without GPU support: pack on the device, stage the message
        // through the host halves of the buffers (only the doubles sent and received)
        typedef Kokkos::View<double *, LMPHostType::memory_space, Kokkos::MemoryUnmanaged> HostMsg;
        typedef Kokkos::View<double *, typename DeviceType::memory_space, Kokkos::MemoryUnmanaged> DevMsg;
        const int nrecv = size_forward_recv[iswap];
        if (nrecv)
          MPI_Irecv(k_buf_recv.h_view.data(),nrecv,MPI_DOUBLE,recvproc[iswap],0,world,&request);
        if (ghost_velocity)
          n = avec->pack_comm_vel_kokkos(sendnum[iswap],k_sendlist,iswap,
                                         k_buf_send,pbc_flag[iswap],pbc[iswap]);
        else
          n = avec->pack_comm_kokkos(sendnum[iswap],k_sendlist,iswap,
                                     k_buf_send,pbc_flag[iswap],pbc[iswap]);
        DeviceType().fence();
        if (n) {
          Kokkos::deep_copy(HostMsg(k_buf_send.h_view.data(),n),
                            DevMsg(k_buf_send.view<DeviceType>().data(),n));
          MPI_Send(k_buf_send.h_view.data(),n,MPI_DOUBLE,sendproc[iswap],0,world);
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
                              HostMsg(k_buf_recv.h_view.data(),nrecv));
            atomKK->modified(ExecutionSpaceFromDevice<DeviceType>::space,X_MASK);
          }
        } else {
          if (nrecv)
            Kokkos::deep_copy(DevMsg(k_buf_recv.view<DeviceType>().data(),nrecv),
                              HostMsg(k_buf_recv.h_view.data(),nrecv));
          if (ghost_velocity) avec->unpack_comm_vel_kokkos(recvnum[iswap],firstrecv[iswap],k_buf_recv);
          else avec->unpack_comm_kokkos(recvnum[iswap],firstrecv[iswap],k_buf_recv);
        }
        DeviceType().fence();
      } else if (sendproc[iswap] != me) {
        if (comm_x_only) {
"""


def patch_comm(c):
    old = "      if (sendproc[iswap] != me) {\n        if (comm_x_only) {\n"
    if c.count(old) != 1:
        sys.exit("fix 6: comm_kokkos.cpp: forward_comm_device's swap loop not found once")
    return c.replace(old, STAGED, 1)


def main(paths):
    if not paths:
        sys.exit(__doc__)
    for p in paths:
        name = os.path.basename(p)
        with open(p) as f:
            s = f.read()
        if MARK in s:
            continue
        if name == "kokkos.cpp":
            s = patch_kokkos(s)
        elif name == "comm_kokkos.cpp":
            s = patch_comm(s)
        else:
            sys.exit("fix 6: do not know how to patch %s" % p)
        with open(p, "w") as f:
            f.write(s)


if __name__ == "__main__":
    main(sys.argv[1:])
