"""minibot3d_map_io (Python): the same cases as test/map_io_test.cpp, the same golden bytes, so
the two languages read and write maps alike."""
import os
import stat
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'src'))
from minibot3d_map_io import (MapIoError, OccupancyGrid, format_double, load_map,  # noqa: E402
                              read_image, save_map, write_atomically)

ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))

# Pixels of a 3 x 2 test image, rows top to bottom, and what trinary mode makes of them with
# occupied_thresh 0.65 / free_thresh 0.196 (p = (255 - v) / 255).
PIXELS = [0, 254, 205,     # p 1.0 occ, 0.004 free, 0.196 unknown
          210, 80, 100]    # p 0.176 free, 0.686 occ, 0.608 unknown
# The same as grid cells, row 0 = the image's bottom row.
TRINARY_CELLS = [0, 100, -1, 100, 0, -1]

# small_map() saved with the default options, byte for byte (map_io_test.cpp holds the same).
GOLDEN_PGM = (b'P5\n# CREATOR: minibot3d_map_io 0.05 m/pix\n4 3\n255\n' +
              bytes([205, 254, 254, 0, 254, 0, 205, 254, 0, 205, 254, 254]))
GOLDEN_YAML = ('image: m.pgm\n'
               'resolution: 0.05\n'
               'origin: [-1.5, 2.25, 0.3]\n'
               'negate: 0\n'
               'occupied_thresh: 0.65\n'
               'free_thresh: 0.196\n'
               '# Cells were written as 0 (occupied, >= 65), 254 (free, 0..25) or 205 (unknown); '
               'the thresholds above read exactly those grey levels back (as map_saver).\n')


def small_map():
    # Row 0 is the bottom (lowest y). Asymmetric so any flip or transpose shows.
    return OccupancyGrid([[100, -1, 0, 0],
                          [0, 100, -1, 0],
                          [-1, 0, 0, 100]], 0.05, (-1.5, 2.25, 0.3))


def write_pgm(path, width, height, pixels, maxval=255):
    os.makedirs(os.path.dirname(str(path)), exist_ok=True)
    dtype = np.uint8 if maxval == 255 else np.dtype('>u2')
    with open(str(path), 'wb') as f:
        f.write(b'P5\n%d %d\n%d\n' % (width, height, maxval))
        f.write(np.asarray(pixels, dtype=dtype).tobytes())


def yaml_text(image, extra='', drop='', occ='0.65', free='0.196', negate='0'):
    """A YAML with every required key; extra is appended, drop names a key to leave out."""
    keys = [('image', image), ('resolution', '0.1'), ('origin', '[-1.5, 2.25, 0.3]'),
            ('negate', negate), ('occupied_thresh', occ), ('free_thresh', free)]
    return ''.join('%s: %s\n' % kv for kv in keys if kv[0] != drop) + extra


def cells(tmp_path, name, text):
    (tmp_path / name).write_text(text)
    return load_map(str(tmp_path / name)).data.ravel().tolist()


def expect_error(fn, *needles):
    with pytest.raises(MapIoError) as info:
        fn()
    for n in needles:
        assert n in str(info.value), '%r does not mention %r' % (str(info.value), n)


def test_saved_files_are_the_golden_bytes(tmp_path):
    save_map(small_map(), str(tmp_path / 'm'))
    assert (tmp_path / 'm.pgm').read_bytes() == GOLDEN_PGM
    assert (tmp_path / 'm.yaml').read_text() == GOLDEN_YAML
    assert stat.S_IMODE(os.stat(str(tmp_path / 'm.pgm')).st_mode) == 0o644


def test_round_trip_keeps_cells_and_geometry(tmp_path):
    m = small_map()
    save_map(m, str(tmp_path / 'm'))
    out = load_map(str(tmp_path / 'm.yaml'))
    assert out.data.tolist() == m.data.tolist()
    assert (out.width, out.height) == (4, 3)
    assert out.resolution == m.resolution and out.origin == m.origin
    assert sorted(os.listdir(str(tmp_path))) == ['m.pgm', 'm.yaml'], 'temporary files left'
    # Any double reads back bit for bit.
    odd = OccupancyGrid(m.data, 0.1 + 0.2, (-73 * 0.05, 1.0 / 3.0, -1e-17))
    save_map(odd, str(tmp_path / 'o'))
    back = load_map(str(tmp_path / 'o.yaml'))
    assert back.origin == odd.origin and back.resolution == odd.resolution


