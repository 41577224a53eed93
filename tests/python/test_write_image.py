# dacrt.write_image: a numpy image written in the format its name says, the bytes the CLI writes
# (a rendered image through the same view is the CLI's --preview), and its refusals.
import pathlib
import subprocess
import warnings

import numpy as np
import pytest

import dacrt
from conftest import CLI, CORNELL

SMALL = dict(width=16, height=12, spp=2)
ACES = "ACES 1.0 SDR-video (sRGB)"


def ramp(channels=3):
    image = np.linspace(-0.5, 3.0, 5 * 4 * channels, dtype=np.float32).reshape(5, 4, channels)
    if channels == 4:
        image[..., 3] = np.linspace(0.0, 1.0, 20).reshape(5, 4)
    return image


def test_a_render_through_a_view_is_the_cli_preview(tmp_path):
    preview = tmp_path / "cli.png"
    run = subprocess.run([CLI, "render", CORNELL, "--quiet", "--width", "16", "--height", "12",
                          "--spp", "2", "-o", str(tmp_path / "cli.exr"), "--preview",
                          str(preview), "--view", ACES, "--exposure", "1.5"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    image = dacrt.render(CORNELL, **SMALL)
    dacrt.write_image(tmp_path / "py.png", image, view=ACES, exposure=1.5)  # a pathlib.Path
    assert (tmp_path / "py.png").read_bytes() == preview.read_bytes()
    dacrt.write_image(str(tmp_path / "plain.png"), image)
    assert (tmp_path / "plain.png").read_bytes() != preview.read_bytes()


def test_each_format_by_its_extension(tmp_path):
    image = ramp()
    for name, magic in [("a.png", b"\x89PNG\r\n\x1a\n"), ("a.JPG", b"\xff\xd8\xff"),
                        ("a.jpeg", b"\xff\xd8\xff"), ("a.hdr", b"#?RADIANCE\n"),
                        ("a.exr", b"\x76\x2f\x31\x01")]:
        dacrt.write_image(tmp_path / name, image)
        assert (tmp_path / name).read_bytes().startswith(magic), name
    exr = dacrt.read_exr(tmp_path / "a.exr")
    assert sorted(exr) == ["B", "G", "R"]
    assert np.array_equal(np.stack([exr["R"], exr["G"], exr["B"]], axis=-1), image)
    # float64 is converted; the PNG's colour type is RGB (2) without alpha, RGBA (6) with it.
    dacrt.write_image(tmp_path / "d.png", image.astype(np.float64))
    assert (tmp_path / "d.png").read_bytes() == (tmp_path / "a.png").read_bytes()
    assert (tmp_path / "a.png").read_bytes()[25] == 2
    dacrt.write_image(tmp_path / "alpha.png", ramp(4))
    assert (tmp_path / "alpha.png").read_bytes()[25] == 6
    dacrt.write_image(tmp_path / "alpha.exr", ramp(4))
    assert np.array_equal(dacrt.read_exr(tmp_path / "alpha.exr")["A"], ramp(4)[..., 3])
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "a.JPG", "a.exr", "a.hdr", "a.jpeg", "a.png", "alpha.exr", "alpha.png", "d.png"]


def test_alpha_that_a_format_cannot_hold_is_a_warning(tmp_path):
    with pytest.warns(UserWarning, match="holds no alpha"):
        dacrt.write_image(tmp_path / "a.jpg", ramp(4))
    with pytest.warns(UserWarning, match="holds no alpha"):
        dacrt.write_image(tmp_path / "a.hdr", ramp(4))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        dacrt.write_image(tmp_path / "b.jpg", ramp(3))
    assert (tmp_path / "a.jpg").exists() and (tmp_path / "b.jpg").exists()


def test_refusals(tmp_path):
    with pytest.raises(ValueError, match=r"\.tif"):
        dacrt.write_image(tmp_path / "a.tif", ramp())
    with pytest.raises(ValueError, match="view="):
        dacrt.write_image(tmp_path / "a.hdr", ramp(), view="sRGB")
    with pytest.raises(ValueError, match="exposure="):
        dacrt.write_image(tmp_path / "a.exr", ramp(), exposure=1.0)
    with pytest.raises(ValueError, match="Nope"):
        dacrt.write_image(tmp_path / "a.png", ramp(), view="Nope")
    with pytest.raises(ValueError, match="shape"):
        dacrt.write_image(tmp_path / "a.png", np.zeros((4, 4), np.float32))
    with pytest.raises(ValueError, match="shape"):
        dacrt.write_image(tmp_path / "a.png", np.zeros((4, 4, 2), np.float32))
    with pytest.raises(TypeError, match="float"):
        dacrt.write_image(tmp_path / "a.png", np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(TypeError):
        dacrt.write_image(42, ramp())
    with pytest.raises(dacrt.Error, match="missing"):
        dacrt.write_image(tmp_path / "missing" / "a.png", ramp())
    assert list(tmp_path.iterdir()) == []
