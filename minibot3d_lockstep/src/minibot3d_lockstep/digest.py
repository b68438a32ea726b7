"""Lock-step digests: what each participant received and sent at each tick, and where two runs
part.

A run under lock-step time writes them when the environment variable MINIBOT3D_LOCKSTEP_DIGEST
names a directory: every participant (C++ and Python) and the simulator append a section to
<dir>/<node>.digest (the format is described in minibot3d_lockstep/digest_log.h). compare() reads
two such directories and names the first tick, node, topic and peer at which they differ;
tools/lockstep_digest.py is its command line.

Two runs are matched up section by section: a section is one process of one node, and sections
written while one ROS master ran (its /run_id) form a phase; phases are ordered by when they
started, and a node's sections within a phase by the order they were written. Messages from nodes
that do not take part in the loop (robot_state_publisher, map_server, rviz) and messages to them
arrive at wall-clock times by design: they are left out unless all_nodes is set, and so are
messages queued to a participant after its last tick (it has left the loop: when its connections
close is a wall-clock moment). So are the topics in DEFAULT_IGNORED, whose count or content
depends on the wall clock.
"""
import collections
import os
import struct
import time
import zlib

DIGEST_ENV = 'MINIBOT3D_LOCKSTEP_DIGEST'

# Topics whose messages depend on the wall clock by design: /clock's count (published at most
# ~pub_clock_frequency times a wall second between rounds), log messages (wall-clock throttling,
# wall times in their text), the simulator's status (its measured and target real-time factors).
DIGEST_MESSAGES_ENV = 'MINIBOT3D_LOCKSTEP_DIGEST_MESSAGES'

DEFAULT_IGNORED = ('/clock', '/rosout', '/rosout_agg', '/minibot3d_sim/status')

SIMULATOR = '/minibot3d_sim'


def chain_crc(crc, data):
    """The CRC-32 on a connection after one more message: its length as 4 bytes little-endian,
    then its bytes (as the C++ ChainCrc)."""
    return zlib.crc32(data, zlib.crc32(struct.pack('<I', len(data)), crc))


def split_topic_list(text):
    """'a, /b c' -> ['a', '/b', 'c'] (the topics of DIGEST_MESSAGES_ENV)."""
    return [t for t in text.replace(',', ' ').split() if t]


def file_name(node):
    """'/ns/node' -> 'ns.node.digest'."""
    return (node.lstrip('/').replace('/', '.') or 'unnamed') + '.digest'


def format_stamp(t):
    """A rospy.Time (or anything with secs and nsecs) as seconds.nanoseconds."""
    return '%d.%09d' % (t.secs, t.nsecs)


class DigestWriter(object):
    """The Python participant's side: appends a section to <dir>/<node>.digest."""

    def __init__(self, directory, node, run_id, pid=None, wall=None):
        os.makedirs(directory, exist_ok=True)
        self.path = os.path.join(directory, file_name(node))
        try:
            self._f = open(self.path, 'a')
        except OSError as e:
            raise RuntimeError('cannot open the lock-step digest %s for appending: %s (%s=%s)'
                               % (self.path, e.strerror, DIGEST_ENV, directory))
        self._written = {}
        self._sent = {}
        self._f.write('N %s run=%s pid=%d wall=%.6f\n' % (
            node, run_id or '-', os.getpid() if pid is None else pid,
            time.time() if wall is None else wall))
        self._f.flush()

    def tick(self, seq, stamp, received, whole=()):
        """received: {(topic, publisher): (count, crc)} for every connection so far; whole:
        [(topic, publisher, number, type, bytes)] messages written whole. Nothing once closed."""
        if self._f.closed:
            return
        lines = ['T %d %s\n' % (seq, stamp)]
        for key in sorted(received):
            count, crc = received[key]
            if self._written.get(key) != count:
                self._written[key] = count
                lines.append('I %s %s %d %08x\n' % (key[0], key[1], count, crc))
        for topic, publisher, number, msg_type, data in whole:
            lines.append('M %s %s %d %s %s\n' % (topic, publisher, number, msg_type or '?',
                                                  data.hex() or '-'))
        self._f.write(''.join(lines))

    def acknowledged(self, sent, next_wake):
        """sent: [(topic, subscriber, count)]; next_wake: seconds.nanoseconds. Nothing once closed."""
        if self._f.closed:
            return
        lines = []
        for topic, peer, count in sorted(sent):
            if self._sent.get((topic, peer)) != count:
                self._sent[(topic, peer)] = count
                lines.append('O %s %s %d\n' % (topic, peer, count))
        lines.append('A %s\n' % next_wake)
        self._f.write(''.join(lines))
        self._f.flush()

    def close(self):
        if not self._f.closed:
            self._f.close()


