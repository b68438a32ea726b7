"""A simple wanderer for global-localization runs (make demo, tools/global_loc_study.py): drive
ahead where the laser shows room, turn away where it does not. It sees only the scan, as a robot
switched on in an unknown place would.

Wanderer(laser_yaw).command(scan) -> (v, w): laser_yaw is the laser's heading on the base
(minibot3d's RPLIDAR is mounted backwards: pi)."""
import math


class Wanderer(object):
    def __init__(self, laser_yaw=math.pi, speed=0.25, turn_rate=0.8, clearance=0.45):
        self.laser_yaw = laser_yaw
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
        # Ahead, steering gently towards the side with more room, slower near obstacles.
        v = self.speed * min(1.0, (front - self.clearance) / 0.5 + 0.3)
        w = max(-0.5, min(0.5, 0.4 * (left - right)))
        return v, w
