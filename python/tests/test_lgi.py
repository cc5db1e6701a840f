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


def test_a_dict_is_read_as_its_json_would_be(tmp_path):
    # numpy arrays and scalars are taken as their lists and numbers; the run is the one of the same JSON text.
    scene = dict(heavy_top(), output={"interval": 0.05})
    (tmp_path / "scene.json").write_text(json.dumps(scene))
    as_numpy = dict(scene, initial={"omega": np.array([0.1, 0.2, 5.0])}, t_end=np.float64(1.0))
    a, b = lgi.run(as_numpy), lgi.run(tmp_path / "scene.json")
    assert len(a.t) > 10 and np.array_equal(a._data, b._data)
    refused = [
        (dict(scene, t_end=float("nan")), r"^<dict>: /t_end: nan is not a number JSON can hold$"),
        (dict(scene, initial={"omega": [0.1, float("inf"), 5]}), r"^<dict>: /initial/omega/1: inf is not a number"),
        (dict(scene, problem=dict(scene["problem"], **{"a/b": 1})), r"^<dict>: /problem/a~1b: unknown key"),
        (dict(scene, extra={1: 2}), r"^<dict>: /extra: a key that is not a string: \"1\""),
        (dict(scene, t_end=2 ** 70), r"^<dict>: /t_end: the integer \"1180591620717411303424\" does not fit in 64 bits"),
        (dict(scene, t_end={1.5}), r"^<dict>: /t_end: a set, which JSON cannot hold"),
    ]
    for bad, message in refused:
        with pytest.raises(lgi.InputError, match=message):
            lgi.run(bad)
    deep = {}
    deep["self"] = deep  # a dict that holds itself: refused at the depth limit, no recursion without end
    with pytest.raises(lgi.InputError, match=r"^<dict>: /extra(/self)+: nested deeper than 64 levels"):
        lgi.run(dict(scene, extra=deep))


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


TOP = dict(inertia=[2.0, 2.0, 1.0], b=1.0, k=[0.0, 0.6, 0.8], z0=[0.0, 0.0, 1.0])


def test_problems_are_classes_and_integrate_runs_their_scene():
    top = lgi.HeavyTop(**TOP)
    assert isinstance(top, lgi.Problem) and top.scene() == {"type": "heavy_top", **TOP}
    assert {"FreeBody", "HeavyTop", "LagrangeTop", "RigidBody", "Gyrostat"} <= set(lgi.__all__)
    R0 = lgi.run({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"axis_angle": {
        "axis": [1, 2, 2], "angle": 0.4}, "omega": [0, 0, 0]}, "integrator": {"method": "lgvi", "dt": 1}, "t_end": 0}).R[0]
    r = lgi.integrate(top, R0=R0, omega0=np.array([0.1, 0.2, 5.0]), t=[0.5, 1.0, 2.0], method="lgvi", dt=0.001)
    same = lgi.run({"problem": top.scene(), "initial": {"R": R0.tolist(), "omega": [0.1, 0.2, 5.0]},
                    "integrator": {"method": "lgvi", "dt": 0.001}, "t_end": 2.0, "output": {"times": [0.5, 1.0]}})
    assert np.array_equal(r.t, [0.0, 0.5, 1.0, 2.0])
    for name in same.columns:
        assert np.array_equal(r.columns[name], same.columns[name]), name
    auto = lgi.integrate(top, quaternion0=[1, 0, 0, 0], omega0=[0.1, 0.2, 5.0], t=3.0, tolerance=1e-8)
    assert auto.method == "rkmk_vern9_cayley" and np.array_equal(auto.t, [0.0, 3.0])


@pytest.mark.parametrize("kwargs, message", [
    (dict(omega0=[1, 2]), "omega0: expected shape 3, got 2"),
    (dict(omega0=[1, float("nan"), 2]), r"omega0\[1\]: not finite"),
    (dict(R0=np.eye(2)), "R0: expected shape 3 x 3, got 2 x 2"),
    (dict(R0=np.eye(3), quaternion0=[1, 0, 0, 0]), "give R0 or quaternion0, not both"),
    (dict(t=[1.0, 0.5]), "t: the output times must increase"),
    (dict(t=np.array([])), "t: no output times"),
    (dict(omega0="fast"), "omega0: not an array of numbers"),
    (dict(method="lgvi"), "/integrator"),
])
def test_integrate_refuses_bad_arguments_naming_them(kwargs, message):
    with pytest.raises(ValueError, match=message):
        lgi.integrate(lgi.HeavyTop(**TOP), **kwargs)
    with pytest.raises(ValueError, match="/problem/bb"):
        lgi.integrate(lgi.HeavyTop(bb=1, **TOP), omega0=[0, 0, 1], t=1.0)


