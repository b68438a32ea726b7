#!/usr/bin/env python3
"""Clutter worlds: a field of thin posts between two walls, with a passage of a known width.

    tools/generators/clutter_world.py one --gap 0.5 --seed 7 --out DIR [--name NAME]
    tools/generators/clutter_world.py set [--out minibot3d_sim/worlds/clutter]   # the 50 shipped

A world is a room 3 m wide (two long walls, closed at both ends so that no route goes round the
field). The robot starts at (0, 0) facing +x; the goal is 5.5 m ahead at (5.5, 0), beyond a field
of posts (radius 0.04 m) 1.0-4.5 m ahead that spans the room's width. The simulator's odometry
starts at the spawn pose, so start and goal are the same in the world frame and in `odom`.

The posts come from Poisson-disc sampling (Bridson 2007) with a spacing that leaves the field
closed to a disc of the requested width. Then, on the clearance field (the exact Euclidean
distance transform of the free space, sampled on a grid):
  1. while the widest disc that gets from start to goal is narrower than `gap`, a post at the
     bottleneck (the narrowest point of the widest path, a maximin path found by binary search
     on the clearance with connected components) is removed;
  2. while it is wider than `gap + tolerance`, a post at the bottleneck is moved towards the
     other obstacle there, so that the gap closes to `gap + tolerance / 2`.
The narrowest gap is refined exactly from the two obstacles that make the bottleneck (the surface
distance between them) when the grid value agrees with it within one cell; otherwise the grid
value is used. Everything is seeded (numpy's PCG64) and written with fixed precision, so the same
arguments give byte-identical files.

Writes NAME.world (SDF, collision cylinders and boxes as the simulator reads them), NAME.pgm +
NAME.yaml (the ground-truth map, rendered by minibot3d_sim's render_world_map) and NAME.json
(start, goal, requested and achieved narrowest gap, optimal path lengths, the post count).

Optimal path length: the shortest path of a disc of the robot's circumscribed radius
(hypot(0.12, 0.115) = 0.166 m for the 0.24 m x 0.23 m footprint). A path that this disc can follow
the robot can follow at any heading, so it is an achievable reference; every gap of the shipped
set (>= 0.36 m) lets that disc through. The length for the inscribed disc (0.115 m, which no real
path of the rectangle can beat) is given too. Lengths come from Dijkstra on a 16-connected grid,
then line-of-sight shortening and pulling the path taut, every segment checked against the exact
clearance: a feasible path, so never shorter than the optimum; round one post it is within
0.005 % of the closed-form length (test/test_clutter_world.py).
"""
import argparse
import json
import math
import os
import subprocess
import sys
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_RENDERER = os.path.join(ROOT, 'devel', 'lib', 'minibot3d_sim', 'render_world_map')
SHIPPED_DIR = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'clutter')

ROBOT_LENGTH, ROBOT_WIDTH = 0.24, 0.23
INSCRIBED_RADIUS = min(ROBOT_LENGTH, ROBOT_WIDTH) / 2.0
CIRCUMSCRIBED_RADIUS = math.hypot(ROBOT_LENGTH / 2.0, ROBOT_WIDTH / 2.0)

# The shipped set: 50 worlds, narrowest gaps evenly spread over 0.36-0.80 m, seed = index.
SET_COUNT, SET_GAP_MIN, SET_GAP_MAX = 50, 0.36, 0.80

WALL_THICKNESS, WALL_HEIGHT, POST_HEIGHT = 0.1, 0.5, 0.5
DECIMALS = 4  # positions are rounded to 0.1 mm before anything is measured


class ClutterError(ValueError):
    """A bad argument (the message names the parameter) or a world that cannot be made."""


