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
    time_limit: bpy.props.FloatProperty(
        name="Time Limit", description="Stop after the pass that crosses this many seconds; 0: "
        "none (--time-limit)", default=0.0, min=0.0, unit='TIME_ABSOLUTE')
    use_adaptive: bpy.props.BoolProperty(
        name="Adaptive Sampling", default=False,
        description="A pixel stops taking samples once its mean is precise enough (--adaptive)")
    adaptive_threshold: bpy.props.FloatProperty(
        name="Noise Threshold", description="Relative error of a pixel's mean at which it stops "
        "(--adaptive)", default=0.01, min=1e-4, max=0.5, precision=4)
    adaptive_min: bpy.props.IntProperty(
        name="Min Samples", description="Samples every pixel takes before any may stop; 0: "
        "dacrt's default, max(16, samples / 16) (--adaptive-min)", default=0, min=0,
        max=1 << 20)
    use_world: bpy.props.BoolProperty(
        name="World", default=True,
        description="Light the scene with the world, which glTF does not carry (--environment): "
        "one colour as R,G,B; an image, sky or any node tree baked by Cycles to an "
        "equirectangular EXR. Off: dacrt's default (black, or a sky of 1 when nothing emits)")
    environment_width: bpy.props.IntProperty(
        name="World Bake Width", description="Width of the world's equirectangular bake in "
        "pixels (height: half)", default=512, min=8, max=8192)
    environment_samples: bpy.props.IntProperty(
        name="World Bake Samples", description="Cycles samples per pixel of the world's bake",
        default=16, min=1, max=4096)
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
        for name in ("spp", "time_limit", "use_adaptive"):
            layout.prop(settings, name)
        column = layout.column()
        column.active = settings.use_adaptive
        column.prop(settings, "adaptive_threshold")
        column.prop(settings, "adaptive_min")
        for name in ("seed", "integrator", "max_depth", "backend", "threads", "use_world"):
            layout.prop(settings, name)
        column = layout.column()
        column.active = settings.use_world
        column.prop(settings, "environment_width")
        column.prop(settings, "environment_samples")
        layout.prop(settings, "light_units")


class VIEWLAYER_PT_dacrt_passes(bpy.types.Panel):
    """The passes dacrt fills from its AOVs."""
    bl_label = "Passes"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "view_layer"
    COMPAT_ENGINES = {'DACRT'}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        view_layer = context.view_layer
        column = layout.column(heading="Data", align=True)
        column.prop(view_layer, "use_pass_combined")
        column.prop(view_layer, "use_pass_z")
        column.prop(view_layer, "use_pass_normal")
        column.prop(view_layer, "use_pass_position")
        column.prop(view_layer, "use_pass_diffuse_color", text="Diffuse Color (albedo)")


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
