"""tune_planner's ROS-free parts: parameter names and grids, per-trial YAML files, the clearance
and speed figures, results.csv, the table, the trial command lines (lock-step time), and the
driver's recording and output files.  No master, no simulator."""
import collections
import math
import os
import sys

import numpy as np
import pytest
import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src'))
from minibot3d_tuning import (  # noqa: E402
    DRIVER_NODE, cli, metrics, params, report, study)

NAMES = params.parse_parameter_names('\n'.join([
    'TrajectoryPlannerROS/max_vel_x', 'TrajectoryPlannerROS/sim_time',
    'TrajectoryPlannerROS/controller_frequency',
    'global_costmap/inflation_radius', 'local_costmap/inflation_radius',
    'NavfnROS/default_tolerance', 'NavfnROS/base_global_planner',
    '/planner_frequency', '/controller_frequency', '/base_global_planner']))


def test_bare_names_resolve_local_planner_then_costmaps_then_move_base():
    assert params.resolve('max_vel_x', NAMES) == [('TrajectoryPlannerROS', 'max_vel_x')]
    assert params.resolve('inflation_radius', NAMES) == [('global_costmap', 'inflation_radius'),
                                                         ('local_costmap', 'inflation_radius')]
    assert params.resolve('planner_frequency', NAMES) == [('', 'planner_frequency')]
    assert params.resolve('base_global_planner', NAMES) == [('', 'base_global_planner')]
    assert params.resolve('default_tolerance', NAMES) == [('NavfnROS', 'default_tolerance')]
    # move_base copies its own into the local planner: only move_base's has an effect.
    assert params.resolve('controller_frequency', NAMES) == [('', 'controller_frequency')]
    assert params.resolve('local_costmap/inflation_radius', NAMES) == [
        ('local_costmap', 'inflation_radius')]


def test_unknown_names_are_all_named_with_suggestions():
    with pytest.raises(params.ParameterError) as e:
        params.check_names(['max_vel_x', 'max_vel_xx', 'local_costmap/sim_time', 'bogus'], NAMES)
    text = str(e.value)
    assert 'max_vel_xx (did you mean' in text and 'max_vel_x' in text
    assert 'local_costmap/sim_time' in text and 'bogus' in text


def test_parse_set_and_grid_order():
    a = params.parse_set('min_vel_x=0.01,0.1')
    b = params.parse_set('max_vel_x=0.1,0.5,1')
    assert a.values == [0.01, 0.1] and b.values == [0.1, 0.5, 1]
    g = params.grid([a, b])
    assert [tuple(s.values()) for s in g] == [(0.01, 0.1), (0.01, 0.5), (0.01, 1), (0.1, 0.1),
                                            (0.1, 0.5), (0.1, 1)]
    assert params.parse_set('dwa=true,false').values == [True, False]
    r = params.parse_set('sim_time=1:3')
    assert r.is_range and (r.low, r.high) == (1, 3)
    with pytest.raises(params.ParameterError):
        params.grid([r])
    for bad in ('max_vel_x', 'max_vel_x=', 'max_vel_x=1,,2', 'max_vel_x=2:1', 'x=1,1'):
        with pytest.raises(params.ParameterError):
            params.parse_set(bad)


def test_trial_files_override_only_the_swept_values(tmp_path):
    tp = tmp_path / 'tp.yaml'
    tp.write_text('TrajectoryPlannerROS:\n  max_vel_x: 0.5\n  min_vel_x: 0.1\n')
    mb = tmp_path / 'mb.yaml'
    mb.write_text('planner_frequency: 1.0\nNavfnROS:\n  allow_unknown: true\n')
    settings = collections.OrderedDict([('max_vel_x', 1.0), ('inflation_radius', 0.5),
                                        ('planner_frequency', 2.0),
                                        ('default_tolerance', 0.2)])
    resolved = params.check_names(list(settings), NAMES)
    out = tmp_path / 'trial'
    out.mkdir()
    tp_out, mb_out = params.write_trial_files(settings, resolved, str(tp), str(mb), str(out))
    t = yaml.safe_load(open(tp_out))
    m = yaml.safe_load(open(mb_out))
    assert t == {'TrajectoryPlannerROS': {'max_vel_x': 1.0, 'min_vel_x': 0.1}}
    assert m == {'planner_frequency': 2.0, 'NavfnROS': {'allow_unknown': True,
                                                        'default_tolerance': 0.2},
                 'global_costmap': {'inflation_radius': 0.5},
                 'local_costmap': {'inflation_radius': 0.5}}


