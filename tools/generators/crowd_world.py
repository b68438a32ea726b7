#!/usr/bin/env python3
"""Crowd worlds: a corridor or an open hall with people walking in it, for navigation among moving
obstacles.

    tools/generators/crowd_world.py one --kind corridor --seed 3 --people 3 --speed 0.8 1.2 --out DIR
    tools/generators/crowd_world.py one --kind doorway --seed 1 --people 1 --speed 0.5 1.0 --out DIR
    tools/generators/crowd_world.py set [--out minibot3d_sim/worlds/crowds]   # the shipped worlds
    tools/generators/crowd_world.py bench --out DIR   # make bench's 50 + 10 worlds

The robot starts at the origin facing +x and its goal is GOAL_DISTANCE (10 m) straight ahead, so
start and goal are the same in the world frame and in `odom`, and the optimal path is the straight
line between them (no static obstacle is in the way): the optimal time is GOAL_DISTANCE /
max_vel_x. Kinds:
  * corridor: 2.0 m wide between walls, closed 3 m behind the start and 3 m past the goal; the
    people start ahead of the robot and walk head-on towards it, past the start to the far end,
    then back (social force pedestrians, Helbing & Molnar 1995, as the simulator plays them: they
    also give way to the robot);
  * hall: 14 m x 8 m; each person walks either across the robot's route (between the side walls)
    or along it head-on (between the end walls), there and back (social force pedestrians);
  * random: the same hall with moving obstacles as DynaBARN makes them (Nair et al. 2022): each
    follows a looping scripted trajectory through 3-5 random points at its own constant speed and
    does not react to anything (an SDF <actor> <script>, waypoints every 0.25 m so that Gazebo's
    spline keeps the speed constant on the straight stretches);
  * doorway: the same hall cut in two by a wall across it at x = DOOR_X with one DOOR_WIDTH door
    (its centre drawn within +-DOOR_SPAN of the hall's centre line), and one person (--people 1)
    standing in the door, which the robot must pass, for a time drawn from STAND (s), then walking
    aside into the far room, where they stay (scripted: they do not react to the robot). The
    optimal path runs through the door's centre.
No person starts within START_CLEAR of the robot. Each person's speed is drawn from the range
given (the social force pedestrians' desired speed; they may walk faster when pushed).

Everything is seeded (Python's random.Random) and written with fixed precision: the same arguments
give byte-identical files. Writes NAME.world (SDF: static walls and the actors), NAME.pgm +
NAME.yaml (the static ground-truth map at 0.05 m, rendered by minibot3d_sim's render_world_map)
and NAME.json (kind, seed, start, goal, optimal length, people with their speeds and routes)."""
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
SHIPPED_DIR = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'crowds')

KINDS = ('corridor', 'hall', 'random', 'doorway')
GOAL_DISTANCE = 10.0          # m, start (0, 0) to goal (GOAL_DISTANCE, 0)
CORRIDOR_WIDTH = 2.0          # m between the walls' inner faces
CORRIDOR_MARGIN = 3.0         # m of corridor behind the start and past the goal
HALL_BEHIND, HALL_AHEAD = 2.0, 2.0    # m of hall behind the start and past the goal
HALL_HALF_WIDTH = 4.0         # m, centre line to a side wall's inner face
WALL, WALL_HEIGHT = 0.15, 1.0
WALL_KEEP = 0.6               # m between a person's route and a wall
START_CLEAR = 1.5             # m round the robot's start with nobody in it at the start
SPACING = 0.7                 # m between two people's starting points, at least
WAYPOINT_STEP = 0.25          # m between a scripted actor's waypoints
SPEED_LIMIT = (0.05, 2.5)     # m/s, the speeds a person may be given
DOOR_X = 5.0                  # m, the doorway world's wall's near face
DOOR_WIDTH = 0.9              # m, its door
DOOR_SPAN = 1.9               # m, the door's centre within +-DOOR_SPAN of y = 0
STAND = (20.0, 40.0)          # s, how long the person stands in the door
ASIDE = 1.5                   # m the person then walks into the far room and sideways

