#!/usr/bin/env python3
"""For test_frames.py: a rospy node that resolves the frames given on its command line with
minibot3d_ros.frames.load_frame_names (run it in a namespace with __ns:=NAME). Prints
"FRAME -> RESOLVED" per frame, or "error: WHY" and exits 2 when a parameter is refused."""
import sys

import rospy

from minibot3d_ros.frames import load_frame_names


def main():
    frames = rospy.myargv(argv=sys.argv)[1:]
    rospy.init_node('frames_probe')
    try:
        names = load_frame_names()
    except ValueError as e:
        print('error: %s' % e, flush=True)
        return 2
    for f in frames:
        print('%s -> %s' % (f, names.resolve(f)), flush=True)
    return 0


if __name__ == '__main__':
    sys.exit(main())
