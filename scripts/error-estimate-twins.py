#!/usr/bin/env python3
"""Where does a render's error live, and where must twin pixels be to calibrate it? (Issue 27.)

Renders a scene with S seeds per configuration as whole-render parts (`--part 0/1`, whose EXR
keeps the film's f64 sums and its twins' bit for bit) and reports, for each configuration:

* concentration: the share of the expected MSE (each pixel's variance across the S seeds, mean
  over channels) carried by the pixels of largest per-sample variance s²/N (top 0.05 %, 0.5 %,
  5 %), their true κ there (expected MSE over mean s²/N), and how many of strata's twins fall
  among them;
* strata's estimate as it is (the film's calibration recomputed from the sums: the pooled ratio
  Σ predicted / Σ expected and the renders within 2× of the expected MSE);
* the same estimator with other twin placements, simulated: a render with another seed is an
  independent randomization with the same sample indices, which is what a twin is, so seeds
  (2k, 2k+1) serve as each other's twins at any pixel. "uniform" is strata's layout (one pixel
  per 4×4 block), "+ peak K" adds the K pixels of largest s²/N of the render being calibrated.

Needs the `strata` binary (`cargo build --release`) and Python with numpy and OpenEXR (a
measuring stick, not a strata dependency):
    python -m venv /tmp/mi && /tmp/mi/bin/pip install numpy OpenEXR
    /tmp/mi/bin/python scripts/error-estimate-twins.py scenes/veach-mis.toml --seeds 16 \\
        --spp 64 --samplers sobol,stratified --peaks 64,256
Renders are kept in --work (default /tmp/strata-twins) and reused by later runs.
"""
import argparse
import itertools
import os
import subprocess
import sys

import numpy as np
import OpenEXR

M32 = 0xFFFFFFFF
TWINS_PER_CLASS = 32  # crates/film/src/lib.rs


def lowbias32(x):
    x ^= x >> 16
    x = (x * 0x7FEB352D) & M32
    x ^= x >> 15
    x = (x * 0x846CA68B) & M32
    return x ^ (x >> 16)


def hash_combine(h, v):
    return lowbias32(h ^ ((v + 0x9E3779B9 + ((h << 6) & M32) + (h >> 2)) & M32))


