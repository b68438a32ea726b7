"""The launch files' arguments: every arg says what it is, and a launch file that includes another
forwards every argument of it that a user would set (roslaunch ignores an unknown command-line
arg without a word, so an arg that is not forwarded is silently dropped)."""
import glob
import os
import re
import subprocess
import tempfile

from xml.etree import ElementTree

import pytest
import roslaunch.config
import rospkg

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCH_FILES = sorted({os.path.realpath(f)
                       for f in glob.glob(os.path.join(ROOT, '**', '*.launch'), recursive=True)
                       if not any(d in f for d in ('/build/', '/devel/', '/install/', '/out/'))})
ENTRY_POINTS = sorted(glob.glob(os.path.join(ROOT, 'launch', '*.launch')))

# (included file, arg): why a file that includes it sets the arg itself or leaves its default.
NOT_FORWARDED = {
    ('minibot3d_gazebo.launch', 'rviz'): 'the stacks start their own rviz with their own config',
    ('amcl.launch', 'use_map_topic'): 'map_server offers the static_map service',
    ('minibot3d_gazebo.launch', 'robots'): 'a single-robot stack runs the one unnamed robot '
                                           '(fleet_navigation.launch starts several)',
}

_rospack = rospkg.RosPack()


def rel(path):
    return os.path.relpath(path, ROOT)


def declared_args(path):
    """The args a user can set: <arg> elements with a default or none, not constants (value=)."""
    root = ElementTree.parse(path).getroot()
    return {a.get('name'): a for a in root.iter('arg') if a.get('value') is None}


def resolve_include(expr, including):
    expr = expr.replace('$(dirname)', os.path.dirname(including))
    expr = re.sub(r'\$\(find ([^)]+)\)', lambda m: _rospack.get_path(m.group(1)), expr)
    assert '$(' not in expr, 'cannot resolve include %s in %s' % (expr, rel(including))
    return os.path.realpath(expr)


def includes():
    """(including file, included file, names the <include> passes) for every include."""
    out = []
    for path in LAUNCH_FILES:
        for inc in ElementTree.parse(path).getroot().iter('include'):
            out.append((path, resolve_include(inc.get('file'), path),
                        {a.get('name') for a in inc.findall('arg')}))
    return out


INCLUDES = includes()


