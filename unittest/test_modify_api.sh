#!/usr/bin/env bash
# sphcut test: no C++ source reads Modify's lists of fixes and computes directly (the arrays
# modify->fix[], compute[], fmask[] and their counts nfix, ncompute, or the index lookups
# find_fix(), find_compute(), find_*_by_style()).  4Jul2026 deprecates the lookups and the
# 13Nov2026 feature release removes the arrays; the sources go through the wrappers in
# src/sphcut_compat.h (sphcut::fix_list(), fix_by_id(), ...), the one file allowed to use them.
#
# Usage: test_modify_api.sh [SOURCE_DIR]   (default: the checkout this script is in)
# Exit status: 0 none found; 1 each one found is listed as file:line: text
set -uo pipefail
ROOT="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
cd "$ROOT" || exit 2

# the old API: the arrays (indexed or not), their counts, the lookups returning an index
pattern='modify->(fix|compute|fmask|nfix|ncompute)\b|\bfind_(fix|compute)(_by_style)?[[:space:]]*\('
dirs=(src KOKKOS tools unittest bench)
nfiles=$(find "${dirs[@]}" -type f \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' -o -name '*.cu' \) | wc -l)
[ "$nfiles" -gt 0 ] || { echo "test_modify_api: no C++ sources under $ROOT" >&2; exit 2; }
found=$(grep -rnE --include='*.cpp' --include='*.h' --include='*.hpp' --include='*.cu' "$pattern" "${dirs[@]}" \
          | grep -v '^src/sphcut_compat\.h:')
if [ -n "$found" ]; then
  echo "$found"
  echo "test_modify_api: FAILED: $(wc -l <<< "$found") lines with direct uses of Modify's fix/compute lists above;" \
       "use sphcut::fix_list(), fix_by_id(), fixes_by_style(), compute_list(), compute_by_id(), ... of src/sphcut_compat.h" >&2
  exit 1
fi
echo "test_modify_api: $nfiles C++ sources in ${dirs[*]}: no direct use of Modify's fix/compute lists outside src/sphcut_compat.h"
