#!/usr/bin/env python3
"""make bench, crowds section: summarises tools/bench/mapless_smoke.sh's runs (the NAME.json files
tools/bench/mapless_run.py writes) through tools/generators/crowd_world.py's bench worlds: per
group (the 50 mixed worlds with obstacles up to 0.5 m/s, by kind and in all; the corridors with 3
people head-on; the doorway worlds, run on their maps) the runs reached within 3x the optimal time
(optimal length / max_vel_x), the collisions with a person with the robot at fault (moving at the
contact's onset) and in all, the closest approach of the footprint to a person, and the sim time
within 0.45 m of one; then how often each recovery behaviour ran (from the stacks' logs beside the
runs). With --picture, draws the hardest run (a failure, else the one with the most time within
0.45 m) with the robot's path and the people's tracks.

  crowd_bench.py RUNS_DIR WORLDS_DIR [--max-vel-x 0.5] [--picture OUT.png] [--json OUT.json]"""
import argparse
import glob
import json
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TIME_FACTOR = 3.0
RECOVERY = re.compile(r'move_base: recovering: ([a-z_]+)')


def load_runs(runs_dir, worlds_dir):
    runs = []
    for path in sorted(glob.glob(os.path.join(worlds_dir, '*.json'))):
        with open(path) as f:
            world = json.load(f)
        out = os.path.join(runs_dir, world['name'] + '.json')
        run = None
        if os.path.isfile(out):
            with open(out) as f:
                run = json.load(f)
        runs.append((world, run))
    return runs


def reached_in_time(world, run, max_vel_x):
    limit = TIME_FACTOR * world['optimal_length'] / max_vel_x
    return (run is not None and run['status'] == 'SUCCEEDED' and run['sim_s'] is not None and
            run['sim_s'] <= limit)


def group_row(label, pairs, max_vel_x):
    n = len(pairs)
    ok = sum(1 for w, r in pairs if reached_in_time(w, r, max_vel_x))
    done = [r for _, r in pairs if r is not None]
    fault = sum(r.get('at_fault_collisions', 0) for r in done)
    contacts = sum(r.get('person_collisions', 0) for r in done)
    closest = [r['min_distance'] for r in done if r.get('min_distance') is not None]
    intimate = [r.get('intimate_s', 0.0) for r in done]
    times = [r['sim_s'] / (w['optimal_length'] / max_vel_x) for w, r in pairs
             if r is not None and r['status'] == 'SUCCEEDED' and r['sim_s']]
    return dict(group=label, runs=n, reached=ok, missing=n - len(done), at_fault=fault,
                contacts=contacts, closest=min(closest) if closest else None,
                intimate_mean=sum(intimate) / len(intimate) if intimate else None,
                time_ratio_mean=sum(times) / len(times) if times else None)


