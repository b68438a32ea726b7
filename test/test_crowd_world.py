"""tools/generators/crowd_world.py: the shipped crowd worlds regenerate byte-identically; nobody
starts near the robot or inside a wall, the scripted obstacles keep their speed, every person's
route stays inside the walls; the doorway world's person stands in its one door for the time drawn,
then steps aside and stays; make bench's set has 50 mixed worlds with obstacles up to 0.5 m/s and
10 head-on corridors; bad arguments are named."""
import json
import math
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools', 'generators'))
import crowd_world as cw  # noqa: E402

SCRIPT = os.path.join(ROOT, 'tools', 'generators', 'crowd_world.py')
needs_renderer = pytest.mark.skipif(not os.path.exists(cw.DEFAULT_RENDERER),
                                    reason='render_world_map is not built (tools/build.sh)')


@needs_renderer
def test_shipped_worlds_regenerate_byte_identically(tmp_path):
    subprocess.run([sys.executable, SCRIPT, 'set', '--out', str(tmp_path)], check=True,
                   stdout=subprocess.DEVNULL)
    shipped = sorted(os.listdir(cw.SHIPPED_DIR))
    assert shipped == sorted(os.listdir(tmp_path))
    assert len(shipped) == 4 * len(cw.SHIPPED)
    for name in shipped:
        with open(tmp_path / name, 'rb') as a, open(os.path.join(cw.SHIPPED_DIR, name), 'rb') as b:
            assert a.read() == b.read(), \
                "%s differs from tools/generators/crowd_world.py's output" % name


def all_worlds():
    out = [cw.generate(k, s, n, v, 'x') for k, s, n, v in cw.SHIPPED]
    out += [cw.generate(k, s, n, v, name) for k, s, n, v, name in cw.bench_set()]
    return out


def test_people_start_clear_of_the_robot_and_each_other_and_walk_inside_the_walls():
    for desc in all_worlds():
        x0, y0, x1, y1 = desc['bounds']
        starts = [p['start'] for p in desc['people']]
        for i, (x, y) in enumerate(starts):
            assert math.hypot(x, y) >= cw.START_CLEAR, desc['name']
            for (u, v) in starts[:i]:
                assert math.hypot(x - u, y - v) >= cw.SPACING, desc['name']
        for p in desc['people']:
            for (x, y) in [p['start']] + p['goals']:
                # The actor's cylinder (0.25 m) stays clear of the walls.
                assert x0 + 0.3 <= x <= x1 - 0.3 and y0 + 0.3 <= y <= y1 - 0.3, (desc['name'], p)
            assert desc['speed'][0] <= p['speed'] <= desc['speed'][1]
        # The goal is straight ahead, inside.
        assert desc['goal'] == {'x': cw.GOAL_DISTANCE, 'y': 0.0, 'yaw': 0.0}
        assert x0 < cw.GOAL_DISTANCE < x1


def test_scripted_obstacles_keep_their_speed_and_loop():
    desc = cw.generate('random', 4, 6, (0.1, 0.5), 'r')
    for p in desc['people']:
        wps = cw._script_waypoints(p)
        assert wps[0][1:3] == wps[-1][1:3], 'the trajectory closes on its start'
        for (t0, x0, y0, _), (t1, x1, y1, _) in zip(wps, wps[1:]):
            assert t1 > t0
            assert math.hypot(x1 - x0, y1 - y0) <= cw.WAYPOINT_STEP + 1e-9
            assert math.hypot(x1 - x0, y1 - y0) / (t1 - t0) == pytest.approx(p['speed'], rel=1e-6)


