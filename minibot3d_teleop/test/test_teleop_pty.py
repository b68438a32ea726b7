"""The real diff_wheeled_robot_key script from the source tree, typed at through a pseudo-terminal
(and through a pipe), against a ROS master of the test's own: the twists it publishes, the
ramps between them, the zero twist on every way out, the terminal restored afterwards, and the
refusal of bad parameters.

Twists are recorded by twist_recorder.py in its own process. Every wait is on a condition (a
message, an exit, a line of output) with a timeout."""
import json
import os
import select
import signal
import subprocess
import sys
import termios
import threading
import xmlrpc.client

import pytest
import rosgraph
from minibot3d_testing import RosCore, wait_until

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', 'scripts', 'diff_wheeled_robot_key')
RECORDER = os.path.join(HERE, 'twist_recorder.py')
DEFAULT_NAME = 'turtlebot_teleop_keyboard'
TIMEOUT = 30.0  # generous: rospy start-up on a loaded 2-core machine

# Ramp steps per tick: 2.0 / 25 = 0.08 m/s and 6.0 / 25 = 0.24 rad/s; full speed in 5 ticks.
SCALE_LINEAR, SCALE_ANGULAR, ACCEL_LINEAR, ACCEL_ANGULAR, RATE = 0.4, 1.2, 2.0, 6.0, 25.0
PARAMS = ['_scale_linear:=%g' % SCALE_LINEAR, '_scale_angular:=%g' % SCALE_ANGULAR,
          '_accel_linear:=%g' % ACCEL_LINEAR, '_accel_angular:=%g' % ACCEL_ANGULAR,
          '_rate:=%g' % RATE]
STEP_LINEAR = ACCEL_LINEAR / RATE * (1 + 1e-6)
STEP_ANGULAR = ACCEL_ANGULAR / RATE * (1 + 1e-6)
ZERO = (0.0, 0.0)


@pytest.fixture(scope='module')
def master():
    # /usr/bin first: the script's "#!/usr/bin/env python3" must find the system Python.
    with RosCore(dict(os.environ, PATH='/usr/bin:' + os.environ.get('PATH', ''),
                      PYTHONUNBUFFERED='1'), rosout=False) as core:
        yield core.env


def clear_params(env, node_name):
    """Private parameters given as _name:=value stay on the server: start each run clean."""
    m = rosgraph.Master('/pytest', env['ROS_MASTER_URI'])
    if m.hasParam('/' + node_name):
        m.deleteParam('/' + node_name)


def wait_publisher_connected(env, node_name):
    """Until the teleop node itself lists an outgoing connection on its cmd_vel topic.

    The subscriber's side is not enough: rospy's publisher sends its connection header before it
    adds the connection, so a message published in between is lost."""
    topic = '/%s/cmd_vel' % node_name
    m = rosgraph.Master('/pytest', env['ROS_MASTER_URI'])

    def connected():
        try:
            node = xmlrpc.client.ServerProxy(m.lookupNode('/' + node_name))
            _, _, bus_info = node.getBusInfo('/pytest')
        except (rosgraph.MasterError, OSError):
            return False  # not registered yet
        return any(c[2] == 'o' and c[4] == topic for c in bus_info)
    wait_until(connected, TIMEOUT, 'a subscriber connection on %s' % topic, interval=0.01)


