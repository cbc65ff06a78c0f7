"""What the Python tests share: the repository, its scenes, the `strata` command built by
`cargo test` (the CLI the bindings are compared with) and the EXR reader."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
SCENES = REPO / "scenes"


def strata_command() -> Path:
    """The `strata` binary: $STRATA_BIN, else the one `cargo test` or `cargo build` left."""
    given = os.environ.get("STRATA_BIN")
    candidates = [Path(given)] if given else [
        REPO / "target" / "debug" / "strata",
        REPO / "target" / "release" / "strata",
    ]
    for path in candidates:
        if path.is_file():
            return path
    pytest.fail(
        "the strata command is not built: run `cargo build` (or set STRATA_BIN); "
        f"looked at {', '.join(map(str, candidates))}"
    )


def run_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Run `strata ARGS...` in the repository; its stderr is what it says."""
    done = subprocess.run(
        [str(strata_command()), *args], cwd=REPO, capture_output=True, text=True
    )
    if check and done.returncode != 0:
        raise AssertionError(f"strata {' '.join(args)} failed:\n{done.stderr}")
    return done


def read_exr(path: Path):
    """An EXR's (R, G, B) and (var.R, var.G, var.B) as H x W x 3 float32 arrays."""
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as f:
        channels = f.channels()
        rgb = np.stack([channels[c].pixels for c in "RGB"], axis=-1)
        var = np.stack([channels[f"var.{c}"].pixels for c in "RGB"], axis=-1)
    return rgb, var


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path
