#!/usr/bin/env bash
# What moves the cutting forces: variants of examples/cutting-2d-ti6al4v at a cheap resolution,
# NP MPI ranks each (default 2), JOBS variants at a time (default 1), each with the force
# decomposition (-var decomp) and a dump every DUMPEVERY steps (default 2000; 0: none) for the
# |F_T|/F_N distribution, then one table (bench/cutting/decompose.py per run).  NY particles
# across (default 11), CUT cut length (default 0.3e-3 m), OUT output folder (default
# ./sensitivity-out), ONLY a space-separated subset of the variant names (also of EXTRA_NAMES,
# run only when named).  A finished variant (its log has "Total wall time") is not rerun:
# delete its folder to repeat it.
# On the cores of a GPU machine with the GPU build (README, "GPU build": build-cuda/lmp_sphcut):
# DEVICE=1, e.g. the 21-across study of doc/validation.md (16 cores):
#   DEVICE=1 NY=21 CUT=0.5e-3 JOBS=8 DUMPEVERY=0 ARGS="-var walltime 480" \
#     ONLY="base coulomb no-conduction eta0 hdx1.5 sfac2 mu0.65-coulomb heatevery1" bash bench/cutting/sensitivity.sh
# Variants of what the input has no -var for (the artificial viscosity, XSPH, vreg, the
# workpiece's clamping, the hourglass control) run a copy of the input edited by sed (EDITS;
# the script stops if an edit does not apply), written to the variant's folder as in.cutting.
# ARGS: more LAMMPS arguments for every variant (e.g. "-var walltime 480").
# After the table, bench/cutting/hourglass.py (the odd-even indicator of the velocity field)
# for the variants that have a dump.
#   source build/env.sh && bash bench/cutting/sensitivity.sh
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
NY="${NY:-11}"; CUT="${CUT:-0.3e-3}"; NP="${NP:-2}"; OUT="${OUT:-$PWD/sensitivity-out}"; JOBS="${JOBS:-1}"
if [ -n "${DEVICE:-}" ]; then
  source "$ROOT/bench/gpu/common.sh"    # the device build (build-cuda/), once per machine
  build
  LMP="$BIN"
fi
: "${LMP:?source build/env.sh first}"
IN="$ROOT/examples/cutting-2d-ti6al4v/in.cutting"
SEED="$ROOT/examples/cutting-2d-ti6al4v/seed003.py"    # the case's constants (spacing, vc)
NAMES=(base memory coulomb centre pfac0.3 pfac3 dfac0 dfac1 split1 mu0.65 mu0.65-memory
       vreg0.1% vreg10% av0.1 av0.5 av2 xsph0 xsph1 clamp-left-half clamp-bottom hg0.1 hg1)
# run only when named in ONLY: the hourglass control with the other variants
EXTRA_NAMES=(hg0.1-mu0.65 hg0.1-pfac3 dtfac0.3 dtfac0.5 cfl0.45-dtfac0.5 pfac10 pfac30
             no-conduction eta0 hdx1.5 sfac2 mu0.65-coulomb heatevery1)
