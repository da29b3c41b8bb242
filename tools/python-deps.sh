#!/usr/bin/env bash
# sphcut - the Python modules the viewer tests need (PyPI, pinned): ovito (the OVITO
# Python module: reads the LAMMPS dumps as OVITO does) and meshio (reads the tool's VTK
# file as ParaView does), in a virtual environment of Debian's python3 under the
# dependency cache, keyed by the versions; reused when complete.
# Usage: tools/python-deps.sh [--print-python]
#   prints the path of the environment's python on the last line of its output
set -euo pipefail
CACHE="${SPHCUT_CACHE:-$HOME/.cache/sphcut}"
PY=/usr/bin/python3
PKGS="ovito==3.17.2 meshio==5.3.5 numpy==2.4.6"
pyver="$($PY -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
key="$(echo "$PKGS" | tr ' =' '_-' | tr -s '_-')"
VENV="$CACHE/python-$pyver-$key"
if [ "${1:-}" = "--print-python" ]; then echo "$VENV/bin/python"; exit 0; fi
if [ ! -f "$VENV/.complete" ]; then
  rm -rf "$VENV"
  mkdir -p "$CACHE"
  $PY -m venv "$VENV"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check $PKGS
  "$VENV/bin/python" -c "import ovito, meshio; print('ovito', ovito.version_string, 'meshio', meshio.__version__)"
  touch "$VENV/.complete"
fi
echo "$VENV/bin/python"
