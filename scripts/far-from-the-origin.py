#!/usr/bin/env python3
"""Write the scenes of docs/measurements/far-from-the-origin.md into DIR.

A closed diffuse sphere of radius 1 (albedo 0.8, emission 1) and a closed cube of half-size 1
made of 12 emitting mesh triangles facing inwards, each seen from inside, with its centre at
(x, x/2, -x/4) for x in 0, 10^2, 10^3, 10^4, 3*10^4, 10^5: every pixel's radiance is exactly
1 / (1 - 0.8) = 5. Render each with

    strata render DIR/sphere-X.toml --device cpu --sampler independent --spp 256 --strategy S

and read the closing `mean:` line.

Usage: far-from-the-origin.py DIR
"""

import sys
from pathlib import Path

OFFSETS = [0, 100, 1000, 10000, 30000, 100000]


def header(c):
    return f"""[camera]
eye = [{c[0] + 0.1}, {c[1] - 0.2}, {c[2] + 0.15}]
look_at = [{c[0] + 0.5}, {c[1] + 0.3}, {c[2] + 1}]
fov = 70

[film]
width = 32
height = 32

[render]
max_depth = 64

[materials.shell]
type = "diffuse"
albedo = 0.8
emission = 1
"""


def cube_obj():
    """The cube [-1, 1]^3 as 6 faces of 4 corners each, wound to face inwards."""
    lines = []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [int(k == (axis + 1) % 3) for k in range(3)]
            v = [int(k == (axis + 2) % 3) for k in range(3)]
            quad = [[n[k] + u[k] * a + v[k] * b for k in range(3)]
                    for a, b in [(-1, -1), (1, -1), (1, 1), (-1, 1)]]
            e1 = [quad[1][k] - quad[0][k] for k in range(3)]
            e2 = [quad[2][k] - quad[0][k] for k in range(3)]
            cross = [e1[1] * e2[2] - e1[2] * e2[1],
                     e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]]
            if sum(cross[k] * n[k] for k in range(3)) > 0:
                quad.reverse()
            lines += ["v %d %d %d" % tuple(p) for p in quad]
    for f in range(6):
        k = 4 * f + 1
        lines += [f"f {k} {k + 1} {k + 2}", f"f {k} {k + 2} {k + 3}"]
    return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    (out / "cube-in.obj").write_text(cube_obj())
    for x in OFFSETS:
        c = (x, x / 2, -x / 4)
        (out / f"sphere-{x}.toml").write_text(header(c) + f"""
[[shapes]]
type = "sphere"
center = [{c[0]}, {c[1]}, {c[2]}]
radius = 1
material = "shell"
""")
        (out / f"cube-{x}.toml").write_text(header(c) + f"""
[[shapes]]
type = "mesh"
file = "cube-in.obj"
material = "shell"
transform = {{ translate = [{c[0]}, {c[1]}, {c[2]}] }}
""")


if __name__ == "__main__":
    main()
