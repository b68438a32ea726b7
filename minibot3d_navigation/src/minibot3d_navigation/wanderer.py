"""A simple wanderer for global-localization runs (simple_navi_goals.py --wander-for-fix, make demo,
tools/bench/global_loc_study.py): drive ahead where the laser shows room, steering towards the
side with more of it, turning away where there is none. It sees only the scan, as a robot switched
on in an unknown place would.

seek_openings=True (the study's --wanderer openings) steers towards the deepest opening instead:
for each beam, the nearest return within the angle a 0.6 m wide corridor subtends at that beam's
range (so a door counts by what lies beyond it only when the robot fits through), less 0.5 m per
radian off the current heading (keep going rather than dither between two equal openings). It
leads out of a room through its door and along corridors. An in-place turn keeps one direction
until the way ahead is clear and the opening ahead; anything in the robot's swept path blocks it
(a wall's end beside the bumper, outside the 25 deg front cone); and a whole turn in place without
1 m driven (a gap it cannot pass) hands over to the side-steering wanderer for 5 s. Those three
keep it from wedging itself in furniture. It is not the default: it does not localize the robot
sooner than steering by the sides, and on the default world it leaves more starts without a right
fix (docs/benchmarks.md, global-localization study).

Wanderer(laser_yaw).command(scan) -> (v, w): laser_yaw is the laser's heading on the base
(minibot3d's RPLIDAR is mounted backwards: pi); mount_yaw(urdf, base, laser) reads it from a robot
description."""
import math
from xml.etree import ElementTree


def _rpy_matrix(roll, pitch, yaw):
    """URDF's fixed-axis roll, pitch, yaw as a rotation matrix: Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr]]


def _mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mount_yaw(urdf_xml, base_frame, frame):
    """The heading (rad) of `frame`'s x axis on `base_frame`, from the joints of a robot
    description (URDF XML): where a laser looks on the base, Wanderer's laser_yaw. ValueError
    naming the frame when the description lacks it or it is mounted upside down (the scan would
    run clockwise, which the wanderer does not handle)."""
    parent_of = {}
    links = set()
    root = ElementTree.fromstring(urdf_xml)
    for link in root.findall('link'):
        links.add(link.get('name'))
    for joint in root.findall('joint'):
        origin = joint.find('origin')
        rpy = (origin.get('rpy') if origin is not None else None) or '0 0 0'
        parent_of[joint.find('child').get('link')] = (joint.find('parent').get('link'),
                                                      _rpy_matrix(*map(float, rpy.split())))

    def in_root(link):
        link = link.lstrip('/')
        if link not in links:
            raise ValueError('frame %s is not a link of the robot description' % link)
        rotation = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        while link in parent_of:
            link, joint = parent_of[link]
            rotation = _mul(joint, rotation)
        return rotation

    base, sensor = in_root(base_frame), in_root(frame)
    relative = _mul([list(r) for r in zip(*base)], sensor)  # base^T sensor
    if relative[2][2] < 0.0:
        raise ValueError('frame %s is mounted upside down on %s' % (frame, base_frame))
    return math.atan2(relative[1][0], relative[0][0])


class Wanderer(object):
    def __init__(self, laser_yaw=math.pi, speed=0.25, turn_rate=0.8, clearance=0.45,
                 seek_openings=False, dt=0.1,
                 half_width=0.115):
        self.laser_yaw = laser_yaw
        self.seek_openings = seek_openings  # see the module docstring
        self.speed = speed
        self.turn_rate = turn_rate
        self.clearance = clearance
        self.dt = dt  # s between commands (the scan period)
        self.half_width = half_width  # m: the robot's (minibot3d's footprint: 0.23 m wide)
        self.turning = 0.0  # sign of an in-place turn in progress (0: driving)
        self.turned = 0.0  # rad turned in place since the robot last drove 1 m between turns
        self.driven = 0.0  # m commanded since the last in-place turn began
        self.escape_s = 5.0  # s of wandering by the sides after a fruitless whole turn
        self.plain = 0  # commands left of that

    def _sectors(self, scan):
        """Nearest return ahead (|bearing| < 25 deg; seeking openings, also any return in the
        robot's swept path, half_width + 0.1 m either side, by its distance along the heading:
        a wall's end beside the bumper) and the mean room left and right."""
        front, left, right = float('inf'), [], []
        for i, r in enumerate(scan.ranges):
            if not (r > scan.range_min):
                continue
            r = min(r, scan.range_max) if math.isfinite(r) else scan.range_max
            b = scan.angle_min + i * scan.angle_increment + self.laser_yaw
            b = math.atan2(math.sin(b), math.cos(b))
            if abs(b) < math.radians(25):
                front = min(front, r)
            elif self.seek_openings and abs(b) < math.pi / 2 and \
                    abs(r * math.sin(b)) < self.half_width + 0.1:
                front = min(front, r * math.cos(b))
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
        bearing = self._deepest_opening(scan) if self.seek_openings and not self.plain else None
        self.plain = max(0, self.plain - 1)
        if self.turning:
            # Keep turning one way until the way ahead is clear with a margin (and, seeking
            # openings, the opening is ahead): never dither between two directions. A whole
            # turn without that (an opening the robot cannot face clear of obstacles; or turns
            # back and forth with less than 1 m driven between them: a gap it cannot pass) ends
            # the turn too: then it wanders by the sides for a while (escape_s).
            self.turned += self.turn_rate * self.dt
            clear = front > 1.5 * self.clearance and (
                bearing is None or abs(bearing) < math.radians(30) or
                self.turned > 2.0 * math.pi)
            if not clear:
                return 0.0, self.turning * self.turn_rate
            if self.turned > 2.0 * math.pi and self.seek_openings:
                self.plain = int(round(self.escape_s / self.dt))
            self.turning = 0.0
        if front < self.clearance:
            # Blocked: turn the way the opening lies (seeking), else the side with more room.
            if bearing is not None and abs(bearing) > math.radians(5):
                side = math.copysign(1.0, bearing)
            else:
                side = 1.0 if left >= right else -1.0
            return self._start_turn(side)
        # Towards the deepest opening: in place when it is well off to a side, else ahead,
        # slower near obstacles.
        if bearing is not None and abs(bearing) > math.radians(60):
            return self._start_turn(math.copysign(1.0, bearing))
        v = self.speed * min(1.0, (front - self.clearance) / 0.5 + 0.3)
        self.driven += v * self.dt
        if bearing is None:
            w = max(-0.5, min(0.5, 0.4 * (left - right)))
        else:
            w = max(-0.6, min(0.6, 1.2 * bearing))
        return v, w

    def _start_turn(self, side):
        """An in-place turn towards side (+1 left, -1 right)."""
        self.turning = side
        if self.driven >= 1.0:
            self.turned = 0.0
        self.driven = 0.0
        return 0.0, self.turning * self.turn_rate

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
