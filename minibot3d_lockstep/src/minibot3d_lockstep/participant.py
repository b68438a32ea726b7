"""Make a rospy script or node a lock-step participant of minibot3d_sim.

With the global parameter ``/use_lockstep`` true, the simulator advances sim time only when every
participant has finished its work for the current time and received every message sent to it.
A script joins in a few lines (import this module before rospy.init_node: it counts messages on
connections made after the import)::

    from minibot3d_lockstep import Participant, action_server_ready
    rospy.init_node('my_client')
    client = actionlib.SimpleActionClient('move_base', MoveBaseAction)  # subscribers first
    lockstep = Participant(wake_topics=['move_base/result'])
    lockstep.wait_for(lambda: action_server_ready(client), timeout=30.0)
    client.send_goal(goal)
    lockstep.wait_for(lambda: client.get_state() in DONE_STATES, timeout=120.0)
    lockstep.sleep(1.0)

``wait_for``, ``sleep`` and ``spin`` are the only places where sim time moves for a participant:
between them the script works "at" one instant, however long it takes in wall time. Never block
in rospy.sleep, rospy.Rate, ``wait_for_result`` or ``wait_for_server`` while participating: sim
time would not move and the simulator would drop the script after ``~lockstep_timeout``.
Predicates are checked at ticks, once every message other participants sent by then has arrived
and its callbacks have run. ``wake_topics`` are the topics whose messages wake the script early;
otherwise it is woken at its ``timeout`` or ``sleep`` deadline, or its ``add_periodic`` jobs. A
predicate on a topic that is not a wake topic (a pose that streams at 50 Hz) is checked every
``poll`` s of sim time when ``wait_for`` is given one, else only at the deadline.

Create the subscribers a script waits on before the ``Participant``: it joins in its constructor,
and the simulator's first messages reach only the subscribers the master knew of by then (the
simulator waits for their connections). One made after joining misses them, and a wait for its
first message then depends on how fast the process started.

With ``/use_lockstep`` false (or unset) the same calls fall back to ordinary rospy waiting on sim
time, so a script written this way runs both ways.
"""
import math
import os
import socket
import subprocess
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
import rospy.impl.registration
import rospy.impl.tcpros_base
import rospy.impl.tcpros_pubsub
import rospy.topics
from minibot3d_lockstep.digest import (DIGEST_ENV, DIGEST_MESSAGES_ENV, DigestWriter, chain_crc,
                                      format_stamp, split_topic_list)
from minibot3d_lockstep.msg import Ack, Link, Participants, Tick
from minibot3d_lockstep.srv import Register, Unregister

LOCKSTEP_PARAM = '/use_lockstep'
REGISTER_SERVICE = '/minibot3d_sim/lockstep/register'
UNREGISTER_SERVICE = '/minibot3d_sim/lockstep/unregister'
ACK_TOPIC = '/minibot3d_sim/lockstep/ack'
PARTICIPANTS_TOPIC = '/minibot3d_sim/lockstep/participants'
TICK_TOPIC_PREFIX = '/minibot3d_sim/lockstep/tick/'

_patch_lock = threading.Lock()
_patched = False
# Under lock-step a queue_size drops nothing (set by Participant): rospy applies a subscriber's to
# whatever one socket read returned, so what it kept would depend on how TCP batched the bytes,
# and a publisher's to what its writer thread has not yet sent.
_keep_all = False
# The digest's directory (see minibot3d_lockstep.digest), read once: the CRCs of received messages
# are chained as rospy reads them, on every connection made after this module's import.
_digest_dir = os.environ.get(DIGEST_ENV) or None
# Topics whose received messages the digest writes whole (resolved when the Participant starts).
_digest_whole = set()


def _recorded(topic):
    """Topics the digest records: not /clock (its count depends on the wall clock) nor the
    lock-step protocol's own."""
    return topic not in ('/clock', ACK_TOPIC) and not topic.startswith(TICK_TOPIC_PREFIX)


