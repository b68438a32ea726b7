"""`make demo` passes on every shipped world and on a user's (minibot3d_sim/worlds/flat.world,
written after the code): each run explores with SLAM until no reachable frontier is left, saves
the map, localizes globally on it and visits goals, by tools/demo.sh itself (lock-step time, so a
run is the same on any machine load).

It passes only when the demo's own checks pass (exploration mapped >= 97 % of the reachable free
area, every goal reached, no collision); the test also reads the summary, so a failure says which
figure was missed. The office world (2,775 m^2) is left to `make bench`: exploring it takes far
longer than a test should."""
import os
import re
import signal
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

WORLDS = {
    'default': ([], {}),
    'arena': (['minibot3d_sim/worlds/arena.world'], {}),
    # tight_spaces: a 0.40 m door, table legs 0.42 m apart and a 0.50 m gap behind a shelf.
    'tight_spaces': (['minibot3d_sim/worlds/tight_spaces.world'],
                     {'DEMO_X': '-3', 'DEMO_Y': '-1.2'}),
    # A user's world (README): rooms behind a 0.8 m and a 0.40 m door, a sofa 0.40 m from a
    # wall, table legs, a rotated table, a diagonal wall.
    'flat': (['minibot3d_sim/worlds/flat.world'], {}),
}


def summary_value(text, row):
    m = re.search(r'^%s\s+(.*)$' % re.escape(row), text, re.M)
    assert m, 'no "%s" row in the demo summary:\n%s' % (row, text[-3000:])
    return m.group(1)


@pytest.mark.parametrize('world', sorted(WORLDS))
def test_demo_passes(world, tmp_path):
    args, extra = WORLDS[world]
    env = dict(os.environ, DEMO_OUT=str(tmp_path / 'out'), ROS_HOME=str(tmp_path), **extra)
    # SIGINT at its default (a runner started in a script's background inherits it ignored, and
    # demo.sh stops its launches with SIGINT).
    try:
        p = subprocess.run(['bash', os.path.join(ROOT, 'tools', 'demo.sh')] + args, cwd=ROOT,
                           env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, timeout=900, start_new_session=True,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    except subprocess.TimeoutExpired as e:
        pytest.fail('demo on %s did not finish in 900 s wall:\n%s' % (world, (e.output or '')[-3000:]))
    out = p.stdout
    explored = summary_value(out, 'explored')
    share = float(re.match(r'([\d.]+) %', explored).group(1))
    assert share >= 97.0, 'exploration of %s mapped %s' % (world, explored)
    assert summary_value(out, 'collisions while exploring') == '0', out[-3000:]
    assert summary_value(out, 'collisions while navigating') == '0', out[-3000:]
    reached = re.match(r'(\d+) of (\d+)', summary_value(out, 'goals reached'))
    assert reached and reached.group(1) == reached.group(2) and int(reached.group(2)) >= 4, \
        'goals on %s: %s' % (world, summary_value(out, 'goals reached'))
    # Time against path length / max_vel_x: no goal faster than the speed limit allows along the
    # path the robot drove.
    ratio = re.search(r'mean ([\d.]+) \(driven path', summary_value(out, 'time / (path / max_vel_x)'))
    assert ratio and float(ratio.group(1)) >= 1.0, summary_value(out, 'time / (path / max_vel_x)')
    assert p.returncode == 0 and 'demo: all steps succeeded' in out, out[-3000:]
    assert os.path.getsize(tmp_path / 'out' / 'demo.png') > 10000