# -- reading -------------------------------------------------------------------------------------

Tick = collections.namedtuple('Tick', 'seq stamp received sent wake line messages')
# received: {(topic, publisher): (count, crc)} as written at this tick (changed connections only);
# messages: {(topic, publisher, number): (type, bytes)} written whole at this tick;
# sent: {(topic, subscriber): count}; wake: the acknowledgement's next wake (None: not acknowledged,
# or a node that is not ticked); line: where the tick starts in its file.


class Section(object):
    """One process of one node: its ticks in order."""

    def __init__(self, path, line, node, run_id, pid, wall):
        self.path, self.line = path, line
        self.node, self.run_id, self.pid, self.wall = node, run_id, pid, wall
        self.ticks = []
        self.phase = None   # set by read()
        self.index = None   # among this node's sections in its phase

    def key(self):
        return (self.phase, self.node, self.index)


def stamp_key(stamp):
    """'12.345000000' -> (12, 345000000), exact and ordered."""
    secs, _, nsecs = stamp.partition('.')
    return (int(secs), int(nsecs or 0))


def read_file(path):
    """The sections of one digest file. A truncated last line (a process that was killed) is
    dropped; any other malformed line raises ValueError naming the file and line."""
    sections = []
    tick = None
    with open(path) as f:
        lines = f.read().split('\n')
    complete = len(lines) - 1  # the text after the last newline is an unfinished line
    for n, text in enumerate(lines[:complete], 1):
        parts = text.split(' ')
        kind = parts[0]
        try:
            if kind == 'N':
                fields = dict(p.split('=', 1) for p in parts[2:])
                sections.append(Section(path, n, parts[1], fields.get('run', '-'),
                                        int(fields.get('pid', 0)), float(fields.get('wall', 0))))
                tick = None
            elif kind == 'T':
                tick = Tick(int(parts[1]), parts[2], {}, {}, [None], n, {})
                sections[-1].ticks.append(tick)
            elif kind == 'I':
                tick.received[(parts[1], parts[2])] = (int(parts[3]), parts[4])
            elif kind == 'M':
                data = b'' if parts[5] == '-' else bytes.fromhex(parts[5])
                tick.messages[(parts[1], parts[2], int(parts[3]))] = (parts[4], data)
            elif kind == 'O':
                tick.sent[(parts[1], parts[2])] = int(parts[3])
            elif kind == 'A':
                tick.wake[0] = parts[1]
            else:
                raise ValueError('unknown record %r' % kind)
        except (IndexError, ValueError, AttributeError) as e:
            raise ValueError('%s:%d: not a lock-step digest line (%s): %r' % (path, n, e, text))
    return sections


def read(directory):
    """Every section in a digest directory, with its phase and index set."""
    if not os.path.isdir(directory):
        raise ValueError('%s is not a directory of lock-step digests' % directory)
    sections = []
    for name in sorted(os.listdir(directory)):
        if name.endswith('.digest'):
            sections += read_file(os.path.join(directory, name))
    if not sections:
        raise ValueError('no lock-step digest (*.digest) in %s: was %s set for the run?'
                         % (directory, DIGEST_ENV))
    starts = {}
    for s in sections:
        starts[s.run_id] = min(starts.get(s.run_id, s.wall), s.wall)
    order = {run: i + 1 for i, run in enumerate(sorted(starts, key=starts.get))}
    seen = collections.Counter()
    for s in sorted(sections, key=lambda s: (s.wall, s.path, s.line)):
        s.phase = order[s.run_id]
        s.index = seen[(s.phase, s.node)]
        seen[(s.phase, s.node)] += 1
    return sections


# -- comparing -----------------------------------------------------------------------------------

