"""Each robot's launch-level interface (config/robot.yaml, config/robots/NAME/robot.yaml, read by
tools/robot_config.py for make demo): it names a model and files that exist, wrong ones are
reported with the file and key, and a stack launched with a shipped robot's args runs with the
robot's topics: the simulator publishes the laser and odometry where the robot's plugins say, and
slam_gmapping, amcl and move_base read and command there."""
import glob
import os
import subprocess
import sys

import pytest
import rosgraph
import minibot3d_testing as testing

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools'))
import robot_config  # noqa: E402

ROBOT_DIRS = [os.path.join(ROOT, 'config')] + sorted(
    os.path.dirname(p) for p in glob.glob(os.path.join(ROOT, 'config', 'robots', '*', 'robot.yaml')))
SHIPPED_MODELS = sorted(glob.glob(os.path.join(ROOT, 'minibot3d_description', 'urdf', '*.xacro')))


def rel(path):
    return os.path.relpath(path, ROOT)


def test_every_shipped_robot_has_a_robot_yaml():
    names = {os.path.basename(d) for d in glob.glob(os.path.join(ROOT, 'config', 'robots', '*'))}
    assert {'diffbot', 'quadbot'} <= names
    for name in names:
        assert os.path.isfile(os.path.join(ROOT, 'config', 'robots', name, 'robot.yaml')), name
    models = {robot_config.load(d)['model'] for d in ROBOT_DIRS}
    assert models == {os.path.realpath(m) for m in SHIPPED_MODELS}


