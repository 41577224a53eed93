#!/usr/bin/env python3
"""Writes scenes/cornell-box.gltf: the Cornell box with its published dimensions; with --lambert,
scenes/cornell-box-lambert.gltf, the same box with every surface purely diffuse
(KHR_materials_specular's specularFactor 0: no Fresnel reflection on top of the base colour).

Geometry and camera follow the Cornell Program of Computer Graphics' measured data (millimetres,
"Cornell Box Data", graphics.cornell.edu): camera at (278, 273, -800) looking +z, 35 mm lens on a
25 mm film. The light is lowered 0.1 mm below the ceiling so the two surfaces do not coincide.
Reflectances and the light's radiance are the usual RGB approximations of the measured spectra.
The geometry sits under a node scaled by 0.001 (glTF is in metres); normals face into the room
and out of the blocks. Run it from the repository root; the output is committed.
"""
import base64, json, math, struct, sys

QUADS = {
    "light": ("light", [(343.0, 548.7, 227.0), (343.0, 548.7, 332.0), (213.0, 548.7, 332.0), (213.0, 548.7, 227.0)]),
    "floor": ("white", [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]),
    "ceiling": ("white", [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]),
    "back wall": ("white", [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]),
    "right wall": ("green", [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]),
    "left wall": ("red", [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]),
}
BLOCKS = {
    "short block": [
        [(130.0, 165.0, 65.0), (82.0, 165.0, 225.0), (240.0, 165.0, 272.0), (290.0, 165.0, 114.0)],
        [(290.0, 0.0, 114.0), (290.0, 165.0, 114.0), (240.0, 165.0, 272.0), (240.0, 0.0, 272.0)],
        [(130.0, 0.0, 65.0), (130.0, 165.0, 65.0), (290.0, 165.0, 114.0), (290.0, 0.0, 114.0)],
        [(82.0, 0.0, 225.0), (82.0, 165.0, 225.0), (130.0, 165.0, 65.0), (130.0, 0.0, 65.0)],
        [(240.0, 0.0, 272.0), (240.0, 165.0, 272.0), (82.0, 165.0, 225.0), (82.0, 0.0, 225.0)],
    ],
    "tall block": [
        [(423.0, 330.0, 247.0), (265.0, 330.0, 296.0), (314.0, 330.0, 456.0), (472.0, 330.0, 406.0)],
        [(423.0, 0.0, 247.0), (423.0, 330.0, 247.0), (472.0, 330.0, 406.0), (472.0, 0.0, 406.0)],
        [(472.0, 0.0, 406.0), (472.0, 330.0, 406.0), (314.0, 330.0, 456.0), (314.0, 0.0, 456.0)],
        [(314.0, 0.0, 456.0), (314.0, 330.0, 456.0), (265.0, 330.0, 296.0), (265.0, 0.0, 296.0)],
        [(265.0, 0.0, 296.0), (265.0, 330.0, 296.0), (423.0, 330.0, 247.0), (423.0, 0.0, 247.0)],
    ],
}
MATERIALS = {
    "white": {"baseColorFactor": [0.725, 0.71, 0.68, 1.0]},
    "red": {"baseColorFactor": [0.63, 0.065, 0.05, 1.0]},
    "green": {"baseColorFactor": [0.14, 0.45, 0.091, 1.0]},
    "light": {"baseColorFactor": [0.78, 0.78, 0.78, 1.0], "emissive": [17.0, 12.0, 4.0]},
}
ROOM_CENTER = (278.0, 274.4, 279.6)


def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def norm(a):
    l = math.sqrt(dot(a, a))
    return tuple(x / l for x in a)


def oriented(quad, toward):
    """The quad's corners, wound so that its normal points toward the point `toward` (or away
    from it when toward is a block's centre, handled by the caller)."""
    n = cross(sub(quad[1], quad[0]), sub(quad[2], quad[0]))
    return quad if dot(n, sub(toward, quad[0])) > 0 else quad[::-1]


