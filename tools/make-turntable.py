#!/usr/bin/env python3
"""Adds a turntable animation to a binary glTF (.glb): the default scene's root nodes turn about
the vertical (Y) axis through the centre of the POSITION accessors' bounds, at TURNS turns per
second for SECONDS seconds (LINEAR rotation keyframes every 1/8 turn). The benchmark's rotating
dragon (docs/benchmarks.md, tools/sequence-bench.sh):

    tools/make-turntable.py ../shared/scenes/stanford/dragon/dragon.glb dragon-turntable.glb

Usage: make-turntable.py IN.glb OUT.glb [--turns T (0.5)] [--seconds S (2)]
"""
import argparse
import json
import math
import struct
import sys


def main():
    ap = argparse.ArgumentParser(description="add a turntable animation to a .glb")
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--turns", type=float, default=0.5, help="turns per second (default 0.5)")
    ap.add_argument("--seconds", type=float, default=2.0, help="length in seconds (default 2)")
    a = ap.parse_args()
    data = open(a.input, "rb").read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2:
        sys.exit(f"{a.input}: not a binary glTF 2.0 file")
    jlen, jtype = struct.unpack_from("<I4s", data, 12)
    if jtype != b"JSON":
        sys.exit(f"{a.input}: the first chunk is not JSON")
    doc = json.loads(data[20:20 + jlen])
    pos = 20 + jlen
    binary = b""
    if pos < length:
        blen, btype = struct.unpack_from("<I4s", data, pos)
        if btype != b"BIN\x00":
            sys.exit(f"{a.input}: the second chunk is not BIN")
        binary = data[pos + 8:pos + 8 + blen]
    if "buffers" not in doc or not doc["buffers"] or "uri" in doc["buffers"][0]:
        sys.exit(f"{a.input}: buffer 0 must be the GLB's binary chunk")

    # The centre of the POSITION bounds (accessor min and max, which glTF requires).
    lo, hi = [math.inf] * 3, [-math.inf] * 3
    for mesh in doc.get("meshes", []):
        for prim in mesh["primitives"]:
            acc = doc["accessors"][prim["attributes"]["POSITION"]]
            lo = [min(x, y) for x, y in zip(lo, acc["min"])]
            hi = [max(x, y) for x, y in zip(hi, acc["max"])]
    centre = [0.5 * (x + y) for x, y in zip(lo, hi)]

    # Keyframes every 1/8 turn.
    steps = max(1, math.ceil(8 * a.turns * a.seconds))
    times, quats = [], []
    for k in range(steps + 1):
        t = a.seconds * k / steps
        angle = 2 * math.pi * a.turns * t
        times.append(t)
        quats += [0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2)]
    binary += b"\0" * (-len(binary) % 4)
    t_off = len(binary)
    binary += struct.pack(f"<{len(times)}f", *times)
    q_off = len(binary)
    binary += struct.pack(f"<{len(quats)}f", *quats)
    doc["buffers"][0]["byteLength"] = len(binary)
    views = doc.setdefault("bufferViews", [])
    accessors = doc.setdefault("accessors", [])
    views += [{"buffer": 0, "byteOffset": t_off, "byteLength": 4 * len(times)},
              {"buffer": 0, "byteOffset": q_off, "byteLength": 4 * len(quats)}]
    accessors += [{"bufferView": len(views) - 2, "componentType": 5126, "count": len(times),
                   "type": "SCALAR", "min": [times[0]], "max": [times[-1]]},
                  {"bufferView": len(views) - 1, "componentType": 5126, "count": len(times),
                   "type": "VEC4"}]
    scene = doc["scenes"][doc.get("scene", 0)]
    nodes = doc["nodes"]
    inner = len(nodes)
    nodes.append({"name": "turntable-offset", "translation": [-c for c in centre],
                  "children": scene["nodes"]})
    turn = len(nodes)
    nodes.append({"name": "turntable", "translation": centre, "children": [inner]})
    scene["nodes"] = [turn]
    doc.setdefault("animations", []).append({
        "name": "turntable",
        "samplers": [{"input": len(accessors) - 2, "output": len(accessors) - 1,
                      "interpolation": "LINEAR"}],
        "channels": [{"sampler": 0, "target": {"node": turn, "path": "rotation"}}]})

    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    out = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + 8 + len(binary))
    out += struct.pack("<I4s", len(text), b"JSON") + text
    out += struct.pack("<I4s", len(binary), b"BIN\x00") + binary
    with open(a.output, "wb") as f:
        f.write(out)


if __name__ == "__main__":
    main()
