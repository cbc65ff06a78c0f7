#!/usr/bin/env python3
"""Write scenes/maps/studio.pfm, the environment map of scenes/environment.toml: 128 x 64
texels, latitude-longitude as strata and Mitsuba 3 read it (top row up, +y; centre column
towards -z). A blue sky brightening to a warm horizon, a dark ground, two white softboxes and a
small sun (2 x 2 texels, radiance 4000 warm white) that carries most of the light: the case that
importance sampling is for. Pure Python, no dependencies; the output is deterministic.
    python3 scripts/make-environment.py
"""
import math
import os
import struct

W, H = 128, 64
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "scenes", "maps", "studio.pfm")


def radiance(i, j):
    u, v = (i + 0.5) / W, (j + 0.5) / H
    theta, phi = math.pi * v, 2 * math.pi * u
    elevation = 0.5 * math.pi - theta
    if elevation < 0:
        # Ground: dark warm grey, darker away from the horizon.
        g = 0.08 + 0.07 * math.exp(8 * elevation)
        rgb = [g * 1.1, g, g * 0.85]
    else:
        t = math.sin(elevation)
        horizon, zenith = [1.0, 0.85, 0.65], [0.25, 0.45, 0.95]
        rgb = [h + (z - h) * t ** 0.6 for h, z in zip(horizon, zenith)]
    # Softboxes: 20 x 12 degree panels at elevation 20, azimuths 60 and 220 degrees.
    for centre in (60, 220):
        dphi = (math.degrees(phi) - centre + 180) % 360 - 180
        if abs(dphi) < 10 and abs(math.degrees(elevation) - 20) < 6:
            rgb = [12.0, 12.0, 12.0]
    # Sun: 2 x 2 texels at elevation ~39, azimuth ~140 degrees.
    if i in (50, 51) and j in (17, 18):
        rgb = [4000.0, 3600.0, 3000.0]
    return rgb


def main():
    rows = [[radiance(i, j) for i in range(W)] for j in range(H)]
    data = bytearray(f"PF\n{W} {H}\n-1.0\n".encode())
    for row in reversed(rows):  # PFM rows go from the bottom up
        for rgb in row:
            data += struct.pack("<3f", *rgb)
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    with open(OUT, "wb") as f:
        f.write(data)
    print(f"wrote {OUT}: {W}x{H}")


if __name__ == "__main__":
    main()