# Shipped worlds (loaded by the tests) and make bench's set.
SHIPPED = [('corridor', 1, 3, (0.8, 1.2)), ('hall', 1, 6, (0.2, 0.5)), ('random', 1, 8, (0.1, 0.5)),
           ('doorway', 1, 1, (0.5, 1.0))]
BENCH_SEEDS = 50                      # mixed worlds, obstacles up to 0.5 m/s
BENCH_KINDS = ('corridor', 'hall', 'random')
BENCH_PEOPLE = {'corridor': (2, 4), 'hall': (4, 8), 'random': (5, 10)}
BENCH_SPEED = (0.1, 0.5)
HEAD_ON_RUNS, HEAD_ON_PEOPLE, HEAD_ON_SPEED = 10, 3, (0.8, 1.2)


class CrowdError(ValueError):
    """Bad parameters or a seed that does not give a world, named."""


def _r(v):
    return round(v, 4) + 0.0


def bounds(kind):
    """Inner faces of the walls: x0, y0, x1, y1."""
    if kind == 'corridor':
        return (-CORRIDOR_MARGIN, -CORRIDOR_WIDTH / 2, GOAL_DISTANCE + CORRIDOR_MARGIN,
                CORRIDOR_WIDTH / 2)
    return (-HALL_BEHIND, -HALL_HALF_WIDTH, GOAL_DISTANCE + HALL_AHEAD, HALL_HALF_WIDTH)


def _far_enough(p, placed):
    return (math.hypot(p[0], p[1]) >= START_CLEAR and
            all(math.hypot(p[0] - q[0], p[1] - q[1]) >= SPACING for q in placed))


def _place_on(rng, route, placed):
    """A starting point on a route (a list of points, walked in order), away from the start and the
    others: the point and the index of the route point it walks to next."""
    legs = list(zip(route, route[1:]))
    for _ in range(200):
        k = rng.randrange(len(legs))
        (ax, ay), (bx, by) = legs[k]
        u = rng.random()
        p = (ax + u * (bx - ax), ay + u * (by - ay))
        if _far_enough(p, placed):
            return p, k + 1
    return None, None


def _door_y(desc):
    return desc['door'][1]


def _doorway(rng, count, speed):
    """The doorway world's door (its centre) and its one person, who stands in it."""
    if count != 1:
        raise CrowdError('doorway: --people %d: must be 1 (the person standing in the door)'
                         % count)
    door = (DOOR_X + WALL / 2, round(rng.uniform(-DOOR_SPAN, DOOR_SPAN), 3))
    stand = round(rng.uniform(*STAND), 1)
    side = 1.0 if door[1] >= 0 else -1.0   # away from the hall's centre line, off the route
    aside = (door[0] + ASIDE, door[1] + side * ASIDE)
    person = {'name': 'person_0', 'speed': round(rng.uniform(*speed), 3), 'route': 'doorway',
              'stand': stand, 'start': [_r(door[0]), _r(door[1])],
              'goals': [[_r(aside[0]), _r(aside[1])]]}
    return [_r(door[0]), _r(door[1])], person


