"""Lock-step time with real processes: the simulator, real nodes and test participants
(lockstep_probe.py), each run on a ROS master of its own.

- a participant that works for a while stops sim time, and one that stops answering for
  ~lockstep_timeout (when set) is dropped with a warning naming it, after which time goes on;
- by default a participant stopped (SIGSTOP, as in a debugger) for 12 s wall is waited for, and
  goes on where it stopped;
- a participant killed while it holds a tick is dropped and the loop goes on;
- a C++ participant ticked every 2 s has every /tf message of those 2 s in its tf buffer (lock-step's
  tf listener; tf2_ros's, which keeps 100, is shown to lose some);
- a burst of 200 messages published in one tick through a one-message publisher queue (rospy and
  roscpp) reaches its receiving participant whole;
- participants of several robots (/robot1/..., /robot2/...): a stalled one is dropped by its full
  name, and the other robot's go on;
- the closed loop (simulator + amcl + move_base + a goal client) gives the same trajectory and
  times twice at real_time_factor 0 (the second time beside two busy processes), and again at
  real_time_factor 1, and the lock-step digests of the runs (every message each participant
  received, tick by tick) agree;
- so do the digests of two explorations (SLAM + move_base + explore), one beside busy processes,
  and of one at real_time_factor 0 against one paced at 1, and of two mapless runs through
  clutter (move_base alone, odometry error), one beside busy processes.
Every wait is on a condition (a line of output, a file, a process exit) with a time limit."""
import json
import os
import re
import signal
import subprocess
import sys
import time

import minibot3d_testing as testing
import pytest
import rospkg
from minibot3d_lockstep import digest

DIGEST_ENV = digest.DIGEST_ENV

HERE = os.path.dirname(os.path.abspath(__file__))
PROBE = os.path.join(HERE, 'lockstep_probe.py')


class Stack(testing.Stack):
    """roslaunch on a master of its own, plus probes on the same master."""

    def __init__(self, tmp_path, launch, args, digest=None):
        """digest: where the run's lock-step digest goes (None: not written)."""
        env = dict(os.environ, ROS_HOME=str(tmp_path))
        env.pop(DIGEST_ENV, None)
        if digest:
            env[DIGEST_ENV] = digest
        super().__init__(['roslaunch'] + launch + args, tmp_path / 'launch.log', env=env)
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


def sim_stack(tmp_path, participant, timeout=None):
    """timeout: ~lockstep_timeout (None: the default, never)."""
    return Stack(tmp_path, ['minibot3d_sim', 'minibot3d_gazebo.launch'],
                 ['lockstep:=true', 'real_time_factor:=0', 'physics:=kinematic',
                  'lockstep_participants:=' + participant] +
                 ([] if timeout is None else ['lockstep_timeout:=%g' % timeout]))


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


def test_a_participant_stopped_as_in_a_debugger_is_waited_for_not_dropped(tmp_path):
    """Slow is not dead: with the default ~lockstep_timeout a participant that does not answer for
    12 s wall (stopped with SIGSTOP, as a debugger stops it) keeps sim time
    where it is and carries on when it continues. Breakage caught: a wall-clock time-out that
    drops a live participant (the run then depends on the machine's load)."""
    stack = sim_stack(tmp_path, '/probe_hold')
    try:
        probe = stack.probe('hold', '0.2')
        assert read_line(probe, 'holding', 90), stack.log(3000)
        os.kill(probe.pid, signal.SIGSTOP)
        try:
            # The simulator says whom it waits for, and for how long so far: past 12 s wall, and
            # nobody dropped.
            def waited():
                return max([float(w) for w in re.findall(
                    r'waits for /probe_hold \(([0-9.]+) s wall so far', stack.log())] or [0.0])
            testing.wait_until(lambda: waited() >= 12.0, 60, lambda: stack.log(3000),
                               interval=0.5)
            assert 'dropped participant' not in stack.log(), stack.log(3000)
        finally:
            os.kill(probe.pid, signal.SIGCONT)
        held = read_line(probe, 'held', 30)
        assert held, stack.log(3000)
        t0, t1 = (float(v) for v in held.split()[1:])
        assert t0 == pytest.approx(t1, abs=1e-9), 'sim time moved while the participant was stopped'
        assert read_line(probe, 'after', 30)
        assert probe.wait(30) == 0
        assert 'dropped participant' not in stack.log()
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


def test_a_participant_ticked_every_2_s_has_every_tf_message_in_its_buffer(tmp_path):
    """A C++ participant ticked every 2 s of sim time receives ~400 /tf messages in between (a
    transform every 10 ms from a probe, the simulator's odometry): with lock-step's tf listener
    every 10 ms sample is in its buffer; tf2_ros's listener (100 messages kept) lost some, which
    the same check finds (so the check can fail)."""
    results = {}
    for mode in ('lockstep', 'tf2_ros'):
        stack = sim_stack(tmp_path, '/probe_zigzag /tf_listener_probe', 30.0)
        try:
            zig = stack.probe('zigzag', '12')
            probe = stack.start(['rosrun', 'minibot3d_lockstep', 'tf_listener_probe', mode, '3'],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                universal_newlines=True).proc
            line = read_line(probe, 'tf_probe', 120)
            assert line, stack.log(3000)
            _, _, _, checked, _, wrong = line.split()
            results[mode] = (int(checked), int(wrong))
            assert read_line(zig, 'zigzag done', 60), stack.log(3000)
        finally:
            stack.stop()
    assert results['lockstep'] == (3 * 191, 0), results
    assert results['tf2_ros'][1] > 0, results


