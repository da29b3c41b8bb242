#!/usr/bin/env bash
# The validation campaign on one GPU, on a machine with an NVIDIA GPU and CUDA: build the GPU plugin
# first (README, "GPU build": build-cuda/lmp_sphcut), then from the repository root
#   bash bench/validation/gpu.sh
# (about 4 minutes of one H100 per parameter set: the 72 tests of the dataset).  It starts the
# CUDA MPS daemon where it exists (several small cuts share the GPU: bench/gpu/cutting.sh concurrent),
# runs one short cut to fill the CUDA JIT cache, then for each parameter set of VAL_SETS
# `validate.py run` with VAL_JOBS runs at a time until VAL_END (an epoch second; runs still going
# then are stopped and rerun by the next start: finished ones stay in the database).
#   VAL_SETS   ;-separated argument lists of validate.py (default "--set seed003"; "-": none, Figure 6 alone)
#   VAL_ARGS   arguments for every set (e.g. "--vc 318.5,100")
#   VAL_JOBS   runs at a time (default 16)
#   VAL_DB     the runs database (default $OUT/runs.sqlite; give an earlier database to continue it)
#   VAL_END    epoch second by which the script ends (default: 9 minutes from its start)
#   FIG6_NY    also seed 003's Figure 6 beside the campaign: the example's cut (h 0.1 mm, the measured
#              edge) at FIG6_NY across over FIG6_CUT (2e-3 m) for each mu of FIG6_MUS (0.35 0.5 0.65),
#              all at once; steady.py's means (after 10 % of the cut) in the summary, forces.dat in
#              $OUT/fig6.tar.gz; a run not finished by VAL_END is stopped and reported as far as it got
# To try it elsewhere (CPU, no build): SPHCUT_LMP=$LMP SPHCUT_GPU_ARGS=" " VAL_ARGS="--limit 1" bash bench/validation/gpu.sh
# Results: $OUT/summary.txt (progress and tables), $OUT/runs.sqlite; make the tables and plots
# anywhere from the database: validate.py report --db runs.sqlite [the same options].
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/bench/gpu/common.sh"
GPUK="$GPU -pk kokkos neigh full newton off"
[ "$GPU" = " " ] && GPUK=""      # the CPU styles (SPHCUT_GPU_ARGS=" "): no kokkos package options
T0=$(date +%s)
VAL_END="${VAL_END:-$((T0 + 540))}"
build
DB="${VAL_DB:-$OUT/runs.sqlite}"
[ -f "$DB" ] || [ ! -f "$ROOT/.carry/validation.sqlite" ] || cp "$ROOT/.carry/validation.sqlite" "$DB"
started=0
if command -v nvidia-cuda-mps-control > /dev/null; then
  nvidia-cuda-mps-control -d 2>/dev/null && started=1
fi
say "validation: MPS $started, $(nvidia-smi -L 2>/dev/null | head -1)"
# the first run JIT-compiles the kernels into the CUDA cache; the runs after it find them there
mkdir -p /tmp/val-warm && (cd /tmp/val-warm && timeout 300 "$BIN" $GPUK \
  -in "$ROOT/examples/cutting-2d-ti6al4v/in.cutting" -var ny 11 -var steps 200 -var dumpevery 0 \
  -log none -screen none) || say "warm-up run failed"
say "warm-up: $(( $(date +%s) - T0 )) s after the start (build included)"
fig6_pids=()
if [ -n "${FIG6_NY:-}" ]; then
  for mu in ${FIG6_MUS:-0.35 0.5 0.65}; do
    d=/tmp/fig6/ny${FIG6_NY}-mu$mu; mkdir -p $d
    (cd $d && exec timeout $(( VAL_END - $(date +%s) - 10 )) "$BIN" $GPUK \
      -in "$ROOT/examples/cutting-2d-ti6al4v/in.cutting" -var ny "$FIG6_NY" -var cut "${FIG6_CUT:-2e-3}" \
      -var mu $mu -var dumpevery 0 -log log.cutting -screen none) &
    fig6_pids+=($!)
  done
  say "fig6: ${#fig6_pids[@]} runs at $FIG6_NY across started"
fi
IFS=';' read -ra SETS <<< "${VAL_SETS:---set seed003}"
[ "${VAL_SETS:-}" = "-" ] && SETS=()    # Figure 6 alone
for s in "${SETS[@]}"; do
  left=$(( VAL_END - $(date +%s) ))
  [ $left -gt 90 ] || { say "no time left for: $s"; continue; }
  say "== validate.py run $s ${VAL_ARGS:-} ($left s left)"
  # shellcheck disable=SC2086
  PYTHONUNBUFFERED=1 python3 "$ROOT/bench/validation/validate.py" run $s ${VAL_ARGS:-} --db "$DB" \
    --out /tmp/val --jobs "${VAL_JOBS:-16}" --deadline $((left - 15)) \
    --lmp "$BIN $GPUK" 2>&1 | tee -a "$SUM"
done
if [ ${#fig6_pids[@]} -gt 0 ]; then
  wait "${fig6_pids[@]}"
  for d in /tmp/fig6/*/; do
    say "fig6 $(basename $d): $(grep -h 'Loop time' $d/log.cutting | tail -1)"
    (cd $d && python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" 2>&1 | head -4 | tee -a "$SUM")
  done
  (cd /tmp/fig6 && tar czf "$OUT/fig6.tar.gz" */forces.dat */log.cutting)
fi
[ $started = 0 ] || { echo quit | nvidia-cuda-mps-control; sleep 1; }
say "== done $(( $(date +%s) - T0 )) s"
