"""The Dzhanibekov flip from Python: a free body spun close to its intermediate axis turns over every half period.
Writes the figure of docs/python.md:

    PYTHONPATH=build/python /usr/bin/python3 python/examples/dzhanibekov.py docs/img/python_dzhanibekov.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import lgi  # noqa: E402
import lgi.plot  # noqa: E402

body = lgi.FreeBody(inertia=[2.0, 3.0, 4.0])
r = lgi.integrate(body, omega0=[0.01, 3.0, 0.01], t=np.linspace(0, 40, 4001), method="auto", tolerance=1e-12)
print(r.method, "- energy change", np.ptp(r.columns["energy"]), "- flips of e2:",
      int(np.sum(np.diff(np.sign(r.R[:, 1, 1])) != 0)))

fig = plt.figure(figsize=(11, 4))
lgi.plot.omega(r, fig.add_subplot(1, 2, 1)).set_title("Omega(t): Omega2 changes sign at every flip")
lgi.plot.body_axis(r, axis=2, ax=fig.add_subplot(1, 2, 2, projection="3d"))
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "dzhanibekov.png", dpi=110)
