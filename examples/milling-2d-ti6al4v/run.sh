#!/usr/bin/env bash
# The 2D milling example.  Run from an output folder.  DX particle spacing in m (default 25e-6: the
# coarse CPU setting; the input's own default, 5e-6, is sized for a GPU), TURN degrees of tooth 0's
# rotation (default 64: one tooth's pass of the default up-milling, 0-60 degrees, from 2 degrees before
# the entry), GPU=1 runs the /kk styles on one GPU, ARGS more -var settings (e.g. "-var mode down").
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
DX="${DX:-25e-6}"; TURN="${TURN:-64}"; GPU="${GPU:-0}"; ARGS="${ARGS:-}"
kk=""
[ "$GPU" = 1 ] && kk="-k on g 1 -sf kk -pk kokkos neigh full newton off"
# shellcheck disable=SC2086
$LMP $kk -in "$here/in.milling" -var exdir "$here" -var dx "$DX" -var turn "$TURN" -var dumpevery 5000 $ARGS \
  -log log.milling | awk '/^milling:|^cutter.py/{print} /^ *Step/{h=1} h && /^ +[0-9]+ /{print} /Loop time|WARNING|ERROR/{print}'
# Debian's python3 has matplotlib (tools/build-deps.sh installs it)
PY=python3; /usr/bin/python3 -c "import matplotlib" 2>/dev/null && PY=/usr/bin/python3
# plot.py takes the process values the run used from milling.params
$PY "$here/plot.py"
$PY "$here/picture.py" && echo "plots: milling.png picture.png"
