"""A screenshot of Blender's window with the default scene rendered by the dacrt add-on: the
render in an Image Editor beside the Render Properties, where dacrt's settings are (README).

xvfb-run -s "-screen 0 1600x900x24" blender --factory-startup -noaudio \
    --python tools/blender-screenshot.py -- DACRT OUT.png
Needs a display (Xvfb will do, with Mesa's software OpenGL).
"""

import os
import sys

import addon_utils
import bpy

cli, out = sys.argv[sys.argv.index("--") + 1:]
os.environ["DACRT_CLI"] = os.path.abspath(cli)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
addon_utils.enable("dacrt_render", default_set=True, handle_error=None)
bpy.context.preferences.view.show_splash = False
scene = bpy.context.scene
scene.render.engine = "DACRT"
scene.render.resolution_x, scene.render.resolution_y = 640, 360
scene.render.resolution_percentage = 100
scene.dacrt.spp = 128


def areas(kind):
    return [a for w in bpy.context.window_manager.windows for a in w.screen.areas if a.type == kind]


def render_and_show():
    bpy.ops.render.render()
    viewport = max(areas("VIEW_3D"), key=lambda a: a.width * a.height)
    viewport.type = "IMAGE_EDITOR"
    viewport.spaces.active.image = bpy.data.images["Render Result"]
    for props in areas("PROPERTIES"):
        props.spaces.active.context = "RENDER"
    return None


def shoot():
    window = bpy.context.window_manager.windows[0]
    for area in window.screen.areas:
        area.tag_redraw()
    bpy.ops.wm.redraw_timer(type="DRAW_WIN_SWAP", iterations=2)
    with bpy.context.temp_override(window=window, screen=window.screen,
                                   area=window.screen.areas[0]):
        bpy.ops.screen.screenshot(filepath=os.path.abspath(out))
    bpy.ops.wm.quit_blender()
    return None


bpy.app.timers.register(render_and_show, first_interval=2.0)
bpy.app.timers.register(shoot, first_interval=12.0)
