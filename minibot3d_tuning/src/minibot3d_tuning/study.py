"""Trials and studies: one trial = one headless stack (simulator + map_server + amcl + move_base,
amcl_navigation.launch) on a ROS master of its own, driven through the route by driver.py.

By default the stack runs on lock-step time (lockstep:=true): the simulator advances sim time only
once amcl, move_base and the driver (all listed in lockstep_participants, so all three join before
time starts) have done their work for the current instant and received every message sent to
them.  A trial's figures then do not depend on the machine's load or the real-time factor, which
defaults to 0 (as fast as the participants allow); the same command gives the same times.
--no-lockstep gives the free-running stack paced at a real-time factor instead.

A grid study runs every (setting, repeat) that results.csv does not already hold, --jobs at a
time; results.csv is rewritten (temp file + rename) after every trial, so an interrupted study
resumes where it stopped.  A trial is identified by its settings, its repeat and a hash of
everything else that changes its outcome (world, maps, start, goals, real-time factor, timeout,
base parameter files, lock-step or not), so changing any of these in the same --out directory
reruns the trials instead of mixing old results in.  Rows with status `error` (the stack did not
come up) are rerun.

--optimize instead asks Optuna's TPE sampler for settings, runs --repeats trials of each and
reports the mean time-to-goal, with the number of collisions plus unreached runs as a constraint
(feasible when 0); trials that miss the route count the timeout as their time.
"""
import collections
import csv
import hashlib
import json
import os
import shutil
import sys
import threading
import time
from concurrent import futures

from minibot3d_testing import CoreError

from . import DRIVER_NODE, metrics, params, processes

RESULT_FIELDS = ['status', 'reached', 'time_to_goal', 'path_length', 'collisions',
                 'min_clearance', 'mean_speed', 'peak_speed', 'goal_error', 'goals_reached',
                 'goals', 'sim_elapsed', 'wall_time', 'achieved_rtf', 'reason']
FINISHED = ('reached', 'aborted', 'timeout')


class Interrupted(Exception):
    """The study is being stopped (Ctrl-C / SIGTERM); the trial is not recorded."""


class Setup(object):
    """Everything a trial needs besides its settings; fixed for a study."""

    def __init__(self, out_dir, world, map_yaml, truth_map_yaml, start, goals, rtf, timeout,
                 base_trajectory_planner, base_move_base_params, footprint, resolved,
                 ready_timeout=180.0, seed=1, lockstep=True):
        self.out_dir = os.path.abspath(out_dir)
        self.world, self.map_yaml = os.path.abspath(world), os.path.abspath(map_yaml)
        self.truth_map_yaml = os.path.abspath(truth_map_yaml)
        self.start, self.goals = start, goals
        self.rtf, self.timeout = float(rtf), float(timeout)
        self.base_trajectory_planner = os.path.abspath(base_trajectory_planner)
        self.base_move_base_params = os.path.abspath(base_move_base_params)
        self.footprint = footprint
        self.resolved = resolved
        self.ready_timeout = ready_timeout
        self.seed = int(seed)
        self.lockstep = bool(lockstep)
        self._truth_map = None
        self._map_lock = threading.Lock()

    def truth_map(self):
        with self._map_lock:
            if self._truth_map is None:
                self._truth_map = metrics.load_map(self.truth_map_yaml)
            return self._truth_map

    def config_hash(self):
        h = hashlib.sha1()
        for part in (self.world, self.map_yaml, self.start, self.goals, repr(self.rtf),
                     repr(self.timeout), repr(self.seed)) + (('free-running',) if not
                                                            self.lockstep else ()):
            h.update(part.encode() + b'\0')
        for path in (self.base_trajectory_planner, self.base_move_base_params, self.world):
            with open(path, 'rb') as f:
                h.update(f.read())
        return h.hexdigest()[:8]

    def goal_xy(self):
        last = self.goals.split()[-1].split(',')
        return float(last[0]), float(last[1])

    def wall_budget(self):
        """Wall seconds a trial may take before it is killed: startup, then the sim-time budget
        at a third of the requested real-time factor (at real time when it is 0, as fast as
        possible), then the teardown."""
        return self.ready_timeout + 3.0 * self.timeout / (self.rtf if self.rtf > 0 else 3.0) + 30.0


def settings_slug(settings):
    return ','.join('%s=%s' % (k.replace('/', '.'), v) for k, v in settings.items()) or 'base'


class TrialSpec(object):
    def __init__(self, settings, repeat, setup, prefix=''):
        self.settings = collections.OrderedDict(settings)
        self.repeat = repeat
        self.seed = setup.seed + repeat - 1
        slug = settings_slug(self.settings)
        self.key = '%s%s|r%d|%s' % (prefix, slug, repeat, setup.config_hash())
        digest = hashlib.sha1(self.key.encode()).hexdigest()[:6]
        self.name = '%s%s_r%d_%s' % (prefix, slug.replace('=', '').replace(',', '_')[:80],
                                     repeat, digest)


