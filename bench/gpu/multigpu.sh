#!/usr/bin/env bash
# Cutting on several GPUs (issue 26): LAMMPS MPI + Kokkos, one rank per GPU (mpirun -np N with
# -k on g N -sf kk), on a machine with several NVIDIA GPUs and CUDA (the figures: 2 and 4 H100 or
# H200).  Build the GPU plugin first (README, "GPU build": build-cuda/lmp_sphcut), then from the
# repository root:  bash bench/gpu/multigpu.sh MODE [MODE ...]
#   check2   2 GPUs vs 1 GPU: the 2D quick cut (11 across) and the 3D cut with free sides (6 across,
#            3 layers) for 1500 steps (tool in contact), then on 2 ranks the rank boundary put just
#            ahead of the tool's leading particle column (balance x) and 1000 steps more, so that tool
#            particles change rank; the final per-atom states compared by compare.py (1e-10; the
#            atoms of the two runs matched by their positions before the 1000 steps: create_atoms
#            numbers atoms by rank).  Then a restart written on 2 GPUs after those steps, continued
#            on 1 GPU for 500 steps, against the 2-GPU run going on (same IDs; 1e-10).  The rows the
#            migration moved are in the summary (must be > 0).
#   strong   the 3D cut (examples/cutting-3d-ti6al4v, periodic slab, all physics) at NY (41) across and
#            NZ (default 232) layers, about 4.1 M particles, on 1, 2, 4 GPUs for STEPS steps
#            (default 200) with migrate device and migrate host: particle-steps/s, efficiency
#            t1 / (N tN), the time per reneighbouring, LAMMPS' timer table (min/avg/max over the
#            ranks) and the sphcut timing table (max over the ranks) per run
#   classic  (after strong) its runs on 2 and 4 GPUs with LAMMPS' classic host path for what
#            MGPU_CLASSIC names (SPHCUT_LAMMPS_CLASSIC_FORWARD=$MGPU_CLASSIC; default 1: all of the
#            communication; "exchange": the exchange and borders at each reneighbouring;
#            "buffers": the fixes' and pairs' whole message buffers; "pageable": the messages staged
#            through LAMMPS' own pageable host buffers, SPHCUT_LAMMPS_STAGE=pageable), the baselines
#            of fixes 6-9 of tools/build-deps.sh
#   weak     the same with NZ x N layers on N GPUs (about 4.1 M particles per GPU): efficiency t1 / tN
#   chip     the 3D cut with free sides at 10 M particles (CHIP_NY 21 across, CHIP_NZ 2048 layers: the
#            1 M-particle cut's spacing on a 30.7 mm wide workpiece) on CHIP_NP (4) GPUs over CHIP_CUT
#            (0.5e-3 m), detached from the call so that it runs on over several calls on one warm
#            machine (see chip() below): time to solution, forces per mm, the last frame around the tool
# Settings (environment): MGPU_NP (GPU counts, default "1 2 4"; counts above the machine's GPUs are
# skipped), MGPU_MIGRATE ("device host"), NZ (232), STEPS (200), REBUILD (reneighbour every this many
# steps, default 20, neigh_modify check no: the tool moves about 1e-3 spacings per step, so with the
# example's check yes a 200-step run would reneighbour only at its setup; 0 keeps the example's
# check yes every NEIGHEVERY (10) steps), GPU_AWARE (on|off: -pk kokkos gpu/aware; default: LAMMPS
# decides, and turns it off where it cannot detect a CUDA-aware MPI, e.g. Open MPI built without
# CUDA: then LAMMPS 29Sep2021 takes its classic host path for ALL Kokkos communication on several
# ranks (exchange, borders, and the forward communication of x and of the fixes' columns every
# step), whatever the fix's migrate keyword; the summary names the MPI and LAMMPS' warning), MGPU_TIMEOUT (s
# per run, default 400), MGPU_BALANCE (1: balance shift xyz before the run, the default; 0: the
# uniform grid LAMMPS picks), FENCE (yes: the sphcut table shows device times, the runs are slower;
# default: the fix's default, host times per style).
# Results: $OUT/summary.txt and logs.tar.gz.  Figures: bench/gpu/RESULTS.md.
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/bench/gpu/common.sh"
EX2="$ROOT/examples/cutting-2d-ti6al4v/in.cutting"
EX3="$ROOT/examples/cutting-3d-ti6al4v/in.cutting"
W=/tmp/mgpu; mkdir -p $W
NGPU=$(nvidia-smi -L 2>/dev/null | grep -c '^GPU' || true)
NGPU=${MGPU_NGPU:-${NGPU:-1}}

