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
    ('minibot3d_gazebo.launch', 'model'): "the stacks' parameters are for this robot",
    ('amcl.launch', 'scan_topic'): "the simulator's topic names are fixed",
    ('amcl.launch', 'use_map_topic'): 'map_server offers the static_map service',
    ('move_base.launch', 'scan_topic'): "the simulator's topic names are fixed",
    ('move_base.launch', 'odom_topic'): "the simulator's topic names are fixed",
    ('move_base.launch', 'config_dir'): 'each of its files is forwarded by its own arg',
    ('slam_gmapping.launch', 'scan_topic'): "the simulator's topic names are fixed",
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
