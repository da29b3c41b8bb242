#!/usr/bin/env bash
# bench/machdyn: what a purely mechanical scene pays for the thermal and contact code (issue 14:
# "nothing, within 5 %").  Builds, in a temporary folder, a second plugin from the committed
# sources (git HEAD) with strip-thermal.patch applied: no temperature predictor, corrector,
# rate bookkeeping or plastic heating in the integration, no tool test when the pair packs its
# rows (CPU styles only).  Then runs in.sphcut isothermal (chi 0: a purely mechanical scene, no
# heat fix, no contact) with the full and the stripped plugin alternately, `reps` times
# (default 2), 1 core, and prints the loop time, the user CPU time and the pair and fix rows
# of the timing table.  The stripped plugin gives the same thermo output (T stays at Tref).
# Usage: bash bench/machdyn/mech-overhead.sh [n] [steps] [reps]     (make build first)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
# shellcheck source=bench/machdyn/common.sh
source "$here/common.sh"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
git -C "$root" archive HEAD | tar -x -C "$tmp"
(cd "$tmp" && patch -s -p1 < "$here/strip-thermal.patch")
cmake -S "$tmp" -B "$tmp/build" -G Ninja -DSPHCUT_DEPS_FILE="$(bash "$root/tools/build-deps.sh" --print-prefix)/sphcut-deps.cmake" \
  -DSPHCUT_KOKKOS=OFF > "$tmp/cmake.log"
cmake --build "$tmp/build" --target sphcutplugin > "$tmp/build.log"
cd "$tmp"
printf '%-9s %3s %8s %7s %7s %7s  %s\n' plugin rep loop_s user_s pair_s fix_s "thermo at the end (step atoms uint ekin Tmax epsmax)"
for r in $(seq 1 "$reps"); do
  for v in full stripped; do
    pp="$root/build"
    [ $v = stripped ] && pp="$tmp/build"
    LAMMPS_PLUGIN_PATH=$pp /usr/bin/time -f %U -o "time.$v" "$LMP" -in "$here/in.sphcut" -var n "$n" -var steps "$steps" \
      -var chi 0 -log "log.$v" > /dev/null
    printf '%-9s %3s %8.3f %7.2f %7.3f %7.3f  %s\n' $v "$r" "$(grep '^Loop time' "log.$v" | awk '{print $4}')" "$(cat "time.$v")" \
      "$(grep '  pair sph' "log.$v" | awk '{print $3}')" "$(grep '  fix sph/jc-thermal' "log.$v" | awk '{print $4}')" \
      "$(grep -A2 '^ *Step' "log.$v" | tail -1 | xargs)"
  done
done
