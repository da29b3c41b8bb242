#!/usr/bin/env bash
# Cutting on the GPU: all sphcut styles under /kk (pair, fix sph/jc-thermal, fix heat/fmfs,
# compute surface/lambda, fix contact/tri-penalty) on a machine with an NVIDIA GPU and CUDA (the
# figures: one H100).  Build the GPU plugin first (README, "GPU build": build-cuda/lmp_sphcut), then
# from the repository root:  bash bench/gpu/cutting.sh MODE [MODE ...]
#   check    CPU (1 rank, CPU styles) vs GPU per-atom state after 1000 steps in contact: the 2D
#            quick cut (11 across) and the 3D cut with free sides (6 across, 3 layers); <= 1e-8; the
#            same with the pair's hourglass 0.1; CHECK_VARS more -var settings (e.g. "-var precision
#            mixed"), CHECK_TOL the tolerance (default 1e-8)
#   sums     the corrector joined to the next first half on the GPU: check's cases under /kk with it
#            on staged rows (SPHCUT_STAGE_ROWS=1) and the default (in place), against the CPU styles:
#            per-atom state and the energy sums formed on the device (plastic work, Dirichlet heat, ...)
#   concurrent  several 2D cuts at once on the one GPU (a parameter study): CONC_N (default "1 4 8
#            16") copies of the cut at CONC_NY (41) across, CONC_STEPS (20000) steps in contact each,
#            started together under MPS (where nvidia-cuda-mps-control starts; CONC_MPS=0: without),
#            then CONC_NOMPS counts (default 8) without MPS: each run's us/step, the wall time of
#            the batch and the particle-steps/s of all runs together against one run alone
#   ncu2d    Nsight Compute on the 2D cut at PROF_NY (41) across in contact: one launch (after
#            NCU_SKIP, 200, of its kind) of each kernel of NCU_KERNELS (;-separated regular
#            expressions of the demangled kernel name; default the contact kernel, the joined
#            corrector and first half, the pair's team pass): duration, registers, occupancy, the
#            warps' stall reasons (sampled) and the SASS instructions with the most stall samples
#            (NCU_PRINT_SOURCE=cuda: the source lines, with a plugin built with SPHCUT_CXX_FLAGS=-lineinfo)
#   rate2d   the 2D cut at NY (default 41) across for STEPS steps in contact: wall time per step
#   cut2d    the 2D cut at NY across over CUT (default 2e-3 m) of cut: wall time, steady forces; in
#            segments with CUT_END (restart files in $OUT, continued by the next run)
#   lowspeed the low-speed case (seed 003 sec. 5.2.2: vc 20 m/min, 0.3 mm of cut) at NY across with
#            cut2d's segments and CUT_ARGS: the mean rake-face temperature (measured about 680 K)
#   watch    the 2D cut at NY across until a particle runs away: the state, its history, GPU vs CPU
#   scale    MPI scaling of the CPU styles, 2D cut at 41 and 81 across, 1-16 ranks
#   slab     2D vs 3D periodic slab (plane strain) at NYS (default 11) across over CUTS (0.3e-3 m):
#            steady forces per mm of width
#   bench3d  the 3D cut (periodic slab, all physics) at about 1 M and 4 M particles: particle-steps/s;
#            BENCH_NZ layers (58 232), BENCH_STEPS (200), BENCH_ARGS more -var settings
#   chip3d   the 3D cut with free sides at NYC across, NZC layers, over CUTC of cut (or CHIP_WALL
#            seconds), tool start XSTARTC; the last frame (chip3d.dump.gz) for tools/render_chip.py; in
#            segments with CHIP_END (the epoch second the segment must end by): restart.cutting in
#            $OUT/chip3d-NYC-NZC/ (about 600 bytes a particle), continued by the next run from there
#            (or from /tmp/cut; see chip3d() below)
#   peer     the peer code (ETH IWF's 2D GPU cutting code; where its binary goes: peer() below) and sphcut on the seed-003
#            case at PEER_NY (41) across over 0.907 mm, one after the other: time, us/step, forces
#   timeline the 2D cut at PROF_NY (41) across, PROF_STEPS (3000) steps in contact under Nsight Systems
#            (when nsys is on the machine): kernel time per step against the wall time per step, the
#            CUDA API calls per step (synchronisations, copies); without nsys the kernel counts only
#   dtstudy  the seed-003 case at DT_NY (21) across over DT_CUT (0.907e-3 m) for each "cfl dtfac" pair
#            of DT_SETS (;-separated), DT_JOBS (4) runs at once on the GPU (under MPS where it starts):
#            steps, wall, Fc/Ft (+- standard error of 5 blocks) over 0.3 mm to the end, rake-face
#            temperature, energy balance (tool work against internal + kinetic energy and contact
#            dissipation); wall times of concurrent runs are not timings
#   launch   the fixed cost of a kernel launch (bench/gpu/launch/launch_overhead.cpp): host and device
#            time per empty launch, small and 3 KB functors, constant memory or kernel argument
#   stepcost the 2D cut in contact, PROF_STEPS steps at STEPCOST_NY (11, 21, 41 and 81) across: us/step
#            against the particle count (the fixed cost per step), LAMMPS' timer table and sphcut's per
#            style; STEPCOST_ARGS more lmp arguments (e.g. "-var dtevery 1"), STEPCOST_TAG a log suffix
#   ab       speed of this tree (A) against a baseline (B: a git archive of another commit, build_b of common.sh),
#            in turn AB_REPS times (default 2): the 2D cut in contact at AB_NY (41) across, PROF_STEPS
#            steps (us/step), and the 3D cut (bench3d's periodic slab) at AB_NZ (58 232) layers, 200
#            steps (particle-steps/s), AB_NY= or AB_NZ= (empty) leaving that part out; AB_KP=NZ:
#            then each variant's slab at NZ layers under kp_timer (kernel times)
#   envab    one binary under ENVAB_SETS environment settings or -var settings of the input (;-separated,
#            e.g. SPHCUT_LOAD_AHEAD=0, the switches of doc/performance.md "Environment switches", or
#            -var balance shift), in
#            turn: the 2D cut at ENVAB_NY across (us/step) and the 3D slab at ENVAB_NZ layers (ms/step)
#   outsteps what an output step costs: the 2D cut in contact at OUT_NY (41) across, PROF_STEPS (3000)
#            steps, a line of forces.dat every 10 steps (the example; its print line without Trake;
#            without Tmax and Trake; no fix print) and every 100, in turn OUT_REPS (2) times; with
#            OUT_NZ layers (e.g. 58) the 3D slab the same way
#   outab    what a line of forces.dat costs, this tree (A) against a baseline (B, as for ab),
#            each with its own example inputs, in turn OUT_REPS (2) times: the 3D slab (41 across,
#            OUT_NZ (58) layers, 200 steps) and the 2D cut at OUT_NY (41) across (2000 steps in
#            contact), a line every 10 and every 100 steps (thermo every 1000); A also every 1000
#   layout   the state row's layout against the integrator's access, without LAMMPS
#            (bench/gpu/layout/state_layout.cu): the first-half kernel's loads and stores over 4.24 M,
#            1.06 M and 18,272 rows stored as 504-byte rows (in place), by columns, in blocks of 32,
#            and as rows staged through shared memory by warps: ms a call
# Results: $OUT/summary.txt and logs.tar.gz.  Figures: bench/gpu/RESULTS.md, doc/validation.md.
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/bench/gpu/common.sh"
GPUK="$GPU -pk kokkos neigh full newton off"
# the neighbour-list check every NEIGHEVERY steps (default 10: a particle moves about 1e-3 spacings per
# step, the skin is 0.3 spacings; the logs report "Dangerous builds")
NEV="-var neighevery ${NEIGHEVERY:-10}"
EX2="$ROOT/examples/cutting-2d-ti6al4v/in.cutting"
EX3="$ROOT/examples/cutting-3d-ti6al4v/in.cutting"
W=/tmp/cut; mkdir -p $W