def _wall_map():
    # 4 m x 4 m at 0.05 m, origin (-2, -2); a wall filling x >= 1.0.
    occ = np.zeros((80, 80), bool)
    occ[:, 60:] = True
    return metrics.GridMap(occ, 0.05, (-2.0, -2.0))


def test_clearance_is_from_the_footprint_outline_to_the_obstacle_edge():
    grid = _wall_map()
    foot = [[-0.12, -0.115], [-0.12, 0.115], [0.12, 0.115], [0.12, -0.115]]
    # Facing the wall: front edge at x = 0.12 + 0.5, wall edge at x = 1.0 -> 0.38 m.
    traj = dict(t=np.array([0.0]), x=np.array([0.5]), y=np.array([0.0]), yaw=np.array([0.0]))
    assert metrics.min_clearance(traj, grid, foot) == pytest.approx(0.38, abs=0.01)
    # Side-on (yaw 90 deg): the side edge at 0.5 + 0.115.
    traj['yaw'] = np.array([math.pi / 2])
    assert metrics.min_clearance(traj, grid, foot) == pytest.approx(0.385, abs=0.01)
    # Overlapping the wall: <= 0.
    traj['x'] = np.array([0.95])
    assert metrics.min_clearance(traj, grid, foot) <= 0.0


def test_path_length_and_speeds():
    t = np.arange(0, 10.01, 0.05)
    traj = dict(t=t, x=0.3 * t, y=np.zeros_like(t), yaw=np.zeros_like(t))
    assert metrics.path_length(traj) == pytest.approx(3.0, abs=1e-6)
    assert metrics.peak_speed(traj) == pytest.approx(0.3, abs=1e-6)
    m = metrics.trial_metrics(traj, _wall_map(), [[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]],
                              (3.1, 0.0), 10.0)
    assert m['mean_speed'] == pytest.approx(0.3, abs=1e-6)
    assert m['goal_error'] == pytest.approx(0.1, abs=1e-6)


def test_load_map_reads_the_shipped_map():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
    grid = metrics.load_map(os.path.join(root, 'maps', 'default_world.yaml'))
    # The spawn pose (-3, -1.5) is free, with the living room's walls around it.
    d = float(grid.distance(np.array([-3.0]), np.array([-1.5]))[0])
    assert 0.4 < d < 3.0


def test_results_file_is_rewritten_atomically_and_resumes(tmp_path):
    path = str(tmp_path / 'results.csv')
    r = study.ResultsFile(path)
    r.add(collections.OrderedDict(key='a', status='reached', time_to_goal='10'))
    r.add(collections.OrderedDict(key='b', status='error', reason='x'))
    r.add(collections.OrderedDict(key='c', status='timeout', extra='1'))
    assert not os.path.exists(path + '.tmp')
    again = study.ResultsFile(path)
    assert list(again.rows) == ['a', 'b', 'c']
    assert again.finished('a') and again.finished('c')
    assert not again.finished('b')  # errors (stack never came up) are rerun
    assert again.rows['c']['extra'] == '1'