class Recorder(object):
    """twist_recorder.py on `topic`; .twists is the list of (linear.x, angular.z) received."""

    def __init__(self, env, topic):
        self.twists = []
        self._cond = threading.Condition()
        self._proc = subprocess.Popen([sys.executable, RECORDER, topic], env=env,
                                      stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        self._thread = threading.Thread(target=self._read, daemon=True)
        self._thread.start()

    def _read(self):
        for line in self._proc.stdout:
            if not line.startswith('{'):
                continue  # rospy's own messages ("Unable to register with master...")
            record = json.loads(line)
            with self._cond:
                assert record['other'] == [0.0] * 4, record
                self.twists.append((record['linear'], record['angular']))
                self._cond.notify_all()

    def wait_for(self, twist, start=0, timeout=TIMEOUT):
        """Index of the first twist == `twist` at or after `start`."""
        def found():
            return next((i for i in range(start, len(self.twists))
                         if self.twists[i] == twist), None)
        with self._cond:
            assert self._cond.wait_for(lambda: found() is not None, timeout), \
                'no twist %s after #%d; received %s' % (twist, start, self.twists)
            return found()

    def close(self):
        self._proc.stdin.close()
        try:
            self._proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()
        self._thread.join(timeout=10)


class PtyTeleop(object):
    """The script with a pseudo-terminal as stdin, stdout and stderr; .output collects its text."""

    def __init__(self, env, *args):
        self.master_fd, self.slave_fd = os.openpty()
        self.terminal_before = termios.tcgetattr(self.slave_fd)
        self.proc = subprocess.Popen([SCRIPT] + list(args), env=env, stdin=self.slave_fd,
                                     stdout=self.slave_fd, stderr=self.slave_fd,
                                     start_new_session=True)
        self._output = []
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._drain, daemon=True)
        self._thread.start()

    def _drain(self):
        # Keep reading, or the child blocks once the pty buffer is full.
        while not self._stop.is_set():
            ready, _, _ = select.select([self.master_fd], [], [], 0.05)
            if not ready:
                continue
            try:
                data = os.read(self.master_fd, 4096)
            except OSError:
                return
            if not data:
                return
            with self._lock:
                self._output.append(data.decode(errors='replace'))

    @property
    def output(self):
        with self._lock:
            return ''.join(self._output)

    def wait_output(self, text):
        wait_until(lambda: text in self.output, TIMEOUT,
                   lambda: '%r in the teleop output:\n%s' % (text, self.output), interval=0.01)

    def send(self, keys):
        os.write(self.master_fd, keys.encode())

    def hang_up(self):
        """Closes the terminal: the teleop reads end of input (EIO)."""
        self._stop.set()
        self._thread.join(timeout=10)
        os.close(self.master_fd)
        os.close(self.slave_fd)
        self.master_fd = self.slave_fd = None

    def wait_exit(self):
        return self.proc.wait(timeout=TIMEOUT)

    def close(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        if self.master_fd is not None:
            self._stop.set()
            self._thread.join(timeout=10)
            os.close(self.master_fd)
            os.close(self.slave_fd)


@pytest.fixture
def start_teleop(master):
    """Starts a recorder on a node name's topic, then the teleop on a pty; cleans both up."""
    started = []

    def start(node_name=DEFAULT_NAME, extra=()):
        clear_params(master, node_name)
        recorder = Recorder(master, '/%s/cmd_vel' % node_name)
        started.append(recorder)
        args = list(PARAMS) + list(extra)
        if node_name != DEFAULT_NAME:
            args.append('__name:=' + node_name)
        teleop = PtyTeleop(master, *args)
        started.append(teleop)
        wait_publisher_connected(master, node_name)
        return recorder, teleop

    yield start
    for thing in reversed(started):
        thing.close()


def assert_ramp(twists, start, end):
    """Each step between twists[start..end] within the acceleration limits."""
    for a, b in zip(twists[start:end], twists[start + 1:end + 1]):
        assert abs(b[0] - a[0]) <= STEP_LINEAR, 'linear step %s -> %s' % (a, b)
        assert abs(b[1] - a[1]) <= STEP_ANGULAR, 'angular step %s -> %s' % (a, b)


def test_script_is_executable_with_the_system_python():
    assert os.access(SCRIPT, os.X_OK), '%s is not executable (chmod +x)' % SCRIPT
    with open(SCRIPT) as f:
        assert f.readline().strip() == '#!/usr/bin/env python3'


def test_help_needs_no_master():
    out = subprocess.run([SCRIPT, '--help'], capture_output=True, text=True, timeout=60,
                         env=dict(os.environ, PATH='/usr/bin:' + os.environ.get('PATH', ''),
                                  ROS_MASTER_URI='http://127.0.0.1:9'))
    assert out.returncode == 0, out.stderr
    assert 'u    i    o' in out.stdout and 'not a terminal' in out.stdout


def test_forward_stop_turn_quit_through_a_terminal(start_teleop):
    recorder, teleop = start_teleop()
    teleop.wait_output('Moving around')
    teleop.wait_output('a terminal (raw mode)')
    # Raw mode: no echo, no line buffering (the key acts without Enter).
    assert not termios.tcgetattr(teleop.slave_fd)[3] & (termios.ICANON | termios.ECHO)

    teleop.send('i')
    full = recorder.wait_for((SCALE_LINEAR, 0.0))
    assert full >= 4, 'no ramp up to full speed: %s' % recorder.twists[:full + 1]
    assert_ramp([ZERO] + recorder.twists, 0, full + 1)
    assert all(0.0 < v <= SCALE_LINEAR and w == 0.0 for v, w in recorder.twists[:full + 1])
    teleop.wait_output('command linear +0.40 m/s')

    teleop.send('k')
    stopped = recorder.wait_for(ZERO, start=full)
    assert stopped - full >= 4, 'no ramp down: %s' % recorder.twists[full:stopped + 1]
    assert_ramp(recorder.twists, full, stopped)

    teleop.send('j')
    turning = recorder.wait_for((0.0, SCALE_ANGULAR), start=stopped + 1)
    assert turning - stopped >= 4
    assert_ramp(recorder.twists, stopped, turning)
    assert all(v == 0.0 for v, _ in recorder.twists[stopped:turning + 1])

    teleop.send('\x03')  # Ctrl-C: a character in raw mode
    assert teleop.wait_exit() == 0, teleop.output
    last = recorder.wait_for(ZERO, start=turning + 1)
    assert recorder.twists[turning:last] == [(0.0, SCALE_ANGULAR)] * (last - turning), \
        'the final zero twist is not ramped: the teleop stops at once on exit'
    teleop.wait_output('quit key, sent a zero twist')
    assert termios.tcgetattr(teleop.slave_fd) == teleop.terminal_before, \
        'terminal settings not restored'
    assert recorder.twists[-1] == ZERO


@pytest.mark.parametrize('how', ['ctrl-d', 'hang-up', 'SIGINT', 'SIGTERM', 'SIGHUP',
                                 'rosnode-kill'])
def test_every_way_out_sends_a_zero_twist(master, start_teleop, how):
    name = 'teleop_exit_%s' % how.lower().replace('-', '_')
    recorder, teleop = start_teleop(name)
    teleop.send('u')
    moving = recorder.wait_for((SCALE_LINEAR, SCALE_ANGULAR))
    if how == 'ctrl-d':
        teleop.send('\x04')
    elif how == 'hang-up':
        teleop.hang_up()
    elif how == 'rosnode-kill':
        subprocess.run(['rosnode', 'kill', '/' + name], env=master, check=True,
                       capture_output=True, timeout=TIMEOUT)
    else:
        teleop.proc.send_signal(getattr(signal, how))
    assert teleop.wait_exit() == 0, teleop.output
    recorder.wait_for(ZERO, start=moving + 1)
    assert recorder.twists[-1] == ZERO
    if teleop.slave_fd is not None:
        assert termios.tcgetattr(teleop.slave_fd) == teleop.terminal_before


def test_keys_from_a_pipe(master, tmp_path):
    """stdin that is not a terminal is read as it comes; its end stops the robot."""
    name = 'teleop_pipe'
    clear_params(master, name)
    recorder = Recorder(master, '/%s/cmd_vel' % name)
    log = open(str(tmp_path / 'teleop.log'), 'w+')
    teleop = subprocess.Popen([SCRIPT, '__name:=' + name] + PARAMS, env=master,
                              stdin=subprocess.PIPE, stdout=log, stderr=subprocess.STDOUT)
    try:
        wait_publisher_connected(master, name)
        teleop.stdin.write(b'iww')  # forward, then the linear speed +10 % twice
        teleop.stdin.flush()
        moving = recorder.wait_for((pytest.approx(SCALE_LINEAR * 1.21), 0.0))
        teleop.stdin.write(b'l')
        teleop.stdin.flush()
        recorder.wait_for((pytest.approx(0.0), -SCALE_ANGULAR), start=moving + 1)
        teleop.stdin.close()
        assert teleop.wait(timeout=TIMEOUT) == 0
        recorder.wait_for(ZERO)
        assert recorder.twists[-1] == ZERO
        log.seek(0)
        text = log.read()
        assert 'not a terminal' in text and 'end of input, sent a zero twist' in text, text
    finally:
        if teleop.poll() is None:
            teleop.kill()
            teleop.wait()
        recorder.close()
        log.close()


@pytest.mark.parametrize('param, value', [('scale_linear', '-0.5'), ('scale_angular', '0'),
                                          ('accel_linear', '.inf'), ('rate', '.nan'),
                                          ('accel_angular', 'fast')])
def test_bad_parameter_is_refused_by_name(master, param, value):
    name = 'teleop_bad'
    clear_params(master, name)
    out = subprocess.run([SCRIPT, '__name:=' + name, '_%s:=%s' % (param, value)], env=master,
                         stdin=subprocess.DEVNULL, capture_output=True, text=True,
                         timeout=TIMEOUT)
    text = out.stdout + out.stderr
    assert out.returncode == 1, text
    assert '~%s must be a positive finite number' % param in text, text


def test_misspelled_parameter_is_reported(master):
    name = 'teleop_typo'
    clear_params(master, name)
    out = subprocess.run([SCRIPT, '__name:=' + name, '_scale_linaer:=1.0'], env=master,
                         stdin=subprocess.DEVNULL, capture_output=True, text=True,
                         timeout=TIMEOUT)
    text = out.stdout + out.stderr
    assert out.returncode == 0, text  # stdin is /dev/null: end of input at once
    assert 'unknown parameter ~scale_linaer' in text, text
