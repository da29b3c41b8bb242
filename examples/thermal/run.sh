#!/usr/bin/env bash
# Laplacian of x^2 + y^2 on 21 x 21 particles (exact 4): FMFS, Brookshaw, and FMFS with
# Brookshaw on the surface layer.  Run from an output folder: the logs land there.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
for args in "fmfs no" "brookshaw no" "fmfs yes"; do
  set -- $args
  $LMP -in "$here/in.laplacian" -var scheme "$1" -var surface "$2" -log "log.laplacian-$1-$2" | grep -E "^LAPLACIAN"
done