def test_save_options_set_the_comments_and_floats_keep_a_point(tmp_path):
    m = OccupancyGrid(small_map().data, 0.05, (-4.0, 2.25, 0.0))
    save_map(m, str(tmp_path / 'g'), pgm_comment='minibot3d_sim ground-truth map',
             explain_grey_levels=False)
    assert (tmp_path / 'g.pgm').read_bytes().startswith(
        b'P5\n# minibot3d_sim ground-truth map\n4 3\n')
    assert (tmp_path / 'g.yaml').read_text() == (
        'image: g.pgm\nresolution: 0.05\norigin: [-4.0, 2.25, 0.0]\nnegate: 0\n'
        'occupied_thresh: 0.65\nfree_thresh: 0.196\n')
    expect_error(lambda: save_map(m, str(tmp_path / 'h'), pgm_comment='two\nlines'),
                 str(tmp_path / 'h'), 'one line')


def test_format_double_is_the_cpp_one():
    assert format_double(0.05) == '0.05'
    assert format_double(50.0) == '50'
    assert format_double(-73 * 0.05) == '-3.6500000000000004'
    assert format_double(1700000000.25) == '1700000000.25'
    assert format_double(1e-5) == '1e-05'
    assert format_double(2e20) == '2e+20'


def test_save_classifies_by_percent_thresholds(tmp_path):
    m = OccupancyGrid([[0, 25, 26, 64, 65, 100, -1, -100]], 0.05, (0, 0, 0))
    save_map(m, str(tmp_path / 'd'))  # --occ 65 --free 25
    assert load_map(str(tmp_path / 'd.yaml')).data.ravel().tolist() == \
        [0, 0, -1, -1, 100, 100, -1, -1]
    m = OccupancyGrid([[10, 11, 49, 50, 0, 100, -1, 30]], 0.05, (0, 0, 0))
    save_map(m, str(tmp_path / 'c'), occupied_percent=50, free_percent=10)
    assert load_map(str(tmp_path / 'c.yaml')).data.ravel().tolist() == \
        [0, -1, -1, 100, 0, 100, -1, -1]


def test_save_overwrites_and_failures_name_the_file(tmp_path):
    m = small_map()
    save_map(m, str(tmp_path / 'm'))
    full = OccupancyGrid(np.full((3, 4), 100), 0.05, (0, 0, 0))
    save_map(full, str(tmp_path / 'm'))
    assert load_map(str(tmp_path / 'm.yaml')).data.tolist() == full.data.tolist()
    (tmp_path / 'blocked.pgm').mkdir()  # a folder where the image goes: the rename fails
    expect_error(lambda: save_map(m, str(tmp_path / 'blocked')), str(tmp_path / 'blocked.pgm'))
    assert sorted(os.listdir(str(tmp_path))) == ['blocked.pgm', 'm.pgm', 'm.yaml']
    expect_error(lambda: save_map(m, str(tmp_path / 'no/such/dir/m')),
                 str(tmp_path / 'no/such/dir/m.pgm'))
    expect_error(lambda: save_map(m, str(tmp_path / 'x'), occupied_percent=25, free_percent=65),
                 'free (65)', 'occupied (25)')
    expect_error(lambda: save_map(OccupancyGrid(m.data, 0.0, (0, 0, 0)), str(tmp_path / 'x')),
                 'resolution')
    expect_error(lambda: write_atomically(str(tmp_path / 'no/such/f'), 'x'),
                 str(tmp_path / 'no/such/f'))


