#!/usr/bin/env bash
# What moves the cutting forces: eight variants of examples/cutting-2d-ti6al4v side by side
# on the device machine's 16 cores (2 MPI ranks each), 21 particles across, CUT of cut
# (default 0.5 mm), WALL seconds at most (default 480).  Each run's forces.dat and log go to
# $OUT/sens-NAME.tar.gz; summarise here with bench/cutting/summarise.py.
#   bash bench/cutting/device-sensitivity.sh   (after device-cut.sh start built LAMMPS + plugin;
#                                               builds them itself on a fresh machine)
set -euo pipefail
NY="${NY:-21}"; CUT="${CUT:-0.5e-3}"; WALL="${WALL:-480}"
OUT="${OUT:-$PWD/device-out}"; ROOT="$PWD"; mkdir -p "$OUT"
source "$ROOT/bench/cutting/device-build.sh"    # once per machine
IN="$ROOT/examples/cutting-2d-ti6al4v/in.cutting"
declare -A VARIANTS=(
  [base]=""
  [stick-no]="-var stick no"
  [no-conduction]="-var thermal 0"
  [eta0]="-var eta 0"
  [hdx1.5]="-var hdx 1.5"
  [sfac2]="-var sfac 2.0"
  [mu0.65-stick-no]="-var mu 0.65 -var stick no"
  [heatevery1]="-var heatevery 1"
)
pids=()
for name in "${!VARIANTS[@]}"; do
  dir="$ROOT/build-device/sens-$name"; rm -rf "$dir"; mkdir -p "$dir"
  ( cd "$dir" && mpirun -np 2 --bind-to none $LMP -in "$IN" -var ny "$NY" -var cut "$CUT" -var dumpevery 0 \
      -var thermoevery 10000 ${VARIANTS[$name]} -var walltime "$WALL" -log log.0 -screen none || true ) &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || true; done
for name in "${!VARIANTS[@]}"; do
  tar czf "$OUT/sens-$name.tar.gz" -C "$ROOT/build-device/sens-$name" forces.dat log.0
done
