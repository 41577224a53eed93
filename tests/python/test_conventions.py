# The module as Python users expect it: paths as pathlib.Path, converge() rows typed, nothing on
# stdout (results returned, notes as warnings), progress where it is seen, the cameras in
# Scene.info.
import dataclasses
import json
import pathlib
import re
import subprocess
import sys
import types

import pytest

import dacrt
from conftest import CLI, CORNELL

SMALL = dict(spp=1, width=8, height=8)


def test_every_path_may_be_a_pathlib_path(tmp_path):
    scene = pathlib.Path(CORNELL)
    out = tmp_path / "cli.exr"
    subprocess.run([CLI, "render", CORNELL, "--quiet", "-o", str(out), "--width", "8",
                    "--height", "8", "--spp", "1"], check=True)
    assert dacrt.load(scene).info["triangles"] == 32
    assert dacrt.render(scene, **SMALL).shape == (8, 8, 3)
    assert set(dacrt.read_exr(out)) >= {"R", "G", "B"}
    lit = dacrt.render(scene, environment=out, **SMALL)  # an environment map
    assert lit.shape == (8, 8, 3)
    assert dacrt.bench(scene, rays="primary", backends="brute", count=64, repeat=1)["results"]
    rows = dacrt.converge(scene, reference=out, config=[""], width=8, height=8, max_spp=2,
                          time_budget=1)
    assert rows and rows[0].rmse is not None


def test_converge_rows_are_typed_and_nothing_goes_to_stdout(capfd):
    with pytest.warns(dacrt.DacrtWarning, match="times under 0.1 s are noisy"):
        rows = dacrt.converge(CORNELL, config=["", "sampler=independent"], width=8, height=8,
                              no_reference=True, max_spp=2, time_budget=1, progress=False)
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    assert [(r.config, r.spp) for r in rows] == [
        (c, s) for c in ("default", "sampler=independent") for s in (1, 2)]
    for r in rows:
        assert isinstance(r, dacrt.ConvergeRow)
        assert type(r.spp) is int and type(r.repeats) is int and r.repeats == 1
        assert type(r.seconds) is float and type(r.noise) is float and r.noise > 0
        assert r.rmse is None and r.reference_mse is None  # no reference: not measured
        assert r.seconds_low is None  # one repeat: no interval


def test_the_csv_columns_are_the_row_fields(tmp_path):
    # The CLI's own CSV: its columns are ConvergeRow's fields, in order.
    subprocess.run([CLI, "converge", CORNELL, "-o", str(tmp_path), "--no-plot", "--quiet",
                    "--no-reference", "--width", "8", "--height", "8", "--max-spp", "1",
                    "--config", ""], check=True, capture_output=True)
    header = (tmp_path / "convergence.csv").read_text().splitlines()[0].split(",")
    assert header == [f.name for f in dataclasses.fields(dacrt.ConvergeRow)]


