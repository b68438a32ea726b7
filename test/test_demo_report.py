"""tools/demo_report.py's figures worked out by hand: the driven path's length, each goal's time
against that length at max_vel_x, which of the saved map's walls lie near a true one, and where the
reachable area the map does not know lies."""
import math
import os
import sys

import numpy as np

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


def write_set(d, **files):
    for name, text in files.items():
        (d / (name + '.yaml')).write_text(text)
    return str(d)


def test_max_vel_x_comes_from_the_config_sets_local_planner(tmp_path):
    assert demo_report.max_vel_x_of(os.path.join(ROOT, 'config')) == 0.5
    d = write_set(tmp_path, trajectory_planner='TrajectoryPlannerROS: {max_vel_x: 0.7}\n'
                  'DWAPlannerROS: {max_vel_x: 0.4}\n', move_base_params='controller_frequency: 10\n')
    assert demo_report.max_vel_x_of(d) == 0.7
    write_set(tmp_path, move_base_params='base_local_planner: dwa_local_planner/DWAPlannerROS\n')
    assert demo_report.max_vel_x_of(d) == 0.4
    write_set(tmp_path, trajectory_planner='TrajectoryPlannerROS: {min_vel_x: 0.1}\n',
              move_base_params='{}\n')
    assert demo_report.max_vel_x_of(d) is None


def test_reach_clearance_is_the_robots_inscribed_radius_when_larger(tmp_path):
    # minibot3d: 0.24 m x 0.23 m, padding 0.01: inscribed 0.125 m, so the 0.15 m floor holds.
    assert abs(demo_report.inscribed_radius(os.path.join(ROOT, 'config')) - 0.125) < 1e-12
    assert demo_report.reach_clearance(os.path.join(ROOT, 'config')) == 0.15
    d = write_set(tmp_path, costmap_common_params=(
        'footprint: "[[-0.2, -0.25], [-0.2, 0.25], [0.35, 0.25], [0.35, -0.25]]"\n'
        'footprint_padding: 0.02\n'))
    assert abs(demo_report.reach_clearance(d) - 0.22) < 1e-12
    write_set(tmp_path, costmap_common_params='robot_radius: 0.3\n')
    assert demo_report.reach_clearance(d) == 0.3


def test_wall_errors_moves_the_slam_map_into_the_world_frame_and_marks_walls_off_by_more_than_the_tolerance():
    # The true world: one wall along x = 2.0-2.1 m (column 20 of a 0.1 m grid at the origin).
    gocc = np.zeros((40, 40), dtype=bool)
    gocc[:, 20] = True
    # The SLAM map frame is the world moved to the spawn pose (1, 0, 90 deg): the map's -y axis
    # points along the world's x. Two occupied cells in column 5 (map x = 0.5 m): row 9 (map
    # y = -1.05 m, world (2.05, 0.5): on the wall) and row 5 (map y = -1.45 m, world (2.45, 0.5):
    # 0.35 m beside it).
    occ = np.zeros((30, 10), dtype=bool)
    occ[9, 5] = True
    occ[5, 5] = True
    walls, right = demo_report.wall_errors(occ, 0.1, (-0.05, -2.0), gocc, 0.1, (0.0, 0.0),
                                           (1.0, 0.0, math.pi / 2))
    order = np.argsort(walls[:, 0])
    assert np.allclose(walls[order], [[2.05, 0.5], [2.45, 0.5]])
    assert right[order].tolist() == [True, False]


def test_the_reachable_cells_the_map_does_not_know_are_grouped_into_patches_in_the_world_frame():
    # The true world: 4 m x 4 m of 0.1 m cells, all reachable but row 39 (3.9-4.0 m).
    reach = np.ones((40, 40), dtype=bool)
    reach[39, :] = False
    # The SLAM map frame is the world moved to the spawn pose (1, 0, 90 deg): world (x, y) is map
    # (y, 1 - x). The map knows everything but three holes:
    known = np.ones((100, 100), dtype=bool)   # 0.1 m cells, origin (-5, -5)
    known[40:42, 50:53] = False   # map x 0.0-0.3, y -1.0..-0.8: world x 1.8-2.0, y 0.0-0.3
    known[55, 80] = False         # map (3.0-3.1, 0.5-0.6): world x 0.4-0.5, y 3.0-3.1
    known[45, 89] = False         # world y 3.9-4.0: not reachable, so not missed
    mapped = demo_report.known_in_world(reach, 0.1, (0.0, 0.0), known, 0.1, (-5.0, -5.0),
                                        (1.0, 0.0, math.pi / 2))
    assert (reach & ~mapped).sum() == 7
    patches = demo_report.unmapped_patches(reach & ~mapped, 0.1, (0.0, 0.0))
    assert len(patches) == 2
    assert np.allclose(patches[0], (0.06, 1.9, 0.15)) and np.allclose(patches[1], (0.01, 0.45, 3.05))
    # The row names the total and the three largest patches.
    assert demo_report.describe_patches(
        [(0.43, 3.21, -3.62), (0.19, 4.7, -3.7), (0.05, -4.5, -3.7), (0.01, 0.0, 0.0)]) == \
        '0.68 m^2 in 4 patches, the largest 0.43 m^2 at (3.2, -3.6), 0.19 m^2 at (4.7, -3.7), ' \
        '0.05 m^2 at (-4.5, -3.7)'
    assert demo_report.describe_patches([(0.01, 0.47, 3.02)]) == '0.01 m^2 in 1 patch at (0.5, 3.0)'
    assert demo_report.describe_patches([]) == 'nothing'
