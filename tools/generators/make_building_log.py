#!/usr/bin/env python3
"""Writes a synthetic CARMEN log of a robot driving a building of long corridors, with its truth.

    tools/generators/make_building_log.py OUT.clf OUT.truth [--width 64] [--height 36] [--laps 2]
        [--fov 180] [--beams 181] [--max-range 30] [--yaw-bias 0.25] [--seed 1] [--png OUT.png]

Why: the SLAM front-end (a scan-matching RBPF) drifts most where a corridor is longer than the
laser sees and its walls have few features: along it, only door recesses pin the position. Round a
building-sized loop the drift of heading and scale bends the map, as it does on real logs of
buildings with long corridors. The Intel log's loops are short, so it does not
exercise this; this log does, with a known truth to score against (make_relations OUT.truth).

The building (--width × --height m): a ring corridor 2.4 m wide inset 6 m from the outer walls,
crossed in the middle by a second corridor, so the drive has two loops sharing a corridor. Rooms
line the corridors on both sides; each room's door onto the corridor is open (a gap showing the
room and a desk in it) with probability 0.3, else a closed door recessed 0.12 m into the wall.
Doors are 3–9 m apart (--door-gap) at random (--seed), so places along a corridor can be told apart, but only
by a few beams. The robot starts in the bottom corridor and drives the outer ring once, then
--laps times round the two halves (figure of eight through the cross corridor), at 0.4 m/s with a
gentle weave of ±3° heading, turning on the spot (0.5 rad/s) at the corners.

The laser (--fov degrees, --beams, --max-range m; 5 Hz): σ 1 cm range noise, 1 % of beams a
spurious short return (people, clutter), and beams without an echo within --max-range logged at
the maximum (the log's max_range field; slam_offline reads those as no-returns). The odometry
(20 Hz ODOM lines, and in each laser line) integrates the true motion with a 2 % scale error on
distance, −1 % on rotation, --yaw-bias degrees of heading per metre driven, and white noise.

Output: OUT.clf with ROBOTLASER1 and ODOM lines (the laser at the base, so its mounting is zero)
and OUT.truth, "timestamp x y theta" per laser line (the true pose), for make_relations.
"""
import argparse
import math
import os
import random
import sys
import tempfile

import numpy as np

CORRIDOR = 2.4       # m, corridor width
INSET = 6.0          # m, corridor centre line from the outer walls
DOOR = 0.9           # m, door width
RECESS = 0.12        # m, a closed door's recess into the wall
SPEED = 0.4          # m/s
TURN_RATE = 0.5      # rad/s
ODOM_DT = 0.05       # s
LASER_EVERY = 4      # odometry steps per laser reading (5 Hz)


