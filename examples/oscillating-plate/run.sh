#!/usr/bin/env bash
# run the oscillating plate (1 period by default; -var periods 3 for the test length) and
# print its period against beam theory.  Run from an output folder: files land there.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
$LMP -in "$here/in.plate" -var periods "${PERIODS:-1}" -log log.plate "$@" | grep -E "beam theory|^ +[0-9]+ " | tail -4
python3 "$here/period.py"
