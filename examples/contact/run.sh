#!/usr/bin/env bash
# run the contact examples: the sliding block (mu 0.3 and 0) and the impacting cube
# (dfac 0, 0.3, 1) and print the measured numbers.  Run from an output folder: log files
# and plate2d.vtk (the 2D tool section) land there.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
for mu in 0.3 0.0; do
  $LMP -in "$here/in.sliding" -var dir "$here" -var mu $mu -log log.sliding_mu$mu -screen none
  grep -E "^(frictionless|sliding):" log.sliding_mu$mu
done
for dfac in 0.0 0.3 1.0; do
  $LMP -in "$here/in.impact" -var dir "$here" -var dfac $dfac -log log.impact_dfac$dfac -screen none
  grep -E "^impact:" log.impact_dfac$dfac
done
