#!/usr/bin/env bash
# sphcut - build LAMMPS 4Jul2026 with Kokkos 5.2.2 (OpenMP) in a Debian sid root filesystem, build
# the plugin (CPU and /kk styles) against it there, and run a part of the test suite against it
# (ctest test_run_lammps_20260704, label compat-run; issue 52, item 1).
#
# Why a chroot: Kokkos 5 is only at hand as Debian sid's libkokkos-dev 5.2.2 binaries, whose
# libraries need a newer glibc than the host's Debian 12.  Steps, each cached under SPHCUT_CACHE
# (default ~/.cache/sphcut) and redone only when its inputs change (the folder names carry a hash
# of them; a step is marked done by a .complete file written after it succeeded):
#   1. $CACHE/sid-root-<hash>: `debootstrap --variant=minbase sid` from deb.debian.org, then
#      apt-get install of CHROOT_PKGS (apt with Acquire::Check-Valid-Until false: the mirror's sid
#      Release file is past its Valid-Until date), then two stub archives for the
#      libkokkosalgorithms.a and libkokkossimd.a that libkokkos-dev's CMake files import but the
#      package does not ship (each holds one dummy function, as upstream builds them).
#   2. <root>/opt/lammps-20260704-<hash>: LAMMPS 4Jul2026 from Debian's orig tarball (downloaded by
#      tools/compat-sources.sh --lammps-tarball), built in the chroot as a shared library with
#      PLUGIN, MOLECULE and KOKKOS (-DEXTERNAL_KOKKOS=ON, sid's Kokkos 5.2.2, OpenMP) and MPI
#      (sid's Open MPI), with the KOKKOS package trimmed: see KK_KEEP below.
#   3. every run: the plugin and the tests of RUN_TARGETS configured and built in the chroot in
#      BUILD_DIR (the checkout is bind-mounted read-only), then `ctest -R RUN_TESTS` there.
#      BUILD_DIR/compat-run.log has each step's time, BUILD_DIR/ctest.log the tests' output.
# /proc, /sys, /dev/pts and /dev/shm are mounted for each chroot command in a private mount
# namespace (unshare), and unmounted by a trap when the command ends; being private, they vanish
# with the namespace even if this script is killed.
#
# Usage: tools/compat-run.sh [--jobs N] [--build-dir DIR] [--tests REGEX]
#   --jobs N        parallel build jobs and ctest -j (default 2)
#   --build-dir D   the plugin's build folder on the host (default: $ROOT/build-compat-run)
#   --tests REGEX   ctest -R of the tests run against 4Jul2026 (default RUN_TESTS below)
# Exit status: 0 passed; 1 failed; 77 the root filesystem or LAMMPS cannot be downloaded and CI is
# not set (ctest shows the test as skipped), or not root / no chroot support outside CI.
# Environment: SPHCUT_CACHE, CI.
# Time with the chroot and LAMMPS cached, 2-core VM shared with other work: 7 min 36 s at a load of
# 3.5-6 (fresh build folder); at a load of about 10 (7 Dec 2026): plugin and tests built in 13 min
# 55 s (fresh build folder) or 3 min 10 s (test_kokkos.cpp changed), the 20 tests 13-33 min, where
# test_kokkos_np2 can reach ctest's 1500 s limit (doc/build.md).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
JOBS=2
BUILD_DIR="$ROOT/build-compat-run"
# ---------------------------------------------------------------- what runs against 4Jul2026
# CPU styles: the plugin's loading and version check, the plugin built alone as LAMMPS' plugin
# examples build theirs and found by the plain lmp in LAMMPS_PLUGIN_PATH (test_plugin_only), kernels, material model, hourglass control,
# conduction, contact (sharp corners included), thermal coupling, dumps, bad inputs, the launcher;
# /kk styles on OpenMP threads (-k on t 2 -sf kk): test_kokkos (every /kk style against its CPU
# style, 1 and 2 ranks), bad inputs and sharp corners again under /kk, -sf kk without -k on.
# Left out (run against 29Sep2021 only): the long ones (mechanics, cutting, invariance on 4 ranks,
# migrate, wear, validation/calibration) and those needing Python packages or ParaView.
# Every case of these tests runs, none filtered out: the restart cases of test_kokkos assert each
# version's behaviour (write_restart records the styles without the -sf suffix from 8Feb2023,
# sphcut::restart_plain_styles), KokkosThermal.HeatBudgetAcrossRuns allows what 2 Kokkos threads
# give there (doc/build.md, "LAMMPS 4Jul2026 with Kokkos 5.2.2, built and run in CI").
RUN_TESTS='^(test_plugin|test_plugin_only|test_plugin_version_mismatch|test_plugin_version_match|test_kernels|test_material|test_hourglass|test_fmfs|test_contact|test_contact_corners|test_thermal|test_dump|test_inputs|test_impact|launcher_plugin_list|test_kokkos|test_kokkos_np2|test_inputs_kk|test_contact_corners_kk|launcher_sf_kk_without_k_on)$'
RUN_TARGETS="sphcutplugin lmp_sphcut test_plugin test_plugin_mismatch sphcut_mismatch_plugin test_kernels
  test_material test_hourglass test_fmfs test_contact test_contact_corners test_thermal test_dump test_inputs
  test_impact test_kokkos test_inputs_kk test_contact_corners_kk"
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) JOBS="$2"; shift ;;
    --build-dir) BUILD_DIR="$2"; shift ;;
    --tests) RUN_TESTS="$2"; shift ;;
    -h|--help) sed -n '2,36p' "$0"; exit 0 ;;
    *) echo "compat-run.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

