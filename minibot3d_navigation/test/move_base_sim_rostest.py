#!/usr/bin/env python3
"""rostest: move_base in the simulator (move_base_sim.test), robot spawned at (-3, -1.5, 0) in the
default world, amcl started there, the map frame = the world frame:
 1. the goal client: `rosrun minibot3d_sim simple_navi_goals.py 1 1` exits 0 and the robot ends
    about 1 m ahead of where it was;
 2. three goals across the apartment are reached (SUCCEEDED, true position within 0.3 m);
 3. a goal inside a wall is ABORTED, and the status text says why;
 4. cancelling a goal mid-way stops the robot (PREEMPTED, ground-truth speed falls to ~0);
 5. a goal with an all-zero quaternion is rejected saying so; one with w = 2 is normalised and
    reached, with feedback in the map frame; after global_localization, `simple_navi_goals.py
    --wait-for-fix` turns on the spot until amcl claims a confident fix, then reaches its goal.
No collisions are reported by the simulator during the whole run.  Every wait is on a condition
(an action result, a message, a process exit) with a timeout, never a fixed sleep."""
import math
import subprocess
import threading
import unittest

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node
from minibot3d_lockstep.run_checks import RunChecks

import actionlib
import rospy
import rostest
import tf2_ros
from actionlib_msgs.msg import GoalStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

GOALS = [(-2.1, 0.6, math.pi / 2), (0.45, 0.6, 0.0), (2.5, -1.0, -math.pi / 2)]
WALL_GOAL = (0.4, 0.0, 0.0)  # the middle of the 4 m wall along y = 0


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def make_goal(x, y, yaw, frame='map'):
    g = MoveBaseGoal()
    g.target_pose.header.frame_id = frame
    g.target_pose.header.stamp = rospy.Time.now()
    g.target_pose.pose.position.x = x
    g.target_pose.pose.position.y = y
    g.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
    g.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
    return g


class Truth(object):
    """Latest /ground_truth/odom and the simulator's collision count."""

    def __init__(self, lockstep):
        self.lockstep = lockstep
        self.cond = threading.Condition()
        self.pose = None
        self.speed = 0.0
        self.collisions = []
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_odom, queue_size=10)
        from minibot3d_sim.msg import SimStatus
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, self.on_status, queue_size=10)
        self.collision_count = 0

    def on_odom(self, m):
        with self.cond:
            p = m.pose.pose
            self.pose = (p.position.x, p.position.y, yaw_of(p.orientation))
            self.speed = math.hypot(m.twist.twist.linear.x, m.twist.twist.linear.y)
            self.cond.notify_all()

    def on_status(self, m):
        with self.cond:
            self.collision_count = m.collisions

    def wait(self, predicate, timeout):
        """Sim time moves on (checked every 0.05 s of it) until predicate() holds."""
        return self.lockstep.wait_for(predicate, timeout)


