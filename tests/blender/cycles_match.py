"""The dacrt add-on against Cycles in headless Blender: what the exporter cannot carry arrives.

Run: blender -b --factory-startup -noaudio --python-exit-code 1 \
         --python tests/blender/cycles_match.py -- DACRT_CLI WORK_DIR

Builds one scene (a glossy floor, a diffuse sphere and cube, a rectangular area light out of
view, a point light, an image world: a small generated equirectangular EXR whose colour changes
with the direction, a camera with depth of field focused 3 m ahead (an empty), the sphere and the
background blurred) and renders it through the add-on and with Cycles at the same size and
samples. Checks:
- the per-channel means agree within 10 % (the area light's power, the world's bake, DoF);
- the world's bake is oriented as Cycles sees the world: four views of the world alone (+Y, +X,
  -X, up), each view's per-channel means within 10 %;
- a disk area light alone on a floor lights it as Cycles' (means within 10 %), and so do a spot
  light and a sun;
- the passes (Depth, Normal, Position, Diffuse Color) hold what Cycles' hold: per-channel means
  over the pixels both hit, the background's depth;
- the warnings of what is lost (the point light's radius, the aperture's blades, a warning line
  of dacrt's own, the glTF exporter's warning) reach Blender's report;
- the CLI got --aperture = lens / f-stop and --focus-distance = the focus object's distance
  along the view axis (in the options the add-on keeps);
- depth of field blurs a bar 10 m away as Cycles does (the mean gradient within 15 %);
- the .glb holds the area light's emitter with radiance colour × P / 4A, one-sided, and an
  area light in view is warned about;
- the panel's time limit and adaptive sampling reach the CLI.
Depth of field needs a dacrt with --aperture: without it (`dacrt render --help` does not list
it) the test says so and renders without depth of field, in both renderers.
"""

import math
import os
import shutil
import subprocess
import sys
import time

import addon_utils
import bpy
import numpy as np

WIDTH, HEIGHT, SPP = 80, 60, 64
TOLERANCE = 0.10
failures = []


def check(condition, message):
    print(("ok: " if condition else "FAIL: ") + message, flush=True)
    if not condition:
        failures.append(message)


def principled(name, color, roughness, metallic=0.0):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    return material


def add_mesh(operator, material, **arguments):
    operator(**arguments)
    obj = bpy.context.object
    obj.data.materials.append(material)
    return obj


def world_image(path):
    """A 64×32 equirectangular EXR whose colour turns with the azimuth and brightens upwards,
    with a bright warm patch: no two views of it alike."""
    width, height = 64, 32
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height  # Blender's rows: bottom first
    azimuth = 2 * math.pi * u[None, :]
    up = v[:, None]
    rgb = np.empty((height, width, 4), dtype=np.float32)
    rgb[..., 0] = 0.3 + 0.25 * np.cos(azimuth) + 0.3 * up
    rgb[..., 1] = 0.3 + 0.25 * np.sin(azimuth) + 0.2 * up
    rgb[..., 2] = 0.3 - 0.2 * np.cos(azimuth) + 0.5 * up
    rgb[..., 3] = 1.0
    rgb[20:26, 10:16, :3] = (6.0, 4.0, 2.0)
    image = bpy.data.images.new("sky", width, height, float_buffer=True)
    image.pixels.foreach_set(rgb.reshape(-1))
    image.filepath_raw = path
    image.file_format = 'OPEN_EXR'
    image.save()
    image.source = 'FILE'
    image.reload()
    return image


def set_world(scene, image):
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    nodes = world.node_tree.nodes
    texture = nodes.new("ShaderNodeTexEnvironment")
    texture.image = image
    world.node_tree.links.new(texture.outputs["Color"], nodes["Background"].inputs["Color"])
    nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world


def setup_cycles(scene):
    c = scene.cycles
    c.device, c.samples, c.seed = 'CPU', SPP, 1
    c.use_adaptive_sampling = c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 12
    c.pixel_filter_type, c.filter_width = 'BOX', 1.0


def render(scene, engine, path):
    scene.render.engine = engine
    scene.render.filepath = path
    start = time.monotonic()
    bpy.ops.render.render(write_still=True)
    return time.monotonic() - start


