#!/usr/bin/env python3
"""rostest (sim_actor.test): the actor of walking_person.world walks its script as the file says.
At every waypoint's time (read from the world file, over two rounds of the looping script) the
actor published on /minibot3d_sim/actors stands at that waypoint's position and heading; between
waypoints it moves; and the robot's laser sees it where /minibot3d_sim/actors says it is (a beam
towards the actor's centre ends on its cylinder).
Catches: an actor that does not move or keeps the wrong times (a script not looped, a delay or a
trajectory out of order), actors published at the wrong time, a laser blind to actors."""
import math
import threading
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
from minibot3d_sim.msg import SimActors
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan


def waypoints(world_file):
    """[(time, x, y, yaw)] of the first actor's only trajectory, and whether it loops."""
    actor = ET.parse(world_file).getroot().find('world/actor')
    script = actor.find('script')
    out = []
    for w in script.find('trajectory').findall('waypoint'):
        pose = [float(v) for v in w.find('pose').text.split()]
        out.append((float(w.find('time').text), pose[0], pose[1], pose[5]))
    return out, script.find('loop').text.strip() == 'true'


class SimActor(unittest.TestCase):
    def setUp(self):
        rospy.init_node('sim_actor_test')
        self.cond = threading.Condition()
        self.actors = {}  # stamp in ms -> message
        self.scans = {}
        self.truth = None
        rospy.Subscriber('/minibot3d_sim/actors', SimActors, self.on_actors, queue_size=1000)
        rospy.Subscriber('/scan', LaserScan, self.on_scan, queue_size=1000)
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=10)

    def on_actors(self, m):
        with self.cond:
            self.actors[round(m.header.stamp.to_sec() * 1000)] = m
            self.cond.notify_all()

    def on_scan(self, m):
        with self.cond:
            self.scans[round(m.header.stamp.to_sec() * 1000)] = m

    def on_truth(self, m):
        with self.cond:
            self.truth = m.pose.pose

    def test_the_actor_walks_its_script_and_the_laser_sees_it(self):
        points, loop = waypoints(rospy.get_param('~world'))
        self.assertTrue(loop)
        length = points[-1][0]
        end_ms = round(2 * length * 1000) + 100
        with self.cond:
            self.assertTrue(self.cond.wait_for(lambda: max(self.actors, default=0) >= end_ms, 90.0),
                            'no /minibot3d_sim/actors up to %.1f s of sim time' % (end_ms / 1000.0))
        checked = 0
        for round_start in (0.0, length):
            for t, x, y, yaw in points:
                ms = round((round_start + t) * 1000)
                if ms not in self.actors:
                    continue  # a message the test's queue dropped
                a = self.actors[ms].actors[0]
                self.assertEqual(a.name, 'walker')
                self.assertAlmostEqual(a.pose.position.x, x, delta=1e-6, msg='x at %d ms' % ms)
                self.assertAlmostEqual(a.pose.position.y, y, delta=1e-6, msg='y at %d ms' % ms)
                heading = 2 * math.atan2(a.pose.orientation.z, a.pose.orientation.w)
                self.assertAlmostEqual(math.cos(heading - yaw), 1.0, delta=1e-9,
                                       msg='heading at %d ms' % ms)
                checked += 1
        self.assertGreaterEqual(checked, len(points), 'too few waypoint times seen')
        # Half-way along the first walk it is moving along +x.
        mid = self.actors.get(2500)
        self.assertIsNotNone(mid)
        self.assertGreater(mid.actors[0].twist.linear.x, 0.5)
        # The laser (a 360-beam scan, frame turned by pi on the robot) sees the actor: on a scan
        # taken while the actor is in view, the beam towards the actor's centre ends on its
        # cylinder, radius before the centre.
        with self.cond:
            truth = self.truth
            common = sorted(set(self.scans) & set(self.actors))
        self.assertTrue(common)
        robot_x, robot_y = truth.position.x, truth.position.y
        seen = 0
        for ms in common:
            scan = self.scans[ms]
            a = self.actors[ms].actors[0]
            laser_x, laser_y = robot_x + 0.02, robot_y
            bearing = math.atan2(a.pose.position.y - laser_y, a.pose.position.x - laser_x)
            beam = math.atan2(math.sin(bearing - math.pi), math.cos(bearing - math.pi))
            k = int(round((beam - scan.angle_min) / scan.angle_increment)) % len(scan.ranges)
            expected = math.hypot(a.pose.position.x - laser_x,
                                  a.pose.position.y - laser_y) - a.radius
            self.assertAlmostEqual(scan.ranges[k], expected, delta=0.06,
                                   msg='beam %d at %d ms: %.3f m, actor at %.3f m' % (
                                       k, ms, scan.ranges[k], expected))
            seen += 1
        self.assertGreater(seen, 10)


if __name__ == '__main__':
    rostest.rosrun('minibot3d_sim', 'sim_actor', SimActor)
