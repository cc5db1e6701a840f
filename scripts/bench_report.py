#!/usr/bin/python3
"""scripts/bench_report.py -- docs/benchmarks.md and its plots from the results of scripts/bench.sh.

    /usr/bin/python3 scripts/bench_report.py --results BUILD/bench --docs docs

Reads RESULTS/work_precision.json (benchmarks/work_precision.cpp), and when present bench_steps.json (Google
Benchmark), callgrind.md (benchmarks/callgrind_steps.sh), callgrind_rhs.json (benchmarks/callgrind_rhs.sh) and
memory.json (scripts/bench.sh); writes
DOCS/benchmarks.md and DOCS/img/wp_<case>.png (error at T against CPU time, one line per method),
DOCS/img/long_<case>.png (energy error and ||R^T R - I|| against time). Run it under Debian's
/usr/bin/python3: the first python3 on PATH may be an interpreter without matplotlib. Numbers are copied
from the JSON, never recomputed here, except t(eps) per method which the JSON already holds.
"""
import argparse
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TARGETS = ["1e-06", "1e-08", "1e-10", "1e-12"]
# Right-hand-side evaluations per fixed step of the stage methods (their tableaus, integrators/butcher_tableaus.hpp;
# fixed steps skip trailing stages with b_i = 0, integrators/rkmk.hpp: Verner 9(8) 15 of its 16, DP5 6 of its 7).
STAGES = {"rk4quat": 4, "rkmk_heun": 2, "rkmk3": 3, "rkmk4": 4, "rkmk4_38": 4, "rkmk4_cayley": 4, "rkmk_dp5": 6,
          "rkmk_dp5_cayley": 6, "rkmk_dp8": 12, "rkmk_dp8_cayley": 12, "rkmk_vern9": 15, "rkmk_vern9_cayley": 15}
EPS_LABEL = {"1e-06": "1e-6", "1e-08": "1e-8", "1e-10": "1e-10", "1e-12": "1e-12"}

# The cost of throwaway prototypes of each algorithm measured when lgi was designed (heavy top, h = 0.01,
# g++ 12 -O3): ns/step and instructions/step. lgi's target: ns/step within 1.5x of these floors.
ANCHORS = {
    "rk4quat": ("RK4 on quaternion + renormalise", 70, 402),
    "split_dmv": ("kick + DMV (quaternion)", 70, 320),
    "lgvi": ("kick + DMV (3x3 R)", 85, 364),
    "split_dmv4": ("preprocessed DMV order 4", 107, 401),
    "split_axes": ("Strang with 5 axis rotations", 114, 954),
    "rkmk4": ("RKMK4", 161, 1307),
    "cf4": ("CF4", 204, 1769),
}


def fmt_time(s):
    if s is None or (isinstance(s, float) and not math.isfinite(s)):
        return "—"
    if s < 1e-3:
        return "%.1f µs" % (s * 1e6)
    if s < 1:
        return "%.2f ms" % (s * 1e3)
    return "%.2f s" % s


def fmt_e(x, digits=1):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return "%.*e" % (digits, x)


def fmt_slope(x):
    return "—" if x is None else "%.2f" % x


# lgi's method families in the plots: each shows its PER_FAMILY fastest methods (by t(1e-8), then t(1e-6), the
# tables' order); every method stays in the tables.
FAMILIES = [
    ("LGVI", lambda n: n.startswith("lgvi")),
    ("splittings", lambda n: n.startswith("split_") or n.startswith("lagrange_split")),
    ("RKMK", lambda n: n.startswith("rkmk")),
    ("CF / CG", lambda n: n in ("cf4", "cg3")),
    ("non-geometric baselines", lambda n: n.startswith("rk4_") or n.startswith("dop853_")),
]
PER_FAMILY = 2
MARKERS = ["o", "s", "^", "v", "D", "P", "X", "*", "<", ">", "h", "p"]


def speed_key(m):
    t = m["t_at"].get("1e-08")
    t6 = m["t_at"].get("1e-06")
    return (t is None, t if t is not None else (t6 if t6 is not None else 1e9))


def plotted_methods(case):
    """lgi's PER_FAMILY fastest methods of each family, then every peer."""
    lgi = [m for m in case["methods"] if m["library"] == "lgi"]
    chosen = []
    for _, member in FAMILIES:
        chosen += sorted([m for m in lgi if member(m["name"])], key=speed_key)[:PER_FAMILY]
    return chosen + [m for m in case["methods"] if m["library"] != "lgi"]


