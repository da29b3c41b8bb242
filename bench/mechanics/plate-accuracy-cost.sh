#!/usr/bin/env bash
# Run time against error for the SPH solid: the oscillating plate (examples/oscillating-plate)
# for one period at several resolutions; prints particles, steps, wall time, cost per
# particle-step and the period error against beam theory.
# Usage: source build/env.sh; bash bench/mechanics/plate-accuracy-cost.sh [ny ...]   (default 11 21; odd ny:
# the tip particle sits on the mid-plane)
set -euo pipefail
: "${LMP:?source build/env.sh first}"
here="$(cd "$(dirname "$0")" && pwd)"
ex="$here/../../examples/oscillating-plate"
work=$(mktemp -d)
cd "$work"
printf '%4s %8s %8s %9s %12s %10s\n' ny atoms steps wall_s us/atom-step period_err
for ny in "${@:-11 21}"; do
  for n in $ny; do
    $LMP -in "$ex/in.plate" -var ny "$n" -var periods 2 -log log.$n > /dev/null
    atoms=$(grep -m1 "Created .* atoms" log.$n | awk '{print $2}')
    read -r wall steps < <(grep "Loop time" log.$n | tail -1 | awk '{print $4, $9}')
    err=$(python3 "$ex/period.py" | awk '/SPH period/{gsub(/[()%]/,"",$5); print $5}')
    us=$(python3 -c "print(f'{1e6*$wall/($atoms*$steps):.3f}')")
    printf '%4s %8s %8s %9.1f %12s %9s%%\n' "$n" "$atoms" "$steps" "$wall" "$us" "$err"
  done
done
rm -rf "$work"
