#!/usr/bin/env bash
# bench/pareto: run time against error (issue 14), one command:
#   plate       examples/oscillating-plate: period of the 2D cantilever plate against beam
#               theory (PLATE_PERIODS, default 1), ny particles across = PLATE_NY (default
#               7 11 15 21), cubic kernel (the example's settings) and Wendland C2 at 11 and 21
#               across (PLATE_WENDLAND_NY); prints the cost per particle-step too;
#   conduction  examples/thermal/in.conduction: sine decay on the unit square against the
#               analytic solution, n x n = 11 21 41 81, FMFS (conservative, the default) and
#               Brookshaw;
#   taylor      examples/taylor-bar/in.taylor: final length of the copper Taylor bar after
#               80 us against the reference 21.47 mm, dx = 0.81 0.6 0.5 0.4 mm;
#   cut         examples/cutting-2d-ti6al4v: the 2D Ti6Al4V cut at 11 across over 2 mm of
#               cut (CUT_LEN=0.3e-3 for the quick case), steady Fc and Ft against the
#               experiment (examples/cutting-2d-ti6al4v/seed003.py) and against the finest run
#               of the same contact model (21 across on one H100, 174.3 / 51.5 N/mm, recorded.csv).
# plate, conduction and taylor run on 1 core (1 MPI rank, OMP_NUM_THREADS=1), the cut on
# 2 MPI ranks (CUT_NP, as the example), one case after the other.  Writes results.csv
# (case, option, resolution, particles, steps, loop wall s, error %, platform, value,
# reference, note, source) and, with matplotlib, pareto.png (error against wall time, the
# measured rows of results.csv with the RECORDED, not rerun rows of recorded.csv: the finer
# cuts, the GPU runs), into $OUT (default bench/pareto/results, committed).
# Time on the shared 2-core development VM: plate 5 min, conduction 1 min, taylor 5 min,
# cut 20 min (2 ranks; CUT_LEN=0.3e-3: 1-4 min): about 35 minutes for all (load 4-5).
# Usage: bash bench/pareto/run.sh [plate|conduction|taylor|cut|all] [--plot-only]
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
    /usr/bin/python3 "$here/plot.py" "$csv" "$here/recorded.csv" "$out/pareto.png"
  else
    echo "no matplotlib for /usr/bin/python3: table only"
    column -s, -t "$csv"
  fi
}
[ "${2:-}" = "--plot-only" ] && { plot; exit 0; }

loop_time() { grep "^Loop time" "$1" | tail -1 | awk '{print $4, $9, $12}'; }    # wall steps atoms
# the run with the most steps (an input with several run commands)
loop_time_max() { awk '/^Loop time/ && $9 + 0 >= m {m = $9 + 0; l = $4 " " $9 " " $12} END {print l}' "$1"; }
header="case,option,resolution,particles,steps,wall_s,error_pct,platform,value,reference,note,source"
[ -f "$csv" ] && [ "$(head -1 "$csv")" = "$header" ] || echo "$header" > "$csv"
today="run.sh $(date -u +%F)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ "$what" = plate ] || [ "$what" = all ]; then
  sed -i '/^plate,/d' "$csv"
  periods=${PLATE_PERIODS:-1}
  for opt in cubic wendland; do
    ladder=${PLATE_NY-7 11 15 21}
    [ $opt = wendland ] && ladder=${PLATE_WENDLAND_NY-11 21}
    for ny in $ladder; do
      d="$work/plate-$opt-$ny"
      mkdir -p "$d" && cd "$d"
      sed "s/kernel cubic/kernel $opt/" "$root/examples/oscillating-plate/in.plate" > in.plate
      $LMP -in in.plate -var ny "$ny" -var periods "$periods" -log log.plate > /dev/null
      read -r wall steps atoms < <(loop_time log.plate)
      err=$(python3 "$root/examples/oscillating-plate/period.py" | awk '/SPH period/{gsub(/[()%+]/,"",$5); print $5}')
      us=$(awk -v w="$wall" -v a="$atoms" -v n="$steps" 'BEGIN{printf "%.3f", 1e6 * w / (a * n)}')
      echo "plate,$opt,$ny,$atoms,$steps,$wall,$err,1 core,,beam theory,$periods period(s); $us us per particle-step,$today" | tee -a "$csv"
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
      echo "conduction,$scheme,$n,$atoms,$steps,$wall,$err,1 core,,analytic,max over the particles,$today" | tee -a "$csv"
    done
  done
