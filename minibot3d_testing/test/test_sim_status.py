"""sim_status.SimStatusWatch, the collision check of the closed-loop tests, against a status
publisher driven by hand (sim_status_probe.py) on a master of its own, in wall time:
- no status at all is reported, not taken for "no collision";
- a collision counted by a status sent after the end of the run is reported (reading the latest
  count at the end would see 0);
- no status after the end is reported;
- statuses before and after the end with no collision pass.
Every wait is on a condition (a line of output, a process exit) with a time limit."""
import json
import os
import subprocess
import sys

import minibot3d_testing as testing
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
PROBE = os.path.join(HERE, 'sim_status_probe.py')
TOPIC = '/minibot3d_sim/status'


@pytest.fixture
def core(tmp_path):
    with testing.RosCore(dict(os.environ, ROS_HOME=str(tmp_path)), log_dir=tmp_path) as c:
        yield c


@pytest.fixture
def processes():
    started = []
    yield started
    for p in reversed(started):
        if p.proc.stdin is not None:
            p.proc.stdin.close()  # a publisher reading its statuses from stdin is done
        p.stop(grace=5.0)


def start(core, processes, *args, **popen):
    p = core.start_process([sys.executable, PROBE] + list(args), stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True, **popen)
    processes.append(p)
    return p.proc


def line(proc, expected):
    got = proc.stdout.readline()  # '' when it exited
    assert got.strip() == expected, 'expected %r, got %r' % (expected, got)


class Run(object):
    """A status publisher (when `statuses`) and a watch that ends its run after them."""

    def __init__(self, core, processes, statuses):
        self.publisher = None
        if statuses:
            self.publisher = start(core, processes, 'publish', TOPIC, stdin=subprocess.PIPE)
            self.send(statuses)
        self.watch = start(core, processes, 'watch', TOPIC, str(len(statuses)))
        line(self.watch, 'ended')

    def send(self, statuses):
        for n in statuses:
            self.publisher.stdin.write('%d\n' % n)
            self.publisher.stdin.flush()
            line(self.publisher, 'published %d' % n)

    def problems(self):
        out, _ = self.watch.communicate(timeout=60)
        assert self.watch.returncode == 0, out
        return json.loads(out.strip().splitlines()[-1])


def test_no_status_at_all_is_reported(core, processes):
    # Catches: a run whose status never arrived taken for one without collision.
    problems = Run(core, processes, []).problems()
    assert problems == ['no message on %s during the run: the collisions were not checked (is '
                        'the simulator up and publishing its status?)' % TOPIC], problems


def test_a_collision_counted_after_the_end_is_reported(core, processes):
    # Catches: the count read as the run ends, before the status that counts its last second.
    run = Run(core, processes, [0])
    run.send([1])
    problems = run.problems()
    assert len(problems) == 1, problems
    assert problems[0].startswith('the simulator reported 1 collision(s), the first by t='), \
        problems


def test_no_status_after_the_end_is_reported(core, processes):
    # Catches: a status from before the end taken for the count at the end.
    problems = Run(core, processes, [0]).problems()
    assert len(problems) == 1, problems
    assert problems[0].startswith('no status on %s stamped after the end of the run' % TOPIC), \
        problems
    assert 'within 2 s of sim time' in problems[0], problems


def test_statuses_without_collision_pass(core, processes):
    # Catches: a clean run reported.
    run = Run(core, processes, [0])
    run.send([0])
    assert run.problems() == []