# Nodes that join the lock-step loop before sim time starts (so it starts at the same point in
# every run): the stack's two participants and the trial's driver.
LOCKSTEP_PARTICIPANTS = ['/amcl', '/move_base', '/' + DRIVER_NODE]


def stack_command(setup, spec, trajectory_planner_yaml, move_base_params_yaml):
    """roslaunch command line of a trial's stack (run with the trial's ROS_MASTER_URI)."""
    sx, sy, syaw = setup.start.split(',')
    cmd = ['roslaunch', 'minibot3d_navigation', 'amcl_navigation.launch',
           'world:=%s' % setup.world, 'map_file:=%s' % setup.map_yaml,
           'x:=%s' % sx, 'y:=%s' % sy, 'yaw:=%s' % syaw,
           'real_time_factor:=%g' % setup.rtf, 'seed:=%d' % spec.seed,
           'trajectory_planner:=%s' % trajectory_planner_yaml,
           'move_base_params:=%s' % move_base_params_yaml]
    if setup.lockstep:
        cmd += ['lockstep:=true', 'lockstep_participants:=%s' % ' '.join(LOCKSTEP_PARTICIPANTS)]
    else:
        cmd += ['lockstep:=false']
    return cmd


def driver_command(setup, trial_dir):
    """Command line of a trial's driver (driver.py, run with the trial's ROS_MASTER_URI)."""
    return [sys.executable, '-m', 'minibot3d_tuning.driver', '--dir=' + trial_dir,
            '--start=' + setup.start, '--goals=' + setup.goals, '--timeout=%g' % setup.timeout,
            '--ready-timeout=%g' % setup.ready_timeout,
            '--lockstep' if setup.lockstep else '--no-lockstep']


# The driver's exit status when the simulator dropped it from the lock-step loop (it did not
# answer within ~lockstep_timeout wall seconds: a starved process on a loaded machine).
DRIVER_DROPPED = 4


def run_trial(setup, spec, registry, stop, attempts=3):
    """Runs one trial; returns its results.csv row, or raises Interrupted.  A trial whose driver
    the simulator dropped from the lock-step loop is run again (a lock-step trial's figures do not
    depend on how often it was tried)."""
    for attempt in range(attempts):
        row, driver_status = _run_trial_once(setup, spec, registry, stop)
        if not (row['status'] == 'error' and driver_status == DRIVER_DROPPED):
            return row
        if attempt + 1 < attempts:
            from tqdm import tqdm
            tqdm.write('%s r%d: %s; running it again' % (settings_slug(spec.settings), spec.repeat,
                                                          row['reason']), file=sys.stderr)
    return row


