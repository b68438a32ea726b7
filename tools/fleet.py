#!/usr/bin/env python3
"""A fleet file: several robots, of any models, each with its config set and spawn pose, turned
into one launch file that starts them in one simulator, each with amcl and move_base in its
namespace on one shared map (what launch/fleet.launch does for N robots of one model).

  tools/fleet.py FLEET.yaml [name:=value ...]
      writes build/fleet/<FLEET's name>.launch and runs roslaunch on it with the args given
      (real_time_factor, lockstep, lockstep_clients, physics, seed, paused, odom_error_params,
      use_sim_time).
  tools/fleet.py FLEET.yaml --out FILE
      only writes the launch file.

A fleet file (config/fleets/mixed.yaml is one):

  world: minibot3d_sim/worlds/default.world   # optional, the default world's; a Gazebo SDF
                                              # world or a floor-plan map YAML
  map_file: maps/default_world.yaml           # optional, that map; what every robot localizes
                                              # and plans on (map_server YAML, world frame)
  robots:
    - name: scout                 # required: its namespace and frame prefix (a ROS name)
      config: config              # its config set (robot.yaml and the stacks' YAMLs); default
                                  # config, minibot3d's
      pose: [-3.0, -1.5, 0.0]     # required: spawn x, y (m), yaw (rad); amcl starts there
      model: ...                  # optional: replaces robot.yaml's model
      amcl_params: ...            # optional: a YAML over the config set's amcl.yaml

Paths are relative to the repository root, absolute, or $(find PACKAGE)/.... Anything wrong (an
unknown key, two robots with one name, a name that is no ROS name, a pose that is not three
numbers, a config set that robot_config.py refuses) stops it with a message naming the file, the
robot and the fix; the simulator refuses robots spawned inside the world or each other."""
import argparse
import os
import re
import sys
import tempfile
from xml.etree import ElementTree

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import robot_config  # noqa: E402  (tools/robot_config.py: robot.yaml, the one reader)

ROOT = robot_config.ROOT
FLEET_KEYS = ('world', 'map_file', 'robots')
ROBOT_KEYS = ('name', 'config', 'pose', 'model', 'amcl_params')
DEFAULT_WORLD = '$(find minibot3d_sim)/worlds/default.world'
DEFAULT_MAP = '$(find minibot3d_bringup)/maps/default_world.yaml'
# The generated launch file's own args: simulator settings a run may change.
LAUNCH_ARGS = (
    ('use_sim_time', 'true', 'set /use_sim_time (the simulator\'s clock)'),
    ('physics', 'bullet', 'physics backend: bullet (wheels slip) or kinematic'),
    ('real_time_factor', '1.0', 'sim seconds per wall second; 0: as fast as possible'),
    ('paused', 'false', 'start the simulator paused'),
    ('seed', '1', 'seed of the sensor noise'),
    ('lockstep', 'false', 'lock-step time: runs are the same at any real_time_factor'),
    ('lockstep_clients', 'none',
     'lock-step: more nodes (full names) sim time waits for, besides every robot\'s amcl and '
     'move_base'),
    ('odom_error_params', 'none', 'YAML of odom_error_* values for every robot; none: none'),
)
NAME = re.compile(r'^[A-Za-z][A-Za-z0-9_]*$')


class FleetError(ValueError):
    """The fleet file is wrong; the message names the file, the robot and the fix."""


def _path(value, source, what):
    if not isinstance(value, str) or not value.strip():
        raise FleetError('%s: %s must be a path, got %r' % (source, what, value))
    try:
        return robot_config.resolve_path(value, ROOT, what, source)
    except robot_config.RobotConfigError as e:
        raise FleetError(str(e))


