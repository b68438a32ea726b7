"""The master of a shell script's run (tools/ros_env.sh's ros_start_core and ros_stop_core).

  python3 -m minibot3d_testing start-core [--log-dir DIR]
      starts rosmaster and rosout as RosCore does (on a port no other process holds) and leaves
      them running; prints one line: the master's URI, then the process group of each.
  python3 -m minibot3d_testing stop PGID...
      stops those process groups: SIGINT, SIGKILL to what is left after --grace seconds."""
import argparse
import shutil
import sys
import tempfile

from minibot3d_testing import CoreError, RosCore, stop_group


def main(argv=None):
    ap = argparse.ArgumentParser(prog='python3 -m minibot3d_testing', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest='command', required=True)
    start = sub.add_parser('start-core', help='start rosmaster and rosout; print URI and groups')
    start.add_argument('--log-dir', help="rosmaster's and rosout's output (default: discarded "
                                         "with a temporary directory)")
    start.add_argument('--timeout', type=float, default=60.0)
    stop = sub.add_parser('stop', help='stop process groups')
    stop.add_argument('pgids', type=int, nargs='+')
    stop.add_argument('--grace', type=float, default=10.0)
    args = ap.parse_args(argv)

    if args.command == 'start-core':
        # RosCore reads rosmaster's output while it starts. The processes outlive this command,
        # so a temporary directory for it is removed here: they write on to the unlinked files.
        log_dir = args.log_dir or tempfile.mkdtemp(prefix='roscore_')
        try:
            core = RosCore(log_dir=log_dir, timeout=args.timeout).start()
        except CoreError as e:
            print('minibot3d_testing: %s' % e, file=sys.stderr)
            return 1
        finally:
            if not args.log_dir:
                shutil.rmtree(log_dir, ignore_errors=True)
        print(' '.join([core.uri] + [str(p.pid) for p in core.processes]))
        return 0
    gone = [stop_group(pgid, args.grace) for pgid in args.pgids]
    return 0 if all(gone) else 1


if __name__ == '__main__':
    sys.exit(main())
