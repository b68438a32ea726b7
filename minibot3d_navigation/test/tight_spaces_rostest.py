#!/usr/bin/env python3
"""rostest: move_base through tight spaces (tight_spaces.test). The robot (0.24 m x 0.23 m) starts
at (-3, -1.2) in tight_spaces.world, amcl at the true pose on the ground-truth map (map frame =
world frame). Each goal must be SUCCEEDED with the true position within 0.3 m of it and the true
heading within 0.3 rad, within about three times the sim time it takes at the run's max_vel_x
(LIMITS), and the simulator must report no collision over the whole run (read from a status sent
after its end):
 1. under the table: between two of its legs, 0.42 m apart;
 2. through the 0.40 m door into the east room;
 3. into the 0.50 m gap between the shelf and the east wall;
 4. back through the door to the start.
Lock-step time at full speed: this node is a participant, so the run is the same on any load.
Catches: a controller that creeps (over a limit) or stops at the wrong heading, a collision or a
simulator status that never arrives."""
import math
import sys
import threading
import unittest

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node
from minibot3d_lockstep.run_checks import RunChecks
from minibot3d_testing.sim_status import SimStatusWatch

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry

GOALS = [('under the table (legs 0.42 m apart)', -2.0, 0.6, math.pi / 2),
         ('through the 0.40 m door', 1.0, 0.0, 0.0),
         ('into the 0.50 m gap beside the shelf', 3.85, 0.0, math.pi / 2),
         ('back to the start, through the door', -3.0, -1.2, math.pi)]
# Each goal's limit in s of sim time, by max_vel_x (the speeds CMakeLists.txt runs): three times
# what a passing run takes (lock-step time: the same on any machine), so a controller that creeps
# fails. Passing runs: 0.1 m/s 23.4, 34.4, 48.1, 87.0 s; 0.5 m/s 6.9, 12.9, 12.3, 25.8 s;
# 1.0 m/s 6.7, 12.4, 11.5, 21.9 s.
LIMITS = {0.1: [70.0, 103.0, 144.0, 261.0],
          0.5: [21.0, 39.0, 37.0, 77.0],
          1.0: [20.0, 37.0, 35.0, 66.0]}
# Where a reached goal may truly be: twice the controller's xy_goal_tolerance and
# yaw_goal_tolerance (0.15 m, 0.15 rad; config/trajectory_planner.yaml), the rest for amcl's error.
POSITION_TOLERANCE = 0.3
HEADING_TOLERANCE = 0.3


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def heading_error(a, b):
    return abs(math.remainder(a - b, 2.0 * math.pi))


class TightSpaces(unittest.TestCase):
    def test_goals_in_tight_spaces(self):
        rospy.init_node('tight_spaces_test')
        lock = threading.Lock()
        state = {'pose': None}

        def on_truth(m):
            p = m.pose.pose
            with lock:
                state['pose'] = (p.position.x, p.position.y, yaw_of(p.orientation))

        rospy.Subscriber('/ground_truth/odom', Odometry, on_truth, queue_size=10)
        status = SimStatusWatch()  # the collisions, with the statuses that arrived
        max_vel_x = rospy.get_param('/move_base/TrajectoryPlannerROS/max_vel_x')
        self.assertIn(max_vel_x, LIMITS, 'no goal limits measured for max_vel_x %g' % max_vel_x)
        lockstep = Participant(wake_topics=['move_base/result'])
        checks = RunChecks()  # no tf sent twice, nothing listening beyond loopback
        client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
        self.assertTrue(lockstep.wait_for(lambda: action_server_ready(client), 120.0),
                        'no move_base action server')
        self.assertTrue(lockstep.wait_for(lambda: state['pose'] is not None, 60.0),
                        'no /ground_truth/odom')
        failures = []
        for (name, x, y, yaw), limit in zip(GOALS, LIMITS[max_vel_x]):
            goal = MoveBaseGoal()
            goal.target_pose.header.frame_id = 'map'
            goal.target_pose.header.stamp = rospy.Time.now()
            goal.target_pose.pose.position.x, goal.target_pose.pose.position.y = x, y
            goal.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
            goal.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
            start = rospy.Time.now()
            client.send_goal(goal)
            done = lockstep.wait_for(
                lambda: client.simple_state == actionlib.SimpleGoalState.DONE, limit)
            with lock:
                px, py, pyaw = state['pose']
            error = math.hypot(px - x, py - y)
            heading = heading_error(pyaw, yaw)
            result = client.get_state() if done else None
            print('tight_spaces: %s: %s in %.1f s sim (limit %g s), %.2f m and %.3f rad from it, '
                  'collisions so far: %d' % (
                      name, GoalStatus.to_string(result) if done else 'no result',
                      (rospy.Time.now() - start).to_sec(), limit, error, heading,
                      status.collisions), flush=True)
            if not done:
                client.cancel_goal()
                failures.append('%s: no result within %g s of sim time' % (name, limit))
            elif (result != GoalStatus.SUCCEEDED or error > POSITION_TOLERANCE
                  or heading > HEADING_TOLERANCE):
                failures.append('%s: %s (%s), %.2f m and %.3f rad from the goal' % (
                    name, GoalStatus.to_string(result), client.get_goal_status_text(), error,
                    heading))
        collisions = status.problems_at_end(lockstep)
        problems = checks.problems()
        lockstep.close()
        self.assertEqual([], failures + collisions + problems)


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'tight_spaces', TightSpaces, sys.argv)