class _Hashed(object):
    """Stands in for a message class in rospy's deserialize_messages: chains the CRC of each
    message's bytes onto its connection's before deserializing it."""
    __slots__ = ('_msg', '_proto')

    def __init__(self, msg, proto):
        self._msg, self._proto = msg, proto

    def deserialize(self, data):
        n, crc = self._proto.__dict__.get('_lockstep_digest', (0, 0))
        self._proto.__dict__['_lockstep_digest'] = (n + 1, chain_crc(crc, data))
        if _digest_whole and getattr(self._proto, 'resolved_name', None) in _digest_whole:
            self._proto.__dict__.setdefault('_lockstep_whole', []).append(
                (n + 1, getattr(self._msg, '_type', '?'), bytes(data)))
        return self._msg.deserialize(data)


def lockstep_enabled():
    """True when the global parameter /use_lockstep is set and true."""
    try:
        return bool(rospy.get_param(LOCKSTEP_PARAM, False))
    except (KeyError, rospy.ROSException):
        return False


def _install_counting():
    """Counts, per rospy connection, messages queued out and messages whose callbacks have run.

    rospy counts messages written (stat_num_msg) but a publisher with queue_size hands them to a
    writer thread first, and a subscriber runs callbacks after counting. The lock-step protocol
    needs "queued" on the sending side and "handled" on the receiving side, so both are counted
    here, on the connection objects rospy already keeps.
    """
    global _patched
    with _patch_lock:
        if _patched:
            return
        _patched = True
        queued_write = rospy.impl.tcpros_pubsub.QueuedConnection.write_data

        def counting_write(self, data):
            self.__dict__['_lockstep_sent'] = self.__dict__.get('_lockstep_sent', 0) + 1
            if _keep_all:
                # Every message queued is announced in the ack, so none may be dropped: a full
                # queue drops its oldest when the writer thread has not yet taken it, which
                # depends on thread timing (and the receiver would wait for it for ever).
                self._queue_size = 0
            return queued_write(self, data)
        rospy.impl.tcpros_pubsub.QueuedConnection.write_data = counting_write

        transport_init = rospy.impl.tcpros_base.TCPROSTransport.__init__

        def marking_init(self, *args, **kwargs):
            transport_init(self, *args, **kwargs)
            self.__dict__['_lockstep_counted'] = True  # its callbacks are counted (below)
        rospy.impl.tcpros_base.TCPROSTransport.__init__ = marking_init

        # A subscriber with queue_size discards all but the newest messages of a socket read
        # before its callbacks see them (and before rospy counts them); count those as handled
        # too. Which ones a read holds depends on TCP timing, so under lock-step none is dropped.
        protocol = rospy.impl.tcpros_base.TCPROSTransportProtocol

        def counting_read(self, b, msg_queue, sock):
            cls = self.recv_data_class
            if _digest_dir and _recorded(getattr(self, 'resolved_name', '')):
                def cls(real=self.recv_data_class, proto=self):
                    return _Hashed(real(), proto)
            if self.queue_size is None or _keep_all:
                return rospy.impl.tcpros_base.deserialize_messages(b, msg_queue, cls)
            parsed = []
            rospy.impl.tcpros_base.deserialize_messages(b, parsed, cls)
            dropped = max(0, len(msg_queue) + len(parsed) - self.queue_size)
            msg_queue.extend(parsed)
            del msg_queue[:-self.queue_size]
            self.__dict__['_lockstep_dropped'] = self.__dict__.get('_lockstep_dropped', 0) + dropped
        protocol.read_messages = counting_read

        receive = rospy.topics._SubscriberImpl.receive_callback

        def counting_receive(self, msgs, connection):
            try:
                return receive(self, msgs, connection)
            finally:
                connection.__dict__['_lockstep_done'] = (
                    connection.__dict__.get('_lockstep_done', 0) + len(msgs))
        rospy.topics._SubscriberImpl.receive_callback = counting_receive


def _nodelay(conn):
    inner = conn.__dict__.get('_connection', conn)
    if inner.__dict__.get('_lockstep_nodelay'):
        return
    sock = getattr(inner, 'socket', None)
    if sock is not None:
        try:
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            inner.__dict__['_lockstep_nodelay'] = True
        except OSError:
            pass


