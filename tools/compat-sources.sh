#!/usr/bin/env bash
# sphcut - the headers of the newer LAMMPS versions sphcut claims to build against, for
# tools/compat-check.sh (ctest test_compat_lammps): the src/ headers of
#   LAMMPS 4Feb2025 (Debian trixie, source package lammps 20250204+dfsg.1-2)
#   LAMMPS 4Jul2026 (Debian sid,    source package lammps 20260704+dfsg-2)
# and the installed headers of Kokkos 5.2.2 (OpenMP; Debian sid, libkokkos-dev 5.2.2-2) and of
# Kokkos 4.5.01 (Serial only, the package's build; Debian sid, libtrilinos-kokkos-dev 16.1.0-5+b2).
#
# Downloaded with apt-get through a private apt configuration under the cache (its own
# sources list with deb-src entries for trixie and sid and a deb entry for sid, its own
# package lists): the system's apt sources are not touched and root is not needed.  Only the
# upstream (orig) tarballs are used: `apt-get source --download-only` of these versions
# fetches them but exits non-zero because the .dsc files are no longer on the mirror, so
# success is judged by the tarball being there.  From each tarball only the headers of src/
# (*.h, *.hpp, every package folder) are unpacked.  No generated header (lmpinstalledpkgs.h,
# lmpgitversion.h, style_*.h) is needed: LAMMPS includes them only from its own .cpp files,
# never from a header a plugin reaches (checked when this was written; were that to change,
# the compile check fails with a missing-include error, it does not pass silently).
#
# Usage: tools/compat-sources.sh [--print-dir | --lammps-tarball YYYYMMDD]
#   prints the folder holding lammps-YYYYMMDD/src, kokkos-5.2.2/include and kokkos-4.5.1/include
#   on its last line
#   --lammps-tarball YYYYMMDD: instead, download the whole orig tarball of that LAMMPS version
#     (one of LAMMPS_DEBS below) into the folder's downloads/ and print its path on the last line;
#     the caller removes it when done (tools/compat-run.sh builds LAMMPS 4Jul2026 from it)
# Exit status: 0 ready; 77 the sources cannot be downloaded (no apt-get, no network) and CI is
# not set (ctest reports the test as skipped); 1 anything else, and a failed download in CI.
# Environment: SPHCUT_CACHE (default $HOME/.cache/sphcut).
set -euo pipefail

CACHE="${SPHCUT_CACHE:-$HOME/.cache/sphcut}"
# bump when the layout below changes, so old caches are not reused
RECIPE=1
DIR="$CACHE/compat-r$RECIPE"
# Debian source version : LAMMPS version as a number (its version.h is checked against it)
LAMMPS_DEBS=("20250204+dfsg.1-2:20250204" "20260704+dfsg-2:20260704")
# Kokkos headers: Debian package=version : folder : its KOKKOS_VERSION : the backend it enables
KOKKOS_DEBS=("libkokkos-dev=5.2.2-2:kokkos-5.2.2:50202:OPENMP"
             "libtrilinos-kokkos-dev=16.1.0-5+b2:kokkos-4.5.1:40501:SERIAL")
if [ "${1:-}" = "--print-dir" ]; then echo "$DIR"; exit 0; fi
WANT_TARBALL=""
if [ "${1:-}" = "--lammps-tarball" ]; then
  WANT_TARBALL="${2:?--lammps-tarball needs a version, e.g. 20260704}"
  for e in "${LAMMPS_DEBS[@]}"; do [ "${e#*:}" = "$WANT_TARBALL" ] && WANT_DEB="${e%%:*}"; done
  [ -n "${WANT_DEB:-}" ] || { echo "compat-sources.sh: no Debian source version known for LAMMPS $WANT_TARBALL" >&2; exit 1; }
fi

