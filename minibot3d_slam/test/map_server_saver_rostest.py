#!/usr/bin/env python3
"""rostest: map_server publishes test/fixtures/tiny_map.yaml latched on /map and /map_metadata and
serves /static_map with the fixture's cells, geometry and frame; map_saver (run as `rosrun
minibot3d_slam map_saver`) writes back the same grey levels and a YAML that says the same."""
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from minibot3d_map_io import load_map, read_image

import rospy
import rostest
import yaml
from nav_msgs.msg import MapMetaData, OccupancyGrid
from nav_msgs.srv import GetMap

# The fixture's cells, grid row 0 = the image's bottom row: 100 occupied (0), 0 free (254),
# -1 unknown (205).
EXPECTED_CELLS = [100, 0, 0, 0, 0,
                  100, 0, 100, 0, -1,
                  100, 0, 0, 0, -1,
                  100, 100, 100, 100, -1]


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class MapServerSaver(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('map_server_saver_test')
        cls.fixture = rospy.get_param('~fixture')
        with open(cls.fixture) as f:
            cls.meta = yaml.safe_load(f)

    def check_info(self, info):
        self.assertEqual((info.width, info.height), (5, 4))
        self.assertAlmostEqual(info.resolution, 0.1, places=6)
        self.assertAlmostEqual(info.origin.position.x, -0.25, places=9)
        self.assertAlmostEqual(info.origin.position.y, -0.2, places=9)
        self.assertAlmostEqual(yaw_of(info.origin.orientation), 0.1, places=9)

    def test_latched_map(self):
        msg = rospy.wait_for_message('/map', OccupancyGrid, timeout=30)
        self.assertEqual(msg.header.frame_id, 'world')
        self.check_info(msg.info)
        self.assertEqual(list(msg.data), EXPECTED_CELLS)

    def test_latched_metadata(self):
        self.check_info(rospy.wait_for_message('/map_metadata', MapMetaData, timeout=30))

    def test_static_map_service(self):
        rospy.wait_for_service('/static_map', timeout=30)
        res = rospy.ServiceProxy('/static_map', GetMap)()
        self.assertEqual(res.map.header.frame_id, 'world')
        self.check_info(res.map.info)
        self.assertEqual(list(res.map.data), EXPECTED_CELLS)

    def test_map_saver_writes_the_served_map(self):
        rospy.wait_for_message('/map', OccupancyGrid, timeout=30)  # map_server is up
        out_dir = tempfile.mkdtemp(prefix='map_saver_rostest.')
        try:
            base = os.path.join(out_dir, 'saved')
            run = subprocess.run(
                ['rosrun', 'minibot3d_slam', 'map_saver', '-f', base, '--timeout', '30'],
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                timeout=60)
            self.assertEqual(run.returncode, 0, 'map_saver failed:\n' + run.stdout)
            self.assertIn('saved.pgm', run.stdout)  # it says what it wrote
            self.assertEqual(sorted(os.listdir(out_dir)), ['saved.pgm', 'saved.yaml'],
                             'temporary files left behind')

            fixture_image = os.path.join(os.path.dirname(self.fixture), self.meta['image'])
            with open(base + '.pgm', 'rb') as f:
                self.assertEqual(f.read(3), b'P5\n', 'map_saver writes binary PGMs')
            self.assertEqual(read_image(base + '.pgm').tolist(), read_image(fixture_image).tolist())
            self.assertEqual(load_map(base + '.yaml').data.ravel().tolist(), EXPECTED_CELLS)

            with open(base + '.yaml') as f:
                saved = yaml.safe_load(f)
            self.assertEqual(saved['image'], 'saved.pgm')
            self.assertAlmostEqual(saved['resolution'], self.meta['resolution'], places=9)
            for got, want in zip(saved['origin'], self.meta['origin']):
                self.assertAlmostEqual(got, want, places=9)
            self.assertEqual(len(saved['origin']), 3)
            self.assertEqual(saved['negate'], 0)
            self.assertAlmostEqual(saved['occupied_thresh'], 0.65)
            self.assertAlmostEqual(saved['free_thresh'], 0.196)
        finally:
            shutil.rmtree(out_dir)


if __name__ == '__main__':
    rostest.rosrun('minibot3d_slam', 'map_server_saver', MapServerSaver, sys.argv)
