#!/usr/bin/env python3
"""Send one navigation goal to move_base and wait for the result.

The goal client users' scripts already call, its command line and log lines kept word for word:

    rosrun minibot3d_navigation simple_navi_goals.py X W

sends position.x = X and orientation.w = W in frame base_link (so "1 1" means
"one metre ahead, keep the heading"), logging "Set X = ...", "Set W = ...",
"Waiting for server" and "Sending Goals".  It also waits for the
result, prints the final state and the time taken, and exits 0 only when the
goal SUCCEEDED (1 otherwise, 2 on bad arguments).

    simple_navi_goals.py --frame map X Y YAW [--timeout S] [--server move_base]

sends a goal at (X, Y) with heading YAW (radians) in the named frame.

    simple_navi_goals.py --frame map X Y YAW --wait-for-fix S [--wander-for-fix M_S | --spin-for-fix RAD_S]

first waits, at most S seconds of ROS time, for a confident fix from amcl (not a fixed number of
turns): amcl's own claim on amcl/confidence (the scan explained at the estimate, one
mode, evidence gathered over motion) and an amcl_pose covariance with cov_xx + cov_yy under
--fix-covariance (0.05 m^2, make demo's threshold), both from messages received after the wait
began.  amcl earns evidence from new views, so the robot has to move while it waits: with
--wander-for-fix it wanders at up to M_S m/s (minibot3d_navigation.wanderer: ahead where the laser
shows room, turning away where not), with --spin-for-fix it turns on the spot at RAD_S, which brings
new views only to a laser with a blind sector (a turn shows a laser that sees all round, such as
minibot3d's, the same scan rotated: amcl counts no evidence from it).  Either stops before the goal
is sent.  With --global-localization it first calls amcl's
global_localization service, so the wait is for a fix found from nothing.  Without a fix in time it
says what was missing and exits 1 without sending the goal.

Its topics are relative names (cmd_vel, scan, amcl_pose, amcl/confidence): a robot whose drive
and laser use others gets them as ROS remappings, as the launch files' cmd_vel_topic and
scan_topic do for move_base, e.g.  cmd_vel:=mobile_base_controller/cmd_vel scan:=front_laser/scan.
--base-frame is amcl's base_frame_id.

In a robot's namespace (__ns:=NAME, or ROS_NAMESPACE) its topics are that robot's, and the frames
(base_link of the X W form, --frame, --base-frame) take the robot's frame_prefix, found from the
node's namespace upwards as the C++ nodes do (minibot3d_ros.frames): --frame odom is NAME/odom,
--frame map the shared map.

Under lock-step time (/use_lockstep, see minibot3d_lockstep) it is a participant: it waits for
the server and the result on sim time that moves only when it is done looking, so a route of
goals gives the same times in every run.
"""
import argparse
import math
import sys
import threading
import time

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float32MultiArray
from std_srvs.srv import Empty

from minibot3d_navigation.wanderer import Wanderer
from minibot3d_ros.frames import load_frame_names

STATE_NAMES = {getattr(GoalStatus, n): n for n in (
    'PENDING', 'ACTIVE', 'PREEMPTED', 'SUCCEEDED', 'ABORTED', 'REJECTED',
    'PREEMPTING', 'RECALLING', 'RECALLED', 'LOST')}



def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog='simple_navi_goals.py',
        description='Send a move_base goal and wait for the result.')
    parser.add_argument('--frame', metavar='FRAME',
                        help='goal frame; then the values are X Y YAW (radians)')
    parser.add_argument('--timeout', type=float, default=0.0, metavar='S',
                        help='give up (and cancel the goal) after S seconds of ROS time; '
                             '0 waits forever (default)')
    parser.add_argument('--server', default='move_base', help='action server name')
    parser.add_argument('--wait-for-fix', type=float, default=0.0, metavar='S',
                        help='before sending the goal, wait at most S seconds of ROS time for a '
                             'confident amcl fix; 0 does not wait (default)')
    parser.add_argument('--fix-covariance', type=float, default=0.05, metavar='M2',
                        help='a fix needs cov_xx + cov_yy of amcl_pose under this (m^2; '
                             'default 0.05, as make demo)')
    parser.add_argument('--spin-for-fix', type=float, default=0.0, metavar='RAD_S',
                        help='turn on the spot at RAD_S (cmd_vel) while waiting for the fix; '
                             'new views only for a laser with a blind sector')
    parser.add_argument('--wander-for-fix', type=float, default=0.0, metavar='M_S',
                        help='wander (cmd_vel) at up to M_S m/s while waiting for the fix: ahead '
                             'where the laser (scan) shows room, turning away where not')
    parser.add_argument('--base-frame', default='base_footprint',
                        help='the robot frame the laser is mounted on (tf), for --wander-for-fix')
    parser.add_argument('--global-localization', action='store_true',
                        help="call amcl's global_localization service before waiting for the fix")
    parser.add_argument('values', nargs='+', type=float,
                        help='X W (seed form, frame base_link) or, with --frame, X Y YAW')
    args = parser.parse_args(argv)
    if args.frame is None and len(args.values) != 2:
        parser.error('expected X W (or --frame FRAME X Y YAW), got %d values' % len(args.values))
    if args.frame is not None and len(args.values) != 3:
        parser.error('with --frame, expected X Y YAW, got %d values' % len(args.values))
    if not all(math.isfinite(v) for v in args.values):
        parser.error('goal values must be finite numbers')
    if args.timeout < 0.0:
        parser.error('--timeout must be >= 0')
    if not math.isfinite(args.wait_for_fix) or args.wait_for_fix < 0.0:
        parser.error('--wait-for-fix must be a finite number of seconds >= 0')
    if not math.isfinite(args.fix_covariance) or args.fix_covariance <= 0.0:
        parser.error('--fix-covariance must be a finite number > 0 (m^2)')
    if not math.isfinite(args.spin_for_fix) or abs(args.spin_for_fix) > 2.0:
        parser.error('--spin-for-fix must be a yaw rate in [-2, 2] rad/s')
    if not math.isfinite(args.wander_for_fix) or not 0.0 <= args.wander_for_fix <= 1.0:
        parser.error('--wander-for-fix must be a speed in [0, 1] m/s')
    if args.wander_for_fix and args.spin_for_fix:
        parser.error('--wander-for-fix and --spin-for-fix: choose one')
    if (args.spin_for_fix or args.wander_for_fix or args.global_localization) and \
            not args.wait_for_fix:
        parser.error('--spin-for-fix, --wander-for-fix and --global-localization need '
                     '--wait-for-fix S')
    return args