# Kokkos switches for N ranks, one GPU each (SPHCUT_GPU_ARGS replaces -k on g N -sf kk: to try the
# script on a host build, e.g. "-k on t 1 -sf kk")
kk() {
  local n=$1
  echo "${SPHCUT_GPU_ARGS:--k on g $n -sf kk} -pk kokkos neigh full newton off${GPU_AWARE:+ gpu/aware $GPU_AWARE}"
}
# host build tries: no gpu/aware keyword without a GPU
[ -n "${SPHCUT_GPU_ARGS:-}" ] && kk() { case "$SPHCUT_GPU_ARGS" in *-pk*) echo "$SPHCUT_GPU_ARGS" ;; *) echo "$SPHCUT_GPU_ARGS -pk kokkos neigh full newton off" ;; esac; }

# the plugin's LAMMPS on N MPI ranks, at most MGPU_TIMEOUT seconds
mlmp() {
  local n=$1; shift
  timeout ${MGPU_TIMEOUT:-400} mpirun -np "$n" "$BIN" "$@"
}

# the example with the fix keyword `migrate $1` (a copy, as cutting.sh edits examples)
with_migrate() {
  local ex=$1 mode=$2 out=$3
  sed "s|^fix          sph all sph/jc-thermal .*|& migrate $mode${FENCE:+ fence $FENCE}|" "$ex" > "$out"
  grep -q "migrate $mode" "$out" || { say "the fix line of $ex did not take migrate $mode"; return 1; }
}

