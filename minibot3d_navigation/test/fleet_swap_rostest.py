#!/usr/bin/env python3
"""rostest: several robots, each with its own amcl and move_base, swap places (fleet_swap.test:
launch/fleet.launch in the default world, lock-step time at full speed) or cross the world
(fleet_goals.test: a fleet file's robots, of several models). All goals of the scenario
(~scenario in ~goals_file: per robot, in the order of ~names (default robot1 .. robotN),
[x, y, yaw, limit], limit in s of sim time, about three times what a passing run takes) are sent
at once; each robot must reach its goal, truly
within 0.3 m and 0.3 rad, within its limit. Reported per robot: reached, time, collisions with
walls and with robots (from its /NAME/minibot3d_sim/collisions, whose object names the other
robot as "robot NAME"), and the smallest distance between two robots' true positions over the run.
No collision may be reported (read from each robot's status sent after the end of the run), and
run_checks finds no transform sent twice and nothing listening beyond loopback.
Catches: a robot whose costmaps do not see the others (they meet head-on and collide, or stop
for good), a stack reading another robot's topics or frames (no pose, or the wrong robot moves),
lock-step time that leaves out a robot's nodes (results differ between runs; the test prints the
times so that two runs can be compared)."""
import math
import time
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
from minibot3d_sim.msg import Collision
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry

POSITION_TOLERANCE = 0.3
HEADING_TOLERANCE = 0.3


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def heading_error(a, b):
    return abs(math.remainder(a - b, 2.0 * math.pi))


def load_goals(path, scenario, robots):
    """[(x, y, yaw, limit)] of robot1 .. robotN; ValueError naming the file and what is wrong."""
    with open(path) as f:
        table = yaml.safe_load(f) or {}
    if scenario not in table:
        raise ValueError('%s: no scenario %s (it has %s)' % (path, scenario, sorted(table)))
    goals = table[scenario]
    if not isinstance(goals, list) or len(goals) != robots:
        raise ValueError('%s: %s: %d robots need %d goals' % (path, scenario, robots, robots))
    out = []
    for g in goals:
        if not isinstance(g, list) or len(g) != 4:
            raise ValueError('%s: %s: goal %r is not [x, y, yaw, limit]' % (path, scenario, g))
        out.append(tuple(float(v) for v in g))
    return out


class Robot(object):
    """One robot's goal, client, true pose and collisions."""

    def __init__(self, name, goal, fleet):
        self.name = name
        self.goal = goal
        self.truth = None
        self.track = {}  # stamp (ns) -> true (x, y)
        self.localized = False
        self.hits = []  # the objects of its collisions
        self.status = SimStatusWatch('/%s/minibot3d_sim/status' % name)
        self.client = actionlib.SimpleActionClient('/%s/move_base' % name, MoveBaseAction)
        self.done_at = None
        rospy.Subscriber('/%s/ground_truth/odom' % name, Odometry,
                         lambda m: fleet.on_truth(self, m), queue_size=10)
        rospy.Subscriber('/%s/amcl_pose' % name, PoseWithCovarianceStamped,
                         lambda m: setattr(self, 'localized', True), queue_size=5)
        rospy.Subscriber('/%s/minibot3d_sim/collisions' % name, Collision,
                         lambda m: self.hits.append(m.object), queue_size=10)

    def robot_hits(self):
        return sum(1 for o in self.hits if o.startswith('robot '))

    def wall_hits(self):
        return len(self.hits) - self.robot_hits()


