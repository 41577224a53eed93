# The example in examples/ runs as its docstring says, and its numbers are sane: the samplers'
# error falls as samples double.
import os
import re
import subprocess
import sys

from conftest import CORNELL, SOURCE


def test_the_convergence_example_runs():
    run = subprocess.run([sys.executable, str(SOURCE / "examples" / "convergence.py"), CORNELL,
                          "--size", "24", "--max-spp", "8"],
                         capture_output=True, text=True, env=os.environ, timeout=300)
    assert run.returncode == 0, run.stderr
    slopes = [float(s) for s in re.findall(r"against log spp: (-?[0-9.]+)", run.stdout)]
    assert len(slopes) == 2 and all(s < -0.2 for s in slopes), run.stdout
