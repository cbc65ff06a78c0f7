#!/usr/bin/env python3
"""Write a scene of TRIANGLES triangles for measuring how strata's cost grows with the scene:
a bumpy UV sphere (a mesh with per-vertex normals) over a floor, under a sun and a sky.

    python3 scripts/make-mesh-scene.py 1000000 /tmp/mesh-1m         # scene.toml + bumpy.obj
    python3 scripts/make-mesh-scene.py 1000000 /tmp/mesh-1m --ply   # scene.toml + bumpy.ply

The OBJ is text (`v`, `vn`, `f a//a b//b c//c`); the PLY is the same mesh in binary
little-endian PLY (float x y z nx ny nz per vertex, a uchar-counted int list per face), the
form scanned models and mesh tools' exports usually take.

Plain Python (no packages), deterministic; the mesh's triangle count is TRIANGLES rounded to
the nearest UV grid (2·rings·segments triangles, rings = segments / 2).
"""

import math
import os
import struct
import sys


def main():
    args = [a for a in sys.argv[1:] if a != "--ply"]
    ply = len(args) + 1 < len(sys.argv)
    if len(args) != 2:
        sys.exit(__doc__)
    triangles = int(args[0])
    out = args[1]
    os.makedirs(out, exist_ok=True)
    # 2·rings·segments triangles with rings = segments / 2: segments² triangles.
    segments = max(8, round(math.sqrt(triangles)))
    rings = max(4, segments // 2)
    points, normals = [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            # Bumps: a few low-frequency waves, so the BVH sees a non-trivial surface.
            r = 1.0 + 0.06 * math.sin(7 * theta) * math.cos(9 * phi) + 0.02 * math.sin(31 * phi)
            points.append((r * n[0], r * n[1], r * n[2]))
            normals.append(n)
    row = segments + 1
    faces = []  # 0-based corners
    for i in range(rings):
        for j in range(segments):
            a = i * row + j
            b, c, d = a + 1, a + row, a + row + 1
            faces.append((a, c, b))
            faces.append((b, c, d))
    mesh = "bumpy.ply" if ply else "bumpy.obj"
    with open(os.path.join(out, mesh), "wb") as f:
        if ply:
            write_ply(f, points, normals, faces)
        else:
            write_obj(f, rings, segments, points, normals, faces)
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
file = "{mesh}"
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


def write_obj(f, rings, segments, points, normals, faces):
    f.write(f"# bumpy UV sphere, {rings} rings x {segments} segments\n".encode())
    f.writelines(f"v {x:.6f} {y:.6f} {z:.6f}\n".encode() for x, y, z in points)
    f.writelines(f"vn {x:.6f} {y:.6f} {z:.6f}\n".encode() for x, y, z in normals)
    f.writelines(
        f"f {a + 1}//{a + 1} {b + 1}//{b + 1} {c + 1}//{c + 1}\n".encode() for a, b, c in faces
    )


def write_ply(f, points, normals, faces):
    f.write(
        (
            "ply\nformat binary_little_endian 1.0\ncomment bumpy UV sphere\n"
            f"element vertex {len(points)}\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            f"element face {len(faces)}\n"
            "property list uchar int vertex_indices\nend_header\n"
        ).encode()
    )
    vertex = struct.Struct("<6f")
    f.write(b"".join(vertex.pack(*p, *n) for p, n in zip(points, normals)))
    face = struct.Struct("<B3i")
    f.write(b"".join(face.pack(3, *t) for t in faces))


if __name__ == "__main__":
    main()
