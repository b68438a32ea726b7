#!/usr/bin/env python3
"""rostest: move_base through tight spaces (tight_spaces.test). The robot (0.24 m x 0.23 m) starts
at (-3, -1.2) in tight_spaces.world, amcl at the true pose on the ground-truth map (map frame =
world frame). Each goal must be SUCCEEDED with the true position within 0.3 m of it, and the
simulator must report no collision over the whole run:
 1. under the table: between two of its legs, 0.42 m apart;
 2. through the 0.40 m door into the east room;
 3. into the 0.50 m gap between the shelf and the east wall;
 4. back through the door to the start.
Lock-step time at full speed: this node is a participant, so the run is the same on any load."""
import math
import sys
import threading
import unittest

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node
from minibot3d_lockstep.run_checks import RunChecks

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from minibot3d_sim.msg import SimStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry

GOALS = [('under the table (legs 0.42 m apart)', -2.0, 0.6, math.pi / 2),
         ('through the 0.40 m door', 1.0, 0.0, 0.0),
         ('into the 0.50 m gap beside the shelf', 3.85, 0.0, math.pi / 2),
         ('back to the start, through the door', -3.0, -1.2, math.pi)]


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class TightSpaces(unittest.TestCase):
    def test_goals_in_tight_spaces(self):
        rospy.init_node('tight_spaces_test')
        lock = threading.Lock()
        state = {'pose': None, 'collisions': 0}

        def on_truth(m):
            p = m.pose.pose
            with lock:
                state['pose'] = (p.position.x, p.position.y, yaw_of(p.orientation))

        def on_status(m):
            with lock:
                state['collisions'] = int(m.collisions)

        rospy.Subscriber('/ground_truth/odom', Odometry, on_truth, queue_size=10)
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, on_status, queue_size=10)
        lockstep = Participant(wake_topics=['move_base/result'])
        checks = RunChecks()  # no tf sent twice, nothing listening beyond loopback
        client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
        self.assertTrue(lockstep.wait_for(lambda: action_server_ready(client), 120.0),
                        'no move_base action server')
        self.assertTrue(lockstep.wait_for(lambda: state['pose'] is not None, 60.0),
                        'no /ground_truth/odom')
        failures = []
        for name, x, y, yaw in GOALS:
            goal = MoveBaseGoal()
            goal.target_pose.header.frame_id = 'map'
            goal.target_pose.header.stamp = rospy.Time.now()
            goal.target_pose.pose.position.x, goal.target_pose.pose.position.y = x, y
            goal.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
            goal.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
            start = rospy.Time.now()
            client.send_goal(goal)
            done = lockstep.wait_for(
                lambda: client.simple_state == actionlib.SimpleGoalState.DONE, 180.0)
            with lock:
                px, py, _ = state['pose']
            error = math.hypot(px - x, py - y)
            status = client.get_state() if done else None
            print('tight_spaces: %s: %s in %.1f s sim, %.2f m from it, %s: %s' % (
                name, GoalStatus.to_string(status) if done else 'no result',
                (rospy.Time.now() - start).to_sec(), error, 'collisions so far',
                state['collisions']), flush=True)
            if not done:
                client.cancel_goal()
                failures.append('%s: no result within 180 s of sim time' % name)
            elif status != GoalStatus.SUCCEEDED or error > 0.3:
                failures.append('%s: %s (%s), %.2f m from the goal' % (
                    name, GoalStatus.to_string(status), client.get_goal_status_text(), error))
        problems = checks.problems()
        lockstep.close()
        self.assertEqual(failures, [])
        self.assertEqual([], problems)
        self.assertEqual(state['collisions'], 0, 'the simulator reported collisions')


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'tight_spaces', TightSpaces, sys.argv)
