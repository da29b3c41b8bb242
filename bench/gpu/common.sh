# Sourced by the GPU scripts of bench/ (gpu/*.sh, cutting/device-cut.sh, cutting/sensitivity.sh
# with DEVICE=1): environment, the summary writer say(), the LAMMPS binary lmp() (build-cuda/lmp_sphcut,
# built as in README "GPU build"), run_modes() and build(), which builds it only where it is missing
# (the dependencies as README's "GPU build"; on a machine without network from the packed sources in
# .carry/, the device machines these figures were measured on).  Expects ROOT.
OUT="${OUT:-$PWD/gpu-out}"
mkdir -p "$OUT"
NJ=$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)    # (nproc follows OMP_NUM_THREADS, exported below: a second script sourcing this would build on one core)
export SPHCUT_CACHE=/tmp/sphcut-cache
export CUDA_CACHE_MAXSIZE=4294967296      # room for the JIT-compiled sm_90 code
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMP_PROC_BIND=false OMP_NUM_THREADS=1
SUM="$OUT/summary.txt"
say() { echo "$*" | tee -a "$SUM"; }
GPU="${SPHCUT_GPU_ARGS:--k on g 1 -sf kk}"

BIN="${SPHCUT_LMP:-$ROOT/build-cuda/lmp_sphcut}"    # (SPHCUT_LMP, SPHCUT_GPU_ARGS: to try the script elsewhere)
lmp() { "$BIN" "$@"; }

# the one device build of bench/ (gpu/*.sh, cutting/device-cut.sh, cutting/sensitivity.sh with
# DEVICE=1): Kokkos (CUDA) + LAMMPS in $SPHCUT_CACHE and the plugin in build-cuda/, skipped when
# build-cuda/lmp_sphcut exists; the plugin path exported for $BIN.  Its LAMMPS runs the CPU styles too
# (without -k on; MPI on the machine's cores).
build() {
  export LAMMPS_PLUGIN_PATH="${LAMMPS_PLUGIN_PATH:-$ROOT/build-cuda}"
  [ -f "$BIN" ] && return 0
  { nvidia-smi -L; nvcc --version | tail -2; echo "cores: $(nproc)"; } > "$OUT/device.txt" 2>&1 || true
  local t0; t0=$(date +%s)
  # a dependency build a previous call packed (pack_deps; its parts joined here into
  # .carry/deps.tar.gz): used as it is, build-deps.sh finds it complete
  if [ -f "$ROOT/.carry/deps.tar.gz" ]; then
    mkdir -p "$SPHCUT_CACHE" && tar xzf "$ROOT/.carry/deps.tar.gz" -C "$SPHCUT_CACHE" \
      && say "deps: from .carry/deps.tar.gz"
  fi
  # the pinned sources: packed (tools/build-deps.sh --pack-sources) for a machine without network, else
  # from Debian's mirror as README's "GPU build" does
  local src=()
  if [ -f "$ROOT/.carry/sphcut-sources.tar.gz" ]; then
    mkdir -p /tmp/sphcut-src && tar xzf "$ROOT/.carry/sphcut-sources.tar.gz" -C /tmp/sphcut-src
    src=(--no-apt --sources /tmp/sphcut-src)
  fi
  bash "$ROOT/tools/build-deps.sh" --cuda "${src[@]}" --jobs "$NJ" > "$OUT/build-deps.log" 2>&1 \
    || { tail -30 "$OUT/build-deps.log"; exit 1; }
  PREFIX=$(bash "$ROOT/tools/build-deps.sh" --cuda --print-prefix)
  # (SPHCUT_CXX_FLAGS: more flags for the plugin's compiler, nvcc_wrapper; e.g. -lineinfo for
  # the source lines of Nsight Compute, cutting.sh ncu2d with NCU_PRINT_SOURCE=cuda)
  cmake -S "$ROOT" -B "$ROOT/build-cuda" -DSPHCUT_DEPS_FILE="$PREFIX/sphcut-deps.cmake" -DBUILD_TESTING=OFF \
    ${SPHCUT_CXX_FLAGS:+"-DCMAKE_CXX_FLAGS=$SPHCUT_CXX_FLAGS"} \
    > "$OUT/plugin-build.log" 2>&1 && cmake --build "$ROOT/build-cuda" -j "$NJ" >> "$OUT/plugin-build.log" 2>&1 \
    || { tail -40 "$OUT/plugin-build.log"; exit 1; }
  cp "$PREFIX/build-times.txt" "$OUT/build-times.txt" 2>/dev/null || true
  say "build: $(( $(date +%s) - t0 )) s (deps + plugin, $NJ jobs)"
}

# a second plugin, the baseline of a speed comparison (cutting.sh ab), built against the same
# dependencies from .carry/b-src.tar.gz (made here with  git archive -o .carry/b-src.tar.gz COMMIT)
# into build-cuda-b (its lmp_sphcut: BIN_B; its plugin folder goes in LAMMPS_PLUGIN_PATH for B runs)
BIN_B="$ROOT/build-cuda-b/lmp_sphcut"
build_b() {
  build
  [ -f "$BIN_B" ] && return 0
  [ -f "$ROOT/.carry/b-src.tar.gz" ] || { say "build_b: no .carry/b-src.tar.gz (git archive -o .carry/b-src.tar.gz COMMIT)"; return 1; }
  local t0 src=/tmp/sphcut-b; t0=$(date +%s)
  mkdir -p $src && tar xzf "$ROOT/.carry/b-src.tar.gz" -C $src
  PREFIX=$(bash "$ROOT/tools/build-deps.sh" --cuda --print-prefix)
  cmake -S $src -B "$ROOT/build-cuda-b" -DSPHCUT_DEPS_FILE="$PREFIX/sphcut-deps.cmake" -DBUILD_TESTING=OFF \
    > "$OUT/plugin-build-b.log" 2>&1 && cmake --build "$ROOT/build-cuda-b" -j "$NJ" >> "$OUT/plugin-build-b.log" 2>&1 \
    || { tail -40 "$OUT/plugin-build-b.log"; return 1; }
  say "build_b: the baseline plugin in $(( $(date +%s) - t0 )) s"
}

# the device build of the dependencies (installed files, nvcc_wrapper and the LAMMPS headers: what
# the plugin build reads; about 17 MB) as $1.part.* in 15 MB parts, so that the next call skips
# it: join them here with  cat DIR/deps.part.* > .carry/deps.tar.gz  (the device machine starts
# bare at every call; its deps build takes 3-5 minutes)
pack_deps() {
  local p b; p=$(bash "$ROOT/tools/build-deps.sh" --cuda --print-prefix); b=$(basename "$p")
  (cd "$SPHCUT_CACHE" && { find "$b" -path "$b/src" -prune -o \( -type f -o -type l \) -print; find "$b/src/kokkos/bin";
    find "$b/src/lammps/src" -name '*.h'; } | tar cf - -T - | gzip -6 > /tmp/deps.tar.gz) \
    && split -b 15M /tmp/deps.tar.gz "$1.part." && say "deps packed: $(du -h /tmp/deps.tar.gz | cut -f1)"
}

# build, then the modes named on the command line (default: check), each a function of the script
run_modes() {
  build
  local mode
  for mode in "${@:-check}"; do
    say "== $mode ($(date -u +%H:%M:%S))"
    $mode
  done
  say "== done ($(date -u +%H:%M:%S))"
}
