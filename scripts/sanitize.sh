#!/usr/bin/env bash
# The input-facing tests under AddressSanitizer and UndefinedBehaviorSanitizer (g++):
# test_scene, test_cli and test_malformed_scenes — and the `lgi` binary they run — in a build directory
# of their own, with -fsanitize=address,undefined -fno-sanitize-recover=all. Every sanitizer report (also
# those of the `lgi` processes the tests start) goes to BUILD_DIR/sanitizer-logs/; the script prints how
# many there are and exits non-zero if any test fails or any report was written.
#
#   scripts/sanitize.sh [-b BUILD_DIR] [-j JOBS]     (defaults: build-sanitize, 2)
#
# Compile level -O1, the sanitizers' usual one: these tests are about input, not speed. Without lgi::fit
# (`lgi fit` is optional; its Ceres instantiations compiled for over 30 min here under ASan). Not in CI
# (its compile cost: see the README).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=build-sanitize
jobs=2
while getopts "b:j:" opt; do
  case $opt in
    b) build=$OPTARG ;;
    j) jobs=$OPTARG ;;
    *) sed -n 2,10p "$0" >&2; exit 2 ;;
  esac
done
[[ "$build" = /* ]] || build=$PWD/$build

# -DLGI_FLATTEN=: no [[gnu::flatten]] (core/scalar.hpp) — flattened, the instrumented runner parts compiled for
# over 50 min; inlining changes no result, and what the sanitizers check is the same code.
flags="-O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -DLGI_FLATTEN="
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DLGI_BUILD_BENCHMARKS=OFF -DLGI_BUILD_FIT=OFF >/dev/null
start=$(date +%s)
cmake --build "$build" -j"$jobs" --target lgi_exe test_scene test_cli test_malformed_scenes
echo "sanitize.sh: built in $(($(date +%s) - start)) s (wall)"

logs=$build/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
# Reports to files (one per process, the lgi processes included); abort on the first error.
export ASAN_OPTIONS="log_path=$logs/asan:detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="log_path=$logs/ubsan:print_stacktrace=1:halt_on_error=1"
set +e
ctest --test-dir "$build" -L unit -R '^(JsonReader|Scene|Cli|MalformedScenes)\.' --output-on-failure -j"$jobs"
status=$?
set -e
reports=$(find "$logs" -type f | wc -l)
echo "sanitize.sh: $reports sanitizer report(s) in $logs"
if ((reports > 0)); then
  cat "$logs"/* >&2
  exit 1
fi
exit "$status"
