"""Mapping by hand, one launch file per step, headless (docs/slam.md "Mapping by hand, one
launch file per step"):

  1. roslaunch minibot3d_sim minibot3d_gazebo.launch            -> /scan arrives
  2. roslaunch minibot3d_sim minibot3d_rviz_gmapping.launch     -> slam_gmapping publishes /map
  3. roslaunch minibot3d_teleop minibot3d_teleop.launch         -> keys typed through a
     pseudo-terminal drive the robot (forward, turn, forward)
  4. rosrun minibot3d_slam map_saver -f test_map                -> test_map.pgm / .yaml
  5. roslaunch minibot3d_navigation amcl_navigation.launch map_file:=.../test_map.yaml
  6. rosrun minibot3d_navigation simple_navi_goals.py 1 1       -> exits 0, robot ~1 m ahead

One ROS master (and rosout) of the test's own for the whole run, as one roscore would be; the
launches run at real_time_factor 4 (rviz:=false).
Every wait is on a condition (a message, a position, a process exit) with a timeout."""
import math
import os
import pty
import select
import signal
import subprocess

import pytest
from minibot3d_testing import RosCore, wait_until

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RTF = '4'


class Ros(object):
    def __init__(self, core, tmp_path):
        self.core, self.env = core, core.env
        self.procs = []
        self.tmp = tmp_path

    def start(self, args, name):
        p = self.core.start_process(args, self.tmp / (name + '.log'))
        self.procs.append(p)
        return p

    def run(self, args, timeout):
        return subprocess.run(args, env=self.env, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, universal_newlines=True, timeout=timeout)

    def wait_message(self, topic, timeout, field=None):
        """One message of `topic` (rostopic echo -n1), as text; fails after `timeout`."""
        out = self.run(['rostopic', 'echo', '-n', '1', topic + ('/' + field if field else '')],
                       timeout)
        assert out.returncode == 0, out.stdout
        return out.stdout

    def truth(self):
        text = self.wait_message('/ground_truth/odom', 60, 'pose/pose')
        vals = {}
        section = None
        for line in text.splitlines():
            s = line.strip()
            if s in ('position:', 'orientation:'):
                section = s[:-1]
            elif ':' in s and section:
                k, v = s.split(':', 1)
                try:
                    vals[section + '.' + k] = float(v)
                except ValueError:
                    pass
        qz, qw = vals['orientation.z'], vals['orientation.w']
        return vals['position.x'], vals['position.y'], 2.0 * math.atan2(qz, qw)


@pytest.fixture
def ros(tmp_path):
    with RosCore(dict(os.environ, ROS_HOME=str(tmp_path))) as core:
        r = Ros(core, tmp_path)
        try:
            yield r
        finally:
            for p in reversed(r.procs):
                p.stop(grace=30)


def type_keys(fd, keys):
    os.write(fd, keys.encode())


def drain(fd):
    while select.select([fd], [], [], 0)[0]:
        try:
            if not os.read(fd, 4096):
                return
        except OSError:
            return


def draining(fd, condition):
    """condition, reading away the teleop's terminal output first (a full pty would block it)."""
    def check():
        drain(fd)
        return condition()
    return check


def test_mapping_workflow(ros, tmp_path):
    # 1. The robot in the default world.
    sim = ros.start(['roslaunch', 'minibot3d_sim', 'minibot3d_gazebo.launch',
                     'real_time_factor:=' + RTF], 'step1')
    assert 'ranges' in ros.wait_message('/scan', 120)
    sim.stop(grace=30)

    # 2. Simulator + slam_gmapping (rviz off: headless).
    mapping = ros.start(['roslaunch', 'minibot3d_sim', 'minibot3d_rviz_gmapping.launch',
                         'rviz:=false', 'real_time_factor:=' + RTF], 'step2')
    assert 'resolution' in ros.wait_message('/map_metadata', 180)
    start = ros.truth()

    # 3. Teleop through a pseudo-terminal: forward, then turn left, then forward, then quit.
    pid, fd = pty.fork()
    if pid == 0:
        os.environ.update(ros.env)
        os.execvp('roslaunch', ['roslaunch', 'minibot3d_teleop', 'minibot3d_teleop.launch'])
    try:
        def teleop_up():  # the node is up when it publishes its topic
            return '/cmd_vel' in ros.run(['rostopic', 'list'], 30).stdout and \
                'turtlebot_teleop_keyboard' in ros.run(['rosnode', 'list'], 30).stdout

        def moved_from(start):
            x, y, _ = ros.truth()
            return math.hypot(x - start[0], y - start[1])

        def turned_from(yaw):
            return abs(math.remainder(ros.truth()[2] - yaw, 2 * math.pi))
        wait_until(draining(fd, teleop_up), 120, 'the teleop node', interval=0)
        type_keys(fd, 'i')
        wait_until(draining(fd, lambda: moved_from(start) > 0.6), 120,
                   'the robot to drive forward (key i)', interval=0)
        type_keys(fd, 'j')
        yaw = ros.truth()[2]
        wait_until(draining(fd, lambda: turned_from(yaw) > 1.0), 120,
                   'the robot to turn left (key j)', interval=0)
        type_keys(fd, 'k')
        type_keys(fd, '\x03')  # Ctrl-C: the teleop sends a zero twist and exits
        wait_until(draining(fd, lambda: os.waitpid(pid, os.WNOHANG)[0] != 0), 60,
                   'teleop to exit', interval=0)
        pid = None
    finally:
        if pid is not None:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
        os.close(fd)

    # 4. Save the map.
    base = str(tmp_path / 'test_map')
    out = ros.run(['rosrun', 'minibot3d_slam', 'map_saver', '-f', base], 120)
    assert out.returncode == 0, out.stdout
    assert os.path.getsize(base + '.pgm') > 0 and os.path.getsize(base + '.yaml') > 0
    mapping.stop(grace=30)

    # 5. Localize and navigate on the saved map. Its frame is where mapping started, which is
    #    the default spawn pose again, so amcl starts at (0, 0, 0) in it.
    nav = ros.start(['roslaunch', 'minibot3d_navigation', 'amcl_navigation.launch',
                     'map_file:=' + base + '.yaml', 'initial_pose_x:=0', 'initial_pose_y:=0',
                     'initial_pose_a:=0', 'real_time_factor:=' + RTF], 'step5')
    ros.wait_message('/amcl_pose', 180)
    before = ros.truth()

    # 6. The goal client, one metre ahead.
    out = ros.run(['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '1', '1',
                   '--timeout', '300'], 600)
    assert out.returncode == 0, out.stdout
    assert 'SUCCEEDED' in out.stdout
    after = ros.truth()
    forward = (after[0] - before[0]) * math.cos(before[2]) + \
        (after[1] - before[1]) * math.sin(before[2])
    assert abs(forward - 1.0) < 0.3, 'moved %.2f m forward' % forward
    nav.stop(grace=30)
