#!/usr/bin/env bash
# The 2D cut on one core (1 MPI rank, OMP_NUM_THREADS=1): examples/cutting-2d-ti6al4v at `ny`
# particles across (default 41, 18,272 particles) for its first `steps` steps (default 2000:
# the tool enters the workpiece), `reps` alternating repetitions (default 2).  Prints the loop
# time, user CPU time, microseconds per particle-step and the sphcut timing table of each run.
# SPHCUT_BEFORE=<folder with another sphcutplugin.so> alternates the same run with that plugin
# (before/after figures).  ARGS: more -var settings of the example; HDX: h/dx (default 1.3, the
# figures of doc/performance.md; the example's own choice is 1.5 from 41 across, which has 1.33x
# the neighbours).  Builds nothing (make build first); logs in $OUT (default a temp dir).
# Usage: bash bench/cutting/cpu-rate.sh [ny] [steps] [reps]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
ny=${1:-41}
steps=${2:-2000}
reps=${3:-2}
# shellcheck disable=SC1091
source "$root/build/env.sh"
export OMP_NUM_THREADS=1
out="${OUT:-$(mktemp -d)}"
plugins="now:$root/build"
[ -n "${SPHCUT_BEFORE:-}" ] && plugins="before:$SPHCUT_BEFORE $plugins"
echo "# $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg); ny=$ny steps=$steps reps=$reps hdx=${HDX:-1.3} ${ARGS:-}; logs in $out"
for r in $(seq 1 "$reps"); do
  for p in $plugins; do
    name=${p%%:*}
    d="$out/$name.$r"
    mkdir -p "$d" && cd "$d"
    LAMMPS_PLUGIN_PATH=${p#*:} /usr/bin/time -f %U -o time "$LMP" -in "$root/examples/cutting-2d-ti6al4v/in.cutting" \
      -var ny "$ny" -var steps "$steps" -var dumpevery 1000000 -var hdx "${HDX:-1.3}" ${ARGS:-} -log log > /dev/null
    grep "^Loop time" log | tail -1 | awk -v n="$name" -v r="$r" -v u="$(cat time)" \
      '{printf("%-6s rep %s: loop %.2f s, user %.2f s, %d steps, %d particles, %.3f us per particle-step (loop)\n", n, r, $4, u, $9, $12, 1e6 * $4 / ($9 * $12))}'
    sed -n '/^sphcut timing of this run/,/rest (neighbour/p' log | tail -n +2
  done
done
