"""Every shipped rviz config opens in rviz under a virtual X server (Xvfb) and rviz stays up.

For each .rviz file: a ROS master of the test's own, `xvfb-run rviz -d CONFIG`; the test waits (bounded) until
rviz has registered with the master and subscribed to the topics its displays name (so the config
was parsed and its displays created), then checks that rviz is still running and printed no
ERROR, and shuts it down. Skipped, saying why, where rviz or xvfb-run is not installed."""
import glob
import os
import re
import shutil
import xmlrpc.client

import pytest
import yaml
from minibot3d_testing import RosCore, wait_until

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIGS = sorted(f for f in glob.glob(os.path.join(ROOT, '**', '*.rviz'), recursive=True)
                 if '/build/' not in f and '/devel/' not in f)

pytestmark = pytest.mark.skipif(
    shutil.which('rviz') is None or shutil.which('xvfb-run') is None,
    reason='rviz or xvfb-run is not installed (apt-get install rviz xvfb)')


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
    env = dict(os.environ, ROS_HOME=str(tmp_path), LIBGL_ALWAYS_SOFTWARE='1',
               GALLIUM_DRIVER='softpipe')  # not llvmpipe: test_rviz_pictures.py says why
    log = tmp_path / 'rviz.log'
    with RosCore(env) as core:
        master = xmlrpc.client.ServerProxy(core.uri)
        rviz = core.start_process(['xvfb-run', '-a', '-s', '-screen 0 1280x1024x24', 'rviz',
                                   '-d', config], log)
        try:
            wanted, seen = topics_in(config), set()

            def subscribed():
                assert rviz.running(), 'rviz exited (%s):\n%s' % (rviz.proc.returncode,
                                                                   rviz.log(3000))
                topic_sets = [t for n, t in subscriptions(master).items() if n.startswith('/rviz')]
                seen.clear()
                seen.update(*topic_sets)
                return topic_sets and wanted <= seen
            wait_until(subscribed, 120, lambda: 'rviz to subscribe to %s (has %s):\n%s' % (
                sorted(wanted - seen), sorted(seen), rviz.log(3000)), interval=0.5)
            assert rviz.running(), rviz.log(3000)
            errors = [line for line in rviz.log().splitlines()
                      if re.search(r'\bERROR\b', line) and 'Fixed Frame' not in line]
            assert not errors, '\n'.join(errors)
        finally:
            rviz.stop()