class Difference(object):
    """Where two runs first differ for one section (a node's process)."""

    def __init__(self, key, a, b, what, details):
        self.key = key            # (phase, node, index)
        self.a, self.b = a, b     # the differing Tick of each run (None: missing there)
        self.what = what          # one line
        self.details = details    # [lines]
        self.peers = []           # [(topic, publisher)] whose received messages differ

    def order(self):
        t = self.a or self.b
        return (self.key[0], stamp_key(t.stamp) if t else (float('inf'), 0),
                t.seq if t else 0, self.key[1])

    @property
    def stamp(self):
        t = self.a or self.b
        return t.stamp if t else None


class Comparison(object):
    def __init__(self):
        self.differences = []   # sorted: the first is the first difference
        self.sections = 0       # matched sections
        self.ticks = 0          # ticks compared (identical)
        self.only = []          # (run, key): sections one run has and the other not
        self.last_stamp = {}    # phase -> the latest sim time compared identical
        self.ends = {}          # phase -> ((s, ns) of run a's last tick, run b's), None: absent

    @property
    def identical(self):
        return not self.differences


def _filter(entries, ignored, participants, stamp=None):
    """entries without ignored topics and, unless participants is None, without peers that do
    not take part ({node: its last tick}); with `stamp`, also without peers that had left the
    loop by then (what is queued to a node after its last tick is read at a wall-clock moment,
    if at all, and reaches nothing in the loop)."""
    return {k: v for k, v in entries.items()
            if k[0] not in ignored and (participants is None or (
                k[1] in participants and (stamp is None or stamp <= participants[k[1]])))}


def _describe(key, ta, tb, ignored, participants_a, participants_b):
    node = key[1]
    if ta is None or tb is None:
        have, run = (ta, 'a') if ta is not None else (tb, 'b')
        return Difference(key, ta, tb, '%s is ticked at %s (tick %d) only in run %s'
                          % (node, have.stamp, have.seq, run), [])
    if ta.stamp != tb.stamp:
        return Difference(key, ta, tb, '%s is next ticked at %s in run a, at %s in run b'
                          % (node, ta.stamp, tb.stamp), [])
    details, peers = [], []
    ra = _filter(ta.received, ignored, participants_a)
    rb = _filter(tb.received, ignored, participants_b)
    for k in sorted(set(ra) | set(rb)):
        if ra.get(k) != rb.get(k):
            peers.append(k)
            details.append('received %s from %s: a %s, b %s' % (
                k[0], k[1], _count_crc(ra.get(k)), _count_crc(rb.get(k))))
    sa = _filter(ta.sent, ignored, participants_a, stamp_key(ta.stamp))
    sb = _filter(tb.sent, ignored, participants_b, stamp_key(tb.stamp))
    for k in sorted(set(sa) | set(sb)):
        if sa.get(k) != sb.get(k):
            details.append('sent %s to %s: a %s messages so far, b %s' % (
                k[0], k[1], sa.get(k, 'no new'), sb.get(k, 'no new')))
    if ta.wake[0] != tb.wake[0]:
        details.append('asked to be woken next at %s in run a, %s in run b'
                       % (ta.wake[0], tb.wake[0]))
    if ta.seq != tb.seq and not details:
        details.append('tick %d in run a, %d in run b: another node was ticked a different '
                       'number of times before' % (ta.seq, tb.seq))
    if not details:
        return None
    d = Difference(key, ta, tb, '%s at sim time %s (tick %d)' % (node, ta.stamp, ta.seq), details)
    d.peers = peers
    return d


def _count_crc(v):
    return 'nothing new' if v is None else 'message %d, CRC %s' % v


