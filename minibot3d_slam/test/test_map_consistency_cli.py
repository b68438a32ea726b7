"""map_consistency and tools/bench/real_logs_bench.sh on a small CARMEN log written here (the room
of test_slam_offline_stream.py, driven up and down): the log's exact poses agree with themselves;
a trajectory whose later legs are placed off the map conflicts, and the scans it lists are on
those legs; bad input is named; the real-logs benchmark runs a list (a missing log skipped, a
reference scored) and refuses a malformed line naming it."""
import os
import re
import subprocess

from test_slam_offline_stream import poses, write_log

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
N = 600  # readings: 0.2 s apart, about 55 m of driving, so the legs pass each other many times


def consistency(*args):
    return subprocess.run(['rosrun', 'minibot3d_slam', 'map_consistency', *map(str, args)],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)


def conflict_pct(stdout):
    m = re.search(r'conflict_pct ([\d.]+) scans_inconsistent (\d+) of (\d+)', stdout)
    assert m, stdout
    return float(m.group(1)), int(m.group(2)), int(m.group(3))


def write_trajectory(path, shifted=range(0), shift=(0.0, 0.0, 0.0)):
    """The true poses as 'timestamp x y theta', the readings in `shifted` (1-based) moved by
    `shift`."""
    with open(path, 'w') as f:
        for i, (x, y, th) in enumerate(poses(N), 1):
            if i in shifted:
                x, y, th = x + shift[0], y + shift[1], th + shift[2]
            f.write('%.6f %.6f %.6f %.6f\n' % (1000.0 + 0.2 * i, x, y, th))


