# Untrusted input through the module: messages whose bytes are not UTF-8, paths as open() takes
# them, times --time refuses, and values of the wrong type, each the Python exception a caller
# expects, naming what is wrong.
import os
import pathlib
import shutil

import pytest

import dacrt
from conftest import CORNELL

SMALL = dict(spp=1, width=8, height=8)


def test_a_message_with_bytes_that_are_not_utf8_keeps_its_text(tmp_path):
    # A file name of Latin-1 bytes (as an old archive unpacks it): the message names the file.
    name = os.fsencode(tmp_path) + b"/caf\xe9.gltf"
    with pytest.raises(dacrt.Error) as missing:
        dacrt.load(name)
    assert "caf\\xe9.gltf" in str(missing.value) and "does not exist" in str(missing.value)
    # The same file, present, loads through bytes and through the str os.fsdecode gives.
    shutil.copy(CORNELL, name)
    scene = dacrt.load(os.fsdecode(name))
    assert os.fsencode(scene.path) == name and os.fsencode(scene.info["path"]) == name
    assert "caf" in repr(scene)
    assert dacrt.load(name).info["triangles"] == scene.info["triangles"]
    # A variant name of such bytes (as os.fsdecode gives it), quoted by the loader's error.
    for variant in ("\udce9t\udce9", b"\xe9t\xe9"):
        with pytest.raises(ValueError) as unknown:
            dacrt.load(CORNELL, variant=variant)
        assert '--variant "\\xe9t\\xe9" is not a material variant' in str(unknown.value)


def test_paths_are_taken_as_open_takes_them(tmp_path):
    for path in (pathlib.Path(CORNELL), os.fsencode(CORNELL), CORNELL):
        assert dacrt.load(path).info["triangles"] > 0
    with pytest.raises(ValueError, match="embedded null byte"):
        dacrt.load(CORNELL + "\0x")
    with pytest.raises(ValueError, match="embedded null byte"):
        dacrt.render(CORNELL + "\0x", **SMALL)
    with pytest.raises(ValueError, match="embedded null byte"):
        dacrt.read_exr(str(tmp_path / "a.exr") + "\0")
    with pytest.raises(TypeError, match="path"):
        dacrt.load(3)
    with pytest.raises(TypeError, match="scene"):
        dacrt.bench(3.5)
    assert dacrt.render(pathlib.Path(CORNELL), **SMALL).shape == (8, 8, 3)


@pytest.mark.parametrize("time", [-1.0, float("inf"), float("nan"), 1e9])
def test_load_refuses_the_times_the_cli_refuses(time):
    with pytest.raises(ValueError, match="time= wants seconds"):
        dacrt.load(CORNELL, time=time)
    with pytest.raises(ValueError, match="time= wants seconds"):
        dacrt.render(CORNELL, time=time, **SMALL)


def test_wrong_types_are_type_errors_naming_the_keyword():
    cases = [
        (dict(progress="yes"), "progress= wants True, False or None, not str"),
        (dict(progress=1), "progress= wants True, False or None, not int"),
        (dict(spp=True), "spp= wants a value, not True"),
        (dict(width=False), "width= wants a value, not False"),
        (dict(seed={"a": 1}), "seed= wants an int, not dict"),
        (dict(seed=1.5), "seed= wants an int, not float"),
        (dict(fov="50"), "fov= wants a number, not str"),
        (dict(integrator=3), "integrator= wants a str, not int"),
        (dict(look_from=(1, object(), 3)), "look_from= wants three numbers (x, y, z), not (1, <object"),
        (dict(look_from="0,1,3"), "look_from= wants three numbers (x, y, z), not str"),
        (dict(samples=(0, 1.5)), "samples= wants two ints (first, last), not (0, 1.5)"),
        (dict(aovs=["albedo", 3]), "aovs= wants a str or a list of str, not a list holding int"),
        (dict(point_light=[b"\0"]), None),
    ]
    for options, message in cases:
        given = dict(SMALL, **options)
        if message is None:
            with pytest.raises(ValueError, match="embedded null byte"):
                dacrt.render(CORNELL, **given)
            continue
        with pytest.raises(TypeError) as raised:
            dacrt.render(CORNELL, **given)
        assert str(raised.value).startswith(message)
    with pytest.raises(TypeError, match="noise= wants True or False, not str"):
        dacrt.converge(CORNELL, noise="yes")
    with pytest.raises(TypeError, match="tmax_at_hit= wants True or False, not int"):
        dacrt.bench(CORNELL, tmax_at_hit=1)
    # A list for a repeatable option is that option repeated, not one value joined by commas.
    two = dacrt.render(CORNELL, point_light=["0.2,0.5,-0.2=1,1,1", "0.3,0.5,-0.2=1,0,0"], **SMALL)
    one = dacrt.render(CORNELL, point_light="0.2,0.5,-0.2=1,1,1", **SMALL)
    assert two.shape == one.shape and (two != one).any()
