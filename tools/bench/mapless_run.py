#!/usr/bin/env python3
"""One mapless run (tools/bench/mapless_smoke.sh starts mapless_navigation.launch; this drives and
records it): sends the world's goal in odom with simple_navi_goals.py (with --frame map: in map,
once amcl publishes map -> odom, for a run on the world's map), records the true path and
the simulator's collision count, prints one summary line and writes OUT.json (the world, the
result, sim time, collisions and the path driven, for tools/bench/mapless_bench.py's and
tools/bench/crowd_bench.py's pictures).

In a world with actors (tools/generators/crowd_world.py's), it also records where they are
(/minibot3d_sim/actors, 20 Hz of sim time) and the robot's contacts with them
(/minibot3d_sim/collisions), and reports the closest approach of the robot's footprint to a
person's body (the actor's cylinder), the sim time spent closer than 0.45 m (the intimate zone of
proxemics, Hall 1966), and the collisions with a person split by fault: the robot at fault when it
was moving at the contact's onset (its true speed above 0.02 m/s or turn rate above 0.05 rad/s).

  mapless_run.py WORLD_JSON OUT_JSON [--timeout SIM_S] [--frame odom|map]

Under lock-step time this script is a participant, so the run (and the path) is the same at any
real-time factor and machine load."""
import argparse
import bisect
import json
import math
import os
import re
import subprocess
import sys
import threading

from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages

import rospy
from minibot3d_sim.msg import Collision, SimActors
from nav_msgs.msg import Odometry

# tools/, one up: make demo's scripts
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from demo_phase import Recorder, write_json, yaw_of  # noqa: E402  (make demo's recorder of the truth)


INTIMATE = 0.45            # m, proxemics' intimate zone
MOVING_SPEED = 0.02       # m/s
MOVING_TURN = 0.05        # rad/s


def footprint_of_params():
    """The robot's footprint polygon (base frame) from move_base's local costmap, or a polygon
    round its robot_radius."""
    fp = rospy.get_param('/move_base/local_costmap/footprint', None)
    if isinstance(fp, str):
        import yaml
        fp = yaml.safe_load(fp)
    if fp and len(fp) >= 3:
        return [(float(x), float(y)) for x, y in fp]
    r = float(rospy.get_param('/move_base/local_costmap/robot_radius', 0.2))
    return [(r * math.cos(a * math.pi / 8), r * math.sin(a * math.pi / 8)) for a in range(16)]


def polygon_distance(poly, px, py):
    """Distance from a point to a polygon (0 inside)."""
    inside = False
    best = float('inf')
    n = len(poly)
    for i in range(n):
        (ax, ay), (bx, by) = poly[i], poly[(i + 1) % n]
        if (ay > py) != (by > py) and px < ax + (py - ay) * (bx - ax) / (by - ay):
            inside = not inside
        dx, dy = bx - ax, by - ay
        u = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy or 1e-12)))
        best = min(best, math.hypot(px - ax - u * dx, py - ay - u * dy))
    return 0.0 if inside else best


