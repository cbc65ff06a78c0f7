#!/usr/bin/env python3
"""The differential check: a scene rendered by strata and by Mitsuba 3 from strata's export of
it (`strata convert SCENE -o scene.xml`), at the same size, path depth and samples, SEEDS seeds
each, compared pixel by pixel against both renderers' variance.

Per pixel and channel: the z-score of the difference of the two means, each mean's standard
error from the spread of its renderer's seeds. Where the two compute the same image the z-scores
follow Student's t with between SEEDS - 1 and 2 (SEEDS - 1) degrees of freedom (Welch's; 2 (SEEDS
- 1) when both spreads are equal): mean 0, standard deviation sqrt(nu / (nu - 2)) (1.08 to 1.18
at 8 seeds). Also: the image means' ratio (strata / Mitsuba - 1, with
its standard error), and the regions that disagree: the image cut into 8 x 8 blocks, each
block's mean ratio and its z-score; blocks beyond 5 are listed (rows and columns as percentages
of the image, from the top left).

Mitsuba is a measuring stick only, never a dependency of strata or its tests. Setup (Debian 12):
    apt-get install libllvm19
    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba==3.9.1 numpy
    cargo build --release
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
        /tmp/mi/bin/python scripts/mitsuba-diff.py scenes/cornell-box.toml --spp 64 --seeds 8

Several scenes may be given; a Markdown table (docs/measurements/mitsuba-diff.md) follows the
details, one row per scene. Writes
OUT/strata.exr and OUT/mitsuba.exr (the means over the seeds) and OUT/z.exr (the z-scores).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

from mitsuba_common import STRATA, read_rgb

BLOCKS = 8


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--size", help="WxH (default: the scene's, times --scale)")
    ap.add_argument("--scale", type=float, default=1.0, help="of the scene's own size, when --size is not given")
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--max-depth", type=int, help="strata's (default: the scene's)")
    ap.add_argument("--out", default=None, help="folder for the export and images (default /tmp/mitsuba-diff/NAME; with several scenes, a folder per scene in it)")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--integrator", default="path", help="Mitsuba's integrator for the export: path (as written) or another, e.g. volpath")
    ap.add_argument("--strata-args", default="", help="more arguments for strata render, e.g. '--strategy bsdf'")
    return ap.parse_args()


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{out.stdout}{out.stderr}")
    return out.stdout + out.stderr


def strata_renders(args, scene, size, out):
    """SEEDS renders by strata's CPU reference; the images and the seconds each took."""
    images, seconds = [], []
    extra = args.strata_args.split() + ["--size", size]
    if args.max_depth is not None:
        extra += ["--max-depth", str(args.max_depth)]
    for seed in range(args.seeds):
        exr = os.path.join(out, f"strata-{seed}.exr")
        t0 = time.time()
        run([STRATA, "render", scene, "--device", "cpu", "--spp", str(args.spp),
             "--seed", str(seed), "-o", exr, *extra])
        seconds.append(time.time() - t0)
        images.append(exr)
    return images, seconds


def mitsuba_renders(mi, args, xml, shape):
    """SEEDS renders by Mitsuba of strata's export, at strata's size and depth."""
    params = {"spp": args.spp, "resx": shape[1], "resy": shape[0]}
    if args.max_depth is not None:
        params["max_depth"] = args.max_depth + 1
    if args.integrator != "path":
        # The export writes Mitsuba's `path`; another integrator (volpath) for a second opinion.
        text = open(xml).read().replace('<integrator type="path"', '<integrator type="%s"' % args.integrator)
        xml = xml.replace(".xml", "-%s.xml" % args.integrator)
        open(xml, "w").write(text)
    scene = mi.load_file(xml, **params)
    images, seconds = [], []
    for seed in range(args.seeds):
        t0 = time.time()
        img = mi.render(scene, spp=args.spp, seed=seed + 1)
        images.append(np.array(img, dtype=np.float64)[..., :3])
        seconds.append(time.time() - t0)
    return images, seconds


