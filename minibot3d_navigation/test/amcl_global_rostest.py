#!/usr/bin/env python3
"""rostest: global localization that claims only what it knows (amcl_global.test).

For each start (a free pose of the default world's route, a heading of its own) the robot is
carried there with the simulator's set_pose (odometry is not told), /global_localization is called
once, and route_driver.py drives on through the next waypoints (about 10 m). Every amcl_pose
published after the call is compared with /ground_truth/odom at its stamp:
  * a claim is a covariance with cov_xx + cov_yy < 0.05 m^2 (make demo's threshold);
  * a false claim is one made while > 1 m or > 30 deg from the truth: there must be none;
  * the first right claim (< 0.3 m, < 10 deg) must come within 10 m of travel.
Lock-step time at full speed: the run is the same on any machine load; timeouts are sim seconds."""
import bisect
import math
import subprocess
import threading
import unittest

from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages

import rospy
import rostest
from geometry_msgs.msg import PoseWithCovarianceStamped
from minibot3d_sim.srv import SetPose
from nav_msgs.msg import Odometry
from std_msgs.msg import Float32MultiArray
from std_srvs.srv import Empty

CLAIM = 0.05          # m^2, cov_xx + cov_yy: make demo's "localized"
FALSE_DIST, FALSE_YAW = 1.0, math.radians(30.0)
RIGHT_DIST, RIGHT_YAW = 0.3, math.radians(10.0)
MAX_TRAVEL = 10.0     # m to the first right claim
# The default world's route (amcl_sim_rostest.py); each start is a waypoint and a heading, the
# drive goes on through the next four waypoints.
WAYPOINTS = [(-2.1, 0.6), (-0.3, 2.0), (0.45, 0.6), (2.5, -1.0), (0.8, -2.15), (-3.0, -1.5)]
STARTS = [(0, 1.0), (3, 2.5), (1, -2.0), (4, -0.5), (5, 1.5)]


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def angle_diff(a, b):
    return abs(math.atan2(math.sin(a - b), math.cos(a - b)))


class Recorder(object):
    """/ground_truth/odom (by stamp, with the distance travelled) and amcl_pose."""

    def __init__(self):
        self.lock = threading.Lock()
        self.truth_t, self.truth, self.travel = [], [], []
        self.poses = []  # (stamp, x, y, yaw, cov_xx + cov_yy)
        self.confidence = None
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=200)
        rospy.Subscriber('/amcl_pose', PoseWithCovarianceStamped, self.on_pose, queue_size=50)
        rospy.Subscriber('/amcl/confidence', Float32MultiArray, self.on_confidence, queue_size=5)

    def on_truth(self, m):
        p = m.pose.pose
        pose = (p.position.x, p.position.y, yaw_of(p.orientation))
        with self.lock:
            d = 0.0
            if self.truth:
                d = math.hypot(pose[0] - self.truth[-1][0], pose[1] - self.truth[-1][1])
                if d > 0.5:  # a teleport is not travel
                    d = 0.0
            self.travel.append((self.travel[-1] if self.travel else 0.0) + d)
            self.truth_t.append(m.header.stamp.to_sec())
            self.truth.append(pose)

    def on_pose(self, m):
        p = m.pose.pose
        c = m.pose.covariance
        with self.lock:
            self.poses.append((m.header.stamp.to_sec(), p.position.x, p.position.y,
                               yaw_of(p.orientation), c[0] + c[7]))

    def on_confidence(self, m):
        with self.lock:
            self.confidence = list(m.data)

    def truth_at(self, t):
        with self.lock:
            i = bisect.bisect_left(self.truth_t, t)
            cands = [k for k in (i - 1, i) if 0 <= k < len(self.truth_t)]
            k = min(cands, key=lambda k: abs(self.truth_t[k] - t))
            return self.truth[k], self.travel[k]

    def latest_truth(self):
        with self.lock:
            return self.truth[-1] if self.truth else None

    def truth_after(self, t):
        """The latest truth if stamped after t, else None."""
        with self.lock:
            return self.truth[-1] if self.truth_t and self.truth_t[-1] > t else None


class AmclGlobal(unittest.TestCase):
    def test_global_localization_starts(self):
        rospy.init_node('amcl_global')
        map_yaml = rospy.get_param('~map_yaml')
        # Woken by the truth too: after a teleport the robot stands still and amcl is quiet.
        lockstep = Participant(wake_topics=['/amcl_pose', '/ground_truth/odom'],
                               wake_on_participants=True)
        rec = Recorder()
        self.assertTrue(lockstep.wait_for(lambda: rec.poses and rec.truth, 120.0),
                        'no amcl_pose or /ground_truth/odom')
        set_pose = rospy.ServiceProxy('/minibot3d_sim/set_pose', SetPose)
        global_loc = rospy.ServiceProxy('/global_localization', Empty)
        failures, summary = [], []
        for k, yaw in STARTS:
            x, y = WAYPOINTS[k]
            t_set = rospy.Time.now().to_sec()
            r = set_pose(x, y, yaw)
            self.assertTrue(r.success, r.message)
            # The simulator also publishes the new pose at once, outside its ticks, which may
            # reach us a tick early or late; a truth of a later tick comes at a fixed sim time.
            def moved():
                p = rec.truth_after(t_set)
                return p is not None and math.hypot(p[0] - x, p[1] - y) < 0.05
            self.assertTrue(lockstep.wait_for(moved, 10.0),
                            'the simulator did not move the robot to (%g, %g)' % (x, y))
            t_call = rospy.Time.now().to_sec()
            n0 = len(rec.poses)
            global_loc()
            route = ' '.join('%g,%g' % WAYPOINTS[(k + i) % len(WAYPOINTS)] for i in range(1, 5))
            finished, proc = lockstep.run(
                '/route_driver',
                ['rosrun', 'minibot3d_sim', 'route_driver.py', '--map', map_yaml,
                 '--waypoints', route, '--speed', '0.3', '--timeout', '300'],
                300, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            out, _ = proc.communicate(timeout=60)
            self.assertTrue(finished and proc.returncode == 0, out)
            _, travel0 = rec.truth_at(t_call)
            false_claims, first_right, last = [], None, None
            for (t, px, py, pyaw, cov) in rec.poses[n0:]:
                if t < t_call:
                    continue
                truth, travel = rec.truth_at(t)
                dist = math.hypot(px - truth[0], py - truth[1])
                dyaw = angle_diff(pyaw, truth[2])
                last = (dist, dyaw, cov)
                if cov >= CLAIM:
                    continue
                if dist > FALSE_DIST or dyaw > FALSE_YAW:
                    false_claims.append((travel - travel0, dist, math.degrees(dyaw)))
                elif first_right is None and dist < RIGHT_DIST and dyaw < RIGHT_YAW:
                    first_right = travel - travel0
            line = ('start (%g, %g, %g): %d false claims %s; first right claim after %s m; '
                    'at the end %.2f m / %.1f deg off, cov_xx+cov_yy %.3g' % (
                        x, y, yaw, len(false_claims), false_claims[:3],
                        '%.2f' % first_right if first_right is not None else 'never',
                        last[0], math.degrees(last[1]), last[2]))
            rospy.loginfo('amcl_global: ' + line)
            summary.append(line)
            if false_claims:
                failures.append(line)
            elif first_right is None or first_right > MAX_TRAVEL:
                failures.append(line)
        self.assertEqual(failures, [], '\n'.join(summary))


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'amcl_global', AmclGlobal)
