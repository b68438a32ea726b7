"""Navigation among moving obstacles and people.

Mapless: mapless_navigation.launch drives minibot3d 10 m through a
hall where eight obstacles (DynaBARN-style, 0.1-0.5 m/s, scripted: they do not give way) cross its
path (minibot3d_sim/worlds/crowds/random_01.world), by tools/bench/mapless_smoke.sh itself (lock-step
time: a run is the same every time).

With moving_obstacles:=true (move_base's obstacle tracker and the DWA's moving-obstacle critic)
the robot must reach the goal within 3x the optimal time (10 m at max_vel_x 0.5 m/s) and never
touch an obstacle while it moves (the collisions tools/bench/mapless_run.py counts with the robot
at fault); an obstacle that walks into it standing is not its fault. The same run without the
tracker is the control: it drives into one (1 collision with the robot at fault, the robot
reaching the goal in 22.9 s), so the test fails if the feature stops working. With it: reached in
34.1 s, 0 at fault (2 obstacles walked into the standing robot).

On the map: amcl_navigation.launch drives it through minibot3d_sim/worlds/crowds/doorway_01.world,
where the only door (0.9 m) into the goal's half of the hall is shut for 30.5 s by someone standing
in it. With the shipped move_base parameters the robot stands off them, runs the wait recovery and
nothing else, and drives on once they have stepped aside (reached after 44.6 s, 9.8 s closer than
0.45 m to them). The control, wait_duration 0 (move_base's own recovery list), clears its costmaps
and turns on the spot beside them (conservative_reset, rotate_recovery, aggressive_reset; 21.8 s
closer than 0.45 m)."""
import json
import os
import re
import signal
import subprocess

import pytest
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORLDS = os.path.join(ROOT, 'minibot3d_sim', 'worlds', 'crowds')
WORLD = os.path.join(WORLDS, 'random_01.world')
DOORWAY = os.path.join(WORLDS, 'doorway_01.world')
OPTIMAL_S = 10.0 / 0.5
RECOVERY = re.compile(r'recovering: ([a-z_]+)')


def smoke(tmp_path, world, out, launch_args, on_map=False):
    """tools/bench/mapless_smoke.sh on one world: its record and the stack's log."""
    env = dict(os.environ, OUT=str(out), TIMEOUT='120', ROS_HOME=str(tmp_path),
               LAUNCH_ARGS=launch_args, ON_MAP='1' if on_map else '0')
    try:
        p = subprocess.run(['bash', os.path.join(ROOT, 'tools', 'bench', 'mapless_smoke.sh'),
                            world], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, universal_newlines=True, timeout=600,
                           start_new_session=True,
                           preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    except subprocess.TimeoutExpired as e:
        pytest.fail('mapless_smoke.sh did not finish in 600 s wall:\n%s' % (e.output or '')[-3000:])
    name = os.path.basename(world)[:-len('.world')]
    path = out / (name + '.json')
    assert path.exists(), 'no run recorded:\n%s' % p.stdout[-3000:]
    with open(path) as f:
        record = json.load(f)
    with open(out / (name + '.launch.log'), errors='replace') as f:
        return record, p.stdout + f.read()


def run(tmp_path, moving_obstacles):
    return smoke(tmp_path, WORLD, tmp_path / ('on' if moving_obstacles else 'off'),
                 'moving_obstacles:=%s' % ('true' if moving_obstacles else 'false'))


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


def doorway(tmp_path, wait):
    """doorway_01 on its map with the shipped move_base parameters, or with wait_duration 0."""
    args = ''
    if not wait:
        with open(os.path.join(ROOT, 'config', 'move_base_params.yaml')) as f:
            params = yaml.safe_load(f)
        params['wait_duration'] = 0.0
        path = tmp_path / 'move_base_params.yaml'
        path.write_text(yaml.safe_dump(params))
        args = 'move_base_params:=%s' % path
    return smoke(tmp_path, DOORWAY, tmp_path / ('wait' if wait else 'no_wait'), args, on_map=True)


def test_the_robot_waits_at_a_distance_for_someone_in_the_doorway(tmp_path):
    with open(DOORWAY[:-len('.world')] + '.json') as f:
        world = json.load(f)
    stand = world['people'][0]['stand']
    r, log = doorway(tmp_path, True)
    assert r['status'] == 'SUCCEEDED', log[-3000:]
    assert RECOVERY.findall(log) == ['wait'], 'recoveries run: %s' % RECOVERY.findall(log)
    assert 'recovery wait ended: the way opened after' in log
    assert stand < r['sim_s'] <= stand + world['optimal_length'] / 0.5, r['sim_s']
    assert r['person_collisions'] == 0 and r['min_distance'] > 0.2, r['contacts']
    assert r['intimate_s'] < 12.0, 'closer than 0.45 m for %.1f s' % r['intimate_s']


def test_without_the_wait_it_turns_on_the_spot_beside_them(tmp_path):
    r, log = doorway(tmp_path, False)
    assert 'rotate_recovery' in RECOVERY.findall(log), (
        'the control run did not turn beside the person (%s): the scene no longer tests the wait'
        % RECOVERY.findall(log))
    assert r['intimate_s'] > 15.0, r['intimate_s']