# final per-atom state of a run as a dump (sorted by id) for compare.py: the example, then
# a dump_sph written by run 0 (the setup recomputes rates only)
snapshot() {
  local ex=$1 out=$2; shift 2
  cat > $W/snap.in <<EOI
include $ex
${SNAP_PRINT:-}
dump_sph snap all \${printevery} $out id x y z vx vy vz density pressure vonmises plastic_strain temperature
dump_modify snap sort id
run 0
EOI
  lmp "$@" -in $W/snap.in -log $W/log.$(basename $out .dump) > $W/screen.$(basename $out .dump) 2>&1 \
    || { tail -5 $W/screen.$(basename $out .dump); return 1; }
  cp forces.dat forces.$(basename $out .dump)
  [ ! -f decomp.dat ] || mv decomp.dat decomp.$(basename $out .dump)
}

# the cases of check (and sums): the 2D quick cut and the 3D cut with free sides, 1000 steps in contact
CHECK2D="-var ny 11 -var xstart 0.6 -var steps 1000 -var thermoevery 100 -var dumpevery 0"
CHECK3D="-var ny 6 -var nz 3 -var sides free -var xstart 0.6 -var steps 1000 -var thermoevery 100"

check() {
  cd $W
  local v2="$CHECK2D -var decomp 7 ${CHECK_VARS:-}" v3="$CHECK3D ${CHECK_VARS:-}"
  local tol=${CHECK_TOL:-1e-8}
  [ -n "${CHECK_VARS:-}" ] && say "check with $CHECK_VARS, tolerance $tol"
  snapshot "$EX2" cpu2.dump $v2 && snapshot "$EX2" gpu2.dump $GPUK $v2 && \
    say "check 2D cut, CPU vs GPU after 1000 steps ($(grep -m1 -A0 'f_cut\[5\]' log.gpu2 >/dev/null; awk '/^ +1000 /{print "contact particles " $9}' log.gpu2)): $(python3 $ROOT/bench/gpu/compare.py cpu2.dump gpu2.dump $tol | tr '\n' ' ')"
  snapshot "$EX3" cpu3.dump $v3 && snapshot "$EX3" gpu3.dump $GPUK $v3 && \
    say "check 3D cut (free sides), CPU vs GPU after 1000 steps: $(python3 $ROOT/bench/gpu/compare.py cpu3.dump gpu3.dump $tol | tr '\n' ' ')"
  # the hourglass control under /kk (its second pass and the ghosts' L by forward communication)
  local hg='s|^pair_style   sph/jc-thermal kernel cubic|& hourglass 0.1|'
  sed "$hg" "$EX2" > $W/in.hg2 && sed "$hg" "$EX3" > $W/in.hg3
  snapshot $W/in.hg2 cpuhg2.dump $v2 && snapshot $W/in.hg2 gpuhg2.dump $GPUK $v2 && \
    say "check 2D cut with hourglass 0.1, CPU vs GPU after 1000 steps: $(python3 $ROOT/bench/gpu/compare.py cpuhg2.dump gpuhg2.dump $tol | tr '\n' ' ')"
  snapshot $W/in.hg3 cpuhg3.dump $v3 && snapshot $W/in.hg3 gpuhg3.dump $GPUK $v3 && \
    say "check 3D cut with hourglass 0.1, CPU vs GPU after 1000 steps: $(python3 $ROOT/bench/gpu/compare.py cpuhg3.dump gpuhg3.dump $tol | tr '\n' ' ')"
  say "  hourglass 0.1 vs none (2D GPU; must differ: the control acts): $(python3 $ROOT/bench/gpu/compare.py gpu2.dump gpuhg2.dump 1e-8 | grep -o 'max relative difference [^ ]*')"
  # the force decomposition by tool feature (vector 16-47, formed on the device from the contact
  # records when read): every 7th step of the 2D check, CPU vs GPU
  say "  decomposition every 7 steps, CPU vs GPU: $(python3 - decomp.cpu2 decomp.gpu2 <<'EOP'
import sys
a, b = ([[float(x) for x in l.split()] for l in open(f) if l.strip() and not l.startswith("#")] for f in sys.argv[1:])
assert len(a) == len(b) > 0, "different lines"
# each column's difference relative to that column's largest magnitude (as compare.py)
worst = 0.0
for k in range(len(a[0])):
    scale = max(abs(r[k]) for r in a)
    if scale > 0:
        worst = max(worst, max(abs(ra[k] - rb[k]) for ra, rb in zip(a, b)) / scale)
print(f"{len(a)} lines, max relative difference {worst:.2e}")
EOP
)"
  say "  forces.dat, last line, CPU: $(tail -1 forces.cpu2)"
  say "                          GPU: $(tail -1 forces.gpu2)"
  grep -B1 -A2 "^ *Step" log.cpu2 log.gpu2 | tail -6 >> "$SUM"
  cd "$ROOT"
}

# the joined corrector's sums on the GPU: check's 2D and 3D cases on the CPU styles and under /kk
# with the corrector in the next step's first-half kernel on staged rows (team sums, one join per
# team: what a GPU runs from 500,000 particles) and the default (in place, joined): each per-atom state against the CPU's (compare.py, CHECK_TOL), and
# the energy sums the corrector forms on the device (internal, kinetic, plastic work; the heat
# fix's convection, Dirichlet and thermal energy) against the CPU's, relative
sums() {
  cd $W
  local v2=$CHECK2D v3=$CHECK3D
  local tol=${CHECK_TOL:-1e-8} d ex v k set sets
  sets=("SPHCUT_STAGE_ROWS=1" "ENVAB_NONE=1")
  local SNAP_PRINT='print "SUMS $(f_sph[2]:%.17g) $(f_sph[3]:%.17g) $(f_sph[4]:%.17g) $(f_heat[1]:%.17g) $(f_heat[3]:%.17g) $(f_heat[5]:%.17g)"'
  export SNAP_PRINT
  for d in 2 3; do
    ex=$EX2 v=$v2; [ $d = 3 ] && { ex=$EX3; v=$v3; }
    snapshot "$ex" scpu$d.dump $v || continue
    for k in "${!sets[@]}"; do
      set=${sets[$k]}
      (export $set; snapshot "$ex" sgpu$d$k.dump $GPUK $v) || continue
      say "sums ${d}D [$set] against the CPU: $(python3 $ROOT/bench/gpu/compare.py scpu$d.dump sgpu$d$k.dump $tol | tail -1)"
      say "  sums (internal, kinetic, plastic work, convection, Dirichlet, thermal energy), relative: $(python3 - log.scpu$d log.sgpu$d$k $tol <<'EOP'
import sys
a, b = ([float(x) for x in next(l for l in open(f) if l.startswith("SUMS")).split()[1:]] for f in sys.argv[1:3])
d = [abs(y - x) / abs(x) if x else abs(y) for x, y in zip(a, b)]
print(" ".join(f"{v:.2e}" for v in d), "| CPU", " ".join(f"{x:.6g}" for x in a),
      "PASS" if max(d) <= float(sys.argv[3]) else "FAIL")
EOP
)"
    done
  done
  unset SNAP_PRINT
  cd "$ROOT"
}

