#!/usr/bin/env python3
"""Test participant for test_lockstep_loop.py.

  lockstep_probe.py hold HOLD_S          joins, lets 0.5 s of sim time pass, then works for HOLD_S
                                         wall seconds in one tick; prints the sim time before and
                                         after ("held T0 T1"), then lets 0.5 s more pass ("after T")
  lockstep_probe.py latch_pub            joins, lets 0.5 s of sim time pass, then advertises a new
                                         latched topic /probe_latched and publishes its sim time
                                         on it at once ("published T")
  lockstep_probe.py latch_sub            waits for /probe_latched (a wake topic); prints the sim
                                         time of the tick at which it first had it, and the
                                         message ("seen T DATA")
  lockstep_probe.py poll                 waits, with poll=0.1 and no wake topic, until
                                         /ground_truth/odom has a stamp 1 s past its first tick;
                                         prints that target and the tick time ("polled T0 T")
  lockstep_probe.py run_for SIM_S        joins, lets SIM_S of sim time pass, prints "ran T" and
                                         leaves (holds sim time for a stack's participants, then
                                         lets go)
  lockstep_probe.py zigzag SIM_S         publishes probe_parent -> probe_zigzag on /tf every 10 ms
                                         of sim time for SIM_S, at x = +1 and -1 in turn (+1 at
                                         even hundredths of a second), then leaves
  lockstep_probe.py burst N             joins, lets 0.5 s of sim time pass, then publishes 1..N on
                                         /probe_burst (std_msgs/UInt32) in one tick through a
                                         publisher whose queue_size is 1 ("burst T"), lets 0.5 s
                                         more pass and leaves
  lockstep_probe.py burst_count          /probe_burst a wake topic: prints the sim time of the
                                         first tick with messages on it, how many and their sum
                                         ("counted T N SUM"), and leaves
  lockstep_probe.py route OUT.json [FRAME X,Y,YAW ...]
                                         move_base goals one after the other (by default two
                                         across the default world, in map); writes the goal
                                         results, times and the whole true trajectory
Prints "holding" (flushed) when it starts working, so a test can kill it then."""
import json
import math
import os
import sys
import time

from minibot3d_lockstep import Participant, action_server_ready  # before rospy.init_node

import actionlib
import rospy
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from nav_msgs.msg import Odometry
from std_msgs.msg import Float64


def hold(seconds):
    lockstep = Participant()
    lockstep.sleep(0.5)
    t0 = rospy.get_rostime().to_sec()

    def work():
        print('holding', flush=True)
        time.sleep(seconds)  # the work itself: wall time spent inside one tick, on purpose
        return True
    lockstep.wait_for(work)
    t1 = rospy.get_rostime().to_sec()
    print('held %.3f %.3f' % (t0, t1), flush=True)
    lockstep.sleep(0.5)
    print('after %.3f' % rospy.get_rostime().to_sec(), flush=True)
    lockstep.close()


def latch_pub():
    lockstep = Participant()
    lockstep.sleep(0.5)
    t = rospy.get_rostime().to_sec()
    pub = rospy.Publisher('/probe_latched', Float64, queue_size=1, latch=True)
    pub.publish(Float64(t))  # before any subscriber has connected to this new publisher
    print('published %.3f' % t, flush=True)
    lockstep.sleep(0.5)
    lockstep.close()


def latch_sub():
    got = []
    rospy.Subscriber('/probe_latched', Float64, lambda m: got.append(m.data), queue_size=1)
    lockstep = Participant(wake_topics=['/probe_latched'])
    if lockstep.wait_for(lambda: got, 30.0):
        print('seen %.3f %.3f' % (rospy.get_rostime().to_sec(), got[0]), flush=True)
    lockstep.close()


def poll():
    stamps = []
    rospy.Subscriber('/ground_truth/odom', Odometry,
                     lambda m: stamps.append(m.header.stamp.to_sec()), queue_size=1000)
    lockstep = Participant()  # after the subscriber: the first messages reach it
    if not lockstep.wait_for(lambda: stamps, 30.0, poll=0.1):
        print('no /ground_truth/odom', flush=True)
        return 1
    target = rospy.get_rostime().to_sec() + 1.0
    if lockstep.wait_for(lambda: stamps[-1] >= target - 1e-9, 30.0, poll=0.1):
        print('polled %.3f %.3f' % (target, rospy.get_rostime().to_sec()), flush=True)
    lockstep.close()
    return 0


