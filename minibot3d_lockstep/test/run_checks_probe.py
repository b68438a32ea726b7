#!/usr/bin/env python3
"""Processes of a run for test_run_checks.py, each a node on the master in ROS_MASTER_URI.

  run_checks_probe.py publish NODE CHILD STAMP
                                            node NODE publishes one transform odom -> CHILD
                                            stamped STAMP seconds on /tf, latched (every
                                            subscriber gets it on connecting), and stays up until
                                            stopped
  run_checks_probe.py listen ADDRESS        listens on ADDRESS (TCP, a port the kernel picks);
                                            prints "listening PORT", stays up until stopped
  run_checks_probe.py check MESSAGES        RunChecks, as a closed-loop rostest makes it; once
                                            MESSAGES messages have arrived on /tf (at most 30 s),
                                            prints one JSON line {"messages": N, "problems": [...]}
RunChecks counts the processes started by this one's parent (the test) as the run."""
import json
import signal
import socket
import sys

import rospy
from minibot3d_testing import WaitTimeout, wait_until


def publish(node, child, stamp):
    from geometry_msgs.msg import TransformStamped
    from tf2_msgs.msg import TFMessage
    rospy.init_node(node)
    t = TransformStamped()
    t.header.frame_id = 'odom'
    t.header.stamp = rospy.Time.from_sec(float(stamp))
    t.child_frame_id = child
    t.transform.rotation.w = 1.0
    pub = rospy.Publisher('/tf', TFMessage, queue_size=10, latch=True)
    pub.publish(TFMessage(transforms=[t]))
    rospy.spin()


def listen(address):
    family = socket.AF_INET6 if ':' in address else socket.AF_INET
    with socket.socket(family) as s:
        s.bind((address, 0))
        s.listen(1)
        print('listening %d' % s.getsockname()[1], flush=True)
        signal.pause()


def check(messages):
    from minibot3d_lockstep.run_checks import RunChecks
    rospy.init_node('run_checks_probe')
    checks = RunChecks()
    try:
        wait_until(lambda: checks.tf.messages >= messages, 30.0, '%d /tf messages' % messages)
    except WaitTimeout:
        pass  # problems() says what arrived
    print(json.dumps({'messages': checks.tf.messages, 'problems': checks.problems()}), flush=True)


if __name__ == '__main__':
    argv = rospy.myargv(sys.argv)
    {'publish': lambda: publish(argv[2], argv[3], argv[4]),
     'listen': lambda: listen(argv[2]),
     'check': lambda: check(int(argv[2]))}[argv[1]]()
