#!/usr/bin/env python3
"""One phase of `make demo` (tools/demo.sh starts the ROS stack; this drives and records it).

  demo_phase.py explore  --out DIR --timeout SIM_S [--config-dir CONFIG]
      runs `explore` with CONFIG/explore.yaml until no reachable frontier is left, recording the
      true path, then saves the SLAM map to DIR/demo_map.{pgm,yaml}; writes DIR/demo_explore.json.
  demo_phase.py navigate --out DIR --spawn X,Y,YAW --goals "x,y,yaw ..." --timeout SIM_S
                [scan:=TOPIC cmd_vel:=TOPIC]
      global localization (amcl's global_localization, then wandering (minibot3d_navigation.wanderer)
      until amcl has a confident fix: see Recorder.fix_problems), then each goal with
      simple_navi_goals.py in the SLAM map's frame; writes DIR/demo_nav.json. The wanderer reads
      the robot's laser on `scan` and drives it on `cmd_vel` (ROS remappings name the robot's
      topics); the laser's mounting comes from robot_description and amcl's base_frame_id.
Poses given on the command line are in the world frame; the SLAM map's frame is the world frame
moved to the exploration's spawn pose (--spawn), as gmapping starts its map at the robot.
CONFIG is the robot's config set (default config/, minibot3d's).

Under lock-step time (/use_lockstep, as make demo runs it) this script is a participant: sim time
moves only while it waits, each process it starts (explore, simple_navi_goals.py) joins while sim
time is held, and it learns that one has finished from the simulator's participant list, at the
same sim time in every run; so two runs give the same summary and the same saved map."""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import threading
import time

from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages

import rosparam
import rospy
from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from minibot3d_sim.msg import SimStatus
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32MultiArray
from std_srvs.srv import Empty
from minibot3d_navigation.wanderer import Wanderer, mount_yaw

ROOT = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))

# A confident fix (what the demo trusts before sending goals): amcl's covariance
# cov_xx + cov_yy under COV_FIX, its scan explained at the estimate (amcl/confidence) and one mode.
COV_FIX = 0.05          # m^2
EXPLAINED_FIX = 0.8     # share of the beams


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def world_to_map(spawn, p):
    """Pose p (world) in the frame of spawn (the SLAM map frame)."""
    sx, sy, sa = spawn
    dx, dy = p[0] - sx, p[1] - sy
    c, s = math.cos(sa), math.sin(sa)
    return (c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(p[2] - sa), math.cos(p[2] - sa)))


def write_json(path, data):
    tmp = path + '.tmp'
    with open(tmp, 'w') as f:
        json.dump(data, f)
    os.replace(tmp, path)


class Recorder(object):
    """Ground truth (world frame), amcl_pose and the simulator's collision count."""

    def __init__(self):
        self.lock = threading.Lock()
        self.truth = None
        self.path = []
        self.collisions = 0
        self.amcl = None
        self.amcl_cov = None
        self.confidence = None  # amcl/confidence: explained_fraction, modes, confident, ...
        self.scan = None
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=20)
        rospy.Subscriber('/amcl/confidence', Float32MultiArray, self.on_confidence, queue_size=5)
        rospy.Subscriber('scan', LaserScan, self.on_scan, queue_size=1)
        rospy.Subscriber('/minibot3d_sim/status', SimStatus, self.on_status, queue_size=5)
        rospy.Subscriber('/amcl_pose', PoseWithCovarianceStamped, self.on_amcl, queue_size=5)

    def on_truth(self, m):
        p = m.pose.pose
        pose = (p.position.x, p.position.y, yaw_of(p.orientation))
        with self.lock:
            self.truth = pose
            if not self.path or math.hypot(pose[0] - self.path[-1][0],
                                           pose[1] - self.path[-1][1]) > 0.02:
                self.path.append(pose)

    def on_status(self, m):
        with self.lock:
            self.collisions = int(m.collisions)

    def on_amcl(self, m):
        p = m.pose.pose
        with self.lock:
            self.amcl = (p.position.x, p.position.y, yaw_of(p.orientation))
            self.amcl_cov = (m.pose.covariance[0], m.pose.covariance[7], m.pose.covariance[35])

    def on_confidence(self, m):
        with self.lock:
            self.confidence = list(m.data)

    def on_scan(self, m):
        with self.lock:
            self.scan = m

    def fix_problems(self):
        """What is missing for a confident fix (empty: there is one)."""
        with self.lock:
            cov, conf = self.amcl_cov, self.confidence
        if cov is None or conf is None:
            return ['no amcl_pose / amcl/confidence yet']
        missing = []
        if cov[0] + cov[1] >= COV_FIX:
            missing.append('covariance cov_xx+cov_yy %.3g m^2 >= %g' % (cov[0] + cov[1], COV_FIX))
        if conf[0] < EXPLAINED_FIX:
            missing.append('explained fraction %.2f < %g' % (conf[0], EXPLAINED_FIX))
        if conf[1] != 1:
            missing.append('%d modes, not 1' % conf[1])
        return missing

    def take_path(self):
        with self.lock:
            path, self.path = self.path, []
        return path


