#!/usr/bin/env python3
"""Test helper for test_teleop_pty.py (not a test itself): subscribes to a Twist topic and prints
one JSON object per line, flushed at once:

  {"linear": x, "angular": z, "other": [linear.y, linear.z, angular.x, angular.y]}

  twist_recorder.py TOPIC

Runs until stdin is closed. Runs as its own process so that the test process never calls
rospy.init_node (which can only happen once per process, with one master)."""
import json
import sys
import threading

import rospy
from geometry_msgs.msg import Twist

_lock = threading.Lock()


def emit(obj):
    with _lock:
        sys.stdout.write(json.dumps(obj) + '\n')
        sys.stdout.flush()


def main():
    topic = sys.argv[1]
    rospy.init_node('twist_recorder', anonymous=True, disable_signals=True)
    rospy.Subscriber(topic, Twist,
                           lambda msg: emit({'linear': msg.linear.x, 'angular': msg.angular.z,
                                             'other': [msg.linear.y, msg.linear.z,
                                                       msg.angular.x, msg.angular.y]}),
                           queue_size=1000)
    sys.stdin.read()  # until the test closes our stdin
    rospy.signal_shutdown('stdin closed')


if __name__ == '__main__':
    main()
