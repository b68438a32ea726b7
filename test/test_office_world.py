"""tools/generators/office_world.py: the shipped office world regenerates byte-identically, has
the promised size (>= 2,000 m^2 free) and every room can be entered from the spawn; bad arguments
are named."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy import ndimage

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools', 'generators'))
import office_world as ow  # noqa: E402

SCRIPT = os.path.join(ROOT, 'tools', 'generators', 'office_world.py')
WORLD = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'office.world')
MAP = os.path.join(ROOT, 'maps', 'office.yaml')
needs_renderer = pytest.mark.skipif(not os.path.exists(ow.DEFAULT_RENDERER),
                                    reason='render_world_map is not built (tools/build.sh)')


@needs_renderer
def test_shipped_office_regenerates_byte_identically(tmp_path):
    subprocess.run([sys.executable, SCRIPT, '--out', str(tmp_path), '--map-out', str(tmp_path)],
                   check=True, stdout=subprocess.DEVNULL)
    for made, shipped in (('office.world', WORLD), ('office.pgm', MAP[:-5] + '.pgm'),
                          ('office.yaml', MAP),
                          ('office.json', os.path.join(os.path.dirname(WORLD), 'office.json'))):
        with open(tmp_path / made, 'rb') as a, open(shipped, 'rb') as b:
            assert a.read() == b.read(), \
                "%s differs from tools/generators/office_world.py's output" % shipped


def test_office_is_building_scale_and_every_room_is_reachable():
    import yaml
    from PIL import Image
    meta = yaml.safe_load(open(MAP))
    res, origin = meta['resolution'], meta['origin']
    pixels = np.array(Image.open(os.path.join(os.path.dirname(MAP), meta['image'])))[::-1, :]
    free, occupied = pixels == 254, pixels == 0  # render_world_map writes 254 / 0 only
    assert free.sum() * res * res >= 2000.0
    desc = json.load(open(os.path.join(os.path.dirname(WORLD), 'office.json')))
    # The robot's centre keeps 0.15 m from anything occupied (its inscribed radius is 0.115 m).
    passable = free & ~ndimage.binary_dilation(occupied, iterations=int(np.ceil(0.15 / res)))
    labels, _ = ndimage.label(passable)
    cell = lambda x, y: (int((y - origin[1]) / res), int((x - origin[0]) / res))
    spawn = labels[cell(desc['spawn']['x'], desc['spawn']['y'])]
    assert spawn != 0, 'the spawn is not on a passable cell'
    assert len(desc['rooms']) >= 60
    for room in desc['rooms']:
        # Some passable cell inside the room (walls excluded) is connected to the spawn.
        j0, i0 = cell(room['x0'] + 0.2, room['y0'] + 0.2)
        j1, i1 = cell(room['x1'] - 0.2, room['y1'] - 0.2)
        assert (labels[j0:j1, i0:i1] == spawn).any(), 'room %s cannot be entered' % room['name']


def test_generation_is_seeded():
    a, _, _ = ow.generate(seed=3)
    b, _, _ = ow.generate(seed=3)
    c, _, _ = ow.generate(seed=4)
    assert a.furniture == b.furniture and a.walls == b.walls
    assert a.furniture != c.furniture


@pytest.mark.parametrize('args,message', [
    (['--height', '30'], 'height=30: must be >= 45'),
    (['--width', '20'], 'width=20: must be >= 30'),
    (['--name', '../x'], "--name '../x': must be a plain file name"),
    (['--renderer', '/nonexistent'], "--renderer '/nonexistent': render_world_map not found"),
])
def test_bad_arguments_are_named(tmp_path, args, message):
    out = subprocess.run([sys.executable, SCRIPT, '--out', str(tmp_path), '--map-out',
                          str(tmp_path)] + args, capture_output=True, text=True)
    assert out.returncode == 2
    assert message in out.stderr
    assert not os.listdir(tmp_path)
