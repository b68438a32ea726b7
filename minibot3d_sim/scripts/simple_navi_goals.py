#!/usr/bin/env python3
"""`rosrun minibot3d_sim simple_navi_goals.py X W`, the classic tutorial's spelling: runs
minibot3d_navigation's simple_navi_goals.py with the same arguments (see that script). A real file rather than a link,
so it is installed and works from the install space as from the source tree."""
import os
import sys

import roslib.packages

try:
    found = roslib.packages.find_node('minibot3d_navigation', 'simple_navi_goals.py')
except Exception as e:  # rospkg.ResourceNotFound: the package is not on ROS_PACKAGE_PATH
    found = None
    reason = str(e)
else:
    reason = 'no simple_navi_goals.py in it'
if not found:
    sys.stderr.write('simple_navi_goals.py: cannot find minibot3d_navigation\'s '
                     'simple_navi_goals.py (%s); source the workspace\'s setup.bash\n' % reason)
    sys.exit(2)
os.execv(sys.executable, [sys.executable, found[0]] + sys.argv[1:])
