"""tune_planner end to end: a small sweep in the simulator (CSV, table, plots, resume), the same
sweep again giving the same figures (lock-step time), a trial that runs out of time, Ctrl-C
mid-trial, and an unknown parameter name.  Every process a study
starts carries TUNE_PLANNER_RUN=<its out dir> in its environment, which is how these tests find
(only) their own processes."""
import csv
import os
import signal
import subprocess
import sys
import time


HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, '..', 'scripts', 'tune_planner')
sys.path.insert(0, os.path.join(HERE, '..', 'src'))
from minibot3d_tuning import processes  # noqa: E402

SHORT_ROUTE = ['--start=-3,-1.5,0', '--goals=-2.1,0.6']  # through the living-room opening, ~2.5 m


def tool(out, *args, **kw):
    return subprocess.run([sys.executable, TOOL, '--out', str(out), '--no-progress'] + list(args),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, **kw)


def read_rows(out):
    with open(os.path.join(str(out), 'results.csv')) as f:
        return list(csv.DictReader(f))


def assert_nothing_left(out):
    left = processes.processes_with_marker(os.path.abspath(str(out)))
    cmds = []
    for pid in left:
        try:
            cmds.append(open('/proc/%d/cmdline' % pid).read().replace('\0', ' ')[:120])
        except OSError:
            pass
    assert not left, 'left running: %s' % cmds


def test_unknown_parameter_is_rejected_before_any_trial(tmp_path):
    r = tool(tmp_path, '--set', 'max_vel_x=0.3,0.5', '--set', 'max_vel_xx=1', *SHORT_ROUTE,
             timeout=120)
    assert r.returncode == 2, r.stdout
    assert 'max_vel_xx' in r.stdout and 'unknown parameter' in r.stdout
    assert not os.path.exists(tmp_path / 'trials')
    assert not os.path.exists(tmp_path / 'results.csv')
    assert_nothing_left(tmp_path)


def test_small_sweep_writes_csv_table_and_plots_and_resumes(tmp_path):
    r = tool(tmp_path, '--set', 'max_vel_x=0.3,0.5', '--repeats', '1', '--jobs', '2',
             '--timeout', '120', *SHORT_ROUTE, timeout=600)
    assert r.returncode == 0, r.stdout
    rows = read_rows(tmp_path)
    assert sorted(row['max_vel_x'] for row in rows) == ['0.3', '0.5']
    for row in rows:
        assert row['status'] == 'reached', row
        assert row['collisions'] == '0'
        assert 2.0 < float(row['path_length']) < 4.0
        assert 0.0 < float(row['min_clearance']) < 1.0
        assert float(row['peak_speed']) <= float(row['max_vel_x']) + 0.05
        assert float(row['goal_error']) < 0.3
    slow, fast = sorted(rows, key=lambda row: float(row['max_vel_x']))
    assert float(fast['time_to_goal']) < float(slow['time_to_goal'])
    table = open(tmp_path / 'results.md').read()
    assert table.count('\n| 0.') == 2 and '| max_vel_x | time to goal' in table
    for png in ('time_to_goal.png', 'trajectories.png'):
        with open(tmp_path / png, 'rb') as f:
            assert f.read(8) == b'\x89PNG\r\n\x1a\n'
    assert_nothing_left(tmp_path)

    # Same command again: both trials are in results.csv, so nothing runs.
    again = tool(tmp_path, '--set', 'max_vel_x=0.3,0.5', '--repeats', '1', '--jobs', '2',
                 '--timeout', '120', *SHORT_ROUTE, timeout=120)
    assert again.returncode == 0, again.stdout
    assert 'resuming: 2 of 2 trials already in' in again.stdout
    assert [row['wall_time'] for row in read_rows(tmp_path)] == [row['wall_time'] for row in rows]


