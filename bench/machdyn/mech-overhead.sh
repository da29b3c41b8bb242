#!/usr/bin/env bash
# bench/machdyn: what a purely mechanical scene pays for the thermal and contact code (issue 14:
# "nothing, within 5 %").  Builds, in a temporary folder, a second plugin from the committed
# sources (git HEAD) with the lines of STRIP below removed or replaced: no temperature predictor,
# corrector, rate bookkeeping or plastic heating in the integration, no tool test when the pair
# packs its rows (CPU styles only).  Each edit names a whole source line and must match it at
# least once; the script stops naming the edit that no longer applies (then update STRIP to
# the current src/).  Then runs in.sphcut isothermal (chi 0: a purely mechanical scene, no
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
# the edits: (file, a source line as it reads without its indentation, its replacement or None: removed)
python3 - "$tmp" <<'PY'
import os, sys
STRIP = [
    ("src/sphcut_solid.h", "s[SL::TEMP_F] = s[SL::TEMP] + dt * s[SL::DTEMP_O];", None),
    ("src/sphcut_solid.h", "s[SL::DTEMP_O] = s[SL::DTEMP];", None),
    ("src/sphcut_solid.h", "s[SL::DTEMP] = 0.0;", None),
    ("src/sphcut_solid.h", "s[SL::TEMP] += hdt * (s[SL::DTEMP_O] + s[SL::DTEMP]);", None),
    ("src/sphcut_solid.h", "if (mt.cp > 0.0) s[SL::TEMP] += mt.chi * wp / mt.cp;", None),
    ("src/pair_sph_jc_thermal.cpp", "if (!(mask[i] & groupbit) || fix->role_of(mask[i]) == F::TOOL) {",
     "if (!(mask[i] & groupbit)) {"),
]
for path, old, new in STRIP:
    f = os.path.join(sys.argv[1], path)
    src = open(f).read().split("\n")
    hits = [k for k, l in enumerate(src) if l.strip() == old]
    if not hits:
        sys.exit(f"mech-overhead.sh: the line '{old}' is no longer in {path}: update STRIP")
    for k in reversed(hits):
        if new is None:
            del src[k]
        else:
            src[k] = src[k][:len(src[k]) - len(src[k].lstrip())] + new
    open(f, "w").write("\n".join(src))
PY
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
