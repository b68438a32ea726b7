"""tools/demo_report.py's figures worked out by hand: the driven path's length and each goal's time
against that length at max_vel_x."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools'))
import demo_report  # noqa: E402


def test_path_length_sums_the_segments():
    assert demo_report.path_length([]) == 0.0
    assert demo_report.path_length([(1.0, 2.0, 0.3)]) == 0.0
    # 3-4-5 then 1 m back along x; the third value (yaw) is not a coordinate.
    assert abs(demo_report.path_length([(0, 0, 0.0), (3, 4, 1.0), (2, 4, 2.0)]) - 6.0) < 1e-12


def test_time_against_path_per_goal_and_mean():
    goals = [dict(ok=True, sim_s=10.0, path=[(0, 0, 0), (2, 0, 0)]),     # 2 m at 0.5 m/s: 4 s
             dict(ok=False, sim_s=30.0, path=[(0, 0, 0), (1, 0, 0)]),    # not reached: no ratio
             dict(ok=True, sim_s=3.0, path=[(0, 0, 0), (0, 1.5, 0)])]    # 1.5 m: 3 s
    text = demo_report.time_against_path(goals, 0.5)
    assert text == '2.50, -, 1.00; mean 1.75 (driven path, max_vel_x 0.50 m/s)', text


def test_time_against_path_without_the_speed_limit_says_so():
    goals = [dict(ok=True, sim_s=10.0, path=[(0, 0, 0), (2, 0, 0)])]
    assert demo_report.time_against_path(goals, None).startswith('n/a')
