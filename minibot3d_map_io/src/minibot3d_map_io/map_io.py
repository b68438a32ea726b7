"""Maps on disk in ROS map_server's format: NAME.yaml (image, resolution, origin, negate,
occupied_thresh, free_thresh, optional mode) and an image (PGM written; PGM, PNG, ... read).

The Python twin of the C++ library (include/minibot3d_map_io/map_io.h): the same semantics, the
same error texts where it matters, byte-identical files from save_map and SaveMap. No ROS.

Loading follows map_server's image_loader.cpp: a pixel's channels are averaged (alpha too, in
trinary mode only), negate flips the mean, and p = (255 - mean) / 255 is classified:
  trinary (default): p > occupied_thresh -> 100, p < free_thresh -> 0, else -1;
  scale: the same, but in between int(99 * (p - free) / (occ - free)), a transparent pixel -1;
  raw:   the (negated) mean itself, 0..255, stored as int8 (so 255 reads as -1).
Saving follows map_saver: cells >= occupied_percent black (0), 0..free_percent white (254), the
rest grey (205); the YAML's thresholds (0.65, 0.196) read exactly those back.
"""
import json
import math
import os
import re
import tempfile

import numpy as np
import yaml

OCCUPIED_PIXEL, FREE_PIXEL, UNKNOWN_PIXEL = 0, 254, 205
SAVED_OCCUPIED_THRESH, SAVED_FREE_THRESH = 0.65, 0.196
MODES = ('trinary', 'scale', 'raw')


class MapIoError(ValueError):
    """A map that cannot be read or written; the message names the file and what is wrong."""


class OccupancyGrid(object):
    """A grid as map_server and nav_msgs/OccupancyGrid see it: data[row, col] (int8), row 0 at
    the lowest y (the image's bottom row); -1 unknown, 0 free .. 100 occupied. origin is
    (x, y, theta) of the outer corner of cell (0, 0)."""

    def __init__(self, data, resolution, origin):
        self.data = np.asarray(data, dtype=np.int8)
        if self.data.ndim != 2:
            raise ValueError('OccupancyGrid: data must be 2-D, got shape %s' % (self.data.shape,))
        self.resolution = float(resolution)
        origin = [float(v) for v in origin]
        if len(origin) == 2:
            origin.append(0.0)
        if len(origin) != 3:
            raise ValueError('OccupancyGrid: origin must be (x, y[, theta]), got %r' % (origin,))
        self.origin = tuple(origin)

    @property
    def width(self):
        return self.data.shape[1]

    @property
    def height(self):
        return self.data.shape[0]

    @property
    def occupied(self):
        """Cells map_server calls occupied (100), as a boolean array."""
        return self.data == 100

    @property
    def free(self):
        """Cells map_server calls free (0), as a boolean array."""
        return self.data == 0

    @property
    def unknown(self):
        return self.data == -1

    @property
    def extent(self):
        """(xmin, xmax, ymin, ymax) for matplotlib's imshow(origin='lower')."""
        return (self.origin[0], self.origin[0] + self.width * self.resolution,
                self.origin[1], self.origin[1] + self.height * self.resolution)


def _fail(yaml_path, what):
    raise MapIoError("map YAML '%s': %s" % (yaml_path, what))


def _require(meta, key, yaml_path):
    if meta.get(key) is None:
        _fail(yaml_path, "missing key '%s'" % key)
    return meta[key]


def _number(value, key, yaml_path):
    # yaml-cpp converts a scalar text; PyYAML has already typed it. Accept what yaml-cpp would.
    if isinstance(value, bool) or isinstance(value, (list, dict)):
        _fail(yaml_path, "'%s' must be a finite number, got '%s'" % (key, value))
    try:
        v = float(value)
    except (TypeError, ValueError):
        _fail(yaml_path, "'%s' must be a finite number, got '%s'" % (key, value))
    if not math.isfinite(v):
        _fail(yaml_path, "'%s' must be a finite number, got '%s'" % (key, value))
    return v


def _negate(value, yaml_path):
    # map_server reads an int; true/false are accepted too because hand-written YAMLs use them.
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip() in ('0', '1'):  # quoted: yaml-cpp reads it too
        value = int(value)
    if isinstance(value, int) and value in (0, 1):
        return value == 1
    _fail(yaml_path, "'negate' must be 0 or 1, got '%s'" % (value,))