mkdir -p "$BUILD_DIR"
BUILD_DIR="$(cd "$BUILD_DIR" && pwd)"
CACHE="${SPHCUT_CACHE:-$HOME/.cache/sphcut}"
SUITE=sid
MIRROR=http://deb.debian.org/debian
# libkokkos-dev pinned: the version tools/compat-check.sh compiles against
CHROOT_PKGS="g++ cmake ninja-build make libkokkos-dev=5.2.2-2 libopenmpi-dev openmpi-bin python3 libgtest-dev"
LAMMPS_VERSION=20260704
LAMMPS_CMAKE=(-DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON -DBUILD_MPI=ON -DBUILD_OMP=ON
  -DLAMMPS_EXCEPTIONS=ON -DPKG_PLUGIN=ON -DPKG_MOLECULE=ON -DPKG_KOKKOS=ON -DEXTERNAL_KOKKOS=ON
  -DCMAKE_CXX_STANDARD=20 -DBUILD_TOOLS=OFF -DBUILD_LAMMPS_SHELL=OFF
  -DBUILD_LAMMPS_GUI=OFF -DWITH_JPEG=OFF -DWITH_PNG=OFF -DWITH_FFMPEG=OFF -DWITH_GZIP=ON)
# The KOKKOS package's styles kept; every other style file (a *_kokkos.h declaring a style, with
# its .cpp) is removed before configuring.  LAMMPS compiles the /kk variant of every style of the
# enabled packages (core and MOLECULE: 110 of them), 10-27 s each; these are the ones the tests and
# the examples use, or that the always-built KOKKOS core (kokkos.cpp, atom/comm/neighbor/modify/
# min_kokkos.cpp, ...) includes.  Safe because under -sf kk a style without a /kk variant is the
# CPU style (LAMMPS looks up NAME/kk and falls back to NAME; the CPU styles are all built); only
# the atom style must have a /kk variant under -k on (atomic, and bond for test_inputs' refusal
# of a molecular atom style), and the run style (verlet/kk); neighbour list styles stay whole.
KK_KEEP="atom_vec_atomic atom_vec_bond verlet nbin npair npair_copy npair_halffull npair_skip npair_trim
  fix_minimize fix_property_atom compute_temp region_block region_sphere fix_gravity fix_addforce
  fix_external fix_setforce fix_enforce2d fix_nve fix_momentum fix_viscous"
# bump when the recipe changes in a way the hashes below do not see
RECIPE=1

# each step and its time, also into BUILD_DIR/compat-run.log (ctest keeps no output of a test that passed)
log() { printf '[compat-run %(%H:%M:%S)T] %s\n' -1 "$*" | tee -a "$BUILD_DIR/compat-run.log"; }
# a step that cannot happen here: skip outside CI, fail in CI (a skipped run proves nothing)
cannot() {
  echo "compat-run.sh: cannot $1" >&2
  if [ "${CI:-}" = "true" ]; then echo "compat-run.sh: CI is set: failing instead of skipping" >&2; exit 1; fi
  echo "compat-run.sh: SKIPPED" >&2
  exit 77
}
hash8() { sha256sum | cut -c1-8; }
secs() { local s=$(( $(date +%s) - $1 )); printf '%d min %02d s' $((s / 60)) $((s % 60)); }

