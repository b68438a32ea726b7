#!/usr/bin/env python3
"""House worlds: small homes of a few rooms with narrow doors, furniture pockets, shelves, table
legs and a diagonal wall, for exploration and navigation benchmarks.

    tools/generators/house_world.py one --seed 7 --out DIR [--name NAME]
    tools/generators/house_world.py set [--out minibot3d_sim/worlds/houses]   # the 12 shipped

A house is a rectangle 7-11 m by 5-8 m cut into 3-5 rooms by recursive splits (binary space
partitioning; a part below the first split stays whole one time in four), each room at least
MIN_ROOM m on a side. Every split wall has one door, so every room can be reached; door widths
are drawn from 0.40-0.90 m and every house has at least one door of at most 0.45 m. Doors stay 0.3 m from wall junctions, and splits stay clear of the doors
already in the walls they end on. In each room, away from its doors (DOOR_KEEP_CLEAR):
  * often a shelf parallel to a wall with a 0.40-0.60 m gap behind it, from a corner: a pocket
    open at one end, seen only from its mouth;
  * sometimes a table on four legs 0.45-0.90 m apart (the lidar sees only the legs);
  * sometimes a sofa or bed against a wall, leaving 0.40-0.60 m to a neighbour;
and one room has a corner cut off by a diagonal wall.

The spawn is the world's origin, in the middle of the first room (kept clear), so `make demo
WORLD=...` needs no spawn pose. Walls are 0.1 m thick and 1 m tall; furniture 0.4-0.9 m tall: all
cut by the lidar plane (0.11 m); table tops (0.72 m) are above it. Everything is seeded (Python's
random.Random) and written with fixed precision: the same arguments give byte-identical files.

Writes NAME.world (SDF: static boxes, rotated for the diagonal wall), NAME.pgm + NAME.yaml (the
ground-truth map at 0.05 m, rendered by minibot3d_sim's render_world_map) and NAME.json (rooms,
doors and their widths, the spawn)."""
import argparse
import json
import math
import os
import random
import subprocess
import sys

from minibot3d_map_io import write_atomically

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_RENDERER = os.path.join(ROOT, 'devel', 'lib', 'minibot3d_sim', 'render_world_map')
SHIPPED_DIR = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'houses')
SET_COUNT = 12

WALL, WALL_HEIGHT = 0.1, 1.0
MIN_ROOM = 2.0                 # m, a room's shortest side (inside the walls, about)
DOOR_MIN, DOOR_MAX = 0.40, 0.90
NARROW_DOOR = 0.45             # every house has a door at most this wide
JUNCTION_CLEAR = 0.3           # m between a door and a wall junction or corner
DOOR_KEEP_CLEAR = 0.9          # m round a door's middle with no furniture
SPAWN_KEEP_CLEAR = 0.6         # m round the spawn with no furniture
GAP_MIN, GAP_MAX = 0.40, 0.60  # furniture pockets and gaps
LEG = 0.05                     # table leg side


class HouseError(ValueError):
    """Bad parameters or a seed that does not give a house, named."""


def _r(v):
    return round(v, 4) + 0.0


