#!/usr/bin/env bash
# sphcut - does the plugin still compile against the newer LAMMPS versions README names?
# Compiles (g++ -fsyntax-only, the plugin's warning flags), with SPHCUT_LAMMPS_VERSION set as
# CMake sets it, against headers fetched and cached by tools/compat-sources.sh:
#   every CPU source, src/*.cpp and tools/lmp_sphcut.cpp, against LAMMPS 4Feb2025 and 4Jul2026
#     (-std=c++17, which their headers require);
#   every /kk source, KOKKOS/*.cpp, against LAMMPS 4Jul2026 with its KOKKOS package and the
#     headers of Kokkos 5.2.2 (OpenMP backend, Debian sid's libkokkos-dev; -std=c++20 -fopenmp,
#     which Kokkos 5 requires), and against LAMMPS 4Feb2025 with the headers of Kokkos 4.5.01
#     (Debian sid's libtrilinos-kokkos-dev, built with the Serial backend only, so the device
#     and host types are the same there; -std=c++17).
# Fails, naming each source and its first errors, when the LAMMPS API drifts away from what
# src/sphcut_compat.h, KOKKOS/sphcut_kokkos.h and the version checks handle.  Nothing is linked
# or run: README, "Compatibility with newer LAMMPS", says what was run by hand.
#
# Usage: tools/compat-check.sh [--jobs N] [--mpi-cflags "FLAGS"]
#   --jobs N          parallel compilations (default 2)
#   --mpi-cflags F    the MPI compile flags (ctest passes CMake's MPI_CXX_INCLUDE_DIRS);
#                     default: `mpicxx --showme:compile` (Open MPI) or `mpicxx -compile_info`
# Exit status: 0 all compile; 1 a source does not; 77 the headers cannot be downloaded
# outside CI (tools/compat-sources.sh; ctest shows the test as skipped).
# Environment: SPHCUT_CACHE, CXX (default g++).
set -uo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
JOBS=2
MPI_CFLAGS=""
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) JOBS="$2"; shift ;;
    --mpi-cflags) MPI_CFLAGS="$2"; shift ;;
    -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
    *) echo "compat-check.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

out=$(bash "$ROOT/tools/compat-sources.sh")
rc=$?
echo "$out"
[ "$rc" = 0 ] || exit "$rc"
DIR=$(tail -1 <<< "$out")

CXX="${CXX:-g++}"
if [ -z "$MPI_CFLAGS" ]; then
  MPI_CFLAGS=$(mpicxx --showme:compile 2>/dev/null || mpicxx -compile_info 2>/dev/null | cut -d' ' -f2- || true)
fi
# MPI and LAMMPS headers as system headers: their own warnings are not the plugin's
sys_flags=()
for f in $MPI_CFLAGS; do
  case "$f" in -I*) sys_flags+=(-isystem "${f#-I}") ;; *) sys_flags+=("$f") ;; esac
done
version=$(sed -n 's/^project(sphcut VERSION \([0-9.]*\).*/\1/p' "$ROOT/CMakeLists.txt")

sources=("$ROOT"/src/*.cpp "$ROOT/tools/lmp_sphcut.cpp")
kk_sources=("$ROOT"/KOKKOS/*.cpp)
# the LAMMPS versions the /kk sources are checked against, each with the Kokkos of its time
KK_VERSIONS=(20250204 20260704)
declare -A KOKKOS_OF=([20250204]=4.5.1 [20260704]=5.2.2)
logs=$(mktemp -d)
trap 'rm -rf "$logs"' EXIT

# compile_one NUMBER SOURCE: the flags a CMake build against that LAMMPS would use
compile_one() {
  local ver="$1" src="$2" lsrc="$DIR/lammps-$1/src"
  local rel="${src#"$ROOT"/}"
  local log="$logs/$ver-${rel//\//_}.log"
  local flags=(-std=c++17)
  if [[ "$src" == "$ROOT"/KOKKOS/* ]]; then
    flags=(-DLMP_KOKKOS -DSPHCUT_HAVE_KOKKOS -I"$ROOT/KOKKOS" -isystem "$lsrc/KOKKOS"
           -isystem "$DIR/kokkos-${KOKKOS_OF[$ver]}/include")
    if [ "${KOKKOS_OF[$ver]%%.*}" -ge 5 ]; then
      # C++20 itself deprecates compound assignments to volatile values and the LAMMPS mask enums'
      # arithmetic (-Wvolatile, -Wdeprecated-enum-enum-conversion): not an API drift, not shown
      flags+=(-std=c++20 -fopenmp -Wno-volatile -Wno-deprecated-enum-enum-conversion)
    else
      flags+=(-std=c++17)
    fi
  fi
  "$CXX" -fsyntax-only -Wall -Wextra -Wno-unused-parameter "${flags[@]}" \
    -DSPHCUT_LAMMPS_VERSION="$ver" -DSPHCUT_VERSION="\"$version\"" \
    -I"$ROOT/src" -isystem "$lsrc" -isystem "$lsrc/PLUGIN" "${sys_flags[@]}" "$src" > "$log" 2>&1
  echo $? > "$log.rc"
}

versions=()
for d in "$DIR"/lammps-*/; do d="${d%/}"; versions+=("${d##*/lammps-}"); done
# the (version, source) pairs to compile
jobs_v=() jobs_s=()
for ver in "${versions[@]}"; do
  for src in "${sources[@]}"; do jobs_v+=("$ver"); jobs_s+=("$src"); done
done
for ver in "${KK_VERSIONS[@]}"; do
  for src in "${kk_sources[@]}"; do jobs_v+=("$ver"); jobs_s+=("$src"); done
done
t0=$(date +%s)
for k in "${!jobs_v[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n; done
  compile_one "${jobs_v[$k]}" "${jobs_s[$k]}" &
done
wait

fail=0
for k in "${!jobs_v[@]}"; do
  ver="${jobs_v[$k]}" src="${jobs_s[$k]}"
  rel="${src#"$ROOT"/}"
  log="$logs/$ver-${rel//\//_}.log"
  if [ "$(cat "$log.rc")" = 0 ]; then
    if grep -q "warning:" "$log"; then
      echo "LAMMPS $ver  $rel  compiles, with warnings:"; grep -m5 "warning:" "$log" | sed 's/^/    /'
    else
      echo "LAMMPS $ver  $rel  compiles"
    fi
  else
    fail=1
    echo "LAMMPS $ver  $rel  FAILS:"
    grep -m8 -E "error|required from here" "$log" | sed 's/^/    /'
  fi
done
kk_pairs=$(for v in "${KK_VERSIONS[@]}"; do printf '%s+Kokkos %s, ' "$v" "${KOKKOS_OF[$v]}"; done)
echo "compat-check: ${#sources[@]} CPU sources x LAMMPS ${versions[*]}, ${#kk_sources[@]} /kk sources x LAMMPS" \
  "${kk_pairs%, }: ${#jobs_v[@]} compilations in $(( $(date +%s) - t0 )) s ($CXX, headers in $DIR)"
if [ $fail = 1 ]; then
  echo "compat-check: FAILED: the sources no longer compile against a LAMMPS version README claims" >&2
  exit 1
fi
