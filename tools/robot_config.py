#!/usr/bin/env python3
"""A robot's launch-level interface: the robot.yaml of its config directory (config/robot.yaml for
minibot3d, config/robots/NAME/robot.yaml for the others; its keys are documented at the top of
each), turned into the launch args every stack takes.

  robot_config.py CONFIG_DIR [--model XACRO]
      prints one `name:=value` line per launch arg (config_dir, model, robot_params, scan_topic,
      cmd_vel_topic, odom_topic and the skid-steer calibration), paths absolute; --model replaces
      robot.yaml's model. Fails, naming the file and the fix, when robot.yaml is missing or wrong,
      a file it names does not exist, or the config set lacks one of CONFIG_SET.

tools/demo.sh passes the lines to both phases' roslaunch; load() is the same for Python."""
import argparse
import os
import re
import sys

import yaml

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))
# The parameter files of a config set, as in config/: every stack's YAML args default to
# $(arg config_dir)/<file>.
CONFIG_SET = ('gmapping.yaml', 'amcl.yaml', 'costmap_common_params.yaml',
              'global_costmap_params.yaml', 'local_costmap_params.yaml',
              'trajectory_planner.yaml', 'move_base_params.yaml', 'explore.yaml')
# robot.yaml's keys and their defaults (model has none).
DEFAULTS = {
    'model': None,
    'robot_params': 'none',
    'scan_topic': 'scan',
    'cmd_vel_topic': 'cmd_vel',
    'odom_topic': 'odom',
    'odom_wheel_separation_multiplier': 1.0,
    'cmd_wheel_separation_multiplier': 1.0,
}
TOPICS = ('scan_topic', 'cmd_vel_topic', 'odom_topic')
MULTIPLIERS = ('odom_wheel_separation_multiplier', 'cmd_wheel_separation_multiplier')


class RobotConfigError(ValueError):
    """robot.yaml, or a file it names, is missing or wrong; the message names it and the fix."""


def resolve_path(value, base, what, source):
    """`value` as an absolute path: $(find PACKAGE)/... through rospack, else relative to base.
    RobotConfigError naming `what` and `source` if it is not a file."""
    m = re.match(r'^\$\(find ([^)\s]+)\)(.*)$', value)
    if m:
        import rospkg
        try:
            path = rospkg.RosPack().get_path(m.group(1)) + m.group(2)
        except rospkg.ResourceNotFound:
            raise RobotConfigError('%s: %s %s: no package %s (is its workspace sourced?)' % (
                source, what, value, m.group(1)))
    else:
        path = os.path.join(base, os.path.expanduser(value))
    path = os.path.realpath(path)
    if not os.path.isfile(path):
        raise RobotConfigError('%s: %s %s: no such file (%s)' % (source, what, value, path))
    return path


def load(config_dir, model=None):
    """The launch args of the robot whose config set is config_dir, as an ordered dict of strings:
    config_dir, then robot.yaml's keys (DEFAULTS for those it leaves out), paths absolute.
    model (a path, relative to the working directory) replaces robot.yaml's."""
    config_dir = os.path.realpath(config_dir)
    source = os.path.join(config_dir, 'robot.yaml')
    if not os.path.isdir(config_dir):
        raise RobotConfigError('config directory %s does not exist' % config_dir)
    if not os.path.isfile(source):
        raise RobotConfigError('%s is missing: a config set needs its robot.yaml (the robot\'s '
                               'model, topics, controllers; see config/robot.yaml)' % source)
    with open(source) as f:
        try:
            data = yaml.safe_load(f)
        except yaml.YAMLError as e:
            raise RobotConfigError('%s: not YAML: %s' % (source, e))
    data = {} if data is None else data
    if not isinstance(data, dict):
        raise RobotConfigError('%s: expected a mapping of keys (%s)' % (source, ', '.join(DEFAULTS)))
    unknown = sorted(set(data) - set(DEFAULTS))
    if unknown:
        raise RobotConfigError('%s: unknown key(s) %s; the keys are %s' % (
            source, ', '.join(map(str, unknown)), ', '.join(DEFAULTS)))
    args = {'config_dir': config_dir}
    for key, default in DEFAULTS.items():
        value = data.get(key, default)
        if key in MULTIPLIERS:
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
                raise RobotConfigError('%s: %s must be a number > 0, got %r' % (source, key, value))
            args[key] = repr(float(value))
            continue
        if not isinstance(value, str) or not value.strip() or re.search(r'\s', value):
            if key == 'model' and model is not None:
                continue
            raise RobotConfigError('%s: %s must be a non-empty string without spaces, got %r%s' % (
                source, key, value, ' (the robot\'s xacro/URDF, relative to the repository root)'
                if key == 'model' else ''))
        args[key] = value
    if model is not None:
        args['model'] = resolve_path(model, os.getcwd(), 'model', 'the model given')
    else:
        args['model'] = resolve_path(args['model'], ROOT, 'model', source)
    if args['robot_params'] != 'none':
        args['robot_params'] = resolve_path(args['robot_params'], config_dir, 'robot_params',
                                            source)
    for key in TOPICS:
        if args[key].startswith('~'):
            raise RobotConfigError('%s: %s %s: a private name is no robot topic' % (
                source, key, args[key]))
    return args


def missing_set_files(config_dir):
    """The files of CONFIG_SET that config_dir lacks."""
    return [f for f in CONFIG_SET if not os.path.isfile(os.path.join(config_dir, f))]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('config_dir')
    parser.add_argument('--model', help="the robot's xacro/URDF, replacing robot.yaml's model")
    args = parser.parse_args(argv)
    try:
        launch_args = load(args.config_dir, args.model)
    except RobotConfigError as e:
        print('robot_config: %s' % e, file=sys.stderr)
        return 1
    missing = missing_set_files(launch_args['config_dir'])
    if missing:
        print('robot_config: %s lacks %s of the config set (copy config/\'s and adapt them to the '
              'robot)' % (launch_args['config_dir'], ', '.join(missing)), file=sys.stderr)
        return 1
    for key, value in launch_args.items():
        print('%s:=%s' % (key, value))
    return 0


if __name__ == '__main__':
    sys.exit(main())
