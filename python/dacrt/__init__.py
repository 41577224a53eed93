"""dacrt: a path tracer whose ray queries are Divide-And-Conquer Ray Tracing with ray sampling.

load() a glTF scene once, render() it to numpy arrays (the pixels of `dacrt render` bit for bit),
trace() your own rays with any backend, read_exr() the CLI's outputs, and run the bench() and
converge() studies as data. Long calls release the GIL; Ctrl-C stops them cleanly and raises
KeyboardInterrupt. Nothing is printed on stdout: results are return values, what was not done as
asked (and notes about the scene) are warnings (DacrtWarning), and progress goes to stderr when
asked (progress=True) or where it is seen (progress=None: a terminal, IPython or Jupyter).

The functions here are Python, with their signatures (inspect.signature, an editor's completion);
the work is done by the native module dacrt._dacrt. render()'s keywords are the CLI's render
options, read from the same option table at import.
"""
import dataclasses
import difflib
import inspect
import os
import sys
import warnings
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _dacrt
from ._dacrt import Error, Scene, _render_keyword_table, _render_keywords

__version__: str = _dacrt.__version__

# The module's own classes, shown as dacrt's.
Error.__module__ = __name__
Scene.__module__ = __name__

PathLike = Union[str, bytes, os.PathLike]
"""A path as open() takes it: a str, bytes or an os.PathLike such as pathlib.Path."""
Point = Tuple[float, float, float]


class DacrtWarning(UserWarning):
    """What dacrt did otherwise than asked, or a note about the scene (a render's lighting, a
    converge run too short to time): the lines the CLI prints on stderr."""


def _warn(messages: Sequence[str], stacklevel: int = 3) -> None:
    for message in messages:
        warnings.warn(message, DacrtWarning, stacklevel=stacklevel)


def _progress_seen() -> bool:
    """Whether progress on stderr is seen: stderr is a terminal, or IPython or Jupyter runs this
    (a notebook shows the kernel's stderr under the cell)."""
    try:
        if sys.stderr is not None and sys.stderr.isatty():
            return True
    except (AttributeError, ValueError):  # no isatty, or a closed stream
        pass
    ipython = sys.modules.get("IPython")
    get_ipython = getattr(ipython, "get_ipython", None)
    try:
        return get_ipython is not None and get_ipython() is not None
    except Exception:  # an IPython half imported: not running it
        return False


def _show_progress(progress: Optional[bool]) -> bool:
    """progress= as given: True or False; None is where it is seen (_progress_seen)."""
    if progress is None:
        return _progress_seen()
    if not isinstance(progress, bool):
        raise TypeError("progress= wants True, False or None, not " + type(progress).__name__)
    return progress


# The Python types of the option table's value types (render/request.h's OptionValue).
_VALUE_TYPES: Dict[str, Any] = {
    "flag": bool,
    "int": int,
    "number": float,
    "str": str,
    "name_or_index": Union[str, int],
    "path": PathLike,
    "point": Point,
    "range": Tuple[int, int],
    "names": Union[str, Sequence[str]],
    "colour_or_file": Union[Point, PathLike],
}

_KW = inspect.Parameter.KEYWORD_ONLY
_PROGRESS = inspect.Parameter("progress", _KW, default=None, annotation=Optional[bool])


def _table_parameters(converge: bool) -> Tuple[List[inspect.Parameter], List[str]]:
    """The keyword parameters of the render option table's Python column (those converge()
    takes, with converge), each defaulting to None (the CLI's default), and their help lines."""
    parameters, docs = [], []
    for keyword, value, repeatable, for_converge, help_text in _dacrt._render_keyword_table():
        if converge and not for_converge:
            continue
        kind = _VALUE_TYPES[value]
        if repeatable and value != "names":
            kind = Union[kind, Sequence[kind]]
        parameters.append(inspect.Parameter(keyword, _KW, default=None,
                                            annotation=Optional[kind]))
        docs.append(_help_entry(keyword, help_text))
    return parameters, docs


