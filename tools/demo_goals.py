#!/usr/bin/env python3
"""The navigation goals of `make demo` for a world without a goal list, sampled from the saved map.

  demo_goals.py MAP.yaml --spawn X,Y,YAW [--config-dir CONFIG] [--count 4]

prints one `x,y,yaw` line per goal (world frame), in the order the demo visits them.

Where the robot can go is the saved map's free space farther than the robot's inscribed radius
(demo_report.reach_clearance: the footprint of the robot's costmap_common_params.yaml, at least
0.15 m) from occupied and unknown cells, connected to where exploration started: a 0.40 m door
that the local planner drives through joins the rooms on either side. A goal needs `clearance`
(0.4 m) round it, so that the robot can turn there.

Every room gets a goal: the roomy space (ROOM_CLEARANCE from walls) splits at doors and gaps
narrower than twice that, and each of its parts of at least MIN_ROOM_AREA gets the cell farthest
from walls in it (the room's middle). When that gives fewer than `count` goals, the rest are
spread by farthest-point sampling on path distance (the geodesic distance through where the robot
can go, not the straight line, so a room behind a wall is far). The goals are then visited in the
order of a greedy nearest-next tour by path distance from the start. Everything is deterministic
(ties go to the lowest cell index; the goal headings come from a seeded generator)."""
import argparse
import math
import os
import random
import sys

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from demo_report import load_trinary, reach_clearance  # noqa: E402

GOAL_CLEARANCE = 0.4   # m from walls for a goal
ROOM_CLEARANCE = 0.5   # m: openings narrower than twice this separate rooms
MIN_ROOM_AREA = 0.25   # m^2 of roomy space for a part to count as a room
START_RADIUS = 0.4     # m: the free cells this near the start start the search


class GoalError(RuntimeError):
    """The saved map leaves nowhere to send a goal, named."""


def _graph(mask, res):
    """The 8-connected graph of the cells in `mask` (edge weights in metres) and the flat
    indices of its nodes."""
    h, w = mask.shape
    node = -np.ones(mask.shape, dtype=np.int64)
    flat = np.flatnonzero(mask)
    node.flat[flat] = np.arange(len(flat))
    rows, cols, weights = [], [], []
    for dy, dx, cost in ((0, 1, res), (1, 0, res), (1, 1, res * math.sqrt(2.0)),
                         (1, -1, res * math.sqrt(2.0))):
        # Pairs (a, b) with b = a shifted by (dy, dx); dy >= 0.
        xa = slice(0, w - dx) if dx >= 0 else slice(-dx, w)
        xb = slice(dx, w) if dx >= 0 else slice(0, w + dx)
        a, b = node[0:h - dy, xa], node[dy:h, xb]
        both = (a >= 0) & (b >= 0)
        rows.append(a[both])
        cols.append(b[both])
        weights.append(np.full(int(both.sum()), cost))
    rows, cols, weights = np.concatenate(rows), np.concatenate(cols), np.concatenate(weights)
    n = len(flat)
    graph = coo_matrix((weights, (rows, cols)), shape=(n, n)).tocsr()
    return graph, flat, node


def sample_goals(map_yaml, spawn, config_dir=None, count=4, clearance=GOAL_CLEARANCE, seed=1):
    """Goals (x, y, yaw) in the world frame; the saved map's frame is the world frame moved to the
    exploration's spawn pose `spawn` (its origin is where exploration started)."""
    free, occ, res, origin = load_trinary(map_yaml)
    h, w = free.shape
    # Metres from each cell to the nearest occupied or unknown cell.
    room = ndimage.distance_transform_edt(free & ~occ) * res
    passable = room > reach_clearance(config_dir or os.path.join(HERE, '..', 'config'))
    graph, flat, node = _graph(passable, res)
    # Start: the passable cells within START_RADIUS of the map's origin (the robot's first cell
    # may be nearer a wall than the inscribed radius).
    sx, sy = -origin[0] / res, -origin[1] / res
    ys, xs = np.divmod(flat, w)
    near = np.hypot(xs + 0.5 - sx, ys + 0.5 - sy) * res <= START_RADIUS
    if not near.any():
        raise GoalError('%s: no free cell the robot fits in within %.1f m of where exploration '
                        'started' % (map_yaml, START_RADIUS))
    from_start = dijkstra(graph, directed=False, indices=np.flatnonzero(near), min_only=True)
    reachable = np.isfinite(from_start)
    candidate = reachable & (room.flat[flat] >= clearance)
    if not candidate.any():
        raise GoalError('%s: no reachable free cell %.2f m from walls to send a goal to' %
                        (map_yaml, clearance))

    chosen = []
    # A goal in every room: the roomy part's cell farthest from walls.
    roomy = np.zeros(free.shape, dtype=bool)
    roomy.flat[flat[candidate & (room.flat[flat] >= ROOM_CLEARANCE)]] = True
    labels, parts = ndimage.label(roomy, structure=np.ones((3, 3)))
    if parts:
        sizes = ndimage.sum(roomy, labels, index=np.arange(1, parts + 1)) * res * res
        for part in np.flatnonzero(sizes >= MIN_ROOM_AREA) + 1:
            cells = np.flatnonzero(labels.ravel() == part)
            chosen.append(int(node.flat[cells[int(np.argmax(room.flat[cells]))]]))
    # Then farthest-point sampling on path distance up to `count` goals; each goal's path
    # distances serve the sampling and the visit order.
    cand_nodes = np.flatnonzero(candidate)
    if not chosen:
        chosen.append(int(cand_nodes[int(np.argmax(from_start[cand_nodes]))]))
    from_goal = {g: dijkstra(graph, directed=False, indices=g) for g in chosen}
    nearest = np.min([from_goal[g] for g in chosen], axis=0)
    while len(chosen) < count:
        d = nearest[cand_nodes]
        if not d.max() > 0.0:
            break
        best = int(cand_nodes[int(np.argmax(d))])
        chosen.append(best)
        from_goal[best] = dijkstra(graph, directed=False, indices=best)
        nearest = np.minimum(nearest, from_goal[best])
    # Visit order: nearest next by path distance, from the start.
    order, left, here = [], list(chosen), from_start
    while left:
        nxt = min(left, key=lambda g: (here[g], g))
        order.append(nxt)
        left.remove(nxt)
        here = from_goal[nxt]
    rng = random.Random(seed)
    c, s = math.cos(spawn[2]), math.sin(spawn[2])
    goals = []
    for g in order:
        y, x = divmod(int(flat[g]), w)
        mx, my = origin[0] + (x + 0.5) * res, origin[1] + (y + 0.5) * res
        goals.append((spawn[0] + c * mx - s * my, spawn[1] + s * mx + c * my,
                      rng.uniform(-math.pi, math.pi)))
    return goals


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('map_yaml')
    parser.add_argument('--spawn', default='0,0,0', help='exploration spawn pose X,Y,YAW')
    parser.add_argument('--config-dir', default=None)
    parser.add_argument('--count', type=int, default=4)
    args = parser.parse_args(argv)
    spawn = tuple(float(v) for v in args.spawn.split(','))
    try:
        goals = sample_goals(args.map_yaml, spawn, args.config_dir, args.count)
    except GoalError as e:
        print('demo_goals.py: %s' % e, file=sys.stderr)
        return 1
    for g in goals:
        print('%.3f,%.3f,%.3f' % g)
    return 0


if __name__ == '__main__':
    sys.exit(main())
