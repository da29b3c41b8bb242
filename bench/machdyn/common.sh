# bench/machdyn: what run.sh and mech-overhead.sh share (sourced, `here` set by the caller):
# the arguments [n] [steps] [reps], the build's environment, one thread
root="$(cd "$here/../.." && pwd)"
n=${1:-31}
steps=${2:-100}
reps=${3:-2}
[ -f "$root/build/env.sh" ] || { echo "no build/env.sh: run 'make build' first" >&2; exit 1; }
# shellcheck disable=SC1091
source "$root/build/env.sh"
export OMP_NUM_THREADS=1
