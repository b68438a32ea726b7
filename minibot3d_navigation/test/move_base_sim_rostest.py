#!/usr/bin/env python3
"""rostest: move_base in the simulator (move_base_sim.test), robot spawned at (-3, -1.5, 0) in the
default world, amcl started there, the map frame = the world frame:
 1. the goal client: `rosrun minibot3d_sim simple_navi_goals.py 1 1` exits 0 and the robot ends
    about 1 m ahead of where it was, facing as it did;
 2. three goals across the apartment are reached (SUCCEEDED, true position within 0.3 m and
    heading within 0.3 rad);
 3. a goal inside a wall is ABORTED, and the status text says why;
 4. cancelling a goal mid-way stops the robot (PREEMPTED, ground-truth speed falls to ~0);
 5. a goal with an all-zero quaternion is rejected saying so; one with w = 2 is normalised and
    reached, with feedback in the map frame; after global_localization, `simple_navi_goals.py
    --wait-for-fix` wanders until amcl claims a confident fix, then reaches its goal.
Each within about three times the sim time it takes (the limits below). No collisions are reported
by the simulator during the whole run, read from a status sent after its end. Every wait is on a
condition (an action result, a message, a process exit) with a timeout, never a fixed sleep.
Catches: a controller that creeps (over a limit) or stops at the wrong heading (yaw_goal_tolerance
3.2: 0.69 and 2.51 rad off), a collision or a simulator status that never arrives."""
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
import tf2_ros
from actionlib_msgs.msg import GoalStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

# Limits in s of sim time: about three times what a passing run takes (lock-step time: the same
# on any machine), so a controller that creeps fails.
# Goals (x, y, yaw, limit) across the apartment, reached in 6.8, 7.3 and 12.0 s.
GOALS = [(-2.1, 0.6, math.pi / 2, 20.0), (0.45, 0.6, 0.0, 22.0),
         (2.5, -1.0, -math.pi / 2, 36.0)]
WALL_GOAL = (0.4, 0.0, 0.0)  # the middle of the 4 m wall along y = 0
WALL_GOAL_LIMIT = 90.0         # aborted after 31.1 s: the planner's patience, then the recoveries
SEED_CLIENT_LIMIT = 9.0        # `simple_navi_goals.py 1 1`, start to exit: 3.0 s
NORMALISED_GOAL_LIMIT = 50.0   # the goal with w = 2: 16.7 s
FIX_LIMIT = 48.0               # after global_localization, a confident fix: 15.8 s
FIXED_GOAL_LIMIT = 32.0        # then the goal: 10.4 s
FIX_CLIENT_LIMIT = 80.0        # that client, start to exit: 26.2 s
# Where a reached goal may truly be: twice the controller's xy_goal_tolerance and
# yaw_goal_tolerance (0.15 m, 0.15 rad; config/trajectory_planner.yaml), the rest for amcl's error.
POSITION_TOLERANCE = 0.3
HEADING_TOLERANCE = 0.3


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def heading_error(a, b):
    return abs(math.remainder(a - b, 2.0 * math.pi))


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
    """Latest /ground_truth/odom."""

    def __init__(self, lockstep):
        self.lockstep = lockstep
        self.cond = threading.Condition()
        self.pose = None
        self.speed = 0.0
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_odom, queue_size=10)

    def on_odom(self, m):
        with self.cond:
            p = m.pose.pose
            self.pose = (p.position.x, p.position.y, yaw_of(p.orientation))
            self.speed = math.hypot(m.twist.twist.linear.x, m.twist.twist.linear.y)
            self.cond.notify_all()

    def wait(self, predicate, timeout):
        """Sim time moves on (checked every 0.05 s of it) until predicate() holds."""
        return self.lockstep.wait_for(predicate, timeout)