def random_bodies(n, seed=7):
    rng = np.random.default_rng(seed)
    omega = rng.normal(size=(n, 3))
    omega[:, 2] += 5.0
    R = np.array([lgi.run({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
                           "initial": {"axis_angle": {"axis": rng.normal(size=3).tolist(), "angle": float(rng.uniform(0, 3))},
                                       "omega": [0, 0, 0]},
                           "integrator": {"method": "lgvi", "dt": 1}, "t_end": 0}).R[0] for _ in range(n)])
    return R, omega


@pytest.mark.parametrize("method", ["lgvi", "rkmk4"])
def test_a_batch_equals_its_bodies_run_one_by_one_to_the_bit(method):
    top = lgi.HeavyTop(**TOP)
    R, omega = random_bodies(19)
    b = np.linspace(0.5, 1.5, 19)
    ones = [lgi.integrate(lgi.HeavyTop(**dict(TOP, b=b[i])), R0=R[i], omega0=omega[i], t=0.5, method=method, dt=0.01)
            for i in range(19)]
    R = np.array([one.R[0] for one in ones])  # the loader's R (an R read from a scene is made exact)
    for kernel in ("automatic", "baseline", "per_body"):
        many = lgi.integrate_batch(top, R, omega, dt=0.01, steps=50, method=method, b=b, kernel=kernel)
        assert list(many.status) == ["ok"] * 19 and np.all(many.steps == 50)
        for i, one in enumerate(ones):
            assert np.array_equal(many.R[i], one.R[-1]), (kernel, i)
            assert np.array_equal(many.omega[i], one.omega[-1]), (kernel, i)


def test_a_batch_refuses_what_its_kernels_do_not_take():
    R, omega = random_bodies(3)
    top = lgi.HeavyTop(**TOP)
    with pytest.raises(ValueError, match="R0: expected shape 3 x 3 x 3, got 2 x 3 x 3"):
        lgi.integrate_batch(top, R[:2], omega, dt=0.01, steps=1)
    with pytest.raises(ValueError, match=r"omega0\[2, 0\]: not finite"):
        lgi.integrate_batch(top, R, np.vstack([omega[:2], [np.inf, 0, 0]]), dt=0.01, steps=1)
    with pytest.raises(ValueError, match=r"R0\[1\]: not a rotation"):
        lgi.integrate_batch(top, R * np.array([1, 1.01, 1])[None, :, None], omega, dt=0.01, steps=1)
    with pytest.raises(ValueError, match="heavy_top and free_body problems, not lagrange_top"):
        lgi.integrate_batch(lgi.LagrangeTop(inertia=[2, 2, 1], b=1, k=[0, 0, 1]), R, omega, dt=0.01, steps=1)
    with pytest.raises(ValueError, match="method must be lgvi or rkmk4"):
        lgi.integrate_batch(top, R, omega, dt=0.01, steps=1, method="rkmk_vern9_cayley")
    with pytest.raises(ValueError, match="kernel must be"):
        lgi.integrate_batch(top, R, omega, dt=0.01, steps=1, kernel="gpu")
    with pytest.raises(ValueError, match="steps: expected a number of steps"):
        lgi.integrate_batch(top, R, omega, dt=0.01, steps=-1)


def test_the_gil_is_released_while_a_batch_integrates():
    top = lgi.HeavyTop(**TOP)
    omega = np.tile([0.1, 0.2, 5.0], (4096, 1))
    ticks = 0
    done = threading.Event()

    def work():
        lgi.integrate_batch(top, None, omega, dt=0.01, steps=3000, kernel="baseline")  # about 0.3 s
        done.set()

    thread = threading.Thread(target=work)
    thread.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    thread.join()
    assert ticks >= 20


def test_a_batch_continues_where_it_stopped():
    top = lgi.HeavyTop(**TOP)
    _, omega = random_bodies(5)
    held = lgi.Batch(top, None, omega, dt=0.01)
    assert len(held) == 5 and held.t == 0
    held.step(25).step(25)
    once = lgi.integrate_batch(top, None, omega, dt=0.01, steps=50)
    assert held.t == 0.5 and np.all(held.steps == 25) and np.all(once.steps == 50)
    # Each call rebuilds the method's internal coordinates (Pi = J Omega) from (R, Omega): equal to round-off.
    assert np.abs(held.R - once.R).max() < 1e-13 and np.abs(held.omega - once.omega).max() < 1e-12
    assert held.seconds > 0 and held.kernel in ("avx512", "avx2", "baseline")


