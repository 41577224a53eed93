"""Blender's lights as dacrt renders them: area lights become emissive meshes, and what the other
lights lose on the way through glTF becomes a warning.

Area lights (which glTF cannot carry) are added to the exported .glb as one-sided emissive
meshes of the light's shape and world transform: square, rectangle (two triangles), disk and
ellipse (a 64-sided polygon). Cycles gives an area light of power P watts, colour c and area A
the radiance c × P / (4 A) on its front side (its -Z), measured here: an area light and a mesh
emitter of that radiance light a floor alike to 1e-6 (intern/cycles/kernel/light: eval_fac =
¼ × 1/area). The mesh's radiance is emissiveFactor × KHR_materials_emissive_strength, as dacrt
reads it; its area is the polygon's, so the power is the light's. Its material is black (it
absorbs what hits it: Cycles' lights are not geometry) and single-sided (dacrt emits from the
front only, as Cycles' area lights). Cycles does not show area lights to camera rays; dacrt's
emitters are seen: a warning says so when the light is in the camera's view.

Point, spot and sun lights go through the exporter (KHR_lights_punctual); with the Blender
(W/4π) units a point or spot light of P watts has intensity P / 4π, the radiant intensity Cycles
gives it, and a sun its strength in W/m². What they lose (a point's radius, a sun's angle,
the spot's blend curve, node-made strengths) is warned about.
"""

import json
import math
import struct

import numpy as np

DISK_SIDES = 64
_JSON, _BIN = 0x4E4F534A, 0x004E4942


def light_warnings(name, light, in_view):
    """The warnings for one light of the evaluated scene: what dacrt will not render of it."""
    warnings = []
    kind = light.type
    if light.use_nodes and light.node_tree and any(
            node.type not in ('EMISSION', 'OUTPUT_LIGHT') for node in light.node_tree.nodes):
        warnings.append(f"light {name}: its shader nodes are ignored (power × colour is used)")
    if kind in ('POINT', 'SPOT') and light.shadow_soft_size > 0:
        warnings.append(f"light {name}: radius {light.shadow_soft_size:g} is lost "
                        "(dacrt's point and spot lights are points: hard shadows)")
    if kind == 'SPOT' and light.spot_blend > 0:
        warnings.append(f"light {name}: the spot blend {light.spot_blend:g} becomes glTF's "
                        "cone falloff (a different curve)")
    if kind == 'SUN' and light.angle > 0:
        warnings.append(f"light {name}: the sun's angle {math.degrees(light.angle):g}° is lost "
                        "(dacrt's sun is parallel rays: hard shadows)")
    if kind == 'AREA':
        if getattr(light, "spread", math.pi) < math.pi - 1e-4:
            warnings.append(f"light {name}: spread {math.degrees(light.spread):g}° is ignored "
                            "(dacrt's emitter spreads over 180°)")
        if getattr(getattr(light, "cycles", None), "is_portal", False):
            warnings.append(f"light {name}: a portal, which dacrt does not have: left out")
        elif in_view:
            warnings.append(f"light {name}: an area light in the camera's view is seen by dacrt "
                            "(Cycles does not show area lights to the camera)")
    return warnings


def area_polygon(light):
    """The light's outline in its own frame (z = 0), counter-clockwise seen from -Z (its front,
    where it emits): a list of (x, y)."""
    size_x = light.size
    size_y = light.size if light.shape in ('SQUARE', 'DISK') else light.size_y
    if light.shape in ('DISK', 'ELLIPSE'):
        angles = [-2 * math.pi * k / DISK_SIDES for k in range(DISK_SIDES)]
        return [(0.5 * size_x * math.cos(a), 0.5 * size_y * math.sin(a)) for a in angles]
    hx, hy = 0.5 * size_x, 0.5 * size_y
    return [(-hx, -hy), (-hx, hy), (hx, hy), (hx, -hy)]


def area_emitter(light, matrix):
    """The emitter of an area light with world matrix `matrix` (4×4, Blender's Z-up): positions
    (N×3, glTF's Y-up world), triangles (a fan), the normal, and the radiance (R, G, B)."""
    outline = area_polygon(light)
    local = np.array([[x, y, 0.0, 1.0] for x, y in outline])
    world = (np.array(matrix) @ local.T).T[:, :3]
    triangles = [(0, k, k + 1) for k in range(1, len(outline) - 1)]
    area = 0.0
    for a, b, c in triangles:
        area += 0.5 * np.linalg.norm(np.cross(world[b] - world[a], world[c] - world[a]))
    normal = np.cross(world[1] - world[0], world[2] - world[0])
    normal /= np.linalg.norm(normal)
    radiance = [c * light.energy / (4.0 * area) if area > 0 else 0.0 for c in light.color]
    to_y_up = lambda v: np.stack([v[..., 0], v[..., 2], -v[..., 1]], axis=-1)  # noqa: E731
    return to_y_up(world), triangles, to_y_up(normal), radiance


