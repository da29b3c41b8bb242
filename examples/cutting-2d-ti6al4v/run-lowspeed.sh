#!/usr/bin/env bash
# Low-speed case of seed 003 sec. 5.2.2: vc = 20 m/min, cut 0.3 mm, lower resolution; prints the
# mean rake-face temperature over the cut and at its end (measured about 680 K, the paper's SPH
# 744 K).  NY (default 11), NP, ARGS: more -var settings (doc/validation.md used
# ARGS="-var cfl 0.45 -var dtfac 0.5").
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
NY="${NY:-11}"; NP="${NP:-$(nproc)}"
mpirun -np "$NP" $LMP -in "$here/in.cutting" -var ny "$NY" -var cut 0.3e-3 -var vc 20 \
  -var dumpevery 0 -var thermoevery 20000 ${ARGS:-} -log log.lowspeed | awk '/Loop time|WARNING/{print}'
PY=python3; /usr/bin/python3 -c "import matplotlib" 2>/dev/null && PY=/usr/bin/python3
$PY "$here/steady.py" --temperature