def test_plots_draw_the_result_columns(tmp_path):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import lgi.plot
    r = lgi.run(os.path.join(SOURCE, "scenes", "wheel_slew.json"))
    ax = lgi.plot.invariants(r)
    names = [line.get_label() for line in ax.lines]
    assert names == ["energy", "momentum_1", "momentum_2", "momentum_3", "momentum_norm", "rotor_rate_1",
                     "rotor_rate_2", "rotor_rate_3"]
    energy = r.columns["energy"]
    assert np.array_equal(ax.lines[0].get_ydata(), np.maximum(np.abs(energy - energy[0]) / abs(energy[0]), 1e-300))
    w = lgi.plot.omega(r)
    assert np.array_equal(w.lines[2].get_ydata(), r.omega[:, 2])
    sphere = lgi.plot.body_axis(r, axis=2)
    x, y, z = sphere.lines[0].get_data_3d()
    assert np.array_equal(np.stack([x, y, z], 1), r.R[:, :, 1])
    with pytest.raises(ValueError, match="axis: must be 1, 2 or 3"):
        lgi.plot.body_axis(r, axis=4)
    wp = lgi.plot.work_precision({"lgvi": ([3.0, 1.0, 2.0], [1e-3, 1e-1, 1e-2])})
    assert np.array_equal(wp.lines[0].get_xdata(), [1.0, 2.0, 3.0])
    fig = lgi.plot.overview(r)
    fig.savefig(tmp_path / "overview.png")
    assert (tmp_path / "overview.png").stat().st_size > 20000