def sent_counts():
    """[(topic, subscriber caller id, messages queued)] for this process's publications."""
    out = []
    tm = rospy.impl.registration.get_topic_manager()
    for topic, impl in list(tm.pubs.items()):
        for c in list(impl.connections):
            _nodelay(c)
            if isinstance(c, rospy.impl.tcpros_pubsub.QueuedConnection):
                n = c.__dict__.get('_lockstep_sent', 0)
            else:
                n = c.stat_num_msg
            out.append((topic, c.endpoint_id, n))
    return sorted(out)


def handled_counts():
    """{(topic, publisher caller id): messages whose callbacks have run}."""
    out = {}
    tm = rospy.impl.registration.get_topic_manager()
    for topic, impl in list(tm.subs.items()):
        for c in list(impl.connections):
            key = (topic, getattr(c, 'callerid_pub', ''))
            if c.__dict__.get('_lockstep_counted'):
                n = c.__dict__.get('_lockstep_done', 0)
                proto = getattr(c, 'protocol', None)
                if proto is not None:
                    n += proto.__dict__.get('_lockstep_dropped', 0)
            else:  # made before this module was imported: received is the best we know
                n = c.stat_num_msg
            out[key] = out.get(key, 0) + n
    return out


def received_digests(whole=None):
    """{(topic, publisher caller id): (messages, CRC)} read so far on each recorded connection.
    whole: a list that gets (topic, publisher, number, type, bytes) for each message read since the
    last call on the topics the digest writes whole."""
    out = {}
    tm = rospy.impl.registration.get_topic_manager()
    for topic, impl in list(tm.subs.items()):
        if not _recorded(topic):
            continue
        for c in list(impl.connections):
            proto = getattr(c, 'protocol', None)
            d = proto.__dict__.get('_lockstep_digest') if proto is not None else None
            if d is not None:
                out[(topic, getattr(c, 'callerid_pub', ''))] = d
            if whole is not None and proto is not None and proto.__dict__.get('_lockstep_whole'):
                pending = proto.__dict__.pop('_lockstep_whole')
                whole.extend((topic, getattr(c, 'callerid_pub', ''), n, t, b)
                             for n, t, b in pending)
    return out


def _sent_by_peer(topic, node):
    """Messages `node` has queued to this node on `topic` (its getBusInfo/getBusStats), or None."""
    try:
        me = rospy.get_name()
        uri = rosgraph.Master(me).lookupNode(node)
        proxy = xmlrpc.client.ServerProxy(uri)
        _, _, info = proxy.getBusInfo(me)
        conn = [c[0] for c in info if c[4] == topic and c[1] == me and c[2] == 'o']
        if not conn:
            return None
        stats = proxy.getBusStats(me)
        if isinstance(stats[0], int):  # rospy wraps it in [code, msg, stats]; roscpp does not
            stats = stats[2]
        # roscpp: [topic, [[id, bytes, data, num, connected]]]; rospy: [topic, data, [[id, bytes,
        # num, connected]]]
        for entry in stats[0]:
            if entry[0] == topic:
                for c in entry[-1]:
                    if c[0] == conn[-1]:
                        return int(c[3] if len(c) >= 5 else c[2])
    except Exception:  # noqa: BLE001 - a node that cannot be asked is reported as missing
        return None
    return None


def node_answers(node):
    """True when `node` is registered with the master and its process answers at the XML-RPC
    address it registered (getPid); False when it is gone (see the C++ NodeAnswers)."""
    try:
        uri = rosgraph.Master(rospy.get_name()).lookupNode(node)
        xmlrpc.client.ServerProxy(uri).getPid(rospy.get_name())
        return True
    except Exception:  # noqa: BLE001 - not registered, or not answering: gone
        return False


def _peer_of(missing):
    """The node a missing_connections() entry names (its last word)."""
    return missing.rsplit(' ', 1)[-1]