class FleetSwap(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('fleet_swap')
        n = int(rospy.get_param('~robots'))
        names = rospy.get_param('~names', 'none')
        names = (['robot%d' % (k + 1) for k in range(n)] if names == 'none' else names.split())
        if len(names) != n:
            raise ValueError('~names %s: %d names for %d robots' % (' '.join(names), len(names), n))
        goals = load_goals(rospy.get_param('~goals_file'), rospy.get_param('~scenario'), n)
        cls.lock = threading.Lock()
        cls.robots = [Robot(names[k], goals[k], cls) for k in range(n)]
        wake = ['/%s/move_base/result' % r.name for r in cls.robots] + \
            ['/%s/amcl_pose' % r.name for r in cls.robots]
        cls.lockstep = Participant(wake_topics=wake)
        cls.lockstep.add_periodic(0.05, lambda now: None)
        cls.checks = RunChecks()
        for r in cls.robots:
            assert cls.lockstep.wait_for(lambda: action_server_ready(r.client), 120.0), \
                'no move_base action server for ' + r.name
            assert cls.lockstep.wait_for(lambda: r.truth is not None, 60.0), \
                'no ground truth for ' + r.name
            assert cls.lockstep.wait_for(lambda: r.localized, 60.0), \
                'no amcl_pose from %s: its amcl gets no scan or no odom -> base tf' % r.name

    @classmethod
    def on_truth(cls, robot, m):
        p = m.pose.pose
        with cls.lock:
            robot.truth = (p.position.x, p.position.y, yaw_of(p.orientation))
            robot.track[m.header.stamp.to_nsec()] = (p.position.x, p.position.y)

    @classmethod
    def closest_approach(cls):
        """(distance, name, name, t) of the two robots closest together at one stamp of their
        ground truth (the simulator stamps every robot's alike), so that the figure does not
        depend on the order in which the robots' messages arrived."""
        with cls.lock:
            tracks = [(r.name, dict(r.track)) for r in cls.robots]
        best = (float('inf'), '', '', 0.0)
        for i, (a, ta) in enumerate(tracks):
            for b, tb in tracks[i + 1:]:
                for stamp in ta.keys() & tb.keys():
                    d = math.hypot(ta[stamp][0] - tb[stamp][0], ta[stamp][1] - tb[stamp][1])
                    if d < best[0]:
                        best = (d, a, b, stamp * 1e-9)
        return best

    def test_1_swap(self):
        start = rospy.get_rostime()
        wall_start = time.monotonic()
        for r in self.robots:
            x, y, yaw, _ = r.goal
            goal = MoveBaseGoal()
            goal.target_pose.header.frame_id = 'map'
            goal.target_pose.header.stamp = start
            goal.target_pose.pose.position.x = x
            goal.target_pose.pose.position.y = y
            goal.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
            goal.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
            r.client.send_goal(goal)

        def all_done():
            for r in self.robots:
                if r.done_at is None and r.client.simple_state == actionlib.SimpleGoalState.DONE:
                    r.done_at = (rospy.get_rostime() - start).to_sec()
            return all(r.done_at is not None for r in self.robots)
        self.lockstep.wait_for(all_done, max(r.goal[3] for r in self.robots))
        all_done()
        sim_span = (rospy.get_rostime() - start).to_sec()
        wall_span = time.monotonic() - wall_start
        print('fleet_swap: %d robots, %.2f s of sim time in %.2f s wall: %.1fx real time' % (
            len(self.robots), sim_span, wall_span, sim_span / wall_span if wall_span > 0 else 0.0),
            flush=True)
        for r in self.robots:
            if r.done_at is None:
                r.client.cancel_goal()
        problems = self.status_problems = []
        for r in self.robots:
            x, y, yaw, limit = r.goal
            px, py, pyaw = r.truth
            state = r.client.get_state()
            reached = (r.done_at is not None and r.done_at <= limit and
                       state == GoalStatus.SUCCEEDED and
                       math.hypot(px - x, py - y) < POSITION_TOLERANCE and
                       heading_error(pyaw, yaw) < HEADING_TOLERANCE)
            print('fleet_swap: %s: goal (%.2f, %.2f, %.2f) %s, %s after %s s of sim time (limit '
                  '%g s), true (%.2f, %.2f, %.2f); collisions: %d with walls, %d with robots' % (
                      r.name, x, y, yaw, 'reached' if reached else 'NOT reached',
                      GoalStatus.to_string(state) if r.done_at is not None else 'no result',
                      '%.2f' % r.done_at if r.done_at is not None else '-', limit, px, py, pyaw,
                      r.wall_hits(), r.robot_hits()), flush=True)
            if not reached:
                problems.append('%s did not reach (%.2f, %.2f, %.2f) within %g s: %s, at true '
                                '(%.2f, %.2f, %.2f)' % (
                                    r.name, x, y, yaw, limit, GoalStatus.to_string(state), px, py,
                                    pyaw))
        print('fleet_swap: min distance between robots %.3f m (%s and %s at t=%.3f s)' %
              self.closest_approach(), flush=True)
        self.assertEqual([], problems)

    def test_2_no_collisions(self):
        end = rospy.get_rostime()
        problems = []
        for r in self.robots:
            problems += ['%s: %s' % (r.name, p) for p in r.status.problems_at_end(self.lockstep,
                                                                                  end=end)]
            if r.hits:
                problems.append('%s collided with %s' % (r.name, ', '.join(r.hits)))
        self.assertEqual([], problems)

    def test_3_run_checks(self):
        self.assertEqual([], self.checks.problems())


if __name__ == '__main__':
    rostest.rosrun('minibot3d_navigation', 'fleet_swap', FleetSwap)