# n copies of the 2D cut at once (concurrent): one batch, its summary line
conc_batch() {
  local n=$1 tag=$2 ny=${CONC_NY:-41} steps=${CONC_STEPS:-20000} k t0 t1
  mkdir -p $W/conc && cd $W/conc
  t0=$(date +%s.%N)
  for k in $(seq $n); do
    mkdir -p $tag$n-$k
    (cd $tag$n-$k && timeout 280 "$BIN" $GPUK $NEV -in "$EX2" -var ny $ny -var xstart 1 -var steps $steps \
      -var thermoevery 10000 -var printevery 100 -var dumpevery 0 -log log.c > screen.c 2>&1) &
  done
  wait
  t1=$(date +%s.%N)
  python3 - $n "$tag" $(awk -v a=$t1 -v b=$t0 'BEGIN{print a - b}') $tag$n-*/log.c >> "$SUM" <<'EOP'
import sys, re
n, tag, wall, logs = int(sys.argv[1]), sys.argv[2], float(sys.argv[3]), sys.argv[4:]
loops, rates, work = [], [], 0.0
for f in logs:
    t = open(f).read()
    m = re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms", t)
    if not m:
        continue
    loop, steps, atoms = float(m[-1][0]), int(m[-1][1]), int(m[-1][2])
    loops.append(loop)
    rates.append(1e6 * loop / steps)
    work += atoms * steps
if not loops:
    print(f"  concurrent {tag}{n}: no run finished"); sys.exit()
print(f"  concurrent {tag}{n}: {len(loops)} of {n} runs, us/step {min(rates):.1f}-{max(rates):.1f} (mean {sum(rates) / len(rates):.1f}),"
      f" batch wall {wall:.1f} s, all runs {work / max(loops):.3e} particle-steps/s over the longest loop,"
      f" {work / wall:.3e} over the batch's wall")
EOP
  cd "$ROOT"
}

concurrent() {
  local started=0 n
  if [ "${CONC_MPS:-1}" = 1 ] && command -v nvidia-cuda-mps-control > /dev/null; then
    nvidia-cuda-mps-control -d 2>/dev/null && started=1
  fi
  say "concurrent: the 2D cut at ${CONC_NY:-41} across, ${CONC_STEPS:-20000} steps each (MPS $started)"
  local tag=plain
  [ $started = 0 ] || tag=mps
  for n in ${CONC_N:-1 4 8 16}; do conc_batch $n $tag; done
  [ $started = 0 ] || { echo quit | nvidia-cuda-mps-control; sleep 2; }
  for n in ${CONC_NOMPS-8}; do conc_batch $n plain; done
}

ncu2d() {
  command -v ncu > /dev/null || { say "ncu2d: no ncu"; return 0; }
  cd $W
  local ks k n=0
  IFS=';' read -ra ks <<< "${NCU_KERNELS:-ContactWide;CorrectThenFirstHalf;neigh_pass_team}"
  for k in "${ks[@]}"; do
    n=$((n + 1))
    rm -f ncu$n.ncu-rep
    timeout ${NCU_TIMEOUT:-150} ncu --kernel-name-base demangled --kernel-name regex:"$k" --launch-skip ${NCU_SKIP:-200} \
      --launch-count 1 --set full -o ncu$n "$BIN" $GPUK $NEV -in "$EX2" -var ny ${PROF_NY:-41} -var xstart 1 \
      -var steps $(( ${NCU_SKIP:-200} + 60 )) -var thermoevery 1000 -var printevery 100 -var dumpevery 0 \
      -log log.ncu$n > screen.ncu$n 2>&1 || tail -3 screen.ncu$n >> "$SUM"
    [ -f ncu$n.ncu-rep ] || { say "ncu2d [$k]: no report"; continue; }
    say "ncu2d [$k] at ${PROF_NY:-41} across:"
    ncu -i ncu$n.ncu-rep --page details 2>/dev/null | grep -E "^  [a-zA-Z_].*\(|  Duration|Registers Per Thread|Block Size|Grid Size|Achieved Occupancy|Theoretical Occupancy|Warp Cycles Per Issued|Executed Ipc Active" \
      | head -12 | sed 's/^/  /' >> "$SUM"
    ncu -i ncu$n.ncu-rep --page raw --csv 2>/dev/null > raw$n.csv
    ncu -i ncu$n.ncu-rep --page source --csv --print-source ${NCU_PRINT_SOURCE:-sass} 2>/dev/null > src$n.csv
    python3 - raw$n.csv src$n.csv >> "$SUM" <<'EOP'
import csv, sys, re
# the stall reasons: the sampled warps per reason (smsp__pcsamp_warps_issue_stalled_*)
try:
    rows = list(csv.reader(open(sys.argv[1])))
    head, vals = rows[0], rows[-1]
    st = []
    for h, v in zip(head, vals):
        m = re.match(r"smsp__pcsamp_warps_issue_stalled_(\w+)$", h)
        if m and not m.group(1).endswith("not_issued"):
            try: st.append((float(v.replace(",", "")), m.group(1)))
            except ValueError: pass
    tot = sum(v for v, _ in st) or 1.0
    print("    stall samples: " + ", ".join(f"{n} {100 * v / tot:.0f} %" for v, n in sorted(st, reverse=True)[:8]))
except Exception as e:
    print("    stall reasons: not read (", e, ")")
# the instructions with the most samples
try:
    rows = list(csv.reader(open(sys.argv[2])))
    k = next(i for i, r in enumerate(rows) if any("Source" == c.strip() for c in r))
    head = [c.strip() for c in rows[k]]
    src = head.index("Source")
    smp = next(i for i, c in enumerate(head) if c.startswith("Warp Stall Sampling (All"))
    data = []
    for r in rows[k + 1:]:
        if len(r) > max(src, smp):
            try: data.append((float(r[smp].replace(",", "") or 0), r[src].strip()))
            except ValueError: pass
    tot = sum(v for v, _ in data) or 1.0
    ops = {}
    for v, t in data:
        op = t.split()[0] if t else "?"
        if op.startswith("@"): op = t.split()[1] if len(t.split()) > 1 else op
        op = op.split(".")[0]
        ops[op] = ops.get(op, 0.0) + v
    print(f"    {len(data)} SASS instructions; samples by opcode: " + ", ".join(f"{o} {100 * v / tot:.0f} %" for o, v in sorted(ops.items(), key=lambda x: -x[1])[:10]))
    for v, t in sorted(data, reverse=True)[:12]:
        print(f"      {100 * v / tot:5.1f} %  {t[:90]}")
except Exception as e:
    print("    source page: not read (", e, ")")
EOP
  done
  cp src*.csv raw*.csv "$OUT/" 2>/dev/null
  cd "$ROOT"
}

# wall time per step of the 2D cut in contact (the tool starts 1 spacing away)
rate2d() {
  local ny=${NY:-41} steps=${STEPS:-20000}
  cd $W
  timeout 580 "$BIN" $GPUK $NEV -in "$EX2" -var ny $ny -var xstart 1 -var steps $steps -var thermoevery 1000 \
    -var printevery 100 -var dumpevery 0 -log log.rate$ny > screen.rate$ny 2>&1 || { tail -5 screen.rate$ny; }
  local loop; loop=$(grep "^Loop time" log.rate$ny | tail -1)
  say "rate2d ny $ny: $loop"
  say "  $(step_rate log.rate$ny)"
  awk '/sphcut timing/{n++} n==2' log.rate$ny | sed -n '1,8p' | grep -v "^Loop" | sed 's/^/    /' >> "$SUM"
  cd "$ROOT"
}

# a run in segments (cut2d, chip3d): into $W/$1, continuing (cont=1) from the restart file a
# previous segment left there (a warm machine) or in .carry/$1/ (the files of $OUT/$1/ of the last
# call); the segment's number (seg: log.seg<seg>) and its wall time (wall, when $2, the epoch
# second the call must end by, is set: that less $3 seconds); returns 1 when no time is left
segment_start() {
  mkdir -p $W/$1 && cd $W/$1
  cont=0
  if [ -f restart.cutting ]; then cont=1
  elif [ -f "$ROOT/.carry/$1/restart.cutting" ]; then cp "$ROOT/.carry/$1/"* . && cont=1; fi
  [ -n "$2" ] && wall=$(( $2 - $(date +%s) - $3 ))
  seg=$(ls log.seg* 2>/dev/null | wc -l)
  [ "$wall" -ge 0 ]
}

