"""Writes the package's type stub, __init__.pyi, from its signatures at run time (inspect): for
editors and type checkers that read files rather than run the module, render()'s and
converge()'s keywords (the render option table's) with their types. The build runs
`python -m dacrt._stub OUT` once the native module is built."""
import dataclasses
import inspect
import os
import sys
import typing

import numpy as np
import numpy.typing as npt

import dacrt

HEADER = '''# The type stub of the package dacrt, written by dacrt._stub from its signatures when the
# module was built (render()'s and converge()'s keywords are the render option table's).
import dataclasses
import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
PathLike = Union[str, bytes, os.PathLike]

class Error(RuntimeError): ...
class DacrtWarning(UserWarning): ...

class Scene:
    @property
    def path(self) -> str: ...
    @property
    def info(self) -> Dict[str, Any]: ...
'''
PATH_PARTS = set(typing.get_args(dacrt.PathLike))


def annotation(a) -> str:
    """A type as the stub spells it."""
    if a is npt.ArrayLike:
        return "npt.ArrayLike"
    if a is None or a is type(None):
        return "None"
    origin, args = typing.get_origin(a), typing.get_args(a)
    if origin is typing.Union:
        parts = list(args)
        optional = type(None) in parts
        parts = [p for p in parts if p is not type(None)]
        names = []
        if PATH_PARTS <= set(parts):
            names.append("PathLike")
            parts = [p for p in parts if p not in PATH_PARTS]
        names += [annotation(p) for p in parts]
        text = names[0] if len(names) == 1 else "Union[%s]" % ", ".join(names)
        return "Optional[%s]" % text if optional else text
    if origin is not None:
        name = {tuple: "Tuple", list: "List", dict: "Dict"}.get(origin)
        if name is None and getattr(origin, "__module__", "") == "collections.abc":
            name = origin.__name__
        return "%s[%s]" % (name, ", ".join(annotation(x) for x in args))
    if a is typing.Any:
        return "Any"
    if a is np.ndarray:
        return "np.ndarray"
    if isinstance(a, type):
        return a.__name__
    raise ValueError("no stub spelling for %r" % (a,))


def function_text(name, function) -> str:
    signature = inspect.signature(function)
    parameters, star = [], False
    for p in signature.parameters.values():
        if p.kind == p.KEYWORD_ONLY and not star:
            parameters.append("*")
            star = True
        text = p.name + ": " + annotation(p.annotation)
        if p.default is not p.empty:
            default = p.default
            text += " = " + ("float('inf')" if default == float("inf") else repr(default))
        parameters.append(text)
    return "def %s(%s) -> %s: ...\n" % (name, ", ".join(parameters),
                                        annotation(signature.return_annotation))


def stub_text() -> str:
    out = [HEADER, "\n@dataclasses.dataclass(frozen=True)\nclass ConvergeRow:\n"]
    for field in dataclasses.fields(dacrt.ConvergeRow):
        out.append("    %s: %s\n" % (field.name, annotation(field.type)))
    out.append("\n")
    for name in dacrt.__all__:
        value = getattr(dacrt, name)
        if inspect.isfunction(value):
            out.append(function_text(name, value))
        elif inspect.isroutine(value):  # a native function left as it is
            out.append("def %s(*args: Any, **kwargs: Any) -> Any: ...\n" % name)
    return "".join(out)


if __name__ == "__main__":
    text = stub_text()
    temporary = sys.argv[1] + ".tmp"
    with open(temporary, "w") as f:
        f.write(text)
    os.replace(temporary, sys.argv[1])
