# Renders a glTF scene with Blender's Cycles, set up to compute what `dacrt render` computes, for
# side-by-side checks of dacrt's images, means and noise. An optional peer: no test, no build step
# and no CI script uses it (Blender is not one of dacrt's dependencies).
#
#   blender -b -noaudio --python tools/cycles-render.py -- SCENE.gltf OUT.exr [--spp N]
#       [--width W --height H] [--seed S] [--max-depth D] [--threads T] [--camera INDEX]
#       [--look-from X,Y,Z --look-at X,Y,Z --up X,Y,Z --fov DEGREES]
#       [--environment R,G,B] [--principled]
#
# Needs Debian 12's `blender` (3.4) and `python3-numpy` (Blender's glTF importer imports numpy).
# Prints `cycles-seconds S` on stdout: the render alone (scene sync, BVH build and sampling, as
# dacrt's seconds_with_build), not Blender's start, the import or the EXR write.
#
# What is set, and why (dacrt's side in brackets):
# - Scene: Blender's bundled glTF importer into an empty file (no default cube, light or world).
#   Emission: the importer sets the emission colour to emissiveFactor and the strength to
#   KHR_materials_emissive_strength (1 without it), with no other factor, and a Cycles mesh
#   emitter of colour c and strength s has radiance c * s: radiance = emissiveFactor x strength,
#   [as dacrt reads it]. Emission is one-sided unless the material is doubleSided [as dacrt]:
#   Cycles emits from both sides, so the emission is gated by the Backfacing input.
#   Punctual lights: lighting mode "Unitless" (COMPAT: point and spot power = 4 pi x intensity,
#   which Cycles divides by 4 pi again; sun strength = intensity), [intensities in renderer units,
#   like emissive factors]; radius and sun angle 0 [points and parallel rays]. Spot cones are
#   Blender's smoothstep blend, not the glTF falloff: approximate.
# - Materials: a material with metallic 0, transmission 0 and KHR_materials_specular factor 0 is
#   pure Lambert in glTF, and becomes Cycles' Diffuse BSDF with roughness 0 (Lambert). Blender's
#   Principled BSDF is not: its diffuse has a roughness-dependent retro-reflection term, and
#   Blender 3.4's importer drops specularFactor (it sets Specular 0.5 for specularFactor 0; the
#   factor only lands in the "glTF Material Output" group). Other materials keep the Principled
#   BSDF with Specular scaled by specularFactor: close to the glTF BRDF, not equal to it.
#   `--principled` keeps the Principled BSDF everywhere (with the specularFactor fix), to see
#   what it changes.
# - Camera: the file's camera, INDEX counted as dacrt counts them (depth-first pre-order over
#   the default scene's nodes), its world transform with scale removed as dacrt removes it,
#   yfov with a vertical sensor fit (the image's aspect decides the horizontal field, [as dacrt]),
#   clip start = znear. Size: W x H, or from the camera's aspectRatio with 512 on the longer side
#   [as dacrt's image_size]. A file without a camera is an error here (dacrt frames the scene),
#   unless the camera is given whole as a LookAt: --look-from, --look-at, --up and --fov (vertical,
#   degrees) together, as `dacrt info` prints them [dacrt's options of the same names, glm::lookAt].
# - Integrator: CPU, `--spp` samples, PMJ (progressive multi-jitter), seed S, no adaptive
#   sampling, no denoising, no clamping (direct and indirect 0), light threshold 0, no glossy
#   filter, caustics on. Bounces: every kind (total, diffuse, glossy, transmission, volume,
#   transparent) = D - 1, since dacrt's depth D counts path vertices from the camera (D = 1 is
#   direct light only) and Cycles' bounces count the scattering events after the first hit
#   (0 = direct light only). Both use unbiased Russian roulette.
# - Film: box pixel filter of width 1 pixel [dacrt's film adds each sample to its own pixel],
#   not transparent, exposure 1.
# - World: black when the scene has emitters or lights, a uniform 1 otherwise [dacrt's default],
#   or `--environment R,G,B`.
# - Output: linear float RGB OpenEXR (32-bit, ZIP), scene-linear Rec.709 (Blender's default
#   OCIO config). View transform Standard, look None, exposure 0, gamma 1 (an EXR is written
#   without a view transform anyway; this is for anything viewed or saved otherwise).
import argparse
import json
import math
import os
import struct
import sys
import time