# the loop time and steps of all segments so far (their logs log.seg*)
segment_total() {
  say "  loop time of all segments: $(cat log.seg* | awk '/^Loop time/{t+=$4;n+=$9} END{printf "%.1f s, %d steps", t, n}')"
}

# the segment's files for the next call: forces.dat, the logs and the restart file into $OUT/$1/
segment_save() {
  mkdir -p "$OUT/$1" && cp forces.dat log.seg* "$OUT/$1/" && { [ ! -f restart.cutting ] || cp restart.cutting "$OUT/$1/"; }
}

# the 2D cut at NY across over CUT of cut, in segments that fit the device tool's calls: with
# CUT_END (the epoch second the call must end by) the run stops in time and writes
# restart.cutting; the next call continues it (from /tmp/cut on a warm machine, else from
# .carry/cut2d-NY/, the files a previous call left in $OUT/cut2d-NY/); HDX: h/dx (default the
# example's auto: 1.5 from 41 across); CUT_ARGS: more -var settings (e.g. "-var dtfac 0.5"), CUT_TAG:
# a suffix of the run's folder (cut2d-NY<tag>) to keep such a run apart
cut2d() {
  local ny=${NY:-41} cut=${CUT:-2e-3} cont=0 wall=0 seg; local tag=cut2d-$ny${CUT_TAG:-}
  segment_start $tag "${CUT_END:-}" 40 || { say "cut2d ny $ny: no time left in this call"; cd "$ROOT"; return 0; }
  local t0; t0=$(date +%s)
  timeout ${CUT_TIMEOUT:-580} "$BIN" $GPUK $NEV -in "$EX2" -var ny $ny -var cut $cut -var thermoevery 10000 \
    -var printevery 100 -var dumpevery 0 -var continue $cont -var walltime $wall -var hdx ${HDX:-0} ${CUT_ARGS:-} \
    -log log.seg$seg > screen 2>&1 || tail -3 screen
  say "cut2d ny $ny cut $cut ${CUT_ARGS:-}, segment $seg (continue $cont, walltime $wall): $(( $(date +%s) - t0 )) s wall; $(grep '^Loop time' log.seg$seg | tail -1)"
  say "  $(tail -1 forces.dat)"
  segment_total
  python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" 2>&1 | head -3 | sed 's/^/  /' | tee -a "$SUM"
  segment_save $tag
  cd "$ROOT"
}

# the low-speed case (examples/cutting-2d-ti6al4v/run-lowspeed.sh) on the GPU: cut2d with vc 20
# m/min over 0.3 mm, in its own folder (cut2d-NY-low<tag>), then the mean rake-face temperature
lowspeed() {
  local ny=${NY:-21}
  CUT=0.3e-3 CUT_ARGS="-var vc 20 ${CUT_ARGS:-}" CUT_TAG="-low${CUT_TAG:-}" cut2d
  cd $W/cut2d-$ny-low${CUT_TAG:-}
  say "  lowspeed ny $ny: $(python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" --temperature 2>&1 | tail -1)"
  cd "$ROOT"
}

# a run that blows up: the 2D cut at NY across with a watchdog (stop when a particle is faster than
# VBAD m/s, checked every 100 steps; restart files every 2000 steps, two alternating), the state
# at the stop (final.dump), then from the older restart file the same steps again on the GPU with
# dumps every 100 steps and on one CPU core (CPU styles): is it the scheme or the port?  The bad
# particles' histories and their neighbours go to $OUT/watch.txt (bench/gpu/watch.py).
# WATCH_ARGS: more settings of the example (e.g. "-var hdx 1.3": the runaways of doc/validation.md;
# the example picks 1.5 from 41 across); WATCH_MODES: the reruns (default "gpu cpu").  A warm
# machine continues.
watch() {
  local ny=${NY:-41}; local d=$W/watch-$ny
  mkdir -p $d; cd $d
  local dumpcols="id type x y vx vy density pressure vonmises plastic_strain plastic_strain_rate temperature role fcontact_n fcontact_t contact_feature"
  sed -e "s|^run          \${nsteps}|variable vmag atom sqrt(vx*vx+vy*vy)\ncompute vmax all reduce max v_vmag\nvariable vbad equal c_vmax\nfix watch all halt 100 v_vbad > ${VBAD:-300} error continue\nrestart 2000 r.a r.b\n&\nunfix watch\ndump_sph snap all \${printevery} final.dump $dumpcols\ndump_modify snap sort id\nrun 0|" \
    "$EX2" > in.watch
  grep -q "fix watch" in.watch || { say "watch: the edit does not apply"; cd "$ROOT"; return 1; }
  local wall=$(( ${CUT_END:-$(( $(date +%s) + 400 ))} - $(date +%s) - 150 ))
  # a warm machine continues the run of the previous call (restart.cutting written at its walltime)
  local cont=0; [ -f restart.cutting ] && cont=1
  [ -f log.watch ] && cat log.watch >> log.watch.all
  timeout $(( wall + 60 )) "$BIN" $GPUK $NEV -in in.watch -var ny $ny -var thermoevery 10000 -var printevery 100 \
    -var dumpevery 0 -var continue $cont -var walltime $wall ${WATCH_ARGS:-} -log log.watch > screen 2>&1 || tail -3 screen
  say "watch ny $ny (continue $cont): $(grep '^Loop time' log.watch | head -1)"
  say "  $(grep -m1 'halt condition' log.watch)"
  say "  $(tail -1 forces.dat)"
  cp forces.dat "$OUT/watch-forces.dat"
  grep -q "halt condition" log.watch || { cd "$ROOT"; return 0; }
  local old; old=$(ls -tr r.a r.b 2>/dev/null | head -1)
  [ -n "$old" ] || { cd "$ROOT"; return 0; }
  local s0; s0=$(grep -m1 "halt condition" log.watch | grep -o "step [0-9]*" | awk '{print $2}')
  for mode in ${WATCH_MODES:-gpu cpu}; do
    mkdir -p $d/re-$mode && cp $old $d/re-$mode/restart.cutting && cd $d/re-$mode
    # a restart written under -k on is read with -k on only (atom style atomic/kk); the CPU styles
    # then run with Kokkos' atoms and run_style verlet/kk (unittest/test_kokkos.cpp)
    local args="$GPUK $NEV" in=../in.watch
    if [ $mode = cpu ]; then
      args="${CPUK:--k on g 1 t 1} $NEV" in=../in.watch.cpu
      sed -e 's|^label        setup|&\nrun_style verlet/kk|' ../in.watch > $in
    fi
    timeout 150 "$BIN" $args -in $in -var ny $ny ${WATCH_ARGS:-} -var continue 1 -var steps 6000 -var thermoevery 1000 \
      -var printevery 100 -var dumpevery 100 -log log.re > screen 2>&1 || tail -3 screen
    say "  rerun on the $mode from $old: $(grep -m1 'halt condition' log.re || grep '^Loop time' log.re | head -1)"
    cd $d
  done
  python3 "$ROOT/bench/gpu/watch.py" final.dump re-gpu re-cpu ${VBAD:-300} > "$OUT/watch.txt" 2>&1
  # the restart file the reruns started from, to rerun it elsewhere (-var continue 1)
  gzip -c $old > "$OUT/watch-restart.gz"
  head -40 "$OUT/watch.txt" >> "$SUM"
  cd "$ROOT"
}

