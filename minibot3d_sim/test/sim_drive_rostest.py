#!/usr/bin/env python3
"""rostest: cmd_vel moves the robot the commanded distance; driving into a wall stops it and is
reported as a collision; reset brings it back to the spawn pose."""
import math
import sys
import threading
import unittest

import rospy
import rostest
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from std_srvs.srv import Empty

from minibot3d_sim.msg import Collision
from minibot3d_sim.srv import SetPose


class SimDrive(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('sim_drive_test')
        cls.lock = threading.Condition()
        cls.truth = None
        cls.collisions = []
        rospy.Subscriber('/ground_truth/odom', Odometry, cls.on_truth, queue_size=10)
        rospy.Subscriber('/minibot3d_sim/collisions', Collision, cls.on_collision, queue_size=10)
        cls.cmd = rospy.Publisher('/cmd_vel', Twist, queue_size=1)
        for srv in ('/minibot3d_sim/reset', '/minibot3d_sim/set_pose'):
            rospy.wait_for_service(srv, timeout=60.0)
        cls.reset = rospy.ServiceProxy('/minibot3d_sim/reset', Empty)
        cls.set_pose = rospy.ServiceProxy('/minibot3d_sim/set_pose', SetPose)
        with cls.lock:
            assert cls.lock.wait_for(lambda: cls.truth is not None, timeout=60.0)
        # Commands sent before the simulator is connected would be lost: wait for the connection.
        deadline = rospy.get_time() + 60.0
        while cls.cmd.get_num_connections() == 0:
            assert rospy.get_time() < deadline, 'the simulator never subscribed to /cmd_vel'
            rospy.rostime.wallsleep(0.01)

    @classmethod
    def on_truth(cls, msg):
        with cls.lock:
            cls.truth = msg
            cls.lock.notify_all()

    @classmethod
    def on_collision(cls, msg):
        with cls.lock:
            cls.collisions.append(msg)
            cls.lock.notify_all()

    def pose(self):
        """The true pose from a ground-truth message stamped after this call."""
        now = rospy.Time.now()
        with self.lock:
            ok = self.lock.wait_for(lambda: self.truth.header.stamp >= now, timeout=30.0)
            self.assertTrue(ok, 'no fresh /ground_truth/odom')
            p = self.truth.pose.pose
        yaw = 2.0 * math.atan2(p.orientation.z, p.orientation.w)
        return p.position.x, p.position.y, yaw

    def drive(self, v, w, sim_seconds):
        """Publishes (v, w) at 20 Hz of sim time for sim_seconds, then a stop."""
        cmd = Twist()
        cmd.linear.x, cmd.angular.z = v, w
        end = rospy.get_time() + sim_seconds
        rate = rospy.Rate(20)
        while rospy.get_time() < end and not rospy.is_shutdown():
            self.cmd.publish(cmd)
            rate.sleep()
        self.cmd.publish(Twist())

    def wait_until_stopped(self):
        rate = rospy.Rate(20)
        for _ in range(100):
            with self.lock:
                v = abs(self.truth.twist.twist.linear.x)
            if v < 0.01:
                return
            rate.sleep()
        self.fail('the robot did not stop')

    def test_1_commanded_distance(self):
        self.reset()
        x0, y0, _ = self.pose()
        self.drive(0.2, 0.0, 2.0)
        self.wait_until_stopped()
        x, y, yaw = self.pose()
        d = math.hypot(x - x0, y - y0)
        # 0.4 m commanded; the motors need a moment to spin up and the robot to stop.
        self.assertAlmostEqual(d, 0.4, delta=0.05)
        self.assertLess(abs(y - y0), 0.02)
        self.assertLess(abs(yaw), math.radians(3))

    def test_2_wall_stops_robot_and_is_reported(self):
        # Facing the east wall (inner face at x = 3) on a line clear of the arena's obstacles.
        res = self.set_pose(2.0, -1.0, 0.0)
        self.assertTrue(res.success, res.message)
        with self.lock:
            before = len(self.collisions)
        self.drive(0.5, 0.0, 4.0)
        with self.lock:
            got = self.lock.wait_for(lambda: len(self.collisions) > before, timeout=30.0)
            new = self.collisions[before:]
        self.assertTrue(got, 'no collision reported')
        self.assertIn('wall', new[0].object.lower())
        self.assertGreater(new[0].position.x, 2.9)
        x, _, _ = self.pose()
        self.assertLess(x, 3.0 - 0.12 + 0.01, 'the robot went into the wall')
        self.assertGreater(x, 2.7)
        refused = self.set_pose(2.95, 0.0, 0.0)
        self.assertFalse(refused.success)
        self.assertIn('overlaps', refused.message)

    def test_3_reset_returns_to_spawn(self):
        self.drive(-0.3, 0.5, 1.0)  # back away from the wall, turning
        self.wait_until_stopped()
        self.reset()

        def at_spawn(msg):
            p = msg.pose.pose
            return (abs(p.position.x) < 1e-3 and abs(p.position.y) < 1e-3 and
                    abs(p.orientation.z) < 1e-3)
        # Ground truth still in flight from before the reset may arrive first; wait for the
        # condition itself, bounded in time.
        with self.lock:
            ok = self.lock.wait_for(lambda: at_spawn(self.truth), timeout=30.0)
        self.assertTrue(ok, 'the robot is not back at the spawn pose (0, 0, 0) after reset')
        x, y, yaw = self.pose()  # and it stays there
        self.assertAlmostEqual(x, 0.0, places=3)
        self.assertAlmostEqual(y, 0.0, places=3)
        self.assertAlmostEqual(yaw, 0.0, places=3)


if __name__ == '__main__':
    rostest.rosrun('minibot3d_sim', 'sim_drive', SimDrive, sys.argv)