def missing_connections():
    """Connections the master says this process should have and does not have yet (see the C++
    MissingConnections): publishers of topics it subscribes to, subscribers of topics it
    advertises, latching publishers whose message has not been handled."""
    try:
        pubs, subs, _ = rosgraph.Master(rospy.get_name()).getSystemState()
    except Exception:  # noqa: BLE001 - any failure to reach the master means "cannot tell"
        return ['master']
    me = rospy.get_name()
    tm = rospy.impl.registration.get_topic_manager()
    missing = []
    handled = handled_counts()
    for topic, nodes in pubs:
        impl = tm.subs.get(topic)
        if impl is None:
            continue
        have = set(getattr(c, 'callerid_pub', '') for c in list(impl.connections))
        missing += ['%s from %s' % (topic, n) for n in nodes if n != me and n not in have]
        for c in list(impl.connections):
            header = getattr(c, 'header', None) or {}
            if header.get('latching') != '1':
                continue
            # A latching publisher sends its last message on connect, the first on the
            # connection: ask it whether it has queued one to us (it may not have published yet;
            # then there is nothing to wait for). Its later messages are not waited for here: a
            # participant's and the simulator's are announced by ticks like any others, and a
            # publisher streaming while sim time runs free (/clock) would always be ahead.
            sent = _sent_by_peer(topic, c.callerid_pub)
            if sent is None or handled.get((topic, c.callerid_pub), 0) < min(sent, 1):
                missing.append('%s (latched) from %s' % (topic, c.callerid_pub))
    for topic, nodes in subs:
        impl = tm.pubs.get(topic)
        if impl is None:
            continue
        have = set(c.endpoint_id for c in list(impl.connections))
        missing += ['%s to %s' % (topic, n) for n in nodes if n != me and n not in have]
    return sorted(missing)


def action_server_ready(client):
    """True once `client` (actionlib SimpleActionClient or ActionClient) is connected to its
    server both ways. Unlike actionlib's wait_for_server it does not wait for a status message
    (the server sends those on a timer, at no fixed sim time), so it is decided the same way in
    every lock-step run."""
    ac = getattr(client, 'action_client', client)
    return (ac.pub_goal.impl.get_num_connections() > 0
            and ac.pub_cancel.impl.get_num_connections() > 0
            and ac.status_sub.impl.get_num_connections() > 0
            and ac.result_sub.impl.get_num_connections() > 0
            and ac.feedback_sub.impl.get_num_connections() > 0)