def test_there_are_includes_and_entry_points():
    assert INCLUDES and ENTRY_POINTS


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=rel)
def test_every_arg_has_a_doc(path):
    undocumented = [n for n, a in declared_args(path).items() if not (a.get('doc') or '').strip()]
    assert not undocumented, '%s: args without doc=: %s' % (rel(path), undocumented)


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=rel)
def test_no_arg_is_reported_required(path):
    # roslaunch --ros-args lists an arg whose default is empty as required, though the file runs
    # without it: every optional arg has a non-empty default (e.g. "none").
    empty = [n for n, a in declared_args(path).items() if a.get('default') == '']
    assert not empty, '%s: args with an empty default: %s' % (rel(path), empty)
    out = subprocess.run(['roslaunch', '--ros-args', path], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stdout + out.stderr
    assert 'Required Arguments' not in out.stdout and 'undocumented' not in out.stdout, out.stdout


@pytest.mark.parametrize('including,included,passed', INCLUDES,
                         ids=['%s > %s' % (rel(i[0]), os.path.basename(i[1])) for i in INCLUDES])
def test_include_forwards_every_arg(including, included, passed):
    name = os.path.basename(included)
    wanted = {a for a in declared_args(included) if (name, a) not in NOT_FORWARDED}
    missing = sorted(wanted - passed)
    assert not missing, '%s includes %s without forwarding %s: a user setting them on the ' \
        'command line would be ignored' % (rel(including), rel(included), missing)


def test_entry_points_forward_without_exceptions():
    # A system launch file forwards everything of the package file it includes.
    for including, included, passed in INCLUDES:
        if including in map(os.path.realpath, ENTRY_POINTS):
            assert set(declared_args(included)) <= passed, (rel(including), rel(included))


def load_params(path, *args):
    config = roslaunch.config.load_config_default([(path, list(args))], None, verbose=False)
    return {k: v.value for k, v in config.params.items()}


def entry_point_calls():
    nav_map = 'map_file:=' + os.path.join(ROOT, 'maps', 'default_world.yaml')
    return [('navigation.launch', []), ('exploration.launch', []), ('demo.launch', []),
            ('demo.launch', ['phase:=navigate', nav_map])]


@pytest.mark.parametrize('name,args', entry_point_calls(),
                         ids=lambda v: v if isinstance(v, str) else ' '.join(v)[:20])
def test_entry_point_takes_a_planner_file(name, args):
    with tempfile.NamedTemporaryFile('w', suffix='.yaml') as f:
        f.write('TrajectoryPlannerROS:\n  max_vel_x: 0.8\n')
        f.flush()
        p = load_params(os.path.join(ROOT, 'launch', name), *args, 'trajectory_planner:=' + f.name)
    assert p['/move_base/TrajectoryPlannerROS/max_vel_x'] == 0.8


def test_navigation_takes_an_amcl_overlay_and_lockstep_clients():
    path = os.path.join(ROOT, 'launch', 'navigation.launch')
    with tempfile.NamedTemporaryFile('w', suffix='.yaml') as f:
        f.write('max_particles: 1234\n')
        f.flush()
        p = load_params(path, 'amcl_params:=' + f.name, 'lockstep:=true',
                        'lockstep_clients:=/simple_navi_goals')
    assert p['/amcl/max_particles'] == 1234
    assert p['/amcl/min_particles'] == 500  # the rest of config/amcl.yaml stays
    assert p['/minibot3d_sim/lockstep_participants'] == '/amcl /move_base /simple_navi_goals'
    p = load_params(path)
    assert p['/minibot3d_sim/lockstep_participants'] == '/amcl /move_base'
    assert p['/amcl/max_particles'] != 1234


def test_exploration_lockstep_participants():
    path = os.path.join(ROOT, 'launch', 'exploration.launch')
    assert load_params(path)['/minibot3d_sim/lockstep_participants'] == \
        '/slam_gmapping /move_base /explore'
    assert load_params(path, 'explore:=false', 'lockstep_clients:=/my_client')[
        '/minibot3d_sim/lockstep_participants'] == '/slam_gmapping /move_base /my_client'


# ---- a robot other than minibot3d: its launch-level args reach every node --------------------

QUADBOT = ['model:=' + os.path.join(ROOT, 'minibot3d_description', 'urdf', 'quadbot.xacro'),
           'robot_params:=' + os.path.join(ROOT, 'config', 'robots', 'quadbot', 'control.yaml'),
           'scan_topic:=front_laser/scan', 'cmd_vel_topic:=mobile_base_controller/cmd_vel',
           'odom_topic:=mobile_base_controller/odom', 'rviz:=true']
# The remaps each node type must carry (from, to), where the file starts that node.
ROBOT_REMAPS = {
    'slam_gmapping': {('scan', 'front_laser/scan')},
    'amcl': {('scan', 'front_laser/scan')},
    'move_base': {('scan', 'front_laser/scan'), ('cmd_vel', 'mobile_base_controller/cmd_vel'),
                  ('odom', 'mobile_base_controller/odom')},
    'rviz': {('/scan', 'front_laser/scan')},
    'diff_wheeled_robot_key': {('turtlebot_teleop_keyboard/cmd_vel',
                                'mobile_base_controller/cmd_vel')},
}
ROBOT_CALLS = [('launch/mapping_teleop.launch', []), ('launch/exploration.launch', []),
               ('launch/navigation.launch', []), ('launch/demo.launch', []),
               ('launch/demo.launch', ['phase:=navigate', 'map_file:=' + os.path.join(
                   ROOT, 'maps', 'default_world.yaml')]),
               ('minibot3d_navigation/launch/mapless_navigation.launch', [])]


@pytest.fixture(scope='module')
def marked_config_dir(tmp_path_factory):
    """config/ with one value changed in each parameter file, to see which folder was read."""
    d = tmp_path_factory.mktemp('config_set')
    marks = {'gmapping.yaml': ('particles', 7), 'amcl.yaml': ('max_particles', 1234),
             'explore.yaml': ('clearance', 0.31), 'move_base_params.yaml': ('planner_patience', 4.5),
             'move_base_mapless_params.yaml': ('blocked_radius', 0.33)}
    import yaml
    for f in glob.glob(os.path.join(ROOT, 'config', '*.yaml')):
        with open(f) as src:
            data = yaml.safe_load(src)
        name = os.path.basename(f)
        if name in marks:
            data[marks[name][0]] = marks[name][1]
        with open(str(d / name), 'w') as dst:
            yaml.safe_dump(data, dst)
    return str(d)


@pytest.mark.parametrize('path,args', ROBOT_CALLS,
                         ids=['%s %s' % (c[0], ' '.join(c[1])[:14]) for c in ROBOT_CALLS])
def test_robot_args_reach_every_node(path, args, marked_config_dir):
    config = roslaunch.config.load_config_default(
        [(os.path.join(ROOT, path), args + QUADBOT + ['config_dir:=' + marked_config_dir])],
        None, verbose=False)
    p = {k: v.value for k, v in config.params.items()}
    assert '<robot name="quadbot"' in p['/robot_description']
    # robot_params at the root namespace, where a ros_control robot's controllers live.
    assert p['/mobile_base_controller/type'] == 'diff_drive_controller/DiffDriveController'
    types = {n.type for n in config.nodes}
    for node in config.nodes:
        wanted = ROBOT_REMAPS.get(node.type, set())
        assert wanted <= {tuple(r) for r in node.remap_args}, (path, node.type, node.remap_args)
    # Every parameter file came from config_dir.
    marked = {'slam_gmapping': ('/slam_gmapping/particles', 7),
              'amcl': ('/amcl/max_particles', 1234), 'explore': ('/explore/clearance', 0.31),
              'move_base': ('/move_base/planner_patience', 4.5)}
    for node_type, (key, value) in marked.items():
        if node_type in types:
            assert p[key] == value, (path, key)
    if 'mapless' in path:
        assert p['/move_base/blocked_radius'] == 0.33


def test_minibot3d_is_the_default_robot():
    p = load_params(os.path.join(ROOT, 'launch', 'exploration.launch'))
    assert '<robot name="minibot3d"' in p['/robot_description']
    assert not any(k.startswith('/mobile_base_controller') for k in p)


# ---- a robot among several: robot:=NAME ----------------------------------------------------

# Each call, and the frames its robot shares with others (a robot mapping on its own shares none).
ROBOT_NAME_CALLS = [
    ('launch/navigation.launch', [], {'map'}),
    ('launch/exploration.launch', [], set()),
    ('launch/demo.launch', [], set()),
    ('launch/demo.launch', ['phase:=navigate', 'map_file:=' + os.path.join(
        ROOT, 'maps', 'default_world.yaml')], {'map'}),
    ('minibot3d_navigation/launch/mapless_navigation.launch', [], {'map'}),
    ('launch/mapping_teleop.launch', [], set()),
]
# Nodes of the whole world rather than of one robot.
WORLD_NODES = {'minibot3d_sim', 'robot_state_publisher', 'map_server', 'rosservice'}


def robot_nodes(config):
    return {n.type: n for n in config.nodes if n.type not in WORLD_NODES}


@pytest.mark.parametrize('path,args,shared', ROBOT_NAME_CALLS,
                         ids=['%s %s' % (c[0], ' '.join(c[1])[:14]) for c in ROBOT_NAME_CALLS])
def test_a_named_robots_nodes_run_in_its_namespace_on_its_frames(path, args, shared):
    """robot:=robot7 moves every node of the robot into /robot7 and prefixes the frames it reads
    (found and resolved as the nodes do); without it nothing moves and every frame stays as the
    config set gives it. Catches a node left at the root, a frame_prefix that misses a node, a
    map prefixed under amcl (or shared by robots that map on their own), and a stack whose
    lock-step participants keep their root names."""
    from launch_frames import resolved_frames
    path = os.path.join(ROOT, path)
    plain = roslaunch.config.load_config_default([(path, args + ['rviz:=false'])], None,
                                                 verbose=False)
    named = roslaunch.config.load_config_default(
        [(path, args + ['rviz:=false', 'robot:=robot7'])], None, verbose=False)
    plain_nodes, named_nodes = robot_nodes(plain), robot_nodes(named)
    assert set(plain_nodes) == set(named_nodes) and plain_nodes
    assert not any(k.endswith('/frame_prefix') or k.endswith('/shared_frames')
                   for k in plain.params), 'a robot without a name has no frame parameters'
    for node_type, node in named_nodes.items():
        assert plain_nodes[node_type].namespace == '/', node_type
        assert node.namespace == '/robot7/', (node_type, node.namespace)
        before = resolved_frames(plain, plain_nodes[node_type])
        after = resolved_frames(named, node)
        assert after == {k: v if v in shared else 'robot7/' + v for k, v in before.items()}, \
            (node_type, before, after)
    if any(t in named_nodes for t in ('amcl', 'move_base', 'slam_gmapping')):
        assert named.params['/robot7/frame_prefix'].value == 'robot7'
    p = {k: v.value for k, v in named.params.items()}
    if p.get('/minibot3d_sim/lockstep_participants'):
        stack = p['/minibot3d_sim/lockstep_participants'].split()
        assert stack and all(n.startswith('/robot7/') for n in stack), stack
    for node in named.nodes:
        if node.type == 'rosservice':
            assert node.args == 'call --wait /robot7/global_localization', node.args


def test_a_named_robots_lockstep_clients_keep_full_names_and_take_relative_ones():
    path = os.path.join(ROOT, 'launch', 'navigation.launch')
    p = load_params(path, 'robot:=r2', 'lockstep_clients:=/goal_client my_client')
    assert p['/minibot3d_sim/lockstep_participants'] == \
        '/r2/amcl /r2/move_base /goal_client /r2/my_client'
    assert load_params(path, 'lockstep_clients:=/goal_client my_client')[
        '/minibot3d_sim/lockstep_participants'] == '/amcl /move_base /goal_client /my_client'


# ---- the simulator's odometry error --------------------------------------------------------

TYPICAL_ODOM_ERROR = os.path.join(ROOT, 'minibot3d_sim', 'config', 'typical_odometry_error.yaml')
ODOM_ERROR_CALLS = [('launch/mapping_teleop.launch', []), ('launch/exploration.launch', []),
                    ('launch/navigation.launch', []),
                    ('minibot3d_navigation/launch/mapless_navigation.launch', []),
                    ('launch/demo.launch', ['odom_error_params:=none']),
                    ('launch/demo.launch', ['phase:=navigate', 'odom_error_params:=none',
                                            'map_file:=' + os.path.join(
                                                ROOT, 'maps', 'default_world.yaml')])]


def odom_error_of(params):
    return {k.rsplit('/', 1)[1]: v for k, v in params.items()
            if k.startswith('/minibot3d_sim/odom_error_')}


@pytest.mark.parametrize('path,args', ODOM_ERROR_CALLS,
                         ids=['%s %s' % (c[0], ' '.join(c[1])[:14]) for c in ODOM_ERROR_CALLS])
def test_odometry_error_reaches_the_simulator(path, args):
    import yaml
    path = os.path.join(ROOT, path)
    # Off unless asked: the drive's odometry exactly.
    assert set(odom_error_of(load_params(path, *args)).values()) == {0}
    one = odom_error_of(load_params(path, *args, 'odom_error_heading_drift:=0.03',
                                    'odom_error_turn_noise:=0.01'))
    assert (one['odom_error_heading_drift'], one['odom_error_turn_noise'],
            one['odom_error_scale']) == (0.03, 0.01, 0)
    # The typical robot's file sets all six, over the args.
    with open(TYPICAL_ODOM_ERROR) as f:
        typical = yaml.safe_load(f)
    assert len(typical) == 6 and all(v != 0 for v in typical.values()), typical
    args = [a for a in args if not a.startswith('odom_error_params')]
    assert odom_error_of(load_params(path, *args, 'odom_error_scale:=0.5',
                                     'odom_error_params:=' + TYPICAL_ODOM_ERROR)) == typical


def test_demo_launch_runs_with_the_typical_odometry_error_as_make_demo():
    import yaml
    with open(TYPICAL_ODOM_ERROR) as f:
        typical = yaml.safe_load(f)
    for args in ([], ['phase:=navigate']):
        assert odom_error_of(load_params(os.path.join(ROOT, 'launch', 'demo.launch'), *args)) \
            == typical
