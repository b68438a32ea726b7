#!/usr/bin/env python3
"""rostest: mapping the default world. Drives a loop through its rooms (route_driver.py), saves
the map with map_saver, and checks it against the world's ground-truth map: at least 90 % of the
occupied cells of the saved map lie within 0.1 m of an occupied ground-truth cell, and the map
covers most of what the route could see.

Under lock-step time (as slam_in_sim.test runs it) this node and route_driver.py are participants:
the route starts and ends at fixed sim times, and sim time holds while the map is saved, so every
run saves the same map."""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages
from minibot3d_lockstep.run_checks import RunChecks
from minibot3d_map_io import load_map

import rospy
import rostest
from nav_msgs.msg import OccupancyGrid

WAYPOINTS = '-2.1,0.6 -2.4,3.0 -2.1,0.6 -0.3,2.0 0.45,0.6 2.5,-1.0 0.8,-2.15 -3,-1.5'


def occupied_points(occupied, res, origin):
    rows, cols = np.nonzero(occupied)
    return np.stack([origin[0] + (cols + 0.5) * res, origin[1] + (rows + 0.5) * res], axis=1)


class SlamInSim(unittest.TestCase):
    def test_map_of_the_default_world(self):
        rospy.init_node('slam_in_sim_test')
        truth_yaml = rospy.get_param('~ground_truth_map')
        sx, sy, syaw = (rospy.get_param('~spawn_x'), rospy.get_param('~spawn_y'),
                        rospy.get_param('~spawn_yaw'))
        maps = []
        rospy.Subscriber('/map', OccupancyGrid, lambda m: maps.append(m.header.stamp),
                         queue_size=2)
        lockstep = Participant(wake_topics=['/map'], wake_on_participants=True)
        checks = RunChecks()  # no tf sent twice, nothing listening beyond loopback
        try:
            # The map is published once slam_gmapping has processed its first scan.
            self.assertTrue(lockstep.wait_for(lambda: maps, 120.0), 'no /map within 120 s')
            finished, drive = lockstep.run(
                '/route_driver',
                ['rosrun', 'minibot3d_sim', 'route_driver.py', '--map', truth_yaml,
                 '--waypoints', WAYPOINTS, '--speed', '0.3', '--timeout', '400'],
                400.0, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            out_text, _ = drive.communicate(timeout=60)
            self.assertTrue(finished, 'route_driver.py did not finish within 400 s of sim time')
            self.assertEqual(drive.returncode, 0, out_text)
            # slam_gmapping's latest map (it maps only while the robot moves), saved while sim
            # time holds.
            out = tempfile.mkdtemp(prefix='slam_in_sim_')
            save = subprocess.run(['rosrun', 'minibot3d_slam', 'map_saver', '-f',
                                   os.path.join(out, 'map'), '--timeout', '60'],
                                  capture_output=True, text=True)
            self.assertEqual(save.returncode, 0, save.stdout + save.stderr)
            self.assertEqual([], checks.problems())
        finally:
            lockstep.close()
        saved_map, truth_map = load_map(os.path.join(out, 'map.yaml')), load_map(truth_yaml)
        saved, res, origin = saved_map.occupied, saved_map.resolution, saved_map.origin
        truth, tres, torigin = truth_map.occupied, truth_map.resolution, truth_map.origin
        pts = occupied_points(saved, res, origin)
        self.assertGreater(len(pts), 300, 'the saved map has almost no walls')
        # SLAM's map frame is where the robot started: put its cells in the world frame.
        c, s = math.cos(syaw), math.sin(syaw)
        world = np.stack([sx + c * pts[:, 0] - s * pts[:, 1], sy + s * pts[:, 0] + c * pts[:, 1]],
                         axis=1)
        tpts = occupied_points(truth, tres, torigin)
        nearest = np.full(len(world), np.inf)
        for chunk in np.array_split(np.arange(len(world)), max(1, len(world) // 500)):
            d = np.hypot(world[chunk, None, 0] - tpts[None, :, 0],
                         world[chunk, None, 1] - tpts[None, :, 1])
            nearest[chunk] = d.min(axis=1)
        within = float(np.mean(nearest <= 0.1))
        print('slam_in_sim: %d occupied cells, %.1f %% within 0.1 m of the ground truth, '
              'median distance %.3f m' % (len(world), 100 * within, float(np.median(nearest))))
        self.assertGreaterEqual(within, 0.90)


if __name__ == '__main__':
    rostest.rosrun('minibot3d_slam', 'slam_in_sim', SlamInSim, sys.argv)