def test_the_doorway_person_stands_in_the_door_then_steps_aside_and_stays():
    for seed in range(1, 30):
        desc = cw.generate('doorway', seed, 1, (0.5, 1.0), 'd')
        (p,) = desc['people']
        dx, dy = desc['door']
        assert p['start'] == [dx, dy] and cw.STAND[0] <= p['stand'] <= cw.STAND[1]
        wps = cw._doorway_waypoints(p)
        assert all(t1 > t0 for (t0, *_), (t1, *_) in zip(wps, wps[1:]))
        standing = [w for w in wps if w[0] <= p['stand']]
        assert standing[0][0] == 0.0 and standing[-1][0] == p['stand']
        assert all(w[1:3] == (dx, dy) for w in standing)
        ax, ay = p['goals'][0]
        assert wps[-1][1:3] == (ax, ay) and wps[-1][0] > 1e4, 'they stay aside'
        assert abs(ay) > abs(dy), 'aside: off the line from the door to the goal'
        # One door in the wall across the hall, the person's cylinder inside it.
        sdf = cw.world_sdf(desc)
        assert '<loop>false</loop>' in sdf
        sizes = re.findall(r'<collision name="door_(south|north)">\s*<pose>([-0-9. ]+)</pose>\s*'
                           r'<geometry><box><size>([-0-9. ]+)</size>', sdf)
        assert len(sizes) == 2
        (_, ps, ss), (_, pn, sn) = sizes
        south_top = float(ps.split()[1]) + float(ss.split()[1]) / 2
        north_bottom = float(pn.split()[1]) - float(sn.split()[1]) / 2
        assert north_bottom - south_top == pytest.approx(cw.DOOR_WIDTH, abs=1e-3)
        assert (south_top + north_bottom) / 2 == pytest.approx(dy, abs=1e-3)


def test_bench_set():
    jobs = cw.bench_set()
    mixed = [j for j in jobs if j[4].startswith('mixed_')]
    headon = [j for j in jobs if j[4].startswith('headon_')]
    assert len(mixed) == 50 and len(headon) == 10
    assert {j[0] for j in mixed} == set(cw.BENCH_KINDS)
    assert all(j[3][1] <= 0.5 for j in mixed)
    assert all(j[0] == 'corridor' and j[2] == 3 for j in headon)
    assert len({j[4] for j in jobs}) == len(jobs)


def test_the_same_seed_gives_the_same_world_and_another_seed_another():
    a = cw.world_sdf(cw.generate('hall', 7, 5, (0.2, 0.5), 'h'))
    assert a == cw.world_sdf(cw.generate('hall', 7, 5, (0.2, 0.5), 'h'))
    assert a != cw.world_sdf(cw.generate('hall', 8, 5, (0.2, 0.5), 'h'))
    assert a.count('<actor ') == 5 and a.count('libminibot3d_social_force.so') == 5
    r = cw.world_sdf(cw.generate('random', 7, 5, (0.2, 0.5), 'r'))
    assert r.count('<actor ') == 5 and r.count('<script>') == 5 and 'social_force' not in r


@pytest.mark.parametrize('args, message', [
    (['--kind', 'park'], r"kind 'park': not one of corridor, hall, random"),
    (['--people', '31'], r'people 31: must be 0-30'),
    (['--speed', '0.5', '0.2'], r'speed 0.5 0.2: must be MIN <= MAX'),
    (['--speed', '0.1', '3.0'], r'speed 0.1 3: must be MIN <= MAX within'),
    (['--name', '../x'], r"--name '../x': must be a plain file name"),
    (['--kind', 'doorway', '--people', '2'], r'doorway: --people 2: must be 1'),
])
def test_bad_arguments_are_named(tmp_path, args, message):
    base = {'--kind': 'hall', '--seed': '1', '--people': '3', '--speed': ['0.2', '0.5']}
    argv = [SCRIPT, 'one', '--out', str(tmp_path), '--renderer', sys.executable]
    given = {args[i]: args[i + 1:i + 3] if args[i] == '--speed' else args[i + 1]
             for i in range(len(args)) if args[i].startswith('--')}
    for key, value in list(base.items()) + [(k, v) for k, v in given.items() if k not in base]:
        value = given.get(key, value)
        argv += [key] + (value if isinstance(value, list) else [value])
    res = subprocess.run([sys.executable] + argv, capture_output=True, text=True)
    assert res.returncode != 0
    assert re.search(message, res.stderr), res.stderr
    assert not any(f.endswith('.world') for f in os.listdir(tmp_path))