def load(path):
    """The fleet: {'world', 'map_file', 'robots': [{'name', 'pose', 'args'}]}, each robot's args
    robot_config.load()'s (config_dir, model, topics, ...) plus amcl_params."""
    source = path
    try:
        with open(path) as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise FleetError('cannot read fleet file %s: %s' % (path, e.strerror))
    except yaml.YAMLError as e:
        raise FleetError('%s: not YAML: %s' % (source, e))
    if not isinstance(data, dict):
        raise FleetError('%s: expected a mapping with %s' % (source, ', '.join(FLEET_KEYS)))
    unknown = sorted(set(map(str, data)) - set(FLEET_KEYS))
    if unknown:
        raise FleetError('%s: unknown key(s) %s; the keys are %s' % (
            source, ', '.join(unknown), ', '.join(FLEET_KEYS)))
    fleet = {
        'world': _path(data['world'], source, 'world') if 'world' in data else DEFAULT_WORLD,
        'map_file': (_path(data['map_file'], source, 'map_file') if 'map_file' in data
                     else DEFAULT_MAP),
        'robots': [],
    }
    robots = data.get('robots')
    if not isinstance(robots, list) or not robots:
        raise FleetError('%s: robots must be a list of robots (name, config, pose), got %r' % (
            source, robots))
    seen = set()
    for i, entry in enumerate(robots, 1):
        where = '%s: robot %d' % (source, i)
        if not isinstance(entry, dict):
            raise FleetError('%s: expected a mapping with %s, got %r' % (
                where, ', '.join(ROBOT_KEYS), entry))
        name = entry.get('name')
        if not isinstance(name, str) or not NAME.match(name):
            raise FleetError('%s: name %r is not a ROS name (a letter, then letters, digits, _)'
                             % (where, name))
        where = '%s (%s)' % (where, name)
        if name in seen:
            raise FleetError('%s: two robots are named %s' % (where, name))
        seen.add(name)
        unknown = sorted(set(map(str, entry)) - set(ROBOT_KEYS))
        if unknown:
            raise FleetError('%s: unknown key(s) %s; the keys are %s' % (
                where, ', '.join(unknown), ', '.join(ROBOT_KEYS)))
        pose = entry.get('pose')
        if (not isinstance(pose, list) or len(pose) != 3 or
                any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in pose)):
            raise FleetError('%s: pose must be [x, y, yaw] (m, m, rad), got %r' % (where, pose))
        config = entry.get('config', 'config')
        if not isinstance(config, str) or not config.strip():
            raise FleetError('%s: config must be a config directory, got %r' % (where, config))
        config_dir = os.path.join(ROOT, os.path.expanduser(config))
        model = None
        if 'model' in entry:
            model = _path(entry['model'], where, 'model')
        try:
            args = robot_config.load(config_dir, model)
        except robot_config.RobotConfigError as e:
            raise FleetError('%s: %s' % (where, e))
        missing = robot_config.missing_set_files(args['config_dir'])
        if missing:
            raise FleetError('%s: config set %s lacks %s' % (
                where, args['config_dir'], ', '.join(missing)))
        args['amcl_params'] = (_path(entry['amcl_params'], where, 'amcl_params')
                               if 'amcl_params' in entry else 'none')
        fleet['robots'].append({'name': name, 'pose': [float(v) for v in pose], 'args': args})
    return fleet


def _comment(text):
    return ElementTree.Comment(' %s ' % text.replace('--', '- -'))  # no "--" in an XML comment


def _sub(parent, tag, **attrs):
    e = ElementTree.SubElement(parent, tag)
    for k, v in attrs.items():
        e.set(k.rstrip('_'), str(v))
    return e


def _include(parent, path, **args):
    inc = _sub(parent, 'include', file=path)
    for k, v in args.items():
        _sub(inc, 'arg', name=k, value=v)
    return inc


