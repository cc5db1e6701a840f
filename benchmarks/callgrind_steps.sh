#!/usr/bin/env bash
# benchmarks/callgrind_steps.sh — callgrind instructions/step of every method × problem of lgi_step_count.
#
#   benchmarks/callgrind_steps.sh BUILD_DIR [N1 N2]        (defaults N1 = 1000, N2 = 11000)
#   PROBLEMS="heavy_top" benchmarks/callgrind_steps.sh BUILD_DIR   (only these problems; default: all three)
#   METHODS="split_dmv lgvi" benchmarks/callgrind_steps.sh BUILD_DIR (only these methods; default: all)
#
# The methods are every method lgi_step_count knows (`lgi_step_count --list`), or those of METHODS.
#
# Runs BUILD_DIR/benchmarks/lgi_step_count under `valgrind --tool=callgrind` at N1 and N2 steps and
# prints a markdown table of (Ir(N2) − Ir(N1)) / (N2 − N1): start-up, set-up and printing cancel in
# the difference, so no --toggle-collect is needed. Ir is the "totals:" line of callgrind's out file.
# Keep N1 and N2 multiples of 1000 (the period of lgi_step_count) so both runs cover whole periods.
set -euo pipefail

build=${1:?usage: callgrind_steps.sh BUILD_DIR [N1 N2]}
n1=${2:-1000}
n2=${3:-11000}
exe=$build/benchmarks/lgi_step_count
# Not part of the default build (benchmarks/CMakeLists.txt): built here, up to date.
cmake --build "$build" --target lgi_step_count -j"${JOBS:-2}" > /dev/null ||
  { echo "callgrind_steps.sh: cannot build lgi_step_count in $build (configured with LGI_BUILD_BENCHMARKS=ON?)" >&2; exit 1; }
command -v valgrind > /dev/null || { echo "callgrind_steps.sh: valgrind not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# ir METHOD PROBLEM N: total instructions of one run (the program's stdout is kept in $tmp/out).
ir() {
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$exe" "$1" "$2" "$3" > "$tmp/out" 2> "$tmp/err" ||
    { echo "callgrind_steps.sh: $1 $2 $3 failed:" >&2; cat "$tmp/err" >&2; exit 1; }
  awk '/^totals:/ { print $2 }' "$tmp/cg"
}

echo "| method | problem | instructions/step | Newton updates/step |"
echo "|---|---|---:|---:|"
methods=${METHODS:-$("$exe" --list)}
for method in $methods; do
  for problem in ${PROBLEMS:-heavy_top heavy_top_tilted free_body}; do
    [[ $method == rk4quat && $problem != heavy_top ]] && continue
    a=$(ir "$method" "$problem" "$n1")
    b=$(ir "$method" "$problem" "$n2")
    newton=$(awk '/^newton_per_step/ { print $3 }' "$tmp/out")
    awk -v a="$a" -v b="$b" -v n1="$n1" -v n2="$n2" -v m="$method" -v p="$problem" -v nw="${newton:-—}" \
      'BEGIN { printf "| %s | %s | %.1f | %s |\n", m, p, (b - a) / (n2 - n1), nw }'
  done
done
