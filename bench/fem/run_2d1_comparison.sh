#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Side-by-side 2D-1 (Schaefer-Turek, Re = 20): grainflow fluid_fem vs dolfinx on the same meshes,
# same machine, same run, one thread each. Writes bench/fem/results_2d1.csv; then
# bench/fem/make_results.py turns it into bench/RESULTS-fem.md.
# Usage: bench/fem/run_2d1_comparison.sh <build dir> [repeats]
set -euo pipefail
build=${1:-build/fem}
reps=${2:-3}
here=$(cd "$(dirname "$0")" && pwd)
exe=$build/tests/fem/gf_fem_bench_st_2d1
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
out=$here/results_2d1.csv
tmp=$(mktemp -d)
echo "code,variant,h_body,h_max,cells,dofs,newton_it,factorizations,cd,cl,dp,cd_err,cl_err,dp_err,t_solve,t_total" > "$out.tmp"
# mesh levels: h_body h_max
levels=("0.01 0.08" "0.005 0.04" "0.0025 0.02" "0.00125 0.01")
/usr/bin/python3 "$here/dolfinx_2d1.py" /dev/null >/dev/null 2>&1 || true
first=1
for lv in "${levels[@]}"; do
  set -- $lv
  hb=$1; hm=$2
  for variant in full reuse nested; do
    best=""
    for r in $(seq "$reps"); do
      line=$("$exe" "$hb" "$hm" 0.2 "$variant" "$tmp/mesh.txt" | tail -1)
      t=$(echo "$line" | cut -d, -f21)
      if [ -z "$best" ] || awk "BEGIN{exit !($t < $(echo "$best" | cut -d, -f21))}"; then best=$line; fi
    done
    IFS=, read -r h_body h_max cells dofs it fac conv cd cl dp cde cle dpe cds cls tm tset tsol tasm tfac ttot <<< "$best"
    echo "grainflow,$variant,$h_body,$h_max,$cells,$dofs,$it,$fac,$cd,$cl,$dp,$cde,$cle,$dpe,$tsol,$ttot" >> "$out.tmp"
  done
  if [ $first = 1 ]; then  # warm dolfinx's JIT cache so that compilation is not timed
    /usr/bin/python3 "$here/dolfinx_2d1.py" "$tmp/mesh.txt" > /dev/null 2>&1; first=0
  fi
  best=""
  for r in $(seq "$reps"); do
    line=$(/usr/bin/python3 "$here/dolfinx_2d1.py" "$tmp/mesh.txt" 2>/dev/null | tail -1)
    t=$(echo "$line" | cut -d, -f16)
    if [ -z "$best" ] || awk "BEGIN{exit !($t < $(echo "$best" | cut -d, -f16))}"; then best=$line; fi
  done
  IFS=, read -r cells dofs it conv cd cl dp cde cle dpe cds cls tset tsol tpost ttot <<< "$best"
  echo "dolfinx,newton_mumps,$hb,$hm,$cells,$dofs,$it,$it,$cd,$cl,$dp,$cde,$cle,$dpe,$tsol,$ttot" >> "$out.tmp"
done
mv "$out.tmp" "$out"
rm -rf "$tmp"
/usr/bin/python3 "$here/make_results.py" "$out" "$here/../RESULTS-fem.md"
