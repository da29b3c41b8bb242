#!/usr/bin/env bash
# The 3D friction stir welding example.  Run from an output folder.  DX particle spacing in m
# (default 0.5e-3: the coarse CPU setting; the input's own default, 0.25e-3, is meant for a GPU),
# SMALL=1 (default on the CPU) the thin-sheet tool (shoulder R 6 mm, pin R 2 mm x 2.7 mm, 4 mm sheet,
# plunge 0.4 m/s, 1 ms dwell, 1 mm traverse at 0.2 m/s: about 2.5 minutes on one core),
# SMALL=0 the full tool of the input's defaults, GPU=1 the /kk styles on one GPU, ARGS more -var
# settings (e.g. "-var rpm 1500 -var steps 1000").  gpu.sh: the full tool on one GPU, bounded in wall time.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
DX="${DX:-0.5e-3}"; GPU="${GPU:-0}"; ARGS="${ARGS:-}"
SMALL="${SMALL:-$([ "$GPU" = 1 ] && echo 0 || echo 1)}"
kk=""
[ "$GPU" = 1 ] && kk="-k on g 1 -sf kk -pk kokkos neigh full newton off"
small=""
[ "$SMALL" = 1 ] && small="-var Rs 6e-3 -var Rpin 2e-3 -var Rtip 2e-3 -var Lpin 2.7e-3 -var t 4e-3 -var vp 0.4 -var dwell 1e-3 -var vt 0.2 -var traverse 1e-3"
# shellcheck disable=SC2086
$LMP $kk -in "$here/in.fsw" -var exdir "$here" -var dx "$DX" -var dumpevery 500 $small $ARGS \
  -log log.fsw | awk '/^fsw:|^tool.py/{print} /^ *Step/{h=1} h && /^ +[0-9]+ /{print} /Loop time|WARNING|ERROR/{print}'
PY=python3; /usr/bin/python3 -c "import matplotlib" 2>/dev/null && PY=/usr/bin/python3
$PY "$here/plot.py" && $PY "$here/picture.py" --dx "$DX" && echo "plots: fsw.png picture.png"