def blocks(a, n=BLOCKS):
    """The mean of each of n x n blocks of a height x width x channels array."""
    h, w = a.shape[:2]
    ys = np.linspace(0, h, n + 1).astype(int)
    xs = np.linspace(0, w, n + 1).astype(int)
    return np.array([[a[ys[i]:ys[i + 1], xs[j]:xs[j + 1]].mean(axis=(0, 1)) for j in range(n)] for i in range(n)])


def rounding(a, b):
    """f32 rounding of two means (2 ulps of the larger), added to their standard error: values
    both renderers compute without noise (a furnace's sky) differ by that much, not by their
    zero variance."""
    return 2.4e-7 * np.maximum(np.abs(a), np.abs(b))


def compare(s, m):
    """The statistics of two stacks of seeds' images (seeds x h x w x 3)."""
    k = s.shape[0]
    ms, mm = s.mean(0), m.mean(0)
    se2 = s.var(0, ddof=1) / k + m.var(0, ddof=1) / k + rounding(ms, mm) ** 2
    ok = se2 > 0
    z = np.zeros_like(ms)
    z[ok] = (ms - mm)[ok] / np.sqrt(se2[ok])
    # Image means, per channel, with the standard error of their ratio from the seeds' means.
    mean_s, mean_m = s.mean(axis=(1, 2)), m.mean(axis=(1, 2))
    ratio = mean_s.mean(0) / mean_m.mean(0) - 1
    ratio_se = np.sqrt(mean_s.var(0, ddof=1) / k / mean_s.mean(0) ** 2 + mean_m.var(0, ddof=1) / k / mean_m.mean(0) ** 2) * (1 + ratio)
    # Blocks: mean ratio and z-score from the seeds' block means.
    bs = np.array([blocks(x.sum(-1, keepdims=True))[..., 0] for x in s])
    bm = np.array([blocks(x.sum(-1, keepdims=True))[..., 0] for x in m])
    bse = np.sqrt(bs.var(0, ddof=1) / k + bm.var(0, ddof=1) / k + rounding(bs.mean(0), bm.mean(0)) ** 2)
    bz = np.where(bse > 0, (bs.mean(0) - bm.mean(0)) / np.where(bse > 0, bse, 1), 0)
    bratio = np.where(bm.mean(0) > 0, bs.mean(0) / np.where(bm.mean(0) > 0, bm.mean(0), 1) - 1, 0)
    return dict(z=z, ok=ok, ratio=ratio, ratio_se=ratio_se, bz=bz, bratio=bratio, ms=ms, mm=mm)


def scene_size(xml, scale):
    """The export's own film size, times `scale`, as WxH."""
    text = open(xml).read()
    w, h = (int(re.search(f'<default name="{k}" value="(\\d+)"', text).group(1)) for k in ("resx", "resy"))
    return f"{max(1, round(w * scale))}x{max(1, round(h * scale))}"


