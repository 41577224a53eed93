"""Blender's world as dacrt's environment (--environment).

A world of one colour (a Background shader with nothing linked, or no nodes) is passed as
R,G,B: the colour × strength. Any other world (an image, a sky texture, any node tree) is baked
by Cycles into an equirectangular EXR, in a Blender process of its own (the render running this
cannot start another render): the world alone, seen by a panoramic equirectangular camera at the
origin looking along Blender's +Y with +Z up, nothing else visible. That is dacrt's map: +Y up
and the image's centre towards -Z in glTF's axes, which are Blender's +Z and +Y after the
exporter's Z-up to Y-up conversion; columns run from the centre towards +X in both.
"""

import os
import subprocess

import bpy

_BAKE_SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bake_world.py")


def uniform_color(world):
    """The world as one radiance (R, G, B), or None when it is not one colour: the Background
    shader's colour × strength when no node feeds either, else the viewport colour without
    nodes."""
    if not world.use_nodes:
        return tuple(world.color)
    output = _output(world)
    surface = output.inputs["Surface"] if output else None
    if surface is None or not surface.is_linked:
        return (0.0, 0.0, 0.0)  # an output with nothing plugged in: Cycles' world is black
    background = surface.links[0].from_node
    if background.type != 'BACKGROUND':
        return None
    color, strength = background.inputs["Color"], background.inputs["Strength"]
    if color.is_linked or strength.is_linked:  # a sky texture, an HDRI: not one colour
        return None
    return tuple(c * strength.default_value for c in color.default_value[:3])


def _output(world):
    return next((node for node in world.node_tree.nodes
                 if node.type == 'OUTPUT_WORLD' and node.is_active_output), None)


def environment(world, work, width, samples):
    """(--environment's value or None for dacrt's default, warnings). A textured world is baked
    to work/environment.exr, width × width/2 pixels, `samples` Cycles samples per pixel."""
    if world is None:  # Cycles renders a scene without a world on black
        return "0.0,0.0,0.0", []
    warnings = []
    if world.use_nodes:
        output = _output(world)
        if output and output.inputs["Volume"].is_linked:
            warnings.append(f"world {world.name}: its volume is ignored")
    color = uniform_color(world)
    if color is not None:
        return ",".join(repr(float(c)) for c in color), warnings
    for image in _images(world):
        if image.is_dirty or (image.source == 'GENERATED' and not image.packed_file):
            warnings.append(f"world {world.name}: image {image.name} is not saved: the bake "
                            "sees its file (save or pack it)")
    path = os.path.join(work, "environment.exr")
    bake(world, work, path, width, samples)
    return path, warnings


def bake(world, work, path, width, samples):
    """Renders world to the equirectangular EXR path with Cycles, in another Blender process."""
    library = os.path.join(work, "world.blend")
    bpy.data.libraries.write(library, {world}, path_remap='ABSOLUTE', fake_user=True)
    command = [bpy.app.binary_path, "-b", "--factory-startup", "-noaudio", "--python-exit-code",
               "1", "--python", _BAKE_SCRIPT, "--", library, world.name, path, str(width),
               str(max(1, width // 2)), str(samples)]
    done = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, text=True)
    if done.returncode != 0 or not os.path.exists(path):
        lines = [line for line in (done.stderr + done.stdout).splitlines() if line.strip()]
        raise RuntimeError(f"baking world {world.name} failed: "
                           f"{lines[-1] if lines else f'exit code {done.returncode}'}")


def _images(world):
    images = []
    trees = [world.node_tree] if world.node_tree else []
    while trees:
        for node in trees.pop().nodes:
            if getattr(node, "image", None) is not None:
                images.append(node.image)
            if node.type == 'GROUP' and node.node_tree:
                trees.append(node.node_tree)
    return images