def test_trinary_thresholds_and_row_order(tmp_path):
    write_pgm(tmp_path / 't.pgm', 3, 2, PIXELS)
    (tmp_path / 't.yaml').write_text(yaml_text('t.pgm'))
    m = load_map(str(tmp_path / 't.yaml'))
    assert (m.width, m.height) == (3, 2)
    assert m.data.ravel().tolist() == TRINARY_CELLS
    assert m.resolution == 0.1 and m.origin == (-1.5, 2.25, 0.3)
    assert m.occupied.ravel().tolist() == [c == 100 for c in TRINARY_CELLS]
    assert m.free.ravel().tolist() == [c == 0 for c in TRINARY_CELLS]
    assert cells(tmp_path, 'e.yaml', yaml_text('t.pgm', 'mode: trinary\n', negate='false')) == \
        TRINARY_CELLS


def test_negate_swaps_black_and_white(tmp_path):
    write_pgm(tmp_path / 't.pgm', 3, 2, PIXELS)
    # p = v / 255: 0 free, 254 occ, 205 occ, 210 occ, 80 unknown, 100 unknown.
    assert cells(tmp_path, 'n.yaml', yaml_text('t.pgm', negate='1')) == \
        [100, -1, -1, 0, 100, 100]


def test_scale_mode_is_linear_between_thresholds(tmp_path):
    write_pgm(tmp_path / 's.pgm', 6, 1, [0, 255, 128, 102, 204, 51])
    got = cells(tmp_path, 's.yaml', yaml_text('s.pgm', 'mode: scale\n', occ='0.8', free='0.2'))
    p = (255.0 - 102) / 255.0
    assert got[:5] == [100, 0, 49, int(99.0 * (p - 0.2) / (0.8 - 0.2)), 0]
    assert got[5] >= 98


def test_raw_mode_keeps_pixel_values(tmp_path):
    write_pgm(tmp_path / 'r.pgm', 4, 1, [0, 50, 100, 200])
    # 200 does not fit an int8 cell: stored as its byte, -56, as map_server does.
    assert cells(tmp_path, 'r.yaml', yaml_text('r.pgm', 'mode: raw\n')) == [0, 50, 100, -56]
    assert cells(tmp_path, 'rn.yaml', yaml_text('r.pgm', 'mode: raw\n', negate='1')) == \
        [-1, -51, -101, 55]


def test_sixteen_bit_pgm_reads_as_eight_bit(tmp_path):
    write_pgm(tmp_path / 'w.pgm', 3, 2, [v * 257 for v in PIXELS], maxval=65535)
    assert read_image(str(tmp_path / 'w.pgm')).ravel().tolist() == PIXELS
    assert cells(tmp_path, 'w.yaml', yaml_text('w.pgm')) == TRINARY_CELLS


def test_colour_and_alpha_as_map_server(tmp_path):
    Image = pytest.importorskip('PIL.Image')
    rgb = np.array([[[255, 0, 0], [254, 254, 254], [210, 150, 255]]], dtype=np.uint8)
    Image.fromarray(rgb, 'RGB').save(str(tmp_path / 'c.png'))
    assert cells(tmp_path, 'c.yaml', yaml_text('c.png')) == [100, 0, -1]
    rgba = np.array([[[128, 128, 128, 255], [128, 128, 128, 0], [254, 254, 254, 0]]],
                    dtype=np.uint8)
    Image.fromarray(rgba, 'RGBA').save(str(tmp_path / 'a.png'))
    # Scale: alpha is not averaged; a transparent in-between pixel is unknown.
    assert cells(tmp_path, 'a.yaml', yaml_text('a.png', 'mode: scale\n', occ='0.8',
                                               free='0.2')) == [49, -1, 0]
    # Trinary: alpha averaged in: (254 * 3 + 0) / 4 = 190.5 -> p 0.25, unknown.
    assert cells(tmp_path, 'b.yaml', yaml_text('a.png'))[2] == -1


def test_relative_image_path_is_relative_to_the_yaml(tmp_path, monkeypatch):
    write_pgm(tmp_path / 'maps' / 'img' / 't.pgm', 3, 2, PIXELS)
    (tmp_path / 'maps' / 't.yaml').write_text(yaml_text('img/t.pgm'))
    monkeypatch.chdir('/')
    assert load_map(str(tmp_path / 'maps' / 't.yaml')).data.ravel().tolist() == TRINARY_CELLS
    (tmp_path / 'abs.yaml').write_text(yaml_text(str(tmp_path / 'maps' / 'img' / 't.pgm')))
    assert cells(tmp_path, 'abs.yaml', (tmp_path / 'abs.yaml').read_text()) == TRINARY_CELLS


