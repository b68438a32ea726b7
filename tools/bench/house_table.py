#!/usr/bin/env python3
"""The generated houses' make demo table for make bench.

  house_table.py HOUSES_DIR OUT_DIR

For every HOUSES_DIR/NAME.world, reads make demo's output in OUT_DIR/demo_NAME.txt (the summary)
and OUT_DIR/demo_NAME/demo_nav.json (the goals), with HOUSES_DIR/NAME.json (the rooms), and prints
one row per house: the share of the reachable free area mapped, exploration sim time, goals
reached, rooms holding a reached goal, map accuracy; then the worst and total figures. A run that
did not finish shows what it printed last."""
import glob
import json
import os
import re
import sys


def row_value(text, row):
    m = re.search(r'^%s\s+(.*)$' % re.escape(row), text, re.M)
    return m.group(1) if m else None


def house_row(world, out_dir):
    name = os.path.splitext(os.path.basename(world))[0]
    with open(os.path.splitext(world)[0] + '.json') as f:
        rooms = json.load(f)['rooms']
    txt = os.path.join(out_dir, 'demo_%s.txt' % name)
    text = open(txt).read() if os.path.exists(txt) else ''
    explored = row_value(text, 'explored')
    if explored is None:
        last = text.strip().splitlines()[-1] if text.strip() else 'no output'
        return dict(name=name, failed=last)
    share = float(re.match(r'([\d.]+) %', explored).group(1))
    sim_s = float(re.match(r'([\d.]+) s sim', row_value(text, 'exploration time')).group(1))
    accuracy = row_value(text, 'map accuracy') or ''
    accuracy = float(re.match(r'([\d.]+) %', accuracy).group(1)) if accuracy else float('nan')
    reached = row_value(text, 'goals reached') or '0 of 0'
    nav_path = os.path.join(out_dir, 'demo_%s' % name, 'demo_nav.json')
    goals = []
    if os.path.exists(nav_path):
        with open(nav_path) as f:
            goals = [g for g in json.load(f)['goals'] if g['ok']]
    visited = sum(any(x0 < g['goal'][0] < x1 and y0 < g['goal'][1] < y1 for g in goals)
                  for x0, y0, x1, y1 in rooms)
    return dict(name=name, share=share, sim_s=sim_s, reached=reached, rooms=len(rooms),
                visited=visited, accuracy=accuracy, passed='all steps succeeded' in text)


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    worlds = sorted(glob.glob(os.path.join(argv[1], '*.world')))
    if not worlds:
        sys.exit('house_table.py: no .world files in %s' % argv[1])
    rows = [house_row(w, argv[2]) for w in worlds]
    print('%-10s %9s %12s %13s %12s %9s %s' % ('house', 'explored', 'explore sim', 'goals reached',
                                               'rooms w/ goal', 'accuracy', 'demo'))
    for r in rows:
        if 'failed' in r:
            print('%-10s did not finish: %s' % (r['name'], r['failed']))
            continue
        print('%-10s %7.1f %% %10.0f s %13s %8d of %d %7.1f %% %s' % (
            r['name'], r['share'], r['sim_s'], r['reached'], r['visited'], r['rooms'],
            r['accuracy'], 'passed' if r['passed'] else 'FAILED'))
    done = [r for r in rows if 'failed' not in r]
    if done:
        print('%d of %d houses >= 99 %% mapped (worst %.1f %%), %d of %d rooms hold a reached goal, '
              'exploration %.0f s sim in all, %d of %d demos passed' % (
                  sum(r['share'] >= 99.0 for r in done), len(rows),
                  min(r['share'] for r in done), sum(r['visited'] for r in done),
                  sum(r['rooms'] for r in done), sum(r['sim_s'] for r in done),
                  sum(r['passed'] for r in done), len(rows)))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
