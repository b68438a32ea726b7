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
import minibot3d_map_io  # noqa: E402


def load_map(yaml_path):
    """The map as map_server reads it, drawn as map_saver writes it (occupied black, free white,
    unknown grey; scale-mode values in between), top row first; with resolution and (x, y)."""
    grid = minibot3d_map_io.load_map(yaml_path)
    cells = grid.data[::-1, :].astype(np.float64)
    img = np.where(cells < 0, 205.0, 254.0 - 2.54 * np.clip(cells, 0, 100)).astype(np.uint8)
    return img, grid.resolution, list(grid.origin[:2])


def main(argv):
    if len(argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    yaml_path, traj_path, out_path = argv[1:]
    try:
        img, res, origin = load_map(yaml_path)
        traj = np.loadtxt(traj_path, ndmin=2)
    except (OSError, ValueError) as e:  # MapIoError is a ValueError
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
