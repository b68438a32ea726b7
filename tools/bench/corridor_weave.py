#!/usr/bin/env python3
"""Weaving on a long straight drive (tools/bench/corridor_weave.sh starts the stack; this drives and
measures it): sends a goal down a straight corridor along +x with simple_navi_goals.py, records
every /cmd_vel and every /ground_truth/odom message, and prints, over the stretch of the drive
with x in [--from, --to] (world frame), the lateral deviation, the heading oscillation, the
number of sign changes of the commanded angular velocity per metre, and the mean speed against
max_vel_x. Writes OUT.json with the samples and the figures.

  corridor_weave.py GOAL_X GOAL_Y OUT_JSON [--from 2] [--to 17] [--timeout SIM_S] [--max-vel-x 0.5]
                    [--spawn X Y YAW] [--frame odom|map] [--record-only SIM_S]

With --record-only no goal is sent (explore drives) and the run is recorded for SIM_S s.

Under lock-step time this script is a participant, so the run is the same at any real-time
factor and machine load."""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import threading

from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry, Path

from minibot3d_sim.msg import SimStatus

# tools/, one up: make demo's scripts
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from demo_phase import write_json, yaw_of  # noqa: E402


class Log(object):
    def __init__(self):
        self.lock = threading.Lock()
        self.truth = []  # (t, x, y, yaw)
        self.cmd = []    # (t, vx, wz)
        self.collisions = 0
        self.plans = []  # (t, [(x, y) every 10th pose]) of the global planner
        rospy.Subscriber('/move_base/NavfnROS/plan', Path, self.on_plan, queue_size=10)
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=100)
        rospy.Subscriber('/cmd_vel', Twist, self.on_cmd, queue_size=100)
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, self.on_status, queue_size=5)

    def on_truth(self, m):
        p = m.pose.pose
        with self.lock:
            self.truth.append((m.header.stamp.to_sec(), p.position.x, p.position.y,
                               yaw_of(p.orientation)))

    def on_cmd(self, m):
        with self.lock:
            self.cmd.append((rospy.get_time(), m.linear.x, m.angular.z))

    def on_plan(self, m):
        pts = [(p.pose.position.x, p.pose.position.y) for p in m.poses[::10]]
        with self.lock:
            self.plans.append((rospy.get_time(), m.header.frame_id, pts))

    def on_status(self, m):
        with self.lock:
            self.collisions = int(m.collisions)


def metrics(truth, cmd, x0, x1, max_vel_x):
    """Figures over the part of the drive with x0 <= x <= x1 (the first pass through it)."""
    seg = [s for s in truth if x0 <= s[1] <= x1]
    if len(seg) < 2:
        return None
    t0, t1 = seg[0][0], seg[-1][0]
    ys = [s[2] for s in seg]
    yaws = [s[3] for s in seg]
    # Path resampled every 2 cm of travel, as the demo's recorder does.
    path = [seg[0]]
    for s in seg[1:]:
        if math.hypot(s[1] - path[-1][1], s[2] - path[-1][2]) > 0.02:
            path.append(s)
    dyaw_path = [abs(math.remainder(b[3] - a[3], 2 * math.pi)) for a, b in zip(path, path[1:])]
    dist = sum(math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(seg, seg[1:]))
    ymean = sum(ys) / len(ys)
    ws = [c for c in cmd if t0 <= c[0] <= t1]
    signs = [1 if c[2] > 1e-9 else -1 for c in ws if abs(c[2]) > 1e-9]
    changes = sum(1 for a, b in zip(signs, signs[1:]) if a != b)
    # Lateral swings: count local extrema of y between which y moves > 1 cm.
    return dict(
        x_from=x0, x_to=x1, sim_s=t1 - t0, distance=dist,
        y_mean=ymean, y_min=min(ys), y_max=max(ys),
        lateral_amplitude=0.5 * (max(ys) - min(ys)),
        lateral_rms=math.sqrt(sum((y - ymean) ** 2 for y in ys) / len(ys)),
        yaw_max_deg=math.degrees(max(abs(a) for a in yaws)),
        yaw_rms_deg=math.degrees(math.sqrt(sum(a * a for a in yaws) / len(yaws))),
        dyaw_per_2cm_max_deg=math.degrees(max(dyaw_path)) if dyaw_path else 0.0,
        cmds=len(ws), cmd_w_zero=sum(1 for c in ws if abs(c[2]) <= 1e-9),
        cmd_w_abs_mean=sum(abs(c[2]) for c in ws) / max(len(ws), 1),
        w_sign_changes=changes, w_sign_changes_per_m=changes / max(dist, 1e-9),
        mean_speed=(seg[-1][1] - seg[0][1]) / max(t1 - t0, 1e-9), max_vel_x=max_vel_x,
        speed_ratio=(seg[-1][1] - seg[0][1]) / max(t1 - t0, 1e-9) / max_vel_x)


