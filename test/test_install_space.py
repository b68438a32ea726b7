"""catkin's install space works on its own.

From a clean copy of the tree (the files git tracks, plus new ones it does not ignore), in an
environment with nothing sourced, `catkin_make install` builds an install space; then, with only
that install space's setup.bash sourced, `roslaunch minibot3d_navigation amcl_navigation.launch`
brings up the simulator, map_server, amcl and move_base: amcl publishes a pose and move_base its
action status. Every process of the launch runs from the install space or the system, none from
the source tree, and every installed launch file reaches its files through $(find pkg) only.

The build is the long part (the whole workspace, without the tests): a few minutes on 2 cores."""
import glob
import os
import shutil
import subprocess

import pytest

from minibot3d_testing import Stack, descendants

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SYSTEM_PATH = '/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin'
EXCLUDED = {'build', 'devel', 'install', 'out', '.git'}


def copy_clean_tree(dest):
    """The source files only: no build/, devel/, install/ or out/ of a previous build."""
    listed = subprocess.run(['git', 'ls-files', '-co', '--exclude-standard', '-z'], cwd=ROOT,
                            capture_output=True)
    if listed.returncode == 0:
        files = [f for f in listed.stdout.decode().split('\0') if f]
    else:  # not a git checkout (an unpacked archive): everything but the build products
        files = []
        for d, dirs, names in os.walk(ROOT):
            dirs[:] = [x for x in dirs if not (d == ROOT and x in EXCLUDED)]
            files += [os.path.relpath(os.path.join(d, n), ROOT) for n in names]
    for rel in files:
        src = os.path.join(ROOT, rel)
        if not os.path.lexists(src):
            continue  # deleted in the working tree, not yet in git
        dst = os.path.join(dest, rel)
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        if os.path.islink(src):
            os.symlink(os.readlink(src), dst)
        else:
            shutil.copy2(src, dst)


def bare_env(**extra):
    """Nothing sourced: no ROS_PACKAGE_PATH, CMAKE_PREFIX_PATH or PYTHONPATH of this workspace."""
    env = {'HOME': os.environ.get('HOME', '/root'), 'PATH': SYSTEM_PATH, 'LANG': 'C.UTF-8'}
    env.update(extra)
    return env


def in_install(install, command, **kwargs):
    return subprocess.run(['bash', '-c', 'source "%s/setup.bash" && %s' % (install, command)],
                          **kwargs)


@pytest.fixture(scope='module')
def install(tmp_path_factory):
    tmp = tmp_path_factory.mktemp('install_space')
    src = tmp / 'src'
    copy_clean_tree(str(src))
    prefix = tmp / 'install'
    build = subprocess.run(
        ['catkin_make', '--source', str(src), '--build', str(tmp / 'build'),
         '-DCMAKE_BUILD_TYPE=Release', '-DPYTHON_EXECUTABLE=/usr/bin/python3',
         '-DCATKIN_ENABLE_TESTING=OFF', '-DCATKIN_DEVEL_PREFIX=%s' % (tmp / 'devel'),
         '-DCMAKE_INSTALL_PREFIX=%s' % prefix, '-j%s' % os.environ.get('JOBS', '2'), 'install'],
        cwd=str(src), env=bare_env(), capture_output=True, text=True, timeout=3600)
    assert build.returncode == 0, 'catkin_make install failed:\n%s\n%s' % (build.stdout[-4000:],
                                                                          build.stderr[-4000:])
    # The source copy goes: nothing may reach it from the install space.
    shutil.rmtree(str(src))
    return str(prefix)