def test_exact_poses_agree_and_a_displaced_half_conflicts(tmp_path):
    log = tmp_path / 'room.clf'
    write_log(log, N)
    r = consistency(log)
    assert r.returncode == 0, r.stderr
    exact, bad, judged = conflict_pct(r.stdout)
    assert judged > 20, r.stdout
    assert exact < 1.0 and bad == 0, r.stdout
    assert 'placed %d of %d' % (N, N) in r.stdout

    # One pass in the middle placed off the map, as a scan match gone wrong leaves it (the other
    # passes agree with each other).
    traj = tmp_path / 'shifted.txt'
    leg = range(N // 2 - 40, N // 2 + 40)
    write_trajectory(traj, shifted=leg, shift=(0.25, 0.3, 0.05))
    r = consistency(log, traj, '--worst', 1000)
    assert r.returncode == 0, r.stderr
    shifted, bad, _ = conflict_pct(r.stdout)
    assert shifted > 5.0 and shifted > 5 * exact + 2.0, r.stdout
    assert bad > 0, r.stdout
    times = [float(t) for t in re.findall(r'inconsistent scan at time ([\d.]+)', r.stdout)]
    assert len(times) == bad
    # The scans placed off the map are those of the displaced pass.
    assert all(1000.0 + 0.2 * leg[0] <= t <= 1000.0 + 0.2 * leg[-1] for t in times), times


def test_a_trajectory_is_scored_on_the_scans_a_reference_log_kept(tmp_path):
    # A reference like GMapping's corrected logs: every 10th reading, with times of its own.
    log = tmp_path / 'room.clf'
    write_log(log, N)
    kept = []
    with open(log) as f:
        for i, line in enumerate(ln for ln in f if ln.startswith('FLASER')):
            if i % 10 == 0:
                fields = line.split()
                fields[-3] = '%.6f' % (float(fields[-3]) - 1000.0)
                kept.append(' '.join(fields))
    reference = tmp_path / 'reference.gfs.log'
    reference.write_text('# corrected\n' + '\n'.join(kept) + '\n')
    traj = tmp_path / 'truth.txt'
    write_trajectory(traj)
    r = consistency(log, traj, '--scans-of', reference)
    assert r.returncode == 0, r.stderr
    assert 'placed %d of %d reference_scans_found %d of %d' % (N // 10, N, N // 10, N // 10) in r.stdout, r.stdout
    # The same scans at the same poses as the reference's own: the same figures.
    own = consistency(reference)
    assert own.returncode == 0, own.stderr
    fields = r'conflict_pct \S+ scans_inconsistent \d+ of \d+ agreed \d+ conflicts \d+'
    assert re.search(fields, r.stdout).group(0) == re.search(fields, own.stdout).group(0), (r.stdout, own.stdout)
    # All the readings make a denser map than the kept ones: another figure.
    assert re.search(fields, consistency(log, traj).stdout).group(0) != re.search(fields, own.stdout).group(0)

    # A log of another run: the same places, every first beam 0.5 m longer.
    other = tmp_path / 'other.clf'
    other.write_text(''.join(
        ' '.join(f[:2] + ['%.3f' % (float(f[2]) + 0.5)] + f[3:]) + '\n'
        for f in (ln.split() for ln in kept)))
    r = consistency(log, traj, '--scans-of', other)
    assert r.returncode == 1
    assert 'none of the %d readings of %s is in %s' % (N, log, other) in r.stderr, r.stderr


def test_bad_input_is_named(tmp_path):
    log = tmp_path / 'room.clf'
    write_log(log, 50)
    r = consistency(log, '--param', 'tolerance=-1')
    assert r.returncode == 2 and 'tolerance=-1 must be >= 0' in r.stderr, r.stderr
    r = consistency(log, '--param', 'toleranse=1')
    assert r.returncode == 2 and "unknown map_consistency parameter 'toleranse'" in r.stderr, r.stderr
    other = tmp_path / 'other.txt'
    other.write_text('5.0 0 0 0\n6.0 1 0 0\n')
    r = consistency(log, other)
    assert r.returncode == 1, r.stdout
    assert 'none of the 50 readings of %s has a pose in %s' % (log, other) in r.stderr, r.stderr
    r = consistency(tmp_path / 'missing.clf')
    assert r.returncode == 1 and 'missing.clf' in r.stderr, r.stderr


def bench(list_path, out):
    env = dict(os.environ, SEEDS='1')
    return subprocess.run([os.path.join(ROOT, 'tools', 'bench', 'real_logs_bench.sh'), str(list_path), str(out)],
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=600, env=env)


def test_real_logs_bench_runs_a_list(tmp_path):
    log = tmp_path / 'room.clf'
    write_log(log, 300)
    listing = tmp_path / 'logs.txt'
    listing.write_text('# name log reference\nroom %s %s\n\ngone %s\n' % (log, log, tmp_path / 'gone.clf'))
    r = bench(listing, tmp_path / 'out')
    assert r.returncode == 0, r.stdout + r.stderr
    assert "gone: skipped, no log at '%s'" % (tmp_path / 'gone.clf') in r.stdout, r.stdout
    line = [ln for ln in r.stdout.splitlines() if ln.startswith('room, 1 seeds:')]
    assert line, r.stdout
    assert re.search(r'conflicts [\d.]+ % of revisited endpoints, inconsistent scans [\d.]+ of \d+', line[0])
    assert re.search(r'wall [\d.]+ s, peak \d+ MB; raw odometry: conflicts [\d.]+ %; reference: conflicts [\d.]+ %, '
                     r"inconsistent scans \d+ of \d+; room on the reference's scans: conflicts [\d.]+ %", line[0]), line[0]
    assert (tmp_path / 'out' / 'room.png').stat().st_size > 0

    listing.write_text('room %s %s extra\n' % (log, log))
    r = bench(listing, tmp_path / 'out')
    assert r.returncode == 2
    assert "%s:1: expected 'NAME LOG [REFERENCE_LOG]'" % listing in r.stderr, r.stderr


def test_shipped_log_list_is_well_formed():
    path = os.path.join(ROOT, 'tools', 'bench', 'real_logs.txt')
    names = []
    with open(path) as f:
        for line in f:
            fields = line.split()
            if not fields or fields[0].startswith('#'):
                continue
            assert 2 <= len(fields) <= 3, line
            names.append(fields[0])
    assert len(names) == len(set(names)) and 'intel' in names