def _help_entry(keyword: str, help_text: str) -> str:
    """`dacrt render --help`'s lines of an option as a keyword's: its text without the flag
    column."""
    lines = []
    for line in help_text.splitlines():
        text = line[29:].strip() if len(line) > 29 and line[27:29] == "  " else ""
        if text:
            lines.append(text)
    if not lines and keyword == "height":
        lines = ["image height (see width=)"]
    return "    %s=: %s" % (keyword, "\n        ".join(lines))


def _signed(function, parameters: List[inspect.Parameter], returns: Any, docs: List[str]):
    """`function` (which takes **options) given the signature of `parameters`."""
    signature = inspect.Signature(parameters, return_annotation=returns)
    function.__signature__ = signature
    function.__annotations__ = {p.name: p.annotation for p in parameters}
    function.__annotations__["return"] = returns
    if docs:
        function.__doc__ = (function.__doc__ or "").rstrip(" ") + "\n".join(docs) + "\n"
    return function


def _check_keywords(name: str, options: Dict[str, Any], function, passed_on: Sequence[str]):
    """TypeError for a keyword not in `function`'s signature (with the nearest one), unless the
    native call refuses it itself with its reason (`passed_on`)."""
    known = [p for p in inspect.signature(function).parameters][1:]
    for key in options:
        if key not in known and key not in passed_on:
            near = difflib.get_close_matches(key, known, n=1)
            hint = " (did you mean %s=?)" % near[0] if near else ""
            raise TypeError("%s() got an unexpected keyword argument '%s'%s" % (name, key, hint))


def load(path: PathLike, *, variant: Optional[Union[str, bytes]] = None,
         scene: Optional[int] = None, time: Optional[float] = None,
         animation: Optional[Union[str, int]] = None) -> Scene:
    """Loads a glTF 2.0 file (.gltf or .glb) once, for many renders.

    variant: a KHR_materials_variants name. scene: the index of a scene of the file (default:
    its default scene). animation: which of its animations play (a name, an index or 'all';
    default: the first). time: the seconds they are evaluated at (default: the rest pose;
    render(time=...) poses it again). Raises dacrt.Error with the loader's one-line message,
    ValueError for a variant the file lacks.
    """
    return _dacrt.load(path, variant=variant, scene=scene, time=time, animation=animation)


def render(scene: Union[Scene, PathLike], **options: Any):
    """Renders a Scene (or a path, loaded for this call) as `dacrt render` does.

    Returns the image as a float32 numpy array of shape (height, width, 3), linear radiance: the
    pixels of the CLI's EXR bit for bit; with aovs=[...], (image, aovs): a dict of (height,
    width[, 3]) arrays by AOV name. The keywords are the CLI's render options (`dacrt render
    --help`), dashes as underscores; None (the default) is the CLI's default. A flag is a bool; a
    list repeats a repeatable option. progress=None shows the progress bar on stderr where it is
    seen (a terminal, IPython, Jupyter); True or False forces it. Notes about the scene (its
    lighting) are warnings (DacrtWarning). Bad options raise TypeError or ValueError, a bad scene
    dacrt.Error. The GIL is released while rendering; Ctrl-C stops the render at its next
    wavefront and raises KeyboardInterrupt.

    Keywords:
    """
    options["progress"] = _show_progress(options.get("progress"))
    image, aovs, notes = _dacrt.render(scene, **options)
    _warn(notes)
    return image if aovs is None else (image, aovs)


_render_parameters, _render_docs = _table_parameters(converge=False)
_signed(render,
        [inspect.Parameter("scene", inspect.Parameter.POSITIONAL_OR_KEYWORD,
                           annotation=Union[Scene, PathLike])] + _render_parameters + [_PROGRESS],
        Union[np.ndarray, Tuple[np.ndarray, Dict[str, np.ndarray]]],
        _render_docs + ["    progress=: progress on stderr (None: where it is seen)"])


