"""Every shipped rviz config draws what it is for.

For each .rviz file the test starts the stack that ships with it (its launch file with rviz:=true)
on a private ROS master, with rviz on its own virtual X server (Xvfb, Mesa's software renderer, as
in a VM), grabs the screen and checks the 3-D view by its colours:
- no display reports an error (its name turns red in the Displays panel);
- the view is not one flat colour (the "olive view": a single colour over most of it);
- the robot model is drawn (its orange chassis, in every config);
- the laser scan is drawn (red points) where the config shows /scan;
- mapping (gmapping.rviz): the map's free-space grey covers a growing area while route_driver.py
  drives the robot into a room it has not seen;
- navigation (navigation.rviz): the map's free space is drawn, and after a goal is sent the global
  plan's green line appears.
Each check polls the screen until it holds or a deadline passes; no fixed sleeps. The last picture
of each config is written atomically to build/rviz_shots/rviz_<name>.png, and also to
docs/rviz_<name>.png when RVIZ_SHOTS_TO_DOCS=1 (how the README's pictures are refreshed):
  RVIZ_SHOTS_TO_DOCS=1 /usr/bin/python3 -m pytest -q test/test_rviz_pictures.py
Skipped, saying why, where rviz, Xvfb or Pillow's X11 grab is not available."""
import glob
import os
import select
import shutil
import tempfile
import time

import minibot3d_testing as testing
import numpy as np
import pytest

try:
    from PIL import ImageGrab, features
    HAVE_GRAB = features.check('xcb')
except ImportError:
    HAVE_GRAB = False

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHOTS = os.path.join(ROOT, 'build', 'rviz_shots')
DOCS = os.path.join(ROOT, 'docs')

pytestmark = pytest.mark.skipif(
    shutil.which('rviz') is None or shutil.which('Xvfb') is None or not HAVE_GRAB,
    reason='rviz, Xvfb or Pillow with X11 grab is not installed (apt-get install rviz xvfb '
           'python3-pil)')

# Every shipped config sets Window Geometry 1200x800; with no window manager rviz's window sits at
# the screen's top-left corner. VIEW is the 3-D render panel inside it (left of it the Displays
# panel, above the tool bar, below the status bar).
WINDOW = (0, 0, 1200, 800)
VIEW = (364, 62, 1184, 770)
# The names column of the Displays panel: rviz writes a display's name in red (192;32;32) while
# its status is Error (a RobotModel without its wheels' transforms yet, a topic of the wrong type).
DISPLAY_NAMES = (44, 85, 170, 660)
SCREEN = '1280x900x24'

# Colours as Mesa draws them (8-bit RGB), from the configs and the URDF:
# - map free space: palette white at the Map display's Alpha 0.7 over the 48-grey background = 192;
# - robot chassis: URDF material "orange" (1.0, 0.45, 0.05): lit, G/R stays near 0.45 and B/R near
#   0.05 (the particle cloud's red over the costmap, 239;67;48, is not orange);
# - scan: LaserScan FlatColor 255;0;0;
# - global plan: Path colour 25;255;0.
FREE_GREY = 192


def classify(view):
    """Pixel counts of the classes the checks use, for an HxWx3 uint8 array of the 3-D view."""
    rgb = view.astype(np.int32)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    spread = rgb.max(axis=2) - rgb.min(axis=2)
    free = (np.abs(rgb - FREE_GREY).max(axis=2) <= 8) & (spread <= 4)
    orange = (r >= 90) & (g >= 0.38 * r) & (g <= 0.55 * r) & (b <= 0.12 * r)
    red = (r >= 150) & (g <= 0.15 * r) & (b <= 0.15 * r)
    green = (g >= 150) & (r <= 0.4 * g) & (b <= 0.25 * g)
    # The dominant colour and the share of the view within a few levels of it (colours packed
    # into one integer: np.unique over rows is ten times slower, and grabs must keep up).
    packed = ((r << 16) | (g << 8) | b).ravel()
    colours, counts = np.unique(packed, return_counts=True)
    best = int(colours[counts.argmax()])
    top = np.array([best >> 16, (best >> 8) & 255, best & 255])
    near_top = (np.abs(rgb - top).max(axis=2) <= 6)
    n = float(r.size)
    return {'free': free.sum() / n, 'robot': int(orange.sum()), 'scan': int(red.sum()),
            'plan': int(green.sum()), 'top': tuple(int(c) for c in top),
            'top_share': near_top.sum() / n, 'colours': len(colours)}


def error_names(panel):
    """Pixels of red (Error status) display names in the Displays panel's names column."""
    rgb = panel.astype(np.int32)
    return int(((rgb[..., 0] >= 150) & (rgb[..., 1] <= 80) & (rgb[..., 2] <= 80)).sum())


def describe(m):
    return ('free %.1f %%, robot %d px, scan %d px, plan %d px, dominant colour %s over %.0f %% '
            'of the view, %d colours, %d px of red (Error) display names' % (
                100 * m['free'], m['robot'], m['scan'], m['plan'], m['top'],
                100 * m['top_share'], m['colours'], m['errors']))


