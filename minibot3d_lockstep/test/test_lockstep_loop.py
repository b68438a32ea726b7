"""Lock-step time with real processes: the simulator, real nodes and test participants
(lockstep_probe.py), each run on a ROS master of its own.

- a participant that works for a while stops sim time, and one that stops answering for
  ~lockstep_timeout is dropped with a warning naming it, after which time goes on;
- a participant killed while it holds a tick is dropped and the loop goes on;
- participants of several robots (/robot1/..., /robot2/...): a stalled one is dropped by its full
  name, and the other robot's go on;
- the closed loop (simulator + amcl + move_base + a goal client) gives the same trajectory and
  times twice at real_time_factor 0, and again at real_time_factor 1.
Every wait is on a condition (a line of output, a file, a process exit) with a time limit."""
import json
import os
import signal
import subprocess
import sys
import time

import minibot3d_testing as testing
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
PROBE = os.path.join(HERE, 'lockstep_probe.py')


class Stack(testing.Stack):
    """roslaunch on a master of its own, plus probes on the same master."""

    def __init__(self, tmp_path, launch, args):
        super().__init__(['roslaunch'] + launch + args, tmp_path / 'launch.log',
                         env=dict(os.environ, ROS_HOME=str(tmp_path)))
        # Nodes read /use_sim_time and /use_lockstep when they start: start them once roslaunch
        # has set its parameters and started the simulator.
        import rosgraph
        master = rosgraph.Master('/test_lockstep_loop', master_uri=self.env['ROS_MASTER_URI'])

        def registered():
            try:
                return master.lookupService('/minibot3d_sim/lockstep/register')
            except rosgraph.MasterError:  # not yet
                return None
        try:
            testing.wait_until(registered, 60, 'the simulator', interval=0.2)
        except testing.WaitTimeout:
            log = self.log(3000)
            self.stop()
            pytest.fail('the simulator did not come up:\n' + log)

    def probe(self, *args):
        return self.start([sys.executable, PROBE] + list(args), stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True).proc

    def wait_log(self, text, timeout):
        """Until the launch's output has `text` (a log file polled: the text is the condition)."""
        testing.wait_until(lambda: text in self.log(), timeout, lambda: '%r in the launch log:\n%s'
                           % (text, self.log(3000)), interval=0.2)


def read_line(proc, prefix, timeout):
    """The first line of proc's output starting with `prefix` (others are skipped)."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        line = proc.stdout.readline()
        if not line:
            return None
        if line.startswith(prefix):
            return line.strip()
    return None


def sim_stack(tmp_path, participant, timeout):
    return Stack(tmp_path, ['minibot3d_sim', 'minibot3d_gazebo.launch'],
                 ['lockstep:=true', 'real_time_factor:=0', 'physics:=kinematic',
                  'lockstep_participants:=' + participant, 'lockstep_timeout:=%g' % timeout])


def test_a_working_participant_holds_time_and_a_stalled_one_is_dropped(tmp_path):
    stack = sim_stack(tmp_path, '/probe_hold', 4.0)
    try:
        short = stack.probe('hold', '1.5')
        held = read_line(short, 'held', 90)
        assert held, stack.log(3000)
        t0, t1 = (float(v) for v in held.split()[1:])
        assert t0 == pytest.approx(t1, abs=1e-9), 'sim time moved while the participant worked'
        after = read_line(short, 'after', 30)
        assert after and float(after.split()[1]) >= t1 + 0.5 - 1e-6
        assert short.wait(30) == 0
        assert 'dropped participant' not in stack.log()

        # Longer than ~lockstep_timeout (4 s): dropped by name, and time goes on without it.
        stalled = stack.probe('hold', '8')
        assert read_line(stalled, 'holding', 60)
        stack.wait_log('dropped participant /probe_hold', 20)
        assert 'no acknowledgement within ~lockstep_timeout' in stack.log()
        held = read_line(stalled, 'held', 30)
        t0, t1 = (float(v) for v in held.split()[1:])
        assert t1 > t0, 'sim time did not go on after the stalled participant was dropped'
    finally:
        stack.stop()


def test_a_latched_message_from_a_new_publisher_arrives_in_the_tick_it_was_sent(tmp_path):
    """A participant advertises a latched topic mid-tick and publishes at once, before anyone has
    connected; the subscribing participant has the message at its next tick (the next quantum),
    not whenever the connection happened to be made in wall time."""
    stack = sim_stack(tmp_path, '/probe_latch_pub /probe_latch_sub', 10.0)
    try:
        sub = stack.probe('latch_sub')
        pub = stack.probe('latch_pub')
        published = read_line(pub, 'published', 60)
        seen = read_line(sub, 'seen', 60)
        assert published and seen, (published, seen, stack.log(3000))
        t_pub = float(published.split()[1])
        t_seen, data = (float(v) for v in seen.split()[1:])
        assert data == pytest.approx(t_pub, abs=1e-6)
        # Mail makes it due at the next quantum (5 ms): the round's ticks are chosen at its start.
        assert t_seen == pytest.approx(t_pub + 0.005, abs=1e-6), (
            'published at %.3f, seen at %.3f' % (t_pub, t_seen))
        assert pub.wait(30) == 0 and sub.wait(30) == 0
    finally:
        stack.stop()


def test_a_wait_with_poll_sees_a_non_wake_topic_within_one_poll(tmp_path):
    """A predicate on a topic that does not wake the script (ground truth) is checked every
    `poll` s of sim time, not only at the wait's 30 s deadline."""
    stack = sim_stack(tmp_path, '/probe_poll', 10.0)
    try:
        probe = stack.probe('poll')
        polled = read_line(probe, 'polled', 90)
        assert polled, stack.log(3000)
        target, seen = (float(v) for v in polled.split()[1:])
        assert target - 1e-6 <= seen <= target + 0.15, (
            'ground truth stamped %.3f seen at %.3f' % (target, seen))
        assert probe.wait(30) == 0
    finally:
        stack.stop()


