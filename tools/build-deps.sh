#!/usr/bin/env bash
# Build the dependencies of sphcut from Debian source packages into a cache
# outside the repository:
#   Kokkos 3.4.01   (from the `trilinos` 13.2.0-4 source package, packages/kokkos)
#   LAMMPS 29Sep2021 Update 2 (the `lammps` 20220106.git7586adbb6a+ds1-2 source package)
#     as a shared library with PLUGIN, KOKKOS (external), OPENMP, MACHDYN, SPH and MPI.
#
# Usage: tools/build-deps.sh [--cuda] [--jobs N] [--no-apt] [--sources DIR] [--print-prefix]
#                            [--pack-sources FILE] [--kokkos-only]
#   --cuda            Kokkos with CUDA (Ampere80 PTX, JIT-compiled on Hopper) instead of OpenMP
#   --kokkos-only     Kokkos alone, in a prefix of its own (tools/cuda-compile-check.sh: with
#                     --cuda, the headers to compile the /kk sources with nvcc on a machine
#                     without a GPU)
#   --jobs N          parallel build jobs (default: nproc)
#   --no-apt          do not install Debian packages or download sources (use --sources)
#   --sources DIR     take the pristine sources from DIR (made by --pack-sources); needed on
#                     machines without a package registry, e.g. the GPU device machine
#   --pack-sources F  write a trimmed tarball of the pinned sources (the parts the build uses)
#   --print-prefix    print the cache prefix this configuration uses and exit
#
# Environment: SPHCUT_CACHE (default $HOME/.cache/sphcut) is where everything goes.
# The install prefix is keyed by versions and options; it is only marked complete
# (file .complete) after every step succeeded, and an incomplete prefix is wiped
# before a new build starts, so an interrupted build never looks complete.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"

LAMMPS_DEB_VERSION="20220106.git7586adbb6a+ds1-2"
TRILINOS_DEB_VERSION="13.2.0-4"
KOKKOS_VERSION="3.4.01"
# bump when the build recipe below changes, so old caches are not reused
RECIPE=2

CUDA=0
JOBS=$(nproc)
USE_APT=1
SOURCES=""
PACK=""
PRINT_PREFIX=0
KOKKOS_ONLY=0
while [ $# -gt 0 ]; do
  case "$1" in
    --cuda) CUDA=1 ;;
    --jobs) JOBS="$2"; shift ;;
    --no-apt) USE_APT=0 ;;
    --sources) SOURCES="$(cd "$2" && pwd)"; shift ;;
    --pack-sources) PACK="$2"; shift ;;
    --print-prefix) PRINT_PREFIX=1 ;;
    --kokkos-only) KOKKOS_ONLY=1 ;;
    -h|--help) sed -n '2,25p' "$0"; exit 0 ;;
    *) echo "build-deps.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

CACHE="${SPHCUT_CACHE:-$HOME/.cache/sphcut}"
if [ $CUDA = 1 ]; then BACKEND=cuda-ampere80; else BACKEND=openmp; fi
KEY="lammps-${LAMMPS_DEB_VERSION}_kokkos-${KOKKOS_VERSION}-${BACKEND}_mpi_r${RECIPE}"
# the CUDA build carries fixes 6 to 9 (communication staged through the host) as well
[ $CUDA = 1 ] && KEY="${KEY}_s9"
[ $KOKKOS_ONLY = 1 ] && KEY="kokkos-${KOKKOS_VERSION}-${BACKEND}_r${RECIPE}"
KEY="${KEY//+/_}"
PREFIX="$CACHE/$KEY"
if [ $PRINT_PREFIX = 1 ]; then echo "$PREFIX"; exit 0; fi

if command -v ninja >/dev/null 2>&1; then GEN=Ninja; else GEN="Unix Makefiles"; fi

log() { printf '[build-deps %(%H:%M:%S)T] %s\n' -1 "$*"; }

# ---------------------------------------------------------------- Debian packages
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
APT_PKGS="cmake ninja-build g++ make libopenmpi-dev openmpi-bin libeigen3-dev dpkg-dev xz-utils
  libgtest-dev python3 python3-numpy python3-matplotlib python3-scipy python3-venv"
install_debian_packages() {
  local missing=""
  for p in $APT_PKGS; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
  done
  [ -z "$missing" ] && return 0
  log "installing Debian packages:$missing"
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends $missing
}