def _people_routes(rng, kind, count, speed):
    x0, y0, x1, y1 = bounds(kind)
    people = []
    placed = []
    for i in range(count):
        v = round(rng.uniform(*speed), 3)
        for _ in range(50):
            if kind == 'corridor':
                lane = CORRIDOR_WIDTH / 2 - 0.4
                far, near = x1 - 0.5, x0 + 0.5
                ya, yb = rng.uniform(-lane, lane), rng.uniform(-lane, lane)
                # Head-on: start ahead of the robot, beyond the start clearance, walking to -x.
                sx = rng.uniform(START_CLEAR + 1.0, x1 - 0.6)
                start = (sx, ya)
                goals = [(near, yb), (far, ya)]
                route = 'head-on'
            elif kind == 'hall':
                if rng.random() < 0.5:
                    x = rng.uniform(1.5, GOAL_DISTANCE - 1.5)
                    a, b = (x, y0 + WALL_KEEP), (x + rng.uniform(-1.5, 1.5), y1 - WALL_KEEP)
                    if rng.random() < 0.5:
                        a, b = b, a
                    route = 'crossing'
                else:
                    y = rng.uniform(-2.0, 2.0)
                    a, b = (x1 - WALL_KEEP, y), (x0 + WALL_KEEP, y + rng.uniform(-1.0, 1.0))
                    route = 'head-on'
                start, nxt = _place_on(rng, [a, b, a], placed)
                if start is None:
                    continue
                goals = [b, a] if nxt == 1 else [a, b]
            else:
                n = rng.randint(3, 5)
                pts = [(rng.uniform(x0 + WALL_KEEP, x1 - WALL_KEEP),
                        rng.uniform(y0 + WALL_KEEP, y1 - WALL_KEEP)) for _ in range(n)]
                start = pts[0]
                goals = pts[1:] + [pts[0]]
                route = 'random'
            if _far_enough(start, placed):
                break
        else:
            raise CrowdError('no room for person %d of %d in a %s (START_CLEAR %.1f m, SPACING '
                             '%.1f m)' % (i + 1, count, kind, START_CLEAR, SPACING))
        placed.append(start)
        people.append({'name': 'person_%d' % i, 'speed': v, 'route': route,
                       'start': [_r(start[0]), _r(start[1])],
                       'goals': [[_r(x), _r(y)] for x, y in goals]})
    return people


def _script_waypoints(person):
    """A scripted actor's looping trajectory: the start, then its goals (the last is the start
    again), at its speed, with a waypoint every WAYPOINT_STEP m or less."""
    pts = [tuple(person['start'])] + [tuple(g) for g in person['goals']]
    out, t = [], 0.0
    for (ax, ay), (bx, by) in zip(pts, pts[1:]):
        length = math.hypot(bx - ax, by - ay)
        yaw = math.atan2(by - ay, bx - ax)
        steps = max(1, int(math.ceil(length / WAYPOINT_STEP)))
        for s in range(steps):
            u = s / steps
            out.append((t + u * length / person['speed'], ax + u * (bx - ax), ay + u * (by - ay),
                        yaw))
        t += length / person['speed']
    x, y, _ = out[0][1], out[0][2], out[0][3]
    out.append((t, x, y, out[-1][3]))
    return out


def _doorway_waypoints(person):
    """The doorway person's trajectory (not looping): standing in the door until `stand` s (a
    waypoint every second, so that Gazebo's spline keeps them still), walking aside at their speed,
    then standing there."""
    (dx, dy), (ax, ay) = person['start'], person['goals'][0]
    yaw = math.atan2(ay - dy, ax - dx)
    out = [(float(t), dx, dy, yaw) for t in range(int(person['stand']))]
    out.append((person['stand'], dx, dy, yaw))
    length = math.hypot(ax - dx, ay - dy)
    steps = max(1, int(math.ceil(length / WAYPOINT_STEP)))
    for k in range(1, steps + 1):
        u = k / steps
        out.append((person['stand'] + u * length / person['speed'], dx + u * (ax - dx),
                    dy + u * (ay - dy), yaw))
    end = out[-1][0]
    out += [(end + 1.0, ax, ay, yaw), (end + 100000.0, ax, ay, yaw)]
    return out


