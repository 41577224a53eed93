# dacrt.render against the CLI: the same options give the same pixels, bit for bit, image and
# AOVs; errors are the CLI's one-line messages as Python exceptions.
import re
import subprocess

import numpy as np
import pytest

import dacrt
from conftest import CLI, CORNELL

EVERY_AOV = ["albedo", "normal", "depth", "position", "variance", "samples"]
# The CLI's channels of each AOV, in the order the arrays hold them.
CHANNELS = {
    "albedo": ["albedo.R", "albedo.G", "albedo.B"],
    "normal": ["N.X", "N.Y", "N.Z"],
    "depth": ["Z"],
    "position": ["P.X", "P.Y", "P.Z"],
    "variance": ["variance.R", "variance.G", "variance.B"],
    "samples": ["samples.X"],
}


def cli_render(tmp_path, scene, *args):
    out = tmp_path / "cli.exr"
    run = subprocess.run([CLI, "render", scene, "--quiet", "-o", str(out), *args],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return dacrt.read_exr(str(out))


def same_bits(a, b):
    a, b = np.ascontiguousarray(a, np.float32), np.ascontiguousarray(b, np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


def channel_of(exr, names):
    layer = [exr[n] for n in names]
    return layer[0] if len(layer) == 1 else np.stack(layer, axis=-1)


@pytest.mark.parametrize("options,flags", [
    (dict(spp=4, width=40, height=30, seed=7), ["--spp", "4", "--width", "40", "--height", "30",
                                                "--seed", "7"]),
    (dict(spp=8, width=24, height=16, samples=(2, 5), backend="dacrt-naive", max_depth=3),
     ["--spp", "8", "--width", "24", "--height", "16", "--samples", "2:5", "--backend",
      "dacrt-naive", "--max-depth", "3"]),
    (dict(spp=2, width=20, height=20, integrator="direct", look_from=(0.2, 1.0, 3.5), fov=50.5,
          sampler="independent"),
     ["--spp", "2", "--width", "20", "--height", "20", "--integrator", "direct", "--look-from",
      "0.2,1.0,3.5", "--fov", "50.5", "--sampler", "independent"]),
    (dict(spp=4, width=24, height=18, aperture=0.05, focus_on=(0.278, 0.273, 0.3)),
     ["--spp", "4", "--width", "24", "--height", "18", "--aperture", "0.05", "--focus-on",
      "0.278,0.273,0.3"]),
])
def test_render_is_the_cli_render_bit_for_bit(tmp_path, cornell, options, flags):
    exr = cli_render(tmp_path, CORNELL, *flags, "--aov", ",".join(EVERY_AOV))
    for scene in (cornell, CORNELL):  # a loaded scene and a path
        image, aovs = dacrt.render(scene, aovs=EVERY_AOV, **options)
        assert image.dtype == np.float32 and image.shape == (options["height"],
                                                             options["width"], 3)
        assert same_bits(image, channel_of(exr, ["R", "G", "B"]))
        assert sorted(aovs) == sorted(EVERY_AOV)
        for name in EVERY_AOV:
            assert same_bits(aovs[name], channel_of(exr, CHANNELS[name])), name
    # Without aovs= the image alone, the same.
    assert same_bits(dacrt.render(cornell, **options), channel_of(exr, ["R", "G", "B"]))


def test_a_scene_loaded_once_renders_again_the_same(cornell):
    a = dacrt.render(cornell, spp=2, width=16, height=16)
    b = dacrt.render(cornell, spp=2, width=16, height=16, time=0.5)  # posed (no animation here)
    c = dacrt.render(cornell, spp=2, width=16, height=16)
    assert same_bits(a, b) and same_bits(a, c)


def cli_error(*args):
    run = subprocess.run([CLI, "render", *args], capture_output=True, text=True)
    assert run.returncode in (1, 2)
    return run.stderr.splitlines()[0]


def help_options():
    """The options `dacrt render --help` defines: those in the option column of its lines."""
    text = subprocess.run([CLI, "render", "--help"], capture_output=True, text=True,
                          check=True).stdout
    return {flag for line in text.splitlines() if line.startswith("  -")
            for flag in re.findall(r"--[a-z][a-z-]*", line[:29])}


def test_every_render_option_is_a_keyword_or_refused_and_no_other():
    keyword = lambda flag: "aovs" if flag == "--aov" else flag[2:].replace("-", "_")
    taken = set(dacrt._render_keywords()) - {"progress"}
    flags = help_options()
    assert len(flags) > 30
    # What render() leaves to the CLI: files, sequences, the scene index (load()'s), the help;
    # progress= stands for --quiet. A new render option is a keyword unless it is added here.
    refused = {"output", "preview", "view", "exposure", "stats", "report", "frames", "fps",
               "resume", "keep_sums", "checkpoint", "help", "scene", "quiet"}
    assert {keyword(flag) for flag in flags} - taken == refused
    for flag in sorted(flags - {"--scene"}):  # scene= is render()'s first argument
        key = keyword(flag)
        # A keyword taken passes to the checks of the values (width=0 fails there); one refused
        # is a TypeError naming it.
        bad = dict(width=0) if key != "width" else dict(height=0)
        if key in taken:
            with pytest.raises(ValueError, match="width=|height="):
                dacrt.render(CORNELL, **{key: None}, **bad)
        else:
            with pytest.raises(TypeError, match="no %s= here" % key):
                dacrt.render(CORNELL, **{key: "x"})
    assert taken <= {keyword(flag) for flag in flags}


def test_errors_are_the_cli_messages_as_exceptions(tmp_path):
    # The CLI's check of the value, naming the keyword as Python spells it.
    with pytest.raises(ValueError) as bad_spp:
        dacrt.render(CORNELL, spp=0)
    assert str(bad_spp.value).replace("spp=", "--spp") in cli_error(CORNELL, "--spp", "0")
    with pytest.raises(ValueError, match="unknown integrator"):
        dacrt.render(CORNELL, integrator="nope")
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        dacrt.render(CORNELL, colour=3)
    with pytest.raises(TypeError, match=r"'sp' \(did you mean spp=\?\)"):
        dacrt.render(CORNELL, sp=3)
    with pytest.raises(ValueError, match="unknown backend 'embre'"):
        dacrt.render(CORNELL, backend="embre")
    # The CLI's repeated --aov is one list here, aovs=, which also returns them.
    with pytest.raises(TypeError, match="aovs="):
        dacrt.render(CORNELL, aov=["albedo"])
    missing = str(tmp_path / "missing.gltf")
    with pytest.raises(dacrt.Error) as no_file:
        dacrt.load(missing)
    assert str(no_file.value) in cli_error(missing)
    broken = tmp_path / "broken.gltf"
    broken.write_text('{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{}]}]}')
    with pytest.raises(dacrt.Error) as bad_file:
        dacrt.render(str(broken), spp=1, width=8, height=8)
    assert str(bad_file.value) in cli_error(str(broken))
    with pytest.raises(TypeError, match="use the CLI"):
        dacrt.render(CORNELL, output="x.exr")
    with pytest.raises(ValueError, match="one backend"):
        dacrt.render(CORNELL, backend="dacrt,embree")
    # The lens: one aperture, one focus, in front of the camera.
    with pytest.raises(ValueError, match="fstop= and aperture= both give the aperture"):
        dacrt.render(CORNELL, aperture=0.1, fstop=2)
    with pytest.raises(ValueError, match="focus_on= and focus_distance= both give the focus"):
        dacrt.render(CORNELL, focus_distance=1, focus_on=(0, 0, 0))
    with pytest.raises(ValueError, match="not in front of the camera"):
        dacrt.render(CORNELL, spp=1, width=8, height=8, fstop=2, focus_on=(0.278, 0.273, -2))


def test_info_says_what_the_scene_holds(cornell):
    info = cornell.info
    assert info["triangles"] == 32 and info["materials"] >= 1
    assert info["emissive_triangles"] >= 2
    assert info["skipped"]["extensions"] == {}
    lo, hi = info["bounds"]
    assert all(l < h for l, h in zip(lo, hi))


def animated_triangle(tmp_path):
    """A triangle whose node moves from x = 0 to x = 0.5 over one second, seen by a camera."""
    import base64, json, struct
    data = struct.pack("9f", -0.5, -0.5, 0, 0.5, -0.5, 0, 0, 0.5, 0)  # positions
    data += struct.pack("2f", 0.0, 1.0)  # key times
    data += struct.pack("6f", 0, 0, 0, 0.5, 0, 0)  # translations
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 8},
                        {"buffer": 0, "byteOffset": 44, "byteLength": 24}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR",
             "min": [0], "max": [1]},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.01}}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 3]}],
        "animations": [{"samplers": [{"input": 1, "output": 2}],
                        "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}}]}],
        "scenes": [{"nodes": [0, 1]}], "scene": 0,
    }
    path = tmp_path / "moving.gltf"
    path.write_text(json.dumps(gltf))
    return str(path)


def test_time_poses_a_loaded_scene_as_the_cli_loads_it(tmp_path):
    scene_path = animated_triangle(tmp_path)
    scene = dacrt.load(scene_path)  # the rest pose
    assert scene.info["animations"] == 1 and scene.info["animation_end"] == 1.0
    size = dict(spp=2, width=32, height=24)
    rest = dacrt.render(scene, **size)
    for t in (0.5, 1.0, 0.25):
        exr = cli_render(tmp_path, scene_path, "--spp", "2", "--width", "32", "--height", "24",
                         "--time", str(t))
        posed = dacrt.render(scene, time=t, **size)
        assert same_bits(posed, channel_of(exr, ["R", "G", "B"])), t
        assert not same_bits(posed, rest)
    assert same_bits(dacrt.render(scene, **size), rest)  # back to the rest pose
    at_half = dacrt.load(scene_path, time=0.5)
    assert same_bits(dacrt.render(at_half, time=0.5, **size), dacrt.render(scene, time=0.5, **size))


def two_clip_triangle(tmp_path):
    """animated_triangle's file with a second animation, "back", moving the same node to x = -0.5."""
    import json, pathlib
    path = pathlib.Path(animated_triangle(tmp_path))
    gltf = json.loads(path.read_text())
    import base64, struct
    data = base64.b64decode(gltf["buffers"][0]["uri"].split(",")[1])
    data += struct.pack("6f", 0, 0, 0, -0.5, 0, 0)
    gltf["buffers"][0] = {"byteLength": len(data), "uri": "data:application/octet-stream;base64," +
                          base64.b64encode(data).decode()}
    gltf["bufferViews"].append({"buffer": 0, "byteOffset": 68, "byteLength": 24})
    gltf["accessors"].append({"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC3"})
    gltf["animations"][0]["name"] = "there"
    gltf["animations"].append({"name": "back", "samplers": [{"input": 1, "output": 3}],
                               "channels": [{"sampler": 0,
                                             "target": {"node": 0, "path": "translation"}}]})
    path.write_text(json.dumps(gltf))
    return str(path)


def test_animation_chooses_the_clips_as_the_cli_does(tmp_path):
    scene_path = two_clip_triangle(tmp_path)
    size = dict(spp=2, width=32, height=24)
    first = dacrt.load(scene_path)
    clips = first.info["animation_list"]
    assert [(c["name"], c["plays"]) for c in clips] == [("there", True), ("back", False)]
    assert clips[0]["shares_targets_with"] == [1]
    for choice in ("back", 1, "all", "there"):
        scene = dacrt.load(scene_path, animation=choice)
        exr = cli_render(tmp_path, scene_path, "--spp", "2", "--width", "32", "--height", "24",
                         "--time", "1", "--animation", str(choice))
        assert same_bits(dacrt.render(scene, time=1.0, **size), channel_of(exr, ["R", "G", "B"]))
        assert same_bits(dacrt.render(scene_path, time=1.0, animation=choice, **size),
                         channel_of(exr, ["R", "G", "B"]))
    assert not same_bits(dacrt.render(first, time=1.0, **size),
                         dacrt.render(dacrt.load(scene_path, animation="back"), time=1.0, **size))
    with pytest.raises(ValueError, match="animation= is the loaded scene's"):
        dacrt.render(first, time=1.0, animation="back", **size)
    with pytest.raises(ValueError, match='--animation "jog" is not an animation of the file'):
        dacrt.load(scene_path, animation="jog")
    with pytest.raises(ValueError, match="is not an animation index of the file"):
        dacrt.load(scene_path, animation=2)
    with pytest.raises(TypeError, match="animation= wants a name, an index or 'all'"):
        dacrt.load(scene_path, animation=True)
