"""Per-trial figures from the ground-truth trajectory and the world's ground-truth map (no ROS).

Clearance is the distance from the robot's footprint outline (the costmap `footprint`, without
`footprint_padding`) to the nearest occupied cell of the world's ground-truth map: the outline is
sampled every 1 cm at each recorded pose, the Euclidean distance transform of the map (distance of
each cell centre to the nearest occupied cell centre) is interpolated there, and half a cell is
subtracted so the figure is to the cell's edge, not its centre.  <= 0 means the footprint touches
an obstacle.  This is the real gap between the chassis and the world, not a circumscribed-radius
bound, which would say a 0.33 m-wide robot is colliding whenever a wall is within 0.17 m of the
centre while driving parallel to it.
"""
import math

import minibot3d_map_io
import numpy as np
from scipy import ndimage


class GridMap(object):
    """A map_server map: occupied[row, col] with row 0 at the lowest y."""

    def __init__(self, occupied, resolution, origin):
        self.occupied = occupied
        self.resolution = float(resolution)
        self.origin = (float(origin[0]), float(origin[1]))
        self._edt = None

    @property
    def extent(self):
        """(xmin, xmax, ymin, ymax) for matplotlib's imshow(origin='lower')."""
        h, w = self.occupied.shape
        return (self.origin[0], self.origin[0] + w * self.resolution,
                self.origin[1], self.origin[1] + h * self.resolution)

    def distance(self, x, y):
        """Distance (m) from points to the nearest occupied cell's edge, bilinear in the EDT."""
        if self._edt is None:
            self._edt = ndimage.distance_transform_edt(~self.occupied) * self.resolution
        gx = (np.asarray(x, float) - self.origin[0]) / self.resolution - 0.5
        gy = (np.asarray(y, float) - self.origin[1]) / self.resolution - 0.5
        d = ndimage.map_coordinates(self._edt, [gy.ravel(), gx.ravel()], order=1,
                                    mode='constant', cval=0.0)
        return d.reshape(np.shape(gx)) - 0.5 * self.resolution


def load_map(yaml_path):
    """map_server YAML + image -> GridMap of the cells map_server calls occupied."""
    grid = minibot3d_map_io.load_map(yaml_path)
    return GridMap(grid.occupied, grid.resolution, grid.origin[:2])


def outline(footprint, step=0.01):
    """Points every `step` m along a closed polygon [[x, y], ...] (robot frame): (N, 2)."""
    poly = np.asarray(footprint, float)
    points = []
    for a, b in zip(poly, np.roll(poly, -1, axis=0)):
        n = max(1, int(math.ceil(np.linalg.norm(b - a) / step)))
        t = np.arange(n)[:, None] / n
        points.append(a + t * (b - a))
    return np.vstack(points)


def min_clearance(traj, grid_map, footprint):
    """Smallest footprint-to-obstacle distance over the trajectory (m); nan if no poses."""
    if len(traj['x']) == 0:
        return float('nan')
    pts = outline(footprint)
    c, s = np.cos(traj['yaw'])[:, None], np.sin(traj['yaw'])[:, None]
    wx = traj['x'][:, None] + c * pts[:, 0] - s * pts[:, 1]
    wy = traj['y'][:, None] + s * pts[:, 0] + c * pts[:, 1]
    return float(np.min(grid_map.distance(wx, wy)))


def path_length(traj):
    if not len(traj['x']):
        return 0.0
    return float(np.sum(np.hypot(np.diff(traj['x']), np.diff(traj['y']))))


def peak_speed(traj, window=0.2):
    """Largest displacement over any `window` sim seconds / window (m/s): robust to the
    physics' contact jitter, which a single ground-truth twist sample is not."""
    t, x, y = traj['t'], traj['x'], traj['y']
    if len(t) < 2:
        return 0.0
    j = np.searchsorted(t, t + window)
    ok = j < len(t)
    if not np.any(ok):
        return float(math.hypot(x[-1] - x[0], y[-1] - y[0]) / max(t[-1] - t[0], 1e-9))
    i = np.nonzero(ok)[0]
    j = j[ok]
    return float(np.max(np.hypot(x[j] - x[i], y[j] - y[i]) / (t[j] - t[i])))


def trial_metrics(traj, grid_map, footprint, goal, time_to_goal):
    """The figures results.csv records, from a trajectory dict of arrays t, x, y, yaw."""
    length = path_length(traj)
    end = (traj['x'][-1], traj['y'][-1]) if len(traj['x']) else (float('nan'),) * 2
    duration = time_to_goal if time_to_goal and time_to_goal > 0 else (
        traj['t'][-1] - traj['t'][0] if len(traj['t']) > 1 else float('nan'))
    return dict(path_length=length,
                min_clearance=(min_clearance(traj, grid_map, footprint) if grid_map
                               else float('nan')),
                mean_speed=length / duration if duration and duration > 0 else float('nan'),
                peak_speed=peak_speed(traj),
                goal_error=float(math.hypot(end[0] - goal[0], end[1] - goal[1])))


def read_trajectory(path):
    """The driver's trajectory.csv (t,x,y,yaw) -> dict of arrays."""
    try:
        data = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
    except (OSError, ValueError):
        data = np.zeros((0, 4))
    if data.size == 0:
        data = np.zeros((0, 4))
    return dict(t=data[:, 0], x=data[:, 1], y=data[:, 2], yaw=data[:, 3])
