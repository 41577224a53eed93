# dacrt.trace: any backend on rays a user makes, numpy in and out. The watertight backends give
# the same hits bit for bit; a hit lies on its triangle.
import math

import numpy as np
import pytest

import dacrt

WATERTIGHT = ["dacrt", "dacrt-naive", "brute"]


def rays_inside(scene, n, seed=1):
    rng = np.random.default_rng(seed)
    lo, hi = (np.array(b, np.float32) for b in scene.info["bounds"])
    origins = (lo + (hi - lo) * rng.uniform(0.05, 0.95, (n, 3))).astype(np.float32)
    directions = rng.normal(size=(n, 3)).astype(np.float32)
    return origins, directions


def test_watertight_backends_give_the_same_hits(cornell):
    origins, directions = rays_inside(cornell, 20000)
    hits = {b: dacrt.trace(cornell, origins, directions, backend=b) for b in WATERTIGHT}
    for b in WATERTIGHT[1:]:
        for key in ("t", "prim", "u", "v"):
            assert np.array_equal(hits[b][key], hits["brute"][key]), (b, key)
    h = hits["dacrt"]
    assert h["t"].dtype == np.float32 and h["prim"].dtype == np.uint32
    missed = h["prim"] == 0xFFFFFFFF
    assert 0 < missed.mean() < 0.3  # the box is open on the camera's side only
    assert np.all(np.isfinite(h["t"][~missed])) and np.all(h["t"][~missed] > 0)


def test_occluded_agrees_with_the_closest_hit(cornell):
    origins, directions = rays_inside(cornell, 5000, seed=2)
    for tmax in (0.05, 0.5, math.inf):
        hit = dacrt.trace(cornell, origins, directions, tmax=tmax)
        blocked = dacrt.trace(cornell, origins, directions, tmax=tmax, occluded=True)
        assert blocked.dtype == np.bool_
        assert np.array_equal(blocked, hit["prim"] != 0xFFFFFFFF)


def test_a_ray_at_a_triangle_hits_it(tmp_path):
    # One triangle in the z = 0 plane; rays from z = 2 straight down at points inside it.
    import json, base64, struct
    positions = struct.pack("9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64," +
                     base64.b64encode(positions).decode()}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0,
    }
    path = tmp_path / "triangle.gltf"
    path.write_text(json.dumps(gltf))
    scene = dacrt.load(str(path))
    origins = np.array([[0.25, 0.25, 2.0], [0.1, 0.6, 2.0], [0.9, 0.9, 2.0]], np.float32)
    down = np.tile(np.array([0, 0, -2.0], np.float32), (3, 1))  # t in units of |d| = 2
    for backend in WATERTIGHT:
        h = dacrt.trace(scene, origins, down, backend=backend)
        assert list(h["prim"]) == [0, 0, 0xFFFFFFFF]  # the third is outside (x + y > 1)
        assert np.allclose(h["t"][:2], 1.0)
        assert np.allclose(h["u"][:2], origins[:2, 0]) and np.allclose(h["v"][:2], origins[:2, 1])
        assert h["t"][2] == np.inf


def test_bad_rays_are_refused(cornell):
    with pytest.raises(ValueError, match="N×3"):
        dacrt.trace(cornell, np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(ValueError, match="N×3"):
        dacrt.trace(cornell, np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(ValueError, match="tmin"):
        dacrt.trace(cornell, np.zeros((1, 3)), np.ones((1, 3)), tmin=2.0, tmax=1.0)
    with pytest.raises(ValueError, match="unknown backend|known"):
        dacrt.trace(cornell, np.zeros((1, 3)), np.ones((1, 3)), backend="nope")
