#!/usr/bin/env bash
# Installs the Debian 12 packages ldaec needs to build, test and benchmark.
# Idempotent: packages already present are skipped, so re-running is cheap.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build ccache git
  antlr4 libantlr4-runtime-dev
  llvm-19-dev llvm-19-tools
  libsundials-dev libsuitesparse-dev
  libeigen3-dev libfmt-dev libgtest-dev libcli11-dev nlohmann-json3-dev
  gnuplot-nox python3-matplotlib python3-scipy
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update
$SUDO apt-get install -y --no-install-recommends "${missing[@]}"