@dataclass(frozen=True)
class Params:
    gap: float                    # requested narrowest gap (m)
    seed: int
    post_radius: float = 0.04
    width: float = 3.0            # between the walls' inner faces
    goal_distance: float = 5.5    # start (0, 0) -> goal (goal_distance, 0)
    field_start: float = 1.0      # the posts lie in x in [field_start, field_end]
    field_end: float = 4.5
    behind: float = 1.0           # room behind the start
    beyond: float = 1.0           # room beyond the goal
    spacing: float = 0.8          # Poisson-disc spacing, in units of gap + 2 * post_radius
    tolerance: float = 0.01       # achieved gap is in [gap, gap + tolerance]
    resolution: float = 0.005     # grid of the clearance field (m)
    max_iterations: int = 400

    def validate(self):
        def bad(name, value, need):
            raise ClutterError('%s=%r: %s' % (name, value, need))
        for name in ('gap', 'post_radius', 'width', 'goal_distance', 'spacing', 'tolerance',
                     'resolution', 'behind', 'beyond', 'field_start', 'field_end'):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v):
                bad(name, v, 'must be a finite number')
        if not self.gap > 0.0:
            bad('gap', self.gap, 'must be > 0 m')
        if self.gap < 2.0 * CIRCUMSCRIBED_RADIUS:
            bad('gap', self.gap, 'is below the robot\'s circumscribed diameter %.3f m: no '
                'optimal path for it would exist' % (2.0 * CIRCUMSCRIBED_RADIUS))
        if not 0.0 < self.post_radius <= 0.5:
            bad('post_radius', self.post_radius, 'must be in (0, 0.5] m')
        if not self.width > 0.0:
            bad('width', self.width, 'must be > 0 m')
        if self.gap > self.width / 2.0:
            bad('gap', self.gap, 'must be at most half of width=%g m, or the field cannot be '
                'closed around the passage' % self.width)
        if not self.spacing > 0.0:
            bad('spacing', self.spacing, 'must be > 0')
        if not self.tolerance > 0.0:
            bad('tolerance', self.tolerance, 'must be > 0 m')
        if not 0.0 < self.resolution <= self.tolerance / 2.0:
            bad('resolution', self.resolution, 'must be in (0, tolerance/2 = %g] m'
                % (self.tolerance / 2.0))
        if not self.behind > CIRCUMSCRIBED_RADIUS:
            bad('behind', self.behind, 'must leave room for the robot behind the start (> %.3f m)'
                % CIRCUMSCRIBED_RADIUS)
        if not self.beyond > CIRCUMSCRIBED_RADIUS:
            bad('beyond', self.beyond, 'must leave room for the robot beyond the goal (> %.3f m)'
                % CIRCUMSCRIBED_RADIUS)
        if not (CIRCUMSCRIBED_RADIUS + self.post_radius < self.field_start
                < self.field_end < self.goal_distance - CIRCUMSCRIBED_RADIUS - self.post_radius):
            bad('field_start/field_end', (self.field_start, self.field_end),
                'need start + robot < field_start < field_end < goal_distance=%g - robot'
                % self.goal_distance)
        if not isinstance(self.seed, int) or isinstance(self.seed, bool) or self.seed < 0:
            bad('seed', self.seed, 'must be an integer >= 0')
        if not isinstance(self.max_iterations, int) or self.max_iterations < 1:
            bad('max_iterations', self.max_iterations, 'must be an integer >= 1')


# ----------------------------------------------------------------------------------------------
# Geometry: obstacles are circles (posts) and axis-aligned boxes (walls).

@dataclass
class Scene:
    posts: np.ndarray                      # (n, 2) centres
    post_radius: float
    boxes: list                            # [(xmin, ymin, xmax, ymax)]
    bounds: tuple                          # (xmin, ymin, xmax, ymax) of the free space searched
    start: tuple
    goal: tuple

    def obstacle_distances(self, p):
        """Distance from point p to every obstacle's surface: posts first, then boxes."""
        d = [math.hypot(p[0] - c[0], p[1] - c[1]) - self.post_radius for c in self.posts]
        for b in self.boxes:
            dx = max(b[0] - p[0], 0.0, p[0] - b[2])
            dy = max(b[1] - p[1], 0.0, p[1] - b[3])
            d.append(math.hypot(dx, dy))
        return np.array(d)


def box_clearance(xs, ys, b):
    dx = np.maximum(np.maximum(b[0] - xs, 0.0), xs - b[2])
    dy = np.maximum(np.maximum(b[1] - ys, 0.0), ys - b[3])
    return np.hypot(dx[np.newaxis, :], dy[:, np.newaxis])


def clearance_points(scene, pts):
    """Exact clearance (distance to the nearest obstacle surface) at points (k, 2)."""
    pts = np.asarray(pts, dtype=float)
    c = np.full(len(pts), np.inf)
    for b in scene.boxes:
        dx = np.maximum(np.maximum(b[0] - pts[:, 0], 0.0), pts[:, 0] - b[2])
        dy = np.maximum(np.maximum(b[1] - pts[:, 1], 0.0), pts[:, 1] - b[3])
        c = np.minimum(c, np.hypot(dx, dy))
    if len(scene.posts):
        d = np.hypot(pts[:, None, 0] - scene.posts[None, :, 0],
                     pts[:, None, 1] - scene.posts[None, :, 1]) - scene.post_radius
        c = np.minimum(c, d.min(axis=1))
    return c