# the first existing file among the arguments (a glob), or nothing
first() { local f; for f in "$@"; do if [ -e "$f" ]; then echo "$f"; break; fi; done; return 0; }
log() { printf '[compat-sources %(%H:%M:%S)T] %s\n' -1 "$*"; }
# a download that cannot happen: skip outside CI, fail in CI (a skipped check proves nothing)
cannot_download() {
  echo "compat-sources.sh: cannot download $1" >&2
  if [ "${CI:-}" = "true" ]; then echo "compat-sources.sh: CI is set: failing instead of skipping" >&2; exit 1; fi
  echo "compat-sources.sh: SKIPPED (needs apt-get and network access to deb.debian.org)" >&2
  exit 77
}

all_complete() {
  local e
  for e in "${LAMMPS_DEBS[@]}"; do [ -f "$DIR/lammps-${e#*:}/.complete" ] || return 1; done
  for e in "${KOKKOS_DEBS[@]}"; do IFS=: read -r _ k _ _ <<< "$e"; [ -f "$DIR/$k/.complete" ] || return 1; done
}
if [ -z "$WANT_TARBALL" ] && all_complete; then echo "$DIR"; exit 0; fi

command -v apt-get >/dev/null 2>&1 || cannot_download "(no apt-get on this machine)"
mkdir -p "$DIR"
exec 9>"$DIR/.lock"
flock 9      # another checkout's test may be fetching: wait for it, then use what it fetched
if [ -z "$WANT_TARBALL" ] && all_complete; then echo "$DIR"; exit 0; fi

# ---------------------------------------------------------------- private apt configuration
APTDIR="$DIR/apt"
mkdir -p "$APTDIR/parts" "$APTDIR/lists/partial" "$APTDIR/cache/archives/partial"
cat > "$APTDIR/parts/sphcut-compat.sources" <<'EOF'
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: trixie sid
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian
Suites: sid
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
APT_OPTS=(-q -o "Dir::Etc::SourceList=/dev/null" -o "Dir::Etc::SourceParts=$APTDIR/parts"
          -o "Dir::State::Lists=$APTDIR/lists" -o "Dir::Cache=$APTDIR/cache"
          -o "Debug::NoLocking=1" -o "APT::Sandbox::User=$(id -un)")
log "apt-get update (trixie, sid; private lists in $APTDIR)"
apt-get "${APT_OPTS[@]}" update > "$APTDIR/update.log" 2>&1 || true
srcs=$(apt-cache "${APT_OPTS[@]}" showsrc lammps 2>/dev/null || true)
if ! grep -q "^Version: ${LAMMPS_DEBS[0]%%:*}$" <<< "$srcs"; then
  tail -5 "$APTDIR/update.log" >&2
  cannot_download "the Debian trixie/sid package lists (apt-get update failed)"
fi

DL="$DIR/downloads"
mkdir -p "$DL"
# ---------------------------------------------------------------- one whole LAMMPS tarball
if [ -n "$WANT_TARBALL" ]; then
  upstream="${WANT_DEB%-*}"
  tarball=$(first "$DL"/lammps_"$upstream".orig.tar.*)
  if [ -z "$tarball" ]; then
    log "apt-get source --download-only lammps=$WANT_DEB"
    (cd "$DL" && apt-get "${APT_OPTS[@]}" source --download-only "lammps=$WANT_DEB") > "$DL/lammps-$WANT_TARBALL.log" 2>&1 || true
    rm -f "$DL"/lammps_"$WANT_DEB".debian.tar.*
    tarball=$(first "$DL"/lammps_"$upstream".orig.tar.*)
    if [ -z "$tarball" ]; then
      tail -5 "$DL/lammps-$WANT_TARBALL.log" >&2
      cannot_download "lammps_$upstream.orig.tar.* (apt-get source lammps=$WANT_DEB)"
    fi
  fi
  rm -rf "$APTDIR/lists" "$APTDIR/cache"
  echo "$tarball"
  exit 0
