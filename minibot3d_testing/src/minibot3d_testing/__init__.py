"""Helpers for the tests and tools that start ROS processes: a ROS master of their own on a port no
other process holds, roslaunch'd stacks on it, process groups stopped cleanly, bounded waits.

Picking a port by binding a socket to port 0 and closing it, then starting a master there, is a
race: another process (a test running in parallel) can take the port in between, and roslaunch or
roscore, finding a master already there, joins it. RosCore therefore starts rosmaster itself and
takes a port only once the master answering there reports rosmaster's own PID. When rosmaster
cannot have the port (it says the port is in use, it exits, or another master answers there) it is
stopped and started again on another port. Only then does rosout start, and a roslaunch started
with RosCore.env finds its master up and starts just its nodes, so nothing of a run ever registers
with another run's master.

    with RosCore(dict(os.environ, ROS_HOME=str(tmp_path))) as core:   # rosmaster + rosout
        launch = core.start_process(['roslaunch', 'minibot3d_sim', 'minibot3d_gazebo.launch'],
                                    tmp_path / 'launch.log')
        wait_until(lambda: ..., 60, 'the first /scan')
        launch.stop()

Stack is that in one object (a RosCore, a roslaunch on it, the helpers started beside it).
`python3 -m minibot3d_testing start-core` and `... stop` start and stop a core for shell scripts
(tools/ros_env.sh).
"""
import http.client
import itertools
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import threading
import time
import xmlrpc.client

LOOPBACK = '127.0.0.1'
_CALLER_ID = '/minibot3d_testing'


class WaitTimeout(AssertionError):
    """wait_until's condition did not hold in time (an AssertionError, so pytest reports it as a
    failed check)."""


class CoreError(RuntimeError):
    """No master could be started."""