@dataclass
class Grid:
    xs: np.ndarray
    ys: np.ndarray
    clear: np.ndarray   # (ny, nx) clearance at cell centres
    resolution: float

    def cell(self, p):
        i = int(round((p[0] - self.xs[0]) / self.resolution))
        j = int(round((p[1] - self.ys[0]) / self.resolution))
        if not (0 <= i < len(self.xs) and 0 <= j < len(self.ys)):
            raise ClutterError('point (%g, %g) is outside the searched area' % tuple(p))
        return j, i

    def point(self, cell):
        return float(self.xs[cell[1]]), float(self.ys[cell[0]])


def clearance_grid(scene, resolution):
    """The exact Euclidean distance transform of the free space, sampled at cell centres."""
    x0, y0, x1, y1 = scene.bounds
    xs = np.arange(x0 + resolution / 2.0, x1, resolution)
    ys = np.arange(y0 + resolution / 2.0, y1, resolution)
    clear = np.full((len(ys), len(xs)), np.inf)
    for b in scene.boxes:
        clear = np.minimum(clear, box_clearance(xs, ys, b))
    # A post only matters where it is nearer than what is already there; the walls bound the
    # clearance by half the room's width, so a window of that size around each post is enough.
    reach = float(np.max(clear[np.isfinite(clear)])) + scene.post_radius if clear.size else 0.0
    w = int(math.ceil(reach / resolution)) + 1
    for cx, cy in scene.posts:
        i = int(round((cx - xs[0]) / resolution))
        j = int(round((cy - ys[0]) / resolution))
        i0, i1 = max(i - w, 0), min(i + w + 1, len(xs))
        j0, j1 = max(j - w, 0), min(j + w + 1, len(ys))
        if i0 >= i1 or j0 >= j1:
            continue
        d = np.hypot(xs[np.newaxis, i0:i1] - cx, ys[j0:j1, np.newaxis] - cy) - scene.post_radius
        np.minimum(clear[j0:j1, i0:i1], d, out=clear[j0:j1, i0:i1])
    return Grid(xs, ys, clear, resolution)


@dataclass
class Bottleneck:
    gap: float             # width of the widest disc that gets from start to goal (m); 0: none
    grid_gap: float        # the same on the grid, before the exact refinement
    point: tuple = None    # where the widest path is narrowest
    pair: tuple = None     # indices of the two obstacles there (posts first, then boxes)
    refined: bool = False  # gap is the exact surface distance between `pair`
    extra: dict = field(default_factory=dict)


def _connected(free, a, b):
    labels, _ = ndimage.label(free)  # 4-connected
    return labels[a] != 0 and labels[a] == labels[b], labels


def bottleneck(scene, resolution, grid=None):
    """The narrowest gap of the widest start -> goal passage (the maximin path's bottleneck)."""
    g = grid or clearance_grid(scene, resolution)
    a, b = g.cell(scene.start), g.cell(scene.goal)
    hi = min(g.clear[a], g.clear[b])
    if not hi > 0.0:
        return Bottleneck(0.0, 0.0)
    values = np.unique(g.clear[(g.clear > 0.0) & (g.clear <= hi)])
    ok, _ = _connected(g.clear >= values[0], a, b)
    if not ok:
        return Bottleneck(0.0, 0.0)
    lo_i, hi_i = 0, len(values) - 1          # values[lo_i] connects; find the largest that does
    while lo_i < hi_i:
        mid = (lo_i + hi_i + 1) // 2
        if _connected(g.clear >= values[mid], a, b)[0]:
            lo_i = mid
        else:
            hi_i = mid - 1
    t = float(values[lo_i])
    # The bottleneck cell: on the path at threshold t, with value t, and touching both the start's
    # side and the goal's side at the next threshold up (they are apart there, by definition).
    _, labels_t = _connected(g.clear >= t, a, b)
    above = g.clear > t
    labels_up, _ = ndimage.label(above)
    on_path = (labels_t == labels_t[a]) & ~above
    sides = []
    for end in (a, b):
        side = labels_up == labels_up[end] if labels_up[end] else np.zeros_like(above)
        side[end] = True
        sides.append(ndimage.binary_dilation(side))
    cand = np.argwhere(on_path & sides[0] & sides[1])
    if not len(cand):  # a bridge of several equal cells: the start-side one nearest the goal side
        cand = np.argwhere(on_path & sides[0])
        goal_cells = np.argwhere(sides[1] & on_path) if np.any(sides[1] & on_path) else [b]
        gc = np.asarray(goal_cells, dtype=float)
        dist = [np.min(np.hypot(gc[:, 0] - c[0], gc[:, 1] - c[1])) for c in cand]
        cand = cand[[int(np.argmin(dist))]]
    cell = tuple(cand[0])
    p = g.point(cell)
    d = scene.obstacle_distances(p)
    order = np.argsort(d, kind='stable')
    pair = (int(order[0]), int(order[1]))
    grid_gap = 2.0 * t
    exact, refined = _pair_gap(scene, pair)
    gap = grid_gap
    if exact is not None and abs(exact - grid_gap) <= 2.0 * resolution:
        gap, refined = exact, True
    else:
        refined = False
    return Bottleneck(gap, grid_gap, p, pair, refined)


