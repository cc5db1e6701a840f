#!/usr/bin/env bash
# scripts/bench.sh — the whole benchmark suite in one command: builds what it needs, runs
# everything in one session, writes the JSON, docs/benchmarks.md and the plots in docs/img/.
#
#   scripts/bench.sh [--smoke] [--no-build] [BUILD_DIR]          (default BUILD_DIR: build-bench)
#
#   1. work_precision      work-precision of lgi and the peers on scenes/bench/*.json, long horizon at equal
#                          CPU time (benchmarks/work_precision.cpp)            -> BUILD_DIR/bench/work_precision.json
#   2. bench_steps         ns/step, Google Benchmark, median of 3 (heavy_top and free_body cases)
#                                                                               -> BUILD_DIR/bench/bench_steps.json
#   3. callgrind_steps.sh  instructions/step of every method on the HV heavy top  -> BUILD_DIR/bench/callgrind.md
#      callgrind_rhs.sh    instructions per call of the peers' right-hand side      -> BUILD_DIR/bench/callgrind_rhs.json
#   4. memory              peak RSS of `lgi run` with output only at t = 0 and t_end, 10^4, 10^6 and 10^8 steps
#                                                                               -> BUILD_DIR/bench/memory.json
#   5. scripts/bench_report.py (Debian's /usr/bin/python3 + matplotlib)  -> docs/benchmarks.md, docs/img/*.png
#
# --no-build: use the binaries already in BUILD_DIR (a tree under edit would otherwise rebuild them first).
# --smoke: tiny sizes (work_precision --smoke, three step benchmarks, memory at 10^4 and 10^5 steps), no
# callgrind, everything written to BUILD_DIR/bench-smoke (report included, not docs/) — a check that the
# pipeline works, not a measurement.
# Runs in about 6 minutes on a 2-core machine once built (the build of lgi_scene and the benchmarks takes
# longer); JOBS (default 2) sets the build parallelism.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
smoke=0
build_first=1
build=$root/build-bench
for arg in "$@"; do
  case $arg in
    --smoke) smoke=1 ;;
    --no-build) build_first=0 ;;
    -h | --help) sed -n '2,22p' "$0"; exit 0 ;;
    -*) echo "bench.sh: unknown option $arg" >&2; exit 1 ;;
    *) build=$arg ;;
  esac
done
py=/usr/bin/python3  # Debian's: the first python3 on PATH may lack matplotlib

if ((build_first)); then
  "$root/scripts/install-deps.sh"
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DLGI_BUILD_BENCHMARKS=ON > /dev/null
  cmake --build "$build" -j"${JOBS:-2}" --target work_precision bench_steps lgi_step_count lgi_exe
fi
for exe in benchmarks/work_precision benchmarks/bench_steps benchmarks/lgi_step_count lgi; do
  [[ -x $build/$exe ]] || { echo "bench.sh: $build/$exe missing (run without --no-build)" >&2; exit 1; }
done
out=$build/bench
((smoke)) && out=$build/bench-smoke  # never overwrite a full run's results
mkdir -p "$out"
start=$(date +%s)

# 1. work-precision and long horizon
if ((smoke)); then
  "$build/benchmarks/work_precision" --smoke --out "$out/work_precision.json"
else
  "$build/benchmarks/work_precision" --out "$out/work_precision.json"
fi

# 2. ns/step (Google Benchmark)
if ((smoke)); then
  "$build/benchmarks/bench_steps" --benchmark_filter='^(split_dmv|lgvi|rk4quat)/heavy_top$' --benchmark_min_time=0.01 \
    --benchmark_out="$out/bench_steps.json" --benchmark_out_format=json > /dev/null
else
  "$build/benchmarks/bench_steps" --benchmark_filter='/(heavy_top|free_body)$' --benchmark_min_time=0.1 \
    --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
    --benchmark_out="$out/bench_steps.json" --benchmark_out_format=json > /dev/null
fi

# 3. instructions/step (callgrind; exact and repeatable)
if ((!smoke)) && command -v valgrind > /dev/null; then
  PROBLEMS=heavy_top "$root/benchmarks/callgrind_steps.sh" "$build" > "$out/callgrind.md"
  "$root/benchmarks/callgrind_rhs.sh" "$build" > "$out/callgrind_rhs.json"
else
  rm -f "$out/callgrind.md" "$out/callgrind_rhs.json"
fi

# 4. memory of long runs that write only their final state: peak RSS (ru_maxrss of the waited child).
if ((smoke)); then steps_list="10000 100000"; else steps_list="10000 1000000 100000000"; fi
"$py" - "$build/lgi" "$root/scenes/bench/hv_free_body.json" "$out" $steps_list <<'EOF'
import json, os, subprocess, sys, time
lgi, base, out, steps = sys.argv[1], sys.argv[2], sys.argv[3], [int(s) for s in sys.argv[4:]]
scene = json.load(open(base))
rows = []
for n in steps:
    s = dict(scene)
    s["description"] = "memory probe (scripts/bench.sh): %d steps, rows only at t = 0 and t_end" % n
    s["integrator"] = {"method": "split_dmv", "dt": 0.01}
    s["t_end"] = n * 0.01
    s["output"] = {"every": 10**12}
    path = os.path.join(out, "memory_%d.json" % n)
    json.dump(s, open(path, "w"), indent=1)
    csv = os.path.join(out, "memory_%d.csv" % n)
    t0 = time.time()
    p = subprocess.Popen([lgi, "run", "-q", path, "-o", csv])
    _, status, ru = os.wait4(p.pid, 0)
    if status != 0:
        sys.exit("bench.sh: lgi run %s failed (status %d)" % (path, status))
    rows.append({"steps": n, "method": "split_dmv", "dt": 0.01, "peak_rss_kib": ru.ru_maxrss,
                 "wall_seconds": time.time() - t0, "csv_rows": sum(1 for _ in open(csv)) - 1})
    print("memory: %d steps, peak RSS %d KiB, %.1f s" % (n, ru.ru_maxrss, rows[-1]["wall_seconds"]), file=sys.stderr)
json.dump({"scene": os.path.relpath(base), "runs": rows}, open(os.path.join(out, "memory.json"), "w"), indent=1)
EOF

# 5. report
docs=$root/docs
((smoke)) && docs=$out/docs
"$py" "$root/scripts/bench_report.py" --results "$out" --docs "$docs"
echo "bench.sh: done in $(($(date +%s) - start)) s: $out/*.json, $docs/benchmarks.md, $docs/img/" >&2