class Participant(object):
    """A rospy script's membership of the lock-step loop (plain rospy when it is off)."""

    def __init__(self, wake_topics=(), delivery_timeout=10.0, wake_on_participants=False):
        """wake_topics: topics whose messages wake the script; wake_on_participants: also wake
        when a participant joins or leaves (see participant_left)."""
        self.enabled = lockstep_enabled()
        self.name = rospy.get_name()
        self._wake_topics = [rospy.resolve_name(t) for t in wake_topics]
        if wake_on_participants:
            self._wake_topics.append(PARTICIPANTS_TOPIC)
        self.participants = set()
        self._joined = False
        self._delivery_timeout = delivery_timeout
        self._jobs = []  # [period, next, fn]
        self._cond = threading.Condition()
        self._tick = None        # arrived, not yet taken
        self._current = None     # being worked on, not yet acknowledged
        self._registered = False
        self.dropped = False  # the simulator dropped this script: its sim time no longer holds
        self._digest = None
        if not self.enabled:
            return
        if _digest_dir:
            self._digest = DigestWriter(_digest_dir, self.name, rospy.get_param('/run_id', ''))
            _digest_whole.update(rospy.resolve_name(t) for t in
                                 split_topic_list(os.environ.get(DIGEST_MESSAGES_ENV, '')))
        global _keep_all
        _keep_all = True
        self._ack_pub = rospy.Publisher(ACK_TOPIC, Ack, queue_size=100, tcp_nodelay=True)
        self._participants_sub = rospy.Subscriber(PARTICIPANTS_TOPIC, Participants,
                                                  self._on_participants, queue_size=10)
        # Every connection this script's topics call for is made, and every latched message is
        # here, before it joins: whoever holds sim time while it joins (a script starting it),
        # nothing is published meanwhile, so it starts with the same messages in every run.
        self._wait_for_simulator()
        self._settle_connections()
        self._register()
        rospy.on_shutdown(self.close)

    # -- public API --------------------------------------------------------------------------

    def now(self):
        return rospy.get_rostime()

    def add_periodic(self, period, fn):
        """Run fn(now) every `period` s of sim time while the script waits (wait_for/sleep/spin)."""
        self._jobs.append([float(period), None, fn])

    def wait_for(self, predicate, timeout=None, poll=None):
        """Wait until predicate() is true (True) or `timeout` s of sim time pass (False). Under
        lock-step the predicate is checked when the script is woken (a wake topic, a job, the
        deadline) and, with `poll` (s of sim time), at least that often."""
        if poll is not None and not poll > 0:
            raise ValueError('wait_for: poll must be > 0 s of sim time, got %r' % (poll,))
        if self.enabled and self._current is None and not rospy.is_shutdown():
            # Not at a tick yet (just joined): sim time is only defined once one arrives.
            if self._next_tick(None) is None:
                return False
            self._run_jobs(self._current.stamp)
        start = rospy.get_rostime()
        deadline = None if timeout is None or timeout <= 0 else start + rospy.Duration(timeout)
        if not self.enabled:
            while not rospy.is_shutdown():
                self._run_jobs_free(rospy.get_rostime())
                if predicate():
                    return True
                if deadline is not None and rospy.get_rostime() >= deadline:
                    return False
                rospy.sleep(0.01)
            return False
        if self._current is not None and predicate():
            return True
        while not rospy.is_shutdown():
            wake = deadline
            if poll is not None:
                at = self._current.stamp + rospy.Duration(poll)
                wake = at if wake is None or at < wake else wake
            tick = self._next_tick(wake)
            if tick is None:
                return False
            self._run_jobs(tick.stamp)
            if predicate():
                return True
            if deadline is not None and tick.stamp >= deadline:
                return False
        return False

    def wait_for_participant(self, name, process=None, wall_timeout=60.0):
        """After starting a participant's process: wait in wall time, with sim time held where it
        is, until `name` has joined, so it joins at the same sim time in every run. `process`
        (a subprocess.Popen) ends the wait early if it exits. False if it did not join."""
        name = rospy.resolve_name(name)
        if not self.enabled:
            return True
        start = beat = time.time()
        while not rospy.is_shutdown() and name not in self.participants:
            if process is not None and process.poll() is not None:
                return False
            if time.time() - start > wall_timeout:
                return False
            if time.time() - beat > 1.0:  # a slow start is not a stalled participant
                beat = time.time()
                self.still_working()
            time.sleep(0.002)
        return name in self.participants

    def run(self, name, args, sim_timeout=None, **popen):
        """Starts `args` (subprocess.Popen's arguments; `popen` its keywords), a process whose node
        `name` joins the loop; waits, sim time held, until it has joined, then, sim time moving,
        until it has left or `sim_timeout` s of sim time have passed. Returns (finished, the
        Popen): the process may still be exiting, so wait() or communicate() on it. Lock-step
        off: waits for the process to exit."""
        proc = subprocess.Popen(args, **popen)
        if not self.wait_for_participant(name, proc):
            return proc.poll() is not None, proc
        return self.wait_for(lambda: self.participant_left(name, proc), sim_timeout), proc

    def _beat(self, state):
        """Heartbeat at most once a wall second while a tick is held in a long wait."""
        if time.time() - state[0] > 1.0:
            state[0] = time.time()
            self.still_working()

    def still_working(self):
        """Tells the simulator this script is alive though not done with its tick (long work,
        waiting for a process): restarts its ~lockstep_timeout."""
        if self.enabled and self._current is not None:
            self._ack_pub.publish(Ack(name=self.name, seq=self._current.seq, working=True))

    def participant_left(self, name, process=None):
        """Predicate for wait_for: `name` has left the loop. With wake_on_participants=True the
        script is woken the quantum after it leaves, whatever its process is still doing. When
        lock-step is off: `process` (a subprocess.Popen) has exited."""
        if not self.enabled:
            return process is None or process.poll() is not None
        return rospy.resolve_name(name) not in self.participants

    def sleep(self, duration):
        """Let `duration` s of sim time pass."""
        end = rospy.get_rostime() + rospy.Duration(duration)
        self.wait_for(lambda: rospy.get_rostime() >= end, timeout=duration)

    def spin(self):
        """Until shutdown, running add_periodic jobs (callbacks run on rospy's threads)."""
        self.wait_for(lambda: False)

    def close(self):
        """Acknowledge the tick in hand and leave the loop (also done on shutdown)."""
        if self._digest is not None:
            # The last tick's lines are written now, not left to the interpreter's exit (which
            # may not flush an open file).
            self._digest.close()
        if not self._registered:
            return
        self._registered = False
        try:
            rospy.wait_for_service(UNREGISTER_SERVICE, timeout=1.0)
            rospy.ServiceProxy(UNREGISTER_SERVICE, Unregister)(self.name)
        except (rospy.ROSException, rospy.ServiceException):
            pass  # the simulator is gone already

    # -- protocol ----------------------------------------------------------------------------

    def _wait_for_simulator(self):
        warned = 0.0
        while not rospy.is_shutdown():
            try:
                rospy.wait_for_service(REGISTER_SERVICE, timeout=1.0)
                return
            except rospy.ROSException:
                if time.time() - warned > 10.0:
                    warned = time.time()
                    rospy.logwarn('%s: /use_lockstep is true; waiting for the simulator\'s %s '
                                  '(is minibot3d_sim running with lockstep:=true?)',
                                  self.name, REGISTER_SERVICE)

    def _register(self):
        res = rospy.ServiceProxy(REGISTER_SERVICE, Register)(self.name, self._wake_topics)
        if not res.accepted:
            raise RuntimeError('%s: the simulator refused lock-step registration: %s'
                               % (self.name, res.message))
        self._tick_sub = rospy.Subscriber(res.tick_topic, Tick, self._on_tick, queue_size=10,
                                          tcp_nodelay=True)
        self._registered = True

    def _on_participants(self, msg):
        self.participants = set(msg.names)
        if self.name in self.participants:
            self._joined = True

    def _on_tick(self, tick):
        with self._cond:
            self._tick = tick
            self._cond.notify_all()

    def _ack(self, next_wake):
        if self._current is None:
            return
        # A publisher or subscriber made during this tick connects now, sim time still held: a
        # latched message published at once is counted in this ack, not delivered at some later
        # tick that depends on how fast the master and the peer answered.
        self._settle_connections()
        tick, self._current = self._current, None
        wake = next_wake
        for job in self._jobs:
            if job[1] is not None and (wake is None or job[1] < wake):
                wake = job[1]
        ack = Ack(name=self.name, seq=tick.seq, next_wake=wake if wake is not None else rospy.Time(0))
        sent = sent_counts()
        ack.sent = [Link(topic=t, peer=p, count=n) for t, p, n in sent]
        if self._digest is not None:
            self._digest.acknowledged([s for s in sent if _recorded(s[0])],
                                      format_stamp(ack.next_wake))
        self._ack_pub.publish(ack)

    def _next_tick(self, deadline):
        self._ack(deadline)
        with self._cond:
            while self._tick is None and not rospy.is_shutdown():
                self._cond.wait(0.5)
                if self._tick is None and self._joined and self.name not in self.participants:
                    rospy.logerr('%s: the simulator dropped this participant from the lock-step '
                                 'loop (it answered too slowly, see the simulator\'s log)',
                                 self.name)
                    self._registered = False
                    self.dropped = True
                    return None
            tick, self._tick = self._tick, None
        if tick is None:
            return None
        self._current = tick  # held from here: heartbeats name it
        self._settle_connections()
        self._wait_for_delivery(tick)
        if self._digest is not None:
            whole = []
            received = received_digests(whole)
            self._digest.tick(tick.seq, format_stamp(tick.stamp), received, whole)
        self._wait_for_clock(tick.stamp)
        return tick

    def _settle_connections(self):
        # Sim time holds while this script has a tick in hand: connections made now are made at
        # the same sim time in every run. Asked again only when this script's topics change.
        tm = rospy.impl.registration.get_topic_manager()
        topics = (tuple(sorted(tm.subs)), tuple(sorted(tm.pubs)))
        if topics == getattr(self, '_settled', None):
            return
        self._settled = topics
        start = checked = time.time()
        beat = [start]
        while not rospy.is_shutdown():
            self._beat(beat)
            missing = missing_connections()
            if not missing:
                return
            # Past delivery_timeout, and then every 10 s: a connection to a node that is running
            # is on its way however loaded the machine; one to a node that is gone never comes.
            now = time.time()
            if now - start > self._delivery_timeout and now - checked > 10.0:
                checked = now
                alive = [m for m in missing if node_answers(_peer_of(m))]
                if not alive:
                    rospy.logwarn('%s: lock-step: going on without connections: %s (their nodes '
                                  'do not answer: registered with the master, no longer running)',
                                  self.name, '; '.join(missing))
                    return
                rospy.logwarn('%s: lock-step: still waiting for connections to running nodes: '
                              '%s (%.0f s wall)', self.name, '; '.join(alive), now - start)
            if time.time() - start > 2.0 and not getattr(self, '_noted', False):
                self._noted = True
                rospy.loginfo('%s: lock-step: waiting for connections: %s', self.name,
                              '; '.join(missing))
            time.sleep(0.002)

    def _wait_for_delivery(self, tick):
        start = noted = time.time()
        beat = [start]
        while not rospy.is_shutdown():
            self._beat(beat)
            have = handled_counts()
            short = [l for l in tick.expected if have.get((l.topic, l.peer), 0) < l.count]
            if not short:
                return
            # Messages on a connection that is there are on their way, however loaded the
            # machine: waited for. A connection that is gone (its publisher died mid-send) brings
            # nothing more.
            now = time.time()
            if now - start > self._delivery_timeout and now - noted > 10.0:
                noted = now
                missing = ['%s from %s (%d of %d)' % (l.topic, l.peer,
                                                       have.get((l.topic, l.peer), 0), l.count)
                           for l in short]
                if not any((l.topic, l.peer) in have for l in short):
                    rospy.logwarn('%s: going on at t=%.3f without messages announced by the '
                                  'simulator\'s tick: %s (their publishers\' connections are '
                                  'gone)', self.name, tick.stamp.to_sec(), '; '.join(missing))
                    return
                rospy.logwarn('%s: lock-step: still waiting at t=%.3f for messages: %s (%.0f s '
                              'wall)', self.name, tick.stamp.to_sec(), '; '.join(missing),
                              now - start)
            if time.time() - start > 2.0 and not getattr(self, '_noted_d', False):
                self._noted_d = True
                rospy.loginfo('%s: lock-step: waiting for messages: %s', self.name, '; '.join(
                    '%s from %s' % (l.topic, l.peer) for l in short))
            time.sleep(0.0001)

    def _wait_for_clock(self, stamp):
        # rospy's /clock subscriber sets the time; /clock for `stamp` precedes the tick and older
        # /clock messages precede it on the same connection.
        # Waited for while a /clock connection is there, however loaded the machine.
        start = noted = time.time()
        while not rospy.is_shutdown() and rospy.get_rostime() < stamp:
            now = time.time()
            if now - start > self._delivery_timeout and now - noted > 10.0:
                noted = now
                clock = rospy.impl.registration.get_topic_manager().subs.get('/clock')
                if clock is None or not list(clock.connections):
                    rospy.logwarn('%s: /clock has not reached the tick\'s time %.3f and its '
                                  'publisher is gone', self.name, stamp.to_sec())
                    return
                rospy.logwarn('%s: lock-step: still waiting for /clock to reach the tick\'s time '
                              '%.3f (%.0f s wall)', self.name, stamp.to_sec(), now - start)
            time.sleep(0.0001)

    def _run_jobs(self, now):
        t = now.to_sec()
        for job in self._jobs:
            period = job[0]
            if job[1] is None:
                job[1] = rospy.Time(math.ceil(t / period - 1e-6) * period)
            if job[1].to_sec() <= t + 1e-9:
                job[2](now)
                while job[1].to_sec() <= t + 1e-9:
                    job[1] = job[1] + rospy.Duration(period)

    def _run_jobs_free(self, now):
        self._run_jobs(now)


# Counting must be in place before the subscriptions it counts are connected: importing this module
# (before rospy.init_node, as scripts do) installs it.
_install_counting()
