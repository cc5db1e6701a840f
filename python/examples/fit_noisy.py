"""A fit from noisy data, in Python: a heavy top's initial spin and two principal moments recovered from attitudes
(noise 1e-3 rad) and gyro readings (noise 1e-2 rad/s) that lgi itself simulated (docs/python.md):

    PYTHONPATH=build/python /usr/bin/python3 python/examples/fit_noisy.py
"""
import numpy as np

import lgi


def rotation(v):
    """exp(hat(v)) by Rodrigues' formula."""
    angle = np.linalg.norm(v)
    K = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / max(angle, 1e-300)
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


truth = dict(inertia=[1.0, 1.2, 1.7], b=1.3, k=[0.0, 0.6, 0.8], z0=[0.6, 0.0, 0.8])
omega0 = [0.7, -0.4, 1.1]
times = np.linspace(0.5, 10, 20)
r = lgi.integrate(lgi.HeavyTop(**truth), omega0=omega0, t=times, method="lgvi", dt=0.01)

rng = np.random.default_rng(7)
observations = []
for t, R, w in zip(r.t[1:], r.R[1:], r.omega[1:]):  # the rows at the observation times (the first is t = 0)
    observations.append({"t": t, "sigma": 1e-3, "R": (R @ rotation(rng.normal(0, 1e-3, 3))).tolist()})
    observations.append({"t": t, "sigma": 1e-2, "omega": (w + rng.normal(0, 1e-2, 3)).tolist()})

guess = dict(truth, inertia=[1.1, 1.1, 1.7])  # 10 % off in I1 and I2; I3 held (it sets the scale)
fit = lgi.fit({
    "problem": {"type": "heavy_top", **guess},
    "initial": {"omega": [0.84, -0.48, 1.32]},  # 20 % off
    "integrator": {"method": "lgvi", "dt": 0.01},
    "t_end": 10,
    "fit": {"unknowns": ["initial.omega", {"name": "problem.inertia", "fixed": [2]}],
            "observations": observations, "continuation": [0.1, 0.3]},
})
print("usable:", fit["usable"], " chi^2 / dof:", round(fit["chi_square"] / fit["degrees_of_freedom"], 3))
for name, value, sigma, true in [("omega0", fit["initial"]["omega"], fit["sigma"]["initial"]["omega"], omega0),
                                 ("inertia", fit["problem"]["inertia"], fit["sigma"]["problem"]["inertia"],
                                  truth["inertia"])]:
    for i in range(3):
        print("%s[%d] = %.5f +- %.5f   (true %.5f, %.1f sigma off)" % (
            name, i, value[i], sigma[i], true[i], abs(value[i] - true[i]) / sigma[i] if sigma[i] else 0.0))
