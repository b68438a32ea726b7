#!/usr/bin/env python3
"""AMCL accuracy in the simulator (part of make bench). Needs a running simulator + map_server +
amcl (tools/bench.sh starts them). Three phases, the robot driven by route_driver.py:
  1. tracking: --laps laps of the route from a known start; amcl_pose vs /ground_truth/odom;
  2. global localization: the global_localization service, then one lap; the distance travelled
     until the error stays below 0.2 m;
  3. kidnapping: the simulator teleports the robot (set_pose), one lap; the distance until the
     error stays below 0.2 m again.
Prints one line per phase."""
import argparse
import bisect
import math
import subprocess
import sys
import threading

import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry
from std_srvs.srv import Empty

from minibot3d_sim.srv import SetPose


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class Recorder(object):
    def __init__(self):
        self.lock = threading.Lock()
        self.truth_t, self.truth = [], []
        self.est = []
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=200)
        rospy.Subscriber('/amcl_pose', PoseWithCovarianceStamped, self.on_est, queue_size=50)

    def on_truth(self, m):
        p = m.pose.pose
        with self.lock:
            self.truth_t.append(m.header.stamp.to_sec())
            self.truth.append((p.position.x, p.position.y, yaw_of(p.orientation)))

    def on_est(self, m):
        p = m.pose.pose
        with self.lock:
            self.est.append((m.header.stamp.to_sec(), p.position.x, p.position.y,
                             yaw_of(p.orientation)))

    def mark(self):
        with self.lock:
            return len(self.est), len(self.truth)

    def errors(self, since):
        """(distance travelled since the phase start, position error, |yaw error|) per estimate."""
        with self.lock:
            est = self.est[since[0]:]
            tt, tr = list(self.truth_t), list(self.truth)
        out = []
        start = since[1]
        travelled, last = 0.0, tr[start] if start < len(tr) else None
        k = start
        for t, x, y, th in est:
            i = min(bisect.bisect_left(tt, t), len(tt) - 1)
            while k < i:  # distance along the truth up to this estimate
                k += 1
                travelled += math.hypot(tr[k][0] - tr[k - 1][0], tr[k][1] - tr[k - 1][1])
            gx, gy, gth = tr[i]
            dth = math.atan2(math.sin(th - gth), math.cos(th - gth))
            out.append((travelled, math.hypot(x - gx, y - gy), abs(dth)))
        return out, travelled


def drive(args, laps):
    r = subprocess.run(['rosrun', 'minibot3d_sim', 'route_driver.py', '--map', args.map,
                        '--waypoints', args.waypoints, '--laps', str(laps), '--speed', '0.3',
                        '--timeout', '900'], capture_output=True, text=True)
    if r.returncode != 0:
        print('amcl_bench: route_driver.py exited with %d: %s' % (
            r.returncode, (r.stderr.strip() or r.stdout.strip())[-600:]), flush=True)
    return r.returncode


def converged_after(errors, threshold=0.2):
    """Distance after which every later error stays below threshold (None if never)."""
    for i in range(len(errors)):
        if all(e[1] < threshold for e in errors[i:]):
            return errors[i][0]
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--map', required=True)
    parser.add_argument('--waypoints', required=True)
    parser.add_argument('--laps', type=int, default=3)
    parser.add_argument('--kidnap', default='2.5,-1.0,1.57')
    args = parser.parse_args()
    rospy.init_node('amcl_bench', anonymous=True)
    rec = Recorder()
    rospy.wait_for_message('/amcl_pose', PoseWithCovarianceStamped, timeout=120)

    since = rec.mark()
    if drive(args, args.laps) != 0:
        print('amcl_bench: tracking drive failed')
        return 1
    err, dist = rec.errors(since)
    pos = sorted(e[1] for e in err)
    print('amcl_bench tracking: %.1f m driven, %d estimates: position error mean %.3f m, '
          'p95 %.3f m, max %.3f m; yaw error mean %.2f deg'
          % (dist, len(err), sum(pos) / len(pos), pos[int(0.95 * (len(pos) - 1))], pos[-1],
             math.degrees(sum(e[2] for e in err) / len(err))))

    rospy.ServiceProxy('/global_localization', Empty)()
    since = rec.mark()
    drive(args, 1)
    err, dist = rec.errors(since)
    c = converged_after(err)
    print('amcl_bench global localization: %s (of %.1f m driven)'
          % ('converged to < 0.2 m after %.1f m' % c if c is not None else 'NOT converged', dist))

    kx, ky, kyaw = (float(v) for v in args.kidnap.split(','))
    res = rospy.ServiceProxy('/minibot3d_sim/set_pose', SetPose)(kx, ky, kyaw)
    if not res.success:
        print('amcl_bench kidnapping: teleport refused: %s' % res.message)
        return 1
    since = rec.mark()
    drive(args, 1)
    err, dist = rec.errors(since)
    c = converged_after(err)
    print('amcl_bench kidnapping to (%.1f, %.1f): %s (of %.1f m driven)'
          % (kx, ky, 'recovered to < 0.2 m after %.1f m' % c if c is not None else
             'NOT recovered', dist))
    return 0


if __name__ == '__main__':
    sys.exit(main())
