#!/usr/bin/env bash
# Builds the scene-loader fuzzer (fuzz/, clang++ -fsanitize=fuzzer,address,undefined) in its own
# directory and fuzzes it for a bounded time; prints the number of inputs tried; exits non-zero on any
# crash, sanitizer report, leak, timeout or broken loader contract (fuzz/scene_fuzzer.cpp).
#
#   scripts/fuzz.sh [-t SECONDS] [-b BUILD_DIR] [-j JOBS] [-c] [-- LIBFUZZER_ARGS...]
#
#   -t SECONDS    how long to fuzz (default 60); the build is not counted
#   -b BUILD_DIR  build directory (default build-fuzz); its corpus/ keeps what earlier runs found,
#                 artifacts/ holds crashing inputs (crash-*, leak-*, timeout-*)
#   -j JOBS       parallel compile jobs (default 2)
#   -c            no fuzzing: line coverage of the loader by BUILD_DIR/corpus and the seeds (llvm-cov,
#                 a build without sanitizers in BUILD_DIR-cov)
#   CXX=clang++-14 scripts/fuzz.sh ...   another clang
#
# Seeds: every scenes/**/*.json, the JSON examples in README.md and docs/*.md, and fuzz/seeds/*.json
# (the options no example scene uses: tolerance, axis_order, limits, ...), plus fuzz/scene.dict
# (JSON tokens and scene keys) as libFuzzer's dictionary. Reproduce a crash: BUILD_DIR/scene_fuzzer FILE.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=60
build=build-fuzz
jobs=2
coverage=0
while getopts "t:b:j:c" opt; do
  case $opt in
    t) seconds=$OPTARG ;;
    b) build=$OPTARG ;;
    j) jobs=$OPTARG ;;
    c) coverage=1 ;;
    *) sed -n 2,16p "$0" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[[ "$build" = /* ]] || build=$PWD/$build

cxx=${CXX:-clang++}
command -v "$cxx" >/dev/null || { echo "fuzz.sh: $cxx not found (scripts/install-deps.sh installs clang)" >&2; exit 2; }
"$cxx" --version | head -1 | grep -q clang || { echo "fuzz.sh: $cxx is not clang++ (libFuzzer needs clang)" >&2; exit 2; }

# ---- build ----
start=$(date +%s)
cmake -S "$root/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE= >/dev/null
cmake --build "$build" -j"$jobs" >"$build/build.log" 2>&1 || { cat "$build/build.log" >&2; exit 2; }
echo "fuzz.sh: built $build/scene_fuzzer in $(($(date +%s) - start)) s (wall)"

# ---- seeds ----
seeds=$build/seeds
rm -rf "$seeds"
mkdir -p "$seeds" "$build/corpus" "$build/artifacts"
while IFS= read -r -d '' f; do
  rel=${f#"$root"/}
  cp "$f" "$seeds/${rel//\//_}"
done < <(find "$root/scenes" "$root/fuzz/seeds" -name '*.json' -print0)
for doc in "$root/README.md" "$root"/docs/*.md; do
  awk -v out="$seeds/$(basename "$doc" .md)_" '
    /^```json$/ { inside = 1; n++; next }
    /^```$/     { inside = 0; next }
    inside      { print > (out n ".json") }' "$doc"
done
echo "fuzz.sh: $(find "$seeds" -type f | wc -l) seeds, $(find "$build/corpus" -type f | wc -l) inputs in the corpus from earlier runs"

# ---- coverage of the corpus (-c) ----
if ((coverage)); then
  cov=$build-cov
  cmake -S "$root/fuzz" -B "$cov" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE= -DLGI_FUZZ_COVERAGE=ON >/dev/null
  cmake --build "$cov" -j"$jobs" >"$cov/build.log" 2>&1 || { cat "$cov/build.log" >&2; exit 2; }
  rm -f "$cov"/*.profraw
  LLVM_PROFILE_FILE="$cov/%p.profraw" "$cov/scene_fuzzer" -runs=0 "$build/corpus" "$seeds" >"$cov/run.log" 2>&1
  llvm-profdata merge -sparse "$cov"/*.profraw -o "$cov/all.profdata"
  llvm-cov report "$cov/scene_fuzzer" -instr-profile="$cov/all.profdata" \
    "$root"/apps/json_reader.cpp "$root"/apps/scene.cpp "$root"/apps/registry.cpp "$root"/apps/problems_*.cpp
  exit 0
fi

# ---- fuzz ----
# -timeout: ten steps take microseconds, so an input that runs 10 s is a hang; -rss_limit_mb: a
# leak or an allocation the size of the input's numbers is a finding, not the machine's problem.
log=$build/fuzz.log
set +e
"$build/scene_fuzzer" "$build/corpus" "$seeds" -dict="$root/fuzz/scene.dict" -max_total_time="$seconds" \
  -max_len=16384 -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/artifacts/" "$@" \
  >"$log" 2>&1
status=$?
set -e

runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | tail -1 || true
echo "fuzz.sh: ${runs:-?} inputs tried in ${seconds} s, corpus $(find "$build/corpus" -type f | wc -l) inputs, exit status $status"
if ((status != 0)); then
  echo "fuzz.sh: FAILED — the fuzzer's report:" >&2
  grep -vE '^#[0-9]+[[:space:]]+(NEW|REDUCE|pulse|RELOAD)' "$log" | tail -60 >&2
  echo "fuzz.sh: crashing inputs in $build/artifacts/ (reproduce: $build/scene_fuzzer FILE)" >&2
  exit 1
fi
echo "fuzz.sh: 0 crashes"
