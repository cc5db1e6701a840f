#!/usr/bin/env bash
# lgi's tests under AddressSanitizer and UndefinedBehaviorSanitizer (g++), in a build directory of their own, with
# -fsanitize=address,undefined -fno-sanitize-recover=all. Every sanitizer report (also those of the `lgi` processes
# the tests start) goes to BUILD_DIR/sanitizer-logs/; the script prints how many there are and exits non-zero if
# any test fails or any report was written.
#
#   scripts/sanitize.sh [-a] [-b BUILD_DIR] [-j JOBS]     (defaults: the input-facing tests, build-sanitize, 2)
#
#   (default)  the input-facing tests — test_scene, test_cli, test_malformed_scenes, test_reliability,
#              test_input_files — and the `lgi` binary they run, without lgi::fit (its Ceres instantiations
#              compiled for over 30 min here under ASan)
#   -a         the whole unit suite (ctest -L unit), lgi::fit and `lgi fit` included: the run to make after a change
#              to the engine, the runner or the integrators (its last result: docs/validation.md)
#
# Compile level -O1, the sanitizers' usual one: these tests are about correctness, not speed. Not in CI (its
# compile cost).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=build-sanitize
jobs=2
all=0
while getopts "ab:j:" opt; do
  case $opt in
    a) all=1 ;;
    b) build=$OPTARG ;;
    j) jobs=$OPTARG ;;
    *) sed -n 2,17p "$0" >&2; exit 2 ;;
  esac
done
[[ "$build" = /* ]] || build=$PWD/$build

# -DLGI_FLATTEN=: no [[gnu::flatten]] (core/scalar.hpp) — flattened, the instrumented runner parts compiled for
# over 50 min; inlining changes no result, and what the sanitizers check is the same code.
flags="-O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -DLGI_FLATTEN="
fit=OFF
targets=(--target lgi_exe test_scene test_cli test_malformed_scenes test_reliability test_input_files)
if ((all)); then
  fit=ON
  targets=()
fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_MODULE_LINKER_FLAGS="-fsanitize=address,undefined" -DLGI_BUILD_BENCHMARKS=OFF -DLGI_BUILD_FIT=$fit >/dev/null
start=$(date +%s)
cmake --build "$build" -j"$jobs" "${targets[@]}"
echo "sanitize.sh: built in $(($(date +%s) - start)) s (wall)"

logs=$build/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
# Reports to files (one per process, the lgi processes included); abort on the first error.
# verify_asan_link_order=0: test_reliability preloads its fault-injection shim (tests/cli/fault_shim.cpp) into `lgi`.
export ASAN_OPTIONS="log_path=$logs/asan:detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:verify_asan_link_order=0"
export UBSAN_OPTIONS="log_path=$logs/ubsan:print_stacktrace=1:halt_on_error=1"
set +e
if ((all)); then
  ctest --test-dir "$build" -L unit --output-on-failure -j"$jobs"
else
  ctest --test-dir "$build" -L unit -R '^(JsonReader|Scene|Cli|MalformedScenes|Reliability|ReliabilityCheckpoint|ReliabilityFit|InputFiles)\.' \
    --output-on-failure -j"$jobs"
fi
status=$?
set -e
reports=$(find "$logs" -type f | wc -l)
echo "sanitize.sh: $reports sanitizer report(s) in $logs"
if ((reports > 0)); then
  cat "$logs"/* >&2
  exit 1
fi
exit "$status"
