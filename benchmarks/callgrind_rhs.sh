#!/usr/bin/env bash
# benchmarks/callgrind_rhs.sh — callgrind instructions per call of the peers' right-hand side, case by case.
#
#   benchmarks/callgrind_rhs.sh BUILD_DIR [N1 N2]        (defaults N1 = 100000, N2 = 300000 calls)
#
# Runs `BUILD_DIR/benchmarks/work_precision --only CASE --rhs-calls N` (the suite's own micro-benchmark loop:
# the right-hand side called through a function pointer, its result kept by a compiler barrier) under
# `valgrind --tool=callgrind` at N1 and N2 calls for every case of scenes/bench and prints JSON
# {"CASE": instructions per call, ...}: (Ir(N2) − Ir(N1)) / (N2 − N1), start-up and loading cancelling in the
# difference. The loop's own few instructions (counter, call, barrier) are included, as they are in the timed ns.
set -euo pipefail

build=${1:?usage: callgrind_rhs.sh BUILD_DIR [N1 N2]}
n1=${2:-100000}
n2=${3:-300000}
root=$(cd "$(dirname "$0")/.." && pwd)
exe=$build/benchmarks/work_precision
[[ -x $exe ]] || { echo "callgrind_rhs.sh: $exe missing (build the target work_precision)" >&2; exit 1; }
command -v valgrind > /dev/null || { echo "callgrind_rhs.sh: valgrind not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

ir() {  # ir CASE N: total instructions of one run
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$exe" --only "$1" --rhs-calls "$2" > /dev/null \
    2> "$tmp/err" || { echo "callgrind_rhs.sh: $1 $2 failed:" >&2; cat "$tmp/err" >&2; exit 1; }
  awk '/^totals:/ { print $2 }' "$tmp/cg"
}

first=1
printf '{'
for scene in "$root"/scenes/bench/*.json; do
  name=$(basename "$scene" .json)
  a=$(ir "$name" "$n1")
  b=$(ir "$name" "$n2")
  ((first)) || printf ', '
  first=0
  printf '"%s": %s' "$name" "$(awk -v a="$a" -v b="$b" -v n1="$n1" -v n2="$n2" 'BEGIN { printf "%.1f", (b - a) / (n2 - n1) }')"
done
printf '}\n'
