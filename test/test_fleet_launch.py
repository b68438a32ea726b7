"""launch/fleet.launch without running it: each robot's nodes, where they run, what they read
(parameters, remaps, the frames they resolve), the robot count it refuses, and the robots' spawn
poses against the default world."""
import collections
import math
import os
import subprocess

import numpy as np
import pytest
import roslaunch.config

from launch_frames import node_name, resolved_frames
from minibot3d_map_io.map_io import load_map

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FLEET = os.path.join(ROOT, 'launch', 'fleet.launch')


def load(*args):
    return roslaunch.config.load_config_default([(FLEET, list(args))], None, verbose=False)


def default_poses():
    from xml.etree import ElementTree
    for a in ElementTree.parse(FLEET).getroot().iter('arg'):
        if a.get('name') == 'spawn_poses':
            return [tuple(float(v) for v in p.split(',')) for p in a.get('default').split()]
    raise AssertionError('fleet.launch has no spawn_poses')


@pytest.mark.parametrize('robots', [1, 3, 8])
def test_every_robot_has_its_stack_in_its_namespace(robots):
    config = load('robots:=%d' % robots)
    names = sorted(node_name(n) for n in config.nodes)
    stacks = sorted('/robot%d/%s' % (k, n) for k in range(1, robots + 1)
                    for n in ('amcl', 'move_base'))
    # One simulator and one map for all; each robot's robot_state_publisher in its namespace.
    assert names == sorted(stacks + ['/map_server', '/minibot3d_sim'] +
                           ['/robot%d/robot_state_publisher' % k for k in range(1, robots + 1)])
    p = {k: v.value for k, v in config.params.items()}
    assert p['/minibot3d_sim/robots'] == str(robots)
    assert '/robot_description' not in p
    poses = default_poses()
    for k in range(1, robots + 1):
        assert p['/robot%d/frame_prefix' % k] == 'robot%d' % k
        assert '<robot name="minibot3d"' in p['/robot%d/robot_description' % k]
        x, y, yaw = poses[k - 1]
        # The simulator spawns robot K where its amcl starts.
        assert (p['/minibot3d_sim/robot%d/x' % k], p['/minibot3d_sim/robot%d/y' % k],
                p['/minibot3d_sim/robot%d/yaw' % k]) == (x, y, yaw)
        assert (p['/robot%d/amcl/initial_pose_x' % k], p['/robot%d/amcl/initial_pose_y' % k],
                p['/robot%d/amcl/initial_pose_a' % k]) == (x, y, yaw)
        # Each robot's config set: the same files, in its own namespace.
        assert p['/robot%d/amcl/base_frame_id' % k] == 'base_footprint'
        assert p['/robot%d/move_base/local_costmap/global_frame' % k] == 'odom'
    assert not any(key.startswith('/robot%d/' % (robots + 1)) for key in p)
    assert p['/minibot3d_sim/lockstep_participants'] == ' '.join(
        '/robot%d/amcl /robot%d/move_base' % (k, k) for k in range(1, robots + 1))
    assert p['/map_server/frame_id'] == 'map'


def test_every_robot_reads_its_own_topics_and_the_shared_map():
    config = load('robots:=2', 'scan_topic:=front_laser/scan',
                  'cmd_vel_topic:=mobile_base_controller/cmd_vel')
    for node in config.nodes:
        remaps = dict(node.remap_args)
        if node.type == 'amcl':
            assert remaps['map'] == '/map' and remaps['static_map'] == '/static_map', remaps
            assert remaps['scan'] == 'front_laser/scan'  # relative: in the robot's namespace
        if node.type == 'move_base':
            assert remaps['map'] == '/map', remaps
            assert remaps['cmd_vel'] == 'mobile_base_controller/cmd_vel'
            assert node.namespace.startswith('/robot')


