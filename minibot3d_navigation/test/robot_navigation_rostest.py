#!/usr/bin/env python3
"""rostest: another robot's whole navigation stack in the simulator (robot_navigation.test, run
once per shipped robot with the launch args of its config set): the simulator with the robot's own
description, map_server, amcl and move_base from its config set, in the default world. The robot
(~robot) reaches each of its goals in ~goals_file ([x, y, yaw, limit]: limit in s of sim time,
about three times what a passing run takes), truly within 0.3 m and 0.3 rad (twice the controllers' goal tolerances,
the rest for amcl's error); no collision is reported for the whole run, read from a status sent
after its end; run_checks finds no transform sent twice and nothing listening beyond loopback.
Catches: a stack left on the default robot's topics (quadbot with scan_topic scan: "no amcl_pose"
in the set-up), a controller that creeps (over a limit), a goal reached at the wrong heading, a
robot whose body the simulator does not stop at walls (collisions)."""
import math
import threading
import unittest

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node
from minibot3d_lockstep.run_checks import RunChecks
from minibot3d_testing.sim_status import SimStatusWatch

import actionlib
import rospy
import rostest
import yaml
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseWithCovarianceStamped
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry

POSITION_TOLERANCE = 0.3
HEADING_TOLERANCE = 0.3


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def heading_error(a, b):
    return abs(math.remainder(a - b, 2.0 * math.pi))


def load_goals(path, robot):
    """The robot's goals in the YAML file at path as (x, y, yaw, limit) tuples; ValueError naming
    the file and what is wrong."""
    with open(path) as f:
        table = yaml.safe_load(f) or {}
    if robot not in table:
        raise ValueError('%s: no goals for robot %s (it has %s)' % (path, robot, sorted(table)))
    goals = []
    for g in table[robot]:
        if not isinstance(g, list) or len(g) != 4:
            raise ValueError('%s: %s: goal %r is not [x, y, yaw, limit]' % (path, robot, g))
        goals.append(tuple(float(v) for v in g))
    return goals


class RobotNavigation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('robot_navigation')
        cls.goals = load_goals(rospy.get_param('~goals_file'), rospy.get_param('~robot'))
        cls.status = SimStatusWatch()
        cls.lockstep = Participant(wake_topics=['move_base/result', '/amcl_pose'])
        cls.lockstep.add_periodic(0.05, lambda now: None)
        cls.checks = RunChecks()
        cls.cond = threading.Condition()
        cls.truth = None
        rospy.Subscriber('/ground_truth/odom', Odometry, cls.on_truth, queue_size=10)
        localized = []
        rospy.Subscriber('/amcl_pose', PoseWithCovarianceStamped, localized.append, queue_size=5)
        cls.client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
        assert cls.lockstep.wait_for(lambda: action_server_ready(cls.client), 120.0), \
            'no move_base action server'
        assert cls.lockstep.wait_for(lambda: cls.truth is not None, 60.0), 'no ground truth'
        assert cls.lockstep.wait_for(lambda: bool(localized), 60.0), \
            'no amcl_pose: amcl gets no scan on the robot\'s scan topic, or no odom -> base tf'

    @classmethod
    def on_truth(cls, m):
        p = m.pose.pose
        with cls.cond:
            cls.truth = (p.position.x, p.position.y, yaw_of(p.orientation))

    def test_1_goals(self):
        for x, y, yaw, limit in self.goals:
            goal = MoveBaseGoal()
            goal.target_pose.header.frame_id = 'map'
            goal.target_pose.header.stamp = rospy.Time.now()
            goal.target_pose.pose.position.x = x
            goal.target_pose.pose.position.y = y
            goal.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
            goal.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
            start = rospy.get_rostime()
            self.client.send_goal(goal)
            finished = self.lockstep.wait_for(
                lambda: self.client.simple_state == actionlib.SimpleGoalState.DONE, limit)
            took = (rospy.get_rostime() - start).to_sec()
            if not finished:
                self.client.cancel_goal()
            state = self.client.get_state()
            px, py, pyaw = self.truth
            print('robot_navigation: goal (%.2f, %.2f, %.2f): %s after %.1f s of sim time (limit '
                  '%g s), true (%.2f, %.2f, %.2f): %.3f m, %.3f rad off' % (
                      x, y, yaw, GoalStatus.to_string(state) if finished else 'no result', took,
                      limit, px, py, pyaw, math.hypot(px - x, py - y), heading_error(pyaw, yaw)),
                  flush=True)
            self.assertTrue(finished, 'goal (%.2f, %.2f): no result within %g s of sim time'
                            % (x, y, limit))
            self.assertEqual(state, GoalStatus.SUCCEEDED, 'goal (%.2f, %.2f): %s: %s' % (
                x, y, GoalStatus.to_string(state), self.client.get_goal_status_text()))
            self.assertLess(math.hypot(px - x, py - y), POSITION_TOLERANCE,
                            'goal (%.2f, %.2f) reached at true (%.2f, %.2f)' % (x, y, px, py))
            self.assertLess(heading_error(pyaw, yaw), HEADING_TOLERANCE,
                            'goal heading %.2f rad reached at true heading %.2f rad' % (yaw, pyaw))

    def test_2_no_collisions(self):
        self.assertEqual([], self.status.problems_at_end(self.lockstep))

    def test_3_run_checks(self):
        self.assertEqual([], self.checks.problems())


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'robot_navigation', RobotNavigation)
