"""Renders Blender's default scene through the dacrt add-on to a PNG (docs/images' picture).

blender -b --factory-startup -noaudio --python tools/blender-default-scene.py -- DACRT OUT.png
Blender's PNG goes through the scene's view transform (Filmic in the default scene).
"""

import os
import sys

import addon_utils
import bpy

cli, out = sys.argv[sys.argv.index("--") + 1:]
os.environ["DACRT_CLI"] = os.path.abspath(cli)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
addon_utils.enable("dacrt_render", default_set=True, handle_error=None)
scene = bpy.context.scene
scene.render.engine = "DACRT"
scene.render.resolution_x, scene.render.resolution_y = 480, 270
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGB"
scene.dacrt.spp = 256
scene.render.filepath = os.path.abspath(out)
bpy.ops.render.render(write_still=True)