def wait_for(lockstep, predicate, sim_timeout, what):
    """Until predicate() (on messages that do not wake the script), checked every 0.05 s of sim
    time; RuntimeError naming `what` after `sim_timeout` s."""
    if not lockstep.wait_for(predicate, sim_timeout, poll=0.05):
        raise RuntimeError('timed out waiting for ' + what)


def explore(args, lockstep, rec):
    wait_for(lockstep, lambda: rec.truth is not None, 60, '/ground_truth/odom')
    # The robot's explore parameters, set before the node starts, as explore.launch loads them.
    for params, ns in rosparam.load_file(os.path.join(args.config_dir, 'explore.yaml'),
                                         default_namespace='/explore'):
        rosparam.upload_params(ns, params)
    t0_sim, t0_wall = rospy.Time.now(), time.time()
    finished, proc = lockstep.run(
        '/explore', ['rosrun', 'minibot3d_navigation', 'explore'], args.timeout)
    ok = finished
    try:
        if not finished:
            print('demo: exploration did not finish within %.0f s of sim time' % args.timeout,
                  flush=True)
            proc.send_signal(2)
        proc.wait(30)
    finally:
        if proc.poll() is None:
            proc.kill()
    ok = ok and proc.returncode == 0
    sim_s, wall_s = (rospy.Time.now() - t0_sim).to_sec(), time.time() - t0_wall
    # Sim time holds while the map is saved: the map is the one SLAM had when explore ended.
    saved = subprocess.run(['rosrun', 'minibot3d_slam', 'map_saver', '-f',
                            os.path.join(args.out, 'demo_map')]).returncode == 0
    write_json(os.path.join(args.out, 'demo_explore.json'), dict(
        ok=ok and saved, explore_exit=proc.returncode, map_saved=saved, sim_s=sim_s,
        wall_s=wall_s, collisions=rec.collisions, path=rec.take_path()))
    return 0 if ok and saved else 1


def localize(lockstep, rec, cmd_pub, spawn, timeout=300.0):
    """Global localization: amcl's global_localization, then wander until amcl has a confident
    fix (Recorder.fix_problems), at most `timeout` s of sim time. Returns the position error
    then (or at the timeout, after saying what was missing)."""
    rospy.wait_for_service('/global_localization', 60)
    rospy.ServiceProxy('/global_localization', Empty)()
    with rec.lock:  # the claim must come from an update after the call
        rec.amcl_cov = rec.confidence = None
    wait_for(lockstep, lambda: rec.scan is not None, 60, rospy.resolve_name('scan'))
    # Where the laser looks on the robot (minibot3d's is mounted backwards): from the robot
    # description, on the base frame amcl localizes.
    wanderer = Wanderer(laser_yaw=mount_yaw(rospy.get_param('/robot_description'),
                                            rospy.get_param('/amcl/base_frame_id', 'base_link'),
                                            rec.scan.header.frame_id))
    start = rospy.Time.now()
    travel, last = 0.0, rec.truth
    cmd = Twist()
    while (rospy.Time.now() - start).to_sec() < timeout and rec.fix_problems():
        cmd.linear.x, cmd.angular.z = wanderer.command(rec.scan)
        cmd_pub.publish(cmd)
        lockstep.sleep(0.05)
        now = rec.truth
        travel += math.hypot(now[0] - last[0], now[1] - last[1])
        last = now
    cmd_pub.publish(Twist())
    lockstep.sleep(0.05)
    t = world_to_map(spawn, rec.truth)
    err = math.hypot(rec.amcl[0] - t[0], rec.amcl[1] - t[1]) if rec.amcl else float('inf')
    missing = rec.fix_problems()
    if not missing:
        print('demo: localized after %.1f m of wandering (%.0f s): error %.3f m'
              % (travel, (rospy.Time.now() - start).to_sec(), err), flush=True)
    else:
        print('demo: no confident fix within %.0f s (%.1f m wandered): %s; error %.3f m'
              % (timeout, travel, '; '.join(missing), err), flush=True)
    return err


