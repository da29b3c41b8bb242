#!/usr/bin/env bash
# The full-length cuts of examples/cutting-2d-ti6al4v on the CPU cores (MPI) of the GPU machine
# (the figures: 16 cores), with the LAMMPS of the GPU build (README, "GPU build":
# build-cuda/lmp_sphcut; the CPU styles run without -k on).  Long runs are split in segments of
# WALL seconds with the example's restart support (-var walltime / -var continue):
#   bash bench/cutting/device-cut.sh start      start the runs
#   bash bench/cutting/device-cut.sh continue   continue every unfinished run from its restart
# Environment: NY (particles across, default 21), CUT (m, default 2e-3), MUS (friction
# coefficients run side by side, default "0.35 0.65"), NP (ranks per run, default cores/runs),
# WALL (seconds of run per segment, default 420).  Runs in /tmp/cut/run-ny*-mu*; each run's
# output goes to $OUT as one archive.
set -euo pipefail
MODE="${1:-start}"
NY="${NY:-21}"; CUT="${CUT:-2e-3}"; MUS="${MUS:-0.35 0.65}"; WALL="${WALL:-420}"
OUT="${OUT:-$PWD/device-out}"
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
nrun=$(echo $MUS | wc -w)
NP="${NP:-$(( $(nproc) / nrun ))}"
source "$ROOT/bench/gpu/common.sh"    # the device build (build-cuda/), once per machine
build
LMP="$BIN"
RUNS=/tmp/cut
IN="$ROOT/examples/cutting-2d-ti6al4v/in.cutting"
pids=()
for mu in $MUS; do
  dir="$RUNS/run-ny$NY-mu$mu"; mkdir -p "$dir"
  if [ -f "$dir/done" ]; then continue; fi
  cont=0; [ "$MODE" = continue ] && [ -f "$dir/restart.cutting" ] && cont=1
  seg=$(find "$dir" -maxdepth 1 -name 'log.*' | wc -l)
  ( cd "$dir" && mpirun -np "$NP" --bind-to none $LMP -in "$IN" -var ny "$NY" -var cut "$CUT" -var mu "$mu" \
      -var dumpevery "${DUMPEVERY:-40000}" -var thermoevery 10000 -var walltime "$WALL" -var continue $cont \
      -log "log.$seg" -screen none || true
    # finished when the halt criterion fired (cut length reached) rather than the timeout
    grep -q "Fix halt condition" "log.$seg" && touch done || true ) &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p"; done
for mu in $MUS; do
  dir="$RUNS/run-ny$NY-mu$mu"
  # one archive per run (the device returns few files): forces, logs, dump, last tool file
  last=$(find "$dir" -maxdepth 1 -name "tool-*.vtk" | sort -t- -k2 -n | tail -1)
  files="forces.dat $(cd "$dir" && { ls log.* dump.cutting done restart.cutting 2>/dev/null || true; } | tr '\n' ' ') ${last##*/}"
  tar czf "$OUT/run-ny$NY-mu$mu.tar.gz" -C "$dir" $files
  echo "mu $mu: $(grep -h 'Loop time' "$dir"/log.* | tail -1); cut $(tail -1 "$dir/forces.dat" | awk '{print $3}') mm"
done | tee "$OUT/progress.txt"
