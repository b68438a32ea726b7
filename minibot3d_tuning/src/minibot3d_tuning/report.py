"""The study's Markdown table (one row per setting: settings -> time to goal, or why
it failed) and its PNG plots (time to goal against each swept parameter; the trajectories of each
setting over the map)."""
import collections
import math
import os

import numpy as np

from . import metrics


def _num(v):
    try:
        f = float(v)
    except (TypeError, ValueError):
        return float('nan')
    return f


def _ok(r):
    """Reached the goal without touching anything."""
    return r['status'] == 'reached' and str(r['collisions']) == '0'


def group_rows(rows, names):
    """OrderedDict settings-tuple -> [rows], in the order the settings first appear."""
    groups = collections.OrderedDict()
    for r in rows:
        groups.setdefault(tuple(str(r.get(n, '')) for n in names), []).append(r)
    return groups


def _stat(values, fmt):
    v = [x for x in values if x == x]
    if not v:
        return '–'
    if len(v) == 1:
        return fmt % v[0]
    return (fmt + ' ± ' + fmt) % (np.mean(v), np.std(v, ddof=1))


def outcome(rs):
    """'87.3 ± 1.2' when every run reached the goal without touching anything, else why not."""
    n = len(rs)
    reached = [r for r in rs if r['status'] == 'reached']
    hits = sum(int(r['collisions']) for r in rs if str(r['collisions']).isdigit())
    times = [_num(r['time_to_goal']) for r in reached]
    parts = []
    if reached:
        parts.append('%s s' % _stat(times, '%.1f'))
    if len(reached) < n:
        why = collections.Counter()
        for r in rs:
            if r['status'] != 'reached':
                why['%s: %s' % (r['status'], r['reason'][:120])] += 1
        parts.append('never reached' if not reached else '%d/%d reached' % (len(reached), n))
        parts.append('; '.join('%s%s' % ('%d× ' % c if c > 1 else '', w) for w, c in why.items()))
    if hits:
        parts.append('**hit an obstacle: %d collision%s**' % (hits, 's' if hits > 1 else ''))
    return ', '.join(parts)


def markdown_table(rows, names, title=None):
    lines = []
    if title:
        lines += [title, '']
    header = list(names) + ['time to goal (sim s)', 'reached', 'collisions',
                            'min clearance (m)', 'path (m)', 'mean / peak speed (m/s)',
                            'goal error (m)', 'wall (s)']
    lines.append('| ' + ' | '.join(header) + ' |')
    lines.append('|' + '|'.join([' --- '] * len(header)) + '|')
    for key, rs in group_rows(rows, names).items():
        reached = [r for r in rs if r['status'] == 'reached']
        cells = list(key) + [
            outcome(rs), '%d/%d' % (len(reached), len(rs)),
            str(sum(int(r['collisions']) for r in rs if str(r['collisions']).isdigit())),
            _stat([_num(r['min_clearance']) for r in rs], '%.3f'),
            _stat([_num(r['path_length']) for r in reached], '%.2f'),
            '%s / %s' % (_stat([_num(r['mean_speed']) for r in reached], '%.2f'),
                         _stat([_num(r['peak_speed']) for r in rs], '%.2f')),
            _stat([_num(r['goal_error']) for r in reached], '%.3f'),
            _stat([_num(r['wall_time']) for r in rs], '%.0f')]
        lines.append('| ' + ' | '.join(c.replace('|', '/') for c in cells) + ' |')
    return '\n'.join(lines) + '\n'


def _label(names, key):
    return ', '.join('%s=%s' % (n.split('/')[-1], v) for n, v in zip(names, key)) or 'base'


