"""lgi — Lie-group geometric integrators for rigid bodies, from Python.

    import lgi
    result = lgi.run("scenes/heavy_top.json")      # a scene file, or the same scene as a dict
    result.t, result.R, result.omega, result.quaternion, result.columns["energy"]
    print(result.summary)

    top = lgi.HeavyTop(inertia=[2, 2, 1], b=1, k=[0, 0.6, 0.8], z0=[0, 0, 1])   # a problem as an object
    r = lgi.integrate(top, omega0=[0.1, 0.2, 5], t=np.linspace(0, 100, 1001), method="auto", tolerance=1e-10)
    many = lgi.integrate_batch(top, R0, omega0, dt=0.01, steps=1000)          # N bodies on the batched kernels
    rows = lgi.sweep("examples/sweep/sleeping_top.json", threads=0)          # lgi sweep's rows as arrays
    lgi.view(result, "run.html")                                              # the 3D page of lgi view

run() loads and runs the scene with the engine of the `lgi run` command: the same loader, method, steps and rows.
Every number equals the command's CSV to the last printed digit (17 significant digits). A scene that does not
load raises InputError (a ValueError) with the command's one-line message (file, JSON path, what is wrong); a run
that does not complete raises RunError with the command's message, its exit status and the rows it reached.
"""

import json as _json
import os as _os
import sys as _sys

import numpy as _np

# RTLD_GLOBAL: a plugin's library (load_plugin) resolves lgi's functions from this extension module.
_flags = _sys.getdlopenflags()
_sys.setdlopenflags(_flags | _os.RTLD_GLOBAL)
try:
    from . import _lgi
finally:
    _sys.setdlopenflags(_flags)

__all__ = ["run", "integrate", "integrate_batch", "sweep", "fit", "view", "load_plugin", "SweepResult", "methods", "problems", "Problem", "TorqueBody", "Result", "Batch",
           "LgiError", "InputError", "RunError"]


class LgiError(Exception):
    """An error of lgi: `message` is the command's one line, `exit_status` the status `lgi run` exits with."""

    def __init__(self, message, exit_status):
        super().__init__(message)
        self.message = message
        self.exit_status = exit_status


class InputError(LgiError, ValueError):
    """The scene does not load: the message names the file (or "<dict>"), the JSON path and what is wrong."""


class RunError(LgiError, RuntimeError):
    """The run did not complete (a failed step, a budget): `result` holds the rows to the last good state."""

    def __init__(self, message, exit_status, result):
        super().__init__(message, exit_status)
        self.result = result


class Result:
    """The rows of a run as numpy arrays (n = the number of rows) and its summary.

    t (n,), R (n, 3, 3), omega (n, 3) in the body frame, quaternion (n, 4) as (w, x, y, z) with its sign continuous
    along the run, columns: every column of the command's standard row by name (t, R11 … R33, omega1 … omega3,
    energy, orthogonality_error and the problem's invariants) and those of the scene's "output.columns";
    summary: the command's summary (str); status ("completed", "step_failed", "stopped"), steps, wall_seconds, method.
    """

    def __init__(self, raw):
        data = raw["data"]
        names = raw["names"]
        self.t = data[:, 0]  # the standard row: t, R11 … R33, omega1 … omega3, ... (every problem's)
        if names[1:2] == ["R11"]:
            self.R = data[:, 1:10].reshape(-1, 3, 3)
            self.omega = data[:, 10:13]
        self._columns, self._scene_columns = None, (raw.get("scene_names", []), raw.get("scene_data"))
        self.quaternion = raw.get("quaternion")
        self.summary = raw["summary"]
        self.status = raw["status"]
        self.steps = raw["steps"]
        self.wall_seconds = raw["wall_seconds"]
        self.method = raw["method"]
        self._names, self._data, self._scene = names, data, None  # for view()

    @property
    def columns(self):
        if self._columns is None:  # made on first use: most calls never ask
            self._columns = {name: self._data[:, k] for k, name in enumerate(self._names)}
            names, data = self._scene_columns
            for k, name in enumerate(names):
                self._columns.setdefault(name, data[:, k])
        return self._columns

    def __repr__(self):
        return "<lgi.Result %s: %d rows to t = %g, %s>" % (self.method, len(self.t), self.t[-1] if len(self.t) else 0,
                                                           self.status)