def test_the_params_resolve_to_each_robots_frames():
    """The frames each node will use, found and resolved as the nodes do: the robot's own
    prefixed, the map shared. Catches a robot whose frame_prefix does not reach a node (a
    parameter set in the wrong namespace) and a map frame prefixed per robot."""
    config = load('robots:=3')
    seen = collections.Counter()
    for node in config.nodes:
        if not node.namespace.startswith('/robot') or node.type == 'robot_state_publisher':
            continue
        r = node.namespace.strip('/')
        frames = resolved_frames(config, node)
        seen[node.type] += 1
        if node.type == 'amcl':
            assert frames == {'base_frame_id': r + '/base_footprint',
                              'odom_frame_id': r + '/odom', 'global_frame_id': 'map'}, frames
        else:
            assert frames == {'global_costmap/global_frame': 'map',
                              'global_costmap/robot_base_frame': r + '/base_link',
                              'local_costmap/global_frame': r + '/odom',
                              'local_costmap/robot_base_frame': r + '/base_link',
                              'global_costmap/laser_scan_sensor/sensor_frame': r + '/laser',
                              'local_costmap/laser_scan_sensor/sensor_frame': r + '/laser'}, \
                frames
    assert seen == {'amcl': 3, 'move_base': 3}


@pytest.mark.parametrize('robots', ['0', '9', 'two'])
def test_a_robot_count_without_spawn_poses_is_refused_by_name(robots):
    out = subprocess.run(['roslaunch', '--nodes', FLEET, 'robots:=' + robots],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode != 0
    assert 'robots_must_be_from_1_to_the_number_of_spawn_poses' in out.stdout + out.stderr, \
        out.stdout + out.stderr


# ---- the spawn poses against the default world ---------------------------------------------

# The largest shipped robot's footprint reaches 0.36 m from its centre (quadbot's corner); a pose
# keeps 0.5 m from every wall and obstacle of the world, and 1.5 m from the other robots.
CLEARANCE = 0.5
SPACING = 1.5


def world_map():
    """The default world's obstacles: maps/default_world is rendered from
    minibot3d_sim/worlds/default.world (minibot3d_sim's test_shipped_maps checks it)."""
    return load_map(os.path.join(ROOT, 'maps', 'default_world.yaml'))


def test_the_spawn_poses_are_free_apart_and_connected_in_the_default_world():
    grid = world_map()
    res, (ox, oy) = grid.resolution, grid.origin[:2]
    blocked = grid.data != 0  # occupied or unknown
    rows, cols = np.nonzero(blocked)
    wx, wy = ox + (cols + 0.5) * res, oy + (rows + 0.5) * res
    poses = default_poses()
    assert len(poses) == 8
    for x, y, _ in poses:
        clearance = math.sqrt(((wx - x) ** 2 + (wy - y) ** 2).min())
        assert clearance >= CLEARANCE, 'spawn pose (%g, %g) is %.2f m from an obstacle' % (
            x, y, clearance)
    for i, a in enumerate(poses):
        for b in poses[i + 1:]:
            assert math.hypot(a[0] - b[0], a[1] - b[1]) >= SPACING, (a, b)
    # Every pose is reachable from the first by a robot that keeps 0.2 m from obstacles: cells
    # that far from every blocked cell, 4-connected.
    r = int(math.ceil(0.2 / res))
    free = ~blocked
    for dr in range(-r, r + 1):
        for dc in range(-r, r + 1):
            if dr * dr + dc * dc <= r * r:
                free &= ~np.roll(np.roll(blocked, dr, axis=0), dc, axis=1)
    cell = lambda x, y: (int((y - oy) / res), int((x - ox) / res))  # noqa: E731
    start = cell(*poses[0][:2])
    reached = {start}
    todo = collections.deque([start])
    while todo:
        rr, cc = todo.popleft()
        for n in ((rr + 1, cc), (rr - 1, cc), (rr, cc + 1), (rr, cc - 1)):
            if 0 <= n[0] < free.shape[0] and 0 <= n[1] < free.shape[1] and free[n] and \
                    n not in reached:
                reached.add(n)
                todo.append(n)
    for x, y, _ in poses:
        assert cell(x, y) in reached, 'spawn pose (%g, %g) is cut off from robot1' % (x, y)


def test_the_default_spawn_pose_of_robot1_is_the_simulators():
    """robot1 starts where the single-robot stacks start, the simulator's own default."""
    from xml.etree import ElementTree
    sim = os.path.join(ROOT, 'minibot3d_sim', 'launch', 'minibot3d_gazebo.launch')
    default = {a.get('name'): float(a.get('default'))
               for a in ElementTree.parse(sim).getroot().iter('arg') if a.get('name') in ('x', 'y', 'yaw')}
    assert (default['x'], default['y'], default['yaw']) == default_poses()[0]
