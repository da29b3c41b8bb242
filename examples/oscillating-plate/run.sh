#!/usr/bin/env bash
# run the oscillating plate (1 period by default; PERIODS=3 for the test length) and
# print its period against beam theory.  Run from an output folder: files land there.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
$LMP -in "$here/in.plate" -var periods "${PERIODS:-1}" -log log.plate "$@" | grep -E "^ +[0-9]+ " | tail -3
python3 "$here/period.py"
