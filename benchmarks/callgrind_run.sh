#!/usr/bin/env bash
# benchmarks/callgrind_run.sh — callgrind instructions per step of the `lgi run` command itself (not a benchmark
# program): the scene's method on the heavy top and the free body, one row at the end.
#
#   benchmarks/callgrind_run.sh LGI_EXE [N1 N2]                  (defaults N1 = 2000, N2 = 22000 steps)
#   METHODS="lgvi split_dmv rkmk4" PROBLEMS="heavy_top" benchmarks/callgrind_run.sh build/lgi
#   ADAPTIVE="rkmk_vern9_cayley" ...     methods run adaptively (rtol = atol = 1e-10), per accepted step
#
# Each figure is (Ir(N2) − Ir(N1)) / (steps(N2) − steps(N1)) of `valgrind --tool=callgrind LGI_EXE run SCENE -o
# FILE` (a file, not /dev/null: lgi before 0.1.0's reliability fixes replaced /dev/null by its output file): start-up,
# loading and the summary cancel in the difference. Fixed steps: t_end = N·dt; adaptive runs:
# t_end = N·dt with dt the first step, and the steps are the accepted ones the summary reports. Ir is the
# "totals:" line of callgrind's out file. Prints a markdown table.
set -euo pipefail

exe=${1:?usage: callgrind_run.sh LGI_EXE [N1 N2]}
n1=${2:-2000}
n2=${3:-22000}
command -v valgrind > /dev/null || { echo "callgrind_run.sh: valgrind not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

scene() {  # scene PROBLEM METHOD N ADAPTIVE
  local problem=$1 method=$2 n=$3 adaptive=$4 body dt integrator
  case $problem in
    heavy_top) body='"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.6, 0.8]},
      "initial": {"omega": [0.1, 0.2, 5.0]}'; dt=0.001 ;;
    free_body) body='"problem": {"type": "free_body", "inertia": [1.0, 2.0, 3.0]},
      "initial": {"omega": [1.0, 0.1, 0.1]}'; dt=0.01 ;;
    *) echo "callgrind_run.sh: unknown problem $problem" >&2; exit 1 ;;
  esac
  integrator="\"method\": \"$method\", \"dt\": $dt"
  ((adaptive)) && integrator+=', "rtol": 1e-10, "atol": 1e-10'
  echo "{$body, \"integrator\": {$integrator}, \"t_end\": $(awk -v n="$n" -v h="$dt" 'BEGIN { printf "%.10g", n * h }')}"
}

# run SCENE_FILE: "instructions steps"
run() {
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$exe" run "$1" -o "$tmp/out.csv" 2> "$tmp/err" ||
    { echo "callgrind_run.sh: $1 failed:" >&2; cat "$tmp/err" >&2; exit 1; }
  local steps
  steps=$(sed -n 's/^  steps *\([0-9]*\) to t.*/\1/p' "$tmp/err")
  echo "$(awk '/^totals:/ { print $2 }' "$tmp/cg") $steps"
}

echo "| method | problem | instructions/step |"
echo "|---|---|---:|"
for method in ${METHODS:-lgvi split_dmv rkmk4} ${ADAPTIVE:-}; do
  adaptive=0
  [[ " ${ADAPTIVE:-} " == *" $method "* ]] && adaptive=1
  for problem in ${PROBLEMS:-heavy_top free_body}; do
    scene "$problem" "$method" "$n1" "$adaptive" > "$tmp/a.json"
    scene "$problem" "$method" "$n2" "$adaptive" > "$tmp/b.json"
    read -r ia sa < <(run "$tmp/a.json")
    read -r ib sb < <(run "$tmp/b.json")
    awk -v ia="$ia" -v ib="$ib" -v sa="$sa" -v sb="$sb" -v m="$method$( ((adaptive)) && echo ' (adaptive)')" -v p="$problem" \
      'BEGIN { printf "| %s | %s | %.1f |\n", m, p, (ib - ia) / (sb - sa) }'
  done
done
