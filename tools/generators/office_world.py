#!/usr/bin/env python3
"""Office world: a building-scale floor of many similar rooms along long corridors.

    tools/generators/office_world.py [--seed 1] [--width 60] [--height 48]
        [--out minibot3d_sim/worlds] [--map-out maps] [--name office] [--renderer render_world_map]

Writes NAME.world (SDF: static box and cylinder collisions, as the simulator reads them) and, with
minibot3d_sim's render_world_map, the ground-truth map NAME.pgm + NAME.yaml (0.05 m cells).
The defaults make the shipped world (minibot3d_sim/worlds/office.world, maps/office.yaml).

Layout, from the bottom (y = 0) up, every band the full width of the floor:
  a row of rooms opening up onto corridor A (2 m wide),
  two rows of rooms back to back (the lower row opening down onto A, the upper up onto B),
  corridor B, an open-plan hall with a grid of pillars and desk islands, corridor C,
  two rows of rooms back to back (onto C and onto D), corridor D, a row of rooms opening down.
Two vertical corridors (at the west wall and in the middle) join A, B, C and D. A room is
3.5-5 m wide (drawn from four widths, so that many rooms have the same size), with one door
(1 m) at a random place in its corridor wall, a desk against a random wall, often a cabinet,
sometimes a bin; one room in six is a meeting room with a table in the middle. The strip of a
room along its door wall (1.1 m) is kept clear, so every room can be entered. Everything is
seeded (Python's random.Random) and written with fixed precision: the same arguments give
byte-identical files.

Walls are 0.1 m thick and 1 m tall; furniture is 0.75 m tall, bins 0.6 m: all cut by the lidar
plane (0.11 m). The robot's spawn (written in the world's header comment and in NAME.json) is in
corridor A near the west end.
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_RENDERER = os.path.join(ROOT, 'devel', 'lib', 'minibot3d_sim', 'render_world_map')

WALL, WALL_HEIGHT = 0.1, 1.0
FURNITURE_HEIGHT, BIN_HEIGHT = 0.75, 0.6
CORRIDOR, ROOM_DEPTH, HALL_DEPTH = 2.0, 5.0, 7.0
ROOM_WIDTHS = (3.5, 4.0, 4.5, 5.0)
DOOR, DOOR_STRIP = 1.0, 1.1


class OfficeError(ValueError):
    """Bad parameters, named."""


def _r(v):
    return round(v, 4) + 0.0


class Floor(object):
    """Boxes (x0, y0, x1, y1, height, name) and cylinders (x, y, radius, height, name)."""

    def __init__(self):
        self.walls, self.furniture, self.bins, self.rooms = [], [], [], []

    def hwall(self, x0, x1, y, name):
        if x1 - x0 > 1e-6:
            self.walls.append((x0 - WALL / 2, y - WALL / 2, x1 + WALL / 2, y + WALL / 2,
                               WALL_HEIGHT, name))

    def vwall(self, x, y0, y1, name):
        if y1 - y0 > 1e-6:
            self.walls.append((x - WALL / 2, y0 - WALL / 2, x + WALL / 2, y1 + WALL / 2,
                               WALL_HEIGHT, name))

    def box(self, x0, y0, x1, y1, name, height=FURNITURE_HEIGHT):
        self.furniture.append((x0, y0, x1, y1, height, name))


def _door_wall(floor, rng, x0, x1, y, name):
    """A horizontal wall from x0 to x1 at y with a door at a random place."""
    d = rng.uniform(x0 + 0.4, x1 - 0.4 - DOOR)
    floor.hwall(x0, d, y, name + '_a')
    floor.hwall(d + DOOR, x1, y, name + '_b')
    return d + DOOR / 2


def _furnish(floor, rng, name, x0, y0, x1, y1, door_below):
    """Furniture in the room [x0, x1] x [y0, y1] (inside the walls); the strip along the door wall
    stays clear. Returns the room's kind."""
    m = WALL / 2 + 0.05  # furniture stands 5 cm off the walls
    ix0, ix1 = x0 + m, x1 - m
    iy0, iy1 = (y0 + DOOR_STRIP, y1 - m) if door_below else (y0 + m, y1 - DOOR_STRIP)
    back_y = iy1 if door_below else iy0  # the wall facing the door
    sign = -1.0 if door_below else 1.0   # from the back wall into the room
    width = x1 - x0
    if width >= 4.5 and rng.random() < 1.0 / 6.0:
        tw, td = rng.uniform(1.8, 2.4), rng.uniform(0.9, 1.1)
        cx = (x0 + x1) / 2 + rng.uniform(-0.3, 0.3)
        cy = (iy0 + iy1) / 2 + rng.uniform(-0.2, 0.2)
        floor.box(cx - tw / 2, cy - td / 2, cx + tw / 2, cy + td / 2, name + '_table')
        return 'meeting'
    # A desk against the back wall or against a side wall.
    dw, dd = rng.uniform(1.2, 1.6), rng.uniform(0.6, 0.8)
    side = rng.choice(('back', 'west', 'east'))
    if side == 'back':
        dx = rng.uniform(ix0, ix1 - dw)
        ya, yb = sorted((back_y, back_y + sign * dd))
        floor.box(dx, ya, dx + dw, yb, name + '_desk')
        used = (dx, dx + dw)
    else:
        dy = rng.uniform(iy0, iy1 - dw)
        xa, xb = (ix0, ix0 + dd) if side == 'west' else (ix1 - dd, ix1)
        floor.box(xa, dy, xb, dy + dw, name + '_desk')
        used = None
    # Often a cabinet against the other side wall (or the back wall beside the desk).
    if rng.random() < 0.6:
        cw, cd = rng.uniform(0.8, 1.2), rng.uniform(0.4, 0.5)
        if side == 'west' or (side == 'back' and rng.random() < 0.5):
            cy = rng.uniform(iy0, iy1 - cw)
            floor.box(ix1 - cd, cy, ix1, cy + cw, name + '_cabinet')
        elif side == 'east':
            cy = rng.uniform(iy0, iy1 - cw)
            floor.box(ix0, cy, ix0 + cd, cy + cw, name + '_cabinet')
        elif used[0] - ix0 > cw + 0.3:
            cx = rng.uniform(ix0, used[0] - cw - 0.3)
            ya, yb = sorted((back_y, back_y + sign * cd))
            floor.box(cx, ya, cx + cw, yb, name + '_cabinet')
    # Sometimes a bin in a corner by the back wall.
    if rng.random() < 0.3:
        r = 0.18
        bx = ix0 + r if rng.random() < 0.5 else ix1 - r
        by = back_y + sign * r
        clear = all(not (b[0] - r < bx < b[2] + r and b[1] - r < by < b[3] + r)
                    for b in floor.furniture)
        if clear:
            floor.bins.append((bx, by, r, BIN_HEIGHT, name + '_bin'))
    return 'office'