def compare(dir_a, dir_b, ignored=DEFAULT_IGNORED, all_nodes=False, until=None):
    """Compares two digest directories tick by tick; returns a Comparison. until: the last sim
    time (s) compared (None: up to the earlier end of each phase)."""
    ignored = set(ignored)
    sa, sb = read(dir_a), read(dir_b)
    by_a = {s.key(): s for s in sa}
    by_b = {s.key(): s for s in sb}

    def participants(sections):
        """{phase: {node: its last tick's (s, ns)}}; a node never ticked is there throughout."""
        out = collections.defaultdict(dict)
        for s in sections:
            last = stamp_key(s.ticks[-1].stamp) if s.ticks else (float('inf'), 0)
            out[s.phase][s.node] = max(out[s.phase].get(s.node, last), last)
        return out
    pa, pb = participants(sa), participants(sb)
    # A node's last tick is the earlier of the two runs' (a node that leaves at another time
    # in one run differs in its own ticks): both runs leave out sends to it after that.
    for phase in set(pa) & set(pb):
        for node in set(pa[phase]) & set(pb[phase]):
            pa[phase][node] = pb[phase][node] = min(pa[phase][node], pb[phase][node])
    last = (float('inf'), 0) if until is None else stamp_key('%.9f' % until)

    def ends(sections):
        out = {}
        for s in sections:
            if s.ticks:
                out[s.phase] = max(out.get(s.phase, (0, 0)), stamp_key(s.ticks[-1].stamp))
        return out
    # A phase ends when its stack is stopped, at a wall-clock moment: only ticks before the
    # earlier end are compared (the last round may be cut short).
    end_a, end_b = ends(sa), ends(sb)
    result = Comparison()
    for phase in set(end_a) | set(end_b):
        result.ends[phase] = (end_a.get(phase), end_b.get(phase))
    for key in sorted(set(by_a) | set(by_b), key=lambda k: (k[0], k[1], k[2])):
        a, b = by_a.get(key), by_b.get(key)
        if a is None or b is None:
            result.only.append(('a' if a else 'b', key))
            t = (a or b).ticks[0] if (a or b).ticks else None
            d = Difference(key, t if a else None, t if b else None,
                           '%s (phase %d, process %d) ran only in run %s'
                           % (key[1], key[0], key[2] + 1, 'a' if a else 'b'), [])
            result.differences.append(d)
            continue
        result.sections += 1
        part_a = None if all_nodes else pa[key[0]]
        part_b = None if all_nodes else pb[key[0]]
        horizon = min(end_a.get(key[0], (0, 0)), end_b.get(key[0], (0, 0)))
        def compared(t):
            return stamp_key(t.stamp) < horizon and stamp_key(t.stamp) <= last
        ticks_a = [t for t in a.ticks if compared(t)]
        ticks_b = [t for t in b.ticks if compared(t)]
        n = min(len(ticks_a), len(ticks_b))
        diff = None
        for i in range(n):
            diff = _describe(key, ticks_a[i], ticks_b[i], ignored, part_a, part_b)
            if diff is not None:
                break
            result.ticks += 1
            st = ticks_a[i].stamp
            if stamp_key(st) > stamp_key(result.last_stamp.get(key[0], '0.0')):
                result.last_stamp[key[0]] = st
        if diff is None and len(ticks_a) != len(ticks_b):
            diff = _describe(key, ticks_a[n] if n < len(ticks_a) else None,
                             ticks_b[n] if n < len(ticks_b) else None, ignored, part_a, part_b)
        if diff is not None:
            result.differences.append(diff)
    result.differences.sort(key=Difference.order)
    # What the first difference's publishers did: their last tick before it in both runs.
    if result.differences:
        first = result.differences[0]
        for topic, peer in first.peers:
            note = _publisher_note(first, peer, topic, by_a)
            if note:
                first.details.append(note)
            first.details += _message_note(first, topic, peer)
    return result


def _message_note(first, topic, peer):
    """Which bytes and fields of the differing message differ, when both runs wrote it whole."""
    if first.a is None or first.b is None:
        return []
    ma = {k[2]: v for k, v in first.a.messages.items() if k[:2] == (topic, peer)}
    mb = {k[2]: v for k, v in first.b.messages.items() if k[:2] == (topic, peer)}
    if not ma or not mb:
        return ['to see which fields differ, run both again with %s=%s'
                % (DIGEST_MESSAGES_ENV, topic)]
    for number in sorted(set(ma) & set(mb)):
        (type_a, a), (_, b) = ma[number], mb[number]
        if a == b:
            continue
        lines = ['message %d of %s from %s (%s): %s' % (number, topic, peer, type_a,
                                                        describe_bytes(a, b))]
        fields = field_differences(type_a, a, b)
        if fields is None:
            lines.append('  (its fields are named where the message type %s can be imported: '
                         'source the workspace)' % type_a)
        for name, va, vb in fields or []:
            lines.append('  field %s: a %s, b %s' % (name, va, vb))
        return lines
    return []


def describe_bytes(a, b):
    """Where two byte strings differ, briefly."""
    n = min(len(a), len(b))
    diff = [i for i in range(n) if a[i] != b[i]]
    if len(a) != len(b):
        return '%d bytes in run a, %d in run b; first difference at byte %d' % (
            len(a), len(b), diff[0] if diff else n)
    return '%d bytes; %d differ, from byte %d to %d' % (len(a), len(diff), diff[0], diff[-1])