def run(scene):
    """Run a scene: a path to a scene file (str or os.PathLike), or the scene as a dict (the file's JSON).

    Returns a Result. Raises InputError (a ValueError) for a scene that does not load, RunError for a run that does
    not complete, TypeError for anything else. File names in a dict (a torque table) are resolved from the current
    directory.
    """
    if isinstance(scene, dict):
        raw = _lgi.run_dict(scene, "<dict>", "")  # "": file names resolved from the current directory
    elif isinstance(scene, (str, bytes, _os.PathLike)):
        raw = _lgi.run_file(_os.fsdecode(scene))
    else:
        raise TypeError("lgi.run: expected a scene file's path or the scene as a dict, got %s" % type(scene).__name__)
    if "data" not in raw:
        raise InputError(raw["error"], raw["exit_status"])
    result = Result(raw)
    result._scene = scene
    if raw["exit_status"] != 0:
        raise RunError(raw["error"], raw["exit_status"], result)
    return result


def _scene_text(scene):
    """(JSON text, name, directory) of a scene given as a path or a dict; ("", "", "") for None."""
    if scene is None:
        return "", "", ""
    if isinstance(scene, (str, bytes, _os.PathLike)):
        path = _os.fsdecode(scene)
        try:
            with open(path, encoding="utf-8") as f:
                return f.read(), path, _os.path.dirname(_os.path.abspath(path))
        except OSError as e:
            raise InputError("%s: cannot read the file: %s" % (path, e.strerror), 1) from None
    if isinstance(scene, dict):
        return _json.dumps(scene, allow_nan=True), "<dict>", _os.getcwd()
    raise TypeError("expected a file's path or a dict, got %s" % type(scene).__name__)


def view(run, path, scene=None, axis=3, max_frames=20000):
    """Write the page of `lgi view` (docs/viewer.md): one self-contained HTML file that animates the run in 3D.

    run: a Result of lgi.run (its scene draws the body), or the path of a run's CSV (then `scene`, a path or a dict,
    draws the body; without it a box stands in). path: the page to write (replaced atomically). axis: the body axis
    whose trace is drawn (1, 2, 3); max_frames: the most frames in the page (longer runs are decimated).
    Returns path. Raises InputError (a ValueError) for what `lgi view` refuses, LgiError when the page cannot be
    written.
    """
    import tempfile
    out = _os.fsdecode(path)
    if isinstance(run, Result):
        import numpy as np
        text, name, directory = _scene_text(run._scene if scene is None else scene)
        with tempfile.TemporaryDirectory(prefix="lgi_view_") as work:
            csv = _os.path.join(work, "run.csv")
            np.savetxt(csv, run._data, fmt="%.17g", delimiter=",", header=",".join(run._names), comments="")
            raw = _lgi.view(csv, text, name, directory, out, int(axis), int(max_frames))
    elif isinstance(run, (str, bytes, _os.PathLike)):
        text, name, directory = _scene_text(scene)
        raw = _lgi.view(_os.fsdecode(run), text, name, directory, out, int(axis), int(max_frames))
    else:
        raise TypeError("lgi.view: expected a Result of lgi.run or a run's CSV path, got %s" % type(run).__name__)
    if "error" in raw:
        if raw["exit_status"] == 1:
            raise InputError(raw["error"], 1)
        raise LgiError(raw["error"], raw["exit_status"])
    return out


def _plain(value):
    """value with numpy arrays and scalars made lists and numbers (for the scene's JSON)."""
    if isinstance(value, _np.ndarray):
        return value.tolist()
    if isinstance(value, _np.generic):
        return value.item()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


