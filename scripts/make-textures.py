#!/usr/bin/env python3
"""Write the images and the mesh of scenes/textures.toml, all generated here (no third-party
files). Pure Python, no dependencies; the output is deterministic.

  scenes/maps/tiles.png        64 x 64 8-bit sRGB: terracotta tiles with light grout, each tile
                               a slightly different hue, an orientation mark (a dark corner at
                               the top left of the image) so a flipped lookup shows.
  scenes/maps/scratches.pfm    64 x 64 grey floats: a roughness map, 0.05 with rougher
                               (0.4) diagonal scratches, for a conductor's GGX alpha.
  scenes/maps/label.png        32 x 16 8-bit sRGB: an "F" on a pale background, clamped, for
                               a plastic's diffuse colour on a box (asymmetric, so a mirrored
                               texture shows).
  scenes/meshes/tile.obj       a bumpy 8 x 8 quad grid with `vt` coordinates and normals.
  scenes/maps/dimples.pfm      64 x 64 grey floats: heights for a bump map (scenes/detail.toml),
                               1 with smooth round dimples down to 0 on a 4 x 4 grid and a
                               raised diagonal ridge, so that a flipped or mirrored lookup shows.
  scenes/maps/studs.png        64 x 64 8-bit linear RGB: a normal map of 2 x 2 rounded studs
                               (tangent-space normals, (n + 1) / 2 per channel) with a flat
                               border, for scenes/detail.toml.
  scenes/maps/leaf.png         64 x 64 8-bit grey: an alpha mask (255 opaque, 0 cut away), a
                               pointed leaf with two holes and a stem, soft at its edge, for
                               the cut-out in scenes/detail.toml (asymmetric: a flip shows).

    python3 scripts/make-textures.py
"""
import math
import os
import struct
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def write_png(path, width, height, rows):
    """An 8-bit RGB PNG; `rows` is a list of `height` lists of `width` (r, g, b) bytes."""
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def write_pfm_grey(path, width, height, rows):
    """A grey PFM (`Pf`), little-endian; `rows` top row first (PFM stores bottom-up)."""
    with open(path, "wb") as f:
        f.write(b"Pf\n%d %d\n-1.0\n" % (width, height))
        for row in reversed(rows):
            f.write(struct.pack("<%df" % width, *row))