declare -A VARIANTS=(
  [base]=""                                  # static-limit friction (stick yes), mu 0.35, split auto
  [memory]="-var friction memory"            # friction with memory (elastic predictor, alpha 0.1)
  [coulomb]="-var friction coulomb"          # plain Coulomb (stick no)
  [centre]="-var sfac 1e6"                   # contact at the particle centre (offset 0.5 h/sfac -> 0)
  [pfac0.3]="-var pfac 0.3"
  [pfac3]="-var pfac 3"
  [pfac10]="-var pfac 10"                    # is Ft converged in the penalty stiffness?
  [pfac30]="-var pfac 30"
  [dfac0]="-var dfac 0"
  [dfac1]="-var dfac 1"
  [split1]="-var split 1"                    # all friction heat into the workpiece (seed 003)
  [mu0.65]="-var mu 0.65"
  [mu0.65-memory]="-var mu 0.65 -var friction memory"
  [hg0.1-mu0.65]="-var mu 0.65"
  [hg0.1-pfac3]="-var pfac 3"
  [dtfac0.3]="-var dtfac 0.3"                # the penalty spring's time step limit (default 0.15):
  [dtfac0.5]="-var dtfac 0.5"                # in contact it sets dt (fewer steps, same physics?)
  [cfl0.45-dtfac0.5]="-var cfl 0.45 -var dtfac 0.5"   # and a larger Courant number (IWF: about 0.6)
  [no-conduction]="-var thermal 0"          # no conduction, no surface losses
  [eta0]="-var eta 0"                        # no friction heat
  [hdx1.5]="-var hdx 1.5"                    # h = 1.5 dx (the example's choice from 41 across)
  [sfac2]="-var sfac 2.0"                    # contact distance 0.5 h/2
  [mu0.65-coulomb]="-var mu 0.65 -var friction coulomb"
  [heatevery1]="-var heatevery 1"            # no thermal sub-cycling
  # input edits only (EDITS below)
  [vreg0.1%]="" [vreg10%]="" [av0.1]="" [av0.5]="" [av2]="" [xsph0]="" [xsph1]=""
  [clamp-left-half]="" [clamp-bottom]="" [hg0.1]="" [hg1]=""
)
# edits of the input (sed expressions), for what it has no -var for
vc_ms=$(python3 -c "print($(python3 "$SEED" vc) / 60.0)")
AV='s/chi 0.9 hdx ${hdx}$/& alpha %s beta %s/'             # workpiece pair_coeff (default 1 1)
declare -A EDITS=(
  [vreg0.1%]="s/sfac \${sfac}/& vreg $(python3 -c "print(0.001 * $vc_ms)")/"   # friction viscous below 0.1 % of vc (default 1 %)
  [vreg10%]="s/sfac \${sfac}/& vreg $(python3 -c "print(0.1 * $vc_ms)")/"
  [av0.1]="$(printf "$AV" 0.1 0.1)"
  [av0.5]="$(printf "$AV" 0.5 0.5)"
  [av2]="$(printf "$AV" 2 2)"
  [xsph0]='s/chi 0.9 hdx ${hdx}$/& xsph 0/'                  # default 0.5 (none for particles in contact)
  [xsph1]='s/chi 0.9 hdx ${hdx}$/& xsph 1/'
  # the left clamp only below half height (IWF GPU code), or none (bottom layers only)
  [clamp-left-half]='s/^region       clampreg block INF -0.5 INF INF INF INF/region       clampreg block INF -0.5 INF $((v_ny-1)\/2) INF INF/'
  [clamp-bottom]='s/^region       clampall union 2 clampreg basereg/region       clampall union 2 basereg basereg/'
  [hg0.1]='s/^pair_style   sph\/jc-thermal kernel cubic$/& hourglass 0.1/'
  [hg1]='s/^pair_style   sph\/jc-thermal kernel cubic$/& hourglass 1/'
  [hg0.1-mu0.65]='s/^pair_style   sph\/jc-thermal kernel cubic$/& hourglass 0.1/'
  [hg0.1-pfac3]='s/^pair_style   sph\/jc-thermal kernel cubic$/& hourglass 0.1/'
)
mkdir -p "$OUT"
running=0
for name in ${ONLY:-${NAMES[@]}}; do
  [ -n "${VARIANTS[$name]+set}" ] || { echo "unknown variant $name" >&2; exit 1; }
  dir="$OUT/$NY-$name"
  if grep -qs "Total wall time" "$dir/log.cutting"; then continue; fi
  rm -rf "$dir"; mkdir -p "$dir"
  in="$IN"
  if [ -n "${EDITS[$name]:-}" ]; then
    in="$dir/in.cutting"
    sed -e "${EDITS[$name]}" "$IN" > "$in"
    if cmp -s "$IN" "$in"; then echo "$name: the edit '${EDITS[$name]}' does not apply to $IN" >&2; exit 1; fi
  fi
  echo "== $name (ny $NY, cut $CUT): ${VARIANTS[$name]} ${EDITS[$name]:-}"
  ( cd "$dir" && nice -n 10 mpirun -np "$NP" --bind-to none $LMP -in "$in" -var ny "$NY" -var cut "$CUT" \
      -var dumpevery "${DUMPEVERY:-2000}" -var thermoevery 20000 -var decomp 100 ${VARIANTS[$name]} ${ARGS:-} \
      -log log.cutting -screen none || echo "$name failed" ) &
  running=$((running + 1))
  if [ "$running" -ge "$JOBS" ]; then wait -n || true; running=$((running - 1)); fi
done
wait
for name in ${ONLY:-${NAMES[@]}}; do
  dir="$OUT/$NY-$name"
  mu=0.35; [[ "$name" == *mu0.65* ]] && mu=0.65
  loop=$(grep -h "Loop time" "$dir/log.cutting" | awk '{s += $4} END {print s}')
  echo; echo "### $name: ${VARIANTS[$name]:-} ${EDITS[$name]:-}  (loop time $loop s on $NP ranks)"
  python3 "$ROOT/bench/cutting/decompose.py" "$dir" "$mu" "$(python3 "$SEED" spacing "$NY")" || true
done
echo; echo "### table (loop times above are of a shared machine)"
runs=()
for name in ${ONLY:-${NAMES[@]}}; do
  mu=0.35; [[ "$name" == *mu0.65* ]] && mu=0.65
  runs+=("$OUT/$NY-$name:$mu")
done
python3 "$ROOT/bench/cutting/decompose.py" --table "$(python3 "$SEED" spacing "$NY")" "${runs[@]}"
echo; echo "### odd-even indicator of the velocity field (bench/cutting/hourglass.py)"
runs=()
for name in ${ONLY:-${NAMES[@]}}; do [ -f "$OUT/$NY-$name/dump.cutting" ] && runs+=("$OUT/$NY-$name"); done
if [ ${#runs[@]} -gt 0 ]; then python3 "$ROOT/bench/cutting/hourglass.py" --table "$NY" "${runs[@]}"; fi
