#!/usr/bin/env bash
# Sourced by the device scripts of bench/cutting: builds LAMMPS (OpenMP Kokkos, MPI) and the
# plugin on the device machine from .carry/sphcut-sources.tar.gz into build-device/ (once per
# machine), with the logs in $OUT.  Expects ROOT and OUT; sets SPHCUT_CACHE.
export SPHCUT_CACHE="$ROOT/build-device/cache"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mkdir -p "$OUT"
if [ ! -f "$ROOT/build-device/plugin/env.sh" ]; then
  { lscpu | grep -E "Model name|^CPU\(s\)|Thread|MHz"; free -g | head -2; } > "$OUT/cpu.txt" 2>&1 || true
  t0=$(date +%s)
  SRC="$ROOT/build-device/src"; mkdir -p "$SRC"; tar xzf "$ROOT/.carry/sphcut-sources.tar.gz" -C "$SRC"
  bash "$ROOT/tools/build-deps.sh" --no-apt --sources "$SRC" --jobs "$(nproc)" > "$OUT/build-deps.log" 2>&1
  PREFIX=$(bash "$ROOT/tools/build-deps.sh" --print-prefix)
  cmake -S "$ROOT" -B "$ROOT/build-device/plugin" -DSPHCUT_DEPS_FILE="$PREFIX/sphcut-deps.cmake" \
    -DBUILD_TESTING=OFF > "$OUT/plugin-build.log" 2>&1
  cmake --build "$ROOT/build-device/plugin" -j "$(nproc)" >> "$OUT/plugin-build.log" 2>&1
  echo "build seconds: $(( $(date +%s) - t0 ))" | tee "$OUT/build-times.txt"
fi
source "$ROOT/build-device/plugin/env.sh"
