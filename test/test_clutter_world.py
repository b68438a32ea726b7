"""tools/generators/clutter_world.py: the bottleneck on hand-made scenes, the disc's shortest path
against a closed form, seed determinism, bad arguments, and the shipped set (regenerates
byte-identically, every world within its tolerance)."""
import filecmp
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools', 'generators'))
import clutter_world as cw  # noqa: E402

SCRIPT = os.path.join(ROOT, 'tools', 'generators', 'clutter_world.py')
SHIPPED = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'clutter')
R = 0.04
RES = 0.005
needs_renderer = pytest.mark.skipif(not os.path.exists(cw.DEFAULT_RENDERER),
                                    reason='render_world_map is not built (tools/build.sh)')


def fence(x, openings, pitch=0.28):
    """Posts across the room (y in [-1.5, 1.5]) at x, `pitch` apart (clear gap pitch - 2R), but
    with the given openings: (y_centre, clear width) between two posts."""
    ys = []
    edges = sorted((c - w / 2.0 - R, c + w / 2.0 + R) for c, w in openings)
    y = -1.5 + R
    for lo, hi in edges + [(1.5 - R + pitch, None)]:
        while y < lo - pitch / 2.0:
            ys.append(y)
            y += pitch
        ys.append(lo)          # the post below the opening
        if hi is None:
            break
        y = hi                 # the post above it
    ys = [v for v in ys if -1.5 + R - 1e-9 <= v <= 1.5 - R + 1e-9]
    return [(x, v) for v in ys]


def scene(posts):
    return cw.make_scene(cw.Params(gap=0.5, seed=0), posts)


def test_one_opening_is_the_bottleneck_exactly():
    bn = cw.bottleneck(scene(fence(2.75, [(0.3, 0.5)])), RES)
    assert bn.refined
    assert bn.gap == pytest.approx(0.5, abs=1e-9)
    assert abs(bn.grid_gap - 0.5) <= 2 * RES
    assert bn.point[0] == pytest.approx(2.75, abs=2 * RES)
    assert bn.point[1] == pytest.approx(0.3, abs=0.05)


def test_widest_route_wins_over_the_shortest():
    # 0.45 m straight ahead, 0.6 m off to the side: the widest disc takes the side.
    bn = cw.bottleneck(scene(fence(2.75, [(0.0, 0.45), (-1.0, 0.6)])), RES)
    assert bn.gap == pytest.approx(0.6, abs=1e-9)
    assert bn.point[1] == pytest.approx(-1.0, abs=0.05)


def test_two_fences_in_series_take_the_narrower():
    posts = fence(2.0, [(0.5, 0.7)]) + fence(3.5, [(-0.5, 0.5)])
    assert cw.bottleneck(scene(posts), RES).gap == pytest.approx(0.5, abs=1e-9)


def test_opening_between_a_post_and_a_wall():
    # Posts from the right wall up to y = 1.5 - 0.42 - R: the gap is to the left wall.
    ys = np.arange(-1.5 + R, 1.5 - 0.42 - R + 1e-9, 0.25)
    ys[-1] = 1.5 - 0.42 - R
    bn = cw.bottleneck(scene([(2.75, y) for y in ys]), RES)
    assert bn.refined
    assert bn.gap == pytest.approx(0.42, abs=1e-9)


def test_uniform_fence_is_its_pitch_less_a_post():
    ys = np.arange(-1.5 + R, 1.5 - R + 1e-9, 0.2)   # the last post is 0.12 m from the wall too
    assert cw.bottleneck(scene([(2.75, y) for y in ys]), RES).gap == pytest.approx(0.12)


def test_closed_field_has_no_passage():
    ys = np.linspace(-1.5 + R, 1.5 - R, 60)  # overlapping posts, touching both walls
    assert cw.bottleneck(scene([(2.75, y) for y in ys]), RES).gap == 0.0


def test_grid_bottleneck_matches_brute_force_pairs_on_random_field():
    # Random posts: the refined gap equals the surface distance of the pair it names.
    rng = np.random.default_rng(5)
    posts = np.column_stack([rng.uniform(1.0, 4.5, 30), rng.uniform(-1.4, 1.4, 30)])
    s = scene(posts)
    bn = cw.bottleneck(s, RES)
    assert bn.gap > 0.0
    i, j = bn.pair
    if bn.refined and j < len(posts):
        assert bn.gap == pytest.approx(np.hypot(*(posts[i] - posts[j])) - 2 * R, abs=1e-9)
    assert abs(bn.gap - bn.grid_gap) <= 2 * RES


@pytest.mark.parametrize('radius', [cw.INSCRIBED_RADIUS, cw.CIRCUMSCRIBED_RADIUS])
def test_shortest_path_round_one_post_matches_closed_form(radius):
    # Start and goal 2.75 m either side of one post: two tangents and an arc of radius R + r.
    length, path = cw.shortest_path(scene([(2.75, 0.0)]), radius, RES)
    rr, c = R + radius, 2.75
    exact = 2 * math.sqrt(c * c - rr * rr) + rr * (math.pi - 2 * math.acos(rr / c))
    assert exact - 1e-4 <= length <= exact * 1.0005
    assert path[0] == (0.0, 0.0) and path[-1] == (5.5, 0.0)