def test_table_and_plot_say_why_a_setting_failed(tmp_path):
    base = dict(collisions='0', min_clearance='0.1', path_length='10', mean_speed='0.2',
                peak_speed='0.5', goal_error='0.1', wall_time='30', repeat='1', reason='')
    rows = [dict(base, max_vel_x='0.5', status='reached', time_to_goal='50'),
            dict(base, max_vel_x='0.5', status='reached', time_to_goal='52'),
            dict(base, max_vel_x='1.0', status='aborted', time_to_goal='',
                 reason='goal 2 aborted: controller stuck'),
            dict(base, max_vel_x='1.0', status='reached', time_to_goal='40', collisions='2'),
            dict(base, max_vel_x='2.0', status='error', time_to_goal='', collisions='',
                 min_clearance='', path_length='', reason='the stack exited')]
    table = report.markdown_table(rows, ['max_vel_x'])
    lines = table.strip().splitlines()
    assert lines[0].startswith('| max_vel_x | time to goal')
    assert '51.0 ± 1.4 s' in lines[2] and '2/2' in lines[2]
    assert 'controller stuck' in lines[3] and 'hit an obstacle: 2 collisions' in lines[3]
    assert '1/2' in lines[3]
    assert 'never reached, error: the stack exited' in lines[4]
    report.plot_time_vs_params(rows, ['max_vel_x'], str(tmp_path / 't.png'))
    assert (tmp_path / 't.png').stat().st_size > 1000


def test_optuna_space_from_lists_and_ranges():
    space = study.optuna_space([params.parse_set('max_vel_x=0.1,0.5,1.0'),
                                params.parse_set('vx_samples=5,20'),
                                params.parse_set('sim_time=1:3'),
                                params.parse_set('dwa=true,false')])
    assert space == [('max_vel_x', 'float', (0.1, 1.0)), ('vx_samples', 'int', (5, 20)),
                     ('sim_time', 'int', (1, 3)), ('dwa', 'categorical', [True, False])]


def test_optimize_records_trials_and_resumes_from_its_storage(tmp_path, monkeypatch):
    """run_optuna with a stand-in for the simulator: time = 10 / max_vel_x, and a collision
    above 0.8 m/s.  The study lands in SQLite; a second call with the same storage only tops
    the study up to --trials."""
    import threading
    foot = [[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]]
    tp, mb = tmp_path / 'tp.yaml', tmp_path / 'mb.yaml'
    tp.write_text('TrajectoryPlannerROS: {max_vel_x: 0.5}\n')
    mb.write_text('planner_frequency: 1.0\n')
    setup = study.Setup(str(tmp_path), str(tp), str(tp), str(tp), '0,0,0', '1,0', 2.0, 60.0,
                        str(tp), str(mb), foot, {'max_vel_x': [('TrajectoryPlannerROS',
                                                                'max_vel_x')]})

    def fake_run_trial(setup, spec, registry, stop):
        v = spec.settings['max_vel_x']
        row = collections.OrderedDict(key=spec.key, trial=spec.name, max_vel_x=v,
                                      repeat=spec.repeat)
        row.update(status='reached', time_to_goal=round(10.0 / v, 2),
                   collisions=1 if v > 0.8 else 0)
        return row

    monkeypatch.setattr(study, 'run_trial', fake_run_trial)
    results = study.ResultsFile(str(tmp_path / 'results.csv'))
    storage = 'sqlite:///%s' % (tmp_path / 'optuna.db')
    sweeps = [params.parse_set('max_vel_x=0.1:1.0')]
    st = study.run_optuna(setup, sweeps, 2, results, 1, None, threading.Event(), storage, 's',
                          6, progress=False)
    assert len(st.trials) == 6 and len(results.rows) == 12
    feasible = [t for t in st.trials if t.user_attrs['constraint'] <= 0]
    assert all(t.params['max_vel_x'] <= 0.8 for t in feasible)
    st = study.run_optuna(setup, sweeps, 2, results, 1, None, threading.Event(), storage, 's',
                          8, progress=False)
    assert len(st.trials) == 8


