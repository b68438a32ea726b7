"""Every C++ node that reads frames finds frame_prefix as the nodes share it
(minibot3d_ros/frames.h): set once in the robot's namespace, above the node. A value that is no
ROS name stops each node at start-up with the parameter's full name (a node that did not read it
would start and publish unprefixed frames), and map_server serves a robot's own map in its frame.
On a master of its own; the nodes run in namespace robot1."""
import os
import subprocess

import minibot3d_testing as testing
import pytest
import rosgraph

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MAP = os.path.join(ROOT, 'maps', 'default_world.yaml')
NODES = [('minibot3d_navigation', 'amcl', []), ('minibot3d_navigation', 'move_base', []),
         ('minibot3d_navigation', 'explore', []), ('minibot3d_slam', 'slam_gmapping', []),
         ('minibot3d_slam', 'map_server', [MAP])]


@pytest.fixture(scope='module')
def core(tmp_path_factory):
    tmp = tmp_path_factory.mktemp('nodes')
    with testing.RosCore(dict(os.environ, ROS_HOME=str(tmp))) as c:
        yield c


def set_params(core, params):
    master = rosgraph.Master('/test_frame_prefix_nodes', master_uri=core.uri)
    if master.hasParam('/robot1'):
        master.deleteParam('/robot1')
    for key, value in params.items():
        master.setParam(key, value)


@pytest.mark.parametrize('package,node,args', NODES, ids=[n[1] for n in NODES])
def test_a_bad_frame_prefix_stops_the_node_naming_it(core, package, node, args):
    set_params(core, {'/robot1/frame_prefix': 'robot 1'})
    try:
        p = subprocess.run(['rosrun', package, node] + args + ['__ns:=robot1'], env=core.env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, timeout=60)
    except subprocess.TimeoutExpired as e:
        pytest.fail('%s did not stop on a bad frame_prefix:\n%s' % (node, e.output))
    assert p.returncode != 0, p.stdout
    assert '/robot1/frame_prefix' in p.stdout and 'not a ROS name' in p.stdout, p.stdout


def test_map_server_serves_a_robots_own_map_in_its_frame(core):
    set_params(core, {'/robot1/frame_prefix': 'robot1', '/robot1/shared_frames': []})
    server = core.start_process(['rosrun', 'minibot3d_slam', 'map_server', MAP, '__ns:=robot1'])
    try:
        p = subprocess.run(['rostopic', 'echo', '-n', '1', '/robot1/map/header/frame_id'],
                           env=core.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, timeout=60)
    finally:
        server.stop()
    # rostopic may warn first that the topic is not published yet; then the field, quoted.
    frames = [l.strip('"') for l in p.stdout.splitlines() if not l.startswith('WARNING')]
    assert frames[0] == 'robot1/map', p.stdout
