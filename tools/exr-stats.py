# Image statistics of float EXRs, read through Blender (no Python EXR binding needed): the means
# per channel and the noise between two renders of different seeds. Used by tools/peer-compare.sh;
# an optional peer tool, never a test dependency.
#
#   blender -b -noaudio --python tools/exr-stats.py -- A.exr [B.exr]
#       prints `mean R G B` (of A, or of A and B averaged) and, with B, `rmse X` and
#       `noise X` = RMSE(A, B) / sqrt 2, over every channel of every pixel (linear RGB)
#   blender -b -noaudio --python tools/exr-stats.py -- --crop X0 Y0 X1 Y1 A.exr
#       prints `mean R G B` over the window [X0, X1) × [Y0, Y1) of A, in fractions of its width
#       and height from the top left (e.g. 0.35 0.35 0.65 0.65: the middle tenth)
#   blender -b -noaudio --python tools/exr-stats.py -- --table MANIFEST
#       MANIFEST: one line per renderer, tab-separated: label, spp, render seconds of the two
#       seeds, whole-process seconds of the two seeds, the two EXRs. Prints a Markdown table,
#       each mean's ratio to the first line's.
import math
import os
import sys

import bpy


def fail(message):
    print("exr-stats: " + message, file=sys.stderr)
    sys.stdout.flush()
    os._exit(1)


try:
    import numpy
except ImportError:
    numpy = None


def read_rgb(path):
    if not os.path.isfile(path):
        fail(path + ": no such file")
    try:
        img = bpy.data.images.load(path, check_existing=False)
    except RuntimeError as e:
        fail(path + ": " + str(e))
    img.colorspace_settings.name = "Non-Color"  # the file's values as they are
    w, h = img.size
    if w == 0 or h == 0 or not img.is_float:
        fail(path + ": not a float image")
    px = numpy.empty(w * h * 4, dtype=numpy.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[:, :, :3].astype(numpy.float64)


def pair_stats(a_path, b_path):
    a = read_rgb(a_path)
    if b_path is None:
        return a.reshape(-1, 3).mean(axis=0), None, None
    b = read_rgb(b_path)
    if a.shape != b.shape:
        fail("%s is %dx%d, %s %dx%d" % (a_path, a.shape[1], a.shape[0], b_path, b.shape[1],
                                         b.shape[0]))
    rmse = math.sqrt(float(numpy.mean((a - b) ** 2)))
    return ((a + b) * 0.5).reshape(-1, 3).mean(axis=0), rmse, rmse / math.sqrt(2.0)


def table(manifest):
    rows = []
    with open(manifest) as f:
        for line in f:
            if line.strip():
                label, spp, ra, rb, wa, wb, ea, eb = line.rstrip("\n").split("\t")
                mean, _, noise = pair_stats(ea, eb)
                rows.append((label, spp, (float(ra) + float(rb)) / 2, (float(wa) + float(wb)) / 2,
                             noise, mean))
    first = rows[0]
    # The figure's reference: Cycles' row when there is one (the peer), else the first.
    ref = next((r for r in rows if r[0].startswith("Cycles")), first)
    print("| renderer | spp | render s | whole process s | noise | mean R | mean G | mean B "
          "| mean / %s's (R, G, B, all) | noise² × s / %s's |" % (first[0], ref[0]))
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, spp, render_s, whole_s, noise, mean in rows:
        ratio = mean / first[5]
        all_ratio = mean.sum() / first[5].sum()
        cost = noise * noise * render_s / (ref[4] * ref[4] * ref[2])
        print("| %s | %s | %.2f | %.2f | %.5f | %.5f | %.5f | %.5f | %.4f, %.4f, %.4f, %.4f | %.2f |"
              % (label, spp, render_s, whole_s, noise, *mean, *ratio, all_ratio, cost))
    print()
    print("render s: the render alone (dacrt: seconds_with_build, the backend's build included; "
          "Cycles: bpy.ops.render.render, sync and BVH included), the mean of the two seeds "
          "(each seed's median over the rounds). "
          "noise: RMSE between the two seeds / sqrt 2, linear RGB. noise² × s: the cost of a "
          "given noise level if noise² falls as 1/time (lower is better); over Cycles': the "
          "fraction of Cycles' time a renderer needs for Cycles' noise.")


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if numpy is None:
        fail("Blender's Python has no numpy: apt-get install python3-numpy")
    if len(argv) == 2 and argv[0] == "--table":
        table(argv[1])
    elif len(argv) == 6 and argv[0] == "--crop":
        x0, y0, x1, y1 = (float(v) for v in argv[1:5])
        a = read_rgb(argv[5])[::-1]  # Blender's rows run bottom to top
        h, w = a.shape[0], a.shape[1]
        window = a[int(y0 * h):max(int(y1 * h), int(y0 * h) + 1),
                   int(x0 * w):max(int(x1 * w), int(x0 * w) + 1)]
        print("mean %.6f %.6f %.6f" % tuple(window.reshape(-1, 3).mean(axis=0)))
    elif len(argv) in (1, 2) and not argv[0].startswith("-"):
        mean, rmse, noise = pair_stats(argv[0], argv[1] if len(argv) == 2 else None)
        print("mean %.6f %.6f %.6f" % tuple(mean))
        if rmse is not None:
            print("rmse %.6f" % rmse)
            print("noise %.6f" % noise)
    else:
        fail("usage: blender -b -noaudio --python tools/exr-stats.py -- A.exr [B.exr] | "
             "--crop X0 Y0 X1 Y1 A.exr | --table MANIFEST")
    sys.stdout.flush()


try:
    main()
except Exception as e:
    import traceback
    traceback.print_exc()
    fail(str(e))