def launch_xml(fleet, source):
    """The launch file of `fleet` (from load()) as a string."""
    root = ElementTree.Element('launch')
    root.append(_comment('Made by tools/fleet.py from %s; edit that file, not this one.' % source))
    for name, default, doc in LAUNCH_ARGS:
        _sub(root, 'arg', name=name, default=default, doc=doc)
    _sub(root, 'param', name='/use_sim_time', value='$(arg use_sim_time)')
    sim_time = '$(arg use_sim_time)'
    names = [r['name'] for r in fleet['robots']]
    participants = ' '.join('/%s/amcl /%s/move_base' % (n, n) for n in names)
    first = fleet['robots'][0]['pose']
    _include(root, '$(find minibot3d_sim)/launch/minibot3d_gazebo.launch',
             use_sim_time=sim_time, world=fleet['world'], robots=' '.join(names),
             x=first[0], y=first[1], yaw=first[2],
             physics='$(arg physics)', real_time_factor='$(arg real_time_factor)',
             paused='$(arg paused)', seed='$(arg seed)', lockstep='$(arg lockstep)',
             lockstep_participants=participants + ' $(arg lockstep_clients)',
             odom_error_params='$(arg odom_error_params)', rviz='false')
    _sub(root, 'node', name='map_server', pkg='minibot3d_slam', type='map_server',
         args=fleet['map_file']).append(ElementTree.Element(
             'param', {'name': 'frame_id', 'value': 'map'}))
    for robot in fleet['robots']:
        name, (x, y, yaw), a = robot['name'], robot['pose'], robot['args']
        root.append(_comment('%s: %s' % (name, a['config_dir'])))
        _include(root, '$(find minibot3d_sim)/launch/spawn_robot.launch',
                 use_sim_time=sim_time, name=name, model=a['model'],
                 robot_params=a['robot_params'], x=x, y=y, yaw=yaw)
        for key in robot_config.MULTIPLIERS:
            _sub(root, 'param', name='/minibot3d_sim/%s/%s' % (name, key), value=a[key])
        _include(root, '$(find minibot3d_navigation)/launch/amcl.launch',
                 use_sim_time=sim_time, robot=name,
                 initial_pose_x=x, initial_pose_y=y, initial_pose_a=yaw,
                 map_topic='/map', scan_topic=a['scan_topic'], config_dir=a['config_dir'],
                 params=a['amcl_params'])
        _include(root, '$(find minibot3d_navigation)/launch/move_base.launch',
                 use_sim_time=sim_time, robot=name, map_topic='/map',
                 config_dir=a['config_dir'],
                 scan_topic=a['scan_topic'], cmd_vel_topic=a['cmd_vel_topic'],
                 odom_topic=a['odom_topic'])
    ElementTree.indent(root, space='  ')
    return '<?xml version="1.0"?>\n' + ElementTree.tostring(root, encoding='unicode') + '\n'


def write_atomically(path, text):
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=directory, prefix='.fleet-', suffix='.launch')
    try:
        with os.fdopen(fd, 'w') as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('fleet', help='the fleet file (YAML)')
    parser.add_argument('--out', help='write the launch file here and stop')
    parser.add_argument('args', nargs='*', help='name:=value args for roslaunch')
    opts = parser.parse_args(argv)
    known = {a[0] for a in LAUNCH_ARGS}
    for a in opts.args:
        if ':=' not in a or a.split(':=', 1)[0] not in known:
            print('fleet: %s is not one of name:=value with name in %s' % (
                a, ', '.join(sorted(known))), file=sys.stderr)
            return 2
    try:
        fleet = load(opts.fleet)
    except FleetError as e:
        print('fleet: %s' % e, file=sys.stderr)
        return 1
    text = launch_xml(fleet, os.path.abspath(opts.fleet))
    out = opts.out or os.path.join(
        ROOT, 'build', 'fleet', os.path.splitext(os.path.basename(opts.fleet))[0] + '.launch')
    write_atomically(out, text)
    if opts.out:
        return 0
    print('fleet: %d robots (%s), launch file %s' % (
        len(fleet['robots']), ' '.join(r['name'] for r in fleet['robots']), out), flush=True)
    os.execvp('roslaunch', ['roslaunch', out] + opts.args)
    return 0


if __name__ == '__main__':
    sys.exit(main())
