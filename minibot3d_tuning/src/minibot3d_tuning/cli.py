"""rosrun minibot3d_tuning tune_planner: the trajectory-planner tuning experiment as a
reproducible study.  Every trial is a full headless stack (simulator + map_server + amcl +
move_base) on its own ROS master port, on lock-step time as fast as it goes (--rtf 0; the same
command gives the same times), driven through a route.

  tune_planner [--set NAME=v1,v2,...]... [--repeats 3] [--jobs 2] [--rtf R] [--no-lockstep]
               [--out DIR]
               [--world W] [--map M] [--start X,Y,YAW] [--goals "x,y x,y ..."] [--timeout S]
  tune_planner --optimize [--set NAME=lo:hi]... [--trials 30] [--storage URL] [--sampler-seed N]

Without --set it runs six settings: min_vel_x in {0.01, 0.1} x max_vel_x in
{0.1, 0.5, 1.0}.  Writes DIR/results.csv, DIR/results.md (also printed), DIR/time_to_goal.png and
DIR/trajectories.png.  Exit status: 0 every trial reached the goal without a collision, 1 some did
not, 2 bad arguments (e.g. an unknown parameter name, checked before any trial starts), 130
interrupted (rerun the same command to resume).
"""
import argparse
import math
import os
import signal
import subprocess
import sys
import threading
import time

import yaml

from . import params, processes, report, study

DEFAULT_SETS = ['min_vel_x=0.01,0.1', 'max_vel_x=0.1,0.5,1.0']
DEFAULT_GOALS = '-2.1,0.6 -0.3,2.0 0.45,0.6 2.5,-1.0'
DEFAULT_START = '-3.0,-1.5,0.0'
# Under lock-step time (the default) the answer does not depend on the real-time factor: 0, as
# fast as the participants allow.
DEFAULT_RTF = 0.0
# --no-lockstep (free-running): the fastest real-time factor at which time-to-goal and collisions
# agreed with real time within the noise between repeats, with two trials in parallel on 2 cores
# (README, "Tuning").
DEFAULT_FREE_RTF = 3.0


class UsageError(Exception):
    pass


def _package_paths():
    import rospkg
    rp = rospkg.RosPack()
    shared = rp.get_path('minibot3d_bringup')
    sim = rp.get_path('minibot3d_sim')
    return dict(config=os.path.join(shared, 'config'), maps=os.path.join(shared, 'maps'),
                world=os.path.join(sim, 'worlds', 'default.world'))


def _pose(text, n, what):
    try:
        v = [float(t) for t in text.split(',')]
    except ValueError:
        v = []
    if len(v) not in n:
        raise UsageError('%s %r: expected %s comma-separated numbers' % (
            what, text, ' or '.join(map(str, n))))
    return v


