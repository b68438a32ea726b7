#!/usr/bin/env bash
# AMCL accuracy in the simulator (part of make bench): simulator + map_server + amcl in the
# default world, then tools/bench/amcl_bench.py (tracking, global localization, kidnapping).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source tools/ros_env.sh
out=build/bench/amcl && mkdir -p "$out"
map=$(realpath maps/default_world.yaml)
ros_start_core
setsid roslaunch minibot3d_sim minibot3d_gazebo.launch x:=-3.0 y:=-1.5 yaw:=0 \
  real_time_factor:=5 > "$out/sim.log" 2>&1 &
sim=$!
amcl=
trap 'ros_stop_groups "$amcl" "$sim"; ros_stop_core' EXIT
ros_wait_launch 60
setsid roslaunch minibot3d_navigation amcl_bench_stack.launch map:="$map" \
  > "$out/amcl.log" 2>&1 &
amcl=$!
/usr/bin/python3 tools/bench/amcl_bench.py --map "$map" --laps 3 \
  --waypoints "-2.1,0.6 -2.4,3.0 -2.1,0.6 -0.3,2.0 0.45,0.6 2.5,-1.0 0.8,-2.15 -3,-1.5"
