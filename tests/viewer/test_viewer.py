"""`lgi view` in a real browser (Debian's headless Chromium, tests/viewer/cdp.py): the page of a run draws its
canvas, plays to t_end, scrubs, and raises no console error, for every example scene; a 10⁶-row run gives a page of
bounded size whose frame rate is measured (written to LGI_VIEWER_REPORT, not asserted: a wall-clock figure)."""

import io
import json
import os
import subprocess
import sys
import time

import pytest

sys.path.insert(0, os.path.dirname(__file__))
import cdp  # noqa: E402

LGI = os.environ["LGI_EXE"]
SOURCE = os.environ["LGI_SOURCE_DIR"]
SCENES = os.path.join(SOURCE, "scenes")

pytestmark = pytest.mark.skipif(cdp.find_chromium() is None, reason="no chromium")


@pytest.fixture(scope="module")
def browser():
    with cdp.Browser(width=1280, height=800) as b:
        yield b


def lgi(*args, check=True):
    r = subprocess.run([LGI, *args], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"lgi {' '.join(args)}: exit {r.returncode}: {r.stderr}")
    return r


def pixels(png, box=None):
    """The distinct colours and the grey-level spread of a screenshot (or of `box` = (left, top, right, bottom))."""
    from PIL import Image, ImageStat
    image = Image.open(io.BytesIO(png)).convert("RGB")
    if box:
        image = image.crop(box)
    return len(set(image.getdata())), ImageStat.Stat(image.convert("L")).stddev[0]


def scene_box(b):
    r = b.evaluate("(() => { const r = document.getElementById('scene').getBoundingClientRect();"
                   " return [r.left, r.top, r.right, r.bottom].map(Math.round); })()")
    return tuple(r)


def dense_scene(tmp_path, t_end=20.0, every=10):
    scene = {
        "problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.6, 0.8],
                    "z0": [0.0, 0.0, 1.0]},
        "initial": {"omega": [0.1, 0.2, 5.0]},
        "integrator": {"method": "lgvi", "dt": 0.001},
        "t_end": t_end,
        "output": {"every": every},
    }
    path = tmp_path / "top.json"
    path.write_text(json.dumps(scene))
    return path


def open_page(b, page):
    b.console_errors.clear()
    b.open(str(page))
    state = b.evaluate("lgiView.state()")
    assert state["webgl"], "the page found no WebGL"
    return state


def test_plays_to_t_end_and_scrubs(browser, tmp_path):
    scene = dense_scene(tmp_path)
    csv, page = tmp_path / "top.csv", tmp_path / "top.html"
    lgi("run", str(scene), "-o", str(csv), "--html", str(page), "-q")
    b = browser
    first = open_page(b, page)
    assert first["frames"] == 2001 and first["t_end"] == 20.0
    # Frames come as fast as the machine draws them (3 fps on a loaded 2-core VM, 40 on an idle one): wait for them,
    # up to a deadline, rather than for a fixed time.
    deadline = time.monotonic() + 20
    while b.evaluate("lgiView.state().rendered") <= first["rendered"] + 5 and time.monotonic() < deadline:
        b.pump(0.2)
    playing = b.evaluate("lgiView.state()")
    assert playing["rendered"] > first["rendered"] + 5, "the frame counter does not advance"
    assert playing["frame"] > first["frame"], "the animation does not move"
    colours, spread = pixels(b.screenshot(), scene_box(b))
    assert colours > 50 and spread > 5, f"the canvas looks blank: {colours} colours, grey spread {spread:.1f}"

    b.evaluate("(() => { const s = document.getElementById('speed'); s.value = '50';"
               " s.dispatchEvent(new Event('change')); })()")
    deadline = time.monotonic() + 20
    while b.evaluate("lgiView.state().playing") and time.monotonic() < deadline:
        b.pump(0.2)
    end = b.evaluate("lgiView.state()")
    assert not end["playing"]
    assert end["frame"] == end["frames"] - 1 and end["time"] == 20.0
    assert end["time_text"] == "t = 20 of 20"
    b.pump(0.3)
    at_end = b.screenshot()

    # Scrub as a user drags the slider: to a third of the run.
    b.evaluate("(() => { const s = document.getElementById('scrub'); s.value = '667';"
               " s.dispatchEvent(new Event('input')); })()")
    b.pump(0.3)
    scrubbed = b.evaluate("lgiView.state()")
    assert scrubbed["frame"] == 667 and abs(scrubbed["time"] - 6.67) < 1e-12
    assert b.screenshot() != at_end, "scrubbing did not change the picture"
    assert b.console_errors == []


def test_every_example_scene(browser, tmp_path):
    """Each example scene's run (its own outputs) gives a page that draws and plays without a console error."""
    b = browser
    scenes = sorted(f for f in os.listdir(SCENES) if f.endswith(".json"))
    assert len(scenes) >= 15
    for name in scenes:
        csv, page = tmp_path / (name + ".csv"), tmp_path / (name + ".html")
        r = lgi("run", os.path.join(SCENES, name), "-o", str(csv), "--html", str(page), "-q", check=False)
        assert r.returncode == 0, f"{name}: {r.stderr}"
        state = open_page(b, page)
        b.pump(0.4)
        later = b.evaluate("lgiView.state()")
        assert later["rendered"] > state["rendered"], name
        assert b.evaluate("lgiView.meta.body.known") is True, name
        assert b.console_errors == [], f"{name}: {b.console_errors}"


def test_million_rows(browser, tmp_path):
    """10⁶ + 1 rows: the page is decimated to 20,000 frames and stays under 3 MB; its frame rate is reported."""
    scene = dense_scene(tmp_path, t_end=1000.0, every=1)
    data = json.loads(scene.read_text())
    data["output"]["columns"] = ["t", "quaternion", "omega", "energy", "invariants"]
    scene.write_text(json.dumps(data))
    csv, page = tmp_path / "million.csv", tmp_path / "million.html"
    lgi("run", str(scene), "-o", str(csv), "-q")
    started = time.monotonic()
    r = lgi("view", str(csv), "--scene", str(scene), "-o", str(page))
    view_seconds = time.monotonic() - started
    csv_bytes = csv.stat().st_size
    csv.unlink()
    assert "1000001 rows shown as 20000 frames" in r.stderr
    size = page.stat().st_size
    assert size < 3_000_000, f"{size} bytes"
    b = browser
    started = time.monotonic()
    state = open_page(b, page)
    load_seconds = time.monotonic() - started
    assert state["frames"] == 20000 and state["t_end"] == 1000.0
    assert "one row in 50" in b.evaluate("document.getElementById('info').textContent")
    b.pump(2.0)  # past the first frames (shader compilation)
    before, t0 = b.evaluate("lgiView.state()"), time.monotonic()
    b.pump(5.0)
    after, t1 = b.evaluate("lgiView.state()"), time.monotonic()
    fps = (after["rendered"] - before["rendered"]) / (t1 - t0)
    assert after["frame"] > before["frame"]
    assert b.console_errors == []
    report = {"rows": 1000001, "csv_bytes": csv_bytes, "page_bytes": size, "view_seconds": round(view_seconds, 2),
              "load_seconds": round(load_seconds, 2), "fps": round(fps, 1), "antialias": after["antialias"],
              "viewport": [1280, 800], "chromium": subprocess.run([cdp.find_chromium(), "--version"],
                                                                  capture_output=True, text=True).stdout.strip()}
    print("viewer 10^6 rows:", json.dumps(report))
    out = os.environ.get("LGI_VIEWER_REPORT")
    if out:
        with open(out, "w") as f:
            json.dump(report, f, indent=1)
