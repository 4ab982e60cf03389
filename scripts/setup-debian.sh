#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Installs the Debian 12 packages grainflow needs; idempotent, and quick when all are present.
set -euo pipefail

# Build and test dependencies of the program itself.
PKGS=(
  build-essential cmake ninja-build pkg-config git
  libyaml-cpp-dev libcli11-dev libfmt-dev libspdlog-dev libeigen3-dev
  libhdf5-dev libgtest-dev libgmock-dev googletest
  libcgal-dev libgmp-dev libmpfr-dev libsuitesparse-dev
  python3 python3-numpy python3-matplotlib python3-vtk9
)
# Peers for side-by-side benchmarks (bench/ only): pass --bench.
BENCH_PKGS=(liggghts lammps python3-dolfinx openfoam hyperfine valgrind time)

want=("${PKGS[@]}")
if [[ "${1:-}" == "--bench" ]]; then want+=("${BENCH_PKGS[@]}"); fi

missing=()
for p in "${want[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#want[@]} packages present"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "setup: missing packages: ${missing[*]}; run this script as root (or install them with apt-get)" >&2
  exit 1
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
