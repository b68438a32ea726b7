#!/usr/bin/env python3
"""Drives the simulated robot around a square through cmd_vel, closed-loop on /odom as a real robot
would (it cannot see the truth), then prints what happened: the true path length from
/ground_truth/odom, the odometry drift (odometry vs truth at the end), collisions, and the achieved
real-time factor (sim seconds per wall second).

  rosrun minibot3d_sim drive_square.py [--side 1.0] [--laps 1] [--speed 0.3] [--timeout 300]

Exits 0 when the square was driven, 1 on timeout or when the simulator never answered.
"""
import argparse
import math
import sys
import time

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from minibot3d_sim.msg import SimStatus


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


class Square(object):
    def __init__(self, args):
        self.args = args
        self.odom = None
        self.truth = None
        self.truth_start = None
        self.path = 0.0
        self.status = None
        self.pub = rospy.Publisher('cmd_vel', Twist, queue_size=1)
        rospy.Subscriber('odom', Odometry, self.on_odom, queue_size=1)
        rospy.Subscriber('ground_truth/odom', Odometry, self.on_truth, queue_size=10)
        rospy.Subscriber('minibot3d_sim/status', SimStatus, self.on_status, queue_size=1)

    def on_odom(self, msg):
        p = msg.pose.pose
        self.odom = (p.position.x, p.position.y, yaw_of(p.orientation))

    def on_truth(self, msg):
        p = msg.pose.pose
        pose = (p.position.x, p.position.y, yaw_of(p.orientation))
        if self.truth is not None:
            self.path += math.hypot(pose[0] - self.truth[0], pose[1] - self.truth[1])
        else:
            self.truth_start = pose
        self.truth = pose

    def on_status(self, msg):
        self.status = msg

    def run(self):
        a = self.args
        deadline = time.time() + a.timeout
        while self.odom is None or self.truth is None:
            if time.time() > deadline or rospy.is_shutdown():
                rospy.logerr('drive_square: no /odom or /ground_truth/odom from the simulator')
                return 1
            time.sleep(0.05)
        wall0, sim0 = time.time(), rospy.get_time()
        x0, y0, th0 = self.odom
        corners = []
        for _ in range(a.laps):
            for (cx, cy) in ((a.side, 0.0), (a.side, a.side), (0.0, a.side), (0.0, 0.0)):
                corners.append((x0 + math.cos(th0) * cx - math.sin(th0) * cy,
                                y0 + math.sin(th0) * cx + math.cos(th0) * cy))
        rate = rospy.Rate(20)  # sim time
        cmd = Twist()
        for (gx, gy) in corners:
            while not rospy.is_shutdown():
                if time.time() > deadline:
                    rospy.logerr('drive_square: timed out after %.0f s wall', a.timeout)
                    self.pub.publish(Twist())
                    return 1
                x, y, th = self.odom
                dist = math.hypot(gx - x, gy - y)
                if dist < 0.03:
                    break
                err = wrap(math.atan2(gy - y, gx - x) - th)
                if abs(err) > 0.25:
                    cmd.linear.x, cmd.angular.z = 0.0, math.copysign(1.2, err)
                else:
                    cmd.linear.x, cmd.angular.z = min(a.speed, dist), 3.0 * err
                self.pub.publish(cmd)
                rate.sleep()
        self.pub.publish(Twist())
        sim_s, wall_s = rospy.get_time() - sim0, time.time() - wall0
        ox, oy, oth = self.odom
        tx, ty, tth = self.truth
        sx, sy, sth = self.truth_start
        # Odometry starts at the spawn pose's origin: express the truth relative to the spawn.
        c, s = math.cos(sth), math.sin(sth)
        rx, ry = c * (tx - sx) + s * (ty - sy), -s * (tx - sx) + c * (ty - sy)
        drift = math.hypot(ox - rx, oy - ry)
        collisions = self.status.collisions if self.status else float('nan')
        print('drive_square: side %.2f m x %d laps: true path %.2f m, odometry drift %.3f m '
              '(yaw %.1f deg), collisions %s, %.1f s sim in %.1f s wall, real-time factor %.1f'
              % (a.side, a.laps, self.path, drift, math.degrees(abs(wrap(oth - (tth - sth)))),
                 collisions, sim_s, wall_s, sim_s / wall_s if wall_s > 0 else float('nan')))
        return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--side', type=float, default=1.0)
    parser.add_argument('--laps', type=int, default=1)
    parser.add_argument('--speed', type=float, default=0.3)
    parser.add_argument('--timeout', type=float, default=300.0, help='wall seconds')
    args = parser.parse_args(rospy.myargv()[1:])
    if args.side <= 0 or args.laps < 1 or args.speed <= 0:
        parser.error('--side and --speed must be > 0 and --laps >= 1')
    rospy.init_node('drive_square')
    return Square(args).run()


if __name__ == '__main__':
    sys.exit(main())
