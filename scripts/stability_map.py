#!/usr/bin/python3
"""scripts/stability_map.py -- the stability map: for every method and stress regime, the largest
h|Omega| with bounded energy and a finite state, measured by running the `lgi` command.

    scripts/stability_map.py --lgi build/lgi            # full map: 10 regimes, 8468 runs, ~7 min on 1 busy core
    scripts/stability_map.py --lgi build/lgi --quick    # a few seconds: 5 methods, the free body, short runs

writes benchmarks/stability_map.json (every run's figures) and docs/stability.md (the table); --quick writes
build/stability_map_quick.json and build/stability_quick.md (beside the binary) unless told otherwise. Nothing here
compiles anything: each point of the map is a scene file written to a temporary directory and run by
`lgi run SCENE -q`, CSV on stdout (so that a run that fails has written its rows up to the failure),
stderr and the exit status kept (0 completed, 2 a step failed: not_converged or non_finite).

Definitions (docs/stability.md repeats them):
- h|Omega| is the step times |Omega(0)|, the body angular velocity at t = 0 (the regimes list how far |Omega(t)|
  moves from it). Each regime runs `periods` rotations: t_end = periods * 2 pi / |Omega(0)|, so that every
  step size sees the same total angle; rows are written every k steps (about `rows` of them), t = 0 and
  t_end included, and the energy error is the largest over those rows.
- A run is STABLE when it completes (exit 0), every number it wrote is finite, the relative energy error
  max_rows |E(t) - E(0)| / |E(0)| stays <= 1e-2 over the whole horizon (so also no growth beyond 1e-2), and
  so do the momentum error (free body: |m(t) - m(0)| / |m(0)| with m = R J Omega; tops: |m.k(t) - m.k(0)| /
  |J Omega(0)|) and ||R^T R - I||. The free body's energy depends on Omega only: without the momentum, whose
  direction is carried by R, a method could turn R into anything and still pass; and a state 1e-2 off
  SO(3) (the baselines that do not renormalise) is no rigid-body state.
- The threshold h* is found on a log grid of h|Omega| from 0.01 to pi (`points` points), then refined by
  bisection in log h between the last stable grid point and the next one (`bisections` steps): h* is the
  largest h|Omega| such that every grid point up to it and the bisection point itself are stable. Stable
  grid points above the first failure ("islands") are listed too.
- The failure mode is that of the smallest unstable h|Omega| found: not_converged or non_finite (exit 2),
  energy_grows (completed, energy error > 1e-2 and its largest value in the last quarter of the run more
  than 4x that in the first quarter) or energy_large (completed, > 1e-2 but not growing that way),
  momentum (energy within 1e-2, momentum not), off_group (||R^T R - I|| > 1e-2 alone), and the
  findings: crash (killed by a signal), hang (timeout), error (any other exit status), nan_written
  (exit 0 with a non-finite number in the CSV).
- Garbage-but-finite: a completed run of a method whose traits claim R on SO(3) with ||R^T R - I|| > 1e-9,
  or claim momentum with |m - m0| / |m0| > 1e-9 (free body: m = R J Omega; tops: m.k), or whose first row
  differs from the scene's initial state by more than 1e-12, is a finding whatever its energy.

Only the Python standard library is used (any python3 >= 3.8); the repository's scripts run under Debian's
/usr/bin/python3.
"""
import argparse
import concurrent.futures
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import threading
import time

ENERGY_TOL = 1e-2        # bounded energy: max relative energy error over the run (momentum, ||R^T R - I|| alike)
GROWTH_FACTOR = 4.0      # energy_grows: last-quarter max > 4 x first-quarter max
CLAIM_TOL = 1e-9         # garbage-but-finite: a claimed exact invariant off by more than this
INITIAL_TOL = 1e-12      # the t = 0 row against the scene's initial state
ORTHO_CLAIM = 1e-12      # the "exact orthogonality" column: ||R^T R - I|| <= 1e-12 over the run
H_MIN, H_MAX = 0.01, math.pi

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


# --------------------------------------------------------------------------------------------------------
# small linear algebra on lists (no numpy: the smoke test runs with any python3)

def matvec(A, x):
    return [sum(A[i][j] * x[j] for j in range(3)) for i in range(3)]


def norm(x):
    return math.sqrt(sum(v * v for v in x))