import bpy

try:
    import numpy
except ImportError:
    numpy = None


def fail(message):
    print("cycles-render: " + message, file=sys.stderr)
    sys.stdout.flush()
    sys.exit(1)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="blender -b -noaudio --python tools/cycles-render.py --")
    p.add_argument("scene")
    p.add_argument("output")
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--width", type=int, default=0)
    p.add_argument("--height", type=int, default=0)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--max-depth", type=int, default=64)
    p.add_argument("--threads", type=int, default=0, help="0: all cores")
    p.add_argument("--camera", type=int, default=0)
    p.add_argument("--look-from", default=None, help="X,Y,Z (with --look-at, --up and --fov)")
    p.add_argument("--look-at", default=None, help="X,Y,Z")
    p.add_argument("--up", default=None, help="X,Y,Z")
    p.add_argument("--fov", type=float, default=None, help="vertical field of view, degrees")
    p.add_argument("--environment", default=None, help="R,G,B (default: 0 with emitters, else 1)")
    p.add_argument("--principled", action="store_true",
                   help="keep the Principled BSDF for Lambert materials too")
    a = p.parse_args(argv)
    if a.spp < 1 or a.max_depth < 1 or a.threads < 0 or a.width < 0 or a.height < 0:
        p.error("--spp and --max-depth must be >= 1; sizes and --threads >= 0")
    def triple(name, text):
        try:
            v = [float(c) for c in text.split(",")]
            assert len(v) == 3 and all(math.isfinite(c) for c in v)
            return v
        except (ValueError, AssertionError):
            p.error("--%s wants three finite numbers X,Y,Z" % name)
    if a.environment is not None:
        a.environment = triple("environment", a.environment)
    look = (a.look_from, a.look_at, a.up, a.fov)
    if any(v is not None for v in look):
        if any(v is None for v in look):
            p.error("--look-from, --look-at, --up and --fov go together (as `dacrt info` prints them)")
        a.look_from = triple("look-from", a.look_from)
        a.look_at = triple("look-at", a.look_at)
        a.up = triple("up", a.up)
        if not 0 < a.fov < 180:
            p.error("--fov wants degrees in (0, 180)")
    return a


def read_gltf_json(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] == b"glTF":  # .glb: the first chunk is the JSON
        length, kind = struct.unpack_from("<II", data, 12)
        if kind != 0x4E4F534A:
            fail(path + ": the first chunk of the .glb is not JSON")
        return json.loads(data[20:20 + length])
    return json.loads(data)


# --- glTF cameras, as dacrt finds them -------------------------------------------------------------

def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def local_matrix(node):
    if "matrix" in node:
        m = node["matrix"]  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(3)] + [[0, 0, 0, 1]]
    tx, ty, tz = node.get("translation", [0, 0, 0])
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    sx, sy, sz = node.get("scale", [1, 1, 1])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[i][0] * sx, r[i][1] * sy, r[i][2] * sz, (tx, ty, tz)[i]] for i in range(3)] + \
        [[0, 0, 0, 1]]


def gltf_cameras(doc):
    """(camera dict, world matrix) in dacrt's order: depth-first, pre-order, children in order."""
    nodes = doc.get("nodes", [])
    scenes = doc.get("scenes", [])
    if not scenes:
        return []
    roots = scenes[doc.get("scene", 0)].get("nodes", [])
    identity = [[float(i == j) for j in range(4)] for i in range(4)]
    stack = [(n, identity) for n in reversed(roots)]
    out = []
    while stack:
        index, parent = stack.pop()
        node = nodes[index]
        world = mat_mul(parent, local_matrix(node))
        if "camera" in node:
            out.append((doc["cameras"][node["camera"]], world))
        for child in reversed(node.get("children", [])):
            stack.append((child, world))
    return out


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v] if n > 0 else None


