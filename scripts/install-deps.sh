#!/usr/bin/env bash
# Installs the Debian 12 packages ldaec needs to build, test and benchmark,
# then builds the -O2 SUNDIALS the build links (scripts/build-sundials.sh,
# docs/sundials.md). Idempotent: packages already present, an existing
# deb-src line and a built SUNDIALS are skipped, so re-running is cheap.
set -euo pipefail
here=$(dirname "$0")

PACKAGES=(
  build-essential cmake ninja-build ccache git dpkg-dev
  antlr4 libantlr4-runtime-dev
  llvm-19-dev llvm-19-tools
  libsuitesparse-dev
  # Not linked by anything of ours (SUNDIALS comes from
  # scripts/build-sundials.sh): kept for its examples' golden outputs
  # (/usr/share/doc/libsundials-dev/examples), which tests and benchmarks
  # compare against, and as the -O0 reference docs/sundials.md measures.
  libsundials-dev
  libeigen3-dev libfmt-dev libgtest-dev libcli11-dev nlohmann-json3-dev
  # external C functions: SHA-256 keys of built code (libssl-dev), the
  # Modelica Standard Library's tables read compressed files (zlib1g-dev)
  libssl-dev zlib1g-dev
  gnuplot-nox python3-matplotlib python3-scipy
  # Results, the Python module and sweeps (docs/results.md, docs/python.md).
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-dask python3-distributed
)
# Debian's source packages, for apt-get source sundials.
DEB_SRC_FILE=/etc/apt/sources.list.d/ldaec-deb-src.sources
DEB_SRC_TEXT='# Written by ldaec scripts/install-deps.sh: Debian source packages,
# so scripts/build-sundials.sh can fetch sundials with apt-get source.
Types: deb-src
URIs: http://deb.debian.org/debian
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg'

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

need_update=0
if [ ${#missing[@]} -gt 0 ]; then need_update=1; fi
if [ ! -f "$DEB_SRC_FILE" ] || [ "$(cat "$DEB_SRC_FILE")" != "$DEB_SRC_TEXT" ]; then
  printf '%s\n' "$DEB_SRC_TEXT" | $SUDO tee "$DEB_SRC_FILE" >/dev/null
  need_update=1
fi
# The source index can be missing though the line is there (lists cleaned).
if ! apt-cache showsrc sundials 2>/dev/null | grep -q '^Version: 6\.4\.1'; then
  need_update=1
fi

if [ $need_update -eq 1 ]; then
  $SUDO apt-get update
fi
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
fi

bash "$here/build-sundials.sh"