def test_a_render_says_its_notes_as_warnings_and_prints_nothing(tmp_path, capfd):
    # A triangle without emitters or camera: lit by the environment, framed: both said.
    scene = tmp_path / "bare.gltf"
    import base64, struct
    positions = struct.pack("9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    scene.write_text(json.dumps({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(positions).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}))
    with pytest.warns(dacrt.DacrtWarning) as said:
        dacrt.render(scene, progress=False, **SMALL)
    messages = [str(w.message) for w in said]
    assert any("no emitters and no lights" in m for m in messages), messages
    assert any("no camera in the file" in m for m in messages), messages
    assert said[0].filename == __file__  # the warning points at the caller's line
    out, err = capfd.readouterr()
    assert out == "" and err == ""
    # Without the sky nothing lights it: a warning says the image is black, and what lights it.
    with pytest.warns(dacrt.DacrtWarning) as said:
        dacrt.render(scene, progress=False, environment="0,0,0", **SMALL)
    dark = [str(w.message) for w in said if "nearly black" in str(w.message)]
    assert len(dark) == 1 and "no sky lights it; --environment 1,1,1 adds one" in dark[0], dark
    # A time limit that ends the render early says how far it got.
    with pytest.warns(dacrt.DacrtWarning) as said:
        dacrt.render(CORNELL, progress=False, spp=100000, width=8, height=8, time_limit=0.01)
    stopped = [str(w.message) for w in said if "time limit" in str(w.message)]
    assert len(stopped) == 1 and " of 100000 samples per pixel" in stopped[0], stopped


class Stream:
    def __init__(self, tty):
        self.tty = tty

    def isatty(self):
        return self.tty

    def write(self, text):
        return len(text)

    def flush(self):
        pass


def test_progress_is_on_where_it_is_seen(monkeypatch):
    monkeypatch.delitem(sys.modules, "IPython", raising=False)
    monkeypatch.setattr(sys, "stderr", Stream(False))
    assert dacrt._show_progress(None) is False  # a pipe, a file: off
    monkeypatch.setattr(sys, "stderr", Stream(True))
    assert dacrt._show_progress(None) is True  # a terminal: on
    monkeypatch.setattr(sys, "stderr", Stream(False))
    ipython = types.ModuleType("IPython")
    ipython.get_ipython = lambda: None  # imported, not running: off
    monkeypatch.setitem(sys.modules, "IPython", ipython)
    assert dacrt._show_progress(None) is False
    ipython.get_ipython = lambda: object()  # IPython or a Jupyter kernel running this: on
    assert dacrt._show_progress(None) is True
    assert dacrt._show_progress(False) is False
    monkeypatch.setitem(sys.modules, "IPython", None)  # a blocked import
    assert dacrt._show_progress(None) is False
    assert dacrt._show_progress(True) is True
    with pytest.raises(TypeError, match="progress= wants True, False or None, not int"):
        dacrt._show_progress(1)


def test_progress_none_shows_it_in_a_notebook(monkeypatch, capfd):
    # The rule above in a render: with a running IPython, progress=None is the progress on stderr.
    ipython = types.ModuleType("IPython")
    ipython.get_ipython = lambda: object()
    monkeypatch.setitem(sys.modules, "IPython", ipython)
    dacrt.render(CORNELL, spp=8, width=32, height=32)
    assert "render" in capfd.readouterr().err
    ipython.get_ipython = lambda: None
    dacrt.render(CORNELL, spp=8, width=32, height=32)
    assert capfd.readouterr().err == ""


def cli_cameras(path):
    """`dacrt info`'s camera lines: (name, position, yfov or None, ortho height or None, aspect)."""
    text = subprocess.run([CLI, "info", str(path)], capture_output=True, text=True,
                          check=True).stdout
    found = []
    pattern = (r"  camera (\d+) (.*): position \(([^)]*)\), (?:yfov ([0-9.]+)°|orthographic, "
               r"height ([0-9.]+)), aspect (\S+)")
    for m in re.finditer(pattern, text):
        found.append((None if m[2] == "(unnamed)" else m[2],
                      tuple(float(v) for v in m[3].split(",")),
                      m[4] and float(m[4]), m[5] and float(m[5]),
                      None if m[6] == "from" else float(m[6])))
    return found


def test_info_lists_the_cameras_as_dacrt_info_does(tmp_path):
    # A file with a perspective and an orthographic camera, and one without any.
    import base64, struct
    positions = struct.pack("9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(positions).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "cameras": [{"name": "wide", "type": "perspective",
                     "perspective": {"yfov": 0.9, "aspectRatio": 1.5, "znear": 0.01}},
                    {"type": "orthographic",
                     "orthographic": {"xmag": 2, "ymag": 1.25, "znear": 0.01, "zfar": 100}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.5, 0.25, 3]},
                  {"camera": 1, "translation": [0, 0, 5]}],
        "scenes": [{"nodes": [0, 1, 2]}], "scene": 0}
    two = tmp_path / "two.gltf"
    two.write_text(json.dumps(gltf))
    info = dacrt.load(two).info
    assert info["cameras_from_file"] == 2 and len(info["cameras"]) == 2
    wide, ortho = info["cameras"]
    assert wide["name"] == "wide" and wide["position"] == pytest.approx((0.5, 0.25, 3))
    assert wide["fov"] == pytest.approx(0.9 * 180 / 3.141592653589793, rel=1e-6)
    assert wide["aspect"] == pytest.approx(1.5) and not wide["orthographic"]
    assert wide["ortho_height"] is None and wide["from_file"]
    assert ortho["name"] is None and ortho["orthographic"] and ortho["fov"] is None
    assert ortho["ortho_height"] == pytest.approx(2.5) and ortho["aspect"] == pytest.approx(1.6)
    for scene in (two, CORNELL):  # as `dacrt info` prints them
        mine = [(c["name"], c["position"], c["fov"], c["ortho_height"], c["aspect"])
                for c in dacrt.load(scene).info["cameras"]]
        theirs = cli_cameras(scene)
        assert len(mine) == len(theirs) >= 1
        for a, b in zip(mine, theirs):
            assert a[0] == b[0] and a[1] == pytest.approx(b[1], rel=1e-5, abs=1e-5)
            for x, y in zip(a[2:], b[2:]):
                assert (x is None) == (y is None) and (x is None or x == pytest.approx(y, 1e-5))
    del gltf["cameras"], gltf["nodes"][1:]
    gltf["scenes"][0]["nodes"] = [0]
    two.write_text(json.dumps(gltf))
    framed = dacrt.load(two).info
    assert framed["cameras_from_file"] == 0 and len(framed["cameras"]) == 1
    assert not framed["cameras"][0]["from_file"]


def test_bench_says_its_warnings_as_warnings(tmp_path, capfd):
    # A camera looking away from the only triangle: no primary ray hits, so no shadow rays.
    import base64, struct
    positions = struct.pack("9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    scene = tmp_path / "away.gltf"
    scene.write_text(json.dumps({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(positions).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3], "rotation": [0, 1, 0, 0]}],
        "scenes": [{"nodes": [0, 1]}], "scene": 0}))
    with pytest.warns(dacrt.DacrtWarning, match="shadow: no rays"):
        report = dacrt.bench(scene, rays="primary,shadow", backends="brute", width=8, height=8,
                             repeat=1, progress=False)
    assert {r["rays"] for r in report["results"]} == {"primary"}
    out, err = capfd.readouterr()
    assert out == "" and err == ""
