#!/usr/bin/env bash
# move_base in the simulator (part of make bench): amcl_navigation.launch in the default world,
# then tools/bench/nav_bench.py sends 20 random reachable goals (fixed seed).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
source tools/ros_env.sh
out=build/bench/nav && mkdir -p "$out"
map=$(realpath maps/default_world.yaml)
rtf="${NAV_BENCH_RTF:-4}"
ros_start_core
setsid roslaunch minibot3d_navigation amcl_navigation.launch \
  real_time_factor:="$rtf" map_file:="$map" > "$out/stack.log" 2>&1 &
stack=$!
trap 'ros_stop_groups "$stack"; ros_stop_core' EXIT
ros_wait_launch 60
/usr/bin/python3 tools/bench/nav_bench.py --map "$map" --goals "${NAV_BENCH_GOALS:-20}" --seed 1