def rotation(axis, angle):
    """Rodrigues: exp(angle * hat(axis / |axis|))."""
    n = norm(axis)
    a = [v / n for v in axis]
    c, s = math.cos(angle), math.sin(angle)
    K = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]]
    K2 = [[sum(K[i][k] * K[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return [[(1.0 if i == j else 0.0) + s * K[i][j] + (1 - c) * K2[i][j] for j in range(3)] for i in range(3)]


def inertia_matrix(inertia):
    if isinstance(inertia[0], list):
        return inertia
    return [[inertia[i] if i == j else 0.0 for j in range(3)] for i in range(3)]


# --------------------------------------------------------------------------------------------------------
# the regimes

def regimes():
    hv_omega = [3.0, 0.5, -0.9]  # Hairer-Vilmart: I = (0.6, 0.8, 1.0), m0 = I Omega0 = (1.8, 0.4, -0.9)
    hv_norm = norm(hv_omega)
    fast = 1e4
    a = 0.1  # separatrix of I = (1, 2, 3): 2 E I2 = |m|^2  <=>  m3 = sqrt(3) m1
    m_sep = [a, math.sqrt(1 - 4 * a * a), math.sqrt(3) * a]
    near_pi = rotation([1.0, 2.0, 2.0], math.pi - 1e-6)
    return [
        {"id": "free_body", "title": "free body (Hairer-Vilmart)",
         "note": "I = (0.6, 0.8, 1.0), m0 = (1.8, 0.4, -0.9), R0 = 1",
         "problem": {"type": "free_body", "inertia": [0.6, 0.8, 1.0]},
         "omega": hv_omega},
        {"id": "skew_top", "title": "heavy top, non-diagonal inertia",
         "note": "scenes/heavy_top_tilted.json: J = [[0.8, 0.1, -0.05], [0.1, 0.7, 0.05], [-0.05, 0.05, 0.9]], "
                 "b = 1, k = e3, z0 = (0.48, 0.6, 0.64), Omega0 = (2, 1, -1)",
         "problem": {"type": "heavy_top", "inertia": [[0.8, 0.1, -0.05], [0.1, 0.7, 0.05], [-0.05, 0.05, 0.9]],
                     "b": 1.0, "k": [0.0, 0.0, 1.0], "z0": [0.48, 0.6, 0.64]},
         "omega": [2.0, 1.0, -1.0]},
        {"id": "fast_spin", "title": "spin 1e4 rad/s",
         "note": "the free body above with Omega0 scaled to |Omega0| = 1e4 rad/s (h = h|Omega| / 1e4, same total "
                 "angle)",
         "problem": {"type": "free_body", "inertia": [0.6, 0.8, 1.0]},
         "omega": [v * fast / hv_norm for v in hv_omega]},
        {"id": "flat_disc", "title": "flat disc I3 = I1 + I2",
         "note": "free body I = (1, 1.001, 2.001) (a lamina: the triangle inequality is an equality), "
                 "Omega0 = (0.3, 0.2, 1)",
         "problem": {"type": "free_body", "inertia": [1.0, 1.001, 2.001]},
         "omega": [0.3, 0.2, 1.0]},
        {"id": "thin_rod", "title": "thin rod, ratio 1e6",
         "note": "free body I = (1, 1e6, 1e6 + 0.5) (I1 + I2 - I3 = I1/2), Omega0 = (1, 1e-3, 2e-3): spin about the "
                 "rod and tumbling carry comparable energy",
         "problem": {"type": "free_body", "inertia": [1.0, 1e6, 1e6 + 0.5]},
         "omega": [1.0, 1e-3, 2e-3]},
        {"id": "separatrix", "title": "intermediate-axis separatrix",
         "note": "free body I = (1, 2, 3), m0 = (0.1, sqrt(0.96), 0.1 sqrt(3)) on the separatrix 2 E I2 = |m|^2 "
                 "(to rounding)",
         "problem": {"type": "free_body", "inertia": [1.0, 2.0, 3.0]},
         "omega": [m_sep[0] / 1.0, m_sep[1] / 2.0, m_sep[2] / 3.0]},
        {"id": "sleeping_top", "title": "sleeping top (axis along k)",
         "note": "lagrange_top I = (2, 2, 1), b = 1, k = e3, R0 = 1 (symmetry axis along k, where Euler angles are "
                 "singular), Omega0 = (0.02, 0, 5) (I3^2 Omega3^2 = 25 > 4 b I1 = 8: stable)",
         "problem": {"type": "lagrange_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.0, 1.0]},
         "omega": [0.02, 0.0, 5.0]},
        {"id": "near_pi_free", "title": "free body, R0 near pi",
         "note": "the free body of the first column started at R0 = rotation by pi - 1e-6 about (1, 2, 2)/3: the "
                 "same body motion, m(t) = R0 m_first(t); compared with the first column below",
         "problem": {"type": "free_body", "inertia": [0.6, 0.8, 1.0]},
         "R": near_pi, "omega": hv_omega},
        {"id": "near_pi", "title": "heavy top, R0 near pi",
         "note": "the Hairer-Vilmart heavy top (I = (0.6, 0.8, 1.0), b = 1, k = z0 = e3) started at R0 = rotation by "
                 "pi - 1e-6 about (1, 2, 2)/3, Omega0 = (3, 0.5, -0.9)",
         "problem": {"type": "heavy_top", "inertia": [0.6, 0.8, 1.0], "b": 1.0, "k": [0.0, 0.0, 1.0],
                     "z0": [0.0, 0.0, 1.0]},
         "R": near_pi, "omega": hv_omega},
        {"id": "near_pi_ref", "title": "its reference, R0 = 1",
         "note": "the same motion as the previous column written in a rotated laboratory frame: R0 = 1, "
                 "k = R0^T e3 (then R(t) = R0^T R_previous(t), with the same energy and m.k); compared below",
         "problem": {"type": "heavy_top", "inertia": [0.6, 0.8, 1.0], "b": 1.0,
                     "k": [near_pi[2][0], near_pi[2][1], near_pi[2][2]], "z0": [0.0, 0.0, 1.0]},
         "omega": hv_omega},
    ]


# --------------------------------------------------------------------------------------------------------
# running lgi

def lgi_methods(lgi):
    """The methods of `lgi list --markdown`, with the traits the checks use."""
    r = subprocess.run([lgi, "list", "--markdown"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit("stability_map: `%s list --markdown` failed (exit %d): %s" % (lgi, r.returncode, r.stderr))
    out = r.stdout
    methods = []
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 8 or not cells[0].startswith("`"):
            continue
        methods.append({"name": cells[0].strip("`"), "order": cells[1], "symplectic": cells[2] == "yes",
                        "on_group": cells[5] == "yes", "momentum": cells[6] == "yes", "title": cells[7]})
    if not methods:
        raise SystemExit("stability_map: `%s list --markdown` listed no methods" % lgi)
    return methods


def lgi_version(lgi):
    r = subprocess.run([lgi, "--version"], capture_output=True, text=True)
    return (r.stdout or r.stderr).strip()


def scene_for(regime, method, x, periods, rows, t_end_override=None):
    w = norm(regime["omega"])
    dt = x / w
    t_end = t_end_override if t_end_override is not None else periods * 2 * math.pi / w
    steps = max(1, math.ceil(t_end / dt - 1e-9))
    initial = {"omega": regime["omega"]}
    if "R" in regime:
        initial["R"] = regime["R"]
    scene = {"description": "stability map: %s, %s, h|Omega| = %.6g" % (regime["id"], method, x),
             "problem": regime["problem"], "initial": initial,
             "integrator": {"method": method, "dt": dt}, "t_end": t_end}
    if t_end > 0:
        scene["output"] = {"every": max(1, steps // rows)}
    return scene, steps


def run_scene(lgi, scene, workdir, tag, timeout):
    path = os.path.join(workdir, tag + ".json")
    csv_path = os.path.join(workdir, tag + ".csv")
    with open(path, "w") as f:
        json.dump(scene, f)
    start = time.monotonic()
    try:
        with open(csv_path, "w") as out:
            r = subprocess.run([lgi, "run", path, "-q"], stdout=out, stderr=subprocess.PIPE, text=True,
                               timeout=timeout)
        rc, err = r.returncode, r.stderr.strip()
    except subprocess.TimeoutExpired:
        rc, err = None, "timeout after %g s" % timeout
    wall = time.monotonic() - start
    with open(csv_path) as f:
        text = f.read()
    os.unlink(path)
    os.unlink(csv_path)
    return rc, err, text, wall


def parse_csv(text):
    lines = [l for l in text.splitlines() if l.strip()]
    if not lines:
        return [], []
    header = lines[0].split(",")
    rows = []
    for l in lines[1:]:
        try:
            rows.append([float(v) for v in l.split(",")])
        except ValueError:
            rows.append(None)  # a malformed row: counted as non-finite
    return header, rows


def measure(regime, method, x, rc, err, text):
    """One run's figures and its classification."""
    header, rows = parse_csv(text)
    res = {"x": x, "exit": rc, "rows": len(rows)}
    col = {name: i for i, name in enumerate(header)}
    finite = all(r is not None and all(math.isfinite(v) for v in r) for r in rows)
    good = [r for r in rows if r is not None and all(math.isfinite(v) for v in r)]
    res["finite"] = finite
    if good and "energy" in col:
        e0 = good[0][col["energy"]]
        errs = [abs(r[col["energy"]] - e0) / abs(e0) for r in good]
        res["energy_error"] = max(errs)
        q = max(1, len(errs) // 4)
        res["energy_first_quarter"] = max(errs[:q])
        res["energy_last_quarter"] = max(errs[-q:])
        res["orthogonality"] = max(r[col["orthogonality_error"]] for r in good)
        # ||R^T R - I|| over every row written (inf where that column itself is not finite)
        oc = [r[col["orthogonality_error"]] if r is not None else math.inf for r in rows]
        res["ortho_rows"] = max(v if math.isfinite(v) else math.inf for v in oc)
        res["t_last"] = good[-1][col["t"]]
        # momentum: free body m = R J Omega (columns momentum_1..3); tops m.k, relative to |J Omega0|
        J = inertia_matrix(regime["problem"]["inertia"])
        m0_norm = norm(matvec(J, regime["omega"]))
        if "momentum_1" in col:
            m0 = [good[0][col["momentum_%d" % i]] for i in (1, 2, 3)]
            res["momentum_error"] = max(norm([r[col["momentum_%d" % i]] - m0[i - 1] for i in (1, 2, 3)])
                                        for r in good) / m0_norm
        elif "momentum_k" in col:
            mk0 = good[0][col["momentum_k"]]
            res["momentum_error"] = max(abs(r[col["momentum_k"]] - mk0) for r in good) / m0_norm
        # the t = 0 row against the scene's initial state
        R0 = regime.get("R", [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
        d = max([abs(good[0][col["R%d%d" % (i + 1, j + 1)]] - R0[i][j]) for i in range(3) for j in range(3)] +
                [abs(good[0][col["omega%d" % (i + 1)]] - regime["omega"][i]) / norm(regime["omega"])
                 for i in range(3)])
        res["initial_row_error"] = d
    # classification
    if rc is None:
        status = "hang"
    elif rc < 0:
        status = "crash"
    elif rc == 2:
        low = err.lower()
        if "converge" in low:
            status = "not_converged"
        elif "non-finite" in low or "non_finite" in low or "not finite" in low:
            # "not finite": rows dropped because energy or an invariant overflowed (the runner exits 2)
            status = "non_finite"
        else:
            status = "failed_other"
    elif rc != 0:
        status = "error"
    elif not finite:
        status = "nan_written"
    elif "energy_error" not in res:
        status = "error"
    elif res["energy_error"] > ENERGY_TOL:
        status = ("energy_grows" if res["energy_last_quarter"] > GROWTH_FACTOR * res["energy_first_quarter"]
                  else "energy_large")
    elif res.get("momentum_error", 0.0) > ENERGY_TOL:
        status = "momentum"
    elif res["orthogonality"] > ENERGY_TOL:
        status = "off_group"
    else:
        status = "stable"
    res["energy_ok"] = "energy_error" in res and res["exit"] == 0 and finite and res["energy_error"] <= ENERGY_TOL
    res["status"] = status
    if rc not in (0, None) and err:
        res["message"] = err.splitlines()[-1][:400]
    return res


def garbage(method, res):
    """Claims of the method's traits that a completed run broke, or a wrong first row."""
    out = []
    if res.get("exit") != 0 or "energy_error" not in res:
        return out
    if method["on_group"] and res["orthogonality"] > CLAIM_TOL:
        out.append("||R^T R - I|| = %.3g although the method keeps R on SO(3)" % res["orthogonality"])
    if method["momentum"] and res.get("momentum_error", 0) > CLAIM_TOL:
        out.append("momentum changed by %.3g (relative to |J Omega0|) although the method conserves it"
                   % res["momentum_error"])
    if res.get("initial_row_error", 0) > INITIAL_TOL:
        out.append("the t = 0 row differs from the scene's initial state by %.3g" % res["initial_row_error"])
    return out


class Runner:
    def __init__(self, args, workdir):
        self.args = args
        self.workdir = workdir
        self.counter = 0
        self.findings = []
        self.silent = []
        self.lock = threading.Lock()

    def run(self, regime, method, x):
        with self.lock:
            self.counter += 1
            tag = "run%d" % self.counter
        scene, steps = scene_for(regime, method["name"], x, self.args.periods, self.args.rows)
        rc, err, text, wall = run_scene(self.args.lgi, scene, self.workdir, tag, self.args.timeout)
        res = measure(regime, method, x, rc, err, text)
        res["steps"] = steps
        res["wall"] = round(wall, 4)
        bad = garbage(method, res)
        if res["exit"] == 2 and not res["finite"]:
            bad.append("a failed run (exit 2) wrote a non-finite number before failing")
        if bad:
            res["garbage"] = bad
        # silent garbage: completed (exit 0, every number finite) with a state that is no longer the body's --
        # energy or momentum off by more than 100 %, or R farther than 1 from SO(3). A property of the method
        # (an explicit method blowing up without overflowing), listed apart from lgi's own defects.
        if res["status"] in ("energy_grows", "energy_large", "momentum", "off_group") and (
                res["energy_error"] > 1 or res.get("momentum_error", 0) > 1 or res["orthogonality"] > 1):
            res["silent_garbage"] = True
            with self.lock:
                self.silent.append({"regime": regime["id"], "method": method["name"], "h_omega": x,
                                    "energy_error": res["energy_error"], "momentum_error": res.get("momentum_error"),
                                    "orthogonality": res["orthogonality"]})
        if res["status"] in ("hang", "crash", "error", "nan_written", "failed_other") or bad:
            with self.lock:
                self.findings.append({"regime": regime["id"], "method": method["name"], "h_omega": x,
                                      "status": res["status"], "exit": rc, "detail": bad or [err[-400:]],
                                      "scene": scene})
        return res


def compare(a_id, b_id, ra, rb):
    """Thresholds and energy errors of two regimes that are the same motion. Ratios of energy errors where
    truncation dominates (> 1e-12), per method; methods whose ratios leave [0.9, 1.1] are listed apart."""
    same, methods, ratios, round_off, differ, outliers = 0, 0, [], [0.0, 0.0], [], []
    for name, a in ra.items():
        b = rb.get(name)
        if not b:
            continue
        methods += 1
        if a["h_star"] == b["h_star"]:
            same += 1
        else:
            differ.append([name, a["h_star"], b["h_star"]])
        mine = []
        for x, y in zip(a["runs"], b["runs"]):
            if x.get("bisection") or y.get("bisection") or not (x["status"] == y["status"] == "stable"):
                continue
            if y["energy_error"] > 1e-12:  # truncation error: the same number expected
                mine.append(x["energy_error"] / y["energy_error"])
            else:  # rounding: compare sizes
                round_off = [max(round_off[0], x["energy_error"]), max(round_off[1], y["energy_error"])]
        if mine and (min(mine) < 0.9 or max(mine) > 1.1):
            outliers.append([name, min(mine), max(mine)])
        else:
            ratios += mine
    ratios.sort()
    return {"regime": a_id, "reference": b_id, "methods": methods, "same_threshold": same, "differ": differ,
            "truncation_runs": len(ratios), "ratio_min": ratios[0] if ratios else None,
            "ratio_max": ratios[-1] if ratios else None, "outliers": outliers, "round_off_max": round_off}


def grid(points):
    if points == 1:
        return [H_MIN]
    r = (H_MAX / H_MIN) ** (1.0 / (points - 1))
    g = [H_MIN * r ** i for i in range(points)]
    g[-1] = H_MAX
    return g


def scan(runner, regime, method, xs, bisections):
    """Every grid point, then bisection above the last stable one of the leading stable run."""
    runs = [runner.run(regime, method, x) for x in xs]
    ok = [r["status"] == "stable" for r in runs]
    lead = 0
    while lead < len(ok) and ok[lead]:
        lead += 1
    result = {"runs": runs}
    if lead == 0:
        result["h_star"] = None  # unstable already at the smallest step
        result["first_failure"] = {"x": xs[0], "status": runs[0]["status"]}
    elif lead == len(xs):
        result["h_star"] = xs[-1]
        result["stable_to_end"] = True
        result["first_failure"] = None
    else:
        lo, hi, hi_status = xs[lead - 1], xs[lead], runs[lead]["status"]
        for _ in range(bisections):
            mid = math.sqrt(lo * hi)
            r = runner.run(regime, method, mid)
            r["bisection"] = True
            runs.append(r)
            if r["status"] == "stable":
                lo = mid
            else:
                hi, hi_status = mid, r["status"]
        result["h_star"] = lo
        result["first_failure"] = {"x": hi, "status": hi_status}
        result["islands"] = [xs[i] for i in range(lead, len(xs)) if ok[i]]
    # the energy criterion alone (the wording), over every run made: the largest h|Omega| below which
    # every run kept its energy; its resolution is the grid's away from the bisected interval
    e = None
    for r in sorted(runs, key=lambda r: r["x"]):
        if not r["energy_ok"]:
            break
        e = r["x"]
    result["h_star_energy_only"] = e
    # exact orthogonality: the largest h|Omega| (grid or bisection) up to which every run that completed kept
    # ||R^T R - I|| <= 1e-12 at every row (None: already broken at the smallest step; all_completed: no
    # completed run broke it), and the largest ||R^T R - I|| of any row any run wrote (inf: a non-finite row)
    o, broken = None, False
    for r in sorted(runs, key=lambda r: r["x"]):
        if r["exit"] != 0:
            continue
        if r["ortho_rows"] <= ORTHO_CLAIM:
            o = r["x"]
        else:
            broken = True
            break
    result["ortho_1e12"] = o
    result["ortho_all_completed"] = not broken
    result["ortho_max"] = max((r["ortho_rows"] for r in runs if "ortho_rows" in r), default=None)
    return result


def applicable(lgi, methods, problem_types, workdir):
    """Which methods each problem type takes: a t_end = 0 scene, rejected with "does not apply" or run."""
    table = {}
    for ptype, regime in problem_types.items():
        names = []
        for m in methods:
            scene, _ = scene_for(regime, m["name"], 0.1, 1, 1, t_end_override=0.0)
            rc, err, _, _ = run_scene(lgi, scene, workdir, "probe_%s_%s" % (ptype, m["name"]), 60)
            if rc == 0:
                names.append(m["name"])
            elif not (rc == 1 and "does not apply" in err):
                raise SystemExit("stability_map: probing %s on %s: exit %s: %s" % (m["name"], ptype, rc, err))
        table[ptype] = names
    return table


# --------------------------------------------------------------------------------------------------------
# the report

FOOT = {
    "not_converged": ("N", "the implicit step's Newton iteration did not converge (exit 2, `not_converged`)"),
    "non_finite": ("F", "a step produced a non-finite state (exit 2, `non_finite`)"),
    "energy_grows": ("G", "completed, but the energy error exceeded 1e-2 and grew (last quarter > 4x first quarter)"),
    "energy_large": ("B", "completed with a bounded energy error, but above 1e-2"),
    "momentum": ("M", "energy error within 1e-2, but the momentum error above it (free body: the attitude is wrong)"),
    "off_group": ("R", "energy and momentum within 1e-2, but ||R^T R - I|| > 1e-2 (the method does not keep R "
                       "on SO(3))"),
    "nan_written": ("W", "FINDING: completed (exit 0) with a non-finite number in its output"),
    "crash": ("C", "FINDING: lgi was killed by a signal"),
    "hang": ("H", "FINDING: lgi did not finish within the timeout"),
    "error": ("E", "FINDING: lgi exited with an unexpected status"),
    "failed_other": ("O", "exit 2 with a status other than not_converged / non_finite"),
}


def fmt(x):
    if x is None:
        return "—"
    return "%.2g" % x if x < 0.1 else "%.2f" % x


def cell(res):
    if res is None:
        return "n/a"
    if res["h_star"] is None:
        return "< 0.01 " + FOOT[res["first_failure"]["status"]][0]
    if res.get("stable_to_end"):
        s = "≥ π"
    else:
        s = fmt(res["h_star"]) + " " + FOOT[res["first_failure"]["status"]][0]
    if res.get("islands"):
        s += "*"
    if any("garbage" in r for r in res["runs"]):
        s += " !"
    return s


def markdown(data):
    regs = data["regimes"]
    out = []
    w = out.append
    w("# Stability map")
    w("")
    w("Generated by `%s` from `benchmarks/stability_map.json`; do not edit by hand." % data["command"])
    w("%s, %s." % (data["lgi_version"], time.strftime("%Y-%m-%d", time.gmtime(data["generated_at"]))))
    w("")
    w("For each method (rows) and stress regime (columns): the largest step h|Ω| — the step times the body "
      "angular velocity at t = 0 — at which a run of **%d rotations** (t_end = %d·2π/|Ω(0)|) completes, writes "
      "only finite numbers, and keeps the relative energy error max |E(t) − E(0)|/|E(0)| over its rows "
      "(about %d, every k steps) at or below **1e-2** — and the momentum error (free body: "
      "|m(t) − m(0)|/|m(0)|, "
      "m = RJΩ; tops: |m·k(t) − m·k(0)|/|JΩ(0)|) and ‖RᵀR − I‖ as well: the free body's energy depends on Ω "
      "alone, so without m a method could lose the attitude and pass. h|Ω| is scanned on a log grid of %d "
      "points from 0.01 to π, then refined by %d bisections (in log h) between the last stable grid point and "
      "the next; the letter after a figure is how the run just above it failed. The energy criterion alone "
      "gives the same figures except where the JSON's `h_star_energy_only` differs (listed below the table)."
      % (data["periods"], data["periods"], data["rows"], len(data["grid"]), data["bisections"]))
    w("")
    w("| method | " + " | ".join(r["title"] for r in regs) + " |")
    w("|---|" + "---|" * len(regs))
    for m in data["methods"]:
        cells = [cell(data["results"][r["id"]].get(m["name"])) for r in regs]
        w("| `%s` | %s |" % (m["name"], " | ".join(cells)))
    w("")
    diffs = []
    for r in regs:
        for m in data["methods"]:
            res = data["results"][r["id"]].get(m["name"])
            if res and res["h_star_energy_only"] != res["h_star"]:
                diffs.append("`%s` on %s: %s" % (m["name"], r["title"], fmt(res["h_star_energy_only"])))
    if diffs:
        w("Energy criterion alone, where it differs (the largest h|Ω| below which every run made kept its "
          "energy; grid resolution): " + "; ".join(diffs) + ".")
        w("")
    w("≥ π: stable at every grid point up to π. n/a: the method does not apply to the problem. "
      "\\*: stable again at some larger grid point (listed in the JSON as `islands`). "
      "!: a run wrote a non-finite number, or a completed run broke a claim of the method's traits (see "
      "Findings).")
    w("")
    for key, (letter, text) in FOOT.items():
        w("- **%s**: %s." % (letter, text))
    w("")
    w("## Notes")
    w("")
    w("- The quaternion baselines (`rk4_quat*`, `dop853_quat*`) evaluate the torque's Γ = Rᵀk as "
      "a − 2s v×a + 2 v×(v×a) (integrators/embedding.hpp), which is Rᵀa only for a unit q; their stages are not "
      "unit, so their results depend on the laboratory frame (R0): see the near-π pair under \"Same motion\".")
    w("- `split_dmv` and everything built on it (`split_dmv4` … `split_dmv10`, `split_dmv_*` compositions) "
      "take ⌈h|Π|/min I⌉ equal DMV substeps wherever h|Π| > min I (`dmv_substeps`, "
      "integrators/free_body_flows.hpp): they shorten their own step where the implicit equation has no "
      "solution, so their figures are those of a method that reduces its step. The LGVI solves the same "
      "equation without substeps and stops with `not_converged` (N) instead.")
    comp = []
    lg = data["results"].get("free_body", {}).get("lgvi")
    if lg and lg["h_star"] and not lg.get("stable_to_end"):
        for m in data["methods"]:
            r = data["results"]["free_body"].get(m["name"])
            if m["name"].startswith("lgvi_") and r and r["h_star"] and not r.get("stable_to_end"):
                comp.append("`%s` %.3f" % (m["name"], lg["h_star"] / r["h_star"]))
    if comp:
        w("- The LGVI's compositions fail where a substep γᵢh passes the LGVI's own limit: on the free body "
          "h\*(lgvi)/h\*(composition) = " + ", ".join(comp) + "; compare max|γᵢ| of their coefficients "
          "(integrators/composition.hpp).")
    w("")
    w("## Regimes")
    w("")
    w("| regime | definition | \\|Ω(0)\\| |")
    w("|---|---|---|")
    for r in regs:
        w("| %s | %s | %.6g |" % (r["title"], r["note"], r["omega_norm"]))
    w("")
    w("## Exact orthogonality on the free body")
    w("")
    w("For each method on the free body (first column): up to which h|Ω| every run that completed kept "
      "‖RᵀR − I‖ ≤ 1e-12 at every row it wrote (grid and bisection points; \"all\": every completed run did, "
      "the figure in brackets is the largest h|Ω| at which a run completed), and the largest ‖RᵀR − I‖ in any "
      "row of any run, failed runs included (inf: a non-finite row). Runs of %d rotations: %d steps at "
      "h|Ω| = 0.01, %d at π." % (data["periods"], math.ceil(data["periods"] * 2 * math.pi / 0.01),
                                 math.ceil(data["periods"] * 2)))
    w("")
    w("| method | R on SO(3) (traits) | ‖RᵀR − I‖ ≤ 1e-12 up to h\\|Ω\\| | largest ‖RᵀR − I‖ |")
    w("|---|---|---|---|")
    fb = data["results"].get("free_body", {})
    for m in data["methods"]:
        res = fb.get(m["name"])
        if res is None:
            continue
        o = res["ortho_1e12"]
        completed = [r["x"] for r in res["runs"] if r["exit"] == 0]
        if res["ortho_all_completed"]:
            top = max(completed, default=None)
            o_txt = "all (%s)" % ("—" if top is None else "≥ π" if top >= H_MAX * (1 - 1e-12) else fmt(top))
        else:
            o_txt = "< 0.01" if o is None else fmt(o)
        mx = res["ortho_max"]
        w("| `%s` | %s | %s | %s |" % (m["name"], "yes" if m["on_group"] else "no", o_txt,
                                        "—" if mx is None else "%.2g" % mx))
    w("")
    w("## Same motion, different coordinates")
    w("")
    w("Pairs of regimes that are one motion: the spin-1e4 body is the free body with Ω scaled by 1e4/|Ω(0)| and h "
      "by the inverse (the same discrete trajectory, so it tests rounding at large |Ω|); the near-π regimes are "
      "their partner started at another attitude or written in a rotated laboratory frame. Thresholds should "
      "agree, and energy errors where truncation dominates (above 1e-12, stable runs at the same grid point); "
      "below 1e-12 the errors are rounding, whose largest values are shown.")
    w("")
    w("| regime | against | thresholds equal | truncation-size energy errors: ratio range (runs) | largest rounding-size energy error (regime / against) |")
    w("|---|---|---|---|---|")
    for c in data.get("comparisons", []):
        rng = "—" if c["ratio_min"] is None else "%.4f – %.4f (%d)" % (c["ratio_min"], c["ratio_max"],
                                                                       c["truncation_runs"])
        if c["outliers"]:
            rng += "; apart: " + ", ".join("`%s` %.2g – %.2g" % tuple(o) for o in c["outliers"])
        diff = "" if not c["differ"] else " (differ: " + ", ".join(
            "`%s` %s / %s" % (n, fmt(x), fmt(y)) for n, x, y in c["differ"]) + ")"
        ro = "—" if max(c["round_off_max"]) == 0 else "%.2g / %.2g" % tuple(c["round_off_max"])
        w("| %s | %s | %d of %d%s | %s | %s |" % (c["regime"], c["reference"], c["same_threshold"], c["methods"],
                                                 diff, rng, ro))
    w("")
    w("## Findings")
    w("")
    if not data["findings"]:
        w("No crash, hang, unexpected exit status, non-finite output, or broken trait claim in %d runs."
          % data["total_runs"])
    else:
        w("%d of %d runs; each run's scene is in the JSON's `findings`. Grouped by kind, with the method, the "
          "regime and the smallest h|Ω| at which it happened:" % (len(data["findings"]), data["total_runs"]))
        w("")
        kinds = {}
        for f in data["findings"]:
            if f["status"] == "nan_written":
                kind = "completed (exit 0) with a non-finite number in its CSV"
            elif f["status"] in ("crash", "hang", "error", "failed_other"):
                kind = "%s: %s" % (f["status"], "; ".join(f["detail"])[:200])
            else:
                kind = "; ".join(f["detail"])
            kinds.setdefault(kind, {}).setdefault((f["method"], f["regime"]), []).append(f["h_omega"])
        for kind, where in kinds.items():
            items = ["`%s` %s %s" % (m, r, fmt(min(xs))) for (m, r), xs in sorted(where.items())]
            w("- **%s** (%d runs): %s." % (kind, sum(len(v) for v in where.values()), ", ".join(items)))
    w("")
    w("## Silent garbage")
    w("")
    w("Runs that completed (exit 0, every number finite) with a state that is no longer the body's: energy or "
      "momentum error above 1 (100 %), or ‖RᵀR − I‖ above 1. Nothing in lgi flags these; the table above counts "
      "them as failures (G, B, M or R). Per method: the regimes (each with the smallest such h|Ω|) and the "
      "worst figures:")
    w("")
    groups = {}
    for g in data["silent_garbage"]:
        groups.setdefault(g["method"], []).append(g)
    if not groups:
        w("None.")
    else:
        w("| method | regimes | from h\\|Ω\\| | runs | largest energy error | largest momentum error | largest ‖RᵀR − I‖ |")
        w("|---|---|---|---|---|---|---|")
        for m in data["methods"]:
            gl = groups.get(m["name"])
            if not gl:
                continue
            first = {}
            for g in gl:
                first[g["regime"]] = min(first.get(g["regime"], math.inf), g["h_omega"])
            regs_txt = ", ".join("%s %s" % (r, fmt(x)) for r, x in sorted(first.items(), key=lambda kv: kv[1]))
            w("| `%s` | %s | %s | %d | %.2g | %.2g | %.2g |" % (
                m["name"], regs_txt, fmt(min(first.values())), len(gl), max(g["energy_error"] for g in gl),
                max((g["momentum_error"] or 0) for g in gl), max(g["orthogonality"] for g in gl)))
    w("")
    w("Full run: %d runs of lgi, %.0f s wall." % (data["total_runs"], data["wall_seconds"]))
    return "\n".join(out) + "\n"


# --------------------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lgi", default=os.path.join(ROOT, "build", "lgi"), help="the lgi binary (default build/lgi)")
    ap.add_argument("--quick", action="store_true", help="a few methods on the free body, short runs (CI smoke)")
    ap.add_argument("--out-json", default=None, help="default benchmarks/stability_map.json")
    ap.add_argument("--out-md", default=None, help="default docs/stability.md")
    ap.add_argument("--methods", default=None, help="comma-separated subset")
    ap.add_argument("--regimes", default=None, help="comma-separated subset of regime ids")
    ap.add_argument("--points", type=int, default=None, help="grid points from 0.01 to pi (default 20; quick 8)")
    ap.add_argument("--bisections", type=int, default=None, help="default 4; quick 6")
    ap.add_argument("--periods", type=int, default=None, help="rotations per run (default 100; quick 20)")
    ap.add_argument("--rows", type=int, default=200, help="output rows per run (energy sampled there)")
    ap.add_argument("--jobs", type=int, default=1, help="parallel (method, regime) scans (machine rule: <= 2)")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per lgi run before it counts as a hang")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless the table is well formed and LGVI's free-body threshold is in its "
                         "expected range (the CTest smoke)")
    ap.add_argument("--label", default=None, help="what the binary is, for the report (e.g. its commit)")
    ap.add_argument("--strict", action="store_true",
                    help="with --check: also fail on every finding (non-finite numbers written, broken claims)")
    args = ap.parse_args()

    if args.quick:
        args.points = args.points or 8
        args.bisections = 6 if args.bisections is None else args.bisections
        args.periods = args.periods or 20
        args.methods = args.methods or "lgvi,lgvi_yoshida4,split_dmv,rkmk4,lie_euler"
        args.regimes = args.regimes or "free_body"
    args.points = args.points or 20
    args.bisections = 4 if args.bisections is None else args.bisections
    args.periods = args.periods or 100
    args.lgi = os.path.abspath(args.lgi)
    # --quick never overwrites the committed map: its files go beside the binary (the build directory)
    here = os.path.dirname(args.lgi) if args.quick else None
    args.out_json = args.out_json or (os.path.join(here, "stability_map_quick.json") if here else
                                      os.path.join(ROOT, "benchmarks", "stability_map.json"))
    args.out_md = args.out_md or (os.path.join(here, "stability_quick.md") if here else
                                  os.path.join(ROOT, "docs", "stability.md"))
    if not os.access(args.lgi, os.X_OK):
        raise SystemExit("stability_map: %s is not an executable (build it: cmake --build build --target lgi_exe)"
                         % args.lgi)

    start = time.monotonic()
    methods = lgi_methods(args.lgi)
    if args.methods:
        want = args.methods.split(",")
        unknown = [m for m in want if m not in {x["name"] for x in methods}]
        if unknown:
            raise SystemExit("stability_map: unknown methods %s" % unknown)
        methods = [m for m in methods if m["name"] in want]
    regs = regimes()
    if args.regimes:
        want = args.regimes.split(",")
        unknown = [r for r in want if r not in {x["id"] for x in regs}]
        if unknown:
            raise SystemExit("stability_map: unknown regimes %s" % unknown)
        regs = [r for r in regs if r["id"] in want]
    for r in regs:
        r["omega_norm"] = norm(r["omega"])
    xs = grid(args.points)

    with tempfile.TemporaryDirectory(prefix="lgi_stability_") as workdir:
        runner = Runner(args, workdir)
        types = {}
        for r in regs:
            types.setdefault(r["problem"]["type"], r)
        takes = applicable(args.lgi, methods, types, workdir)
        jobs = [(r, m) for r in regs for m in methods if m["name"] in takes[r["problem"]["type"]]]
        results = {r["id"]: {} for r in regs}
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, min(args.jobs, 2))) as pool:
            futures = {pool.submit(scan, runner, r, m, xs, args.bisections): (r, m) for r, m in jobs}
            done = 0
            for fut in concurrent.futures.as_completed(futures):
                r, m = futures[fut]
                results[r["id"]][m["name"]] = fut.result()
                done += 1
                if sys.stderr.isatty() or not args.quick:
                    print("[%d/%d %5.0f s] %-12s %-32s %s" % (done, len(jobs), time.monotonic() - start, r["id"],
                                                              m["name"], cell(results[r["id"]][m["name"]])),
                          file=sys.stderr, flush=True)

    data = {
        "command": "scripts/stability_map.py --lgi build/lgi" + (" --quick" if args.quick else ""),
        "lgi_version": lgi_version(args.lgi) + (" (%s)" % args.label if args.label else ""),
        "generated_at": time.time(),
        "criterion": {"energy_tol": ENERGY_TOL, "growth_factor": GROWTH_FACTOR, "claim_tol": CLAIM_TOL,
                      "initial_tol": INITIAL_TOL, "ortho_claim": ORTHO_CLAIM},
        "periods": args.periods, "rows": args.rows, "grid": xs, "bisections": args.bisections,
        "quick": args.quick,
        "regimes": [{k: v for k, v in r.items()} for r in regs],
        "methods": methods,
        "applicable": takes,
        "results": results,
        "findings": runner.findings,
        "silent_garbage": runner.silent,
        "total_runs": runner.counter,  # plus one t_end = 0 probe per method and problem type (applicability)
    }
    # pairs of regimes that are the same motion (scaled in time, or in a rotated frame): the same thresholds
    # and energy errors are expected, up to rounding
    data["comparisons"] = []
    for a_id, b_id in (("fast_spin", "free_body"), ("near_pi_free", "free_body"), ("near_pi", "near_pi_ref")):
        if a_id in results and b_id in results:
            data["comparisons"].append(compare(a_id, b_id, results[a_id], results[b_id]))
    data["wall_seconds"] = time.monotonic() - start

    md = markdown(data)
    for path, text in ((args.out_json, serialise(data)), (args.out_md, md)):
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        tmp = path + ".tmp"
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    print("stability_map: %d runs in %.0f s -> %s, %s" % (runner.counter, data["wall_seconds"], args.out_json,
                                                         args.out_md), file=sys.stderr)
    if args.check:
        sys.exit(check(data, md, args.strict))


RUN_FIELDS = ["x", "status", "exit", "steps", "energy_error", "energy_first_quarter", "energy_last_quarter",
              "momentum_error", "orthogonality", "ortho_rows", "initial_row_error", "wall", "bisection", "garbage"]


def serialise(data):
    """The JSON file: each run as one row of RUN_FIELDS (figures to 4 significant digits), one line each."""
    def r4(v):
        if isinstance(v, float) and math.isfinite(v) and v != 0:
            return float("%.4g" % v)
        if isinstance(v, float) and not math.isfinite(v):
            return str(v)  # "inf" / "nan": JSON has no such numbers
        return v
    out = dict(data)
    out["run_fields"] = RUN_FIELDS
    results = {}
    for reg, by_method in data["results"].items():
        results[reg] = {}
        for name, res in by_method.items():
            r = {k: v for k, v in res.items() if k != "runs"}
            r["runs"] = [[r4(run.get(f)) for f in RUN_FIELDS] for run in res["runs"]]
            results[reg][name] = r
    out["results"] = results
    text = json.dumps(out, indent=1)
    # one run per line
    text = re.sub(r"\[\n\s+([^\[\]{}]*?)\n\s+\]", lambda m: "[" + re.sub(r"\s*\n\s*", " ", m.group(1)) + "]", text)
    return text + "\n"


def check(data, md, strict=False):
    """The CTest smoke: a well-formed table, and LGVI's free-body threshold where its theory puts it."""
    problems = []
    lines = md.splitlines()
    try:
        head = next(i for i, l in enumerate(lines) if l.startswith("| method |"))
    except StopIteration:
        return fail(["no table"])
    ncols = len(data["regimes"]) + 1
    body = []
    for l in lines[head + 2:]:
        if not l.startswith("|"):
            break
        body.append(l)
    if len(body) != len(data["methods"]):
        problems.append("table has %d rows for %d methods" % (len(body), len(data["methods"])))
    cell_re = re.compile(r"^(n/a|≥ π|< 0\.01 [A-Z]|[0-9.e-]+ [A-Z])\*?( !)?$")
    for l in body:
        cells = [c.strip() for c in l.strip().strip("|").split("|")]
        if len(cells) != ncols:
            problems.append("row with %d cells: %s" % (len(cells), l))
            continue
        for c in cells[1:]:
            if not cell_re.match(c):
                problems.append("malformed cell %r in %s" % (c, l))
    # lgi must never crash, hang or exit with a status other than 0 and 2 on a valid scene; the other findings
    # (a non-finite number written, a trait's claim broken) fail the check only with --strict, because
    # "no NaN in the output" is the command's own contract, tested with its failure handling (tests/cli).
    for f in data["findings"]:
        severe = f["status"] in ("crash", "hang", "error", "failed_other")
        if severe or strict:
            problems.append("%s on %s at h|Omega| = %.4g: %s, %s" % (f["method"], f["regime"], f["h_omega"],
                                                                     f["status"], f["detail"]))
        else:
            print("stability_map --check: warning: %s on %s at h|Omega| = %.4g: %s" % (
                f["method"], f["regime"], f["h_omega"], "; ".join(f["detail"])), file=sys.stderr)
    fb = data["results"].get("free_body", {})
    lgvi = fb.get("lgvi")
    if lgvi is None:
        problems.append("no lgvi result on the free body")
    else:
        # The LGVI is symplectic: below its stability limit its energy error is bounded and O((h|Omega|)^2)
        # (backward error analysis, Hairer-Lubich-Wanner ch. IX; on the free body DMV even keeps E exactly),
        # so it does not lose 1e-2 of the energy before its implicit equation stops being solvable. That
        # equation, hJ Omega = (2/(1+|c|^2))(Jc + c x Jc), has on a principal axis the solution
        # sin(phi) = h|Omega| and none beyond h|Omega| = 1 (README, Findings); the Hairer-Vilmart body turns
        # mostly about its first axis (Omega0 = (3, 0.5, -0.9)), so its limit must lie near 1 too: a
        # threshold outside [0.7, 1.3) means a broken method or a broken map.
        h = lgvi["h_star"] or 0.0
        if not (0.7 <= h < 1.3):
            problems.append("lgvi free-body threshold h|Omega| = %s outside [0.7, 1.3)" % h)
        ff = lgvi.get("first_failure")
        if not ff or ff["status"] != "not_converged":
            problems.append("lgvi should fail by not_converged above its threshold, got %s" % ff)
    # A composition runs the LGVI with substeps gamma_i h; it fails once max|gamma_i| h|Omega| passes the LGVI's
    # own limit L, so its threshold is L / max|gamma_i|: Yoshida's triple jump (Phys. Lett. A 150 (1990) 262)
    # has gamma = (x1, x0, x1), x1 = 1/(2 - 2^(1/3)), x0 = -2^(1/3) x1, max|gamma| = |x0| = 1.7024. Both
    # thresholds are bracketed by their bisections (last stable, first failed); the brackets, scaled, must
    # overlap (2 % slack: |Omega| along the orbit where each first fails differs a little).
    y4 = fb.get("lgvi_yoshida4")
    if y4 is not None and lgvi is not None and lgvi.get("first_failure") and y4.get("first_failure"):
        x1 = 1 / (2 - 2 ** (1 / 3))
        g = 2 ** (1 / 3) * x1
        lo, hi = lgvi["h_star"] / g, lgvi["first_failure"]["x"] / g
        ylo, yhi = y4["h_star"] or 0.0, y4["first_failure"]["x"]
        if not (ylo <= hi * 1.02 and yhi >= lo / 1.02):
            problems.append("lgvi_yoshida4 threshold [%.4g, %.4g] is not lgvi's [%.4g, %.4g] / %.4f"
                            % (ylo, yhi, lgvi["h_star"], lgvi["first_failure"]["x"], g))
    le = fb.get("lie_euler")
    if le is not None and lgvi is not None and not ((le["h_star"] or 0) < (lgvi["h_star"] or 0)):
        problems.append("lie_euler (order 1, not symplectic) is not less stable than lgvi: %s >= %s"
                        % (le["h_star"], lgvi["h_star"]))
    return fail(problems)


def fail(problems):
    for p in problems:
        print("stability_map --check: " + p, file=sys.stderr)
    if not problems:
        print("stability_map --check: ok", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    main()
