"""Every shipped launch file parses, resolves its includes/args/xacro commands, and names nodes
whose packages and executables exist (roslaunch --nodes and roslaunch-check's API)."""
import glob
import os
import subprocess

from xml.etree import ElementTree

import pytest
import roslaunch.config
import roslib.packages
import rospkg
from roslaunch.rlutil import check_roslaunch

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCH_FILES = sorted(glob.glob(os.path.join(ROOT, '**', '*.launch'), recursive=True))
LAUNCH_FILES = [f for f in LAUNCH_FILES
                if not any(d in f for d in ('/build/', '/devel/', '/install/', '/out/'))]
# minibot3d_bringup/launch links to launch/: each file once, by its own path.
LAUNCH_FILES = sorted({os.path.realpath(f) for f in LAUNCH_FILES})

# rviz is only started when asked: check both ways where the file has that argument.
HEADLESS = ['rviz:=false']


def test_there_are_launch_files():
    assert LAUNCH_FILES, 'no launch files found under %s' % ROOT


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=lambda p: os.path.relpath(p, ROOT))
def test_launch_file_loads(path):
    out = subprocess.run(['roslaunch', '--nodes', path], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, 'roslaunch --nodes %s failed:\n%s%s' % (path, out.stdout,
                                                                         out.stderr)


def missing_executables(path, *args):
    """What roslaunch-check's node check finds, for files outside any package (launch/), which
    roslaunch-check itself cannot take: it also checks the package.xml of the file's package."""
    config = roslaunch.config.load_config_default([(path, list(args))], None, verbose=False)
    missing = []
    for node in config.nodes + config.tests:
        try:
            found = roslib.packages.find_node(node.package, node.type)
        except rospkg.ResourceNotFound:
            found = None
        if not found:
            missing.append('%s/%s' % (node.package, node.type))
    return missing


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=lambda p: os.path.relpath(p, ROOT))
def test_launch_file_nodes_exist(path):
    if rospkg.get_package_name(path) is None:
        assert not missing_executables(path), (path, missing_executables(path))
        return
    error = check_roslaunch(path)
    assert error is None, 'roslaunch-check %s: %s' % (path, error)


# ---- the system-level entry points (launch/) ----------------------------------------------------

TOP_LEVEL = os.path.join(ROOT, 'launch')
# Each entry point: the nodes (by type) it must start, for each way of calling it.
ENTRY_POINTS = [
    ('mapping_teleop.launch', [], {'minibot3d_sim', 'slam_gmapping', 'rviz',
                                   'diff_wheeled_robot_key'}),
    ('exploration.launch', [], {'minibot3d_sim', 'slam_gmapping', 'move_base', 'explore'}),
    ('navigation.launch', [], {'minibot3d_sim', 'map_server', 'amcl', 'move_base'}),
    ('demo.launch', [], {'minibot3d_sim', 'slam_gmapping', 'move_base', 'explore'}),
    ('demo.launch', ['phase:=navigate', 'map_file:=' + os.path.join(ROOT, 'maps',
                                                                    'default_world.yaml')],
     {'minibot3d_sim', 'map_server', 'amcl', 'move_base', 'rosservice'}),
    ('fleet.launch', [], {'minibot3d_sim', 'map_server', 'amcl', 'move_base',
                          'robot_state_publisher'}),
]


def test_launch_dir_holds_the_entry_points():
    assert sorted(f for f in os.listdir(TOP_LEVEL) if f.endswith('.launch')) == \
        sorted({e[0] for e in ENTRY_POINTS})


@pytest.mark.parametrize('name,args,types', ENTRY_POINTS,
                         ids=['%s %s' % (e[0], ' '.join(a.split(':=')[0] for a in e[1]))
                              for e in ENTRY_POINTS])
def test_entry_point_starts_its_stack(name, args, types):
    path = os.path.join(TOP_LEVEL, name)
    config = roslaunch.config.load_config_default([(path, args)], None, verbose=False)
    assert {n.type for n in config.nodes} >= types, (name, args)
    assert not missing_executables(path, *args)
    # Thin: the file only includes package launch files and sets no node or parameter itself.
    root = ElementTree.parse(path).getroot()
    assert not root.findall('.//node'), name
    for inc in root.iter('include'):
        assert inc.get('file').startswith(('$(find minibot3d_', '$(dirname)/')), inc.get('file')


def test_demo_launch_rejects_an_unknown_phase():
    out = subprocess.run(['roslaunch', '--nodes', os.path.join(TOP_LEVEL, 'demo.launch'),
                          'phase:=mapping'], capture_output=True, text=True, timeout=120)
    assert out.returncode != 0 and 'phase_must_be_explore_or_navigate' in out.stdout + out.stderr


# ---- what the launch files set ------------------------------------------------------------------

import roslaunch.config  # noqa: E402
import roslaunch.xmlloader  # noqa: E402

# robot.yaml holds launch args, not parameters (tools/robot_config.py reads it; test_robot_config.py).
CONFIG_FILES = sorted(f for f in glob.glob(os.path.join(ROOT, 'config', '*.yaml'))
                      if os.path.basename(f) != 'robot.yaml')
