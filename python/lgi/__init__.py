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
    if raw["exit_status"] != 0:
        raise RunError(raw["error"], raw["exit_status"], result)
    return result


def methods():
    """The methods `lgi list` prints: a list of dicts (name, title, order, free_body_order, symplectic, symmetric,
    explicit, exact_on_group, preserves_momentum, exact_solution, options)."""
    return _lgi.methods()


def problems():
    """The problem types `lgi list` prints: a list of dicts (name, summary, keys, methods)."""
    return _lgi.problems()
