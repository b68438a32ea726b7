#!/usr/bin/env python3
"""make bench, mapless section: summarises tools/mapless_smoke.sh's lines for the shipped clutter
worlds by difficulty band (narrowest gap): success rate, collisions, mean time against the optimal
time, and the score success x OT / clip(t, 2 OT, 8 OT) with OT = optimal path / max_vel_x (0.5 is
the best), averaged over the worlds.

  mapless_bench.py SMOKE_OUTPUT.txt [--max-vel-x 0.5]"""
import argparse
import json
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
WORLDS = os.path.join(HERE, '..', 'minibot3d_sim', 'worlds', 'clutter')
BANDS = [(0.36, 0.45), (0.45, 0.55), (0.55, 0.65), (0.65, 0.81)]
LINE = re.compile(r'^(clutter_\d+) gap [0-9.]+ m: Result: (\w+).*?after ([0-9.]+) s .*collisions '
                  r'(\d+)')


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('smoke_output')
    parser.add_argument('--max-vel-x', type=float, default=0.5)
    args = parser.parse_args()
    runs = {}
    with open(args.smoke_output) as f:
        for line in f:
            m = LINE.match(line)
            if m:
                runs[m.group(1)] = (m.group(2) == 'SUCCEEDED', float(m.group(3)), int(m.group(4)))
            elif line.startswith('clutter_'):
                runs[line.split()[0]] = (False, float('nan'), 0)
    if not runs:
        print('mapless: no results in %s' % args.smoke_output)
        return 1
    rows = []
    for name, (ok, t, collisions) in sorted(runs.items()):
        with open(os.path.join(WORLDS, name + '.json')) as f:
            meta = json.load(f)
        ot = meta['optimal_path_length'] / args.max_vel_x
        score = ot / min(max(t, 2 * ot), 8 * ot) if ok else 0.0
        rows.append((meta['achieved_gap'], ok and collisions == 0, collisions, t / ot if ok else None,
                     score))
    print('band (narrowest gap)  worlds  reached  collisions  time/OT (mean)  score (mean)')
    for lo, hi in BANDS + [(0.0, 9.0)]:
        sel = [r for r in rows if lo <= r[0] < hi]
        if not sel:
            continue
        reached = sum(r[1] for r in sel)
        ratios = [r[3] for r in sel if r[3] is not None]
        label = 'all' if hi == 9.0 else '%.2f-%.2f m' % (lo, hi)
        print('%-20s  %6d  %7s  %10d  %14s  %12.3f' % (
            label, len(sel), '%d (%.0f %%)' % (reached, 100.0 * reached / len(sel)),
            sum(r[2] for r in sel), '%.2f' % (sum(ratios) / len(ratios)) if ratios else '-',
            sum(r[4] for r in sel) / len(sel)))
    return 0


if __name__ == '__main__':
    sys.exit(main())
