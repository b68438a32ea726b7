#!/usr/bin/env python3
"""Processes for test_sim_status.py, each a node on the master in ROS_MASTER_URI (wall time).

  sim_status_probe.py publish TOPIC        for each line "N" on stdin, publishes a
                                           minibot3d_sim/SimStatus stamped now with N collisions on
                                           TOPIC (latched, as the simulator does); prints
                                           "published N"
  sim_status_probe.py watch TOPIC BEFORE   a SimStatusWatch on TOPIC; once BEFORE statuses have
                                           arrived (at most 30 s), prints "ended" (the end of the
                                           run), then one JSON line: problems_at_end with a 2 s
                                           limit"""
import json
import sys

import rospy
from minibot3d_testing import WaitTimeout, wait_until
from minibot3d_testing.sim_status import SimStatusWatch


class WallWait(object):
    """wait_for as the lock-step Participant has it, when lock-step is off."""

    def wait_for(self, predicate, timeout, poll=None):
        try:
            return wait_until(predicate, timeout, 'the condition', interval=poll or 0.05)
        except WaitTimeout:
            return False


def publish(topic):
    from minibot3d_sim.msg import SimStatus
    rospy.init_node('status_publisher')
    pub = rospy.Publisher(topic, SimStatus, queue_size=10, latch=True)
    for line in sys.stdin:
        s = SimStatus()
        s.header.stamp = rospy.Time.now()
        s.collisions = int(line)
        pub.publish(s)
        print('published %d' % s.collisions, flush=True)
    rospy.spin()


def watch(topic, before):
    rospy.init_node('status_watch')
    status = SimStatusWatch(topic)
    WallWait().wait_for(lambda: status.messages >= before, 30.0)
    end = rospy.get_rostime()
    print('ended', flush=True)
    print(json.dumps(status.problems_at_end(WallWait(), 2.0, end)), flush=True)


if __name__ == '__main__':
    argv = rospy.myargv(sys.argv)
    if argv[1] == 'publish':
        publish(argv[2])
    else:
        watch(argv[2], int(argv[3]))