class House(object):
    def __init__(self):
        self.boxes = []   # (cx, cy, sx, sy, yaw, z of the bottom, height, name, model)
        self.rooms = []   # (x0, y0, x1, y1) inside the walls' centre lines
        self.doors = []   # dict(x, y, width, axis)
        self.furniture = []  # axis-aligned footprints (x0, y0, x1, y1) to keep apart

    def box(self, x0, y0, x1, y1, height, name, model='furniture', bottom=0.0):
        self.boxes.append(((x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0, 0.0, bottom, height,
                           name, model))

    def wall(self, x0, y0, x1, y1, name, door_at_start=False, door_at_end=False):
        """A wall along a centre line (axis-aligned); its ends reach WALL / 2 past the line's
        ends to close the corners, but not at a door's edge (the door keeps its width)."""
        a = 0.0 if door_at_start else WALL / 2
        b = 0.0 if door_at_end else WALL / 2
        if x0 == x1 and y1 - y0 > 1e-6:
            self.box(x0 - WALL / 2, y0 - a, x0 + WALL / 2, y1 + b, WALL_HEIGHT, name, 'walls')
        elif y0 == y1 and x1 - x0 > 1e-6:
            self.box(x0 - a, y0 - WALL / 2, x1 + b, y0 + WALL / 2, WALL_HEIGHT, name, 'walls')


def _split(rng, house, region, doors, depth, name, narrow_left):
    """Splits `region` (x0, y0, x1, y1) or makes it a room. `doors`: (axis, position, lo, hi) of
    doors in the region's boundary walls (axis 'x': a wall along x at y=position, the door over
    [lo, hi] in x). Returns how many narrow doors are still owed."""
    x0, y0, x1, y1 = region
    w, h = x1 - x0, y1 - y0
    can_x = w >= 2 * MIN_ROOM   # a wall along y at some x
    can_y = h >= 2 * MIN_ROOM
    if depth <= 0 or not (can_x or can_y) or (name != 's' and rng.random() < 0.25):
        house.rooms.append(region)
        return narrow_left
    vertical = can_x and (not can_y or (w >= h if rng.random() < 0.8 else rng.random() < 0.5))
    lo, hi = (x0, x1) if vertical else (y0, y1)
    # The split must not end on a door in the walls it meets.
    blocked = [(d_lo - JUNCTION_CLEAR - WALL, d_hi + JUNCTION_CLEAR + WALL)
               for axis, pos, d_lo, d_hi in doors if axis == ('x' if vertical else 'y')]
    for _ in range(50):
        c = rng.uniform(lo + MIN_ROOM, hi - MIN_ROOM)
        if all(not (a <= c <= b) for a, b in blocked):
            break
    else:
        house.rooms.append(region)
        return narrow_left
    # The door in the new wall.
    span = (y0, y1) if vertical else (x0, x1)
    width = rng.uniform(DOOR_MIN, NARROW_DOOR) if narrow_left else rng.uniform(DOOR_MIN, DOOR_MAX)
    narrow_left = max(0, narrow_left - (width <= NARROW_DOOR))
    width = round(width, 2)
    d_lo = rng.uniform(span[0] + JUNCTION_CLEAR + WALL, span[1] - JUNCTION_CLEAR - WALL - width)
    d_hi = d_lo + width
    wall_name = '%s_wall' % name
    if vertical:
        house.wall(c, y0, c, d_lo, wall_name + '_a', door_at_end=True)
        house.wall(c, d_hi, c, y1, wall_name + '_b', door_at_start=True)
        house.doors.append(dict(x=_r(c), y=_r((d_lo + d_hi) / 2), width=width, axis='y'))
        door = ('y', c, d_lo, d_hi)
        halves = ((x0, y0, c, y1), (c, y0, x1, y1))
    else:
        house.wall(x0, c, d_lo, c, wall_name + '_a', door_at_end=True)
        house.wall(d_hi, c, x1, c, wall_name + '_b', door_at_start=True)
        house.doors.append(dict(x=_r((d_lo + d_hi) / 2), y=_r(c), width=width, axis='x'))
        door = ('x', c, d_lo, d_hi)
        halves = ((x0, y0, x1, c), (x0, c, x1, y1))
    order = [0, 1] if rng.random() < 0.5 else [1, 0]
    for k in order:
        narrow_left = _split(rng, house, halves[k], doors + [door], depth - 1,
                             name + ('a' if k == 0 else 'b'), narrow_left)
    return narrow_left


def _overlaps(house, fp, gap):
    """True when footprint fp (x0, y0, x1, y1) comes nearer than `gap` to other furniture."""
    x0, y0, x1, y1 = fp
    for a0, b0, a1, b1 in house.furniture:
        if x0 < a1 + gap and a0 < x1 + gap and y0 < b1 + gap and b0 < y1 + gap:
            return True
    return False


def _near_door_or_spawn(house, fp, spawn):
    x0, y0, x1, y1 = fp

    def dist(px, py):
        return math.hypot(max(x0 - px, 0.0, px - x1), max(y0 - py, 0.0, py - y1))
    if any(dist(d['x'], d['y']) < DOOR_KEEP_CLEAR + d['width'] / 2 for d in house.doors):
        return True
    return spawn is not None and dist(*spawn) < SPAWN_KEEP_CLEAR


def _place(house, fp, spawn, gap=GAP_MIN):
    if _near_door_or_spawn(house, fp, spawn) or _overlaps(house, fp, gap):
        return False
    house.furniture.append(fp)
    return True


def _furnish(rng, house, index, room, spawn):
    """A shelf with a pocket behind it, a table on legs, a sofa: each tried a few times at random
    places, kept when it leaves the doors, the spawn and the other furniture clear."""
    x0, y0, x1, y1 = room
    m = WALL / 2  # the inside face of the walls
    ix0, iy0, ix1, iy1 = x0 + m, y0 + m, x1 - m, y1 - m
    name = 'room%d' % index
    if rng.random() < 0.75:
        # Shelf: length 1.0-1.8 m, depth 0.3 m, gap to the wall behind it 0.40-0.60 m, from a
        # corner (the pocket is closed at that end by the side wall).
        for _ in range(20):
            length, depth = rng.uniform(1.0, 1.8), 0.3
            gap = round(rng.uniform(GAP_MIN, GAP_MAX), 2)
            side = rng.choice(('south', 'north', 'west', 'east'))
            from_low = rng.random() < 0.5
            if side in ('south', 'north'):
                if ix1 - ix0 < length + 0.8:
                    continue
                sx0 = ix0 if from_low else ix1 - length
                sy0 = iy0 + gap if side == 'south' else iy1 - gap - depth
                fp = (sx0, sy0, sx0 + length, sy0 + depth)
                pocket = (sx0, iy0, sx0 + length, sy0) if side == 'south' else \
                    (sx0, sy0 + depth, sx0 + length, iy1)
            else:
                if iy1 - iy0 < length + 0.8:
                    continue
                sy0 = iy0 if from_low else iy1 - length
                sx0 = ix0 + gap if side == 'west' else ix1 - gap - depth
                fp = (sx0, sy0, sx0 + depth, sy0 + length)
                pocket = (ix0, sy0, sx0, sy0 + length) if side == 'west' else \
                    (sx0 + depth, sy0, ix1, sy0 + length)
            # The pocket must not hold a door either.
            if _near_door_or_spawn(house, pocket, None):
                continue
            if _place(house, (min(fp[0], pocket[0]), min(fp[1], pocket[1]),
                              max(fp[2], pocket[2]), max(fp[3], pocket[3])), spawn):
                house.box(*fp, 0.9, name + '_shelf')
                break
    if rng.random() < 0.5:
        # Table on legs: legs 0.45-0.90 m apart (inside), top above the lidar plane.
        for _ in range(20):
            lx, ly = rng.uniform(0.45, 0.9), rng.uniform(0.45, 0.9)
            tw, td = lx + 2 * LEG, ly + 2 * LEG
            if ix1 - ix0 < tw + 2 * GAP_MIN or iy1 - iy0 < td + 2 * GAP_MIN:
                break
            tx = rng.uniform(ix0 + GAP_MIN, ix1 - GAP_MIN - tw)
            ty = rng.uniform(iy0 + GAP_MIN, iy1 - GAP_MIN - td)
            if _place(house, (tx, ty, tx + tw, ty + td), spawn):
                for k, (ax, ay) in enumerate(((tx, ty), (tx + tw - LEG, ty), (tx, ty + td - LEG),
                                              (tx + tw - LEG, ty + td - LEG))):
                    house.box(ax, ay, ax + LEG, ay + LEG, 0.7, '%s_table_leg%d' % (name, k + 1))
                house.box(tx, ty, tx + tw, ty + td, 0.04, name + '_table_top', bottom=0.7)
                break
    if rng.random() < 0.6:
        # Sofa or bed against a wall, 0.40-0.60 m from anything else it comes near.
        for _ in range(20):
            sw, sd = rng.uniform(1.4, 2.0), rng.uniform(0.8, 1.0)
            side = rng.choice(('south', 'north', 'west', 'east'))
            if side in ('south', 'north'):
                if ix1 - ix0 < sw + 0.5:
                    continue
                sx0 = rng.uniform(ix0, ix1 - sw)
                fp = (sx0, iy0, sx0 + sw, iy0 + sd) if side == 'south' else \
                    (sx0, iy1 - sd, sx0 + sw, iy1)
            else:
                if iy1 - iy0 < sw + 0.5:
                    continue
                sy0 = rng.uniform(iy0, iy1 - sw)
                fp = (ix0, sy0, ix0 + sd, sy0 + sw) if side == 'west' else \
                    (ix1 - sd, sy0, ix1, sy0 + sw)
            if _place(house, fp, spawn, gap=rng.uniform(GAP_MIN, GAP_MAX)):
                house.box(*fp, 0.45, name + '_sofa')
                break


def _diagonal(rng, house, rooms, spawn):
    """Cuts a corner of a room off with a 45-degree wall whose legs are 0.8-1.3 m."""
    for index in rng.sample(range(len(rooms)), len(rooms)):
        x0, y0, x1, y1 = rooms[index]
        leg = rng.uniform(0.8, 1.3)
        corners = [(x0, y0, 1, 1), (x1, y0, -1, 1), (x0, y1, 1, -1), (x1, y1, -1, -1)]
        for cx, cy, sx, sy in rng.sample(corners, 4):
            fp = (min(cx, cx + sx * leg), min(cy, cy + sy * leg), max(cx, cx + sx * leg),
                  max(cy, cy + sy * leg))
            if not (_near_door_or_spawn(house, fp, spawn) or _overlaps(house, fp, GAP_MIN)):
                break
        else:
            continue
        house.furniture.append(fp)
        mx, my = cx + sx * leg / 2, cy + sy * leg / 2
        yaw = math.atan2(sy * leg, -sx * leg)
        length = math.hypot(leg, leg) + WALL
        house.boxes.append((mx, my, length, WALL, yaw, 0.0, WALL_HEIGHT,
                            'room%d_diagonal' % index, 'walls'))
        return index
    return None


def generate(seed):
    rng = random.Random(seed)
    width, height = round(rng.uniform(7.0, 11.0), 1), round(rng.uniform(5.0, 8.0), 1)
    for _ in range(100):
        house = House()
        narrow = _split(rng, house, (0.0, 0.0, width, height), [], 3, 's', 1)
        if 3 <= len(house.rooms) <= 5 and narrow == 0:
            break
    else:
        raise HouseError('seed %d: no split gave 3-5 rooms with a narrow door' % seed)
    x0, y0, x1, y1 = house.rooms[0]
    spawn = ((x0 + x1) / 2, (y0 + y1) / 2)
    for k, room in enumerate(house.rooms):
        _furnish(rng, house, k, room, spawn)
    cut = _diagonal(rng, house, house.rooms, spawn)
    # The outer walls.
    house.wall(0.0, 0.0, width, 0.0, 'outer_south')
    house.wall(0.0, height, width, height, 'outer_north')
    house.wall(0.0, 0.0, 0.0, height, 'outer_west')
    house.wall(width, 0.0, width, height, 'outer_east')
    return house, (width, height), spawn, cut


def world_sdf(house, name, seed, size, spawn):
    """The world, moved so that the spawn is the origin."""
    ox, oy = spawn
    lines = [
        '<?xml version="1.0"?>',
        '<!-- %s: a generated house, %g m x %g m, %d rooms, doors %s m wide.'
        % (name, size[0], size[1], len(house.rooms),
           ', '.join('%.2f' % d['width'] for d in house.doors)),
        '     The spawn is the origin (yaw 0), in the middle of the first room.',
        '     Regenerate with: tools/generators/house_world.py one --seed %d --name %s -->'
        % (seed, name),
        '<sdf version="1.6">',
        '  <world name="%s">' % name,
        '    <include><uri>model://ground_plane</uri></include>',
        '    <include><uri>model://sun</uri></include>',
    ]
    for model in ('walls', 'furniture'):
        lines += ['    <model name="%s">' % model, '      <static>true</static>',
                  '      <link name="%s">' % model]
        for (cx, cy, sx, sy, yaw, bottom, h, n, m) in house.boxes:
            if m != model:
                continue
            z = bottom + h / 2
            lines += [
                '        <collision name="%s">' % n,
                '          <pose>%.4f %.4f %.4f 0 0 %.6f</pose>' % (cx - ox, cy - oy, z, yaw),
                '          <geometry><box><size>%.4f %.4f %.4f</size></box></geometry>'
                % (sx, sy, h),
                '        </collision>',
            ]
        lines += ['      </link>', '    </model>']
    lines += ['  </world>', '</sdf>', '']
    return '\n'.join(lines)


def write_house(seed, out, name, renderer):
    house, size, spawn, cut = generate(seed)
    os.makedirs(out, exist_ok=True)
    world = os.path.join(out, name + '.world')
    write_atomically(world, world_sdf(house, name, seed, size, spawn))
    base = os.path.join(out, name)
    res = subprocess.run([renderer, world, base, '--resolution', '0.05'],
                         capture_output=True, text=True)
    if res.returncode != 0:
        raise HouseError('render_world_map failed on %s: %s' % (world, res.stderr.strip()))
    ox, oy = spawn
    desc = {'name': name, 'seed': seed, 'size': [size[0], size[1]],
            'spawn': {'x': 0.0, 'y': 0.0, 'yaw': 0.0},
            'rooms': [[_r(a - ox), _r(b - oy), _r(c - ox), _r(d - oy)]
                      for a, b, c, d in house.rooms],
            'doors': [dict(d, x=_r(d['x'] - ox), y=_r(d['y'] - oy)) for d in house.doors],
            'diagonal_wall_room': cut}
    write_atomically(base + '.json', json.dumps(desc, indent=1, sort_keys=True) + '\n')
    return world, desc


def main(argv=None):
    ap = argparse.ArgumentParser(prog='house_world.py', description=__doc__.split('\n\n')[0])
    sub = ap.add_subparsers(dest='mode', required=True)
    one = sub.add_parser('one', help='one house')
    one.add_argument('--seed', type=int, required=True)
    one.add_argument('--out', required=True)
    one.add_argument('--name', default=None, help='default house_SEED')
    many = sub.add_parser('set', help='the %d shipped houses (seeds 1-%d)' % (SET_COUNT, SET_COUNT))
    many.add_argument('--out', default=SHIPPED_DIR)
    for p in (one, many):
        p.add_argument('--renderer', default=DEFAULT_RENDERER, help='render_world_map binary')
    args = ap.parse_args(argv)
    if not (os.path.isfile(args.renderer) and os.access(args.renderer, os.X_OK)):
        ap.error('--renderer %r: render_world_map not found; build the workspace '
                 '(tools/build.sh) or pass --renderer' % args.renderer)
    if args.mode == 'one':
        jobs = [(args.seed, args.name or 'house_%02d' % args.seed)]
        if os.sep in jobs[0][1] or jobs[0][1].startswith('.'):
            ap.error('--name %r: must be a plain file name' % jobs[0][1])
    else:
        jobs = [(s, 'house_%02d' % s) for s in range(1, SET_COUNT + 1)]
    for seed, name in jobs:
        try:
            world, desc = write_house(seed, args.out, name, args.renderer)
        except HouseError as e:
            sys.exit('house_world.py: %s' % e)
        print('%s: %g m x %g m, %d rooms, doors %s m' % (
            world, desc['size'][0], desc['size'][1], len(desc['rooms']),
            ' '.join('%.2f' % d['width'] for d in desc['doors'])))
    return 0


if __name__ == '__main__':
    sys.exit(main())
