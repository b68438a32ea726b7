#!/usr/bin/env bash
# Regenerates docs/rviz_navigation.png: the navigation stack at real time, rviz on a virtual X
# display (Xvfb :77) with minibot3d_navigation/rviz/navigation.rviz, grabbed with Pillow while the
# robot drives to a goal.
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source tools/ros_env.sh
setsid roslaunch -p $ROS_PORT minibot3d_navigation amcl_navigation.launch real_time_factor:=1 > /tmp/shot_stack.log 2>&1 &
stack=$!
wait_for_master 60
export DISPLAY=:77
Xvfb :77 -screen 0 1280x900x24 > /dev/null 2>&1 &
xv=$!
sleep 2
rviz -d minibot3d_navigation/rviz/navigation.rviz > /tmp/shot_rviz.log 2>&1 &
rv=$!
timeout 120 rosrun minibot3d_navigation simple_navi_goals.py --frame map 0.45 0.6 0 --timeout 100 > /tmp/shot_goal.log 2>&1 &
g=$!
# wait until the robot is under way, then grab the screen
for i in $(seq 60); do
  v=$(timeout 5 rostopic echo -n1 /ground_truth/odom/twist/twist/linear/x 2>/dev/null | head -1)
  python3 -c "import sys; sys.exit(0 if abs(float('${v:-0}')) > 0.2 else 1)" 2>/dev/null && break
  sleep 1
done
sleep 4
/usr/bin/python3 -c "from PIL import ImageGrab; ImageGrab.grab(xdisplay=':77').crop((0, 0, 1200, 800)).save('docs/rviz_navigation.png')" && echo shot-ok
kill $g $rv 2>/dev/null; kill $xv; kill -INT -- -$stack; wait $stack
