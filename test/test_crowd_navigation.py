"""Navigation among moving obstacles: mapless_navigation.launch drives minibot3d 10 m through a
hall where eight obstacles (DynaBARN-style, 0.1-0.5 m/s, scripted: they do not give way) cross its
path (minibot3d_sim/worlds/crowds/random_01.world), by tools/bench/mapless_smoke.sh itself (lock-step
time: a run is the same every time).

With moving_obstacles:=true (move_base's obstacle tracker and the DWA's moving-obstacle critic)
the robot must reach the goal within 3x the optimal time (10 m at max_vel_x 0.5 m/s) and never
touch an obstacle while it moves (the collisions tools/bench/mapless_run.py counts with the robot
at fault); an obstacle that walks into it standing is not its fault. The same run without the
tracker is the control: it drives into one (1 collision with the robot at fault, the robot
reaching the goal in 22.9 s), so the test fails if the feature stops working. With it: reached in
34.1 s, 0 at fault (2 obstacles walked into the standing robot)."""
import json
import os
import signal
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORLD = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'crowds', 'random_01.world')
OPTIMAL_S = 10.0 / 0.5


def run(tmp_path, moving_obstacles):
    out = tmp_path / ('on' if moving_obstacles else 'off')
    env = dict(os.environ, OUT=str(out), TIMEOUT='120', ROS_HOME=str(tmp_path),
               LAUNCH_ARGS='moving_obstacles:=%s' % ('true' if moving_obstacles else 'false'))
    try:
        p = subprocess.run(['bash', os.path.join(ROOT, 'tools', 'bench', 'mapless_smoke.sh'),
                            WORLD], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True, timeout=600,
                           start_new_session=True,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    except subprocess.TimeoutExpired as e:
        pytest.fail('mapless_smoke.sh did not finish in 600 s wall:\n%s' % (e.output or '')[-3000:])
    path = out / 'random_01.json'
    assert path.exists(), 'no run recorded:\n%s' % p.stdout[-3000:]
    with open(path) as f:
        return json.load(f), p.stdout


def test_the_robot_never_drives_into_a_moving_obstacle(tmp_path):
    r, log = run(tmp_path, True)
    assert r['status'] == 'SUCCEEDED', log
    assert r['sim_s'] <= 3.0 * OPTIMAL_S, 'reached after %.1f s of sim time' % r['sim_s']
    assert r['at_fault_collisions'] == 0, 'contacts (sim s, actor, robot moving): %s' % (
        r['contacts'],)


def test_without_the_tracker_it_does(tmp_path):
    r, log = run(tmp_path, False)
    assert r['at_fault_collisions'] >= 1, (
        'the control run touched nobody while moving: the scene no longer tests the tracker '
        '(%s)' % log[-2000:])
