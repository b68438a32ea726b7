"""Every shipped launch file parses, resolves its includes/args/xacro commands, and names nodes
whose packages and executables exist (roslaunch --nodes and roslaunch-check's API)."""
import glob
import os
import subprocess

import pytest
from roslaunch.rlutil import check_roslaunch

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAUNCH_FILES = sorted(glob.glob(os.path.join(ROOT, '**', '*.launch'), recursive=True))
LAUNCH_FILES = [f for f in LAUNCH_FILES if '/build/' not in f and '/devel/' not in f]

# rviz is only started when asked: check both ways where the file has that argument.
HEADLESS = ['rviz:=false']


def test_there_are_launch_files():
    assert LAUNCH_FILES, 'no launch files found under %s' % ROOT


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=lambda p: os.path.relpath(p, ROOT))
def test_launch_file_loads(path):
    out = subprocess.run(['roslaunch', '--nodes', path], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, 'roslaunch --nodes %s failed:\n%s%s' % (path, out.stdout,
                                                                         out.stderr)


@pytest.mark.parametrize('path', LAUNCH_FILES, ids=lambda p: os.path.relpath(p, ROOT))
def test_launch_file_nodes_exist(path):
    error = check_roslaunch(path)
    assert error is None, 'roslaunch-check %s: %s' % (path, error)
