"""What a Python process keeps and how it stops: a loop of renders compiles its kernel once;
Ctrl-C raises KeyboardInterrupt promptly, leaves no torn file and the interpreter usable."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np

import strata
from conftest import SCENES, read_exr

SCENE = SCENES / "soft-shadow-line.toml"


def test_a_loop_of_renders_compiles_once():
    scene = strata.load(SCENE)
    films = [
        strata.render(scene, device="gpu", spp=2, size=(24, 16), seed=seed, progress=False)
        for seed in range(20)
    ]
    compiled = [f.stats["compile_seconds"] > 0 for f in films]
    # The first may find the kernel compiled by an earlier test of this process; none after.
    assert not any(compiled[1:]), compiled
    seconds = [f.seconds for f in films]
    print(f"20 renders: compiled {sum(compiled)}x, median {np.median(seconds):.3f} s each")
    assert len({f.image.tobytes() for f in films}) == 20, "the seeds gave the same image"


SCRIPT = textwrap.dedent(
    """
    import signal, sys, time
    import strata
    # Python's own Ctrl-C handler, even where this runs under a runner started in the
    # background (`nohup ... &`), whose SIGINT is ignored and inherited as ignored.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    first = strata.render({scene!r}, device="cpu", spp=2, size=(16, 16), progress=False)
    first.write("first.exr")
    try:
        strata.render({scene!r}, device="cpu", spp=1 << 16, size=(256, 256), progress=True)
    except KeyboardInterrupt:
        print("interrupted", time.monotonic(), flush=True)
        after = strata.render({scene!r}, device="cpu", spp=2, size=(16, 16), progress=False)
        print("after", after.spp, flush=True)
        raise
    """
)


def test_ctrl_c_raises_keyboard_interrupt_and_leaves_no_torn_file(tmp_path):
    script = tmp_path / "long.py"
    script.write_text(SCRIPT.format(scene=str(SCENE)))
    child = subprocess.Popen(
        [sys.executable, str(script)], cwd=tmp_path, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True, env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    # Wait until the long render reports progress (its bar's first redraw), then Ctrl-C.
    seen = ""
    while "samples" not in seen:
        char = child.stderr.read(1)
        assert char, f"the script ended before reporting progress: {seen}"
        seen += char
    sent = time.monotonic()
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=120)
    assert "Traceback" in err and "KeyboardInterrupt" in err, err
    assert child.returncode != 0
    lines = dict(line.split(" ", 1) for line in out.splitlines())
    latency = float(lines["interrupted"]) - sent
    print(f"KeyboardInterrupt {latency:.2f} s after SIGINT")
    assert lines["after"] == "2", out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["first.exr", "long.py"]
    assert read_exr(tmp_path / "first.exr")[0].shape == (16, 16, 3)