def _read_pgm(path):
    """A PGM (P5 binary or P2 ASCII, maxval 255 or 65535) as uint8 or uint16, top row first;
    None when the file is not a PGM."""
    with open(path, 'rb') as f:
        data = f.read()
    if data[:2] not in (b'P5', b'P2'):
        return None
    tokens, pos = [], 0
    while len(tokens) < 4:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if pos >= len(data):
            raise ValueError('truncated PGM header')
        if data[pos:pos + 1] == b'#':
            end = data.find(b'\n', pos)
            pos = len(data) if end < 0 else end + 1
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos])
    try:
        width, height, maxval = int(tokens[1]), int(tokens[2]), int(tokens[3])
    except ValueError:
        raise ValueError('bad PGM header %r' % b' '.join(tokens))
    if width <= 0 or height <= 0 or maxval not in (255, 65535):
        raise ValueError('PGM of %d x %d pixels, maxval %d (positive size, maxval 255 or 65535 '
                         'expected)' % (width, height, maxval))
    if tokens[0] == b'P5':
        dtype = np.uint8 if maxval == 255 else np.dtype('>u2')
        count = width * height
        body = data[pos + 1:]
        if len(body) < count * np.dtype(dtype).itemsize:
            raise ValueError('%d pixel bytes for %d x %d pixels' % (len(body), width, height))
        img = np.frombuffer(body, dtype=dtype, count=count)
    else:
        values = data[pos:].split()
        if len(values) < width * height:
            raise ValueError('%d pixel values for %d x %d pixels' % (len(values), width, height))
        img = np.array(values[:width * height], dtype=np.int64)
        img = img.astype(np.uint8 if maxval == 255 else np.uint16)
    return img.reshape(height, width)


def _read_other(path):
    """Any other image format (PNG, ...) through Pillow: grey, grey+alpha (as RGBA), RGB or
    RGBA, as OpenCV's IMREAD_UNCHANGED sees them up to channel order."""
    try:
        from PIL import Image
    except ImportError:
        raise ValueError('not a PGM, and Pillow (python3-pil) is not installed to read it')
    with Image.open(path) as im:
        if im.mode in ('I;16', 'I;16B', 'I;16L', 'I'):
            return np.asarray(im, dtype=np.uint16)
        if im.mode == '1':
            im = im.convert('L')
        elif im.mode == 'LA' or (im.mode == 'P' and 'transparency' in im.info):
            im = im.convert('RGBA')
        elif im.mode not in ('L', 'RGB', 'RGBA'):
            im = im.convert('RGB')
        return np.asarray(im, dtype=np.uint8)


def read_image(image_path, yaml_path=None):
    """The image of a map as uint8, (h, w) or (h, w, channels), top row first. 16-bit images
    are brought to 8 bits as an 8-bit reader would see them (65535 -> 255)."""
    where = yaml_path if yaml_path is not None else image_path
    if not os.path.exists(image_path):
        _fail(where, "image '%s' does not exist" % image_path)
    if os.path.isdir(image_path):
        _fail(where, "image '%s' is a directory" % image_path)
    try:
        img = _read_pgm(image_path)
        if img is None:
            img = _read_other(image_path)
    except (OSError, ValueError) as e:
        _fail(where, "image '%s' cannot be read as an image (PGM, PNG, ...): %s" % (image_path, e))
    if img.dtype != np.uint8:
        img = np.floor(img.astype(np.float64) / 257.0 + 0.5).astype(np.uint8)
    if img.ndim == 3 and img.shape[2] not in (1, 3, 4):
        _fail(where, "image '%s' has %d channels (1, 3 or 4 expected)" % (image_path,
                                                                         img.shape[2]))
    if img.ndim == 3 and img.shape[2] == 1:
        img = img[:, :, 0]
    return img


