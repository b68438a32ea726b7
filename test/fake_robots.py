#!/usr/bin/env python3
"""Robots without a simulator, for test_fleet_robots_stacks.py: for each NAME given, what a
simulator publishes of a robot standing still at its odometry's origin, on the frames and topics
of robot NAME among several: /tf NAME/odom -> NAME/base_footprint, /tf_static NAME/base_footprint
-> NAME/base_link -> NAME/laser, and /NAME/scan from NAME/laser, every beam at 1 m (a ring of
obstacles round the robot). On wall time, at 20 Hz."""
import math
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from sensor_msgs.msg import LaserScan


def transform(parent, child, stamp, x=0.0, z=0.0):
    t = TransformStamped()
    t.header.stamp = stamp
    t.header.frame_id = parent
    t.child_frame_id = child
    t.transform.translation.x = x
    t.transform.translation.z = z
    t.transform.rotation.w = 1.0
    return t


def main():
    names = rospy.myargv(argv=sys.argv)[1:]
    rospy.init_node('fake_robots')
    static = tf2_ros.StaticTransformBroadcaster()
    now = rospy.Time.now()
    fixed = []
    for n in names:
        fixed += [transform(n + '/base_footprint', n + '/base_link', now, z=0.05),
                  transform(n + '/base_link', n + '/laser', now, x=0.05, z=0.1)]
    static.sendTransform(fixed)
    tf = tf2_ros.TransformBroadcaster()
    scans = {n: rospy.Publisher('/%s/scan' % n, LaserScan, queue_size=5) for n in names}
    rate = rospy.Rate(20)
    while not rospy.is_shutdown():
        stamp = rospy.Time.now()
        tf.sendTransform([transform(n + '/odom', n + '/base_footprint', stamp) for n in names])
        for n, pub in scans.items():
            s = LaserScan()
            s.header.stamp = stamp
            s.header.frame_id = n + '/laser'
            s.angle_min, s.angle_max = -math.pi, math.pi - 2 * math.pi / 360
            s.angle_increment = 2 * math.pi / 360
            s.range_min, s.range_max = 0.15, 12.0
            s.ranges = [1.0] * 360
            pub.publish(s)
        rate.sleep()


if __name__ == '__main__':
    try:
        main()
    except rospy.ROSInterruptException:
        pass
