#!/usr/bin/env python3
"""Write a scene of TRIANGLES triangles for measuring how strata's cost grows with the scene:
a bumpy UV sphere (an OBJ mesh with per-vertex normals) over a floor, under a sun and a sky.

    python3 scripts/make-mesh-scene.py 1000000 /tmp/mesh-1m      # writes scene.toml + bumpy.obj

Plain Python (no packages), deterministic; the mesh's triangle count is TRIANGLES rounded to
the nearest UV grid (2·rings·segments triangles, rings = segments / 2).
"""

import math
import os
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    triangles = int(sys.argv[1])
    out = sys.argv[2]
    os.makedirs(out, exist_ok=True)
    # 2·rings·segments triangles with rings = segments / 2: segments² triangles.
    segments = max(8, round(math.sqrt(triangles)))
    rings = max(4, segments // 2)
    obj = os.path.join(out, "bumpy.obj")
    with open(obj, "w") as f:
        f.write(f"# bumpy UV sphere, {rings} rings x {segments} segments\n")
        vertices, normals = [], []
        for i in range(rings + 1):
            theta = math.pi * i / rings
            for j in range(segments + 1):
                phi = 2 * math.pi * j / segments
                n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
                # Bumps: a few low-frequency waves, so the BVH sees a non-trivial surface.
                r = 1.0 + 0.06 * math.sin(7 * theta) * math.cos(9 * phi) + 0.02 * math.sin(31 * phi)
                vertices.append(f"v {r * n[0]:.6f} {r * n[1]:.6f} {r * n[2]:.6f}\n")
                normals.append(f"vn {n[0]:.6f} {n[1]:.6f} {n[2]:.6f}\n")
        f.writelines(vertices)
        f.writelines(normals)
        row = segments + 1
        faces = []
        for i in range(rings):
            for j in range(segments):
                a = i * row + j + 1
                b, c, d = a + 1, a + row, a + row + 1
                faces.append(f"f {a}//{a} {c}//{c} {b}//{b}\nf {b}//{b} {c}//{c} {d}//{d}\n")
        f.writelines(faces)
    count = 2 * rings * segments
    with open(os.path.join(out, "scene.toml"), "w") as f:
        f.write(f"""# {count} triangles: a bumpy UV sphere over a floor, sun and sky (scripts/make-mesh-scene.py).
[camera]
eye = [0, 1.2, -4]
look_at = [0, 0.2, 0]
fov = 40

[film]
width = 256
height = 256

[render]
spp = 16
max_depth = 4

[materials.floor]
type = "diffuse"
albedo = 0.6

[materials.clay]
type = "diffuse"
albedo = [0.7, 0.45, 0.3]

[[shapes]]
type = "rectangle"
corner = [-8, -1.1, -8]
edge_u = [0, 0, 16]
edge_v = [16, 0, 0]
material = "floor"

[[shapes]]
type = "mesh"
file = "bumpy.obj"
material = "clay"

[[lights]]
type = "distant"
direction = [0.4, 1, -0.3]    # towards the sun
irradiance = 3
angular_diameter = 1

[sky]
color = [0.3, 0.4, 0.6]
""")
    print(f"{out}: {count} triangles")


if __name__ == "__main__":
    main()