def _cells(img, negate, mode, occ_th, free_th):
    """map_server's image_loader, vectorised: image (top row first) -> int8 cells."""
    if img.ndim == 2:
        px = img[:, :, None].astype(np.int64)
    else:
        px = img.astype(np.int64)
    n = px.shape[2]
    has_alpha = n == 4
    # map_server averages alpha in with the colours in trinary mode (kept for compatibility),
    # and leaves it out in scale and raw mode.
    avg = n if (mode == 'trinary' or not has_alpha) else n - 1
    mean = px[:, :, :avg].sum(axis=2) / float(avg)
    alpha = px[:, :, n - 1] if has_alpha else np.full(mean.shape, 255)
    if negate:
        mean = 255.0 - mean
    if mode == 'raw':
        cells = mean.astype(np.uint8).view(np.int8)
    else:
        p = (255.0 - mean) / 255.0
        cells = np.full(mean.shape, -1, dtype=np.int8)
        if mode == 'scale':
            between = (alpha != 0)
            scaled = (99.0 * (p - free_th) / (occ_th - free_th)) if occ_th != free_th else p
            cells[between] = np.trunc(scaled[between]).astype(np.int8)
        cells[p < free_th] = 0
        cells[p > occ_th] = 100
    return np.ascontiguousarray(cells[::-1, :])  # image row 0 is the top; grid row 0 the bottom


def load_map(yaml_path):
    """NAME.yaml and its image (a relative image path is relative to the YAML's folder) ->
    OccupancyGrid, with map_server's semantics. Raises MapIoError naming the file and the key
    or value at fault."""
    try:
        with open(yaml_path) as f:
            meta = yaml.safe_load(f)
    except OSError:
        raise MapIoError("map YAML '%s' cannot be opened" % yaml_path)
    except yaml.YAMLError as e:
        mark = getattr(e, 'problem_mark', None)
        raise MapIoError("map YAML '%s'%s does not parse: %s" % (
            yaml_path, ' line %d' % (mark.line + 1) if mark is not None else '',
            getattr(e, 'problem', None) or e))
    if not isinstance(meta, dict):
        _fail(yaml_path, 'expected a mapping of keys (image, resolution, ...)')
    image = _require(meta, 'image', yaml_path)
    if not isinstance(image, str) or not image:
        _fail(yaml_path, "'image' must be a file name, got '%s'" % (image,))
    resolution = _number(_require(meta, 'resolution', yaml_path), 'resolution', yaml_path)
    if resolution <= 0.0:
        _fail(yaml_path, "'resolution' must be positive, got %s" % format_double(resolution))
    origin = _require(meta, 'origin', yaml_path)
    if not isinstance(origin, list) or len(origin) != 3:
        _fail(yaml_path, "'origin' must be [x, y, yaw], got '%s'" % (origin,))
    negate = _negate(_require(meta, 'negate', yaml_path), yaml_path)
    occ_th = _number(_require(meta, 'occupied_thresh', yaml_path), 'occupied_thresh', yaml_path)
    free_th = _number(_require(meta, 'free_thresh', yaml_path), 'free_thresh', yaml_path)
    for key, v in (('occupied_thresh', occ_th), ('free_thresh', free_th)):
        if v < 0.0 or v > 1.0:
            _fail(yaml_path, "'%s' must be within [0, 1], got %s" % (key, format_double(v)))
    if occ_th < free_th:
        _fail(yaml_path, "'occupied_thresh' (%s) is below 'free_thresh' (%s)" % (
            format_double(occ_th), format_double(free_th)))
    mode = meta.get('mode')
    if mode is None:
        mode = 'trinary'
    if mode not in MODES:
        _fail(yaml_path, "'mode' must be trinary, scale or raw, got '%s'" % (mode,))
    if mode == 'scale' and occ_th == free_th:
        _fail(yaml_path, "mode scale needs 'free_thresh' below 'occupied_thresh'")
    xyz = [_number(v, 'origin[%d]' % i, yaml_path) for i, v in enumerate(origin)]
    if not os.path.isabs(image):
        image = os.path.join(os.path.dirname(yaml_path), image)
    img = read_image(image, yaml_path)
    return OccupancyGrid(_cells(img, negate, mode, occ_th, free_th), resolution, xyz)


def format_double(v):
    """The shortest decimal text that reads back as exactly v (as the C++ FormatDouble in
    minibot3d_map_io/file_util.h: plain decimals where short, exponents for tiny or huge)."""
    v = float(v)
    if 1e-4 <= abs(v) < 1e15:
        for decimals in range(18):
            text = '%.*f' % (decimals, v)
            if float(text) == v:
                return text
    for precision in range(1, 18):
        text = '%.*g' % (precision, v)
        if float(text) == v:
            break
    return text


def _yaml_float(v):
    text = format_double(v)
    if not any(c in text for c in '.eEn'):
        text += '.0'
    return text


