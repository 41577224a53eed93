"""Bakes a world to an equirectangular EXR with Cycles (run by world.bake in its own Blender).

blender -b --factory-startup -noaudio --python bake_world.py -- LIBRARY.blend WORLD OUT.exr W H SPP

The world is linked from LIBRARY; a panoramic equirectangular camera at the origin looks along
+Y with +Z up (dacrt's image centre, -Z in glTF's Y-up axes); nothing else is in the scene. Box
filter one pixel wide: each pixel is the mean over its own solid angle's directions.
"""

import math
import sys

import bpy


def main(library, name, path, width, height, samples):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    with bpy.data.libraries.load(library, link=False) as (source, target):
        target.worlds = [name]
    world = target.worlds[0]
    if world is None:
        sys.exit(f"no world {name} in {library}")
    scene = bpy.context.scene
    scene.world = world
    scene.render.engine = 'CYCLES'
    cycles = scene.cycles
    cycles.device = 'CPU'
    cycles.samples = samples
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.pixel_filter_type = 'BOX'
    cycles.filter_width = 1.0
    camera_data = bpy.data.cameras.new("bake")
    camera_data.type = 'PANO'
    camera_data.cycles.panorama_type = 'EQUIRECTANGULAR'
    camera = bpy.data.objects.new("bake", camera_data)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)  # looks along +Y, up +Z
    scene.collection.objects.link(camera)
    scene.camera = camera
    render = scene.render
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    render.film_transparent = False
    settings = render.image_settings
    settings.file_format, settings.color_depth, settings.exr_codec = 'OPEN_EXR', '32', 'ZIP'
    settings.color_mode = 'RGB'
    render.filepath = path
    render.use_file_extension = False
    bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    arguments = sys.argv[sys.argv.index("--") + 1:]
    main(arguments[0], arguments[1], arguments[2], int(arguments[3]), int(arguments[4]),
         int(arguments[5]))