[ "$(id -u)" = 0 ] || cannot "build a chroot without root (run as root, as CI does)"
command -v unshare >/dev/null && command -v chroot >/dev/null || cannot "find unshare and chroot (util-linux, coreutils)"

ROOTFS="$CACHE/sid-root-$(printf '%s\n' "$RECIPE" "$SUITE" "$MIRROR" "$CHROOT_PKGS" | hash8)"
LMP_KEY="$(printf '%s\n' "$RECIPE" "$LAMMPS_VERSION" "${LAMMPS_CMAKE[*]}" "$KK_KEEP" | hash8)"
LMP_SRC="/opt/lammps-$LAMMPS_VERSION-$LMP_KEY/src-tree"      # paths inside the chroot
LMP_PREFIX="/opt/lammps-$LAMMPS_VERSION-$LMP_KEY"

# in_chroot BINDS COMMAND...: run COMMAND in the root filesystem, BINDS a space-separated list of
# HOSTDIR:CHROOTDIR[:ro] bind mounts; /proc, /sys, /dev/pts, /dev/shm mounted for it and unmounted after
in_chroot() {
  local binds="$1"; shift
  unshare --mount --propagation private bash -c '
    set -eu
    R="$1" binds="$2"; shift 2
    mounted=()
    cleanup() { local i; for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount -l "${mounted[i]}" || true; done; }
    trap cleanup EXIT
    mnt() { mount "$@"; mounted+=("${@: -1}"); }
    mkdir -p "$R/proc" "$R/sys" "$R/dev/pts" "$R/dev/shm"
    mnt -t proc proc "$R/proc"
    mnt -t sysfs sysfs "$R/sys"
    mnt -t devpts -o newinstance,ptmxmode=0666 devpts "$R/dev/pts"
    mnt -t tmpfs -o size=2g tmpfs "$R/dev/shm"
    for b in $binds; do
      IFS=: read -r src dst ro <<< "$b"
      mkdir -p "$R$dst"
      mnt --bind "$src" "$R$dst"
      [ -z "$ro" ] || mount -o remount,bind,ro "$R$dst"
    done
    rc=0
    chroot "$R" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM=dumb \
      PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin "$@" || rc=$?
    exit $rc
  ' bash "$ROOTFS" "$binds" "$@"
}

# nothing may be mounted below a folder that is about to be removed
safe_rm() {
  if grep -q " $1/" /proc/self/mountinfo; then
    echo "compat-run.sh: something is still mounted below $1; not removing it" >&2; exit 1
  fi
  rm -rf "$1"
}

mkdir -p "$CACHE"
exec 8>"$CACHE/sid-root.lock"
flock 8    # another checkout may be building the chroot or LAMMPS: wait, then use its result