BURST = 200


@pytest.mark.parametrize('sender', ['rospy', 'roscpp'])
def test_a_burst_through_a_one_message_queue_reaches_its_receiver_whole(tmp_path, sender):
    """A participant publishes 200 messages in one tick through a publisher whose queue holds one
    (rospy's queue_size=1, roscpp's advertise queue 1); the receiving participant (woken by the
    topic) has all 200, in order, when it is next ticked. Breakage caught: a publisher queue that
    drops messages its writer thread has not yet sent (which ones depends on thread timing): the
    sender's ack counts them all, so the receiver would wait for the dropped ones for ever."""
    name = '/probe_burst' if sender == 'rospy' else '/burst_probe'
    stack = sim_stack(tmp_path, '/probe_burst_count ' + name)
    try:
        counter = stack.probe('burst_count')
        if sender == 'rospy':
            burst = stack.probe('burst', str(BURST))
        else:
            burst = stack.start(['rosrun', 'minibot3d_lockstep', 'burst_probe', str(BURST)],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                universal_newlines=True).proc
        sent = read_line(burst, 'burst', 90)
        assert sent, stack.log(3000)
        counted = read_line(counter, 'counted', 60)
        assert counted, 'the receiver never had the burst:\n' + stack.log(3000)
        _, at, n, total = counted.split()
        assert (int(n), int(total)) == (BURST, BURST * (BURST + 1) // 2), counted
        assert float(at) >= float(sent.split()[1]) - 1e-9
        assert burst.wait(30) == 0 and counter.wait(30) == 0
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


class Busy(object):
    """n processes that keep a core each busy while the block runs (CPU load)."""

    def __init__(self, n):
        self.n, self.procs = n, []

    def __enter__(self):
        self.procs = [subprocess.Popen([sys.executable, '-c', 'while True: pass'])
                      for _ in range(self.n)]
        return self

    def __exit__(self, *exc):
        for p in self.procs:
            p.kill()
            p.wait()


def closed_loop(tmp_path, rtf, busy=0, launch=('minibot3d_navigation', 'amcl_navigation.launch'),
                participants='/amcl /move_base', args=(), goals=()):
    """A route of move_base goals (lockstep_probe.py route; goals: FRAME X,Y,YAW ..., by default
    the probe's) in the stack `launch` starts; returns the probe's results."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    with Busy(busy):
        stack = Stack(tmp_path, list(launch),
                      ['lockstep:=true', 'real_time_factor:=%s' % rtf,
                       'lockstep_participants:=%s /probe_route' % participants] + list(args),
                      digest=str(tmp_path / 'digest'))
        out = str(tmp_path / 'route.json')
        try:
            client = stack.probe('route', out, *goals)
            assert client.wait(300) == 0, client.stdout.read() + stack.log(3000)
        finally:
            stack.stop()
    with open(out) as f:
        return json.load(f)


def test_two_closed_loop_runs_are_identical_at_any_real_time_factor_and_load(tmp_path):
    first = closed_loop(tmp_path / 'a', 0)
    assert [g[0] for g in first['goals']] == [3, 3], first['goals']  # SUCCEEDED
    assert len(first['path']) > 500
    second = closed_loop(tmp_path / 'b', 0, busy=2)
    assert second['goals'] == first['goals']
    assert second['path'] == first['path']
    paced = closed_loop(tmp_path / 'c', 1)
    assert paced['goals'] == first['goals']
    assert paced['path'] == first['path']
    # Tick by tick, every participant received the same messages. Breakage caught: a participant
    # whose output depends on the wall clock or on thread timing (say, a timer that fires at the
    # tick it falls due in at one speed and the next at another).
    for other in ('b', 'c'):
        result = digest.compare(str(tmp_path / 'a' / 'digest'), str(tmp_path / other / 'digest'))
        assert result.identical, '\n'.join(digest.report(result, 'a', other))
        # The simulator, amcl, move_base and the client, compared over the whole route.
        assert result.sections >= 4, digest.report(result, 'a', other)
        assert float(result.last_stamp[1]) >= first['path'][-1][0], \
            digest.report(result, 'a', other)


def test_two_mapless_runs_through_clutter_are_identical_beside_busy_processes(tmp_path):
    """The mapless loop (move_base with its global costmap in odom, no map, no amcl; a robot with
    a typical odometry error) through a clutter world to a goal 5.5 m ahead in odom, twice, the
    second time beside two busy processes: the same result, trajectory and digests. Breakage
    caught: timing-dependent behaviour in the rolling costmaps and the odometry error model,
    which the map-based loop above does not use."""
    sim = rospkg.RosPack().get_path('minibot3d_sim')
    world = os.path.join(sim, 'worlds', 'clutter', 'clutter_43.world')
    error = os.path.join(sim, 'config', 'typical_odometry_error.yaml')
    kwargs = dict(launch=('minibot3d_navigation', 'mapless_navigation.launch'),
                  participants='/move_base',
                  args=('world:=' + world, 'odom_error_params:=' + error),
                  goals=('odom', '5.5,0.0,0.0'))
    first = closed_loop(tmp_path / 'a', 0, **kwargs)
    assert [g[0] for g in first['goals']] == [3], first['goals']  # SUCCEEDED
    assert len(first['path']) > 300
    second = closed_loop(tmp_path / 'b', 0, busy=2, **kwargs)
    assert second == first
    result = digest.compare(str(tmp_path / 'a' / 'digest'), str(tmp_path / 'b' / 'digest'))
    assert result.identical, '\n'.join(digest.report(result, 'a', 'b'))
    assert result.sections >= 3, digest.report(result, 'a', 'b')
    assert float(result.last_stamp[1]) >= first['path'][-1][0], digest.report(result, 'a', 'b')


# Sim time of the explorations at full speed, and of the one paced at real time (wall time as
# long): make test's lengths; make bench runs both at 300 s (MINIBOT3D_EXPLORE_SIM_S,
# MINIBOT3D_PACED_SIM_S).
EXPLORE_SIM_S = float(os.environ.get('MINIBOT3D_EXPLORE_SIM_S', '150'))
PACED_SIM_S = float(os.environ.get('MINIBOT3D_PACED_SIM_S', '60'))


def exploration(tmp_path, busy, rtf=0, sim_s=EXPLORE_SIM_S):
    """SLAM + move_base + explore on the default world at real-time factor rtf for sim_s of sim
    time (held from 0 by a probe that then leaves); returns the probe's "ran T" time."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    with Busy(busy):
        stack = Stack(tmp_path, ['minibot3d_navigation', 'explore.launch'],
                      ['lockstep:=true', 'real_time_factor:=%g' % rtf,
                       'lockstep_clients:=/probe_run_for'],
                      digest=str(tmp_path / 'digest'))
        try:
            probe = stack.probe('run_for', '%g' % sim_s)
            # Paced, the run takes at least its sim time divided by the factor in wall time.
            ran = read_line(probe, 'ran', 600 + (sim_s / rtf if rtf > 0 else 0.0))
            assert ran, stack.log(3000)
            assert probe.wait(30) == 0
            # explore's goals reached move_base: the loop ran.
            assert 'move_base: new goal' in stack.log(), stack.log(3000)
        finally:
            stack.stop()
    return float(ran.split()[1])


def assert_explorations_agree(tmp_path, a, b, ran, sim_s):
    """The digests of explorations a and b (directories under tmp_path) agree tick for tick up to
    the probe's end `ran` (after it, time runs on until the stack is stopped, a wall-clock moment
    at which its nodes die one after the other), for the three participants, the probe and the
    simulator, over at least sim_s."""
    result = digest.compare(str(tmp_path / a / 'digest'), str(tmp_path / b / 'digest'), until=ran)
    assert result.identical, '\n'.join(digest.report(result, a, b))
    assert result.sections >= 5, digest.report(result, a, b)
    reached = digest.stamp_key(result.last_stamp[1])
    assert reached >= (int(sim_s), 0), digest.report(result, a, b)


def test_two_explorations_agree_tick_for_tick_beside_busy_processes(tmp_path):
    """The loop that builds a map (SLAM, costmaps, frontier choice, move_base) twice, the second
    time beside two busy processes: every participant receives the same messages at the same
    ticks for the whole EXPLORE_SIM_S. Breakage caught: anything in that loop that depends on
    thread timing under load (a timer firing a tick late, callbacks in socket order, a
    participant that goes on without a message it was sent), which the route above, without SLAM
    and explore, does not exercise. make bench compares whole demos the same way."""
    ran_a = exploration(tmp_path / 'a', 0)
    ran_b = exploration(tmp_path / 'b', 2)
    assert ran_a == ran_b >= EXPLORE_SIM_S
    assert_explorations_agree(tmp_path, 'a', 'b', ran_a, EXPLORE_SIM_S)


def test_an_exploration_paced_at_real_time_agrees_with_one_at_full_speed(tmp_path):
    """The same loop at real_time_factor 1 (PACED_SIM_S of wall time) and at 0: the same messages
    at the same ticks. Breakage caught: anything that reads the wall clock or depends on how much
    wall time a tick takes (a wall-time timer, a timeout in wall seconds deciding an outcome)."""
    ran_fast = exploration(tmp_path / 'fast', 0, sim_s=PACED_SIM_S)
    ran_paced = exploration(tmp_path / 'paced', 0, rtf=1, sim_s=PACED_SIM_S)
    assert ran_fast == ran_paced >= PACED_SIM_S
    assert_explorations_agree(tmp_path, 'fast', 'paced', ran_fast, PACED_SIM_S)
