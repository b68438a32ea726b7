"""A simple wanderer for global-localization runs (make demo, tools/global_loc_study.py): drive
ahead where the laser shows room, steering towards the side with more of it, turning away where
there is none. It sees only the scan, as a robot switched on in an unknown place would.

seek_openings=True (the study's --wanderer openings) steers towards the deepest opening instead:
for each beam, the nearest return within the angle a 0.6 m wide corridor subtends at that beam's
range (so a door counts by what lies beyond it only when the robot fits through), less 0.5 m per
radian off the current heading (keep going rather than dither between two equal openings). It
leads out of a room through its door and along corridors, where a place shows what tells it apart
from look-alikes: on the office world's first 15 starts the first right claim came after a median
of 4.9 m instead of 5.9 m. But in the default world's furnished rooms it wedges itself (2.5-2.8 m
driven in 150 s in 3 of 11 starts), so it is not the default.

Wanderer(laser_yaw).command(scan) -> (v, w): laser_yaw is the laser's heading on the base
(minibot3d's RPLIDAR is mounted backwards: pi)."""
import math


class Wanderer(object):
    def __init__(self, laser_yaw=math.pi, speed=0.25, turn_rate=0.8, clearance=0.45,
                 seek_openings=False):
        self.laser_yaw = laser_yaw
        self.seek_openings = seek_openings  # see the module docstring
        self.speed = speed
        self.turn_rate = turn_rate
        self.clearance = clearance
        self.turning = 0.0  # sign of an in-place turn in progress (0: driving)

    def _sectors(self, scan):
        """Nearest return ahead (|bearing| < 25 deg) and the mean room left and right."""
        front, left, right = float('inf'), [], []
        for i, r in enumerate(scan.ranges):
            if not (r > scan.range_min):
                continue
            r = min(r, scan.range_max) if math.isfinite(r) else scan.range_max
            b = scan.angle_min + i * scan.angle_increment + self.laser_yaw
            b = math.atan2(math.sin(b), math.cos(b))
            if abs(b) < math.radians(25):
                front = min(front, r)
            elif 0 < b < math.radians(100):
                left.append(r)
            elif -math.radians(100) < b < 0:
                right.append(r)
        mean = lambda v: sum(v) / len(v) if v else 0.0
        return front, mean(left), mean(right)

    def command(self, scan):
        if scan is None:
            return 0.0, 0.0
        front, left, right = self._sectors(scan)
        if self.turning:
            # Keep turning one way until the way ahead is clear with a margin (no dithering).
            if front > 1.5 * self.clearance:
                self.turning = 0.0
            else:
                return 0.0, self.turning * self.turn_rate
        if front < self.clearance:
            self.turning = 1.0 if left >= right else -1.0
            return 0.0, self.turning * self.turn_rate
        # Towards the deepest opening: in place when it is well off to a side, else ahead,
        # slower near obstacles.
        bearing = self._deepest_opening(scan) if self.seek_openings else None
        if bearing is not None and abs(bearing) > math.radians(60):
            return 0.0, math.copysign(self.turn_rate, bearing)
        v = self.speed * min(1.0, (front - self.clearance) / 0.5 + 0.3)
        if bearing is None:
            w = max(-0.5, min(0.5, 0.4 * (left - right)))
        else:
            w = max(-0.6, min(0.6, 1.2 * bearing))
        return v, w

    def _deepest_opening(self, scan, half_width=0.3, per_radian=0.5):
        """Bearing (base frame, |b| < 100 deg) of the deepest opening, or None without returns."""
        beams = []
        for i, r in enumerate(scan.ranges):
            if math.isnan(r) or r < scan.range_min:
                continue
            r = min(r, scan.range_max)  # inf: nothing within range
            b = scan.angle_min + i * scan.angle_increment + self.laser_yaw
            beams.append((math.atan2(math.sin(b), math.cos(b)), r))
        if not beams:
            return None
        beams.sort()
        n, step = len(beams), abs(scan.angle_increment) or 1e-3
        full_circle = len(scan.ranges) * step >= 2.0 * math.pi - 1.5 * step
        best, best_score = None, -float('inf')
        for i, (b, r) in enumerate(beams):
            if abs(b) > math.radians(100):
                continue
            k = int(math.atan2(half_width, max(r, half_width)) / step)
            window = (beams[(i + j) % n] for j in range(-k, k + 1)) if full_circle else \
                beams[max(0, i - k):i + k + 1]
            depth = min(w[1] for w in window)
            score = depth - per_radian * abs(b)
            if score > best_score:
                best, best_score = b, score
        return best
