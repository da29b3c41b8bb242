#!/usr/bin/env bash
# What moves the thrust force: variants of examples/cutting-2d-ti6al4v at a cheap resolution,
# run one after the other (NP MPI ranks each, default 2), each with the force decomposition
# (-var decomp) and a dump for the |F_T|/F_N distribution, then one table
# (bench/cutting/decompose.py per run).  NY particles across (default 11), CUT cut length
# (default 0.3e-3 m), OUT output folder (default ./sensitivity-out), ONLY a space-separated
# subset of the variant names.  A finished variant (its log has "Total wall time") is not
# rerun: delete its folder to repeat it.
#   source build/env.sh && bash bench/cutting/sensitivity.sh
set -euo pipefail
: "${LMP:?source build/env.sh first}"
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
NY="${NY:-11}"; CUT="${CUT:-0.3e-3}"; NP="${NP:-2}"; OUT="${OUT:-$PWD/sensitivity-out}"
IN="$ROOT/examples/cutting-2d-ti6al4v/in.cutting"
NAMES=(base memory coulomb centre pfac0.3 pfac3 dfac0 dfac1 split1 mu0.65 mu0.65-memory)
declare -A VARIANTS=(
  [base]=""                                  # static-limit friction (stick yes), mu 0.35, split auto
  [memory]="-var friction memory"            # friction with memory (elastic predictor, alpha 0.1)
  [coulomb]="-var friction coulomb"          # plain Coulomb (stick no)
  [centre]="-var sfac 1e6"                   # contact at the particle centre (offset 0.5 h/sfac -> 0)
  [pfac0.3]="-var pfac 0.3"
  [pfac3]="-var pfac 3"
  [dfac0]="-var dfac 0"
  [dfac1]="-var dfac 1"
  [split1]="-var split 1"                    # all friction heat into the workpiece (seed 003)
  [mu0.65]="-var mu 0.65"
  [mu0.65-memory]="-var mu 0.65 -var friction memory"
)
mkdir -p "$OUT"
for name in ${ONLY:-${NAMES[@]}}; do
  dir="$OUT/$NY-$name"
  if grep -qs "Total wall time" "$dir/log.cutting"; then continue; fi
  rm -rf "$dir"; mkdir -p "$dir"
  echo "== $name (ny $NY, cut $CUT): ${VARIANTS[$name]}"
  ( cd "$dir" && nice -n 10 mpirun -np "$NP" $LMP -in "$IN" -var ny "$NY" -var cut "$CUT" -var dumpevery 2000 \
      -var thermoevery 20000 -var decomp 100 ${VARIANTS[$name]} -log log.cutting -screen none ) || echo "$name failed"
done
for name in ${ONLY:-${NAMES[@]}}; do
  dir="$OUT/$NY-$name"
  mu=0.35; [[ "$name" == mu0.65* ]] && mu=0.65
  loop=$(grep -h "Loop time" "$dir/log.cutting" | awk '{s += $4} END {print s}')
  echo; echo "### $name: ${VARIANTS[$name]:-(defaults)}  (loop time $loop s on $NP ranks)"
  python3 "$ROOT/bench/cutting/decompose.py" "$dir" "$mu" "$(python3 -c "print(0.3e-3 / ($NY - 1))")" || true
done
echo; echo "### table (loop times above are of a shared machine)"
runs=()
for name in ${ONLY:-${NAMES[@]}}; do
  mu=0.35; [[ "$name" == mu0.65* ]] && mu=0.65
  runs+=("$OUT/$NY-$name:$mu")
done
python3 "$ROOT/bench/cutting/decompose.py" --table "$(python3 -c "print(0.3e-3 / ($NY - 1))")" "${runs[@]}"
