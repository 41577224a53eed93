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

import numpy as np

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
    environment: str = None  # --environment's R,G,B or FILE.exr, or None for dacrt's default
    time_limit: float = 0.0  # seconds; 0: none
    adaptive: float = 0.0  # --adaptive's relative error; 0: off
    adaptive_min: int = 0  # --adaptive-min; 0: dacrt's default
    aperture: float = 0.0  # lens diameter in scene units; 0: a pinhole
    focus_distance: float = 0.0  # with an aperture
    aovs: tuple = ()  # --aov's names

    def arguments(self):
        args = ["--width", str(self.width), "--height", str(self.height), "--spp", str(self.spp),
                "--seed", str(self.seed), "--camera", str(self.camera), "--backend", self.backend,
                "--integrator", self.integrator, "--max-depth", str(self.max_depth)]
        if self.threads > 0:
            args += ["--threads", str(self.threads)]
        if self.environment is not None:
            args += ["--environment", self.environment]
        if self.time_limit > 0:
            args += ["--time-limit", _setting(self.time_limit)]
        if self.adaptive > 0:
            args += ["--adaptive", _setting(self.adaptive)]
            if self.adaptive_min > 0:
                args += ["--adaptive-min", str(self.adaptive_min)]
        if self.aperture > 0:
            args += ["--aperture", repr(float(self.aperture)),
                     "--focus-distance", repr(float(self.focus_distance))]
        if self.aovs:
            args += ["--aov", ",".join(self.aovs)]
        return args


def _setting(value):
    """A setting of Blender's (a float32) as the decimal shown in its panel: 0.02, not
    0.019999999552965164."""
    return f"{value:.7g}"


@dataclass
class Frame:
    """A rendered image: float32 H×W×3, rows top-down, or None when a cancel came before any
    sample; cancelled says it has fewer samples than asked for. aovs: each AOV asked for, by
    name, H×W×channels (albedo, normal, position: 3; depth: 1), glTF's axes; warnings: dacrt's
    warning lines."""
    pixels: object
    cancelled: bool
    aovs: dict = None
    warnings: list = None


# The EXR channels of each AOV (docs/usage.md, "AOVs").
AOV_CHANNELS = {"albedo": ("albedo.R", "albedo.G", "albedo.B"), "normal": ("N.X", "N.Y", "N.Z"),
                "depth": ("Z",), "position": ("P.X", "P.Y", "P.Z")}
# A warning line of dacrt's: "warning: ..." or "dacrt: warning: ...", perhaps indented.
_WARNING = re.compile(r"^\s*(?:dacrt: )?warning: (.*)$")


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
    warnings = []
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
                    warning = _WARNING.match(line)
                    if warning:
                        warnings.append(warning.group(1))
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
        if not os.path.exists(exr_path):
            return Frame(None, cancelled=interrupted, aovs={}, warnings=warnings)
        names = [channel for aov in job.aovs for channel in AOV_CHANNELS[aov]]
        planes = exr.read_channels(exr_path, ["R", "G", "B"] + names)
        pixels = np.stack([planes[c] for c in "RGB"], axis=-1)
        aovs = {aov: np.stack([planes[c] for c in AOV_CHANNELS[aov]], axis=-1)
                for aov in job.aovs}
        return Frame(pixels, cancelled=interrupted, aovs=aovs, warnings=warnings)
    match = _ERROR.match(last_line)
    reason = match.group(1) if match else last_line or f"exit code {code}"
    raise RenderError(f"dacrt: {reason}")
