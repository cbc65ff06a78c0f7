#!/usr/bin/env python3
"""Error per second of strata against Mitsuba 3 on Mitsuba's own Cornell box, in one run.

Mitsuba is a measuring stick only, never a dependency of strata or its tests. Setup (Debian 12):

    apt-get install libllvm19
    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba==3.9.1 numpy
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
        /tmp/mi/bin/python scripts/compare-mitsuba.py [--spp 64] [--seeds 4]

Both renderers draw `mitsuba.cornell_box()` (strata: scenes/mitsuba/cornell-box.toml, generated
from that dictionary) at 256x256 with a box pixel filter and the same path length (Mitsuba
max_depth 8 = strata max_depth 7). The reference is the mean of a high-spp Mitsuba render and a
high-spp strata render; first the two are checked to agree per pixel (z-scores of their
difference against both variances: strata's calibrated variance, Mitsuba's from the spread of
independent seeds). Each configuration renders SPP samples per pixel with SEEDS seeds; its
error is the MSE against the reference, less the reference's own variance, averaged over
seeds; its time the median wall time of a render (Mitsuba after a warm-up render that compiles
its kernels; strata's render line less its kernel's compile). `--variant cuda_ad_rgb
--devices gpu` compares the two on an NVIDIA GPU. Efficiency is 1 / (MSE * seconds), printed relative to the
best.
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np
import mitsuba as mi

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "scenes", "mitsuba", "cornell-box.toml")
SIZE = 256


def mitsuba_scene(sampler, spp):
    d = mi.cornell_box()
    d["sensor"]["film"]["width"] = SIZE
    d["sensor"]["film"]["height"] = SIZE
    d["sensor"]["film"]["rfilter"] = {"type": "box"}
    d["sensor"]["sampler"] = {"type": sampler, "sample_count": spp}
    d["integrator"]["max_depth"] = 8
    return mi.load_dict(d)


def mitsuba_render(scene, spp, seed):
    start = time.perf_counter()
    image = np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)
    return image, time.perf_counter() - start


def exr_layer(path, layer):
    """The RGB of a strata EXR (`layer` "<root>": R, G, B) or its variance ("var": var.*)."""
    return np.array(dict(mi.Bitmap(path).split())[layer], dtype=np.float64)


def strata_render(strata, out, args):
    cmd = [strata, "render", SCENE, "-o", out] + args
    result = subprocess.run(cmd, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"strata failed: {' '.join(cmd)}\n{result.stderr}")
    seconds = float(re.search(r" in ([0-9.]+) s:", result.stderr).group(1))
    # Like Mitsuba's time after its warm-up render: without the kernel's compile, which a GPU
    # render's wall time holds (the `gpu:` line says how long it took).
    compiled = re.search(r"compiled in ([0-9.]+) s", result.stderr)
    if compiled:
        seconds -= float(compiled.group(1))
    device = result.stderr.splitlines()[0]
    return exr_layer(out, "<root>"), seconds, device


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--strata", default=os.path.join(ROOT, "target", "release", "strata"))
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--reference-spp", type=int, default=1024)
    parser.add_argument("--variant", default="llvm_ad_rgb",
                        help="Mitsuba's variant: llvm_ad_rgb (CPU) or cuda_ad_rgb (NVIDIA GPU)")
    parser.add_argument("--devices", default="cpu,cpu8,gpu",
                        help="strata's devices to measure: cpu (three samplers), cpu8 (the "
                             "eight-lane prototype, Sobol), gpu (Sobol)")
    parser.add_argument("--traversal", default="auto",
                        help="strata's --traversal for the gpu device: auto, bvh or ray-query")
    parser.add_argument("--reference-device", default="cpu",
                        help="strata's device for its half of the reference")
    args = parser.parse_args()
    mi.set_variant(args.variant)
    tmp = tempfile.mkdtemp(prefix="strata-mitsuba-")

    # ---- The reference, and whether the two renderers draw the same scene ---------------------
    ref_seeds = 16
    per = args.reference_spp // ref_seeds
    scene = mitsuba_scene("independent", per)
    mitsuba_render(scene, per, 0)  # compile
    runs = [mitsuba_render(scene, per, 1000 + s)[0] for s in range(ref_seeds)]
    mi_mean = np.mean(runs, axis=0)
    mi_var = np.var(runs, axis=0, ddof=1) / ref_seeds
    out = os.path.join(tmp, "reference.exr")
    st_mean, _, _ = strata_render(
        args.strata, out,
        ["--device", args.reference_device, "--spp", str(args.reference_spp), "--seed", "1000"])
    st_var = exr_layer(out, "var")
    z = (st_mean - mi_mean) / np.sqrt(st_var + mi_var + 1e-30)
    print(f"agreement: strata {args.reference_spp} spp vs Mitsuba {args.reference_spp} spp: "
          f"per-pixel z mean {z.mean():+.3f}, std {z.std():.3f} (1 if the scenes are the same); "
          f"image means {st_mean.mean():.5f} vs {mi_mean.mean():.5f}")
    reference = (st_mean + mi_mean) / 2
    ref_var = (st_var + mi_var).mean() / 4

    # ---- Every configuration -----------------------------------------------------------------
    rows = []

    def record(name, images, seconds):
        mse = statistics.mean(float(((im - reference) ** 2).mean()) - ref_var for im in images)
        rows.append((name, statistics.median(seconds), mse))
        print(f"  {name}: {statistics.median(seconds):.3g} s, MSE {mse:.3e}", flush=True)

    for sampler in ["independent", "multijitter", "orthogonal", "stratified"]:
        scene = mitsuba_scene(sampler, args.spp)
        mitsuba_render(scene, args.spp, 0)  # compile
        images, seconds = zip(*(mitsuba_render(scene, args.spp, s + 1) for s in range(args.seeds)))
        record(f"Mitsuba {mi.__version__} {args.variant} / {sampler}", images, seconds)
    devices = {}
    wanted = args.devices.split(",")
    for device, samplers in [("cpu", ["sobol", "stratified", "independent"]), ("cpu8", ["sobol"]),
                             ("gpu", ["sobol"])]:
        if device not in wanted:
            continue
        for sampler in samplers:
            images, seconds = [], []
            for s in range(args.seeds):
                out = os.path.join(tmp, f"{device}-{sampler}-{s}.exr")
                flags = ["--device", device, "--sampler", sampler, "--spp", str(args.spp),
                         "--seed", str(s + 1)]
                if device == "gpu":
                    flags += ["--traversal", args.traversal]
                image, t, line = strata_render(args.strata, out, flags)
                images.append(image)
                seconds.append(t)
                devices[device] = line
            record(f"strata {device} / {sampler} / mis", images, seconds)

    best = max(1 / (mse * t) for _, t, mse in rows)
    print(f"\n{SIZE}x{SIZE}, {args.spp} spp, {args.seeds} seeds, reference {args.reference_spp} spp "
          f"(strata + Mitsuba); {os.cpu_count()} cores")
    for device, line in devices.items():
        print(f"strata {device}: {line}")
    print("| renderer / sampler | seconds | MSE | efficiency 1/(MSE·s), relative to the best |")
    print("|---|---|---|---|")
    for name, t, mse in sorted(rows, key=lambda r: -1 / (r[2] * r[1])):
        print(f"| {name} | {t:.3g} | {mse:.3e} | {1 / (mse * t) / best:.3f} |")


if __name__ == "__main__":
    main()
