#!/usr/bin/env python3
"""make bench, mapless section: summarises tools/bench/mapless_smoke.sh's runs (the clutter_NN.json
files tools/bench/mapless_run.py writes) for the shipped clutter worlds by difficulty band
(narrowest gap): success rate, collisions, mean time against the optimal time, and the score
success x OT / clip(t, 2 OT, 8 OT) with OT = optimal path / max_vel_x (0.5 is the best), averaged
over the worlds; with --picture, draws the hardest world reached (narrowest gap) with the path
driven, the start and the goal.

  mapless_bench.py SMOKE_OUT_DIR [--max-vel-x 0.5] [--picture OUT.png]"""
import argparse
import json
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WORLDS = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'clutter')
BANDS = [(0.36, 0.45), (0.45, 0.55), (0.55, 0.65), (0.65, 0.81)]


def picture(run, out_png):
    """The world's ground-truth map with the path driven (tools/bench/mapless_run.py's JSON)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    sys.path.insert(0, os.path.join(ROOT, 'minibot3d_slam', 'scripts'))
    # plot_map needs minibot3d_map_io: from devel/ when sourced, else from the source tree.
    sys.path.append(os.path.join(ROOT, 'minibot3d_map_io', 'src'))
    from plot_map import load_map
    img, res, origin = load_map(os.path.join(WORLDS, run['world'] + '.yaml'))
    with open(os.path.join(WORLDS, run['world'] + '.json')) as f:
        meta = json.load(f)
    h, w = img.shape
    fig, ax = plt.subplots(figsize=(10, 10.0 * h / w + 1.6), dpi=120)
    ax.imshow(img, cmap='gray', vmin=0, vmax=255, origin='upper', interpolation='nearest',
              extent=[origin[0], origin[0] + w * res, origin[1], origin[1] + h * res])
    xs, ys = zip(*run['path'])
    ax.plot(xs, ys, '-', color='tab:red', linewidth=1.0, label='path driven (ground truth)')
    ax.plot(meta['start']['x'], meta['start']['y'], 'o', color='tab:green', label='start')
    ax.plot(meta['goal']['x'], meta['goal']['y'], '*', color='tab:blue', markersize=12,
            label='goal')
    b = meta['bottleneck']
    ax.plot(b['x'], b['y'], 'x', color='tab:orange', markersize=10,
            label='narrowest gap of the guaranteed passage (%.3f m)' % meta['achieved_gap'])
    ax.set_title('%s: %s in %s s sim, %d collisions' % (
        run['world'], run['status'], '%.1f' % run['sim_s'] if run['sim_s'] else '-',
        run['collisions']))
    ax.set_xlabel('x [m]')
    ax.set_ylabel('y [m]')
    ax.set_aspect('equal')
    ax.legend(loc='upper center', bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=8)
    fig.tight_layout()
    tmp = out_png + '.tmp.png'
    fig.savefig(tmp)
    os.replace(tmp, out_png)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('smoke_dir')
    parser.add_argument('--max-vel-x', type=float, default=0.5)
    parser.add_argument('--picture', help='PNG of the hardest world reached, with the path')
    args = parser.parse_args()
    runs = {}
    for name in sorted(os.listdir(args.smoke_dir)):
        if re.match(r'^clutter_\d+\.json$', name):
            with open(os.path.join(args.smoke_dir, name)) as f:
                run = json.load(f)
            runs[run['world']] = run
    if not runs:
        print('mapless: no clutter_NN.json results in %s' % args.smoke_dir)
        return 1
    rows = []
    for name, run in sorted(runs.items()):
        ok = run['status'] == 'SUCCEEDED' and run['collisions'] == 0
        t = run['sim_s']
        with open(os.path.join(WORLDS, name + '.json')) as f:
            meta = json.load(f)
        ot = meta['optimal_path_length'] / args.max_vel_x
        score = ot / min(max(t, 2 * ot), 8 * ot) if ok else 0.0
        rows.append((meta['achieved_gap'], ok, run['collisions'], t / ot if ok else None, score))
    print('band (narrowest gap)  worlds  reached  collisions  time/OT (mean)  score (mean)')
    for lo, hi in BANDS + [(0.40, 9.0), (0.0, 9.0)]:
        sel = [r for r in rows if lo <= r[0] < hi]
        if not sel:
            continue
        reached = sum(r[1] for r in sel)
        ratios = [r[3] for r in sel if r[3] is not None]
        label = 'all' if lo == 0.0 else ('gap >= 0.40 m' if hi == 9.0 else '%.2f-%.2f m' % (lo, hi))
        print('%-20s  %6d  %7s  %10d  %14s  %12.3f' % (
            label, len(sel), '%d (%.0f %%)' % (reached, 100.0 * reached / len(sel)),
            sum(r[2] for r in sel), '%.2f' % (sum(ratios) / len(ratios)) if ratios else '-',
            sum(r[4] for r in sel) / len(sel)))
    failed = ['%s (gap %.3f m: %s)' % (n, r['gap'], r['status']) for n, r in sorted(runs.items())
              if not (r['status'] == 'SUCCEEDED' and r['collisions'] == 0)]
    print('not reached: %s' % (', '.join(failed) if failed else 'none'))
    if args.picture:
        reached = [r for r in runs.values() if r['status'] == 'SUCCEEDED' and r['collisions'] == 0]
        if reached:
            hardest = min(reached, key=lambda r: r['gap'])
            picture(hardest, args.picture)
            print('picture: %s (%s, narrowest gap %.3f m)' % (args.picture, hardest['world'],
                                                          hardest['gap']))
    return 0


if __name__ == '__main__':
    sys.exit(main())
