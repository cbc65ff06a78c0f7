#!/usr/bin/env python3
"""Compare a strata render with a reference image of the same scene from another renderer
(e.g. the Tungsten renders that come with Benedikt Bitterli's scenes): the image mean ratio per
channel, with its z from strata's own error estimate, and a per-block comparison.

The reference is block-averaged down to strata's resolution when it is an integer multiple of
it (a render at W×H with strata's default box filter integrates each pixel's footprint, which is
the mean of the reference's sub-pixels there). Blocks: the image cut into a `--blocks` ×
`--blocks` grid; each block's luminance ratio strata / reference.

Reads OpenEXR through Mitsuba 3's Bitmap (a measuring stick, not a strata dependency):
    python -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba numpy
    /tmp/mi/bin/python scripts/compare-reference.py render.exr TungstenRender.exr --blocks 16
"""
import argparse
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_rgb")


def read(path):
    """The image as a float64 array (H, W, channels), and its channel names."""
    bitmap = mi.Bitmap(path)
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    return np.array(bitmap, dtype=np.float64).reshape(bitmap.height(), bitmap.width(), -1), names


def block_mean(img, fy, fx):
    h, w, c = img.shape
    return img.reshape(h // fy, fy, w // fx, fx, c).mean(axis=(1, 3))


def block_mean_nan(img, fy, fx):
    h, w, c = img.shape
    return np.nanmean(img.reshape(h // fy, fy, w // fx, fx, c), axis=(1, 3))


def luminance(rgb):
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("strata")
    parser.add_argument("reference")
    parser.add_argument("--blocks", type=int, default=16)
    parser.add_argument("--name", default="")
    args = parser.parse_args()

    ours, names = read(args.strata)
    ref, _ = read(args.reference)
    rgb = ours[..., :3]
    var = ours[..., 3:6] if "var.R" in names else None
    ref = ref[..., :3]
    (h, w), (rh, rw) = rgb.shape[:2], ref.shape[:2]
    if rh % h or rw % w or rh // h != rw // w:
        sys.exit(f"reference {rw}×{rh} is not an integer multiple of {w}×{h}")
    bad = ~np.isfinite(ref).all(axis=2)
    if bad.any():
        # A half-float reference can hold infinities (overflowed texels): left out, and said.
        print(f"reference: {bad.sum()} non-finite pixels left out of the comparison")
        ref[bad] = np.nan
    ref = block_mean_nan(ref, rh // h, rw // w)
    keep = np.isfinite(ref).all(axis=2)
    rgb = np.where(keep[..., None], rgb, np.nan)
    if var is not None:
        var = np.where(keep[..., None], var, np.nan)

    mean, ref_mean = np.nanmean(rgb, axis=(0, 1)), np.nanmean(ref, axis=(0, 1))
    ratio = mean / ref_mean
    line = f"{args.name or args.strata}: {w}×{h}; image mean strata {mean.round(5)} reference {ref_mean.round(5)}; ratio − 1 = {np.round((ratio - 1) * 100, 3)} %"
    if var is not None:
        stderr = np.sqrt(np.nansum(var, axis=(0, 1))) / keep.sum()
        line += f" (strata's own standard error {np.round(stderr / mean * 100, 3)} %)"
    print(line)

    b = args.blocks
    by, bx = h // b, w // b
    ours_b = block_mean_nan(rgb[: by * b, : bx * b], by, bx)
    ref_b = block_mean_nan(ref[: by * b, : bx * b], by, bx)
    lo, lr = luminance(ours_b), luminance(ref_b)
    lit = np.isfinite(lr) & (lr > 1e-3 * np.nanmax(lr))
    r = lo[lit] / lr[lit] - 1
    print(
        f"  {b}×{b} blocks ({lit.sum()} lit): luminance ratio − 1: median |·| {np.median(np.abs(r)) * 100:.2f} %, "
        f"within 2 %: {np.mean(np.abs(r) < 0.02) * 100:.0f} %, within 5 %: {np.mean(np.abs(r) < 0.05) * 100:.0f} %, "
        f"range {r.min() * 100:+.1f} … {r.max() * 100:+.1f} %"
    )
    worst = np.argsort(-np.abs(lo / np.maximum(lr, 1e-12) - 1) * lit, axis=None)[:3]
    for k in worst:
        y, x = divmod(int(k), b)
        print(f"  worst block (row {y}, column {x}): strata {lo[y, x]:.4f} reference {lr[y, x]:.4f}")


if __name__ == "__main__":
    main()
