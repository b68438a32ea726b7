#!/usr/bin/env python3
"""Global-localization study (make bench): N seeded random starts in one world, each: the robot is
carried (the simulator's set_pose; odometry is not told) to a random free pose, amcl's
/global_localization is called once, and minibot3d_navigation.wanderer drives it (ahead where the
laser shows room, turning away where not) for --travel metres. Every amcl_pose after the call is
compared with /ground_truth/odom:
  claim        cov_xx + cov_yy < 0.05 m^2 (make demo's threshold)
  false claim  a claim while > 1 m or > 30 deg from the truth
  right        < 0.3 m and < 10 deg
Prints one line per start and a summary: share right at the end, false claims, travel until the
first right claim. With --kidnaps N, after each of the first N starts the robot is carried again,
at least --kidnap-distance away (or as far as the map allows), without telling amcl (a
kidnapping), and driven --kidnap-travel metres: every amcl_pose from then on is scored the same
way (a claim of the old place is false), with the travel until amcl is right again. Run by
tools/bench/global_loc_study.sh (which starts the simulator, map_server and amcl on lock-step
time: this script is a participant, so a seed gives the same starts and driving; the carrying
and the global_localization call are service calls, answered between ticks, so two runs can
differ by a tick there: claims move by up to a few tenths of a metre of travel, and on a map
too large for the map-wide search, whose uniform spread depends on such details, outcomes can
change).

  global_loc_study.py --map MAP.yaml --starts N [--seed S] [--travel M] [--timeout SIM_S]
                      [--spawn X,Y] [--kidnaps N] [--kidnap-distance M] [--kidnap-travel M]
  global_loc_study.py --map MAP.yaml --pick-spawn"""
import argparse
import math
import os
import random
import sys
import threading

from minibot3d_lockstep import Participant  # before rospy.init_node: it counts messages

import rospy
from geometry_msgs.msg import PoseArray, PoseWithCovarianceStamped, Twist
from minibot3d_navigation.wanderer import Wanderer
from minibot3d_sim.srv import SetPose
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32MultiArray
from std_srvs.srv import Empty

# tools/, one up: make demo's scripts
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from demo_report import load_trinary, route_driver  # noqa: E402

CLAIM = 0.05
FALSE_DIST, FALSE_YAW = 1.0, math.radians(30.0)
RIGHT_DIST, RIGHT_YAW = 0.3, math.radians(10.0)


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def angle_diff(a, b):
    return abs(math.atan2(math.sin(a - b), math.cos(a - b)))


class State(object):
    def __init__(self):
        self.lock = threading.Lock()
        self.truth, self.truth_t, self.scan = None, 0.0, None
        self.travel = 0.0
        self.events = []  # (travel, dist, dyaw, cov, stamp) per amcl_pose
        self.searches = []  # travel at each map-wide search amcl ran (amcl/search_candidates)
        self.recording = None  # for --picture: {'truth': [...], 'estimates': [...], 'searches': [...]}
        rospy.Subscriber('/ground_truth/odom', Odometry, self.on_truth, queue_size=50)
        rospy.Subscriber('/amcl_pose', PoseWithCovarianceStamped, self.on_pose, queue_size=50)
        rospy.Subscriber('/scan', LaserScan, self.on_scan, queue_size=1)
        rospy.Subscriber('/amcl/search_candidates', PoseArray, self.on_candidates, queue_size=5)
        self.confidence = None  # the last amcl/confidence, for --trace
        self.trace = None  # --trace: an open file, one line per amcl_pose
        rospy.Subscriber('/amcl/confidence', Float32MultiArray, self.on_confidence, queue_size=5)

    def on_confidence(self, m):
        with self.lock:
            self.confidence = list(m.data)

    def on_truth(self, m):
        p = m.pose.pose
        pose = (p.position.x, p.position.y, yaw_of(p.orientation))
        with self.lock:
            if self.truth is not None:
                d = math.hypot(pose[0] - self.truth[0], pose[1] - self.truth[1])
                if d < 0.5:  # a teleport is not travel
                    self.travel += d
            self.truth, self.truth_t = pose, m.header.stamp.to_sec()
            if self.recording is not None:
                self.recording['truth'].append(pose[:2])

    def on_pose(self, m):
        p = m.pose.pose
        c = m.pose.covariance
        with self.lock:
            if self.truth is None:
                return
            t = self.truth
            self.events.append((self.travel, math.hypot(p.position.x - t[0], p.position.y - t[1]),
                                angle_diff(yaw_of(p.orientation), t[2]), c[0] + c[7],
                                m.header.stamp.to_sec()))
            if self.recording is not None:
                self.recording['estimates'].append((p.position.x, p.position.y, c[0] + c[7]))
            if self.trace is not None:
                e = self.events[-1]
                self.trace.write('%.3f %.2f %.2f %.2f %.2f %.3f %.3f %.1f %.4g %s\n' % (
                    e[4], e[0], t[0], t[1], p.position.x, p.position.y, e[1],
                    math.degrees(e[2]), e[3], ' '.join('%.3g' % v for v in self.confidence or [])))

    def on_candidates(self, m):
        with self.lock:
            self.searches.append(self.travel)
            if self.recording is not None:
                self.recording['searches'].append(
                    [(q.position.x, q.position.y, yaw_of(q.orientation)) for q in m.poses])

    def on_scan(self, m):
        with self.lock:
            self.scan = m