def trace(scene: Scene, origins: npt.ArrayLike, directions: npt.ArrayLike, *,
          backend: str = "dacrt", tmin: float = 0.0, tmax: float = float("inf"),
          occluded: bool = False) -> Union[Dict[str, np.ndarray], np.ndarray]:
    """The backend's closest hits of N rays.

    origins and directions: N×3 arrays, converted to float32; directions need not be unit length,
    t is in their units. Returns a dict of numpy arrays t (float32, inf where nothing is hit),
    prim (uint32 triangle index, 0xFFFFFFFF for a miss), u and v (barycentric weights of the
    triangle's corners 1 and 2). With occluded=True, one bool per ray: anything hit in [tmin,
    tmax]. Every triangle is opaque here (alpha masks are the renderer's business). dacrt,
    dacrt-naive and brute give the same hits bit for bit. The GIL is released while tracing.
    """
    return _dacrt.trace(scene, origins, directions, backend=backend, tmin=tmin, tmax=tmax,
                        occluded=occluded)


def read_exr(path: PathLike) -> Dict[str, np.ndarray]:
    """Every channel of an OpenEXR file as a float32 numpy array of shape (height, width), by
    channel name ('R', 'albedo.R', ...): to compare with the CLI's outputs. Integer channels come
    as floats."""
    return _dacrt.read_exr(path)


def write_image(path: PathLike, image: npt.ArrayLike, view: Optional[str] = None,
                exposure: float = 0.0) -> None:
    """Writes a scene-linear image (a float array of shape (height, width, 3), or 4 with alpha,
    such as render()'s) in the format its file name says: .exr (float RGB, alpha as A), .hdr
    (Radiance RGBE), .png (8-bit, with alpha) or .jpg/.jpeg, the last two through the display
    view (view=, a name of `dacrt views`; default sRGB) after scaling by 2**exposure: the bytes
    `dacrt render --preview` and `dacrt convert` write. JPEG and HDR hold no alpha (a UserWarning
    says it is dropped). An unknown extension or a bad view raises ValueError, a file that cannot
    be written dacrt.Error. Written to a temporary name and renamed."""
    _dacrt.write_image(path, image, view=view, exposure=exposure)


def bench(scene: PathLike, *, rays: Optional[Union[str, Sequence[str]]] = None,
          backends: Optional[Union[str, Sequence[str]]] = None, width: Optional[int] = None,
          height: Optional[int] = None, count: Optional[int] = None,
          repeat: Optional[int] = None, threads: Optional[int] = None,
          backend_option: Optional[Union[str, Sequence[str]]] = None,
          sweep: Optional[str] = None, seed: Optional[int] = None,
          tmax_at_hit: Optional[bool] = None, progress: Optional[bool] = None) -> Dict[str, Any]:
    """`dacrt bench`: every backend on the same rays of each type, in the same run.

    Returns what `dacrt bench --json` writes, as a dict: the results per backend and ray type
    (build and trace seconds of every run, medians with 95 % intervals, Mrays/s, peak memory).
    The keywords are the command's options (`dacrt bench --help`), dashes as underscores; None is
    the command's default: rays='primary,shadow' (or a list), backends=, width=, height=, count=,
    repeat=, threads=, backend_option= (a list repeats it), sweep='rays' or 'triangles', seed=,
    tmax_at_hit=True. progress= as render()'s; its warnings (a ray type without rays, backends
    that disagree) are DacrtWarning. The GIL is released while it runs.
    """
    options = dict(rays=rays, backends=backends, width=width, height=height, count=count,
                   repeat=repeat, threads=threads, backend_option=backend_option, sweep=sweep,
                   seed=seed, tmax_at_hit=tmax_at_hit, progress=_show_progress(progress))
    report, notes = _dacrt.bench(scene, **options)
    _warn(notes)
    return report


@dataclasses.dataclass(frozen=True)
class ConvergeRow:
    """One point of a converge() curve: a row of `dacrt converge`'s convergence.csv. A value
    the run did not measure (an error without a reference, an interval of one repeat) is None."""
    config: str  # the configuration's label ("default" for "")
    spp: int
    seconds: float  # render seconds to reach spp (the mean of the repeats)
    rmse: Optional[float]
    relmse: Optional[float]
    mae: Optional[float]
    smape: Optional[float]
    noise: Optional[float]
    repeats: int
    seconds_low: Optional[float]  # 95 % interval of the repeats' mean (None for one repeat)
    seconds_high: Optional[float]
    rmse_low: Optional[float]
    rmse_high: Optional[float]
    relmse_low: Optional[float]
    relmse_high: Optional[float]
    mae_low: Optional[float]
    mae_high: Optional[float]
    smape_low: Optional[float]
    smape_high: Optional[float]
    noise_low: Optional[float]
    noise_high: Optional[float]
    rmse_raw: Optional[float]  # before the reference's own error is subtracted
    relmse_raw: Optional[float]
    reference_mse: Optional[float]  # the reference's own error, when known
    reference_relmse: Optional[float]


