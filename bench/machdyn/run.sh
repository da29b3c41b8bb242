#!/usr/bin/env bash
# bench/machdyn: sphcut against LAMMPS MACHDYN (pair smd/ulsph) on the 3D scene of issue 14:
# a steel block of n^3 particles (default 31^3 = 29,791; spacing 0.1 mm, 80 neighbours in
# the kernel support in both codes), compressed by an initial velocity field, `steps` steps
# (default 100) with a fixed dt, on one core (1 MPI rank, OMP_NUM_THREADS=1).  Three cases:
#   machdyn   smd/ulsph with smd/integrate_ulsph (in.machdyn; linear plastic)
#   sphcut    pair + fix sph/jc-thermal (in.sphcut; Johnson-Cook)
#   thermal   the same + fix heat/fmfs + compute surface/lambda every step
# run alternately (machdyn, sphcut, thermal, machdyn, ...) `reps` times (default 2), since
# a shared machine is noisy.  Prints the loop time and particle-steps/s of every run, the
# means, sphcut's speed relative to MACHDYN, and sphcut's timing table of its last runs.
# Builds nothing: MACHDYN is in the cached LAMMPS build (tools/build-deps.sh), the plugin
# in build/ (make build).  SPHCUT_BEFORE=<folder with another sphcutplugin.so> adds the cases
# `before` and `before_th`: the mechanics and the thermal case with that plugin (e.g. built
# from an older commit), in the same alternation, for before/after figures.
# Usage: bash bench/machdyn/run.sh [n] [steps] [reps]     (logs kept in $OUT, default a temp dir)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
# shellcheck source=bench/machdyn/common.sh
source "$here/common.sh"
if ! "$LMP_PLAIN" -h | grep "smd/ulsph" > /dev/null; then
  echo "the cached LAMMPS ($LMP_PLAIN) has no MACHDYN package: no comparison possible" >&2
  exit 1
fi
out="${OUT:-$(mktemp -d)}"
mkdir -p "$out"
cd "$out"
: > results.txt    # the means are of this invocation's runs, also where $OUT is reused

run_case() {    # case rep -> prints "case rep atoms steps loop_s user_s"
  local c=$1 r=$2 log="log.$1.$2"
  local -a cmd=("$LMP" -in "$here/in.sphcut" -var n "$n" -var steps "$steps" -log "$log")
  case $c in
    machdyn) cmd=("$LMP_PLAIN" -in "$here/in.machdyn" -var n "$n" -var steps "$steps" -log "$log") ;;
    before)  cmd=(env LAMMPS_PLUGIN_PATH="$SPHCUT_BEFORE" "${cmd[@]}" -var thermal 0) ;;
    before_th) cmd=(env LAMMPS_PLUGIN_PATH="$SPHCUT_BEFORE" "${cmd[@]}" -var thermal 1) ;;
    sphcut)  cmd+=(-var thermal 0) ;;
    thermal) cmd+=(-var thermal 1) ;;
  esac
  /usr/bin/time -f %U -o "time.$c.$r" "${cmd[@]}" > /dev/null
  grep "^Loop time" "$log" | tail -1 | awk -v c="$c" -v r="$r" -v u="$(cat "time.$c.$r")" '{print c, r, $12, $9, $4, u}'
}

# the loop time is wall time, which the other work on a shared machine stretches; the user CPU
# time of the whole process (setup included) is steadier: both are reported
echo "# $(date -u +%FT%TZ) $(hostname) $(getconf _NPROCESSORS_ONLN) cores, load $(cut -d' ' -f1-3 /proc/loadavg); n=$n steps=$steps reps=$reps; logs in $out"
printf '%-8s %3s %7s %6s %9s %14s %8s %14s\n' case rep atoms steps loop_s particle-steps/s user_s per_user_s
cases="machdyn sphcut thermal"
[ -n "${SPHCUT_BEFORE:-}" ] && cases="machdyn before sphcut thermal before_th"
for r in $(seq 1 "$reps"); do
  for c in $cases; do
    run_case "$c" "$r"
  done | awk '{printf("%-8s %3s %7s %6s %9.3f %14.4g %8.2f %14.4g\n", $1, $2, $3, $4, $5, $3 * $4 / $5, $6, $3 * $4 / $6)}' | tee -a results.txt
done
awk '{s[$1] += $3 * $4 / $5; u[$1] += $3 * $4 / $7; t[$1] += $5; tu[$1] += $7; k[$1]++}
     function rate(c) { return s[c] / k[c] }
     function urate(c) { return u[c] / k[c] }
     END {printf("means (wall / user CPU): machdyn %.4g / %.4g, sphcut %.4g / %.4g, thermal %.4g / %.4g particle-steps/s\n",
                 rate("machdyn"), urate("machdyn"), rate("sphcut"), urate("sphcut"), rate("thermal"), urate("thermal"));
          if (k["before"]) printf("before: %.4g / %.4g particle-steps/s, %.2fx / %.2fx MACHDYN; after / before: %.2fx / %.2fx\n",
                                  rate("before"), urate("before"), rate("before") / rate("machdyn"), urate("before") / urate("machdyn"),
                                  rate("sphcut") / rate("before"), urate("sphcut") / urate("before"));
          printf("sphcut mechanics / MACHDYN speed (wall / user CPU): %.2fx / %.2fx; thermal part (fix heat/fmfs + compute surface/lambda) costs %.2fx / %.2fx the mechanics\n",
                 rate("sphcut") / rate("machdyn"), urate("sphcut") / urate("machdyn"),
                 (t["thermal"] - t["sphcut"]) / t["sphcut"], (tu["thermal"] - tu["sphcut"]) / tu["sphcut"]);
          if (k["before_th"]) printf("before: thermal part costs %.2fx / %.2fx the mechanics (wall / user CPU)\n",
                                     (t["before_th"] - t["before"]) / t["before"], (tu["before_th"] - tu["before"]) / tu["before"])}' results.txt
for c in $cases; do
  [ "$c" = machdyn ] && continue
  echo "sphcut timing table, $c, last run:"
  sed -n '/^sphcut timing of this run/,/rest (neighbour/p' "log.$c.$reps"
done
