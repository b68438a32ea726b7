"""The parameter space of a tuning study, and the per-trial parameter files (no ROS needed).

A swept name is either bare (`max_vel_x`) or qualified (`local_costmap/inflation_radius`,
`TrajectoryPlannerROS/sim_time`, `NavfnROS/default_tolerance`, `/planner_frequency` for move_base's
own).  Valid names come from the move_base node itself (`move_base --print-parameter-names`), so
the tool rejects a misspelt name before any trial starts instead of move_base ignoring it.  A bare
name resolves to the first namespace that has it, in this order: TrajectoryPlannerROS, the costmaps
(both global_costmap and local_costmap, as costmap_common_params.yaml is loaded into both),
move_base's own, NavfnROS.

A trial's parameters are applied by writing two files into its directory, passed to
amcl_navigation.launch: trajectory_planner.yaml (the base file with TrajectoryPlannerROS values
replaced) and move_base_params.yaml (the base file plus move_base / NavfnROS values and costmap
overrides under global_costmap: / local_costmap:; move_base.launch loads it last, and roslaunch
merges nested dictionaries key by key, so it overrides the shipped costmap files).
"""
import collections
import difflib
import itertools
import os
import subprocess

import yaml

LOCAL_NS = 'TrajectoryPlannerROS'
COSTMAP_NS = ('global_costmap', 'local_costmap')
MOVE_BASE_NS = ''
GLOBAL_PLANNER_NS = 'NavfnROS'
# move_base copies its own controller_frequency into the local planner, so a bare
# controller_frequency must go to move_base to change anything.
_MOVE_BASE_FIRST = {'controller_frequency'}


class ParameterError(ValueError):
    """A swept name or value the tool cannot use; the message names it."""


def query_parameter_names(command=None):
    """{namespace: set(names)} from `move_base --print-parameter-names` ('' = move_base's own)."""
    command = command or ['rosrun', 'minibot3d_navigation', 'move_base', '--print-parameter-names']
    try:
        out = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             universal_newlines=True, timeout=60, check=True).stdout
    except (OSError, subprocess.SubprocessError) as e:
        raise ParameterError('cannot list move_base parameter names with `%s` (%s); is the '
                             'workspace built and devel/setup.bash sourced?'
                             % (' '.join(command), e))
    return parse_parameter_names(out)


def parse_parameter_names(text):
    names = collections.defaultdict(set)
    for line in text.splitlines():
        line = line.strip()
        if '/' in line:
            ns, name = line.rsplit('/', 1)
            names[ns].add(name)
    if not names:
        raise ParameterError('move_base --print-parameter-names printed no names')
    return dict(names)


def resolve(name, valid):
    """Name as typed -> list of (namespace, key) it sets.  Raises ParameterError if unknown."""
    if '/' in name:
        ns, key = name.rsplit('/', 1)
        ns = ns.strip('/')
        if key in valid.get(ns, ()):
            return [(ns, key)]
        raise ParameterError('unknown parameter %r' % name)
    if name in _MOVE_BASE_FIRST and name in valid.get(MOVE_BASE_NS, ()):
        return [(MOVE_BASE_NS, name)]
    if name in valid.get(LOCAL_NS, ()):
        return [(LOCAL_NS, name)]
    costmaps = [(ns, name) for ns in COSTMAP_NS if name in valid.get(ns, ())]
    if costmaps:
        return costmaps
    for ns in (MOVE_BASE_NS, GLOBAL_PLANNER_NS):
        if name in valid.get(ns, ()):
            return [(ns, name)]
    raise ParameterError('unknown parameter %r' % name)


def check_names(names, valid):
    """{name: [(ns, key)]} for every name, or one ParameterError naming every unknown one."""
    resolved, unknown = {}, []
    everything = sorted({k for keys in valid.values() for k in keys} |
                        {'%s/%s' % (ns, k) for ns, keys in valid.items() for k in keys})
    for name in names:
        try:
            resolved[name] = resolve(name, valid)
        except ParameterError:
            close = difflib.get_close_matches(name, everything, n=3)
            unknown.append('%s%s' % (name, ' (did you mean %s?)' % ', '.join(close)
                                     if close else ''))
    if unknown:
        raise ParameterError('unknown parameter name%s: %s; valid names are listed by '
                             '`rosrun minibot3d_navigation move_base --print-parameter-names`'
                             % ('s' if len(unknown) > 1 else '', '; '.join(unknown)))
    return resolved


