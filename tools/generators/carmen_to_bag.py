#!/usr/bin/python3
"""Converts a CARMEN log's FLASER messages to a ROS bag, to run slam_offline's bag reader on a real log.

    tools/generators/carmen_to_bag.py IN.clf OUT.bag [--no-return 81.83]

Each FLASER becomes a sensor_msgs/LaserScan on /scan (frame 'laser', 180° from -90°, as the CARMEN
reader lays the beams out; readings at or above --no-return become +inf) and a transform
odom → base_footprint on /tf at the same stamp with the message's odometry fields; ODOM lines
add odom → base_footprint transforms in between. base_footprint → laser is an identity on
/tf_static. Stamps and bag times are the ipc_timestamps. Readings go through float32 as in any bag,
so a run on the bag is close to, not bit-identical with, a run on the log.
"""
import argparse
import math
import sys

import rosbag
import rospy
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage


def transform(parent, child, stamp, x, y, yaw):
    t = TransformStamped()
    t.header.stamp = stamp
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x = x
    t.transform.translation.y = y
    t.transform.rotation.z = math.sin(yaw / 2)
    t.transform.rotation.w = math.cos(yaw / 2)
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("log")
    ap.add_argument("bag")
    ap.add_argument("--no-return", type=float, default=81.83)
    a = ap.parse_args()
    first = True
    scans = 0
    with open(a.log) as f, rosbag.Bag(a.bag, "w") as bag:
        for number, line in enumerate(f, 1):
            fields = line.split()
            if not fields or fields[0] not in ("FLASER", "ODOM"):
                continue
            try:
                stamp = rospy.Time.from_sec(float(fields[-3]))
                if fields[0] == "ODOM":
                    x, y, th = map(float, fields[1:4])
                else:
                    n = int(fields[1])
                    ranges = [float(r) for r in fields[2:2 + n]]
                    x, y, th = map(float, fields[2 + n + 3:2 + n + 6])
            except (ValueError, IndexError):
                sys.exit(f"{a.log}:{number}: malformed {fields[0]} line")
            if first:
                bag.write("/tf_static", TFMessage([transform("base_footprint", "laser", stamp, 0, 0, 0)]), stamp)
                first = False
            bag.write("/tf", TFMessage([transform("odom", "base_footprint", stamp, x, y, th)]), stamp)
            if fields[0] == "FLASER":
                s = LaserScan()
                s.header.stamp = stamp
                s.header.frame_id = "laser"
                step = math.pi / (n - 1) if n % 2 == 1 else math.pi / n
                s.angle_min = -math.pi / 2
                s.angle_increment = step
                s.angle_max = s.angle_min + (n - 1) * step
                s.range_min = 0.0
                s.range_max = a.no_return
                s.ranges = [r if r < a.no_return else math.inf for r in ranges]
                bag.write("/scan", s, stamp)
                scans += 1
    print(f"{a.bag}: {scans} scans")


if __name__ == "__main__":
    main()