def check(mi, args, scene, out):
    """One scene: export, render both, compare; prints the details and returns the table row."""
    name = os.path.splitext(os.path.basename(scene))[0]
    os.makedirs(out, exist_ok=True)
    xml = os.path.join(out, "scene.xml")
    convert_log = run([STRATA, "convert", scene, "-o", xml])
    warnings = [l for l in convert_log.splitlines() if l.startswith("warning: Mitsuba:")]
    size = args.size or scene_size(xml, args.scale)
    s_files, s_sec = strata_renders(args, scene, size, out)
    s = np.array([read_rgb(f) for f in s_files], dtype=np.float64)
    m_images, m_sec = mitsuba_renders(mi, args, xml, s.shape[1:3])
    m = np.array(m_images)
    r = compare(s, m)
    z = r["z"][r["ok"]]
    for path, img in (("strata.exr", r["ms"]), ("mitsuba.exr", r["mm"]), ("z.exr", r["z"])):
        mi.util.write_bitmap(os.path.join(out, path), img.astype(np.float32), write_async=False)
    nu = 2 * (args.seeds - 1)
    print(f"{scene}: {size}, {args.spp} spp x {args.seeds} seeds; "
          f"strata {np.median(s_sec):.2f} s, Mitsuba ({args.variant}) {np.median(m_sec):.2f} s per render (medians)")
    for w in warnings:
        print("  " + w)
    print(f"  z-scores: mean {z.mean():+.3f}, standard deviation {z.std():.3f} (expected {np.sqrt(nu / (nu - 2)):.3f}), "
          f"|z| > 5: {np.mean(np.abs(z) > 5) * 100:.3f} % of {z.size} values")
    print("  image mean strata / Mitsuba - 1 (R, G, B): " + ", ".join(
        f"{x * 100:+.2f} ± {e * 100:.2f} %" for x, e in zip(r["ratio"], r["ratio_se"])))
    bad = [(i, j) for i in range(BLOCKS) for j in range(BLOCKS) if abs(r["bz"][i, j]) > 5]
    for i, j in sorted(bad, key=lambda ij: -abs(r["bz"][ij]))[:10]:
        print(f"  block rows {100 * i // BLOCKS}-{100 * (i + 1) // BLOCKS} %, columns {100 * j // BLOCKS}-{100 * (j + 1) // BLOCKS} %: "
              f"{r['bratio'][i, j] * 100:+.1f} % (z {r['bz'][i, j]:+.1f})")
    sys.stdout.flush()
    with open(os.path.join(out, "summary.json"), "w") as f:
        json.dump(dict(scene=scene, z_mean=float(z.mean()), z_sd=float(z.std()), ratio=r["ratio"].tolist(),
                       ratio_se=r["ratio_se"].tolist(), blocks_beyond_5=len(bad), warnings=warnings), f, indent=1)
    return (f"| {scene} | {size.replace('x', '×')} | {z.mean():+.3f} | {z.std():.3f} | "
            + ", ".join(f"{x * 100:+.2f}" for x in r["ratio"]) + f" (± {max(r['ratio_se']) * 100:.2f}) | "
            f"{len(bad)} of {BLOCKS * BLOCKS} | {len(warnings)} |")


def unique_name(scene, scenes):
    """`scene`'s file name without its extension, with as many of its folders before it as
    tell it from the other `scenes` (Bitterli's are all `scene-v4.pbrt`)."""
    parts = os.path.normpath(os.path.splitext(scene)[0]).split(os.sep)
    for n in range(1, len(parts) + 1):
        name = "-".join(parts[-n:])
        others = [o for o in scenes if o != scene]
        if all("-".join(os.path.normpath(os.path.splitext(o)[0]).split(os.sep)[-n:]) != name for o in others):
            return name
    return "-".join(parts)


def main():
    args = parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)
    rows = []
    for scene in args.scenes:
        name = unique_name(scene, args.scenes)
        if args.out is None:
            out = os.path.join("/tmp/mitsuba-diff", name)
        else:
            out = args.out if len(args.scenes) == 1 else os.path.join(args.out, name)
        try:
            rows.append(check(mi, args, scene, out))
        except (SystemExit, Exception) as e:  # noqa: BLE001 - one scene's failure is a row
            print(f"{scene}: {e}")
            rows.append(f"| {scene} | failed: {str(e).splitlines()[-1] if str(e) else e!r} | | | | | |")
    print(f"\n{args.spp} spp, {args.seeds} seeds each; z: mean and standard deviation of the per-pixel z-scores "
          f"(expected 0 and {np.sqrt(2 * (args.seeds - 1) / (2 * (args.seeds - 1) - 2)):.3f})\n")
    print("| scene | size | z mean | z sd | image mean strata / Mitsuba − 1, % (R, G, B) | blocks beyond 5σ | warnings |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        print(row)


if __name__ == "__main__":
    main()
    sys.stdout.flush()
    # Dr.Jit's LLVM thread pool can hang the interpreter's exit; nothing is left to do.
    os._exit(0)
