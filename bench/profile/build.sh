#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the profiling helpers of bench/profile (not part of the CMake build):
#   stream       STREAM-like triad, 1..T threads (OpenMP)
#   list_stats   neighbour-list statistics of a checkpoint (HDF5 C API)
# Usage: bench/profile/build.sh [outdir]   (default: build/profile-tools)
set -e
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-$here/../../build/profile-tools}
mkdir -p "$out"
CXX=${CXX:-g++}
$CXX -std=c++20 -O3 -march=native -fopenmp "$here/stream.cpp" -o "$out/stream"
$CXX -std=c++20 -O2 -I/usr/include/hdf5/serial "$here/list_stats.cpp" -o "$out/list_stats" \
  -L/usr/lib/x86_64-linux-gnu/hdf5/serial -lhdf5
echo "built $out/stream $out/list_stats"
