#!/usr/bin/env python3
"""Every example of README.md and docs/*.md runs as it is written.

Each ```sh block's commands run verbatim in bash, page by page in the order they are written, in a
fresh folder laid out as a checkout: build/dacrt (the built CLI, also `dacrt` on PATH),
build/python (the module), scenes/ and tools/ (the source tree's), and ../shared (the shared
scenes, when the source tree has them beside it; a command that names ../shared is skipped with a
message when they are not there). Each exits 0. Each ```python block of `>>>` lines runs as a
doctest in the same folder, its printed results compared with those written.

A command that cannot run in a test is in NOT_RUN below, with the reason; every other command runs,
so an example added to a page is run (or the test fails until it is listed). A file an example
reads but no example of its page writes (a placeholder such as SCENE.glb, a reference image) is made
first as FIXTURES says. Blocks in other languages are in NOT_RUN_LANGUAGES; an untagged block is a
synopsis or a program's output, and one that holds a command line fails the test (tag it).

Usage: docs_examples.py [PAGE...]   (environment: DACRT_CLI, DACRT_SOURCE_DIR, DACRT_PYTHON_DIR)
Exit 0 when every example ran, 1 otherwise.
"""
import doctest
import json
import os
import pathlib
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

SOURCE = pathlib.Path(os.environ.get("DACRT_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[1]))
CLI = pathlib.Path(os.environ.get("DACRT_CLI", SOURCE / "build" / "dacrt"))
PYTHON_DIR = os.environ.get("DACRT_PYTHON_DIR", "")
SHARED = SOURCE.parent / "shared"

# The commands that are not run, each with its page, the command as written (its lines joined,
# comments dropped, spaces collapsed) and why.
NOT_RUN = {
    ("README.md", "make render"): "installs packages and builds the project (what ctest runs on)",
    ("README.md", "make test"): "installs packages, builds and runs every test, this one too",
    ("README.md", "build/dacrt render scenes/cornell-box.gltf -o cornell.exr --spp 256 --width 1024 "
                  "--height 1024"): "long: 1024 x 1024 pixels at 256 spp (the line before it "
                                    "renders the same scene)",
    ("README.md", 'build/dacrt converge scenes/cornell-box.gltf --config "" --config '
                  '"sampler=independent" --repeats 3'): "long: a 1024 spp reference, then three "
                                                         "repeats of 10 s budgets per configuration",
    ("README.md", "mpirun -np 4 build/dacrt render SCENE.glb --spp 1024 -o SCENE.exr"):
        "four MPI ranks (and as root OpenMPI's own flags, as the text after it says); the mpi "
        "ctests run ranks",
    ("usage.md", "mpirun -np 2 build/dacrt render scene.glb --spp 1024 -o scene.exr"):
        "an MPI launcher (as root OpenMPI's own flags); the mpi ctests run ranks",
    ("usage.md", "mpirun -H a,b,c,d -np 4 --bind-to none build/dacrt render scene.glb --spp 4096 "
                 "-o scene.exr"): "four machines a, b, c and d",
    ("usage.md", "build/dacrt bench ../shared/scenes/stanford/dragon/dragon.glb --rays "
                 "primary,shadow,bounce --count 1048576 --repeat 5 --backends "
                 "dacrt,dacrt-naive,embree"): "long: a benchmark of a million rays, five repeats",
    ("benchmarks.md", "build/dacrt bench ../shared/scenes/stanford/dragon/dragon.glb --rays "
                      "primary,shadow,bounce --count 1048576 --repeat 5 --backends "
                      "dacrt,dacrt-naive,embree"): "long: a benchmark of a million rays, five "
                                                    "repeats",
    ("benchmarks.md", "tools/backend-table.sh 384 16 3"): "long: every scene of ../shared with "
                                                          "every backend",
    ("benchmarks.md", 'BACKENDS="dacrt embree" NO_BENCH=1 tools/backend-table.sh 384 64 3'):
        "long: every scene of ../shared at 64 spp, three runs of each backend",
    ("benchmarks.md", 'BACKENDS="dacrt embree" NO_BENCH=1 tools/backend-table.sh 1024 64 3'):
        "long: every scene of ../shared at 1024 x 1024 and 64 spp, three runs of each backend",
    ("benchmarks.md", 'DACRT_OPTIONS="walk_rays=4" BACKENDS="dacrt embree" '
                      'tools/backend-table.sh 1024 64 3'):
        "long: every scene of ../shared at 1024 x 1024 and 64 spp, three runs of each backend",
    ("benchmarks.md", "dacrt render ../shared/scenes/mcguire/conference/conference.glb "
                      "--look-from 1600,420,300 --look-at -600,150,-500 --fov 55 --width 1920 "
                      "--height 1080 --spp 64 --aov albedo,normal,depth,position,variance,samples "
                      "--point-light -500,600,-200=300000,290000,270000 --point-light "
                      "300,600,-200=300000,290000,270000 --point-light "
                      "1100,600,-200=300000,290000,270000 -o conference.exr --preview "
                      "conference.png"): "long: 1920 x 1080 pixels of the conference room",
    ("benchmarks.md", "tools/peer-compare.sh scenes/cornell-box-lambert.gltf --spp 64 --width 512 "
                      "--height 512"): "Blender (Cycles) renders the other side",
    ("benchmarks.md", "tools/peer-compare.sh --views"): "Blender (Cycles) and ../shared's scenes",
    ("benchmarks.md", 'LAMPS="4000 256 64 16 4" tools/many-lights-bench.sh build/dacrt '
                      "/tmp/many-lights-bench"): "long: dacrt converge on six scenes, minutes each",
    ("benchmarks.md", "BEFORE=/path/to/old/dacrt tools/peer-compare.sh --view helmet --rounds 3"):
        "another build of dacrt, and Blender",
    ("benchmarks.md", 'VIEWS="sponza-inside helmet" '
                      "FILES=../shared/scenes/mcguire/dabrovic-sponza/sponza.glb "
                      "BEFORE=/path/to/9b9465e/dacrt tools/before-after.sh 384 64 7"):
        "another build of dacrt, and long: 7 rounds of each view with two binaries",
    ("benchmarks.md", 'VIEWS="sponza-inside helmet" '
                      "BEFORE=/path/to/9b9465e/dacrt tools/before-after.sh 384 64 10"):
        "another build of dacrt, and long: 10 rounds of each view with two binaries",
    ("benchmarks.md", 'VIEWS="sponza-inside helmet" '
                      "FILES=../shared/scenes/mcguire/dabrovic-sponza/sponza.glb "
                      "BEFORE=/path/to/9b9465e/dacrt tools/before-after.sh 384 64 5"):
        "another build of dacrt, and long: 5 rounds of each view with two binaries",
    ("benchmarks.md", "blender -b -noaudio --python tools/cycles-render.py -- SCENE.gltf OUT.exr "
                      "[--spp N] [--width W --height H] [--seed S] [--max-depth D] [--threads T] "
                      "[--camera INDEX] [--look-from=X,Y,Z --look-at=X,Y,Z --up=X,Y,Z "
                      "--fov=DEGREES] [--environment R,G,B] [--principled]"): "Blender, and a "
                                                                               "synopsis",
    ("benchmarks.md", "blender -b -noaudio --python tools/exr-stats.py -- A.exr [B.exr]"):
        "Blender, and a synopsis",
    ("converge.md", 'dacrt converge scenes/cornell-box.gltf --width 256 --height 256 '
                    '--reference-spp 1024 --time-budget 20 --config "" --config '
                    '"sampler=independent" --config "backend=embree" --config "backend=embree '
                    'sampler=independent"'): "long: a 1024 spp reference and 20 s per "
                                             "configuration (the study the page shows)",
    ("converge.md", 'dacrt converge scenes/cornell-box.gltf --width 384 --height 384 '
                    '--reference-spp 256 --time-budget 25 --config "" --config "adaptive=0.05" '
                    '--config "adaptive=0.2"'): "long: 25 s per configuration",
    ("converge.md", "dacrt converge DamagedHelmet.glb --width 384 --height 384 --environment "
                    "1,1,1 ..."): "abbreviated (...: the configurations above)",
    ("converge.md", "dacrt converge sponza.glb --width 384 --height 256 --environment 1,1,1 "
                    "--look-from -14,3,0 --look-at 10,6,0 --fov 60 ..."): "abbreviated (...)",
    ("library.md", "cmake -S . -B build && cmake --build build -j"): "builds the project (the "
                                                                     "package ctest builds and "
                                                                     "installs it)",
    ("library.md", "cmake --install build --prefix /opt/dacrt"): "installs into /opt (the "
                                                                 "package ctest installs into "
                                                                 "the build tree)",
}

# Blocks in these languages are not run.
NOT_RUN_LANGUAGES = {
    "cmake": "a host project's CMakeLists.txt lines: tests/consumer is such a project, built "
             "against the installed package by the package ctest",
    "cpp": "a fragment of a host program: tests/consumer renders through the same calls",
}

SHELL_LANGUAGES = {"sh", "bash", "shell"}
PYTHON_LANGUAGES = {"python", "pycon"}


def make_scene_glb(path):
    """A small scene as a GLB: a unit cube on a floor under the default sky, seen by two cameras
    (README's --camera 1), mostly sky in view so that renders of it are quick."""
    positions, normals, indices = [], [], []

    def quad(corners, normal):
        base = len(positions)
        positions.extend(corners)
        normals.extend([normal] * 4)
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3])

    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = [(axis + 1) % 3, (axis + 2) % 3]
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[v] = 0.5 * sign, 0.5 * a * sign, 0.5 * b
                corners.append(p)
            n = [0.0, 0.0, 0.0]
            n[axis] = sign
            quad(corners, n)
    quad([[-3, -0.5, -3], [-3, -0.5, 3], [3, -0.5, 3], [3, -0.5, -3]], [0.0, 1.0, 0.0])
    vertex_bytes = b"".join(struct.pack("<3f", *p) for p in positions)
    normal_bytes = b"".join(struct.pack("<3f", *n) for n in normals)
    index_bytes = struct.pack("<%dH" % len(indices), *indices)
    index_bytes += b"\0" * (-len(index_bytes) % 4)
    binary = vertex_bytes + normal_bytes + index_bytes
    n = len(positions)
    gltf = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 1, 12]},
            {"camera": 1, "translation": [12, 1, 0], "rotation": [0, 0.70710678, 0, 0.70710678]},
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.01}}] * 2,
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1],
                                                "metallicFactor": 0}}],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(vertex_bytes)},
            {"buffer": 0, "byteOffset": len(vertex_bytes), "byteLength": len(normal_bytes)},
            {"buffer": 0, "byteOffset": len(vertex_bytes) + len(normal_bytes),
             "byteLength": 2 * len(indices)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [min(p[k] for p in positions) for k in range(3)],
             "max": [max(p[k] for p in positions) for k in range(3)]},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        ],
    }
    text = json.dumps(gltf).encode()
    text += b" " * (-len(text) % 4)
    chunks = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(binary), b"BIN\0") + binary
    path.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)


