"""tune_planner past one machine: two `tune_planner --optimize` workers share one Optuna study on
PostgreSQL (README "Past one machine").  A throw-away server (Debian's initdb + pg_ctl, as the
`postgres` user when run as root) runs in a temporary directory, listening on a Unix socket only;
two workers with their own output directories and sampler seeds run at once against one study,
and every trial either ran must be in the study exactly once: as many COMPLETE trials as the
workers' results.csv rows, no trial number twice, each with the value and settings its worker
measured, no setting measured twice, and the two workers' trials overlapping in time.  Workers that
start together on a fresh database all open the study (Optuna's schema is created once).  Skipped only
when the PostgreSQL server binaries are not installed (Debian package `postgresql`)."""
import csv
import glob
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
TOOL = os.path.join(HERE, '..', 'scripts', 'tune_planner')
sys.path.insert(0, os.path.join(HERE, '..', 'src'))
from minibot3d_tuning import processes  # noqa: E402

SHORT_ROUTE = ['--start=-3,-1.5,0', '--goals=-2.1,0.6']  # through the living-room opening, ~2.5 m
TRIALS = 4  # the study's target, counted over both workers (tune_planner --trials)


def postgres_bin_dir():
    """Debian's server binaries, /usr/lib/postgresql/<version>/bin, the newest version present."""
    found = []
    for d in glob.glob('/usr/lib/postgresql/*/bin'):
        if all(os.access(os.path.join(d, b), os.X_OK) for b in ('initdb', 'pg_ctl', 'createdb')):
            try:
                found.append((float(d.split('/')[-2]), d))
            except ValueError:
                pass
    return max(found)[1] if found else None


class Server:
    """A PostgreSQL cluster in a temporary directory, on a Unix socket there and no TCP port."""

    def __init__(self, bindir):
        self.bindir = bindir
        self.as_root = os.geteuid() == 0
        # Not under pytest's tmp_path: that is private to root and the server runs as postgres.
        self.dir = tempfile.mkdtemp(prefix='minibot3d-pg-')
        self.data = os.path.join(self.dir, 'data')
        self.log = os.path.join(self.dir, 'server.log')
        if self.as_root:
            shutil.chown(self.dir, 'postgres', 'postgres')
        self.started = False

    def run(self, *cmd, timeout=120):
        argv = [os.path.join(self.bindir, cmd[0])] + list(cmd[1:])
        if self.as_root:  # initdb and postgres refuse to run as root
            argv = ['runuser', '-u', 'postgres', '--'] + argv
        r = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           universal_newlines=True, timeout=timeout)
        assert r.returncode == 0, '%s failed:\n%s%s' % (' '.join(argv), r.stdout, self.server_log())
        return r.stdout

    def server_log(self):
        try:
            return '\nserver log:\n' + open(self.log).read()
        except OSError:
            return ''

    def start(self):
        # trust: only local socket connections exist, in a directory only this test uses.
        self.run('initdb', '-D', self.data, '-U', 'postgres', '-A', 'trust', '--no-sync')
        self.started = True
        # -w: pg_ctl returns once the server accepts connections (or fails after -t seconds).
        self.run('pg_ctl', '-D', self.data, '-l', self.log, '-w', '-t', '60', '-o',
                 "-c listen_addresses='' -k %s -c fsync=off" % self.dir, 'start')
        return self.create_database('tune')

    def create_database(self, name):
        """A new, empty database; its URL."""
        self.run('createdb', '-h', self.dir, '-U', 'postgres', name)
        return 'postgresql://postgres@/%s?host=%s' % (name, self.dir)

    def stop(self):
        try:
            if self.started:
                self.run('pg_ctl', '-D', self.data, '-w', '-t', '60', '-m', 'fast', 'stop')
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)


@pytest.fixture
def postgres_server():
    bindir = postgres_bin_dir()
    if bindir is None:
        pytest.skip('PostgreSQL server binaries not found under /usr/lib/postgresql/*/bin '
                    '(Debian package postgresql; make setup installs it)')
    server = Server(bindir)
    try:
        server.url = server.start()
        yield server
    finally:
        server.stop()


@pytest.fixture
def postgres_url(postgres_server):
    return postgres_server.url


def read_rows(out):
    with open(os.path.join(str(out), 'results.csv')) as f:
        return list(csv.DictReader(f))


