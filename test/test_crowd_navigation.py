"""Navigation among moving obstacles, by tools/bench/mapless_smoke.sh itself on lock-step time (a
run is the same every time), mapless_navigation.launch driving minibot3d 10 m:
- through a hall where eight obstacles (DynaBARN-style, 0.1-0.5 m/s, scripted: they do not give
  way) cross its path (minibot3d_sim/worlds/crowds/random_01.world);
- down a corridor 2 m wide against three people walking head-on at 0.8-1.2 m/s (social force:
  they give way to the robot only as much as to each other; corridor_01.world).

With moving_obstacles:=true (move_base's obstacle tracker and the DWA's moving-obstacle critic)
the robot must reach the goal within 3x the optimal time (10 m at max_vel_x 0.5 m/s) and never
touch anyone while it moves (the collisions tools/bench/mapless_run.py counts with the robot at
fault); someone who walks into it standing is not its fault. In the corridor it must also step
out of the people's way early enough that nobody touches it at all. The same runs without the
tracker are the control: they drive into someone, so the test fails if the feature stops working.
Measured: random_01 reached in 49.8 s with tracking, 0 at fault (1 obstacle walked into the
standing robot), and without it 1 at fault; corridor_01 reached in 49.3 s with no contact (closest
0.21 m), and without tracking 1 at fault."""
import json
import os
import signal
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CROWDS = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'crowds')
OPTIMAL_S = 10.0 / 0.5


def run(tmp_path, moving_obstacles, name='random_01'):
    out = tmp_path / ('on' if moving_obstacles else 'off')
    env = dict(os.environ, OUT=str(out), TIMEOUT='120', ROS_HOME=str(tmp_path),
               LAUNCH_ARGS='moving_obstacles:=%s' % ('true' if moving_obstacles else 'false'))
    try:
        p = subprocess.run(['bash', os.path.join(ROOT, 'tools', 'bench', 'mapless_smoke.sh'),
                            os.path.join(CROWDS, name + '.world')], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True, timeout=600,
                           start_new_session=True,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    except subprocess.TimeoutExpired as e:
        pytest.fail('mapless_smoke.sh did not finish in 600 s wall:\n%s' % (e.output or '')[-3000:])
    path = out / (name + '.json')
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


def test_in_a_corridor_the_robot_steps_out_of_the_way_of_people_walking_at_it(tmp_path):
    r, log = run(tmp_path, True, 'corridor_01')
    assert r['status'] == 'SUCCEEDED', log
    assert r['sim_s'] <= 3.0 * OPTIMAL_S, 'reached after %.1f s of sim time' % r['sim_s']
    assert r['person_collisions'] == 0, 'contacts (sim s, actor, robot moving): %s' % (
        r['contacts'],)


def test_in_a_corridor_without_the_tracker_it_walks_into_people(tmp_path):
    r, log = run(tmp_path, False, 'corridor_01')
    assert r['at_fault_collisions'] >= 1, (
        'the control run touched nobody while moving: the scene no longer tests the tracker '
        '(%s)' % log[-2000:])
