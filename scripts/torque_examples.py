#!/usr/bin/python3
"""Runs the examples of torques that do work and plots them (docs/torques.md), in one command:

    /usr/bin/python3 scripts/torque_examples.py [--lgi build/lgi]

For each of scenes/damped_top.json, scenes/attitude_slew.json, scenes/torque_replay.json, scenes/flat_spin.json and
scenes/wheel_slew.json it writes a copy of the
scene with dense outputs into a temporary directory (the scenes themselves are read, never written; a torque table's
path is made absolute in the copy), runs `lgi run` on it and draws docs/img/torque_<name>.png from the CSV. The
figures' numbers that docs/torques.md quotes are printed. Needs matplotlib (Debian: python3-matplotlib, under
/usr/bin/python3) and numpy.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(lgi, scene_path, every, workdir):
    """The scene's rows at every `every`-th step (the scene otherwise unchanged)."""
    with open(scene_path) as f:
        scene = json.load(f)
    scene["output"] = {"every": every}
    for term in scene["problem"].get("torques", []):
        if term.get("type") == "table" and not os.path.isabs(term["file"]):
            term["file"] = os.path.join(os.path.dirname(os.path.abspath(scene_path)), term["file"])
    name = os.path.splitext(os.path.basename(scene_path))[0]
    copy = os.path.join(workdir, name + ".json")
    out = os.path.join(workdir, name + ".csv")
    with open(copy, "w") as f:
        json.dump(scene, f)
    subprocess.run([lgi, "run", "-q", copy, "-o", out], check=True)
    with open(out) as f:
        rows = list(csv.DictReader(f))
    cols = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    cols["R"] = np.stack([np.array([[float(r["R%d%d" % (i, j)]) for j in (1, 2, 3)] for i in (1, 2, 3)]) for r in rows])
    cols["omega"] = np.stack([cols["omega1"], cols["omega2"], cols["omega3"]], axis=1)
    return scene, cols