class Building:
    """Axis-aligned wall segments (x0, y0, x1, y1)."""

    def __init__(self, width, height, door_gap, rng):
        self.walls = []
        self.door_gap = door_gap
        self.w, self.h = width, height
        w, h, c = width, height, CORRIDOR / 2
        xm = width / 2
        # Outer walls.
        self.box(0, 0, w, h)
        # Ring corridor: its outer side (rooms between it and the outer walls), its inner side
        # (two blocks of rooms either side of the cross corridor), the cross corridor's sides.
        lo, hi = INSET - c, INSET + c
        xl, xr, yb, yt = lo, w - lo, lo, h - lo          # outer side of the ring
        ixl, ixr, iyb, iyt = hi, w - hi, hi, h - hi      # inner side of the ring
        self.corridor_wall((xl, yb), (xr, yb), -1, rng)  # bottom, rooms below (outward)
        self.corridor_wall((xr, yb), (xr, yt), +1, rng, axis=1)
        self.corridor_wall((xl, yt), (xr, yt), +1, rng)
        self.corridor_wall((xl, yb), (xl, yt), -1, rng, axis=1)
        for bx0, bx1 in ((ixl, xm - c), (xm + c, ixr)):   # the two inner blocks
            self.corridor_wall((bx0, iyb), (bx1, iyb), +1, rng)
            self.corridor_wall((bx0, iyt), (bx1, iyt), -1, rng)
            self.corridor_wall((bx0, iyb), (bx0, iyt), +1, rng, axis=1)
            self.corridor_wall((bx1, iyb), (bx1, iyt), -1, rng, axis=1)
            # A core of services in the middle of the block.
            self.box(bx0 + 5, iyb + 5, bx1 - 5, iyt - 5)
        # Outer rooms: partitions from the ring's outer side to the outer walls.
        for x in self.partitions(xl, xr, rng):
            self.walls.append((x, 0, x, yb))
            self.walls.append((x, yt, x, h))
        for y in self.partitions(yb, yt, rng):
            self.walls.append((0, y, xl, y))
            self.walls.append((xr, y, w, y))

    def box(self, x0, y0, x1, y1):
        self.walls += [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]

    @staticmethod
    def partitions(a, b, rng):
        out, x = [], a + rng.uniform(3.5, 6.0)
        while x < b - 3.0:
            out.append(x)
            x += rng.uniform(3.5, 6.0)
        return out

    def corridor_wall(self, p, q, room_side, rng, axis=0):
        """A wall from p to q along `axis` (0: x, 1: y) with doors into rooms on `room_side`
        (the sign of the other coordinate's direction)."""
        a, b = p[axis], q[axis]
        fixed = p[1 - axis]

        def seg(s0, s1, off=0.0):
            u0, u1, v = s0, s1, fixed + off
            if axis == 0:
                self.walls.append((u0, v, u1, v))
            else:
                self.walls.append((v, u0, v, u1))

        def cross(s, off0, off1):
            v0, v1 = fixed + off0, fixed + off1
            if axis == 0:
                self.walls.append((s, v0, s, v1))
            else:
                self.walls.append((v0, s, v1, s))

        s = a
        d = a + rng.uniform(2.0, 6.0)
        while d + DOOR < b - 1.5:
            seg(s, d)
            if rng.random() < 0.3:  # open: a gap, a desk in the room behind
                depth = room_side * rng.uniform(1.5, 3.0)
                desk = d + rng.uniform(-1.0, 1.5)
                lo, hi = sorted((fixed + depth, fixed + depth + room_side * 0.7))
                if axis == 0:
                    self.box(desk, lo, desk + 1.4, hi)
                else:
                    self.box(lo, desk, hi, desk + 1.4)
            else:  # closed: recessed
                r = room_side * RECESS
                cross(d, 0, r)
                seg(d, d + DOOR, r)
                cross(d + DOOR, r, 0)
            s = d + DOOR
            d = s + rng.uniform(*self.door_gap) - DOOR
        seg(s, b)

    def cast(self, x, y, angles, max_range):
        """Ranges from (x, y) along `angles` (rad, world frame) to the nearest wall, inf if none."""
        segs = np.asarray(self.walls, dtype=float)
        dx, dy = np.cos(angles)[:, None], np.sin(angles)[:, None]
        ex, ey = (segs[:, 2] - segs[:, 0])[None, :], (segs[:, 3] - segs[:, 1])[None, :]
        wx, wy = (segs[:, 0] - x)[None, :], (segs[:, 1] - y)[None, :]
        den = dx * ey - dy * ex
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (wx * ey - wy * ex) / den
            u = (wx * dy - wy * dx) / den
        ok = (np.abs(den) > 1e-12) & (t > 1e-9) & (u >= 0) & (u <= 1)
        t = np.where(ok, t, np.inf)
        r = t.min(axis=1)
        r[r > max_range] = np.inf
        return r


def route(width, height, laps):
    """Corridor centre-line waypoints: the outer ring once, then `laps` figures of eight."""
    x0, x1, xm, y0, y1 = INSET, width - INSET, width / 2, INSET, height - INSET
    pts = [(x0 + 2, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0), (xm, y0)]
    for _ in range(laps):
        pts += [(xm, y1), (x1, y1), (x1, y0), (xm, y0), (xm, y1), (x0, y1), (x0, y0), (xm, y0)]
    pts.append((xm + 6, y0))
    return pts


