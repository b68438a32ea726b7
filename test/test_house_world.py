"""tools/generators/house_world.py: the 12 shipped houses regenerate byte-identically; in each,
every room can be entered from the spawn by minibot3d (its centre 0.15 m from walls), at least
one door is at most 0.45 m wide, and make demo's goal sampler (tools/demo_goals.py) puts a goal
in every room of the ground-truth map; bad arguments are named."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy import ndimage

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools', 'generators'))
sys.path.insert(0, os.path.join(ROOT, 'tools'))
import demo_goals  # noqa: E402
import house_world as hw  # noqa: E402
from minibot3d_map_io import load_map  # noqa: E402

SCRIPT = os.path.join(ROOT, 'tools', 'generators', 'house_world.py')
NAMES = ['house_%02d' % s for s in range(1, hw.SET_COUNT + 1)]
needs_renderer = pytest.mark.skipif(not os.path.exists(hw.DEFAULT_RENDERER),
                                    reason='render_world_map is not built (tools/build.sh)')


@needs_renderer
def test_shipped_houses_regenerate_byte_identically(tmp_path):
    subprocess.run([sys.executable, SCRIPT, 'set', '--out', str(tmp_path)], check=True,
                   stdout=subprocess.DEVNULL)
    shipped = sorted(os.listdir(hw.SHIPPED_DIR))
    assert shipped == sorted(os.listdir(tmp_path))
    assert len(shipped) == 4 * hw.SET_COUNT
    for name in shipped:
        with open(tmp_path / name, 'rb') as a, open(os.path.join(hw.SHIPPED_DIR, name), 'rb') as b:
            assert a.read() == b.read(), \
                "%s differs from tools/generators/house_world.py's output" % name


def inside(room, margin=0.3):
    x0, y0, x1, y1 = room
    return x0 + margin, y0 + margin, x1 - margin, y1 - margin


@pytest.mark.parametrize('name', NAMES)
def test_every_room_is_reachable_and_gets_a_demo_goal(name):
    base = os.path.join(hw.SHIPPED_DIR, name)
    desc = json.load(open(base + '.json'))
    grid = load_map(base + '.yaml')
    res, origin = grid.resolution, grid.origin
    assert 3 <= len(desc['rooms']) <= 5
    assert min(d['width'] for d in desc['doors']) <= hw.NARROW_DOOR
    assert len(desc['doors']) == len(desc['rooms']) - 1
    passable = grid.free & ~ndimage.binary_dilation(grid.occupied,
                                                    iterations=int(np.ceil(0.15 / res)))
    labels, _ = ndimage.label(passable)

    def cell(x, y):
        return int((y - origin[1]) / res), int((x - origin[0]) / res)
    spawn = labels[cell(0.0, 0.0)]
    assert spawn != 0, '%s: the spawn is not on a passable cell' % name
    for k, room in enumerate(desc['rooms']):
        x0, y0, x1, y1 = inside(room)
        (j0, i0), (j1, i1) = cell(x0, y0), cell(x1, y1)
        assert (labels[j0:j1, i0:i1] == spawn).any(), '%s: room %d cannot be entered' % (name, k)
    # The truth map's frame is the world frame: the spawn is the origin.
    goals = demo_goals.sample_goals(base + '.yaml', (0.0, 0.0, 0.0))
    for k, room in enumerate(desc['rooms']):
        x0, y0, x1, y1 = room
        assert any(x0 < g[0] < x1 and y0 < g[1] < y1 for g in goals), \
            '%s: no demo goal in room %d %s: %s' % (name, k, room, goals)


def test_generation_is_seeded():
    a = hw.generate(3)[0]
    b = hw.generate(3)[0]
    c = hw.generate(4)[0]
    assert a.boxes == b.boxes and a.doors == b.doors
    assert a.boxes != c.boxes


@pytest.mark.parametrize('args,message', [
    (['one', '--seed', '1', '--name', '../x'], "--name '../x': must be a plain file name"),
    (['one', '--seed', '1', '--renderer', '/nonexistent'],
     "--renderer '/nonexistent': render_world_map not found"),
])
def test_bad_arguments_are_named(tmp_path, args, message):
    out = subprocess.run([sys.executable, SCRIPT] + args[:1] + ['--out', str(tmp_path)] + args[1:],
                         capture_output=True, text=True)
    assert out.returncode == 2
    assert message in out.stderr
    assert not os.listdir(tmp_path)
