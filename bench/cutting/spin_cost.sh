#!/usr/bin/env bash
# What the rotating tool's contact path costs (fix contact/tri-penalty spin, issue 55): the 2D cut of
# examples/cutting-2d-ti6al4v, adiabatic (-var thermal 0: spin cannot take tool particles), once with
# the translating insert and once with "spin 0 0 1 0 0 0 0.0" added, a rotation at rate 0: the same
# motion through the rotating path (the query in the tool frame, the normal, contact point and surface
# velocity turned back, the torque).  NYS (default "11 21") across, STEPS (6000) steps, REPS (3)
# rounds in turn; KK="-k on t 1 -sf kk" times the /kk contact kernel on a host thread.  Prints the
# contact fix's seconds from the per-style timing table, its ratio, and the largest relative
# difference of Fc, Ft over forces.dat.  Run from an output folder (source build/env.sh first).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
: "${LMP:?source build/env.sh first}"
ex="$here/../../examples/cutting-2d-ti6al4v/in.cutting"
sed 's|velocity -${v} 0 0 E 620e9|velocity -${v} 0 0 ${spinkw} E 620e9|' "$ex" > in.spin
grep -q 'spinkw' in.spin || { echo "spin_cost: the example's fix line changed; adapt the sed"; exit 1; }
for ny in ${NYS:-11 21}; do
  for r in $(seq "${REPS:-3}"); do
    for v in translate spin; do
      k=""; [ $v = spin ] && k="spin 0 0 1 0 0 0 0.0"
      d=ny$ny-$v-$r; mkdir -p $d
      # shellcheck disable=SC2086
      (cd $d && $LMP ${KK:-} -in ../in.spin -var ny "$ny" -var thermal 0 -var steps "${STEPS:-6000}" -var xstart 0.3 \
         -var dumpevery 0 -var spinkw "$k" -log log > screen 2>&1) || { tail -5 $d/screen; exit 1; }
    done
  done
  python3 - "$ny" "${REPS:-3}" <<'EOP'
import sys
ny, reps = sys.argv[1], int(sys.argv[2])
def t(d):
    for l in open(d + '/log'):
        if l.strip().startswith('fix contact/tri-penalty'):
            return float(l.split()[-4])
def rows(d):
    return [list(map(float, l.split())) for l in open(d + '/forces.dat') if l.strip() and not l.startswith('#')]
tt = [t(f'ny{ny}-translate-{r}') for r in range(1, reps + 1)]
ts = [t(f'ny{ny}-spin-{r}') for r in range(1, reps + 1)]
a, b = rows(f'ny{ny}-translate-1'), rows(f'ny{ny}-spin-1')
m = max(abs(x[c] - y[c]) / max(abs(x[c]), 1e-30) for x, y in zip(a, b) for c in (3, 4) if x[c] != 0.0)
print(f"{ny} across: contact fix {' '.join('%.3f' % x for x in tt)} s translating, "
      f"{' '.join('%.3f' % x for x in ts)} s spinning at rate 0: ratio {sum(ts) / sum(tt):.3f}; "
      f"Fc, Ft over {len(a)} lines: largest relative difference {m:.1e}")
EOP
done
