#!/bin/sh
# `pip install .` as docs/library.md gives it, in a new virtual environment in WORK, offline
# (PIP_NO_INDEX: nothing is downloaded), then `import dacrt` from another folder: the package
# found in the environment, with the library it carries, renders.
#   pip_check.sh SOURCE WORK [BUILD]
# BUILD (DACRT_BUILD_DIR): a configured build tree whose module and library are reused, so that
# the check does not compile the library a second time (a fresh build takes many minutes).
set -eu
source=$1 work=$2
[ $# -ge 3 ] && export DACRT_BUILD_DIR="$3"
export PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1
rm -rf "$work"
mkdir -p "$work/elsewhere"
cd "$work"
# The documented commands (docs/library.md), with the source tree for `.`:
/usr/bin/python3 -m venv --system-site-packages .venv
.venv/bin/pip install --no-build-isolation "$source"
cd "$work/elsewhere"
"$work/.venv/bin/python" -c '
import importlib.metadata, pathlib, sys
import dacrt
here = pathlib.Path(sys.argv[1])
assert pathlib.Path(dacrt.__file__).is_relative_to(here / ".venv"), dacrt.__file__
assert importlib.metadata.version("dacrt") == dacrt.__version__, dacrt.__version__
# The library the module loaded is the one the package carries, beside it.
libraries = {line.split()[-1] for line in open("/proc/self/maps") if "libdacrt" in line}
assert libraries == {str(pathlib.Path(dacrt._dacrt.__file__).resolve().parent / "libdacrt.so")}, \
    libraries
assert (pathlib.Path(dacrt.__file__).parent / "py.typed").exists()
image = dacrt.render(sys.argv[2], spp=1, width=8, height=8, progress=False)
assert image.shape == (8, 8, 3) and image.mean() > 0
print("pip check: dacrt", dacrt.__version__, "from", dacrt.__file__)
' "$work" "$source/scenes/cornell-box.gltf"
