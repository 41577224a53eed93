"""The dacrt render engine: export the scene as glTF, render it with dacrt, show the image."""

import os
import shutil
import tempfile

import bpy
import numpy as np

from . import cli, export, lights, world

# Blender's passes dacrt fills, by the view layer's switch: (AOV, pass name, channels,
# channel ids, kind), as Cycles registers them.
PASSES = (("use_pass_z", "depth", "Depth", 1, "Z", 'VALUE'),
          ("use_pass_normal", "normal", "Normal", 3, "XYZ", 'VECTOR'),
          ("use_pass_position", "position", "Position", 3, "XYZ", 'VECTOR'),
          ("use_pass_diffuse_color", "albedo", "DiffCol", 3, "RGB", 'COLOR'))

# Set to a directory, the engine copies there the .glb it rendered and the CLI's EXR
# (scene.glb, render.exr): to render the same file from the command line, or compare with it.
KEEP_ENV = "DACRT_BLENDER_KEEP"


class DacrtRenderEngine(bpy.types.RenderEngine):
    bl_idname = "DACRT"
    bl_label = "dacrt"
    bl_use_preview = False           # material previews: each would be a whole export and render
    bl_use_eevee_viewport = True     # the viewport's Material Preview and Rendered modes
    bl_use_shading_nodes_custom = False  # Blender's shader nodes, which the exporter reads

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", 'COLOR')
        for switch, _, name, channels, ids, kind in PASSES:
            if getattr(renderlayer, switch):
                self.register_pass(scene, renderlayer, name, channels, ids, kind)

    def render(self, depsgraph):
        width, height = self.resolution_x, self.resolution_y
        region = _region(depsgraph.scene.render, width, height)
        # Blender calls render() once per view layer, each with its own depsgraph. The result
        # is the Render Region's size, at (0, 0).
        result = self.begin_result(0, 0, region[2], region[3], layer=depsgraph.view_layer.name)
        try:
            with tempfile.TemporaryDirectory(prefix="dacrt-blender-") as work:
                frame = self._render(depsgraph, work, width, height)
                if frame and frame.pixels is not None:
                    _show_pixels(result.layers[0], frame.pixels, region)
                    _show_aovs(result.layers[0], frame.aovs, region)
                self._keep(work)
        except (cli.RenderError, OSError, RuntimeError, ValueError) as error:
            self._show_error(str(error))
        finally:
            self.end_result(result)

    def _render(self, depsgraph, work, width, height):
        scene = depsgraph.scene
        settings = scene.dacrt
        camera = self.camera_override or scene.camera
        if camera is None:
            raise cli.RenderError("the scene has no camera")
        glb, exr = os.path.join(work, "scene.glb"), os.path.join(work, "render.exr")
        self.update_stats("dacrt", "exporting the scene to glTF")
        warnings = export.export_scene(glb, scene, depsgraph.view_layer, settings.light_units)
        warnings += _add_lights(depsgraph, camera, glb)
        index = export.camera_index(export.read_glb_json(glb), camera.name)
        if index is None:
            raise cli.RenderError(f"camera {camera.name} is not in the exported scene "
                                  "(disabled for rendering?)")
        environment = None
        if settings.use_world:
            self.update_stats("dacrt", "baking the world")
            environment, lost = world.environment(scene.world, work, settings.environment_width,
                                                  settings.environment_samples)
            warnings += lost
        else:
            warnings.append("World is off in dacrt's settings: dacrt's default environment "
                            "is used")
        aperture, focus, lost = _depth_of_field(scene, camera)
        warnings += lost
        if self._cancelled():
            return None
        aovs = tuple(aov for switch, aov, *_ in PASSES if getattr(depsgraph.view_layer, switch))
        job = cli.RenderJob(width=width, height=height, spp=settings.spp, seed=settings.seed,
                            camera=index, backend=settings.backend,
                            integrator=settings.integrator, max_depth=settings.max_depth,
                            threads=settings.threads, environment=environment,
                            time_limit=settings.time_limit,
                            adaptive=settings.adaptive_threshold if settings.use_adaptive else 0,
                            adaptive_min=settings.adaptive_min, aperture=aperture,
                            focus_distance=focus, aovs=aovs)
        self._write_command(work, job)
        for warning in warnings:
            self._show_warning(warning)
        frame = cli.render_glb(cli.find_executable(_preferred_executable()), glb, exr, job,
                               self._show_progress, self._cancelled)
        for warning in frame.warnings:
            self._show_warning("dacrt: " + warning)
        self.update_stats("dacrt", "cancelled: the samples done so far" if frame.cancelled
                          else "done")
        return frame

    @staticmethod
    def _write_command(work, job):
        """The CLI's options, one a line, in work/options.txt (kept with DACRT_BLENDER_KEEP)."""
        with open(os.path.join(work, "options.txt"), "w", encoding="utf-8") as file:
            file.write("\n".join(job.arguments()) + "\n")

    # Blender's own calls go through these Python methods: an instance finds RNA's functions
    # (test_break, report, ...) before anything a subclass or a test defines under their names.
    def _cancelled(self):
        return self.test_break()

    def _show_progress(self, fraction, text):
        self.update_progress(fraction)
        self.update_stats("dacrt", text)

    def _show_error(self, message):
        self.report({'ERROR'}, message)

    def _show_warning(self, message):
        print("dacrt: warning: " + message, flush=True)
        self.report({'WARNING'}, message)

    @staticmethod
    def _keep(work):
        keep = os.environ.get(KEEP_ENV)
        if not keep:
            return
        os.makedirs(keep, exist_ok=True)
        for name in ("scene.glb", "render.exr", "environment.exr", "options.txt"):
            if os.path.exists(os.path.join(work, name)):
                shutil.copyfile(os.path.join(work, name), os.path.join(keep, name))