@pytest.mark.parametrize("name", ["sleeping_top.json", "heavy_top_cloud.json"])
def test_a_sweep_gives_the_command_s_bytes(name, tmp_path):
    path = os.path.join(SOURCE, "examples", "sweep", name)
    out = tmp_path / "sweep.csv"
    done = subprocess.run([LGI, "sweep", "-q", path, "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    result = lgi.sweep(path, threads=2)
    assert result.csv == out.read_text()
    with open(path) as f:
        assert lgi.sweep(json.load(f)).csv == result.csv  # a dict: file names resolved from the current directory
    assert result.columns["member"].dtype == float and set(result.columns["status"]) <= {"completed"}
    assert len(result) == len(out.read_text().splitlines()) - 1


def test_a_sweep_refuses_what_the_command_refuses():
    with open(os.path.join(SOURCE, "examples", "sweep", "sleeping_top.json")) as f:
        sweep = json.load(f)
    sweep["sweep"]["grid"] = {"/initial/nope": [1, 2]}
    with pytest.raises(ValueError, match=r"<dict>: /sweep/grid/~1initial~1nope: \"/initial/nope\" is not in the scene"):
        lgi.sweep(sweep)


def test_a_sweep_s_crossings_are_the_command_s(tmp_path):
    with open(os.path.join(SOURCE, "examples", "sweep", "heavy_top_poincare.json")) as f:
        sweep = json.load(f)
    sweep["t_end"] = 50.0
    sweep["sweep"]["grid"]["/initial/euler_angles/2"]["count"] = 20
    path = tmp_path / "poincare.json"
    path.write_text(json.dumps(sweep))
    out = tmp_path / "poincare.csv"
    done = subprocess.run([LGI, "sweep", "-q", str(path), "-o", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    result = lgi.sweep(path, threads=2)
    assert result.csv == out.read_text()
    command = (tmp_path / "poincare.crossings.csv").read_text()
    assert result.crossings.csv == command
    c = result.crossings
    rows = [line.split(",") for line in command.splitlines()[1:]]
    assert len(c) == len(rows) > 0
    k = len(rows) // 2
    assert c.member[k] == int(rows[k][0]) and c.crossing[k] == int(rows[k][1]) and c.t[k] == float(rows[k][2])
    assert np.array_equal(c.R[k], np.array([float(x) for x in rows[k][3:12]]).reshape(3, 3))
    assert np.array_equal(c.omega[k], [float(x) for x in rows[k][12:15]])
    # Each member's count in the rows is its number of crossings.
    counts = result.columns["crossings"]
    for m in range(len(result)):
        assert len(c.of(m)) == counts[m]
    assert lgi.sweep(os.path.join(SOURCE, "examples", "sweep", "sleeping_top.json")).crossings is None


def test_a_fit_gives_the_command_s_result(tmp_path):
    if not hasattr(lgi._lgi, "fit"):
        pytest.skip("built without Ceres")
    for name in ("fit.json", "truth.json"):
        (tmp_path / name).write_text(open(os.path.join(SOURCE, "examples", "fit", name)).read())
    done = subprocess.run([LGI, "run", "-q", str(tmp_path / "truth.json"), "-o", str(tmp_path / "obs.csv")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    command = subprocess.run([LGI, "fit", "-q", str(tmp_path / "fit.json")], capture_output=True, text=True)
    assert command.returncode == 0, command.stderr
    expected = json.loads(command.stdout)
    result = lgi.fit(str(tmp_path / "fit.json"))
    assert result["usable"] is True
    for key in ("initial", "problem", "final_cost", "iterations", "residuals", "chi_square"):
        assert result[key] == expected[key], key
    # The covariance's last bits follow the heap addresses of Ceres' dense algebra (Eigen aligns its loops on them).
    for key in ("covariance", "correlation"):
        assert np.allclose(result[key], expected[key], rtol=1e-12, atol=0), key
    for part, values in expected["sigma"].items():
        for name, sigma in values.items():
            assert np.allclose(result["sigma"][part][name], sigma, rtol=1e-12, atol=0), (part, name)
    with open(tmp_path / "fit.json") as f:
        document = json.load(f)
    document["fit"]["unknowns"] = ["nope"]
    cwd = os.getcwd()
    os.chdir(tmp_path)  # a dict's file names (obs.csv) resolve from the current directory
    try:
        with pytest.raises(ValueError, match=r"<dict>: /fit/unknowns/0: unknown unknown \"nope\""):
            lgi.fit(document)
    finally:
        os.chdir(cwd)


def test_a_python_torque_runs_as_the_built_in_one_and_its_errors_stop_the_run():
    def damping(t, R, omega):
        assert R.shape == (3, 3) and omega.shape == (3,)
        return -0.1 * omega
    body = lgi.TorqueBody(inertia=[1, 2, 3], torque=damping)
    built_in = lgi.RigidBody(inertia=[1, 2, 3], torques=[{"type": "damping", "coefficient": 0.1}])
    for method, steps in (("rkmk4", dict(dt=1e-3)), ("rkmk_vern9_cayley", dict(dt=0.01, rtol=1e-10, atol=1e-10))):
        a = lgi.integrate(body, omega0=[1, 0.1, 0], t=2, method=method, **steps)
        b = lgi.integrate(built_in, omega0=[1, 0.1, 0], t=2, method=method, **steps)
        assert np.array_equal(a.R, b.R) and np.array_equal(a.omega, b.omega), method
    assert lgi.integrate(body, omega0=[1, 0.1, 0], t=2, tolerance=1e-8).method == "rkmk_vern9_cayley"
    # The LGVI's forced form: ∂M/∂Ω by forward differences for the Python torque, exact for the built-in term; both
    # Newton iterations stop at the same tolerance, so the runs agree to it, not to the bit.
    a = lgi.integrate(body, omega0=[1, 0.1, 0], t=2, method="lgvi", dt=1e-3)
    b = lgi.integrate(built_in, omega0=[1, 0.1, 0], t=2, method="lgvi", dt=1e-3)
    assert a.steps == b.steps == 2000
    assert np.abs(a.R - b.R).max() < 1e-13 and np.abs(a.omega - b.omega).max() < 1e-13

    def fails(t, R, omega):
        if t > 0.5:
            raise ZeroDivisionError("the model broke")
        return [0.0, 0.0, 0.0]
    with pytest.raises(lgi.RunError, match=r"the torque callable raised at t = 0\.5.*: ZeroDivisionError: the model broke"
                       ) as e:
        lgi.integrate(lgi.TorqueBody(inertia=[1, 2, 3], torque=fails), omega0=[1, 0, 0], t=1, method="rkmk4", dt=0.01)
    assert e.value.result.t[-1] == 0.5 and "\n" not in str(e.value)
    with pytest.raises(lgi.RunError, match=r"returned \[1, 2\] at t = 0, not 3 numbers"):
        lgi.integrate(lgi.TorqueBody(inertia=[1, 2, 3], torque=lambda t, R, w: [1, 2]), omega0=[1, 0, 0], t=1,
                      method="rkmk4", dt=0.01)
    with pytest.raises(lgi.RunError, match="not finite"):
        lgi.integrate(lgi.TorqueBody(inertia=[1, 2, 3], torque=lambda t, R, w: [np.nan, 0, 0]), omega0=[1, 0, 0], t=1,
                      method="rkmk4", dt=0.01)
    with pytest.raises(ValueError, match=r"/integrator/method: .*methods that apply to python_torque: lgvi, rkmk4, "
                                         r"rkmk_vern9_cayley"):
        lgi.integrate(body, omega0=[1, 0, 0], t=1, method="rkmk3", dt=0.01)
    with pytest.raises(TypeError, match="expected a function"):
        lgi.TorqueBody(inertia=[1, 2, 3], torque=3)