def _run_trial_once(setup, spec, registry, stop):
    if stop.is_set():
        raise Interrupted()
    trial_dir = os.path.join(setup.out_dir, 'trials', spec.name)
    if os.path.isdir(trial_dir):
        shutil.rmtree(trial_dir)
    os.makedirs(trial_dir)
    tp_yaml, mb_yaml = params.write_trial_files(
        spec.settings, setup.resolved, setup.base_trajectory_planner,
        setup.base_move_base_params, trial_dir)
    ros_log = os.path.join(trial_dir, 'ros_log')
    env = dict(os.environ, ROS_LOG_DIR=ros_log)
    env[processes.MARKER] = setup.out_dir
    # The driver runs as `python3 -m minibot3d_tuning.driver`, also from the source tree.
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env['PYTHONPATH'] = os.pathsep.join([here] + [p for p in env.get('PYTHONPATH', '').split(
        os.pathsep) if p])
    launch = stack_command(setup, spec, tp_yaml, mb_yaml)
    drive = driver_command(setup, trial_dir)
    wall0 = time.monotonic()
    core = stack = driver = None
    overran = stack_died = False
    no_master = None
    try:
        core = processes.Core(env, ros_log, registry)
        core.start()
        stack = processes.Group(launch, core.env, os.path.join(trial_dir, 'stack.log'), registry)
        driver = processes.Group(drive, core.env, os.path.join(trial_dir, 'driver.log'),
                                 registry)
        deadline = wall0 + setup.wall_budget()
        while driver.wait(0.5) is None:
            if stop.is_set():
                raise Interrupted()
            if not stack.running():
                stack_died = True
                driver.wait(5.0)
                break
            if time.monotonic() > deadline:
                overran = True
                break
    except CoreError as e:
        no_master = str(e)
    finally:
        for g in (driver, stack, core):
            if g is not None:
                g.stop()
    wall = time.monotonic() - wall0
    driver_status = driver.proc.returncode if driver is not None else None

    row = collections.OrderedDict(key=spec.key, trial=spec.name)
    row.update(spec.settings)
    row.update(repeat=spec.repeat, seed=spec.seed, rtf=setup.rtf)
    for f in RESULT_FIELDS:
        row[f] = ''
    result_path = os.path.join(trial_dir, 'result.json')
    traj = metrics.read_trajectory(os.path.join(trial_dir, 'trajectory.csv'))
    if os.path.exists(result_path):
        with open(result_path) as f:
            res = json.load(f)
        row.update(status=res['status'], reason=res['reason'], collisions=res['collisions'],
                   goals_reached=res['goals_reached'], goals=res['goals'],
                   sim_elapsed=round(res['elapsed'], 2),
                   achieved_rtf=round(res['achieved_rtf'], 2)
                   if res['achieved_rtf'] == res['achieved_rtf'] else '')
        row['time_to_goal'] = round(res['time_to_goal'], 2) if res['time_to_goal'] else ''
        m = metrics.trial_metrics(traj, setup.truth_map(), setup.footprint, setup.goal_xy(),
                                  res['time_to_goal'] or res['elapsed'])
        row.update((k, round(v, 3)) for k, v in m.items())
    elif overran:
        row.update(status='timeout', reason='killed: no result within the wall budget of '
                   '%.0f s' % setup.wall_budget())
    elif no_master:
        row.update(status='error', reason=no_master)
    else:
        why = 'the stack exited' if stack_died else 'the driver gave up'
        said = _driver_said(trial_dir)
        row.update(status='error', reason='%s before a result%s (see %s)' % (
            why, ': ' + said if said else '', os.path.relpath(trial_dir, setup.out_dir)))
    row['reached'] = int(row['status'] == 'reached')
    row['wall_time'] = round(wall, 1)
    if row['status'] in FINISHED:
        shutil.rmtree(os.path.join(trial_dir, 'ros_log'), ignore_errors=True)
    return row, driver_status


def _driver_said(trial_dir):
    """The driver's last message (why it gave up), or ''."""
    try:
        with open(os.path.join(trial_dir, 'driver.log'), errors='replace') as f:
            lines = [l.strip() for l in f if l.startswith('driver: ')]
    except OSError:
        return ''
    return lines[-1][len('driver: '):] if lines else ''


class ResultsFile(object):
    """results.csv: rows keyed by trial key, rewritten atomically after each change."""

    def __init__(self, path):
        self.path = path
        self.lock = threading.Lock()
        self.rows = collections.OrderedDict()
        if os.path.exists(path):
            with open(path, newline='') as f:
                for r in csv.DictReader(f):
                    self.rows[r['key']] = r

    def finished(self, key):
        r = self.rows.get(key)
        return r is not None and r.get('status') in FINISHED

    def add(self, row):
        with self.lock:
            self.rows[row['key']] = row
            fields = []
            for r in self.rows.values():
                for k in r:
                    if k not in fields:
                        fields.append(k)
            tmp = self.path + '.tmp'
            with open(tmp, 'w', newline='') as f:
                w = csv.DictWriter(f, fieldnames=fields, restval='')
                w.writeheader()
                for r in self.rows.values():
                    w.writerow(r)
            os.replace(tmp, self.path)


def _describe(row):
    status = row['status']
    if status == 'reached':
        return '%s s, %s collisions' % (row['time_to_goal'], row['collisions'])
    return '%s: %s' % (status, row['reason'])


def run_grid(setup, specs, results, jobs, registry, stop, progress=True):
    """Runs the specs results does not hold yet; returns the number run."""
    from tqdm import tqdm
    todo = [s for s in specs if not results.finished(s.key)]
    skipped = len(specs) - len(todo)
    bar = tqdm(total=len(specs), initial=skipped, unit='trial', disable=not progress,
               dynamic_ncols=True, file=sys.stderr)
    if skipped:
        bar.write('resuming: %d of %d trials already in %s' % (skipped, len(specs), results.path))
    pool = futures.ThreadPoolExecutor(max_workers=max(1, jobs))
    try:
        pending = {pool.submit(run_trial, setup, s, registry, stop): s for s in todo}
        for fut in futures.as_completed(pending):
            spec = pending[fut]
            try:
                row = fut.result()
            except Interrupted:
                continue
            results.add(row)
            bar.update(1)
            bar.write('%s r%d: %s' % (settings_slug(spec.settings), spec.repeat, _describe(row)))
    except BaseException:
        stop.set()
        registry.stop_all()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        bar.close()
    return len(todo)


