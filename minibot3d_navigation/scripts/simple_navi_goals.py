#!/usr/bin/env python3
"""Send one navigation goal to move_base and wait for the result.

The seed's goal client, kept word for word where users see it:

    rosrun minibot3d_navigation simple_navi_goals.py X W

sends position.x = X and orientation.w = W in frame base_link (so "1 1" means
"one metre ahead, keep the heading"), logging "Set X = ...", "Set W = ...",
"Waiting for server" and "Sending Goals".  Beyond the seed it waits for the
result, prints the final state and the time taken, and exits 0 only when the
goal SUCCEEDED (1 otherwise, 2 on bad arguments).

    simple_navi_goals.py --frame map X Y YAW [--timeout S] [--server move_base]

sends a goal at (X, Y) with heading YAW (radians) in the named frame.

Under lock-step time (/use_lockstep, see minibot3d_lockstep) it is a participant: it waits for
the server and the result on sim time that moves only when it is done looking, so a route of
goals gives the same times in every run.
"""
import argparse
import math
import sys
import time

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal

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
    return args


def make_goal(args):
    goal = MoveBaseGoal()
    pose = goal.target_pose.pose
    if args.frame is None:
        x, w = args.values
        rospy.loginfo('Set X = %s', x)
        rospy.loginfo('Set W = %s', w)
        goal.target_pose.header.frame_id = 'base_link'
        pose.position.x = x
        pose.orientation.w = w
    else:
        x, y, yaw = args.values
        rospy.loginfo('Set X = %s, Y = %s, YAW = %s in frame %s', x, y, yaw, args.frame)
        goal.target_pose.header.frame_id = args.frame
        pose.position.x = x
        pose.position.y = y
        pose.orientation.z = math.sin(yaw / 2.0)
        pose.orientation.w = math.cos(yaw / 2.0)
    return goal


def main():
    args = parse_args(rospy.myargv(argv=sys.argv)[1:])
    rospy.init_node('simple_navi_goals')
    goal = make_goal(args)
    client = actionlib.SimpleActionClient(args.server, MoveBaseAction)
    lockstep = Participant(wake_topics=[args.server.rstrip('/') + '/result',
                                        args.server.rstrip('/') + '/status'])
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


if __name__ == '__main__':
    try:
        sys.exit(main())
    except rospy.ROSInterruptException:
        sys.exit(1)
