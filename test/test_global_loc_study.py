"""tools/bench/global_loc_study.py's kidnapping draw: a pose far enough away when the map has one,
the farthest of its draws when it has none (a small map), and never an endless draw (the study is
a lock-step participant that must answer every tick)."""
import itertools
import math
import os
import random
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, 'tools', 'bench'))
from global_loc_study import far_poses  # noqa: E402


def square(side, rng):
    """Endless random poses in a side x side square centred on the origin."""
    while True:
        yield (rng.uniform(-side / 2, side / 2), rng.uniform(-side / 2, side / 2),
               rng.uniform(-math.pi, math.pi))


def test_far_enough_when_the_map_has_room():
    poses = square(20.0, random.Random(1))
    for p in itertools.islice(far_poses(poses, (0.0, 0.0), 5.0), 20):
        assert math.hypot(p[0], p[1]) >= 5.0


def test_farthest_draw_when_nothing_is_far_enough():
    # A 6 m square: nothing is 5 m from its centre (the corners are 4.24 m away).
    rng = random.Random(2)
    draws = [next(square(6.0, rng)) for _ in range(100)]
    got = next(far_poses(iter(draws), (0.0, 0.0), 5.0, tries=100))
    assert got == max(draws, key=lambda p: math.hypot(p[0], p[1]))


def test_same_draws_same_poses():
    a = list(itertools.islice(far_poses(square(8.0, random.Random(3)), (1.0, 1.0), 5.0), 10))
    b = list(itertools.islice(far_poses(square(8.0, random.Random(3)), (1.0, 1.0), 5.0), 10))
    assert a == b
