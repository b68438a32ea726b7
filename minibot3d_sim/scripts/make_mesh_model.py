#!/usr/bin/python3
"""Writes the mesh of the minibot3d_sculpture model: a twisted five-pointed star column.

A closed, outward-facing triangle mesh (binary STL) about 0.5 m across and 0.8 m tall, standing on
z = 0 and centred on the z axis. It exists so that the default world has one obstacle that only a
mesh loader can represent: its horizontal cut is a star whose orientation changes with height.

Usage: make_mesh_model.py [OUTPUT.stl]   (default: ../worlds/models/minibot3d_sculpture/meshes/
sculpture.stl next to this script). Pure standard library; the output is deterministic.
"""
import math
import os
import struct
import sys

POINTS = 5
OUTER_RADIUS = 0.25
INNER_RADIUS = 0.11
HEIGHT = 0.8
LAYERS = 16  # layer spacing 0.05 m; the lidar plane (0.11 m) falls between layers
TWIST = math.radians(72.0)  # total rotation from bottom to top: one point-to-point turn


def ring(z):
    """The star outline at height z, counter-clockwise seen from above."""
    twist = TWIST * z / HEIGHT
    pts = []
    for k in range(2 * POINTS):
        r = OUTER_RADIUS if k % 2 == 0 else INNER_RADIUS
        a = twist + math.pi * k / POINTS
        pts.append((r * math.cos(a), r * math.sin(a), z))
    return pts


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normal(a, b, c):
    n = cross(sub(b, a), sub(c, a))
    length = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    return (n[0] / length, n[1] / length, n[2] / length)


def triangles():
    rings = [ring(HEIGHT * i / LAYERS) for i in range(LAYERS + 1)]
    n = 2 * POINTS
    tris = []
    # Sides: each quad between consecutive rings, split in two, wound counter-clockwise as seen from
    # outside (the ring runs counter-clockwise seen from above).
    for lo, hi in zip(rings[:-1], rings[1:]):
        for k in range(n):
            a, b = lo[k], lo[(k + 1) % n]
            c, d = hi[(k + 1) % n], hi[k]
            tris.append((a, b, c))
            tris.append((a, c, d))
    # Caps: fans from the axis; the star is star-shaped about its centre, so a fan covers it exactly.
    bottom_c = (0.0, 0.0, 0.0)
    top_c = (0.0, 0.0, HEIGHT)
    for k in range(n):
        tris.append((bottom_c, rings[0][(k + 1) % n], rings[0][k]))  # faces down
        tris.append((top_c, rings[-1][k], rings[-1][(k + 1) % n]))  # faces up
    return tris


def write_binary_stl(path, tris):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    header = b"minibot3d_sculpture: twisted star column, metres, z up".ljust(80, b" ")
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header)
        f.write(struct.pack("<I", len(tris)))
        for a, b, c in tris:
            f.write(struct.pack("<3f", *normal(a, b, c)))
            for v in (a, b, c):
                f.write(struct.pack("<3f", *v))
            f.write(struct.pack("<H", 0))
    os.replace(tmp, path)


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1] in ("-h", "--help")):
        print(__doc__.strip())
        return 2 if len(argv) > 2 else 0
    here = os.path.dirname(os.path.abspath(__file__))
    default = os.path.join(here, "..", "worlds", "models", "minibot3d_sculpture", "meshes",
                           "sculpture.stl")
    path = os.path.normpath(argv[1] if len(argv) == 2 else default)
    tris = triangles()
    write_binary_stl(path, tris)
    print("wrote %s: %d triangles" % (path, len(tris)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
