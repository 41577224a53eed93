#!/usr/bin/env python3
"""Writes a glTF scene of many small lamps: a 40 m x 40 m Lambert floor with a few grey blocks
on it, under N small emissive squares (0.1 m to 0.2 m a side, 0.3 m to 3 m up), of powers spread
over two decades (eight emissive strengths 0.2 to 20, KHR_materials_emissive_strength), most facing down,
one in eight facing sideways. A camera looks over the floor at an angle. Deterministic: the same
N and seed give the same file.

    tools/make_many_lights.py OUT.gltf [--lamps N] [--seed S]

It is the generated scene of docs/benchmarks.md's "Many lights" table (tools/many-lights-bench.sh),
where next-event estimation picking by power spends most shadow rays on lamps far from the
shading point.
"""
import argparse, base64, json, math, random, struct

parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
parser.add_argument("out")
parser.add_argument("--lamps", type=int, default=4000)
parser.add_argument("--seed", type=int, default=1)
args = parser.parse_args()
rng = random.Random(args.seed)

LEVELS = 8  # emissive strengths 0.2 .. 20, log-spaced
positions, primitives = [], []  # primitives: (material, first vertex, vertex count)


def quad(corners):
    # Two triangles, non-indexed: (a, b, c), (a, c, d).
    a, b, c, d = corners
    positions.extend([a, b, c, a, c, d])


def add_primitive(material, body):
    first = len(positions)
    body()
    primitives.append((material, first, len(positions) - first))


def floor_and_blocks():
    s = 20.0
    quad([(-s, 0, -s), (-s, 0, s), (s, 0, s), (s, 0, -s)])  # facing +y
    for _ in range(12):
        x, z = rng.uniform(-15, 15), rng.uniform(-15, 15)
        w, h = rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.5)
        x0, x1, z0, z1 = x - w, x + w, z - w, z + w
        quad([(x0, h, z0), (x0, h, z1), (x1, h, z1), (x1, h, z0)])  # top, facing +y
        quad([(x0, 0, z1), (x1, 0, z1), (x1, h, z1), (x0, h, z1)])  # +z
        quad([(x1, 0, z0), (x0, 0, z0), (x0, h, z0), (x1, h, z0)])  # -z
        quad([(x1, 0, z1), (x1, 0, z0), (x1, h, z0), (x1, h, z1)])  # +x
        quad([(x0, 0, z0), (x0, 0, z1), (x0, h, z1), (x0, h, z0)])  # -x


lamps = [[] for _ in range(LEVELS)]
for _ in range(args.lamps):
    x, y, z = rng.uniform(-19, 19), rng.uniform(0.3, 3.0), rng.uniform(-19, 19)
    r = rng.uniform(0.05, 0.1)
    level = rng.randrange(LEVELS)
    if rng.random() < 0.125:  # facing sideways, along +x or -x
        sx = rng.choice([1.0, -1.0])
        corners = [(x, y - r, z - r), (x, y + r, z - r), (x, y + r, z + r), (x, y - r, z + r)]
        if sx < 0:
            corners.reverse()
    else:  # facing down
        corners = [(x - r, y, z - r), (x + r, y, z - r), (x + r, y, z + r), (x - r, y, z + r)]
    lamps[level].append(corners)

add_primitive(0, floor_and_blocks)
for level in range(LEVELS):
    if lamps[level]:
        add_primitive(1 + level, lambda level=level: [quad(c) for c in lamps[level]])

data = b"".join(struct.pack("<3f", *p) for p in positions)
lo = [min(p[k] for p in positions) for k in range(3)]
hi = [max(p[k] for p in positions) for k in range(3)]
materials = [{"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1.0],
                                                        "metallicFactor": 0.0, "roughnessFactor": 1.0}}]
for level in range(LEVELS):
    strength = 0.2 * 100.0 ** (level / (LEVELS - 1))
    materials.append({"name": "lamp %d" % level, "emissiveFactor": [1.0, 0.85, 0.6],
                      "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": strength}},
                      "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0}})
accessors, prims = [], []
for material, first, count in primitives:
    sub = positions[first:first + count]
    accessors.append({"bufferView": 0, "byteOffset": 12 * first, "componentType": 5126, "count": count,
                      "type": "VEC3", "min": [min(p[k] for p in sub) for k in range(3)],
                      "max": [max(p[k] for p in sub) for k in range(3)]})
    prims.append({"attributes": {"POSITION": len(accessors) - 1}, "material": material})
gltf = {
    "asset": {"version": "2.0", "generator": "dacrt tools/make_many_lights.py"},
    "extensionsUsed": ["KHR_materials_emissive_strength"],
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0, "name": "floor and lamps"},
              {"camera": 0, "name": "camera", "translation": [0.0, 9.0, 24.0],
               "rotation": [-math.sin(math.radians(14)), 0.0, 0.0, math.cos(math.radians(14))]}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}],
    "meshes": [{"primitives": prims}],
    "materials": materials,
    "buffers": [{"byteLength": len(data),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    "bufferViews": [{"buffer": 0, "byteLength": len(data)}],
    "accessors": accessors,
}
with open(args.out, "w") as f:
    json.dump(gltf, f)
