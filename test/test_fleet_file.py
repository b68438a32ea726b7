"""Fleet files (tools/fleet.py): the launch file made of config/fleets/mixed.yaml starts each robot
of its own model with its own config set in its namespace (loaded with roslaunch, not run), bad
fleet files are refused naming the file, the robot and the fix, and the mixed fleet crosses the
default world on lock-step time (fleet_goals.test: every robot reaches its goal, no collision)."""
import os
import re
import subprocess
import sys

import pytest
import roslaunch.config
import roslib.packages

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOOL = [sys.executable, os.path.join(ROOT, 'tools', 'fleet.py')]
MIXED = os.path.join(ROOT, 'config', 'fleets', 'mixed.yaml')
NAMES = ['scout', 'rover', 'carrier']


def generate(fleet, out):
    run = subprocess.run(TOOL + [fleet, '--out', str(out)], capture_output=True, text=True,
                         timeout=120)
    return run


@pytest.fixture(scope='module')
def mixed(tmp_path_factory):
    out = tmp_path_factory.mktemp('fleet') / 'mixed.launch'
    run = generate(MIXED, out)
    assert run.returncode == 0, run.stderr
    return str(out)


def test_each_robot_runs_its_model_and_config_set_in_its_namespace(mixed):
    config = roslaunch.config.load_config_default([(mixed, [])], None, verbose=False)
    names = sorted(n.namespace.rstrip('/') + '/' + n.name for n in config.nodes)
    expected = ['/map_server', '/minibot3d_sim'] + [
        '/%s/%s' % (r, n) for r in NAMES for n in ('amcl', 'move_base', 'robot_state_publisher')]
    assert names == sorted(expected)
    p = {k: v.value for k, v in config.params.items()}
    assert p['/minibot3d_sim/robots'] == 'scout rover carrier'
    assert '/robot_description' not in p
    models = {r: re.search(r'<robot name="([^"]+)"', p['/%s/robot_description' % r]).group(1)
              for r in NAMES}
    assert models == {'scout': 'minibot3d', 'rover': 'diffbot', 'carrier': 'quadbot'}
    # Spawned where its amcl starts; its own config set's amcl and costmaps.
    for r, pose in zip(NAMES, [(-3.0, -1.5, 0.0), (2.5, -1.0, 1.57), (-0.1, 2.0, 0.0)]):
        assert (p['/minibot3d_sim/%s/x' % r], p['/minibot3d_sim/%s/y' % r],
                p['/minibot3d_sim/%s/yaw' % r]) == pose
        assert (p['/%s/amcl/initial_pose_x' % r], p['/%s/amcl/initial_pose_y' % r],
                p['/%s/amcl/initial_pose_a' % r]) == pose
        assert p['/%s/frame_prefix' % r] == r
    # quadbot's controllers in its namespace, its skid-steer-free calibration 1.0; minibot3d's 1.56.
    assert '/carrier/mobile_base_controller/type' in p
    assert p['/minibot3d_sim/carrier/odom_wheel_separation_multiplier'] == 1.0
    assert p['/minibot3d_sim/scout/cmd_wheel_separation_multiplier'] == 1.56
    remaps = {n.namespace.strip('/') + '/' + n.name: dict(n.remap_args) for n in config.nodes}
    assert remaps['carrier/move_base']['cmd_vel'] == 'mobile_base_controller/cmd_vel'
    assert remaps['carrier/amcl']['scan'] == 'front_laser/scan'
    assert remaps['scout/move_base']['cmd_vel'] == 'cmd_vel'
    assert p['/minibot3d_sim/lockstep_participants'] == ' '.join(
        '/%s/amcl /%s/move_base' % (r, r) for r in NAMES)
    assert p['/map_server/frame_id'] == 'map'


def test_every_node_of_the_launch_file_exists(mixed):
    config = roslaunch.config.load_config_default([(mixed, [])], None, verbose=False)
    for node in config.nodes:
        assert roslib.packages.find_node(node.package, node.type), (node.package, node.type)
    for flag in ('true', 'false'):
        config = roslaunch.config.load_config_default([(mixed, ['use_sim_time:=' + flag])], None,
                                                      verbose=False)
        assert config.params['/use_sim_time'].value is (flag == 'true')


