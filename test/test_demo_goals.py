"""tools/demo_goals.py on small hand-drawn maps: a room behind a door the robot (minibot3d's
0.24 m x 0.23 m footprint, config/) drives through gets a goal, one behind a gap it does not fit
through gets none, and a map with nowhere to go is a named error.

Catches: goals kept 0.4 m from walls all the way from the start (the sampler before path
distance) never put one behind the 0.40 m door; the test asserts a goal there."""
import math
import os
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools'))
import demo_goals  # noqa: E402
from minibot3d_map_io import OccupancyGrid, save_map  # noqa: E402

RES = 0.05
# Exploration started at SPAWN (world frame) in the first room: the saved map's frame is the world
# frame moved there, so its origin is at -SPAWN; the goals come back in the world frame.
SPAWN = (1.5, 1.7, 0.0)
SPAWN_ORIGIN = (-1.5, -1.7)


def write_map(tmp_path, occupied, origin=(0.0, 0.0), name='m'):
    """A map_server map (minibot3d_map_io.save_map) whose cell (row 0 = lowest y) is occupied
    where `occupied`, free elsewhere; `origin` is its lower left corner."""
    save_map(OccupancyGrid(np.where(occupied, 100, 0), RES, origin), str(tmp_path / name))
    return str(tmp_path / (name + '.yaml'))


def two_rooms(door):
    """Two 3 m x 3 m rooms side by side (x 0-3 and 3.1-6.1 m, walls 0.1 m), the wall between them
    with a door `door` m wide in its middle."""
    w, h = int(round(6.4 / RES)), int(round(3.4 / RES))
    occ = np.zeros((h, w), dtype=bool)
    occ[:2, :] = occ[-2:, :] = True
    occ[:, :2] = occ[:, -2:] = True
    wall = int(round(3.1 / RES))
    occ[:, wall:wall + 2] = True
    lo = int(round((1.7 - door / 2) / RES))
    occ[lo:lo + int(round(door / RES)), wall:wall + 2] = False
    return occ


def in_second_room(goals):
    return [g for g in goals if g[0] > 3.3]


@pytest.mark.parametrize('door', [0.40, 0.90])
def test_a_room_behind_a_door_the_robot_passes_gets_a_goal(tmp_path, door):
    goals = demo_goals.sample_goals(write_map(tmp_path, two_rooms(door), SPAWN_ORIGIN), SPAWN)
    assert len(goals) == 4
    behind = in_second_room([(g[0], g[1]) for g in goals])
    assert behind, 'no goal in the room behind the %.2f m door: %s' % (door, goals)
    for x, y, yaw in goals:
        assert 0.4 <= x <= 6.0 and 0.4 <= y <= 3.0, (x, y)
        assert -math.pi <= yaw <= math.pi


def test_goals_are_visited_nearest_first_and_the_same_every_time(tmp_path):
    path = write_map(tmp_path, two_rooms(0.40), SPAWN_ORIGIN)
    goals = demo_goals.sample_goals(path, SPAWN)
    assert goals == demo_goals.sample_goals(path, SPAWN)
    # The first room's goals come before the door, the second room's after.
    rooms = [g[0] > 3.3 for g in goals]
    assert rooms == sorted(rooms), goals


def test_a_room_behind_a_gap_the_robot_does_not_fit_gets_no_goal(tmp_path):
    path = write_map(tmp_path, two_rooms(0.20), SPAWN_ORIGIN)
    goals = demo_goals.sample_goals(path, SPAWN)
    assert goals and not in_second_room(goals), goals


def test_a_larger_footprint_does_not_pass_the_narrow_door(tmp_path):
    path = write_map(tmp_path, two_rooms(0.40), SPAWN_ORIGIN)
    config = tmp_path / 'config'
    config.mkdir()
    (config / 'costmap_common_params.yaml').write_text('robot_radius: 0.25\n')
    goals = demo_goals.sample_goals(path, SPAWN, str(config))
    assert goals and not in_second_room(goals), goals


def test_nowhere_to_go_is_a_named_error(tmp_path):
    occ = np.ones((40, 40), dtype=bool)
    path = write_map(tmp_path, occ)
    with pytest.raises(demo_goals.GoalError, match='m.yaml: no free cell'):
        demo_goals.sample_goals(path, (0.0, 0.0, 0.0))
    assert demo_goals.main([path]) == 1
