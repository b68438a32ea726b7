#!/usr/bin/env python3
"""A rospy node that only listens (it does not take part in lock-step): how far its sim clock
(rospy.Time.now(), driven by /clock) lags behind the messages it receives, and how many /clock
messages per wall second reach it. For make bench (tools/bench/lockstep_bench.sh).

  clock_listener_bench.py LABEL --seconds WALL_S
Prints: LABEL: /clock N msgs/wall s, sim rate Xx real time, lag of rospy.Time.now() behind
/ground_truth/odom stamps: median A ms, p99 B ms, max C ms (over K messages)."""
import argparse
import sys
import threading
import time

import rospy
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('label')
    parser.add_argument('--seconds', type=float, default=10.0)
    args = parser.parse_args(rospy.myargv()[1:])
    rospy.init_node('clock_listener_bench', anonymous=True)
    lock = threading.Lock()
    lags, clocks = [], [0]

    def on_truth(m):
        lag = (m.header.stamp - rospy.Time.now()).to_sec()
        with lock:
            lags.append(lag)

    def on_clock(_):
        with lock:
            clocks[0] += 1

    rospy.Subscriber('/ground_truth/odom', Odometry, on_truth, queue_size=1000)
    rospy.Subscriber('/clock', Clock, on_clock, queue_size=1000)
    deadline = time.time() + 60
    while rospy.Time.now().is_zero() and time.time() < deadline:
        time.sleep(0.01)  # waiting for the first /clock (rospy has no event for it)
    with lock:
        lags.clear()
        clocks[0] = 0
    sim0, wall0 = rospy.Time.now().to_sec(), time.time()
    time.sleep(args.seconds)  # the measurement window itself
    sim1, wall1 = rospy.Time.now().to_sec(), time.time()
    with lock:
        data = sorted(lags)
        n_clock = clocks[0]
    wall = wall1 - wall0
    if not data:
        print('%s: no /ground_truth/odom received' % args.label)
        return 1
    med = data[len(data) // 2]
    p99 = data[min(len(data) - 1, int(0.99 * len(data)))]
    rate = (sim1 - sim0) / wall
    # A lag of L s of sim time at R x real time is L / R s of wall time: how late the node's /clock
    # thread ran (rospy's threads share the GIL, which changes hands every 5 ms by default).
    print('%s: /clock %.0f msgs/wall s, sim rate %.1fx real time, lag of rospy.Time.now() behind '
          '/ground_truth/odom stamps: median %.1f ms, p99 %.1f ms, max %.1f ms of sim time '
          '(p99 %.1f ms of wall time; over %d messages)'
          % (args.label, n_clock / wall, rate, 1000 * med, 1000 * p99, 1000 * data[-1],
             1000 * p99 / rate if rate > 0 else float('nan'), len(data)), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
