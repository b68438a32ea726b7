"""minibot3d_testing: masters of their own on ports nobody else holds, also when started at once,
on a port another socket or another master holds; stacks on them; process groups stopped; waits
that fail naming what they waited for; the command-line form the shell scripts use."""
import os
import signal
import socket
import subprocess
import sys
import threading
import time

import pytest
import rosgraph

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'src'))
from minibot3d_testing import (RosCore, Stack, WaitTimeout, candidate_ports,  # noqa: E402
                               descendants, group_members, master_pid, stop_group, wait_until)

# A launch file that sets one parameter and runs one node, to tell two stacks apart.
LAUNCH = """<launch>
  <arg name="who"/>
  <param name="who" value="$(arg who)"/>
  <node name="sleeper" pkg="rosout" type="rosout" args="__name:=sleeper"/>
</launch>
"""


def param(uri, name):
    return rosgraph.Master('/test_minibot3d_testing', master_uri=uri).getParam(name)


def node_up(master, name):
    try:
        return master.lookupNode(name)
    except rosgraph.MasterError:
        return None


def test_wait_until_returns_the_value_and_fails_naming_what_it_waited_for():
    calls = []
    assert wait_until(lambda: calls.append(1) or (len(calls) >= 3 and 'done'), 5, 'x') == 'done'
    start = time.monotonic()
    with pytest.raises(WaitTimeout, match='timed out after 0.2 s waiting for the answer 42'):
        wait_until(lambda: False, 0.2, 'the answer 42')
    assert time.monotonic() - start < 2
    with pytest.raises(AssertionError, match='waiting for text made late'):
        wait_until(lambda: False, 0.1, lambda: 'text made late')


def test_candidate_ports_are_not_handed_out_twice():
    ports = candidate_ports()
    taken = [next(ports) for _ in range(50)]
    assert len(set(taken)) == 50
    assert not set(taken) & {next(candidate_ports()) for _ in range(20)}


def test_core_answers_as_itself_and_is_gone_after_stop(tmp_path):
    with RosCore(log_dir=tmp_path) as core:
        master = core.processes[0]
        assert master_pid(core.uri) == master.pid
        assert core.env['ROS_MASTER_URI'] == core.uri and core.env['ROS_IP'] == '127.0.0.1'
        wait_until(lambda: node_up(rosgraph.Master('/t', master_uri=core.uri), '/rosout'), 30,
                   'rosout to register')
        pgids = [p.pid for p in core.processes]
    assert master_pid(core.uri) is None
    assert not any(group_members(g) for g in pgids)


def test_a_port_held_by_another_socket_is_given_up_for_another(tmp_path):
    with socket.socket() as holder:
        holder.bind(('127.0.0.1', 0))
        holder.listen(1)  # connects, never answers: a server of something else
        taken = holder.getsockname()[1]
        with RosCore(log_dir=tmp_path, ports=[taken]) as core:
            assert core.port != taken
            assert core.tried and core.tried[0].startswith('%d: ' % taken), core.tried
            assert 'already in use' in core.tried[0], core.tried
            assert master_pid(core.uri) == core.processes[0].pid


def test_a_port_of_another_master_is_given_up_and_that_master_left_alone(tmp_path):
    with RosCore(log_dir=tmp_path / 'a', rosout=False) as first:
        rosgraph.Master('/t', master_uri=first.uri).setParam('/owner', 'first')
        with RosCore(log_dir=tmp_path / 'b', rosout=False, ports=[first.port]) as second:
            assert second.port != first.port, second.tried
            assert master_pid(first.uri) == first.processes[0].pid
            assert master_pid(second.uri) == second.processes[0].pid
            assert not rosgraph.Master('/t', master_uri=second.uri).hasParam('/owner')
        assert param(first.uri, '/owner') == 'first'


def test_two_stacks_started_at_once_on_the_same_first_port_get_masters_of_their_own(tmp_path):
    launch = tmp_path / 'who.launch'
    launch.write_text(LAUNCH)
    port = next(candidate_ports())
    stacks, errors = {}, []

    def start(name):
        try:
            (tmp_path / name).mkdir()
            stacks[name] = Stack(['roslaunch', str(launch), 'who:=' + name],
                                 tmp_path / name / 'launch.log', log_dir=tmp_path / name,
                                 env=dict(os.environ, ROS_HOME=str(tmp_path / name)),
                                 ports=[port])
        except Exception as e:  # noqa: BLE001 -- reported below
            errors.append(e)
    threads = [threading.Thread(target=start, args=(n,)) for n in ('a', 'b')]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    try:
        assert not errors, errors
        a, b = stacks['a'], stacks['b']
        assert a.core.port != b.core.port
        # One of them had the port and the other moved on. The port is only a candidate (free
        # when asked, not reserved): when another process's connection took it meanwhile, both
        # moved on, and each says so for that port.
        if port not in (a.core.port, b.core.port):
            for s in (a, b):
                assert s.core.tried and s.core.tried[0].startswith('%d: ' % port), s.core.tried
        for name, s in stacks.items():
            master = rosgraph.Master('/t', master_uri=s.core.uri)
            assert master_pid(s.core.uri) == s.core.processes[0].pid
            wait_until(lambda: master.hasParam('/who'), 60,
                       lambda: 'stack %s to set /who:\n%s' % (name, s.log(3000)))
            assert master.getParam('/who') == name
            wait_until(lambda: node_up(master, '/sleeper'), 60,
                       lambda: "stack %s's node:\n%s" % (name, s.log(3000)))
    finally:
        for s in stacks.values():
            s.stop()
    for s in stacks.values():
        assert not s.launch.running()
        assert master_pid(s.core.uri) is None


def test_stop_group_kills_what_ignores_sigint(tmp_path):
    script = 'trap "" INT; sleep 300 & sleep 300; wait'
    p = subprocess.Popen(['bash', '-c', script], start_new_session=True)
    wait_until(lambda: len(group_members(p.pid)) >= 3, 10, 'the group to start its children')
    assert sorted(descendants(p.pid)) == sorted(group_members(p.pid))  # bash and its two sleeps
    assert descendants(os.getpid())[0] == os.getpid() and p.pid in descendants(os.getpid())
    start = time.monotonic()
    assert stop_group(p.pid, grace=0.5, proc=p)
    assert time.monotonic() - start < 10
    assert p.returncode == -signal.SIGKILL
    assert not group_members(p.pid)


def test_the_command_line_starts_and_stops_a_core():
    out = subprocess.run([sys.executable, '-m', 'minibot3d_testing', 'start-core'],
                         capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(
                             [os.path.join(HERE, '..', 'src'), os.environ.get('PYTHONPATH', '')])))
    assert out.returncode == 0, out.stderr
    uri, *pgids = out.stdout.split()
    try:
        assert uri.startswith('http://127.0.0.1:') and len(pgids) == 2
        assert master_pid(uri) == int(pgids[0])
    finally:
        stopped = subprocess.run([sys.executable, '-m', 'minibot3d_testing', 'stop'] + pgids,
                                 capture_output=True, text=True, timeout=60,
                                 env=dict(os.environ, PYTHONPATH=os.pathsep.join(
                                     [os.path.join(HERE, '..', 'src'),
                                      os.environ.get('PYTHONPATH', '')])))
    assert stopped.returncode == 0, stopped.stderr
    assert master_pid(uri) is None
    assert not any(group_members(int(g)) for g in pgids)
