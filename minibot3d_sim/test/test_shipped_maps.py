"""The ground-truth maps under maps/ are the ones render_world_map makes of the shipped worlds
(a world edited without re-rendering its map is caught here)."""
import filecmp
import os
import subprocess

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))
RENDER = os.path.join(ROOT, 'devel', 'lib', 'minibot3d_sim', 'render_world_map')
PAIRS = [('default.world', 'default_world'), ('arena.world', 'arena'),
         ('tight_spaces.world', 'tight_spaces'), ('office.world', 'office')]


@pytest.mark.parametrize('world,name', PAIRS)
def test_shipped_map_is_rendered_from_its_world(tmp_path, world, name):
    assert os.path.exists(RENDER), 'build first: no ' + RENDER
    out = tmp_path / name
    subprocess.run([RENDER, os.path.join(ROOT, 'minibot3d_sim', 'worlds', world), str(out)],
                   check=True, stdout=subprocess.DEVNULL)
    shipped = os.path.join(ROOT, 'maps', name)
    assert filecmp.cmp(str(out) + '.pgm', shipped + '.pgm', shallow=False), (
        'maps/%s.pgm differs from a fresh render of %s: re-run render_world_map' % (name, world))
    assert (tmp_path / (name + '.yaml')).read_text() == open(shipped + '.yaml').read()
