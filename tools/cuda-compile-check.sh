#!/usr/bin/env bash
# Compile the /kk sources (KOKKOS/*.cpp) as CUDA code with nvcc, on a machine without a GPU:
# what the device machine's build would reject (a device lambda in a private member function,
# a host-only call in a kernel, ...) shows up here, before device time is spent on it.
# Needs nvcc and the CUDA Kokkos headers, which it builds once into the cache
# (tools/build-deps.sh --cuda --kokkos-only, a few minutes), and the LAMMPS sources of the
# OpenMP dependency build (make deps).  PTX only (no machine code): a compile check, not a build.
# Usage: tools/cuda-compile-check.sh [--jobs N] [FILE.cpp ...]   (default: all of KOKKOS/*.cpp and
# LAMMPS' comm_kokkos.cpp and kokkos.cpp with the CUDA build's fixes 6-9)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
JOBS=1
FILES=()
while [ $# -gt 0 ]; do
  case "$1" in
    --jobs) JOBS="$2"; shift ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) FILES+=("$1") ;;
  esac
  shift
done
DEFAULT_FILES=0
[ ${#FILES[@]} -gt 0 ] || { FILES=("$ROOT"/KOKKOS/*.cpp); DEFAULT_FILES=1; }
command -v nvcc >/dev/null 2>&1 || export PATH="$PATH:/usr/local/cuda/bin"
command -v nvcc >/dev/null 2>&1 || { echo "cuda-compile-check: no nvcc" >&2; exit 2; }
LPREFIX=$(bash "$ROOT/tools/build-deps.sh" --print-prefix)
[ -f "$LPREFIX/.complete" ] || { echo "cuda-compile-check: no dependency build in $LPREFIX (make deps)" >&2; exit 2; }
KPREFIX=$(bash "$ROOT/tools/build-deps.sh" --cuda --kokkos-only --print-prefix)
if [ ! -f "$KPREFIX/.complete" ]; then
  bash "$ROOT/tools/build-deps.sh" --cuda --kokkos-only --jobs "$JOBS" || exit 1
fi
LSRC="$LPREFIX/src/lammps/src"
NVW="$KPREFIX/src/kokkos/bin/nvcc_wrapper"
MPI_INC=$(mpicxx --showme:incdirs 2>/dev/null | tr ' ' '\n' | sed 's/^/-isystem /' | tr '\n' ' ')
OUTDIR=$(mktemp -d)
trap 'rm -rf "$OUTDIR"' EXIT
# by default also LAMMPS' two files that fixes 6-9 of tools/build-deps.sh patch for the CUDA build
# (tools/lammps-staged-comm.py), patched here as there
if [ $DEFAULT_FILES = 1 ]; then
  mkdir -p "$OUTDIR/lammps"
  cp "$LSRC/KOKKOS/comm_kokkos.cpp" "$LSRC/KOKKOS/kokkos.cpp" "$OUTDIR/lammps/"
  python3 "$ROOT/tools/lammps-staged-comm.py" "$OUTDIR/lammps/comm_kokkos.cpp" "$OUTDIR/lammps/kokkos.cpp"
  FILES+=("$OUTDIR/lammps/comm_kokkos.cpp" "$OUTDIR/lammps/kokkos.cpp")
fi
compile() {
  local f=$1
  local t0; t0=$(date +%s)
  if NVCC_WRAPPER_DEFAULT_COMPILER=g++ "$NVW" -std=c++17 -O1 -arch=compute_80 -code=compute_80 \
      --expt-extended-lambda --expt-relaxed-constexpr \
      -DLAMMPS_EXCEPTIONS -DLAMMPS_SMALLBIG -DLMP_KOKKOS -DSPHCUT_HAVE_KOKKOS \
      -DSPHCUT_LAMMPS_VERSION=20210929 -DSPHCUT_VERSION='"0.1.0"' \
      -I"$ROOT/src" -I"$ROOT/KOKKOS" -I"$LSRC" -I"$LSRC/KOKKOS" -isystem "$KPREFIX/include" $MPI_INC \
      -Xcudafe --display_error_number -Xcudafe --diag_error=20011 -Xcudafe --diag_error=20014 \
      -Xcudafe --diag_suppress=20012 \
      -c "$f" -o "$OUTDIR/$(basename "$f").o" > "$OUTDIR/$(basename "$f").log" 2>&1; then
    echo "ok    $(basename "$f") ($(( $(date +%s) - t0 )) s)"
  else
    echo "FAIL  $(basename "$f")"
    grep -E "error|warning" -A3 "$OUTDIR/$(basename "$f").log" | head -40
    return 1
  fi
}
export -f compile
export NVW ROOT LSRC KPREFIX MPI_INC OUTDIR
printf '%s\n' "${FILES[@]}" | xargs -P "$JOBS" -I{} bash -c 'compile "$@"' _ {}