def test_the_launch_args_reach_the_simulator(mixed):
    config = roslaunch.config.load_config_default(
        [(mixed, ['real_time_factor:=0', 'lockstep:=true', 'lockstep_clients:=/probe',
                  'physics:=kinematic'])], None, verbose=False)
    p = {k: v.value for k, v in config.params.items()}
    assert p['/minibot3d_sim/real_time_factor'] == 0.0
    assert p['/minibot3d_sim/physics'] == 'kinematic'
    assert p['/minibot3d_sim/lockstep_participants'].split()[-1] == '/probe'


def fleet_file(tmp_path, text):
    path = tmp_path / 'fleet.yaml'
    path.write_text(text)
    return str(path)


GOOD = 'robots:\n  - {name: a, pose: [-3.0, -1.5, 0.0]}\n  - {name: b, pose: [2.5, -1.0, 1.57]}\n'


@pytest.mark.parametrize('text, said', [
    (GOOD.replace('name: b', 'name: a'), 'two robots are named a'),
    (GOOD.replace('name: b', 'name: 2b'), "name '2b' is not a ROS name"),
    (GOOD.replace('name: b', 'name: b/c'), "name 'b/c' is not a ROS name"),
    (GOOD.replace('[2.5, -1.0, 1.57]', '[2.5, -1.0]'), 'robot 2 (b): pose must be [x, y, yaw]'),
    (GOOD.replace('[2.5, -1.0, 1.57]', '[2.5, x, 0]'), 'robot 2 (b): pose must be [x, y, yaw]'),
    (GOOD.replace('{name: b,', '{name: b, colour: red,'), "unknown key(s) colour"),
    (GOOD.replace('{name: b,', '{name: b, config: config/robots/nosuchbot,'),
     'robot 2 (b): config directory'),
    (GOOD.replace('{name: b,', '{name: b, model: nosuch.xacro,'),
     'model nosuch.xacro: no such file'),
    ('world: nosuch.world\n' + GOOD, 'world nosuch.world: no such file'),
    ('robots: []\n', 'robots must be a list of robots'),
    ('fleet: 3\n', 'unknown key(s) fleet'),
    ('robots: [a, b]\n', 'robot 1: expected a mapping'),
])
def test_bad_fleet_files_are_named(tmp_path, text, said):
    path = fleet_file(tmp_path, text)
    run = generate(path, tmp_path / 'out.launch')
    assert run.returncode == 1, run.stdout
    assert said in run.stderr and path in run.stderr, run.stderr
    assert not (tmp_path / 'out.launch').exists()


def test_unknown_launch_args_are_refused(tmp_path):
    run = subprocess.run(TOOL + [MIXED, 'robots:=3'], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and 'robots:=3 is not one of' in run.stderr, run.stderr


def test_mixed_fleet_crosses_the_world(tmp_path):
    """Closed loop: scout (minibot3d), rover (diffbot) and carrier (quadbot) cross the default
    world at once, each on its own stack (fleet_goals.test, lock-step time at full speed)."""
    out = tmp_path / 'mixed.launch'
    assert generate(MIXED, out).returncode == 0
    run = subprocess.run(['rostest', '--text', 'minibot3d_navigation', 'fleet_goals.test',
                          'fleet_launch:=%s' % out, 'names:=%s' % ' '.join(NAMES)],
                         capture_output=True, text=True, timeout=900, cwd=str(tmp_path))
    report = [line for line in run.stdout.splitlines() if line.startswith('fleet_swap:')]
    print('\n'.join(report))
    # With --text rostest's exit status does not follow the result: its summary does.
    assert run.returncode == 0 and ' * RESULT: SUCCESS' in run.stdout, \
        '\n'.join(report) + run.stdout[-3000:]
    for name in NAMES:
        assert any(line.startswith('fleet_swap: %s: ' % name) and ' reached,' in line and
                   '0 with walls, 0 with robots' in line for line in report), report
