#!/usr/bin/env python3
"""Write scenes/maps/studio.pfm, the environment map of scenes/environment.toml: 128 x 64
texels, latitude-longitude as strata and Mitsuba 3 read it (top row up, +y; centre column
towards -z). A blue sky brightening to a warm horizon, a dark ground, two white softboxes and a
small sun (2 x 2 texels, radiance 4000 warm white) that carries most of the light: the case that
importance sampling is for.

Also scenes/maps/studio-octahedral.pfm, the same studio in pbrt-v4's equal-area octahedral
layout (128 x 128, z up: the image's centre looks up), for scenes/environment-octahedral.toml:
each texel the mean of 8 x 8 lookups of the latitude-longitude map (bilinear, as strata reads
it) inside it, so the two maps carry the same light to within the resampling. Pure Python, no dependencies; the
output is deterministic.
    python3 scripts/make-environment.py
"""
import math
import os
import struct

W, H = 128, 64
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "scenes", "maps", "studio.pfm")
OCTAHEDRAL = os.path.join(ROOT, "scenes", "maps", "studio-octahedral.pfm")
N, SUB = 128, 8


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


def square_to_sphere(px, py):
    """Clarberg's equal-area map, as pbrt-v4 (and strata's warp::equal_area) define it."""
    u, v = 2 * px - 1, 2 * py - 1
    up, vp = abs(u), abs(v)
    sd = 1 - (up + vp)
    r = 1 - abs(sd)
    phi = (1 if r == 0 else (vp - up) / r + 1) * math.pi / 4
    z = math.copysign(1 - r * r, sd)
    s = r * math.sqrt(max(2 - r * r, 0))
    return (math.copysign(math.cos(phi), u) * s, math.copysign(math.sin(phi), v) * s, z)


def lookup(rows, u, v):
    """strata's (and Mitsuba 3's) bilinear lookup of the latitude-longitude map at (u, v):
    x = u W - 1/2 wrapping around, y = v (H - 1)."""
    x, y = u * W - 0.5, v * (H - 1)
    x0, y0 = math.floor(x), math.floor(y)
    fx, fy = x - x0, y - y0
    c0, c1 = x0 % W, (x0 + 1) % W
    r0 = min(y0, H - 1)
    r1 = min(r0 + 1, H - 1)
    top = [a * (1 - fx) + b * fx for a, b in zip(rows[r0][c0], rows[r0][c1])]
    bottom = [a * (1 - fx) + b * fx for a, b in zip(rows[r1][c0], rows[r1][c1])]
    return [t * (1 - fy) + b * fy for t, b in zip(top, bottom)]


def octahedral(rows):
    """The studio in the octahedral layout, z up: the scene turns it with rotate = [-90, ...],
    which takes the map's (x, y, z) to (x, z, -y) in the latitude-longitude map's frame."""
    out = []
    for j in range(N):
        row = []
        for i in range(N):
            acc = [0.0, 0.0, 0.0]
            for b in range(SUB):
                for a in range(SUB):
                    x, y, z = square_to_sphere((i + (a + 0.5) / SUB) / N, (j + (b + 0.5) / SUB) / N)
                    dx, dy, dz = x, z, -y
                    u = (math.atan2(dx, -dz) / (2 * math.pi)) % 1.0
                    v = math.acos(max(-1.0, min(1.0, dy))) / math.pi
                    rgb = lookup(rows, u, v)
                    acc = [s + c for s, c in zip(acc, rgb)]
            row.append([s / (SUB * SUB) for s in acc])
        out.append(row)
    return out


def write_pfm(path, rows):
    h, w = len(rows), len(rows[0])
    data = bytearray(f"PF\n{w} {h}\n-1.0\n".encode())
    for row in reversed(rows):  # PFM rows go from the bottom up
        for rgb in row:
            data += struct.pack("<3f", *rgb)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)
    print(f"wrote {path}: {w}x{h}")


def main():
    rows = [[radiance(i, j) for i in range(W)] for j in range(H)]
    write_pfm(OUT, rows)
    write_pfm(OCTAHEDRAL, octahedral(rows))


if __name__ == "__main__":
    main()
