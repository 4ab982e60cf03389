#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Second README command: installs what is missing, builds in Release, runs the whole test suite
# (unit, validation, python read-back, case smoke tests).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup-debian.sh
cmake --preset release >/dev/null
cmake --build --preset release -j2
ctest --preset release -j2 "$@"