fi
# ---------------------------------------------------------------- LAMMPS headers
for e in "${LAMMPS_DEBS[@]}"; do
  deb="${e%%:*}"; ver="${e#*:}"
  dst="$DIR/lammps-$ver"
  [ -f "$dst/.complete" ] && continue
  upstream="${deb%-*}"
  tarball=$(first "$DL"/lammps_"$upstream".orig.tar.*)
  if [ -z "$tarball" ]; then
    log "apt-get source --download-only lammps=$deb"
    (cd "$DL" && apt-get "${APT_OPTS[@]}" source --download-only "lammps=$deb") > "$DL/lammps-$ver.log" 2>&1 || true
    tarball=$(first "$DL"/lammps_"$upstream".orig.tar.*)
    if [ -z "$tarball" ]; then
      tail -5 "$DL/lammps-$ver.log" >&2
      cannot_download "lammps_$upstream.orig.tar.* (apt-get source lammps=$deb)"
    fi
  fi
  # the tarball's top folder (lammps-4Feb2025/, or none at all), then its src/ headers
  tar tf "$tarball" > "$DL/members.txt"
  top=$(awk '!done && /(^|\/)src\/version\.h$/ { sub(/src\/version\.h$/, ""); print; done = 1 }' "$DL/members.txt")
  grep -E "^${top//./\\.}src/.*\.(h|hpp)$" "$DL/members.txt" > "$DL/headers.txt"
  log "unpacking the $(wc -l < "$DL/headers.txt") headers of ${top}src from $(basename "$tarball")"
  rm -rf "$dst" "$dst.tmp"
  mkdir -p "$dst.tmp"
  tar xf "$tarball" -C "$dst.tmp" -T "$DL/headers.txt"
  mkdir -p "$dst"
  mv "$dst.tmp/${top}src" "$dst/src"
  rm -rf "$dst.tmp"
  got=$(sed -n 's/.*LAMMPS_VERSION "\([0-9]*\) \([A-Za-z]*\) \([0-9]*\)".*/\1 \2 \3/p' "$dst/src/version.h")
  [ "$(date -d "$got" +%Y%m%d)" = "$ver" ] || { echo "compat-sources.sh: $tarball is LAMMPS '$got', expected $ver" >&2; exit 1; }
  rm -f "$tarball" "$DL"/lammps_"$deb".debian.tar.* "$DL/members.txt" "$DL/headers.txt"    # 130-210 MB; the headers are all the check needs
  touch "$dst/.complete"
done

# ---------------------------------------------------------------- Kokkos headers
for e in "${KOKKOS_DEBS[@]}"; do
  IFS=: read -r pkgver kdir knum kbackend <<< "$e"
  pkg="${pkgver%%=*}"; pver="${pkgver#*=}"
  kdst="$DIR/$kdir"
  [ -f "$kdst/.complete" ] && continue
  log "apt-get download $pkgver (sid)"
  (cd "$DL" && apt-get "${APT_OPTS[@]}" download "$pkgver") > "$DL/$kdir.log" 2>&1 || true
  deb=$(first "$DL"/"${pkg}"_"${pver//:/%3a}"_*.deb)
  [ -n "$deb" ] || { tail -5 "$DL/$kdir.log" >&2; cannot_download "${pkg}_$pver (apt-get download, sid)"; }
  rm -rf "$kdst" "$kdst.tmp"
  mkdir -p "$kdst.tmp"
  dpkg-deb -x "$deb" "$kdst.tmp"
  mkdir -p "$kdst"
  mv "$kdst.tmp/usr/include/kokkos" "$kdst/include"
  rm -rf "$kdst.tmp" "$deb"
  grep -q "define KOKKOS_VERSION $knum\$" "$kdst/include/KokkosCore_config.h" \
    && grep -q "define KOKKOS_ENABLE_$kbackend" "$kdst/include/KokkosCore_config.h" \
    || { echo "compat-sources.sh: $deb is not Kokkos $knum with $kbackend" >&2; exit 1; }
  touch "$kdst/.complete"
done
rm -rf "$APTDIR/lists" "$APTDIR/cache"   # the package lists (about 35 MB) are not needed again
log "ready: $DIR"
echo "$DIR"
