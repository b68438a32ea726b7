"""Every shipped rviz config opens in rviz under a virtual X server (Xvfb) and rviz stays up.

For each .rviz file: a private roscore, `xvfb-run rviz -d CONFIG`; the test waits (bounded) until
rviz has registered with the master and subscribed to the topics its displays name (so the config
was parsed and its displays created), then checks that rviz is still running and printed no
ERROR, and shuts it down. Skipped, saying why, where rviz or xvfb-run is not installed."""
import glob
import os
import re
import shutil
import signal
import socket
import subprocess
import time
import xmlrpc.client

import pytest
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = sorted(f for f in glob.glob(os.path.join(ROOT, '**', '*.rviz'), recursive=True)
                 if '/build/' not in f and '/devel/' not in f)

pytestmark = pytest.mark.skipif(
    shutil.which('rviz') is None or shutil.which('xvfb-run') is None,
    reason='rviz or xvfb-run is not installed (apt-get install rviz xvfb)')


def free_port():
    s = socket.socket()
    s.bind(('127.0.0.1', 0))
    port = s.getsockname()[1]
    s.close()
    return port


def topics_in(config):
    with open(config) as f:
        data = yaml.safe_load(f)
    found = set()

    def walk(node):
        if isinstance(node, dict):
            for k, v in node.items():
                if k == 'Topic' and isinstance(v, str) and v.startswith('/') and \
                        node.get('Enabled', True) and 'Class' in node and \
                        not node['Class'].startswith('rviz/Set'):
                    found.add(v)
                walk(v)
        elif isinstance(node, list):
            for v in node:
                walk(v)
    walk(data.get('Visualization Manager', {}).get('Displays', []))
    return found


def subscriptions(master, caller='/test_rviz'):
    code, _, state = master.getSystemState(caller)
    assert code == 1
    subs = {}
    for topic, nodes in state[1]:
        for n in nodes:
            subs.setdefault(n, set()).add(topic)
    return subs


def test_there_are_rviz_configs():
    assert CONFIGS


@pytest.mark.parametrize('config', CONFIGS, ids=lambda p: os.path.relpath(p, ROOT))
def test_rviz_opens_config(config, tmp_path):
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI='http://127.0.0.1:%d' % port, ROS_IP='127.0.0.1',
               ROS_HOME=str(tmp_path), LIBGL_ALWAYS_SOFTWARE='1',
               GALLIUM_DRIVER='softpipe')  # not llvmpipe: test_rviz_pictures.py says why
    env.pop('ROS_HOSTNAME', None)
    core = subprocess.Popen(['roscore', '-p', str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    rviz = None
    log = tmp_path / 'rviz.log'
    try:
        master = xmlrpc.client.ServerProxy(env['ROS_MASTER_URI'])
        deadline = time.time() + 60
        while True:
            try:
                master.getSystemState('/test_rviz')
                break
            except OSError:
                assert time.time() < deadline, 'roscore did not start'
                time.sleep(0.2)
        with open(log, 'w') as out:
            rviz = subprocess.Popen(['xvfb-run', '-a', '-s', '-screen 0 1280x1024x24', 'rviz',
                                     '-d', config], env=env, stdout=out, stderr=subprocess.STDOUT,
                                    start_new_session=True)
        wanted = topics_in(config)
        deadline = time.time() + 120
        while True:
            assert rviz.poll() is None, 'rviz exited (%s):\n%s' % (rviz.returncode,
                                                                  log.read_text()[-3000:])
            subs = subscriptions(master)
            rviz_topics = set().union(*[t for n, t in subs.items() if n.startswith('/rviz')] or
                                      [set()])
            if wanted <= rviz_topics and any(n.startswith('/rviz') for n in subs):
                break
            assert time.time() < deadline, 'rviz did not subscribe to %s (has %s):\n%s' % (
                sorted(wanted - rviz_topics), sorted(rviz_topics), log.read_text()[-3000:])
            time.sleep(0.5)
        assert rviz.poll() is None, log.read_text()[-3000:]
        errors = [line for line in log.read_text().splitlines()
                  if re.search(r'\bERROR\b', line) and 'Fixed Frame' not in line]
        assert not errors, '\n'.join(errors)
    finally:
        for p in (rviz, core):
            if p is not None and p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
                try:
                    p.wait(20)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait()