# a deb-src entry for bookworm, so `apt-get source` finds the pinned packages
ensure_deb_src() {
  if ! apt-cache showsrc lammps 2>/dev/null | grep -q "^Version: ${LAMMPS_DEB_VERSION}$"; then
    log "adding deb-src entry for bookworm"
    $SUDO tee /etc/apt/sources.list.d/sphcut-src.sources >/dev/null <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    $SUDO apt-get update -q
  fi
}

# ---------------------------------------------------------------- sources
# unpacks into $1/lammps and $1/kokkos
unpack_sources() {
  local dst="$1"
  mkdir -p "$dst"
  if [ -n "$SOURCES" ]; then
    log "using sources from $SOURCES"
    cp -a "$SOURCES/lammps" "$dst/lammps"
    cp -a "$SOURCES/kokkos" "$dst/kokkos"
    # --pack-sources drops kokkos/example, but Kokkos' standalone CMakeLists.txt always
    # calls add_subdirectory(example) (cmake/kokkos_tribits.cmake): give it an empty one
    if [ ! -f "$dst/kokkos/example/CMakeLists.txt" ]; then
      mkdir -p "$dst/kokkos/example"
      echo "# sphcut: examples trimmed by build-deps.sh --pack-sources" > "$dst/kokkos/example/CMakeLists.txt"
    fi
    return
  fi
  local dl="$CACHE/downloads"
  mkdir -p "$dl"
  if [ ! -f "$dl/lammps_${LAMMPS_DEB_VERSION}.dsc" ] || [ ! -f "$dl/trilinos_${TRILINOS_DEB_VERSION}.dsc" ]; then
    ensure_deb_src
    log "apt-get source lammps=$LAMMPS_DEB_VERSION trilinos=$TRILINOS_DEB_VERSION"
    (cd "$dl" && apt-get source -q --download-only \
      "lammps=${LAMMPS_DEB_VERSION}" "trilinos=${TRILINOS_DEB_VERSION}")
  fi
  log "unpacking LAMMPS (upstream source, Debian patches not applied: they only relocate potentials)"
  (cd "$dl" && dpkg-source --skip-patches -x "lammps_${LAMMPS_DEB_VERSION}.dsc" "$dst/lammps" >/dev/null)
  log "unpacking packages/kokkos from trilinos ${TRILINOS_DEB_VERSION}"
  local top="Trilinos-trilinos-release-13-2-0"   # top folder of the pinned orig tarball
  tar xzf "$dl/trilinos_${TRILINOS_DEB_VERSION%-*}.orig.tar.gz" -C "$dst" "$top/packages/kokkos"
  mv "$dst/$top/packages/kokkos" "$dst/kokkos"
  rm -rf "${dst:?}/$top"
  grep -q "Kokkos_VERSION_MINOR 4" "$dst/kokkos/CMakeLists.txt" || { echo "unexpected Kokkos version" >&2; exit 1; }
  grep -q '"29 Sep 2021"' "$dst/lammps/src/version.h" || { echo "unexpected LAMMPS version" >&2; exit 1; }
}

if [ -n "$PACK" ]; then
  [ $USE_APT = 1 ] && install_debian_packages
  tmp=$(mktemp -d)
  unpack_sources "$tmp"
  # keep what the build reads: cmake/, src/ (top level + the packages we enable), lib/ stubs
  (cd "$tmp/lammps" && rm -rf examples bench doc/src doc/utils potentials tools unittest python fortran)
  for d in "$tmp"/lammps/src/*/; do
    case "$(basename "$d")" in
      KOKKOS|PLUGIN|OPENMP|MACHDYN|SPH|STUBS|fmt|MAKE) ;;
      *) rm -rf "$d" ;;
    esac
  done
  (cd "$tmp/kokkos" && rm -rf benchmarks example doc */unit_test core/perf_test containers/performance_tests)
  tar czf "$PACK" -C "$tmp" lammps kokkos
  rm -rf "$tmp"
  log "wrote $PACK ($(du -h "$PACK" | cut -f1))"
  exit 0
fi

# ---------------------------------------------------------------- cache handling
if [ -f "$PREFIX/.complete" ]; then
  log "cached: $PREFIX"
  exit 0
fi
mkdir -p "$CACHE"
exec 9>"$CACHE/.lock-$KEY"
if ! flock -n 9; then
  log "another build of $KEY is running; waiting for it"
  flock 9
  [ -f "$PREFIX/.complete" ] && { log "cached: $PREFIX"; exit 0; }