def run_metrics(truth, cmd, max_vel_x):
    """Figures over the whole recording: distance, mean speed, turning on the spot, w sign changes."""
    if len(truth) < 2:
        return None
    dist = sum(math.hypot(b[1] - a[1], b[2] - a[2]) for a, b in zip(truth, truth[1:]))
    sim_s = truth[-1][0] - truth[0][0]
    moving = [c for c in cmd if abs(c[1]) > 1e-9 or abs(c[2]) > 1e-9]
    on_spot = sum(1 for c in moving if abs(c[1]) <= 1e-9)
    signs = [1 if c[2] > 0 else -1 for c in moving if abs(c[2]) > 1e-9]
    changes = sum(1 for a, b in zip(signs, signs[1:]) if a != b)
    return dict(sim_s=sim_s, distance=dist, mean_speed=dist / max(sim_s, 1e-9),
                speed_ratio=dist / max(sim_s, 1e-9) / max_vel_x, cmds=len(cmd),
                moving_cmds=len(moving), on_spot_cmds=on_spot,
                w_sign_changes=changes, w_sign_changes_per_m=changes / max(dist, 1e-9))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('goal_x', type=float, help='world frame')
    parser.add_argument('goal_y', type=float, help='world frame')
    parser.add_argument('out_json')
    parser.add_argument('--from', dest='x0', type=float, default=2.0)
    parser.add_argument('--to', dest='x1', type=float, default=17.0)
    parser.add_argument('--timeout', type=float, default=120.0, help='sim seconds for the goal')
    parser.add_argument('--max-vel-x', type=float, default=0.5)
    parser.add_argument('--spawn', type=float, nargs=3, default=(0.0, 0.0, 0.0),
                        metavar=('X', 'Y', 'YAW'),
                        help='the spawn pose (world frame), where odom starts')
    parser.add_argument('--record-only', type=float, default=0.0, metavar='SIM_S',
                        help='send no goal (something else drives, e.g. explore): record for '
                        'SIM_S s of sim time')
    parser.add_argument('--frame', default='odom', choices=('odom', 'map'),
                        help='the goal\'s frame: odom (starts at the spawn pose) or map (= world)')
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node('corridor_weave')
    lockstep = Participant(wake_on_participants=True)
    lockstep.add_periodic(0.05, lambda now: None)
    log = Log()
    if not lockstep.wait_for(lambda: len(log.truth) > 0, 60.0):
        print('no /ground_truth/odom within 60 s of sim time', flush=True)
        return 1
    # Goal heading +x in the world; odom starts at the spawn pose.
    gx, gy, gyaw = args.goal_x, args.goal_y, 0.0
    if args.frame == 'odom':
        sx, sy, syaw = args.spawn
        dx, dy = args.goal_x - sx, args.goal_y - sy
        gx = math.cos(syaw) * dx + math.sin(syaw) * dy
        gy = -math.sin(syaw) * dx + math.cos(syaw) * dy
        gyaw = -syaw
    if args.record_only > 0.0:
        lockstep.wait_for(lambda: False, args.record_only)
        status, sim_s = 'RECORDED', args.record_only
    else:
        finished, proc = lockstep.run(
            '/simple_navi_goals',
            ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', args.frame,
             str(gx), str(gy), str(gyaw), '--timeout', str(args.timeout)],
            args.timeout + 60.0, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            universal_newlines=True)
        if not finished:
            proc.send_signal(2)
        stdout, _ = proc.communicate(timeout=60)
        m = re.findall(r'Result: (\w+) \((.*)\) after ([0-9.]+) s', stdout)
        status, sim_s = (m[-1][0], float(m[-1][2])) if m else ('NONE', None)
    with log.lock:
        truth, cmd, collisions = list(log.truth), list(log.cmd), log.collisions
        plans = list(log.plans)
    fig = metrics(truth, cmd, args.x0, args.x1, args.max_vel_x)
    whole = run_metrics(truth, cmd, args.max_vel_x)
    write_json(args.out_json, dict(status=status, sim_s=sim_s, collisions=collisions,
                                   metrics=fig, run=whole, truth=truth, cmd=cmd,
                                   plans=plans))
    print('%s%s, collisions %d' % (status, ' after %.2f s' % sim_s if sim_s else '', collisions))
    if whole is not None:
        print('whole run: %(distance).2f m in %(sim_s).2f s sim = %(mean_speed).3f m/s = '
              '%(speed_ratio).3f x max_vel_x; %(moving_cmds)d non-zero commands, %(on_spot_cmds)d of '
              'them turning on the spot; %(w_sign_changes_per_m).2f sign changes of w per m' % whole)
    if fig is None:
        print('the robot never drove through x in [%g, %g]' % (args.x0, args.x1))
        return 1
    print('x in [%(x_from)g, %(x_to)g]: %(distance).2f m in %(sim_s).2f s, mean speed '
          '%(mean_speed).3f m/s = %(speed_ratio).3f x max_vel_x\n'
          '  lateral: y in [%(y_min).3f, %(y_max).3f], amplitude %(lateral_amplitude).3f m, '
          'rms %(lateral_rms).3f m\n'
          '  heading: max |yaw| %(yaw_max_deg).1f deg, rms %(yaw_rms_deg).1f deg, largest change '
          'between 2 cm samples %(dyaw_per_2cm_max_deg).1f deg\n'
          '  cmd_vel: %(cmds)d commands, %(cmd_w_zero)d with w = 0, mean |w| %(cmd_w_abs_mean).3f '
          'rad/s, %(w_sign_changes)d sign changes of w = %(w_sign_changes_per_m).2f per m' % fig,
          flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
