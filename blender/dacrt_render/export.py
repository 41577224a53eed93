"""The scene as a .glb through Blender's own glTF exporter, and where its camera ends up.

The exporter writes what glTF carries: meshes with modifiers applied, Principled BSDF materials
and their image textures, cameras, and point, spot and sun lights. It drops area lights, the
world, volumes and any shader node it cannot map to glTF's metallic-roughness material. Area
lights are added to the file afterwards as emissive meshes (add_area_lights); the world goes to
dacrt's --environment (world.py). Every function here returns the warnings of what it loses, for
the engine to show in Blender's report.
"""

import contextlib
import io
import json
import re
import struct
import sys

import bpy

# glTF lights in candela (SPEC) are Blender's watts × 683 / 4π: 683 times what Cycles gives a
# point light. COMPAT writes W / 4π, the radiant intensity Cycles renders.
LIGHT_UNITS = (
    ("COMPAT", "Blender (W/4π)", "Light intensities as Cycles and Eevee use them: a 1000 W point "
     "light is 1000/4π, which dacrt takes as radiant intensity"),
    ("SPEC", "glTF standard (cd)", "Photometric units as the glTF specification defines them: "
     "683 times brighter in dacrt, which reads intensities as radiometric"),
)


# The exporter's warnings: "HH:MM:SS | WARNING: text" on stdout (io_scene_gltf2's print_console).
_EXPORTER_WARNING = re.compile(r"\|\s*WARNING:\s*(.*)$")


def export_scene(path, scene, view_layer, light_units):
    """Writes the evaluated scene (modifiers applied, current frame, Y up) to path as GLB and
    returns the exporter's warnings (also left on the console), but for area lights, which
    add_area_lights turns into emitters."""
    captured = io.StringIO()
    with bpy.context.temp_override(scene=scene, view_layer=view_layer), \
            contextlib.redirect_stdout(captured):
        result = bpy.ops.export_scene.gltf(
            filepath=path, export_format='GLB', use_active_scene=True, use_renderable=True,
            export_cameras=True, export_lights=True, export_apply=True, export_yup=True,
            # The pose of the current frame, without animation channels that the renderer
            # would evaluate at its own time 0.
            export_animations=False, export_current_frame=True, export_extras=False,
            convert_lighting_mode=light_units)
    sys.stdout.write(captured.getvalue())
    if result != {'FINISHED'}:
        raise RuntimeError(f"the glTF exporter returned {sorted(result)}")
    warnings = []
    for line in captured.getvalue().splitlines():
        match = _EXPORTER_WARNING.search(line)
        if match and match.group(1) != "Unsupported light source AREA":
            warnings.append("glTF exporter: " + match.group(1))
    return list(dict.fromkeys(warnings))  # once each, in order


def read_glb_json(path):
    """The JSON chunk of a .glb file."""
    with open(path, "rb") as file:
        header = file.read(20)
        magic, _, _, length, kind = struct.unpack("<4sIIII", header)
        if magic != b"glTF" or kind != 0x4E4F534A:  # "JSON"
            raise ValueError(f"{path}: not a binary glTF file")
        return json.loads(file.read(length))


def camera_index(gltf, object_name):
    """The --camera index dacrt gives the camera of Blender's object object_name, or None.

    dacrt numbers cameras in the order it walks the default scene (io/gltf/nodes.cpp): depth
    first from the scene's root nodes in order, a node before its children. The exporter names
    a camera's node after its object (and keeps the camera on that node when it has children).
    """
    nodes = gltf.get("nodes", [])
    scenes = gltf.get("scenes", [])
    if not scenes:
        return None
    roots = scenes[gltf.get("scene", 0)].get("nodes", [])
    index = 0
    stack = list(reversed(roots))
    while stack:
        node = nodes[stack.pop()]
        if "camera" in node:
            if node.get("name") == object_name:
                return index
            index += 1
        stack.extend(reversed(node.get("children", [])))
    return None
