#!/usr/bin/env bash
# Taylor bar convergence on one GPU (examples/taylor-bar/in.taylor: copper, 227 m/s, 80 us; two
# mirrored bars = a rigid frictionless wall), on a machine with an NVIDIA GPU and CUDA.  Build the
# GPU plugin first (README, "GPU build": build-cuda/lmp_sphcut), then from the repository root:
#   bash bench/gpu/taylor.sh [MODE ...]
#   conv  (default) the bar at each spacing of TAYLOR_DX (default 0.4e-3 0.2e-3 0.141e-3 0.1e-3 m) with
#         the settings of TAYLOR_BEST, then at each of TAYLOR_DEFAULT_DX (default 0.4e-3 0.2e-3
#         0.141e-3) with the example's defaults; a line each: dx, particles, steps, loop time, final
#         length, mushroom radius (the example's measure: outermost particle + half a spacing, reads
#         L0 and R0 at t = 0), max plastic strain, energy error; then a Richardson extrapolation of
#         length and radius per settings (python3).  The whole mode keeps within TAYLOR_BUDGET seconds
#         (default 300): each run's timeout is the budget left (at most TAYLOR_TIMEOUT, 240 s), a run
#         that would start with less than 20 s left is skipped and said so.
#   t0    the t = 0 readings (run 0) at TAYLOR_T0_DX (default 0.8e-3 0.4e-3 0.2e-3 0.1e-3), rings and sc
#   wall  bar A alone against a rigid frictionless plate (fix contact/tri-penalty, mu 0, contact radius
#         dx/2: the first layer's distance) in place of the mirrored bar B, at each of TAYLOR_DX with the
#         settings of TAYLOR_BEST (bar B's far layer stays, 32 mm from the plate: the pair's hdx needs
#         atoms of each type to derive the spacing); the interface at the rim, mirror against wall
# TAYLOR_BEST: -var settings of the best case (issue 51 item 7; examples/taylor-bar/README.md, "What
# limits the accuracy"); TAYLOR_ARGS: more lmp arguments for every run.
# Results: $OUT/summary.txt, $OUT/taylor.csv, $OUT/taylor-logs.tar.gz.  Figures: examples/taylor-bar/README.md.
# To try it elsewhere (CPU, no build):  SPHCUT_LMP=$LMP SPHCUT_GPU_ARGS=" " TAYLOR_DX="0.8e-3" bash bench/gpu/taylor.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/bench/gpu/common.sh"
GPUK="$GPU -pk kokkos neigh full newton off"
[ "$GPU" = " " ] && GPUK=""      # the CPU styles (SPHCUT_GPU_ARGS=" "): no kokkos package options
EX="$ROOT/examples/taylor-bar/in.taylor"
W=/tmp/taylor-conv; mkdir -p $W
BEST="${TAYLOR_BEST:--var alpha 0.5 -var beta 0.5}"
CSV="$OUT/taylor.csv"
CSV_HEADER="settings,dx,particles,steps,loop_s,length_mm,radius_mm,rim_radius_mm,eps_max,energy_error,status"
T_START=$(date +%s)    # (set again at the start of conv: the build does not count)

# one run: label, dx, more lmp arguments; a line of the summary and of taylor.csv
one() {
  local label=$1 dx=$2; shift 2
  local left=$(( ${TAYLOR_BUDGET:-300} - ($(date +%s) - T_START) ))
  local tmo=$(( left < ${TAYLOR_TIMEOUT:-240} ? left : ${TAYLOR_TIMEOUT:-240} ))
  if [ "$tmo" -lt 20 ]; then say "$label dx $dx: skipped (budget: ${left} s left)"; return 0; fi
  local log="$W/log.$label-$dx" t0; t0=$(date +%s)
  timeout "$tmo" "$BIN" $GPUK -in "$EX" -var dx "$dx" "$@" ${TAYLOR_ARGS:-} -log "$log" > "$log.screen" 2>&1
  local rc=$? wall=$(( $(date +%s) - t0 ))
  local line; line=$(grep "^TAYLOR final" "$log" 2>/dev/null | tail -1)
  if [ -z "$line" ]; then
    local why; why=$(grep -m1 -E "ERROR|Exception" "$log.screen" | cut -c1-200)
    [ "$rc" = 124 ] && why="timed out after $tmo s; $(grep -E '^ +[0-9]+ ' "$log" | tail -1 | awk '{print "last thermo: step", $1, "t", $2}')"
    say "$label dx $dx: FAILED (rc $rc, ${wall} s): $why"
    echo "$label,$dx,,,,,,,,,FAILED" >> "$CSV"
    return 0
  fi
  # the timed run is the one with the most steps
  local loop; loop=$(grep "^Loop time" "$log" | sort -k9,9n | tail -1 | awk '{print $4}')
  echo "$line" | awk -v l="$label" -v dx="$dx" -v loop="$loop" -v wall="$wall" -v csv="$CSV" '{
    for (i = 1; i <= NF; i++) {
      if ($i == "length") L = $(i+1); if ($i == "mushroom") R = $(i+2); if ($i == "rim") Rr = $(i+2); if ($i == "strain") e = $(i+1)
      if ($i == "error") ee = $(i+1); if ($i == "particles") n = $(i+1); if ($i == "steps") s = $(i+1)
      if ($i == "work") wp = $(i+1)
    }
    gsub(",", "", e); gsub(",", "", ee); gsub(",", "", n); gsub(",", "", s)
    printf "%-8s dx %-8s %9d particles %6d steps  loop %7.1f s (wall %d s)  length %.3f mm  radius %.3f mm  rim radius %.3f mm  eps_max %.2f  energy error %.1e  plastic work %.3f of E0\n", l, dx, n, s, loop, wall, L, R, Rr, e, ee, wp
    printf "%s,%s,%d,%d,%.2f,%.4f,%.4f,%.4f,%.3f,%.3e,ok\n", l, dx, n, s, loop, L, R, Rr, e, ee >> csv
  }' | tee -a "$SUM"
  grep -h "Dangerous builds" "$log" | tail -1 | sed "s/^/    /" >> "$SUM"
}

