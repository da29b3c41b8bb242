#!/usr/bin/env bash
# sphcut - the plugin built alone against a LAMMPS source tree, as LAMMPS' examples/plugins build
# theirs (SPHCUT_PLUGIN_ONLY: headers, version.h, MPI, the C++ standard of `lmp -h`; nothing linked), installed with
# `cmake --install` into a plugin folder, and run by that LAMMPS's own plain `lmp` on 2 MPI ranks:
# loaded with `plugin load` (29Sep2021) or found in LAMMPS_PLUGIN_PATH (--autoload: LAMMPS from
# 4May2022 on), a short 2D SPH run with sph/jc-thermal.  Passes when the run completes, the plugin's
# styles were registered and no version warning was printed.
#
# Usage: unittest/test_plugin_only.sh SPHCUT_SOURCE LAMMPS_SRC_DIR LMP WORKDIR [--autoload] [--jobs N]
set -euo pipefail
SRC="$1" LSRC="$2" LMP="$3" WORK="$4"; shift 4
AUTOLOAD=0 JOBS=2
while [ $# -gt 0 ]; do
  case "$1" in --autoload) AUTOLOAD=1 ;; --jobs) JOBS="$2"; shift ;; *) echo "unknown option $1" >&2; exit 2 ;; esac
  shift
done
rm -rf "$WORK"; mkdir -p "$WORK/run"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 OMP_NUM_THREADS=1
cmake -S "$SRC" -B "$WORK/build" -DLAMMPS_SOURCE_DIR="$LSRC" -DLAMMPS_BINARY="$LMP" -DCMAKE_INSTALL_PREFIX="$WORK/install" \
  -DSPHCUT_PLUGIN_DIR=plugins > "$WORK/build.log" 2>&1 \
  && cmake --build "$WORK/build" -j "$JOBS" >> "$WORK/build.log" 2>&1 \
  && cmake --install "$WORK/build" >> "$WORK/build.log" 2>&1 \
  || { tail -30 "$WORK/build.log"; echo "test_plugin_only: the plugin-only build failed"; exit 1; }
grep "sphcut: " "$WORK/build.log"
so="$WORK/install/plugins/sphcutplugin.so"
[ -f "$so" ] || { echo "test_plugin_only: $so was not installed"; exit 1; }
cd "$WORK/run"
{
  [ $AUTOLOAD = 1 ] || echo "plugin load $so"
  cat <<'IN'
units si
dimension 2
boundary f f p
atom_style atomic
atom_modify map array
lattice sq 1e-3
region box block 0 8 0 8 -0.5 0.5
create_box 1 box
create_atoms 1 box
mass 1 0.0078
pair_style sph/jc-thermal
pair_coeff 1 1 rho0 7800 E 200e9 nu 0.3 h 1.3e-3
fix sph all sph/jc-thermal
velocity all set 1.0 0.0 0.0 units box
thermo 10
run 20
plugin list
IN
} > in.sph
if [ $AUTOLOAD = 1 ]; then export LAMMPS_PLUGIN_PATH="$WORK/install/plugins"; else unset LAMMPS_PLUGIN_PATH; fi
rc=0
mpirun -np 2 "$LMP" -in in.sph -log log.sph > out.sph 2>&1 || rc=$?
cat out.sph
[ $rc = 0 ] || { echo "test_plugin_only: lmp exited with status $rc"; exit 1; }
grep -q "^Loop time of .* on 2 procs" out.sph || { echo "test_plugin_only: the run did not complete on 2 ranks"; exit 1; }
grep -q "pair style plugin sph/jc-thermal" out.sph || { echo "test_plugin_only: sph/jc-thermal not registered"; exit 1; }
if grep -qi "warning.*sphcut" out.sph; then echo "test_plugin_only: the plugin warned"; exit 1; fi
echo "test_plugin_only: passed ($(sed -n 's/^LAMMPS (\(.*\))$/\1/p' out.sph | head -1), $([ $AUTOLOAD = 1 ] && echo LAMMPS_PLUGIN_PATH || echo 'plugin load'))"
