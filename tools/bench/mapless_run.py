#!/usr/bin/env python3
"""One mapless run (tools/bench/mapless_smoke.sh starts mapless_navigation.launch; this drives and
records it): sends the clutter world's goal in odom with simple_navi_goals.py, records the true
path and the simulator's collision count, prints one summary line and writes OUT.json (the world,
the result, sim time, collisions and the path driven, for tools/bench/mapless_bench.py's picture).

  mapless_run.py WORLD_JSON OUT_JSON [--timeout SIM_S]

Under lock-step time this script is a participant, so the run (and the path) is the same at any
real-time factor and machine load."""
import argparse
import json
import math
import os
import re
import subprocess
import sys

from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages

import rospy

# tools/, one up: make demo's scripts
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from demo_phase import Recorder, write_json  # noqa: E402  (make demo's recorder of the truth)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('world_json')
    parser.add_argument('out_json')
    parser.add_argument('--timeout', type=float, default=150.0, help='sim seconds for the goal')
    args = parser.parse_args(rospy.myargv()[1:])
    with open(args.world_json) as f:
        world = json.load(f)
    rospy.init_node('mapless_run')
    lockstep = Participant(wake_on_participants=True)
    lockstep.add_periodic(0.05, lambda now: None)
    rec = Recorder()
    if not lockstep.wait_for(lambda: rec.truth is not None, 60.0):
        print('%s: no /ground_truth/odom within 60 s of sim time' % world['name'], flush=True)
        return 1
    goal = world['goal']
    finished, proc = lockstep.run(
        '/simple_navi_goals',
        ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'odom',
         str(goal['x']), str(goal['y']), str(goal['yaw']), '--timeout', str(args.timeout)],
        args.timeout + 60.0, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
        universal_newlines=True)
    if not finished:
        proc.send_signal(2)
    stdout, _ = proc.communicate(timeout=60)
    m = re.findall(r'Result: (\w+) \((.*)\) after ([0-9.]+) s', stdout)
    path = rec.take_path()  # (x, y, yaw) every 2 cm, world frame
    with rec.lock:
        collisions = rec.collisions
    if m:
        status, text, sim_s = m[-1][0], m[-1][1], float(m[-1][2])
    else:
        lines = [l for l in stdout.splitlines() if 'ERROR' in l or 'not reached' in l]
        status, text, sim_s = 'NONE', (lines[-1] if lines else 'no result'), None
    end = path[-1]
    write_json(args.out_json, dict(
        world=world['name'], gap=world['achieved_gap'], status=status, message=text, sim_s=sim_s,
        exit=proc.returncode, collisions=collisions, goal_error=math.hypot(
            end[0] - goal['x'], end[1] - goal['y']), path=[p[:2] for p in path]))
    print('%s gap %.3f m: %s%s, exit %d, collisions %d, true end (%.2f, %.2f)' % (
        world['name'], world['achieved_gap'], status,
        ' after %.2f s' % sim_s if sim_s is not None else ' (%s)' % text, proc.returncode,
        collisions, end[0], end[1]), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