def drive(pts):
    """True poses every ODOM_DT: straight legs with a weave, turns on the spot."""
    x, y = pts[0]
    th = math.atan2(pts[1][1] - y, pts[1][0] - x)
    poses = [(x, y, th)]
    phase = 0.0
    for tx, ty in pts[1:]:
        heading = math.atan2(ty - y, tx - x)
        while True:  # turn on the spot
            err = math.remainder(heading - th, math.tau)
            if abs(err) < 1e-9:
                break
            th += max(-TURN_RATE * ODOM_DT, min(TURN_RATE * ODOM_DT, err))
            poses.append((x, y, th))
        start, length = (x, y), math.hypot(tx - x, ty - y)
        travelled = 0.0
        while travelled < length - 1e-9:
            step = min(SPEED * ODOM_DT, length - travelled)
            travelled += step
            phase += step / 4.0
            # The centre line plus a lateral weave of ±0.15 m; heading along the weave's tangent.
            off = 0.15 * math.sin(phase * math.tau) * min(1.0, travelled, length - travelled)
            nx, ny = -math.sin(heading), math.cos(heading)
            x = start[0] + travelled * math.cos(heading) + off * nx
            y = start[1] + travelled * math.sin(heading) + off * ny
            px, py = poses[-1][0], poses[-1][1]
            th = math.atan2(y - py, x - px)
            poses.append((x, y, th))
        x, y = tx, ty
    return poses


def odometry(poses, yaw_bias_deg, rng):
    """Odometry integrating the true increments with scale errors, a yaw bias and noise."""
    ox, oy, oth = 0.0, 0.0, 0.0
    out = [(ox, oy, oth)]
    bias = math.radians(yaw_bias_deg)
    for (x0, y0, t0), (x1, y1, t1) in zip(poses, poses[1:]):
        c, s = math.cos(t0), math.sin(t0)
        dx, dy = c * (x1 - x0) + s * (y1 - y0), -s * (x1 - x0) + c * (y1 - y0)
        dth = math.remainder(t1 - t0, math.tau)
        dist = math.hypot(dx, dy)
        dx = dx * 1.02 + rng.gauss(0, 0.01 * dist)
        dy = dy * 1.02 + rng.gauss(0, 0.005 * dist)
        dth = dth * 0.99 + bias * dist + rng.gauss(0, 0.02 * abs(dth) + 0.002 * dist)
        ox += math.cos(oth) * dx - math.sin(oth) * dy
        oy += math.sin(oth) * dx + math.cos(oth) * dy
        oth = math.remainder(oth + dth, math.tau)
        out.append((ox, oy, oth))
    return out