def fix_problems(cov_xy, confidence, max_cov):
    """What keeps amcl's estimate from being a confident fix (an empty list: it is one).
    cov_xy: cov_xx + cov_yy of the latest amcl_pose; confidence: the latest amcl/confidence data
    (explained_fraction, modes, confident, evidence_updates, beams_used, constraint); None: not
    received."""
    if cov_xy is None or confidence is None:
        return ['no %s received since the wait began' % ' or '.join(
            n for n, v in (('amcl_pose', cov_xy), ('amcl/confidence', confidence)) if v is None)]
    missing = []
    if len(confidence) < 3 or confidence[2] < 0.5:
        detail = ''
        if len(confidence) >= 5:
            detail = ' (explained fraction %.2f of %d beams, %d modes, %d evidence updates)' % (
                confidence[0], confidence[4], confidence[1], confidence[3])
        missing.append('amcl not confident%s' % detail)
    if not cov_xy < max_cov:
        missing.append('covariance cov_xx+cov_yy %.3g m^2 >= %g' % (cov_xy, max_cov))
    return missing


class FixWatch(object):
    """The latest amcl_pose covariance and amcl/confidence, from after its creation."""

    def __init__(self):
        self.cov_xy = None
        self.confidence = None
        self._subs = [rospy.Subscriber('amcl_pose', PoseWithCovarianceStamped, self._on_pose),
                      rospy.Subscriber('amcl/confidence', Float32MultiArray, self._on_confidence)]

    def _on_pose(self, m):
        self.cov_xy = m.pose.covariance[0] + m.pose.covariance[7]

    def _on_confidence(self, m):
        self.confidence = list(m.data)

    def reset(self):
        self.cov_xy = self.confidence = None

    def problems(self, max_cov):
        return fix_problems(self.cov_xy, self.confidence, max_cov)


class ScanWatch(object):
    """The latest scan and the yaw of its laser on base_frame (from tf), for the wanderer."""

    def __init__(self, base_frame):
        import tf2_ros  # only when wandering
        self.base_frame = base_frame
        self.buffer = tf2_ros.Buffer()
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.lock = threading.Lock()
        self.scan = None
        self.laser_yaw = None
        self.error = ''
        self.sub = rospy.Subscriber('scan', LaserScan, self._on_scan, queue_size=1)

    def _on_scan(self, m):
        import tf2_ros
        yaw = self.laser_yaw
        if yaw is None:
            try:
                t = self.buffer.lookup_transform(self.base_frame, m.header.frame_id, rospy.Time(0))
                q = t.transform.rotation
                yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                    tf2_ros.ExtrapolationException) as e:
                with self.lock:
                    self.error = 'no tf from %s to the scan frame %s yet (%s)' % (
                        self.base_frame, m.header.frame_id, e)
                return
        with self.lock:
            self.scan, self.laser_yaw, self.error = m, yaw, ''

    def latest(self):
        with self.lock:
            return self.scan, self.laser_yaw


def make_goal(args, frames):
    goal = MoveBaseGoal()
    pose = goal.target_pose.pose
    if args.frame is None:
        x, w = args.values
        rospy.loginfo('Set X = %s', x)
        rospy.loginfo('Set W = %s', w)
        goal.target_pose.header.frame_id = frames.resolve('base_link')
        pose.position.x = x
        pose.orientation.w = w
    else:
        x, y, yaw = args.values
        frame = frames.resolve(args.frame)
        rospy.loginfo('Set X = %s, Y = %s, YAW = %s in frame %s', x, y, yaw, frame)
        goal.target_pose.header.frame_id = frame
        pose.position.x = x
        pose.position.y = y
        pose.orientation.z = math.sin(yaw / 2.0)
        pose.orientation.w = math.cos(yaw / 2.0)
    return goal