def _setup(tmp_path, **kw):
    foot = [[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]]
    tp = tmp_path / 'tp.yaml'
    tp.write_text('TrajectoryPlannerROS: {max_vel_x: 0.5}\n')
    return study.Setup(str(tmp_path), str(tp), str(tp), str(tp), '-3,-1.5,0', '-2.1,0.6 1,2',
                       kw.pop('rtf', 0.0), 300.0, str(tp), str(tp), foot, {}, **kw)


def test_trials_run_on_lockstep_time_as_fast_as_possible_by_default():
    args = cli.build_parser().parse_args([])
    assert args.lockstep and cli.real_time_factor(args) == 0.0
    args = cli.build_parser().parse_args(['--rtf', '2'])
    assert args.lockstep and cli.real_time_factor(args) == 2.0
    # Free-running: a real-time factor of its own, where 0 would starve the nodes.
    args = cli.build_parser().parse_args(['--no-lockstep'])
    assert not args.lockstep and cli.real_time_factor(args) == cli.DEFAULT_FREE_RTF == 3.0
    with pytest.raises(cli.UsageError):
        cli.real_time_factor(cli.build_parser().parse_args(['--no-lockstep', '--rtf', '0']))
    with pytest.raises(cli.UsageError):
        cli.real_time_factor(cli.build_parser().parse_args(['--rtf', '-1']))


def test_stack_requests_lockstep_with_the_driver_as_a_participant(tmp_path):
    setup = _setup(tmp_path)
    spec = study.TrialSpec({'max_vel_x': 0.5}, 1, setup)
    cmd = study.stack_command(setup, spec, 'tp.yaml', 'mb.yaml')
    assert cmd[:3] == ['roslaunch', 'minibot3d_navigation', 'amcl_navigation.launch']
    args = dict(a.split(':=', 1) for a in cmd[3:])
    assert args['lockstep'] == 'true' and args['real_time_factor'] == '0'
    # Every participant is listed, so sim time starts only once all have joined: the driver under
    # the very name it takes.
    assert args['lockstep_participants'].split() == ['/amcl', '/move_base', '/' + DRIVER_NODE]
    drive = study.driver_command(setup, str(tmp_path))
    assert drive[1:3] == ['-m', 'minibot3d_tuning.driver'] and '--lockstep' in drive
    from minibot3d_tuning import driver
    assert driver.NODE_NAME == DRIVER_NODE
    assert setup.wall_budget() < 1e4  # rtf 0 is not a division by zero

    free = _setup(tmp_path, rtf=3.0, lockstep=False)
    args = dict(a.split(':=', 1) for a in study.stack_command(free, spec, 'a', 'b')[3:])
    assert args['lockstep'] == 'false' and 'lockstep_participants' not in args
    assert args['real_time_factor'] == '3'
    assert '--no-lockstep' in study.driver_command(free, str(tmp_path))
    # Lock-step and free-running results are different trials (not resumed from one another).
    assert free.config_hash() != _setup(tmp_path, rtf=3.0).config_hash()


def test_a_trial_whose_driver_was_dropped_from_the_loop_is_run_again(tmp_path, monkeypatch):
    from minibot3d_tuning import driver
    assert driver.DROPPED == study.DRIVER_DROPPED
    setup = _setup(tmp_path)
    spec = study.TrialSpec({'max_vel_x': 0.5}, 1, setup)
    outcomes = [(dict(status='error', reason='dropped'), study.DRIVER_DROPPED),
                (dict(status='reached', reason=''), 0)]
    monkeypatch.setattr(study, '_run_trial_once', lambda *a: outcomes.pop(0))
    assert study.run_trial(setup, spec, None, None)['status'] == 'reached' and not outcomes
    # Any other error (the stack did not come up) is not retried here.
    outcomes = [(dict(status='error', reason='the stack exited'), 3),
                (dict(status='reached', reason=''), 0)]
    assert study.run_trial(setup, spec, None, None)['status'] == 'error'


def _truth(t, x, y=0.0):
    from nav_msgs.msg import Odometry
    import rospy
    m = Odometry()
    m.header.stamp = rospy.Time.from_sec(t)
    m.pose.pose.position.x, m.pose.pose.position.y = x, y
    m.pose.pose.orientation.w = 1.0
    return m