def look_at_camera(a):
    """A perspective glTF camera and its world matrix from the LookAt options (glm::lookAt's frame:
    the camera looks along -Z, X = up x Z)."""
    z = normalize([f - t for f, t in zip(a.look_from, a.look_at)])
    if z is None:
        fail("--look-at must differ from --look-from")
    up = a.up
    x = normalize([up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]])
    if x is None:
        fail("--up is parallel to the viewing direction")
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    world = [[x[i], y[i], z[i], a.look_from[i]] for i in range(3)] + [[0, 0, 0, 1]]
    return {"type": "perspective", "perspective": {"yfov": math.radians(a.fov), "znear": 1e-6}}, world


def setup_camera(scene, doc, a, width, height):
    index = a.camera
    if a.look_from is not None:
        src, world = look_at_camera(a)
    else:
        cams = gltf_cameras(doc)
        if not cams:
            fail("the scene has no camera (dacrt would frame the scene; give the file a camera, "
                 "or --look-from, --look-at, --up and --fov from `dacrt info`)")
        if not 0 <= index < len(cams):
            fail("camera %d does not exist (the scene has %d)" % (index, len(cams)))
        src, world = cams[index]
    # Scale and shear removed as dacrt does: keep the viewing axis (Z), then Y.
    z = normalize([world[i][2] for i in range(3)])
    y0 = [world[i][1] for i in range(3)]
    d = sum(a * b for a, b in zip(y0, z))
    y = normalize([y0[i] - d * z[i] for i in range(3)])
    if z is None or y is None:
        fail("camera %d has a degenerate transform" % index)
    x = [y[1] * z[2] - y[2] * z[1], y[2] * z[0] - y[0] * z[2], y[0] * z[1] - y[1] * z[0]]
    t = [world[i][3] for i in range(3)]
    import mathutils
    m = mathutils.Matrix(((x[0], y[0], z[0], t[0]), (x[1], y[1], z[1], t[1]),
                          (x[2], y[2], z[2], t[2]), (0, 0, 0, 1)))
    # glTF is +Y up, Blender +Z up: the importer's conversion, (x, y, z) -> (x, -z, y).
    yup_to_zup = mathutils.Matrix(((1, 0, 0, 0), (0, 0, -1, 0), (0, 1, 0, 0), (0, 0, 0, 1)))
    data = bpy.data.cameras.new("dacrt camera %d" % index)
    data.sensor_fit = "VERTICAL"
    if src.get("type") == "orthographic":
        o = src["orthographic"]
        data.type = "ORTHO"
        data.ortho_scale = 2 * abs(o["ymag"])
        aspect = abs(o["xmag"]) / abs(o["ymag"])
        data.clip_start = max(o.get("znear", 0.0), 1e-6)
        data.clip_end = o.get("zfar", 1e12)
    else:
        p = src["perspective"]
        data.type = "PERSP"
        data.lens_unit = "FOV"
        data.angle_y = p["yfov"]
        aspect = p.get("aspectRatio", 0.0)
        data.clip_start = max(p.get("znear", 0.0), 1e-6)
        data.clip_end = p.get("zfar", 1e12)
    obj = bpy.data.objects.new(data.name, data)
    scene.collection.objects.link(obj)
    obj.matrix_world = yup_to_zup @ m
    scene.camera = obj
    # dacrt's image_size: both given, or one derived from the aspect, or 512 on the longer side.
    if not (width and height):
        if aspect > 0:
            if width:
                height = max(1, round(width / aspect))
            elif height:
                width = max(1, round(height * aspect))
            elif aspect >= 1:
                width, height = 512, max(1, round(512 / aspect))
            else:
                width, height = max(1, round(512 * aspect)), 512
        else:
            width = height = width or height or 512
    return width, height


# --- materials ---------------------------------------------------------------------------------

def socket_value(sock):
    v = sock.default_value
    return tuple(v) if hasattr(v, "__len__") else v