def test_two_workers_share_one_study_on_postgresql(tmp_path, postgres_url):
    import optuna
    cmd = ['--optimize', '--set', 'max_vel_x=0.3:0.7', '--repeats', '1', '--jobs', '1',
           '--trials', str(TRIALS), '--timeout', '120', '--storage', postgres_url,
           '--study-name', 'shared', '--no-progress'] + SHORT_ROUTE
    workers, logs = {}, {}
    try:
        for name, seed in (('a', 1), ('b', 2)):
            logs[name] = open(str(tmp_path / ('%s.log' % name)), 'w+')
            workers[name] = subprocess.Popen(
                [sys.executable, TOOL, '--out', str(tmp_path / name),
                 '--sampler-seed', str(seed)] + cmd,
                stdout=logs[name], stderr=subprocess.STDOUT)
        codes = {name: w.wait(timeout=600) for name, w in workers.items()}
    finally:
        for w in workers.values():
            if w.poll() is None:
                w.kill()
                w.wait()
    output = {}
    for name, f in logs.items():
        f.seek(0)
        output[name] = f.read()
        f.close()
    for name in ('a', 'b'):
        assert codes[name] == 0, 'worker %s exited %d:\n%s' % (name, codes[name], output[name])
        assert not processes.processes_with_marker(str(tmp_path / name))

    # What each worker ran, from its own results.csv (one row per trial with --repeats 1).
    ran = {name: read_rows(tmp_path / name) for name in ('a', 'b')}
    for name, rows in ran.items():
        assert rows, 'worker %s ran no trial:\n%s' % (name, output[name])
    numbers = [int(r['optuna_trial']) for rows in ran.values() for r in rows]
    assert len(numbers) == len(set(numbers)), 'a trial number ran twice: %s' % sorted(numbers)

    st = optuna.load_study(study_name='shared', storage=postgres_url)
    complete = [t for t in st.trials if t.state == optuna.trial.TrialState.COMPLETE]
    assert len(st.trials) == len(complete), [(t.number, t.state) for t in st.trials]
    # Each worker stops once the study holds TRIALS complete trials; one still running then
    # finishes too, so there may be up to one more per worker, never fewer.
    assert TRIALS <= len(complete) <= TRIALS + 1
    assert len(complete) == len(numbers)
    assert sorted(t.number for t in complete) == sorted(numbers)
    by_number = {t.number: t for t in complete}
    for name, rows in sorted(ran.items()):  # shown with pytest -s
        print('worker %s: %s' % (name, ', '.join('trial %s max_vel_x %s -> %s s' % (
            r['optuna_trial'], r['max_vel_x'], r['time_to_goal']) for r in rows)))
    for name, rows in ran.items():
        for r in rows:
            t = by_number[int(r['optuna_trial'])]
            assert r['status'] == 'reached' and r['collisions'] == '0', r
            assert t.value == pytest.approx(float(r['time_to_goal']), abs=1e-6), (name, r)
            assert t.user_attrs['settings']['max_vel_x'] == pytest.approx(
                float(r['max_vel_x'])), (name, r)
            assert t.user_attrs['constraint'] == 0.0
    # Their own --sampler-seed each: no setting was measured twice.
    settings = [r['max_vel_x'] for rows in ran.values() for r in rows]
    assert len(settings) == len(set(settings)), settings
    # The two workers ran at the same time: each one's first trial started before the other's
    # last trial ended.
    spans = {name: [by_number[int(r['optuna_trial'])] for r in rows] for name, rows in ran.items()}
    a, b = spans['a'], spans['b']
    assert min(t.datetime_start for t in a) < max(t.datetime_complete for t in b)
    assert min(t.datetime_start for t in b) < max(t.datetime_complete for t in a)


OPEN_STUDY = '''
import sys
sys.path.insert(0, sys.argv[1])
import optuna
from minibot3d_tuning import study
optuna.logging.set_verbosity(optuna.logging.WARNING)
study.open_study(optuna, 'race', sys.argv[2], optuna.samplers.RandomSampler(seed=1))
'''


def test_workers_starting_together_on_a_fresh_database_all_open_the_study(postgres_server):
    """Optuna creates its schema on first use, and workers started together race to create it
    (a worker failed with 'relation "studies" already exists'). Six processes open one study at
    once on each of three fresh databases: every one must get it."""
    import optuna
    for db in ('race1', 'race2', 'race3'):
        url = postgres_server.create_database(db)
        procs = [subprocess.Popen([sys.executable, '-c', OPEN_STUDY, os.path.join(HERE, '..', 'src'),
                                   url], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  universal_newlines=True) for _ in range(6)]
        outs = [p.communicate(timeout=300)[0] for p in procs]
        for p, out in zip(procs, outs):
            assert p.returncode == 0, 'a worker could not open the study on %s:\n%s' % (db, out)
        assert optuna.load_study(study_name='race', storage=url).study_name == 'race'