def test_shortest_path_empty_room_is_straight():
    assert cw.shortest_path(scene([]), cw.CIRCUMSCRIBED_RADIUS, RES)[0] == pytest.approx(5.5)


def test_shortest_path_none_when_closed():
    ys = np.arange(-1.5 + R, 1.5, 0.3)   # 0.22 m gaps: too narrow for either disc
    length, path = cw.shortest_path(scene([(2.75, y) for y in ys]), cw.INSCRIBED_RADIUS, RES)
    assert length == math.inf and path == []


def test_generate_meets_the_request_and_is_seed_deterministic():
    p = cw.Params(gap=0.62, seed=11)
    s1, b1, _ = cw.generate(p)
    s2, b2, _ = cw.generate(p)
    assert np.array_equal(s1.posts, s2.posts)
    assert p.gap <= b1.gap <= p.gap + p.tolerance
    # And independently measured again on the written (rounded) positions.
    again = cw.bottleneck(cw.make_scene(p, s1.posts), p.resolution)
    assert again.gap == pytest.approx(b1.gap, abs=1e-12)
    s3, _, _ = cw.generate(cw.Params(gap=0.62, seed=12))
    assert not np.array_equal(s1.posts, s3.posts)
    assert np.all(np.abs(s1.posts[:, 1]) <= 1.5 - R)


@needs_renderer
def test_written_files_are_byte_identical(tmp_path):
    for d in ('a', 'b'):
        cw.write_world(cw.Params(gap=0.7, seed=4), str(tmp_path / d), 'w')
    for ext in ('.world', '.pgm', '.yaml', '.json'):
        assert filecmp.cmp(tmp_path / 'a' / ('w' + ext), tmp_path / 'b' / ('w' + ext),
                           shallow=False), ext
    desc = json.loads((tmp_path / 'a' / 'w.json').read_text())
    assert desc['optimal_path_length'] >= desc['optimal_path_length_inscribed'] - 1e-3
    assert desc['optimal_path_length'] >= 5.5


@pytest.mark.parametrize('kwargs, name', [
    (dict(gap=-0.1), 'gap'),
    (dict(gap=0.2), 'gap'),                # below the robot's circumscribed diameter
    (dict(gap=float('nan')), 'gap'),
    (dict(gap=2.0), 'gap'),                # more than half the width
    (dict(post_radius=0.0), 'post_radius'),
    (dict(width=-3.0), 'width'),
    (dict(spacing=0.0), 'spacing'),
    (dict(tolerance=0.0), 'tolerance'),
    (dict(resolution=0.01), 'resolution'),  # coarser than tolerance / 2
    (dict(seed=-1), 'seed'),
    (dict(field_start=0.1), 'field_start'),
    (dict(max_iterations=0), 'max_iterations'),
])
def test_bad_arguments_name_the_parameter(kwargs, name):
    args = dict(gap=0.5, seed=1)
    args.update(kwargs)
    with pytest.raises(cw.ClutterError) as e:
        cw.generate(cw.Params(**args))
    assert str(e.value).startswith(name), str(e.value)


def test_cli_bad_arguments(tmp_path):
    def run(*args):
        return subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True,
                              text=True, timeout=60)
    out = run('one', '--gap', '0.1', '--seed', '1', '--out', str(tmp_path))
    assert out.returncode == 2 and 'gap=0.1' in out.stderr
    out = run('one', '--gap', 'wide', '--seed', '1')
    assert out.returncode == 2 and '--gap' in out.stderr
    out = run('one', '--gap', '0.5', '--seed', '1', '--out', str(tmp_path),
              '--renderer', '/nonexistent')
    assert out.returncode == 2 and 'renderer' in out.stderr
    assert not list(tmp_path.iterdir())


# ---- the shipped set --------------------------------------------------------------------------

def manifest():
    with open(os.path.join(SHIPPED, 'manifest.json')) as f:
        return json.load(f)


def test_shipped_set_matches_its_manifest_and_tolerance():
    worlds = manifest()['worlds']
    assert [(w['name'], w['seed'], w['requested_gap']) for w in worlds] == cw.shipped_set()
    assert len(worlds) == 50
    assert worlds[0]['requested_gap'] == 0.36 and worlds[-1]['requested_gap'] == 0.8
    for w in worlds:
        assert w['requested_gap'] <= w['achieved_gap'] <= w['requested_gap'] + 0.01, w['name']
        assert w['optimal_path_length'] >= 5.5
        for f in (w['world'], w['map'], w['name'] + '.pgm', w['name'] + '.json'):
            assert os.path.exists(os.path.join(SHIPPED, f)), f


@needs_renderer
@pytest.mark.parametrize('index', [0, 25, 49])
def test_shipped_worlds_regenerate_byte_identically(tmp_path, index):
    name, seed, gap = cw.shipped_set()[index]
    cw.write_world(cw.Params(gap=gap, seed=seed), str(tmp_path), name)
    for ext in ('.world', '.pgm', '.yaml', '.json'):
        assert filecmp.cmp(tmp_path / (name + ext), os.path.join(SHIPPED, name + ext),
                           shallow=False), name + ext