def _converge_row(header: Sequence[str], cells: Sequence[str]) -> ConvergeRow:
    values = {}
    for field, text in zip(header, cells):
        kind = ConvergeRow.__dataclass_fields__[field].type
        if kind is str:
            values[field] = text
        elif kind is int:
            values[field] = int(text)
        else:
            values[field] = float(text) if text != "" else None
    return ConvergeRow(**values)


def converge(scene: PathLike, **options: Any) -> List[ConvergeRow]:
    """`dacrt converge`: renders each configuration at 1, 2, 4, ... samples per pixel until its
    time budget is spent and measures each point's error.

    Returns the points as ConvergeRow (the rows of its convergence.csv, typed; None for a value
    not measured), in a temporary directory removed afterwards; prints nothing on stdout (its
    summary is the CLI's), its warnings are DacrtWarning. The keywords are the command's options
    (`dacrt converge --help`), dashes as underscores, None being its default; config= and
    target_error= take a list (one option each). progress= as render()'s. Ctrl-C stops it as it
    stops the CLI (KeyboardInterrupt); a second Ctrl-C ends the process, as the CLI's does.

    Keywords:
    """
    _check_keywords("converge", options, converge, _REFUSED_BY_CONVERGE)
    options["progress"] = _show_progress(options.get("progress"))
    header, rows, notes = _dacrt.converge(scene, **options)
    if list(header) != list(ConvergeRow.__dataclass_fields__):
        raise Error("converge: convergence.csv's columns are not ConvergeRow's: " + ",".join(header))
    _warn(notes)
    return [_converge_row(header, cells) for cells in rows]


# What converge() leaves to the CLI (files and the help): the native call says why.
_REFUSED_BY_CONVERGE = ("output", "o", "no_plot", "help", "quiet")
_CONVERGE_OWN = [
    ("config", Union[str, Sequence[str]],
     "one configuration: render options overriding the shared ones, 'KEY=VALUE ...' (a list: "
     "several; default: '', 'sampler=independent', 'backend=embree')"),
    ("time_budget", float, "seconds per configuration (default 10)"),
    ("max_spp", int, "stop at this spp at most (default 65536)"),
    ("repeats", int, "render each configuration this many times (default 1)"),
    ("reference", PathLike, "the converged image, an EXR of the renders' size"),
    ("reference_spp", int, "without reference=: render one of this spp (default 1024)"),
    ("no_reference", bool, "no reference: the error is the noise between two seeds"),
    ("noise", bool, "also the noise: every point rendered again with seed S + 1"),
    ("metric", str, "rmse (default), relmse, mae, smape, noise"),
    ("target_error", Union[float, Sequence[float]], "the equal-error comparison's level"),
]
_converge_table, _converge_table_docs = _table_parameters(converge=True)
_signed(converge,
        [inspect.Parameter("scene", inspect.Parameter.POSITIONAL_OR_KEYWORD, annotation=PathLike)]
        + [inspect.Parameter(k, _KW, default=None, annotation=Optional[t])
           for k, t, _ in _CONVERGE_OWN] + _converge_table + [_PROGRESS],
        List[ConvergeRow],
        ["    %s=: %s" % (k, text) for k, _, text in _CONVERGE_OWN] + _converge_table_docs
        + ["    progress=: progress on stderr (None: where it is seen)"])

__all__ = ["DacrtWarning", "ConvergeRow", "Error", "PathLike", "Scene", "bench", "converge",
           "load", "read_exr", "render", "trace", "write_image"]

# A function the native module has and this file does not wrap is dacrt's as it is.
for _name in dir(_dacrt):
    if not _name.startswith("_") and _name not in globals():
        globals()[_name] = getattr(_dacrt, _name)
        __all__.append(_name)
del _name