def wait_until(predicate, timeout, what, interval=0.05):
    """Calls predicate() until it returns a true value, and returns that value. Fails with
    WaitTimeout naming `what` after `timeout` wall seconds; `what` may be a function returning the
    text (called only then, e.g. for the tail of a log). An exception from predicate propagates at
    once (a check that the process waited on is still alive belongs there)."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() >= deadline:
            raise WaitTimeout('timed out after %g s waiting for %s' % (
                timeout, what() if callable(what) else what))
        time.sleep(interval)


def ros_env(master_uri, base=None, **extra):
    """The environment of processes on the master at master_uri: base (default os.environ) with
    ROS_MASTER_URI, ROS_IP=127.0.0.1 (every server binds loopback; README "Security") and no
    ROS_HOSTNAME, which would override ROS_IP; then `extra`."""
    env = dict(os.environ if base is None else base)
    env.pop('ROS_HOSTNAME', None)
    env.update(ROS_MASTER_URI=master_uri, ROS_IP=LOOPBACK)
    env.update(extra)
    return env


_ports_lock = threading.Lock()
_ports_handed_out = set()


def candidate_ports():
    """Ports free on 127.0.0.1 when asked (the kernel's choice for port 0), none twice in this
    process. Candidates only: whoever binds one first has it, so a server started on one must
    check that it got it (RosCore does)."""
    while True:
        with socket.socket() as s:
            s.bind((LOOPBACK, 0))
            port = s.getsockname()[1]
        with _ports_lock:
            if port in _ports_handed_out:
                continue
            _ports_handed_out.add(port)
        yield port


# ---- process groups --------------------------------------------------------------------------

def process_table():
    """(pid, state, ppid, pgid) of every process, from /proc/PID/stat (state 'Z' or 'X': exited,
    not yet reaped)."""
    table = []
    for entry in os.listdir('/proc'):
        if not entry.isdigit():
            continue
        try:
            with open('/proc/%s/stat' % entry) as f:
                stat = f.read()
        except OSError:
            continue  # gone meanwhile
        fields = stat[stat.rindex(')') + 2:].split()  # after "pid (comm) ": state ppid pgrp ...
        table.append((int(entry), fields[0], int(fields[1]), int(fields[2])))
    return table


def group_members(pgid):
    """PIDs of the live (non-zombie) processes of process group pgid."""
    return [pid for pid, state, _, group in process_table()
            if group == pgid and state not in ('Z', 'X')]


def descendants(root):
    """root and every process below it."""
    children = {}
    for pid, _, ppid, _ in process_table():
        children.setdefault(ppid, []).append(pid)
    out, todo = [], [root]
    while todo:
        pid = todo.pop()
        out.append(pid)
        todo.extend(children.get(pid, []))
    return out


def stop_group(pgid, grace=20.0, proc=None):
    """Ends process group pgid: SIGINT to all of it (roslaunch then shuts its nodes down in
    order), SIGKILL to whatever is left after `grace` seconds. Returns once no member is alive
    (True), or False if some survive SIGKILL for 10 s. proc: the group leader's Popen, reaped
    here."""
    for sig, wait_s in ((signal.SIGINT, grace), (signal.SIGKILL, 10.0)):
        try:
            os.killpg(pgid, sig)
        except ProcessLookupError:
            pass
        deadline = time.monotonic() + wait_s
        while True:
            if proc is not None:
                proc.poll()  # reaps the leader once it has exited
            if not group_members(pgid):  # zombies do not count
                try:
                    if proc is not None:
                        proc.wait(10.0)  # a zombie by now, unless it left the group
                except subprocess.TimeoutExpired:
                    return False
                return True
            if time.monotonic() > deadline:
                break
            time.sleep(0.05)
    return False


class Process(object):
    """A command in a process group of its own (setsid), so stop() reaches every process it
    starts, and nothing else. Its stdout and stderr go to log_path when given (appended), else
    where popen_kwargs say (default: nowhere)."""

    def __init__(self, cmd, env=None, log_path=None, **popen_kwargs):
        self.cmd = [str(c) for c in cmd]
        self.log_path = str(log_path) if log_path is not None else None
        self._log = None
        if self.log_path is not None:
            self._log = open(self.log_path, 'ab')
            popen_kwargs.setdefault('stdout', self._log)
            popen_kwargs.setdefault('stderr', subprocess.STDOUT)
        else:
            popen_kwargs.setdefault('stdout', subprocess.DEVNULL)
            popen_kwargs.setdefault('stderr', subprocess.DEVNULL)
        popen_kwargs.setdefault('stdin', subprocess.DEVNULL)
        self.proc = subprocess.Popen(self.cmd, env=env, start_new_session=True, **popen_kwargs)
        self.pid = self.proc.pid

    def running(self):
        return self.proc.poll() is None

    def wait(self, timeout=None):
        """The exit status, or None if it still runs after `timeout` seconds."""
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            return None

    def log(self, tail=None):
        """What it has written to log_path so far (the last `tail` characters), or ''."""
        if self.log_path is None:
            return ''
        with open(self.log_path, errors='replace') as f:
            text = f.read()
        return text[-tail:] if tail else text

    def stop(self, grace=20.0):
        """Stops the whole group (stop_group); the exit status of the command itself."""
        stop_group(self.pid, grace, self.proc)
        if self._log is not None:
            self._log.close()
            self._log = None
        return self.proc.poll()


# ---- the master ------------------------------------------------------------------------------

class _Transport(xmlrpc.client.Transport):
    """XML-RPC over HTTP with a time limit: something else listening on a port may never answer."""

    def __init__(self, timeout):
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host):
        conn = super().make_connection(host)
        conn.timeout = self._timeout
        return conn


def master_pid(uri, timeout=1.0):
    """The PID the master at uri reports, or None when nothing there answers as a master."""
    proxy = xmlrpc.client.ServerProxy(uri, transport=_Transport(timeout))
    try:
        code, _, pid = proxy.getPid(_CALLER_ID)
    except (OSError, xmlrpc.client.Error, http.client.HTTPException, ValueError, TypeError):
        return None
    return pid if code == 1 else None


def _rosout_executable():
    import roslib.packages
    found = roslib.packages.find_node('rosout', 'rosout')
    if not found:
        raise CoreError('rosout is not installed (Debian package rosout)')
    return found[0]


class RosCore(object):
    """rosmaster and rosout (what roscore starts) for one test or run, on a port no other process
    holds; each in a process group of its own.

    env: the environment they and everything started with .env run in (default os.environ);
    log_dir: where rosmaster's output goes (default a temporary directory, removed by stop());
    rosout: start rosout too; timeout: wall seconds to get a master at all; ports: ports to try
    before the kernel's candidates (tests use it to hand over a taken one); preexec_fn: passed to
    Popen for both processes (after their setsid).

    After start(): .uri, .port, .env (env pointing at this master, see ros_env), .tried (the ports
    given up, each with the reason)."""

    def __init__(self, env=None, log_dir=None, rosout=True, timeout=60.0, ports=(),
                 preexec_fn=None):
        self.base_env = dict(os.environ if env is None else env)
        self.rosout = rosout
        self.timeout = timeout
        self.ports = list(ports)
        self.preexec_fn = preexec_fn
        self._own_log_dir = log_dir is None
        self.log_dir = str(log_dir) if log_dir is not None else None
        self.uri = self.port = self.env = None
        self.tried = []
        self.processes = []

    def start(self):
        if self._own_log_dir:
            self.log_dir = tempfile.mkdtemp(prefix='roscore_')
        else:
            os.makedirs(self.log_dir, exist_ok=True)
        deadline = time.monotonic() + self.timeout
        try:
            for port in itertools.chain(self.ports, candidate_ports()):
                why = self._start_master(port, deadline)
                if why is None:
                    break
                self.tried.append('%d: %s' % (port, why))
                if time.monotonic() >= deadline:
                    raise CoreError('no ROS master within %g s; ports tried: %s' % (
                        self.timeout, '; '.join(self.tried)))
            if self.rosout:
                self.processes.append(Process(
                    [_rosout_executable()], self.env,
                    os.path.join(self.log_dir, 'rosout-%d.log' % self.port),
                    preexec_fn=self.preexec_fn))
        except BaseException:
            self.stop()
            raise
        return self

    def _start_master(self, port, deadline):
        """Starts rosmaster on port; None once it answers there as itself, else why not (it has
        been stopped again)."""
        uri = 'http://%s:%d' % (LOOPBACK, port)
        env = ros_env(uri, self.base_env, PYTHONUNBUFFERED='1')  # its "in use" line at once
        master = Process(['rosmaster', '--core', '-p', str(port)], env,
                         os.path.join(self.log_dir, 'rosmaster-%d.log' % port),
                         preexec_fn=self.preexec_fn)
        while True:
            said = master.log()
            if not master.running():
                why = 'rosmaster exited with status %s: %s' % (master.proc.returncode,
                                                               said[-500:].strip())
            elif 'Unable to start XML-RPC server' in said:  # e.g. "port N is already in use"
                why = said.strip().splitlines()[-1]
            else:
                pid = master_pid(uri)
                if pid == master.pid:
                    self.uri, self.port = uri, port
                    self.env = ros_env(uri, self.base_env)
                    self.processes.append(master)
                    return None
                why = None if pid is None else 'another master (PID %d) answers there' % pid
                if why is None and time.monotonic() >= deadline:
                    why = 'rosmaster did not answer there: %s' % said[-500:].strip()
            if why is not None:
                master.stop(grace=5.0)
                return why
            time.sleep(0.05)

    def start_process(self, cmd, log_path=None, env=None, **popen_kwargs):
        """A Process running cmd on this master (env: extra variables over .env); stop() it, or
        use a Stack, which stops its processes with it."""
        return Process(cmd, dict(self.env, **(env or {})), log_path, **popen_kwargs)

    def stop(self):
        """Stops rosout, then the master; removes the log directory if it made it."""
        for p in reversed(self.processes):
            p.stop(grace=10.0)
        self.processes = []
        if self._own_log_dir and self.log_dir is not None:
            shutil.rmtree(self.log_dir, ignore_errors=True)
            self.log_dir = None

    def __enter__(self):
        return self.start()

    def __exit__(self, *exc):
        self.stop()


class Stack(object):
    """A roslaunch (or any command: launch_cmd) on a RosCore of its own, and helpers started
    beside it with start(); stop() ends the helpers, the launch, then the core.

    env, core_kwargs: as RosCore's. .env is the environment of everything in the stack, .launch
    the launch's Process (its output in log_path)."""

    def __init__(self, launch_cmd, log_path, env=None, **core_kwargs):
        self.core = RosCore(env, **core_kwargs).start()
        self.env = self.core.env
        self.processes = []
        try:
            self.launch = self.core.start_process(launch_cmd, log_path)
        except BaseException:
            self.core.stop()
            raise

    def start(self, cmd, log_path=None, **popen_kwargs):
        """A helper (a goal client, a probe) on the stack's master, stopped with the stack."""
        p = self.core.start_process(cmd, log_path, **popen_kwargs)
        self.processes.append(p)
        return p

    def log(self, tail=None):
        """The launch's output so far (its last `tail` characters)."""
        return self.launch.log(tail)

    def stop(self):
        for p in reversed(self.processes):
            p.stop()
        self.launch.stop()
        self.core.stop()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()
