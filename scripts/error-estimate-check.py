#!/usr/bin/env python3
"""How honest is strata's error estimate on a scene? (Issue 27, step 1.)

Renders the scene with S seeds per configuration (sampler × strategy × spp) and compares, render
by render, the error strata predicts (the mean over pixels and channels of the EXR's `var.*`, the
calibrated variance of each pixel's mean) with the expected error, estimated without a
reference from the spread across seeds: each pixel's unbiased sample variance over the S renders
is its expected squared error (the renderers are unbiased), and their mean over pixels and
channels is the expected MSE of one render.

For each configuration it prints the pooled ratio Σ predicted / Σ expected (1 when the estimate
is right on average) and the fraction of single renders whose predicted MSE is within 2× of the
expected one (what a user of one render's error line or of `--target-error` relies on), with the
spread of single predictions (min / median / max of predicted / expected).

The expected MSE is itself estimated from S renders: its relative standard error is about
√(2 / (S − 1)) for a smooth scene and larger where a few bright samples dominate, so use S ≥ 16.

Needs the `strata` binary (built with `cargo build --release`) and Python with numpy and
Mitsuba 3 (to read OpenEXR; a measuring stick, not a strata dependency):
    python -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba numpy
    /tmp/mi/bin/python scripts/error-estimate-check.py scenes/veach-mis.toml --seeds 16 \\
        --spp 16,64 --samplers sobol,stratified,independent --strategies mis --size 128x96
"""
import argparse
import itertools
import os
import subprocess
import sys
import tempfile

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def read(path):
    """(H, W, 3) means and (H, W, 3) calibrated variances of a strata EXR."""
    bitmap = mi.Bitmap(path)
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    a = np.array(bitmap, dtype=np.float64).reshape(bitmap.height(), bitmap.width(), -1)
    return a[..., [names.index(c) for c in "RGB"]], a[..., [names.index("var." + c) for c in "RGB"]]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--spp", default="64", help="comma-separated")
    parser.add_argument("--samplers", default="sobol,stratified,independent")
    parser.add_argument("--strategies", default="mis")
    parser.add_argument("--size", default=None, help="WxH")
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--strata", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "strata"))
    args = parser.parse_args()
    if args.seeds < 4:
        sys.exit("--seeds: at least 4 (16 or more to trust the expected MSE)")

    print(f"{args.scene}: {args.seeds} seeds per configuration; MSE = mean over pixels and channels")
    print("| sampler | strategy | spp | expected MSE per render | predicted MSE (min / median / max) | pooled Σ predicted / Σ expected | renders within 2× | predicted / expected (min / median / max) |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for sampler, strategy, spp in itertools.product(
            args.samplers.split(","), args.strategies.split(","), [int(s) for s in args.spp.split(",")]
        ):
            means, predicted = [], []
            for seed in range(args.seeds):
                out = os.path.join(tmp, f"{seed}.exr")
                command = [args.strata, "render", args.scene, "--seed", str(seed), "--spp", str(spp),
                           "--sampler", sampler, "--strategy", strategy, "--device", args.device, "-o", out]
                if args.size:
                    command += ["--size", args.size]
                subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                m, v = read(out)
                means.append(m)
                predicted.append(v.mean())
            means = np.stack(means)
            expected = means.var(axis=0, ddof=1).mean()
            predicted = np.array(predicted)
            ratio = predicted / expected
            within = np.mean((ratio >= 0.5) & (ratio <= 2.0))
            print(
                f"| {sampler} | {strategy} | {spp} | {expected:.4g} | {predicted.min():.3g} / {np.median(predicted):.3g} / {predicted.max():.3g} "
                f"| {predicted.sum() / (expected * args.seeds):.2f} | {round(within * args.seeds)} of {args.seeds} "
                f"| {ratio.min():.2f} / {np.median(ratio):.2f} / {ratio.max():.2f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