def _room_row(floor, rng, label, xa, xb, y0, y1, door_below):
    """Rooms side by side in [xa, xb] x [y0, y1], each with its door in the wall at y0 (door_below)
    or y1. The walls at xa, xb, y0 and y1 are drawn here except the back wall (the caller's)."""
    x, k = xa, 0
    while xb - x > 1e-6:
        w = rng.choice(ROOM_WIDTHS)
        if xb - (x + w) < 3.0:
            w = xb - x
        name = '%s_%02d' % (label, k)
        door = _door_wall(floor, rng, x, x + w, y0 if door_below else y1, name + '_front')
        if x + w < xb - 1e-6:
            floor.vwall(x + w, y0, y1, name + '_side')
        kind = _furnish(floor, rng, name, x, y0, x + w, y1, door_below)
        floor.rooms.append({'name': name, 'kind': kind, 'x0': _r(x), 'y0': _r(y0),
                            'x1': _r(x + w), 'y1': _r(y1), 'door_x': _r(door)})
        x, k = x + w, k + 1


def generate(seed=1, width=60.0, height=48.0):
    """The floor: see the module docstring. Raises OfficeError when it does not fit."""
    need = 2 * ROOM_DEPTH * 3 + 4 * CORRIDOR + HALL_DEPTH
    if not (height >= need - 1e-9):
        raise OfficeError('height=%g: must be >= %g m (six rows of rooms, four corridors, the '
                          'hall)' % (height, need))
    if not (width >= 30.0):
        raise OfficeError('width=%g: must be >= 30 m' % width)
    rng = random.Random(seed)
    f = Floor()
    # Outer walls.
    f.hwall(0.0, width, 0.0, 'outer_south')
    f.hwall(0.0, width, height, 'outer_north')
    f.vwall(0.0, 0.0, height, 'outer_west')
    f.vwall(width, 0.0, height, 'outer_east')
    # Bands: rows of rooms get whatever height is left over the fixed parts, shared evenly.
    depth = ROOM_DEPTH + (height - need) / 6.0
    y = 0.0
    south_row = (y, y + depth)
    y += depth
    cor_a = (y, y + CORRIDOR)
    y += CORRIDOR
    double1 = (y, y + depth, y + 2 * depth)
    y += 2 * depth
    cor_b = (y, y + CORRIDOR)
    y += CORRIDOR
    hall = (y, y + HALL_DEPTH)
    y += HALL_DEPTH
    cor_c = (y, y + CORRIDOR)
    y += CORRIDOR
    double2 = (y, y + depth, y + 2 * depth)
    y += 2 * depth
    cor_d = (y, y + CORRIDOR)
    y += CORRIDOR
    north_row = (y, height)
    # Vertical corridors: along the west wall and in the middle, from corridor A to corridor D.
    mid = round(width / 2.0 - CORRIDOR / 2.0, 2)
    west_x1 = CORRIDOR
    segments = [(west_x1, mid), (mid + CORRIDOR, width)]
    # South and north rows span the whole width.
    _room_row(f, rng, 'south', 0.0, width, south_row[0], south_row[1], door_below=False)
    _room_row(f, rng, 'north', 0.0, width, north_row[0], north_row[1], door_below=True)
    for b, (lo, midy, hi), cb, ct in (('a', double1, cor_a, cor_b), ('c', double2, cor_c, cor_d)):
        for s, (xa, xb) in enumerate(segments):
            _room_row(f, rng, 'band%s%d_lo' % (b, s), xa, xb, lo, midy, door_below=True)
            _room_row(f, rng, 'band%s%d_hi' % (b, s), xa, xb, midy, hi, door_below=False)
            f.hwall(xa, xb, midy, 'band%s%d_back' % (b, s))
            # The segment's ends: the vertical corridors' walls (full height of the band).
            f.vwall(xa, lo, hi, 'band%s%d_west' % (b, s))
            if xb < width - 1e-6:
                f.vwall(xb, lo, hi, 'band%s%d_east' % (b, s))
    # The hall: pillars on a 5 m grid (0.4 m square) and desk islands between some of them.
    y0, y1 = hall
    py = (y0 + 2.0, y1 - 2.0)
    k = 0
    for px in [5.0 * i for i in range(1, int(width / 5.0))]:
        for yy in py:
            f.box(px - 0.2, yy - 0.2, px + 0.2, yy + 0.2, 'hall_pillar_%02d' % k, WALL_HEIGHT)
            k += 1
        if px + 5.0 < width and rng.random() < 0.45:
            iw, idp = rng.uniform(1.6, 3.0), rng.uniform(1.0, 1.6)
            cx = px + 2.5 + rng.uniform(-0.5, 0.5)
            cy = (y0 + y1) / 2 + rng.uniform(-0.4, 0.4)
            f.box(cx - iw / 2, cy - idp / 2, cx + iw / 2, cy + idp / 2, 'hall_island_%02d' % k)
    spawn = (1.0, (cor_a[0] + cor_a[1]) / 2.0, 0.0)
    layout = {'corridor_a': cor_a, 'corridor_b': cor_b, 'hall': hall, 'corridor_c': cor_c,
              'corridor_d': cor_d, 'vertical_corridors_x': [(0.0, west_x1), (mid, mid + CORRIDOR)],
              'room_depth': depth}
    return f, spawn, layout


