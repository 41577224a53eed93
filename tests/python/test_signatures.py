# Every function has a real signature (inspect.signature, an editor's completion): names, defaults
# and types. render()'s keywords are the render option table's, as _render_keywords() gives them;
# converge()'s and bench()'s are their commands' options.
import inspect
import re
import subprocess
import typing
from typing import Optional, Sequence, Tuple, Union

import dacrt
from conftest import CLI

KW = inspect.Parameter.KEYWORD_ONLY


def test_render_signature_is_the_option_table():
    parameters = inspect.signature(dacrt.render).parameters
    names = list(parameters)
    assert names[0] == "scene"
    assert names[1:] == dacrt._render_keywords()  # the table's Python column, then progress
    for name in names[1:]:
        p = parameters[name]
        assert p.kind == KW and p.default is None, name
    # Each keyword's type is its option's value type, None being the CLI's default.
    hints = typing.get_type_hints(dacrt.render)
    assert hints["spp"] == Optional[int] and hints["seed"] == Optional[int]
    assert hints["fov"] == Optional[float] and hints["integrator"] == Optional[str]
    assert hints["look_from"] == Optional[Tuple[float, float, float]]
    assert hints["samples"] == Optional[Tuple[int, int]]
    assert hints["aovs"] == Optional[Union[str, Sequence[str]]]
    assert hints["point_light"] == Optional[Union[str, Sequence[str]]]  # repeatable: a list
    assert hints["animation"] == Optional[Union[str, int]]
    assert hints["progress"] == Optional[bool]
    assert hints["scene"] == Union[dacrt.Scene, dacrt.PathLike]
    # The documentation has every keyword with its help line from the table.
    for name in names[1:]:
        assert "    %s=: " % name in dacrt.render.__doc__, name
    assert "samples per pixel (default 64)" in dacrt.render.__doc__


def test_every_function_has_a_signature_with_types():
    expected = {
        dacrt.load: ["path", "variant", "scene", "time", "animation"],
        dacrt.trace: ["scene", "origins", "directions", "backend", "tmin", "tmax", "occluded"],
        dacrt.read_exr: ["path"],
    }
    for function, names in expected.items():
        signature = inspect.signature(function)
        assert list(signature.parameters) == names, function.__name__
        assert signature.return_annotation is not inspect.Signature.empty, function.__name__
        for p in signature.parameters.values():
            assert p.annotation is not inspect.Parameter.empty, (function.__name__, p.name)
    assert inspect.signature(dacrt.trace).parameters["tmax"].default == float("inf")
    assert inspect.signature(dacrt.load).parameters["time"].default is None
    for function in (dacrt.bench, dacrt.converge):
        for p in list(inspect.signature(function).parameters.values())[1:]:
            assert p.kind == KW and p.default is None, (function.__name__, p.name)
            assert p.annotation is not inspect.Parameter.empty, (function.__name__, p.name)


def command_options(command):
    """The options of `dacrt COMMAND --help`, as keywords."""
    text = subprocess.run([CLI, command, "--help"], capture_output=True, text=True,
                          check=True).stdout
    return {flag[2:].replace("-", "_") for line in text.splitlines()
            if line.startswith("  -") for flag in re.findall(r"--[a-z][a-z-]*", line[:29])}


def test_bench_and_converge_keywords_are_their_commands_options():
    # What they leave to the CLI: files, the help, --quiet (progress= instead).
    bench = set(inspect.signature(dacrt.bench).parameters) - {"scene", "progress"}
    assert bench == command_options("bench") - {"json", "report", "help", "quiet"}
    # converge's own options, and the render options it takes: the table's (its --help names
    # them in a sentence).
    converge = set(inspect.signature(dacrt.converge).parameters) - {"scene", "progress"}
    table = {row[0] for row in dacrt._render_keyword_table() if row[3]}
    assert len(table) > 20 and {"width", "integrator", "backend_option"} <= table
    assert converge == (command_options("converge") - {"output", "no_plot", "help", "quiet"}) | table


def test_a_keyword_converge_does_not_take_is_a_type_error_with_the_nearest():
    try:
        dacrt.converge(dacrt.__file__, max_sp=4)
    except TypeError as e:
        assert "unexpected keyword argument 'max_sp' (did you mean max_spp=?)" in str(e)
    else:
        raise AssertionError("no TypeError")


def test_the_type_stub_has_the_same_signatures():
    # __init__.pyi (written at build time) for editors that read files: every function with its
    # parameters, render()'s being the table's keywords.
    import ast
    import pathlib
    import pytest
    stub = pathlib.Path(dacrt.__file__).with_name("__init__.pyi")
    if not stub.exists():
        pytest.skip("no type stub in this build (a sanitizer build writes none)")
    tree = ast.parse(stub.read_text())
    functions = {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}
    public = {name for name in dacrt.__all__ if inspect.isfunction(getattr(dacrt, name))}
    assert public <= set(functions)
    for name in public:
        node = functions[name]
        names = [a.arg for a in node.args.posonlyargs + node.args.args + node.args.kwonlyargs]
        assert names == list(inspect.signature(getattr(dacrt, name)).parameters), name
    spp = [a for a in functions["render"].args.kwonlyargs if a.arg == "spp"][0]
    assert ast.unparse(spp.annotation) == "Optional[int]"
    assert "class ConvergeRow" in stub.read_text() and "def info(self)" in stub.read_text()
