#!/usr/bin/env bash
# The mechanical step on the GPU (pair sph/jc-thermal/kk + fix sph/jc-thermal/kk), run on the
# a machine with an NVIDIA GPU and CUDA (the figures: one H100, 16 cores).  Build the GPU plugin
# first (README, "GPU build": build-cuda/lmp_sphcut), then from the repository root:
#   bash bench/gpu/mechanics.sh MODE [MODE ...]
#   check   CPU (1 rank) vs GPU state after 100 steps of a 3D plastic collision (<= 1e-8 relative);
#           a GPU run split by a restart vs the unsplit one
#   bench   block collision at 0.1, 1, 4 and 16 M particles: particle-steps/s on the GPU (FP64),
#           and on the 16 CPU cores with the CPU styles and MPI (0.1, 1, 4 M; GPU_ONLY=1: not)
#   taylor  Taylor bar (examples/taylor-bar) on the GPU at dx 0.4, 0.2, 0.1 mm (TAYLOR_DX)
#   taylor_cpu  the same on the 16 CPU cores with the CPU styles (TAYLOR_DX, default 0.4 0.2 mm)
#   profile Nsight Compute on the main kernels at 1 M particles
#   arch    the plugin also built with native sm_90 code: the 1 M and 4 M block runs again
# Results (logs, summary.txt) go to $OUT (or ./gpu-out).  Figures: bench/gpu/RESULTS.md.
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/bench/gpu/common.sh"

check() {
  local d=/tmp/check; mkdir -p $d; cd $d
  local B="$ROOT/bench/gpu"
  lmp -in "$B/in.collision" -var nx 24 -var out cpu.dump -log log.cpu > /dev/null 2>&1 || { tail log.cpu; return 1; }
  lmp $GPU -in "$B/in.collision" -var nx 24 -var out gpu.dump -log log.gpu > screen.gpu 2>&1 || { tail -20 screen.gpu; return 1; }
  lmp $GPU -in "$B/in.collision" -var nx 24 -var steps 50 -var write r50 -var out half.dump -log log.half > /dev/null 2>&1
  lmp $GPU -in "$B/in.collision" -var restart r50 -var steps 50 -var out split.dump -log log.split > /dev/null 2>&1
  say "check CPU vs GPU (3D collision, 100 steps): $(python3 "$B/compare.py" cpu.dump gpu.dump 1e-8 | tr '\n' ' ')"
  say "check GPU split by restart vs unsplit: $(python3 "$B/compare.py" gpu.dump split.dump 1e-10 | tr '\n' ' ')"
  grep -A3 "^ *Step" log.cpu log.gpu | tail -8 >> "$SUM"
  cp log.cpu log.gpu log.split "$OUT/" 2>/dev/null
  cd "$ROOT"
}

# one block run: label, lmp arguments; prints particle-steps/s from the timed run's Loop time
block() {
  local label=$1; shift
  local log="/tmp/bench/log.$label"
  mkdir -p /tmp/bench; cd /tmp/bench
  if ! timeout 500 "$@" -in "$ROOT/bench/gpu/in.block" -log "$log" > "$log.screen" 2>&1; then
    say "$label: FAILED ($(grep -m1 ERROR "$log.screen"))"; cd "$ROOT"; return 0
  fi
  local loop; loop=$(grep "^Loop time" "$log" | tail -1)
  local t n a; t=$(echo "$loop" | awk '{print $4}'); n=$(echo "$loop" | awk '{print $9}'); a=$(echo "$loop" | awk '{print $12}')
  say "$(awk -v l="$label" -v a="$a" -v n="$n" -v t="$t" 'BEGIN{printf "%-22s %9d particles %5d steps %9.3f s  %.3e particle-steps/s\n", l, a, n, t, a*n/t}')"
  awk '/sphcut timing/{n++} n==2' "$log" | sed -n '1,8p' | grep -v "^Loop" | sed "s/^/    /" >> "$SUM"
  cd "$ROOT"
}

bench() {
  nvidia-smi --query-gpu=name,memory.total --format=csv,noheader >> "$SUM"
  # nx: 2 nx^3 particles
  block gpu-0.1M "$BIN" $GPU -var nx 37 -var steps 200
  block gpu-1M "$BIN" $GPU -var nx 80 -var steps 100
  block gpu-4M "$BIN" $GPU -var nx 126 -var steps 50
  block gpu-16M "$BIN" $GPU -var nx 200 -var steps 20
  [ -n "${GPU_ONLY:-}" ] && return 0
  block cpu16-0.1M mpirun -np 16 "$BIN" -var nx 37 -var steps 20
  block cpu16-1M mpirun -np 16 "$BIN" -var nx 80 -var steps 10
  block cpu16-4M mpirun -np 16 "$BIN" -var nx 126 -var steps 5
}

