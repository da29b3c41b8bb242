#!/usr/bin/env bash
# `make example`: run the first example that exists (the flagship cutting case once it is
# there), in a fresh output folder, and tell the user where the results are.
set -euo pipefail
BUILD="${1:-build}"
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
# shellcheck disable=SC1090,SC1091
source "$ROOT/$BUILD/env.sh"
for ex in cutting-2d-ti6al4v oscillating-plate; do
  dir="$ROOT/examples/$ex"
  [ -x "$dir/run.sh" ] || continue
  out="$ROOT/$BUILD/example-output/$ex"
  rm -rf "$out"
  mkdir -p "$out"
  echo "sphcut: running example $ex (output in $out)"
  (cd "$out" && bash "$dir/run.sh")
  echo "sphcut: example $ex finished; its files are in $out:"
  ls -1 "$out" | sed 's/^/  /'
  exit 0
done
echo "sphcut: no example found" >&2
exit 1
