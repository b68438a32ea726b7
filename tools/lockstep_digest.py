#!/usr/bin/env python3
"""Finds where two lock-step runs part: the first tick, node, topic and peer whose messages differ.

  lockstep_digest.py compare DIR_A DIR_B [--ignore TOPIC ...] [--all-nodes] [--until SIM_S]
      compares two runs' digests (directories written with MINIBOT3D_LOCKSTEP_DIGEST=DIR), up to
      sim time SIM_S if given; exit status 0 when they agree tick for tick, 1 when they differ.
  lockstep_digest.py run [--out DIR] [--busy N] [--second K=V ...] -- COMMAND [ARG ...]
      runs COMMAND twice, the first time with MINIBOT3D_LOCKSTEP_DIGEST=DIR/a, the second with
      DIR/b, N busy processes beside it (CPU load) and the environment variables K=V added (say
      DEMO_REAL_TIME_FACTOR=1), then compares the two. COMMAND's output goes to DIR/a.log and
      DIR/b.log. Exit status as compare's (2 if a run of COMMAND failed; compared all the same).

A digest records, for every participant (and the simulator) and every tick, the CRC of every
message it received and the count of every message it sent; see docs/lockstep.md. Examples:

  tools/lockstep_digest.py run --out /tmp/dg --busy 2 -- tools/demo.sh
  MINIBOT3D_LOCKSTEP_DIGEST=/tmp/a make demo; MINIBOT3D_LOCKSTEP_DIGEST=/tmp/b make demo
  tools/lockstep_digest.py compare /tmp/a /tmp/b
"""
import argparse
import importlib.util
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def _load_digest():
    """minibot3d_lockstep/digest.py from this tree, alone: it needs nothing of ROS."""
    path = os.path.join(HERE, '..', 'minibot3d_lockstep', 'src', 'minibot3d_lockstep', 'digest.py')
    spec = importlib.util.spec_from_file_location('minibot3d_lockstep_digest', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


digest = _load_digest()


def start_busy(n):
    """n processes that keep a core each busy (plain Python loops)."""
    return [subprocess.Popen([sys.executable, '-c', 'while True: pass']) for _ in range(n)]


def run_once(command, directory, extra_env, log_path, busy):
    if os.path.exists(directory):
        shutil.rmtree(directory)
    os.makedirs(directory)
    env = dict(os.environ, **extra_env)
    env[digest.DIGEST_ENV] = os.path.abspath(directory)
    load = start_busy(busy)
    try:
        with open(log_path, 'w') as log:
            return subprocess.call(command, env=env, stdout=log, stderr=subprocess.STDOUT)
    finally:
        for p in load:
            p.kill()
            p.wait()


def compare(dir_a, dir_b, ignored, all_nodes, until=None):
    try:
        result = digest.compare(dir_a, dir_b, ignored=ignored, all_nodes=all_nodes, until=until)
    except ValueError as e:
        print('lockstep_digest: %s' % e, file=sys.stderr)
        return 2
    print('\n'.join(digest.report(result, dir_a, dir_b)))
    return 0 if result.identical else 1


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    sub = parser.add_subparsers(dest='cmd', required=True)
    ignore_help = ('a topic to leave out (repeatable; added to the defaults: %s)'
                   % ', '.join(digest.DEFAULT_IGNORED))
    c = sub.add_parser('compare', help='compare two digest directories')
    c.add_argument('a')
    c.add_argument('b')
    c.add_argument('--ignore', action='append', default=[], help=ignore_help)
    c.add_argument('--all-nodes', action='store_true',
                   help='also compare messages from and to nodes without a digest')
    c.add_argument('--until', type=float, metavar='SIM_S',
                   help='compare ticks up to this sim time only (say, where a test stopped)')
    r = sub.add_parser('run', help='run a command twice and compare')
    r.add_argument('--out', default='build/lockstep_digest', help='where the runs go')
    r.add_argument('--busy', type=int, default=0, metavar='N',
                   help='busy processes beside the second run')
    r.add_argument('--second', action='append', default=[], metavar='K=V',
                   help='an environment variable for the second run only')
    r.add_argument('--ignore', action='append', default=[], help=ignore_help)
    r.add_argument('--all-nodes', action='store_true')
    r.add_argument('command', nargs=argparse.REMAINDER)
    args = parser.parse_args(argv)
    ignored = tuple(digest.DEFAULT_IGNORED) + tuple(args.ignore)
    if args.cmd == 'compare':
        return compare(args.a, args.b, ignored, args.all_nodes, args.until)
    command = args.command[1:] if args.command[:1] == ['--'] else args.command
    if not command:
        parser.error('run: give the command after --')
    second = {}
    for kv in args.second:
        k, sep, v = kv.partition('=')
        if not sep or not k:
            parser.error('--second takes K=V, got %r' % kv)
        second[k] = v
    if args.busy < 0:
        parser.error('--busy must be >= 0')
    dir_a, dir_b = os.path.join(args.out, 'a'), os.path.join(args.out, 'b')
    print('lockstep_digest: run a: %s (log %s.log)' % (' '.join(command), dir_a), flush=True)
    rc_a = run_once(command, dir_a, {}, dir_a + '.log', 0)
    print('lockstep_digest: run b%s%s (log %s.log)' % (
        ' beside %d busy processes' % args.busy if args.busy else '',
        ' with ' + ' '.join(args.second) if args.second else '', dir_b), flush=True)
    rc_b = run_once(command, dir_b, second, dir_b + '.log', args.busy)
    rc = compare(dir_a, dir_b, ignored, args.all_nodes)
    if rc_a or rc_b:
        print('lockstep_digest: the command exited with %d (run a) and %d (run b)' % (rc_a, rc_b))
        return 2
    return rc


if __name__ == '__main__':
    sys.exit(main())
