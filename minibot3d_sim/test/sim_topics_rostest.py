#!/usr/bin/env python3
"""rostest: what the simulator publishes — scans at the sensor's rate in sim time, odometry, the tf
chain odom → base_footprint → base_link → laser, and an advancing /clock."""
import math
import sys
import threading
import unittest

import rospy
import rostest
import tf2_ros
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan


class Collector(object):
    """Keeps messages of one topic and lets a test wait for a condition on them."""

    def __init__(self, topic, msg_type):
        self.msgs = []
        self.cond = threading.Condition()
        self.sub = rospy.Subscriber(topic, msg_type, self.on_msg, queue_size=100)

    def on_msg(self, msg):
        with self.cond:
            self.msgs.append(msg)
            self.cond.notify_all()

    def wait_for(self, predicate, wall_timeout):
        with self.cond:
            return self.cond.wait_for(lambda: predicate(self.msgs), timeout=wall_timeout)


class SimTopics(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('sim_topics_test')

    def test_scan_rate_frame_and_beams(self):
        scans = Collector('/scan', LaserScan)
        self.assertTrue(scans.wait_for(lambda m: len(m) >= 31, 60.0), 'fewer than 31 scans')
        msgs = list(scans.msgs)
        scans.sub.unregister()
        first, last = msgs[0], msgs[-1]
        for m in msgs:
            self.assertEqual(m.header.frame_id, 'laser')
            self.assertEqual(len(m.ranges), 360)
        self.assertAlmostEqual(first.angle_min, -math.pi, places=4)
        self.assertAlmostEqual(first.angle_increment, (first.angle_max - first.angle_min) / 359,
                               places=6)
        self.assertAlmostEqual(first.scan_time, 0.1, places=6)
        self.assertAlmostEqual(first.range_min, 0.15, places=6)
        self.assertAlmostEqual(first.range_max, 12.0, places=6)
        span = (last.header.stamp - first.header.stamp).to_sec()
        rate = (len(msgs) - 1) / span
        self.assertTrue(9.0 <= rate <= 11.0, 'scan rate %.2f Hz of sim time' % rate)
        # Indoors every beam but a few sees something: finite ranges within the limits, and any
        # no-return is +inf (REP 117), never 0 or range_max.
        finite = [r for r in last.ranges if math.isfinite(r)]
        self.assertGreater(len(finite), 300)
        for r in finite:
            self.assertTrue(0.15 <= r <= 12.0, r)
        for r in last.ranges:
            self.assertFalse(r == 0.0)

    def test_odometry_and_tf_chain(self):
        odom = Collector('/odom', Odometry)
        self.assertTrue(odom.wait_for(lambda m: len(m) >= 5, 60.0), 'no /odom')
        m = odom.msgs[-1]
        self.assertEqual(m.header.frame_id, 'odom')
        self.assertEqual(m.child_frame_id, 'base_footprint')
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        t = buf.lookup_transform('odom', 'laser', rospy.Time(0), rospy.Duration(30.0))
        # At rest at the start: the laser is 0.02 m ahead and 0.095 m up, facing backwards.
        self.assertAlmostEqual(t.transform.translation.x, 0.02, delta=0.01)
        self.assertAlmostEqual(t.transform.translation.z, 0.095, places=3)
        buf.lookup_transform('base_footprint', 'base_link', rospy.Time(0), rospy.Duration(10.0))
        for wheel in ('front_left_wheel', 'rear_right_wheel'):
            buf.lookup_transform('base_link', wheel, rospy.Time(0), rospy.Duration(10.0))

    def test_clock_advances(self):
        clock = Collector('/clock', Clock)
        self.assertTrue(clock.wait_for(lambda m: len(m) >= 2 and
                                       (m[-1].clock - m[0].clock).to_sec() >= 1.0, 60.0),
                        '/clock did not advance by 1 s')
        stamps = [c.clock.to_sec() for c in clock.msgs]
        self.assertEqual(stamps, sorted(stamps), '/clock went backwards')


if __name__ == '__main__':
    rostest.rosrun('minibot3d_sim', 'sim_topics', SimTopics, sys.argv)