def parse_value(text):
    """'0.5' -> 0.5, '10' -> 10, 'true' -> True, anything else -> the string (YAML scalars)."""
    text = text.strip()
    if not text:
        raise ParameterError('empty value')
    value = yaml.safe_load(text)
    if isinstance(value, (dict, list)) or value is None:
        return text
    return value


class Sweep(object):
    """One swept name: either a list of values (grid) or a range lo:hi (Optuna only)."""

    def __init__(self, name, values=None, low=None, high=None):
        self.name, self.values, self.low, self.high = name, values, low, high

    @property
    def is_range(self):
        return self.values is None

    def __repr__(self):
        return 'Sweep(%s=%s)' % (self.name, self.values if self.values is not None
                                 else '%s:%s' % (self.low, self.high))


def parse_set(spec):
    """'max_vel_x=0.1,0.5,1.0' -> Sweep; 'max_vel_x=0.1:1.0' -> a range (for --optimize)."""
    if '=' not in spec:
        raise ParameterError('--set %r: expected NAME=v1,v2,... or NAME=low:high' % spec)
    name, rhs = spec.split('=', 1)
    name = name.strip()
    if not name:
        raise ParameterError('--set %r: empty name' % spec)
    if ':' in rhs and ',' not in rhs:
        lo, hi = (parse_value(t) for t in rhs.split(':', 1))
        if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (lo, hi)) \
                or lo >= hi:
            raise ParameterError('--set %s: a range needs two numbers low < high' % spec)
        return Sweep(name, low=lo, high=hi)
    try:
        values = [parse_value(t) for t in rhs.split(',')]
    except ParameterError:
        raise ParameterError('--set %s: empty value in the list' % spec)
    if len(set(map(repr, values))) != len(values):
        raise ParameterError('--set %s: repeated value' % spec)
    return Sweep(name, values=values)


def grid(sweeps):
    """Every combination, first --set varying slowest: [OrderedDict(name -> value)]."""
    for s in sweeps:
        if s.is_range:
            raise ParameterError('--set %s=%s:%s is a range: ranges are for --optimize; give a '
                                 'list of values for a grid' % (s.name, s.low, s.high))
    names = [s.name for s in sweeps]
    return [collections.OrderedDict(zip(names, combo))
            for combo in itertools.product(*[s.values for s in sweeps])]


def _load_yaml(path):
    with open(path) as f:
        data = yaml.safe_load(f) or {}
    if not isinstance(data, dict):
        raise ParameterError('%s: expected a YAML mapping' % path)
    return data


def write_trial_files(settings, resolved, base_trajectory_planner, base_move_base_params,
                      trial_dir):
    """Writes the trial's two parameter files; returns their paths (trajectory_planner,
    move_base_params)."""
    tp = _load_yaml(base_trajectory_planner)
    mb = _load_yaml(base_move_base_params)
    tp.setdefault(LOCAL_NS, {})
    for name, value in settings.items():
        for ns, key in resolved[name]:
            if ns == LOCAL_NS:
                tp[LOCAL_NS][key] = value
            elif ns == MOVE_BASE_NS:
                mb[key] = value
            else:
                mb.setdefault(ns, {})[key] = value
    paths = (os.path.join(trial_dir, 'trajectory_planner.yaml'),
             os.path.join(trial_dir, 'move_base_params.yaml'))
    header = '# written by tune_planner for this trial: %s\n' % ', '.join(
        '%s=%s' % kv for kv in settings.items())
    for path, data in zip(paths, (tp, mb)):
        with open(path + '.tmp', 'w') as f:
            f.write(header)
            yaml.safe_dump(data, f, default_flow_style=False, sort_keys=False)
        os.replace(path + '.tmp', path)
    return paths