def wp_plot(case, path):
    fig, ax = plt.subplots(figsize=(11, 6.2))
    lgi_colours = plt.get_cmap("tab10").colors
    peer_colours = plt.get_cmap("Dark2").colors + plt.get_cmap("Set1").colors
    n_lgi = n_peer = 0
    for m in plotted_methods(case):
        pts = [p for p in m["points"] if p.get("ok") and not p.get("below_reference") and p["error"] > 0]
        if not pts:
            continue
        xs = [p["seconds"] for p in pts]
        ys = [p["error"] for p in pts]
        if m["library"] == "lgi":
            colour, marker, ls, label = lgi_colours[n_lgi % 10], MARKERS[n_lgi % len(MARKERS)], "-", m["name"]
            n_lgi += 1
        else:
            colour = peer_colours[n_peer % len(peer_colours)]
            marker, ls = MARKERS[(n_peer + 5) % len(MARKERS)], "--"
            label = "%s (%s)" % (m["name"], m["library"])
            n_peer += 1
        ax.loglog(xs, ys, ls, color=colour, marker=marker, markersize=4, linewidth=1.3, label=label)
    for eps in (1e-6, 1e-8, 1e-10, 1e-12):
        ax.axhline(eps, color="0.8", linewidth=0.6, zorder=0)
    ax.set_xlabel("CPU time (s), median")
    ax.set_ylabel(r"error at T: $|\log(R_{ref}^T R)| + |\Omega - \Omega_{ref}|$")
    ax.set_title("%s (T = %g): solid, lgi's %d fastest of each family; dashed, every peer; all methods in the table"
                 % (case["name"], case["t_eval"], PER_FAMILY), fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def long_plot(lh, path):
    """lgi's runs (solid) and the peers tuned to the CPU time of the headline lgi method (dashed)."""
    best = lh["summary"]["lgi_method"] if lh.get("summary") else None
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for r in lh["runs"]:
        lgi = r["library"] == "lgi"
        if not lgi and r.get("matched_to") != best:
            continue
        ls = "-" if lgi else "--"
        label = "%s (%s)" % (r["method"], fmt_time(r["seconds"]))
        e = [max(v, 1e-17) for v in r["energy"]]
        o = [max(v, 1e-17) for v in r["orthogonality"]]
        axes[0].loglog(r["times"], e, ls, linewidth=1.1, label=label)
        axes[1].loglog(r["times"], o, ls, linewidth=1.1, label=label)
    axes[0].set_ylabel("relative energy error")
    axes[1].set_ylabel(r"$\|R^TR - I\|_F$ (peers: of $R(q)$, $q$ not normalised)")
    for ax in axes:
        ax.set_xlabel("t")
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.suptitle("%s, T = %g; solid: lgi; dashed: peers tuned to the CPU time of %s" % (lh["case"], lh["t_end"], best))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", required=True)
    ap.add_argument("--docs", required=True)
    a = ap.parse_args()
    wp_path = os.path.join(a.results, "work_precision.json")
    try:
        wp = json.load(open(wp_path))
    except (OSError, ValueError) as e:
        sys.exit("bench_report.py: cannot read %s: %s" % (wp_path, e))
    img = os.path.join(a.docs, "img")
    os.makedirs(img, exist_ok=True)
    m = wp["machine"]
    rhs_instr = {}  # the peers' right-hand side: instructions per call, by case (benchmarks/callgrind_rhs.sh)
    rhs_path = os.path.join(a.results, "callgrind_rhs.json")
    if os.path.exists(rhs_path):
        rhs_instr = json.load(open(rhs_path))
    L = []
    w = L.append
    w("# Benchmarks")
    w("")
    w("Generated by `scripts/bench.sh` (do not edit: rerun it). One run, one process, one machine:")
    w("")
    w("| | |")
    w("|---|---|")
    w("| date | %s |" % m["date"])
    w("| CPU | %s (%d logical CPUs, shared; noisy) |" % (m["cpu"], m["logical_cpus"]))
    w("| system | %s |" % m.get("kernel", "?"))
    w("| compiler | %s, flags `%s` (lgi and the peers alike); the peers' code (Boost.Odeint and every right-hand "
      "side; GSL and SUNDIALS are Debian's builds) for %s, lgi's steps dispatched at run time to AVX2 where the CPU "
      "has it |" % (m["compiler"], m["flags"].strip(), m.get("peer_isa", "x86-64 baseline")))
    w("| libraries | %s |" % ", ".join("%s %s" % (k, v) for k, v in m["libraries"].items()))
    w("| timing | %s; %s; %d repetitions; %s |" %
      (wp["timing"]["clock"], wp["timing"]["statistic"], wp["timing"]["repetitions"],
       wp["timing"].get("order", "methods interleaved")))
    w("| error | %s |" % wp["error_measure"])
    if wp.get("smoke"):
        w("| **smoke run** | tiny sizes, one repetition: not a measurement |")
    w("")
    w("Every solver integrates the same body from the same state: lgi's methods on SO(3) × R³ as `lgi run` runs "
      "them (the case's scene with the method, through the command's engine and its compilation), the peers on "
      "the unit quaternion and the body momentum (7 entries, about 60 flops per right-hand side with gravity). "
      "Solver creation and re-initialisation are outside the timing. t(ε) is the CPU time to reach error ε at T, "
      "interpolated log-log on each method's Pareto front: fixed-step entries (swept over the number of steps; "
      "`_fixed`: an embedded pair's method, or a peer's stepper, at fixed steps) are timed at the step that reaches "
      "ε, as adaptive entries are at the tolerance that does; the `auto` row pays for finding its own. "
      "`—`: not reached within the sweep "
      "(a single run is capped at %s). `≤`: even the cheapest point of the sweep is below ε (an upper bound). Ratio = lgi best / peer best from the medians: **> 1 means a peer wins** (marked); its spread is the same ratio within each timed pass (every pass times every point once, in its own shuffled order), as quartiles over the passes and the number of passes in which the peer is faster. The last column is the same comparison from each point's lower quartile over the passes instead of its median, each side's best chosen afresh: the machine's noise only ever slows a run, so a sceptic can see whether a ratio depends on when the slow spells fell." %
      fmt_time(wp["timing"]["max_run_seconds"]))
    w("")

    # Headline table
    w("## Headline: fastest lgi method against the fastest peer")
    w("")
    w("| case | ε | lgi best | t | peer best | t | lgi / peer | per pass: quartiles, passes the peer wins | from lower quartiles |")
    w("|---|---|---|---:|---|---:|---:|---|---:|")
    for c in wp["cases"]:
        for eps in TARGETS:
            s = c["summary"][eps]
            r = s["ratio_lgi_over_peer"]
            rs = "—" if r is None else ("**%.2f (peer wins)**" % r if r > 1 else "%.2f" % r)
            lt = ("≤ " if s.get("lgi_upper_bound") else "") + fmt_time(s["lgi_seconds"])
            pt = ("≤ " if s.get("peer_upper_bound") else "") + fmt_time(s["peer_seconds"])
            spread = ("%.2f–%.2f, %d of %d" % (s["ratio_q1"], s["ratio_q3"], s["peer_wins_passes"], s["ratio_passes"])
                      if s.get("ratio_passes") else "—")
            lq = (s.get("lower_quartiles") or {}).get("ratio_lgi_over_peer")
            w("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                c["name"], EPS_LABEL[eps], s["lgi_best"] or "—", lt, s["peer_best"] or "—", pt, rs, spread,
                "—" if lq is None else "%.2f" % lq))
    w("")
    wins = [(c["name"], EPS_LABEL[e]) for c in wp["cases"] for e in TARGETS
            if c["summary"][e]["peer_wins"]]
    w("Peers win at %d of %d (case, ε) pairs%s." % (
        len(wins), len(wp["cases"]) * len(TARGETS),
        (": " + ", ".join("%s at %s" % x for x in wins)) if wins else ""))
    w("")

    # method auto against the fastest lgi method
    if any(c["summary"][e].get("auto_seconds") is not None for c in wp["cases"] for e in TARGETS):
        w("## `method: auto` against the fastest lgi method")
        w("")
        w("`\"method\": \"auto\"` swept over the same tolerances (apps/auto_method.hpp): its choice, the probes that set a "
          "fixed step included, is made in every timed run. t(ε) as above; the ratio's spread is the same ratio within "
          "each timed pass, as quartiles over the passes.")
        w("")
        w("| case | ε | auto | fastest lgi method | t | auto / fastest | per pass: quartiles |")
        w("|---|---|---:|---|---:|---:|---|")
        accuracy = []
        for c in wp["cases"]:
            for eps in TARGETS:
                s = c["summary"][eps]
                if s.get("auto_seconds") is None:
                    continue
                r = s.get("ratio_auto_over_lgi_best")
                spread = ("%.2f–%.2f" % (s["auto_ratio_q1"], s["auto_ratio_q3"]) if "auto_ratio_q1" in s else "—")
                w("| %s | %s | %s | %s | %s | %s | %s |" % (
                    c["name"], EPS_LABEL[eps], ("≤ " if s.get("auto_upper_bound") else "") + fmt_time(s["auto_seconds"]),
                    s["lgi_best"] or "—", ("≤ " if s.get("lgi_upper_bound") else "") + fmt_time(s["lgi_seconds"]),
                    "—" if r is None else "%.2f" % r, spread))
            auto = [m for m in c["methods"] if m["name"] == "auto"]
            pts = [p for m in auto for p in m["points"] if p.get("ok", True) and p.get("tol") is not None
                   and 1e-12 * 0.999 <= p["tol"] <= 1e-6 * 1.001 and p.get("error") is not None]
            if pts:
                accuracy.append("%s %.2f" % (c["name"], max(p["error"] / p["tol"] for p in pts)))
        w("")
        if accuracy:
            w("auto's error at T (this page's measure: the rotation angle + |Ω − Ω_ref|, Ω absolute) over its tolerance, "
              "largest over the tolerances 1e-6 … 1e-12 of the sweep: " + "; ".join(accuracy) + ".")
            w("")

    # Per case
    w("## Work-precision per case")
    w("")
    for c in wp["cases"]:
        ref = c["reference"]
        png = "wp_%s.png" % c["name"]
        wp_plot(c, os.path.join(img, png))
        w("### %s" % c["name"])
        w("")
        w("`%s`, %s, T = %g%s. Reference: %s; error bar %s%s; chaos guard: Ω0 perturbed by %g relative "
          "diverges by %s at t_end (amplification %s)." % (
              c["scene"], c["problem"], c["t_eval"],
              "" if c["t_eval"] == c["t_end"] else " (**shortened from %g by the chaos guard**)" % c["t_end"],
              ref["method"], fmt_e(ref["error_bar"]),
              ("; exact vs integration %s" % fmt_e(ref["cross_check_exact_vs_integration"]))
              if "cross_check_exact_vs_integration" in ref else "",
              ref["guard"]["perturbation"], fmt_e(ref["guard"]["divergence"][-1]),
              fmt_e(ref["guard"]["amplification_at_t_end"])))
        w("")
        if c.get("peer_rhs_ns"):
            r = c["peer_rhs_ns"]
            rhs_text = (" and %.0f instructions (callgrind, the loop's call included)" % rhs_instr[c["name"]]
                        if c["name"] in rhs_instr else "")
            w("The peers' right-hand side (scalar code, called through a function pointer): %.1f ns a call (quartiles "
              "%.1f–%.1f ns over %d batches, one in each timed pass)%s." % (r["median"], r["q1"], r["q3"], r["batches"], rhs_text))
            w("")
        w("![work-precision %s](img/%s)" % (c["name"], png))
        w("")
        w("| method | library | order | t(1e-6) | t(1e-8) | t(1e-10) | t(1e-12) | best error | status |")
        w("|---|---|---:|---:|---:|---:|---:|---:|---|")

        for mm in sorted(c["methods"], key=speed_key):
            errs = [p["error"] for p in mm["points"] if p.get("ok")]
            cells = []
            for eps in TARGETS:
                t = mm["t_at"].get(eps)
                s = fmt_time(t)
                if mm["t_at"].get(eps + "_upper_bound"):
                    s = "≤ " + s
                cells.append(s)
            order = "exact" if mm.get("exact_solution") else mm["order"] if mm["order"] else "var."
            w("| %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                mm["name"], mm["library"], order, cells[0], cells[1], cells[2], cells[3],
                fmt_e(min(errs)) if errs else "—", mm["status"]))
        w("")

    # Long horizon
    if wp.get("long_horizon"):
        w("## Long horizon at equal CPU time")
        w("")
        w("lgi's methods at fixed steps; for each symplectic one, every peer's tolerance (rk4: its step) is chosen "
          "from probe runs over T/100 so that its CPU time matches that lgi run's. Errors are the largest over "
          "[0, T] at 40 log-spaced times: relative energy, momentum (heavy top: |Δ(m·k)|/|m|; free body: "
          "|Δm|/|m|), the Casimir |Π| (free body), ‖RᵀR − I‖ (peers: of R(q) with q as integrated). Drift "
          "exponent: slope of log(running max of the error) against log t over [T/100, T] (0: bounded; 1: linear "
          "drift). lgi's target: an energy error at least 100× smaller than the best peer's at equal CPU time.")
        w("")
        for lh in wp["long_horizon"]:
            png = "long_%s.png" % lh["case"]
            long_plot(lh, os.path.join(img, png))
            w("### %s, T = %g" % (lh["case"], lh["t_end"]))
            w("")
            w("| lgi method (budget) | CPU time | lgi energy error | best peer at that time | its energy error | peer / lgi |")
            w("|---|---:|---:|---|---:|---:|")
            for mt in lh["matches"]:
                ratio = mt["ratio_peer_over_lgi"]
                rs = "—" if ratio is None else ("%.3g" % ratio if ratio >= 100 else "**%.3g (target missed)**" % ratio)
                w("| %s | %s | %s | %s | %s | %s |" % (
                    mt["lgi_method"], fmt_time(mt["budget_seconds"]), fmt_e(mt["lgi_max_energy_error"]),
                    mt["best_peer"], fmt_e(mt["peer_max_energy_error"]), rs))
            w("")
            w("![long horizon %s](img/%s)" % (lh["case"], png))
            w("")
            has_cas = any("casimir" in r["max"] for r in lh["runs"])
            w("| method | matched to | parameter | CPU time | energy | momentum |%s ‖RᵀR − I‖ | drift exp. energy | momentum | orthogonality |" %
              (" \\|Π\\| |" if has_cas else ""))
            w("|---|---|---|---:|---:|---:|%s---:|---:|---:|---:|" % ("---:|" if has_cas else ""))
            for r in lh["runs"]:
                param = ("h = %g" % (lh["t_end"] / r["n_steps"])) if "n_steps" in r else ("tol = %.2g" % r["tol"])
                d = r["drift_exponent"]
                w("| %s | %s | %s | %s | %s | %s |%s %s | %s | %s | %s |" % (
                    r["method"], r.get("matched_to", "(lgi)"), param, fmt_time(r["seconds"]),
                    fmt_e(r["max"]["energy"]), fmt_e(r["max"]["momentum"]),
                    (" %s |" % fmt_e(r["max"].get("casimir"))) if has_cas else "",
                    fmt_e(r["max"]["orthogonality"]), fmt_slope(d["energy"]), fmt_slope(d["momentum"]),
                    fmt_slope(d["orthogonality"])))
            w("")

    # ns/step
    bs_path = os.path.join(a.results, "bench_steps.json")
    if os.path.exists(bs_path):
        bs = json.load(open(bs_path))
        rows = {}
        for b in bs["benchmarks"]:
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            name = b.get("run_name", b["name"])
            method, _, problem = name.partition("/")
            ns = b["cpu_time"]  # µs per 1000-step iteration = ns per step
            if b.get("time_unit") == "ns":
                ns /= 1000.0
            rows.setdefault(method, {})[problem] = ns
        # instructions per step on the HV heavy top from the same run's callgrind.md, beside the times
        instr = {}
        cg = os.path.join(a.results, "callgrind.md")
        if os.path.exists(cg):
            for line in open(cg):
                cells = [c.strip() for c in line.strip().strip("|").split("|")]
                if len(cells) >= 3 and cells[1] == "heavy_top":
                    try:
                        instr[cells[0]] = float(cells[2])
                    except ValueError:
                        pass
        w("## Cost per step (Google Benchmark, ns/step, median)")
        w("")
        w("`bench_steps`, h = 0.01, periods of 1000 steps (benchmarks/bench_cases.hpp), every method of the "
          "registry; instructions per step on the HV heavy top from callgrind (next section). Floors: the "
          "cost of minimal hand-written prototypes of each algorithm, measured when lgi was designed (g++ 12 -O3, "
          "heavy top, h = 0.01); lgi's target is within 1.5× of them.")
        w("")
        w("| method | heavy_top ns | free_body ns | heavy_top instr. | prototype floor | heavy_top / floor |")
        w("|---|---:|---:|---:|---|---:|")
        for method in sorted(rows, key=lambda k: rows[k].get("heavy_top", 1e9)):
            r = rows[method]
            an = ANCHORS.get(method)
            ratio = "—"
            if an and "heavy_top" in r:
                q = r["heavy_top"] / an[1]
                ratio = ("**%.2f**" % q) if q > 1.5 else "%.2f" % q
            w("| %s | %s | %s | %s | %s | %s |" % (
                method, "%.0f" % r["heavy_top"] if "heavy_top" in r else "—",
                "%.0f" % r["free_body"] if "free_body" in r else "—",
                "%.0f" % instr[method] if method in instr else "—",
                ("%s: %d ns" % (an[0], an[1])) if an else "", ratio))
        w("")
        # Per stage: the stage methods' cost per right-hand-side evaluation beside the peers' right-hand side.
        hv = next((c for c in wp["cases"] if c["name"] == "hv_heavy_top" and c.get("peer_rhs_ns")), None)
        staged = [k for k in STAGES if "heavy_top" in rows.get(k, {})]
        if hv and staged:
            w("### Per stage, HV heavy top")
            w("")
            w("A stage method's step over its right-hand-side evaluations (fixed steps; `rk4quat`: RK4 on the "
              "quaternion and Ω, the peers' formulation, hand-written) against the peers' right-hand side alone "
              "(`hv_heavy_top` above: %.1f ns%s a call): what a stage costs beyond the right-hand side is its "
              "share of the stage sums and, for lgi, the chart (dexp⁻¹ or dcay⁻¹ and the stage attitude)."
              % (hv["peer_rhs_ns"]["median"],
                 " and %.0f instructions" % rhs_instr["hv_heavy_top"] if "hv_heavy_top" in rhs_instr else ""))
            w("")
            w("| method | stages | ns/stage | instr./stage | ns/stage ÷ peer RHS ns | instr./stage ÷ peer RHS instr. |")
            w("|---|---:|---:|---:|---:|---:|")
            peer_ns = hv["peer_rhs_ns"]["median"]
            peer_in = rhs_instr.get("hv_heavy_top")
            for k in sorted(staged, key=lambda k: rows[k]["heavy_top"] / STAGES[k]):
                s = STAGES[k]
                ns = rows[k]["heavy_top"] / s
                ins = instr[k] / s if k in instr else None
                w("| %s | %d | %.1f | %s | %.2f | %s |" % (
                    k, s, ns, "%.0f" % ins if ins is not None else "—", ns / peer_ns,
                    "%.2f" % (ins / peer_in) if ins is not None and peer_in else "—"))
            w("")
    cg_path = os.path.join(a.results, "callgrind.md")
    if os.path.exists(cg_path):
        w("## Instructions per step (callgrind, HV heavy top)")
        w("")
        w("`PROBLEMS=heavy_top benchmarks/callgrind_steps.sh BUILD` (exact, repeatable; anchors: split_dmv "
          "320–364, rk4quat 402, rkmk4 1307, cf4 1769).")
        w("")
        L.extend(open(cg_path).read().rstrip().splitlines())
        w("")
    mem_path = os.path.join(a.results, "memory.json")
    if os.path.exists(mem_path):
        mem = json.load(open(mem_path))
        w("## Memory of long runs that write only their final state")
        w("")
        w("`lgi run` on `%s` with split_dmv, dt = 0.01, `output.every` = 10¹² (rows at t = 0 and t_end only); "
          "peak resident set size of the process (ru_maxrss)." % mem["scene"])
        w("")
        w("| steps | peak RSS | wall time | CSV rows |")
        w("|---:|---:|---:|---:|")
        for r in mem["runs"]:
            w("| %.0e | %d KiB | %.1f s | %d |" % (r["steps"], r["peak_rss_kib"], r["wall_seconds"], r["csv_rows"]))
        w("")
    os.makedirs(a.docs, exist_ok=True)
    with open(os.path.join(a.docs, "benchmarks.md"), "w") as f:
        f.write("\n".join(L) + "\n")
    print("bench_report.py: wrote %s and %s/*.png" % (os.path.join(a.docs, "benchmarks.md"), img), file=sys.stderr)


if __name__ == "__main__":
    main()
