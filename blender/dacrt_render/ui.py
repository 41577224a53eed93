"""The engine's settings (Render properties), its preference, and the stock panels it uses."""

import bpy

from . import export


class DacrtSettings(bpy.types.PropertyGroup):
    """scene.dacrt: the render options the CLI takes, with its defaults."""
    spp: bpy.props.IntProperty(name="Samples", description="Samples per pixel (--spp)",
                               default=64, min=1, max=1 << 20)
    seed: bpy.props.IntProperty(name="Seed", description="Random seed (--seed)", default=0, min=0)
    backend: bpy.props.EnumProperty(
        name="Backend", description="The ray tracing backend (--backend)", default="dacrt",
        items=(("dacrt", "dacrt", "The wavefront tracer"),
               ("dacrt-naive", "dacrt-naive", "The same BVH traced one ray at a time"),
               ("embree", "Embree", "Intel Embree, when dacrt was built with it"),
               ("brute", "brute", "Every triangle for every ray: the reference, very slow")))
    integrator: bpy.props.EnumProperty(
        name="Integrator", description="What each pixel shows (--integrator)", default="path",
        items=(("path", "Path", "Path tracing: global illumination"),
               ("direct", "Direct", "Direct lighting only"),
               ("ao", "Ambient occlusion", "Ambient occlusion"),
               ("albedo", "Albedo", "The first hit's albedo"),
               ("normal", "Normal", "The first hit's shading normal"),
               ("depth", "Depth", "Distance to the first hit")))
    max_depth: bpy.props.IntProperty(name="Max Depth", description="Scattering events per path "
                                     "(--max-depth)", default=64, min=0, max=1 << 16)
    threads: bpy.props.IntProperty(name="Threads", description="Worker threads; 0: all cores "
                                   "(--threads)", default=0, min=0, max=1024)
    use_world: bpy.props.BoolProperty(
        name="World Colour", default=True,
        description="Light the scene with the world's background colour × strength "
        "(--environment), which glTF does not carry; off, or with a textured world: dacrt's "
        "default (black, or a sky of 1 when nothing emits)")
    light_units: bpy.props.EnumProperty(
        name="Light Units", description="How the glTF exporter converts light strengths",
        items=export.LIGHT_UNITS, default="COMPAT")


class DacrtPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__
    executable: bpy.props.StringProperty(
        name="dacrt executable", subtype='FILE_PATH',
        description="Path of the dacrt program; empty: `dacrt` on PATH. $DACRT_CLI overrides it")

    def draw(self, context):
        self.layout.prop(self, "executable")


class RENDER_PT_dacrt(bpy.types.Panel):
    bl_label = "dacrt"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "render"
    COMPAT_ENGINES = {'DACRT'}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.dacrt
        for name in ("spp", "seed", "integrator", "max_depth", "backend", "threads",
                     "use_world", "light_units"):
            layout.prop(settings, name)


# Stock panels for what the exporter reads but Blender shows only for Eevee: materials (the
# Principled BSDF), light power and colour.
_EEVEE_PANELS = ("EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface",
                 "DATA_PT_EEVEE_light")
# Stock panels marked for every engine that do not apply: render passes dacrt does not fill.
_EXCLUDED = ("VIEWLAYER_PT_filter", "VIEWLAYER_PT_layer_passes")


def stock_panels():
    """Blender's panels to show with dacrt: the engine-neutral ones (those Blender marks with
    BLENDER_RENDER: output, dimensions, colour management, camera, ...) and a few of Eevee's."""
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if engines is None or panel.__name__ in _EXCLUDED:
            continue
        if 'BLENDER_RENDER' in engines or panel.__name__ in _EEVEE_PANELS:
            panels.append(panel)
    return panels