def twin_pixels(width, height):
    """Flat pixel indices of strata's twins (crates/film/src/twin.rs, TwinLayout)."""
    for block in (4, 2, 1):
        bx, by = -(-width // block), -(-height // block)
        if bx * by >= 256 or block == 1:
            break
    out = []
    for k in range(bx * by):
        x, y = k % bx, k // bx
        h = hash_combine(hash_combine(0x7E1AB10C, x), y)
        px = min(x * block + h % block, width - 1)
        py = min(y * block + (h // block) % block, height - 1)
        out.append(py * width + px)
    return np.array(out)


def f64(channels, name):
    hi = channels[name + ".hi"].pixels.astype(np.uint64)
    lo = channels[name + ".lo"].pixels.astype(np.uint64)
    return ((hi << np.uint64(32)) | lo).view(np.float64).reshape(-1)


def read_part(path):
    """Flat (pixels, 3) sums and sums of squares, counts, and the twins' sums when present."""
    f = OpenEXR.File(path, separate_channels=True)
    c = f.parts[0].channels
    film = {
        "sum": np.stack([f64(c, f"sum.{k}") for k in "RGB"], -1),
        "sq": np.stack([f64(c, f"sum_sq.{k}") for k in "RGB"], -1),
        "n": c["count"].pixels.astype(np.float64).reshape(-1),
        "shape": c["count"].pixels.shape,
    }
    if len(f.parts) > 1:
        t = f.parts[1].channels
        film["twin_sum"] = np.stack([f64(t, f"sum.{k}") for k in "RGB"], -1)
        film["twin_sq"] = np.stack([f64(t, f"sum_sq.{k}") for k in "RGB"], -1)
    return film


def variance_of_mean(s, q, n):
    n = n[:, None]
    m = s / n
    return np.maximum((q - n * m * m) / (n - 1), 0) / n


def calibrated(film, twins, other=None, mean_of_ratios=False):
    """strata's estimate (Film::variances): κ per class of twins by s²/N, times s²/N. The twins
    are at flat pixels `twins`, their sums from the film's own twins or from `other`."""
    v = variance_of_mean(film["sum"], film["sq"], film["n"])
    n = film["n"][twins][:, None]
    if other is None:
        ts, tq = film["twin_sum"], film["twin_sq"]
    else:
        ts, tq = other["sum"][twins], other["sq"][twins]
    num = ((film["sum"][twins] - ts) / n) ** 2 / 2
    den = (v[twins] + variance_of_mean(ts, tq, film["n"][twins])) / 2
    key = v[twins].mean(1)
    order = np.argsort(key, kind="stable")
    classes = max(len(key) // TWINS_PER_CLASS, 1)
    edges = np.array([key[order[c * len(key) // classes]] for c in range(1, classes)])
    cls = np.searchsorted(edges, key, side="right")
    if mean_of_ratios:
        # An alternative tried: each pair's own ratio, every pair weighing the same in its class.
        ok = den > 0
        r = np.where(ok, num / np.where(ok, den, 1), 0)
        count = np.array([ok[cls == c].sum(0) for c in range(classes)])
        kappa = np.array([r[cls == c].sum(0) for c in range(classes)]) / np.maximum(count, 1)
    else:
        film_kappa = num.sum(0) / np.maximum(den.sum(0), 1e-300)
        kappa = np.array([
            np.where(den[cls == c].sum(0) > 0, num[cls == c].sum(0) / np.maximum(den[cls == c].sum(0), 1e-300), film_kappa)
            for c in range(classes)
        ])
    return kappa[np.searchsorted(edges, v.mean(1), side="right")] * v


def summary(ratio):
    within = int(((ratio >= 0.5) & (ratio <= 2.0)).sum())
    return f"{ratio.mean():.2f} | {within} of {len(ratio)} | {ratio.min():.2f} / {np.median(ratio):.2f} / {ratio.max():.2f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scene")
    parser.add_argument("--seeds", type=int, default=16)
    parser.add_argument("--spp", default="64", help="comma-separated")
    parser.add_argument("--samplers", default="sobol,stratified")
    parser.add_argument("--strategies", default="mis")
    parser.add_argument("--peaks", default="64,256", help="extra twins at the pixels of largest s²/N, comma-separated counts")
    parser.add_argument("--size", default=None, help="WxH")
    parser.add_argument("--mean-of-ratios", action="store_true",
                        help="also an estimator tried and not kept: a class's κ as the mean of its pairs' ratios")
    parser.add_argument("--work", default="/tmp/strata-twins")
    parser.add_argument("--strata", default=os.path.join(os.path.dirname(__file__), "..", "target", "release", "strata"))
    args = parser.parse_args()
    if args.seeds < 4 or args.seeds % 2:
        sys.exit("--seeds: an even number, at least 4 (16 or more to trust the expected MSE)")
    os.makedirs(args.work, exist_ok=True)
    name = os.path.basename(os.path.dirname(args.scene)) + "-" + os.path.basename(args.scene).split(".")[0]
    peaks = [int(k) for k in args.peaks.split(",") if k]

    print(f"{args.scene}: {args.seeds} seeds per configuration")
    for sampler, strategy, spp in itertools.product(
        args.samplers.split(","), args.strategies.split(","), [int(s) for s in args.spp.split(",")]
    ):
        films = []
        for seed in range(args.seeds):
            out = os.path.join(args.work, f"{name}-{sampler}-{strategy}-{spp}-{args.size}-{seed}.exr")
            if not os.path.exists(out):
                command = [args.strata, "render", args.scene, "--seed", str(seed), "--spp", str(spp),
                           "--sampler", sampler, "--strategy", strategy, "--device", "cpu",
                           "--part", "0/1", "-o", out]
                if args.size:
                    command += ["--size", args.size]
                subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            films.append(read_part(out))
        height, width = films[0]["shape"]
        means = np.stack([f["sum"] / f["n"][:, None] for f in films])
        expected_pixel = means.var(axis=0, ddof=1).mean(1)
        expected = expected_pixel.mean()
        v_mean = np.stack([variance_of_mean(f["sum"], f["sq"], f["n"]).mean(1) for f in films]).mean(0)
        uniform = twin_pixels(width, height)
        is_twin = np.zeros(width * height, bool)
        is_twin[uniform] = True
        print(f"\n### {sampler} / {strategy}, {spp} spp, {width}×{height}: expected MSE per render {expected:.4g}\n")
        print("| pixels by s²/N | share of the expected MSE | true κ there | strata's twins among them |")
        print("|---|---|---|---|")
        order = np.argsort(-v_mean)
        for frac in (0.0005, 0.005, 0.05):
            top = order[: max(1, int(frac * len(order)))]
            share = expected_pixel[top].sum() / expected_pixel.sum()
            kappa = expected_pixel[top].sum() / max(v_mean[top].sum(), 1e-300)
            print(f"| top {frac * 100:g} % ({len(top)}) | {share * 100:.1f} % | {kappa:.3g} | {is_twin[top].sum()} |")
        print("\n| twins | pooled Σ predicted / Σ expected | renders within 2× | predicted / expected (min / median / max) |")
        print("|---|---|---|---|")
        if "twin_sum" in films[0]:
            ratio = np.array([calibrated(f, uniform).mean() for f in films]) / expected
            print(f"| strata's own (rendered) | {summary(ratio)} |")
            if args.mean_of_ratios:
                ratio = np.array([calibrated(f, uniform, mean_of_ratios=True).mean() for f in films]) / expected
                print(f"| strata's own, κ as the mean of the pairs' ratios | {summary(ratio)} |")
        else:
            # The independent sampler: strata's estimate is the per-sample variance (κ = 1).
            ratio = np.array([variance_of_mean(f["sum"], f["sq"], f["n"]).mean() for f in films]) / expected
            print(f"| none: the per-sample variance, as strata uses it | {summary(ratio)} |")
            continue
        placements = [("uniform, simulated", 0)] + [(f"uniform + peak {k}, simulated", k) for k in peaks]
        for label, k in placements:
            ratio = []
            for a, film in enumerate(films):
                twins = uniform
                if k:
                    v = variance_of_mean(film["sum"], film["sq"], film["n"]).mean(1)
                    twins = np.union1d(uniform, np.argsort(-v, kind="stable")[:k])
                ratio.append(calibrated(film, twins, films[a ^ 1]).mean() / expected)
            print(f"| {label} | {summary(np.array(ratio))} |", flush=True)


if __name__ == "__main__":
    main()