def read(path, names):
    from dacrt_render import exr
    planes = exr.read_channels(path, names)
    return np.stack([planes[n] for n in names], axis=-1)


def layer_names(path):
    from dacrt_render import exr
    with open(path, "rb") as file:
        data = file.read()
    attributes, _ = exr._header(data, path)
    return [name for name, _ in exr._channels(attributes["channels"][1])]


def channel(path, pass_name, letters):
    """A pass of Blender's multilayer EXR: its channels `letters`, H×W×len(letters)."""
    names = layer_names(path)
    found = []
    for letter in letters:
        match = [n for n in names if n.endswith(f".{pass_name}.{letter}")]
        found.append(match[0] if match else f"?.{pass_name}.{letter}")
    return read(path, found)


def means_agree(label, ours, theirs, tolerance=TOLERANCE):
    a, b = ours.reshape(-1, ours.shape[-1]).mean(0), theirs.reshape(-1, theirs.shape[-1]).mean(0)
    ratio = a / np.maximum(b, 1e-12)
    check(bool(np.all(np.abs(ratio - 1) < tolerance)),
          f"{label}: dacrt means {np.round(a, 4).tolist()}, Cycles {np.round(b, 4).tolist()} "
          f"(ratio {np.round(ratio, 3).tolist()})")
    return a, b


