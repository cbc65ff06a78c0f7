"""The example script runs (quickly) and writes its figure."""

import subprocess
import sys

from conftest import REPO


def test_the_example_renders_and_plots(tmp_path):
    done = subprocess.run(
        [sys.executable, str(REPO / "examples" / "error_vs_spp.py"), "--quick"],
        cwd=tmp_path, capture_output=True, text=True, timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "error-vs-spp.png").stat().st_size > 0
    assert (tmp_path / "cornell-box.png").stat().st_size > 0
    sobol = [float(e) for e in done.stdout.splitlines()[1].split()[1:]]
    assert sobol[-1] < sobol[0]