class People(object):
    """The robot's distances to the world's actors and its contacts with them. Each actors message
    and each collision is taken with the ground truth of its own sim time (the latest truth stamped
    at or before it) and in stamp order, so the figures do not depend on the order in which the
    topics' messages arrive."""

    TRUTH_KEPT = 500          # ground-truth messages kept for the lookup (seconds of them)

    def __init__(self, footprint):
        self.footprint = footprint
        self.lock = threading.Lock()
        self.truth = []         # (stamp, x, y, yaw, moving), in stamp order
        self.pending = []       # (stamp, kind, message): kind 0 actors, 1 collision
        self.last_stamp = None
        self.min_distance = None
        self.min_at = None      # (sim s, actor)
        self.intimate_s = 0.0
        self.contacts = []      # (sim s, actor, robot moving)
        self.tracks = {}        # actor: [(t, x, y)] every 0.25 s
        self.robot_track = []   # (t, x, y) every 0.25 s
        self.t0 = None
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=100)
        rospy.Subscriber('/minibot3d_sim/actors', SimActors, self.on_actors, queue_size=100)
        rospy.Subscriber('/minibot3d_sim/collisions', Collision, self.on_collision,
                         queue_size=100)

    def on_truth(self, m):
        p, t = m.pose.pose, m.twist.twist
        moving = (math.hypot(t.linear.x, t.linear.y) > MOVING_SPEED or
                  abs(t.angular.z) > MOVING_TURN)
        with self.lock:
            stamp = m.header.stamp.to_sec()
            if self.truth and stamp < self.truth[-1][0]:
                return
            self.truth.append((stamp, p.position.x, p.position.y, yaw_of(p.orientation), moving))
            del self.truth[:-self.TRUTH_KEPT]
            self.drain(stamp)

    def on_actors(self, m):
        with self.lock:
            self.pending.append((m.header.stamp.to_sec(), 0, m))
            if self.truth:
                self.drain(self.truth[-1][0])

    def on_collision(self, m):
        if not m.object.startswith('actor '):
            return
        with self.lock:
            self.pending.append((m.header.stamp.to_sec(), 1, m))
            if self.truth:
                self.drain(self.truth[-1][0])

    def truth_at(self, stamp):
        i = bisect.bisect_right([e[0] for e in self.truth], stamp)
        return self.truth[i - 1] if i > 0 else None

    def drain(self, upto):
        """Takes the waiting messages stamped at or before `upto`, in stamp order."""
        self.pending.sort(key=lambda e: (e[0], e[1]))
        while self.pending and self.pending[0][0] <= upto:
            stamp, kind, m = self.pending.pop(0)
            truth = self.truth_at(stamp)
            if truth is None:
                continue
            if kind == 0:
                self.take_actors(stamp, m, truth)
            else:
                t = stamp - (self.t0 if self.t0 is not None else stamp)
                self.contacts.append((round(t, 3), m.object[len('actor '):], truth[4]))

    def take_actors(self, stamp, m, truth):
        if self.t0 is None:
            self.t0 = stamp
        _, x, y, yaw, _ = truth
        c, s = math.cos(yaw), math.sin(yaw)
        nearest, who = float('inf'), None
        for a in m.actors:
            ax, ay = a.pose.position.x, a.pose.position.y
            lx, ly = c * (ax - x) + s * (ay - y), -s * (ax - x) + c * (ay - y)
            d = max(0.0, polygon_distance(self.footprint, lx, ly) - a.radius)
            if d < nearest:
                nearest, who = d, a.name
            track = self.tracks.setdefault(a.name, [])
            if not track or stamp - self.t0 - track[-1][0] >= 0.25:
                track.append((round(stamp - self.t0, 2), round(ax, 3), round(ay, 3)))
        if not self.robot_track or stamp - self.t0 - self.robot_track[-1][0] >= 0.25:
            self.robot_track.append((round(stamp - self.t0, 2), round(x, 3), round(y, 3)))
        if who is not None:
            if self.min_distance is None or nearest < self.min_distance:
                self.min_distance, self.min_at = nearest, (stamp - self.t0, who)
            if nearest < INTIMATE and self.last_stamp is not None:
                self.intimate_s += stamp - self.last_stamp
        self.last_stamp = stamp

    def summary(self):
        with self.lock:
            self.drain(float('inf'))
            return dict(
                min_distance=self.min_distance,
                min_distance_at=self.min_at,
                intimate_s=round(self.intimate_s, 2),
                person_collisions=len(self.contacts),
                at_fault_collisions=sum(1 for c in self.contacts if c[2]),
                contacts=self.contacts, tracks=self.tracks, robot_track=self.robot_track)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('world_json')
    parser.add_argument('out_json')
    parser.add_argument('--timeout', type=float, default=150.0, help='sim seconds for the goal')
    parser.add_argument('--frame', choices=('odom', 'map'), default='odom',
                        help="the goal's frame (the world's, both starting at the spawn pose); "
                             'map waits for the localizer first')
    args = parser.parse_args(rospy.myargv()[1:])
    with open(args.world_json) as f:
        world = json.load(f)
    rospy.init_node('mapless_run')
    # Subscribers before the lock-step Participant: connected before it joins, they have the
    # ground truth from its first tick on, whenever their connections are made in wall time.
    rec = Recorder()
    people = People(footprint_of_params()) if world.get('people') else None
    lockstep = Participant(wake_on_participants=True)
    lockstep.add_periodic(0.05, lambda now: None)
    if not lockstep.wait_for(lambda: rec.truth is not None, 60.0):
        print('%s: no /ground_truth/odom within 60 s of sim time' % world['name'], flush=True)
        return 1
    if args.frame == 'map':
        import tf2_ros
        tf_buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(tf_buffer)
        if not lockstep.wait_for(lambda: tf_buffer.can_transform('map', 'odom', rospy.Time(0)),
                                 60.0):
            print('%s: no map -> odom transform (the localizer) within 60 s of sim time'
                  % world['name'], flush=True)
            return 1
    goal = world['goal']
    finished, proc = lockstep.run(
        '/simple_navi_goals',
        ['rosrun', 'minibot3d_navigation', 'simple_navi_goals.py', '--frame', args.frame,
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
    result = dict(
        world=world['name'], gap=world.get('achieved_gap'), status=status, message=text,
        sim_s=sim_s, exit=proc.returncode, collisions=collisions, goal_error=math.hypot(
            end[0] - goal['x'], end[1] - goal['y']), path=[p[:2] for p in path])
    what = 'gap %.3f m' % world['achieved_gap'] if 'achieved_gap' in world else world.get('kind', '')
    extra = ''
    if people is not None:
        result.update(people.summary())
        extra = ', closest %s m, %.1f s within %.2f m, person collisions %d (%d at fault)' % (
            '%.3f' % result['min_distance'] if result['min_distance'] is not None else '-',
            result['intimate_s'], INTIMATE, result['person_collisions'],
            result['at_fault_collisions'])
    write_json(args.out_json, result)
    print('%s %s: %s%s, exit %d, collisions %d, true end (%.2f, %.2f)%s' % (
        world['name'], what, status,
        ' after %.2f s' % sim_s if sim_s is not None else ' (%s)' % text, proc.returncode,
        collisions, end[0], end[1], extra), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