# MPI scaling of the CPU styles on the device machine's cores (issue 14): the 2D cut at each
# of SCALE_NY (default 41 81) across, the tool in contact from the start (xstart 1), SCALE_STEPS
# steps (default 400) on 1, 2, 4, 8, 16 ranks; parallel efficiency t1 / (N tN) of the loop time;
# SCALE_LB=rcb: the example's -var balance rcb instead of shift
scale() {
  mkdir -p $W/scale; cd $W/scale
  local ny np lb=${SCALE_LB:-shift}
  for ny in ${SCALE_NY:-41 81}; do
    local t1=""
    for np in 1 2 4 8 16; do
      local lg=log.$ny.$np.$lb
      timeout 200 mpirun -np $np "$BIN" -in "$EX2" -var ny $ny -var xstart 1 -var steps ${SCALE_STEPS:-400} -var balance $lb \
        -var thermoevery 100 -var printevery 100 -var dumpevery 0 ${SCALE_ARGS:-} -log $lg > screen.$ny.$np 2>&1 || tail -3 screen.$ny.$np
      local t; t=$(awk '/^Loop time/{t=$4} END{print t}' $lg)
      [ -z "$t1" ] && t1=$t
      say "scale ny $ny np $np balance $lb: $(grep '^Loop time' $lg | tail -1); efficiency $(awk -v a=$t1 -v b=$t -v n=$np 'BEGIN{printf "%.0f %%", 100*a/(n*b)}')"
      awk '/^Per MPI rank memory/{next} /Nlocal:/{print "    " $0}' $lg | tail -1 >> "$SUM"
    done
  done
  mkdir -p "$OUT/scale" && cp log.* "$OUT/scale/"
  cd "$ROOT"
}

slab() {
  local ny=${NYS:-11} cut=${CUTS:-0.3e-3}
  mkdir -p $W/slab2d $W/slab3d
  cd $W/slab2d && timeout 280 "$BIN" $GPUK $NEV -in "$EX2" -var ny $ny -var cut $cut -var thermoevery 10000 \
    -var printevery 100 -var dumpevery 0 -log log.cutting > screen 2>&1
  say "slab: 2D ny $ny: $(grep '^Loop time' log.cutting | tail -1)"
  python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" 2>&1 | head -2 | sed 's/^/  /' | tee -a "$SUM"
  cd $W/slab3d && timeout 280 "$BIN" $GPUK $NEV -in "$EX3" -var ny $ny -var nz ${NZS:-4} -var cut $cut -var thermoevery 10000 \
    -var printevery 100 -log log.cutting > screen 2>&1
  say "slab: 3D periodic ny $ny nz ${NZS:-4}: $(grep '^Loop time' log.cutting | tail -1)"
  python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" 2>&1 | head -2 | sed 's/^/  /' | tee -a "$SUM"
  cd "$ROOT"
}

# the 3D cut, periodic slab, all physics; nz layers set the size (ny 41: about 17.6 k per layer)
# one run of bench3d's periodic slab (41 across, all physics, BENCH_STEPS steps): label, layers,
# more lmp arguments; the binary $BIN (LAMMPS_PLUGIN_PATH from the environment); log.<label>
slab_run() {
  local label=$1 nz=$2; shift 2
  timeout 290 "$BIN" $GPUK $NEV -in "$EX3" -var ny 41 -var nz $nz -var xstart 1 -var steps ${BENCH_STEPS:-200} \
    -var thermoevery 100 -var printevery 100 "$@" -log log.$label > screen.$label 2>&1 || tail -3 screen.$label
}

# a 2D run's rate from its log: particles, steps, us a step, particle-steps/s
step_rate() {
  awk '/^Loop time/{t=$4;n=$9;a=$12} END{printf "%d particles, %d steps, %.1f us/step, %.3e particle-steps/s", a, n, 1e6*t/n, a*n/t}' "$1"
}

# a slab run's rate from its log: particles, steps, ms a step, particle-steps/s
slab_rate() {
  awk '/^Loop time/{t=$4;n=$9;a=$12} END{printf "%d particles, %d steps, %.2f ms/step, %.3e particle-steps/s", a, n, 1e3*t/n, a*n/t}' "$1"
}

# the CUDA toolkit's folder (the nvcc on PATH)
cuda_root() { dirname "$(dirname "$(command -v nvcc)")"; }

# bench/gpu/kp_timer.cpp as $W/libkp_timer.so (KOKKOS_PROFILE_LIBRARY)
kp_timer_lib() {
  local cuda; cuda=$(cuda_root)
  g++ -O2 -shared -fPIC -o $W/libkp_timer.so "$ROOT/bench/gpu/kp_timer.cpp" -I$cuda/include -L$cuda/lib64 -lcudart
}

bench3d() {
  cd $W
  for nz in ${BENCH_NZ:-58 232}; do
    slab_run b3d$nz $nz ${BENCH_ARGS:-}
    say "bench3d ny 41 nz $nz${BENCH_ARGS:+ ($BENCH_ARGS)}: $(grep '^Loop time' log.b3d$nz | tail -1)"
    say "  $(awk '/^Loop time/{t=$4;n=$9;a=$12} END{printf "%d particles, %.3e particle-steps/s", a, a*n/t}' log.b3d$nz)"
    awk '/sphcut timing/{n++} n==2' log.b3d$nz | sed -n '1,8p' | grep -v "^Loop" | sed 's/^/    /' >> "$SUM"
  done
  cd "$ROOT"
}

chip3d() {
  local ny=${NYC:-11} nz=${NZC:-20} cut=${CUTC:-0.3e-3} cont=0 wall=${CHIP_WALL:-0} seg
  local tag=chip3d-$ny-$nz${CHIP_TAG:-}
  # a cut longer than one call goes on from the restart file of the previous segment
  segment_start $tag "${CHIP_END:-}" 60 || { say "chip3d ny $ny nz $nz: no time left in this call"; cd "$ROOT"; return 0; }
  cat > chip.in <<EOI
include $EX3
dump_sph snap all \${printevery} chip.dump id type x y z temperature plastic_strain role
dump_modify snap sort id
run 0
EOI
  timeout ${CHIP_TIMEOUT:-590} "$BIN" $GPUK $NEV -in chip.in -var ny $ny -var nz $nz -var sides free -var cut $cut \
    -var xstart ${XSTARTC:-3} -var walltime $wall -var continue $cont -var thermoevery 5000 -var printevery 100 \
    ${CHIP_ARGS:-} -log log.seg$seg > screen 2>&1 || tail -3 screen
  say "chip3d ny $ny nz $nz (free sides), segment $seg (continue $cont, walltime $wall): $(grep '^Loop time' log.seg$seg | tail -2 | head -1)"
  say "  $(tail -1 forces.dat)"
  segment_total
  python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" 2>&1 | head -3 | sed 's/^/  /' | tee -a "$SUM"
  segment_save $tag
  # the region around the tool (x >= CHIP_CROP, m) for the picture
  [ -f chip.dump ] && CHIP_CROP=${CHIP_CROP:--1} python3 - "$OUT/chip3d.dump.gz" <<'EOP'
import gzip, os, sys
lines = open("chip.dump").read().splitlines()
k = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
ix = lines[k].split()[2:].index("x")
xmin = float(os.environ["CHIP_CROP"])
rows = [l for l in lines[k + 1:] if float(l.split()[ix]) >= xmin]
head = lines[:k + 1]
head[3] = str(len(rows))
with gzip.open(sys.argv[1], "wt") as f:
    f.write("\n".join(head + rows) + "\n")
EOP
  cd "$ROOT"
}

# one run of the 2D (or 3D) cut in contact: label, example, extra lmp arguments; says us/step
# the runs in contact start the tool 1 spacing right of the workpiece: closer (0.6 and 0.7, until
# 2026-11-26 the choice here) the start is impulsive at 41 across and with spall release ejects a
# particle at about 700 m/s that flies on (the lists rebuilt every 10 steps, each build dangerous;
# RESULTS.md "The half list"); from 1 and 3 none (CPU, 7000 steps)
prof_run() {
  local label=$1 ex=$2; shift 2
  timeout 280 "$BIN" ${PROF_GPUK:-$GPUK} -in "$ex" -var xstart 1 -var thermoevery 1000 -var printevery 100 -var dumpevery 0 \
    "$@" -log log.$label > screen.$label 2>&1 || tail -3 screen.$label
  say "  $label: $(step_rate log.$label)"
}