fi
[ $USE_APT = 1 ] && install_debian_packages
if [ -e "$PREFIX" ]; then
  log "removing incomplete cache $PREFIX"
  rm -rf "$PREFIX"
fi
mkdir -p "$PREFIX"
T0=$(date +%s)
unpack_sources "$PREFIX/src"
KSRC="$PREFIX/src/kokkos"
LSRC="$PREFIX/src/lammps"

# ---------------------------------------------------------------- Kokkos
KOKKOS_OPTS=(-DKokkos_ENABLE_SERIAL=ON -DKokkos_ENABLE_OPENMP=ON)
CXX_FOR_KOKKOS="${CXX:-g++}"
CXXSTD=14
# packages we compare against; MACHDYN needs Eigen (libeigen3-dev), CPU only
CMP_PKGS=(-DPKG_MACHDYN=ON -DDOWNLOAD_EIGEN3=OFF -DPKG_SPH=ON)
# The patches (table with the checks: doc/build.md "Patches to the dependencies"); each line says
# why and what breaks without it.
# Fix 0 (every backend): Kokkos_MemoryPool.cpp uses uint32_t without <cstdint>, which
# g++ >= 13 no longer includes transitively (the device machine's compiler).
#   Without it: Kokkos does not compile with g++ >= 13 ("'uint32_t' has not been declared").
grep -q "sphcut fix 0" "$KSRC/core/src/impl/Kokkos_MemoryPool.cpp" || \
  sed -i '0,/^#include/s//#include <cstdint>  \/\/ sphcut fix 0: g++ >= 13\n#include/' \
    "$KSRC/core/src/impl/Kokkos_MemoryPool.cpp"
grep -q "sphcut fix 0" "$KSRC/core/src/impl/Kokkos_MemoryPool.cpp"
if [ $CUDA = 1 ]; then
  # Fixes to Kokkos 3.4.01, which predates CUDA 13 and Hopper:
  # (1) nvcc_wrapper's default architecture sm_35 is rejected by CUDA 13: default to sm_80.
  #     Without it: every compile without -arch (CMake's compiler check first) stops with
  #     "nvcc fatal : Unsupported gpu architecture 'sm_35'".
  sed -i 's/^default_arch="sm_35"/default_arch="sm_80"/' "$KSRC/bin/nvcc_wrapper"
  grep -q '^default_arch="sm_80"' "$KSRC/bin/nvcc_wrapper"
  # (2) Kokkos_Cuda_Half.hpp: the CUDA_VERSION < 11100 guard picks the wrong half-type
  #     conversion branch for CUDA >= 12; always take the first branch.
  #     Without it: every source including Kokkos_Core.hpp fails against CUDA 13's cuda_fp16.h
  #     ("no suitable user-defined conversion from half_t to __half").
  sed -i 's/#if (CUDA_VERSION < 11100)/#if 1 \/* sphcut: was (CUDA_VERSION < 11100) *\//' \
    "$KSRC/core/src/Cuda/Kokkos_Cuda_Half.hpp"
  grep -q 'sphcut: was (CUDA_VERSION < 11100)' "$KSRC/core/src/Cuda/Kokkos_Cuda_Half.hpp"
  # (3) CUDA 13 changed cudaMemPrefetchAsync(ptr, n, device, stream) to
  #     (ptr, n, cudaMemLocation{type, id}, flags, stream).
  #     Without it: Kokkos_CudaSpace.cpp does not compile ("no suitable constructor exists to
  #     convert from int to cudaMemLocation").
  python3 - "$KSRC/core/src/Cuda/Kokkos_CudaSpace.cpp" <<'EOF'
import re, sys
p = sys.argv[1]; s = open(p).read()
pat = re.compile(r'cudaMemPrefetchAsync\(\s*([^,]+),\s*([^,]+),\s*([^,]+),\s*([^)]+)\)')
n = 0
def rep(m):
    global n; n += 1
    return ('cudaMemPrefetchAsync(%s, %s, cudaMemLocation{cudaMemLocationTypeDevice, %s}, 0, %s)'
            % (m.group(1), m.group(2), m.group(3).strip(), m.group(4)))