def world_sdf(desc):
    x0, y0, x1, y1 = bounds(desc['kind'])
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    lx, ly = x1 - x0 + 2 * WALL, y1 - y0
    lines = [
        '<?xml version="1.0"?>',
        '<!-- %s: a generated %s, %g m x %g m, %d people at %g-%g m/s; the robot starts at the'
        % (desc['name'], desc['kind'], x1 - x0, y1 - y0, len(desc['people']),
           desc['speed'][0], desc['speed'][1]),
        '     origin facing +x, its goal is (%g, 0).' % GOAL_DISTANCE,
    ]
    if desc['kind'] == 'doorway':
        lines.append('     A %g m door at (%.3f, %.3f); %s stands in it for %g s.'
                     % (DOOR_WIDTH, desc['door'][0], desc['door'][1], desc['people'][0]['name'],
                        desc['people'][0]['stand']))
    lines += [
        '     Regenerate with: tools/generators/crowd_world.py one --kind %s --seed %d --people %d'
        % (desc['kind'], desc['seed'], len(desc['people'])),
        '     --speed %g %g --name %s -->' % (desc['speed'][0], desc['speed'][1], desc['name']),
        '<sdf version="1.6">',
        '  <world name="%s">' % desc['name'],
        '    <include><uri>model://ground_plane</uri></include>',
        '    <include><uri>model://sun</uri></include>',
        '    <model name="walls">',
        '      <static>true</static>',
        '      <link name="walls">',
    ]
    walls = [('south', cx, y0 - WALL / 2, lx, WALL), ('north', cx, y1 + WALL / 2, lx, WALL),
             ('west', x0 - WALL / 2, cy, WALL, ly), ('east', x1 + WALL / 2, cy, WALL, ly)]
    if desc['kind'] == 'doorway':
        wx, dy = DOOR_X + WALL / 2, _door_y(desc)
        lo, hi = dy - DOOR_WIDTH / 2, dy + DOOR_WIDTH / 2
        walls += [('door_south', wx, (y0 + lo) / 2, WALL, lo - y0),
                  ('door_north', wx, (hi + y1) / 2, WALL, y1 - hi)]
    for name, x, y, sx, sy in walls:
        lines += ['        <collision name="%s">' % name,
                  '          <pose>%.4f %.4f %.4f 0 0 0</pose>' % (x, y, WALL_HEIGHT / 2),
                  '          <geometry><box><size>%.4f %.4f %.4f</size></box></geometry>'
                  % (sx, sy, WALL_HEIGHT),
                  '        </collision>']
    lines += ['      </link>', '    </model>']
    for p in desc['people']:
        sx, sy = p['start']
        gx, gy = p['goals'][0]
        yaw = math.atan2(gy - sy, gx - sx)
        lines += ['    <actor name="%s">' % p['name'],
                  '      <pose>%.4f %.4f 0 0 0 %.4f</pose>' % (sx, sy, yaw)]
        if desc['kind'] in ('random', 'doorway'):
            doorway = desc['kind'] == 'doorway'
            lines += ['      <script>',
                      '        <loop>%s</loop>' % ('false' if doorway else 'true'),
                      '        <trajectory id="0" type="walking">']
            for t, x, y, a in _doorway_waypoints(p) if doorway else _script_waypoints(p):
                lines.append('          <waypoint><time>%.3f</time><pose>%.4f %.4f 0 0 0 %.4f'
                             '</pose></waypoint>' % (t, x, y, a))
            lines += ['        </trajectory>', '      </script>']
        else:
            lines.append('      <plugin name="walk" filename="libminibot3d_social_force.so">')
            lines += ['        <goal>%.4f %.4f</goal>' % tuple(g) for g in p['goals']]
            lines += ['        <desired_speed>%.3f</desired_speed>' % p['speed'],
                      '      </plugin>']
        lines.append('    </actor>')
    lines += ['  </world>', '</sdf>', '']
    return '\n'.join(lines)


def generate(kind, seed, people, speed, name):
    if kind not in KINDS:
        raise CrowdError('kind %r: not one of %s' % (kind, ', '.join(KINDS)))
    if not 0 <= people <= 30:
        raise CrowdError('people %d: must be 0-30' % people)
    lo, hi = speed
    if not (SPEED_LIMIT[0] <= lo <= hi <= SPEED_LIMIT[1]):
        raise CrowdError('speed %g %g: must be MIN <= MAX within %g-%g m/s'
                         % (lo, hi, SPEED_LIMIT[0], SPEED_LIMIT[1]))
    rng = random.Random('%s/%d' % (kind, seed))
    x0, y0, x1, y1 = bounds(kind)
    desc = {'name': name, 'kind': kind, 'seed': seed, 'speed': [lo, hi],
            'bounds': [x0, y0, x1, y1],
            'start': {'x': 0.0, 'y': 0.0, 'yaw': 0.0},
            'goal': {'x': GOAL_DISTANCE, 'y': 0.0, 'yaw': 0.0},
            'optimal_length': GOAL_DISTANCE}
    if kind == 'doorway':
        door, person = _doorway(rng, people, (lo, hi))
        desc['door'] = door
        desc['optimal_length'] = _r(math.hypot(door[0], door[1]) +
                                    math.hypot(GOAL_DISTANCE - door[0], door[1]))
        desc['people'] = [person]
    else:
        desc['people'] = _people_routes(rng, kind, people, (lo, hi))
    return desc


