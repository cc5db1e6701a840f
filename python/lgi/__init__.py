"""lgi — Lie-group geometric integrators for rigid bodies, from Python.

    import lgi
    result = lgi.run("scenes/heavy_top.json")      # a scene file, or the same scene as a dict
    result.t, result.R, result.omega, result.quaternion, result.columns["energy"]
    print(result.summary)

run() loads and runs the scene with the engine of the `lgi run` command: the same loader, method, steps and rows.
Every number equals the command's CSV to the last printed digit (17 significant digits). A scene that does not
load raises InputError (a ValueError) with the command's one-line message (file, JSON path, what is wrong); a run
that does not complete raises RunError with the command's message, its exit status and the rows it reached.
"""

import json as _json
import os as _os

import numpy as _np

from . import _lgi

__all__ = ["run", "methods", "problems", "Result", "LgiError", "InputError", "RunError"]


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
        self.columns = {name: data[:, k] for k, name in enumerate(names)}
        for k, name in enumerate(raw.get("scene_names", [])):
            self.columns.setdefault(name, raw["scene_data"][:, k])
        self.t = self.columns["t"]
        if "R11" in self.columns:
            self.R = data[:, names.index("R11"):names.index("R11") + 9].reshape(-1, 3, 3)
            self.omega = data[:, names.index("omega1"):names.index("omega1") + 3]
        self.quaternion = raw.get("quaternion")
        self.summary = raw["summary"]
        self.status = raw["status"]
        self.steps = raw["steps"]
        self.wall_seconds = raw["wall_seconds"]
        self.method = raw["method"]
        self._names, self._data, self._scene = names, data, None  # for view()

    def __repr__(self):
        return "<lgi.Result %s: %d rows to t = %g, %s>" % (self.method, len(self.t), self.t[-1] if len(self.t) else 0,
                                                           self.status)


def run(scene):
    """Run a scene: a path to a scene file (str or os.PathLike), or the scene as a dict (the file's JSON).

    Returns a Result. Raises InputError (a ValueError) for a scene that does not load, RunError for a run that does
    not complete, TypeError for anything else. File names in a dict (a torque table) are resolved from the current
    directory.
    """
    if isinstance(scene, (str, bytes, _os.PathLike)):
        raw = _lgi.run_file(_os.fsdecode(scene))
    elif isinstance(scene, dict):
        try:
            text = _json.dumps(scene, allow_nan=True)
        except (TypeError, ValueError) as e:
            raise InputError("<dict>: not a JSON document: %s" % e, 1) from None
        raw = _lgi.run_text(text, "<dict>", _os.getcwd())
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
            raise InputError("%s: cannot read the scene: %s" % (path, e.strerror), 1) from None
    if isinstance(scene, dict):
        return _json.dumps(scene, allow_nan=True), "<dict>", _os.getcwd()
    raise TypeError("lgi.view: scene: expected a scene file's path or a dict, got %s" % type(scene).__name__)


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


def methods():
    """The methods `lgi list` prints: a list of dicts (name, title, order, free_body_order, symplectic, symmetric,
    explicit, exact_on_group, preserves_momentum, exact_solution, options)."""
    return _lgi.methods()


def problems():
    """The problem types `lgi list` prints: a list of dicts (name, summary, keys, methods)."""
    return _lgi.problems()
