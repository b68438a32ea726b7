"""Checks every closed-loop rostest makes on the whole run, beside its own: RunChecks.

/tf arrived at all: a run whose monitor heard nothing has checked nothing for repeats (the
simulator never published, or the test subscribed to the wrong master or topic).

TfRepeatMonitor: tf2 drops a transform whose child frame already has one at the same stamp and
warns "TF_REPEATED_DATA ignoring data with redundant timestamp" in every listener, on stderr rather
than /rosout. The monitor watches /tf for that cause itself: a (child frame, stamp) pair sent twice,
by whichever publisher (the connection's callerid names it).

non_loopback_listeners: the TCP sockets listening on an address other than loopback held by the
processes of this run (the rostest/roslaunch process that started the test and all it started),
except what ROS 1 itself forces: roscpp's XML-RPC server (XmlRpc++) binds INADDR_ANY whatever
ROS_IP or ROS_HOSTNAME say. With ROS_IP=127.0.0.1 (tools/ros_env.sh) everything else binds
127.0.0.1: rosmaster, roslaunch, rospy's XML-RPC and TCPROS servers, and roscpp's TCPROS server
(which binds INADDR_ANY for ROS_HOSTNAME=127.0.0.1). A roscpp node's XML-RPC port is the one in
the URI it registered with the master, so nothing else on 0.0.0.0 passes.
"""
import collections
import os
import socket
import struct
import threading
import urllib.parse

import rosgraph
import rospy
from minibot3d_testing import descendants  # the run's processes
from tf2_msgs.msg import TFMessage


def _transform_tuple(t):
    r, q = t.transform.translation, t.transform.rotation
    return (r.x, r.y, r.z, q.x, q.y, q.z, q.w)


class TfRepeatMonitor(object):
    """Subscribes to /tf and records every (child frame, stamp) sent more than once.

    Stamps are remembered for ``horizon`` seconds behind the newest one of their frame (tf2's
    buffer keeps 10 s), so a long run does not grow the memory without bound."""

    def __init__(self, topic='/tf', horizon=15.0, subscribe=True):
        self._lock = threading.Lock()
        self._horizon_ns = int(horizon * 1e9)
        # (child frame, stamp in ns) -> (callerid of its first sender, (parent, transform))
        self._first = {}
        self._order = collections.defaultdict(collections.deque)  # child -> its stamps, in order
        self._repeats = []
        self.messages = 0
        if subscribe:  # else messages come through record()
            rospy.Subscriber(topic, TFMessage, self._on_tf, queue_size=1000, buff_size=1 << 22)

    def _on_tf(self, msg):
        header = getattr(msg, '_connection_header', None) or {}
        self.record(header.get('callerid', '?'), header.get('latching') == '1', msg.transforms)

    def record(self, sender, latched, transforms):
        """One /tf message from `sender` (latched: sent on a latching connection). A latched
        message arrives once per connection, and a subscriber may briefly hold two connections
        to one publisher: the same transforms again from the same latching sender are that
        message delivered twice, not sent twice, and are not counted."""
        with self._lock:
            values = [(t.child_frame_id.lstrip('/'), t.header.stamp.to_nsec(),
                       t.header.frame_id, _transform_tuple(t)) for t in transforms]
            if latched and values and all(
                    self._first.get(v[:2]) == (sender, v[2:]) for v in values):
                return
            self.messages += 1
            for child, stamp, parent, value in values:
                key = (child, stamp)
                if key not in self._first:
                    self._first[key] = (sender, (parent, value))
                    order = self._order[child]
                    order.append(stamp)
                    while order and order[0] < stamp - self._horizon_ns:
                        self._first.pop((child, order.popleft()), None)
                    continue
                self._repeats.append('%s (parent %s) at %.9f s: first from %s, again from %s'
                                     % (child, parent, stamp * 1e-9, self._first[key][0], sender))

    def repeats(self):
        """The repeated transforms seen so far (empty when none)."""
        with self._lock:
            return list(self._repeats)


# ---- listening sockets ---------------------------------------------------------------------------

_LISTEN = '0A'  # TCP state LISTEN in /proc/net/tcp*