def render_fixture(*args):
    def make(path):
        subprocess.run([str(CLI), "render", *args, "-o", str(path), "--quiet"], check=True,
                       cwd=path.parent)
    return make


# Files the examples read that no example of their page writes: what each stands for, and how it
# is made (in the page's folder, before its commands, when the page names it).
FIXTURES = {
    "SCENE.glb": ("a scene of the reader's (README's --camera 1 wants two cameras)", make_scene_glb),
    "scene.glb": ("the same", make_scene_glb),
    "SCENE": ("the same, written without its extension", make_scene_glb),
    "reference.exr": ("a reference image of the Cornell box, the size of the renders it is "
                      "compared with", render_fixture("scenes/cornell-box.gltf", "--spp", "4",
                                                      "--seed", "1")),
    "render.exr": ("a render of the Cornell box", render_fixture("scenes/cornell-box.gltf",
                                                                 "--spp", "2")),
    "b.exr": ("the other part of README's split render (the samples 128 to 256)",
              render_fixture("SCENE.glb", "--spp", "256", "--samples", "128:256")),
}


def blocks(text):
    """The fenced blocks of a markdown page: (language, first line number, lines)."""
    out, language, start, lines = [], None, 0, []
    for number, line in enumerate(text.splitlines(), 1):
        if line.startswith("```"):
            if language is None:
                language, start, lines = line[3:].strip(), number, []
            else:
                out.append((language, start, lines))
                language = None
        elif language is not None:
            lines.append(line)
    return out