def _closest_point_on_box(b, p):
    return (min(max(p[0], b[0]), b[2]), min(max(p[1], b[1]), b[3]))


def _pair_gap(scene, pair):
    """Surface distance between two obstacles, if the midpoint of their closest points is no
    nearer any third obstacle (then it is the saddle's exact width); else None."""
    n = len(scene.posts)
    i, j = pair
    if i >= n and j >= n:
        return None, False
    if i >= n:
        i, j = j, i
    ci = scene.posts[i]
    if j < n:
        cj = scene.posts[j]
        dist = math.hypot(*(cj - ci))
        gap = dist - 2.0 * scene.post_radius
        u = (cj - ci) / dist
        qi, qj = ci + u * scene.post_radius, cj - u * scene.post_radius
    else:
        qj = np.array(_closest_point_on_box(scene.boxes[j - n], ci))
        dist = math.hypot(*(qj - ci))
        gap = dist - scene.post_radius
        qi = ci + (qj - ci) / dist * scene.post_radius
    mid = (qi + qj) / 2.0
    if clearance_points(scene, [mid])[0] < gap / 2.0 - 1e-9:
        return None, False
    return gap, True


# ----------------------------------------------------------------------------------------------
# Shortest path of a disc.

_STEPS = [(1, 0), (0, 1), (1, 1), (1, -1), (2, 1), (1, 2), (2, -1), (1, -2)]