def build_parser():
    p = argparse.ArgumentParser(
        prog='tune_planner', description=__doc__.split('\n')[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog='Parameter names: bare (max_vel_x, sim_time, inflation_radius, planner_frequency) '
        'or qualified (local_costmap/inflation_radius, NavfnROS/default_tolerance); the list is '
        '`rosrun minibot3d_navigation move_base --print-parameter-names`.')
    p.add_argument('--set', action='append', metavar='NAME=V1,V2',
                   help='a swept parameter and its values (repeatable; the grid is the product). '
                   'NAME=LOW:HIGH gives a range for --optimize. Default: %s' %
                   ' '.join(DEFAULT_SETS))
    p.add_argument('--world', help='simulator world (default: minibot3d_sim default.world)')
    p.add_argument('--map', help="map_server YAML for amcl and move_base (default: the shipped "
                   "map for the default world, else the world's rendered ground-truth map)")
    p.add_argument('--start', default=DEFAULT_START,
                   help='spawn pose X,Y,YAW (default %(default)s)')
    p.add_argument('--goals', default=DEFAULT_GOALS,
                   help='route, "x,y[,yaw] ..." in the map frame; a goal without yaw faces along '
                   'the leg to it (default: "%(default)s")')
    p.add_argument('--repeats', type=int, default=3,
                   help='runs per setting, lidar noise seeds SEED..SEED+N-1 (default %(default)s)')
    p.add_argument('--seed', type=int, default=1, help='first noise seed (default %(default)s)')
    p.add_argument('--jobs', type=int, default=2, help='trials in parallel (default %(default)s)')
    p.add_argument('--rtf', type=float, default=None,
                   help='simulator real-time factor: 0 runs as fast as the lock-step '
                   'participants allow (default %g); N > 0 paces sim time at N x wall time. '
                   'With --no-lockstep the default is %g and 0 is not accepted (the nodes could '
                   'not keep up)' % (DEFAULT_RTF, DEFAULT_FREE_RTF))
    p.add_argument('--no-lockstep', dest='lockstep', action='store_false',
                   help='free-running stacks (the tool before lock-step time): nodes take '
                   'messages as they come, so results vary with the machine\'s load')
    p.add_argument('--timeout', type=float, default=300.0,
                   help='SIM seconds a trial may take for the whole route, from the first goal '
                   '(default %(default)s); a trial is also killed if it has no result after '
                   '180 + 3 x timeout / rtf + 30 WALL seconds (rtf 0 counts as 3)')
    p.add_argument('--out', default='tune_planner_out',
                   help='study directory (default %(default)s)')
    p.add_argument('--trajectory-planner', help='base TrajectoryPlannerROS YAML '
                   '(default config/trajectory_planner.yaml)')
    p.add_argument('--move-base-params', help='base move_base YAML (default '
                   'config/move_base_params.yaml)')
    p.add_argument('--optimize', action='store_true',
                   help='search the --set space with Optuna TPE: minimise the mean time to goal '
                   'over --repeats runs subject to zero collisions and every run reaching the goal')
    p.add_argument('--trials', type=int, default=30,
                   help='--optimize: stop once the study holds this many complete trials, counting '
                   "every worker's (default %(default)s)")
    p.add_argument('--storage', help='--optimize: Optuna storage URL, e.g. '
                   'postgresql://user@host/db for workers on several machines '
                   '(default sqlite:///OUT/optuna.db)')
    p.add_argument('--study-name', default='tune_planner', help='--optimize: Optuna study name')
    p.add_argument('--sampler-seed', type=int, help='--optimize: seed of the TPE sampler (default: '
                   '--seed). Give each worker sharing a --storage its own: workers with the same '
                   'one suggest the same settings')
    p.add_argument('--report-only', action='store_true',
                   help='rewrite the table and plots from OUT/results.csv; run nothing')
    p.add_argument('--no-progress', action='store_true', help='no progress bar')
    return p


def real_time_factor(args):
    """The trials' real-time factor: --rtf, else 0 (as fast as possible) on lock-step time and
    DEFAULT_FREE_RTF with --no-lockstep, where 0 is refused."""
    rtf = args.rtf
    if rtf is None:
        rtf = DEFAULT_RTF if args.lockstep else DEFAULT_FREE_RTF
    if not (rtf >= 0 and math.isfinite(rtf)):
        raise UsageError('--rtf must be >= 0 (0: as fast as possible)')
    if rtf == 0 and not args.lockstep:
        raise UsageError('--rtf 0 needs lock-step time: free-running, as fast as possible '
                         'starves the nodes (drop --no-lockstep, or give --rtf > 0)')
    return float(rtf)


def prepare(args):
    """Checks every argument (parameter names included) and returns (setup, sweeps)."""
    args.rtf = real_time_factor(args)
    if args.repeats < 1 or args.jobs < 1 or args.timeout <= 0 or args.trials < 1:
        raise UsageError('--repeats, --jobs, --trials and --timeout must be positive')
    start = _pose(args.start, (3,), '--start')
    goals = args.goals.split()
    if not goals:
        raise UsageError('--goals: no goal given')
    for g in goals:
        _pose(g, (2, 3), '--goals')
    sweeps = [params.parse_set(s) for s in (args.set or DEFAULT_SETS)]
    names = [s.name for s in sweeps]
    if len(set(names)) != len(names):
        raise UsageError('--set: a name is given twice')
    resolved = params.check_names(names, params.query_parameter_names())
    if not args.optimize:
        params.grid(sweeps)  # rejects ranges

    paths = _package_paths()
    world = os.path.abspath(args.world or paths['world'])
    tp = args.trajectory_planner or os.path.join(paths['config'], 'trajectory_planner.yaml')
    mb = args.move_base_params or os.path.join(paths['config'], 'move_base_params.yaml')
    for what, path in (('--world', world), ('--trajectory-planner', tp),
                       ('--move-base-params', mb)) + ((('--map', args.map),) if args.map else ()):
        if not os.path.isfile(path):
            raise UsageError('%s %s: no such file' % (what, path))
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    truth = os.path.join(out, 'ground_truth_map')
    if not os.path.exists(truth + '.yaml'):
        rc = subprocess.run(['rosrun', 'minibot3d_sim', 'render_world_map', world, truth],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            universal_newlines=True)
        if rc.returncode != 0:
            raise UsageError('cannot render the ground-truth map of %s: %s' % (world, rc.stdout))
    if args.map:
        map_yaml = args.map
    elif os.path.samefile(world, paths['world']):
        map_yaml = os.path.join(paths['maps'], 'default_world.yaml')
    else:
        map_yaml = truth + '.yaml'
    with open(os.path.join(paths['config'], 'costmap_common_params.yaml')) as f:
        common = yaml.safe_load(f)
    footprint = common.get('footprint')
    if not footprint:
        r = float(common.get('robot_radius', 0.2))
        footprint = [[r * math.cos(a * math.pi / 8), r * math.sin(a * math.pi / 8)]
                     for a in range(16)]
    setup = study.Setup(out, world, map_yaml, truth + '.yaml', ','.join('%g' % v for v in start),
                        ' '.join(goals), args.rtf, args.timeout, tp, mb, footprint, resolved,
                        seed=args.seed, lockstep=args.lockstep)
    return setup, sweeps


def write_report(setup, rows, names, title):
    from . import metrics
    table = report.markdown_table(rows, names, title)
    path = os.path.join(setup.out_dir, 'results.md')
    with open(path + '.tmp', 'w') as f:
        f.write(table)
    os.replace(path + '.tmp', path)
    if rows:
        report.plot_time_vs_params(rows, names, os.path.join(setup.out_dir, 'time_to_goal.png'),
                                   setup.timeout)
        start = [float(v) for v in setup.start.split(',')]
        report.plot_trajectories(
            rows, names, metrics.load_map(setup.truth_map_yaml),
            lambda r: os.path.join(setup.out_dir, 'trials', r['trial']), setup.goals, start,
            os.path.join(setup.out_dir, 'trajectories.png'))
    return table


def _raise_interrupt(signum, frame):
    raise KeyboardInterrupt()


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        setup, sweeps = prepare(args)
    except (UsageError, params.ParameterError) as e:
        print('tune_planner: %s' % e, file=sys.stderr)
        return 2
    names = [s.name for s in sweeps]
    results = study.ResultsFile(os.path.join(setup.out_dir, 'results.csv'))
    registry = processes.Registry()
    stop = threading.Event()
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGTERM, _raise_interrupt)
    t0 = time.monotonic()
    specs = []
    try:
        if args.optimize:
            storage = args.storage or 'sqlite:///%s' % os.path.join(setup.out_dir, 'optuna.db')
            if not args.report_only:
                st = study.run_optuna(setup, sweeps, args.repeats, results, args.jobs, registry,
                                      stop, storage, args.study_name, args.trials,
                                      progress=not args.no_progress,
                                      sampler_seed=args.sampler_seed)
            else:
                import optuna
                st = optuna.load_study(study_name=args.study_name, storage=storage)
            rows = [r for r in results.rows.values() if r['key'].startswith('optuna')]
        else:
            specs = [study.TrialSpec(s, r, setup) for r in range(1, args.repeats + 1)
                     for s in params.grid(sweeps)]
            if not args.report_only:
                study.run_grid(setup, specs, results, args.jobs, registry, stop,
                               progress=not args.no_progress)
            keys = {s.key for s in specs}
            order = {s.key: i for i, s in enumerate(
                sorted(specs, key=lambda s: (list(map(str, s.settings.values())), s.repeat)))}
            rows = sorted((r for r in results.rows.values() if r['key'] in keys),
                          key=lambda r: order[r['key']])
            # Grid order of the settings (first --set slowest), not completion order.
            grid_order = {tuple(map(str, s.values())): i for i, s in enumerate(params.grid(sweeps))}
            rows.sort(key=lambda r: (grid_order.get(tuple(str(r.get(n, '')) for n in names), 0),
                                     int(r['repeat'])))
    except KeyboardInterrupt:
        stop.set()
        registry.stop_all()
        print('\ntune_planner: interrupted; %d trials are in %s — rerun the same command to '
              'resume' % (len(results.rows), results.path), file=sys.stderr)
        return 130
    wall = time.monotonic() - t0
    title = ('Time to goal over the route %s from %s (%s, real-time factor %g%s; %d trial%s, '
             '%.0f s wall with --jobs %d)' % (
                 setup.goals, setup.start, 'lock-step' if setup.lockstep else 'free-running',
                 setup.rtf, ' = as fast as possible' if setup.rtf == 0 else '', len(rows),
                 's' if len(rows) != 1 else '', wall, args.jobs))
    print(write_report(setup, rows, names, title))
    if args.optimize:
        feasible = [t for t in st.trials if t.value is not None and
                    t.user_attrs.get('constraint', 1.0) <= 0]
        if feasible:
            best = min(feasible, key=lambda t: t.value)
            print('best feasible (optuna trial %d): %s -> mean time to goal %.1f sim s' % (
                best.number, ', '.join('%s=%s' % kv for kv in best.user_attrs.get(
                    'settings', best.params).items()), best.value))
        else:
            print('no feasible trial yet (every one collided or missed the goal)')
    print('results: %s, plots: %s, %s' % (results.path,
                                          os.path.join(setup.out_dir, 'time_to_goal.png'),
                                          os.path.join(setup.out_dir, 'trajectories.png')))
    good = rows and all(r['status'] == 'reached' and str(r['collisions']) == '0' for r in rows)
    return 0 if good else 1
