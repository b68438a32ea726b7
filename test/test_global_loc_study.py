"""tools/bench/global_loc_study.py's kidnapping draw: a pose far enough away when the map has one,
the farthest of its draws when it has none (a small map), and never an endless draw (the study is
a lock-step participant that must answer every tick); its spawn for a map without one (the middle
of the largest free region); tools/bench/real_maps_global_loc.sh's handling of its arguments."""
import itertools
import math
import os
import random
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools', 'bench'))
from global_loc_study import far_poses  # noqa: E402


def square(side, rng):
    """Endless random poses in a side x side square centred on the origin."""
    while True:
        yield (rng.uniform(-side / 2, side / 2), rng.uniform(-side / 2, side / 2),
               rng.uniform(-math.pi, math.pi))


def test_far_enough_when_the_map_has_room():
    poses = square(20.0, random.Random(1))
    for p in itertools.islice(far_poses(poses, (0.0, 0.0), 5.0), 20):
        assert math.hypot(p[0], p[1]) >= 5.0


def test_farthest_draw_when_nothing_is_far_enough():
    # A 6 m square: nothing is 5 m from its centre (the corners are 4.24 m away).
    rng = random.Random(2)
    draws = [next(square(6.0, rng)) for _ in range(100)]
    got = next(far_poses(iter(draws), (0.0, 0.0), 5.0, tries=100))
    assert got == max(draws, key=lambda p: math.hypot(p[0], p[1]))


def test_same_draws_same_poses():
    a = list(itertools.islice(far_poses(square(8.0, random.Random(3)), (1.0, 1.0), 5.0), 10))
    b = list(itertools.islice(far_poses(square(8.0, random.Random(3)), (1.0, 1.0), 5.0), 10))
    assert a == b


def write_map(tmp_path, rows, res=0.1):
    """A map_server map from rows of '#' (occupied), '.' (free) and '?' (unknown), top row first."""
    shades = {'#': 0, '.': 254, '?': 205}
    h, w = len(rows), len(rows[0])
    (tmp_path / 'm.pgm').write_bytes(b'P5\n%d %d\n255\n' % (w, h) +
                                     bytes(shades[c] for row in rows for c in row))
    (tmp_path / 'm.yaml').write_text(
        'image: m.pgm\nresolution: %g\norigin: [-1.0, -2.0, 0.0]\nnegate: 0\n'
        'occupied_thresh: 0.65\nfree_thresh: 0.196\n' % res)
    return str(tmp_path / 'm.yaml')


def test_spawn_in_the_middle_of_the_largest_free_region(tmp_path):
    from global_loc_study import pick_spawn
    # A 12 x 12 cell room on the left, a 5 x 5 one on the right, unknown space round them.
    room, small = '#' + '.' * 12 + '#', '#' + '.' * 5 + '#'
    rows = (['?' * 23] + ['#' * 14 + '??' + '#' * 7] +
            [room + '??' + (small if 2 <= k < 7 else '#' * 7 if k in (1, 7) else '?' * 7)
             for k in range(1, 13)] + ['#' * 14 + '?' * 9] + ['?' * 23])
    x, y = pick_spawn(write_map(tmp_path, rows))
    # The big room's free cells are columns 1-12 and rows 2-13 from the bottom: its middle cells
    # are columns 6-7 (x -0.35, -0.25) and rows 7-8 (y -1.25, -1.15).
    assert -0.36 < x < -0.24 and -1.26 < y < -1.14, (x, y)


def test_spawn_on_a_map_without_room_is_a_named_error(tmp_path):
    from global_loc_study import pick_spawn
    path = write_map(tmp_path, ['#####', '#...#', '#####'])
    try:
        pick_spawn(path)
    except SystemExit as e:
        assert 'm.yaml has no free cell 0.30 m from obstacles' in str(e)
    else:
        raise AssertionError('no error for a map without room')


def run_real_maps(*args):
    import subprocess
    return subprocess.run([os.path.join(ROOT, 'tools', 'bench', 'real_maps_global_loc.sh')] +
                          [str(a) for a in args], capture_output=True, text=True, timeout=60)


def test_real_maps_study_names_bad_input_and_skips_missing_logs(tmp_path):
    listing = tmp_path / 'logs.txt'
    listing.write_text('# name log\ngone %s\n' % (tmp_path / 'gone.clf'))
    r = run_real_maps(listing, 0, tmp_path / 'out')
    assert r.returncode == 2 and "STARTS='0' must be a positive integer" in r.stderr, r.stderr
    r = run_real_maps(listing, 1, tmp_path / 'out')
    assert r.returncode == 0, r.stderr
    assert "gone: skipped, no log at '%s'" % (tmp_path / 'gone.clf') in r.stdout, r.stdout
    listing.write_text('one\n')
    r = run_real_maps(listing, 1, tmp_path / 'out')
    assert r.returncode == 2, r.stdout
    assert "%s:1: expected 'NAME LOG [REFERENCE_LOG]'" % listing in r.stderr, r.stderr
