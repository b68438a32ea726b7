#!/usr/bin/env bash
# make demo: the project's main job, headless.
# At this stage (simulator): the robot in a world, driven around a square through cmd_vel; prints
# the true path length, the odometry drift and the achieved real-time factor.
#   tools/demo.sh [WORLD]   (DEMO_X, DEMO_Y, DEMO_YAW: spawn pose, free in that world)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source tools/ros_env.sh
world="${1:-$(pwd)/minibot3d_sim/worlds/default.world}"
x="${DEMO_X:--3.0}"; y="${DEMO_Y:--1.5}"; yaw="${DEMO_YAW:-0.0}"
rtf="${DEMO_REAL_TIME_FACTOR:-20}"
mkdir -p out
log=out/demo_sim.log
echo "demo: world $world, spawn ($x, $y, $yaw), real-time factor $rtf (log: $log)"
setsid roslaunch -p "$ROS_PORT" minibot3d_sim minibot3d_gazebo.launch world:="$world" \
  x:="$x" y:="$y" yaw:="$yaw" real_time_factor:="$rtf" > "$log" 2>&1 &
launch_pid=$!
cleanup() { kill -INT -- -"$launch_pid" 2>/dev/null || true; wait "$launch_pid" 2>/dev/null || true; }
trap cleanup EXIT
wait_for_master 60
status=0
rosrun minibot3d_sim drive_square.py --side 1.0 --laps 2 --timeout 300 || status=$?
if [ $status -ne 0 ]; then
  echo "demo: FAILED (exit $status); the simulator said:" >&2
  grep -E "FATAL|ERROR" "$log" >&2 || tail -20 "$log" >&2
fi
exit $status
