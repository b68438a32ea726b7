#!/usr/bin/env python3
"""rostest (mapless_clutter.test): in a clutter world, with no map and no localizer and a typical
small indoor robot's odometry error, the goal from the world's JSON (5.5 m ahead of the start,
given in odom) is reached by `simple_navi_goals.py --frame odom` (exit 0, SUCCEEDED) within about
three times the sim time it takes (LIMITS), the robot's odometry ends within 0.3 m of it and
0.3 rad of its heading, and the simulator reports no collision (read from a status sent after the
end). The goal is in odom, so that is where it is checked: the true end pose differs from the
odometry's by the odometry's error over the drive (printed; 0.07-0.23 m over the 5.5 m), which a
robot without a map cannot know. Collisions are the true ones, so obstacles that the odometry's
drift moves in the odom costmap count. Lock-step time: this node and simple_navi_goals.py are
participants; every wait is on a condition in sim time.
Catches: a controller that creeps (over the limit) or stops at the wrong heading, a collision or a
simulator status that never arrives."""
import json
import math
import subprocess
import threading
import unittest

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node
from minibot3d_lockstep.run_checks import RunChecks
from minibot3d_testing.sim_status import SimStatusWatch

import actionlib
import rospy
import rostest
from move_base_msgs.msg import MoveBaseAction
from nav_msgs.msg import Odometry

# The goal's limit in s of sim time, by world (those CMakeLists.txt runs): three times what a
# passing run takes (lock-step time: the same on any machine), so a controller that creeps fails.
# Passing runs: 23.9, 16.7, 17.4, 15.7 and 13.5 s.
LIMITS = {'clutter_12': 72.0, 'clutter_20': 50.0, 'clutter_37': 52.0, 'clutter_43': 47.0,
          'clutter_49': 41.0}
# The client's run may take this much longer than its goal, so that a goal over its limit is
# reported by the client itself ("Goal not reached within --timeout").
CLIENT_MARGIN = 10.0
# Where the odometry may end: twice the controller's xy_goal_tolerance and yaw_goal_tolerance
# (0.15 m, 0.15 rad; config/trajectory_planner.yaml).
POSITION_TOLERANCE = 0.3
HEADING_TOLERANCE = 0.3


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def heading_error(a, b):
    return abs(math.remainder(a - b, 2.0 * math.pi))


class MaplessClutter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('mapless_clutter')
        with open(rospy.get_param('~world_json')) as f:
            cls.world = json.load(f)
        cls.lock = threading.Lock()
        cls.pose = cls.odom = None
        rospy.Subscriber('/ground_truth/odom', Odometry, cls.on_truth, queue_size=10)
        rospy.Subscriber('/odom', Odometry, cls.on_odom, queue_size=10)
        cls.status = SimStatusWatch()  # the collisions, with the statuses that arrived
        cls.lockstep = Participant(wake_on_participants=True)
        cls.lockstep.add_periodic(0.05, lambda now: None)
        cls.checks = RunChecks()  # no tf sent twice, nothing listening beyond loopback
        client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
        assert cls.lockstep.wait_for(lambda: action_server_ready(client), 120.0), \
            'no move_base action server'
        assert cls.lockstep.wait_for(lambda: cls.pose is not None and cls.odom is not None,
                                     60.0), 'no ground truth or odometry'

    @staticmethod
    def pose_of(m):
        p = m.pose.pose
        return (p.position.x, p.position.y, yaw_of(p.orientation))

    @classmethod
    def on_truth(cls, m):
        with cls.lock:
            cls.pose = cls.pose_of(m)

    @classmethod
    def on_odom(cls, m):
        with cls.lock:
            cls.odom = cls.pose_of(m)

    def test_goal_ahead_in_odom_is_reached_without_collision(self):
        goal = self.world['goal']
        name = '%s (narrowest gap %.3f m)' % (self.world['name'], self.world['achieved_gap'])
        self.assertIn(self.world['name'], LIMITS, 'no goal limit measured for ' + name)
        limit = LIMITS[self.world['name']]
        start = rospy.get_rostime()
        finished, proc = self.lockstep.run(
            '/simple_navi_goals',
            ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'odom',
             str(goal['x']), str(goal['y']), str(goal['yaw']), '--timeout', '%g' % limit],
            limit + CLIENT_MARGIN, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            universal_newlines=True)
        took = (rospy.get_rostime() - start).to_sec()
        if not finished:
            proc.kill()
        stdout, _ = proc.communicate(timeout=60)
        print('mapless_clutter: %s: %.1f s of sim time (goal limit %g s)\n%s'
              % (name, took, limit, stdout), flush=True)
        self.assertTrue(finished, '%s: simple_navi_goals.py did not finish within %g s of sim '
                        'time:\n%s' % (name, limit + CLIENT_MARGIN, stdout))
        self.assertEqual(proc.returncode, 0, '%s:\n%s' % (name, stdout))
        self.assertIn('SUCCEEDED', stdout)
        with self.lock:
            (x, y, yaw), (tx, ty, tyaw) = self.odom, self.pose
        # The simulator starts odometry at the spawn pose, the world's origin: odom = world.
        print('mapless_clutter: %s: goal (%.2f, %.2f, %.2f) reached at (%.2f, %.2f, %.2f) in '
              'odom, truly at (%.2f, %.2f, %.2f): the odometry %.2f m and %.2f rad off'
              % (name, goal['x'], goal['y'], goal['yaw'], x, y, yaw, tx, ty, tyaw,
                 math.hypot(x - tx, y - ty), heading_error(yaw, tyaw)), flush=True)
        self.assertLess(math.hypot(x - goal['x'], y - goal['y']), POSITION_TOLERANCE,
                        '%s: goal reached at (%.2f, %.2f) in odom' % (name, x, y))
        self.assertLess(heading_error(yaw, goal['yaw']), HEADING_TOLERANCE,
                        '%s: goal heading %.2f rad reached at heading %.2f rad in odom'
                        % (name, goal['yaw'], yaw))
        self.assertEqual([], self.status.problems_at_end(self.lockstep), name)
        self.assertEqual([], self.checks.problems())

if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'mapless_clutter', MaplessClutter)
