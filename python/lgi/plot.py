"""Plots of lgi results with matplotlib (optional: imported when a function here is called).

    import lgi, lgi.plot
    r = lgi.run("scenes/heavy_top.json")
    fig = lgi.plot.overview(r)               # the four panels below in one figure
    lgi.plot.invariants(r)                    # |X(t) - X(0)| / |X(0)| of the energy and every invariant, log scale
    lgi.plot.body_axis(r, axis=3)             # the trace of R(t) e_axis on the unit sphere (3D axes)
    lgi.plot.omega(r)                         # Omega_1, Omega_2, Omega_3 (body frame) against t
    lgi.plot.work_precision({"lgvi": (cost, error), ...})   # error against cost, log-log, one line per method

Each function draws into `ax` when given (for body_axis a 3D axes) or into new axes of a new figure, and returns the
axes. Nothing is shown or saved: call matplotlib's plt.show() or fig.savefig().
"""

import numpy as _np

_STANDARD = {"t", "omega1", "omega2", "omega3", "orthogonality_error"} | {"R%d%d" % (r, c) for r in (1, 2, 3)
                                                                            for c in (1, 2, 3)}
_TINY = 1e-300  # a floor for log axes: a change of exactly 0 is drawn there


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("lgi.plot needs matplotlib (Debian: apt-get install python3-matplotlib)") from e
    return plt


def _axes(ax, projection=None):
    if ax is not None:
        return ax
    plt = _pyplot()
    fig = plt.figure()
    return fig.add_subplot(projection=projection) if projection else fig.add_subplot()


def invariant_names(result):
    """The columns lgi.plot.invariants draws: energy and the problem's invariants (not t, R, Omega, the
    orthogonality error, nor the scene's own output columns)."""
    names = [n for n in result._names if n not in _STANDARD]
    return names


def relative_change(values):
    """|X(t) - X(0)| / |X(0)| (|X(t) - X(0)| where X(0) = 0)."""
    values = _np.asarray(values, dtype=float)
    scale = abs(values[0]) if values[0] != 0 else 1.0
    return _np.abs(values - values[0]) / scale


def invariants(result, ax=None, names=None):
    """The relative change of the energy and each invariant against t, log scale (a change of 0 at the floor)."""
    ax = _axes(ax)
    for name in names or invariant_names(result):
        ax.plot(result.t, _np.maximum(relative_change(result.columns[name]), _TINY), label=name)
    ax.set_yscale("log")
    ax.set_xlabel("t")
    ax.set_ylabel("|X(t) - X(0)| / |X(0)|")
    ax.legend(fontsize="small")
    return ax


def body_axis(result, axis=3, ax=None):
    """The trace of the body axis R(t) e_axis (axis 1, 2 or 3) on the unit sphere, in a 3D axes."""
    if axis not in (1, 2, 3):
        raise ValueError("axis: must be 1, 2 or 3, got %r" % (axis,))
    ax = _axes(ax, projection="3d")
    u, v = _np.mgrid[0:2 * _np.pi:25j, 0:_np.pi:13j]
    ax.plot_wireframe(_np.cos(u) * _np.sin(v), _np.sin(u) * _np.sin(v), _np.cos(v), color="0.85", linewidth=0.5)
    trace = result.R[:, :, axis - 1]
    ax.plot(trace[:, 0], trace[:, 1], trace[:, 2], color="C1", linewidth=1.0)
    ax.scatter(*trace[0], color="C2", s=12, label="t = %g" % result.t[0])
    ax.scatter(*trace[-1], color="C3", s=12, label="t = %g" % result.t[-1])
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_box_aspect((1, 1, 1))
    ax.set_title("R(t) e%d" % axis)
    ax.legend(fontsize="small")
    return ax


def omega(result, ax=None):
    """Omega_1, Omega_2, Omega_3 in the body frame against t."""
    ax = _axes(ax)
    for i in range(3):
        ax.plot(result.t, result.omega[:, i], label="Omega%d" % (i + 1))
    ax.set_xlabel("t")
    ax.set_ylabel("body angular velocity")
    ax.legend(fontsize="small")
    return ax


def work_precision(curves, ax=None, xlabel="cost (s)", ylabel="error"):
    """Error against cost on log-log axes: curves maps a label to (costs, errors), one point per run (for example a
    method's CPU time and error at each tolerance of a sweep)."""
    ax = _axes(ax)
    for label, (cost, error) in curves.items():
        cost, error = _np.asarray(cost, dtype=float), _np.asarray(error, dtype=float)
        order = _np.argsort(cost)
        ax.plot(cost[order], _np.maximum(error[order], _TINY), marker="o", markersize=3, label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize="small")
    return ax


def overview(result, axis=3):
    """One figure: the invariants' relative change, Omega(t), the body axis on the sphere, and the orthogonality
    error. Returns the figure."""
    plt = _pyplot()
    fig = plt.figure(figsize=(11, 7.5))
    invariants(result, fig.add_subplot(2, 2, 1))
    omega(result, fig.add_subplot(2, 2, 2))
    body_axis(result, axis, fig.add_subplot(2, 2, 3, projection="3d"))
    ax = fig.add_subplot(2, 2, 4)
    ax.plot(result.t, _np.maximum(result.columns["orthogonality_error"], _TINY), color="C4")
    ax.set_yscale("log")
    ax.set_xlabel("t")
    ax.set_ylabel("|R^T R - I|")
    fig.suptitle("%s, %s" % (result.summary.splitlines()[0].split(": ", 1)[-1].split(",")[0], result.method))
    fig.tight_layout()
    return fig
