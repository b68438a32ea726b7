#!/usr/bin/env python3
"""Measures a running minibot3d_sim's real-time factor from its ~status: sim seconds advanced per
wall second between a status message after --warmup sim seconds and one --span sim seconds later.

  measure_node_rtf.py LABEL [--warmup 5] [--span 60] [--timeout 120]
"""
import argparse
import sys
import threading
import time

import rospy

from minibot3d_sim.msg import SimStatus


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('label')
    parser.add_argument('--warmup', type=float, default=5.0)
    parser.add_argument('--span', type=float, default=60.0)
    parser.add_argument('--timeout', type=float, default=120.0)
    args = parser.parse_args()
    rospy.init_node('measure_node_rtf', anonymous=True, disable_signals=True)
    cond = threading.Condition()
    samples = []  # (wall time, status)

    def on_status(msg):
        with cond:
            samples.append((time.monotonic(), msg))
            cond.notify_all()

    rospy.Subscriber('/minibot3d_sim/status', SimStatus, on_status, queue_size=100)
    with cond:
        ok = cond.wait_for(lambda: samples and samples[-1][1].sim_time >= args.warmup,
                           timeout=args.timeout)
        if not ok:
            print('%s: no status from the simulator' % args.label)
            return 1
        w0, s0 = samples[-1]
        ok = cond.wait_for(lambda: samples[-1][1].sim_time >= s0.sim_time + args.span,
                           timeout=args.timeout)
        w1, s1 = samples[-1]
    sim = s1.sim_time - s0.sim_time
    print('%s node_real_time_factor=%.0f (%.0f s of sim in %.2f s wall) collisions=%d%s'
          % (args.label, sim / (w1 - w0), sim, w1 - w0, s1.collisions,
             '' if ok else ' (timed out before the full span)'))
    return 0


if __name__ == '__main__':
    sys.exit(main())