def move_input(tree, src, dst):
    """dst takes src's link, or its value."""
    if src.is_linked:
        tree.links.new(src.links[0].from_socket, dst)
    else:
        dst.default_value = src.default_value


def fix_material(mat, lambert_allowed):
    """Returns whether the material emits."""
    if not mat.use_nodes:
        return False
    tree = mat.node_tree
    nodes, links = tree.nodes, tree.links
    pbr = next((n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)
    out = next((n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial"
                and n.is_active_output), None) or \
        next((n for n in nodes if n.bl_idname == "ShaderNodeOutputMaterial"), None)
    if pbr is None or out is None:
        return False
    gltf_out = next((n for n in nodes if n.bl_idname == "ShaderNodeGroup" and n.node_tree
                     and n.node_tree.name.startswith("glTF Material Output")), None)
    spec_in = gltf_out.inputs.get("Specular") if gltf_out else None
    spec_factor = None
    if spec_in is not None and not spec_in.is_linked:
        spec_factor = spec_in.default_value
    # KHR_materials_specular's factor, which Blender 3.4's importer leaves out of Specular.
    if spec_factor is not None and not pbr.inputs["Specular"].is_linked:
        pbr.inputs["Specular"].default_value *= spec_factor

    one_sided = mat.use_backface_culling  # the importer: culling = not doubleSided
    ins = pbr.inputs
    emission_color, strength = ins["Emission"], ins["Emission Strength"]
    emits = (emission_color.is_linked or any(c > 0 for c in socket_value(emission_color)[:3])) \
        and (strength.is_linked or strength.default_value > 0)

    lambert = (lambert_allowed and spec_factor == 0.0
               and not ins["Metallic"].is_linked and ins["Metallic"].default_value == 0.0
               and not ins["Transmission"].is_linked and ins["Transmission"].default_value == 0.0
               and not ins["Specular"].is_linked
               and not ins["Clearcoat"].is_linked and ins["Clearcoat"].default_value == 0.0
               and not ins["Sheen"].is_linked and ins["Sheen"].default_value == 0.0
               and not ins["Subsurface"].is_linked and ins["Subsurface"].default_value == 0.0)

    surface = pbr.outputs["BSDF"]
    if lambert:
        diffuse = nodes.new("ShaderNodeBsdfDiffuse")
        move_input(tree, ins["Base Color"], diffuse.inputs["Color"])
        diffuse.inputs["Roughness"].default_value = 0.0  # Lambert, not Oren-Nayar
        if ins["Normal"].is_linked:
            links.new(ins["Normal"].links[0].from_socket, diffuse.inputs["Normal"])
        surface = diffuse.outputs["BSDF"]
        alpha = ins["Alpha"]
        if alpha.is_linked or alpha.default_value < 1.0:
            transparent = nodes.new("ShaderNodeBsdfTransparent")
            mix = nodes.new("ShaderNodeMixShader")
            move_input(tree, alpha, mix.inputs["Fac"])
            links.new(transparent.outputs[0], mix.inputs[1])
            links.new(surface, mix.inputs[2])
            surface = mix.outputs[0]
    if emits:
        emission = nodes.new("ShaderNodeEmission")
        move_input(tree, emission_color, emission.inputs["Color"])
        move_input(tree, strength, emission.inputs["Strength"])
        for link in list(strength.links):
            links.remove(link)
        strength.default_value = 0.0  # the Principled BSDF no longer emits
        light = emission.outputs[0]
        if one_sided:
            geometry = nodes.new("ShaderNodeNewGeometry")
            gate = nodes.new("ShaderNodeMixShader")  # front: emission; back: nothing
            links.new(geometry.outputs["Backfacing"], gate.inputs["Fac"])
            links.new(light, gate.inputs[1])
            light = gate.outputs[0]
        add = nodes.new("ShaderNodeAddShader")
        links.new(surface, add.inputs[0])
        links.new(light, add.inputs[1])
        surface = add.outputs[0]
    links.new(surface, out.inputs["Surface"])
    return emits


# --- the render --------------------------------------------------------------------------------

def main():
    a = parse_args()
    if numpy is None:
        fail("Blender's Python has no numpy, which its glTF importer needs: "
             "apt-get install python3-numpy")
    # Blender 3.4's importer still uses numpy.bool, which numpy 1.24 removed (Debian 12 ships
    # both): give it the alias back, in this process only.
    if "bool" not in numpy.__dict__:
        numpy.bool = bool
    if not os.path.isfile(a.scene):
        fail(a.scene + ": no such file")
    out_dir = os.path.dirname(os.path.abspath(a.output))
    if not os.path.isdir(out_dir):
        fail(a.output + ": its directory does not exist")
    try:
        doc = read_gltf_json(a.scene)
    except (OSError, ValueError, struct.error) as e:
        fail(a.scene + ": not a readable glTF: " + str(e))

    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.preferences.addon_enable(module="io_scene_gltf2")
    if bpy.ops.import_scene.gltf(filepath=a.scene, convert_lighting_mode="COMPAT") != {"FINISHED"}:
        fail(a.scene + ": Blender's glTF importer failed")
    scene = bpy.context.scene
    for obj in list(scene.objects):  # the file's own cameras: ours replaces them
        if obj.type == "CAMERA":
            obj.hide_render = True
    width, height = setup_camera(scene, doc, a, a.width, a.height)

    emitters = False
    used = {slot.material for obj in scene.objects if obj.type == "MESH"
            for slot in obj.material_slots if slot.material}
    for mat in used:
        emitters |= fix_material(mat, not a.principled)
    for obj in scene.objects:
        if obj.type == "LIGHT":
            emitters = True
            if obj.data.type in ("POINT", "SPOT"):
                obj.data.shadow_soft_size = 0.0
            elif obj.data.type == "SUN":
                obj.data.angle = 0.0

    world = bpy.data.worlds.new("dacrt environment")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    env = a.environment if a.environment is not None else ([0.0] * 3 if emitters else [1.0] * 3)
    background.inputs["Color"].default_value = (*env, 1.0)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world

    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = a.spp
    c.sampling_pattern = "PROGRESSIVE_MULTI_JITTER"
    c.seed = a.seed
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    bounces = a.max_depth - 1
    c.max_bounces = bounces
    c.diffuse_bounces = bounces
    c.glossy_bounces = bounces
    c.transmission_bounces = bounces
    c.volume_bounces = bounces
    c.transparent_max_bounces = bounces
    c.min_light_bounces = 0
    c.min_transparent_bounces = 0
    c.pixel_filter_type = "BOX"
    c.filter_width = 1.0
    c.film_exposure = 1.0
    r = scene.render
    r.film_transparent = False
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.threads_mode = "FIXED" if a.threads else "AUTO"
    if a.threads:
        r.threads = a.threads
    r.use_compositing = False
    r.use_sequencer = False
    scene.display_settings.display_device = "sRGB"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.view_settings.use_curve_mapping = False
    s = r.image_settings
    s.file_format = "OPEN_EXR"
    s.color_mode = "RGB"
    s.color_depth = "32"
    s.exr_codec = "ZIP"

    camera = ("look-from %s" % ",".join("%g" % v for v in a.look_from)) if a.look_from else \
        "camera %d" % a.camera
    print("cycles-render: %s, %s, %dx%d, %d spp, seed %d, max depth %d (%d bounces), "
          "%s threads, environment %s, %s" %
          (a.scene, camera, width, height, a.spp, a.seed, a.max_depth, bounces,
           a.threads or "all", ",".join("%g" % v for v in env),
           "Principled BSDF" if a.principled else "Lambert materials as Diffuse BSDF"),
          file=sys.stderr)
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=False)
    seconds = time.perf_counter() - t0
    bpy.data.images["Render Result"].save_render(a.output, scene=scene)
    print("cycles-seconds %.3f" % seconds)
    sys.stdout.flush()


try:
    main()
except SystemExit as e:
    # Blender ignores the script's exit status; make the process's say what happened.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(e.code if isinstance(e.code, int) else 1)
except Exception as e:
    import traceback
    traceback.print_exc()
    fail(str(e))
