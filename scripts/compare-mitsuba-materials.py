#!/usr/bin/env python3
"""strata's materials against Mitsuba 3's: the image mean of one sphere under a constant white
environment, per material, rendered by both. Mitsuba is a measuring stick only, never a
dependency of strata or its tests. Setup (Debian 12):
    apt-get install libllvm19
    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba==3.9.1 numpy
    cargo build --release
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
        /tmp/mi/bin/python scripts/compare-mitsuba-materials.py [--spp 1024]
The scene: a unit sphere at the origin, a pinhole camera 4 away with a 40° vertical field of
view, 64x64 pixels, box filter, independent sampler, a constant environment of radiance 1 (a
symmetric image, so the renderers' handedness does not matter); for anisotropic roughness also
a large plate seen at 75° from its normal along x and along y. Path lengths match (Mitsuba's
max_depth counts the emitter vertex: strata's depth + 1). Each line prints both means, their
relative difference and its z-score against both standard errors (Mitsuba's from the spread of
its pixels' means over SEEDS seeds).

This compares image means only; per-pixel z-scores and textured / environment-lit objects are
still to come (issue 25, section 4). The anisotropic sphere is not like for like: Mitsuba orients
(alpha_u, alpha_v) along the sphere's dp/du, strata along the tangents of its shading frame
(docs/reference/scene-format.md), until strata has uv tangents; on the plate both are x and y.
"""
import argparse
import os
import sys
import tempfile

import numpy as np
import mitsuba as mi

from mitsuba_common import GOLD, sensor, strata_mean as parse_mean, strata_render

# (name, Mitsuba bsdf dictionary, strata material keys, strata max_depth, view): view None is
# the sphere; "x" or "y" a plate in the xy plane (normal +z) seen 75° from its normal along that
# axis through a 3° field of view, where both renderers orient (alpha_u, alpha_v) along (x, y).
MATERIALS = [
    (f"gold, alpha {a}",
     {"type": "roughconductor", "distribution": "ggx", "alpha": a,
      "eta": {"type": "rgb", "value": GOLD[0]}, "k": {"type": "rgb", "value": GOLD[1]}},
     f'type = "conductor"\neta = {GOLD[0]}\nk = {GOLD[1]}\nroughness = {a}', 1, None)
    for a in (0.05, 0.3, 0.6)
] + [
    ("gold, alpha (0.05, 0.4)",
     {"type": "roughconductor", "distribution": "ggx", "alpha_u": 0.05, "alpha_v": 0.4,
      "eta": {"type": "rgb", "value": GOLD[0]}, "k": {"type": "rgb", "value": GOLD[1]}},
     f'type = "conductor"\neta = {GOLD[0]}\nk = {GOLD[1]}\nroughness = [0.05, 0.4]', 1, None),
] + [
    (f"gold plate ({au}, {av}), along {view}",
     {"type": "roughconductor", "distribution": "ggx", "alpha_u": au, "alpha_v": av,
      "eta": {"type": "rgb", "value": GOLD[0]}, "k": {"type": "rgb", "value": GOLD[1]}},
     f'type = "conductor"\neta = {GOLD[0]}\nk = {GOLD[1]}\nroughness = [{au}, {av}]', 1, view)
    for view in ("x", "y") for (au, av) in ((0.05, 0.4), (0.4, 0.05))
] + [
    (f"rough glass 1.5, alpha {a}",
     {"type": "roughdielectric", "distribution": "ggx", "alpha": a, "int_ior": 1.5, "ext_ior": 1.0},
     f'type = "dielectric"\nior = 1.5\nroughness = {a}', 8, None)
    for a in (0.05, 0.3)
]


def camera(view):
    """(eye, up, fov, size) of the sphere's camera, or of the plate's seen along `view`."""
    if view is None:
        return [0, 0, 4], [0, 1, 0], 40, 64
    t = np.radians(75)
    eye = [np.sin(t) * 10, 0, np.cos(t) * 10] if view == "x" else [0, np.sin(t) * 10, np.cos(t) * 10]
    return [float(x) for x in eye], [0, 0, 1], 3, 32


def mitsuba_mean(bsdf, spp, depth, seeds, view):
    eye, up, fov, size = camera(view)
    if view is None:
        shape = {"type": "sphere", "radius": 1.0, "bsdf": bsdf}
    else:
        shape = {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([50, 50, 1]), "bsdf": bsdf}
    d = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth + 1},
        "sensor": sensor(eye, up, fov, size, spp),
        "emitter": {"type": "constant", "radiance": {"type": "rgb", "value": 1.0}},
        "shape": shape,
    }
    scene = mi.load_dict(d)
    means = [np.array(mi.render(scene, spp=spp, seed=s)).reshape(-1, 3).mean(0) for s in range(seeds)]
    means = np.array(means)
    return means.mean(0), means.std(0, ddof=1) / np.sqrt(seeds)


def strata_mean(material, spp, depth, tmp, view):
    eye, up, fov, size = camera(view)
    if view is None:
        shape = 'type = "sphere"\ncenter = [0, 0, 0]\nradius = 1'
    else:
        shape = 'type = "rectangle"\ncorner = [-50, -50, 0]\nedge_u = [100, 0, 0]\nedge_v = [0, 100, 0]'
    path = os.path.join(tmp, "scene.toml")
    with open(path, "w") as f:
        f.write(f"""[camera]
eye = {eye}
look_at = [0, 0, 0]
up = {up}
fov = {fov}

[film]
width = {size}
height = {size}

[render]
spp = {spp}
max_depth = {depth}
sampler = "independent"

[materials.m]
{material}

[[shapes]]
{shape}
material = "m"

[sky]
color = 1
""")
    return parse_mean(strata_render(path, os.path.join(tmp, "s.exr")))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--seeds", type=int, default=4)
    args = ap.parse_args()
    mi.set_variant("llvm_ad_rgb")
    print(f"{'material':34} {'channel':>7} {'Mitsuba':>9} {'strata':>9} {'strata/Mitsuba - 1':>19} {'z':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, bsdf, material, depth, view in MATERIALS:
            mm, ms = mitsuba_mean(bsdf, args.spp // args.seeds, depth, args.seeds, view)
            sm, ss = strata_mean(material, args.spp, depth, tmp, view)
            for c, channel in enumerate("RGB"):
                rel = sm[c] / mm[c] - 1
                z = (sm[c] - mm[c]) / np.hypot(ms[c], ss[c])
                print(f"{name:34} {channel:>7} {mm[c]:9.5f} {sm[c]:9.5f} {100 * rel:18.3f}% {z:6.1f}")
            sys.stdout.flush()


if __name__ == "__main__":
    main()