class Stack:
    """Xvfb on a display number it picks itself (-displayfd: no clash with parallel tests), the
    config's stack roslaunch'd on a ROS master of its own, and screen grabs."""

    def __init__(self, tmp_path):
        self.tmp = tmp_path
        self.xvfb = self.ros = None
        self.display = None
        self.last = None

    def start_x(self):
        rd, wr = os.pipe()
        # -noreset: by default an X server resets when its last client disconnects, and a
        # client connecting meanwhile is refused. Before rviz is up, each screen grab is the only
        # client: rviz, connecting during the reset a grab had started, aborted ("could not
        # connect to display") in about 1 run in 20.
        self.xvfb = testing.Process(['Xvfb', '-displayfd', str(wr), '-screen', '0', SCREEN,
                                     '-nolisten', 'tcp', '-noreset'], None,
                                    self.tmp / 'xvfb.log', pass_fds=(wr,))
        os.close(wr)
        number = b''
        deadline = time.time() + 30
        while not number.endswith(b'\n'):
            ready, _, _ = select.select([rd], [], [], max(0.0, deadline - time.time()))
            assert ready, 'Xvfb did not report a display number:\n' + self.xvfb.log(2000)
            chunk = os.read(rd, 16)
            assert chunk, 'Xvfb exited:\n' + self.xvfb.log(2000)
            number += chunk
        os.close(rd)
        self.display = ':' + number.decode().strip()

    def launch(self, package, launch_file, *args):
        self.start_x()
        # GALLIUM_DRIVER=softpipe: Mesa's software renderer without LLVM. With llvmpipe (Mesa
        # 22.3, LLVM 15) rviz crashed about once in 100 starts inside LLVM while compiling a
        # shader (SIGSEGV in llvm::FixedVectorType::get under Ogre's buffer swap; once glibc's
        # "free(): invalid next size" abort). softpipe draws the same colours, at 3 fps.
        env = dict(os.environ, ROS_HOME=str(self.tmp), DISPLAY=self.display,
                   GALLIUM_DRIVER='softpipe')
        self.log = self.tmp / 'stack.log'
        self.ros = testing.Stack(['roslaunch', package, launch_file, 'rviz:=true'] + list(args),
                                 self.log, env=env)
        # rviz's window is up when the screen is no longer Xvfb's black. Its start (Ogre, Mesa's
        # shader compiles) takes a few seconds, minutes on a machine loaded many times over, so
        # this deadline is long; the picture checks' deadlines count from here.

        def window_drawn():
            self.check_rviz_alive()
            window = np.asarray(ImageGrab.grab(xdisplay=self.display).crop(WINDOW))
            return (window.max(axis=2) > 0).mean() > 0.5
        testing.wait_until(window_drawn, 240, lambda: 'an rviz window within 240 s:\n' +
                           self.rviz_log(), interval=0.5)

    def check_rviz_alive(self):
        assert self.ros.launch.running(), 'the stack exited:\n' + self.ros.log(3000)
        died = [line for line in self.log.read_text().splitlines()
                if '[rviz-' in line and ('died' in line or 'finished' in line)]
        assert not died, 'rviz exited:\n' + self.rviz_log() + '\n' + self.x_state()

    def x_state(self):
        """What the X server looked like when rviz failed: is Xvfb running, does a new client
        connect, which of its sockets (file, abstract) exist."""
        try:
            ImageGrab.grab(xdisplay=self.display)
            connects = 'a new client connects'
        except Exception as e:  # noqa: BLE001 -- reported, not handled
            connects = 'a new client does not connect: %s' % e
        name = '/tmp/.X11-unix/X' + self.display[1:]
        with open('/proc/net/unix') as f:
            listening = sorted({line.split()[-1] for line in f if line.rstrip().endswith(name)})
        return 'Xvfb on %s: %s; %s; file socket %s; unix sockets bound to it: %s' % (
            self.display, 'running' if self.xvfb.running() else 'exited %s' % (
                self.xvfb.proc.returncode),
            connects, 'exists' if os.path.exists(name) else 'missing', listening or 'none')

    def run(self, *cmd):
        """Starts a helper (goal sender, driver) in the stack's environment."""
        return self.ros.start(cmd, self.tmp / 'helper.log')

    def rviz_log(self):
        """roslaunch's word on rviz and the tail of rviz's own log (under ROS_HOME)."""
        said = [line for line in self.log.read_text().splitlines() if 'rviz' in line]
        logs = sorted(glob.glob(str(self.tmp / 'log' / '*' / 'rviz-*.log')))
        tail = open(logs[-1], errors='replace').read()[-2000:] if logs else '(no rviz log)'
        return '\n'.join(said[-10:]) + '\n' + tail

    def grab(self):
        self.last = ImageGrab.grab(xdisplay=self.display).crop(WINDOW).convert('RGB')
        m = classify(np.asarray(self.last.crop(VIEW)))
        m['errors'] = error_names(np.asarray(self.last.crop(DISPLAY_NAMES)))
        return m

    def wait_for(self, what, ok, timeout):
        """Grabs the screen until ok(measures) holds; fails naming what and the last picture's
        measures after timeout wall seconds."""
        deadline = time.time() + timeout
        while True:
            self.check_rviz_alive()
            m = self.grab()
            if ok(m):
                return m
            if time.time() > deadline:
                shot = self.tmp / 'failed.png'
                self.last.save(shot)
                pytest.fail('%s: not within %.0f s; last picture (%s): %s\nrviz:\n%s' % (
                    what, timeout, shot, describe(m), self.rviz_log()))
            time.sleep(0.25)

    def save(self, name):
        os.makedirs(SHOTS, exist_ok=True)
        targets = [SHOTS] + ([DOCS] if os.environ.get('RVIZ_SHOTS_TO_DOCS') == '1' else [])
        for d in targets:
            fd, tmp = tempfile.mkstemp(prefix='.rviz_%s.' % name, suffix='.png', dir=d)
            with os.fdopen(fd, 'wb') as f:
                self.last.save(f, format='PNG')
            os.chmod(tmp, 0o644)  # mkstemp's 0600 would stay on the committed picture
            os.replace(tmp, os.path.join(d, 'rviz_%s.png' % name))

    def stop(self):
        for part in (self.ros, self.xvfb):
            if part is not None:
                part.stop()