class MoveBaseSim(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('move_base_sim_test')
        cls.status = SimStatusWatch()  # the collisions, with the statuses that arrived
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
        """Sends goal; (finished within `timeout` s of sim time, state, status text)."""
        start = rospy.get_rostime()
        self.client.send_goal(goal)
        finished = self.result(timeout)
        if not finished:
            self.client.cancel_goal()
        p = goal.target_pose.pose
        print('move_base_sim: goal (%.2f, %.2f, %.2f): %s after %.1f s of sim time (limit %g s)'
              % (p.position.x, p.position.y, yaw_of(p.orientation),
                 GoalStatus.to_string(self.client.get_state()) if finished else 'no result',
                 (rospy.get_rostime() - start).to_sec(), timeout), flush=True)
        return finished, self.client.get_state(), self.client.get_goal_status_text()

    def run_client(self, args, limit):
        """Runs a goal client (a lock-step participant) to its end; its output. Fails when it
        takes longer than `limit` s of sim time or exits non-zero."""
        start = rospy.get_rostime()
        finished, proc = self.lockstep.run(
            '/simple_navi_goals', ['rosrun'] + args, limit, stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT, universal_newlines=True)
        took = (rospy.get_rostime() - start).to_sec()
        if not finished:
            proc.kill()
        stdout, _ = proc.communicate(timeout=60)
        print('move_base_sim: %s: %.1f s of sim time (limit %g s)\n%s' % (
            ' '.join(args), took, limit, stdout), flush=True)
        # A loop that stalls (sim time stops) ends the wait only when the test is shut down: the
        # sim time that passed tells the two apart.
        self.assertTrue(finished, '%s did not finish within %g s of sim time (%.1f s passed%s):\n%s'
                        % (' '.join(args), limit, took,
                           ', then the test was shut down' if rospy.is_shutdown() else '', stdout))
        self.assertEqual(proc.returncode, 0, stdout)
        return stdout

    def assert_reached(self, x, y, yaw, what=''):
        """The true pose is at (x, y) and heading yaw, within the tolerances."""
        px, py, pyaw = self.truth.pose
        print('move_base_sim: goal (%.2f, %.2f, %.2f) reached at true (%.2f, %.2f, %.2f): %.3f m, '
              '%.3f rad off' % (x, y, yaw, px, py, pyaw, math.hypot(px - x, py - y),
                                heading_error(pyaw, yaw)), flush=True)
        self.assertLess(math.hypot(px - x, py - y), POSITION_TOLERANCE,
                        'goal (%.2f, %.2f) reached at true (%.2f, %.2f)%s' % (x, y, px, py, what))
        self.assertLess(heading_error(pyaw, yaw), HEADING_TOLERANCE,
                        'goal heading %.2f rad reached at true heading %.2f rad%s'
                        % (yaw, pyaw, what))

    def test_1_goal_client_moves_one_metre(self):
        start = self.truth.pose
        # The goal client joins the loop while sim time is held, and is done when it leaves.
        stdout = self.run_client(['minibot3d_sim', 'simple_navi_goals.py', '1', '1'],
                                 SEED_CLIENT_LIMIT)
        for text in ('Set X = 1.0', 'Set W = 1.0', 'Waiting for server', 'Sending Goals',
                     'SUCCEEDED'):
            self.assertIn(text, stdout)
        end = self.truth.pose
        forward = (end[0] - start[0]) * math.cos(start[2]) + (end[1] - start[1]) * math.sin(start[2])
        sideways = -(end[0] - start[0]) * math.sin(start[2]) + (end[1] - start[1]) * math.cos(start[2])
        self.assertAlmostEqual(forward, 1.0, delta=0.25)
        self.assertLess(abs(sideways), 0.25)
        # Facing as it did (W = 1: yaw 0 in base_link).
        self.assertLess(heading_error(end[2], start[2]), HEADING_TOLERANCE,
                        'heading %.2f rad at the end, %.2f at the start' % (end[2], start[2]))

    def test_2_three_goals(self):
        for x, y, yaw, limit in GOALS:
            finished, state, text = self.send_and_wait(make_goal(x, y, yaw), limit)
            self.assertTrue(finished, 'goal (%.2f, %.2f) not finished in %g s' % (x, y, limit))
            self.assertEqual(state, GoalStatus.SUCCEEDED,
                             'goal (%.2f, %.2f): state %d: %s' % (x, y, state, text))
            self.assert_reached(x, y, yaw)

    def test_3_goal_in_wall_is_aborted_with_reason(self):
        finished, state, text = self.send_and_wait(make_goal(*WALL_GOAL), WALL_GOAL_LIMIT)
        self.assertTrue(finished, 'no result within %g s of sim time' % WALL_GOAL_LIMIT)
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
        start = rospy.get_rostime()
        self.client.send_goal(good, feedback_cb=feedback.append)
        self.assertTrue(self.result(NORMALISED_GOAL_LIMIT),
                        'no result within %g s of sim time' % NORMALISED_GOAL_LIMIT)
        print('move_base_sim: goal with w = 2: %.1f s of sim time (limit %g s)' % (
            (rospy.get_rostime() - start).to_sec(), NORMALISED_GOAL_LIMIT), flush=True)
        self.assertEqual(self.client.get_state(), GoalStatus.SUCCEEDED,
                         self.client.get_goal_status_text())
        self.assert_reached(-2.0, -1.5, 0.0)
        self.assertTrue(feedback, 'no feedback published')
        self.assertEqual(feedback[-1].base_position.header.frame_id, 'map')

    def test_5b_goal_after_global_localization_waits_for_a_fix(self):
        # Lost on purpose: the client calls global_localization, wanders until amcl claims a
        # confident fix (turning on the spot would earn none: the lidar sees all round), and
        # only then sends its goal.
        x, y, yaw, _ = GOALS[1]
        stdout = self.run_client(
            ['minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'map',
             str(x), str(y), str(yaw), '--global-localization',
             '--wait-for-fix', '%g' % FIX_LIMIT, '--wander-for-fix', '0.2',
             '--timeout', '%g' % FIXED_GOAL_LIMIT], FIX_CLIENT_LIMIT)
        for text in ('Calling global_localization', 'Waiting for a confident fix',
                     'Confident fix after', 'Sending Goals', 'SUCCEEDED'):
            self.assertIn(text, stdout)
        self.assertLess(stdout.index('Confident fix after'), stdout.index('Sending Goals'))
        self.assert_reached(x, y, yaw, ':\n' + stdout)

    def test_6_no_collisions(self):
        self.assertEqual([], self.status.problems_at_end(self.lockstep))

    def test_7_run_checks(self):
        self.assertEqual([], self.checks.problems())


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'move_base_sim', MoveBaseSim)