def clear_regions(map_yaml, clearance):
    """The map's free cells at least `clearance` from obstacles and unknown space, labelled by
    4-connected region: (labels, free, occupied, resolution, origin); labels is 0 elsewhere."""
    from scipy import ndimage
    free, occ, res, origin = load_trinary(map_yaml)
    ok = free & ~route_driver().inflate(occ | ~free, int(math.ceil(clearance / res)))
    labels, _ = ndimage.label(ok)
    return labels, free, occ, res, origin


def free_poses(map_yaml, rng, spawn, clearance=0.3):
    """Random poses on free cells at least `clearance` from obstacles and unknown space that
    the robot could reach from `spawn` (not, say, the yard round a building's outer walls). The
    cells are found at once (seconds on a building's map): call it before joining lock-step,
    where a participant must answer every tick within ~lockstep_timeout."""
    import numpy as np
    labels, _, _, res, origin = clear_regions(map_yaml, clearance)
    h, w = labels.shape
    si, sj = int((spawn[0] - origin[0]) / res), int((spawn[1] - origin[1]) / res)
    if not (0 <= si < w and 0 <= sj < h and labels[sj, si]):
        raise SystemExit('global_loc_study: spawn (%g, %g) is not on a free cell of %s'
                         % (spawn[0], spawn[1], map_yaml))
    # Row-major (j, i) order, so that a seed draws the same cells every run.
    cells = [(int(j), int(i)) for j, i in zip(*np.nonzero(labels == labels[sj, si]))]

    def draw():
        while True:
            j, i = cells[rng.randrange(len(cells))]
            yield (origin[0] + (i + 0.5) * res, origin[1] + (j + 0.5) * res,
                   rng.uniform(-math.pi, math.pi))
    return draw()


def pick_spawn(map_yaml, clearance=0.3):
    """A spawn for a map without one (a floor plan made from a SLAM map): the cell farthest from
    obstacles and unknown space in the largest 4-connected region of cells at least `clearance`
    from them, so that the starts drawn from it cover most of the building. Returns (x, y)."""
    import numpy as np
    from scipy import ndimage
    labels, free, occ, res, origin = clear_regions(map_yaml, clearance)
    if not labels.any():
        raise SystemExit('global_loc_study: %s has no free cell %.2f m from obstacles and unknown '
                         'space' % (map_yaml, clearance))
    largest = 1 + int(np.argmax(np.bincount(labels.ravel())[1:]))
    room = ndimage.distance_transform_edt(free & ~occ) * (labels == largest)
    j, i = np.unravel_index(int(np.argmax(room)), room.shape)
    return origin[0] + (i + 0.5) * res, origin[1] + (j + 0.5) * res


def far_poses(poses, here, distance, tries=5000):
    """Poses from `poses` at least `distance` from `here`; when none of `tries` draws is that
    far (a small map, the robot in its middle), the farthest of them. Never loops for ever: the
    study is a lock-step participant and must answer every tick within ~lockstep_timeout."""
    while True:
        best, best_d = None, -1.0
        for _ in range(tries):
            p = next(poses)
            d = math.hypot(p[0] - here[0], p[1] - here[1])
            if d >= distance:
                best = p
                break
            if d > best_d:
                best, best_d = p, d
        yield best


