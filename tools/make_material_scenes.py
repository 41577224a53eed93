#!/usr/bin/env python3
# Writes one small glTF scene per material extension into DIR, for cross-checks of dacrt's
# material lobes against another renderer (tools/material-crosscheck.sh runs dacrt and Cycles on
# them): a smooth sphere of radius 1 on a grey Lambert floor, seen by a perspective camera, lit by
# the renderer's uniform sky (no lights in the file). The sphere's material is the only change:
#   base        glTF's default BRDF: a rough red dielectric (the reference for model differences)
#   clearcoat   the same under a smooth clear coat (KHR_materials_clearcoat)
#   sheen       a dark base with white sheen (KHR_materials_sheen)
#   specular    a dimmer, tinted dielectric specular (KHR_materials_specular factors)
#   volume      a refractive glass of absorbing interior (KHR_materials_transmission + _volume)
#   unlit       KHR_materials_unlit
#   anisotropy  brushed metal (KHR_materials_anisotropy)
#   iridescence a thin film on a dark dielectric (KHR_materials_iridescence)
#
#   python3 tools/make_material_scenes.py DIR
import base64
import json
import math
import os
import struct
import sys

MATERIALS = {
    "base": {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1], "metallicFactor": 0,
                                      "roughnessFactor": 0.7}},
    "clearcoat": {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1],
                                           "metallicFactor": 0, "roughnessFactor": 0.7},
                  "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 1,
                                                             "clearcoatRoughnessFactor": 0.1}}},
    "sheen": {"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.3, 1], "metallicFactor": 0,
                                       "roughnessFactor": 0.8},
              "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [1, 1, 1],
                                                     "sheenRoughnessFactor": 0.5}}},
    "specular": {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.5, 0.2, 1],
                                          "metallicFactor": 0, "roughnessFactor": 0.3},
                 "extensions": {"KHR_materials_specular": {"specularFactor": 0.5,
                                                           "specularColorFactor": [1, 0.5, 0.5]}}},
    "volume": {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0,
                                        "roughnessFactor": 0},
               "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                              "KHR_materials_volume": {"thicknessFactor": 2,
                                                       "attenuationDistance": 1,
                                                       "attenuationColor": [0.9, 0.5, 0.2]}}},
    "unlit": {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.6, 0.9, 1]},
              "extensions": {"KHR_materials_unlit": {}}},
    "anisotropy": {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                                            "metallicFactor": 1, "roughnessFactor": 0.4},
                   "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.8}}},
    "iridescence": {"pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.05, 0.05, 1],
                                             "metallicFactor": 0, "roughnessFactor": 0.2},
                    "extensions": {"KHR_materials_iridescence": {
                        "iridescenceFactor": 1, "iridescenceIor": 1.3,
                        "iridescenceThicknessMaximum": 400}}},
}


def sphere(rings=48, segments=96):
    """Positions, normals, tangents and triangle indices of a unit UV sphere centred at (0, 1, 0)."""
    pos, nrm, tan, idx = [], [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            pos.append((n[0], n[1] + 1.0, n[2]))
            nrm.append(n)
            tan.append((-math.sin(phi), 0.0, math.cos(phi), 1.0))
    for r in range(rings):
        for s in range(segments):
            a = r * (segments + 1) + s
            b = a + segments + 1
            idx += [a, a + 1, b, a + 1, b + 1, b]
    return pos, nrm, tan, idx


def floor(size=6.0):
    pos = [(-size, 0, -size), (size, 0, -size), (size, 0, size), (-size, 0, size)]
    return pos, [(0, 1, 0)] * 4, [(1, 0, 0, 1)] * 4, [0, 2, 1, 0, 3, 2]


def scene(material):
    data = bytearray()
    views, accessors = [], []

    def add(values, fmt, kind, component, target, minmax=False):
        while len(data) % 4:
            data.append(0)
        start = len(data)
        for v in values:
            data.extend(struct.pack(fmt, *(v if isinstance(v, tuple) else (v,))))
        views.append({"buffer": 0, "byteOffset": start, "byteLength": len(data) - start,
                      "target": target})
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": len(values),
                    "type": kind}
        if minmax:
            accessor["min"] = [min(v[i] for v in values) for i in range(3)]
            accessor["max"] = [max(v[i] for v in values) for i in range(3)]
        accessors.append(accessor)
        return len(accessors) - 1

    meshes = []
    for (pos, nrm, tan, idx), mat in ((sphere(), 0), (floor(), 1)):
        attributes = {"POSITION": add(pos, "<3f", "VEC3", 5126, 34962, True),
                      "NORMAL": add(nrm, "<3f", "VEC3", 5126, 34962),
                      "TANGENT": add(tan, "<4f", "VEC4", 5126, 34962)}
        indices = add(idx, "<I", "SCALAR", 5125, 34963)
        meshes.append({"primitives": [{"attributes": attributes, "indices": indices,
                                       "material": mat}]})
    used = sorted(material.get("extensions", {}).keys())
    # The camera 5 units away, 1 up, looking at the sphere's centre slightly from above.
    pitch = math.atan2(0.8, 5.0)
    rotation = [-math.sin(pitch / 2), 0, 0, math.cos(pitch / 2)]
    return {
        "asset": {"version": "2.0", "generator": "dacrt tools/make_material_scenes.py"},
        "extensionsUsed": used,
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0}, {"mesh": 1},
                  {"camera": 0, "translation": [0, 1.8, 5], "rotation": rotation}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.6, "znear": 0.05, "aspectRatio": 1.0}}],
        "meshes": meshes,
        "materials": [material, {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                          "metallicFactor": 0},
                                 "extensions": {"KHR_materials_specular": {"specularFactor": 0}}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(bytes(data)).decode()}],
    }


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: make_material_scenes.py DIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, material in MATERIALS.items():
        doc = scene(material)
        if "KHR_materials_specular" not in doc["extensionsUsed"]:
            doc["extensionsUsed"] = sorted(doc["extensionsUsed"] + ["KHR_materials_specular"])
        with open(os.path.join(out, name + ".gltf"), "w") as f:
            json.dump(doc, f)
        print(os.path.join(out, name + ".gltf"))


if __name__ == "__main__":
    main()
