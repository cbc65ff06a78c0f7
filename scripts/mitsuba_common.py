"""What scripts/compare-mitsuba-materials.py and compare-mitsuba-pixels.py share: where strata
is, the gold of both, and the pieces of a scene that both renderers must set up alike (a
pinhole camera with a box filter and independent samples, strata's command line and its
output). efficiency-ab.py reads EXRs with its `read_rgb`. Mitsuba is a measuring stick only,
never a dependency of strata or its tests.
"""
import os
import re
import subprocess

import numpy as np
import mitsuba as mi

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STRATA = os.path.join(ROOT, "target", "release", "strata")
# Gold's (eta, k) at R, G, B, as both renderers take it.
GOLD = ([0.143, 0.374, 1.442], [3.983, 2.385, 1.603])


def rgb(v):
    """A Mitsuba RGB value."""
    return {"type": "rgb", "value": v}


def sensor(eye, up, fov, size, spp):
    """Mitsuba's pinhole camera at `eye` looking at the origin with a `fov`-degree vertical
    field of view, `size` x `size` pixels, a box filter and independent samples: strata's
    `filter = "box"` and `sampler = "independent"`."""
    return {
        "type": "perspective", "fov": fov, "fov_axis": "y",
        "to_world": mi.ScalarTransform4f().look_at(origin=eye, target=[0, 0, 0], up=up),
        "film": {"type": "hdrfilm", "width": size, "height": size, "rfilter": {"type": "box"},
                 "pixel_format": "rgb"},
        "sampler": {"type": "independent", "sample_count": spp},
    }


def strata_render(scene, exr, *extra):
    """Render `scene` with strata's CPU reference into `exr`; its stdout and stderr."""
    out = subprocess.run([STRATA, "render", scene, "--device", "cpu", "-o", exr, *extra],
                         capture_output=True, text=True, check=True)
    return out.stdout + out.stderr


def strata_mean(text):
    """The image mean and its standard error from strata's closing `mean:` line."""
    m = re.search(r"^mean: (\S+) (\S+) (\S+) \(± (\S+) (\S+) (\S+)\)", text, re.M)
    v = [float(x) for x in m.groups()]
    return np.array(v[:3]), np.array(v[3:])


def read_rgb(exr):
    """An EXR's R, G, B channels as a height x width x 3 array."""
    bitmap = mi.Bitmap(exr)
    channels = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    data = np.array(bitmap)
    return np.stack([data[..., channels.index(c)] for c in "RGB"], axis=-1)
