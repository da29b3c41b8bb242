#!/usr/bin/env bash
# sphcut test: the environment variables the styles read are the ones doc/performance.md lists in
# its "Environment switches" table, and there are at most three.  Every name a source in KOKKOS/
# or src/ reads (a literal "SPHCUT_..." string: sphcut::env_switch's and getenv's arguments, and
# any other getenv("...")) must be a row of that table, every row must be read somewhere, and
# getenv may take a variable only inside sphcut::env_switch (KOKKOS/sphcut_kokkos.h).
#
# Usage: test_env_switches.sh [SOURCE_DIR]   (default: the checkout this script is in)
# Exit status: 0 all listed; 1 what differs is printed
set -uo pipefail
ROOT="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
cd "$ROOT" || exit 2
DOC=doc/performance.md
MAX=3
[ -f "$DOC" ] || { echo "test_env_switches: $DOC missing" >&2; exit 2; }

srcs=(--include='*.cpp' --include='*.h' --include='*.hpp' --include='*.cu')
# the names read: SPHCUT_ string literals and the literal arguments of getenv
read_names=$( { grep -rhoE "${srcs[@]}" '"SPHCUT_[A-Z0-9_]+"' KOKKOS src
                grep -rhoE "${srcs[@]}" 'getenv[[:space:]]*\([[:space:]]*"[^"]+"' KOKKOS src | grep -oE '"[^"]+"'; } \
              | tr -d '"' | sort -u)
# getenv with anything but a literal, outside env_switch
other=$(grep -rnE "${srcs[@]}" 'getenv[[:space:]]*\([[:space:]]*[^"[:space:]]' KOKKOS src \
          | grep -v '^KOKKOS/sphcut_kokkos\.h:.*std::getenv(name)')
# the table's names: the first column of the rows under "## Environment switches"
table=$(awk '/^## /{on = ($0 == "## Environment switches")} on && /^\| `/' "$DOC" \
          | sed -E 's/^\| `([^`]+)`.*/\1/' | sort -u)

fail=0
ntable=$(printf '%s\n' "$table" | grep -c . || true)
if [ "$ntable" -eq 0 ]; then
  echo "test_env_switches: no table under \"## Environment switches\" in $DOC"; fail=1
fi
if [ "$ntable" -gt "$MAX" ]; then
  echo "test_env_switches: $ntable switches in $DOC's table, at most $MAX"; fail=1
fi
for n in $read_names; do
  if ! grep -qx "$n" <<< "$table"; then
    echo "test_env_switches: $n is read here but not listed in $DOC \"Environment switches\":"
    grep -rnE "${srcs[@]}" "\"$n\"" KOKKOS src | sed 's/^/    /'
    fail=1
  fi
done
for n in $table; do
  grep -qx "$n" <<< "$read_names" || { echo "test_env_switches: $DOC lists $n, which no source in KOKKOS/ or src/ reads"; fail=1; }
done
if [ -n "$other" ]; then
  echo "test_env_switches: getenv of a name that is not a literal, outside sphcut::env_switch:"
  echo "$other" | sed 's/^/    /'
  fail=1
fi
[ $fail = 0 ] || { echo "test_env_switches: FAILED" >&2; exit 1; }
echo "test_env_switches: the sources read" $read_names "- all in $DOC's table ($ntable of at most $MAX)"