def mesh_data(quads):
    positions, normals, indices = [], [], []
    for q in quads:
        n = norm(cross(sub(q[1], q[0]), sub(q[2], q[0])))
        base = len(positions)
        positions += q
        normals += [n] * 4
        indices += [base, base + 1, base + 2, base, base + 2, base + 3]
    return positions, normals, indices


def main():
    lambert = "--lambert" in sys.argv[1:]
    blob = bytearray()
    gltf = {"asset": {"version": "2.0", "generator": "dacrt tools/make_cornell_box.py"},
            "extensionsUsed": ["KHR_materials_emissive_strength"],
            "scene": 0, "scenes": [{"name": "Cornell box", "nodes": [0, 1]}],
            "nodes": [{"name": "cornell-box", "scale": [0.001, 0.001, 0.001], "children": []},
                      {"name": "camera", "camera": 0, "translation": [0.278, 0.273, -0.8],
                       "rotation": [0.0, 1.0, 0.0, 0.0]}],
            "cameras": [{"name": "cornell", "type": "perspective",
                         "perspective": {"yfov": 2.0 * math.atan(12.5 / 35.0), "aspectRatio": 1.0,
                                         "znear": 0.01}}],
            "materials": [], "meshes": [], "accessors": [], "bufferViews": [], "buffers": []}
    material_index = {}
    for name, m in MATERIALS.items():
        mat = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": m["baseColorFactor"],
                                                      "metallicFactor": 0.0, "roughnessFactor": 1.0}}
        if lambert:
            mat.setdefault("extensions", {})["KHR_materials_specular"] = {"specularFactor": 0.0}
        if "emissive" in m:
            strength = max(m["emissive"])
            mat["emissiveFactor"] = [c / strength for c in m["emissive"]]
            mat.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {"emissiveStrength": strength}
        material_index[name] = len(gltf["materials"])
        gltf["materials"].append(mat)

    def add_view(data, target):
        while len(blob) % 4: blob.append(0)
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data), "target": target})
        blob.extend(data)
        return len(gltf["bufferViews"]) - 1

    def add_mesh(name, material, quads):
        positions, normals, indices = mesh_data(quads)
        pv = add_view(b"".join(struct.pack("<3f", *p) for p in positions), 34962)
        nv = add_view(b"".join(struct.pack("<3f", *n) for n in normals), 34962)
        iv = add_view(struct.pack("<%dH" % len(indices), *indices), 34963)
        acc = gltf["accessors"]
        lo = [min(p[k] for p in positions) for k in range(3)]
        hi = [max(p[k] for p in positions) for k in range(3)]
        acc.append({"bufferView": pv, "componentType": 5126, "count": len(positions), "type": "VEC3", "min": lo, "max": hi})
        acc.append({"bufferView": nv, "componentType": 5126, "count": len(normals), "type": "VEC3"})
        acc.append({"bufferView": iv, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
        gltf["meshes"].append({"name": name, "primitives": [{
            "attributes": {"POSITION": len(acc) - 3, "NORMAL": len(acc) - 2}, "indices": len(acc) - 1,
            "material": material_index[material]}]})
        gltf["nodes"].append({"name": name, "mesh": len(gltf["meshes"]) - 1})
        gltf["nodes"][0]["children"].append(len(gltf["nodes"]) - 1)

    for name, (material, quad) in QUADS.items():
        add_mesh(name, material, [oriented(quad, ROOM_CENTER)])
    for name, faces in BLOCKS.items():
        corners = [p for f in faces for p in f]
        center = tuple(sum(p[k] for p in corners) / len(corners) for k in range(3))
        # Block faces point away from the block's centre.
        add_mesh(name, "white", [oriented(f, center)[::-1] for f in faces])

    gltf["buffers"].append({"byteLength": len(blob),
                            "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()})
    if lambert:
        gltf["extensionsUsed"].append("KHR_materials_specular")
    with open("scenes/cornell-box-lambert.gltf" if lambert else "scenes/cornell-box.gltf", "w") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