def tiles():
    n, tile, grout = 64, 16, 2
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            tx, ty = x // tile, y // tile
            if x % tile < grout or y % tile < grout:
                px = (214, 208, 196)
            else:
                shade = ((tx * 7 + ty * 3) % 5) * 9
                px = (168 + shade, 82 + shade // 2, 52)
            if x < 6 and y < 6:
                px = (30, 30, 40)
            row.append(px)
        rows.append(row)
    return n, n, rows


def scratches():
    n = 64
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            d = (x + 2 * y) % 16
            row.append(0.4 if d < 2 else 0.05)
        rows.append(row)
    return n, n, rows


def label():
    w, h = 32, 16
    rows = [[(235, 228, 205) for _ in range(w)] for _ in range(h)]
    ink = (40, 60, 150)
    for y in range(3, 13):
        for x in range(10, 13):
            rows[y][x] = ink
    for x in range(10, 22):
        for y in range(3, 5):
            rows[y][x] = ink
    for x in range(10, 19):
        for y in range(7, 9):
            rows[y][x] = ink
    return w, h, rows


def grid(n, texel):
    """n x n rows of texel(u, v) at the texel centres (u, v) in [0, 1), the top row first."""
    return [[texel((x + 0.5) / n, (y + 0.5) / n) for x in range(n)] for y in range(n)]


def cell(u, v, cells):
    """(u, v) relative to the centre of its cell of a cells x cells grid, in cell widths."""
    return (u * cells) % 1 - 0.5, (v * cells) % 1 - 0.5


def dimples():
    def height(u, v):
        # Each cell's dimple a smooth cos^2 bowl of radius 0.4 cell.
        cu, cv = cell(u, v, 4)
        r = math.sqrt(cu * cu + cv * cv) / 0.4
        h = -math.cos(0.5 * math.pi * r) ** 2 if r < 1 else 0.0
        # A ridge along u = v, narrow and smooth.
        d = abs(u - v) / 0.05
        if d < 1:
            h += 0.6 * math.cos(0.5 * math.pi * d) ** 2
        # Texels are >= 0: the flat level at 1.
        return 1.0 + h

    return 64, 64, grid(64, height)


def studs():
    def normal(u, v):
        cu, cv = cell(u, v, 2)
        r = math.sqrt(cu * cu + cv * cv) / 0.35
        # A stud's slope: the gradient of a cos^2 dome of radius 0.35 cell, zero outside.
        nx, ny, nz = 0.0, 0.0, 1.0
        if 0 < r < 1:
            slope = 1.5 * math.sin(math.pi * r)
            nx, ny = slope * cu / (r * 0.35), slope * cv / (r * 0.35)
            # Image rows grow downwards (v), the map's y along n x dp/du: v upwards.
            ny = -ny
        length = math.sqrt(nx * nx + ny * ny + nz * nz)
        return tuple(round(255 * (c / length + 1) / 2) for c in (nx, ny, nz))

    return 64, 64, grid(64, normal)


def leaf():
    def mask(u, v):
        # A lens-shaped leaf along the diagonal from bottom left to top right.
        a, b = (u + (1 - v)) / 2, (u - (1 - v)) / 2
        width = 0.28 * math.sin(math.pi * min(max((a - 0.08) / 0.84, 0), 1))
        inside = abs(b) < width
        # Two holes, and a stem at the bottom left.
        for cx, cy, r in ((0.62, 0.35, 0.06), (0.42, 0.52, 0.04)):
            if (u - cx) ** 2 + (v - cy) ** 2 < r * r:
                inside = False
        if a < 0.12 and abs(b) < 0.02:
            inside = True
        g = 255 if inside else 0
        return (g, g, g)

    return 64, 64, grid(64, mask)


def tile_obj():
    n = 8
    lines = ["# An 8 x 8 quad grid over [-1, 1]^2 in the xz plane, bumped in y, with uv and normals."]
    height = lambda u, v: 0.06 * math.sin(3 * math.pi * u) * math.sin(2 * math.pi * v)
    for j in range(n + 1):
        for i in range(n + 1):
            u, v = i / n, j / n
            lines.append("v %.6f %.6f %.6f" % (2 * u - 1, height(u, v), 2 * v - 1))
    for j in range(n + 1):
        for i in range(n + 1):
            lines.append("vt %.6f %.6f" % (i / n, j / n))
    for j in range(n + 1):
        for i in range(n + 1):
            u, v = i / n, j / n
            du = 0.06 * 3 * math.pi * math.cos(3 * math.pi * u) * math.sin(2 * math.pi * v) / 2
            dv = 0.06 * 2 * math.pi * math.sin(3 * math.pi * u) * math.cos(2 * math.pi * v) / 2
            nx, ny, nz = -du, 1.0, -dv
            length = math.sqrt(nx * nx + ny * ny + nz * nz)
            lines.append("vn %.6f %.6f %.6f" % (nx / length, ny / length, nz / length))
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i + 1
            b, c, d = a + 1, a + n + 2, a + n + 1
            # Counter-clockwise seen from +y: the front faces up.
            lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, d, d, d, c, c, c, b, b, b))
    return "\n".join(lines) + "\n"


def main():
    maps = os.path.join(ROOT, "scenes", "maps")
    w, h, rows = tiles()
    write_png(os.path.join(maps, "tiles.png"), w, h, rows)
    w, h, rows = scratches()
    write_pfm_grey(os.path.join(maps, "scratches.pfm"), w, h, rows)
    w, h, rows = label()
    write_png(os.path.join(maps, "label.png"), w, h, rows)
    with open(os.path.join(ROOT, "scenes", "meshes", "tile.obj"), "w") as f:
        f.write(tile_obj())
    w, h, rows = dimples()
    write_pfm_grey(os.path.join(maps, "dimples.pfm"), w, h, rows)
    w, h, rows = studs()
    write_png(os.path.join(maps, "studs.png"), w, h, rows)
    w, h, rows = leaf()
    write_png(os.path.join(maps, "leaf.png"), w, h, rows)


if __name__ == "__main__":
    main()