def _read_glb(path):
    with open(path, "rb") as file:
        data = file.read()
    magic, _, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF":
        raise ValueError(f"{path}: not a binary glTF file")
    chunks, at = {}, 12
    while at < length:
        size, kind = struct.unpack_from("<II", data, at)
        chunks[kind] = data[at + 8:at + 8 + size]
        at += 8 + size
    return json.loads(chunks[_JSON]), bytearray(chunks.get(_BIN, b""))


def _write_glb(path, gltf, binary):
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary = bytes(binary) + b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(text), _JSON) + text
    if binary:
        chunks += struct.pack("<II", len(binary), _BIN) + binary
    with open(path, "wb") as file:
        file.write(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)


def _sharpen_spots(gltf):
    """A spot of blend 0 is exported with innerConeAngle = outerConeAngle, which glTF (and
    dacrt) refuse: the inner angle a hair below the outer one is the same hard edge. True when
    a spot was changed."""
    changed = False
    for light in gltf.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights", []):
        spot = light.get("spot")
        if spot is None:
            continue
        outer = spot.get("outerConeAngle", math.pi / 4)
        if spot.get("innerConeAngle", 0.0) >= outer:
            spot["innerConeAngle"] = outer * (1 - 1e-6)
            changed = True
    return changed


def add_area_lights(glb_path, emitters):
    """Adds each (name, light, matrix) of `emitters` to the .glb at glb_path as an emissive mesh
    on a node of its own at the default scene's root (and makes its spot lights valid glTF)."""
    gltf, binary = _read_glb(glb_path)
    if not _sharpen_spots(gltf) and not emitters:
        return
    if not emitters:
        _write_glb(glb_path, gltf, binary)
        return
    if not gltf.get("buffers"):
        gltf["buffers"] = [{"byteLength": 0}]
    for key in ("bufferViews", "accessors", "meshes", "materials", "nodes"):
        gltf.setdefault(key, [])
    scenes = gltf.setdefault("scenes", [{"nodes": []}])
    roots = scenes[gltf.get("scene", 0)].setdefault("nodes", [])
    used = gltf.setdefault("extensionsUsed", [])
    if "KHR_materials_emissive_strength" not in used:
        used.append("KHR_materials_emissive_strength")

    def add_view(payload, target):
        binary.extend(b"\0" * (-len(binary) % 4))
        gltf["bufferViews"].append({"buffer": 0, "byteOffset": len(binary),
                                    "byteLength": len(payload), "target": target})
        binary.extend(payload)
        return len(gltf["bufferViews"]) - 1

    for name, light, matrix in emitters:
        positions, triangles, normal, radiance = area_emitter(light, matrix)
        positions = positions.astype("<f4")
        normals = np.tile(normal, (len(positions), 1)).astype("<f4")
        indices = np.array(triangles, dtype="<u4").reshape(-1)
        accessors = gltf["accessors"]
        accessors.append({"bufferView": add_view(positions.tobytes(), 34962), "componentType":
                          5126, "count": len(positions), "type": "VEC3",
                          "min": positions.min(axis=0).tolist(),
                          "max": positions.max(axis=0).tolist()})
        accessors.append({"bufferView": add_view(normals.tobytes(), 34962), "componentType": 5126,
                          "count": len(normals), "type": "VEC3"})
        accessors.append({"bufferView": add_view(indices.tobytes(), 34963), "componentType": 5125,
                          "count": len(indices), "type": "SCALAR"})
        peak = max(radiance)
        gltf["materials"].append({
            "name": f"{name} (area light)", "doubleSided": False,
            "pbrMetallicRoughness": {"baseColorFactor": [0.0, 0.0, 0.0, 1.0],
                                     "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "emissiveFactor": [c / peak if peak > 0 else 0.0 for c in radiance],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": peak}}})
        gltf["meshes"].append({"name": f"{name} (area light)", "primitives": [{
            "attributes": {"POSITION": len(accessors) - 3, "NORMAL": len(accessors) - 2},
            "indices": len(accessors) - 1, "material": len(gltf["materials"]) - 1}]})
        gltf["nodes"].append({"name": name, "mesh": len(gltf["meshes"]) - 1})
        roots.append(len(gltf["nodes"]) - 1)
    gltf["buffers"][0]["byteLength"] = len(binary)
    gltf["buffers"][0].pop("uri", None)
    _write_glb(glb_path, gltf, binary)
