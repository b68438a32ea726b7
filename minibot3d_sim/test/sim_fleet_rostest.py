#!/usr/bin/env python3
"""rostest: two robots in one simulator (sim_fleet.test). Each robot's topics are under its name
and its frames carry its name as a prefix on the one /tf (r1's laser scan in frame r1/laser, r2's
in r2/base_scan; r1/odom -> r1/base_footprint and r2's likewise, each robot's links through its own
robot_state_publisher); each has its ground truth in the world frame; r1's laser sees r2's body
ahead where r2 stands; r1 driven into r2 stops short of it and both report the collision, naming
each other, on their own collision topics.
A subscriber that connects late gets both robots' fixed joints in the latched /tf_static.
Catches: frames without the prefix, a laser blind to the other robot, robots passing through each
other or a collision reported on one side only."""
import math
import threading
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Twist
from minibot3d_sim.msg import Collision
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from tf2_msgs.msg import TFMessage


class Latest(object):
    """The latest message of a topic, and every message kept."""

    def __init__(self, topic, msg_type):
        self.cond = threading.Condition()
        self.msgs = []
        rospy.Subscriber(topic, msg_type, self.on_msg, queue_size=100)

    def on_msg(self, m):
        with self.cond:
            self.msgs.append(m)
            self.cond.notify_all()

    def wait(self, predicate, timeout):
        with self.cond:
            return self.cond.wait_for(lambda: predicate(self.msgs), timeout=timeout)


class SimFleet(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('sim_fleet_test')
        cls.scan1 = Latest('/r1/scan', LaserScan)
        cls.scan2 = Latest('/r2/scan', LaserScan)
        cls.truth1 = Latest('/r1/ground_truth/odom', Odometry)
        cls.truth2 = Latest('/r2/ground_truth/odom', Odometry)
        cls.hit1 = Latest('/r1/minibot3d_sim/collisions', Collision)
        cls.hit2 = Latest('/r2/minibot3d_sim/collisions', Collision)
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)

    def test_1_topics_and_frames_carry_the_robots_names(self):
        self.assertTrue(self.scan1.wait(bool, 60.0), 'no scan on /r1/scan')
        self.assertTrue(self.scan2.wait(bool, 60.0), 'no scan on /r2/scan')
        self.assertEqual(self.scan1.msgs[-1].header.frame_id, 'r1/laser')
        self.assertEqual(self.scan2.msgs[-1].header.frame_id, 'r2/base_scan')
        self.assertTrue(self.truth1.wait(bool, 60.0))
        self.assertEqual(self.truth1.msgs[-1].header.frame_id, 'world')
        self.assertEqual(self.truth1.msgs[-1].child_frame_id, 'r1/base_footprint')
        for a, b in (('r1/odom', 'r1/laser'), ('r2/odom', 'r2/base_scan'),
                     ('r2/base_footprint', 'r2/camera_optical_frame')):
            ok = False
            deadline = rospy.Time.now() + rospy.Duration(30.0)
            while not ok and rospy.Time.now() < deadline and not rospy.is_shutdown():
                ok = self.tf_buffer.can_transform(a, b, rospy.Time(0), rospy.Duration(1.0))
            self.assertTrue(ok, 'no transform %s -> %s' % (a, b))

    def test_1b_a_late_subscriber_gets_every_robots_fixed_joints(self):
        """/tf_static is latched: a subscriber that connects after the simulator published it
        gets its last message only, which must hold the fixed joints of both robots (catches one
        message per robot, which leaves a late subscriber with the last robot's joints only)."""
        self.assertTrue(self.scan1.wait(bool, 60.0), 'no scan on /r1/scan')  # published by now
        from_sim = Latest('/tf_static', TFMessage)
        self.assertTrue(from_sim.wait(lambda ms: any(
            m._connection_header['callerid'] == '/minibot3d_sim' for m in ms), 30.0),
            'no latched /tf_static from /minibot3d_sim')
        msgs = [m for m in from_sim.msgs if m._connection_header['callerid'] == '/minibot3d_sim']
        children = {t.child_frame_id for t in msgs[0].transforms}
        self.assertIn('r1/laser', children)
        self.assertIn('r2/base_scan', children)

    def test_2_a_laser_sees_the_other_robot(self):
        self.assertTrue(self.truth2.wait(bool, 60.0))
        self.assertTrue(self.scan1.wait(bool, 60.0))
        p1 = self.truth1.msgs[-1].pose.pose.position
        p2 = self.truth2.msgs[-1].pose.pose.position
        scan = self.scan1.msgs[-1]
        # r1's laser (0.02 m ahead of its root, turned round) passes over r2's body
        # (0.11 m high) and meets r2's own laser housing: a cylinder of radius 0.035 m, 0.03 m
        # behind r2's centre, i.e. 0.03 m further from r1 since r2 faces r1.
        laser = (p1.x + 0.02, p1.y)
        expected = math.hypot(p2.x - laser[0], p2.y - laser[1]) + 0.03 - 0.035
        # The beam pointing at r2: r1 faces +x, its laser yaw is pi.
        k = int(round((0.0 - math.pi - scan.angle_min) / scan.angle_increment)) % len(scan.ranges)
        self.assertAlmostEqual(scan.ranges[k], expected, delta=0.03,
                               msg='beam %d reads %.3f m, r2 is at %.3f m' % (
                                   k, scan.ranges[k], expected))

    def test_3_robots_stop_each_other_and_both_report_it(self):
        pub = rospy.Publisher('/r1/cmd_vel', Twist, queue_size=1)
        cmd = Twist()
        cmd.linear.x = 0.3
        rate = rospy.Rate(20)
        deadline = rospy.Time.now() + rospy.Duration(10.0)
        while not self.hit1.msgs and rospy.Time.now() < deadline and not rospy.is_shutdown():
            pub.publish(cmd)
            rate.sleep()
        self.assertTrue(self.hit1.wait(bool, 5.0), 'r1 reported no collision')
        self.assertTrue(self.hit2.wait(bool, 5.0), 'r2 reported no collision')
        self.assertEqual(self.hit1.msgs[0].object, 'robot r2')
        self.assertEqual(self.hit2.msgs[0].object, 'robot r1')
        p1 = self.truth1.msgs[-1].pose.pose.position
        p2 = self.truth2.msgs[-1].pose.pose.position
        # Front of r1 (0.12 m ahead) meets r2's back (0.13 m behind it): never closer.
        self.assertGreaterEqual(p2.x - p1.x, 0.12 + 0.13 - 0.01)
        self.assertAlmostEqual(p2.x, -1.8, places=6)  # r2 is not pushed


if __name__ == '__main__':
    rostest.rosrun('minibot3d_sim', 'sim_fleet', SimFleet)