def test_same_command_gives_the_same_figures(tmp_path):
    """Lock-step time (the default): the driver joins before sim time starts, and two runs of one
    command, each two trials at once, the second beside a busy process, agree to the last digit,
    trajectories included."""
    cmd = ['--set', 'max_vel_x=0.3,0.6', '--repeats', '1', '--jobs', '2', '--timeout', '120',
           *SHORT_ROUTE]
    runs = []
    for name, busy in (('a', 0), ('b', 1)):
        hogs = [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range(busy)]
        try:
            r = tool(tmp_path / name, *cmd, timeout=300)
        finally:
            for h in hogs:
                h.kill()
                h.wait()
        assert r.returncode == 0, r.stdout
        assert 'lock-step, real-time factor 0' in r.stdout
        runs.append({row['key']: row for row in read_rows(tmp_path / name)})
    a, b = runs
    assert sorted(a) == sorted(b) and len(a) == 2
    for key in a:
        for field in ('status', 'time_to_goal', 'sim_elapsed', 'path_length', 'collisions',
                      'min_clearance', 'peak_speed', 'goal_error'):
            assert a[key][field] == b[key][field], (key, field, a[key][field], b[key][field])
        trial = a[key]['trial']
        traj = [open(str(tmp_path / n / 'trials' / trial / 'trajectory.csv')).read()
                for n in ('a', 'b')]
        assert traj[0] == traj[1] and traj[0].count('\n') > 50
        stack = open(str(tmp_path / 'a' / 'trials' / trial / 'stack.log')).read()
        assert '/tune_planner_driver joined at sim time 0.001' in stack  # before time started
        assert 'starting time without' not in stack
    assert_nothing_left(tmp_path / 'a')
    assert_nothing_left(tmp_path / 'b')


def test_trial_over_its_time_budget_is_recorded_as_timeout(tmp_path):
    r = tool(tmp_path, '--set', 'max_vel_x=0.1', '--repeats', '1', '--timeout', '2',
             *SHORT_ROUTE, timeout=300)
    assert r.returncode == 1, r.stdout
    (row,) = read_rows(tmp_path)
    assert row['status'] == 'timeout' and 'within 2 sim s' in row['reason'], row
    assert 'timeout' in open(tmp_path / 'results.md').read()
    assert_nothing_left(tmp_path)


def test_ctrl_c_mid_trial_stops_every_process(tmp_path):
    log = open(str(tmp_path / 'tool.log'), 'w')
    # Paced at wall time (--rtf 1): the trials take 70 and 126 sim s, so both are still driving
    # when Ctrl-C comes, however loaded the machine (as fast as possible they take 15 and 21 s
    # wall). The tool starts as from a terminal, SIGINT at its default: a test runner started in
    # the background of a script inherits SIGINT ignored, and so would the tool (Python then
    # installs no KeyboardInterrupt handler, and the Ctrl-C below would be lost).
    proc = subprocess.Popen([sys.executable, TOOL, '--out', str(tmp_path), '--no-progress',
                             '--set', 'max_vel_x=0.1,0.2', '--repeats', '1', '--jobs', '2',
                             '--rtf', '1'],
                            stdout=log, stderr=subprocess.STDOUT,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        # Mid-way: both trials' drivers have seen their stacks ready and are driving.
        deadline = time.monotonic() + 180
        ready = 0
        while ready < 2 and proc.poll() is None and time.monotonic() < deadline:
            ready = 0
            for root, _, files in os.walk(str(tmp_path / 'trials')):
                if 'driver.log' in files and 'ready after' in open(
                        os.path.join(root, 'driver.log')).read():
                    ready += 1
            time.sleep(0.2)
        assert ready == 2, open(str(tmp_path / 'tool.log')).read()
        assert len(processes.processes_with_marker(str(tmp_path))) >= 10
        assert not os.path.exists(str(tmp_path / 'results.csv')), \
            'a trial ended before Ctrl-C: not mid-trial'
        proc.send_signal(signal.SIGINT)
        assert proc.wait(90) == 130
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        log.close()
    assert_nothing_left(tmp_path)
    assert 'rerun the same command to resume' in open(str(tmp_path / 'tool.log')).read()
    assert not os.path.exists(tmp_path / 'results.csv')  # interrupted trials are not recorded
