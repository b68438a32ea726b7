#!/usr/bin/env python3
"""`make demo`'s summary: the table on the terminal, out/demo.png (the saved map with the
exploration path and the navigation paths drawn on it, and the reachable free area the map does
not know in orange) and out/demo_map_accuracy.png (the saved map's walls on the true ones, those
more than 0.1 m off in red).

  demo_report.py --out DIR --truth-map GT.yaml --spawn X,Y,YAW [--config-dir CONFIG]
  demo_report.py --reachable-area --out DIR --truth-map GT.yaml --spawn X,Y,YAW [--config-dir CONFIG]

CONFIG is the robot's config set (default config/, minibot3d's): the time ratio takes max_vel_x
from its trajectory_planner.yaml (the local planner move_base_params.yaml names), and the free
area counts as reachable where the robot fits: REACH_CLEARANCE from walls, or the footprint's
inscribed radius in costmap_common_params.yaml when that is larger.

Map accuracy compares the saved SLAM map with the world's ground-truth map: the SLAM map's
occupied cells are moved into the world frame (the SLAM map frame is the world frame moved to the
exploration's spawn pose) and counted as right when a ground-truth occupied cell is within 0.1 m.
Explored is the share of the ground-truth free cells reachable from the spawn pose that the SLAM
map knows (free or occupied, not unknown); the demo fails below MIN_COVERAGE. The cells it does
not know are grouped into patches (8-connected), and the "not mapped" row gives their area and
where the largest lie. The SLAM map's known-free area is printed beside it: it is a little
smaller than the true free area even when every cell is mapped (SLAM's walls look about a cell
thicker)."""
import argparse
import importlib.util
import json
import math
import os
import sys
from collections import deque

import numpy as np
import yaml
from minibot3d_map_io import load_map
from scipy import ndimage

HERE = os.path.dirname(os.path.abspath(__file__))
MIN_COVERAGE = 0.97  # make demo's bar: exploration maps >= 97 % of the reachable free area
REACH_CLEARANCE = 0.15  # m from walls for a free cell to count as reachable, at least
ACCURACY_TOLERANCE = 0.1  # m: an occupied cell this near a true wall is right


