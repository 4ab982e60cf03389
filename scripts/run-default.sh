#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# First README command: installs what is missing, builds in Release, runs the default case.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup-debian.sh
cmake --preset release >/dev/null
cmake --build --preset release -j2
./build/release/grainflow run cases/dem/terrain_settling/case.yaml --output out/terrain_settling --overwrite "$@"
echo "output: $(pwd)/out/terrain_settling (open particles.pvd and walls.pvd in ParaView)"
