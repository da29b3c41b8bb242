#!/usr/bin/env bash
# sphcut test: the /kk integrator owns only integration (doc/design.md, "The hooks of the /kk
# integrator").  Fix sph/jc-thermal/kk (KOKKOS/fix_sph_jc_thermal_kokkos.h/.cpp) runs the other
# /kk styles' per-particle work only as hooks (KOKKOS/sphcut_hooks_kokkos.h) and names no other
# style, none of their fields and none of their hook types; the /kk pair and the integrator do not
# include each other; the thermal dt limit's loop body is written once (sphcut::thermal_dt_min),
# and the heat fix's rules live in its own header (src/sphcut_heat_rules.h), not in sphcut_solid.h.
#
# Usage: test_integrator_seam.sh [SOURCE_DIR]   (default: the checkout this script is in)
# Exit status: 0 all hold; 1 each violation is listed
set -uo pipefail
ROOT="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
cd "$ROOT" || exit 2
fail=0
bad() { echo "test_integrator_seam: $*"; fail=1; }

INTEG=(KOKKOS/fix_sph_jc_thermal_kokkos.h KOKKOS/fix_sph_jc_thermal_kokkos.cpp)
for f in "${INTEG[@]}" KOKKOS/sphcut_hooks_kokkos.h KOKKOS/sphcut_heat_hooks_kokkos.h src/sphcut_heat_rules.h; do
  [ -f "$f" ] || { echo "test_integrator_seam: $f missing" >&2; exit 2; }
done

# 1. the integrator names no other style: no class, member, hook type or header of theirs
names='pairkk|PairSPHJCThermal|FixHeatFMFS|FixContactTriPenalty|ComputeSurfaceLambda|heat_rules|qdir|'
names+='ToolHeatGather|RowPacker|packer|HeatPredictHook|HeatCorrectorHook|tool_heat|dirichlet|Dirichlet|'
names+='hold_predicted|hold_corrected|add_held_rate|thermal_dt|heat_slot|\bgather\b|gather_|take_tool|HOOK_HEAT|HOOK_ROWS|'
names+='pair_sph_jc_thermal_kokkos\.h|fix_heat_fmfs|fix_contact_tri_penalty|sphcut_tool_heat_kokkos\.h|'
names+='sphcut_heat_hooks_kokkos\.h|sphcut_row_packer_kokkos\.h|sphcut_heat_rules\.h|sphcut_thermal\.h'
hits=$(grep -nE "$names" "${INTEG[@]}")
[ -z "$hits" ] || bad "the integrator names another style's class, field, hook or header:
$hits"

# 2. the pair and the integrator do not know each other
hits=$(grep -nE 'fix_sph_jc_thermal_kokkos\.h|FixSPHJCThermalKokkos' KOKKOS/pair_sph_jc_thermal_kokkos.h \
         KOKKOS/pair_sph_jc_thermal_kokkos.cpp KOKKOS/sphcut_row_packer_kokkos.h)
[ -z "$hits" ] || bad "the /kk pair names the integrator:
$hits"

# 3. the integrator calls the hooks at their points, and holds them as the hooks header's aggregates
for p in after_first_half before_corrector after_corrector arm_hooks FirstHalfHooks CorrectorHooks; do
  grep -q "$p" KOKKOS/fix_sph_jc_thermal_kokkos.cpp || bad "fix_sph_jc_thermal_kokkos.cpp does not use $p"
done

# 4. the thermal limit's loop body once: thermal_dt_limit is called only by sphcut::thermal_dt_min
#    (src/sphcut_thermal.h), which the CPU heat fix, its /kk reduction and its hook call
srcs=(--include='*.cpp' --include='*.h')
hits=$(grep -rnE "${srcs[@]}" 'thermal_dt_limit[[:space:]]*\(' src KOKKOS | grep -v '^src/sphcut_thermal\.h:')
[ -z "$hits" ] || bad "thermal_dt_limit called outside sphcut::thermal_dt_min:
$hits"
for f in src/fix_heat_fmfs.cpp KOKKOS/fix_heat_fmfs_kokkos.cpp KOKKOS/sphcut_heat_hooks_kokkos.h; do
  grep -q 'thermal_dt_min' "$f" || bad "$f does not take the thermal limit through sphcut::thermal_dt_min"
done

# 5. the heat fix's rules are in its own header, not in the integration of one particle
hits=$(grep -nE 'hold_predicted_temperature|hold_corrected_temperature|dirichlet_index|add_held_rate' src/sphcut_solid.h)
[ -z "$hits" ] || bad "heat rules in src/sphcut_solid.h:
$hits"

if [ $fail -ne 0 ]; then
  echo "test_integrator_seam: FAILED" >&2
  exit 1
fi
echo "test_integrator_seam: fix sph/jc-thermal/kk names no other style (hooks only), the /kk pair and it" \
     "do not include each other, the thermal limit's loop once, the heat rules in sphcut_heat_rules.h"