class Problem:
    """A problem of a scene (docs/scenes.md): its type and its keys, the scene's "problem" object.

    Problem("heavy_top", inertia=[2, 2, 1], b=1, k=[0, 0.6, 0.8], z0=[0, 0, 1]) equals lgi.HeavyTop(inertia=...):
    every problem type of `lgi list` has its class, named in CamelCase (FreeBody, HeavyTop, LagrangeTop, RigidBody,
    Gyrostat, ...); a plugin's type is Problem(type, ...). The keys are checked by the scene loader when the problem
    runs: a wrong one raises InputError naming its JSON path (/problem/KEY).
    """

    def __init__(self, type, **keys):
        self.type = type
        self.keys = keys

    def scene(self):
        """The scene's "problem" object (a dict)."""
        return {"type": self.type, **_plain(self.keys)}

    def __repr__(self):
        return "lgi.Problem(%r, %s)" % (self.type, ", ".join("%s=%r" % kv for kv in self.keys.items()))


def _problem_class(name, summary):
    def __init__(self, **keys):
        Problem.__init__(self, name, **keys)
    camel = "".join(part.capitalize() for part in name.split("_"))
    return type(camel, (Problem,), {"__init__": __init__, "__doc__": "%s (scene type %r): %s" % (camel, name, summary)})


def _add_problem_classes():
    for p in _lgi.problems():
        if p["name"] == "python_torque":  # TorqueBody below
            continue
        cls = _problem_class(p["name"], p["summary"])
        if cls.__name__ not in globals():
            globals()[cls.__name__] = cls
            __all__.append(cls.__name__)


_add_problem_classes()


def _csv_columns(text):
    """(names, {name: numpy array}) of a CSV's text: numbers as float64 (an empty field as nan), other columns as
    strings."""
    import csv as _csv
    import io as _io
    rows = list(_csv.reader(_io.StringIO(text)))
    names, body = rows[0], rows[1:]
    columns = {}
    for k, name in enumerate(names):
        cells = [row[k] for row in body]
        try:
            columns[name] = _np.array([float(c) if c != "" else _np.nan for c in cells])
        except ValueError:
            columns[name] = _np.array(cells)
    return names, columns


class Crossings:
    """A sweep's Poincaré-section crossings (docs/sweep.md, "The crossings file"), one row per crossing, members in
    member order: member (n,) and crossing (n,) as integers (the crossing's index within its member), t (n,), R
    (n, 3, 3), omega (n, 3); csv holds the command's crossings file."""

    def __init__(self, text):
        self.csv = text
        names, columns = _csv_columns(text)
        self.member = columns["member"].astype(_np.int64)
        self.crossing = columns["crossing"].astype(_np.int64)
        self.t = columns["t"]
        self.R = _np.stack([columns["R%d%d" % (i, j)] for i in (1, 2, 3) for j in (1, 2, 3)], axis=-1).reshape(-1, 3, 3)
        self.omega = _np.stack([columns["omega%d" % i] for i in (1, 2, 3)], axis=-1)

    def __len__(self):
        return len(self.t)

    def of(self, member):
        """The indices of member's crossings (in time order)."""
        return _np.flatnonzero(self.member == member)

    def __repr__(self):
        return "<lgi.Crossings %d crossings of %d members>" % (len(self), len(_np.unique(self.member)))


class SweepResult:
    """The rows of a sweep, one per member, as `lgi sweep` writes them (docs/sweep.md): columns maps every CSV column
    to a numpy array — numbers as float64 (an empty field, a number that was not finite, as nan), the status column
    as strings — and csv holds the command's bytes; crossings: a Crossings where the sweep records them, else None."""

    def __init__(self, text, crossings=None):
        self.csv = text
        self.names, self.columns = _csv_columns(text)
        self.crossings = Crossings(crossings) if crossings is not None else None

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def __repr__(self):
        return "<lgi.SweepResult %d members, columns %s>" % (len(self), ", ".join(self.names))