def field_differences(msg_type, a, b):
    """[(field path, value in a, value in b)] of two serialized messages of msg_type, or None when
    the type cannot be imported here (no ROS Python on the path)."""
    try:
        import roslib.message
        cls = roslib.message.get_message_class(msg_type)
    except Exception:  # noqa: BLE001 - any import or lookup failure: bytes only
        return None
    if cls is None:
        return None
    try:
        ma, mb = cls().deserialize(a), cls().deserialize(b)
    except Exception as e:  # noqa: BLE001 - genpy raises several kinds
        return [('(not a %s)' % msg_type, str(e), '')]
    out = []

    def walk(path, x, y):
        slots = getattr(x, '__slots__', None)
        if slots and type(x) is type(y):
            for name in slots:
                walk(path + '.' + name if path else name, getattr(x, name), getattr(y, name))
        elif isinstance(x, (list, tuple)) and isinstance(y, (list, tuple)) and len(x) == len(y):
            for i, (u, v) in enumerate(zip(x, y)):
                walk('%s[%d]' % (path, i), u, v)
        elif x != y:
            out.append((path, _show(x), _show(y)))
    walk('', ma, mb)
    return out


def _show(v):
    if isinstance(v, float):
        return repr(v)
    text = str(v)
    return text if len(text) <= 80 else text[:77] + '...'


def _last_tick_before(section, tick):
    best = None
    for t in section.ticks:
        if t.seq < tick.seq:
            best = t
    return best


def _publisher_note(first, peer, topic, by_a):
    """Says where the differing message on `topic` from `peer` came from."""
    phase = first.key[0]
    if peer == SIMULATOR:
        return ('%s comes from the simulator: its physics between rounds made it; its inputs '
                '(the commands it received) agree up to this point, so look at the simulator '
                '(or at a command from a node that does not take part)' % topic)
    secs_a = [s for k, s in by_a.items() if k[0] == phase and k[1] == peer]
    if not secs_a:
        return ('%s is not a participant (no digest): its messages arrive at wall-clock times'
                % peer)
    tick = first.a or first.b
    before = [(_last_tick_before(s, tick), s) for s in secs_a]
    before = [(t, s) for t, s in before if t is not None]
    if not before:
        return None
    t, _ = max(before, key=lambda ts: ts[0].seq)
    return ('%s published it at or before its tick at %s (tick %d), where everything it had '
            'received and sent agrees in both runs: %s computed something different from the '
            'same inputs (a wall-clock read, thread timing, an unordered container, an '
            'uninitialised value, an input that is not a recorded topic: a service call or a '
            'non-participant\'s message)' % (peer, t.stamp, t.seq, peer))


def _ends_note(ends):
    """How far each run went on after the compared part (its stack was stopped then)."""
    if not ends or None in ends or ends[0] == ends[1]:
        return ''
    return ' (the runs were stopped at %d.%09d and %d.%09d)' % (ends[0] + ends[1])


def report(result, dir_a, dir_b, limit=5):
    """The comparison as text lines."""
    lines = []
    if result.identical:
        lines.append('identical: %d sections, %d ticks compared (run a %s, run b %s)'
                     % (result.sections, result.ticks, dir_a, dir_b))
        for phase in sorted(result.last_stamp):
            lines.append('  phase %d: up to sim time %s%s' % (
                phase, result.last_stamp[phase], _ends_note(result.ends.get(phase))))
        return lines
    first = result.differences[0]
    lines.append('first difference (phase %d): %s' % (first.key[0], first.what))
    for d in first.details:
        lines.append('  ' + d)
    for run, t, directory in (('a', first.a, dir_a), ('b', first.b, dir_b)):
        if t is not None:
            lines.append('  run %s: %s, line %d' % (run, os.path.join(directory, file_name(
                first.key[1])), t.line))
    rest = result.differences[1:limit]
    if rest:
        lines.append('then (each section\'s first difference):')
        for d in rest:
            lines.append('  phase %d, %s%s' % (d.key[0], d.what,
                                              (': ' + d.details[0]) if d.details else ''))
    if len(result.differences) > limit:
        lines.append('  ... %d more sections differ' % (len(result.differences) - limit))
    lines.append('%d ticks of %d sections agree' % (result.ticks, result.sections))
    return lines