def route_driver():
    path = os.path.join(HERE, '..', 'minibot3d_sim', 'scripts', 'route_driver.py')
    spec = importlib.util.spec_from_file_location('route_driver', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def load_trinary(yaml_path):
    """(free, occupied) boolean arrays, row 0 = lowest y, with resolution and origin."""
    grid = load_map(yaml_path)
    return grid.free, grid.occupied, grid.resolution, grid.origin


def reachable_free(free, occupied, res, origin, start, clearance=REACH_CLEARANCE):
    """Free cells connected to start (4-connected), as a boolean array."""
    blocked = route_driver().inflate(occupied, int(math.ceil(clearance / res)))
    h, w = free.shape
    sx = int((start[0] - origin[0]) / res)
    sy = int((start[1] - origin[1]) / res)
    seen = np.zeros_like(free)
    if not (0 <= sx < w and 0 <= sy < h):
        return seen
    q = deque([(sy, sx)])
    seen[sy, sx] = True
    while q:
        y, x = q.popleft()
        for dy, dx in ((1, 0), (-1, 0), (0, 1), (0, -1)):
            yy, xx = y + dy, x + dx
            if 0 <= yy < h and 0 <= xx < w and not seen[yy, xx] and free[yy, xx] and \
                    not blocked[yy, xx]:
                seen[yy, xx] = True
                q.append((yy, xx))
    # Add back the clearance band next to reachable cells (the robot sees it).
    grown = seen.copy()
    r = int(math.ceil(clearance / res))
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            grown |= np.roll(np.roll(seen, dy, axis=0), dx, axis=1)
    return grown & free


def map_to_world(spawn, x, y):
    c, s = math.cos(spawn[2]), math.sin(spawn[2])
    return spawn[0] + c * x - s * y, spawn[1] + s * x + c * y


def known_in_world(reach, gres, gorigin, known, res, origin, spawn):
    """Over the ground-truth grid: True at the cells of `reach` whose SLAM-map cell is in
    `known`."""
    ys, xs = np.nonzero(reach)
    wx = gorigin[0] + (xs + 0.5) * gres - spawn[0]
    wy = gorigin[1] + (ys + 0.5) * gres - spawn[1]
    c, s = math.cos(spawn[2]), math.sin(spawn[2])
    mx = np.floor((c * wx + s * wy - origin[0]) / res).astype(int)
    my = np.floor((-s * wx + c * wy - origin[1]) / res).astype(int)
    inside = (mx >= 0) & (my >= 0) & (mx < known.shape[1]) & (my < known.shape[0])
    hit = np.zeros(len(xs), dtype=bool)
    hit[inside] = known[my[inside], mx[inside]]
    out = np.zeros_like(reach)
    out[ys[hit], xs[hit]] = True
    return out


def unmapped_patches(missed, gres, gorigin):
    """The reachable cells the map does not know (`missed`, over the ground-truth grid), grouped
    into 8-connected patches: (area m^2, centre x, centre y in the world frame), largest first."""
    labels, n = ndimage.label(missed, structure=np.ones((3, 3), dtype=bool))
    if n == 0:
        return []
    index = np.arange(1, n + 1)
    cells = ndimage.sum_labels(missed, labels, index)
    centres = ndimage.center_of_mass(missed, labels, index)
    patches = [(float(k) * gres * gres, gorigin[0] + (cx + 0.5) * gres, gorigin[1] + (cy + 0.5) * gres)
               for k, (cy, cx) in zip(cells, centres)]
    return sorted(patches, key=lambda p: -p[0])


def describe_patches(patches, largest=3):
    """`make demo`'s "not mapped" row: the total area, the number of patches and where the largest
    lie (world frame)."""
    if not patches:
        return 'nothing'
    if len(patches) == 1:
        return '%.2f m^2 in 1 patch at (%.1f, %.1f)' % patches[0]
    return '%.2f m^2 in %d patches, the largest %s' % (
        sum(p[0] for p in patches), len(patches),
        ', '.join('%.2f m^2 at (%.1f, %.1f)' % p for p in patches[:largest]))


def wall_errors(occ, res, origin, gocc, gres, gorigin, spawn, tolerance=ACCURACY_TOLERANCE):
    """The SLAM map's occupied cells in the world frame (an N x 2 array of cell centres) and, for
    each, whether a ground-truth occupied cell lies within `tolerance` metres."""
    near = route_driver().inflate(gocc, int(round(tolerance / gres)))
    ys, xs = np.nonzero(occ)
    world = np.column_stack(map_to_world(spawn, origin[0] + (xs + 0.5) * res, origin[1] + (ys + 0.5) * res))
    gx = np.floor((world[:, 0] - gorigin[0]) / gres).astype(int)
    gy = np.floor((world[:, 1] - gorigin[1]) / gres).astype(int)
    inside = (gx >= 0) & (gy >= 0) & (gx < near.shape[1]) & (gy < near.shape[0])
    right = np.zeros(len(world), dtype=bool)
    right[inside] = near[gy[inside], gx[inside]]
    return world, right


def draw_wall_errors(gocc, gres, gorigin, walls, right, accuracy, png):
    """The true walls (grey) with the SLAM map's occupied cells on them: green within
    ACCURACY_TOLERANCE of a true wall, red farther. Written atomically."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    h, w = gocc.shape
    fig, ax = plt.subplots(figsize=(8, 7))
    ax.imshow(np.where(gocc, 0.6, 1.0), cmap='gray', origin='lower', vmin=0, vmax=1,
              extent=(gorigin[0], gorigin[0] + w * gres, gorigin[1], gorigin[1] + h * gres))
    for mask, colour, label in ((right, 'tab:green', 'within %.1f m of a true wall' % ACCURACY_TOLERANCE),
                                (~right, 'tab:red', 'farther')):
        if mask.any():
            ax.plot(walls[mask, 0], walls[mask, 1], 's', ms=1.0, color=colour, mec='none', label=label)
    ax.set_aspect('equal')
    ax.set_xlabel('x (m, world)')
    ax.set_ylabel('y (m, world)')
    ax.set_title('make demo: map accuracy %.1f %% (true walls grey)' % (100.0 * accuracy))
    ax.legend(loc='upper center', bbox_to_anchor=(0.5, -0.08), ncol=2, markerscale=6)
    fig.savefig(png + '.tmp.png', dpi=110, bbox_inches='tight')
    plt.close(fig)
    os.replace(png + '.tmp.png', png)


def load_yaml(path):
    with open(path) as f:
        return yaml.safe_load(f) or {}


def max_vel_x_of(config_dir):
    """The local planner's max_vel_x (m/s) in a config set, None if it sets none: move_base loads
    trajectory_planner.yaml, then move_base_params.yaml, whose base_local_planner names the
    namespace (TrajectoryPlannerROS or DWAPlannerROS)."""
    params = load_yaml(os.path.join(config_dir, 'trajectory_planner.yaml'))
    params.update(load_yaml(os.path.join(config_dir, 'move_base_params.yaml')))
    planner = str(params.get('base_local_planner', 'base_local_planner/TrajectoryPlannerROS'))
    ns = 'DWAPlannerROS' if 'DWAPlannerROS' in planner else 'TrajectoryPlannerROS'
    value = (params.get(ns) or {}).get('max_vel_x')
    return float(value) if value is not None else None


def inscribed_radius(config_dir):
    """The robot's inscribed radius (m) from costmap_common_params.yaml: the footprint polygon's
    nearest edge to the base (or robot_radius), plus footprint_padding; 0 if it gives neither."""
    params = load_yaml(os.path.join(config_dir, 'costmap_common_params.yaml'))
    footprint = params.get('footprint')
    if isinstance(footprint, str):  # costmap_2d also takes "[[x, y], ...]" as a string
        footprint = yaml.safe_load(footprint)
    if footprint:
        pts = np.asarray(footprint, dtype=float)
        radius = float('inf')
        for a, b in zip(pts, np.roll(pts, -1, axis=0)):
            d = b - a
            t = np.clip(-a.dot(d) / max(d.dot(d), 1e-12), 0.0, 1.0)
            radius = min(radius, float(np.hypot(*(a + t * d))))
    else:
        radius = float(params.get('robot_radius', 0.0))
    return radius + float(params.get('footprint_padding', 0.0))


def reach_clearance(config_dir):
    """How far from walls a free cell must be to count as reachable by the robot."""
    return max(REACH_CLEARANCE, inscribed_radius(config_dir))


def path_length(path):
    """Length (m) of a driven path, a list of [x, y, ...] points."""
    if len(path) < 2:
        return 0.0
    p = np.asarray(path, dtype=float)[:, :2]
    return float(np.hypot(*np.diff(p, axis=0).T).sum())


def time_against_path(goals, max_vel_x):
    """Each reached goal's sim time over the time its driven path takes at max_vel_x (1.0 would
    be the whole way at full speed, no turning on the spot), and their mean."""
    if not max_vel_x or max_vel_x <= 0:
        return 'n/a (max_vel_x not recorded)'
    ratios = []
    for g in goals:
        length = path_length(g['path'])
        ratios.append(g['sim_s'] / (length / max_vel_x)
                      if g['ok'] and g['sim_s'] and length > 0.05 else None)
    known = [r for r in ratios if r is not None]
    return '%s; mean %s (driven path, max_vel_x %.2f m/s)' % (
        ', '.join('%.2f' % r if r is not None else '-' for r in ratios),
        '%.2f' % np.mean(known) if known else 'n/a', max_vel_x)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--out', required=True)
    parser.add_argument('--truth-map', required=True)
    parser.add_argument('--spawn', required=True)
    parser.add_argument('--reachable-area', action='store_true',
                        help='print the free area (m^2) reachable from --spawn on --truth-map '
                        'and exit (demo.sh sizes the exploration time budget by it)')
    parser.add_argument('--config-dir', default=os.path.join(HERE, '..', 'config'),
                        help="the robot's config set (default config/, minibot3d's)")
    args = parser.parse_args()
    clearance = reach_clearance(args.config_dir)
    spawn = tuple(float(v) for v in args.spawn.split(','))
    failures = []
    if args.reachable_area:
        gfree, gocc, gres, gorigin = load_trinary(args.truth_map)
        print('%.1f' % (reachable_free(gfree, gocc, gres, gorigin, spawn, clearance).sum() *
                        gres * gres))
        return 0

    with open(os.path.join(args.out, 'demo_explore.json')) as f:
        ex = json.load(f)
    nav_path = os.path.join(args.out, 'demo_nav.json')
    nav = None
    if os.path.exists(nav_path):
        with open(nav_path) as f:
            nav = json.load(f)
    if not ex['ok']:
        failures.append('exploration')

    free, occ, res, origin = load_trinary(os.path.join(args.out, 'demo_map.yaml'))
    gfree, gocc, gres, gorigin = load_trinary(args.truth_map)
    explored = free.sum() * res * res
    reach = reachable_free(gfree, gocc, gres, gorigin, spawn, clearance)
    world_free = reach.sum() * gres * gres
    mapped = known_in_world(reach, gres, gorigin, free | occ, res, origin, spawn)
    covered = float(mapped[reach].mean()) if reach.any() else 0.0
    missed = reach & ~mapped
    any_missed = missed.any()
    patches = unmapped_patches(missed, gres, gorigin)
    if covered < MIN_COVERAGE:
        failures.append('exploration mapped %.1f %% of the reachable free area (< %.0f %%; not '
                        'mapped: %s)' % (100.0 * covered, 100.0 * MIN_COVERAGE,
                                         describe_patches(patches)))

    # Map accuracy: SLAM occupied cells (world frame) near a ground-truth occupied cell.
    walls, right = wall_errors(occ, res, origin, gocc, gres, gorigin, spawn)
    accuracy = right.sum() / max(len(walls), 1)

    rows = [('explored', '%.1f %% of the %.1f m^2 reachable free area mapped (%.1f m^2 known '
             'free)' % (100.0 * covered, world_free, explored)),
            ('not mapped', describe_patches(patches)),
            ('map accuracy', '%.1f %% of %d occupied cells within %.1f m of a true wall' % (
                100.0 * accuracy, len(walls), ACCURACY_TOLERANCE)),
            ('exploration time', '%.0f s sim, %.0f s wall (%.1fx real time)' % (
                ex['sim_s'], ex['wall_s'], ex['sim_s'] / max(ex['wall_s'], 1e-9))),
            ('collisions while exploring', str(ex['collisions']))]
    if nav is not None:
        goals = nav['goals']
        reached = [g for g in goals if g['ok']]
        loc = [g['amcl_error'] for g in goals if g['amcl_error'] is not None]
        rows += [('global localization error', '%.3f m' % nav['localization_error']),
                 ('localization error at the goals', 'mean %.3f m, max %.3f m' % (
                     np.mean(loc), np.max(loc)) if loc else 'n/a'),
                 ('goals reached', '%d of %d' % (len(reached), len(goals))),
                 ('true pose at the goals', ', '.join(
                     '%.2f m %.2f rad' % (g['error'], g['heading_error']) for g in goals)),
                 ('time per goal', ', '.join('%.1f s' % g['sim_s'] if g['sim_s'] else '?'
                                             for g in goals) + ' (sim)'),
                 ('time / (path / max_vel_x)',
                  time_against_path(goals, max_vel_x_of(args.config_dir))),
                 ('collisions while navigating', str(nav['collisions']))]
        if len(reached) != len(goals):
            failures.append('navigation (%d of %d goals)' % (len(reached), len(goals)))
        if nav['collisions']:
            failures.append('collisions while navigating')
    else:
        failures.append('navigation did not run')
    if ex['collisions']:
        failures.append('collisions while exploring')
    width = max(len(r[0]) for r in rows)
    print('\n== make demo summary')
    for k, v in rows:
        print('%-*s  %s' % (width, k, v))

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    img = np.where(occ, 0.0, np.where(free, 1.0, 0.75))
    h, w = img.shape
    # Draw in the world frame: the map's cell corners moved by the spawn pose.
    fig, ax = plt.subplots(figsize=(8, 7))
    from matplotlib.transforms import Affine2D
    tr = Affine2D().rotate(spawn[2]).translate(spawn[0], spawn[1]) + ax.transData
    ax.imshow(img, cmap='gray', origin='lower', vmin=0, vmax=1, transform=tr,
              extent=(origin[0], origin[0] + w * res, origin[1], origin[1] + h * res))
    if any_missed:
        from matplotlib.colors import ListedColormap
        gh, gw = missed.shape
        ax.imshow(np.ma.masked_where(~missed, missed), cmap=ListedColormap(['tab:orange']),
                  origin='lower', interpolation='nearest',
                  extent=(gorigin[0], gorigin[0] + gw * gres, gorigin[1], gorigin[1] + gh * gres))
    p = np.array(ex['path'])
    if len(p):
        ax.plot(p[:, 0], p[:, 1], '-', color='tab:blue', lw=1, label='exploration')
    if nav is not None:
        for i, g in enumerate(nav['goals']):
            q = np.array(g['path'])
            if len(q):
                ax.plot(q[:, 0], q[:, 1], '-', color='tab:red', lw=1.2,
                        label='navigation' if i == 0 else None)
            ax.plot(g['goal'][0], g['goal'][1], 'o', color='tab:green' if g['ok'] else 'k')
    # Zoom to the mapped part of the grid and the reachable part left unmapped.
    ys, xs = np.nonzero(free | occ)
    corners = []
    if len(xs):
        corners = [map_to_world(spawn, origin[0] + cx * res, origin[1] + cy * res)
                   for cx in (xs.min(), xs.max() + 1) for cy in (ys.min(), ys.max() + 1)]
    ys, xs = np.nonzero(missed)
    if len(xs):
        corners += [(gorigin[0] + cx * gres, gorigin[1] + cy * gres)
                    for cx in (xs.min(), xs.max() + 1) for cy in (ys.min(), ys.max() + 1)]
    if corners:
        cx_, cy_ = zip(*corners)
        ax.set_xlim(min(cx_) - 0.5, max(cx_) + 0.5)
        ax.set_ylim(min(cy_) - 0.5, max(cy_) + 0.5)
    ax.set_aspect('equal')
    ax.set_xlabel('x (m, world)')
    ax.set_ylabel('y (m, world)')
    ax.set_title('make demo: explored map, exploration and navigation paths')
    handles, labels = ax.get_legend_handles_labels()
    if any_missed:
        from matplotlib.patches import Patch
        handles.append(Patch(color='tab:orange'))
        labels.append('reachable, not mapped')
    ax.legend(handles, labels, loc='upper center', bbox_to_anchor=(0.5, -0.08), ncol=len(handles))
    png = os.path.join(args.out, 'demo.png')
    fig.savefig(png + '.tmp.png', dpi=110, bbox_inches='tight')
    os.replace(png + '.tmp.png', png)
    print('map with paths: %s' % png)
    png = os.path.join(args.out, 'demo_map_accuracy.png')
    draw_wall_errors(gocc, gres, gorigin, walls, right, accuracy, png)
    print('map with the true walls: %s' % png)
    if failures:
        print('demo: FAILED: %s' % ', '.join(failures), file=sys.stderr)
        return 1
    print('demo: all steps succeeded')
    return 0


if __name__ == '__main__':
    sys.exit(main())