def write_world(desc, out, renderer):
    os.makedirs(out, exist_ok=True)
    base = os.path.join(out, desc['name'])
    world = base + '.world'
    write_atomically(world, world_sdf(desc))
    res = subprocess.run([renderer, world, base, '--resolution', '0.05'],
                         capture_output=True, text=True)
    if res.returncode != 0:
        raise CrowdError('render_world_map failed on %s: %s' % (world, res.stderr.strip()))
    write_atomically(base + '.json', json.dumps(desc, indent=1, sort_keys=True) + '\n')
    return world


def bench_set():
    """make bench's worlds: BENCH_SEEDS mixed worlds with obstacles up to 0.5 m/s (the kinds in
    turn, the number of people drawn per seed), then HEAD_ON_RUNS corridors with 3 people
    walking head-on at pedestrian speeds."""
    jobs = []
    for s in range(BENCH_SEEDS):
        kind = BENCH_KINDS[s % len(BENCH_KINDS)]
        lo, hi = BENCH_PEOPLE[kind]
        n = random.Random('people/%d' % s).randint(lo, hi)
        jobs.append((kind, s, n, BENCH_SPEED, 'mixed_%02d_%s' % (s, kind)))
    for s in range(HEAD_ON_RUNS):
        jobs.append(('corridor', 100 + s, HEAD_ON_PEOPLE, HEAD_ON_SPEED, 'headon_%02d' % s))
    return jobs


def main(argv=None):
    ap = argparse.ArgumentParser(prog='crowd_world.py', description=__doc__.split('\n\n')[0])
    sub = ap.add_subparsers(dest='mode', required=True)
    one = sub.add_parser('one', help='one world')
    one.add_argument('--kind', required=True, help=', '.join(KINDS))
    one.add_argument('--seed', type=int, required=True)
    one.add_argument('--people', type=int, required=True)
    one.add_argument('--speed', type=float, nargs=2, metavar=('MIN', 'MAX'), required=True,
                     help='m/s')
    one.add_argument('--out', required=True)
    one.add_argument('--name', default=None, help='default KIND_SEED')
    shipped = sub.add_parser('set', help='the %d shipped worlds' % len(SHIPPED))
    shipped.add_argument('--out', default=SHIPPED_DIR)
    bench = sub.add_parser('bench', help="make bench's %d worlds" % (BENCH_SEEDS + HEAD_ON_RUNS))
    bench.add_argument('--out', required=True)
    for p in (one, shipped, bench):
        p.add_argument('--renderer', default=DEFAULT_RENDERER, help='render_world_map binary')
    args = ap.parse_args(argv)
    if not (os.path.isfile(args.renderer) and os.access(args.renderer, os.X_OK)):
        ap.error('--renderer %r: render_world_map not found; build the workspace '
                 '(tools/build.sh) or pass --renderer' % args.renderer)
    if args.mode == 'one':
        name = args.name or '%s_%02d' % (args.kind, args.seed)
        if os.sep in name or name.startswith('.'):
            ap.error('--name %r: must be a plain file name' % name)
        jobs = [(args.kind, args.seed, args.people, tuple(args.speed), name)]
    elif args.mode == 'set':
        jobs = [(k, s, n, v, '%s_%02d' % (k, s)) for k, s, n, v in SHIPPED]
    else:
        jobs = bench_set()
    for kind, seed, people, speed, name in jobs:
        try:
            world = write_world(generate(kind, seed, people, speed, name), args.out,
                                args.renderer)
        except CrowdError as e:
            sys.exit('crowd_world.py: %s' % e)
        print('%s: %s, %d people at %g-%g m/s' % (world, kind, people, speed[0], speed[1]))
    return 0


if __name__ == '__main__':
    sys.exit(main())
