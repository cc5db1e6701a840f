#!/usr/bin/env bash
# Builds lgi's fuzzers (fuzz/, clang++ -fsanitize=fuzzer,address,undefined) in their own directory and fuzzes each
# input format for a bounded time or number of inputs; prints the inputs tried per fuzzer; exits non-zero on any
# crash, sanitizer report, leak, timeout or broken reader contract (each harness checks one, fuzz/*_fuzzer.cpp).
#
#   scripts/fuzz.sh [-t SECONDS | -r RUNS] [-f NAME]... [-b BUILD_DIR] [-j JOBS] [-c] [-- LIBFUZZER_ARGS...]
#
#   -t SECONDS    how long to fuzz each fuzzer (default 60); the build is not counted
#   -r RUNS       instead: this many inputs for each fuzzer (the documented long run: -r 1000000)
#   -f NAME       only this fuzzer (repeatable): scene, checkpoint, sweep, part, fit (default: all that were built)
#   -b BUILD_DIR  build directory (default build-fuzz); its corpus/NAME/ keeps what earlier runs found,
#                 artifacts/ holds failing inputs (crash-*, leak-*, timeout-*)
#   -j JOBS       parallel compile jobs (default 2)
#   -c            no fuzzing: line coverage of the readers by BUILD_DIR/corpus and the seeds (llvm-cov,
#                 a build without sanitizers in BUILD_DIR-cov)
#   CXX=clang++-14 scripts/fuzz.sh ...   another clang
#
# Seeds: scenes — every scenes/**/*.json, the JSON examples in README.md and docs/*.md, fuzz/seeds/*.json (the options
# no example scene uses); checkpoints, parts — fuzz/seeds/checkpoint/, fuzz/seeds/part/ (written by lgi run and lgi
# sweep --shard); sweeps — examples/sweep/*.json; fit files and tables — examples/fit/*.json, fuzz/seeds/fit/*.csv.
# The checkpoint, part and fit harnesses read a mode byte first (see each harness): their seeds get one. fuzz/scene.dict
# (JSON tokens and lgi's keys) is every fuzzer's dictionary. Reproduce a failure: BUILD_DIR/NAME_fuzzer FILE.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=60
runs=0
build=build-fuzz
jobs=2
coverage=0
only=()
while getopts "t:r:f:b:j:c" opt; do
  case $opt in
    t) seconds=$OPTARG ;;
    r) runs=$OPTARG ;;
    f) only+=("$OPTARG") ;;
    b) build=$OPTARG ;;
    j) jobs=$OPTARG ;;
    c) coverage=1 ;;
    *) sed -n 2,22p "$0" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[[ "$build" = /* ]] || build=$PWD/$build

cxx=${CXX:-clang++}
command -v "$cxx" >/dev/null || { echo "fuzz.sh: $cxx not found (scripts/install-deps.sh installs clang)" >&2; exit 2; }
"$cxx" --version | head -1 | grep -q clang || { echo "fuzz.sh: $cxx is not clang++ (libFuzzer needs clang)" >&2; exit 2; }

# ---- build ----
start=$(date +%s)
mkdir -p "$build"
cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE= >/dev/null
cmake --build "$build" -j"$jobs" >"$build/build.log" 2>&1 || { cat "$build/build.log" >&2; exit 2; }
echo "fuzz.sh: built the fuzzers in $build in $(($(date +%s) - start)) s (wall)"
names=()
for n in scene checkpoint sweep part fit; do
  [[ -x "$build/${n}_fuzzer" ]] || continue
  if ((${#only[@]} > 0)) && [[ ! " ${only[*]} " == *" $n "* ]]; then continue; fi
  names+=("$n")
done
((${#names[@]} > 0)) || { echo "fuzz.sh: no fuzzer to run (${only[*]:-})" >&2; exit 2; }

# ---- seeds ----
seeds=$build/seeds
rm -rf "$seeds"
for n in "${names[@]}"; do mkdir -p "$seeds/$n" "$build/corpus/$n"; done
mkdir -p "$build/artifacts"
# copy_seed FUZZER FILE [MODE_BYTES...]: FILE as a seed of FUZZER, once per mode byte given (none: as it is).
copy_seed() {
  local n=$1 f=$2 rel
  shift 2
  [[ -d "$seeds/$n" ]] || return 0
  rel=${f#"$root"/}
  rel=${rel//\//_}
  if (($# == 0)); then cp "$f" "$seeds/$n/$rel"; return; fi
  for mode in "$@"; do { printf "\\x$mode"; cat "$f"; } >"$seeds/$n/${mode}_$rel"; done
}
while IFS= read -r -d '' f; do copy_seed scene "$f"; done < <(find "$root/scenes" "$root/fuzz/seeds" -maxdepth 1 -name '*.json' -print0; find "$root/scenes" -mindepth 2 -name '*.json' -print0)
if [[ -d "$seeds/scene" ]]; then
  for doc in "$root/README.md" "$root"/docs/*.md; do
    awk -v out="$seeds/scene/$(basename "$doc" .md)_" '
      /^```json$/ { inside = 1; n++; next }
      /^```$/     { inside = 0; next }
      inside      { print > (out n ".json") }' "$doc"
  done
fi
for f in "$root"/fuzz/seeds/checkpoint/*; do copy_seed checkpoint "$f" 00 01; done
for f in "$root"/examples/sweep/*.json; do copy_seed sweep "$f"; done
for f in "$root"/fuzz/seeds/part/*; do copy_seed part "$f" 00 01; done
for f in "$root"/examples/fit/*.json; do copy_seed fit "$f" 00; done
for f in "$root"/fuzz/seeds/fit/*.csv; do copy_seed fit "$f" 03 05 07; done

# ---- coverage of the corpus (-c) ----
if ((coverage)); then
  cov=$build-cov
  cmake -S "$root/fuzz" -B "$cov" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE= -DLGI_FUZZ_COVERAGE=ON >/dev/null
  cmake --build "$cov" -j"$jobs" >"$cov/build.log" 2>&1 || { cat "$cov/build.log" >&2; exit 2; }
  for n in "${names[@]}"; do
    rm -f "$cov"/*.profraw
    LLVM_PROFILE_FILE="$cov/%p.profraw" "$cov/${n}_fuzzer" -runs=0 "$build/corpus/$n" "$seeds/$n" >"$cov/run_$n.log" 2>&1
    llvm-profdata merge -sparse "$cov"/*.profraw -o "$cov/$n.profdata"
    echo "== $n"
    llvm-cov report "$cov/${n}_fuzzer" -instr-profile="$cov/$n.profdata" "$root"/apps/*.cpp | tail -1
  done
  exit 0
fi

# ---- fuzz ----
# -timeout: an input of these readers runs in microseconds, so one that runs 10 s is a hang; -rss_limit_mb: a leak
# or an allocation the size of the input's numbers is a finding, not the machine's problem.
failed=0
for n in "${names[@]}"; do
  log=$build/fuzz_$n.log
  limit=(-max_total_time="$seconds")
  ((runs > 0)) && limit=(-runs="$runs")
  set +e
  "$build/${n}_fuzzer" "$build/corpus/$n" "$seeds/$n" -dict="$root/fuzz/scene.dict" "${limit[@]}" -max_len=16384 \
    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/artifacts/${n}-" "$@" >"$log" 2>&1
  status=$?
  set -e
  tried=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  echo "fuzz.sh: $n: ${tried:-?} inputs tried, corpus $(find "$build/corpus/$n" -type f | wc -l) inputs, exit status $status"
  if ((status != 0)); then
    failed=1
    echo "fuzz.sh: $n FAILED — the fuzzer's report:" >&2
    grep -vE '^#[0-9]+[[:space:]]+(NEW|REDUCE|pulse|RELOAD)' "$log" | tail -60 >&2
    echo "fuzz.sh: failing inputs in $build/artifacts/$n-* (reproduce: $build/${n}_fuzzer FILE)" >&2
  fi
done
((failed == 0)) || exit 1
echo "fuzz.sh: 0 crashes"
