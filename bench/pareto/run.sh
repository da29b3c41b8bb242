#!/usr/bin/env bash
# bench/pareto: run time against error for the cheapest references (issue 14), one command:
#   plate       examples/oscillating-plate: period of the 2D cantilever plate against beam
#               theory (1 period), ny particles across = 7 11 15 21, cubic kernel (the
#               example's settings) and Wendland C2 at 11 and 21 across;
#   conduction  examples/thermal/in.conduction: sine decay on the unit square against the
#               analytic solution, n x n = 11 21 41 81, FMFS (conservative, the default) and
#               Brookshaw.
# Every case runs on 1 core (1 MPI rank, OMP_NUM_THREADS=1), one after the other.  Writes
# results.csv (case, option, resolution, particles, steps, loop wall s, error %) and, with
# matplotlib, pareto.png (error against wall time), into $OUT (default bench/pareto/results, committed).
# About 10 minutes on one core of the 2-core development machine.
# Usage: bash bench/pareto/run.sh [plate|conduction|all] [--plot-only]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
what=${1:-all}
[ -f "$root/build/env.sh" ] || { echo "no build/env.sh: run 'make build' first" >&2; exit 1; }
# shellcheck disable=SC1091
source "$root/build/env.sh"
export OMP_NUM_THREADS=1
out="${OUT:-$here/results}"
mkdir -p "$out"
csv="$out/results.csv"
plot() {
  # matplotlib: Debian's python3 (tools/build-deps.sh installs python3-matplotlib)
  if /usr/bin/python3 -c "import matplotlib" 2> /dev/null; then
    /usr/bin/python3 "$here/plot.py" "$csv" "$out/pareto.png"
  else
    echo "no matplotlib for /usr/bin/python3: table only"
    column -s, -t "$csv"
  fi
}
[ "${2:-}" = "--plot-only" ] && { plot; exit 0; }

loop_time() { grep "^Loop time" "$1" | tail -1 | awk '{print $4, $9, $12}'; }    # wall steps atoms
[ -f "$csv" ] || echo "case,option,resolution,particles,steps,wall_s,error_pct" > "$csv"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ "$what" = plate ] || [ "$what" = all ]; then
  sed -i '/^plate,/d' "$csv"
  for opt in cubic wendland; do
    ladder="7 11 15 21"
    [ $opt = wendland ] && ladder="11 21"
    for ny in $ladder; do
      d="$work/plate-$opt-$ny"
      mkdir -p "$d" && cd "$d"
      sed "s/kernel cubic/kernel $opt/" "$root/examples/oscillating-plate/in.plate" > in.plate
      $LMP -in in.plate -var ny "$ny" -var periods 1 -log log.plate > /dev/null
      read -r wall steps atoms < <(loop_time log.plate)
      err=$(python3 "$root/examples/oscillating-plate/period.py" | awk '/SPH period/{gsub(/[()%+]/,"",$5); print $5}')
      echo "plate,$opt,$ny,$atoms,$steps,$wall,$err" | tee -a "$csv"
    done
  done
fi

if [ "$what" = conduction ] || [ "$what" = all ]; then
  sed -i '/^conduction,/d' "$csv"
  for scheme in fmfs brookshaw; do
    for n in 11 21 41 81; do
      d="$work/cond-$scheme-$n"
      mkdir -p "$d" && cd "$d"
      $LMP -in "$root/examples/thermal/in.conduction" -var scheme $scheme -var n "$n" -log log.cond > /dev/null
      read -r wall steps atoms < <(loop_time log.cond)
      # max error relative to the amplitude, in %
      err=$(grep "^CONDUCTION" log.cond | tail -1 | awk '{print 100 * $16}')
      echo "conduction,$scheme,$n,$atoms,$steps,$wall,$err" | tee -a "$csv"
    done
  done
fi
plot