def optuna_space(sweeps):
    """Sweep -> a suggest function (numeric lists become their [min, max] range)."""
    space = []
    for s in sweeps:
        if s.is_range:
            lo, hi = s.low, s.high
        elif all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in s.values) \
                and len(s.values) > 1:
            lo, hi = min(s.values), max(s.values)
        else:
            space.append((s.name, 'categorical', list(s.values)))
            continue
        kind = 'int' if isinstance(lo, int) and isinstance(hi, int) else 'float'
        space.append((s.name, kind, (lo, hi)))
    return space


# Key of the PostgreSQL advisory lock that serialises opening studies (any 64-bit number that no
# other application on the same database uses for its own lock).
SCHEMA_LOCK_KEY = 0x6d696e69626f7433  # "minibot3"


def open_study(optuna, study_name, storage, sampler):
    """Creates the study, or loads it if another worker has.  Optuna creates its schema on a
    database's first use, and workers started together on a fresh database race to create it: the
    loser's CREATE TABLE or CREATE TYPE fails ('relation "studies" already exists', or a unique
    violation on pg_type).  On PostgreSQL the workers therefore take turns, holding an advisory
    lock (pg_advisory_lock: the next worker blocks until the holder has committed the
    schema and its study), so the second finds both in place.  Other databases (SQLite, for one
    machine) open the study directly."""
    if not str(storage).startswith('postgresql'):
        return optuna.create_study(study_name=study_name, storage=storage, sampler=sampler,
                                   direction='minimize', load_if_exists=True)
    import sqlalchemy
    engine = sqlalchemy.create_engine(storage, poolclass=sqlalchemy.pool.NullPool)
    try:
        with engine.connect() as conn:
            conn.execute(sqlalchemy.text('SELECT pg_advisory_lock(:key)'), {'key': SCHEMA_LOCK_KEY})
            try:
                return optuna.create_study(study_name=study_name, storage=storage, sampler=sampler,
                                           direction='minimize', load_if_exists=True)
            finally:
                conn.execute(sqlalchemy.text('SELECT pg_advisory_unlock(:key)'),
                             {'key': SCHEMA_LOCK_KEY})
    finally:
        engine.dispose()


def run_optuna(setup, sweeps, repeats, results, jobs, registry, stop, storage, study_name,
               n_trials, progress=True, sampler_seed=None):
    """sampler_seed: the TPE sampler's seed (default setup.seed).  Workers sharing a study need
    different ones: with the same seed they suggest the same settings."""
    import warnings
    import optuna
    from tqdm import tqdm
    optuna.logging.set_verbosity(optuna.logging.WARNING)  # each trial is printed below
    warnings.filterwarnings('ignore', category=optuna.exceptions.ExperimentalWarning)
    space = optuna_space(sweeps)
    sampler = optuna.samplers.TPESampler(
        seed=setup.seed if sampler_seed is None else sampler_seed,
        constraints_func=lambda t: [t.user_attrs.get('constraint', 1.0)])
    study = open_study(optuna, study_name, storage, sampler)
    done = len([t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE])
    remaining = max(0, n_trials - done)
    bar = tqdm(total=n_trials, initial=min(done, n_trials), unit='trial',
               disable=not progress, dynamic_ncols=True, file=sys.stderr)

    def objective(trial):
        settings = collections.OrderedDict()
        for name, kind, arg in space:
            if kind == 'categorical':
                settings[name] = trial.suggest_categorical(name, arg)
            elif kind == 'int':
                settings[name] = trial.suggest_int(name, arg[0], arg[1])
            else:
                settings[name] = round(trial.suggest_float(name, arg[0], arg[1]), 4)
        times, bad = [], 0
        for r in range(1, repeats + 1):
            spec = TrialSpec(settings, r, setup, prefix='optuna%d:' % trial.number)
            row = run_trial(setup, spec, registry, stop)
            row['optuna_trial'] = trial.number
            results.add(row)
            bar.write('optuna trial %d %s r%d: %s' % (trial.number, settings_slug(settings), r,
                                                       _describe(row)))
            ok = row['status'] == 'reached'
            bad += int(row['collisions'] or 0) + (0 if ok else 1)
            times.append(float(row['time_to_goal']) if ok else setup.timeout)
        trial.set_user_attr('constraint', float(bad))
        trial.set_user_attr('settings', dict(settings))
        bar.update(1)
        return sum(times) / len(times)

    try:
        if remaining:
            study.optimize(objective, n_trials=remaining, n_jobs=max(1, jobs),
                           callbacks=[optuna.study.MaxTrialsCallback(
                               n_trials, states=(optuna.trial.TrialState.COMPLETE,))],
                           catch=())
    except BaseException:
        stop.set()
        registry.stop_all()
        raise
    finally:
        bar.close()
    return study