# atoms of B's final dump renumbered with the IDs of A, matched by their positions in the start
# dumps (the state after the first run, equal to round-off): writes $5, sorted by A's IDs
match_ids() {
  python3 - "$@" <<'EOP'
import sys
import numpy as np
def load(path):
    with open(path) as f:
        lines = f.readlines()
    k = next(i for i, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    return lines[:k + 1], np.loadtxt(lines[k + 1:], ndmin=2)
_, sa = load(sys.argv[1])          # start A: id x y z
_, sb = load(sys.argv[2])          # start B
head, fb = load(sys.argv[3])       # final B (sorted by B's id)
size = np.ptp(sa[:, 1])
amap = np.empty(len(sb), dtype=np.int64)
worst = 0.0
xb = sb[:, 1:4]
for i0 in range(0, len(sa), 256):  # nearest B atom of each A atom (brute force in blocks)
    d = ((sa[i0:i0 + 256, None, 1:4] - xb[None, :, :]) ** 2).sum(axis=2)
    j = d.argmin(axis=1)
    worst = max(worst, float(np.sqrt(d[np.arange(len(j)), j]).max()))
    amap[i0:i0 + len(j)] = j
assert len(set(amap.tolist())) == len(sa) == len(sb), "atoms not matched one to one"
byid = {int(r[0]): r for r in fb}
rows = [byid[int(sb[j, 0])].copy() for j in amap]
for r, ida in zip(rows, sa[:, 0]):
    r[0] = ida
rows.sort(key=lambda r: r[0])
with open(sys.argv[4], "w") as f:
    f.writelines(head)
    for r in rows:
        f.write(" ".join("%d" % r[0] if k == 0 else "%.17g" % v for k, v in enumerate(r)) + "\n")
print(f"matched {len(sa)} atoms by position, worst distance {worst / size:.2e} of the body size")
EOP
}

# the cut's first STEPS0 steps, then (several ranks) the boundary ahead of the tool, MORE steps,
# the final state (dump_sph by id); optionally a restart then MORE2 steps.  $1 ranks, $2 label,
# $3 example, rest: -var arguments
cut_run() {
  local n=$1 tag=$2 ex=$3; shift 3
  cat > $W/check/in.$tag <<EOI
processors   * 1 1
include      $ex
write_dump   all custom start.$tag.dump id x y z modify sort id format float %.17g
if "\$(is_defined(fix,lb))" then "unfix lb"
if "$n > 1" then "balance 1.0 x \$((v_xtip+f_cut[8]+0.95*v_dx-xlo)/(xhi-xlo))"
run          1000
print        "migrated rows after 1000 steps: see the migrate line above"
dump_sph     snap all \${printevery} final.$tag.dump id x y z vx vy vz density pressure vonmises plastic_strain temperature
dump_modify  snap sort id format float %.17g
run          0
undump       snap
if "${RESTART_TAG:-none} != none" then "write_restart restart.cutting" "run 500" &
  "dump_sph snap2 all \${printevery} cont.$tag.dump id x y z vx vy vz density pressure vonmises plastic_strain temperature" &
  "dump_modify snap2 sort id format float %.17g" "run 0"
EOI
  mlmp $n $(kk $n) -in in.$tag "$@" -log log.$tag > screen.$tag 2>&1 \
    || { say "  $tag failed: $(grep -m1 ERROR screen.$tag || tail -2 screen.$tag)"; return 1; }
}

check2() {
  [ "$NGPU" -ge 2 ] || { say "check2: needs 2 GPUs, this machine has $NGPU"; return 0; }
  mkdir -p $W/check; cd $W/check
  local v2="-var ny 11 -var xstart 1 -var steps 1500 -var cut 1e-3 -var thermoevery 500 -var dumpevery 0"
  local v3="-var ny 6 -var nz 3 -var sides free -var xstart 1 -var steps 1500 -var cut 1e-3 -var thermoevery 500"
  local d ex v
  for d in ${CHECK2_DIMS:-2 3}; do
    if [ $d = 2 ]; then ex=$EX2 v=$v2; else ex=$EX3 v=$v3; fi
    cut_run 1 g1d$d $ex $v || continue
    RESTART_TAG=$([ $d = 2 ] && echo yes || echo none) cut_run 2 g2d$d $ex $v || continue
    say "check2 ${d}D cut, the 1000 steps on 2 GPUs: $(awk '/^run +1000$/{f=1} f && /migrate device/{print; exit}' log.g2d$d)"
    grep -m1 -E "GPU-aware|classic exchange" log.g2d$d | sed 's/^/  LAMMPS: /' >> "$SUM"
    say "  $(match_ids start.g1d$d.dump start.g2d$d.dump final.g2d$d.dump final.g2d$d.as1.dump | tr '\n' ' ')"
    say "  2 GPUs vs 1 GPU after 1000 steps: $(python3 $ROOT/bench/gpu/compare.py final.g1d$d.dump final.g2d$d.as1.dump 1e-10 | tr '\n' ' ')"
    # the restart of the 2-GPU run continued on 1 GPU for 500 steps (the 2D example's continue mode;
    # the 3D example has none)
    [ $d = 2 ] || continue
    mkdir -p $W/check/re$d && cp restart.cutting $W/check/re$d/ && cd $W/check/re$d
    cat > in.re <<EOI
include      $ex
dump_sph     snap all \${printevery} cont.re.dump id x y z vx vy vz density pressure vonmises plastic_strain temperature
dump_modify  snap sort id format float %.17g
run          0
EOI
    timeout ${MGPU_TIMEOUT:-400} "$BIN" $(kk 1) -in in.re ${v/-var steps 1500/-var steps 500} -var continue 1 -log log.re \
      > screen.re 2>&1 || say "  restart on 1 GPU failed: $(grep -m1 ERROR screen.re || tail -2 screen.re)"
    say "  restart written on 2 GPUs, 500 steps on 1 GPU vs on 2: $(python3 $ROOT/bench/gpu/compare.py ../cont.g2d$d.dump cont.re.dump 1e-10 | tr '\n' ' ')"
    cd $W/check
  done
  cd "$ROOT"
}

# one scaling run: $1 ranks, $2 migrate mode, $3 layers, $4 label
scale_run() {
  local n=$1 mode=$2 nz=$3 tag=$4
  local in=$W/scale/in.$mode
  with_migrate "$EX3" $mode $in.tmp || return 1
  # neighbour lists rebuilt every REBUILD steps (check no), and the particles shared among the ranks
  local rb=${REBUILD:-20} nev="-var neighevery ${NEIGHEVERY:-10}"
  if [ "$rb" -gt 0 ]; then
    sed -i "s|^neigh_modify every \${neighevery} delay 0 check yes|neigh_modify every $rb delay 0 check no|" $in.tmp
    nev=""
  fi
  [ "${MGPU_BALANCE:-1}" = 1 ] && sed -i "s|^run          0$|balance      1.0 shift xyz 10 1.02\n&|" $in.tmp
  mv $in.tmp $in
  # thermo and the per-atom state on the host at the start and the end only
  local steps=${STEPS:-200}
  mlmp $n $(kk $n) -in $in -var ny ${NY:-41} -var nz $nz -var xstart 1 -var steps $steps \
    -var thermoevery $steps -var printevery $steps $nev -log log.$tag > screen.$tag 2>&1 \
    || { say "  $tag failed: $(grep -m1 ERROR screen.$tag || tail -2 screen.$tag)"; return 1; }
}

# the rate of the last run of a log (particle-steps/s), its loop time, steps and builds
rate_of() { awk '/^Loop time/{t=$4;n=$9;a=$12} END{printf "%.6g", a*n/t}' "$1"; }
loop_of() { awk '/^Loop time/{t=$4} END{print t}' "$1"; }

# LAMMPS' timer table of the main run (each section's min/avg/max over the ranks), the atoms per
# rank, and the sphcut timing table (each style's max over the ranks)
breakdown() {
  local lg=$1
  say "    $(grep '^Loop time' $lg | tail -1)"
  say "    $(grep -E '^Neighbor list builds' $lg | tail -1); $(grep '^sph/jc-thermal/kk migrate device' $lg | tail -1)"
  { grep -m1 "GPU-aware" $lg; grep -m1 "classic exchange" $lg; } | sed 's/^/      LAMMPS: /' >> "$SUM"
  awk '/^MPI task timing breakdown/{n++} n==2 && /^(Section|Pair |Neigh |Comm |Output |Modify |Other )/' $lg | sed 's/^/      /' >> "$SUM"
  grep -E '^(Nlocal|Nghost):' $lg | tail -2 | sed 's/^/      /' >> "$SUM"
  awk '/^sphcut timing/{buf = $0 "\n"; f = 1; next} f && /^  /{buf = buf $0 "\n"; next} f{f = 0; last = buf}
       END{if (f) last = buf; printf "%s", last}' $lg | sed 's/^/      /' >> "$SUM"
}

# one scaling run's line: $1 label, $2 tag, $3 GPUs, $4 the 1-GPU rate of the call (may be empty);
# strong: t1 / (N tN) = rate_N / (N rate_1); weak (N times the particles): the same ratio
report() {
  local label=$1 tag=$2 n=$3 r1=$4 eff="n/a (no 1-GPU run)"
  [ -n "$r1" ] && eff=$(awk -v a=$r1 -v b=$(rate_of log.$tag) -v n=$n 'BEGIN{printf "%.0f %%", 100*b/(n*a)}')
  say "$label: $(awk '/^Loop time/{t=$4;n=$9;a=$12} END{printf "%d particles, %d steps, %.1f ms/step, %.3e particle-steps/s", a, n, 1e3*t/n, a*n/t}' log.$tag), efficiency $eff"
  breakdown log.$tag
}

scaling() {
  local kind=$1
  mkdir -p $W/scale; cd $W/scale
  local nz0=${NZ:-232} mode n
  for mode in ${MGPU_MIGRATE:-device host}; do
    # without a 1-GPU run of its own, weak takes the strong 1-GPU run of the call (the same input)
    local r1=""
    [ $kind = weak ] && [ -f log.strong.$mode.1 ] && r1=$(rate_of log.strong.$mode.1)
    for n in ${MGPU_NP:-1 2 4}; do
      [ "$n" -le "$NGPU" ] || { say "$kind: $n GPUs skipped (this machine has $NGPU)"; continue; }
      local nz=$nz0
      [ $kind = weak ] && nz=$(( nz0 * n ))
      local tag=$kind.$mode.$n
      scale_run $n $mode $nz $tag || continue
      [ "$n" -eq 1 ] && r1=$(rate_of log.$tag)
      report "$kind migrate $mode, $n GPU(s), nz $nz" $tag $n "$r1"
    done
  done
  # the cost of a reneighbouring with the classic host path against the device migration
  for n in ${MGPU_NP:-1 2 4}; do
    local a=log.$kind.host.$n b=log.$kind.device.$n
    [ -f $a ] && [ -f $b ] || continue
    local ta tb nb
    ta=$(loop_of $a); tb=$(loop_of $b)
    nb=$(awk '/^Neighbor list builds/{n=$5} END{print n+0}' $b)
    [ -n "$ta" ] && [ -n "$tb" ] || continue
    say "$kind $n GPU(s): migrate host - migrate device $(awk -v ta="$ta" -v tb="$tb" -v nb="$nb" \
      'BEGIN{d = ta - tb; printf "%.3f s over the run, %.1f ms per reneighbouring (%d builds)", d, (nb > 0 ? 1e3 * d / nb : 0), nb}')"
  done
  cd "$ROOT"
}
strong() { scaling strong; }
# the strong runs on more than one GPU again with LAMMPS' own choice for an MPI that is not GPU-aware
# (SPHCUT_LAMMPS_CLASSIC_FORWARD=1: every communication through its classic host path, the whole x
# array and each fix's columns to the host and back every step, every atom array at each
# reneighbouring; MGPU_CLASSIC=exchange: only the exchange and borders; buffers: the fixes' and
# pairs' whole buffers staged; pageable: the messages through LAMMPS' pageable host buffers) instead
# of the device packing with the messages staged through page-locked host buffers (fixes 6-9 of
# tools/build-deps.sh); run after `strong` (its 1-GPU run is the reference)
classic() {
  mkdir -p $W/scale; cd $W/scale
  local r1="" n what=${MGPU_CLASSIC:-1}
  [ -f log.strong.device.1 ] && r1=$(rate_of log.strong.device.1)
  for n in ${MGPU_NP:-2 4}; do
    [ "$n" -gt 1 ] && [ "$n" -le "$NGPU" ] || continue
    local tag=strong.classic.${what//[^a-z0-9]/_}.$n
    if [ "$what" = pageable ]; then
      SPHCUT_LAMMPS_STAGE=pageable scale_run $n device ${NZ:-232} $tag || continue
      report "strong, the messages staged through LAMMPS' pageable buffers (fix 9 off), $n GPU(s)" $tag $n "$r1"
    else
      SPHCUT_LAMMPS_CLASSIC_FORWARD=$what scale_run $n device ${NZ:-232} $tag || continue
      report "strong, LAMMPS' classic host path for '$what', $n GPU(s)" $tag $n "$r1"
    fi
  done
  cd "$ROOT"
}
weak() { scaling weak; }
check() { check2; }

# the 3D cut with free sides at scale on CHIP_NP (4) GPUs, detached from the device call: the call
# that finds no run starts one (setsid: it goes on after the call returns, while the machine stays
# warm), and each call waits for it until CHIP_WAIT_END (the epoch second it returns by, default
# 500 s on), saying how far it got; the call that finds it ended reports it and copies its files to
# $OUT/chip/ (CHIP_WAIT_END must fall inside the call's limit, the first call's build included).
# The run ends at CHIP_CUT of cut or at CHIP_RUN_END (the epoch second; LAMMPS' timer timeout from
# the start, setup included), whichever comes first, then writes the last frame of the region
# around the tool (x from CHIP_PIC_AHEAD, 0.3e-3 m, ahead of the tool tip, where the chip is; z in
# CHIP_PIC_Z: one free side and 1.5 mm in) for tools/render_chip.py; CHIP_STOP=1 ends it at once,
# CHIP_FRESH=1 starts anew where the last run ended.  The 10 M-particle cut of RESULTS.md: three
# calls of  CHIP_RUN_END=<first call's start + 1450> CHIP_WAIT_END=<now + 500> multigpu.sh chip
chip() {
  local n=${CHIP_NP:-4} ny=${CHIP_NY:-21} nz=${CHIP_NZ:-2048} cut=${CHIP_CUT:-0.5e-3}
  local d=$W/chip-$ny-$nz
  # CHIP_FRESH=1: a new run, the folder of an earlier one (ended) removed
  [ "${CHIP_FRESH:-0}" = 1 ] && [ -f $d/ended ] && rm -rf $d
  mkdir -p $d && cd $d
  if [ ! -f started ]; then
    [ "$n" -le "$NGPU" ] || { say "chip: needs $n GPUs, this machine has $NGPU"; cd "$ROOT"; return 0; }
    local now; now=$(date +%s)
    local tout=$(( ${CHIP_RUN_END:-$(( now + 3600 ))} - now ))
    # the example with a second halt: the run also ends where a later call writes the file "stop"
    sed 's|^run          \${nsteps}$|fix          stopfile all halt 100 v_stopfile > 0 error continue\n&|' "$EX3" > in.example
    grep -q "^fix          stopfile" in.example || { say "chip: the run line of $EX3 not found"; cd "$ROOT"; return 1; }
    # the domain split across the width, where the work is the same everywhere
    cat > in.chip <<EOI
processors   1 1 *
timer        timeout $tout every 100
variable     stopfile equal is_file(stop)
include      in.example
timer        timeout off
region       pic block \$(v_xtip+f_cut[8]-${CHIP_PIC_AHEAD:-0.3e-3}) INF INF INF ${CHIP_PIC_Z:--0.3e-3 1.5e-3} units box
group        pic region pic
dump_sph     snap pic \${printevery} chip.dump id type x y z temperature plastic_strain role
dump_modify  snap sort id
run          0
EOI
    echo $now > started
    setsid nohup bash -c "mpirun -np $n $BIN $(kk $n) -in in.chip -var ny $ny -var nz $nz -var sides free \
      -var cut $cut -var xstart 1 -var thermoevery 5000 -var printevery 100 ${CHIP_ARGS:-} -log log.chip; echo \$? > ended" \
      > screen 2>&1 < /dev/null &
    say "chip: started on $n GPUs, ny $ny nz $nz, cut $cut m, $tout s at most"
  fi
  # CHIP_STOP=1: end the run now (at its next check, every 100 steps), with its last frame
  [ "${CHIP_STOP:-0}" = 1 ] && [ ! -f ended ] && touch stop && say "chip: asked to stop"
  local end=${CHIP_WAIT_END:-$(( $(date +%s) + 500 ))} t0; t0=$(cat started)
  while [ ! -f ended ] && [ $(( $(date +%s) + 15 )) -lt $end ]; do sleep 10; done
  local last; last=$(grep -v '^#' forces.dat 2>/dev/null | tail -1)
  say "chip: $(( $(date +%s) - t0 )) s since the start; $(grep -m1 -o 'Created [0-9]* atoms' log.chip | head -1) (workpiece),"\
    "$(grep '^Loop time' log.chip | head -1 | awk '{print $(NF-1), "particles"}'); forces.dat: ${last:-none yet}"
  grep -m1 -E "ERROR|Wall time limit" screen log.chip 2>/dev/null | sed 's/^/  /' | tee -a "$SUM"
  if [ -f ended ]; then
    say "chip: ended (exit $(cat ended)); $(grep '^Loop time' log.chip | sed -n 2p)"
    sed '/^dump_sph/,$d' log.chip > log.main && breakdown log.main
    python3 "$ROOT/examples/cutting-2d-ti6al4v/steady.py" 2>&1 | head -3 | sed 's/^/  /' | tee -a "$SUM"
    mkdir -p "$OUT/chip" && cp forces.dat log.chip in.chip "$OUT/chip/" && tail -20 screen > "$OUT/chip/screen.tail"
    [ -f chip.dump ] && gzip -c chip.dump > "$OUT/chip/chip.dump.gz"
  fi
  cd "$ROOT"
}

say "multigpu: $NGPU GPU(s); MPI: $(mpirun --version 2>&1 | head -1); CUDA-aware: $(ompi_info --parsable --all 2>/dev/null | grep -m1 mpi_built_with_cuda_support:value || echo unknown)"
run_modes "$@"
[ -n "${NOLOGS:-}" ] || tar czf "$OUT/logs.tar.gz" --exclude='*.dump' --exclude='restart.*' -C /tmp mgpu 2>/dev/null || true