def test_install_space_holds_what_a_user_needs(install):
    share = os.path.join(install, 'share')
    lib = os.path.join(install, 'lib')
    for path in ['minibot3d_bringup/config/amcl.yaml', 'minibot3d_bringup/config/gmapping.yaml',
                 'minibot3d_bringup/maps/default_world.yaml',
                 'minibot3d_bringup/maps/default_world.pgm',
                 'minibot3d_bringup/launch/navigation.launch',
                 'minibot3d_sim/worlds/default.world', 'minibot3d_sim/rviz',
                 'minibot3d_description/urdf/minibot3d.xacro', 'minibot3d_description/meshes',
                 'minibot3d_navigation/launch/amcl_navigation.launch',
                 'minibot3d_navigation/rviz/navigation.rviz',
                 'minibot3d_slam/launch/slam_gmapping.launch',
                 'minibot3d_teleop/launch/minibot3d_teleop.launch']:
        assert os.path.exists(os.path.join(share, path)), path
    for path in ['minibot3d_sim/minibot3d_sim', 'minibot3d_sim/simple_navi_goals.py',
                 'minibot3d_sim/route_driver.py', 'minibot3d_slam/slam_gmapping',
                 'minibot3d_slam/map_saver', 'minibot3d_slam/map_server',
                 'minibot3d_navigation/amcl', 'minibot3d_navigation/move_base',
                 'minibot3d_navigation/explore', 'minibot3d_navigation/simple_navi_goals.py',
                 'minibot3d_tuning/tune_planner', 'minibot3d_teleop/diff_wheeled_robot_key']:
        assert os.access(os.path.join(lib, path), os.X_OK), path


def test_map_io_is_installed_for_cpp_and_python(install):
    for path in ['include/minibot3d_map_io/map_io.h', 'lib/libminibot3d_map_io.so']:
        assert os.path.exists(os.path.join(install, path)), path
    read = in_install(
        install, '/usr/bin/python3 -c "import minibot3d_map_io as m, os, sys; '
        'g = m.load_map(sys.argv[1]); print(g.width, g.height, os.path.dirname(m.__file__))" '
        '%s/share/minibot3d_bringup/maps/default_world.yaml' % install,
        env=bare_env(), capture_output=True, text=True, timeout=60)
    assert read.returncode == 0, read.stderr
    width, height, where = read.stdout.split()
    assert int(width) > 0 and int(height) > 0
    assert where.startswith(install), 'minibot3d_map_io imported from %s' % where


def test_installed_launch_files_use_find_only(install):
    launch_files = glob.glob(os.path.join(install, 'share', '*', 'launch', '*.launch'))
    assert len(launch_files) >= 10
    relative = [f for f in launch_files if '$(dirname)/..' in open(f).read()]
    assert not relative, 'launch files reaching outside their package by path: %s' % relative


def test_amcl_navigation_runs_from_the_install_space(install, tmp_path):
    found = in_install(install, 'rospack find minibot3d_bringup', env=bare_env(),
                       capture_output=True, text=True, timeout=60)
    assert found.returncode == 0 and found.stdout.strip().startswith(install), found

    # The master (rosmaster, rosout) is the system's, started before the launch; everything
    # the launch starts is checked below.
    stack = Stack(['bash', '-c', 'source "%s/setup.bash" && exec roslaunch minibot3d_navigation '
                   'amcl_navigation.launch rviz:=false real_time_factor:=2' % install],
                  tmp_path / 'launch.log', env=bare_env(ROS_HOME=str(tmp_path)))
    try:
        # Waits on messages (rostopic echo blocks until one comes), each bounded: amcl's first
        # pose, move_base's action status.
        for topic in ('/amcl_pose', '/move_base/status'):
            try:
                got = in_install(install, 'rostopic echo -n 1 %s' % topic, env=stack.env,
                                 capture_output=True, text=True, timeout=240)
            except subprocess.TimeoutExpired:
                got = None
            assert got is not None and got.returncode == 0 and got.stdout.strip(), \
                'no %s from the install space (%s):\n%s' % (
                    topic, got and got.stderr, stack.log(4000))
        # Every process the launch started runs from the install space or the system.
        from_source = []
        for pid in descendants(stack.launch.pid):
            try:
                cmdline = open('/proc/%d/cmdline' % pid, 'rb').read().decode(errors='replace')
            except OSError:
                continue
            if ROOT in cmdline:
                from_source.append(cmdline.replace('\0', ' '))
        assert not from_source, from_source
    finally:
        stack.stop()