def main():
    args = parse_args(rospy.myargv(argv=sys.argv)[1:])
    rospy.init_node('simple_navi_goals')
    try:
        frames = load_frame_names()
    except ValueError as e:
        rospy.logerr('simple_navi_goals.py: bad parameter %s', e)
        return 2
    goal = make_goal(args, frames)
    client = actionlib.SimpleActionClient(args.server, MoveBaseAction)
    wake = [args.server.rstrip('/') + '/result', args.server.rstrip('/') + '/status']
    if args.wait_for_fix:
        args.fix_watch = FixWatch()
        moving = args.spin_for_fix or args.wander_for_fix
        args.cmd_pub = rospy.Publisher('cmd_vel', Twist, queue_size=1) if moving else None
        args.scan_watch = ScanWatch(frames.resolve(args.base_frame)) if args.wander_for_fix \
            else None
        wake += ['amcl_pose', 'amcl/confidence']
    lockstep = Participant(wake_topics=wake)
    try:
        return run(args, goal, client, lockstep)
    finally:
        lockstep.close()  # leave the loop at the sim time the result came


def run(args, goal, client, lockstep):
    rospy.loginfo('Waiting for server')
    if not lockstep.wait_for(lambda: action_server_ready(client), args.timeout):
        rospy.logerr('No action server %s within %.1f s: is move_base running?',
                     args.server, args.timeout)
        return 1
    if args.wait_for_fix and not wait_for_fix(args, lockstep):
        return 1
    goal.target_pose.header.stamp = rospy.Time.now()
    rospy.loginfo('Sending Goals')
    start_ros, start_wall = rospy.Time.now(), time.time()
    client.send_goal(goal)
    finished = lockstep.wait_for(lambda: client.simple_state == actionlib.SimpleGoalState.DONE,
                                 args.timeout)
    elapsed_ros = (rospy.Time.now() - start_ros).to_sec()
    elapsed_wall = time.time() - start_wall
    if not finished:
        client.cancel_goal()
        rospy.logerr('Goal not reached within --timeout %.1f s; cancelled it', args.timeout)
        return 1
    state = client.get_state()
    text = client.get_goal_status_text()
    name = STATE_NAMES.get(state, str(state))
    log = rospy.loginfo if state == GoalStatus.SUCCEEDED else rospy.logerr
    log('Result: %s%s after %.2f s (%.2f s wall)', name, (' (%s)' % text) if text else '',
        elapsed_ros, elapsed_wall)
    return 0 if state == GoalStatus.SUCCEEDED else 1


def wait_for_fix(args, lockstep):
    """Waits for a confident fix (see the module doc); True when there is one."""
    watch = args.fix_watch
    if args.global_localization:
        rospy.loginfo('Calling global_localization')
        try:
            rospy.wait_for_service('global_localization', 30.0)
            rospy.ServiceProxy('global_localization', Empty)()
        except (rospy.ROSException, rospy.ServiceException) as e:
            rospy.logerr('global_localization failed: %s (is amcl running?)', e)
            return False
    watch.reset()  # a fix must come from estimates made after this point
    rospy.loginfo('Waiting for a confident fix (at most %.1f s)', args.wait_for_fix)
    start = rospy.Time.now()
    spinning = [args.cmd_pub is not None]
    if spinning[0]:
        wanderer = None
        if args.wander_for_fix:
            wanderer = Wanderer(speed=args.wander_for_fix)

        def command():
            cmd = Twist()
            if wanderer is None:
                cmd.angular.z = args.spin_for_fix
            else:  # stands still until the first scan and the laser's mounting are known
                scan, laser_yaw = args.scan_watch.latest()
                if scan is not None:
                    wanderer.laser_yaw = laser_yaw
                    cmd.linear.x, cmd.angular.z = wanderer.command(scan)
            return cmd

        # At 10 Hz of sim time while waiting (the job stays, idle, once the wait is over).
        lockstep.add_periodic(0.1, lambda now: args.cmd_pub.publish(command())
                              if spinning[0] else None)
        args.cmd_pub.publish(command())
    ok = lockstep.wait_for(lambda: not watch.problems(args.fix_covariance), args.wait_for_fix)
    if spinning[0]:
        spinning[0] = False
        args.cmd_pub.publish(Twist())
    if args.scan_watch is not None and args.scan_watch.error:
        rospy.logerr('--wander-for-fix: %s', args.scan_watch.error)
    waited = (rospy.Time.now() - start).to_sec()
    if not ok:
        rospy.logerr('No confident fix within --wait-for-fix %.1f s: %s', args.wait_for_fix,
                     '; '.join(watch.problems(args.fix_covariance)))
        return False
    rospy.loginfo('Confident fix after %.1f s (cov_xx+cov_yy %.3g m^2)', waited, watch.cov_xy)
    return True


if __name__ == '__main__':
    try:
        sys.exit(main())
    except rospy.ROSInterruptException:
        sys.exit(1)