def picture(world, run, worlds_dir, out_png, max_vel_x):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    x0, y0, x1, y1 = world['bounds']
    fig, ax = plt.subplots(figsize=(12, 12.0 * (y1 - y0) / (x1 - x0) + 2.2), dpi=110)
    ax.add_patch(plt.Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, color='black', lw=2))
    end_t = run['robot_track'][-1][0] if run['robot_track'] else 0.0
    cmap = plt.get_cmap('viridis')
    for name, track in sorted(run['tracks'].items()):
        pts = [(t, x, y) for t, x, y in track if t <= end_t]
        if not pts:
            continue
        ax.scatter([p[1] for p in pts], [p[2] for p in pts], c=[p[0] for p in pts], cmap=cmap,
                   vmin=0, vmax=max(end_t, 1e-3), s=6, marker='o')
        ax.annotate(name.replace('person_', 'p'), (pts[0][1], pts[0][2]), fontsize=7)
    robot = run['robot_track']
    sc = ax.scatter([p[1] for p in robot], [p[2] for p in robot], c=[p[0] for p in robot],
                    cmap=cmap, vmin=0, vmax=max(end_t, 1e-3), s=18, marker='s',
                    edgecolors='tab:red', linewidths=0.6, label='robot (ground truth)')
    for t, name, moving in run['contacts']:
        near = min(robot, key=lambda p: abs(p[0] - t)) if robot else None
        if near:
            ax.plot(near[1], near[2], 'x', color='red' if moving else 'orange', markersize=14,
                    mew=3)
    ax.plot(world['start']['x'], world['start']['y'], 'o', color='tab:green', markersize=10,
            label='start')
    ax.plot(world['goal']['x'], world['goal']['y'], '*', color='tab:blue', markersize=16,
            label='goal')
    fig.colorbar(sc, ax=ax, label='sim time (s); people: dots, robot: squares', shrink=0.8)
    status = run['status'] + (' after %.1f s (optimal %.1f s)' % (
        run['sim_s'], world['optimal_length'] / max_vel_x) if run['sim_s'] else '')
    ax.set_title('%s (%s, %d people at %g-%g m/s): %s\nclosest %s m, %.1f s within 0.45 m, '
                 '%d collisions with a person (%d robot at fault: red x)' % (
                     world['name'], world['kind'], len(world['people']), world['speed'][0],
                     world['speed'][1], status,
                     '%.2f' % run['min_distance'] if run.get('min_distance') is not None else '-',
                     run.get('intimate_s', 0.0), run.get('person_collisions', 0),
                     run.get('at_fault_collisions', 0)), fontsize=10)
    ax.set_xlabel('x [m]')
    ax.set_ylabel('y [m]')
    ax.set_aspect('equal')
    ax.set_xlim(x0 - 0.3, x1 + 0.3)
    ax.set_ylim(y0 - 0.3, y1 + 0.3)
    ax.legend(loc='upper center', bbox_to_anchor=(0.5, -0.3), ncol=3, fontsize=8)
    fig.tight_layout()
    tmp = out_png + '.tmp.png'
    fig.savefig(tmp)
    os.replace(tmp, out_png)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('runs_dir')
    parser.add_argument('worlds_dir')
    parser.add_argument('--max-vel-x', type=float, default=0.5)
    parser.add_argument('--picture')
    parser.add_argument('--json')
    args = parser.parse_args()
    if args.max_vel_x <= 0:
        parser.error('--max-vel-x %g: must be positive' % args.max_vel_x)
    runs = load_runs(args.runs_dir, args.worlds_dir)
    if not runs:
        sys.exit('crowd_bench.py: no world JSON in %s (tools/generators/crowd_world.py bench '
                 '--out %s makes them)' % (args.worlds_dir, args.worlds_dir))
    mixed = [p for p in runs if p[0]['name'].startswith('mixed_')]
    headon = [p for p in runs if p[0]['name'].startswith('headon_')]
    doorway = [p for p in runs if p[0]['kind'] == 'doorway']
    rows = []
    if mixed:
        rows += [group_row('mixed, %s' % k, [p for p in mixed if p[0]['kind'] == k],
                           args.max_vel_x) for k in ('corridor', 'hall', 'random')]
        rows.append(group_row('mixed, all', mixed, args.max_vel_x))
    if headon:
        rows.append(group_row('corridor, 3 people head-on', headon, args.max_vel_x))
    if doorway:
        rows.append(group_row('doorway shut by one standing in it', doorway, args.max_vel_x))
    print('| worlds | runs | reached within %gx optimal | robot-at-fault collisions | '
          'collisions with a person | closest approach (m) | mean s within 0.45 m | '
          'mean time / optimal |' % TIME_FACTOR)
    print('|---|---|---|---|---|---|---|---|')
    for r in rows:
        print('| %s | %d | %d (%.0f %%)%s | %d | %d | %s | %s | %s |' % (
            r['group'], r['runs'], r['reached'], 100.0 * r['reached'] / max(1, r['runs']),
            ', %d not run' % r['missing'] if r['missing'] else '', r['at_fault'], r['contacts'],
            '%.2f' % r['closest'] if r['closest'] is not None else '-',
            '%.1f' % r['intimate_mean'] if r['intimate_mean'] is not None else '-',
            '%.2f' % r['time_ratio_mean'] if r['time_ratio_mean'] is not None else '-'))
    recoveries = {}
    for w, _ in runs:
        log = os.path.join(args.runs_dir, w['name'] + '.launch.log')
        if os.path.isfile(log):
            with open(log, errors='replace') as f:
                for name in RECOVERY.findall(f.read()):
                    recoveries[name] = recoveries.get(name, 0) + 1
    print('recoveries run: %s' % (', '.join('%s %d' % kv for kv in sorted(recoveries.items()))
                                  or 'none'))
    for w, r in runs:
        if r is None:
            print('%s: no run' % w['name'])
        elif not reached_in_time(w, r, args.max_vel_x) or r.get('at_fault_collisions'):
            print('%s: %s%s, %d at-fault collisions' % (
                w['name'], r['status'], ' after %.1f s' % r['sim_s'] if r['sim_s'] else '',
                r.get('at_fault_collisions', 0)))
    if args.json:
        from minibot3d_map_io import write_atomically
        write_atomically(args.json, json.dumps(rows, indent=1) + '\n')
    done = [(w, r) for w, r in runs if r is not None]
    if args.picture and done:
        def hardness(pair):
            w, r = pair
            return (not reached_in_time(w, r, args.max_vel_x), r.get('at_fault_collisions', 0),
                    r.get('intimate_s', 0.0))
        w, r = max(done, key=hardness)
        picture(w, r, args.worlds_dir, args.picture, args.max_vel_x)
        print('picture: %s (%s)' % (args.picture, w['name']))
    return 0


if __name__ == '__main__':
    sys.exit(main())