def _yaml_name(name):
    # Plain where it reads back as the same string, else a double-quoted (JSON) scalar.
    if re.match(r'^[A-Za-z0-9_][A-Za-z0-9_./+-]*$', name) and yaml.safe_load(name) == name:
        return name
    return json.dumps(name)


def write_atomically(path, data):
    """Replaces path with data (bytes or str) through a temporary file in the same folder that
    is renamed into place: a reader never sees a half-written file, and a failed write leaves
    the previous file as it was. Raises MapIoError naming the file."""
    if isinstance(data, str):
        data = data.encode('utf-8')
    folder = os.path.dirname(os.path.abspath(path))
    try:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=os.path.basename(path) + '.tmp.')
    except OSError as e:
        raise MapIoError("cannot write '%s': cannot create a temporary file next to it: %s" % (
            path, e.strerror))
    try:
        with os.fdopen(fd, 'wb') as f:
            f.write(data)
            f.flush()
            os.fchmod(f.fileno(), 0o644)  # mkstemp makes 0600; maps are read by other users
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise MapIoError("cannot write '%s': %s" % (path, e.strerror or e))


def save_map(grid, base, occupied_percent=65, free_percent=25, pgm_comment=None,
             explain_grey_levels=True):
    """Writes BASE.pgm and BASE.yaml as map_saver does, byte for byte as the C++ SaveMap with
    the same options. Raises MapIoError naming the file."""
    data = np.asarray(grid.data)
    if data.ndim != 2 or data.size == 0:
        raise MapIoError("cannot save map '%s': the map is empty (%s cells)" % (
            base, ' x '.join(str(d) for d in data.shape[::-1])))
    if not (grid.resolution > 0.0) or not math.isfinite(grid.resolution):
        raise MapIoError("cannot save map '%s': resolution must be positive, got %s" % (
            base, grid.resolution))
    if not all(math.isfinite(v) for v in grid.origin):
        raise MapIoError("cannot save map '%s': the origin is not finite" % base)
    if not (1 <= occupied_percent <= 100 and 0 <= free_percent <= 100 and
            free_percent < occupied_percent):
        raise MapIoError("cannot save map '%s': need 0 <= free (%d) < occupied (%d) <= 100" % (
            base, free_percent, occupied_percent))
    if pgm_comment is not None and ('\n' in pgm_comment or '\r' in pgm_comment):
        raise MapIoError("cannot save map '%s': the PGM comment must be one line" % base)
    pgm_path, yaml_path = base + '.pgm', base + '.yaml'
    comment = pgm_comment or 'CREATOR: minibot3d_map_io %s m/pix' % format_double(grid.resolution)
    height, width = data.shape
    cells = data.astype(np.int16)[::-1, :]  # PGM row 0 is the top (highest y)
    pixels = np.full(cells.shape, UNKNOWN_PIXEL, dtype=np.uint8)
    pixels[(cells >= 0) & (cells <= free_percent)] = FREE_PIXEL
    pixels[(cells >= occupied_percent) & (cells <= 100)] = OCCUPIED_PIXEL
    pgm = ('P5\n# %s\n%d %d\n255\n' % (comment, width, height)).encode('utf-8') + \
        pixels.tobytes()
    text = ('image: %s\nresolution: %s\norigin: [%s, %s, %s]\nnegate: 0\n'
            'occupied_thresh: %s\nfree_thresh: %s\n' % (
                _yaml_name(os.path.basename(pgm_path)), _yaml_float(grid.resolution),
                _yaml_float(grid.origin[0]), _yaml_float(grid.origin[1]),
                _yaml_float(grid.origin[2]), _yaml_float(SAVED_OCCUPIED_THRESH),
                _yaml_float(SAVED_FREE_THRESH)))
    if explain_grey_levels:
        text += ('# Cells were written as %d (occupied, >= %d), %d (free, 0..%d) or %d '
                 '(unknown); the thresholds above read exactly those grey levels back (as '
                 'map_saver).\n' % (OCCUPIED_PIXEL, occupied_percent, FREE_PIXEL, free_percent,
                                    UNKNOWN_PIXEL))
    # Image first: a YAML on disk always points at a complete image.
    try:
        write_atomically(pgm_path, pgm)
    except MapIoError as e:
        raise MapIoError("cannot write map image '%s': %s" % (pgm_path, e))
    try:
        write_atomically(yaml_path, text)
    except MapIoError as e:
        raise MapIoError("cannot write map YAML '%s': %s" % (yaml_path, e))