def write_png(building, poses, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(10, 10 * building.h / building.w))
    for x0, y0, x1, y1 in building.walls:
        ax.plot([x0, x1], [y0, y1], "k-", lw=0.8)
    ax.plot([p[0] for p in poses], [p[1] for p in poses], "r-", lw=0.5)
    ax.set_aspect("equal")
    fig.savefig(path + ".tmp.png", dpi=100, bbox_inches="tight")
    os.replace(path + ".tmp.png", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("log")
    ap.add_argument("truth")
    ap.add_argument("--width", type=float, default=64.0)
    ap.add_argument("--height", type=float, default=36.0)
    ap.add_argument("--laps", type=int, default=2)
    ap.add_argument("--fov", type=float, default=180.0, help="degrees")
    ap.add_argument("--beams", type=int, default=181)
    ap.add_argument("--max-range", type=float, default=30.0)
    ap.add_argument("--yaw-bias", type=float, default=0.25, help="degrees of odometry heading per metre")
    ap.add_argument("--door-gap", type=float, nargs=2, default=(3.0, 9.0), metavar=("MIN", "MAX"),
                    help="m between door centres along a corridor wall, drawn uniformly")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--png", help="also draw the building and the true path")
    a = ap.parse_args()
    for name, v, lo in (("--width", a.width, 2 * INSET + 12), ("--height", a.height, 2 * INSET + 12)):
        if v < lo:
            sys.exit(f"{name} {v}: must be at least {lo} m (two corridors {INSET} m from the walls and rooms between)")
    if not DOOR + 0.5 <= a.door_gap[0] <= a.door_gap[1]:
        sys.exit(f"--door-gap {a.door_gap[0]} {a.door_gap[1]}: need {DOOR + 0.5} <= MIN <= MAX")
    if a.laps < 0:
        sys.exit(f"--laps {a.laps}: must be >= 0")
    if not 0 < a.fov <= 360 or a.beams < 2 or a.max_range <= 0:
        sys.exit(f"--fov {a.fov} (0, 360], --beams {a.beams} (>= 2), --max-range {a.max_range} (> 0): out of range")

    rng = random.Random(a.seed)
    building = Building(a.width, a.height, a.door_gap, rng)
    poses = drive(route(a.width, a.height, a.laps))
    odom = odometry(poses, a.yaw_bias, rng)
    nprng = np.random.default_rng(a.seed)
    fov = math.radians(a.fov)
    res = fov / (a.beams - 1) if a.fov < 360 else fov / a.beams
    start = -fov / 2 if a.fov < 360 else -math.pi
    rel = start + res * np.arange(a.beams)
    t0 = 1000000000.0

    def stamp(t):
        return f"{t:.6f} synthetic {t - t0:.6f}"

    dirname = os.path.dirname(os.path.abspath(a.log))
    with tempfile.NamedTemporaryFile("w", dir=dirname, delete=False) as log, \
            tempfile.NamedTemporaryFile("w", dir=os.path.dirname(os.path.abspath(a.truth)), delete=False) as truth:
        log.write("# synthetic building log: tools/generators/make_building_log.py " + " ".join(sys.argv[1:]) + "\n")
        log.write(f"PARAM robot_front_laser_max {a.max_range:g} nohost 0\n")
        for k, ((x, y, th), (ox, oy, oth)) in enumerate(zip(poses, odom)):
            t = t0 + k * ODOM_DT
            if k % LASER_EVERY == 0:
                r = building.cast(x, y, th + rel, a.max_range)
                r = r + nprng.normal(0, 0.01, r.shape)
                spurious = nprng.random(r.shape) < 0.01
                r = np.where(spurious, nprng.uniform(0.3, 1.0, r.shape) * np.minimum(r, a.max_range), r)
                r = np.where(np.isfinite(r) & (r < a.max_range), r, a.max_range)
                ranges = " ".join(f"{v:.3f}" for v in r)
                log.write(f"ROBOTLASER1 0 {start:.6f} {fov:.6f} {res:.6f} {a.max_range:g} 0.01 0 {a.beams} {ranges} 0 "
                          f"{ox:.6f} {oy:.6f} {oth:.6f} {ox:.6f} {oy:.6f} {oth:.6f} 0 0 0.5 0.5 0 {stamp(t)}\n")
                truth.write(f"{t:.6f} {x:.6f} {y:.6f} {th:.6f}\n")
            log.write(f"ODOM {ox:.6f} {oy:.6f} {oth:.6f} 0 0 0 {stamp(t)}\n")
    os.replace(log.name, a.log)
    os.replace(truth.name, a.truth)
    length = sum(math.hypot(q[0] - p[0], q[1] - p[1]) for p, q in zip(poses, poses[1:]))
    end_err = math.hypot(odom[-1][0] - (poses[-1][0] - poses[0][0]), odom[-1][1] - (poses[-1][1] - poses[0][1]))
    print(f"{len(poses) // LASER_EVERY + 1} scans, {len(poses) * ODOM_DT:.0f} s, {length:.0f} m driven, "
          f"{len(building.walls)} walls; odometry ends {end_err:.1f} m from the truth (frames aligned at the start)")
    if a.png:
        write_png(building, poses, a.png)


if __name__ == "__main__":
    main()