def shortest_path(scene, radius, resolution, grid=None):
    """Length and waypoints of the shortest start -> goal path of a disc of `radius`, or
    (inf, []) when none exists."""
    g = grid or clearance_grid(scene, resolution)
    ok = g.clear >= radius
    ny, nx = ok.shape
    idx = np.arange(ny * nx).reshape(ny, nx)
    rows, cols, w = [], [], []
    for di, dj in _STEPS:    # (di along x, dj along y); 16-connected with their reverses
        j0, j1 = max(0, -dj), ny - max(0, dj)
        i0, i1 = max(0, -di), nx - max(0, di)
        a = ok[j0:j1, i0:i1] & ok[j0 + dj:j1 + dj, i0 + di:i1 + di]
        if abs(di) + abs(dj) == 3:  # a knight's move passes between two cells: both free
            mx, my = (di // 2 if abs(di) == 2 else 0), (dj // 2 if abs(dj) == 2 else 0)
            sx, sy = di - mx, dj - my
            a &= ok[j0 + my:j1 + my, i0 + mx:i1 + mx] & ok[j0 + sy:j1 + sy, i0 + sx:i1 + sx]
        src = idx[j0:j1, i0:i1][a]
        dst = idx[j0 + dj:j1 + dj, i0 + di:i1 + di][a]
        rows.append(src)
        cols.append(dst)
        w.append(np.full(len(src), math.hypot(di, dj) * resolution))
    rows, cols, w = np.concatenate(rows), np.concatenate(cols), np.concatenate(w)
    graph = coo_matrix((w, (rows, cols)), shape=(ny * nx, ny * nx)).tocsr()
    a, b = g.cell(scene.start), g.cell(scene.goal)
    if not (ok[a] and ok[b]):
        return math.inf, []
    dist, pred = dijkstra(graph, directed=False, indices=int(idx[a]), return_predecessors=True)
    if not math.isfinite(dist[idx[b]]):
        return math.inf, []
    cells = [int(idx[b])]
    while cells[-1] != idx[a]:
        cells.append(int(pred[cells[-1]]))
    cells.reverse()
    pts = [g.point(divmod(c, nx)) for c in cells]
    pts[0], pts[-1] = tuple(scene.start), tuple(scene.goal)
    pts = _relax(scene, _shorten(scene, pts, radius, resolution), radius, resolution)
    length = sum(math.hypot(q[0] - p[0], q[1] - p[1]) for p, q in zip(pts, pts[1:]))
    return length, pts


def _visible(scene, p, q, radius, step):
    n = max(2, int(math.ceil(math.hypot(q[0] - p[0], q[1] - p[1]) / step)) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    seg = np.asarray(p)[None, :] * (1.0 - t) + np.asarray(q)[None, :] * t
    return bool(np.all(clearance_points(scene, seg) >= radius))


def _shorten(scene, pts, radius, resolution):
    """Greedy line-of-sight shortening: from each kept point, jump to the farthest visible one."""
    out, i = [pts[0]], 0
    while i < len(pts) - 1:
        j = len(pts) - 1
        lo = i + 1
        # farthest visible by scanning back from the end (binary search is not valid: visibility
        # is not monotone along the path), bounded by a coarse stride first.
        while j > lo and not _visible(scene, pts[i], pts[j], radius, resolution / 2.0):
            j = max(lo, j - max(1, (j - lo) // 8))
        while j + 1 < len(pts) and _visible(scene, pts[i], pts[j + 1], radius, resolution / 2.0):
            j += 1
        out.append(pts[j])
        i = j
    return out


def _relax(scene, pts, radius, resolution, rounds=4, passes=40):
    """Pulls the path taut: each interior vertex moves towards the midpoint of its neighbours as
    far as both segments stay clear, vertices whose neighbours see each other are dropped, and
    segments are split between rounds so that the path can wrap round posts. Every step keeps
    the path feasible, so the length only falls towards the optimum."""
    step = resolution / 2.0
    pts = [np.asarray(q, dtype=float) for q in pts]
    for rnd in range(rounds):
        if rnd:
            split = [pts[0]]
            for a, b in zip(pts, pts[1:]):
                if math.hypot(*(b - a)) > 0.05:
                    split.append((a + b) / 2.0)
                split.append(b)
            pts = split
        for _ in range(passes):
            moved = 0.0
            i = 1
            while i < len(pts) - 1:
                a, v, b = pts[i - 1], pts[i], pts[i + 1]
                if _visible(scene, a, b, radius, step):
                    del pts[i]
                    moved += 1.0
                    continue
                m = (a + b) / 2.0
                lo, hi = 0.0, 1.0
                for _ in range(10):
                    f = (lo + hi) / 2.0
                    c = v + (m - v) * f
                    if _visible(scene, a, c, radius, step) and _visible(scene, c, b, radius, step):
                        lo = f
                    else:
                        hi = f
                if lo > 0.0:
                    pts[i] = v + (m - v) * lo
                    moved += lo * math.hypot(*(m - v))
                i += 1
            if moved < 1e-6:
                break
    return [tuple(map(float, q)) for q in pts]


# ----------------------------------------------------------------------------------------------
# Generation.

def make_scene(params, posts):
    p = params
    half = p.width / 2.0
    x0, x1 = -p.behind, p.goal_distance + p.beyond
    t = WALL_THICKNESS
    boxes = [(x0 - t, half, x1 + t, half + t),        # left wall (+y)
             (x0 - t, -half - t, x1 + t, -half),      # right wall (-y)
             (x0 - t, -half, x0, half),               # end behind the start
             (x1, -half, x1 + t, half)]               # end beyond the goal
    return Scene(np.asarray(posts, dtype=float).reshape(-1, 2), p.post_radius, boxes,
                 (x0, -half, x1, half), (0.0, 0.0), (p.goal_distance, 0.0))


def poisson_disc(rng, xmin, ymin, xmax, ymax, spacing, k=30):
    """Bridson's maximal Poisson-disc sampling of a rectangle."""
    cell = spacing / math.sqrt(2.0)
    gw, gh = int(math.ceil((xmax - xmin) / cell)), int(math.ceil((ymax - ymin) / cell))
    grid = -np.ones((gh, gw), dtype=int)
    pts, active = [], []

    def fits(q):
        gi, gj = int((q[0] - xmin) / cell), int((q[1] - ymin) / cell)
        for jj in range(max(gj - 2, 0), min(gj + 3, gh)):
            for ii in range(max(gi - 2, 0), min(gi + 3, gw)):
                s = grid[jj, ii]
                if s >= 0 and math.hypot(pts[s][0] - q[0], pts[s][1] - q[1]) < spacing:
                    return False
        return True

    def add(q):
        grid[int((q[1] - ymin) / cell), int((q[0] - xmin) / cell)] = len(pts)
        pts.append(q)
        active.append(len(pts) - 1)

    add((xmin + rng.random() * (xmax - xmin), ymin + rng.random() * (ymax - ymin)))
    while active:
        a = active[int(rng.integers(len(active)))]
        placed = False
        for _ in range(k):
            r = spacing * (1.0 + rng.random())
            th = 2.0 * math.pi * rng.random()
            q = (pts[a][0] + r * math.cos(th), pts[a][1] + r * math.sin(th))
            if xmin <= q[0] < xmax and ymin <= q[1] < ymax and fits(q):
                add(q)
                placed = True
                break
        if not placed:
            active.remove(a)
    return np.array(pts)


def _round(posts):
    return np.round(np.asarray(posts, dtype=float), DECIMALS) + 0.0  # + 0.0: no "-0.0"


def generate(params, log=None):
    """Returns (scene, bottleneck, info) for params; raises ClutterError when it cannot."""
    params.validate()
    p = params
    rng = np.random.default_rng(p.seed)
    half = p.width / 2.0
    r = p.post_radius
    spacing = p.spacing * (p.gap + 2.0 * r)
    posts = _round(poisson_disc(rng, p.field_start, -half + r, p.field_end, half - r, spacing))
    initial = len(posts)
    target = p.gap + p.tolerance / 2.0
    removed = moved = 0
    for it in range(p.max_iterations):
        scene = make_scene(p, posts)
        bn = bottleneck(scene, p.resolution)
        if log:
            log('iteration %d: %d posts, narrowest gap %.4f m (%s)'
                % (it, len(posts), bn.gap, 'exact' if bn.refined else 'grid'))
        if p.gap <= bn.gap <= p.gap + p.tolerance:
            info = dict(initial_posts=initial, removed=removed, moved=moved, iterations=it + 1)
            return scene, bn, info
        n = len(posts)
        movable = [k for k in bn.pair if k < n]
        if bn.gap < p.gap:
            if bn.gap == 0.0 and bn.point is None:
                # Closed with no saddle found: drop the post nearest the straight line.
                k = int(np.argmin(np.abs(posts[:, 1]))) if n else None
            else:
                if not movable:
                    raise ClutterError('the walls alone make the passage narrower than gap=%g'
                                       % p.gap)
                k = movable[int(rng.integers(len(movable)))]
            if k is None:
                raise ClutterError('no post left to remove and the passage is still closed')
            posts = np.delete(posts, k, axis=0)
            removed += 1
            continue
        # Too wide: move a post at the bottleneck towards the other obstacle there.
        if not movable:
            raise ClutterError('the bottleneck is between walls: width=%g is too narrow for '
                               'gap=%g' % (p.width, p.gap))
        shrink = bn.gap - target
        done = False
        order = list(movable)
        if len(order) == 2 and rng.integers(2):
            order.reverse()
        for k in order:
            other = bn.pair[1] if bn.pair[0] == k else bn.pair[0]
            q = _towards(scene, k, other, shrink)
            cand = posts.copy()
            cand[k] = q
            cand = _round(cand)
            if _placeable(p, cand, k):
                posts = cand
                moved += 1
                done = True
                break
        if not done:
            # Neither can move that far: remove one and let the loop close the gap again.
            posts = np.delete(posts, movable[0], axis=0)
            removed += 1
    raise ClutterError('seed=%d, gap=%g: no world within tolerance=%g after max_iterations=%d; '
                       'try another seed or a larger tolerance'
                       % (p.seed, p.gap, p.tolerance, p.max_iterations))


def _towards(scene, k, other, distance):
    c = scene.posts[k]
    n = len(scene.posts)
    q = scene.posts[other] if other < n else np.array(_closest_point_on_box(scene.boxes[other - n],
                                                                            c))
    u = (q - c) / math.hypot(*(q - c))
    return c + u * distance


def _placeable(p, posts, k):
    """Post k stays inside the field, off the walls and apart from the other posts."""
    x, y = posts[k]
    half = p.width / 2.0
    if not (p.field_start - 1e-9 <= x <= p.field_end + 1e-9):
        return False
    if abs(y) > half - p.post_radius:
        return False
    d = np.hypot(posts[:, 0] - x, posts[:, 1] - y)
    d[k] = np.inf
    return bool(np.all(d >= 2.0 * p.post_radius + 0.01))


# ----------------------------------------------------------------------------------------------
# Output.

def world_sdf(params, scene, name):
    p = params
    half = p.width / 2.0
    lines = [
        '<?xml version="1.0"?>',
        '<!-- %s: a clutter world made by tools/generators/clutter_world.py (seed %d, requested narrowest '
        'gap %.4f m).' % (name, p.seed, p.gap),
        '     A room %.2f m wide between walls at y = +-%.2f, closed at x = %.2f and %.2f;'
        % (p.width, half, -p.behind, p.goal_distance + p.beyond),
        '     %d posts of radius %.3f m in x in [%.2f, %.2f]. Start (0, 0, yaw 0), goal (%.2f, 0).'
        % (len(scene.posts), p.post_radius, p.field_start, p.field_end, p.goal_distance),
        '     Regenerate with: tools/generators/clutter_world.py one --seed %d --gap %.4f --name %s -->'
        % (p.seed, p.gap, name),
        '<sdf version="1.6">',
        '  <world name="%s">' % name,
        '    <include><uri>model://ground_plane</uri></include>',
        '    <include><uri>model://sun</uri></include>',
        '    <model name="walls">',
        '      <static>true</static>',
        '      <link name="walls">',
    ]
    for wall, b in zip(('left', 'right', 'back', 'front'), scene.boxes):
        cx, cy = (b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0
        sx, sy = b[2] - b[0], b[3] - b[1]
        lines += [
            '        <collision name="%s">' % wall,
            '          <pose>%.4f %.4f %.4f 0 0 0</pose>' % (cx, cy, WALL_HEIGHT / 2.0),
            '          <geometry><box><size>%.4f %.4f %.4f</size></box></geometry>'
            % (sx, sy, WALL_HEIGHT),
            '        </collision>',
        ]
    lines += ['      </link>', '    </model>', '    <model name="posts">',
              '      <static>true</static>', '      <link name="posts">']
    for i, (x, y) in enumerate(scene.posts):
        lines += [
            '        <collision name="post_%03d">' % i,
            '          <pose>%.4f %.4f %.4f 0 0 0</pose>' % (x, y, POST_HEIGHT / 2.0),
            '          <geometry><cylinder><radius>%.4f</radius><length>%.4f</length></cylinder>'
            '</geometry>' % (p.post_radius, POST_HEIGHT),
            '        </collision>',
        ]
    lines += ['      </link>', '    </model>', '  </world>', '</sdf>', '']
    return '\n'.join(lines)


def describe(params, scene, bn, info, name):
    grid = clearance_grid(scene, params.resolution)
    outer, outer_path = shortest_path(scene, CIRCUMSCRIBED_RADIUS, params.resolution, grid)
    inner, _ = shortest_path(scene, INSCRIBED_RADIUS, params.resolution, grid)
    r4 = lambda v: round(float(v), 4) + 0.0
    return {
        'name': name,
        'world': name + '.world',
        'map': name + '.yaml',
        'seed': params.seed,
        'frame': 'world (= odom: the simulator starts odometry at the spawn pose)',
        'start': {'x': 0.0, 'y': 0.0, 'yaw': 0.0},
        'goal': {'x': r4(params.goal_distance), 'y': 0.0, 'yaw': 0.0},
        'requested_gap': r4(params.gap),
        'achieved_gap': r4(bn.gap),
        'gap_exact': bn.refined,
        'bottleneck': {'x': r4(bn.point[0]), 'y': r4(bn.point[1])},
        'posts': int(len(scene.posts)),
        'post_radius': r4(params.post_radius),
        'optimal_path_length': r4(outer),
        'optimal_path_radius': r4(CIRCUMSCRIBED_RADIUS),
        'optimal_path_length_inscribed': r4(inner),
        'inscribed_radius': r4(INSCRIBED_RADIUS),
        'straight_line': r4(params.goal_distance),
        'generator': {k: (r4(v) if isinstance(v, float) else v)
                      for k, v in sorted(vars(params).items())},
        'stats': info,
        '_path': outer_path,
    }


def write_world(params, out_dir, name, renderer=DEFAULT_RENDERER, log=None):
    """Generates one world; writes NAME.world/.pgm/.yaml/.json in out_dir; returns the JSON dict."""
    if not name or os.sep in name or name.startswith('.'):
        raise ClutterError('name=%r: must be a plain file name' % name)
    if not (os.path.isfile(renderer) and os.access(renderer, os.X_OK)):
        raise ClutterError('renderer=%r: render_world_map not found; build the workspace '
                           '(tools/build.sh) or pass --renderer' % renderer)
    scene, bn, info = generate(params, log)
    desc = describe(params, scene, bn, info, name)
    desc.pop('_path')
    os.makedirs(out_dir, exist_ok=True)
    base = os.path.join(out_dir, name)
    _write(base + '.world', world_sdf(params, scene, name))
    out = subprocess.run([renderer, base + '.world', base, '--resolution', '0.05',
                          '--margin', '0.3'], capture_output=True, text=True)
    if out.returncode != 0:
        raise ClutterError('render_world_map failed on %s.world: %s' % (base, out.stderr.strip()))
    _write(base + '.json', json.dumps(desc, indent=2, sort_keys=True) + '\n')
    return desc


def _write(path, text):
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        f.write(text)
    os.replace(tmp, path)


def shipped_set():
    """(name, seed, gap) of the shipped set."""
    gaps = np.linspace(SET_GAP_MIN, SET_GAP_MAX, SET_COUNT)
    return [('clutter_%02d' % i, i, round(float(g), 3)) for i, g in enumerate(gaps)]


def main(argv=None):
    ap = argparse.ArgumentParser(prog='clutter_world.py', description=__doc__.split('\n\n')[0])
    sub = ap.add_subparsers(dest='cmd', required=True)
    one = sub.add_parser('one', help='one world')
    one.add_argument('--gap', type=float, required=True, help='requested narrowest gap (m)')
    one.add_argument('--seed', type=int, required=True)
    one.add_argument('--out', default='.', help='output directory')
    one.add_argument('--name', default=None, help='file name (default clutter_s<SEED>)')
    for k in ('post_radius', 'width', 'spacing', 'tolerance', 'resolution'):
        one.add_argument('--' + k.replace('_', '-'), type=float, default=None)
    st = sub.add_parser('set', help='the %d shipped worlds and manifest.json' % SET_COUNT)
    st.add_argument('--out', default=SHIPPED_DIR)
    st.add_argument('--only', type=int, nargs='*', help='indices to (re)make')
    for s in (one, st):
        s.add_argument('--renderer', default=DEFAULT_RENDERER, help='render_world_map binary')
        s.add_argument('-v', '--verbose', action='store_true')
    args = ap.parse_args(argv)
    log = (lambda m: print(m, file=sys.stderr)) if args.verbose else None
    try:
        if args.cmd == 'one':
            extra = {k: getattr(args, k) for k in ('post_radius', 'width', 'spacing', 'tolerance',
                                                     'resolution') if getattr(args, k) is not None}
            params = Params(gap=args.gap, seed=args.seed, **extra)
            d = write_world(params, args.out, args.name or 'clutter_s%d' % args.seed,
                            args.renderer, log)
            print('%s: requested gap %.4f m, achieved %.4f m (%s), %d posts, optimal path %.3f m'
                  % (d['name'], d['requested_gap'], d['achieved_gap'],
                     'exact' if d['gap_exact'] else 'grid', d['posts'],
                     d['optimal_path_length']))
            return 0
        entries = []
        for i, (name, seed, gap) in enumerate(shipped_set()):
            if args.only and i not in args.only:
                with open(os.path.join(args.out, name + '.json')) as f:
                    d = json.load(f)
            else:
                d = write_world(Params(gap=gap, seed=seed), args.out, name, args.renderer, log)
                print('%s: requested %.3f, achieved %.4f, %d posts, optimal path %.3f m'
                      % (name, gap, d['achieved_gap'], d['posts'], d['optimal_path_length']),
                      flush=True)
            entries.append({k: d[k] for k in ('name', 'world', 'map', 'seed', 'requested_gap',
                                              'achieved_gap', 'posts', 'optimal_path_length',
                                              'start', 'goal')})
        manifest = {
            'command': 'tools/generators/clutter_world.py set',
            'description': '%d clutter worlds, requested narrowest gaps evenly spread over '
                           '%.2f-%.2f m; seed = index. Start and goal are in the world frame, '
                           'which is odom for a robot spawned at the start.'
                           % (SET_COUNT, SET_GAP_MIN, SET_GAP_MAX),
            'worlds': entries,
        }
        _write(os.path.join(args.out, 'manifest.json'),
               json.dumps(manifest, indent=2, sort_keys=True) + '\n')
        return 0
    except ClutterError as e:
        print('clutter_world.py: %s' % e, file=sys.stderr)
        return 2


if __name__ == '__main__':
    sys.exit(main())