def sweep(sweep, threads=1):
    """Run a sweep (docs/sweep.md): a sweep file's path, or the sweep as a dict (a scene with a "sweep" section), on
    `threads` threads (0: all cores; the rows do not depend on it) with the engine of `lgi sweep`, the GIL released.
    Returns a SweepResult (with its crossings where the sweep records them); a sweep that does not load raises
    InputError with the command's message. The command's files are written to a temporary directory, read and
    removed."""
    import tempfile
    text, name, _ = _scene_text(sweep)
    with tempfile.TemporaryDirectory(prefix="lgi_sweep_") as work:
        output = _os.path.join(work, "sweep.csv")
        raw = _lgi.sweep(text, name, int(threads), output)
        if "error" in raw:
            if raw["exit_status"] == 1:
                raise InputError(raw["error"], 1)
            raise LgiError(raw["error"], raw["exit_status"])
        with open(output, encoding="utf-8") as f:
            rows = f.read()
        crossings = None
        if raw["crossings"]:
            with open(_os.path.join(work, "sweep.crossings.csv"), encoding="utf-8") as f:
                crossings = f.read()
    return SweepResult(rows, crossings)


def fit(fit):
    """Run a fit (docs/fitting.md, "The lgi fit command"): a fit file's path, or the fit as a dict (a scene with a
    "fit" section; file names in it, the observations', resolved from the current directory), with the engine of
    `lgi fit`, the GIL released. Returns its result JSON as a dict — the fitted values with their standard deviations,
    the residuals, "usable" — also when the solution is not usable ("usable": false, as the command's exit status 5
    and 6 say). A fit that does not load raises InputError with the command's message."""
    if not hasattr(_lgi, "fit"):
        raise LgiError("lgi.fit: this package was built without Ceres (libceres-dev; scripts/install-deps.sh)", 1)
    text, name, _ = _scene_text(fit)
    raw = _lgi.fit(text, name)
    if "error" in raw:
        if raw["exit_status"] == 1:
            raise InputError(raw["error"], 1)
        raise LgiError(raw["error"], raw["exit_status"])
    return _json.loads(raw["result"])


def load_plugin(path):
    """Adds the problem types of a plugin (docs/new_problem.md: a library built with lgi_add_plugin against this lgi),
    as `lgi run --plugin` does: scenes may then use them, and each gets its class (lgi.TetheredTop, ...). Loading the
    same file again does nothing. Raises InputError naming the file and the reason (not found, not an lgi plugin,
    built for another lgi, a type defined already)."""
    raw = _lgi.load_plugin(_os.fsdecode(path))
    if "error" in raw:
        raise InputError(raw["error"], raw["exit_status"])
    _add_problem_classes()


class TorqueBody(Problem):
    """A rigid body whose torque is a Python function: torque(t, R, omega) -> 3 numbers, the body-frame torque at time
    t for the attitude R (3 x 3, body -> laboratory) and the body angular velocity omega (3) — the slow path for a
    torque the scenes do not offer (a controller of your own, a disturbance model), called at every stage with the
    GIL taken (its cost per step: docs/python.md).

        def damping(t, R, omega):
            return -0.1 * omega
        r = lgi.integrate(lgi.TorqueBody(inertia=[1, 2, 3], torque=damping), omega0=[1, 0.1, 0], t=10, method="rkmk4",
                          dt=1e-3)

    Methods: lgvi (its forced Lagrange-d'Alembert form, dM/domega by forward differences: 4 calls and more a step),
    rkmk4 (fixed steps) and rkmk_vern9_cayley (adaptive; "auto" takes it). No
    potential: the energy column is the kinetic energy; momentum_1..3 and momentum_norm follow. An exception in the
    function, or a result that is not 3 finite numbers, stops the run at that step: RunError with the function's
    message and the rows so far. lgi keeps every function it was given for the life of the process.
    """

    def __init__(self, inertia, torque):
        if not callable(torque):
            raise TypeError("lgi.TorqueBody: torque: expected a function torque(t, R, omega), got %s"
                            % type(torque).__name__)
        Problem.__init__(self, "python_torque", inertia=inertia)
        self.function = torque

    def scene(self):
        _lgi.register_callable(id(self.function), self.function)
        return {"type": "python_torque", "inertia": _plain(self.keys["inertia"]), "torque": id(self.function)}

    def __repr__(self):
        return "lgi.TorqueBody(inertia=%r, torque=%r)" % (self.keys["inertia"], self.function)


