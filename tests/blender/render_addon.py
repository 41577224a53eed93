"""The dacrt add-on in headless Blender: its render of the default scene equals the CLI's.

Run: blender -b --factory-startup -noaudio --python-exit-code 1 \
         --python tests/blender/render_addon.py -- DACRT_CLI WORK_DIR

Registers the add-on from the source tree, renders the default scene (plus a second camera, so
the active one is not the file's first) at 128×96 × 50 % and 8 spp, and checks:
- the render result, written as a float EXR, equals bit for bit the CLI's render of the .glb
  the add-on exported, at the camera `dacrt info` names after the active camera and with the
  default world's grey as --environment;
- progress reached Blender (update_progress up to 1);
- a Render Region shows the same pixels where it is;
- a render cancelled (the engine's test_break turning true) returns promptly, shows the samples
  done, and leaves no temporary files; a CLI that cannot run is reported as an error.
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import addon_utils
import bpy
import numpy as np

WIDTH, HEIGHT, SPP, SEED = 64, 48, 8, 7
CANCEL_SPP = 1 << 17  # ~45 s on two cores: a cancel that is ignored shows
CANCEL_AFTER = 1.0    # seconds of rendering before test_break turns true
PROMPT = 30.0         # seconds a cancel may take, far above the ~0.1 s it does take

failures = []


def check(condition, message):
    print(("ok: " if condition else "FAIL: ") + message, flush=True)
    if not condition:
        failures.append(message)


def load_pixels(path):
    """RGBA float32 rows bottom-up, as Blender reads the file."""
    image = bpy.data.images.load(path, check_existing=False)
    width, height = image.size
    pixels = np.empty(width * height * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)


def camera_index_from_info(cli, glb, name):
    """The --camera index of the camera named name, from `dacrt info` (not the add-on's code)."""
    info = subprocess.run([cli, "info", glb], check=True, capture_output=True, text=True).stdout
    match = re.search(r"^\s*camera (\d+) " + re.escape(name) + ":", info, re.MULTILINE)
    return int(match.group(1)) if match else None


def render(scene, path):
    scene.render.filepath = path
    start = time.monotonic()
    bpy.ops.render.render(write_still=True)
    return time.monotonic() - start


def main(cli, work):
    shutil.rmtree(work, ignore_errors=True)  # a previous run's files would count as left over
    os.makedirs(work)
    temp_root = os.path.join(work, "tmp")
    os.makedirs(temp_root, exist_ok=True)
    tempfile.tempdir = temp_root  # the add-on's temporary files land here, to be counted
    keep = os.path.join(work, "kept")
    os.environ["DACRT_CLI"] = cli
    os.environ["DACRT_BLENDER_KEEP"] = keep
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "blender"))
    addon_utils.enable("dacrt_render", default_set=True, handle_error=None)
    from dacrt_render.engine import DacrtRenderEngine

    scene = bpy.context.scene
    # A second camera, exported before the active one: rendering the file's first camera fails.
    decoy_data = bpy.data.cameras.new("Decoy")
    decoy = bpy.data.objects.new("Decoy", decoy_data)
    decoy.location = (0.0, -12.0, 1.0)
    decoy.rotation_euler = (1.5, 0.0, 0.0)
    scene.collection.objects.link(decoy)
    check(scene.camera.name == "Camera", "the default scene's camera is active")

    scene.render.engine = "DACRT"
    scene.render.resolution_x, scene.render.resolution_y = 2 * WIDTH, 2 * HEIGHT
    scene.render.resolution_percentage = 50
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth, settings.exr_codec = "OPEN_EXR", "32", "ZIP"
    settings.color_mode = "RGB"
    scene.dacrt.spp, scene.dacrt.seed = SPP, SEED

    # The engine's own methods around RNA's update_progress, report and test_break (which an
    # instance finds before any Python attribute): recorded, then passed on.
    progress, errors = [], []
    show_progress, show_error = DacrtRenderEngine._show_progress, DacrtRenderEngine._show_error
    DacrtRenderEngine._show_progress = lambda self, fraction, text: (
        progress.append(fraction), show_progress(self, fraction, text))
    DacrtRenderEngine._show_error = lambda self, message: (
        errors.append(message), show_error(self, message))

    ours = os.path.join(work, "addon.exr")
    render(scene, ours)
    check(not errors, f"the render reports no error {errors}")
    glb = os.path.join(keep, "scene.glb")
    index = camera_index_from_info(cli, glb, "Camera")
    check(index is not None and index > 0,
          f"the active camera is not the file's first (dacrt info: camera {index})")
    reference = os.path.join(work, "cli.exr")
    # The default world: a Background shader of grey 0.050876 at strength 1, which the add-on
    # passes as --environment (glTF has no world).
    background = scene.world.node_tree.nodes["Background"].inputs
    sky = [c * background["Strength"].default_value for c in background["Color"].default_value[:3]]
    check(all(0.05 < c < 0.052 for c in sky), f"the default world is grey 0.05 ({sky})")
    subprocess.run([cli, "render", glb, "--width", str(WIDTH), "--height", str(HEIGHT), "--spp",
                    str(SPP), "--seed", str(SEED), "--camera", str(index), "--environment",
                    ",".join(map(repr, sky)), "-o", reference, "--quiet"], check=True)
    a, b = load_pixels(ours), load_pixels(reference)
    check(a.shape == b.shape == (HEIGHT, WIDTH, 4), f"both {WIDTH}×{HEIGHT} ({a.shape}, {b.shape})")
    if a.shape == b.shape:
        difference = float(np.max(np.abs(a[..., :3] - b[..., :3])))
        check(np.array_equal(a[..., :3], b[..., :3]),
              f"the add-on's pixels equal the CLI's bit for bit (max difference {difference:g})")
        check(float(np.ptp(b[..., :3])) > 0, "the image is not blank")
    check(progress and progress[-1] == 1.0 and any(0 < p < 1 for p in progress),
          f"progress reached Blender: {progress}")

    # A Render Region, not cropped: Blender puts the region's pixels (alpha 1) into an otherwise
    # empty frame (alpha 0); they are the reference's pixels there.
    scene.render.use_border, scene.render.use_crop_to_border = True, False
    scene.render.border_min_x, scene.render.border_max_x = 0.3, 0.8
    scene.render.border_min_y, scene.render.border_max_y = 0.2, 0.65
    settings.color_mode = "RGBA"
    render(scene, os.path.join(work, "region.exr"))
    region = load_pixels(os.path.join(work, "region.exr"))
    inside = region[..., 3] == 1
    rows, columns = np.nonzero(inside)
    check(inside.sum() == (np.ptp(rows) + 1) * (np.ptp(columns) + 1) and
          30 * 20 < inside.sum() < 33 * 23, f"the region is a rectangle of about 32×22 pixels "
          f"({np.ptp(columns) + 1}×{np.ptp(rows) + 1}, {inside.sum()} pixels)")
    check(np.array_equal(region[inside][:, :3], b[inside][:, :3]),
          "the region's pixels are the CLI's")
    scene.render.use_border = False
    settings.color_mode = "RGB"

    # Cancel: test_break turns true CANCEL_AFTER seconds into the render.
    del os.environ["DACRT_BLENDER_KEEP"]
    scene.dacrt.spp = CANCEL_SPP
    first_call = []
    broken_at = []

    def cancelled(self):
        now = time.monotonic()
        first_call[:1] = first_call[:1] or [now]
        if now - first_call[0] < CANCEL_AFTER:
            return False
        broken_at[:1] = broken_at[:1] or [now]
        return True

    engine_cancelled = DacrtRenderEngine._cancelled
    DacrtRenderEngine._cancelled = cancelled
    cancelled = os.path.join(work, "cancelled.exr")
    render(scene, cancelled)
    after_break = time.monotonic() - broken_at[0] if broken_at else float("inf")
    check(after_break < PROMPT, f"a cancelled render returns {after_break:.2f} s after the break")
    check(float(np.max(load_pixels(cancelled)[..., :3])) > 0,
          "a cancelled render shows the samples done")
    check(not os.listdir(temp_root), f"no temporary files left: {os.listdir(temp_root)}")

    # A CLI that cannot run: the add-on reports it (and the operator fails with the report).
    DacrtRenderEngine._cancelled = engine_cancelled
    os.environ["DACRT_CLI"] = os.path.join(work, "no-such-dacrt")
    scene.dacrt.spp = SPP
    try:
        render(scene, os.path.join(work, "failed.exr"))
    except RuntimeError as error:
        print(f"the render failed as it should: {error}")
    check(len(errors) == 1 and "cannot run" in errors[0], f"a missing CLI is reported: {errors}")
    check(not os.listdir(temp_root), "no temporary files left after the failure")


if __name__ == "__main__":
    arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(arguments) != 2:
        sys.exit("usage: blender -b --python render_addon.py -- DACRT_CLI WORK_DIR")
    main(os.path.abspath(arguments[0]), os.path.abspath(arguments[1]))
    if failures:
        sys.exit(f"{len(failures)} check(s) failed")
    print("all checks passed", flush=True)
    # Blender ends with exit code 1 after a render that reported an error (the one above, on
    # purpose): the script's own verdict is the exit code.
    sys.exit(0)
