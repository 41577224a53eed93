"""The renderer behind the engine: the dacrt command-line program.

render_glb() is the one function the engine calls to turn an exported .glb into pixels. It runs
`dacrt render`, reads its progress from stderr, stops it with SIGINT when the user cancels and
returns the EXR's colour as a float32 H×W×3 array, rows top-down: what the Python module's
dacrt.render() returns. Switching to the module is a render_glb() that calls dacrt.render()
(progress and cancel through its callbacks); the engine does not change. Imports no bpy.
"""

import os
import queue
import re
import shutil
import signal
import subprocess
import threading
from dataclasses import dataclass

from . import exr

# The line util/progress.cpp prints when stderr is not a terminal (at each 10 % step, every few
# seconds and at the end): "render: 40%, 25/64 spp, 1.20 Mrays/s, ETA 0:03".
_PROGRESS = re.compile(r"^(render[^:]*): (\d+)%(?:, )?(.*)$")
# What a failing CLI prints last (apps/dacrt.cpp): "dacrt: error: <one line>".
_ERROR = re.compile(r"^dacrt: (?:error: )?(.*)$")
# After SIGINT: 130 once the render has started (it wrote what it had); killed by the signal
# before (loading the scene, with the default handler still in place).
_INTERRUPTED = (130, -signal.SIGINT)
_POLL_SECONDS = 0.1


class RenderError(Exception):
    """A render that produced no image, with the one-line reason to show the user."""


@dataclass
class RenderJob:
    """What to render: the CLI's options, one field each."""
    width: int
    height: int
    spp: int
    seed: int
    camera: int
    backend: str = "dacrt"
    integrator: str = "path"
    max_depth: int = 64
    threads: int = 0  # 0: all cores
    environment: tuple = None  # a uniform radiance (R, G, B), or None for dacrt's default

    def arguments(self):
        args = ["--width", str(self.width), "--height", str(self.height), "--spp", str(self.spp),
                "--seed", str(self.seed), "--camera", str(self.camera), "--backend", self.backend,
                "--integrator", self.integrator, "--max-depth", str(self.max_depth)]
        if self.threads > 0:
            args += ["--threads", str(self.threads)]
        if self.environment is not None:
            args += ["--environment", _environment_argument(self.environment)]
        return args


def _environment_argument(rgb):
    """R,G,B for --environment, each digit that tells the float apart (repr)."""
    return ",".join(repr(float(c)) for c in rgb)


@dataclass
class Frame:
    """A rendered image: float32 H×W×3, rows top-down, or None when a cancel came before any
    sample; cancelled says it has fewer samples than asked for."""
    pixels: object
    cancelled: bool


def find_executable(preference=""):
    """The dacrt program: $DACRT_CLI, else the add-on's preference, else `dacrt` on PATH."""
    for candidate in (os.environ.get("DACRT_CLI", ""), preference):
        if candidate:
            return candidate
    return shutil.which("dacrt") or ""


def parse_progress(line):
    """(fraction, rest of the line) from a progress line, or None for any other line."""
    match = _PROGRESS.match(line)
    if not match:
        return None
    return int(match.group(2)) / 100.0, f"{match.group(1)} {match.group(2)}%  {match.group(3)}"


def _read_lines(stream, lines):
    for raw in stream:
        lines.put(raw.decode("utf-8", "replace").rstrip("\r\n"))
    lines.put(None)


def render_glb(executable, glb_path, exr_path, job, on_progress, cancelled):
    """Renders glb_path (through the file exr_path) and returns the Frame.

    on_progress(fraction, text) is called on the caller's thread for each progress line;
    cancelled() is polled every 0.1 s: when it turns true the CLI gets SIGINT, finishes the paths
    in flight and writes what it has, which is returned (frame.cancelled set).
    """
    if not executable:
        raise RenderError("dacrt executable not found: set it in the add-on's preferences, "
                          "put dacrt on PATH or set DACRT_CLI")
    command = [executable, "render", glb_path, "-o", exr_path] + job.arguments()
    try:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                   stderr=subprocess.PIPE)
    except OSError as error:
        raise RenderError(f"cannot run {executable}: {error.strerror}") from None
    # stderr is read on a thread so that polling for a cancel never waits for the next line.
    lines = queue.Queue()
    reader = threading.Thread(target=_read_lines, args=(process.stderr, lines), daemon=True)
    reader.start()
    interrupted = False
    last_line = ""
    try:
        while True:
            try:
                line = lines.get(timeout=_POLL_SECONDS)
            except queue.Empty:
                line = ""
            if line is None:
                break
            if line:
                progress = parse_progress(line)
                if progress:
                    on_progress(*progress)
                else:
                    last_line = line
            if not interrupted and cancelled():
                process.send_signal(signal.SIGINT)
                interrupted = True
        code = process.wait()
    finally:
        if process.poll() is None:  # an exception above (the caller's callbacks): stop it now
            process.kill()
            process.wait()
        reader.join()  # the pipe is at its end once the process is gone
        process.stderr.close()
    if code == 0 or (interrupted and code in _INTERRUPTED):
        # A render cut short keeps its exact sums, which Blender's EXR reader refuses: read here.
        pixels = exr.read_rgb(exr_path) if os.path.exists(exr_path) else None
        return Frame(pixels, cancelled=interrupted)
    match = _ERROR.match(last_line)
    reason = match.group(1) if match else last_line or f"exit code {code}"
    raise RenderError(f"dacrt: {reason}")
