"""Process groups for trials: each stack (roslaunch + its master + nodes) and each driver runs in
its own session, so one killpg reaches every process of a trial and nothing else.  Stopping is
SIGINT to the group (roslaunch shuts its nodes down in order), then SIGKILL to whatever is left
after a grace period; a group is gone when /proc lists none of its members alive (zombies, which
an init that does not reap would leave, do not count).

Every process started here carries TUNE_PLANNER_RUN=<study dir> in its environment (inherited by
roslaunch's children), so a caller can find anything of a study that is still running.
"""
import ctypes
import os
import signal
import socket
import subprocess
import threading
import time

MARKER = 'TUNE_PLANNER_RUN'
_PR_SET_PDEATHSIG = 1

_ports_lock = threading.Lock()
_ports_taken = set()


def free_port():
    """A TCP port free now on 127.0.0.1 and not handed out before by this process."""
    with _ports_lock:
        for _ in range(100):
            s = socket.socket()
            s.bind(('127.0.0.1', 0))
            port = s.getsockname()[1]
            s.close()
            if port not in _ports_taken:
                _ports_taken.add(port)
                return port
    raise RuntimeError('no free TCP port')


def _die_with_parent():
    """preexec_fn: new session, and SIGTERM if the tool dies without cleaning up (SIGKILL)."""
    os.setsid()
    try:
        ctypes.CDLL('libc.so.6', use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except OSError:
        pass


def group_members(pgid):
    """PIDs of live (non-zombie) processes in process group pgid, from /proc."""
    members = []
    for entry in os.listdir('/proc'):
        if not entry.isdigit():
            continue
        try:
            with open('/proc/%s/stat' % entry) as f:
                stat = f.read()
        except OSError:
            continue
        fields = stat[stat.rindex(')') + 2:].split()  # state ppid pgrp ...
        if int(fields[2]) == pgid and fields[0] not in ('Z', 'X'):
            members.append(int(entry))
    return members


def processes_with_marker(value):
    """PIDs of live processes whose environment has TUNE_PLANNER_RUN=value."""
    needle = ('%s=%s' % (MARKER, value)).encode() + b'\0'
    found = []
    for entry in os.listdir('/proc'):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open('/proc/%s/environ' % entry, 'rb') as f:
                env = f.read() + b'\0'
            with open('/proc/%s/stat' % entry) as f:
                state = f.read().rsplit(')', 1)[1].split()[0]
        except OSError:
            continue
        if needle in env and state not in ('Z', 'X'):
            found.append(int(entry))
    return found


class Group(object):
    """A command in its own session; stop() ends the whole group."""

    def __init__(self, cmd, env, log_path, registry=None):
        self.log = open(log_path, 'ab')
        self.proc = subprocess.Popen(cmd, env=env, stdout=self.log, stderr=subprocess.STDOUT,
                                     stdin=subprocess.DEVNULL, preexec_fn=_die_with_parent)
        self.pgid = self.proc.pid
        self.registry = registry
        if registry is not None:
            registry.add(self)

    def wait(self, timeout):
        """Exit status, or None if still running after timeout wall seconds."""
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            return None

    def stop(self, grace=15.0):
        """SIGINT the group, SIGKILL what is left after `grace` s; returns once none is alive."""
        for sig, wait_s in ((signal.SIGINT, grace), (signal.SIGKILL, 10.0)):
            try:
                os.killpg(self.pgid, sig)
            except ProcessLookupError:
                pass
            deadline = time.monotonic() + wait_s
            while True:
                self.proc.poll()  # reaps the leader
                if not group_members(self.pgid):
                    break
                if time.monotonic() > deadline:
                    break
                time.sleep(0.1)
            if not group_members(self.pgid):
                break
        self.proc.poll()
        self.log.close()
        if self.registry is not None:
            self.registry.discard(self)


class Registry(object):
    """Every live group of this tool, so Ctrl-C can stop them all."""

    def __init__(self):
        self._lock = threading.Lock()
        self._groups = set()

    def add(self, g):
        with self._lock:
            self._groups.add(g)

    def discard(self, g):
        with self._lock:
            self._groups.discard(g)

    def stop_all(self):
        with self._lock:
            groups = list(self._groups)
        for g in groups:
            try:
                os.killpg(g.pgid, signal.SIGINT)
            except ProcessLookupError:
                pass
        threads = [threading.Thread(target=g.stop) for g in groups]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
