#!/usr/bin/env python3
"""rostest (mapless_clutter.test): in a clutter world, with no map and no localizer, the goal from
the world's JSON (5.5 m ahead of the start, given in odom) is reached by
`simple_navi_goals.py --frame odom` (exit 0, SUCCEEDED), the robot truly ends within 0.3 m of it,
and the simulator reports no collision. Lock-step time: this node and simple_navi_goals.py are
participants; every wait is on a condition in sim time."""
import json
import math
import subprocess
import threading
import unittest

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node
from minibot3d_lockstep.run_checks import RunChecks

import actionlib
import rospy
import rostest
from minibot3d_sim.msg import SimStatus
from move_base_msgs.msg import MoveBaseAction
from nav_msgs.msg import Odometry


class MaplessClutter(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('mapless_clutter')
        with open(rospy.get_param('~world_json')) as f:
            cls.world = json.load(f)
        cls.lockstep = Participant(wake_on_participants=True)
        cls.lockstep.add_periodic(0.05, lambda now: None)
        cls.checks = RunChecks()  # no tf sent twice, nothing listening beyond loopback
        cls.lock = threading.Lock()
        cls.pose = None
        cls.collisions = 0
        rospy.Subscriber('/ground_truth/odom', Odometry, cls.on_odom, queue_size=10)
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, cls.on_status, queue_size=10)
        client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
        assert cls.lockstep.wait_for(lambda: action_server_ready(client), 120.0), \
            'no move_base action server'
        assert cls.lockstep.wait_for(lambda: cls.pose is not None, 60.0), 'no ground truth'

    @classmethod
    def on_odom(cls, m):
        with cls.lock:
            cls.pose = (m.pose.pose.position.x, m.pose.pose.position.y)

    @classmethod
    def on_status(cls, m):
        with cls.lock:
            cls.collisions = m.collisions

    def test_goal_ahead_in_odom_is_reached_without_collision(self):
        goal = self.world['goal']
        finished, proc = self.lockstep.run(
            '/simple_navi_goals',
            ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'odom',
             str(goal['x']), str(goal['y']), str(goal['yaw']), '--timeout', '180'],
            300.0, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertTrue(finished, 'simple_navi_goals.py did not finish within 300 s of sim time')
        stdout, _ = proc.communicate(timeout=60)
        name = '%s (narrowest gap %.3f m)' % (self.world['name'], self.world['achieved_gap'])
        self.assertEqual(proc.returncode, 0, '%s:\n%s' % (name, stdout))
        self.assertIn('SUCCEEDED', stdout)
        with self.lock:
            x, y = self.pose
            collisions = self.collisions
        self.assertLess(math.hypot(x - goal['x'], y - goal['y']), 0.3,
                        '%s: goal reached at true (%.2f, %.2f)' % (name, x, y))
        self.assertEqual(collisions, 0, '%s: %d collisions' % (name, collisions))
        self.assertEqual([], self.checks.problems())


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'mapless_clutter', MaplessClutter)