def _listening_sockets():
    """inode -> (address, port) of every TCP socket listening on this machine (IPv4 and IPv6)."""
    found = {}
    for path, family in (('/proc/net/tcp', socket.AF_INET), ('/proc/net/tcp6', socket.AF_INET6)):
        try:
            with open(path) as f:
                lines = f.readlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            if fields[3] != _LISTEN:
                continue
            hexaddr, hexport = fields[1].split(':')
            raw = bytes.fromhex(hexaddr)
            # /proc prints the address as host-order 32-bit words.
            raw = b''.join(struct.pack('<I', struct.unpack('>I', raw[i:i + 4])[0])
                           for i in range(0, len(raw), 4))
            found[int(fields[9])] = (socket.inet_ntop(family, raw), int(hexport, 16))
    return found


def _is_loopback(address):
    return address.startswith('127.') or address == '::1' or address.startswith('::ffff:127.')


def _socket_inodes(pid):
    inodes = set()
    try:
        for fd in os.listdir('/proc/%d/fd' % pid):
            try:
                target = os.readlink('/proc/%d/fd/%s' % (pid, fd))
            except OSError:
                continue
            if target.startswith('socket:['):
                inodes.add(int(target[8:-1]))
    except OSError:
        pass
    return inodes


def _process_name(pid):
    try:
        with open('/proc/%d/cmdline' % pid, 'rb') as f:
            argv = f.read().split(b'\0')
        return ' '.join(a.decode(errors='replace') for a in argv[:2] if a)
    except OSError:
        return '?'


def _uses_roscpp(pid):
    try:
        with open('/proc/%d/maps' % pid) as f:
            return 'libroscpp.so' in f.read()
    except OSError:
        return False


def _xmlrpc_ports(caller_id):
    """The XML-RPC server port of every node the master knows (from the URI it registered)."""
    master = rosgraph.Master(caller_id)
    nodes = set()
    for kind in master.getSystemState():
        for _, names in kind:
            nodes.update(names)
    ports = set()
    for node in nodes:
        try:
            ports.add(urllib.parse.urlparse(master.lookupNode(node)).port)
        except (OSError, rosgraph.MasterException, ValueError):
            continue  # the node went away meanwhile
    return ports


def non_loopback_listeners(root_pid=None, caller_id=None):
    """Sockets of this run listening beyond loopback that ROS 1 does not force, as strings.

    root_pid: the process whose tree is the run (default: this process's parent, the rostest or
    roslaunch that started the test node, which also started the master and every node)."""
    root = root_pid if root_pid is not None else os.getppid()
    caller = caller_id or rospy.get_name()
    listening = _listening_sockets()
    forced_ports = _xmlrpc_ports(caller)
    problems = []
    for pid in descendants(root):
        for inode in _socket_inodes(pid):
            if inode not in listening:
                continue
            address, port = listening[inode]
            if _is_loopback(address):
                continue
            if port in forced_ports and _uses_roscpp(pid):
                continue  # roscpp's XML-RPC server: XmlRpc++ binds INADDR_ANY itself
            problems.append('%s (pid %d) listens on %s:%d' % (_process_name(pid), pid, address,
                                                               port))
    return problems


class RunChecks(object):
    """The checks for a closed-loop rostest: create it right after rospy.init_node, and call
    problems() at the end of the run, while the nodes are still up::

        checks = RunChecks()
        ...  # the test's own run
        self.assertEqual([], checks.problems())
    """

    def __init__(self):
        self.tf = TfRepeatMonitor()

    def problems(self):
        out = []
        if self.tf.messages == 0:
            out.append('no message on /tf during the run: nothing was checked for repeated '
                       'transforms (is the simulator up on this master?)')
        repeats = self.tf.repeats()
        out += ['tf sent twice at one stamp (listeners drop it with TF_REPEATED_DATA): ' + r
                for r in repeats[:20]]
        if len(repeats) > 20:
            out.append('... and %d more repeated transforms' % (len(repeats) - 20))
        out += ['listening beyond loopback (run with ROS_IP=127.0.0.1, as tools/ros_env.sh and '
                'make test do; README "Security"): ' + p for p in non_loopback_listeners()]
        return out
