#!/usr/bin/env python3
"""What test_fleet_robots_stacks.py checks, seen from inside the running system: for each NAME
given, the map -> NAME/base_footprint transform (amcl's map -> NAME/odom on top of the robot's
odometry), and the frame and lethal cells of NAME's local and global costmaps and footprint.
Prints one JSON line once it has all of them (or, after 90 s, what it has)."""
import json
import sys
import time

import rospy
import tf2_ros
from geometry_msgs.msg import PolygonStamped
from nav_msgs.msg import OccupancyGrid


def main():
    names = rospy.myargv(argv=sys.argv)[1:]
    rospy.init_node('fleet_probe')
    buffer = tf2_ros.Buffer()
    tf2_ros.TransformListener(buffer)
    seen = {}

    def keep(key):
        def on(msg):
            entry = {'frame': msg.header.frame_id}
            if isinstance(msg, OccupancyGrid):
                entry['lethal'] = sum(1 for v in msg.data if v == 100)
            seen[key] = entry
        return on
    subs = []
    for n in names:
        for what in ('local_costmap/costmap', 'global_costmap/costmap'):
            subs.append(rospy.Subscriber('/%s/move_base/%s' % (n, what), OccupancyGrid,
                                         keep(n + ' ' + what), queue_size=1))
        subs.append(rospy.Subscriber('/%s/move_base/local_costmap/footprint' % n, PolygonStamped,
                                     keep(n + ' footprint'), queue_size=1))
    out = {}
    deadline = time.time() + 90
    while time.time() < deadline and not rospy.is_shutdown():
        for n in names:
            try:
                t = buffer.lookup_transform('map', n + '/base_footprint', rospy.Time(0))
                out[n + ' pose'] = [t.transform.translation.x, t.transform.translation.y]
            except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                    tf2_ros.ExtrapolationException):
                pass
        out.update(seen)
        local_lethal = all(out.get(n + ' local_costmap/costmap', {}).get('lethal') for n in names)
        if len(out) == 4 * len(names) and local_lethal:
            break
        time.sleep(0.2)
    print(json.dumps(out, sort_keys=True), flush=True)


if __name__ == '__main__':
    main()