def sharpness(image):
    """The mean gradient of the luminance's 2×2 box means: how sharp the picture is, with some
    of the sampling noise averaged out."""
    luminance = image @ np.array([0.2126, 0.7152, 0.0722])
    h, w = (d // 2 * 2 for d in luminance.shape)
    blocks = luminance[:h, :w].reshape(h // 2, 2, w // 2, 2).mean(axis=(1, 3))
    return float(np.abs(np.diff(blocks, axis=0)).mean() + np.abs(np.diff(blocks, axis=1)).mean())


def main(cli, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    keep = os.path.join(work, "kept")
    # A dacrt that prints one warning line of its own first: the add-on must show it.
    wrapper = os.path.join(work, "dacrt-wrapper.sh")
    with open(wrapper, "w") as file:
        file.write(f'#!/bin/sh\necho "warning: a line of dacrt\'s own" >&2\nexec "{cli}" "$@"\n')
    os.chmod(wrapper, 0o755)
    os.environ["DACRT_CLI"] = wrapper
    os.environ["DACRT_BLENDER_KEEP"] = keep
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "blender"))
    addon_utils.enable("dacrt_render", default_set=True, handle_error=None)
    from dacrt_render.engine import DacrtRenderEngine
    warnings, errors = [], []
    show_warning, show_error = DacrtRenderEngine._show_warning, DacrtRenderEngine._show_error
    DacrtRenderEngine._show_warning = lambda self, message: (
        warnings.append(message), show_warning(self, message))
    DacrtRenderEngine._show_error = lambda self, message: (
        errors.append(message), show_error(self, message))
    help_text = subprocess.run([cli, "render", "--help"], capture_output=True, text=True).stdout
    has_dof = "--aperture" in help_text

    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    scene = bpy.context.scene
    setup_cycles(scene)
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = 'Standard'
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth, settings.exr_codec = 'OPEN_EXR', '32', 'ZIP'
    settings.color_mode = 'RGB'
    scene.dacrt.spp, scene.dacrt.max_depth = SPP, 13  # Cycles' 12 bounces
    scene.dacrt.environment_width = 256
    set_world(scene, world_image(os.path.join(work, "sky.exr")))

    # The orientation of the world: views of it alone, each direction's colour its own. A small
    # cube far below (the glTF exporter wants something to export besides the camera).
    add_mesh(bpy.ops.mesh.primitive_cube_add, principled("grey", (0.5, 0.5, 0.5), 0.5),
             size=0.01, location=(0.0, 0.0, -50.0))
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.data.lens = 18
    for label, rotation in (("+Y", (math.pi / 2, 0, 0)), ("+X", (math.pi / 2, 0, -math.pi / 2)),
                            ("-X", (math.pi / 2, 0, math.pi / 2)), ("up", (math.pi, 0.0, 0.0))):
        camera.rotation_euler = rotation
        render(scene, 'DACRT', os.path.join(work, f"world-{label}-dacrt.exr"))
        render(scene, 'CYCLES', os.path.join(work, f"world-{label}-cycles.exr"))
        means_agree(f"the world seen towards {label}",
                    read(os.path.join(work, f"world-{label}-dacrt.exr"), ["R", "G", "B"]),
                    read(os.path.join(work, f"world-{label}-cycles.exr"), ["R", "G", "B"]))
    check(os.path.exists(os.path.join(keep, "environment.exr")), "the world was baked to an EXR")

    # Depth of field: a black bar 10 m ahead against the world, focused 1 m ahead through a
    # 10 cm lens: the bar's edges are blurred over a disk 9 cm wide on the plane in focus, 19 %
    # of the image's height, and the blur is as Cycles' (the mean gradient: twice the lens
    # makes it 2/3).
    if has_dof:
        bar = add_mesh(bpy.ops.mesh.primitive_cube_add, principled("black", (0, 0, 0), 1.0),
                       size=1.0, location=(0.0, 10.0, 0.0))
        bar.scale = (0.3, 0.3, 30.0)
        camera.data.lens = 50
        camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
        dof = camera.data.dof
        dof.use_dof, dof.focus_distance, dof.aperture_fstop = True, 1.0, 0.5
        blurred = {}
        for engine in ('DACRT', 'CYCLES'):
            path = os.path.join(work, f"world-dof-{engine.lower()}.exr")
            render(scene, engine, path)
            blurred[engine] = read(path, ["R", "G", "B"])
        means_agree("the world through the lens", blurred['DACRT'], blurred['CYCLES'])
        a, b = sharpness(blurred['DACRT']), sharpness(blurred['CYCLES'])
        check(abs(a / b - 1) < 0.15, f"depth of field blurs as Cycles': mean gradient {a:.4f}, "
              f"Cycles {b:.4f}")
        dof.use_dof = False
        bpy.data.objects.remove(bar)
    else:
        print(f"NOTE: {cli} has no --aperture: depth of field is not checked", flush=True)

    # The scene.
    bpy.data.objects.remove(bpy.data.objects["Cube"])
    add_mesh(bpy.ops.mesh.primitive_plane_add, principled("floor", (0.6, 0.6, 0.6), 0.25),
             size=12)
    sphere = add_mesh(bpy.ops.mesh.primitive_uv_sphere_add,
                      principled("orange", (0.8, 0.35, 0.1), 0.6), radius=0.5,
                      location=(0.0, 0.0, 0.5), segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    add_mesh(bpy.ops.mesh.primitive_cube_add, principled("blue", (0.1, 0.2, 0.7), 0.5), size=0.7,
             location=(1.3, 1.2, 0.35))
    area_data = bpy.data.lights.new("Area", 'AREA')
    area_data.shape, area_data.size, area_data.size_y = 'RECTANGLE', 1.2, 0.6
    area_data.energy, area_data.color = 400.0, (1.0, 0.9, 0.8)
    area = bpy.data.objects.new("Area", area_data)
    area.location, area.rotation_euler = (-1.5, -1.0, 3.0), (0.3, -0.4, 0.0)
    scene.collection.objects.link(area)
    point_data = bpy.data.lights.new("Point", 'POINT')
    point_data.energy, point_data.shadow_soft_size = 150.0, 0.1
    # Its default node tree (Emission, strength 1: the same light) makes the glTF exporter warn
    # that it finds no Light Falloff node.
    point_data.use_nodes = True
    point = bpy.data.objects.new("Point", point_data)
    point.location = (2.0, -1.5, 2.0)
    scene.collection.objects.link(point)
    camera.data.lens = 50
    camera.location = (0.0, -6.0, 1.6)
    camera.rotation_euler = (math.radians(78), 0.0, 0.0)
    # Focused 3 m ahead, in front of everything, through a 20 cm lens: the sphere (6 m) is a
    # disk 10 cm wide on the plane in focus, 5 % of the image's height.
    focus_target = bpy.data.objects.new("Focus", None)
    focus_target.location = (0.3, -3.0, 1.0)
    scene.collection.objects.link(focus_target)
    dof = camera.data.dof
    dof.use_dof = has_dof
    dof.focus_object, dof.aperture_fstop, dof.aperture_blades = focus_target, 0.25, 6
    view_layer = scene.view_layers[0]
    view_layer.use_pass_z = view_layer.use_pass_normal = True
    view_layer.use_pass_position = view_layer.use_pass_diffuse_color = True
    settings.color_depth = '32'
    settings.file_format = 'OPEN_EXR_MULTILAYER'

    warnings.clear()
    ours, theirs = os.path.join(work, "scene-dacrt.exr"), os.path.join(work, "scene-cycles.exr")
    seconds = render(scene, 'DACRT', ours)
    seconds_cycles = render(scene, 'CYCLES', theirs)
    print(f"scene: dacrt through the add-on {seconds:.1f} s, Cycles {seconds_cycles:.1f} s")
    check(not errors, f"no error reported {errors}")
    means_agree("the scene (area light, point light, image world, glossy floor, DoF)",
                channel(ours, "Combined", "RGB"), channel(theirs, "Combined", "RGB"))
    for needle in ("light Point: radius 0.1", "camera Camera: the aperture's blades",
                   "dacrt: a line of dacrt's own", "glTF exporter: No quadratic light falloff"):
        if "blades" in needle and not has_dof:
            continue
        check(any(w.startswith(needle) for w in warnings),
              f"the report warns '{needle}...' ({warnings})")
    check(not any("Area" in w for w in warnings), "the area light out of view: no warning")

    with open(os.path.join(keep, "options.txt")) as file:
        options = file.read().split("\n")
    if has_dof:
        aperture = float(options[options.index("--aperture") + 1])
        focus = float(options[options.index("--focus-distance") + 1])
        view = -(camera.matrix_world.to_3x3().col[2])
        expected_focus = (focus_target.location - camera.location).dot(view)
        check(abs(aperture - 0.050 / 0.25) < 1e-9, f"--aperture {aperture} = 50 mm / f 0.25")
        check(abs(focus - expected_focus) < 1e-5, f"--focus-distance {focus} = the focus "
              f"object's distance along the view axis {expected_focus:.6f}")
    else:
        check("--aperture" not in options, "no --aperture without depth of field")

    # The passes, against Cycles' (depth and position: the pixels both hit).
    depth_ours, depth_theirs = channel(ours, "Depth", "Z"), channel(theirs, "Depth", "Z")
    hit = (depth_ours[..., 0] < 1e9) & (depth_theirs[..., 0] < 1e9)
    # (With depth of field, a pixel whose samples hit only in part has dacrt's mean depth of
    # those that hit, and Cycles' first sample's: more pixels hit in dacrt's.)
    hit_ours, hit_theirs = (depth_ours[..., 0] < 1e9).mean(), (depth_theirs[..., 0] < 1e9).mean()
    check(0.3 < hit.mean() < 0.95 and abs(hit_ours - hit_theirs) < 0.05,
          f"the background is 1e10 in both Depth passes (hit: {hit_ours:.3f}, {hit_theirs:.3f})")
    means_agree("Depth (along the view axis)", depth_ours[hit], depth_theirs[hit], 0.02)
    for name in ("Normal", "Position"):
        a, b = channel(ours, name, "XYZ")[hit], channel(theirs, name, "XYZ")[hit]
        difference = np.abs(a.mean(0) - b.mean(0))
        check(bool(np.all(difference < 0.05)), f"{name}: dacrt means "
              f"{np.round(a.mean(0), 3).tolist()}, Cycles {np.round(b.mean(0), 3).tolist()}")
    means_agree("Diffuse Color (dacrt's albedo)", channel(ours, "DiffCol", "RGB")[hit],
                channel(theirs, "DiffCol", "RGB")[hit])

    # The emitter in the file: radiance colour × P / (4 A); an area light moved into view warns.
    from dacrt_render import engine as engine_module, export
    glb = os.path.join(work, "in-view.glb")
    area.location, area.rotation_euler = (0.0, -2.0, 1.6), (math.pi / 2, 0.0, 0.0)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    export.export_scene(glb, scene, view_layer, "COMPAT")
    lost = engine_module._add_lights(depsgraph, camera, glb)
    check(any(w.startswith("light Area: an area light in the camera's view") for w in lost),
          f"an area light in view is warned about ({lost})")
    material = next(m for m in export.read_glb_json(glb)["materials"]
                    if m["name"] == "Area (area light)")
    strength = material["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"]
    radiance = [f * strength for f in material["emissiveFactor"]]
    expected = [c * 400.0 / (4 * 1.2 * 0.6) for c in (1.0, 0.9, 0.8)]
    check(np.allclose(radiance, expected, rtol=1e-6) and not material["doubleSided"],
          f"the area light's emitter: one-sided, radiance {radiance} = colour × P / 4A")
    area.location, area.rotation_euler = (-1.5, -1.0, 3.0), (0.3, -0.4, 0.0)

    # A disk area light alone, with nothing else lit: its power as Cycles'.
    for obj in (area, point):
        obj.hide_render = True
    disk_data = bpy.data.lights.new("Disk", 'AREA')
    disk_data.shape, disk_data.size, disk_data.energy = 'DISK', 0.8, 200.0
    disk = bpy.data.objects.new("Disk", disk_data)
    disk.location = (0.5, 0.0, 2.0)
    scene.collection.objects.link(disk)
    scene.world = None
    dof.use_dof = False
    view_layer.use_pass_z = view_layer.use_pass_normal = False
    view_layer.use_pass_position = view_layer.use_pass_diffuse_color = False
    settings.file_format = 'OPEN_EXR'
    render(scene, 'DACRT', os.path.join(work, "disk-dacrt.exr"))
    render(scene, 'CYCLES', os.path.join(work, "disk-cycles.exr"))
    means_agree("a disk area light alone", read(os.path.join(work, "disk-dacrt.exr"), "RGB"),
                read(os.path.join(work, "disk-cycles.exr"), "RGB"))

    # A spot light (no blend, no radius) and a sun (no angle) alone: through KHR_lights_punctual
    # with the exporter's Blender units, the power Cycles gives them.
    disk.hide_render = True
    spot_data = bpy.data.lights.new("Spot", 'SPOT')
    spot_data.energy, spot_data.shadow_soft_size = 300.0, 0.0
    spot_data.spot_size, spot_data.spot_blend = math.radians(50), 0.0
    spot = bpy.data.objects.new("Spot", spot_data)
    spot.location, spot.rotation_euler = (-1.0, -1.0, 3.0), (0.3, -0.3, 0.0)
    scene.collection.objects.link(spot)
    sun_data = bpy.data.lights.new("Sun", 'SUN')
    sun_data.energy, sun_data.angle, sun_data.color = 1.5, 0.0, (0.6, 0.7, 1.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (0.6, 0.4, 0.0)
    scene.collection.objects.link(sun)
    warnings.clear()
    # The panel's time limit (not reached) and adaptive sampling reach the CLI.
    scene.dacrt.time_limit, scene.dacrt.use_adaptive = 300.0, True
    scene.dacrt.adaptive_threshold, scene.dacrt.adaptive_min = 0.02, 16
    render(scene, 'DACRT', os.path.join(work, "punctual-dacrt.exr"))
    with open(os.path.join(keep, "options.txt")) as file:
        options = " ".join(file.read().split())
    check("--time-limit 300 --adaptive 0.02 --adaptive-min 16" in options,
          f"time limit and adaptive sampling passed on ({options})")
    render(scene, 'CYCLES', os.path.join(work, "punctual-cycles.exr"))
    means_agree("a spot light and a sun", read(os.path.join(work, "punctual-dacrt.exr"), "RGB"),
                read(os.path.join(work, "punctual-cycles.exr"), "RGB"))
    check(not any(w.startswith(("light Spot", "light Sun")) for w in warnings),
          f"nothing of them lost, nothing warned ({warnings})")


if __name__ == "__main__":
    arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(arguments) != 2:
        sys.exit("usage: blender -b --python cycles_match.py -- DACRT_CLI WORK_DIR")
    start = time.monotonic()
    main(os.path.abspath(arguments[0]), os.path.abspath(arguments[1]))
    print(f"{time.monotonic() - start:.0f} s in all", flush=True)
    if failures:
        sys.exit(f"{len(failures)} check(s) failed")
    print("all checks passed", flush=True)
    sys.exit(0)