class MoveBaseSim(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('move_base_sim_test')
        # A lock-step participant (move_base_sim.test): woken by results, by the participant
        # list (simple_navi_goals.py leaving) and every 0.05 s of sim time to check the truth.
        cls.lockstep = Participant(wake_topics=['move_base/result', '/amcl_pose'],
                                   wake_on_participants=True)
        cls.lockstep.add_periodic(0.05, lambda now: None)
        cls.truth = Truth(cls.lockstep)
        cls.checks = RunChecks()  # no tf sent twice, nothing listening beyond loopback
        localized = []
        rospy.Subscriber('/amcl_pose', PoseWithCovarianceStamped, localized.append, queue_size=5)
        cls.client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
        assert cls.lockstep.wait_for(lambda: action_server_ready(cls.client), 120.0), \
            'no move_base action server'
        assert cls.truth.wait(lambda: cls.truth.pose is not None, 60.0), 'no ground truth'
        # Goals in base_link need map -> base_link now: amcl publishes map -> odom with its
        # first pose (first scan), and the lookup needs it to cover the latest odometry.
        assert cls.lockstep.wait_for(lambda: bool(localized), 60.0), 'no amcl_pose'
        tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(tf_buffer)
        assert cls.lockstep.wait_for(
            lambda: tf_buffer.can_transform('map', 'base_link', rospy.Time(0)), 60.0), \
            'no map -> base_link transform'

    def result(self, timeout):
        return self.lockstep.wait_for(
            lambda: self.client.simple_state == actionlib.SimpleGoalState.DONE, timeout)

    def send_and_wait(self, goal, timeout):
        self.client.send_goal(goal)
        finished = self.result(timeout)
        if not finished:
            self.client.cancel_goal()
        return finished, self.client.get_state(), self.client.get_goal_status_text()

    def test_1_goal_client_moves_one_metre(self):
        start = self.truth.pose
        # The goal client joins the loop while sim time is held, and is done when it leaves.
        finished, proc = self.lockstep.run(
            '/simple_navi_goals', ['rosrun', 'minibot3d_sim', 'simple_navi_goals.py', '1', '1'],
            600.0, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertTrue(finished, 'simple_navi_goals.py did not finish within 600 s of sim time')
        stdout, _ = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 0, stdout)
        for text in ('Set X = 1.0', 'Set W = 1.0', 'Waiting for server', 'Sending Goals',
                     'SUCCEEDED'):
            self.assertIn(text, stdout)
        end = self.truth.pose
        forward = (end[0] - start[0]) * math.cos(start[2]) + (end[1] - start[1]) * math.sin(start[2])
        sideways = -(end[0] - start[0]) * math.sin(start[2]) + (end[1] - start[1]) * math.cos(start[2])
        self.assertAlmostEqual(forward, 1.0, delta=0.25)
        self.assertLess(abs(sideways), 0.25)

    def test_2_three_goals(self):
        for x, y, yaw in GOALS:
            finished, state, text = self.send_and_wait(make_goal(x, y, yaw), 300.0)
            self.assertTrue(finished, 'goal (%.2f, %.2f) not finished in 300 s' % (x, y))
            self.assertEqual(state, GoalStatus.SUCCEEDED,
                             'goal (%.2f, %.2f): state %d: %s' % (x, y, state, text))
            px, py, _ = self.truth.pose
            self.assertLess(math.hypot(px - x, py - y), 0.3,
                            'goal (%.2f, %.2f) reached at true (%.2f, %.2f)' % (x, y, px, py))

    def test_3_goal_in_wall_is_aborted_with_reason(self):
        finished, state, text = self.send_and_wait(make_goal(*WALL_GOAL), 300.0)
        self.assertTrue(finished)
        self.assertEqual(state, GoalStatus.ABORTED, text)
        self.assertIn('valid plan', text)
        self.assertIn('lethal', text)

    def test_4_cancel_stops_the_robot(self):
        self.client.send_goal(make_goal(-3.0, -1.5, 0.0))
        self.assertTrue(self.truth.wait(lambda: self.truth.speed > 0.1, 60.0),
                        'robot never started moving')
        self.client.cancel_goal()
        self.assertTrue(self.result(10.0))
        self.assertEqual(self.client.get_state(), GoalStatus.PREEMPTED)
        self.assertTrue(self.truth.wait(lambda: self.truth.speed < 0.02, 5.0),
                        'robot still moving at %.2f m/s after cancel' % self.truth.speed)

    def test_5_goal_quaternions(self):
        # All-zero quaternion: rejected (ABORTED) with the reason, the robot does not move.
        bad = make_goal(-2.0, -1.5, 0.0)
        bad.target_pose.pose.orientation.z = 0.0
        bad.target_pose.pose.orientation.w = 0.0
        finished, state, text = self.send_and_wait(bad, 30.0)
        self.assertTrue(finished)
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn('quaternion', text)
        # Not normalised (w = 2): normalised and reached, with feedback on the way.
        feedback = []
        good = make_goal(-2.0, -1.5, 0.0)
        good.target_pose.pose.orientation.w = 2.0
        self.client.send_goal(good, feedback_cb=feedback.append)
        self.assertTrue(self.result(300.0))
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED,
                         self.client.get_goal_status_text())
        self.assertTrue(feedback, 'no feedback published')
        self.assertEqual(feedback[-1].base_position.header.frame_id, 'map')

    def test_5b_goal_after_global_localization_waits_for_a_fix(self):
        # Lost on purpose: the client calls global_localization, wanders until amcl claims a
        # confident fix (turning on the spot would earn none: the lidar sees all round), and
        # only then sends its goal.
        x, y, yaw = GOALS[1]
        finished, proc = self.lockstep.run(
            '/simple_navi_goals',
            ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'map',
             str(x), str(y), str(yaw), '--global-localization', '--wait-for-fix', '120',
             '--wander-for-fix', '0.2', '--timeout', '300'],
            600.0, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertTrue(finished, 'simple_navi_goals.py did not finish within 600 s of sim time')
        stdout, _ = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 0, stdout)
        for text in ('Calling global_localization', 'Waiting for a confident fix',
                     'Confident fix after', 'Sending Goals', 'SUCCEEDED'):
            self.assertIn(text, stdout)
        self.assertLess(stdout.index('Confident fix after'), stdout.index('Sending Goals'))
        px, py, _ = self.truth.pose
        self.assertLess(math.hypot(px - x, py - y), 0.3,
                        'goal (%.2f, %.2f) reached at true (%.2f, %.2f):\n%s' % (x, y, px, py, stdout))

    def test_6_no_collisions(self):
        self.assertEqual(self.truth.collision_count, 0)

    def test_7_run_checks(self):
        self.assertEqual([], self.checks.problems())


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'move_base_sim', MoveBaseSim)
