#!/usr/bin/env bash
# Quick version of the 2D Ti6Al4V cut (make example): NY particles across the height
# (default 11), CUT cut length in m (default 0.3e-3), NP MPI ranks (default: all cores), HDX
# h/dx (default auto: the input's 1.3 below 41 across, 1.5 from 41 across; with 1.3 the
# 41-across cut ran away after 0.25-0.56 mm, see README.md), LENGTH the workpiece's length in m
# (default the paper's 3e-3; 0: sized to the cut, README.md).  The full case of the paper: NY=41
# CUT=2e-3.  Run from an output folder.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
NY="${NY:-11}"; CUT="${CUT:-0.3e-3}"; NP="${NP:-$(nproc)}"
HDX="${HDX:-0}"; LENGTH="${LENGTH:-3.0e-3}"
mpirun -np "$NP" $LMP -in "$here/in.cutting" -var ny "$NY" -var cut "$CUT" -var length "$LENGTH" -var hdx "$HDX" \
  -var dumpevery 1000 -var thermoevery 4000 \
  -log log.cutting | awk '/^ *Step/{h=1} h && /^ +[0-9]+ /{print} /Loop time|WARNING/{print}'
# Debian's python3 has numpy and matplotlib (tools/build-deps.sh installs them)
PY=python3; /usr/bin/python3 -c "import matplotlib" 2>/dev/null && PY=/usr/bin/python3
$PY "$here/steady.py"
$PY "$here/plot.py" && echo "plots: forces.png temperature.png"