def test_driver_records_the_truth_itself_and_writes_whole_files(tmp_path, monkeypatch):
    """The driver keeps what its subscriber callbacks got (no bag read back while another process
    still writes it) and writes trajectory.csv, then result.json, each as a temp file renamed
    into place: whoever sees result.json sees the whole trajectory."""
    import json
    from move_base_msgs.msg import MoveBaseActionResult
    from geometry_msgs.msg import PoseStamped
    from minibot3d_tuning import driver
    import rospy
    rec = driver.Recorder()
    for i in range(0, 1001):  # 10 s of ground truth at 100 Hz, 0.5 m/s along x
        rec.on_truth(_truth(i * 0.01, 0.005 * i))
    goal = PoseStamped()
    goal.header.stamp = rospy.Time.from_sec(1.0)
    rec.on_goal(goal)
    res = MoveBaseActionResult()
    res.header.stamp = rospy.Time.from_sec(9.0)
    res.status.status = 3
    rec.on_result(res)
    accepted, results, rows = rec.snapshot()
    assert len(rows) == 201 and rows[1][0] == pytest.approx(0.05)  # every RECORD_PERIOD
    _, route = driver.parse_route('0,0,0', '4,0')
    result, rows = driver.summarize(dict(status='reached', reason='', goals_reached=1), route,
                                    accepted, results, rows, 0.9, 2, 2, 0.5)
    assert result['time_to_goal'] == pytest.approx(8.0) and result['collisions'] == 0
    assert result['achieved_rtf'] == pytest.approx(16.0)

    replaced = []
    real_replace = os.replace

    def spying_replace(src, dst):
        # Nothing is visible under its final name before it is complete.
        assert not os.path.exists(dst)
        replaced.append(os.path.basename(dst))
        real_replace(src, dst)
    monkeypatch.setattr(driver.os, 'replace', spying_replace)
    driver.write_outputs(str(tmp_path), result, rows)
    monkeypatch.undo()
    assert replaced == ['trajectory.csv', 'result.json']
    assert sorted(os.listdir(str(tmp_path))) == ['result.json', 'trajectory.csv']  # no temp files
    traj = metrics.read_trajectory(str(tmp_path / 'trajectory.csv'))
    assert len(traj['t']) == len(rows) == 163  # 0.95 .. 9.05 s
    assert traj['t'][0] == pytest.approx(0.95) and traj['t'][-1] == pytest.approx(9.05)
    assert json.load(open(str(tmp_path / 'result.json')))['time_to_goal'] == pytest.approx(8.0)


def test_driver_leaves_no_result_when_writing_fails(tmp_path, monkeypatch):
    from minibot3d_tuning import driver
    _, route = driver.parse_route('0,0,0', '4,0')
    result, rows = driver.summarize(dict(status='reached', reason='', goals_reached=1), route,
                                    [1.0], [(2.0, 3)], [(1.0, 0.0, 0.0, 0.0), (2.0, 1.0, 0.0, 0.0)],
                                    1.0, 0, 0, 1.0)

    def full_disk(*a, **kw):
        raise OSError(28, 'No space left on device')
    monkeypatch.setattr(driver.json, 'dumps', full_disk)
    with pytest.raises(OSError):
        driver.write_outputs(str(tmp_path), result, rows)
    assert os.listdir(str(tmp_path)) == ['trajectory.csv']  # no result.json, no temp file


def test_driver_does_not_record_with_rosbag():
    """The driver records the trajectory itself: reading a bag that `rosbag record` may still be
    writing (run.bag.active) loses its end."""
    import ast
    import inspect
    from minibot3d_tuning import driver
    source = inspect.getsource(driver)
    imported = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            imported.update(a.name.split('.')[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            imported.add(node.module.split('.')[0])
    assert not imported & {'rosbag', 'subprocess'}
    assert 'rosbag' not in source