fi

if [ "$what" = taylor ] || [ "$what" = all ]; then
  sed -i '/^taylor,/d' "$csv"
  lref=21.47    # mm: Kamoulakos (1990) and the verification suites, 21.4-21.5 mm
  for dx in ${TAYLOR_DX:-0.81e-3 0.6e-3 0.5e-3 0.4e-3}; do
    d="$work/taylor-$dx"
    mkdir -p "$d" && cd "$d"
    $LMP -in "$root/examples/taylor-bar/in.taylor" -var dx "$dx" -log log.taylor > /dev/null
    read -r wall steps atoms < <(loop_time_max log.taylor)
    len=$(awk '/^TAYLOR final length/{print $4}' log.taylor)
    err=$(awk -v l="$len" -v r="$lref" 'BEGIN{printf "%.2f", 100 * (l / r - 1)}')
    res=$(awk -v d="$dx" 'BEGIN{printf "%g mm", d * 1000}')
    echo "taylor,cubic,$res,$atoms,$steps,$wall,$err,1 core,$len,$lref mm,,$today" | tee -a "$csv"
  done
fi

if [ "$what" = cut ] || [ "$what" = all ]; then
  sed -i '/^cut,/d' "$csv"
  ny=${CUT_NY:-11}; len=${CUT_LEN:-2e-3}; np=${CUT_NP:-2}
  d="$work/cut-$ny"
  mkdir -p "$d" && cd "$d"
  mpirun -np "$np" $LMP -in "$root/examples/cutting-2d-ti6al4v/in.cutting" -var ny "$ny" -var cut "$len" \
    -var dumpevery 0 -var thermoevery 4000 -log log.cutting > /dev/null
  read -r wall steps atoms < <(loop_time_max log.cutting)
  res=$ny
  [ "$len" = 2e-3 ] || res="$ny ($(awk -v c="$len" 'BEGIN{printf "%g", c * 1000}') mm)"
  # steady forces (mean after 10 % of the cut), against the experiment and against the finest
  # run of the same contact model (recorded.csv: 21 across, 2 mm, one H100)
  PYTHONPATH="$root/examples/cutting-2d-ti6al4v" python3 - "$res" "$atoms" "$steps" "$wall" "$np ranks (this VM)" "$today" <<'PY' | tee -a "$csv"
import sys
from seed003 import EXP_FC, EXP_FT, STEADY_FROM, steady_rows
from steady import read_rows
res, atoms, steps, wall, platform, src = sys.argv[1:]
lmax, sel = steady_rows(read_rows("forces.dat"))
fc = sum(r[2] for r in sel) / len(sel)
ft = sum(r[3] for r in sel) / len(sel)
note = f"mean over {STEADY_FROM * lmax:.2f}-{lmax:.2f} mm"
for name, val, ref, label in (("Fc vs experiment", fc, EXP_FC, f"experiment {EXP_FC}"),
                              ("Ft vs experiment", ft, EXP_FT, f"experiment {EXP_FT}"),
                              ("Fc vs finest", fc, 174.3, "21 across H100 174.3"),
                              ("Ft vs finest", ft, 51.5, "21 across H100 51.5")):
    print(f"cut,{name},{res},{atoms},{steps},{wall},{100 * (val / ref - 1):.1f},{platform},{val:.1f},{label},{note},{src}")
PY
fi
plot