# ---------------------------------------------------------------- 1. the sid root filesystem
if [ ! -f "$ROOTFS/.complete" ]; then
  t0=$(date +%s)
  [ -d "$ROOTFS" ] && { log "removing the incomplete $ROOTFS"; safe_rm "$ROOTFS"; }
  if ! command -v debootstrap >/dev/null; then
    log "installing debootstrap"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap > /dev/null 2>&1 \
      || { apt-get update -q > /dev/null 2>&1 || true
           DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap > /dev/null 2>&1 \
             || cannot "install debootstrap (apt-get install debootstrap)"; }
  fi
  log "debootstrap --variant=minbase $SUITE $ROOTFS $MIRROR"
  mkdir -p "$ROOTFS"
  if ! debootstrap --variant=minbase "$SUITE" "$ROOTFS" "$MIRROR" > "$CACHE/sid-root-debootstrap.log" 2>&1; then
    tail -5 "$CACHE/sid-root-debootstrap.log" >&2
    grep -q "Failed getting release file\|Couldn't download\|Temporary failure resolving" "$CACHE/sid-root-debootstrap.log" \
      && { safe_rm "$ROOTFS"; cannot "download Debian $SUITE (debootstrap; log $CACHE/sid-root-debootstrap.log)"; }
    echo "compat-run.sh: debootstrap failed (log $CACHE/sid-root-debootstrap.log)" >&2; exit 1
  fi
  t1=$(date +%s)
  log "debootstrap: $(secs "$t0"), $(du -sm "$ROOTFS" | cut -f1) MB"
  echo 'Acquire::Check-Valid-Until "false";' > "$ROOTFS/etc/apt/apt.conf.d/99sphcut-valid-until"
  printf 'APT::Install-Recommends "false";\nAPT::Install-Suggests "false";\n' > "$ROOTFS/etc/apt/apt.conf.d/99sphcut-norecommends"
  log "apt-get install $CHROOT_PKGS"
  # shellcheck disable=SC2086
  if ! in_chroot "" bash -c "apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $CHROOT_PKGS \
        && apt-get clean" > "$CACHE/sid-root-apt.log" 2>&1; then
    tail -8 "$CACHE/sid-root-apt.log" >&2
    echo "compat-run.sh: apt-get install in the chroot failed (log $CACHE/sid-root-apt.log)" >&2; exit 1
  fi
  log "apt-get install: $(secs "$t1"), root filesystem now $(du -sm "$ROOTFS" | cut -f1) MB"
  # the two archives libkokkos-dev's KokkosTargets-*.cmake imports but does not ship
  in_chroot "" bash -c '
    set -e
    cd /usr/lib/$(gcc -dumpmachine)
    for lib in kokkosalgorithms kokkossimd; do
      if grep -rqs "lib$lib.a" /usr/lib/*/cmake/Kokkos/ && [ ! -e lib$lib.a ]; then
        echo "void sphcut_stub_$lib() {}" > /tmp/stub_$lib.cpp
        g++ -c -fPIC -O1 /tmp/stub_$lib.cpp -o /tmp/stub_$lib.o && ar rcs lib$lib.a /tmp/stub_$lib.o
        rm -f /tmp/stub_$lib.*
        echo "stub archive $PWD/lib$lib.a (imported by Kokkos CMake files, not shipped)"
      fi
    done
    dpkg-query -W -f="\${Package} \${Version}\n" g++ cmake libkokkos-dev libopenmpi-dev libgtest-dev'
  touch "$ROOTFS/.complete"
  log "root filesystem ready: $(secs "$t0") in all"
fi

# ---------------------------------------------------------------- 2. LAMMPS 4Jul2026 in it
if [ ! -f "$ROOTFS$LMP_PREFIX/.complete" ]; then
  t0=$(date +%s)
  # older LAMMPS builds of other recipes in this root filesystem go
  for d in "$ROOTFS"/opt/lammps-*; do [ -e "$d" ] && [ "$d" != "$ROOTFS$LMP_PREFIX" ] && safe_rm "$d"; done
  [ -e "$ROOTFS$LMP_PREFIX" ] && safe_rm "$ROOTFS$LMP_PREFIX"
  set +e
  out=$(bash "$ROOT/tools/compat-sources.sh" --lammps-tarball "$LAMMPS_VERSION")
  rc=$?
  set -e
  echo "$out" | grep -v '^/' || true
  [ "$rc" = 0 ] || exit "$rc"      # 77 (cannot download, outside CI) or 1, as compat-sources said
  tarball=$(tail -1 <<< "$out")
  mkdir -p "$ROOTFS$LMP_SRC"
  log "unpacking $(basename "$tarball")"
  tar xf "$tarball" -C "$ROOTFS$LMP_SRC" --exclude='*/examples/*' --exclude='*/doc/*' --exclude='*/bench/*' \
    --exclude='*/potentials/*' --exclude='*/unittest/*' --exclude='*/python/*' --exclude='*/tools/*'
  top=$(find "$ROOTFS$LMP_SRC" -maxdepth 3 -path '*/src/version.h' | head -1)
  top="${top%/src/version.h}"
  [ "$top" = "$ROOTFS$LMP_SRC" ] || { shopt -s dotglob; mv "$top"/* "$ROOTFS$LMP_SRC/"; shopt -u dotglob; }
  rm -f "$tarball"      # 130 MB; the unpacked tree stays (the plugin's LAMMPS_SOURCE_DIR)
  kk="$ROOTFS$LMP_SRC/src/KOKKOS"
  removed=0
  for h in "$kk"/*_kokkos.h; do
    b=$(basename "$h" _kokkos.h)
    grep -qE '^[A-Za-z]+Style\(' "$h" || continue        # not a style (pair_kokkos.h, kokkos_type.h, ...)
    case " $(echo $KK_KEEP) " in *" $b "*) continue ;; esac
    rm -f "$h" "$kk/${b}_kokkos.cpp"
    removed=$((removed + 1))
  done
  log "KOKKOS package: removed $removed style files not used here, kept: $(echo $KK_KEEP)"
  log "configuring and building LAMMPS $LAMMPS_VERSION in the chroot (-j $JOBS; log $ROOTFS$LMP_PREFIX/build.log)"
  if ! in_chroot "" bash -c "set -e; cd $LMP_PREFIX
      cmake -S $LMP_SRC/cmake -B $LMP_PREFIX/build -G Ninja -DCMAKE_INSTALL_PREFIX=$LMP_PREFIX \
        -DCMAKE_INSTALL_LIBDIR=lib -DCMAKE_INSTALL_RPATH=$LMP_PREFIX/lib ${LAMMPS_CMAKE[*]}
      nice -n 10 cmake --build $LMP_PREFIX/build -j $JOBS
      cmake --install $LMP_PREFIX/build
      cp $LMP_PREFIX/build/.ninja_log $LMP_PREFIX/build-times.ninja_log    # each file's compile time
      rm -rf $LMP_PREFIX/build
      $LMP_PREFIX/bin/lmp -h | sed -n '/^Installed packages:/,/^List of individual/p' | head -6" \
      > "$ROOTFS$LMP_PREFIX/build.log" 2>&1; then
    grep -m10 -E "error|Error|FAILED" "$ROOTFS$LMP_PREFIX/build.log" >&2 || tail -20 "$ROOTFS$LMP_PREFIX/build.log" >&2
    echo "compat-run.sh: the LAMMPS $LAMMPS_VERSION build failed (log $ROOTFS$LMP_PREFIX/build.log)" >&2; exit 1
  fi
  grep -A3 "^Installed packages:" "$ROOTFS$LMP_PREFIX/build.log" || true
  touch "$ROOTFS$LMP_PREFIX/.complete"
  log "LAMMPS $LAMMPS_VERSION built and installed in $(secs "$t0")"
fi
flock -s 8    # from here on the root filesystem is only read: other checkouts' runs may share it

# ---------------------------------------------------------------- 3. the plugin and its tests
t0=$(date +%s)
M=/mnt/sphcut     # a private mount namespace each: runs of several checkouts do not meet
BINDS="$ROOT:$M/src:ro $BUILD_DIR:$M/build"
log "building the plugin and its tests against LAMMPS $LAMMPS_VERSION in the chroot ($BUILD_DIR)"
# shellcheck disable=SC2086
if ! in_chroot "$BINDS" bash -c "set -e
    cmake -S $M/src -B $M/build -G Ninja -DLAMMPS_SOURCE_DIR=$LMP_SRC/src -DLAMMPS_ROOT=$LMP_PREFIX \
      -DSPHCUT_KOKKOS=ON -DSPHCUT_PYTHON=/usr/bin/python3
    nice -n 10 cmake --build $M/build -j $JOBS --target $(echo $RUN_TARGETS)" > "$BUILD_DIR/build.log" 2>&1; then
  grep -m15 -E "error|Error|FAILED" "$BUILD_DIR/build.log" >&2 || tail -20 "$BUILD_DIR/build.log" >&2
  echo "compat-run.sh: the plugin does not build against LAMMPS $LAMMPS_VERSION (log $BUILD_DIR/build.log)" >&2
  exit 1
fi
grep -E "sphcut: (LAMMPS|KOKKOS)" "$BUILD_DIR/build.log" || true
t1=$(date +%s)
log "plugin and tests built in $(secs "$t0")"
set +e
in_chroot "$BINDS" \
  bash -c "cd $M/build && ctest --output-on-failure -j $JOBS -R '$RUN_TESTS'" 2>&1 | tee "$BUILD_DIR/ctest.log"
rc=${PIPESTATUS[0]}
set -e
log "tests against LAMMPS $LAMMPS_VERSION: $(secs "$t1") (exit status $rc)"
exit $rc