def world_sdf(f, name, seed, width, height, spawn):
    lines = [
        '<?xml version="1.0"?>',
        '<!-- %s: an office floor, %g m x %g m (x 0..%g, y 0..%g), made by tools/generators/office_world.py '
        '(seed %d).' % (name, width, height, width, height, seed),
        '     %d rooms along four corridors and two vertical ones, an open-plan hall in the middle;'
        % len(f.rooms),
        '     walls %g m thick, %g m tall; furniture %g m tall. Spawn (%.2f, %.2f, yaw 0) in corridor A.'
        % (WALL, WALL_HEIGHT, FURNITURE_HEIGHT, spawn[0], spawn[1]),
        '     Regenerate with: tools/generators/office_world.py --seed %d --width %g --height %g --name %s -->'
        % (seed, width, height, name),
        '<sdf version="1.6">',
        '  <world name="%s">' % name,
        '    <include><uri>model://ground_plane</uri></include>',
        '    <include><uri>model://sun</uri></include>',
    ]
    for model, boxes in (('walls', f.walls), ('furniture', f.furniture)):
        lines += ['    <model name="%s">' % model, '      <static>true</static>',
                  '      <link name="%s">' % model]
        for (x0, y0, x1, y1, h, n) in boxes:
            lines += [
                '        <collision name="%s">' % n,
                '          <pose>%.4f %.4f %.4f 0 0 0</pose>' % ((x0 + x1) / 2, (y0 + y1) / 2, h / 2),
                '          <geometry><box><size>%.4f %.4f %.4f</size></box></geometry>'
                % (x1 - x0, y1 - y0, h),
                '        </collision>',
            ]
        if model == 'furniture':
            for (x, y, r, h, n) in f.bins:
                lines += [
                    '        <collision name="%s">' % n,
                    '          <pose>%.4f %.4f %.4f 0 0 0</pose>' % (x, y, h / 2),
                    '          <geometry><cylinder><radius>%.4f</radius><length>%.4f</length>'
                    '</cylinder></geometry>' % (r, h),
                    '        </collision>',
                ]
        lines += ['      </link>', '    </model>']
    lines += ['  </world>', '</sdf>', '']
    return '\n'.join(lines)


