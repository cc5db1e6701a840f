#!/usr/bin/env python3
"""What calling lgi from Python costs over the C++ it runs (issue 26's acceptance), measured in one process run:

    PYTHONPATH=build/python /usr/bin/python3 benchmarks/python_overhead.py [--lgi build/lgi]
        [--bench-batch build/benchmarks/bench_batch] [--out build/bench/python_overhead.json]

1. lgi.run against `lgi run` on scenes of 10^4, 10^5 and 10^6 LGVI steps (the seed paper's top, dt = 1e-4, 11 rows):
   the Python call's wall time against the command's own integration time (its summary's "wall time"), and against
   the engine's time inside the Python call (Result.wall_seconds). Interleaved, medians of --runs. The processes'
   comparison carries the machine's noise between processes (a few per cent on a shared VM); the Python layer's own
   cost is measured apart, back to back in one process: the call's time minus the engine's inside it, over
   --back-to-back calls after as many warm-up calls, against the engine's time.
2. lgi.Batch against bench_batch (Google Benchmark, the same kernels): 65,536 Hairer-Vilmart heavy tops drawn as
   bench_batch draws them, calls of 16 steps of 0.01 continuing the same bodies, ns per body-step of the whole
   Python call (step()) against bench_batch's s_per_body_step for the kernel that ran, one thread; and
   lgi.integrate_batch (copies in and out included) with 1,000 steps a call. Rounds interleave the two programs.
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import time

import numpy as np

import lgi

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def seed_top_scene(path, t_end):
    scene = {
        "problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.6, 0.8],
                    "z0": [0.0, 0.0, 1.0]},
        "initial": {"omega": [0.1, 0.2, 5.0]},
        "integrator": {"method": "lgvi", "dt": 1e-4},
        "t_end": t_end,
        "output": {"interval": t_end / 10},
    }
    with open(path, "w") as f:
        json.dump(scene, f)
    return scene


def command_wall(lgi_exe, scene_path):
    """The integration time `lgi run` reports (its summary's wall time line: ns per step × steps), in seconds."""
    r = subprocess.run([lgi_exe, "run", scene_path, "-o", "/dev/null"], capture_output=True, text=True, check=True)
    per_step = float(re.search(r"\(([0-9.eE+-]+) ns/step\)", r.stderr).group(1))
    steps = int(re.search(r"steps\s+([0-9]+) to t", r.stderr).group(1))
    return per_step * 1e-9 * steps


def hv_ensemble(n, seed=2026):
    """bench_batch's ensemble in distribution: uniformly random rotation axes with angles up to pi, body momenta of
    random direction with |J Omega| uniform in [0.5, 2] x |(1.8, 0.4, -0.9)|; J = diag(0.6, 0.8, 1)."""
    rng = np.random.default_rng(seed)
    axis = rng.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    angle = 3.14159 * rng.uniform(size=n)
    K = np.zeros((n, 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    K -= K.transpose(0, 2, 1)
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    R = np.eye(3) + s * K + (1 - c) * (K @ K)
    direction = rng.normal(size=(n, 3))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    m = direction * (np.linalg.norm([1.8, 0.4, -0.9]) * (0.5 + 1.5 * rng.uniform(size=n)))[:, None]
    return R, m / np.array([0.6, 0.8, 1.0])


def bench_batch_ns(binary, kernel, n):
    r = subprocess.run([binary, f"--benchmark_filter=^lgvi_heavy_top/{kernel}/N:{n}/threads:1/",
                        "--benchmark_format=json", "--benchmark_min_time=1"], capture_output=True, text=True, check=True)
    data = json.loads(r.stdout)
    return data["benchmarks"][0]["s_per_body_step"] * 1e9


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lgi", default=os.path.join(ROOT, "build", "lgi"))
    ap.add_argument("--bench-batch", default=os.path.join(ROOT, "build", "benchmarks", "bench_batch"))
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "bench", "python_overhead.json"))
    ap.add_argument("--runs", type=int, default=21)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--back-to-back", type=int, default=201)
    args = ap.parse_args()
    os.makedirs(os.path.dirname(args.out), exist_ok=True)

    # 1. lgi.run against lgi run, at 10^4, 10^5 and 10^6 steps.
    run_report = []
    for t_end in (1.0, 10.0, 100.0):
        scene_path = os.path.join(os.path.dirname(args.out), "python_overhead_scene.json")
        scene = seed_top_scene(scene_path, t_end)
        lgi.run(scene)  # warm
        command, call, engine, first = [], [], [], []
        for _ in range(args.runs):
            command.append(command_wall(args.lgi, scene_path))
            # The first call after the subprocess's wait starts on an idle CPU (its wake-up costs 0.1-0.3 ms whatever
            # runs); the second, back to back, is in the steady state the command's own timer measures.
            start = time.perf_counter()
            lgi.run(scene)
            first.append(time.perf_counter() - start)
            start = time.perf_counter()
            result = lgi.run(scene)
            call.append(time.perf_counter() - start)
            engine.append(result.wall_seconds)
        ratio = np.array(call) / np.array(engine)
        entry = {
            "steps": result.steps, "rows": len(result.t),
            "command_integration_s": statistics.median(command), "python_call_s": statistics.median(call),
            "python_first_call_s": statistics.median(first),
            "call_over_command_quartiles": [float(q) for q in np.percentile(np.array(call) / np.array(command), [25, 75])],
            "engine_inside_python_s": statistics.median(engine),
            "call_over_command": statistics.median(call) / statistics.median(command),
            "call_over_engine": float(np.median(ratio)),
            "call_over_engine_quartiles": [float(q) for q in np.percentile(ratio, [25, 75])],
            "call_minus_engine_us": float(np.median(np.array(call) - np.array(engine))) * 1e6,
        }
        calls = max(5, args.back_to_back if t_end < 50 else args.back_to_back // 10)
        extra, inside = [], []
        for k in range(2 * calls):
            start = time.perf_counter()
            result = lgi.run(scene)
            took = time.perf_counter() - start
            if k >= calls:  # the first half warms up
                extra.append(took - result.wall_seconds)
                inside.append(result.wall_seconds)
        entry["back_to_back_calls"] = calls
        entry["back_to_back_extra_us"] = statistics.median(extra) * 1e6
        entry["back_to_back_extra_quartiles_us"] = [float(q) * 1e6 for q in np.percentile(extra, [25, 75])]
        entry["back_to_back_engine_s"] = statistics.median(inside)
        entry["back_to_back_overhead"] = statistics.median(extra) / statistics.median(inside)
        run_report.append(entry)
        print("lgi.run: %d steps; the command integrates in %.3f ms, the Python call takes %.3f ms (%.3f x, quartiles "
              "%.3f-%.3f; the first call after idle %.3f ms); %.0f us more than the engine's time inside it"
              % (entry["steps"], 1e3 * entry["command_integration_s"], 1e3 * entry["python_call_s"],
                 entry["call_over_command"], *entry["call_over_command_quartiles"], 1e3 * entry["python_first_call_s"],
                 entry["call_minus_engine_us"]))
        print("         back to back: the call costs %.1f us (quartiles %.1f-%.1f) over the engine's %.3f ms: %.2f %%"
              % (entry["back_to_back_extra_us"], *entry["back_to_back_extra_quartiles_us"],
                 1e3 * entry["back_to_back_engine_s"], 100 * entry["back_to_back_overhead"]))

    # 2. lgi.Batch against bench_batch.
    n, steps_per_call = 65536, 16
    R, omega = hv_ensemble(n)
    top = lgi.HeavyTop(inertia=[0.6, 0.8, 1.0], b=1.0, k=[0, 0, 1], z0=[0, 0, 1])
    held = lgi.Batch(top, R, omega, dt=0.01).step(steps_per_call)
    kernel = held.kernel
    cpp, py, whole = [], [], []
    for _ in range(args.rounds):
        cpp.append(bench_batch_ns(args.bench_batch, kernel, n))
        calls = []
        for _ in range(60):
            start = time.perf_counter()
            held.step(steps_per_call)
            calls.append(time.perf_counter() - start)
        py.append(statistics.median(calls) / (n * steps_per_call) * 1e9)
        start = time.perf_counter()
        lgi.integrate_batch(top, R, omega, dt=0.01, steps=1000)
        whole.append((time.perf_counter() - start) / (n * 1000) * 1e9)
    assert all(s == "ok" for s in held.status)
    batch_report = {
        "bodies": n, "kernel": kernel, "steps_per_call": steps_per_call,
        "cpp_ns_per_body_step": statistics.median(cpp), "cpp_rounds": cpp,
        "python_step_ns_per_body_step": statistics.median(py), "python_rounds": py,
        "python_over_cpp": statistics.median(py) / statistics.median(cpp),
        "integrate_batch_1000_steps_ns_per_body_step": statistics.median(whole),
        "integrate_batch_over_cpp": statistics.median(whole) / statistics.median(cpp),
    }
    print("batch: %d heavy tops, kernel %s: bench_batch %.2f ns per body-step, lgi.Batch.step(16) %.2f (%.3f x); "
          "lgi.integrate_batch of 1000 steps, copies included, %.2f (%.3f x)"
          % (n, kernel, batch_report["cpp_ns_per_body_step"], batch_report["python_step_ns_per_body_step"],
             batch_report["python_over_cpp"], batch_report["integrate_batch_1000_steps_ns_per_body_step"],
             batch_report["integrate_batch_over_cpp"]))
    with open(args.out, "w") as f:
        json.dump({"run": run_report, "batch": batch_report, "cpu": cpu_name(), "date": time.strftime("%Y-%m-%d %H:%M")},
                  f, indent=1)
    print("written", args.out)


def cpu_name():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "?"


if __name__ == "__main__":
    main()