def test_a_killed_participant_is_dropped_and_the_loop_goes_on(tmp_path):
    stack = sim_stack(tmp_path, '/probe_hold', 30.0)
    try:
        victim = stack.probe('hold', '60')
        assert read_line(victim, 'holding', 90), stack.log(3000)
        os.killpg(victim.pid, signal.SIGKILL)
        victim.wait(10)
        # Detected by its vanished connection, long before the 30 s time-out.
        stack.wait_log('its process is gone', 15)
        assert 'dropped participant /probe_hold' in stack.log()
        # Time goes on: a new participant joins and sees 0.5 s pass.
        again = stack.probe('hold', '0')
        held = read_line(again, 'held', 60)
        assert held
        after = read_line(again, 'after', 30)
        assert after and float(after.split()[1]) >= float(held.split()[2]) + 0.5 - 1e-6
    finally:
        stack.stop()


def test_a_stalled_robot_is_dropped_by_name_and_the_other_robot_goes_on(tmp_path):
    """Two robots' participants, /robot1/probe_hold and /robot2/probe_hold: robot1's stalls
    after 0.5 s of sim time; sim time waits for it (robot2, ticked after it in the same round, is
    held at the same time) until ~lockstep_timeout drops /robot1/probe_hold by name, and robot2's
    goes on.
    Catches a drop of the wrong node (a name resolved without its namespace) and a loop that stops
    for every robot once one has stalled."""
    stack = sim_stack(tmp_path, '/robot1/probe_hold /robot2/probe_hold', 4.0)
    try:
        stalled = stack.probe('hold', '8', '__ns:=robot1')
        other = stack.probe('hold', '0', '__ns:=robot2')
        assert read_line(stalled, 'holding', 90), stack.log(3000)
        held = read_line(other, 'held', 60)
        assert held, stack.log(3000)
        assert 'dropped participant /robot1/probe_hold' in stack.log(), stack.log(3000)
        assert 'dropped participant /robot2' not in stack.log()
        t0, t1 = (float(v) for v in held.split()[1:])
        assert t1 == t0, held
        after = read_line(other, 'after', 30)
        assert after and float(after.split()[1]) >= t1 + 0.5 - 1e-6, after
        assert other.wait(30) == 0
        assert 'dropped participant /robot2' not in stack.log()
        # robot2 was held at the sim time robot1 stalled at (robot1 prints it once it is done).
        stalled_held = read_line(stalled, 'held', 30)
        assert stalled_held and float(stalled_held.split()[1]) == t0, (stalled_held, held)
    finally:
        stack.stop()


def closed_loop(tmp_path, rtf):
    tmp_path.mkdir(parents=True, exist_ok=True)
    stack = Stack(tmp_path, ['minibot3d_navigation', 'amcl_navigation.launch'],
                  ['lockstep:=true', 'real_time_factor:=%s' % rtf,
                   'lockstep_participants:=/amcl /move_base /probe_route'])
    out = str(tmp_path / 'route.json')
    try:
        client = stack.probe('route', out)
        assert client.wait(300) == 0, client.stdout.read() + stack.log(3000)
    finally:
        stack.stop()
    with open(out) as f:
        return json.load(f)


def test_two_closed_loop_runs_are_identical_at_any_real_time_factor(tmp_path):
    first = closed_loop(tmp_path / 'a', 0)
    assert [g[0] for g in first['goals']] == [3, 3], first['goals']  # SUCCEEDED
    assert len(first['path']) > 500
    second = closed_loop(tmp_path / 'b', 0)
    assert second['goals'] == first['goals']
    assert second['path'] == first['path']
    paced = closed_loop(tmp_path / 'c', 1)
    assert paced['goals'] == first['goals']
    assert paced['path'] == first['path']
