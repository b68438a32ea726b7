#!/usr/bin/env python3
"""rostest: the frames of the robot appear in tf with the geometry of the URDF."""
import math
import sys
import unittest

import rospy
import rostest
import tf2_ros


class ViewMobileRobotTf(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('view_mobile_robot_tf_test')
        cls.buffer = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.buffer)

    def lookup(self, target, source):
        # Waits on the condition (the transform being available), bounded by a timeout.
        return self.buffer.lookup_transform(target, source, rospy.Time(0), rospy.Duration(20.0))

    def test_chain_to_laser(self):
        t = self.lookup('base_footprint', 'base_link').transform.translation
        self.assertAlmostEqual(t.z, 0.04, places=6)
        laser = self.lookup('chassis', 'laser').transform
        self.assertAlmostEqual(laser.translation.x, 0.02, places=6)
        q = laser.rotation
        yaw = math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
        self.assertAlmostEqual(abs(yaw), math.pi, places=3)
        self.lookup('base_footprint', 'laser')

    def test_four_wheels(self):
        for fr in ('front', 'rear'):
            for lr in ('left', 'right'):
                t = self.lookup('base_link', '%s_%s_wheel' % (fr, lr)).transform.translation
                self.assertAlmostEqual(abs(t.y), 0.1, places=6)
                self.assertAlmostEqual(t.x, 0.075 if fr == 'front' else -0.075, places=6)


if __name__ == '__main__':
    rostest.rosrun('minibot3d_description', 'view_mobile_robot_tf', ViewMobileRobotTf, sys.argv)
