"""A dacrt EXR as Blender reads it (docs/usage.md#aovs).

Run by ctest as `python3 exr_layers.py DACRT SCENE WORKDIR`: renders SCENE with every AOV and its
exact sums, then runs itself in `blender -b --factory-startup`, which loads the EXR as a
multilayer image and, through the compositor, checks that every pass is there with the values
of the file's channels, and that a background pixel's depth is 1e10. Exits 77 (skipped) when
blender is not on PATH.
"""

import os
import struct
import subprocess
import sys
import zlib

# Blender's pass → the file's channels it must hold, in order (one channel: a Value socket).
PASSES = {
    "Combined": ["R", "G", "B"],
    "albedo": ["albedo.R", "albedo.G", "albedo.B"],
    "N": ["N.X", "N.Y", "N.Z"],
    "Depth": ["Z"],
    "P": ["P.X", "P.Y", "P.Z"],
    "variance": ["variance.R", "variance.G", "variance.B"],
    "samples": ["samples.X"],
}
BACKGROUND_DEPTH = 1e10


def read_exr(path):
    """The float channels of a single-part scanline EXR (no or ZIP compression), by name: lists
    of floats, rows from the top."""
    b = open(path, "rb").read()
    i, header = 8, {}
    while b[i] != 0:
        fields = []
        for _ in range(2):
            end = b.index(b"\0", i)
            fields.append(b[i:end].decode())
            i = end + 1
        size = struct.unpack_from("<i", b, i)[0]
        header[fields[0]] = b[i + 4 : i + 4 + size]
        i += 4 + size
    i += 1
    channels, j = [], 0
    chlist = header["channels"]
    while chlist[j] != 0:
        end = chlist.index(b"\0", j)
        channels.append((chlist[j:end].decode(), struct.unpack_from("<i", chlist, end + 1)[0]))
        j = end + 17
    x0, y0, x1, y1 = struct.unpack("<4i", header["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    compression = header["compression"][0]
    assert compression in (0, 3), "compression %d" % compression
    lines = 16 if compression == 3 else 1
    chunks = (height + lines - 1) // lines
    offsets = struct.unpack_from("<%dQ" % chunks, b, i)
    out = {name: [] for name, _ in channels}
    for offset in offsets:
        y, size = struct.unpack_from("<2i", b, offset)
        data = b[offset + 8 : offset + 8 + size]
        rows = min(lines, y1 + 1 - y)
        raw = width * rows * sum(2 if t == 1 else 4 for _, t in channels)
        if size < raw:  # ZIP: deflate, then a predictor over the bytes, then two halves
            t = bytearray(zlib.decompress(data))
            for k in range(1, len(t)):
                t[k] = (t[k - 1] + t[k] - 128) & 0xFF
            half = (len(t) + 1) // 2
            data = bytearray(len(t))
            data[0::2], data[1::2] = t[:half], t[half:]
        at = 0
        for _ in range(rows):
            for name, t in channels:
                n = width * (2 if t == 1 else 4)
                if t == 2:
                    out[name] += struct.unpack_from("<%df" % width, data, at)
                at += n
    return width, height, {k: v for k, v in out.items() if v}


def drive(dacrt, scene, work):
    import shutil

    blender = shutil.which("blender")
    if not blender:
        print("blender is not on PATH: skipped")
        return 77
    os.makedirs(work, exist_ok=True)
    exr = os.path.join(work, "every-aov.exr")
    subprocess.run([dacrt, "render", scene, "--width", "24", "--height", "16", "--spp", "2",
                    "--quiet", "--look-from", "0.25,1,3.5", "--keep-sums", "-o", exr,
                    "--aov", "albedo,normal,depth,position,variance,samples"], check=True)
    r = subprocess.run([blender, "-b", "--factory-startup", "--python-exit-code", "1",
                        "--python", os.path.abspath(__file__), "--", exr, work],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = [l for l in r.stdout.splitlines() if l.startswith(("check:", "Error", "Traceback"))
             or "exr_layers" in l]
    print("\n".join(lines) if r.returncode == 0 else r.stdout)
    return 0 if r.returncode == 0 and "check: ok" in r.stdout else 1


def in_blender(exr, work):
    import bpy

    width, height, channels = read_exr(exr)
    image = bpy.data.images.load(exr)
    scene = bpy.context.scene
    scene.use_nodes = True
    tree = scene.node_tree
    tree.nodes.clear()
    node = tree.nodes.new("CompositorNodeImage")
    node.image = image
    assert image.type == "MULTILAYER", image.type
    outputs = {o.name: o for o in node.outputs if o.enabled}
    assert set(outputs) == set(PASSES) | {"Alpha"}, sorted(outputs)
    # Each pass through the compositor into a float EXR: Blender's values of that pass.
    composite = tree.nodes.new("CompositorNodeComposite")
    render = scene.render
    render.engine = "CYCLES"  # renders nothing (no objects, no camera) but runs the compositor
    scene.cycles.samples = 1
    render.resolution_x, render.resolution_y, render.resolution_percentage = width, height, 100
    render.image_settings.file_format = "OPEN_EXR"
    render.image_settings.color_depth = "32"
    render.image_settings.exr_codec = "NONE"
    scene.view_settings.view_transform = "Standard"
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    background = [p for p, z in enumerate(channels["Z"]) if z == BACKGROUND_DEPTH]
    assert background, "no background pixel in the file"
    assert all(z != float("inf") for z in channels["Z"])
    for name, names in PASSES.items():
        socket = outputs[name]
        assert socket.type == ("VALUE" if len(names) == 1 else "RGBA"), (name, socket.type)
        tree.links.new(socket, composite.inputs["Image"])
        bpy.ops.render.render()
        out = os.path.join(work, "pass-%s.exr" % name)
        bpy.data.images["Render Result"].save_render(out, scene=scene)
        _, _, got = read_exr(out)
        for k, channel in enumerate(names):
            want = channels[channel]
            have = got["RGB"[k]]
            # Both files list rows from the top: pixel p is the same pixel in both.
            bad = [p for p in range(width * height) if have[p] != want[p]]
            assert not bad, "%s: %s differs at %d pixels, first %d: %r in Blender, %r in file" % (
                name, channel, len(bad), bad[0], have[bad[0]], want[bad[0]])
        if name == "Depth":
            assert all(got["R"][p] == BACKGROUND_DEPTH for p in background)
        print("check: pass %s: %d channel(s) as in the file" % (name, len(names)))
    print("check: ok (%d background pixels at depth 1e10)" % len(background))


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    try:
        import bpy  # noqa: F401
    except ImportError:
        sys.exit(drive(*args))
    in_blender(*args)