prof() {
  cd $W
  kp_timer_lib || { say "prof: kp_timer build failed"; cd "$ROOT"; return 1; }
  local steps=${PROF_STEPS:-3000}
  for ny in ${PROF_NY-21 41}; do
    say "prof 2D ny $ny ($steps steps in contact)"
    prof_run p2d$ny "$EX2" -var ny $ny -var steps $steps
    prof_run p2d${ny}n10 "$EX2" -var ny $ny -var steps $steps -var neighevery 10
    PROF_GPUK="$GPUK neigh/thread off" prof_run p2d${ny}n10nt "$EX2" -var ny $ny -var steps $steps -var neighevery 10
    KOKKOS_PROFILE_LIBRARY=$W/libkp_timer.so KP_TIMER_OUT=$W/kp.2d$ny.txt prof_run p2d${ny}kp "$EX2" -var ny $ny -var steps $steps -var neighevery 10
    head -32 $W/kp.2d$ny.txt | sed 's/^/    /' >> "$SUM"
  done
  [ "${PROF_3D:-1}" = 1 ] || { cd "$ROOT"; return 0; }
  local nz=${PROF_NZ:-58}
  say "prof 3D ny 41 nz $nz (${PROF_STEPS3:-300} steps)"
  prof_run p3d "$EX3" -var ny 41 -var nz $nz -var steps ${PROF_STEPS3:-300} $NEV
  PROF_GPUK="$GPUK neigh/thread on" prof_run p3dteam "$EX3" -var ny 41 -var nz $nz -var steps ${PROF_STEPS3:-300} $NEV
  KOKKOS_PROFILE_LIBRARY=$W/libkp_timer.so KP_TIMER_OUT=$W/kp.3d.txt prof_run p3dkp "$EX3" -var ny 41 -var nz $nz -var steps ${PROF_STEPS3:-300} $NEV
  head -24 $W/kp.3d.txt | sed 's/^/    /' >> "$SUM"
  cd "$ROOT"
}