@pytest.fixture
def stack(tmp_path):
    s = Stack(tmp_path)
    yield s
    s.stop()


def drawn(m):
    """No display reports an error, and the view is not one flat colour other than the configs'
    background (48, 48, 48): a view rviz fails to draw (the "olive view") has one colour over all
    of it."""
    return m['errors'] == 0 and (m['top_share'] < 0.95 or
                                 max(abs(c - 48) for c in m['top']) <= 4)


def test_view_mobile_robot(stack):
    stack.launch('minibot3d_description', 'view_mobile_robot.launch')
    # Close up (0.8 m): the chassis takes a good part of the view.
    stack.wait_for('the robot model drawn', lambda m: drawn(m) and m['robot'] > 5000, 90)
    stack.save('view_mobile_robot')


def test_sim(stack):
    stack.launch('minibot3d_sim', 'minibot3d_gazebo.launch')
    stack.wait_for('the robot model and the scan drawn',
                   lambda m: drawn(m) and m['robot'] > 150 and m['scan'] > 150, 90)
    stack.save('minibot3d_sim')


def test_gmapping(stack):
    stack.launch('minibot3d_sim', 'minibot3d_rviz_gmapping.launch', 'real_time_factor:=2')
    first = stack.wait_for('the first map (free space) with the robot and the scan',
                           lambda m: drawn(m) and m['free'] > 0.02 and m['robot'] > 30 and
                           m['scan'] > 100, 90)
    # North out of the start room into the next one (waypoints from tools/bench.sh's route).
    stack.run('rosrun', 'minibot3d_sim', 'route_driver.py', '--map',
              os.path.join(ROOT, 'minibot3d_bringup', 'maps', 'default_world.yaml'),
              '--waypoints', '-2.1,0.6 -2.4,3.0', '--speed', '0.4', '--timeout', '120')
    stack.wait_for('free space growing by half as the robot maps (first map: %.1f %% of the view)'
                   % (100 * first['free']),
                   lambda m: drawn(m) and m['free'] > 1.5 * first['free'] and m['robot'] > 30,
                   120)
    stack.save('gmapping')


def test_navigation(stack):
    # Real time: the global plan is drawn only while the robot is under way, and the goal, in the
    # room 5.5 m east of the start, keeps it under way for some 15 s, many grabs.
    stack.launch('minibot3d_navigation', 'amcl_navigation.launch')
    stack.wait_for('the map (free space) with the robot', lambda m: drawn(m) and
                   m['free'] > 0.02 and m['robot'] > 30, 90)
    stack.run('rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'map',
              '2.5', '-1.0', '0', '--timeout', '100')
    stack.wait_for('the global plan drawn after a goal', lambda m: drawn(m) and
                   m['free'] > 0.02 and m['robot'] > 30 and m['plan'] > 40, 90)
    stack.save('navigation')


CONFIG_TESTS = {
    'minibot3d_description/rviz/view_mobile_robot.rviz': test_view_mobile_robot,
    'minibot3d_sim/rviz/minibot3d_sim.rviz': test_sim,
    'minibot3d_sim/rviz/gmapping.rviz': test_gmapping,
    'minibot3d_navigation/rviz/navigation.rviz': test_navigation,
}


def test_every_config_has_a_picture_test():
    shipped = sorted(os.path.relpath(f, ROOT)
                     for f in glob.glob(os.path.join(ROOT, '*', 'rviz', '*.rviz')))
    assert shipped == sorted(CONFIG_TESTS), 'configs without a picture test: %s' % sorted(
        set(shipped) - set(CONFIG_TESTS))