def plot_time_vs_params(rows, names, path, timeout=None):
    """One panel per swept parameter: each trial's time to goal (x: failed, at the top), and
    the mean over repeats joined for each combination of the other parameters."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    shown = names or ['setting']
    fig, axes = plt.subplots(1, len(shown), figsize=(5.5 * len(shown), 4.2), squeeze=False)
    times = [_num(r['time_to_goal']) for r in rows if r['status'] == 'reached']
    top = max(times) * 1.15 if times else (timeout or 1.0)
    for ax, name in zip(axes[0], shown):
        others = [n for n in names if n != name]
        for ci, (okey, rs) in enumerate(group_rows(rows, others).items()):
            color = 'C%d' % (ci % 10)
            xs = [_num(r.get(name, 0)) for r in rs]
            if any(x != x for x in xs):  # non-numeric values: categorical axis
                cats = sorted({str(r.get(name, '')) for r in rows})
                xs = [cats.index(str(r.get(name, ''))) for r in rs]
                ax.set_xticks(range(len(cats)))
                ax.set_xticklabels(cats)
            ok = [(x, _num(r['time_to_goal'])) for x, r in zip(xs, rs)
                  if _ok(r)]
            bad = [(x, top) for x, r in zip(xs, rs)
                   if not (_ok(r))]
            label = _label(others, okey) if others else None
            if ok:
                ax.plot(*zip(*ok), 'o', color=color, alpha=0.6, label=label)
                means = collections.OrderedDict()
                for x, t in sorted(ok):
                    means.setdefault(x, []).append(t)
                ax.plot(list(means), [np.mean(v) for v in means.values()], '-', color=color)
            if bad:
                ax.plot(*zip(*bad), 'x', color=color, markersize=10, mew=2,
                        label=None if ok else label)
        if not all(_ok(r) for r in rows):
            ax.axhline(top, color='0.6', lw=0.8, ls=':')
            ax.text(ax.get_xlim()[0], top, ' x = not reached / collided', va='bottom',
                    fontsize=8, color='0.4')
        ax.set_xlabel(name)
        ax.set_ylabel('time to goal (sim s)')
        ax.grid(alpha=0.3)
        if others:
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path + '.tmp.png', dpi=110)
    plt.close(fig)
    os.replace(path + '.tmp.png', path)


def plot_trajectories(rows, names, grid_map, trial_dir_of, goals, start, path):
    """One panel per setting: the map, the route's goals and every repeat's true trajectory."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    groups = group_rows(rows, names)
    n = max(1, len(groups))
    cols = min(3, n)
    nrows = int(math.ceil(n / float(cols)))
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.4 * nrows), squeeze=False)
    gx = [float(g.split(',')[0]) for g in goals.split()]
    gy = [float(g.split(',')[1]) for g in goals.split()]
    pts_x = gx + [start[0]]
    pts_y = gy + [start[1]]
    for ax in axes.ravel()[n:]:
        ax.axis('off')
    for ax, (key, rs) in zip(axes.ravel(), groups.items()):
        ax.imshow(grid_map.occupied, origin='lower', extent=grid_map.extent, cmap='Greys',
                  vmin=0, vmax=1.6, interpolation='nearest')
        for i, r in enumerate(rs):
            traj = metrics.read_trajectory(os.path.join(trial_dir_of(r), 'trajectory.csv'))
            ok = _ok(r)
            ax.plot(traj['x'], traj['y'], '-', color='C%d' % (i % 10), lw=1.2,
                    label='r%s %s' % (r['repeat'], r['status'] if ok or r['status'] != 'reached'
                                      else 'collided'))
            if len(traj['x']) and not ok:
                ax.plot(traj['x'][-1], traj['y'][-1], 'x', color='red', ms=9, mew=2)
        ax.plot([start[0]], [start[1]], 's', color='k', ms=6)
        ax.plot(gx, gy, '*', color='gold', mec='k', ms=12)
        pad = 0.8
        ax.set_xlim(min(pts_x) - pad, max(pts_x) + pad)
        ax.set_ylim(min(pts_y) - pad, max(pts_y) + pad)
        ax.set_aspect('equal')
        ax.set_title(_label(names, key), fontsize=9)
        ax.legend(fontsize=7, loc='lower right')
    fig.tight_layout()
    fig.savefig(path + '.tmp.png', dpi=110)
    plt.close(fig)
    os.replace(path + '.tmp.png', path)
