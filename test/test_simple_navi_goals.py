"""simple_navi_goals.py without a ROS master: its arguments (bad ones exit 2 naming the option) and
what it says is missing for a confident amcl fix (--wait-for-fix; the closed loop is in
minibot3d_navigation's move_base_sim.test)."""
import importlib.util
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, 'minibot3d_navigation', 'scripts', 'simple_navi_goals.py')


def load():
    spec = importlib.util.spec_from_file_location('simple_navi_goals', SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize('argv, message', [
    (['--frame', 'map', '1', '2', '0', '--spin-for-fix', '0.5'], '--wait-for-fix'),
    (['--frame', 'map', '1', '2', '0', '--global-localization'], '--wait-for-fix'),
    (['--frame', 'map', '1', '2', '0', '--wait-for-fix', '-1'], '--wait-for-fix'),
    (['--frame', 'map', '1', '2', '0', '--wait-for-fix', '9', '--fix-covariance', '0'],
     '--fix-covariance'),
    (['--frame', 'map', '1', '2', '0', '--wait-for-fix', '9', '--spin-for-fix', '5'],
     '--spin-for-fix'),
    (['--frame', 'map', '1', '2', '0', '--wander-for-fix', '0.2'], '--wait-for-fix'),
    (['--frame', 'map', '1', '2', '0', '--wait-for-fix', '9', '--wander-for-fix', '3'],
     '--wander-for-fix must be a speed'),
    (['--frame', 'map', '1', '2', '0', '--wait-for-fix', '9', '--wander-for-fix', '0.2',
      '--spin-for-fix', '0.5'], 'choose one'),
])
def test_bad_fix_options_exit_2_naming_the_option(argv, message):
    p = subprocess.run(['/usr/bin/python3', SCRIPT] + argv, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, universal_newlines=True, timeout=60)
    assert p.returncode == 2, p.stdout
    assert message in p.stdout, p.stdout


def test_fix_problems_names_what_is_missing():
    m = load()
    assert m.fix_problems(None, None, 0.05) == [
        'no amcl_pose or amcl/confidence received since the wait began']
    assert m.fix_problems(0.01, None, 0.05) == ['no amcl/confidence received since the wait began']
    # Confident, small covariance: a fix.
    assert m.fix_problems(0.01, [0.95, 1, 1, 15, 60], 0.05) == []
    # Not confident (two modes), large covariance: both said, with amcl's reasons.
    problems = m.fix_problems(2.0, [0.6, 2, 0, 3, 60], 0.05)
    assert problems[0] == ('amcl not confident (explained fraction 0.60 of 60 beams, 2 modes, '
                           '3 evidence updates)'), problems
    assert problems[1] == 'covariance cov_xx+cov_yy 2 m^2 >= 0.05', problems
    # Confident but the covariance not yet under the threshold.
    assert m.fix_problems(0.07, [0.9, 1, 1, 20, 60], 0.05) == [
        'covariance cov_xx+cov_yy 0.07 m^2 >= 0.05']