s2 = pat.sub(rep, s)
if n == 0: sys.exit("fix 3: no cudaMemPrefetchAsync call found")
open(p, "w").write(s2)
EOF
  # (5) Kokkos_Cuda_Instance.cpp refuses to run sm_80 code on a compute capability 9.0 device;
  #     allow a newer major version, the embedded PTX is JIT-compiled for sm_90 (Kokkos 3.4 has
  #     no Hopper architecture).  Without it: every run on an H100/H200 aborts in
  #     Kokkos::initialize ("running kernels compiled for compute capability 8.0 on device with
  #     compute capability 9.0 is not supported by CUDA!").
  python3 - "$KSRC/core/src/Cuda/Kokkos_Cuda_Instance.cpp" <<'EOF'
import sys
p = sys.argv[1]; s = open(p).read()
old = "if (compiled_major != cudaProp.major || compiled_minor > cudaProp.minor) {"
new = ("if (compiled_major > cudaProp.major ||  /* sphcut fix 5: newer major JITs the PTX */\n"
       "        (compiled_major == cudaProp.major && compiled_minor > cudaProp.minor)) {")
if old not in s: sys.exit("fix 5: compute capability check not found")
s = s.replace(old, new, 1)
open(p, "w").write(s)
EOF
  CXX_FOR_KOKKOS="$KSRC/bin/nvcc_wrapper"
  CXXSTD=17      # CUDA 13's own headers need C++17
  CMP_PKGS=(-DPKG_SPH=ON)    # the GPU build is for sphcut's /kk styles; MACHDYN comparisons run on CPUs
  KOKKOS_OPTS=(-DKokkos_ENABLE_SERIAL=ON -DKokkos_ENABLE_CUDA=ON -DKokkos_ENABLE_CUDA_LAMBDA=ON
               -DKokkos_ARCH_AMPERE80=ON)
fi
log "building Kokkos $KOKKOS_VERSION ($BACKEND)"
TK0=$(date +%s)
cmake -S "$KSRC" -B "$PREFIX/build/kokkos" -G "$GEN" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$CXX_FOR_KOKKOS" -DCMAKE_CXX_STANDARD=$CXXSTD \
  -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_INSTALL_LIBDIR=lib -DBUILD_SHARED_LIBS=ON \
  "${KOKKOS_OPTS[@]}" > "$PREFIX/build-kokkos.log" 2>&1 \
  || { tail -30 "$PREFIX/build-kokkos.log"; exit 1; }
cmake --build "$PREFIX/build/kokkos" -j "$JOBS" >> "$PREFIX/build-kokkos.log" 2>&1 \
  && cmake --install "$PREFIX/build/kokkos" >> "$PREFIX/build-kokkos.log" 2>&1 \
  || { tail -30 "$PREFIX/build-kokkos.log"; exit 1; }
if [ $CUDA = 1 ]; then
  # (4) with CMake >= 3.31 the installed KokkosConfig.cmake must find the CUDA toolkit
  #     before it loads its exported targets, which name CUDA::cudart etc.
  #     Without it: LAMMPS' configure fails in find_package(Kokkos) with CMake >= 3.31.
  cfg="$PREFIX/lib/cmake/Kokkos/KokkosConfig.cmake"
  #     (the installed file spells it INCLUDE(, so match either case)
  grep -q "sphcut fix 4" "$cfg" || \
    sed -i '0,/^[Ii][Nn][Cc][Ll][Uu][Dd][Ee](/s//# sphcut fix 4: CUDA targets are needed by the exported TPLs\nfind_package(CUDAToolkit REQUIRED)\ninclude(/' "$cfg"
  grep -q "sphcut fix 4" "$cfg" || { echo "fix 4: no include( in $cfg" >&2; exit 1; }
fi
TK1=$(date +%s)
if [ $KOKKOS_ONLY = 1 ]; then
  touch "$PREFIX/.complete"
  log "done: Kokkos in $PREFIX ($((TK1 - TK0)) s)"
  exit 0
fi

