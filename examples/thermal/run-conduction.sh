#!/usr/bin/env bash
# Sine decay at n = 11, 21, 41 with FMFS (conservative default and per particle) and Brookshaw: errors and observed orders of
# convergence (log2 of the error ratio of successive resolutions, dt/dx^2 fixed).
# Further arguments go to LAMMPS.  Run from an output folder: the logs land there.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
for variant in fmfs:yes fmfs:no brookshaw:yes; do
  scheme=${variant%:*} cons=${variant#*:}
  echo "scheme $scheme, conservative $cons"
  for n in 11 21 41; do
    $LMP -in "$here/in.conduction" -var scheme $scheme -var conservative $cons -var n $n \
      -log "log.conduction-$scheme-$cons-$n" "$@" |
      grep -E "^CONDUCTION"
  done | awk '{print} {e = $16; r = $19; if (NR > 1) printf("  order %s -> %s: max error %.3f, rms error %.3f\n", n, $5, log(pe/e)/log(2), log(pr/r)/log(2)); pe = e; pr = r; n = $5}'
done
