#!/usr/bin/env python3
"""Render Bitterli's veach-mis scene in Mitsuba 3 from strata's own conversion of it (a
`vm.toml` written by strata's pbrt import, with world-space binary PLY meshes), as a third
renderer's opinion next to strata and the Tungsten reference.

Mapping (strata -> Mitsuba 3):
  conductor (eta, k, roughness = alpha)  -> roughconductor, distribution --distribution, alpha,
                                            eta/k as rgb, specular_reflectance 1, sample_visible
  diffuse albedo                         -> diffuse reflectance
  emission (radiance)                    -> area emitter radiance on that shape
  camera eye / look_at / up / fov        -> perspective, look_at, fov_axis "y" (vertical fov)
  filter "tent" width 1                  -> hdrfilm rfilter tent radius 1 (pixels)
  render max_depth d                     -> path integrator max_depth d + 1 (Mitsuba counts the
                                            emitter vertex; as scripts/mitsuba_common.py)

    /tmp/mi/bin/python scripts/mitsuba-veach-mis.py /tmp/vm/vm.toml out.exr \
        --distribution ggx --spp 256 --size 320x180
"""
import argparse
import os
import time
import tomllib


def pick_variant(mi, want):
    if want.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ:
        for p in ("/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1", "/usr/lib/x86_64-linux-gnu/libLLVM-14.so.1"):
            if os.path.exists(p):
                os.environ["DRJIT_LIBLLVM_PATH"] = p
                break
    for v in (want, "scalar_rgb"):
        try:
            mi.set_variant(v)
            return v
        except Exception as e:  # noqa: BLE001
            print(f"variant {v} unavailable: {e}")
    raise SystemExit("no usable Mitsuba variant")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("toml", nargs="?", default="/tmp/vm/vm.toml")
    ap.add_argument("out", nargs="?", default="mitsuba-veach-mis.exr")
    ap.add_argument("--distribution", choices=["ggx", "beckmann"], default="ggx")
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--max-depth", type=int, default=None, help="strata's max_depth (default: the toml's)")
    ap.add_argument("--sampler", default="independent", choices=["independent", "multijitter"])
    ap.add_argument("--variant", default="scalar_rgb", help="llvm_ad_rgb crashed in LLVM 15 codegen on this machine")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--specular-reflectance", type=float, default=1.0,
                    help="experiment: conductors' specular_reflectance (Tungsten's 'albedo' factor)")
    ap.add_argument("--alpha-power", type=float, default=1.0,
                    help="experiment: alpha = roughness ** this (1: the toml's roughness is alpha, as strata reads it)")
    args = ap.parse_args()

    import mitsuba as mi
    variant = pick_variant(mi, args.variant)

    with open(args.toml, "rb") as f:
        cfg = tomllib.load(f)
    base = os.path.dirname(os.path.abspath(args.toml))
    w, h = (int(x) for x in args.size.lower().split("x"))
    cam, film = cfg["camera"], cfg.get("film", {})
    depth = args.max_depth if args.max_depth is not None else cfg["render"]["max_depth"]
    rgb = lambda v: {"type": "rgb", "value": [float(x) for x in v]}

    if film.get("filter", "box") == "tent":
        rfilter = {"type": "tent", "radius": float(film.get("filter_width", 1.0))}
    elif film.get("filter", "box") == "box":
        rfilter = {"type": "box"}
    else:
        raise SystemExit(f"filter {film['filter']} not mapped")

    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth + 1},
        "sensor": {
            "type": "perspective", "fov": float(cam["fov"]), "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=cam["eye"], target=cam["look_at"], up=cam["up"]),
            "film": {"type": "hdrfilm", "width": w, "height": h, "rfilter": rfilter, "pixel_format": "rgb"},
            "sampler": {"type": args.sampler, "sample_count": args.spp, "seed": args.seed},
        },
    }

    def bsdf(m):
        if m["type"] == "conductor":
            return {"type": "roughconductor", "distribution": args.distribution, "alpha": float(m["roughness"]) ** args.alpha_power,
                    "eta": rgb(m["eta"]), "k": rgb(m["k"]), "specular_reflectance": args.specular_reflectance, "sample_visible": True}
        if m["type"] == "diffuse":
            return {"type": "diffuse", "reflectance": rgb(m["albedo"])}
        raise SystemExit(f"material type {m['type']} not mapped")

    mats = cfg["materials"]
    for i, s in enumerate(cfg["shapes"]):
        m = mats[s["material"]]
        if s["type"] == "mesh":
            shape = {"type": "ply", "filename": os.path.join(base, s["file"]), "face_normals": False}
        elif s["type"] == "sphere":
            shape = {"type": "sphere", "center": [float(x) for x in s["center"]], "radius": float(s["radius"])}
        else:
            raise SystemExit(f"shape type {s['type']} not mapped")
        shape["bsdf"] = bsdf(m)
        if "emission" in m:
            shape["emitter"] = {"type": "area", "radiance": rgb(m["emission"])}
        scene[f"shape{i:03d}"] = shape

    t0 = time.time()
    sc = mi.load_dict(scene)
    img = mi.render(sc, spp=args.spp, seed=args.seed)
    mi.util.write_bitmap(args.out, img)
    import numpy as np
    a = np.array(img)
    print(f"{variant}, {args.distribution}, {w}x{h}, {args.spp} spp, strata depth {depth} (Mitsuba {depth + 1}), "
          f"alpha = roughness^{args.alpha_power}, specular_reflectance {args.specular_reflectance}, {rfilter['type']} filter, {args.sampler}: {time.time() - t0:.1f} s; wrote {args.out}")
    print("mean:", " ".join(f"{x:.5f}" for x in a[..., :3].reshape(-1, 3).mean(axis=0)))


if __name__ == "__main__":
    main()
