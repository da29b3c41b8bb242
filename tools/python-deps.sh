#!/usr/bin/env bash
# sphcut - the Python modules the viewer tests need (PyPI, pinned): ovito (the OVITO
# Python module: reads the LAMMPS dumps as OVITO does) and meshio (reads the tool's VTK
# file as ParaView does), in a virtual environment of Debian's python3 under the
# dependency cache, keyed by the versions; reused when complete.  Also ParaView's own Python
# (pvpython, Debian's python3-paraview 5.11, about 70 MB to download, 700 MB installed) for
# test_paraview, from Debian: it is not on PyPI.
# Usage: tools/python-deps.sh [--print-python] [--no-apt]
#   prints the path of the environment's python on the last line of its output
#   --no-apt: do not install python3-paraview (test_paraview then fails, saying so)
set -euo pipefail
CACHE="${SPHCUT_CACHE:-$HOME/.cache/sphcut}"
PY=/usr/bin/python3
PKGS="ovito==3.17.2 meshio==5.3.5 numpy==2.4.6"
pyver="$($PY -c 'import sys; print("%d.%d" % sys.version_info[:2])')"
key="$(echo "$PKGS" | tr ' =' '_-' | tr -s '_-')"
VENV="$CACHE/python-$pyver-$key"
if [ "${1:-}" = "--print-python" ]; then echo "$VENV/bin/python"; exit 0; fi
if [ "${1:-}" != "--no-apt" ] && ! command -v pvpython >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
  echo "python-deps.sh: installing python3-paraview (pvpython) from Debian"
  { $SUDO apt-get update -q && DEBIAN_FRONTEND=noninteractive \
      $SUDO apt-get install -y -q --no-install-recommends python3-paraview; } \
    || echo "python-deps.sh: WARNING: python3-paraview not installed: test_paraview will fail" >&2
fi
if [ ! -f "$VENV/.complete" ]; then
  rm -rf "$VENV"
  mkdir -p "$CACHE"
  $PY -m venv "$VENV"
  "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check $PKGS
  "$VENV/bin/python" -c "import ovito, meshio; print('ovito', ovito.version_string, 'meshio', meshio.__version__)"
  touch "$VENV/.complete"
fi
echo "$VENV/bin/python"
