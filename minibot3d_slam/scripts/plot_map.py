#!/usr/bin/python3
"""Draws a map (map_server YAML + image) with a trajectory on it.

usage: plot_map.py MAP.yaml TRAJECTORY.txt OUT.png

TRAJECTORY.txt holds 'timestamp x y theta' lines in the map frame (slam_offline's output).
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402


def read_pgm(path):
    """Reads a binary (P5) or ASCII (P2) PGM into a uint8/uint16 array, top row first."""
    with open(path, "rb") as f:
        data = f.read()
    tokens, pos = [], 0
    while len(tokens) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            while data[pos:pos + 1] not in (b"\n", b""):
                pos += 1
            continue
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos])
    magic, width, height, maxval = tokens[0], int(tokens[1]), int(tokens[2]), int(tokens[3])
    if magic == b"P5":
        dtype = np.uint8 if maxval < 256 else np.dtype(">u2")
        img = np.frombuffer(data, dtype=dtype, count=width * height, offset=pos + 1)
    elif magic == b"P2":
        img = np.array(data[pos:].split()[: width * height], dtype=np.uint16)
    else:
        raise ValueError("%s: not a PGM (magic %r)" % (path, magic))
    return img.reshape(height, width)


def load_map(yaml_path):
    with open(yaml_path) as f:
        meta = yaml.safe_load(f)
    for key in ("image", "resolution", "origin"):
        if key not in meta:
            raise ValueError("%s: missing key '%s'" % (yaml_path, key))
    image = meta["image"]
    if not os.path.isabs(image):
        image = os.path.join(os.path.dirname(os.path.abspath(yaml_path)), image)
    if image.lower().endswith(".pgm"):
        img = read_pgm(image)
    else:
        img = plt.imread(image)
        if img.ndim == 3:
            img = img[..., :3].mean(axis=2)
        if img.dtype != np.uint8:
            img = (img * 255).astype(np.uint8)
    return img, float(meta["resolution"]), [float(v) for v in meta["origin"][:2]]


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    yaml_path, traj_path, out_path = argv[1:]
    try:
        img, res, origin = load_map(yaml_path)
        traj = np.loadtxt(traj_path, ndmin=2)
    except (OSError, ValueError, yaml.YAMLError) as e:
        sys.stderr.write("plot_map.py: %s\n" % e)
        return 1
    height, width = img.shape
    extent = [origin[0], origin[0] + width * res, origin[1], origin[1] + height * res]
    # About 10 inches along the longer side at ~1 image pixel per map cell (at least 100 dpi).
    longer = max(width, height)
    fig, ax = plt.subplots(figsize=(max(3.0, 10.0 * width / longer) + 1.0, max(3.0, 10.0 * height / longer) + 0.8),
                           dpi=max(100, min(400, int(longer / 9))))
    # Image rows are top first; with origin='upper' and this extent, row 0 lands at the top (max y).
    ax.imshow(img, cmap="gray", vmin=0, vmax=255, extent=extent, origin="upper", interpolation="nearest")
    if traj.size:
        ax.plot(traj[:, 1], traj[:, 2], "-", color="tab:red", linewidth=0.6)
        ax.plot(traj[0, 1], traj[0, 2], "o", color="tab:green", markersize=3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")
    ax.set_title(os.path.basename(yaml_path))
    fig.tight_layout()
    fig.savefig(out_path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
