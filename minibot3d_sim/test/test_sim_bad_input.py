"""The simulator node refuses bad input with a message naming what is wrong, and does not crash:
missing or broken robot_description, a URDF without the drive plugin or with a laser it cannot
simulate, a world
that does not exist or does not parse, a mesh that cannot be found, bad parameters.

Each case runs the real node against a ROS master of the test's own."""
import os
import re
import subprocess
import tempfile

import pytest
from minibot3d_testing import RosCore

HERE = os.path.dirname(os.path.abspath(__file__))
XACRO = os.path.join(HERE, '..', '..', 'minibot3d_description', 'urdf', 'minibot3d.xacro')
ARENA = os.path.join(HERE, '..', 'worlds', 'arena.world')


@pytest.fixture(scope='module')
def master():
    with RosCore(rosout=False) as core:
        yield core.env


@pytest.fixture(scope='module')
def urdf():
    return subprocess.run(['xacro', XACRO], check=True, capture_output=True, text=True).stdout


def run_node(env, description, *params):
    # Private parameters given as _name:=value stay on the server: start each case clean.
    subprocess.run(['rosparam', 'delete', '/minibot3d_sim'], env=env, capture_output=True)
    if description is None:
        subprocess.run(['rosparam', 'delete', '/robot_description'], env=env,
                       capture_output=True)
    else:
        with tempfile.NamedTemporaryFile('w', suffix='.urdf', delete=False) as f:
            f.write(description)
        subprocess.run(['rosparam', 'set', '/robot_description', '-t', f.name], env=env,
                       check=True, capture_output=True)
        os.unlink(f.name)
    out = subprocess.run(['rosrun', 'minibot3d_sim', 'minibot3d_sim'] + list(params), env=env,
                         capture_output=True, text=True, timeout=60)
    return out.returncode, out.stdout + out.stderr


def expect_refusal(env, description, needle, *params):
    rc, text = run_node(env, description, *params)
    assert rc == 1, 'exit %d (expected 1), output:\n%s' % (rc, text)
    assert needle in text, 'message does not mention %r:\n%s' % (needle, text)


def test_missing_robot_description(master):
    expect_refusal(master, None, 'robot_description is not set', '_world:=' + ARENA)


def test_unparsable_robot_description(master):
    expect_refusal(master, '<robot name="x"><link>', 'not valid XML', '_world:=' + ARENA)


def test_no_drive_plugin(master, urdf):
    broken = urdf.replace('libgazebo_ros_skid_steer_drive.so', 'libsomething_else.so')
    expect_refusal(master, broken, 'libgazebo_ros_skid_steer_drive.so', '_world:=' + ARENA)


def test_laser_without_beams(master, urdf):
    broken = re.sub(r'<samples>\s*360\s*</samples>', '<samples>0</samples>', urdf)
    assert broken != urdf
    expect_refusal(master, broken, '<samples> must be a whole number', '_world:=' + ARENA)


def test_world_missing(master, urdf):
    expect_refusal(master, urdf, '/no/such/world.world', '_world:=/no/such/world.world')


def test_world_unparsable(master, urdf, tmp_path):
    bad = tmp_path / 'broken.world'
    bad.write_text('<sdf version="1.6"><world name="w"><model name="m">')
    expect_refusal(master, urdf, str(bad), '_world:=' + str(bad))


def test_mesh_missing(master, urdf, tmp_path):
    world = tmp_path / 'mesh.world'
    world.write_text(
        '<sdf version="1.6"><world name="w"><model name="statue"><static>true</static>'
        '<link name="l"><collision name="c"><geometry><mesh><uri>meshes/statue.dae</uri>'
        '</mesh></geometry></collision></link></model></world></sdf>')
    expect_refusal(master, urdf, 'statue.dae', '_world:=' + str(world))


def test_bad_parameters(master, urdf):
    expect_refusal(master, urdf, 'warp', '_world:=' + ARENA, '_physics:=warp', '_x:=0', '_y:=0')
    expect_refusal(master, urdf, 'physics_step', '_world:=' + ARENA, '_physics_step:=0.5',
                   '_x:=0', '_y:=0')
    expect_refusal(master, urdf, 'real_time_factor', '_world:=' + ARENA,
                   '_real_time_factor:=-1', '_x:=0', '_y:=0')


def test_spawn_inside_a_wall(master, urdf):
    expect_refusal(master, urdf, 'overlaps', '_world:=' + ARENA, '_x:=3.05', '_y:=0')


def set_descriptions(env, urdf, names):
    with tempfile.NamedTemporaryFile('w', suffix='.urdf', delete=False) as f:
        f.write(urdf)
    for name in names:
        subprocess.run(['rosparam', 'set', '/%s/robot_description' % name, '-t', f.name],
                       env=env, check=True, capture_output=True)
    os.unlink(f.name)


def test_several_robots_bad_names_and_spawns(master, urdf):
    set_descriptions(master, urdf, ['r1', 'r2'])
    expect_refusal(master, urdf, "'r1'", '_world:=' + ARENA, '_robots:=r1 r1',
                   '_r1/x:=0', '_r1/y:=0')
    expect_refusal(master, urdf, '2r', '_world:=' + ARENA, '_robots:=r1 2r', '_r1/x:=0',
                   '_r1/y:=0')
    # r2 0.1 m from r1: the bodies overlap.
    expect_refusal(master, urdf, 'overlap', '_world:=' + ARENA, '_robots:=r1 r2', '_r1/x:=0',
                   '_r1/y:=0', '_r2/x:=0.1', '_r2/y:=0')
    # r2 inside the arena's wall: the message names the robot.
    expect_refusal(master, urdf, 'robot r2', '_world:=' + ARENA, '_robots:=r1 r2', '_r1/x:=0',
                   '_r1/y:=0', '_r2/x:=3.05', '_r2/y:=0')
