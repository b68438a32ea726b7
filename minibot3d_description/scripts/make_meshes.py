#!/usr/bin/env python3
"""Writes the robots' meshes, made for this project (binary STL, metres, z up):

- meshes/rplidar_a1.stl: an RPLIDAR A1: a square-ish base plate (rounded corners approximated by a
  polygon), the round scanner head on top of it and a thin cap; origin at the centre of the bottom
  of the base.
- meshes/quadbot_bumper.stl: quadbot's front bumper, a bar 0.06 m high, 0.04 m deep and 0.34 m wide
  with rounded ends; origin at the middle of its back face's centre line.

Run: /usr/bin/python3 scripts/make_meshes.py (rewrites the files atomically).
"""
import math
import os
import struct
import sys
import tempfile


def prism(outline, z0, z1):
    """Triangles of a closed prism over a convex outline (counter-clockwise)."""
    tris = []
    n = len(outline)
    cx = sum(p[0] for p in outline) / n
    cy = sum(p[1] for p in outline) / n
    for i in range(n):
        a, b = outline[i], outline[(i + 1) % n]
        tris.append(((cx, cy, z0), (b[0], b[1], z0), (a[0], a[1], z0)))  # bottom, facing down
        tris.append(((cx, cy, z1), (a[0], a[1], z1), (b[0], b[1], z1)))  # top, facing up
        tris.append(((a[0], a[1], z0), (b[0], b[1], z0), (b[0], b[1], z1)))
        tris.append(((a[0], a[1], z0), (b[0], b[1], z1), (a[0], a[1], z1)))
    return tris


def circle(r, n=32, cx=0.0, cy=0.0):
    return [(cx + r * math.cos(2 * math.pi * i / n), cy + r * math.sin(2 * math.pi * i / n))
            for i in range(n)]


def rounded_rect(w, h, r, n=6):
    pts = []
    for (sx, sy, a0) in ((1, 1, 0), (-1, 1, 90), (-1, -1, 180), (1, -1, 270)):
        cx, cy = sx * (w / 2 - r), sy * (h / 2 - r)
        for i in range(n + 1):
            a = math.radians(a0 + 90.0 * i / n)
            pts.append((cx + r * math.cos(a), cy + r * math.sin(a)))
    return pts


def normal(t):
    (ax, ay, az), (bx, by, bz), (cx, cy, cz) = t
    ux, uy, uz = bx - ax, by - ay, bz - az
    vx, vy, vz = cx - ax, cy - ay, cz - az
    nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
    length = math.sqrt(nx * nx + ny * ny + nz * nz) or 1.0
    return nx / length, ny / length, nz / length


def write_stl(out, header, tris):
    """Writes the triangles as binary STL through a temporary file renamed into place."""
    fd, tmp = tempfile.mkstemp(dir=os.path.dirname(out), suffix='.tmp')
    with os.fdopen(fd, 'wb') as f:
        f.write(header.ljust(80, b' '))
        f.write(struct.pack('<I', len(tris)))
        for t in tris:
            f.write(struct.pack('<3f', *normal(t)))
            for v in t:
                f.write(struct.pack('<3f', *v))
            f.write(b'\0\0')
    os.chmod(tmp, 0o644)
    os.replace(tmp, out)
    print('wrote %s (%d triangles)' % (os.path.normpath(out), len(tris)))


def main():
    meshes = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'meshes')
    lidar = []
    lidar += prism(rounded_rect(0.097, 0.070, 0.01), 0.0, 0.010)    # base plate
    lidar += prism(circle(0.035), 0.010, 0.040)                      # rotating head
    lidar += prism(circle(0.030), 0.040, 0.045)                      # cap
    lidar += prism(rounded_rect(0.020, 0.012, 0.003), 0.010, 0.014)  # motor housing bump
    write_stl(os.path.join(meshes, 'rplidar_a1.stl'), b'minibot3d RPLIDAR A1 model', lidar)
    # The bumper: a rounded rectangle 0.04 deep and 0.34 wide, its back face on x = 0.
    outline = [(x + 0.02, y) for (x, y) in rounded_rect(0.04, 0.34, 0.019)]
    write_stl(os.path.join(meshes, 'quadbot_bumper.stl'), b'minibot3d quadbot bumper',
              prism(outline, -0.03, 0.03))


if __name__ == '__main__':
    sys.exit(main())
