"""run_checks.RunChecks, the check every closed-loop rostest makes on its whole run, against runs
made by hand on a master of their own (run_checks_probe.py: latched /tf publishers, listeners,
the checking node, all started by this test as a rostest starts its nodes):
- a clean run (two frames at one stamp, a listener on 127.0.0.1, rosout's XML-RPC server on
  0.0.0.0 as roscpp forces it) has no problem;
- one child frame sent at one stamp by two publishers is reported, naming both; a latched message
  delivered twice (two connections to one publisher) is not;
- a process of the run listening on 0.0.0.0 is reported, with its port;
- a run in which no /tf arrived is reported.
Every wait is on a condition (a line of output, a message count, a process exit) with a limit."""
import json
import os
import subprocess
import sys

import minibot3d_testing as testing
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
PROBE = os.path.join(HERE, 'run_checks_probe.py')


@pytest.fixture
def core(tmp_path):
    with testing.RosCore(dict(os.environ, ROS_HOME=str(tmp_path)), log_dir=tmp_path) as c:
        yield c


def start(core, processes, *args):
    p = core.start_process([sys.executable, PROBE] + list(args), stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True)
    processes.append(p)
    return p


def listener(core, processes, address):
    """A process of the run listening on address; its port."""
    p = start(core, processes, 'listen', address)
    line = p.proc.stdout.readline()  # "listening PORT", or '' when it exited
    assert line.startswith('listening '), line + p.proc.stdout.read()
    return int(line.split()[1])


def run_checks(core, processes, tf_messages):
    """RunChecks' result once tf_messages have arrived on /tf."""
    p = start(core, processes, 'check', str(tf_messages))
    out, _ = p.proc.communicate(timeout=90)
    assert p.proc.returncode == 0, out
    result = json.loads(out.strip().splitlines()[-1])
    assert result['messages'] >= tf_messages, result
    return result['problems']


@pytest.fixture
def processes():
    started = []
    yield started
    for p in reversed(started):
        p.stop(grace=5.0)


def test_a_clean_run_has_no_problem(core, processes):
    # Catches: loopback listeners, roscpp's forced XML-RPC server or distinct frames reported.
    start(core, processes, 'publish', 'tf_base', 'base_link', '100.0')
    start(core, processes, 'publish', 'tf_laser', 'laser', '100.0')
    listener(core, processes, '127.0.0.1')
    assert run_checks(core, processes, 2) == []


def test_one_frame_at_one_stamp_from_two_publishers_is_reported(core, processes):
    # Catches: a repeated (child frame, stamp) on /tf not reported (TfRepeatMonitor broken).
    start(core, processes, 'publish', 'tf_first', 'base_link', '100.0')
    start(core, processes, 'publish', 'tf_second', 'base_link', '100.0')
    problems = run_checks(core, processes, 2)
    assert len(problems) == 1, problems
    assert problems[0].startswith('tf sent twice at one stamp'), problems
    assert 'base_link (parent odom) at 100.000000000 s' in problems[0], problems
    assert '/tf_first' in problems[0] and '/tf_second' in problems[0], problems


def transform(child, stamp, x=0.0):
    from geometry_msgs.msg import TransformStamped
    import rospy
    t = TransformStamped()
    t.header.frame_id = 'odom'
    t.header.stamp = rospy.Time.from_sec(stamp)
    t.child_frame_id = child
    t.transform.translation.x = x
    t.transform.rotation.w = 1.0
    return t


def test_a_latched_message_delivered_twice_is_not_a_repeat():
    """rospy delivers a latched message once per connection, and a subscriber may briefly hold two
    connections to one publisher. Catches: that second delivery reported as tf sent twice (a
    run failed for it), or a real repeat hidden by the rule."""
    from minibot3d_lockstep.run_checks import TfRepeatMonitor
    m = TfRepeatMonitor(subscribe=False)
    m.record('/pub', True, [transform('base_link', 100.0)])
    m.record('/pub', True, [transform('base_link', 100.0)])  # the same message again
    assert m.repeats() == [] and m.messages == 1
    m.record('/pub', True, [transform('base_link', 100.0, x=0.5)])  # another transform: sent
    m.record('/other', True, [transform('base_link', 100.0)])  # another publisher: sent
    m.record('/pub', False, [transform('laser', 100.0)])
    m.record('/pub', False, [transform('laser', 100.0)])  # not latched: sent twice
    assert len(m.repeats()) == 3 and m.messages == 5, m.repeats()
    assert 'first from /pub, again from /other' in m.repeats()[1]


def test_a_listener_on_all_addresses_is_reported(core, processes):
    # Catches: a socket of the run on 0.0.0.0 not reported (non_loopback_listeners broken).
    start(core, processes, 'publish', 'tf_base', 'base_link', '100.0')
    port = listener(core, processes, '0.0.0.0')
    problems = run_checks(core, processes, 1)
    assert len(problems) == 1, problems
    assert problems[0].startswith('listening beyond loopback'), problems
    assert 'run_checks_probe.py (pid ' in problems[0], problems
    assert 'listens on 0.0.0.0:%d' % port in problems[0], problems


def test_a_run_without_tf_is_reported(core, processes):
    # Catches: a run whose monitor heard no /tf passing as if it had been checked.
    problems = run_checks(core, processes, 0)
    assert problems == ['no message on /tf during the run: nothing was checked for repeated '
                        'transforms (is the simulator up on this master?)'], problems
