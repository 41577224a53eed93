# Where the tests find the module, the CLI and the scenes: ctest sets PYTHONPATH to the build
# tree's python/ folder, DACRT_CLI to the CLI and DACRT_SOURCE_DIR to the source tree.
import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("DACRT_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
CLI = os.environ.get("DACRT_CLI", str(SOURCE / "build" / "dacrt"))
CORNELL = str(SOURCE / "scenes" / "cornell-box.gltf")


@pytest.fixture
def cornell():
    import dacrt

    return dacrt.load(CORNELL)
