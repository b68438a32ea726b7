"""Two robots' stacks running, without a simulator: minibot3d_navigation's fleet_robots.launch
(amcl and move_base of robot1 and robot2, each in its namespace), map_server at the root, and
fake_robots.py standing in for the simulator (each robot's odometry and laser tf and its scan, on
its prefixed frames). On a master of its own, on wall time.

Each amcl places its robot on the shared map (tf map -> robotK/odom, from its own initial pose),
and each move_base builds its costmaps in its robot's frames: the local one in robotK/odom with
the robot's scan ring in it (seen through the laser robotK/laser), the global one in map, the
footprint in robotK/base_link. Catches a node that reads the robot's frames unprefixed (no tf
between them: no pose, no costmap, no obstacles), two robots that share a frame, and a robot that
reads the other's map or scan."""
import json
import math
import os
import subprocess
import sys

import minibot3d_testing as testing
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
POSES = [(-3.0, -1.5, 0.0), (2.5, -1.0, 1.57)]


def test_two_robots_stacks_localize_and_map_on_their_own_frames(tmp_path):
    poses = ' '.join('%g,%g,%g' % p for p in POSES)
    stack = testing.Stack(['roslaunch', 'minibot3d_navigation', 'fleet_robots.launch',
                           'robots:=2', 'use_sim_time:=false', 'spawn_poses:=' + poses],
                          tmp_path / 'launch.log', env=dict(os.environ, ROS_HOME=str(tmp_path)))
    try:
        stack.start(['rosrun', 'minibot3d_slam', 'map_server',
                     os.path.join(ROOT, 'maps', 'default_world.yaml')], tmp_path / 'map.log')
        stack.start([sys.executable, os.path.join(HERE, 'fake_robots.py'), 'robot1', 'robot2'],
                    tmp_path / 'robots.log')
        probe = subprocess.run([sys.executable, os.path.join(HERE, 'fleet_probe.py'), 'robot1',
                                'robot2'], env=stack.env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, universal_newlines=True, timeout=180)
        seen = json.loads(probe.stdout.strip().splitlines()[-1])
        log = stack.log()
    finally:
        stack.stop()
    for k, (x, y, _) in enumerate(POSES, start=1):
        r = 'robot%d' % k
        assert r + ' pose' in seen, ('no map -> %s/base_footprint' % r, seen, log[-3000:])
        # amcl starts at the robot's own spawn pose (the fake robot stands at its odom origin).
        px, py = seen[r + ' pose']
        assert math.hypot(px - x, py - y) < 0.5, (r, seen[r + ' pose'], (x, y))
        assert seen[r + ' local_costmap/costmap']['frame'] == r + '/odom', seen
        assert seen[r + ' local_costmap/costmap']['lethal'] > 0, (
            '%s: its scan ring is not in its local costmap' % r, seen, log[-3000:])
        assert seen[r + ' global_costmap/costmap']['frame'] == 'map', seen
        assert seen[r + ' footprint']['frame'] == r + '/base_link', seen