def _array(value, name, shape):
    """value as a float64 array of `shape` (None: any length there), finite; ValueError naming `name` otherwise."""
    try:
        a = _np.array(value, dtype=float)
    except (TypeError, ValueError) as e:
        raise InputError("%s: not an array of numbers (%s)" % (name, e), 1) from None
    if a.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, a.shape)):
        want = " x ".join("N" if s is None else str(s) for s in shape)
        raise InputError("%s: expected shape %s, got %s" % (name, want, " x ".join(map(str, a.shape)) or "a scalar"), 1)
    if not _np.all(_np.isfinite(a)):
        bad = tuple(int(i) for i in _np.argwhere(~_np.isfinite(a))[0])
        raise InputError("%s%s: not finite (%r)" % (name, list(bad), a[bad]), 1)
    return a


def integrate(problem, R0=None, omega0=(0.0, 0.0, 0.0), t=10.0, method="auto", dt=None, rtol=None, atol=None,
              tolerance=1e-10, quaternion0=None):
    """Integrate `problem` (a Problem) from R(0) = R0 (3 x 3, default the identity; or quaternion0 = (w, x, y, z)),
    Ω(0) = omega0 (body frame) to t_end.

    t: t_end (rows at 0 and t_end), or the increasing output times (rows at 0, at each time in (0, t_end) and at
    t_end = t[-1]). method: "auto" (the default: the method and steps that reach `tolerance`, docs/scenes.md), or any
    method of lgi.methods() with dt (fixed steps) or rtol and atol (the adaptive pairs). Runs the scene
    {problem, initial, integrator, t_end, output} with lgi.run: returns its Result, raises its errors; wrong shapes
    or non-finite values raise InputError (a ValueError) naming the argument.
    """
    if not isinstance(problem, Problem):
        raise TypeError("lgi.integrate: problem: expected an lgi.Problem (lgi.HeavyTop(...), ...), got %s"
                        % type(problem).__name__)
    initial = {"omega": _array(omega0, "omega0", (3,)).tolist()}
    if quaternion0 is not None and R0 is not None:
        raise InputError("give R0 or quaternion0, not both", 1)
    if quaternion0 is not None:
        initial["quaternion"] = _array(quaternion0, "quaternion0", (4,)).tolist()
    elif R0 is not None:
        initial["R"] = _array(R0, "R0", (3, 3)).tolist()
    times = _array(t, "t", (None,)) if _np.ndim(t) == 1 else _array(t, "t", ())
    if times.ndim == 1 and len(times) == 0:
        raise InputError("t: no output times", 1)
    t_end = float(times[-1]) if times.ndim == 1 else float(times)
    if times.ndim == 1:
        if _np.any(_np.diff(times) <= 0) or times[0] < 0:
            raise InputError("t: the output times must increase from t >= 0", 1)
    integrator = {"method": method}
    if method == "auto":
        integrator["tolerance"] = tolerance
    for key, value in (("dt", dt), ("rtol", rtol), ("atol", atol)):
        if value is not None:
            integrator[key] = value
    scene = {"problem": problem.scene(), "initial": initial, "integrator": integrator, "t_end": t_end}
    if times.ndim == 1:
        inside = times[(times > 0) & (times < t_end)]
        if len(inside):
            scene["output"] = {"times": inside.tolist()}
    return run(scene)