def commands(lines):
    """The commands of a shell block: (the command as written, its key for NOT_RUN)."""
    out, current = [], []
    for line in lines:
        current.append(line)
        if line.rstrip().endswith("\\"):
            continue
        written = "\n".join(current)
        current = []
        key = " ".join(re.sub(r"(^|\s)#\s.*$", "", part.rstrip().rstrip("\\"))
                       for part in written.splitlines())
        key = " ".join(key.split())
        if key:
            out.append((written, key))
    return out


def checkout(folder):
    """The folder laid out as a checkout with its build, the shared scenes beside it."""
    repo = folder / "repo"
    (repo / "build").mkdir(parents=True)
    (repo / "build" / "dacrt").symlink_to(CLI)
    if PYTHON_DIR:
        (repo / "build" / "python").symlink_to(PYTHON_DIR)
    for name in ("scenes", "tools"):
        (repo / name).symlink_to(SOURCE / name)
    if SHARED.is_dir():
        (folder / "shared").symlink_to(SHARED)
    return repo


def environment(repo):
    env = dict(os.environ)
    env["PATH"] = str(repo / "build") + os.pathsep + env.get("PATH", "")
    env["PYTHONPATH"] = str(repo / "build" / "python")
    env.pop("OCIO", None)  # the built-in views the pages describe
    return env