def _write(path, text):
    tmp = path + '.tmp'
    with open(tmp, 'w') as fh:
        fh.write(text)
    os.replace(tmp, path)


def main(argv=None):
    ap = argparse.ArgumentParser(prog='office_world.py', description=__doc__.split('\n\n')[0])
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--width', type=float, default=60.0)
    ap.add_argument('--height', type=float, default=48.0)
    ap.add_argument('--name', default='office')
    ap.add_argument('--out', default=os.path.join(ROOT, 'minibot3d_sim', 'worlds'),
                    help='directory for NAME.world and NAME.json')
    ap.add_argument('--map-out', default=os.path.join(ROOT, 'maps'),
                    help='directory for NAME.pgm and NAME.yaml')
    ap.add_argument('--renderer', default=DEFAULT_RENDERER, help='render_world_map binary')
    args = ap.parse_args(argv)
    if not args.name or os.sep in args.name or args.name.startswith('.'):
        ap.error('--name %r: must be a plain file name' % args.name)
    try:
        f, spawn, layout = generate(args.seed, args.width, args.height)
    except OfficeError as e:
        ap.error(str(e))
    if not (os.path.isfile(args.renderer) and os.access(args.renderer, os.X_OK)):
        ap.error('--renderer %r: render_world_map not found; build the workspace '
                 '(tools/build.sh) or pass --renderer' % args.renderer)
    os.makedirs(args.out, exist_ok=True)
    os.makedirs(args.map_out, exist_ok=True)
    world = os.path.join(args.out, args.name + '.world')
    _write(world, world_sdf(f, args.name, args.seed, args.width, args.height, spawn))
    base = os.path.join(args.map_out, args.name)
    out = subprocess.run([args.renderer, world, base, '--resolution', '0.05'],
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit('office_world.py: render_world_map failed on %s: %s' % (world, out.stderr.strip()))
    desc = {'name': args.name, 'seed': args.seed, 'width': args.width, 'height': args.height,
            'spawn': {'x': _r(spawn[0]), 'y': _r(spawn[1]), 'yaw': 0.0},
            'rooms': f.rooms, 'layout': {k: ([_r(v) for v in val] if isinstance(val, tuple) else
                                             [[_r(a), _r(b)] for a, b in val] if isinstance(val, list)
                                             else _r(val)) for k, val in layout.items()}}
    _write(os.path.join(args.out, args.name + '.json'),
           json.dumps(desc, indent=1, sort_keys=True) + '\n')
    print('%s: %d rooms, %d walls, %d furniture boxes, %d bins; map %s.pgm'
          % (world, len(f.rooms), len(f.walls), len(f.furniture), len(f.bins), base))
    return 0


if __name__ == '__main__':
    sys.exit(main())
