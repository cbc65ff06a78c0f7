#!/usr/bin/env python3
"""Efficiency of two strata configurations side by side: 1 / (variance × seconds).

Renders SCENE with seeds 0 … S−1 under configuration A and configuration B, alternating which
goes first from seed to seed (this machine's speed drifts between runs), and prints for each the
median seconds of its render line, the variance of one render and the efficiency, then B's speed
and efficiency relative to A's.

The variance needs no reference image: two renders with different seeds are independent and
unbiased, so the mean over pixels and channels of (a − b)² / 2 over the pairs of seeds (0, 1),
(2, 3), … estimates one render's mean squared error. S must be even.

A configuration is a `strata` binary, optionally followed by `@NAME=VALUE` to set one environment
variable for its runs (for a measuring build that reads a parameter from the environment), e.g.
    /tmp/mi/bin/python scripts/efficiency-ab.py scenes/cornell-box.toml \\
        --a /tmp/strata-before --b target/release/strata --spp 64 --seeds 10
Extra `strata render` options go after `--`, e.g. `-- --size 128x128 --sampler stratified`.

Needs Python with numpy and Mitsuba 3 (to read OpenEXR; a measuring stick, not a strata
dependency): `python -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba numpy`.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")
from mitsuba_common import read_rgb  # noqa: E402 (after the variant is set)

RENDER_LINE = re.compile(r"^rendered .* in ([0-9.]+) s:", re.M)


def render(config, scene, seed, args, out):
    """(seconds from the render line, image) of one render under `config`."""
    binary, _, assignment = config.partition("@")
    env = dict(os.environ)
    if assignment:
        name, _, value = assignment.partition("=")
        env[name] = value
    command = [binary, "render", scene, "--spp", str(args.spp), "--seed", str(seed),
               "--device", args.device, "--output", out] + args.extra
    run = subprocess.run(command, env=env, capture_output=True, text=True)
    found = RENDER_LINE.search(run.stderr)
    if run.returncode != 0 or not found:
        sys.exit(f"{' '.join(command)} failed ({run.returncode}):\n{run.stderr}")
    return float(found.group(1)), read_rgb(out).astype(np.float64)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--a", required=True, help="configuration A: BINARY[@NAME=VALUE]")
    parser.add_argument("--b", required=True, help="configuration B: BINARY[@NAME=VALUE]")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--device", default="cpu")
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    args = parser.parse_args(argv[:cut])
    args.extra = argv[cut + 1:]
    if args.seeds < 2 or args.seeds % 2:
        sys.exit("--seeds must be even and at least 2: the variance comes from pairs of seeds")
    configs = [args.a, args.b]
    seconds = {c: [] for c in configs}
    images = {c: [] for c in configs}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "render.exr")
        for seed in range(args.seeds):
            for config in configs if seed % 2 == 0 else configs[::-1]:
                s, image = render(config, args.scene, seed, args, out)
                seconds[config].append(s)
                images[config].append(image)
    summary = {}
    for name, config in zip("AB", configs):
        im = images[config]
        variance = statistics.mean(
            float(((im[i] - im[i + 1]) ** 2).mean()) / 2 for i in range(0, len(im), 2))
        median = statistics.median(seconds[config])
        summary[config] = (median, variance)
        mean = statistics.mean(float(x.mean()) for x in im)
        print(f"{name} {config}: median {median:.3f} s, variance {variance:.4e}, "
              f"image mean {mean:.5f}, efficiency {1 / (variance * median):.4g}")
    (ta, va), (tb, vb) = summary[args.a], summary[args.b]
    ratios = [a / b for a, b in zip(seconds[args.a], seconds[args.b])]
    print(f"B against A: speed {statistics.median(ratios):.3f} (pairs {min(ratios):.2f}-"
          f"{max(ratios):.2f}), variance {vb / va:.4f}, efficiency {(va * ta) / (vb * tb):.3f}")


if __name__ == "__main__":
    main()