@pytest.mark.parametrize('key', ['image', 'resolution', 'origin', 'negate', 'occupied_thresh',
                                 'free_thresh'])
def test_missing_keys_are_named(tmp_path, key):
    write_pgm(tmp_path / 't.pgm', 3, 2, PIXELS)
    (tmp_path / 'k.yaml').write_text(yaml_text('t.pgm', drop=key))
    expect_error(lambda: load_map(str(tmp_path / 'k.yaml')), str(tmp_path / 'k.yaml'),
                 "missing key '%s'" % key)


@pytest.mark.parametrize('text,needles', [
    (yaml_text('t.pgm').replace('0.1\n', '-0.05\n'), ["'resolution'", 'positive']),
    (yaml_text('t.pgm').replace('0.1\n', 'abc\n'), ["'resolution'", "'abc'"]),
    (yaml_text('t.pgm', occ='0.1', free='0.3'), ["'occupied_thresh'", "'free_thresh'"]),
    (yaml_text('t.pgm', occ='1.5', free='0.3'), ["'occupied_thresh'", '[0, 1]']),
    (yaml_text('t.pgm', negate='2'), ["'negate'"]),
    (yaml_text('t.pgm', 'mode: fancy\n'), ["'mode'", 'fancy']),
    (yaml_text('t.pgm').replace('[-1.5, 2.25, 0.3]', '[1, 2]'), ["'origin'"]),
    (yaml_text('t.pgm').replace('[-1.5, 2.25, 0.3]', '[1, 2, x]'), ['origin[2]']),
    ('image: [t.pgm\n', ['line', 'does not parse']),
    ('just a string\n', ['mapping']),
])
def test_bad_values_are_named(tmp_path, text, needles):
    write_pgm(tmp_path / 't.pgm', 3, 2, PIXELS)
    (tmp_path / 'b.yaml').write_text(text)
    expect_error(lambda: load_map(str(tmp_path / 'b.yaml')), str(tmp_path / 'b.yaml'), *needles)


def test_missing_or_unreadable_image_is_named(tmp_path):
    (tmp_path / 'm.yaml').write_text(yaml_text('nothere.pgm'))
    expect_error(lambda: load_map(str(tmp_path / 'm.yaml')), str(tmp_path / 'm.yaml'),
                 str(tmp_path / 'nothere.pgm'), 'does not exist')
    (tmp_path / 'junk.pgm').write_text('this is not an image')
    (tmp_path / 'j.yaml').write_text(yaml_text('junk.pgm'))
    expect_error(lambda: load_map(str(tmp_path / 'j.yaml')), str(tmp_path / 'j.yaml'),
                 str(tmp_path / 'junk.pgm'), 'cannot be read')
    (tmp_path / 'short.pgm').write_bytes(b'P5\n4 4\n255\n\x00\x00')
    (tmp_path / 's.yaml').write_text(yaml_text('short.pgm'))
    expect_error(lambda: load_map(str(tmp_path / 's.yaml')), str(tmp_path / 'short.pgm'),
                 '2 pixel bytes')
    expect_error(lambda: load_map(str(tmp_path / 'absent.yaml')), str(tmp_path / 'absent.yaml'),
                 'cannot be opened')


@pytest.mark.parametrize('name', ['arena', 'default_world', 'tight_spaces', 'office'])
def test_shipped_maps_read_and_write_back_byte_for_byte(tmp_path, name):
    """The repository's ground-truth maps (written by render_world_map through the C++ writer)
    are what this writer makes of what this reader reads."""
    m = load_map(os.path.join(ROOT, 'maps', name + '.yaml'))
    assert m.occupied.any() and m.free.any() and not m.unknown.any()
    save_map(m, str(tmp_path / name), pgm_comment='minibot3d_sim ground-truth map',
             explain_grey_levels=False)
    for ext in ('.pgm', '.yaml'):
        with open(os.path.join(ROOT, 'maps', name + ext), 'rb') as f:
            assert (tmp_path / (name + ext)).read_bytes() == f.read(), name + ext
