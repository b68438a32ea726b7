#!/usr/bin/env python3
"""Drives the simulated robot through a list of waypoints, for tests and benchmarks that need the
robot to move along a long route without a navigation stack: paths between waypoints are planned
with A* on the world's ground-truth map (inflated by --clearance) and followed by pure pursuit on
/ground_truth/odom. It is test equipment: it sees the true pose, which a robot never does.

  route_driver.py --map MAP.yaml --waypoints "x1,y1 x2,y2 ..." [--speed 0.3] [--laps 1]
                  [--clearance 0.3] [--timeout 600] [--record FILE]

--record writes the true trajectory ("time x y theta" per line, sim time) atomically at the end.
Exits 0 when every waypoint was reached, 1 on timeout, 2 on bad arguments or an unreachable
waypoint (named). Under lock-step time (/use_lockstep) it is a participant: it steers every
0.05 s of sim time and sim time waits for it."""
import argparse
import heapq
import math
import sys
import threading
import time

import numpy as np
from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages
from minibot3d_map_io import MapIoError, load_map, write_atomically

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry


def inflate(occupied, cells):
    out = occupied.copy()
    for dy in range(-cells, cells + 1):
        for dx in range(-cells, cells + 1):
            if dx * dx + dy * dy > cells * cells:
                continue
            shifted = np.zeros_like(occupied)
            ys = slice(max(dy, 0), occupied.shape[0] + min(dy, 0))
            yd = slice(max(-dy, 0), occupied.shape[0] + min(-dy, 0))
            xs = slice(max(dx, 0), occupied.shape[1] + min(dx, 0))
            xd = slice(max(-dx, 0), occupied.shape[1] + min(-dx, 0))
            shifted[yd, xd] = occupied[ys, xs]
            out |= shifted
    return out


def astar(blocked, start, goal):
    """8-connected A* on a grid; returns the list of cells from start to goal, or None."""
    h, w = blocked.shape
    if blocked[start] or blocked[goal]:
        return None
    dist = {start: 0.0}
    came = {}
    heap = [(0.0, start)]
    moves = [(dy, dx, math.hypot(dx, dy)) for dy in (-1, 0, 1) for dx in (-1, 0, 1)
             if dx or dy]
    while heap:
        _, cur = heapq.heappop(heap)
        if cur == goal:
            path = [cur]
            while cur in came:
                cur = came[cur]
                path.append(cur)
            return path[::-1]
        d = dist[cur]
        for dy, dx, c in moves:
            n = (cur[0] + dy, cur[1] + dx)
            if not (0 <= n[0] < h and 0 <= n[1] < w) or blocked[n]:
                continue
            nd = d + c
            if nd < dist.get(n, float('inf')):
                dist[n] = nd
                came[n] = cur
                heapq.heappush(heap, (nd + math.hypot(goal[0] - n[0], goal[1] - n[1]), n))
    return None


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--map', required=True)
    parser.add_argument('--waypoints', required=True, help='"x1,y1 x2,y2 ..." (map/world frame)')
    parser.add_argument('--speed', type=float, default=0.3)
    parser.add_argument('--laps', type=int, default=1)
    parser.add_argument('--clearance', type=float, default=0.3)
    parser.add_argument('--timeout', type=float, default=600.0, help='wall seconds')
    parser.add_argument('--record', default='')
    args = parser.parse_args(rospy.myargv()[1:])
    try:
        waypoints = [tuple(float(v) for v in p.split(',')) for p in args.waypoints.split()]
        assert all(len(p) == 2 for p in waypoints) and waypoints
    except (ValueError, AssertionError):
        parser.error('--waypoints must be "x1,y1 x2,y2 ...", got %r' % args.waypoints)
    try:
        grid = load_map(args.map)
    except MapIoError as e:
        parser.error(str(e))
    occupied, res, origin = grid.occupied, grid.resolution, grid.origin
    blocked = inflate(occupied, int(math.ceil(args.clearance / res)))

    def cell(x, y):
        return (int((y - origin[1]) / res), int((x - origin[0]) / res))

    rospy.init_node('route_driver')
    lock = threading.Condition()
    state = {'pose': None, 'trail': []}

    def on_truth(msg):
        p = msg.pose.pose
        pose = (p.position.x, p.position.y, yaw_of(p.orientation))
        with lock:
            state['pose'] = pose
            state['trail'].append((msg.header.stamp.to_sec(),) + pose)
            lock.notify_all()

    rospy.Subscriber('ground_truth/odom', Odometry, on_truth, queue_size=50)
    pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
    lockstep = Participant()
    try:
        return drive(args, waypoints, blocked, cell, origin, res, lock, state, pub, lockstep)
    finally:
        pub.publish(Twist())
        lockstep.close()


def drive(args, waypoints, blocked, cell, origin, res, lock, state, pub, lockstep):
    deadline = time.time() + args.timeout
    if not lockstep.wait_for(lambda: state['pose'] is not None, 60.0):
        rospy.logerr('route_driver: no /ground_truth/odom')
        return 1
    # Commands before the simulator listens are lost.
    if not lockstep.wait_for(lambda: pub.get_num_connections() > 0, 60.0):
        rospy.logerr('route_driver: nothing subscribes to cmd_vel')
        return 1

    route = waypoints * args.laps
    for index, goal in enumerate(route):
        with lock:
            x, y, _ = state['pose']
        cells = astar(blocked, cell(x, y), cell(*goal))
        if cells is None:
            rospy.logerr('route_driver: waypoint %d (%.2f, %.2f) is unreachable from (%.2f, %.2f) '
                         'with %.2f m clearance', index, goal[0], goal[1], x, y, args.clearance)
            pub.publish(Twist())
            return 2
        path = [(origin[0] + (c[1] + 0.5) * res, origin[1] + (c[0] + 0.5) * res) for c in cells]
        path[-1] = goal
        k = 0
        while not rospy.is_shutdown():
            if time.time() > deadline:
                rospy.logerr('route_driver: timed out before waypoint %d', index)
                pub.publish(Twist())
                return 1
            with lock:
                x, y, th = state['pose']
            if math.hypot(goal[0] - x, goal[1] - y) < 0.08:
                break
            # Pure pursuit: the first path point at least 0.25 m ahead.
            while k < len(path) - 1 and math.hypot(path[k][0] - x, path[k][1] - y) < 0.25:
                k += 1
            tx, ty = path[k]
            err = math.atan2(ty - y, tx - x) - th
            err = math.atan2(math.sin(err), math.cos(err))
            cmd = Twist()
            if abs(err) > 0.6:
                cmd.angular.z = math.copysign(1.0, err)
            else:
                cmd.linear.x = args.speed * max(0.2, math.cos(err))
                cmd.angular.z = 2.5 * err
            pub.publish(cmd)
            lockstep.sleep(0.05)
    pub.publish(Twist())
    if args.record:
        with lock:
            trail = list(state['trail'])
        write_atomically(args.record,
                         ''.join('%.6f %.6f %.6f %.6f\n' % (t, x, y, th) for t, x, y, th in trail))
    length = sum(math.hypot(b[1] - a[1], b[2] - a[2])
                 for a, b in zip(state['trail'], state['trail'][1:]))
    print('route_driver: %d waypoints reached, %.1f m driven' % (len(route), length))
    return 0


if __name__ == '__main__':
    sys.exit(main())
