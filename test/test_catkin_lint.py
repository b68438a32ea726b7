"""catkin_lint (Debian's catkin-lint, installed by make setup) finds no error or warning in any
package of the workspace: `catkin_lint -W1 .` from the repository root prints nothing.

Without a rosdep database catkin_lint ignores system dependencies it cannot resolve; --offline
keeps it from trying to download one, so the result does not depend on the network."""
import os
import shutil
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def catkin_lint():
    # Debian's first: a pip-installed catkin_lint under /usr/local/bin may be another version.
    if os.access('/usr/bin/catkin_lint', os.X_OK):
        return '/usr/bin/catkin_lint'
    return shutil.which('catkin_lint')


def test_catkin_lint_reports_nothing():
    exe = catkin_lint()
    if exe is None:
        pytest.skip('catkin_lint is not installed (Debian package catkin-lint; make setup installs '
                    'it)')
    env = dict(os.environ, PATH='/usr/bin:/bin:' + os.environ.get('PATH', ''))
    out = subprocess.run([exe, '-W1', '--quiet', '--offline', '--text', '--color', 'never', '.'],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    problems = [line for line in out.stdout.splitlines() if line.strip()]
    assert out.returncode == 0 and not problems, \
        'catkin_lint -W1 . (exit %d) reports:\n%s\n%s' % (out.returncode, out.stdout, out.stderr)