# Launch files whose default is wall time, with the reason (see the file).
WALL_TIME_DEFAULT = {'minibot3d_description/launch/view_mobile_robot.launch'}


class _RecordingLoader(roslaunch.xmlloader.XmlLoader):
    """Notes every file a <rosparam command="load"> reads."""

    def __init__(self):
        super().__init__()
        self.files = set()

    def load_rosparam(self, context, ros_config, cmd, param, file_, text, **kwargs):
        if file_:
            self.files.add(os.path.realpath(file_))
        return super().load_rosparam(context, ros_config, cmd, param, file_, text, **kwargs)


def load(path, *args):
    loader = _RecordingLoader()
    config = roslaunch.config.load_config_default([(path, list(args))], None, loader=loader,
                                                  verbose=False)
    return config, loader.files


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=lambda p: os.path.relpath(p, ROOT))
def test_launch_file_sets_use_sim_time_from_its_arg(path):
    # Whichever file is started first, its nodes see the simulator's clock.
    rel = os.path.relpath(path, ROOT)
    config, _ = load(path, *HEADLESS)
    assert '/use_sim_time' in config.params, '%s does not set /use_sim_time' % rel
    assert config.params['/use_sim_time'].value is (rel not in WALL_TIME_DEFAULT), rel
    flipped = 'false' if rel not in WALL_TIME_DEFAULT else 'true'
    config, _ = load(path, 'use_sim_time:=' + flipped, *HEADLESS)
    assert config.params['/use_sim_time'].value is (flipped == 'true'), rel


def test_every_config_file_is_loaded_by_a_launch_file():
    loaded = set()
    for path in LAUNCH_FILES:
        loaded |= load(path, *HEADLESS)[1]
    missing = [os.path.relpath(c, ROOT) for c in CONFIG_FILES if os.path.realpath(c) not in loaded]
    assert not missing, 'config files no launch file loads: %s' % missing


def move_base_parameter_names():
    out = subprocess.run(['rosrun', 'minibot3d_navigation', 'move_base',
                          '--print-parameter-names'], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return set(out.stdout.split())


def test_mapless_navigation_has_an_odom_costmap_and_no_map():
    config, files = load(os.path.join(ROOT, 'minibot3d_navigation', 'launch',
                                      'mapless_navigation.launch'), *HEADLESS)
    assert os.path.realpath(os.path.join(ROOT, 'config', 'global_costmap_mapless_params.yaml')) \
        in files
    assert os.path.realpath(os.path.join(ROOT, 'config', 'global_costmap_params.yaml')) \
        not in files
    p = {k: v.value for k, v in config.params.items()}
    g = '/move_base/global_costmap/'
    assert p[g + 'global_frame'] == 'odom'
    assert p[g + 'static_map'] is False and p[g + 'rolling_window'] is False
    assert p[g + 'track_unknown_space'] is False  # unseen space is free: planned through
    assert (p[g + 'width'], p[g + 'height']) == (24.0, 24.0)
    assert (p[g + 'origin_x'], p[g + 'origin_y']) == (-12.0, -12.0)
    assert p['/move_base/NavfnROS/allow_unknown'] is True
    # Pockets met without a map: back_out, remembered blocked stretches, recovery reset (loaded
    # over move_base_params.yaml, which leaves them off for the mapped stacks).
    assert os.path.realpath(os.path.join(ROOT, 'config', 'move_base_mapless_params.yaml')) in files
    assert p['/move_base/back_out_distance'] == 0.6
    assert p['/move_base/blocked_radius'] == 0.2
    assert p['/move_base/recovery_reset_distance'] == 0.5
    for k in ('back_out_distance', 'blocked_radius', 'recovery_reset_distance'):
        assert '/' + k in move_base_parameter_names()
    assert p['/use_lockstep'] is False
    types = sorted(n.type for n in config.nodes)
    assert 'amcl' not in types and 'map_server' not in types
    assert 'move_base' in types and 'minibot3d_sim' in types
    # Every global costmap key is one move_base reads (a misspelling would only be warned about).
    names = move_base_parameter_names()
    unknown = [k for k in p if k.startswith(g) and k[len('/move_base/'):] not in names
               and k != g + 'observation_sources' and not k.startswith(g + 'laser_scan_sensor')]
    assert not unknown, unknown

    config, _ = load(os.path.join(ROOT, 'minibot3d_navigation', 'launch',
                                  'mapless_navigation.launch'), *HEADLESS, 'pocket_recoveries:=false')
    assert '/move_base/back_out_distance' not in config.params

    config, _ = load(os.path.join(ROOT, 'minibot3d_navigation', 'launch',
                                  'mapless_navigation.launch'),
                     'lockstep:=true', 'lockstep_participants:=/move_base /simple_navi_goals')
    sim = [n for n in config.nodes if n.type == 'minibot3d_sim'][0]
    assert config.params['/use_lockstep'].value is True
    assert config.params['/minibot3d_sim/lockstep_participants'].value == \
        '/move_base /simple_navi_goals'
    assert sim.name == 'minibot3d_sim'
