"""A robot's frame names for the Python nodes (minibot3d_ros.frames): every case of
frame_names_cases.txt, the table the C++ resolver's frames_test.cpp runs too (a rule changed in
one language only fails here or there), and the parameters found on a master as rospy nodes find
them: in the robot's namespace, overridden in the node's private one, refused with their full
name."""
import os
import subprocess
import sys

import minibot3d_testing as testing
import pytest
import rosgraph

from minibot3d_ros.frames import FrameNames, parse_list

HERE = os.path.dirname(os.path.abspath(__file__))
PROBE = os.path.join(HERE, 'frames_probe.py')


def cases():
    out = []
    with open(os.path.join(HERE, 'frame_names_cases.txt')) as f:
        for n, line in enumerate(f, start=1):
            if not line.strip() or line.strip().startswith('#'):
                continue
            fields = [x.strip() for x in line.rstrip('\n').split('|')]
            fields += [''] * (4 - len(fields))
            assert len(fields) == 4, 'line %d: %r' % (n, line)
            out.append(pytest.param(*fields, id='line%d' % n))
    return out


@pytest.mark.parametrize('prefix,shared,frame,resolved', cases())
def test_every_case_of_the_table(prefix, shared, frame, resolved):
    if resolved == '!':
        with pytest.raises(ValueError):
            FrameNames(prefix, parse_list(shared))
        return
    assert FrameNames(prefix, parse_list(shared)).resolve(frame) == resolved


def test_the_table_has_cases_of_every_kind():
    rows = [c.values for c in cases()]
    assert len(rows) >= 20
    assert any(r[3] == '!' for r in rows) and any(r[0] == '' for r in rows)


@pytest.fixture(scope='module')
def core(tmp_path_factory):
    tmp = tmp_path_factory.mktemp('frames')
    with testing.RosCore(dict(os.environ, ROS_HOME=str(tmp))) as c:
        yield c


def probe(core, params, ns, *frames):
    master = rosgraph.Master('/test_frames', master_uri=core.uri)
    for key in ('/robot1', '/robot2', '/frame_prefix', '/shared_frames'):
        if master.hasParam(key):
            master.deleteParam(key)
    for key, value in params.items():
        master.setParam(key, value)
    p = subprocess.run([sys.executable, PROBE] + list(frames) + ['__ns:=' + ns], env=core.env,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       universal_newlines=True, timeout=60)
    return p.returncode, dict(l.split(' -> ') for l in p.stdout.splitlines() if ' -> ' in l), \
        p.stdout


def test_a_node_finds_its_robots_prefix_in_the_namespace_above_it(core):
    rc, got, out = probe(core, {'/robot1/frame_prefix': 'robot1', '/robot2/frame_prefix': 'robot2'},
                         'robot1', 'odom', 'map', '/world')
    assert rc == 0, out
    assert got == {'odom': 'robot1/odom', 'map': 'map', '/world': 'world'}, out
    # Another robot's namespace is not above it; without a prefix frames stay.
    rc, got, out = probe(core, {'/robot2/frame_prefix': 'robot2'}, 'robot1', 'odom')
    assert (rc, got) == (0, {'odom': 'odom'}), out


def test_a_private_value_wins_and_shared_frames_are_found_alike(core):
    rc, got, out = probe(core, {'/robot1/frame_prefix': 'robot1',
                                '/robot1/frames_probe/frame_prefix': 'other',
                                '/robot1/shared_frames': []}, 'robot1', 'odom', 'map')
    assert rc == 0, out
    assert got == {'odom': 'other/odom', 'map': 'other/map'}, out


def test_a_bad_value_is_refused_naming_the_parameter(core):
    rc, _, out = probe(core, {'/robot1/frame_prefix': 'robot 1'}, 'robot1', 'odom')
    assert rc == 2 and '/robot1/frame_prefix' in out, out
    rc, _, out = probe(core, {'/shared_frames': ['map', ' ']}, 'robot1', 'odom')
    assert rc == 0, out  # an empty item is no frame (as the option tables read lists)
    rc, _, out = probe(core, {'/shared_frames': ['map', 'my map']}, 'robot1', 'odom')
    assert rc == 2 and '/shared_frames' in out, out
