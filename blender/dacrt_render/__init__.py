"""dacrt as a Blender render engine.

The engine exports the scene with Blender's glTF exporter, renders the file with dacrt (today
the command-line program; see cli.py for switching to the Python module) and loads the image
into the render result. Install by zipping this folder (Preferences > Add-ons > Install) or by
linking it into Blender's addons directory; see docs/usage.md, "Blender".
"""

bl_info = {
    "name": "dacrt",
    "author": "dacrt",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > dacrt",
    "description": "Renders with the dacrt path tracer, through a glTF export of the scene",
    "category": "Render",
}

import bpy

from . import engine, ui

_CLASSES = (ui.DacrtSettings, ui.DacrtPreferences, ui.RENDER_PT_dacrt, ui.VIEWLAYER_PT_dacrt_passes,
            engine.DacrtRenderEngine)


def register():
    for cls in _CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.dacrt = bpy.props.PointerProperty(type=ui.DacrtSettings)
    for panel in ui.stock_panels():
        panel.COMPAT_ENGINES.add(engine.DacrtRenderEngine.bl_idname)


def unregister():
    for panel in ui.stock_panels():
        panel.COMPAT_ENGINES.discard(engine.DacrtRenderEngine.bl_idname)
    del bpy.types.Scene.dacrt
    for cls in reversed(_CLASSES):
        bpy.utils.unregister_class(cls)