def run_page(page, problems, skipped, timings):
    name = page.name
    text = page.read_text()
    with tempfile.TemporaryDirectory(prefix="dacrt-docs-") as tmp:
        repo = checkout(pathlib.Path(tmp))
        env = environment(repo)
        made = set()
        for fixture, (_, make) in FIXTURES.items():
            named = re.search(r"(^|[\s/])" + re.escape(fixture) + r"($|\s)", text, re.M)
            written = re.search(r"-o " + re.escape(fixture) + r"($|\s)", text, re.M)
            if named and not written and not (repo / fixture).exists():
                if fixture == "b.exr" and not (repo / "SCENE.glb").exists():
                    make_scene_glb(repo / "SCENE.glb")
                make(repo / fixture)
                made.add(fixture)
        for language, line, lines in blocks(text):
            where = "%s:%d" % (name, line)
            if language in NOT_RUN_LANGUAGES:
                continue
            if language == "":
                for l in lines:
                    if re.match(r"\s*(build/dacrt |\$ |>>> |tools/\S|mpirun |python3? )", l):
                        problems.append("%s: an untagged block holds the command line '%s': tag "
                                        "the block sh or python so that it runs" % (where, l))
                continue
            if language in PYTHON_LANGUAGES:
                run_python(where, "\n".join(lines), repo, problems, timings)
                continue
            if language not in SHELL_LANGUAGES:
                problems.append("%s: a block in '%s', which the test neither runs nor lists in "
                                "NOT_RUN_LANGUAGES" % (where, language))
                continue
            for written, key in commands(lines):
                if (name, key) in NOT_RUN:
                    skipped.add((name, key))
                    continue
                if "../shared" in written and not SHARED.is_dir():
                    print("skipped (../shared is not there): %s: %s" % (where, key))
                    skipped.add((name, key))
                    continue
                start = time.monotonic()
                result = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", written], cwd=repo,
                                        env=env, capture_output=True, text=True, timeout=600,
                                        stdin=subprocess.DEVNULL)
                seconds = time.monotonic() - start
                timings.append((seconds, where, key))
                print("%6.1f s  %s: %s" % (seconds, where, key), flush=True)
                if result.returncode != 0:
                    problems.append("%s: '%s' exits %d:\n%s" % (where, key, result.returncode,
                                                                 (result.stderr or result.stdout)[-2000:]))


def run_python(where, source, repo, problems, timings):
    if not PYTHON_DIR:
        print("skipped (no Python module built): the Python example at " + where)
        return
    # In a process of its own, as a user's interpreter: the module from build/python.
    program = (
        "import doctest, sys\n"
        "test = doctest.DocTestParser().get_doctest(sys.stdin.read(), {}, %r, %r, 0)\n"
        "runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)\n"
        "runner.run(test)\n"
        "sys.exit(1 if runner.failures or not runner.tries else 0)\n" % (where, where))
    start = time.monotonic()
    result = subprocess.run([sys.executable, "-c", program], input=source, cwd=repo,
                            env=environment(repo), capture_output=True, text=True, timeout=600)
    seconds = time.monotonic() - start
    timings.append((seconds, where, "python"))
    print("%6.1f s  %s: the Python example" % (seconds, where), flush=True)
    if result.returncode != 0:
        problems.append("%s: the Python example fails:\n%s" % (where, (result.stdout + result.stderr)[-3000:]))


def main(argv):
    pages = [SOURCE / "README.md"] + sorted((SOURCE / "docs").glob("*.md"))
    if argv:
        pages = [p for p in pages if p.name in argv]
    if not CLI.is_file():
        print("no dacrt at %s (set DACRT_CLI)" % CLI)
        return 1
    problems, skipped, timings = [], set(), []
    for page in pages:
        run_page(page, problems, skipped, timings)
    # A NOT_RUN entry that no longer matches a command of its page: the page changed.
    for key in NOT_RUN:
        if key not in skipped and (not argv or key[0] in argv):
            problems.append("NOT_RUN lists '%s' of %s, which the page no longer has" % key[::-1])
    print("%d examples ran in %.0f s; %d listed as not run:" %
          (len(timings), sum(t[0] for t in timings), len(NOT_RUN)))
    for (page, key), why in NOT_RUN.items():
        print("  not run: %s: %s (%s)" % (page, key[:90], why))
    for problem in problems:
        print("FAIL " + problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