def navigate(args, lockstep, rec, cmd_pub):
    spawn = tuple(float(v) for v in args.spawn.split(','))
    if args.goals.strip():
        goals = [tuple(float(v) for v in g.split(',')) for g in args.goals.split()]
    else:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        from demo_goals import sample_goals
        goals = sample_goals(os.path.join(args.out, 'demo_map.yaml'), spawn, args.config_dir)
        print('demo: goals sampled from the saved map: %s' % ' '.join(
            '%.2f,%.2f' % g[:2] for g in goals), flush=True)
    wait_for(lockstep, lambda: rec.truth is not None, 60, '/ground_truth/odom')
    wait_for(lockstep, lambda: rec.amcl is not None, 120, 'amcl_pose')
    loc_error = localize(lockstep, rec, cmd_pub, spawn)
    rec.take_path()
    results = []
    for g in goals:
        gm = world_to_map(spawn, g)
        t0 = time.time()
        _, proc = lockstep.run(
            '/simple_navi_goals',
            ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', 'map',
             '%.3f' % gm[0], '%.3f' % gm[1], '%.3f' % gm[2], '--timeout', str(args.timeout)],
            args.timeout + 30, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            universal_newlines=True)
        stdout, _ = proc.communicate()
        out = subprocess.CompletedProcess(proc.args, proc.returncode, stdout)
        m = re.search(r'after ([0-9.]+) s', out.stdout)
        truth = rec.truth
        tm = world_to_map(spawn, truth)
        amcl_err = math.hypot(rec.amcl[0] - tm[0], rec.amcl[1] - tm[1]) if rec.amcl else None
        results.append(dict(goal=g, ok=out.returncode == 0, sim_s=float(m.group(1)) if m else None,
                            wall_s=time.time() - t0, error=math.hypot(truth[0] - g[0], truth[1] - g[1]),
                            heading_error=abs(math.remainder(truth[2] - g[2], 2.0 * math.pi)),
                            amcl_error=amcl_err, path=rec.take_path()))
        if out.returncode != 0:
            print('demo: simple_navi_goals.py said:\n  ' +
                  '\n  '.join(out.stdout.strip().splitlines()[-6:]), flush=True)
        print('demo: goal (%.2f, %.2f): %s in %s s sim, truly %.2f m and %.2f rad from it, '
              'localization error %s m'
              % (g[0], g[1], 'reached' if out.returncode == 0 else 'FAILED',
                 m.group(1) if m else '?', results[-1]['error'], results[-1]['heading_error'],
                 '%.3f' % amcl_err if amcl_err is not None else '?'), flush=True)
    write_json(os.path.join(args.out, 'demo_nav.json'), dict(
        localization_error=loc_error, goals=results, collisions=rec.collisions))
    return 0 if all(r['ok'] for r in results) else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('phase', choices=['explore', 'navigate'])
    parser.add_argument('--out', required=True)
    parser.add_argument('--timeout', type=float, default=1500.0, help='sim seconds')
    parser.add_argument('--spawn', default='-3,-1.5,0')
    parser.add_argument('--goals', default='')
    parser.add_argument('--config-dir', default=os.path.join(ROOT, 'config'),
                        help="the robot's config set (default config/, minibot3d's)")
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node('demo_' + args.phase)
    # Subscribers first: the simulator's first messages reach those the master knows of when the
    # participant joins; one made later would see the first pose at a sim time that depends on
    # how fast this process started.
    rec = Recorder()
    cmd_pub = rospy.Publisher('cmd_vel', Twist, queue_size=1) if args.phase == 'navigate' else None
    lockstep = Participant(wake_on_participants=True)
    try:
        if args.phase == 'explore':
            return explore(args, lockstep, rec)
        return navigate(args, lockstep, rec, cmd_pub)
    except (RuntimeError, ValueError) as e:  # ValueError: the laser's mounting
        print('demo: %s' % e, file=sys.stderr, flush=True)
        return 1
    finally:
        lockstep.close()


if __name__ == '__main__':
    sys.exit(main())