def run_for(seconds):
    lockstep = Participant()
    lockstep.sleep(seconds)
    print('ran %.3f' % rospy.get_rostime().to_sec(), flush=True)
    lockstep.close()


def zigzag(seconds):
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage
    pub = rospy.Publisher('/tf', TFMessage, queue_size=1000)
    lockstep = Participant()

    def send(now):
        t = TransformStamped()
        t.header.frame_id, t.header.stamp, t.child_frame_id = 'probe_parent', now, 'probe_zigzag'
        t.transform.translation.x = 1.0 if round(now.to_sec() * 100) % 2 == 0 else -1.0
        t.transform.rotation.w = 1.0
        pub.publish(TFMessage(transforms=[t]))
    lockstep.add_periodic(0.01, send)
    lockstep.sleep(seconds)
    print('zigzag done %.3f' % rospy.get_rostime().to_sec(), flush=True)
    lockstep.close()


def burst(n):
    from std_msgs.msg import UInt32
    pub = rospy.Publisher('/probe_burst', UInt32, queue_size=1)
    lockstep = Participant()
    lockstep.sleep(0.5)
    for i in range(1, n + 1):
        pub.publish(UInt32(i))
    print('burst %.3f' % rospy.get_rostime().to_sec(), flush=True)
    lockstep.sleep(0.5)
    lockstep.close()


def burst_count():
    from std_msgs.msg import UInt32
    got = []
    rospy.Subscriber('/probe_burst', UInt32, lambda m: got.append(m.data), queue_size=1)
    lockstep = Participant(wake_topics=['/probe_burst'])
    if lockstep.wait_for(lambda: got, 60.0):
        print('counted %.3f %d %d' % (rospy.get_rostime().to_sec(), len(got), sum(got)),
              flush=True)
    lockstep.close()


DEFAULT_ROUTE = ('map', [(-2.1, 0.6, 1.57), (-0.3, 2.0, 0.0)])


def route(out, frame=DEFAULT_ROUTE[0], poses=DEFAULT_ROUTE[1]):
    path = []
    rospy.Subscriber('/ground_truth/odom', Odometry, lambda m: path.append(
        (m.header.stamp.to_sec(), m.pose.pose.position.x, m.pose.pose.position.y)),
        queue_size=1000)
    client = actionlib.SimpleActionClient('move_base', MoveBaseAction)
    lockstep = Participant(wake_topics=['move_base/result'])
    if not lockstep.wait_for(lambda: action_server_ready(client), 30.0):
        print('no move_base', flush=True)
        return 1
    goals = []
    for x, y, yaw in poses:
        g = MoveBaseGoal()
        g.target_pose.header.frame_id = frame
        g.target_pose.pose.position.x, g.target_pose.pose.position.y = x, y
        g.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
        g.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
        start = rospy.get_rostime()
        client.send_goal(g)
        lockstep.wait_for(lambda: client.simple_state == actionlib.SimpleGoalState.DONE, 120.0)
        goals.append((client.get_state(), (rospy.get_rostime() - start).to_sec()))
    trajectory = list(path)  # up to the last result: once this leaves, time runs on without it
    lockstep.close()
    tmp = out + '.tmp'
    with open(tmp, 'w') as f:
        json.dump({'goals': goals, 'path': trajectory}, f)
    os.replace(tmp, out)
    return 0


def main():
    mode = sys.argv[1]
    rospy.init_node('probe_' + mode)
    if mode == 'hold':
        hold(float(sys.argv[2]))
        return 0
    if mode == 'latch_pub':
        latch_pub()
        return 0
    if mode == 'latch_sub':
        latch_sub()
        return 0
    if mode == 'poll':
        return poll()
    if mode == 'zigzag':
        zigzag(float(sys.argv[2]))
        return 0
    if mode == 'burst':
        burst(int(sys.argv[2]))
        return 0
    if mode == 'burst_count':
        burst_count()
        return 0
    if mode == 'run_for':
        run_for(float(sys.argv[2]))
        return 0
    if len(sys.argv) > 3:
        return route(sys.argv[2], sys.argv[3],
                     [tuple(float(v) for v in p.split(',')) for p in sys.argv[4:]])
    return route(sys.argv[2])


if __name__ == '__main__':
    sys.exit(main())