# ---------------------------------------------------------------- LAMMPS
if [ $CUDA = 1 ]; then
  # Fixes 6 to 9 (CUDA): with an MPI that is not GPU-aware (Open MPI built without CUDA, as on the
  # device machine) LAMMPS 29Sep2021 sends all Kokkos communication on several ranks through its
  # classic host path (the whole x array to the host and back every step, every atom array at every
  # reneighbouring); tools/lammps-staged-comm.py packs on the device and stages only the messages
  # through the host: the forward communication (fix 6), the exchange and borders (fix 7), the
  # fixes' and pairs' messages without their whole buffers (fix 8), all of them through page-locked
  # host buffers (fix 9)
  # (checked on the OpenMP backend by ctest -R test_migrate_np2_staged; figures bench/gpu/RESULTS.md)
  # Performance only, for several GPUs without a GPU-aware MPI (LAMMPS' host path gives the same
  # results); without each, on the 3D slab of 4.24 M particles: fix 6 2 H100 46.7 against 34.8 ms
  # a step, fix 7 4 H200 19.6 against 16.6, fix 8 15.0 against 13.5, fix 9 12.1 against 11.1.
  # LAMMPS 4Jul2026 still takes its host path with gpu/aware off on several ranks.
  python3 "$HERE/lammps-staged-comm.py" "$LSRC/src/KOKKOS/kokkos.cpp" "$LSRC/src/KOKKOS/comm_kokkos.cpp"
  grep -q "sphcut fix 6" "$LSRC/src/KOKKOS/comm_kokkos.cpp"
  grep -q "sphcut fix 7" "$LSRC/src/KOKKOS/comm_kokkos.cpp"
  grep -q "sphcut fix 8" "$LSRC/src/KOKKOS/comm_kokkos.cpp"
  grep -q "sphcut fix 9" "$LSRC/src/KOKKOS/comm_kokkos.cpp"
fi
log "building LAMMPS (shared, MPI, OpenMP, PLUGIN KOKKOS OPENMP ${CMP_PKGS[*]})"
mkdir -p "$LSRC/potentials"    # its install step copies this folder (absent in packed sources)
LAMMPS_CXX="${CXX:-g++}"
[ $CUDA = 1 ] && LAMMPS_CXX="$KSRC/bin/nvcc_wrapper"
cmake -S "$LSRC/cmake" -B "$PREFIX/build/lammps" -G "$GEN" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$LAMMPS_CXX" \
  -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_INSTALL_LIBDIR=lib \
  -DCMAKE_INSTALL_RPATH="$PREFIX/lib" -DLAMMPS_INSTALL_RPATH=ON \
  -DBUILD_SHARED_LIBS=ON -DBUILD_MPI=ON -DBUILD_OMP=ON -DLAMMPS_EXCEPTIONS=ON \
  -DPKG_PLUGIN=ON -DPKG_MOLECULE=ON -DPKG_KOKKOS=ON -DEXTERNAL_KOKKOS=ON -DKokkos_DIR="$PREFIX/lib/cmake/Kokkos" \
  -DCMAKE_CXX_STANDARD=$CXXSTD -DPKG_OPENMP=ON "${CMP_PKGS[@]}" \
  > "$PREFIX/build-lammps.log" 2>&1 || { tail -30 "$PREFIX/build-lammps.log"; exit 1; }
cmake --build "$PREFIX/build/lammps" -j "$JOBS" >> "$PREFIX/build-lammps.log" 2>&1 \
  && cmake --install "$PREFIX/build/lammps" >> "$PREFIX/build-lammps.log" 2>&1 \
  || { tail -40 "$PREFIX/build-lammps.log"; exit 1; }
TL1=$(date +%s)

# what the plugin build reads (CMakeLists.txt includes this file)
cat > "$PREFIX/sphcut-deps.cmake" <<EOF
# written by tools/build-deps.sh
set(LAMMPS_SOURCE_DIR "$LSRC/src" CACHE PATH "LAMMPS source tree (headers)")
set(LAMMPS_ROOT "$PREFIX" CACHE PATH "LAMMPS install prefix")
set(Kokkos_ROOT "$PREFIX" CACHE PATH "Kokkos install prefix")
set(SPHCUT_DEPS_BACKEND "$BACKEND")
set(CMAKE_CXX_STANDARD $CXXSTD)
EOF
[ $CUDA = 1 ] && echo "set(CMAKE_CXX_COMPILER \"$KSRC/bin/nvcc_wrapper\" CACHE FILEPATH \"\")" >> "$PREFIX/sphcut-deps.cmake"
# drop the object files, keep logs and the source tree (headers for plugins)
rm -rf "$PREFIX/build"
printf 'kokkos_s=%d lammps_s=%d total_s=%d jobs=%d\n' $((TK1-TK0)) $((TL1-TK1)) $((TL1-T0)) "$JOBS" \
  > "$PREFIX/build-times.txt"
touch "$PREFIX/.complete"
log "done in $((TL1-T0)) s (Kokkos $((TK1-TK0)) s, LAMMPS $((TL1-TK1)) s): $PREFIX"