def _region(render, width, height):
    """The pixels Blender asks for, (x, y, width, height) from the bottom-left: the Render
    Region's, rounded as Blender's pipeline does (float products truncated), or the frame."""
    if not render.use_border:
        return 0, 0, width, height
    x0, x1 = (int(np.float32(b) * np.float32(width))
              for b in (render.border_min_x, render.border_max_x))
    y0, y1 = (int(np.float32(b) * np.float32(height))
              for b in (render.border_min_y, render.border_max_y))
    return x0, y0, x1 - x0, y1 - y0


def _show_pixels(render_layer, pixels, region):
    """H×W×3 rows top-down (the whole frame) into the layer's Combined pass: the region's
    pixels as RGBA, rows bottom-up as Blender's."""
    x, y, width, height = region
    rgba = np.ones((height, width, 4), dtype=np.float32)
    rgba[..., :3] = pixels[::-1][y:y + height, x:x + width]
    rect = render_layer.passes["Combined"].rect
    if len(rect) != width * height:
        raise cli.RenderError(f"the render result has {len(rect)} pixels, not the "
                              f"{width}×{height} of the render region")
    rect.foreach_set(rgba.reshape(-1, 4))  # no per-value conversion: 1080p in 0.3 s, not 1.5


def _add_lights(depsgraph, camera, glb):
    """Adds the area lights to the .glb; the warnings of every light's losses."""
    from bpy_extras.object_utils import world_to_camera_view
    scene = depsgraph.scene
    warnings, areas = [], []
    for instance in depsgraph.object_instances:
        obj = instance.object
        if obj.type != 'LIGHT':
            continue
        light, matrix = obj.data, instance.matrix_world.copy()
        in_view = False
        if light.type == 'AREA':
            for x, y in lights.area_polygon(light)[::max(1, lights.DISK_SIDES // 8)]:
                point = world_to_camera_view(scene, camera, matrix @ _vector((x, y, 0.0)))
                in_view = in_view or (0 <= point.x <= 1 and 0 <= point.y <= 1 and point.z > 0)
            if not getattr(light.cycles, "is_portal", False):
                areas.append((obj.name, light, [list(row) for row in matrix]))
        warnings += lights.light_warnings(obj.name, light, in_view)
    lights.add_area_lights(glb, areas)
    return warnings


def _vector(values):
    from mathutils import Vector
    return Vector(values)


def _depth_of_field(scene, camera):
    """(--aperture, --focus-distance, warnings): the lens diameter in scene units (0 without
    depth of field) and the focus distance along the view axis, as Cycles takes them."""
    data = camera.data
    dof = data.dof
    if not dof.use_dof:
        return 0.0, 0.0, []
    if data.type != 'PERSP':
        return 0.0, 0.0, [f"camera {camera.name}: depth of field of a {data.type.lower()} "
                          "camera is lost"]
    warnings = []
    units = scene.unit_settings
    metres = units.scale_length if units.system != 'NONE' and units.scale_length > 0 else 1.0
    aperture = data.lens * 1e-3 / max(dof.aperture_fstop, 1e-5) / metres
    if dof.aperture_blades >= 3 or abs(dof.aperture_ratio - 1) > 1e-6:
        warnings.append(f"camera {camera.name}: the aperture's blades and ratio are lost "
                        "(dacrt's lens is a disk)")
    if dof.focus_object is not None:
        world = camera.matrix_world
        target = dof.focus_object.matrix_world.translation
        if dof.focus_subtarget and dof.focus_object.type == 'ARMATURE':
            bone = dof.focus_object.pose.bones.get(dof.focus_subtarget)
            if bone:
                target = dof.focus_object.matrix_world @ bone.head
        view = -(world.to_3x3() @ _vector((0.0, 0.0, 1.0))).normalized()
        focus = max((target - world.translation).dot(view), 1e-6)
    else:
        focus = dof.focus_distance
    return aperture, focus, warnings


def _show_aovs(render_layer, aovs, region):
    """dacrt's AOVs (glTF's Y-up axes) into Blender's passes (Z-up), where the layer has them:
    normal and position (x, y, z) → (x, -z, y); depth and albedo as they are."""
    x, y, width, height = region
    for _, aov, name, channels, _, _ in PASSES:
        render_pass = render_layer.passes.get(name)
        if render_pass is None or aov not in aovs:
            continue
        values = aovs[aov][::-1][y:y + height, x:x + width].astype(np.float32)
        if aov in ("normal", "position"):
            values = np.stack([values[..., 0], -values[..., 2], values[..., 1]], axis=-1)
        render_pass.rect.foreach_set(np.ascontiguousarray(values).reshape(-1, channels))


def _preferred_executable():
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences.executable if addon else ""
