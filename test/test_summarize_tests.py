"""tools/summarize_tests.py counts each test case once: a rostest's run (rostest-*.xml, one case
that passes whenever its test node wrote results) is not counted beside the test node's own cases
(rosunit-*.xml), but stands for them when the run failed and they are missing.
Catches: the rostest run's case counted as well (3 more passed here), or dropped when it failed."""
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SUMMARIZE = os.path.join(ROOT, 'tools', 'summarize_tests.py')

# The shapes catkin's run_tests writes: gtest, rostest (the run, then the test node's cases), pytest.
GTEST = """<?xml version="1.0" encoding="UTF-8"?>
<testsuites tests="3" failures="0" disabled="0" errors="0" name="AllTests">
  <testsuite name="GridTest" tests="3" failures="0" disabled="0" skipped="1" errors="0">
    <testcase name="RayTraces" status="run" result="completed" classname="GridTest" />
    <testcase name="Grows" status="run" result="completed" classname="GridTest" />
    <testcase name="IntelLog" status="run" result="skipped" classname="GridTest">
      <skipped message="Intel log absent"/>
    </testcase>
  </testsuite>
</testsuites>
"""


def rostest_run(name, error=None):
    body = ('<error type="" message="%s"/>' % error) if error else ''
    return ('<?xml version="1.0" encoding="utf-8"?>\n'
            '<testsuite errors="%d" failures="0" name="unittest.suite.TestSuite" tests="1">'
            '<testcase classname="rostest.runner.RosTest" name="test%s">%s</testcase>'
            '<system-out>[ROSTEST]...</system-out></testsuite>\n' % (bool(error), name, body))


def rosunit(cls, passed, failed=()):
    cases = ''.join('<testcase classname="__main__.%s" name="%s" time="1.0" />' % (cls, n)
                    for n in passed)
    cases += ''.join('<testcase classname="__main__.%s" name="%s" time="1.0"><failure type="'
                     'AssertionError" message="%s">Traceback...</failure></testcase>'
                     % (cls, n, why) for n, why in failed)
    return ('<?xml version="1.0" encoding="utf-8"?>\n<testsuite errors="0" failures="%d" '
            'name="unittest.suite.TestSuite" tests="%d">%s</testsuite>\n'
            % (len(failed), len(passed) + len(failed), cases))


PYTEST = """<?xml version="1.0" encoding="utf-8"?><testsuites><testsuite name="pytest" errors="0"
failures="0" skipped="1" tests="2"><testcase classname="test.test_a" name="test_one" time="0.1" />
<testcase classname="test.test_a" name="test_two" time="0.0"><skipped type="pytest.skip"
message="PostgreSQL is not installed">skipped</skipped></testcase></testsuite></testsuites>
"""


def summarize(tmp_path, files):
    for rel, text in files.items():
        path = tmp_path / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    done = subprocess.run([sys.executable, SUMMARIZE, str(tmp_path)], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True, timeout=60)
    return done.returncode, done.stdout


def test_each_case_once_when_everything_passes(tmp_path):
    rc, out = summarize(tmp_path, {
        'pkg/gtest-grid_test.xml': GTEST,
        'pkg/rostest-test_move_base_sim.xml': rostest_run('move_base_sim'),
        'pkg/rosunit-move_base_sim.xml': rosunit('MoveBaseSim', ['test_1', 'test_2', 'test_3']),
        'pkg/rostest-test_tight_spaces.xml': rostest_run('tight_spaces'),
        'pkg/rosunit-tight_spaces.xml': rosunit('TightSpaces', ['test_goals']),
        'pkg/rostest-test_sim_topics.xml': rostest_run('sim_topics'),
        'pkg/rosunit-sim_topics.xml': rosunit('SimTopics', ['test_scan', 'test_odom']),
        'pytest/pytest.xml': PYTEST})
    # gtest 2 + 1 skipped, rostests 3 + 1 + 2, pytest 1 + 1 skipped.
    assert out.splitlines()[-1] == '9 passed, 0 failed, 2 skipped', out
    assert rc == 0, out


def test_a_failed_case_inside_a_rostest_counts_once_and_a_failed_run_stands_for_its_cases(
        tmp_path):
    rc, out = summarize(tmp_path, {
        'pkg/rostest-test_move_base_sim.xml': rostest_run('move_base_sim'),
        'pkg/rosunit-move_base_sim.xml': rosunit(
            'MoveBaseSim', ['test_1'], [('test_6_no_collisions', '2 != 0')]),
        # Over its time limit: no rosunit file, the run's case says why.
        'pkg/rostest-test_tight_spaces.xml': rostest_run(
            'tight_spaces', 'max time [900.0s] allotted for test [tight_spaces] of type ...')})
    assert out.splitlines()[-1] == '1 passed, 2 failed, 0 skipped', out
    assert 'FAILED __main__.MoveBaseSim.test_6_no_collisions' in out, out
    assert 'FAILED rostest.runner.RosTest.testtight_spaces' in out, out
    assert 'max time [900.0s]' in out, out
    assert rc == 1, out


def test_nothing_ran_is_a_failure(tmp_path):
    rc, out = summarize(tmp_path, {
        'pkg/rostest-test_sim_topics.xml': rostest_run('sim_topics')})
    assert out.splitlines()[-1] == '0 passed, 0 failed, 0 skipped', out
    assert rc == 1, out