conv() {
  T_START=$(date +%s)
  echo "$CSV_HEADER" > "$CSV"
  say "best settings: $BEST ${TAYLOR_ARGS:-}"
  local dx
  for dx in ${TAYLOR_DX:-0.4e-3 0.2e-3 0.141e-3 0.1e-3}; do one best "$dx" $BEST; done
  for dx in ${TAYLOR_DEFAULT_DX:-0.4e-3 0.2e-3 0.141e-3}; do one default "$dx"; done
  richardson
}

# Richardson extrapolation per settings: f(h) = f0 + C h^p through the three finest spacings
# (p from them, searched in 0.3-4), and f0 with p = 1 from the two finest; h is the particle spacing
# (volume a particle)^(1/3) = (2 pi R0^2 L0 / particles)^(1/3) (rings: (pi/3 dr^2 dz)^(1/3), about
# 1.015 dx), not the nominal dx (0.141e-3 gives dr 0.1391, dz 0.1409 mm)
richardson() {
  python3 - "$CSV" <<'EOF' | tee -a "$SUM"
import csv, math, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "ok"]
ref = {"length_mm": (21.42, 21.48), "radius_mm": (7.11, 7.22), "rim_radius_mm": (7.11, 7.22)}   # issue 51's bands
for s in dict.fromkeys(r["settings"] for r in rows):
    sp = lambda r: (2 * math.pi * 3.2**2 * 32.4 / int(r["particles"])) ** (1 / 3)   # mm
    pts = sorted(((sp(r), r) for r in rows if r["settings"] == s), key=lambda t: t[0])
    for q in ("length_mm", "radius_mm", "rim_radius_mm"):
        h = [p[0] for p in pts]; f = [float(p[1][q]) for p in pts]
        lo, hi = ref[q]
        line = f"richardson {s:8s} {q[:-3]:10s}: " + ", ".join(f"{fi:.3f} (h {hi_:.4f} mm)" for fi, hi_ in zip(f, h))
        if len(h) >= 2:
            e1 = f[0] + (f[0] - f[1]) * h[0] / (h[1] - h[0])
            line += f"; p=1 from the finest two: {e1:.3f}"
        if len(h) >= 3:
            (h1, h2, h3), (f1, f2, f3) = h[:3], f[:3]
            g = lambda p: (f2 - f1) / (h2**p - h1**p) - (f3 - f2) / (h3**p - h2**p)
            a, b = 0.3, 4.0
            if g(a) * g(b) < 0:
                for _ in range(100):
                    m = 0.5 * (a + b)
                    if g(a) * g(m) <= 0: b = m
                    else: a = m
                p = 0.5 * (a + b); C = (f2 - f1) / (h2**p - h1**p); f0 = f1 - C * h1**p
                line += f"; the finest three: order {p:.2f}, limit {f0:.3f}"
            else:
                line += "; the finest three: no order in 0.3-4 (not monotonic or not in the asymptotic range)"
        line += f" (reference {lo}-{hi})"
        print(line)
EOF
}

wall() {
  T_START=$(date +%s)
  [ -f "$CSV" ] || echo "$CSV_HEADER" > "$CSV"
  # the plate: x, y in +-20 mm, z from -5 mm to 0, outward normals
  python3 - "$W/plate.stl" "$ROOT/tools" <<'EOP'
import sys
sys.path.insert(0, sys.argv[2])
from stl_ascii import facet
L, zb = 20e-3, -5e-3
v = [(x, y, z) for z in (zb, 0.0) for y in (-L, L) for x in (-L, L)]
with open(sys.argv[1], "w") as out:
    out.write("solid plate\n")
    for a, b, c in ((0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4), (2, 6, 3), (3, 6, 7),
                    (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)):
        facet(out, v[a], v[b], v[c])
    out.write("endsolid plate\n")
EOP
  sed -e "s|^fix          sph all sph/jc-thermal cfl \${cfl}|variable     farB atom \"z > -v_L + v_dz\"\ngroup        Bz variable farB\ngroup        Bdel intersect Bz B\ndelete_atoms group Bdel\n&\nfix          wall all contact/tri-penalty stl $W/plate.stl mu 0 sfac \${hdx}|" \
    "$EX" > "$W/in.wall"
  grep -q "contact/tri-penalty" "$W/in.wall" || { say "wall: the input's fix sph line was not found"; return 1; }
  local EX="$W/in.wall" dx
  for dx in ${TAYLOR_DX:-0.4e-3 0.2e-3 0.141e-3 0.1e-3}; do one wall "$dx" $BEST; done
}

t0() {
  local dx lat
  for lat in rings sc; do
    for dx in ${TAYLOR_T0_DX:-0.8e-3 0.4e-3 0.2e-3 0.1e-3}; do
      "$BIN" -in "$EX" -var dx "$dx" -var lattice $lat -var tend 0 -log "$W/log.t0-$lat-$dx" > /dev/null 2>&1
      say "$(grep -h '^TAYLOR t=0' "$W/log.t0-$lat-$dx")"
    done
  done
}

[ $# -eq 0 ] && set -- conv
run_modes "$@"
tar czf "$OUT/taylor-logs.tar.gz" -C /tmp taylor-conv 2>/dev/null || true
