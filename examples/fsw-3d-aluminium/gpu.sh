#!/usr/bin/env bash
# The full FSW tool of in.fsw's defaults (shoulder R 10 mm, pin R 3 mm x 5.7 mm, 6.35 mm plates,
# 1000 rpm after a 2 ms ramp, plunge 0.2 m/s, 2 ms dwell, 5 mm traverse at 0.1 m/s), started with the
# pin in a hole of its shape (START, default inserted; plunge: from above, README) on one GPU
# under the /kk styles, bounded in wall time.  Run from an output folder:
#   source build-cuda/env.sh && mkdir run && cd run && bash ../examples/fsw-3d-aluminium/gpu.sh
# DX spacing (default 0.25e-3: 540,000 particles, the full case about 31,000 steps), WALL seconds
# of wall time for the run loop (default 300: timer timeout, checked every 100 steps), STEPS (> 0:
# stop there as well), KK the accelerator switches (default one GPU; "-k on t 2 -sf kk -pk kokkos
# neigh full newton off" runs the same styles on 2 host threads, for a check), ARGS more -var
# settings, CONTINUE=1 continues the weld from the restart.fsw that a run stopped by WALL or STEPS
# left in the folder (fsw.dat appended; a weld longer than one machine session in several calls).  Writes fsw.dat, log.fsw, dump.fsw every DUMP steps (default 0: none; a frame of 540,000
# particles is about 30 MB), the last frame to dump.final (id type x y z temperature plastic_strain vonmises, 5 digits) and then, where matplotlib is,
# fsw.png and picture.png (temperature on the top surface and in the section across the joint) from
# it, and gzips it to dump.final.gz; prints the particle count, the steps, the loop's wall time and
# particle-steps/s.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build-cuda/env.sh (or build/env.sh) first}"
DX="${DX:-0.25e-3}"; WALL="${WALL:-300}"; STEPS="${STEPS:-0}"; DUMP="${DUMP:-0}"; ARGS="${ARGS:-}"
START="${START:-inserted}"
KK="${KK:--k on g 1 -sf kk -pk kokkos neigh full newton off}"
t0=$(date +%s.%N)
# shellcheck disable=SC2086
$LMP $KK -in "$here/in.fsw" -var exdir "$here" -var dx "$DX" -var walltime "$WALL" -var steps "$STEPS" \
  -var dumpevery "$DUMP" -var start "$START" -var finaldump 1 -var continue "${CONTINUE:-0}" $ARGS -log log.fsw \
  | awk '/^fsw:|^tool.py/{print} /^ *Step/{h=1} h && /^ +[0-9]+ /{print} /Loop time|WARNING|ERROR|[Tt]imeout/{print}'
t1=$(date +%s.%N)
# the run's loop: the first "Loop time" line (the second is the final frame's run 0)
awk -v t0="$t0" -v t1="$t1" '/^Loop time of/ && !done {
    done = 1; loop = $4; steps = $9; atoms = $12
    printf "fsw gpu: %d particles, %d steps, loop %.1f s, %.3g particle-steps/s, whole command %.1f s\n",
           atoms, steps, loop, (loop > 0 ? atoms * steps / loop : 0), t1 - t0 }' log.fsw
PY=python3; /usr/bin/python3 -c "import matplotlib" 2>/dev/null && PY=/usr/bin/python3
if $PY -c "import matplotlib" 2>/dev/null; then
  $PY "$here/plot.py" && echo "plot: fsw.png"
  $PY "$here/picture.py" -i dump.final --dx "$DX" && echo "picture: picture.png"
fi
gzip -f dump.final && ls -l dump.final.gz
