"""map_saver and map_server on the command line: map_saver gives up with exit 1 and a clear
message when nothing publishes a map, refuses bad arguments with exit 2 and its usage, and
map_server refuses a bad map YAML with exit 1 and the loader's message.

Each case runs the real node through rosrun against a ROS master of the test's own."""
import subprocess
import time

import pytest
from minibot3d_testing import RosCore


@pytest.fixture(scope='module')
def master():
    with RosCore(rosout=False) as core:
        yield core.env


def rosrun(env, node, *args, timeout=60):
    out = subprocess.run(['rosrun', 'minibot3d_slam', node] + list(args), env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, timeout=timeout)
    return out.returncode, out.stdout


def test_map_saver_times_out_without_a_map(master, tmp_path):
    start = time.monotonic()
    rc, text = rosrun(master, 'map_saver', '-f', str(tmp_path / 'never'), '--timeout', '2')
    elapsed = time.monotonic() - start
    assert rc == 1, 'exit %d (expected 1):\n%s' % (rc, text)
    assert 'no map received on /map within 2 s — is slam_gmapping running?' in text, text
    assert 1.5 <= elapsed < 20, 'gave up after %.1f s' % elapsed
    assert list(tmp_path.iterdir()) == [], 'wrote files without a map'


def test_map_saver_names_a_remapped_topic(master, tmp_path):
    rc, text = rosrun(master, 'map_saver', '-f', str(tmp_path / 'never'), '--timeout', '1',
                      'map:=/slam/map')
    assert rc == 1, text
    assert 'no map received on /slam/map within 1 s' in text, text


@pytest.mark.parametrize('args, needle', [
    (['--bogus'], "unknown argument '--bogus'"),
    (['-f'], '-f needs a value'),
    (['--occ', '0'], '--occ must be an integer in 1..100'),
    (['--occ', '65x'], '--occ must be an integer in 1..100'),
    (['--free', '70'], '--free (70) must be below --occ (65)'),
    (['--occ', '50', '--free', '50'], '--free (50) must be below --occ (50)'),
    (['--timeout', '-1'], '--timeout must be a positive number'),
    (['--timeout', 'soon'], '--timeout must be a positive number'),
    (['extra_positional'], "unknown argument 'extra_positional'"),
])
def test_map_saver_bad_arguments(master, args, needle):
    rc, text = rosrun(master, 'map_saver', *args)
    assert rc == 2, 'exit %d (expected 2) for %s:\n%s' % (rc, args, text)
    assert needle in text, text
    assert 'Usage: map_saver' in text, text


def test_map_saver_help(master):
    rc, text = rosrun(master, 'map_saver', '-h')
    assert rc == 0, text
    assert 'Usage: map_saver' in text and '--timeout' in text, text


def test_map_server_bad_yaml(master, tmp_path):
    yaml_path = tmp_path / 'broken.yaml'
    yaml_path.write_text('image: broken.pgm\nresolution: -0.05\norigin: [0, 0, 0]\nnegate: 0\n'
                         'occupied_thresh: 0.65\nfree_thresh: 0.196\n')
    rc, text = rosrun(master, 'map_server', str(yaml_path), timeout=30)
    assert rc == 1, 'exit %d (expected 1):\n%s' % (rc, text)
    assert str(yaml_path) in text and "'resolution' must be positive" in text, text

    rc, text = rosrun(master, 'map_server', str(tmp_path / 'absent.yaml'), timeout=30)
    assert rc == 1, text
    assert str(tmp_path / 'absent.yaml') in text and 'cannot be opened' in text, text

    rc, text = rosrun(master, 'map_server', timeout=30)
    assert rc == 2 and 'Usage: map_server' in text, text
