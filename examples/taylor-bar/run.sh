#!/usr/bin/env bash
# Taylor bar impact; DX=particle spacing (default 0.4e-3 m, 31,104 particles), NP=MPI ranks.
# Run from an output folder: the log lands there.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
mpirun -np "${NP:-1}" $LMP -in "$here/in.taylor" -var dx "${DX:-0.4e-3}" -log log.taylor | grep -E "^TAYLOR"