class Batch:
    """N bodies of one heavy_top or free_body problem, held by lgi between calls (structure of arrays) and stepped by
    the batched kernels: method "lgvi" (the kick + LGVI) or "rkmk4", vectorised across bodies with AVX-512 or AVX2
    where the CPU has them and J is diagonal, with the same bits as one body at a time (docs/performance.md).

    Batch(problem, R0, omega0, dt, method="lgvi", b=None, threads=1, kernel="automatic"): R0 is N x 3 x 3 rotations,
    used as given (orthogonal to 1e-9, else InputError; None: the identity for every body), omega0 N x 3 (body
    frame), b N values of b for the heavy top (None: the problem's), threads the worker threads (0: all cores), kernel
    "automatic", "avx512", "avx2", "baseline" or "per_body". step(steps) advances every body `steps` steps of dt
    with the GIL released (a body that fails keeps its last good state and stops). Attributes: R (N, 3, 3), omega
    (N, 3), status (N strings: "ok", "not_converged", "non_finite"), steps (good steps of the last call), t, kernel
    (the kernel that ran), seconds (the kernels' wall time so far). Bad arguments raise InputError (a ValueError).
    """

    def __init__(self, problem, R0, omega0, dt, method="lgvi", b=None, threads=1, kernel="automatic"):
        if not isinstance(problem, Problem):
            raise TypeError("lgi.Batch: problem: expected an lgi.Problem, got %s" % type(problem).__name__)
        omega = _array(omega0, "omega0", (None, 3))
        n = omega.shape[0]
        R = _np.broadcast_to(_np.eye(3), (n, 3, 3)) if R0 is None else _array(R0, "R0", (n, 3, 3))
        if R0 is not None and n > 0:
            defect = _np.abs(_np.einsum("nji,njk->nik", R, R) - _np.eye(3)).max(axis=(1, 2))
            worst = int(_np.argmax(defect))
            if defect[worst] > 1e-9:
                raise InputError("R0[%d]: not a rotation (|R^T R - I| = %.3g)" % (worst, defect[worst]), 1)
        per_body = _np.empty(0) if b is None else _array(b, "b", (n,))
        try:
            self._batch = _lgi.Batch(_json.dumps(problem.scene()), _np.ascontiguousarray(R), omega, float(dt), method,
                                     per_body, int(threads), kernel)
        except ValueError as e:
            raise InputError(str(e), 1) from None
        self.seconds = 0.0

    def step(self, steps):
        """Advances every body `steps` steps of dt (the GIL released); returns self."""
        if not isinstance(steps, (int, _np.integer)) or steps < 0:
            raise InputError("steps: expected a number of steps >= 0, got %r" % (steps,), 1)
        try:
            self.seconds += self._batch.step(int(steps))
        except ValueError as e:
            raise InputError(str(e), 1) from None
        return self

    R = property(lambda self: self._batch.R)
    omega = property(lambda self: self._batch.omega)
    steps = property(lambda self: self._batch.steps)
    t = property(lambda self: self._batch.t)
    kernel = property(lambda self: self._batch.kernel)
    status = property(lambda self: _np.array(_lgi.Batch.status_names())[self._batch.status])

    def __len__(self):
        return self._batch.size

    def __repr__(self):
        return "<lgi.Batch %d bodies at t = %g, kernel %s>" % (len(self), self.t, self.kernel)


def integrate_batch(problem, R0, omega0, dt, steps, method="lgvi", b=None, threads=1, kernel="automatic"):
    """Batch(problem, R0, omega0, dt, method, b, threads, kernel).step(steps): N bodies, each from its own
    (R0[i], omega0[i]) at t = 0, `steps` steps of dt on the batched kernels. Returns the Batch (R, omega, status,
    steps, kernel, seconds; step() continues it)."""
    return Batch(problem, R0, omega0, dt, method, b, threads, kernel).step(steps)


def methods():
    """The methods `lgi list` prints: a list of dicts (name, title, order, free_body_order, symplectic, symmetric,
    explicit, exact_on_group, preserves_momentum, exact_solution, options)."""
    return _lgi.methods()


def problems():
    """The problem types `lgi list` prints: a list of dicts (name, summary, keys, methods)."""
    return _lgi.problems()
