#!/usr/bin/env bash
# Builds SUNDIALS 6.4.1 with -O2 from Debian's own source package into a
# prefix shared by every clone on the machine (docs/sundials.md says why:
# Debian's libsundials-dev is -O0 code). Only what the runtime links is
# built: IDA, CVODE, the serial N_Vector, dense and sparse SUNMatrix, dense
# and KLU SUNLinearSolver (KLU from libsuitesparse-dev), as static
# libraries with -fPIC so they can go into ldaec and into a shared library.
#
# Skipped when the prefix's stamp records the same source version and
# options. Needs the deb-src line and the packages scripts/install-deps.sh
# sets up (dpkg-dev, cmake, ninja-build, libsuitesparse-dev).
#
# Usage: scripts/build-sundials.sh [--force]
# LDAEC_SUNDIALS_PREFIX overrides the prefix (the top-level CMakeLists.txt
# reads the same variable at configure time).
set -euo pipefail

DEB_VERSION=6.4.1+dfsg1-3
PREFIX=${LDAEC_SUNDIALS_PREFIX:-/opt/ldaec/sundials-6.4.1}
CFLAGS_OPT="-O2 -g"
JOBS=${LDAEC_SUNDIALS_JOBS:-$(nproc)}

# Everything that decides the result; a change here rebuilds.
OPTIONS=(
  -DCMAKE_BUILD_TYPE=None
  "-DCMAKE_C_FLAGS=$CFLAGS_OPT"
  -DCMAKE_POSITION_INDEPENDENT_CODE=ON
  -DBUILD_STATIC_LIBS=ON -DBUILD_SHARED_LIBS=OFF
  -DBUILD_IDA=ON -DBUILD_CVODE=ON
  -DBUILD_ARKODE=OFF -DBUILD_CVODES=OFF -DBUILD_IDAS=OFF -DBUILD_KINSOL=OFF
  -DBUILD_NVECTOR_MANYVECTOR=OFF -DBUILD_FORTRAN_MODULE_INTERFACE=OFF
  -DENABLE_KLU=ON -DKLU_INCLUDE_DIR=/usr/include/suitesparse
  -DKLU_LIBRARY_DIR=/usr/lib/x86_64-linux-gnu
  -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_ENABLE_CXX=OFF -DEXAMPLES_INSTALL=OFF
)
STAMP_TEXT="sundials $DEB_VERSION ${OPTIONS[*]}"
STAMP="$PREFIX/ldaec-build.stamp"

if [ "${1:-}" != "--force" ] && [ -f "$STAMP" ] &&
   [ "$(cat "$STAMP")" = "$STAMP_TEXT" ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
parent=$(dirname "$PREFIX")
$SUDO mkdir -p "$parent"

# Two clones running install-deps.sh at once must not build into the same
# prefix together: the second waits, then finds the stamp.
exec 9>"/tmp/ldaec-sundials-build.lock"
flock 9
if [ "${1:-}" != "--force" ] && [ -f "$STAMP" ] &&
   [ "$(cat "$STAMP")" = "$STAMP_TEXT" ]; then
  exit 0
fi

scratch=$(mktemp -d /tmp/ldaec-sundials.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
# apt-get source downloads as the _apt user when it can write there.
chmod 755 "$scratch"
if id _apt >/dev/null 2>&1; then chown _apt "$scratch" 2>/dev/null || true; fi

# Each step's output goes to a log, shown only when the step fails.
quiet() {
  "$@" >"$scratch/log" 2>&1 || { cat "$scratch/log" >&2; exit 1; }
}

cd "$scratch"
if ! apt-cache showsrc sundials 2>/dev/null | grep -qxF "Version: $DEB_VERSION"; then
  echo "build-sundials: no source package sundials $DEB_VERSION in apt's index;" \
       "scripts/install-deps.sh adds the deb-src line and updates it" >&2
  exit 1
fi
echo "build-sundials: SUNDIALS $DEB_VERSION, $CFLAGS_OPT, static -fPIC -> $PREFIX"
quiet apt-get source --download-only "sundials=$DEB_VERSION"
# apt checked the files against the signed Sources index, as its own
# unpacking (dpkg-source --no-check) trusts.
quiet dpkg-source --no-check -x "sundials_$DEB_VERSION.dsc" src
quiet cmake -S src -B build -G Ninja -Wno-dev "${OPTIONS[@]}" \
  -DCMAKE_INSTALL_PREFIX="$PREFIX" -DCMAKE_INSTALL_LIBDIR=lib
quiet cmake --build build -j "$JOBS"
# Install into a staging tree beside the prefix (same file system) and
# rename it into place, so builds linking from the prefix never see it
# half there.
stage=$($SUDO mktemp -d "$parent/.sundials-stage.XXXXXX")
trap 'rm -rf "$scratch"; $SUDO rm -rf "$stage"' EXIT
quiet $SUDO env DESTDIR="$stage" cmake --install build
echo "$STAMP_TEXT" | $SUDO tee "$stage$PREFIX/ldaec-build.stamp" >/dev/null
if [ -e "$PREFIX" ]; then $SUDO mv "$PREFIX" "$stage/old"; fi
$SUDO mv "$stage$PREFIX" "$PREFIX"
echo "build-sundials: done"
