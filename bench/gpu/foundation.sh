#!/usr/bin/env bash
# GPU foundation check, on a machine with an NVIDIA GPU and CUDA (the figures: one H100, CUDA 13):
#   1. Kokkos 3.4.01 (CUDA, the fixes in tools/build-deps.sh) + LAMMPS, and
#   2. the sphcut plugin against that LAMMPS (the /kk registration compiled with nvcc_wrapper):
#      build them first as in README, "GPU build" (bash tools/build-deps.sh --cuda, then
#      build-cuda/); the script uses build-cuda/lmp_sphcut
#   3. the LJ melt benchmark, 864,000 atoms: GPU (-k on g 1 -sf kk) and one CPU core
# Results (timings, logs) go to $OUT (or ./gpu-out).
# Usage, from the repository root: bash bench/gpu/foundation.sh [steps_gpu] [steps_cpu]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
STEPS_GPU="${1:-1000}"
STEPS_CPU="${2:-20}"
source "$ROOT/bench/gpu/common.sh"
build
{ nvidia-smi -L; nvcc --version | tail -2; cmake --version | head -1; g++ --version | head -1; echo "cores: $(nproc)"; } > "$OUT/device.txt" 2>&1 || true

LMP="$(bash "$ROOT/tools/build-deps.sh" --cuda --print-prefix)/bin/lmp"
cd "$ROOT/bench/lj-melt"
# warm-up run (not reported): fills the JIT cache, so the timed run's loop does not
# include compiling the sm_80 PTX for the device; screen output kept for errors
"$LMP" -k on g 1 -sf kk -in in.lj-melt -var x 3 -var y 3 -var z 3 -var steps 100 \
  -log none > /tmp/screen-gpu-warmup.txt 2>&1 || { tail -30 /tmp/screen-gpu-warmup.txt; exit 1; }
"$LMP" -k on g 1 -sf kk -in in.lj-melt -var x 3 -var y 3 -var z 3 -var steps "$STEPS_GPU" \
  -log "$OUT/log.melt-gpu" > /tmp/screen-gpu.txt 2>&1 || { tail -30 /tmp/screen-gpu.txt; exit 1; }
"$LMP" -in in.lj-melt -var x 3 -var y 3 -var z 3 -var steps "$STEPS_CPU" \
  -log "$OUT/log.melt-cpu1" > /tmp/screen-cpu1.txt 2>&1 || { tail -30 /tmp/screen-cpu1.txt; exit 1; }
cd "$ROOT"
# plugin loads into the CUDA LAMMPS via the launcher
printf 'plugin list\n' > /tmp/in.plugins
"$BIN" -k on g 1 -sf kk -in /tmp/in.plugins -log none > "$OUT/plugin-list.txt" 2>&1 || true
grep -h "Loop time" "$OUT"/log.melt-* | tee -a "$SUM"