@pytest.mark.parametrize('config_dir', ROBOT_DIRS, ids=rel)
def test_robot_yaml_names_existing_files(config_dir):
    args = robot_config.load(config_dir)
    assert list(args) == ['config_dir'] + list(robot_config.DEFAULTS)
    assert os.path.isfile(args['model'])
    out = subprocess.run(['xacro', args['model']], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and '<robot' in out.stdout, out.stderr
    if args['robot_params'] != 'none':
        assert os.path.isfile(args['robot_params'])
        assert os.path.dirname(args['robot_params']) == os.path.realpath(config_dir)
    with open(os.path.join(config_dir, 'robot.yaml')) as f:
        head = f.read().split('\n\n')[0]
    for key in robot_config.DEFAULTS:  # the keys are documented at the top of each
        assert key in head, (rel(config_dir), key)


def test_minibot3d_robot_yaml_matches_the_launch_defaults():
    args = robot_config.load(os.path.join(ROOT, 'config'))
    assert args['model'] == os.path.join(ROOT, 'minibot3d_description', 'urdf', 'minibot3d.xacro')
    assert (args['scan_topic'], args['cmd_vel_topic'], args['odom_topic']) == \
        ('scan', 'cmd_vel', 'odom')
    assert args['odom_wheel_separation_multiplier'] == '1.56'
    assert args['cmd_wheel_separation_multiplier'] == '1.56'


def test_quadbot_names_its_controllers_and_topics():
    args = robot_config.load(os.path.join(ROOT, 'config', 'robots', 'quadbot'))
    assert rel(args['robot_params']) == 'config/robots/quadbot/control.yaml'
    assert (args['scan_topic'], args['cmd_vel_topic'], args['odom_topic']) == \
        ('front_laser/scan', 'mobile_base_controller/cmd_vel', 'mobile_base_controller/odom')


def write(d, text):
    os.makedirs(str(d), exist_ok=True)
    (d / 'robot.yaml').write_text(text)
    return str(d)


@pytest.mark.parametrize('text,said', [
    ('model: minibot3d_description/urdf/minibot3d.xacro\nscan: front/scan\n',
     'unknown key(s) scan'),
    ('scan_topic: scan\n', 'model must be'),
    ('model: minibot3d_description/urdf/no_such.xacro\n', 'no such file'),
    ('model: minibot3d_description/urdf/diffbot.xacro\nrobot_params: control.yaml\n',
     'robot_params control.yaml: no such file'),
    ('model: minibot3d_description/urdf/diffbot.xacro\ncmd_vel_topic: mobile base\n',
     'cmd_vel_topic must be'),
    ('model: minibot3d_description/urdf/diffbot.xacro\nodom_topic: ~odom\n', 'private name'),
    ('model: minibot3d_description/urdf/diffbot.xacro\nodom_wheel_separation_multiplier: 0\n',
     'must be a number > 0'),
    ('- model\n', 'expected a mapping'),
])
def test_bad_robot_yaml_is_named(tmp_path, text, said):
    d = write(tmp_path / 'robot', text)
    with pytest.raises(robot_config.RobotConfigError) as e:
        robot_config.load(d)
    assert said in str(e.value) and 'robot.yaml' in str(e.value), str(e.value)


def test_missing_robot_yaml_is_named(tmp_path):
    with pytest.raises(robot_config.RobotConfigError, match='robot.yaml is missing'):
        robot_config.load(str(tmp_path))


def test_model_option_replaces_robot_yaml_model(tmp_path):
    d = write(tmp_path / 'robot', 'scan_topic: base_scan\n')
    model = os.path.join(ROOT, 'minibot3d_description', 'urdf', 'diffbot.xacro')
    args = robot_config.load(d, model=model)
    assert args['model'] == model and args['scan_topic'] == 'base_scan'
    assert args['robot_params'] == 'none' and args['odom_wheel_separation_multiplier'] == '1.0'


def test_cli_prints_launch_args_and_wants_the_whole_config_set(tmp_path):
    tool = [sys.executable, os.path.join(ROOT, 'tools', 'robot_config.py')]
    out = subprocess.run(tool + [os.path.join(ROOT, 'config')], capture_output=True, text=True,
                         timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines()[:2] == ['config_dir:=' + os.path.join(ROOT, 'config'),
                                           'model:=' + os.path.join(
                                               ROOT, 'minibot3d_description', 'urdf',
                                               'minibot3d.xacro')]
    d = write(tmp_path / 'robot', 'model: minibot3d_description/urdf/diffbot.xacro\n')
    (tmp_path / 'robot' / 'gmapping.yaml').write_text('particles: 30\n')
    out = subprocess.run(tool + [d], capture_output=True, text=True, timeout=60)
    assert out.returncode == 1 and not out.stdout
    assert 'lacks amcl.yaml' in out.stderr and 'gmapping.yaml' not in out.stderr, out.stderr


# ---- the stacks, live, with each shipped robot's args ------------------------------------------

def config_set(robot_dir, tmp_path):
    """The robot's config set, with config/'s file wherever the robot's folder lacks one."""
    d = tmp_path / 'config_set'
    d.mkdir()
    for f in robot_config.CONFIG_SET:
        own = os.path.join(robot_dir, f)
        os.symlink(own if os.path.isfile(own) else os.path.join(ROOT, 'config', f), str(d / f))
    return str(d)


def topic_graph(master):
    pubs, subs, _ = master.getSystemState()
    return ({t: set(n) for t, n in pubs}, {t: set(n) for t, n in subs})


STACKS = {'exploration': ('launch/exploration.launch', ['explore:=false'], '/slam_gmapping'),
          'navigation': ('launch/navigation.launch', [], '/amcl')}


@pytest.mark.parametrize('robot', ['diffbot', 'quadbot'])
@pytest.mark.parametrize('stack', sorted(STACKS))
def test_stack_runs_on_the_robots_topics(robot, stack, tmp_path):
    robot_dir = os.path.join(ROOT, 'config', 'robots', robot)
    args = robot_config.load(robot_dir)
    args['config_dir'] = config_set(robot_dir, tmp_path)
    path, extra, localizer = STACKS[stack]
    scan, cmd_vel, odom = ('/' + args[k] for k in ('scan_topic', 'cmd_vel_topic', 'odom_topic'))
    cmd = ['roslaunch', os.path.join(ROOT, path)] + extra + \
        ['%s:=%s' % kv for kv in args.items()]
    with testing.Stack(cmd, str(tmp_path / 'launch.log'),
                       dict(os.environ, ROS_HOME=str(tmp_path))) as s:
        master = rosgraph.Master('/test_robot_config', master_uri=s.core.uri)

        def wired():
            assert s.launch.running(), 'the launch ended:\n' + s.log(3000)
            pubs, subs = topic_graph(master)
            return ('/minibot3d_sim' in pubs.get(scan, ()) and
                    localizer in subs.get(scan, ()) and '/move_base' in subs.get(scan, ()) and
                    '/move_base' in pubs.get(cmd_vel, ()) and
                    '/minibot3d_sim' in subs.get(cmd_vel, ()) and
                    '/minibot3d_sim' in pubs.get(odom, ()) and
                    '/move_base' in subs.get(odom, ()))

        testing.wait_until(wired, 90, lambda: 'the stack on %s, %s, %s; topics: %s\n%s' % (
            scan, cmd_vel, odom, topic_graph(master), s.log(3000)))
        pubs, subs = topic_graph(master)
        # Nothing left on the default names the robot does not use.
        for default, own in (('/scan', scan), ('/cmd_vel', cmd_vel), ('/odom', odom)):
            if default != own:
                assert default not in pubs and default not in subs, (default, pubs, subs)
