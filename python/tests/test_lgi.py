"""Tests of lgi's Python package (python/lgi) against the lgi command: run by CTest (test `python`) with
PYTHONPATH = the build's python/ directory, LGI_EXE = the command, LGI_SOURCE_DIR = the source tree."""

import copy
import glob
import json
import os
import random
import subprocess
import threading
import time

import numpy as np
import pytest

import lgi

SOURCE = os.environ.get("LGI_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
LGI = os.environ.get("LGI_EXE", os.path.join(SOURCE, "build", "lgi"))
SCENES = sorted(glob.glob(os.path.join(SOURCE, "scenes", "*.json")))


def command_csv(scene, tmp_path):
    out = tmp_path / "rows.csv"
    done = subprocess.run([LGI, "run", "-q", scene, "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = out.read_text().splitlines()
    names = lines[0].split(",")
    rows = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    return names, rows


@pytest.mark.parametrize("scene", SCENES, ids=[os.path.basename(s) for s in SCENES])
def test_every_example_scene_equals_the_command_to_the_last_digit(scene, tmp_path):
    names, rows = command_csv(scene, tmp_path)
    result = lgi.run(scene)
    assert result.status == "completed"
    assert len(result.t) == rows.shape[0]
    for k, name in enumerate(names):
        assert np.array_equal(result.columns[name], rows[:, k]), name
    if "R11" in result.columns:
        assert result.R.shape == (rows.shape[0], 3, 3)
        assert np.array_equal(result.R[:, 1, 2], result.columns["R23"])
        assert np.array_equal(result.omega[:, 2], result.columns["omega3"])
        # The quaternion is R's (R = R(q), (w, x, y, z)), its sign continuous.
        w, x, y, z = result.quaternion.T
        assert np.allclose(result.R[:, 0, 1], 2 * (x * y - w * z), atol=1e-14)
        assert np.all(np.sum(result.quaternion[1:] * result.quaternion[:-1], axis=1) >= 0)
    assert "steps" in result.summary and result.steps > 0


def test_a_dict_runs_as_its_file():
    path = os.path.join(SOURCE, "scenes", "heavy_top.json")
    with open(path) as f:
        scene = json.load(f)
    a, b = lgi.run(path), lgi.run(scene)
    assert np.array_equal(a.columns["omega2"], b.columns["omega2"]) and np.array_equal(a.R, b.R)
    assert b.summary.startswith("<dict>: heavy_top, lgvi")


def heavy_top(**integrator):
    return {"problem": {"type": "heavy_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0, 1], "z0": [0, 0, 1]},
            "initial": {"omega": [0.1, 0.2, 5]},
            "integrator": integrator or {"method": "lgvi", "dt": 0.01}, "t_end": 1.0}


def test_bad_input_raises_value_error_with_the_command_message_and_status():
    scene = heavy_top()
    scene["problem"]["inertai"] = [1, 2, 3]
    with pytest.raises(lgi.InputError) as e:
        lgi.run(scene)
    assert isinstance(e.value, ValueError)
    assert e.value.exit_status == 1
    assert e.value.message.startswith("<dict>: /problem/inertai: unknown key")
    with pytest.raises(lgi.InputError, match="/initial/omega: expected an array of 3 numbers"):
        lgi.run(dict(heavy_top(), initial={"omega": [1, 2]}))
    with pytest.raises(lgi.InputError, match="no_such.json"):
        lgi.run("no_such.json")
    with pytest.raises(TypeError):
        lgi.run(42)


def test_a_failed_step_raises_with_the_rows_it_reached():
    scene = heavy_top(method="lgvi", dt=0.5)  # h|Omega| = 2.5: beyond the LGVI's implicit equation
    with pytest.raises(lgi.RunError) as e:
        lgi.run(scene)
    assert e.value.exit_status == 2
    assert "failed: Newton iteration did not converge" in e.value.message
    assert e.value.result.status == "step_failed" and len(e.value.result.t) >= 1


def test_method_auto_and_the_registry():
    r = lgi.run(heavy_top(method="auto", tolerance=1e-8))
    assert r.method == "rkmk_vern9_cayley" and "method auto" in r.summary
    names = [m["name"] for m in lgi.methods()]
    listed = subprocess.run([LGI, "list"], capture_output=True, text=True).stdout
    assert len(names) == 48 and all(" " + n + " " in listed for n in names)
    assert {p["name"] for p in lgi.problems()} >= {"free_body", "heavy_top", "lagrange_top", "gyrostat"}


def mutate(scene, rng):
    """One random edit of a valid scene: a key renamed, a value replaced by a value of another type, a number
    made NaN or huge, an array shortened, a section removed."""
    s = copy.deepcopy(scene)
    paths = []

    def walk(node, path):
        if isinstance(node, dict):
            for k, v in node.items():
                paths.append(path + [k])
                walk(v, path + [k])
        elif isinstance(node, list):
            for i, v in enumerate(node):
                paths.append(path + [i])
                walk(v, path + [i])
    walk(s, [])
    path = rng.choice(paths)
    parent = s
    for k in path[:-1]:
        parent = parent[k]
    key = path[-1]
    choice = rng.randrange(6)
    if choice == 0 and isinstance(key, str):
        parent[key + "x"] = parent.pop(key)
    elif choice == 1:
        parent[key] = rng.choice(["text", None, True, [], {}, [1, 2], -1.0, 0])
    elif choice == 2:
        parent[key] = rng.choice([float("nan"), float("inf"), 1e308, -1e308, 1e-308])
    elif choice == 3 and isinstance(parent[key], list) and parent[key]:
        parent[key].pop()
    elif isinstance(parent, dict):
        del parent[key]
    else:
        parent[key] = "x"
    return s


def test_a_thousand_malformed_dicts_raise_value_errors_and_nothing_crashes():
    rng = random.Random(20261127)
    scene = heavy_top()
    scene["t_end"] = 0.05
    errors = 0
    for _ in range(1000):
        try:
            lgi.run(mutate(scene, rng))
        except lgi.InputError as e:
            errors += 1
            assert e.message.startswith("<dict>:") and "\n" not in e.message
        except lgi.RunError as e:
            assert e.exit_status in (2, 6)
    assert errors > 500


def test_the_gil_is_released_while_a_run_integrates():
    scene = heavy_top(method="rkmk4", dt=1e-4)
    scene["t_end"] = 50.0  # about 0.3 s
    ticks = 0
    done = threading.Event()

    def work():
        lgi.run(scene)
        done.set()

    thread = threading.Thread(target=work)
    start = time.perf_counter()
    thread.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    thread.join()
    assert time.perf_counter() - start > 0.05
    assert ticks >= 20  # the main thread ran while the run integrated


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_no_memory_growth_over_ten_thousand_calls():
    scene = heavy_top()
    scene["t_end"] = 0.02
    for _ in range(200):
        lgi.run(scene)
    before = rss_bytes()
    for _ in range(10000):
        lgi.run(scene)
    assert rss_bytes() - before < 8 << 20


def test_view_writes_the_page_of_lgi_view(tmp_path):
    """lgi.view(result) gives the page `lgi view` gives for the command's CSV and scene; bad input raises ValueError."""
    scene = os.path.join(SOURCE, "scenes", "wheel_slew.json")
    result = lgi.run(scene)
    page = tmp_path / "from_python.html"
    assert lgi.view(result, page) == str(page)
    csv, command_page = tmp_path / "run.csv", tmp_path / "run.html"
    done = subprocess.run([LGI, "run", "-q", scene, "-o", str(csv), "--html", str(command_page)], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    # The same page but for the CSV's file name, which the page names.
    assert page.read_text().replace("run.csv", "X") == command_page.read_text().replace("run.csv", "X")
    assert lgi.view(str(csv), tmp_path / "from_csv.html", scene=scene).endswith("from_csv.html")
    assert (tmp_path / "from_csv.html").read_text() == command_page.read_text()
    bare = tmp_path / "bare.html"
    lgi.view(str(csv), bare, axis=1, max_frames=5)
    assert '"known":false' in bare.read_text() and '"frames":5,' in bare.read_text()
    not_a_run = tmp_path / "notes.csv"
    not_a_run.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="notes.csv: no column t"):
        lgi.view(str(not_a_run), tmp_path / "never.html")
    with pytest.raises(ValueError, match="--axis: must be 1, 2 or 3"):
        lgi.view(result, tmp_path / "never.html", axis=0)
    with pytest.raises(ValueError, match="unknown-problem|/problem/type"):
        lgi.view(str(csv), tmp_path / "never.html", scene={"problem": {"type": "unknown-problem"}})
    assert not (tmp_path / "never.html").exists()
