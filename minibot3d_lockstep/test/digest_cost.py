#!/usr/bin/env python3
"""make bench: what recording the lock-step digest costs. The closed loop of
test_lockstep_loop.py (simulator, amcl, move_base and a goal client on lock-step time at
real-time factor 0, two goals across the default world) is run RUNS times with the digest and
RUNS times without, alternately; printed: each run's wall time from the client's start to its
last result, and the median with the digest against the median without.

  digest_cost.py [RUNS]"""
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_lockstep_loop as loop  # noqa: E402


def one_run(digest_on):
    tmp = Path(tempfile.mkdtemp(prefix='digest_cost_'))
    stack = loop.Stack(tmp, ['minibot3d_navigation', 'amcl_navigation.launch'],
                       ['lockstep:=true', 'real_time_factor:=0',
                        'lockstep_participants:=/amcl /move_base /probe_route'],
                       digest=str(tmp / 'digest') if digest_on else None)
    try:
        start = time.monotonic()
        client = stack.probe('route', str(tmp / 'route.json'))
        if client.wait(300) != 0:
            raise RuntimeError('the route failed:\n' + client.stdout.read() + stack.log(3000))
        return time.monotonic() - start
    finally:
        stack.stop()


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    walls = {True: [], False: []}
    for k in range(runs):
        for on in (False, True):
            walls[on].append(one_run(on))
            print('  run %d, digest %s: %.2f s wall' % (k + 1, 'on ' if on else 'off',
                                                       walls[on][-1]), flush=True)
    off, on = statistics.median(walls[False]), statistics.median(walls[True])
    print('digest cost: median %.2f s wall with the digest, %.2f s without: %+.1f %%'
          % (on, off, 100.0 * (on - off) / off), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