# the peer (ETH IWF's 2D GPU cutting code, ../shared/peer/: its binary travels in .carry/peer/,
# copied there with  mkdir -p .carry/peer && cp ../shared/peer/ul_cut_gpu/bin/mfree_gpu .carry/peer/)
# and sphcut side by side on the seed-003 case at PEER_NY (default 41) across over the peer's cut
# (its tool travels 1 mm from 0.093 mm before the workpiece: 0.907 mm of cut), one after the other
# on the same GPU.  sphcut runs the README's GPU command with dumps off, once per setting in
# PEER_SETS (;-separated lists of -var settings; "default" is none; default: the defaults and half
# their time step, -var cfl 0.25); each line prints particles,
# steps, wall time, us/step, Fc/Ft over 0.3-0.907 mm of cut and the time against the peer's.
peer() {
  local ny=${PEER_NY:-41} bin="$ROOT/.carry/peer/mfree_gpu"
  [ -x "$bin" ] || { say "peer: no $bin (copy ../shared/peer/ul_cut_gpu/bin/mfree_gpu into .carry/peer/)"; return 1; }
  mkdir -p $W/peer$ny && cd $W/peer$ny
  # sphcut's kernels are built for sm_80: the driver compiles their PTX for the GPU at the first
  # run after a build (about 20 s, cached): a short run first, so that no timed run pays it
  mkdir -p warm && (cd warm && timeout 120 "$BIN" $GPUK -in "$EX2" -var ny 11 -var steps 20 -var dumpevery 0 \
    -log none > screen 2>&1) || say "peer: the warm-up run failed"
  local t0; t0=$(date +%s.%N)
  LD_LIBRARY_PATH=/usr/local/nvidia/lib64:${LD_LIBRARY_PATH:-} timeout 400 "$bin" -r 0 -c 7 -f 0.00028 \
    -v 0.000530833299 -n $ny -q 0.01 > screen 2>&1 || tail -3 screen
  local wall; wall=$(awk -v a="$(date +%s.%N)" -v b=$t0 'BEGIN{print a - b}')
  local gpu; gpu=$(awk '/^gpu time/{print $4}' screen)
  # 136 rows, row i at i/135 mm of tool travel = i/135 - 0.093 mm of cut; 1e6 N/mm per unit, Fc = +x, Ft = -y
  local f; f=$(awk '{c = NR - 1; cut = c / 135 - 0.093; if (cut >= 0.3) {n++; fc += $1; ft -= $2}}
    END{printf "Fc %.1f Ft %.1f N/mm over 0.3-0.907 mm (%d rows)", 1e6 * fc / n, 1e6 * ft / n, n}' results/force_*)
  local steps; steps=$(grep -o "of [0-9]*:" screen | tail -1 | tr -dc 0-9)
  say "peer ny $ny: wall $(printf %.1f $wall) s (its loop, dumps included: $gpu s), $steps steps, $(awk -v t=$gpu -v n=$steps 'BEGIN{printf "%.0f us/step", 1e6*t/n}'); $f"
  local sets="${PEER_SETS:-default;-var cfl 0.25}" set
  IFS=';' read -ra sets <<< "$sets"
  for set in "${sets[@]}"; do
    local args="$set" tag; [ "$set" = default ] && args=""
    tag=$(echo "${set:-default}" | tr -c 'a-zA-Z0-9.\n' '_')
    mkdir -p $W/peer$ny/s-$tag && cd $W/peer$ny/s-$tag
    t0=$(date +%s.%N)
    # the example's defaults (under /kk printevery 100 and neighevery 10: both auto) with the
    # peer's edge, seed 003's 2.8 um (the example's default is the measured 28.7 um since issue 51)
    timeout 580 "$BIN" $GPUK -in "$EX2" -var ny $ny -var cut 0.907e-3 -var thermoevery 10000 \
      -var dumpevery 0 -var rn 2.8e-6 $args -log log.cutting > screen 2>&1 || tail -3 screen
    local w; w=$(awk -v a="$(date +%s.%N)" -v b=$t0 'BEGIN{print a - b}')
    local ff; ff=$(awk '!/^#/ && $3 >= 0.3 {n++; fc += $4; ft += $5} END{printf "Fc %.1f Ft %.1f N/mm over 0.3-0.907 mm (%d rows)", fc / n, ft / n, n}' forces.dat)
    say "sphcut ny $ny [$set]: wall $(printf %.1f $w) s = $(awk -v a=$w -v b=$wall 'BEGIN{printf "%.2f", a / b}')x the peer's; $(awk '/^Loop time/{t=$4;n=$9;a=$12} END{printf "%d particles, %d steps, loop %.1f s, %.0f us/step", a, n, t, 1e6*t/n}' log.cutting); $ff"
    cp log.cutting "$OUT/peer-log.$tag" 2>/dev/null
  done
  cp $W/peer$ny/results/force_* "$OUT/peer-force.dat" 2>/dev/null
  cd "$ROOT"
}

timeline() {
  cd $W
  local ny=${PROF_NY:-41} steps=${PROF_STEPS:-3000}
  local nsys; nsys=$(command -v nsys || ls /usr/local/cuda/bin/nsys /opt/nvidia/nsight-systems/*/bin/nsys 2>/dev/null | head -1)
  prof_run tl$ny "$EX2" -var ny $ny -var steps $steps $NEV
  if [ -n "$nsys" ]; then
    "$nsys" profile -o $W/tl$ny --force-overwrite true --trace=cuda --sample=none --cpuctxsw=none \
      "$BIN" $GPUK -in "$EX2" -var xstart 1 -var thermoevery 1000 -var printevery 100 -var dumpevery 0 \
      -var ny $ny -var steps $steps $NEV -log log.tln > screen.tln 2>&1 || tail -5 screen.tln
    "$nsys" stats -q -r cuda_api_sum,cuda_gpu_kern_sum,cuda_gpu_mem_time_sum -f csv -o $W/tl$ny $W/tl$ny.nsys-rep \
      > /dev/null 2>&1 || say "timeline: nsys stats failed"
    for f in $W/tl${ny}_*.csv; do cp "$f" "$OUT/" 2>/dev/null; done
    say "timeline ny $ny: $(awk '/^Loop time/{printf "loop %.2f s, %d steps", $4, $9}' log.tln) under nsys"
    python3 - "$W/tl$ny" "$steps" <<'EOP' | tee -a "$SUM"
import csv, glob, sys
base, steps = sys.argv[1], float(sys.argv[2])
def rows(name):
    f = glob.glob(base + '_' + name + '*.csv')
    return list(csv.DictReader(open(f[0]))) if f else []
def col(r, *names):
    for n in names:
        for k in r:
            if k.strip().lower().startswith(n):
                return r[k]
    return '0'
k = rows('cuda_gpu_kern_sum')
tot = sum(float(col(r, 'total time')) for r in k)
print('  kernels: %.1f us of GPU time per step, %.1f launches per step' % (tot / 1e3 / steps, sum(float(col(r, 'instances')) for r in k) / steps))
for r in sorted(k, key=lambda r: -float(col(r, 'total time')))[:16]:
    print('    %7.2f us/step %6.2f calls/step  %s' % (float(col(r, 'total time')) / 1e3 / steps, float(col(r, 'instances')) / steps, col(r, 'name')[:110]))
for r in sorted(rows('cuda_api_sum'), key=lambda r: -float(col(r, 'total time')))[:12]:
    print('  api %7.2f us/step %6.2f calls/step  %s' % (float(col(r, 'total time')) / 1e3 / steps, float(col(r, 'num calls', 'calls')) / steps, col(r, 'name')))
for r in rows('cuda_gpu_mem_time_sum'):
    print('  mem %7.2f us/step %6.2f per step  %s' % (float(col(r, 'total time')) / 1e3 / steps, float(col(r, 'count', 'instances')) / steps, col(r, 'operation')))
EOP
  else
    # no profiler on the machine: the device's own clock through CUDA events (kp_timer events mode)
    kp_timer_lib
    KP_TIMER_SYNC=events KP_TIMER_SKIP=${KP_SKIP:-6000} KP_TIMER_CALLS=${KP_CALLS:-24000} KOKKOS_PROFILE_LIBRARY=$W/libkp_timer.so \
      KP_TIMER_OUT=$W/kpe$ny.txt prof_run tle$ny "$EX2" -var ny $ny -var steps $steps $NEV
    say "timeline: no nsys; the device's clock (CUDA events) over a window of calls:"
    head -40 $W/kpe$ny.txt | sed 's/^/    /' | tee -a "$SUM"
    cp $W/kpe$ny.txt "$OUT/" 2>/dev/null
  fi
  cd "$ROOT"
}

# one run of the dt study: ny, cfl, dtfac; writes one summary line
dt_one() {
  local ny=$1 cfl=$2 dtfac=$3 d=$W/dt/n$1-c$2-d$3
  mkdir -p $d && cd $d
  cat > in.dt <<EOI
include $EX2
print "EBAL \$(f_cut[13]) \$(f_sph[2]+f_sph[3]-v_e0) \$(f_cut[15]) \$(v_lcut)"
EOI
  local t0; t0=$(date +%s.%N)
  timeout ${DT_TIMEOUT:-560} "$BIN" $GPUK $NEV -in in.dt -var ny $ny -var cut ${DT_CUT:-0.907e-3} -var cfl $cfl -var dtfac $dtfac \
    -var thermoevery 10000 -var printevery 100 -var dumpevery 0 ${DT_ARGS:-} -log log.dt > screen 2>&1
  local rc=$? w; w=$(awk -v a="$(date +%s.%N)" -v b=$t0 'BEGIN{print a - b}')
  local f; f=$(python3 - forces.dat "$ROOT/examples/cutting-2d-ti6al4v" <<'EOP'
import sys
sys.path.insert(0, sys.argv[2])
from seed003 import block_error
rows = [l.split() for l in open(sys.argv[1]) if not l.startswith('#')]
rows = [[float(x) for x in r] for r in rows if float(r[2]) >= 0.3]
if len(rows) < 10:
    print('too short'); sys.exit()
def blocks(c):
    n = len(rows) // 5 * 5
    return sum(r[c] for r in rows[:n]) / n, block_error([r[c] for r in rows])
fc, ft, tr = blocks(3), blocks(4), blocks(6)
print('Fc %.1f +- %.1f Ft %.1f +- %.1f Trake %.0f to %.3f mm' % (fc[0], fc[1], ft[0], ft[1], tr[0], rows[-1][2]))
EOP
)
  local e; e=$(awk '/^EBAL/{w=$2; printf "energy: work %.4g J, (work - dE - dissipated)/work %.2e", w, (w - $3 - $4) / w}' log.dt)
  local err; err=$(grep -h -m1 -E "^(ERROR|WARNING: the run ended)" screen | head -1 | cut -c1-140)
  say "dt ny $ny cfl $cfl dtfac $dtfac: rc $rc, $(awk '/^Loop time/{t=$4; n=$9} END{printf "%d steps, loop %.1f s", n, t}' log.dt), wall $(printf %.0f $w) s; $f; $e ${err:+; $err}"
}

dtstudy() {
  mkdir -p $W/dt
  local started=0
  if command -v nvidia-cuda-mps-control > /dev/null; then
    nvidia-cuda-mps-control -d 2>/dev/null && started=1
  fi
  say "dtstudy ny ${DT_NY:-21}, ${DT_JOBS:-4} at once (MPS $started)"
  local sets="${DT_SETS:-0.3 0.5}" set n=0 ny
  IFS=';' read -ra sets <<< "$sets"
  for ny in ${DT_NY:-21}; do
    for set in "${sets[@]}"; do
      dt_one $ny $set &
      n=$((n + 1))
      if [ $((n % ${DT_JOBS:-4})) = 0 ]; then wait; fi
    done
  done
  wait
  [ $started = 0 ] || echo quit | nvidia-cuda-mps-control
  cd "$ROOT"
}

launch() {
  local prefix; prefix=$(bash "$ROOT/tools/build-deps.sh" --cuda --print-prefix)
  cmake -S "$ROOT/bench/gpu/launch" -B $W/launch -DKokkos_DIR=$prefix/lib/cmake/Kokkos \
    -DCMAKE_CXX_COMPILER=$prefix/bin/nvcc_wrapper > $W/launch.log 2>&1 && cmake --build $W/launch >> $W/launch.log 2>&1 \
    || { tail -20 $W/launch.log; say "launch: build failed"; return 1; }
  say "launch overhead (Kokkos $(grep -o 'KOKKOS_VERSION [0-9]*' $prefix/include/KokkosCore_config.h), one GPU):"
  $W/launch/launch_overhead 2>&1 | grep -v WARNING | sed 's/^/  /' | tee -a "$SUM"
}

stepcost() {
  cd $W
  local steps=${PROF_STEPS:-2000} ny
  for ny in ${STEPCOST_NY:-11 21 41 81}; do
    prof_run sc$ny${STEPCOST_TAG:-} "$EX2" -var ny $ny -var steps $steps $NEV ${STEPCOST_ARGS:-}
    sed -n '/^Section |/,/^Other/p' log.sc$ny${STEPCOST_TAG:-} | sed 's/^/    /' >> "$SUM"
    grep -A14 "sphcut timing" log.sc$ny${STEPCOST_TAG:-} | sed 's/^/    /' >> "$SUM"
  done
  cd "$ROOT"
}

# the speed of this tree against the baseline build (build_b), A and B in turn; each run is first
# warmed by 30 steps (the driver compiles a kernel's PTX at its first launch)
ab() {
  build_b || return 1
  cd $W
  local steps=${PROF_STEPS:-2000} ny nz r v bin pp
  # variant $1's binary and plugin folder into bin, pp
  ab_variant() { bin=$BIN pp=$ROOT/build-cuda; [ $1 = B ] && bin=$BIN_B pp=$ROOT/build-cuda-b; }
  for v in A B; do
    ab_variant $v
    LAMMPS_PLUGIN_PATH=$pp timeout 120 "$bin" $GPUK -in "$EX2" -var xstart 1 -var ny 11 -var steps 30 \
      -var dumpevery 0 -log none > /dev/null 2>&1
  done
  for r in $(seq ${AB_REPS:-2}); do
    for v in A B; do
      ab_variant $v
      for ny in ${AB_NY-41}; do
        BIN=$bin LAMMPS_PLUGIN_PATH=$pp prof_run ab$v${ny}r$r "$EX2" -var ny $ny -var steps $steps $NEV
      done
      for nz in ${AB_NZ-58 232}; do
        BIN=$bin LAMMPS_PLUGIN_PATH=$pp slab_run ab$v$nz$r $nz
        say "  ab$v 3D nz $nz r$r: $(slab_rate log.ab$v$nz$r)"
      done
    done
  done
  # AB_KP=NZ: each variant's 3D slab at NZ layers once more under kp_timer (synchronised kernel
  # times; the first lines of its table per variant)
  if [ -n "${AB_KP:-}" ]; then
    kp_timer_lib || { say "ab: kp_timer build failed"; cd "$ROOT"; return 1; }
    for v in A B; do
      ab_variant $v
      BIN=$bin LAMMPS_PLUGIN_PATH=$pp KOKKOS_PROFILE_LIBRARY=$W/libkp_timer.so KP_TIMER_OUT=$W/kp.ab$v.txt \
        slab_run abkp$v $AB_KP
      say "  ab$v 3D nz $AB_KP under kp_timer:"
      head -${AB_KP_LINES:-20} $W/kp.ab$v.txt | sed 's/^/    /' >> "$SUM"
    done
  fi
  cd "$ROOT"
}

# the same binary under different environment settings, in turn ENVAB_REPS (2) times: each ';'-separated
# set of ENVAB_SETS (default "SPHCUT_LOAD_AHEAD=0;ENVAB_NONE=1": the neighbour loops without their
# loads ahead against the default) on the 2D cut in contact at ENVAB_NY
# (41 81) across, PROF_STEPS steps (us/step), and on the 3D slab at ENVAB_NZ (232) layers (ms/step);
# ENVAB_NY= or ENVAB_NZ= (empty) leaves that part out
layout() {
  nvcc -O3 -arch=sm_90 -std=c++17 --extended-lambda -o $W/state_layout "$ROOT/bench/gpu/layout/state_layout.cu" \
    || { say "layout: nvcc failed"; return 0; }
  local n
  for n in 4239104 1059776 18272; do "$W/state_layout" $n $([ $n -lt 100000 ] && echo 200 || echo 20) | tee -a "$SUM"; done
}

envab() {
  cd $W
  local steps=${PROF_STEPS:-2000} sets r k set ny nz
  IFS=';' read -ra sets <<< "${ENVAB_SETS:-SPHCUT_LOAD_AHEAD=0;ENVAB_NONE=1}"
  for r in $(seq ${ENVAB_REPS:-2}); do
    for k in "${!sets[@]}"; do
      set=${sets[$k]}
      say "  envab r$r [$set]"
      # a set of -var settings goes to lmp, any other set into the environment
      local env=ENVAB_NONE=1 args=""
      if [[ $set == -* ]]; then args=$set; else env=$set; fi
      for ny in ${ENVAB_NY-41 81}; do
        (export $env; prof_run ev${k}n${ny}r$r "$EX2" -var ny $ny -var steps $steps $NEV $args)
      done
      for nz in ${ENVAB_NZ-232}; do
        (export $env; slab_run ev${k}z${nz}r$r $nz $args)
        say "    3D nz $nz: $(slab_rate log.ev${k}z${nz}r$r)"
      done
    done
  done
  cd "$ROOT"
}

# the example's input with its print line changed (as: as it is, notrake, nottmax, noprint)
print_variant() {
  case $3 in
    as) cp "$1" "$2" ;;
    notrake) sed 's| \${Tmax} \${Trake}"| ${Tmax}"|' "$1" > "$2" ;;
    nottmax) sed 's| \${Ft} \${Tmax} \${Trake}"| ${Ft}"|' "$1" > "$2" ;;
    noprint) sed -e 's|^fix          series all print.*&$|variable noprint string \&|' \
                 -e 's|^             screen no title "# step time cut_mm.*$|"x"|' "$1" > "$2" ;;
  esac
}

outab() {
  build_b || return 1
  cd $W
  local r v pe d bin pp ex in args
  for r in $(seq ${OUT_REPS:-2}); do
    for v in A B; do
      bin=$BIN pp=$ROOT/build-cuda ex=$ROOT/examples
      [ $v = B ] && { bin=$BIN_B; pp=$ROOT/build-cuda-b; ex=/tmp/sphcut-b/examples; }
      for d in 3D 2D; do
        for pe in 10 100 $([ $v = A ] && echo 1000); do
          in=$ex/cutting-2d-ti6al4v/in.cutting args="-var ny ${OUT_NY:-41} -var steps 2000"
          [ $d = 3D ] && { in=$ex/cutting-3d-ti6al4v/in.cutting; args="-var ny 41 -var nz ${OUT_NZ:-58} -var steps 200"; }
          LAMMPS_PLUGIN_PATH=$pp timeout 280 "$bin" $GPUK -in $in $args -var xstart 1 $NEV -var thermoevery 1000 \
            -var printevery $pe -var dumpevery 0 -log log.oab$v$d$pe$r > screen.oab$v$d$pe$r 2>&1 || tail -3 screen.oab$v$d$pe$r
          say "  outab $v $d, a line every $pe steps, r$r: $([ $d = 3D ] && slab_rate log.oab$v$d$pe$r || step_rate log.oab$v$d$pe$r)"
        done
      done
    done
  done
  cd "$ROOT"
}

outsteps() {
  cd $W
  local steps=${PROF_STEPS:-3000} ny=${OUT_NY:-41} r v
  for v in as notrake nottmax noprint; do
    print_variant "$EX2" $W/in2.$v $v
    [ -z "${OUT_NZ:-}" ] || print_variant "$EX3" $W/in3.$v $v
  done
  # one run: label, input, printevery, more lmp arguments
  one() {
    local label=$1 in=$2 pe=$3; shift 3
    timeout 280 "$BIN" $GPUK $NEV -in $in -var ny $ny -var xstart 1 -var steps $steps -var thermoevery 1000 \
      -var printevery $pe -var dumpevery 0 "$@" -log log.$label > screen.$label 2>&1 || tail -3 screen.$label
    say "  $label: $(step_rate log.$label)"
  }
  # the 3D slab of bench3d (41 across, OUT_NZ layers, 200 steps) from the input in
  one3() {
    local label=$1 in=$2 pe=$3
    timeout 290 "$BIN" $GPUK $NEV -in $in -var ny 41 -var nz $OUT_NZ -var xstart 1 -var steps ${BENCH_STEPS:-200} \
      -var thermoevery 100 -var printevery $pe -log log.$label > screen.$label 2>&1 || tail -3 screen.$label
    say "  $label: $(slab_rate log.$label)"
  }
  for r in $(seq ${OUT_REPS:-2}); do
    for v in as notrake nottmax noprint; do one os${v}p10r$r $W/in2.$v 10; done
    one osasp100r$r $W/in2.as 100
    if [ -n "${OUT_NZ:-}" ]; then
      for v in as noprint; do one3 os3${v}p10r$r $W/in3.$v 10; done
      one3 os3asp100r$r $W/in3.as 100
    fi
  done
  cd "$ROOT"
}

run_modes "$@"
[ -n "${NOLOGS:-}" ] || tar czf "$OUT/logs.tar.gz" --exclude='*.dump' -C /tmp cut 2>/dev/null || true
