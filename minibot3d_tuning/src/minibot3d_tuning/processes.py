"""The processes of trials: each trial has a ROS master and rosout of its own (Core, a
minibot3d_testing.RosCore on a port no other process holds), and its stack (roslaunch and its
nodes) and its driver each run in a process group of their own (Group), so one killpg reaches every
process of a group and nothing else.  Stopping is SIGINT to the group (roslaunch shuts its nodes
down in order), then SIGKILL to whatever is left after a grace period; a group is gone when /proc
lists none of its members alive.  Every process started here also gets SIGTERM when the tool dies
without cleaning up (SIGKILL).

Every process started here carries TUNE_PLANNER_RUN=<study dir> in its environment (inherited by
roslaunch's children), so a caller can find anything of a study that is still running.
"""
import ctypes
import os
import signal
import threading

import minibot3d_testing as testing

MARKER = 'TUNE_PLANNER_RUN'
_PR_SET_PDEATHSIG = 1


def _die_with_parent():
    """preexec_fn (after setsid): SIGTERM if the tool dies without cleaning up."""
    try:
        ctypes.CDLL('libc.so.6', use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    except OSError:
        pass


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


class Group(testing.Process):
    """A command in its own process group, its output appended to log_path; stop() ends the whole
    group.  Listed in registry until stopped."""

    def __init__(self, cmd, env, log_path, registry=None):
        super().__init__(cmd, env, log_path, preexec_fn=_die_with_parent)
        self.pgid = self.pid
        self.registry = registry
        if registry is not None:
            registry.add(self)

    def stop(self, grace=15.0):
        """SIGINT the group, SIGKILL what is left after `grace` s; returns once none is alive."""
        status = super().stop(grace)
        if self.registry is not None:
            self.registry.discard(self)
        return status


class Core(testing.RosCore):
    """A trial's ROS master and rosout (their output in log_dir).  Listed in registry from
    start() until stopped."""

    def __init__(self, env, log_dir, registry=None):
        super().__init__(env, log_dir=log_dir, preexec_fn=_die_with_parent)
        self.registry = registry

    def start(self):
        if self.registry is not None:
            self.registry.add(self)
        return super().start()

    def stop(self):
        super().stop()
        if self.registry is not None:
            self.registry.discard(self)


class Registry(object):
    """Every live group and core of this tool, so Ctrl-C can stop them all."""

    def __init__(self):
        self._lock = threading.Lock()
        self._items = set()

    def add(self, g):
        with self._lock:
            self._items.add(g)

    def discard(self, g):
        with self._lock:
            self._items.discard(g)

    def stop_all(self):
        """Stops the groups, all at once; then the masters they ran on."""
        with self._lock:
            items = list(self._items)
        for batch in ([g for g in items if not isinstance(g, Core)],
                      [g for g in items if isinstance(g, Core)]):
            threads = [threading.Thread(target=g.stop) for g in batch]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