def angle(R):
    """The rotation angle of R (rad), robust near 0 and pi."""
    return math.atan2(np.linalg.norm([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2, (np.trace(R) - 1) / 2)


def quaternion_matrix(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def axis_angle_matrix(a):
    axis = np.array(a["axis"], dtype=float)
    axis /= np.linalg.norm(axis)
    th = math.radians(a["angle"]) if a.get("unit") == "deg" else a["angle"]
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K


def target_of(scene):
    for term in scene["problem"]["torques"]:
        if term["type"] == "attitude_control":
            t = term["target"]
            if "R" in t:
                return np.array(t["R"], dtype=float)
            if "quaternion" in t:
                return quaternion_matrix(np.array(t["quaternion"], dtype=float))
            return axis_angle_matrix(t["axis_angle"])
    raise ValueError("no attitude_control term")


def two_panels(png, panels):
    """A figure of two plots side by side: each panel (draw(ax), xlabel, ylabel, title)."""
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    for a, (draw, xlabel, ylabel, title) in zip(ax, panels):
        draw(a)
        a.set_xlabel(xlabel)
        a.set_ylabel(ylabel)
        a.set_title(title)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


def damped_top(lgi, workdir, png):
    scene, c = run(lgi, os.path.join(ROOT, "scenes", "damped_top.json"), 100, workdir)
    t, E = c["t"], c["energy"]
    k = np.array(scene["problem"]["gravity"]["k"], dtype=float)
    tilt = np.degrees([math.acos(max(-1.0, min(1.0, float(R[:, 2] @ k)))) for R in c["R"]])
    rises = np.diff(E)
    two_panels(png, [(lambda a: a.plot(t, E), "t", "energy", "damped heavy top: energy (falls by the damping's work)"),
                     (lambda a: a.plot(t, tilt), "t", "angle of the symmetry axis from k (deg)",
                      "the top loses its spin and hangs down")])
    print("damped_top: E from %.6f to %.6f over t = %g; largest change between rows %.3e; axis from k: %.2f deg at "
          "t = 0, %.2f deg at the end" % (E[0], E[-1], t[-1], rises.max(), tilt[0], tilt[-1]))


def attitude_slew(lgi, workdir, png):
    scene, c = run(lgi, os.path.join(ROOT, "scenes", "attitude_slew.json"), 1, workdir)
    Rd = target_of(scene)
    t = c["t"]
    err = np.array([angle(Rd.T @ R) for R in c["R"]])
    rate = np.linalg.norm(c["omega"], axis=1)
    two_panels(png, [(lambda a: a.semilogy(t, np.degrees(err), marker="."), "t (s)", "angle to the target (deg)",
                      "90 deg PD slew on SO(3): attitude error (adaptive steps)"),
                     (lambda a: a.plot(t, rate, marker="."), "t (s)", "|Omega| (rad/s)", "body rate")])
    print("attitude_slew: %d accepted steps; angle to the target %.1f deg at t = 0, %.3e rad at t = %g; peak |Omega| "
          "%.4f rad/s" % (len(t) - 1, math.degrees(err[0]), err[-1], t[-1], rate.max()))


def torque_replay(lgi, workdir, png):
    scene, c = run(lgi, os.path.join(ROOT, "scenes", "torque_replay.json"), 10, workdir)
    t = c["t"]
    err = np.array([angle(R) for R in c["R"]])  # the target is R = I
    with open(os.path.join(ROOT, "scenes", "torque_replay.csv")) as f:
        table = np.array([[float(x) for x in r] for r in list(csv.reader(f))[1:]])
    k_R = next(term["k_R"] for term in scene["problem"]["torques"] if term["type"] == "attitude_control")
    predicted = np.max(np.linalg.norm(table[:, 1:], axis=1)) / k_R
    def table_panel(a):
        for i, name in enumerate(("M1", "M2", "M3")):
            a.plot(table[:, 0], table[:, i + 1], ".", markersize=3, label=name + " (table rows)")
        a.legend(fontsize=8)

    def error_panel(a):
        a.plot(t, np.degrees(err))
        a.axhline(math.degrees(predicted), color="gray", linestyle="--", label="max |M| / k_R")
        a.legend(fontsize=8)

    two_panels(png, [(table_panel, "t (s)", "laboratory-frame torque (N m)", "replayed disturbance (torque_replay.csv)"),
                     (error_panel, "t (s)", "pointing error (deg)", "PD hold against the disturbance")])
    print("torque_replay: pointing error at most %.3e rad (max |M|/k_R = %.3e rad) over t = %g"
          % (err.max(), predicted, t[-1]))


def flat_spin(lgi, workdir, png):
    scene, c = run(lgi, os.path.join(ROOT, "scenes", "flat_spin.json"), 100, workdir)
    t, E = c["t"], c["energy"]
    m = np.stack([c["momentum_1"], c["momentum_2"], c["momentum_3"]], axis=1)
    I_max = max(scene["problem"]["inertia"])
    flat = float(m[0] @ m[0]) / (2 * I_max)
    # The angle of the body's minor axis e3 (the initial spin axis) from the angular momentum.
    nutation = np.degrees([math.acos(max(-1.0, min(1.0, float(R[:, 2] @ mi) / np.linalg.norm(mi)))) for R, mi in zip(c["R"], m)])
    drift = np.max(np.linalg.norm(m - m[0], axis=1)) / np.linalg.norm(m[0])

    def energy_panel(a):
        a.plot(t, E, label="energy")
        a.axhline(flat, color="gray", linestyle="--", label="|H|^2 / (2 I_max)")
        a.legend(fontsize=8)

    two_panels(png, [(energy_panel, "t", "kinetic energy", "Explorer 1: energy falls at constant |H|"),
                     (lambda a: a.plot(t, nutation), "t", "angle of the minor axis from H (deg)",
                      "from a minor-axis spin to a flat spin")])
    print("flat_spin: E from %.6f to %.15g, |H|^2/(2 I_max) = %.15g (relative %.2e); nutation %.2f -> %.4f deg; "
          "largest rise between rows %.3e; |RH - R0H0|/|H0| <= %.2e"
          % (E[0], E[-1], flat, (E[-1] - flat) / flat, nutation[0], nutation[-1], np.diff(E).max(), drift))


def wheel_slew(lgi, workdir, png):
    scene, c = run(lgi, os.path.join(ROOT, "scenes", "wheel_slew.json"), 5, workdir)
    t = c["t"]
    err = np.array([angle(R) for R in c["R"]])  # the target is R = I
    m = np.stack([c["momentum_1"], c["momentum_2"], c["momentum_3"]], axis=1)
    drift = np.max(np.linalg.norm(m - m[0], axis=1)) / np.linalg.norm(m[0])

    def wheels_panel(a):
        for i in range(len(scene["problem"]["rotors"])):
            a.plot(t, c["rotor_rate_%d" % (i + 1)], label="wheel %d" % (i + 1))
        a.legend(fontsize=8)

    two_panels(png, [(lambda a: a.semilogy(t, err), "t (s)", "angle to the target (rad)",
                      "PD slew through three reaction wheels"),
                     (wheels_panel, "t (s)", "wheel rate relative to the body (rad/s)", "wheel rates")])
    print("wheel_slew: angle to the target %.3f rad at t = 0, %.3e rad at t = %g; |RH - R0H0|/|H0| <= %.2e"
          % (err[0], err[-1], t[-1], drift))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--lgi", default=os.path.join(ROOT, "build", "lgi"))
    args = parser.parse_args()
    img = os.path.join(ROOT, "docs", "img")
    os.makedirs(img, exist_ok=True)
    with tempfile.TemporaryDirectory() as workdir:
        damped_top(args.lgi, workdir, os.path.join(img, "torque_damped_top.png"))
        attitude_slew(args.lgi, workdir, os.path.join(img, "torque_attitude_slew.png"))
        torque_replay(args.lgi, workdir, os.path.join(img, "torque_replay.png"))
        flat_spin(args.lgi, workdir, os.path.join(img, "torque_flat_spin.png"))
        wheel_slew(args.lgi, workdir, os.path.join(img, "torque_wheel_slew.png"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
