"""The dacrt render engine: export the scene as glTF, render it with dacrt, show the image."""

import os
import shutil
import tempfile

import bpy
import numpy as np

from . import cli, export

# Set to a directory, the engine copies there the .glb it rendered and the CLI's EXR
# (scene.glb, render.exr): to render the same file from the command line, or compare with it.
KEEP_ENV = "DACRT_BLENDER_KEEP"


class DacrtRenderEngine(bpy.types.RenderEngine):
    bl_idname = "DACRT"
    bl_label = "dacrt"
    bl_use_preview = False           # material previews: each would be a whole export and render
    bl_use_eevee_viewport = True     # the viewport's Material Preview and Rendered modes
    bl_use_shading_nodes_custom = False  # Blender's shader nodes, which the exporter reads

    def render(self, depsgraph):
        width, height = self.resolution_x, self.resolution_y
        region = _region(depsgraph.scene.render, width, height)
        # Blender calls render() once per view layer, each with its own depsgraph. The result
        # is the Render Region's size, at (0, 0).
        result = self.begin_result(0, 0, region[2], region[3], layer=depsgraph.view_layer.name)
        try:
            with tempfile.TemporaryDirectory(prefix="dacrt-blender-") as work:
                frame = self._render(depsgraph, os.path.join(work, "scene.glb"),
                                     os.path.join(work, "render.exr"), width, height)
                if frame and frame.pixels is not None:
                    _show_pixels(result.layers[0], frame.pixels, region)
                self._keep(work)
        except (cli.RenderError, OSError, RuntimeError, ValueError) as error:
            self._show_error(str(error))
        finally:
            self.end_result(result)

    def _render(self, depsgraph, glb, exr, width, height):
        scene = depsgraph.scene
        settings = scene.dacrt
        camera = self.camera_override or scene.camera
        if camera is None:
            raise cli.RenderError("the scene has no camera")
        self.update_stats("dacrt", "exporting the scene to glTF")
        export.export_scene(glb, scene, depsgraph.view_layer, settings.light_units)
        index = export.camera_index(export.read_glb_json(glb), camera.name)
        if index is None:
            raise cli.RenderError(f"camera {camera.name} is not in the exported scene "
                                  "(disabled for rendering?)")
        if self._cancelled():
            return None
        job = cli.RenderJob(width=width, height=height, spp=settings.spp, seed=settings.seed,
                            camera=index, backend=settings.backend,
                            integrator=settings.integrator, max_depth=settings.max_depth,
                            threads=settings.threads,
                            environment=export.world_color(scene.world) if settings.use_world
                            else None)
        frame = cli.render_glb(cli.find_executable(_preferred_executable()), glb, exr, job,
                               self._show_progress, self._cancelled)
        self.update_stats("dacrt", "cancelled: the samples done so far" if frame.cancelled
                          else "done")
        return frame

    # Blender's own calls go through these Python methods: an instance finds RNA's functions
    # (test_break, report, ...) before anything a subclass or a test defines under their names.
    def _cancelled(self):
        return self.test_break()

    def _show_progress(self, fraction, text):
        self.update_progress(fraction)
        self.update_stats("dacrt", text)

    def _show_error(self, message):
        self.report({'ERROR'}, message)

    @staticmethod
    def _keep(work):
        keep = os.environ.get(KEEP_ENV)
        if not keep:
            return
        os.makedirs(keep, exist_ok=True)
        for name in ("scene.glb", "render.exr"):
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


def _preferred_executable():
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences.executable if addon else ""