def draw(path, map_yaml, rec, k):
    """The picture of one start: map, candidates of every search, true path, estimates (grey while
    amcl makes no claim, green when it claims the pose), the kidnapping (second search) in orange."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import numpy as np
    free, occ, res, origin = load_trinary(map_yaml)
    img = np.where(occ, 0.0, np.where(free, 1.0, 0.75))
    h, w = img.shape
    fig, ax = plt.subplots(figsize=(12, 10.8))
    ax.imshow(img, cmap='gray', vmin=0, vmax=1, origin='lower', interpolation='nearest',
              extent=(origin[0], origin[0] + w * res, origin[1], origin[1] + h * res))
    cut_t, cut_e = rec['kidnap_at'] or (len(rec['truth']), len(rec['estimates']))
    for part, (truth, est) in enumerate(((rec['truth'][:cut_t], rec['estimates'][:cut_e]),
                                         (rec['truth'][cut_t:], rec['estimates'][cut_e:]))):
        if truth:
            t = np.array(truth)
            # A jump is the carrying, not a path: split there.
            breaks = np.nonzero(np.hypot(*np.diff(t, axis=0).T) > 0.5)[0] + 1
            for i, seg in enumerate(np.split(t, breaks)):
                ax.plot(seg[:, 0], seg[:, 1], '-', color='black' if part == 0 else 'saddlebrown',
                        lw=1.5, label=None if i else
                        'true path' if part == 0 else 'true path after the kidnapping')
        if est:
            e = np.array(est)
            claimed = e[:, 2] < CLAIM
            ax.plot(e[~claimed, 0], e[~claimed, 1], '.', color='0.55', ms=4,
                    label='estimate, no claim' if part == 0 else None)
            ax.plot(e[claimed, 0], e[claimed, 1], '.', color='green', ms=4,
                    label='estimate, claimed' if part == 0 else None)
    for s_i, cands in enumerate(rec['searches']):
        color = 'tab:blue' if s_i == 0 else 'tab:orange'
        for rank, (cx, cy, cyaw) in enumerate(cands):
            ax.arrow(cx, cy, 1.2 * math.cos(cyaw), 1.2 * math.sin(cyaw), width=0.12,
                     color=color, length_includes_head=True,
                     label=None if rank or s_i > 1 else
                     'search candidates (global_localization)' if s_i == 0 else
                     'later searches (lost, or the look-alike check before a claim)')
            ax.annotate(str(rank + 1), (cx, cy), xytext=(4, 4), textcoords='offset points',
                        color=color, fontsize=9, weight='bold')
    if rec['truth']:
        ax.plot(*rec['truth'][0], 'o', color='black', ms=7, label='start')
    ax.set_aspect('equal')
    ax.set_xlabel('x (m)')
    ax.set_ylabel('y (m)')
    ax.set_title('Global localization, %s, start %d: candidates ranked by score' % (
        os.path.basename(map_yaml), k))
    ax.legend(loc='upper center', bbox_to_anchor=(0.5, -0.07), ncol=4, fontsize=9)
    fig.tight_layout()
    tmp = path + '.tmp.png'
    fig.savefig(tmp, dpi=90)
    plt.close(fig)
    os.replace(tmp, path)
    print('global_loc_study: picture of start %d written to %s' % (k, path), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--map', required=True)
    ap.add_argument('--pick-spawn', action='store_true',
                    help='print a spawn "X Y" for --map (see pick_spawn) and exit')
    ap.add_argument('--starts', type=int, default=10)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--travel', type=float, default=12.0, help='m driven per start')
    ap.add_argument('--timeout', type=float, default=150.0, help='sim s per start')
    ap.add_argument('--spawn', default='-3.0,-1.5', help='x,y: starts are reachable from here')
    ap.add_argument('--kidnaps', type=int, default=0,
                    help='after each of the first N starts, carry the robot elsewhere (amcl not '
                    'told) and drive on')
    ap.add_argument('--kidnap-distance', type=float, default=5.0,
                    help='m: how far at least (on a small map: the farthest of 5000 draws)')
    ap.add_argument('--kidnap-travel', type=float, default=15.0, help='m driven after a kidnap')
    ap.add_argument('--wanderer', choices=('sides', 'openings'), default='sides',
                    help='the wanderer: steer towards the side with more room (default), or '
                    'head for the deepest opening (its module doc and the README say why it is '
                    'not the default)')
    ap.add_argument('--picture', help='PNG: the map, the search candidates, the true and estimated '
                    'paths of one start (and its kidnapping)')
    ap.add_argument('--picture-start', type=int, default=0, help='which start --picture shows')
    ap.add_argument('--trace', help='text file: one line per amcl_pose (stamp, travel, truth x y, '
                    'estimate x y, error m and deg, cov_xx + cov_yy, then amcl/confidence)')
    args = ap.parse_args(rospy.myargv()[1:])
    if args.pick_spawn:
        print('%.3f %.3f' % pick_spawn(args.map))
        return 0
    for name, ok in (('--starts', args.starts >= 1), ('--travel', args.travel > 0),
                     ('--timeout', args.timeout > 0), ('--kidnaps', args.kidnaps >= 0),
                     ('--kidnap-distance', args.kidnap_distance >= 0),
                     ('--kidnap-travel', args.kidnap_travel > 0),
                     ('--picture-start', 0 <= args.picture_start < args.starts)):
        if not ok:
            ap.error('%s=%s: out of range' % (name, getattr(args, name[2:].replace('-', '_'))))
    rospy.init_node('global_loc_study')
    rng = random.Random(args.seed)
    poses = free_poses(args.map, rng, [float(v) for v in args.spawn.split(',')])
    lockstep = Participant(wake_topics=['/amcl_pose', '/ground_truth/odom'],
                           wake_on_participants=True)
    st = State()
    if args.trace:
        st.trace = open(args.trace, 'w')
    cmd_pub = rospy.Publisher('/cmd_vel', Twist, queue_size=1)
    if not lockstep.wait_for(lambda: st.truth is not None and st.scan is not None, 120.0):
        print('global_loc_study: no /ground_truth/odom or /scan', flush=True)
        return 1
    rospy.wait_for_service('/global_localization', 60)
    set_pose = rospy.ServiceProxy('/minibot3d_sim/set_pose', SetPose)
    global_loc = rospy.ServiceProxy('/global_localization', Empty)

    def carry(pose_source):
        """Teleports the robot to the next pose that the simulator accepts; waits for the truth."""
        for _ in range(50):
            x, y, yaw = next(pose_source)
            t_set = rospy.Time.now().to_sec()
            if set_pose(x, y, yaw).success:
                break
        lockstep.wait_for(lambda: st.truth_t > t_set and math.hypot(
            st.truth[0] - x, st.truth[1] - y) < 0.05, 10.0)
        with st.lock:
            return x, y, yaw, st.truth_t  # the first ground truth at the new place

    def drive(travel, since):
        """Wanders `travel` metres (or until --timeout); returns (events, metres driven) from now.
        Only poses amcl computed from data after `since` (the carrying) count: one stamped before
        it describes the robot before it was moved."""
        with st.lock:
            st.events = []
            st.searches = []
            travel0 = st.travel
        wanderer = Wanderer(laser_yaw=math.pi, seek_openings=args.wanderer == 'openings')
        start = rospy.Time.now()
        cmd = Twist()
        while (st.travel - travel0 < travel and
               (rospy.Time.now() - start).to_sec() < args.timeout):
            cmd.linear.x, cmd.angular.z = wanderer.command(st.scan)
            cmd_pub.publish(cmd)
            lockstep.sleep(0.05)
        cmd_pub.publish(Twist())
        lockstep.sleep(0.1)
        if lockstep.dropped:
            raise SystemExit('global_loc_study: the simulator dropped this script from the '
                             'lock-step loop (see its log): the figures would not be reproducible')
        with st.lock:
            return ([(e[0] - travel0,) + e[1:] for e in st.events if e[4] > since],
                    st.travel - travel0, [s - travel0 for s in st.searches])

    def score(events):
        """(right at the end, false claims, travel to the first right claim or None, last event)."""
        false = [e for e in events if e[3] < CLAIM and (e[1] > FALSE_DIST or e[2] > FALSE_YAW)]
        right = [e for e in events if e[3] < CLAIM and e[1] < RIGHT_DIST and e[2] < RIGHT_YAW]
        last = events[-1] if events else None
        right_end = bool(last and last[3] < CLAIM and last[1] < RIGHT_DIST and
                         last[2] < RIGHT_YAW)
        return right_end, false, right[0][0] if right else None, last

    def describe(right_end, false, first, last, travelled, searches):
        return '%s; %d false claims%s; first right claim %s; driven %.1f m; searches at %s; ' \
            'end %.2f m / %.0f deg off, cov %.3g' % (
                'right at the end' if right_end else 'NOT right at the end', len(false),
                ' (first %.1f m off after %.1f m)' % (false[0][1], false[0][0]) if false else '',
                'after %.1f m' % first if first is not None else 'never', travelled,
                ', '.join('%.1f' % s for s in searches) + ' m' if searches else '-',
                last[1] if last else float('nan'), math.degrees(last[2]) if last else float('nan'),
                last[3] if last else float('nan'))

    rows, kidnaps, picture = [], [], None
    for k in range(args.starts):
        x, y, yaw, t_set = carry(poses)
        if args.picture and k == args.picture_start:
            with st.lock:
                st.recording = {'truth': [], 'estimates': [], 'searches': [], 'kidnap_at': None}
        global_loc()
        events, travelled, searches = drive(args.travel, t_set)
        right_end, false, first, last = score(events)
        rows.append((right_end, len(false), first))
        print('start %2d (%6.2f, %6.2f, %5.2f): %s' % (
            k, x, y, yaw, describe(right_end, false, first, last, travelled, searches)), flush=True)
        if k < args.kidnaps:
            # Kidnapped: carried at least --kidnap-distance away (or as far as the map allows),
            # amcl not told.
            with st.lock:
                here = st.truth
            kx, ky, kyaw, t_set = carry(far_poses(poses, here, args.kidnap_distance))
            with st.lock:
                if st.recording is not None:
                    st.recording['kidnap_at'] = (len(st.recording['truth']),
                                                 len(st.recording['estimates']))
            events, travelled, searches = drive(args.kidnap_travel, t_set)
            right_end, false, first, last = score(events)
            carried = math.hypot(kx - here[0], ky - here[1])
            kidnaps.append((right_end, len(false), first, carried))
            print('  kidnapped %5.1f m to (%6.2f, %6.2f, %5.2f): %s' % (
                carried, kx, ky, kyaw,
                describe(right_end, false, first, last, travelled, searches)), flush=True)
        with st.lock:
            if st.recording is not None:
                picture = (st.recording, k)
            st.recording = None
    # Drawing takes seconds: out of the lock-step loop.
    lockstep.close()
    if picture is not None:
        draw(args.picture, args.map, *picture)
    n = len(rows)
    firsts = sorted(r[2] for r in rows if r[2] is not None)
    within10 = sum(1 for r in rows if r[2] is not None and r[2] <= 10.0)
    print('global_loc_study %s: %d starts (seed %d, %.0f m each): right at the end %d/%d; '
          'false claims %d (in %d starts); right claim within 10 m %d/%d; travel to the first right '
          'claim median %s m, max %s m' % (
              os.path.basename(args.map), n, args.seed, args.travel, sum(r[0] for r in rows), n,
              sum(r[1] for r in rows), sum(1 for r in rows if r[1]), within10, n,
              '%.1f' % firsts[len(firsts) // 2] if firsts else '-',
              '%.1f' % firsts[-1] if firsts else '-'), flush=True)
    if kidnaps:
        n = len(kidnaps)
        firsts = sorted(r[2] for r in kidnaps if r[2] is not None)
        print('global_loc_study %s kidnapping: %d runs (carried %.1f-%.1f m, %.0f m driven): right '
              'at the end %d/%d; false claims %d (in %d runs); right again within 10 m %d/%d; '
              'travel until right again median %s m, max %s m' % (
                  os.path.basename(args.map), n, min(r[3] for r in kidnaps),
                  max(r[3] for r in kidnaps), args.kidnap_travel,
                  sum(r[0] for r in kidnaps), n, sum(r[1] for r in kidnaps),
                  sum(1 for r in kidnaps if r[1]),
                  sum(1 for r in kidnaps if r[2] is not None and r[2] <= 10.0), n,
                  '%.1f' % firsts[len(firsts) // 2] if firsts else '-',
                  '%.1f' % firsts[-1] if firsts else '-'), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
