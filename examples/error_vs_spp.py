"""strata from Python: render a scene, plot its error against spp for two samplers, show the
image. Run it from the repository after `pip install .[examples]`:

    python examples/error_vs_spp.py [SCENE] [--quick]

It writes error-vs-spp.png and SCENE-NAME.png in the current folder (and shows the figure when
there is a display).
"""

import sys
from pathlib import Path

import numpy as np

import strata

quick = "--quick" in sys.argv
paths = [a for a in sys.argv[1:] if not a.startswith("--")]
scene = strata.load(paths[0] if paths else Path(__file__).parents[1] / "scenes/cornell-box.toml")
size = (48, 48) if quick else (128, 128)
levels = [2, 4, 8, 16] if quick else [2, 4, 8, 16, 32, 64, 128]

# The calibrated relative error of the image mean, against spp, for two samplers (from 2 spp:
# a pixel's variance needs two samples): Sobol's falls faster than 1/sqrt(spp), the
# independent sampler's at that rate.
errors = {}
for sampler in ("independent", "sobol"):
    errors[sampler] = [
        strata.render(scene, sampler=sampler, spp=spp, size=size, progress=False).error
        for spp in levels
    ]
    print(sampler, " ".join(f"{e:.4f}" for e in errors[sampler]))

image = strata.render(scene, spp=levels[-1], size=size, progress=not quick)
print(f"{image.device}: {image.spp} spp in {image.seconds:.2f} s, error {100 * image.error:.2f} %")

import matplotlib

if quick:
    matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.5))
for sampler, errs in errors.items():
    left.loglog(levels, errs, "o-", label=sampler)
left.loglog(levels, errors["independent"][0] * np.sqrt(levels[0] / np.array(levels)), "k:",
           label="1/sqrt(spp)")
left.set_xlabel("samples per pixel")
left.set_ylabel("relative standard error of the image mean")
left.legend()
# The linear image, tone-mapped for display as the PNG writer does (clamp, sRGB curve).
linear = np.clip(image.image, 0.0, 1.0)
srgb = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
right.imshow(srgb)
right.set_axis_off()
fig.tight_layout()
fig.savefig("error-vs-spp.png", dpi=80)
image.write(f"{Path(str(scene.path)).stem}.png")
if not quick:
    plt.show()
