#!/usr/bin/env python3
"""move_base benchmark in the simulator (part of make bench; needs amcl_navigation.launch running):
N random reachable goals in the map (fixed seed), sent one after the other with actionlib.

A goal is a random free cell at least --clearance metres from any occupied cell, with a random
heading; it counts as reachable when move_base's ~make_plan returns a path to it from where the
robot is.  For each goal: the result, the sim time it took, the planned path length, the final
true position error (/ground_truth/odom) and the simulator's collision count.  The summary is
what the issue asks for: % reached, collisions, and mean time-to-goal over
(path length / max_vel_x)."""
import argparse
import importlib.util
import math
import os
import random
import sys
import threading

import actionlib
import numpy as np
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from minibot3d_map_io import load_map
from minibot3d_sim.msg import SimStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry
from nav_msgs.srv import GetPlan

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def load_route_driver():
    path = os.path.join(ROOT, 'minibot3d_sim', 'scripts', 'route_driver.py')
    spec = importlib.util.spec_from_file_location('route_driver', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def pose_stamped(x, y, yaw, frame='map'):
    p = PoseStamped()
    p.header.frame_id = frame
    p.pose.position.x = x
    p.pose.position.y = y
    p.pose.orientation.z = math.sin(yaw / 2.0)
    p.pose.orientation.w = math.cos(yaw / 2.0)
    return p


class Truth(object):
    def __init__(self):
        self.lock = threading.Lock()
        self.pose = None
        self.collisions = 0
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_odom, queue_size=5)
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, self.on_status, queue_size=5)

    def on_odom(self, m):
        with self.lock:
            self.pose = (m.pose.pose.position.x, m.pose.pose.position.y)

    def on_status(self, m):
        with self.lock:
            self.collisions = m.collisions


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--map', required=True, help='map_server YAML of the world')
    parser.add_argument('--goals', type=int, default=20)
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--clearance', type=float, default=0.35)
    parser.add_argument('--timeout', type=float, default=300.0, help='sim seconds per goal')
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node('nav_bench')

    grid = load_map(args.map)
    occupied, res, origin = grid.occupied, grid.resolution, grid.origin
    blocked = load_route_driver().inflate(occupied, int(math.ceil(args.clearance / res)))
    free = np.argwhere(~blocked)  # (row, col), row 0 = lowest y
    rng = random.Random(args.seed)

    truth = Truth()
    client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
    if not client.wait_for_server(rospy.Duration(120.0)):
        sys.exit('nav_bench: no move_base action server')
    rospy.wait_for_service('/move_base/make_plan', 60.0)
    make_plan = rospy.ServiceProxy('/move_base/make_plan', GetPlan)
    max_vel = rospy.get_param('/move_base/TrajectoryPlannerROS/max_vel_x', 0.5)
    while truth.pose is None and not rospy.is_shutdown():
        rospy.sleep(0.1)

    rows = []
    tries = 0
    while len(rows) < args.goals and tries < 50 * args.goals and not rospy.is_shutdown():
        tries += 1
        r, c = free[rng.randrange(len(free))]
        x = origin[0] + (c + 0.5) * res
        y = origin[1] + (r + 0.5) * res
        yaw = rng.uniform(-math.pi, math.pi)
        try:
            plan = make_plan(PoseStamped(), pose_stamped(x, y, yaw), 0.0).plan
        except rospy.ServiceException as e:
            rospy.logwarn('make_plan failed: %s', e)
            continue
        if len(plan.poses) < 2:
            continue  # unreachable (outside the walls, enclosed): draw another
        length = sum(math.hypot(b.pose.position.x - a.pose.position.x,
                                b.pose.position.y - a.pose.position.y)
                     for a, b in zip(plan.poses, plan.poses[1:]))
        goal = MoveBaseGoal()
        goal.target_pose = pose_stamped(x, y, yaw)
        before = truth.collisions
        t0 = rospy.Time.now()
        goal.target_pose.header.stamp = t0
        client.send_goal(goal)
        done = client.wait_for_result(rospy.Duration(args.timeout))
        elapsed = (rospy.Time.now() - t0).to_sec()
        if not done:
            client.cancel_goal()
            client.wait_for_result(rospy.Duration(10.0))
        state = client.get_state()
        px, py = truth.pose
        row = dict(i=len(rows) + 1, x=x, y=y, length=length, time=elapsed,
                   ok=done and state == GoalStatus.SUCCEEDED,
                   error=math.hypot(px - x, py - y), collisions=truth.collisions - before,
                   text=client.get_goal_status_text() if state != GoalStatus.SUCCEEDED else '')
        rows.append(row)
        print('goal %2d (%5.2f, %5.2f): %-9s %6.1f s  path %5.2f m  ratio %.2f  err %.2f m  '
              'collisions %d %s' % (row['i'], x, y, 'reached' if row['ok'] else 'FAILED',
                                   elapsed, length, elapsed / max(length / max_vel, 1e-6),
                                   row['error'], row['collisions'], row['text'][:100]),
              flush=True)
    reached = [r for r in rows if r['ok']]
    ratios = [r['time'] / (r['length'] / max_vel) for r in reached if r['length'] > 0.05]
    mean_time = np.mean([r['time'] for r in reached]) if reached else float('nan')
    mean_ideal = np.mean([r['length'] / max_vel for r in reached]) if reached else float('nan')
    print('goals %d, reached %d (%.0f %%), collisions %d; mean time-to-goal %.1f s vs mean path '
          'length / max_vel_x (%.2f) %.1f s: %.2fx (target <= 1.5x); mean of the per-goal '
          'ratios %.2f' % (
              len(rows), len(reached), 100.0 * len(reached) / max(len(rows), 1),
              sum(r['collisions'] for r in rows), mean_time, max_vel, mean_ideal,
              mean_time / mean_ideal, np.mean(ratios) if ratios else float('nan')))
    return 0 if rows and len(reached) == len(rows) else 1


if __name__ == '__main__':
    sys.exit(main())