taylor() {
  mkdir -p /tmp/taylor; cd /tmp/taylor
  for dx in ${TAYLOR_DX:-0.4e-3 0.2e-3 0.1e-3}; do
    local t0; t0=$(date +%s)
    timeout "${TAYLOR_TIMEOUT:-500}" "$BIN" $GPU -in "$ROOT/examples/taylor-bar/in.taylor" -var dx $dx \
      -log log.taylor-$dx > screen-$dx 2>&1 \
      || say "taylor dx $dx: FAILED or timed out ($(grep -m1 ERROR screen-$dx))"
    say "taylor dx $dx: $(grep '^TAYLOR final' log.taylor-$dx) atoms $(grep -m1 'Created .* atoms' log.taylor-$dx | awk '{print $2}'), wall $(( $(date +%s) - t0 )) s"
    grep "^Loop time" log.taylor-$dx | tail -2 >> "$SUM"
    cp log.taylor-$dx "$OUT/" 2>/dev/null
  done
  cd "$ROOT"
}

# Nsight Compute on the pair kernel (1 M particles): speed of light, occupancy, launch
profile() {
  command -v ncu > /dev/null || { say "profile: no ncu"; return 0; }
  mkdir -p /tmp/prof; cd /tmp/prof
  # Kokkos names every kernel cuda_parallel_launch_*: select by the functor in the demangled name
  timeout 400 ncu --kernel-name-base demangled --kernel-name regex:"${PROFILE_KERNELS:-full_pass|SecondHalf|FirstHalf|initial_integrate|stress_pass}" \
    --launch-skip 8 --launch-count "${PROFILE_COUNT:-4}" \
    --section SpeedOfLight --section Occupancy --section LaunchStats --section MemoryWorkloadAnalysis \
    "$BIN" $GPU -in "$ROOT/bench/gpu/in.block" -var nx 80 -var steps 10 -log none > ncu.txt 2>&1
  cp ncu.txt "$OUT/ncu.txt"
  grep -E "^  [a-zA-Z_].*\(|Duration|DRAM Throughput|Compute \(SM\) Throughput|Memory Throughput|Achieved Occupancy|Registers Per|Theoretical Occupancy|L1/TEX Hit|L2 Hit" ncu.txt | head -60 >> "$SUM"
  cd "$ROOT"
}

# the same Taylor bar with the CPU styles on the 16 cores (MPI): GPU and CPU over a whole run
taylor_cpu() {
  mkdir -p /tmp/taylor; cd /tmp/taylor
  for dx in ${TAYLOR_DX:-0.4e-3 0.2e-3}; do
    local t0; t0=$(date +%s)
    timeout "${TAYLOR_TIMEOUT:-500}" mpirun -np 16 "$BIN" -in "$ROOT/examples/taylor-bar/in.taylor" -var dx $dx \
      -log log.taylor-cpu16-$dx > screen-cpu-$dx 2>&1 || say "taylor cpu16 dx $dx: FAILED or timed out"
    say "taylor cpu16 dx $dx: $(grep '^TAYLOR final' log.taylor-cpu16-$dx), wall $(( $(date +%s) - t0 )) s"
    grep "^Loop time" log.taylor-cpu16-$dx | tail -2 >> "$SUM"
  done
  cd "$ROOT"
}

arch() {
  PREFIX=$(bash "$ROOT/tools/build-deps.sh" --cuda --print-prefix)
  cmake -S "$ROOT" -B "$ROOT/build-cuda90" -DSPHCUT_DEPS_FILE="$PREFIX/sphcut-deps.cmake" -DBUILD_TESTING=OFF \
    -DSPHCUT_CUDA_ARCH=sm_90 > "$OUT/plugin-build90.log" 2>&1 \
    && cmake --build "$ROOT/build-cuda90" -j "$NJ" >> "$OUT/plugin-build90.log" 2>&1 \
    || { tail -20 "$OUT/plugin-build90.log"; return 0; }
  grep "sphcut:.*-arch" "$OUT/plugin-build90.log" | tee -a "$SUM"
  command -v cuobjdump > /dev/null && cuobjdump --list-elf "$ROOT/build-cuda90/sphcutplugin.so" 2>&1 | head -3 | tee -a "$SUM"
  local p90="env LAMMPS_PLUGIN_PATH=$ROOT/build-cuda90"
  block sm80ptx-1M "$BIN" $GPU -var nx 80 -var steps 100
  block sm90-1M $p90 "$BIN" $GPU -var nx 80 -var steps 100
  block sm80ptx-4M "$BIN" $GPU -var nx 126 -var steps 50
  block sm90-4M $p90 "$BIN" $GPU -var nx 126 -var steps 50
}

run_modes "$@"
tar czf "$OUT/logs.tar.gz" -C /tmp bench check taylor 2>/dev/null || true
